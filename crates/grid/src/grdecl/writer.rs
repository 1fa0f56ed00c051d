//! The GRDECL writer: MAPUNITS/MAPAXES, GRIDUNIT, SPECGRID, COORD, ZCORN, ACTNUM and
//! every property, as Eclipse, resdata and xtgeo read them.
//!
//! Arrays are formatted in parallel, in pieces of [`PIECE`] values, a wave of pieces
//! at a time, and streamed through one `BufWriter`: a 1000 x 1000 x 100 grid (3.2 GB
//! of ZCORN) never has more than one wave of text in memory, at most [`MAX_WAVE`]
//! pieces however many cores there are. Runs of three or more equal values are
//! written `N*v`, undefined (NaN) property values as `N*`.
//! Floats are written as short as fixed notation allows while still reading back
//! bit for bit (`f32` ZCORN and properties, `f64` COORD and MAPAXES), see
//! [`put_float`]; infinities as `1e39` / `1e309`.

use std::borrow::Cow;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use ndarray::Array3;
use rayon::prelude::*;

use super::deck::is_special;
use super::lex::keyword;
use super::numbers::{Num, POW10};
use crate::{CornerPointGrid, Error, Result};

/// Values per parallel piece.
const PIECE: usize = 1 << 16;

/// Most pieces formatted at once: about 40 MB of text however many cores format
/// them, as a wave of four pieces a thread would grow with the machine.
const MAX_WAVE: usize = 64;
/// Lines are kept within this many bytes; Eclipse ignores anything past column 132.
const LINE: usize = 100;
/// Shortest run written as `N*v`: `2*5` is no shorter than `5 5`.
const RUN: usize = 3;

/// Writes `grid` to `path`.
pub(super) fn write(grid: &CornerPointGrid, path: &Path) -> Result<()> {
    for name in grid.properties.keys() {
        // `--` would start a comment in the middle of the name.
        if keyword(name.as_bytes()).as_deref() != Some(name.as_str())
            || name.contains("--")
            || is_special(name)
        {
            return Err(Error::Invalid(format!(
                "property {name} cannot be written to GRDECL: a keyword is 1 to 8 upper-case \
                 letters, digits, '_', '-' or '+', starting with a letter, and not one of the \
                 grid keywords"
            )));
        }
    }
    let file = File::create(path).map_err(|e| Error::io(path, e))?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    write_deck(grid, &mut w)
        .and_then(|()| w.flush())
        .map_err(|e| Error::io(path, e))
}

fn write_deck(grid: &CornerPointGrid, w: &mut impl Write) -> io::Result<()> {
    let d = grid.dims();
    writeln!(w, "-- Written by strata {}", env!("CARGO_PKG_VERSION"))?;
    let unit = grid.units.eclipse_name();
    if let Some(m) = &grid.mapaxes {
        writeln!(w, "\nMAPUNITS\n  '{unit}' /\n\nMAPAXES")?;
        let mut text = Vec::new();
        for pair in m.values().chunks(2) {
            text.extend_from_slice(b" ");
            for v in pair {
                text.push(b' ');
                v.put(&mut text);
            }
            text.push(b'\n');
        }
        w.write_all(&text)?;
        writeln!(w, "/")?;
    }
    writeln!(w, "\nGRIDUNIT\n  '{unit}' '  ' /")?;
    writeln!(w, "\nSPECGRID\n  {} {} {} 1 F /", d.nx, d.ny, d.nz)?;
    values(w, "COORD", &grid.coord)?;
    values(w, "ZCORN", &grid.zcorn)?;
    values(w, "ACTNUM", &grid.actnum)?;
    for (name, array) in &grid.properties {
        values(w, name, array)?;
    }
    Ok(())
}

/// Writes one keyword and its values in file order, formatting pieces in parallel.
fn values<T: Put>(w: &mut impl Write, name: &str, array: &Array3<T>) -> io::Result<()> {
    writeln!(w, "\n{name}")?;
    // Arrays built by this crate are contiguous; anything else is copied once.
    let data: Cow<[T]> = match array.as_slice() {
        Some(s) => Cow::Borrowed(s),
        None => Cow::Owned(array.iter().copied().collect()),
    };
    let wave = PIECE * (4 * rayon::current_num_threads()).clamp(1, MAX_WAVE);
    for group in data.chunks(wave) {
        let texts: Vec<Vec<u8>> = group.par_chunks(PIECE).map(format_piece).collect();
        for t in &texts {
            w.write_all(t)?;
        }
    }
    writeln!(w, "/")
}

