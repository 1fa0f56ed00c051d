//! A selection's cells read back: which cells each selected node covers, the
//! property's value on each and at their corners, tile by tile, so that a renderer
//! colours and draws isolines on any level as on the model.

use rayon::prelude::*;

use super::format::NodeRecord;
use super::read::LodFile;
use crate::cover::cell_corners;
use crate::{CellCover, CoverPiece, Error, Result};

/// A selected node's box cut into tiles of the file's tile size, and where the values
/// of each tile asked for start among the node's (see [`LodFile::selection_values`]).
struct TileLayout {
    piece: CoverPiece,
    starts: Vec<Option<usize>>,
    /// Values of the node's tiles asked for.
    values: usize,
}

/// Sets the `len` bits of `dst` from bit `to` that are set in `src` from bit `from`
/// (bit `b` of a slice is bit `b % 32` of word `b / 32`), a word of `dst` at a time: a
/// row of a layer's faces into a box's bits.
fn copy_bits((src, from): (&[u32], usize), (dst, to): (&mut [u32], usize), len: usize) {
    let (mut from, mut to, mut left) = (from, to, len);
    while left > 0 {
        let n = (32 - to % 32).min(left);
        let (w, s) = (from / 32, from % 32);
        let mut chunk = src[w] >> s;
        if s + n > 32 {
            chunk |= src[w + 1] << (32 - s);
        }
        if n < 32 {
            chunk &= (1 << n) - 1;
        }
        dst[to / 32] |= chunk << (to % 32);
        (from, to, left) = (from + n, to + n, left - n);
    }
}

impl LodFile {
    /// The cells under the nodes `selection`, for drawing
    /// [`LodFile::selection_mesh`] coloured cell by cell as the model's faces are: a
    /// piece per node (its vertices in `vertex_piece`), whose box is the node's cells
    /// and whose bits its layer's faces there. `None` without a property.
    pub fn selection_cover(&self, selection: &[u32]) -> Result<Option<CellCover>> {
        if !self.has_scalars() {
            return Ok(None);
        }
        let ni = self.header.dims[0] as usize;
        let mut cover = CellCover::default();
        for &i in selection {
            let (n, mut piece) = self.node_box(i)?;
            let Some((faces, _)) = self.layer_cells(n.layer as usize) else {
                return Ok(None);
            };
            let [i0, j0, i1, j1] = n.cells.map(|c| c as usize);
            let mut bits = vec![0u32; piece.box_cells().div_ceil(32)];
            for (y, j) in (j0..j1).enumerate() {
                copy_bits((faces, j * ni + i0), (&mut bits, y * (i1 - i0)), i1 - i0);
            }
            let index = cover.pieces.len() as u32;
            cover
                .vertex_piece
                .extend(std::iter::repeat_n(index, n.vertex_count as usize));
            piece.bits = bits;
            cover.pieces.push(piece);
        }
        Ok(Some(cover))
    }

    /// The property's value on every cell of the boxes of
    /// [`LodFile::selection_cover`], each box cut into tiles of
    /// [`LodFile::tile_cells`] (its leaves' squares, see [`CoverPiece::tiles`]), tile
    /// after tile and node after node, each tile's cells row by row; NaN where the
    /// layer has no face. Only for the tiles that `wanted` marks, one flag per tile of
    /// each box in that order (all without it): a view needs the values of the part
    /// of the model it shows. `None` without a property.
    pub fn selection_values(
        &self,
        selection: &[u32],
        wanted: Option<&[bool]>,
    ) -> Result<Option<Vec<f32>>> {
        if !self.has_scalars() {
            return Ok(None);
        }
        let side = self.tile_cells();
        let ni = self.header.dims[0] as usize;
        let layouts = self.tile_layouts(selection, wanted, 1)?;
        let mut values = Vec::with_capacity(layouts.iter().map(|l| l.values).sum());
        for (&i, layout) in selection.iter().zip(&layouts) {
            let n = self.node(i)?;
            let Some((_, layer_values)) = self.layer_cells(n.layer as usize) else {
                return Ok(None);
            };
            let piece = &layout.piece;
            for t in (0..layout.starts.len()).filter(|&t| layout.starts[t].is_some()) {
                let [x0, y0, x1, y1] = piece.tile_box(side, t).map(|c| c as usize);
                let [i0, j0] = [n.cells[0] as usize, n.cells[1] as usize];
                for j in j0 + y0..j0 + y1 {
                    let row = j * ni + i0;
                    values.extend_from_slice(&layer_values[row + x0..row + x1]);
                }
            }
        }
        Ok(Some(values))
    }

