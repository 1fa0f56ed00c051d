//! Synthetic reservoir generator: a folded layer cake of varying thickness cut by
//! vertical and inclined faults with throw, with pinched-out cells, an inactive
//! region and smooth PORO / PERMX fields. Deterministic by seed.
//!
//! Built so that large models stay cheap: node depths of every horizon are computed
//! once (`(nz + 1) (ny + 1) (nx + 1)` values), fault throws once per map corner
//! (`4 nx ny` values), and ZCORN is their sum, filled in parallel, so that ZCORN
//! itself (`8 nx ny nz` values of `f32`) is most of the memory a large model needs
//! (measured in docs/performance.md).

use ndarray::{Array3, Axis};
use rayon::prelude::*;

/// The golden ratio, the icosahedron's corner coordinate.
const PHI: f32 = 1.618_034;

/// Corners of a regular icosahedron centred on the origin (not unit length): the seed
/// of the sphere meshes that stand for the papers' scanned models in tests and
/// benchmarks.
pub const ICOSAHEDRON_CORNERS: [[f32; 3]; 12] = [
    [-1.0, PHI, 0.0],
    [1.0, PHI, 0.0],
    [-1.0, -PHI, 0.0],
    [1.0, -PHI, 0.0],
    [0.0, -1.0, PHI],
    [0.0, 1.0, PHI],
    [0.0, -1.0, -PHI],
    [0.0, 1.0, -PHI],
    [PHI, 0.0, -1.0],
    [PHI, 0.0, 1.0],
    [-PHI, 0.0, -1.0],
    [-PHI, 0.0, 1.0],
];

/// The icosahedron's faces, indices into [`ICOSAHEDRON_CORNERS`], counter-clockwise
/// seen from outside.
pub const ICOSAHEDRON_FACES: [[u32; 3]; 20] = [
    [0, 11, 5],
    [0, 5, 1],
    [0, 1, 7],
    [0, 7, 10],
    [0, 10, 11],
    [1, 5, 9],
    [5, 11, 4],
    [11, 10, 2],
    [10, 7, 6],
    [7, 1, 8],
    [3, 9, 4],
    [3, 4, 2],
    [3, 2, 6],
    [3, 6, 8],
    [3, 8, 9],
    [4, 9, 5],
    [2, 4, 11],
    [6, 2, 10],
    [8, 6, 7],
    [9, 8, 1],
];

use crate::{CornerPointGrid, Dims, Result, Units};

/// What to generate.
#[derive(Clone, Debug)]
pub struct SynthParams {
    /// Cells along `i` (east), each 50 m wide.
    pub nx: usize,
    /// Cells along `j` (north), each 50 m wide.
    pub ny: usize,
    /// Layers; with more than two, the middle one pinches out in the west.
    pub nz: usize,
    /// Number of faults (vertical and inclined, each with a throw).
    pub faults: usize,
    /// Draws the fault positions, throws and field phases: the same seed and sizes
    /// give the same grid.
    pub seed: u64,
}

/// Horizontal cell size in metres.
const CELL_SIZE: f64 = 50.0;
/// Map position of the grid's first pillar, UTM-like so that consumers must cope
/// with large coordinates.
const MAP_ORIGIN: [f64; 2] = [456_000.0, 6_780_000.0];
/// Depth of the top horizon's mean, metres.
const TOP_DEPTH: f64 = 1600.0;
/// Mean total thickness of the layer cake, metres.
const TOTAL_THICKNESS: f64 = 120.0;

/// One fault: it follows a line of pillars, so it is as inclined as those pillars
/// are; the cells on its far side are thrown down by a throw that tapers to zero
/// at the fault's tips.
#[derive(Clone, Debug)]
struct Fault {
    /// `true`: along the pillar line `i = line` (the fault runs in j); else `j = line`.
    along_j: bool,
    line: usize,
    /// Extent along the fault, in pillar indices, `start < end`.
    start: usize,
    end: usize,
    throw: f64,
}

