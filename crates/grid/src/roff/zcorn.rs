//! ROFF z values with split nodes to Eclipse ZCORN (see the model module's notes).

use super::tags::{Place, Roff, Values};
use crate::{Dims, Result};

/// The values a node gives to the 8 cells around it: south-west, south-east,
/// north-west, north-east below the node, then the same above it.
fn node_values(split: u8, z: &[f32]) -> Option<[f32; 8]> {
    Some(match (split, z.len()) {
        (1, 1) => [z[0]; 8],
        (2, 2) => [z[0], z[0], z[0], z[0], z[1], z[1], z[1], z[1]],
        (4, 4) => [z[0], z[1], z[2], z[3], z[0], z[1], z[2], z[3]],
        (8, 8) => std::array::from_fn(|n| z[n]),
        _ => return None,
    })
}

/// Pillars along I taken together when spreading z values (see [`expand`]): eight
/// pillars fill a 64-byte line of ZCORN's 4-byte values.
const PILLAR_BLOCK: usize = 8;

/// The z values of `zvalues/data` spread over ZCORN (`[2 nz, 2 ny, 2 nx]`, flat) as
/// depths `(z + zoffset) * zscale`.
pub fn expand(place: &Place, roff: &Roff, d: Dims, zoff: f64, zscale: f64) -> Result<Vec<f32>> {
    let nodes = (d.nx + 1) * (d.ny + 1) * (d.nz + 1);
    let find = |key: &str| {
        roff.tags.iter().enumerate().find_map(|(n, t)| {
            (t.name == "zvalues")
                .then(|| t.key(key).map(|k| (n + 1, k)))
                .flatten()
        })
    };
    let missing = |key: &str| {
        place.error(
            0,
            &format!("zvalues/{key}"),
            0,
            "missing: a ROFF grid needs its z values",
        )
    };
    let (no, split_key) = find("splitEnz").ok_or_else(|| missing("splitEnz"))?;
    let (zno, z_key) = find("data").ok_or_else(|| missing("data"))?;
    let Values::Byte(split) = &split_key.values else {
        return Err(place.error(no, "zvalues/splitEnz", split_key.at, "expected bytes"));
    };
    let Values::Float(z) = &z_key.values else {
        return Err(place.error(zno, "zvalues/data", z_key.at, "expected floats"));
    };
    if split.len() != nodes {
        return Err(place.error(
            no,
            "zvalues/splitEnz",
            split_key.at,
            format!(
                "{} values, the dimensions need {nodes} (one per node)",
                split.len()
            ),
        ));
    }
    if let Some(n) = split.iter().position(|s| ![1, 2, 4, 8].contains(s)) {
        let (pi, pj, kr) = (
            n / ((d.ny + 1) * (d.nz + 1)),
            (n / (d.nz + 1)) % (d.ny + 1),
            n % (d.nz + 1),
        );
        let msg = format!(
            "split {} at node ({pi}, {pj}, {kr}); ROFF has 1, 2, 4 or 8",
            split[n]
        );
        return Err(place.error(no, "zvalues/splitEnz", split_key.at, msg));
    }
    let want: usize = split.iter().map(|&s| usize::from(s)).sum();
    if want != z.len() {
        return Err(place.error(
            zno,
            "zvalues/data",
            z_key.at,
            format!("{} z values, splitEnz asks for {want}", z.len()),
        ));
    }
    let (nx, ny, nz) = (d.nx, d.ny, d.nz);
    // Where each pillar's z values start (pillars with j fastest, as stored).
    let pillar_at: Vec<usize> = split
        .chunks_exact(nz + 1)
        .scan(0, |at, pillar| {
            let start = *at;
            *at += pillar.iter().map(|&s| usize::from(s)).sum::<usize>();
            Some(start)
        })
        .collect();
    let mut zcorn = vec![0.0f32; 8 * d.cell_count()];
    let depth = |v: f32| ((f64::from(v) + zoff) * zscale) as f32;
    let slab = 4 * nx * ny;
    // Pillars are taken a block of I at a time, J by J, and within that K by K: the
    // values of one node level of the block's pillars land side by side in a few
    // lines of ZCORN, where a pillar at a time would write one value per line of
    // every layer.
    for pi0 in (0..=nx).step_by(PILLAR_BLOCK) {
        let block = pi0..(pi0 + PILLAR_BLOCK).min(nx + 1);
        for pj in 0..=ny {
            let mut pillars = [(0usize, 0usize, [None; 4]); PILLAR_BLOCK];
            for (pillar, pi) in pillars.iter_mut().zip(block.clone()) {
                let p = pi * (ny + 1) + pj;
                // The ZCORN columns of the (up to four) cells around the pillar, by
                // quadrant: south-west, south-east, north-west, north-east.
                let mut columns = [None; 4];
                for (q, column) in columns.iter_mut().enumerate() {
                    let (ci, cj) = (
                        (pi + (q & 1)).wrapping_sub(1),
                        (pj + (q >> 1)).wrapping_sub(1),
                    );
                    if ci < nx && cj < ny {
                        *column = Some((2 * cj + pj - cj) * 2 * nx + 2 * ci + pi - ci);
                    }
                }
                *pillar = (p * (nz + 1), pillar_at[p], columns);
            }
            for kr in 0..=nz {
                for ((first_node, at, columns), pi) in pillars.iter_mut().zip(block.clone()) {
                    let s = split[*first_node + kr];
                    let values = &z[*at..*at + usize::from(s)];
                    *at += usize::from(s);
                    let v = node_values(s, values).ok_or_else(|| {
                        let msg =
                            format!("split {s} at node ({pi}, {pj}, {kr}); ROFF has 1, 2, 4 or 8");
                        place.error(no, "zvalues/splitEnz", split_key.at, msg)
                    })?;
                    let v = v.map(depth);
                    for (q, column) in columns.iter().enumerate() {
                        let Some(column) = column else { continue };
                        if kr >= 1 {
                            zcorn[2 * (nz - kr) * slab + column] = v[q];
                        }
                        if kr < nz {
                            zcorn[(2 * (nz - 1 - kr) + 1) * slab + column] = v[4 + q];
                        }
                    }
                }
            }
        }
    }
    Ok(zcorn)
}
