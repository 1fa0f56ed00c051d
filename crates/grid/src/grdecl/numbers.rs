//! Bulk numeric keyword data (COORD, ZCORN, ACTNUM, properties): the hot path.
//!
//! A body runs from just after its keyword to the first `/` outside a comment
//! ([`find_slash`], a `memchr` scan). It is then cut into pieces of about
//! [`CHUNK`] bytes, each ending just after a newline: no token, `N*v` repeat or
//! `--` comment spans a newline, so every piece parses on its own, in parallel.
//! Pieces are parsed in waves of a few per thread, at most [`MAX_WAVE`], and
//! appended in order, so the memory beside the result stays a few tens of megabytes
//! however large the body is and however many threads parse it.
//! Short plain decimals (nearly all bulk data) are converted by [`plain`]; anything
//! else goes through `fast_float2` straight from the bytes, and Fortran `D`
//! exponents through a small stack buffer.

use std::sync::atomic::{AtomicUsize, Ordering};

use fast_float2::FastFloat;
use rayon::prelude::*;

use super::lex::{comment_at, is_sep, line_end, shown};
use crate::pages::Pages;

/// Bytes of text per parallel piece: large enough that rayon's overhead vanishes
/// (tens of thousands of values), small enough that a wave gives 16 threads two
/// each. Smaller pieces (256 KiB) were measured to raise the peak of reading a large
/// deck (docs/performance.md): glibc keeps their freed values in its heaps, where
/// larger ones are unmapped.
const CHUNK: usize = 512 << 10;

/// Most pieces parsed at once: at most 16 MiB of text and what it parses to, however
/// many cores parse it (four 1 MiB pieces a thread held 64 MiB of text on 16).
const MAX_WAVE: usize = 32;

/// Bytes of a mapped deck scanned or parsed before their pages go back
/// ([`Pages`]).
const GIVE_BACK_EVERY: usize = 16 << 20;

/// A float type a keyword is read into.
pub(super) trait Num: FastFloat + Copy + Send + Sync {
    fn finite(self) -> bool;
    /// `r`, the correctly rounded `f64` of a decimal, as this type, or `None` where
    /// converting it could round differently from the decimal itself.
    fn from_rounded(r: f64) -> Option<Self>;
}

impl Num for f32 {
    fn finite(self) -> bool {
        self.is_finite()
    }

    /// Rounding the decimal to `f64` and then to `f32` is exact unless the `f64`
    /// landed exactly on a midpoint between two `f32`s (the 29 bits `f32` drops are
    /// then `1000...0`): the decimal may have been just above or below it, so that
    /// case goes to the full parser. `r` is in the normal `f32` range here.
    #[inline]
    fn from_rounded(r: f64) -> Option<Self> {
        const DROPPED: u64 = (1 << 29) - 1;
        (r.to_bits() & DROPPED != 1 << 28).then_some(r as f32)
    }
}

impl Num for f64 {
    fn finite(self) -> bool {
        self.is_finite()
    }

    #[inline]
    fn from_rounded(r: f64) -> Option<Self> {
        Some(r)
    }
}

/// Powers of ten exactly representable as `f64`.
pub(super) const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// How one keyword's numbers are read.
pub(super) struct Spec<T> {
    /// The most values the data may expand to. A repeat that goes past it is an
    /// error before anything is allocated, so `9999999999*1` in a tiny file cannot
    /// exhaust memory.
    pub cap: usize,
    /// The value of a defaulted item (`3*`), `None` where defaults are not allowed.
    pub default: Option<T>,
    /// Refuse NaN and infinities (geometry must be finite).
    pub finite: bool,
}

/// A syntax error at byte `offset` of the file.
#[derive(Debug)]
pub(super) struct NumError {
    pub offset: usize,
    pub message: String,
}

