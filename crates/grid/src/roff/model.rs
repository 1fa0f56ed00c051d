//! From the tags of a ROFF file to a grid, as xtgeo's `RoffGrid` and `RoffParameter`
//! read them.
//!
//! ROFF orders cells and nodes with `i` slowest and `k` fastest, `k` counted from the
//! bottom; strata's arrays have `i` fastest and `k` from the top. Coordinates are local:
//! `(value + offset) * scale` per axis, the default z scale -1 turning elevations into
//! depths. Corner lines hold bottom then top point per pillar. Each node of a pillar
//! holds 1, 2, 4 or 8 z values (`splitEnz`): 1 shared by the 8 cells around it, 2 one
//! for the cells below and one above, 4 one per quadrant (south-west, south-east,
//! north-west, north-east), 8 the quadrants below then above. xtgeo reads only 1 and 4;
//! every cell keeping its own 8 depths, strata reads all four.

use super::tags::{Key, Place, Roff, Tag, Values};
use crate::{CornerPointGrid, Dims, Result};

/// A tag, its 1-based number and the key asked for, or `None`.
fn find<'r>(roff: &'r Roff, tag: &str, key: &str) -> Option<(usize, &'r Tag, &'r Key)> {
    roff.tags.iter().enumerate().find_map(|(n, t)| {
        (t.name == tag)
            .then(|| t.key(key).map(|k| (n + 1, t, k)))
            .flatten()
    })
}

fn missing(place: &Place, tag: &str, key: &str) -> crate::Error {
    place.error(
        0,
        &format!("{tag}/{key}"),
        0,
        "missing: this is not a complete ROFF grid or parameter file",
    )
}

/// What the file says it holds: `grid`, `parameter`, ... (None when it does not say).
pub fn filetype(roff: &Roff) -> Option<&str> {
    match find(roff, "filedata", "filetype").map(|(_, _, k)| &k.values) {
        Some(Values::Char(v)) => v.first().map(String::as_str),
        _ => None,
    }
}

fn single_int(place: &Place, roff: &Roff, tag: &str, key: &str) -> Result<i64> {
    let (no, _, k) = find(roff, tag, key).ok_or_else(|| missing(place, tag, key))?;
    match &k.values {
        Values::Int(v) if v.len() == 1 => Ok(i64::from(v[0])),
        v => Err(place.error(
            no,
            &format!("{tag}/{key}"),
            k.at,
            format!("expected one int, found {} {}", v.len(), v.type_name()),
        )),
    }
}

fn single_float(place: &Place, roff: &Roff, tag: &str, key: &str, default: f64) -> Result<f64> {
    let Some((no, _, k)) = find(roff, tag, key) else {
        return Ok(default);
    };
    match &k.values {
        Values::Float(v) if v.len() == 1 => Ok(f64::from(v[0])),
        Values::Double(v) if v.len() == 1 => Ok(v[0]),
        v => Err(place.error(
            no,
            &format!("{tag}/{key}"),
            k.at,
            format!("expected one float, found {} {}", v.len(), v.type_name()),
        )),
    }
}

/// The grid dimensions (`dimensions/nX`, `nY`, `nZ`).
pub fn dims(place: &Place, roff: &Roff) -> Result<Dims> {
    let mut d = [0usize; 3];
    for (v, key) in d.iter_mut().zip(["nX", "nY", "nZ"]) {
        let n = single_int(place, roff, "dimensions", key)?;
        *v = usize::try_from(n).ok().filter(|&n| n > 0).ok_or_else(|| {
            place.error(
                0,
                &format!("dimensions/{key}"),
                0,
                format!("{n} is not a positive size"),
            )
        })?;
    }
    Dims::new(d[0], d[1], d[2]).map_err(|e| place.error(0, "dimensions", 0, e.to_string()))
}

/// The array `tag/key`, its type checked by `pick` and its length against `len`.
fn array<'r, T>(
    place: &Place,
    roff: &'r Roff,
    (tag, key): (&str, &str),
    len: usize,
    pick: impl Fn(&'r Values) -> Option<&'r [T]>,
) -> Result<Option<&'r [T]>> {
    let Some((no, _, k)) = find(roff, tag, key) else {
        return Ok(None);
    };
    let keyword = format!("{tag}/{key}");
    let v = pick(&k.values).ok_or_else(|| {
        place.error(
            no,
            &keyword,
            k.at,
            format!("unexpected type {}", k.values.type_name()),
        )
    })?;
    if v.len() != len {
        return Err(place.error(
            no,
            &keyword,
            k.at,
            format!("{} values, the dimensions need {len}", v.len()),
        ));
    }
    Ok(Some(v))
}