impl Fault {
    /// Throw at pillar position `p` along the fault: a sine bump over its extent.
    fn throw_at(&self, p: usize) -> f64 {
        if p <= self.start || p >= self.end {
            return 0.0;
        }
        let t = (p - self.start) as f64 / (self.end - self.start) as f64;
        self.throw * (std::f64::consts::PI * t).sin().powf(0.3)
    }
}

/// SplitMix64: tiny, fast and good enough to place faults and phases reproducibly.
struct SplitMix(u64);

impl SplitMix {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform integer in `[lo, hi)`; `lo` when the range is empty.
    fn index(&mut self, lo: usize, hi: usize) -> usize {
        if hi <= lo {
            lo
        } else {
            lo + (self.next_u64() % (hi - lo) as u64) as usize
        }
    }
}

/// The smooth fields of one model, drawn from the seed.
struct Fields {
    phase: [f64; 4],
    lx: f64,
    ly: f64,
}

impl Fields {
    fn new(rng: &mut SplitMix, lx: f64, ly: f64) -> Self {
        Fields {
            phase: std::array::from_fn(|_| rng.range(0.0, std::f64::consts::TAU)),
            lx,
            ly,
        }
    }

    /// Depth of the top horizon: an anticline with folds and a regional dip.
    fn top(&self, x: f64, y: f64) -> f64 {
        let (u, v) = (x / self.lx, y / self.ly);
        let dome = 60.0 * ((u - 0.5).powi(2) + (v - 0.5).powi(2));
        let folds = 25.0
            * (std::f64::consts::TAU * 1.5 * u + self.phase[0]).sin()
            * (std::f64::consts::TAU * v + self.phase[1]).cos();
        TOP_DEPTH + dome + folds + 40.0 * u
    }

    /// Thickness of layer `k` of `nz`: varies smoothly, and the middle layer pinches
    /// out (zero thickness) over the western third of the model.
    fn thickness(&self, k: usize, nz: usize, x: f64, y: f64) -> f64 {
        let (u, v) = (x / self.lx, y / self.ly);
        let mean = TOTAL_THICKNESS / nz as f64;
        let wobble = 1.0
            + 0.45 * (std::f64::consts::TAU * (u + 0.7 * v) + self.phase[2] + k as f64 * 0.9).sin();
        if nz > 2 && k == nz / 2 {
            mean * wobble * ((u - 0.33) * 4.0).clamp(0.0, 1.0)
        } else {
            mean * wobble
        }
    }

    /// Porosity: smooth lateral trends, layer to layer variation, bounded to [0.02, 0.35].
    fn poro(&self, k: usize, x: f64, y: f64) -> f64 {
        let (u, v) = (x / self.lx, y / self.ly);
        let lateral = 0.06
            * (std::f64::consts::TAU * 2.0 * u + self.phase[3]).sin()
            * (std::f64::consts::TAU * 1.3 * v).cos();
        let layer = 0.04 * (k as f64 * 1.7 + self.phase[0]).sin();
        (0.2 + lateral + layer - 0.05 * v).clamp(0.02, 0.35)
    }
}