    /// The stored scalar at the four corners of every cell of the boxes of
    /// [`LodFile::selection_cover`] (each cell's as [`CellCover::corner_values`]
    /// orders them), read from the full-resolution leaves under each selected node,
    /// tile after tile as [`LodFile::selection_values`] gives values: with them the
    /// renderer draws the isolines of the model's surfaces on whatever level is
    /// chosen. Only for the tiles that `wanted` marks: the leaves under the others
    /// are not read. `None` without a property.
    pub fn selection_corners(
        &self,
        selection: &[u32],
        wanted: Option<&[bool]>,
    ) -> Result<Option<Vec<f32>>> {
        if !self.has_scalars() {
            return Ok(None);
        }
        let layouts = self.tile_layouts(selection, wanted, 4)?;
        let mut corners = vec![f32::NAN; layouts.iter().map(|l| l.values).sum()];
        let mut boxes = Vec::with_capacity(layouts.len());
        let mut rest = &mut corners[..];
        for layout in &layouts {
            let (this, next) = rest.split_at_mut(layout.values);
            boxes.push(this);
            rest = next;
        }
        selection
            .par_iter()
            .zip(&layouts)
            .zip(boxes)
            .filter(|(_, out)| !out.is_empty())
            .try_for_each(|((&i, layout), out)| self.node_corners(i, layout, out))?;
        Ok(Some(corners))
    }

    /// Per node of `selection`, its box cut into tiles and where the values of the
    /// tiles that `wanted` marks (one flag per tile of each box, node after node; all
    /// without it) start among the node's, `per_cell` to a cell.
    fn tile_layouts(
        &self,
        selection: &[u32],
        wanted: Option<&[bool]>,
        per_cell: usize,
    ) -> Result<Vec<TileLayout>> {
        let side = self.tile_cells();
        let pieces = selection
            .iter()
            .map(|&i| Ok(self.node_box(i)?.1))
            .collect::<Result<Vec<CoverPiece>>>()?;
        let tiles: usize = pieces.iter().map(|p| p.tile_count(side)).sum();
        if let Some(wanted) = wanted
            && wanted.len() != tiles
        {
            return Err(Error::Option(format!(
                "{} tiles marked of a selection of {tiles}",
                wanted.len()
            )));
        }
        let mut first_tile = 0;
        Ok(pieces
            .into_iter()
            .map(|piece| {
                let mut values = 0;
                let starts = (0..piece.tile_count(side))
                    .map(|t| {
                        wanted.is_none_or(|w| w[first_tile + t]).then(|| {
                            let start = values;
                            values += per_cell * piece.tile_cells(side, t);
                            start
                        })
                    })
                    .collect();
                first_tile += piece.tile_count(side);
                TileLayout {
                    piece,
                    starts,
                    values,
                }
            })
            .collect())
    }

    /// Node `i` and the box of its cells as a piece of a selection's cover (no bits
    /// yet).
    fn node_box(&self, i: u32) -> Result<(&NodeRecord, CoverPiece)> {
        let n = self.node(i)?;
        let [i0, j0, i1, j1] = n.cells;
        let [Ok(oi), Ok(oj)] = [i0, j0].map(i32::try_from) else {
            return Err(self.damaged(
                self.node_record_at(i),
                format!("node {i}: cells from ({i0}, {j0}) are beyond a cell cover's reach"),
            ));
        };
        let piece = CoverPiece {
            origin: [oi, oj],
            size: [i1.saturating_sub(i0), j1.saturating_sub(j0)],
            bits: Vec::new(),
        };
        Ok((n, piece))
    }