/// The `/` ending data that starts at `from`: the first one outside a `--`
/// comment. `None` when the file ends first (truncated data).
///
/// Quotes are not looked at: a quote in numeric data is an error that the parse
/// reports at the quote, which comes before any slash inside it.
pub(super) fn find_slash(b: &[u8], from: usize, pages: Pages) -> Option<usize> {
    let mut i = from.min(b.len());
    let mut given = i;
    loop {
        // A window at a time: a body of gigabytes is scanned here and parsed next,
        // so its pages go back as the scan passes them (and come in again, from the
        // page cache, to be parsed).
        let window = &b[i..b.len().min(i.saturating_add(GIVE_BACK_EVERY))];
        let Some(at) = memchr::memchr2(b'/', b'-', window) else {
            if i + window.len() == b.len() {
                return None;
            }
            i += window.len();
            given = pages.give_back(given, i);
            continue;
        };
        let p = i + at;
        if b[p] == b'/' {
            return Some(p);
        }
        i = if comment_at(b, p) {
            line_end(b, p)
        } else {
            p + 1
        };
    }
}

/// Parses the numbers in `b[start..end]` (no terminator inside).
pub(super) fn parse<T: Num>(
    b: &[u8],
    start: usize,
    end: usize,
    spec: &Spec<T>,
    pages: Pages,
) -> Result<Vec<T>, NumError> {
    let end = end.min(b.len());
    let start = start.min(end);
    // Without repeats a value takes at least two bytes; with them, at most `cap`.
    let mut out: Vec<T> = Vec::with_capacity(((end - start) / 2 + 1).min(spec.cap));
    let ranges = chunk_ranges(b, start, end);
    let wave = (4 * rayon::current_num_threads()).clamp(1, MAX_WAVE);
    let mut given = start;
    for group in ranges.chunks(wave) {
        // What the groups before parsed goes back.
        let parsed = group.first().map_or(start, |&(s, _)| s);
        if parsed - given >= GIVE_BACK_EVERY {
            given = pages.give_back(given, parsed);
        }
        let room = spec.cap.saturating_sub(out.len());
        let expanded = AtomicUsize::new(0);
        if let [(s, e)] = group {
            out.extend_from_slice(&parse_range(b, *s, *e, spec, room, &expanded)?);
            continue;
        }
        let parts: Vec<Result<Vec<T>, NumError>> = group
            .par_iter()
            .map(|&(s, e)| parse_range(b, s, e, spec, room, &expanded))
            .collect();
        for part in parts {
            out.extend_from_slice(&part?);
        }
    }
    Ok(out)
}

/// Cuts `[start, end)` into pieces of about [`CHUNK`] bytes, each ending just after
/// a newline (or at `end`).
fn chunk_ranges(b: &[u8], start: usize, end: usize) -> Vec<(usize, usize)> {
    let mut ranges = Vec::new();
    let mut s = start;
    while end - s > CHUNK {
        match memchr::memchr(b'\n', &b[s + CHUNK..end]) {
            Some(p) => {
                let cut = s + CHUNK + p + 1;
                ranges.push((s, cut));
                s = cut;
            }
            None => break,
        }
    }
    ranges.push((s, end));
    ranges
}

/// Parses one piece. `room` bounds what repeats may add, here and (through
/// `expanded`, shared by the pieces of a wave) in all pieces together.
fn parse_range<T: Num>(
    b: &[u8],
    start: usize,
    end: usize,
    spec: &Spec<T>,
    room: usize,
    expanded: &AtomicUsize,
) -> Result<Vec<T>, NumError> {
    let b = &b[..end];
    let mut out = Vec::with_capacity(((end - start) / 4).min(room));
    let mut i = start;
    while i < end {
        let c = b[i];
        if is_sep(c) {
            i += 1;
            continue;
        }
        if comment_at(b, i) {
            i = line_end(b, i);
            continue;
        }
        let (v, k) = number::<T>(b, i)?;
        if b.get(k) != Some(&b'*') {
            if spec.finite && !v.finite() {
                return Err(not_finite(b, i));
            }
            out.push(v);
            i = k;
            continue;
        }
        let n = repeat_count(b, i, k)?;
        let (value, next) = if k + 1 >= end || is_sep(b[k + 1]) || comment_at(b, k + 1) {
            let d = spec.default.ok_or_else(|| NumError {
                offset: i,
                message: format!(
                    "'{}': a defaulted value is not allowed here",
                    shown(&b[i..k + 1])
                ),
            })?;
            (d, k + 1)
        } else {
            let (v, e) = number::<T>(b, k + 1)?;
            if b.get(e) == Some(&b'*') || (spec.finite && !v.finite()) {
                return Err(bad(b, i));
            }
            (v, e)
        };
        let total = expanded.fetch_add(n, Ordering::Relaxed).saturating_add(n);
        if n > room.saturating_sub(out.len()) || total > room {
            return Err(NumError {
                offset: i,
                message: format!(
                    "repeat '{}' makes more values than the {} this keyword can take",
                    shown(&b[i..next]),
                    spec.cap
                ),
            });
        }
        out.resize(out.len() + n, value);
        i = next;
    }
    Ok(out)
}

