//! Per-cell arrays of a deck (properties, ACTNUM, DX/DY/DZ/TOPS) and the edits
//! decks apply to them: `BOX`, `EQUALS`, `MULTIPLY`, `ADD`, `COPY`.
//!
//! Every array is kept over all cells in file order (`i` fastest), NaN where the
//! deck never gave a value, so that values given in a box, a top layer only, or by
//! `EQUALS` over part of the grid can be combined in the order the deck gives them.

use std::collections::BTreeMap;

use crate::Dims;

/// A box of cells, 0-based and half-open per axis `[i, j, k]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Region {
    pub lo: [usize; 3],
    pub hi: [usize; 3],
}

impl Region {
    pub fn all(d: Dims) -> Self {
        Region {
            lo: [0; 3],
            hi: [d.nx, d.ny, d.nz],
        }
    }

    /// The top layer (`k = 0`) of the whole grid.
    pub fn top_layer(d: Dims) -> Self {
        Region {
            lo: [0; 3],
            hi: [d.nx, d.ny, 1],
        }
    }

    pub fn len(&self) -> usize {
        (0..3).map(|a| self.hi[a] - self.lo[a]).product()
    }

    /// From 1-based inclusive bounds `i1 i2 j1 j2 k1 k2`, each `None` when defaulted
    /// (taken from `default`). Checked against the grid: `Err` explains the problem.
    pub fn from_bounds(
        bounds: [Option<usize>; 6],
        default: Region,
        d: Dims,
    ) -> Result<Region, String> {
        let n = [d.nx, d.ny, d.nz];
        let mut r = default;
        for a in 0..3 {
            let lo = bounds[2 * a].map_or(r.lo[a] + 1, |v| v);
            let hi = bounds[2 * a + 1].map_or(r.hi[a], |v| v);
            if lo < 1 || lo > hi || hi > n[a] {
                return Err(format!(
                    "box {}{lo}..{hi} is not within 1..{} or is empty",
                    ["I", "J", "K"][a],
                    n[a]
                ));
            }
            r.lo[a] = lo - 1;
            r.hi[a] = hi;
        }
        Ok(r)
    }

    /// Linear cell indices of the region, `i` fastest.
    pub fn indices(self, d: Dims) -> impl Iterator<Item = usize> {
        let [i0, j0, k0] = self.lo;
        let [i1, j1, k1] = self.hi;
        (k0..k1).flat_map(move |k| {
            (j0..j1).flat_map(move |j| (i0..i1).map(move |i| d.cell_index(i, j, k)))
        })
    }
}

/// The arrays of a deck, by upper-case keyword.
pub(super) struct Cells {
    pub dims: Dims,
    pub arrays: BTreeMap<String, Vec<f32>>,
}

impl Cells {
    pub fn new(dims: Dims) -> Self {
        Cells {
            dims,
            arrays: BTreeMap::new(),
        }
    }

    /// Does assigning into `region` need a new full-size array (which the caller
    /// must budget for)?
    pub fn needs_allocation(&self, name: &str, region: Region) -> bool {
        region != Region::all(self.dims) && !self.arrays.contains_key(name)
    }

    /// Stores `values` (one per cell of `region`, in region order) into `name`.
    pub fn assign(&mut self, name: &str, region: Region, values: Vec<f32>) {
        if region == Region::all(self.dims) {
            self.arrays.insert(name.to_string(), values);
            return;
        }
        let dims = self.dims;
        let array = self.array_mut(name);
        for (cell, v) in region.indices(dims).zip(values) {
            array[cell] = v;
        }
    }

    /// `EQUALS`: sets `name` to `value` over `region`, creating it if needed.
    pub fn equals(&mut self, name: &str, value: f32, region: Region) {
        let dims = self.dims;
        let array = self.array_mut(name);
        for cell in region.indices(dims) {
            array[cell] = value;
        }
    }

    /// `MULTIPLY` and `ADD`: `f` applied over `region`. `Err` when the array does
    /// not exist (a deck may only edit what it defined).
    pub fn update(
        &mut self,
        name: &str,
        region: Region,
        f: impl Fn(f32) -> f32,
    ) -> Result<(), String> {
        let dims = self.dims;
        let array = self
            .arrays
            .get_mut(name)
            .ok_or_else(|| format!("{name} is not defined before it is edited"))?;
        for cell in region.indices(dims) {
            array[cell] = f(array[cell]);
        }
        Ok(())
    }

    /// `COPY`: `src` into `dst` over `region`.
    pub fn copy(&mut self, src: &str, dst: &str, region: Region) -> Result<(), String> {
        let dims = self.dims;
        let from = self
            .arrays
            .get(src)
            .ok_or_else(|| format!("{src} is not defined before it is copied"))?;
        let values: Vec<f32> = region.indices(dims).map(|c| from[c]).collect();
        self.assign(dst, region, values);
        Ok(())
    }

    fn array_mut(&mut self, name: &str) -> &mut Vec<f32> {
        let n = self.dims.cell_count();
        self.arrays
            .entry(name.to_string())
            .or_insert_with(|| vec![f32::NAN; n])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boxes_and_edits() {
        let d = Dims::new(3, 2, 2).unwrap();
        let all = Region::all(d);
        let b =
            Region::from_bounds([Some(2), Some(3), None, None, Some(2), Some(2)], all, d).unwrap();
        assert_eq!(b.len(), 4);
        assert_eq!(b.indices(d).collect::<Vec<_>>(), [7, 8, 10, 11]);
        let err = Region::from_bounds([Some(0), None, None, None, None, None], all, d);
        assert!(err.unwrap_err().contains("I0..3"));
        assert!(Region::from_bounds([None, Some(4), None, None, None, None], all, d).is_err());

        let mut c = Cells::new(d);
        c.equals("PORO", 0.5, b);
        c.update("PORO", all, |v| v * 2.0).unwrap();
        assert_eq!(c.arrays["PORO"][7], 1.0);
        assert!(c.arrays["PORO"][0].is_nan());
        c.copy("PORO", "NTG", b).unwrap();
        c.assign("NTG", Region::top_layer(d), vec![0.0; 6]);
        assert_eq!(c.arrays["NTG"][11], 1.0);
        assert_eq!(c.arrays["NTG"][5], 0.0);
        assert!(c.update("PERMX", all, |v| v).unwrap_err().contains("PERMX"));
        assert!(c.copy("PERMX", "X", all).is_err());
    }
}
