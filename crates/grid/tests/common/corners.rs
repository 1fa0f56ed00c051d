//! The reference corner files of `tests/reference/` (layout in `make_reference.py`):
//! 24 planes (3 * corner + axis), each `n` high bytes then `n` low bytes of the
//! wrapping u16 delta from the previous cell's quantized value.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use flate2::read::GzDecoder;

/// The folder of the reference files.
pub const REFERENCE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/reference");

/// The bytes of a gzipped reference file.
pub fn gunzip(name: &str) -> Vec<u8> {
    let path = Path::new(REFERENCE).join(name);
    let file = File::open(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut bytes = Vec::new();
    GzDecoder::new(file)
        .read_to_end(&mut bytes)
        .unwrap_or_else(|e| panic!("{path:?}: {e}"));
    bytes
}

/// Decoded reference corners of `cells` cells.
pub struct Corners {
    cells: usize,
    q: Vec<u16>,
    lo: [f64; 3],
    scale: [f64; 3],
}

impl Corners {
    /// Loads `file`, quantized between `lo` and `hi`.
    pub fn load(file: &str, cells: usize, lo: [f64; 3], hi: [f64; 3]) -> Self {
        let bytes = gunzip(file);
        assert_eq!(bytes.len(), 48 * cells, "{file}: size");
        let mut q = Vec::with_capacity(24 * cells);
        for plane in bytes.chunks_exact(2 * cells) {
            let (h, l) = plane.split_at(cells);
            let mut value = 0u16;
            for (&h, &l) in h.iter().zip(l) {
                value = value.wrapping_add(u16::from_be_bytes([h, l]));
                q.push(value);
            }
        }
        let scale = std::array::from_fn(|a| (hi[a] - lo[a]) / 65535.0);
        Corners {
            cells,
            q,
            lo,
            scale,
        }
    }

    /// Corner `c` (Eclipse order) of cell `cell` (file order), map x, y, depth.
    pub fn corner(&self, cell: usize, c: usize) -> [f64; 3] {
        std::array::from_fn(|a| {
            let q = self.q[(3 * c + a) * self.cells + cell];
            self.lo[a] + f64::from(q) * self.scale[a]
        })
    }
}
