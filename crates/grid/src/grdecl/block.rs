//! Block-centred geometry (DX/DY/DZ/TOPS, or the DXV/DYV/DZV vectors) converted to
//! corner-point pillars and depths.
//!
//! Pillars are vertical. Pillar `(pi, pj)` sits at `x = sum of DX over i < pi` along
//! row `min(pj, ny - 1)` of the top layer, and likewise `y` from DY along column
//! `min(pi, nx - 1)`: exact whenever DX depends on `i` only and DY on `j` only, the
//! usual case, and a consistent choice otherwise (corner-point pillars cannot bend
//! with a DX that changes from row to row). Each cell's top is its TOPS and its
//! bottom TOPS + DZ; a layer without TOPS starts where the layer above ends, and a
//! layer without DZ repeats the layer above.

use std::collections::BTreeMap;

use rayon::prelude::*;

use crate::Dims;

/// A problem with the block-centred input: the keyword and the message.
pub(super) type BlockError = (String, String);

/// Is there block-centred geometry to convert?
pub(super) fn present(
    arrays: &BTreeMap<String, Vec<f32>>,
    vectors: &BTreeMap<String, Vec<f64>>,
) -> bool {
    ["DX", "DY", "DZ", "TOPS"]
        .iter()
        .any(|k| arrays.contains_key(*k))
        || !vectors.is_empty()
}

/// The values [`to_corner_point`] allocates for `dims` (ZCORN, COORD and a few
/// per-cell arrays on the way), `None` on overflow.
pub(super) fn cost(dims: Dims) -> Option<usize> {
    dims.zcorn_len()?
        .checked_add(dims.coord_len()?)?
        .checked_add(dims.cell_count_checked()?.checked_mul(3)?)
}

/// COORD and ZCORN (file order) for a block-centred grid.
pub(super) fn to_corner_point(
    dims: Dims,
    arrays: &BTreeMap<String, Vec<f32>>,
    vectors: &BTreeMap<String, Vec<f64>>,
) -> Result<(Vec<f64>, Vec<f32>), BlockError> {
    let Dims { nx, ny, nz } = dims;
    let layer = nx * ny;
    let dx = sizes(dims, "DX", 0, 1, arrays, vectors)?;
    let dy = sizes(dims, "DY", 1, 1, arrays, vectors)?;
    let dz = sizes(dims, "DZ", 2, nz, arrays, vectors)?;
    let given = arrays.get("TOPS").ok_or_else(|| {
        (
            "TOPS".to_string(),
            "no TOPS for a DX/DY/DZ grid".to_string(),
        )
    })?;
    let mut tops = vec![0f64; dims.cell_count()];
    for cell in 0..tops.len() {
        let t = f64::from(given[cell]);
        tops[cell] = if !t.is_nan() {
            t
        } else if cell >= layer {
            tops[cell - layer] + dz[cell - layer]
        } else {
            let (i, j, _) = dims.cell_ijk(cell);
            return Err(missing("TOPS", i, j, 0));
        };
        if !tops[cell].is_finite() {
            let (i, j, k) = dims.cell_ijk(cell);
            return Err((
                "TOPS".to_string(),
                format!("cell ({}, {}, {}) has no finite top", i + 1, j + 1, k + 1),
            ));
        }
    }

    let (mut zmin, mut zmax) = (f64::INFINITY, f64::NEG_INFINITY);
    for (t, d) in tops.iter().zip(&dz) {
        zmin = zmin.min(t.min(t + d));
        zmax = zmax.max(t.max(t + d));
    }
    if zmax <= zmin {
        zmax = zmin + 1.0;
    }
    // Running sums: x along each pillar row, y down each pillar column.
    let mut coord = Vec::with_capacity((nx + 1) * (ny + 1) * 6);
    let mut y = vec![0f64; nx + 1];
    for pj in 0..=ny {
        let row = pj.min(ny - 1);
        let mut x = 0.0;
        for (pi, &y) in y.iter().enumerate() {
            coord.extend([x, y, zmin, x, y, zmax]);
            if pi < nx {
                x += dx[row * nx + pi];
            }
        }
        if pj < ny {
            for (pi, y) in y.iter_mut().enumerate() {
                *y += dy[pj * nx + pi.min(nx - 1)];
            }
        }
    }

    let mut zcorn = vec![0f32; 8 * dims.cell_count()];
    zcorn
        .par_chunks_mut(4 * layer)
        .enumerate()
        .for_each(|(zk, slab)| {
            let (k, bottom) = (zk / 2, zk % 2 == 1);
            for zj in 0..2 * ny {
                for zi in 0..2 * nx {
                    let cell = k * layer + (zj / 2) * nx + zi / 2;
                    let z = tops[cell] + if bottom { dz[cell] } else { 0.0 };
                    slab[zj * 2 * nx + zi] = z as f32;
                }
            }
        });
    Ok((coord, zcorn))
}