/// Generates a grid with PORO and PERMX.
pub fn generate(params: &SynthParams) -> Result<CornerPointGrid> {
    let dims = Dims::new(params.nx, params.ny, params.nz)?;
    let Dims { nx, ny, nz } = dims;
    let mut rng = SplitMix(params.seed ^ 0x5EED_5EED_5EED_5EED);
    let (lx, ly) = (nx as f64 * CELL_SIZE, ny as f64 * CELL_SIZE);
    let fields = Fields::new(&mut rng, lx, ly);
    let faults = draw_faults(&mut rng, params.faults, nx, ny);

    // Pillars are vertical in the west and lean east by up to 0.35 m per metre in the
    // east, so faults there are inclined. Their span brackets every horizon.
    let z_lo = TOP_DEPTH - 200.0;
    let z_hi = TOP_DEPTH + 400.0 + TOTAL_THICKNESS * 2.0;
    let lean = |pi: usize| 0.35 * ((pi as f64 / nx as f64 - 0.5) * 2.0).clamp(0.0, 1.0);
    let mut coord = Vec::with_capacity(dims.coord_len().unwrap_or(0));
    for pj in 0..=ny {
        for pi in 0..=nx {
            let (x, y) = (
                MAP_ORIGIN[0] + pi as f64 * CELL_SIZE,
                MAP_ORIGIN[1] + pj as f64 * CELL_SIZE,
            );
            let l = lean(pi);
            coord.extend([
                x + l * (z_lo - TOP_DEPTH),
                y,
                z_lo,
                x + l * (z_hi - TOP_DEPTH),
                y,
                z_hi,
            ]);
        }
    }

    // Horizon depths at the nodes, measured where each pillar crosses the mean top.
    let mut horizons = Array3::<f32>::zeros((nz + 1, ny + 1, nx + 1));
    horizons
        .axis_iter_mut(Axis(1))
        .into_par_iter()
        .enumerate()
        .for_each(|(pj, mut rows)| {
            for pi in 0..=nx {
                let (x, y) = (pi as f64 * CELL_SIZE, pj as f64 * CELL_SIZE);
                let mut depth = fields.top(x, y);
                for h in 0..=nz {
                    rows[[h, pi]] = depth as f32;
                    if h < nz {
                        depth += fields.thickness(h, nz, x, y);
                    }
                }
            }
        });

    let throws = corner_throws(&faults, nx, ny);
    let mut zcorn = vec![0f32; dims.zcorn_len().unwrap_or(0)];
    zcorn
        .par_chunks_mut(4 * nx * ny)
        .enumerate()
        .for_each(|(zk, slab)| {
            let (k, dk) = (zk / 2, zk % 2);
            for zj in 0..2 * ny {
                let pj = zj / 2 + zj % 2;
                for zi in 0..2 * nx {
                    let pi = zi / 2 + zi % 2;
                    slab[zj * 2 * nx + zi] = horizons[[k + dk, pj, pi]] + throws[zj * 2 * nx + zi];
                }
            }
        });
    drop(horizons);

    // Inactive: an ellipse in the south-east corner through all layers (an eroded or
    // water-filled region), plus the top layer in a northern strip.
    let mut actnum = vec![true; dims.cell_count()];
    actnum
        .par_chunks_mut(nx * ny)
        .enumerate()
        .for_each(|(k, layer)| {
            for j in 0..ny {
                for i in 0..nx {
                    let u = (i as f64 + 0.5) / nx as f64;
                    let v = (j as f64 + 0.5) / ny as f64;
                    let ellipse = ((u - 0.9) / 0.18).powi(2) + ((v - 0.12) / 0.2).powi(2) < 1.0;
                    let strip = k == 0 && nz > 1 && v > 0.85 && u < 0.4;
                    if ellipse || strip {
                        layer[j * nx + i] = false;
                    }
                }
            }
        });

    let mut grid = CornerPointGrid::from_arrays(dims, coord, zcorn, Some(actnum))?;
    grid.units = Units::Metres;
    let poro = Array3::from_shape_fn((nz, ny, nx), |(k, j, i)| {
        fields.poro(
            k,
            (i as f64 + 0.5) * CELL_SIZE,
            (j as f64 + 0.5) * CELL_SIZE,
        ) as f32
    });
    // Permeability follows porosity log-linearly, as core data usually does.
    let permx = poro.mapv(|p| 10f32.powf(-1.0 + 18.0 * p));
    grid.set_property("PORO", poro)?;
    grid.set_property("PERMX", permx)?;
    Ok(grid)
}

