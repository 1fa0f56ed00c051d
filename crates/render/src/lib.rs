//! strata-render: wgpu rendering of strata surfaces (see DESIGN.md section 3).