/// The number starting at `i` and the position just after it, which must be a
/// separator, `*`, `/`, a comment or the end.
#[inline]
fn number<T: Num>(b: &[u8], i: usize) -> Result<(T, usize), NumError> {
    match plain(b, i) {
        Some(v) => Ok(v),
        None => general(b, i),
    }
}

/// The common case in bulk data, `-12.345` (no exponent, at most 15 digits): the
/// digits as an integer below 2^53 divided by an exact power of ten is the correctly
/// rounded `f64` (IEEE division of exact operands). `None` sends anything else,
/// including the rare `f32` midpoint, to [`general`].
#[inline(always)]
fn plain<T: Num>(b: &[u8], i: usize) -> Option<(T, usize)> {
    let negative = b.get(i) == Some(&b'-');
    let mut j = i + usize::from(negative);
    let digits_start = j;
    let mut m: u64 = 0;
    while let Some(d) = b.get(j).map(|c| c.wrapping_sub(b'0')).filter(|&d| d < 10) {
        m = m.wrapping_mul(10).wrapping_add(u64::from(d));
        j += 1;
    }
    let mut frac = 0;
    let dot = b.get(j) == Some(&b'.');
    if dot {
        j += 1;
        let frac_start = j;
        while let Some(d) = b.get(j).map(|c| c.wrapping_sub(b'0')).filter(|&d| d < 10) {
            m = m.wrapping_mul(10).wrapping_add(u64::from(d));
            j += 1;
        }
        frac = j - frac_start;
    }
    let digits = j - digits_start - usize::from(dot);
    if digits == 0 || digits > 15 {
        return None;
    }
    if let Some(&c) = b.get(j) {
        if !(is_sep(c) || c == b'/' || c == b'*' || comment_at(b, j)) {
            return None;
        }
    }
    let r = m as f64 / POW10[frac];
    T::from_rounded(if negative { -r } else { r }).map(|v| (v, j))
}

/// Any number `fast_float2` reads (exponents, many digits, `inf`, `nan`), and the
/// Fortran `D` exponent.
#[cold]
fn general<T: Num>(b: &[u8], i: usize) -> Result<(T, usize), NumError> {
    let Ok((v, n)) = fast_float2::parse_partial::<T, _>(&b[i..]) else {
        return Err(bad(b, i));
    };
    let k = i + n;
    match b.get(k) {
        None => Ok((v, k)),
        Some(&c) if is_sep(c) || c == b'*' || c == b'/' || comment_at(b, k) => Ok((v, k)),
        Some(b'D' | b'd') => fortran(b, i),
        Some(_) => Err(bad(b, i)),
    }
}

/// A Fortran double-precision literal (`1.5D+03`): the token with its `D` made an
/// `e`, parsed whole.
fn fortran<T: Num>(b: &[u8], i: usize) -> Result<(T, usize), NumError> {
    let j = token_end(b, i);
    let mut buf = [0u8; 64];
    let text = &b[i..j];
    if text.len() > buf.len() {
        return Err(bad(b, i));
    }
    buf[..text.len()].copy_from_slice(text);
    let d = text
        .iter()
        .position(|c| matches!(c, b'D' | b'd'))
        .ok_or_else(|| bad(b, i))?;
    buf[d] = b'e';
    let v = fast_float2::parse::<T, _>(&buf[..text.len()]).map_err(|_| bad(b, i))?;
    Ok((v, j))
}

