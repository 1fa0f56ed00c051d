//! Map grid lines (Celes & Abraham 2011, section 6, Fig. 13a): two families of lines
//! at constant map x and constant map y, drawn with the wireframe's coverage from a
//! coordinate generated in object space, so they keep their thickness in pixels on
//! any surface (a terrain TIN, whose vertices carry no structured coordinates, or a
//! reservoir layer) without touching the mesh.
//!
//! The fragment shader (`extra_lines` in wire/common.wgsl) turns the display-frame
//! position into `u = 2 (x + offset_x) / spacing + 1` (and likewise for y), which is
//! odd exactly on the lines. Map coordinates are UTM-sized, too large for `f32`; the
//! offset is therefore folded on the CPU, in `f64`, to the remainder of the display
//! frame's origin minus the grid origin modulo the spacing, so that the shader only
//! ever adds small numbers.

/// Where map grid lines are drawn and how they look.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridLines {
    /// Distance between lines, map units (metres), the same for both families.
    pub spacing: f64,
    /// A map point (x, y) where an x line and a y line cross.
    pub origin: [f64; 2],
    /// Map coordinates of the display frame's (0, 0): the drawn meshes' `origin`.
    pub display_origin: [f64; 2],
    /// Line colour; alpha scales the coverage.
    pub color: [f32; 4],
}

impl GridLines {
    /// Lines every `spacing` through map (0, 0), for meshes whose display frame starts
    /// at `display_origin` (their `SurfaceMesh::origin`).
    pub fn new(spacing: f64, display_origin: [f64; 2]) -> Self {
        GridLines {
            spacing,
            origin: [0.0, 0.0],
            display_origin,
            color: [0.15, 0.15, 0.2, 0.85],
        }
    }

    /// `None` unless the spacing is positive and finite and the origins are finite.
    pub(crate) fn validate(&self) -> Option<()> {
        let finite = self
            .origin
            .iter()
            .chain(&self.display_origin)
            .all(|v| v.is_finite());
        (self.spacing > 0.0 && self.spacing.is_finite() && finite).then_some(())
    }

    /// The frame uniform: (offset x, offset y, 2 / spacing, 1), the offsets in
    /// `[0, spacing)` so that `f32` keeps its precision.
    pub(crate) fn uniform(&self) -> [f32; 4] {
        let fold = |a: usize| (self.display_origin[a] - self.origin[a]).rem_euclid(self.spacing);
        [
            fold(0) as f32,
            fold(1) as f32,
            (2.0 / self.spacing) as f32,
            1.0,
        ]
    }

    /// Map x (`axis` 0) or y (1) of the line with the given index, counted from the
    /// grid origin.
    pub fn line_at(&self, axis: usize, index: i64) -> f64 {
        self.origin[axis] + index as f64 * self.spacing
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_are_folded_in_double_precision() {
        let g = GridLines {
            origin: [456_100.0, 6_780_050.0],
            ..GridLines::new(500.0, [456_987.25, 6_781_234.5])
        };
        let [ox, oy, k, on] = g.uniform();
        // 887.25 mod 500 and 1184.5 mod 500.
        assert!((ox - 387.25).abs() < 1e-4 && (oy - 184.5).abs() < 1e-4);
        assert_eq!((k, on), (0.004, 1.0));
        // A display-frame x on a line gives an odd coordinate: map x 457 100 is
        // display x 112.75; between lines, an even one.
        let u = (112.75 + ox) * k + 1.0;
        assert!((u - 3.0).abs() < 1e-5, "{u}");
        let between = (112.75 + 250.0 + ox) * k + 1.0;
        assert!((between - 4.0).abs() < 1e-5, "{between}");
        assert_eq!(g.line_at(0, 2), 457_100.0);
    }

    #[test]
    fn a_grid_below_the_display_origin_folds_to_a_positive_offset() {
        let g = GridLines::new(100.0, [-30.0, 250.0]);
        let [ox, oy, ..] = g.uniform();
        assert!((ox - 70.0).abs() < 1e-5 && (oy - 50.0).abs() < 1e-5);
        assert!(g.validate().is_some());
        assert!(GridLines::new(0.0, [0.0; 2]).validate().is_none());
        assert!(GridLines::new(f64::NAN, [0.0; 2]).validate().is_none());
    }
}