/// Cells along I taken together when reordering (see [`reorder`]): 64 one-byte
/// values fill a cache line of the output.
const CELL_BLOCK: usize = 64;

/// Per-cell values from ROFF order (I slowest, K fastest from the bottom) to strata's
/// (I fastest, K from the top), each mapped by `convert`. A block of I is taken J by
/// J, so that the lines of the output the block writes stay in the cache until it
/// has filled them, where a cell at a time would write one value per line of every
/// layer. `values` holds one value per cell of `d` (the callers check its length).
pub(super) fn reorder<T: Copy, U: Copy>(
    d: Dims,
    values: &[T],
    fill: U,
    convert: impl Fn(T) -> U,
) -> Vec<U> {
    let mut out = vec![fill; values.len()];
    let (nx, ny, nz) = (d.nx, d.ny, d.nz);
    for i0 in (0..nx).step_by(CELL_BLOCK) {
        for j in 0..ny {
            for i in i0..(i0 + CELL_BLOCK).min(nx) {
                let column = &values[(i * ny + j) * nz..][..nz];
                for (kr, &v) in column.iter().enumerate() {
                    out[d.cell_index(i, j, nz - 1 - kr)] = convert(v);
                }
            }
        }
    }
    out
}

/// The grid a ROFF grid file describes, with its parameters when `with_parameters`.
pub fn grid(place: &Place, roff: &Roff, with_parameters: bool) -> Result<CornerPointGrid> {
    let d = dims(place, roff)?;
    let mut off = [0.0; 3];
    let mut scale = [1.0, 1.0, -1.0];
    for a in 0..3 {
        let axis = ["x", "y", "z"][a];
        off[a] = single_float(place, roff, "translate", &format!("{axis}offset"), 0.0)?;
        scale[a] = single_float(place, roff, "scale", &format!("{axis}scale"), scale[a])?;
    }
    let pillars = (d.nx + 1) * (d.ny + 1);
    let lines = array(
        place,
        roff,
        ("cornerLines", "data"),
        6 * pillars,
        |v| match v {
            Values::Float(f) => Some(f.as_slice()),
            _ => None,
        },
    )?
    .ok_or_else(|| missing(place, "cornerLines", "data"))?;
    let mut coord = vec![0.0; 6 * pillars];
    for pi in 0..=d.nx {
        for pj in 0..=d.ny {
            let src = &lines[6 * (pi * (d.ny + 1) + pj)..][..6];
            let dst = &mut coord[6 * (pj * (d.nx + 1) + pi)..][..6];
            for a in 0..3 {
                dst[a] = (f64::from(src[3 + a]) + off[a]) * scale[a]; // top
                dst[3 + a] = (f64::from(src[a]) + off[a]) * scale[a]; // bottom
            }
        }
    }
    let zcorn = super::zcorn::expand(place, roff, d, off[2], scale[2])?;
    let active = array(
        place,
        roff,
        ("active", "data"),
        d.cell_count(),
        |v| match v {
            Values::Bool(b) | Values::Byte(b) => Some(b.as_slice()),
            _ => None,
        },
    )?;
    let actnum = active.map(|a| reorder(d, a, false, |b| b != 0));
    let mut grid = CornerPointGrid::from_arrays(d, coord, zcorn, actnum)
        .map_err(|e| place.error(0, "cornerLines", 0, e.to_string()))?;
    grid.zones = zones(place, roff, d)?;
    if with_parameters {
        for p in super::params::parameters(place, roff, d)? {
            super::params::add(&mut grid, p, place.path)?;
        }
    }
    Ok(grid)
}

/// One zone name per layer from `subgrids/nLayers` (counted from the top), named
/// `subgrid_0`, `subgrid_1`, ... as xtgeo names them; empty when there are none.
fn zones(place: &Place, roff: &Roff, d: Dims) -> Result<Vec<String>> {
    let Some((no, _, k)) = find(roff, "subgrids", "nLayers") else {
        return Ok(Vec::new());
    };
    let err = |m: String| place.error(no, "subgrids/nLayers", k.at, m);
    let Values::Int(counts) = &k.values else {
        return Err(err(format!("unexpected type {}", k.values.type_name())));
    };
    let total: i64 = counts.iter().map(|&c| i64::from(c)).sum();
    if counts.iter().any(|&c| c < 0) || total != d.nz as i64 {
        return Err(err(format!(
            "layer counts {counts:?} do not add up to nZ = {}",
            d.nz
        )));
    }
    Ok(counts
        .iter()
        .enumerate()
        .flat_map(|(z, &c)| std::iter::repeat_n(format!("subgrid_{z}"), c as usize))
        .collect())
}