/// The count of a repeat `N*`: digits only, at least 1.
fn repeat_count(b: &[u8], i: usize, star: usize) -> Result<usize, NumError> {
    let digits = &b[i..star];
    let err = |what: &str| NumError {
        offset: i,
        message: format!("repeat count '{}' {what}", shown(digits)),
    };
    if !digits.iter().all(u8::is_ascii_digit) {
        return Err(err("is not a positive integer"));
    }
    let n = digits.iter().try_fold(0usize, |n, &d| {
        n.checked_mul(10)?.checked_add(usize::from(d - b'0'))
    });
    match n {
        None => Err(err("is too large")),
        Some(0) => Err(err("is zero")),
        Some(n) => Ok(n),
    }
}

/// Where the token starting at `i` ends: a separator, `/`, a quote or a comment.
fn token_end(b: &[u8], i: usize) -> usize {
    let mut j = i + 1;
    while j < b.len() && !(is_sep(b[j]) || matches!(b[j], b'/' | b'\'') || comment_at(b, j)) {
        j += 1;
    }
    j.min(b.len())
}

#[cold]
fn bad(b: &[u8], i: usize) -> NumError {
    NumError {
        offset: i,
        message: format!("'{}' is not a number", shown(&b[i..token_end(b, i)])),
    }
}

#[cold]
fn not_finite(b: &[u8], i: usize) -> NumError {
    NumError {
        offset: i,
        message: format!("'{}' is not a finite number", shown(&b[i..token_end(b, i)])),
    }
}