/// Cell sizes along `axis` for the first `layers` layers, from the per-cell array
/// `name` (lower layers without values repeat the layer above) or else its vector
/// `name` + `V`.
fn sizes(
    dims: Dims,
    name: &str,
    axis: usize,
    layers: usize,
    arrays: &BTreeMap<String, Vec<f32>>,
    vectors: &BTreeMap<String, Vec<f64>>,
) -> Result<Vec<f64>, BlockError> {
    let layer = dims.nx * dims.ny;
    let mut out = vec![0f64; layer * layers];
    let vector = vectors.get(&format!("{name}V"));
    let array = arrays.get(name);
    if array.is_none() && vector.is_none() {
        return Err((
            name.to_string(),
            format!("no {name} or {name}V for a block-centred grid"),
        ));
    }
    for cell in 0..out.len() {
        let (i, j, k) = dims.cell_ijk(cell);
        let given = array.map_or(f64::NAN, |a| f64::from(a[cell]));
        let v = if !given.is_nan() {
            given
        } else if let Some(v) = vector {
            v[[i, j, k][axis]]
        } else if k > 0 {
            out[cell - layer]
        } else {
            return Err(missing(name, i, j, k));
        };
        if !v.is_finite() {
            return Err((
                name.to_string(),
                format!(
                    "cell ({}, {}, {}) has a size that is not finite",
                    i + 1,
                    j + 1,
                    k + 1
                ),
            ));
        }
        out[cell] = v;
    }
    Ok(out)
}

fn missing(name: &str, i: usize, j: usize, k: usize) -> BlockError {
    (
        name.to_string(),
        format!("no value for cell ({}, {}, {})", i + 1, j + 1, k + 1),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tops_follow_dz_down_and_pillars_follow_dx() {
        let d = Dims::new(2, 1, 2).unwrap();
        let nan = f32::NAN;
        let mut arrays = BTreeMap::new();
        arrays.insert("DX".to_string(), vec![10.0, 20.0, nan, nan]);
        arrays.insert("DZ".to_string(), vec![1.0, 2.0, 3.0, nan]);
        arrays.insert("TOPS".to_string(), vec![100.0, 200.0, nan, nan]);
        let mut vectors = BTreeMap::new();
        vectors.insert("DYV".to_string(), vec![5.0]);
        let (coord, zcorn) = to_corner_point(d, &arrays, &vectors).unwrap();
        let xs: Vec<f64> = coord.chunks(6).map(|p| p[0]).collect();
        assert_eq!(xs, [0.0, 10.0, 30.0, 0.0, 10.0, 30.0]);
        assert_eq!(coord[6 * 3 + 1], 5.0);
        assert_eq!((coord[2], coord[5]), (100.0, 204.0));
        // Layer 2 starts where layer 1 ends; cell i=2 there copies DZ = 2 down.
        assert_eq!(zcorn[2 * 8], 101.0);
        assert_eq!(zcorn[2 * 8 + 3], 202.0);
        assert_eq!(zcorn[3 * 8 + 3], 204.0);

        arrays.remove("TOPS");
        assert_eq!(to_corner_point(d, &arrays, &vectors).unwrap_err().0, "TOPS");
        arrays.insert("TOPS".to_string(), vec![nan; 4]);
        let e = to_corner_point(d, &arrays, &vectors).unwrap_err();
        assert!(e.1.contains("cell (1, 1, 1)"), "{e:?}");
        vectors.clear();
        assert_eq!(to_corner_point(d, &arrays, &vectors).unwrap_err().0, "DY");
    }
}