/// Formats one piece: tokens separated by spaces, lines wrapped at [`LINE`], a
/// newline at the end so pieces join cleanly.
fn format_piece<T: Put>(piece: &[T]) -> Vec<u8> {
    let mut out = Vec::with_capacity(piece.len() * 10);
    let mut col = 0;
    let mut i = 0;
    while i < piece.len() {
        let v = piece[i];
        let mut n = 1;
        while i + n < piece.len() && piece[i + n].same(v) {
            n += 1;
        }
        let (tokens, run) = if v.undefined() || n >= RUN {
            (1, n)
        } else {
            (n, 1)
        };
        for _ in 0..tokens {
            let sep = out.len();
            if col > 0 {
                out.push(b' ');
            }
            let start = out.len();
            if run > 1 || v.undefined() {
                put_int(run as u64, &mut out);
                out.push(b'*');
            }
            if !v.undefined() {
                v.put(&mut out);
            }
            let len = out.len() - start;
            if col > 0 && col + 1 + len > LINE {
                out[sep] = b'\n';
                col = len;
            } else {
                col += out.len() - sep;
            }
        }
        i += n;
    }
    out.push(b'\n');
    out
}

/// A value the writer can format.
trait Put: Copy + Send + Sync {
    /// Bitwise equality, so runs never merge values that read back differently.
    fn same(self, other: Self) -> bool;
    /// Undefined values (NaN) are written as defaults, `N*`.
    fn undefined(self) -> bool;
    fn put(self, out: &mut Vec<u8>);
}

impl Put for f32 {
    fn same(self, other: Self) -> bool {
        self.to_bits() == other.to_bits()
    }
    fn undefined(self) -> bool {
        self.is_nan()
    }
    /// Infinities are written as a number too large for `f32` (`1e39`), which reads
    /// back as infinity: a bare `inf` would look like a keyword.
    fn put(self, out: &mut Vec<u8>) {
        if self.is_infinite() {
            out.extend_from_slice(if self > 0.0 { b"1e39" } else { b"-1e39" });
            return;
        }
        let bits = self.to_bits();
        let reads_back = |r: f64| f32::from_rounded(r).is_some_and(|x| x.to_bits() == bits);
        put_float(
            f64::from(self),
            self.is_sign_negative(),
            12,
            reads_back,
            out,
            |o| {
                // Writing into a Vec cannot fail.
                let _ = if (1e-5..1e16).contains(&self.abs()) {
                    write!(o, "{self}")
                } else {
                    write!(o, "{self:e}")
                };
            },
        );
    }
}

impl Put for f64 {
    fn same(self, other: Self) -> bool {
        self.to_bits() == other.to_bits()
    }
    fn undefined(self) -> bool {
        self.is_nan()
    }
    /// Infinities as for `f32`, with `1e309`.
    fn put(self, out: &mut Vec<u8>) {
        if self.is_infinite() {
            out.extend_from_slice(if self > 0.0 { b"1e309" } else { b"-1e309" });
            return;
        }
        let reads_back = |r: f64| r.to_bits() == self.to_bits();
        put_float(self, self.is_sign_negative(), 17, reads_back, out, |o| {
            // Writing into a Vec cannot fail.
            let _ = if (1e-5..1e16).contains(&self.abs()) {
                write!(o, "{self}")
            } else {
                write!(o, "{self:e}")
            };
        });
    }
}

impl Put for bool {
    fn same(self, other: Self) -> bool {
        self == other
    }
    fn undefined(self) -> bool {
        false
    }
    fn put(self, out: &mut Vec<u8>) {
        out.push(if self { b'1' } else { b'0' });
    }
}

/// Whole numbers (most coordinates, many depths) take an integer path. Other values
/// are written with the fewest decimals `d <= max_decimals` for which
/// `m = round(v 10^d)` reads back as `v`: `reads_back` checks `m / 10^d` rounded to
/// `f64` the way the reader's plain-decimal path does ([`Num::from_rounded`]), and
/// a decimal that passes rounds to `v` under any correctly rounding parser. This is
/// several times faster than `{}`'s shortest-digit search, and as short in fixed
/// notation. What it cannot do (very large or small values) goes through `general`.
#[inline]
fn put_float(
    v: f64,
    negative: bool,
    max_decimals: usize,
    reads_back: impl Fn(f64) -> bool,
    out: &mut Vec<u8>,
    general: impl FnOnce(&mut Vec<u8>),
) {
    if v == v.trunc() && v.abs() < 1e15 {
        if negative {
            out.push(b'-');
        }
        put_int(v.abs() as u64, out);
        return;
    }
    for (d, &scale) in POW10.iter().enumerate().take(max_decimals + 1).skip(1) {
        let m = (v * scale).round();
        if m.abs() >= (1u64 << 53) as f64 {
            break;
        }
        if reads_back(m / scale) {
            put_fixed(m, d, out);
            return;
        }
    }
    general(out);
}

