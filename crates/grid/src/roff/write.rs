//! Writes a grid as a little-endian binary ROFF file, as xtgeo writes one: map
//! coordinates (MAPAXES applied, ROFF has none) relative to whole-metre offsets so that
//! float32 keeps UTM coordinates precise, depths as elevations (`zscale` -1), each node
//! with the fewest z values that keep every cell's own depths (split 1 or 4 where
//! layers meet without a gap, which xtgeo reads; 2 or 8 otherwise), subgrids from the
//! runs of zone names, and every property, discrete ones (those with codes) as `int`
//! with their code names.

use std::path::Path;

use crate::{CornerPointGrid, Error, Result};

/// A ROFF binary buffer being written.
struct Out(Vec<u8>);

impl Out {
    fn word(&mut self, w: &str) {
        self.0.extend_from_slice(w.as_bytes());
        self.0.push(0);
    }

    fn tag(&mut self, name: &str) {
        self.word("tag");
        self.word(name);
    }

    fn key(&mut self, ty: &str, name: &str) {
        self.word(ty);
        self.word(name);
    }

    fn int(&mut self, name: &str, v: i32) {
        self.key("int", name);
        self.0.extend_from_slice(&v.to_le_bytes());
    }

    fn float(&mut self, name: &str, v: f32) {
        self.key("float", name);
        self.0.extend_from_slice(&v.to_le_bytes());
    }

    fn array(&mut self, ty: &str, name: &str, len: usize) {
        self.word("array");
        self.key(ty, name);
        // Dimensions were checked when the grid was built; a count past i32 is refused
        // by `to_bytes` before any array is written.
        self.0.extend_from_slice(&(len as i32).to_le_bytes());
    }

    fn floats(&mut self, name: &str, v: &[f32]) {
        self.array("float", name, v.len());
        v.iter()
            .for_each(|x| self.0.extend_from_slice(&x.to_le_bytes()));
    }

    fn ints(&mut self, name: &str, v: &[i32]) {
        self.array("int", name, v.len());
        v.iter()
            .for_each(|x| self.0.extend_from_slice(&x.to_le_bytes()));
    }

    fn bytes(&mut self, ty: &str, name: &str, v: &[u8]) {
        self.array(ty, name, v.len());
        self.0.extend_from_slice(v);
    }
}

/// The node values around node (pi, pj, kr) of ROFF numbering, as in the model module:
/// south-west, south-east, north-west, north-east below, then above; `None` for cells
/// outside the grid.
fn around(grid: &CornerPointGrid, pi: usize, pj: usize, kr: usize) -> [Option<f32>; 8] {
    let d = grid.dims();
    std::array::from_fn(|n| {
        let q = n % 4;
        let (ci, cj) = (
            (pi + (q & 1)).wrapping_sub(1),
            (pj + (q >> 1)).wrapping_sub(1),
        );
        let above = n >= 4;
        if ci >= d.nx || cj >= d.ny || (!above && kr == 0) || (above && kr == d.nz) {
            return None;
        }
        // Below the node: the node is the top of that cell; above: its bottom.
        let (k, dk) = if above {
            (d.nz - 1 - kr, 1)
        } else {
            (d.nz - kr, 0)
        };
        let c = (pi - ci) + 2 * (pj - cj) + 4 * dk;
        Some(-grid.corner_depth(ci, cj, k, c))
    })
}

/// The fewest values that give every existing cell around a node its own z.
fn split(v: [Option<f32>; 8]) -> Vec<f32> {
    let any = v.iter().flatten().copied().next().unwrap_or(0.0);
    let same = |a: &[Option<f32>]| {
        let mut it = a.iter().flatten();
        let first = it.next().copied();
        it.all(|x| Some(*x) == first).then(|| first.unwrap_or(any))
    };
    if let Some(z) = same(&v) {
        return vec![z];
    }
    let quads: Option<Vec<f32>> = (0..4)
        .map(|q| match (v[q], v[4 + q]) {
            (Some(a), Some(b)) => (a == b).then_some(a),
            (a, b) => Some(a.or(b).unwrap_or(any)),
        })
        .collect();
    if let Some(q) = quads {
        return q;
    }
    if let (Some(b), Some(a)) = (same(&v[..4]), same(&v[4..])) {
        return vec![b, a];
    }
    v.iter().map(|z| z.unwrap_or(any)).collect()
}

/// The ROFF binary bytes of a grid.
pub fn to_bytes(grid: &CornerPointGrid, path: &Path) -> Result<Vec<u8>> {
    let d = grid.dims();
    let nodes = (d.nx + 1) * (d.ny + 1) * (d.nz + 1);
    if i32::try_from(nodes.max(8 * d.cell_count())).is_err() {
        return Err(Error::model(path, "", "too many cells for a ROFF file"));
    }
    let mut o = Out(Vec::with_capacity(64 * nodes));
    o.0.extend_from_slice(b"roff-bin\0#ROFF file#\0#Creator: strata#\0");
    o.tag("filedata");
    o.int("byteswaptest", 1);
    o.key("char", "filetype");
    o.word("grid");
    o.word("endtag");
    o.tag("version");
    o.int("major", 2);
    o.int("minor", 0);
    o.word("endtag");
    o.tag("dimensions");
    for (k, n) in [("nX", d.nx), ("nY", d.ny), ("nZ", d.nz)] {
        o.int(k, n as i32);
    }
    o.word("endtag");
    geometry(&mut o, grid);
    properties(&mut o, grid);
    o.tag("eof");
    o.word("endtag");
    Ok(o.0)
}