/// Draws `count` faults, alternating between the two pillar directions; lines are
/// kept off the outer pillars and at least one cell apart when possible.
fn draw_faults(rng: &mut SplitMix, count: usize, nx: usize, ny: usize) -> Vec<Fault> {
    (0..count)
        .map(|f| {
            let along_j = f % 2 == 0;
            let (across, along) = if along_j { (nx, ny) } else { (ny, nx) };
            let line = rng.index(1, across.max(2));
            // Every third fault spans the model (tips outside); the others end inside.
            let (start, end) = if f % 3 == 0 || along < 6 {
                (0, along + along / 2 + 1)
            } else {
                let start = rng.index(0, along / 3);
                (
                    start,
                    rng.index(start + along / 2, along + 1).max(start + 2),
                )
            };
            let throw = rng.range(4.0, 25.0) * if rng.next_u64() & 1 == 0 { 1.0 } else { -1.0 };
            Fault {
                along_j,
                line,
                start,
                end,
                throw,
            }
        })
        .collect()
}

/// Fault throw of every map corner of every cell, laid out like one ZCORN layer
/// (`[2 ny][2 nx]`): a corner is thrown by each fault whose far side its cell is on,
/// by that fault's throw at the corner's pillar. Cells on the same side of a fault
/// share a pillar's throw, so only the fault plane is split.
fn corner_throws(faults: &[Fault], nx: usize, ny: usize) -> Vec<f32> {
    let mut throws = vec![0f32; 4 * nx * ny];
    for zj in 0..2 * ny {
        let (j, pj) = (zj / 2, zj / 2 + zj % 2);
        for zi in 0..2 * nx {
            let (i, pi) = (zi / 2, zi / 2 + zi % 2);
            let t: f64 = faults
                .iter()
                .map(|f| match (f.along_j, f.line) {
                    (true, line) if i >= line => f.throw_at(pj),
                    (false, line) if j >= line => f.throw_at(pi),
                    _ => 0.0,
                })
                .sum();
            throws[zj * 2 * nx + zi] = t as f32;
        }
    }
    throws
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(faults: usize) -> SynthParams {
        SynthParams {
            nx: 30,
            ny: 20,
            nz: 6,
            faults,
            seed: 7,
        }
    }

    #[test]
    fn deterministic_by_seed() {
        let a = generate(&params(3)).unwrap();
        let b = generate(&params(3)).unwrap();
        assert_eq!(a.zcorn, b.zcorn);
        let c = generate(&SynthParams {
            seed: 8,
            ..params(3)
        })
        .unwrap();
        assert_ne!(a.zcorn, c.zcorn);
    }

    #[test]
    fn faults_split_and_only_faults_split() {
        assert_eq!(generate(&params(0)).unwrap().fault_split_fraction(), 0.0);
        let f = generate(&params(4)).unwrap().fault_split_fraction();
        assert!(f > 0.0 && f < 0.25, "fault split fraction {f}");
    }

    #[test]
    fn has_pinchouts_inactive_cells_and_properties() {
        let g = generate(&params(2)).unwrap();
        let k = g.dims().nz / 2;
        let pinched = (0..g.dims().nx).filter(|&i| {
            (0..4).all(|c| g.corner_depth(i, 5, k, c) == g.corner_depth(i, 5, k, c + 4))
        });
        assert!(pinched.count() >= 5);
        let active = g.active_count();
        assert!(active < g.cell_count() && active > g.cell_count() / 2);
        let poro = g.property("PORO").unwrap();
        assert!(poro.iter().all(|p| (0.02..=0.35).contains(p)));
        assert!(g.property("permx").is_some());
    }

    #[test]
    fn layers_never_cross() {
        let g = generate(&params(5)).unwrap();
        let d = g.dims();
        for k in 0..d.nz {
            for j in 0..d.ny {
                for i in 0..d.nx {
                    for c in 0..4 {
                        assert!(g.corner_depth(i, j, k, c) <= g.corner_depth(i, j, k, c + 4));
                    }
                }
            }
        }
    }
}
