//! strata-lod: level of detail for strata surfaces (see DESIGN.md section 4).
