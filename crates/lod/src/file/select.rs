//! Choosing the nodes a view draws: the coarsest whose error, projected from the eye,
//! is within a pixel budget, and reading a selection back as one mesh.

use strata_grid::SurfaceMesh;

use super::format::NodeRecord;
use super::read::LodFile;
use crate::{Error, Result};

/// Where a frame is seen from, for choosing levels of detail.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewPoint {
    /// Eye position in the display frame *after* vertical exaggeration (as a camera
    /// fitted with that exaggeration has it).
    pub eye: [f32; 3],
    /// Vertical exaggeration of the view: errors are projected as drawn.
    pub z_scale: f32,
    /// Vertical field of view, degrees.
    pub fov_y_deg: f32,
    /// Image height, pixels.
    pub height_px: u32,
    /// The planes that bound the picture, in the same frame as `eye`, each `(a, b, c,
    /// d)` with `a x + b y + c z + d >= 0` inside (as `Camera::frustum` of
    /// strata-render gives them): nodes wholly outside one are not chosen. `None`
    /// chooses over the whole model.
    pub frustum: Option<[[f32; 4]; 5]>,
}

impl ViewPoint {
    /// Pixels that a length `error` at distance `distance` covers.
    pub(crate) fn pixels(&self, error: f64, distance: f64) -> f64 {
        if distance <= 0.0 {
            return f64::INFINITY;
        }
        let focal = f64::from(self.height_px)
            / (2.0 * (f64::from(self.fov_y_deg).to_radians() / 2.0).tan());
        error * focal / distance
    }

    /// Whether the box `[min, max]` (unscaled) lies wholly outside one of the planes
    /// of `frustum`: then its corner furthest along the plane's normal is outside.
    fn misses(&self, min: [f32; 3], max: [f32; 3]) -> bool {
        let Some(planes) = &self.frustum else {
            return false;
        };
        let scale = [1.0, 1.0, f64::from(self.z_scale)];
        planes.iter().any(|plane| {
            let furthest: f64 = (0..3)
                .map(|a| {
                    let corner = if plane[a] >= 0.0 { max[a] } else { min[a] };
                    f64::from(plane[a]) * f64::from(corner) * scale[a]
                })
                .sum();
            furthest + f64::from(plane[3]) < 0.0
        })
    }
}

impl LodFile {
    /// The coarsest nodes whose error, projected from `view`, is at most `max_pixels`
    /// (leaves where nothing coarser is good enough): a cut through each layer's tree,
    /// so every cell is drawn exactly once, except under nodes wholly outside the
    /// view's frustum, which are left out.
    pub fn select(&self, view: &ViewPoint, max_pixels: f32) -> Vec<u32> {
        self.select_exposed(view, max_pixels, &[])
    }

    /// [`LodFile::select`], where the layer surfaces flagged in `inner` (indexed as
    /// [`LodFile::layers`]; missing ones are not inner) lie inside a closed stack drawn
    /// with its side faces: of those, only nodes with exposed faces
    /// ([`NodeRecord::exposed`]) are chosen, and one whose cells are mostly hidden
    /// gives way to its children, so that the hidden ones drop out. A stack of a
    /// hundred layers seen close up would otherwise have each hidden layer fill the
    /// picture only to be rejected by the depth test.
    pub fn select_exposed(&self, view: &ViewPoint, max_pixels: f32, inner: &[bool]) -> Vec<u32> {
        let nodes = self.nodes();
        let zs = f64::from(view.z_scale);
        let eye = view.eye.map(f64::from);
        let mut out = Vec::new();
        let mut stack: Vec<u32> = self.layers().iter().map(|l| l.root).collect();
        stack.reverse();
        while let Some(i) = stack.pop() {
            let n = &nodes[i as usize];
            // Widened by the node's error, the box holds the surface it stands for.
            let (across, up) = (n.error[0], n.error[1]);
            let widen = |p: [f32; 3], sign: f32| {
                [p[0] + sign * across, p[1] + sign * across, p[2] + sign * up]
            };
            if view.misses(widen(n.min, -1.0), widen(n.max, 1.0)) {
                continue;
            }
            if inner.get(n.layer as usize).copied().unwrap_or(false) {
                if n.exposed == 0 {
                    continue;
                }
                let [i0, j0, i1, j1] = n.cells.map(u64::from);
                let cells = i1.saturating_sub(i0) * j1.saturating_sub(j0);
                if n.child_count > 0 && 2 * u64::from(n.exposed) < cells {
                    stack.extend((n.first_child..n.first_child + n.child_count).rev());
                    continue;
                }
            }
            let error =
                (f64::from(n.error[0]).powi(2) + (zs * f64::from(n.error[1])).powi(2)).sqrt();
            // Distance from the eye to the node's box, in the exaggerated frame.
            let d2: f64 = (0..3)
                .map(|a| {
                    let s = if a == 2 { zs } else { 1.0 };
                    let (lo, hi) = (f64::from(n.min[a]) * s, f64::from(n.max[a]) * s);
                    let e = eye[a];
                    if e < lo {
                        (lo - e).powi(2)
                    } else if e > hi {
                        (e - hi).powi(2)
                    } else {
                        0.0
                    }
                })
                .sum();
            if n.child_count == 0 || view.pixels(error, d2.sqrt()) <= f64::from(max_pixels) {
                out.push(i);
            } else {
                stack.extend((n.first_child..n.first_child + n.child_count).rev());
            }
        }
        out
    }

    /// The leaf of layer surface `l` whose cells hold cell `(i, j)`, found down its
    /// tree; `None` where no tile of the layer holds it.
    pub fn leaf_of(&self, l: usize, [i, j]: [u32; 2]) -> Option<u32> {
        let nodes = self.nodes();
        let holds = |n: &NodeRecord| {
            (n.cells[0]..n.cells[2]).contains(&i) && (n.cells[1]..n.cells[3]).contains(&j)
        };
        // `open` checked that children are one level below their parents: this ends.
        let mut at = self.layers().get(l)?.root;
        loop {
            let n = nodes.get(at as usize).filter(|n| holds(n))?;
            if n.child_count == 0 {
                return Some(at);
            }
            at = (n.first_child..n.first_child + n.child_count)
                .find(|&c| nodes.get(c as usize).is_some_and(holds))?;
        }
    }

    /// The nodes `selection` in one mesh (relative to [`LodFile::origin`]).
    pub fn selection_mesh(&self, selection: &[u32]) -> Result<SurfaceMesh> {
        let mut mesh = SurfaceMesh::with_origin(self.origin());
        for &i in selection {
            if i as usize >= self.nodes().len() {
                return Err(Error::Option(format!("no node {i}")));
            }
            self.append_to(i as usize, &mut mesh)?;
        }
        Ok(mesh)
    }
}