/// Parses one standalone token (a record item such as a SPECGRID dimension or an
/// EQUALS value), with the same syntax as bulk data.
pub(super) fn parse_token<T: Num>(text: &[u8]) -> Option<T> {
    match number::<T>(text, 0) {
        Ok((v, k)) if k == text.len() => Some(v),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(cap: usize, default: Option<f32>) -> Spec<f32> {
        Spec {
            cap,
            default,
            finite: true,
        }
    }

    fn read(s: &str, sp: &Spec<f32>) -> Result<Vec<f32>, NumError> {
        let b = s.as_bytes();
        let end = find_slash(b, 0, Pages::default()).unwrap_or(b.len());
        parse(b, 0, end, sp, Pages::default())
    }

    #[test]
    fn repeats_defaults_commas_comments_and_fortran_exponents() {
        let v = read(
            "1,2.5 3*4 -- 9 9 9 / not data\n 2* 1.5D+03 -2d-1 .5 +7 1e2/",
            &spec(100, Some(f32::NAN)),
        )
        .unwrap();
        assert_eq!(&v[..5], &[1.0, 2.5, 4.0, 4.0, 4.0]);
        assert!(v[5].is_nan() && v[6].is_nan());
        assert_eq!(&v[7..], &[1500.0, -0.2, 0.5, 7.0, 100.0]);
    }

    #[test]
    fn slash_is_found_outside_comments_only() {
        let b = b"1 2 -- a/b\n -3 4/ 5 /";
        let none = Pages::default();
        assert_eq!(find_slash(b, 0, none), Some(16));
        assert_eq!(find_slash(b"1 2 -- no end /", 0, none), None);
        assert_eq!(find_slash(b"1 2 3", 0, none), None);
    }

    #[test]
    fn bad_tokens_are_reported_where_they_are() {
        let e = read("1 2 x3 4 /", &spec(10, None)).unwrap_err();
        assert_eq!((e.offset, e.message.as_str()), (4, "'x3' is not a number"));
        let e = read("1 2.5.5 /", &spec(10, None)).unwrap_err();
        assert!(e.message.contains("'2.5.5'"), "{}", e.message);
        let e = read("1 'a' /", &spec(10, None)).unwrap_err();
        assert_eq!(e.offset, 2);
        let e = read("1 nan /", &spec(10, None)).unwrap_err();
        assert!(e.message.contains("not a finite number"));
        let e = read("1 1e39 /", &spec(10, None)).unwrap_err();
        assert!(e.message.contains("not a finite number"));
        let e = read("3* /", &spec(10, None)).unwrap_err();
        assert!(e.message.contains("defaulted value is not allowed"));
        let e = read("1.5*2 /", &spec(10, None)).unwrap_err();
        assert!(e.message.contains("not a positive integer"));
        let e = read("0*2 /", &spec(10, None)).unwrap_err();
        assert!(e.message.contains("is zero"));
        let e = read("99999999999999999999999*2 /", &spec(10, None)).unwrap_err();
        assert!(e.message.contains("too large"));
        let e = read("1 2 11*2 /", &spec(10, None)).unwrap_err();
        assert!(
            e.message.contains("more values than the 10"),
            "{}",
            e.message
        );
        let e = read("2*3*4 /", &spec(10, None)).unwrap_err();
        assert!(e.message.contains("'2*3*4'"), "{}", e.message);
    }

    /// The plain-decimal shortcut agrees bit for bit with `fast_float2`, including
    /// at `f32` midpoints where rounding through `f64` could go wrong.
    #[test]
    fn plain_decimals_round_like_fast_float() {
        let mut cases: Vec<String> = [
            "16777217",
            "16777219",
            "1.000000059604645",
            "1.0000000596046448",
            "0.1",
            "-0",
            "1.",
            ".5",
            "-.5",
            "999999999999999",
            "3.4028235e38",
            "0.000000000000000000001",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let v = f32::from_bits((x as u32 & 0x3fff_ffff) | 0x3000_0000);
            cases.push(format!("{v}"));
            cases.push(format!("{:.*}", (x >> 40) as usize % 12, v));
            cases.push(format!("{}", (x >> 11) as f64 / (1u64 << (x % 40)) as f64));
        }
        for c in &cases {
            let b = c.as_bytes();
            let want32 = fast_float2::parse::<f32, _>(b).ok();
            let got32 = number::<f32>(b, 0).ok().map(|(v, _)| v);
            assert_eq!(got32.map(f32::to_bits), want32.map(f32::to_bits), "{c}");
            let want64 = fast_float2::parse::<f64, _>(b).ok();
            let got64 = number::<f64>(b, 0).ok().map(|(v, _)| v);
            assert_eq!(got64.map(f64::to_bits), want64.map(f64::to_bits), "{c}");
        }
        assert!(plain::<f32>(b"16777217", 0).is_none());
        assert!(plain::<f32>(b"1.5", 0).is_some());
    }

    #[test]
    fn tokens_parse_whole_or_not_at_all() {
        assert_eq!(parse_token::<f64>(b"1.25D2"), Some(125.0));
        assert_eq!(parse_token::<f64>(b"12"), Some(12.0));
        assert_eq!(parse_token::<f64>(b"12x"), None);
        assert_eq!(parse_token::<f64>(b""), None);
    }

    /// A body of several chunks with repeats, defaults and comments on every line
    /// gives the same values as the line-by-line reference.
    #[test]
    fn parallel_pieces_join_in_order() {
        let mut text = String::new();
        let mut want = Vec::new();
        let mut line = 0u32;
        while text.len() < 3 * CHUNK + 1000 {
            let v = (line % 1000) as f32 * 0.25;
            text.push_str(&format!("{v} 3*{v} 2* -- {line} / 1\n"));
            want.extend([v; 4]);
            want.extend([-1.0; 2]);
            line += 1;
        }
        text.push('/');
        let sp = Spec {
            cap: want.len(),
            default: Some(-1.0),
            finite: true,
        };
        let got = read(&text, &sp).unwrap();
        assert_eq!(got, want);
        // A repeat that overflows the cap in a late piece is still caught.
        let sp = Spec { cap: 10, ..sp };
        assert!(read(&text, &sp).is_err());
    }
}