/// Translate, scale, subgrids, corner lines, z values and active cells.
fn geometry(o: &mut Out, grid: &CornerPointGrid) {
    let d = grid.dims();
    let pillar = |pi: usize, pj: usize| {
        let p = grid.pillar(pi, pj);
        [
            grid.to_map([p[0], p[1], p[2]]),
            grid.to_map([p[3], p[4], p[5]]),
        ]
    };
    // The offsets are float32 in the file: measure from what will be read back.
    let origin = pillar(0, 0)[0].map(|v| f64::from(v.round() as f32));
    o.tag("translate");
    o.float("xoffset", origin[0] as f32);
    o.float("yoffset", origin[1] as f32);
    o.float("zoffset", 0.0);
    o.word("endtag");
    o.tag("scale");
    o.float("xscale", 1.0);
    o.float("yscale", 1.0);
    o.float("zscale", -1.0);
    o.word("endtag");
    if grid.zones.len() == d.nz {
        let mut runs: Vec<i32> = Vec::new();
        for (k, z) in grid.zones.iter().enumerate() {
            match runs.last_mut() {
                Some(n) if grid.zones[k - 1] == *z => *n += 1,
                _ => runs.push(1),
            }
        }
        o.tag("subgrids");
        o.ints("nLayers", &runs);
        o.word("endtag");
    }
    let mut lines = Vec::with_capacity(6 * (d.nx + 1) * (d.ny + 1));
    for pi in 0..=d.nx {
        for pj in 0..=d.ny {
            let [top, bottom] = pillar(pi, pj);
            for p in [bottom, top] {
                lines.extend([
                    (p[0] - origin[0]) as f32,
                    (p[1] - origin[1]) as f32,
                    -p[2] as f32,
                ]);
            }
        }
    }
    o.tag("cornerLines");
    o.floats("data", &lines);
    o.word("endtag");
    let (mut splits, mut z) = (Vec::new(), Vec::new());
    for pi in 0..=d.nx {
        for pj in 0..=d.ny {
            for kr in 0..=d.nz {
                let v = split(around(grid, pi, pj, kr));
                splits.push(v.len() as u8);
                z.extend(v);
            }
        }
    }
    o.tag("zvalues");
    o.bytes("byte", "splitEnz", &splits);
    o.floats("data", &z);
    o.word("endtag");
    let act: Vec<bool> = grid.actnum.iter().copied().collect();
    let active = roff_order(d, |c| u8::from(act[c]));
    o.tag("active");
    o.bytes("bool", "data", &active);
    o.word("endtag");
}

/// Values per cell in ROFF order (`i` slowest, `k` fastest from the bottom) from a
/// function of strata's linear cell index.
fn roff_order<T>(d: crate::Dims, of: impl Fn(usize) -> T) -> Vec<T> {
    let mut out = Vec::with_capacity(d.cell_count());
    for i in 0..d.nx {
        for j in 0..d.ny {
            for kr in 0..d.nz {
                out.push(of(d.cell_index(i, j, d.nz - 1 - kr)));
            }
        }
    }
    out
}

/// One `parameter` tag per property: discrete ones (with codes) as `int` with -999 for
/// undefined and their code names, the others as `float` with -999.0.
fn properties(o: &mut Out, grid: &CornerPointGrid) {
    let d = grid.dims();
    for (name, values) in &grid.properties {
        let flat: Vec<f32> = values.iter().copied().collect();
        o.tag("parameter");
        o.key("char", "name");
        o.word(name);
        if let Some(codes) = grid.codes.get(name) {
            if !codes.is_empty() {
                o.array("char", "codeNames", codes.len());
                codes.values().for_each(|n| o.word(n));
                o.ints("codeValues", &codes.keys().copied().collect::<Vec<_>>());
            }
            let v = roff_order(d, |c| {
                if flat[c].is_nan() {
                    -999
                } else {
                    flat[c] as i32
                }
            });
            o.ints("data", &v);
        } else {
            let v = roff_order(d, |c| if flat[c].is_nan() { -999.0 } else { flat[c] });
            o.floats("data", &v);
        }
        o.word("endtag");
    }
}

/// Writes a grid as a binary ROFF file.
pub fn write(grid: &CornerPointGrid, path: &Path) -> Result<()> {
    let bytes = to_bytes(grid, path)?;
    std::fs::write(path, bytes).map_err(|e| Error::io(path, e))
}