    /// [`LodFile::selection_corners`] of node `i`, whose box is `piece`, into `out`,
    /// four per cell of each tile of the box that `starts` gives a place in `out`; the
    /// leaves under the other tiles are not read.
    fn node_corners(&self, i: u32, layout: &TileLayout, out: &mut [f32]) -> Result<()> {
        let TileLayout { piece, starts, .. } = layout;
        let side = self.tile_cells().max(1);
        let across = piece.tiles(side)[0];
        // Does the box of node `m` hold a tile that `starts` places?
        let wanted = |m: &NodeRecord| {
            let [i0, j0, i1, j1] = m.cells;
            let rel = |c: u32, o: i32| (i64::from(c) - i64::from(o)).max(0) as u64;
            let lo = [rel(i0, piece.origin[0]), rel(j0, piece.origin[1])];
            let hi = [rel(i1, piece.origin[0]), rel(j1, piece.origin[1])];
            let side = u64::from(side);
            (lo[1] / side..hi[1].div_ceil(side)).any(|ty| {
                (lo[0] / side..hi[0].div_ceil(side).min(u64::from(across))).any(|tx| {
                    starts
                        .get((ty * u64::from(across) + tx) as usize)
                        .is_some_and(Option::is_some)
                })
            })
        };
        let mut stack = vec![i];
        while let Some(k) = stack.pop() {
            let m = self.node(k)?;
            if !wanted(m) {
                continue;
            }
            if m.level > 0 {
                stack.extend(m.first_child..m.first_child + m.child_count);
                continue;
            }
            let vertices = self.vertices(k as usize);
            let indices = self.indices(k as usize);
            for t in 0..indices.len() / 3 {
                let tri = [0, 1, 2].map(|c| vertices.get(indices.get(3 * t + c) as usize));
                let [Some(a), Some(b), Some(c)] = tri else {
                    return Err(self.damaged(
                        m.data_offset,
                        format!("node {k}: triangle {t} names a vertex the node does not have"),
                    ));
                };
                let tri = [a, b, c];
                let slot = cell_corners(tri.map(|v| v.texcoord))
                    .and_then(|(cell, at)| Some((piece.tile_slot(side, cell)?, at)));
                let Some(((tile, slot), at)) = slot else {
                    return Err(self.damaged(
                        m.data_offset,
                        format!("node {k}: triangle {t} is not a half of a cell of node {i}"),
                    ));
                };
                if let Some(start) = starts[tile] {
                    for (v, c) in tri.iter().zip(at) {
                        out[start + 4 * slot + c] = v.scalar;
                    }
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_are_copied_at_any_offsets_as_one_by_one() {
        // A pattern with runs and isolated bits, no period of 32.
        let src: Vec<u32> = (0..6u32)
            .map(|k| k.wrapping_mul(0x9E37_79B9) ^ 0x0F0F_3C3C)
            .collect();
        let bit = |v: &[u32], b: usize| v[b / 32] >> (b % 32) & 1;
        for from in [0, 1, 31, 32, 33, 70] {
            for to in [0, 5, 31, 32, 63] {
                for len in [0, 1, 7, 31, 32, 33, 64, 100] {
                    let mut dst = vec![0u32; 6];
                    copy_bits((&src, from), (&mut dst, to), len);
                    let mut want = vec![0u32; 6];
                    for b in 0..len {
                        want[(to + b) / 32] |= bit(&src, from + b) << ((to + b) % 32);
                    }
                    assert_eq!(dst, want, "from {from}, to {to}, {len} bits");
                }
            }
        }
    }
}