/// Writes the integer `m` (below 2^53 in magnitude) with a decimal point `d`
/// digits from its right: `put_fixed(5, 3)` is `0.005`.
fn put_fixed(m: f64, d: usize, out: &mut Vec<u8>) {
    if m < 0.0 {
        out.push(b'-');
    }
    let mut n = m.abs() as u64;
    let mut buf = [0u8; 48];
    let mut i = buf.len();
    let mut k = 0;
    loop {
        i -= 1;
        buf[i] = b'0' + (n % 10) as u8;
        n /= 10;
        k += 1;
        if k == d {
            i -= 1;
            buf[i] = b'.';
        }
        if n == 0 && k > d {
            break;
        }
    }
    out.extend_from_slice(&buf[i..]);
}

fn put_int(mut n: u64, out: &mut Vec<u8>) {
    let mut buf = [0u8; 20];
    let mut i = buf.len();
    loop {
        i -= 1;
        buf[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    out.extend_from_slice(&buf[i..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text<T: Put>(v: &[T]) -> String {
        String::from_utf8(format_piece(v)).unwrap()
    }

    #[test]
    fn runs_defaults_and_shortest_floats() {
        assert_eq!(text(&[1.5f32, 1.5, 1.5, 2.0, 2.0, -0.0]), "3*1.5 2 2 -0\n");
        assert_eq!(text(&[f32::NAN, f32::NAN, 7.0]), "2* 7\n");
        assert_eq!(
            text(&[1e-30f32, 3e20, 0.1, -123456.79]),
            "1e-30 3e20 0.1 -123456.79\n"
        );
        assert_eq!(text(&[0.1f64, 456510.625, -2.0]), "0.1 456510.625 -2\n");
        assert_eq!(text(&[true, true, true, false]), "3*1 0\n");
        assert_eq!(text(&[f32::INFINITY, f32::NEG_INFINITY]), "1e39 -1e39\n");
        assert_eq!(text(&[f64::NEG_INFINITY]), "-1e309\n");
    }

    /// Whatever the bits, a written `f32` reads back identical, through the
    /// reader's own number parser and through `fast_float2`.
    #[test]
    fn every_kind_of_f32_reads_back() {
        let mut x: u64 = 0x2545_F491_4F6C_DD1D;
        let mut values = vec![0.001f32, 1e-5, 9.999e-6, 16777217.0, 1e15, 0.1 + 0.2];
        for _ in 0..300_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let v = f32::from_bits(x as u32);
            if v.is_finite() {
                values.push(v);
            }
            values.push((x >> 40) as f32 / 1024.0 + 1000.0);
        }
        let t = text(&values);
        let tokens: Vec<&str> = t.split_whitespace().collect();
        assert_eq!(tokens.len(), values.len());
        for (tok, v) in tokens.iter().zip(&values) {
            let ours = crate::grdecl::numbers::parse_token::<f32>(tok.as_bytes());
            let theirs = fast_float2::parse::<f32, _>(tok).ok();
            assert_eq!(ours.map(f32::to_bits), Some(v.to_bits()), "{tok} for {v:e}");
            assert_eq!(
                theirs.map(f32::to_bits),
                Some(v.to_bits()),
                "{tok} for {v:e}"
            );
        }
    }

    #[test]
    fn fixed_point_digits() {
        let mut out = Vec::new();
        put_fixed(5.0, 3, &mut out);
        out.push(b' ');
        put_fixed(-16085248.0, 4, &mut out);
        out.push(b' ');
        put_fixed(12.0, 1, &mut out);
        assert_eq!(String::from_utf8(out).unwrap(), "0.005 -1608.5248 1.2");
    }

    #[test]
    fn lines_stay_short() {
        let v: Vec<f64> = (0..1000).map(|i| i as f64 * 0.123456789).collect();
        let t = text(&v);
        assert!(t.lines().all(|l| l.len() <= LINE && !l.starts_with(' ')));
        let back: Vec<f64> = t.split_whitespace().map(|s| s.parse().unwrap()).collect();
        assert_eq!(back, v);
    }
}
