//! The keyword level of a deck: sections, INCLUDE, and what each keyword's data
//! becomes.
//!
//! Two ways of walking a file:
//! * **read** (a plain GRDECL file, and the GRID and PROPS sections of a `.DATA`
//!   deck): every token must belong to a keyword; geometry, edits and per-cell
//!   arrays are read, other keywords' records skipped, and malformed data is an
//!   error;
//! * **skim** (RUNSPEC and the other sections): only a word that starts a line and
//!   spells a keyword is looked at, so the free-form records of SCHEDULE, SUMMARY,
//!   ... (strings, dates, several `/`-terminated records) cannot trip the reader.
//!   RUNSPEC gives DIMENS and the unit system (METRIC, FIELD, LAB).
//!
//! A keyword followed directly by another keyword has no data. An unknown keyword's
//! records run to the next keyword; if they are one record of numbers with one value
//! per cell (or per cell of the current BOX), the keyword is a property.
//!
//! Nothing read from a file sizes an allocation before it is checked against a budget
//! that grows with the bytes of text read (see [`Deck::limit`]).

use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};

use memmap2::Mmap;
use ndarray::Array3;

use super::block;
use super::cells::{Cells, Region};
use super::lex::{Kind, Lexer, Token, comment_at, is_keyword, is_sep, keyword, line_at, shown};
use super::numbers::{self, Num, Spec, find_slash, parse_token};
use crate::pages::Pages;
use crate::{Content, CornerPointGrid, Dims, Error, MapAxes, ReadOptions, Result, Units};

/// The least number of values (array elements) a deck may allocate, whatever its
/// size: room for a 8-million-cell block-centred model written in a few lines
/// (`DX 8000000*20 /`). About 256 MB of `f32`.
const MIN_BUDGET: usize = 1 << 26;
/// Values a deck may allocate per byte of its text, beyond [`MIN_BUDGET`]. A
/// corner-point deck spells out its pillars (at least a few bytes for each of the
/// `6 (nx + 1)(ny + 1)` COORD values), so 64 per byte allows any layer count a real
/// model has, and refuses a 1 kB file that claims a billion cells.
const VALUES_PER_BYTE: usize = 64;
/// Arrays of its grid's size that a property deck may allocate however briefly it is
/// written (`PORO 100000000*0.2 /`): the grid, read before, already holds eight values
/// per cell in ZCORN, so a deck for it may cost as much again.
const PROPERTY_ARRAYS: usize = 8;
/// INCLUDE nesting deeper than this is refused (cycles are caught before; this
/// bounds the stack for long chains of distinct files).
const MAX_INCLUDE_DEPTH: usize = 32;

/// Arrays that are geometry: read even with `grid_only`.
const GEOMETRY: [&str; 5] = ["ACTNUM", "DX", "DY", "DZ", "TOPS"];
/// Arrays whose data is an error when malformed or of the wrong length, rather than
/// a reason not to take the keyword as a property.
const KNOWN_ARRAYS: [&str; 10] = [
    "ACTNUM", "DX", "DY", "DZ", "TOPS", "PORO", "PERMX", "PERMY", "PERMZ", "NTG",
];
/// Keywords whose records continue until an empty record (`/` alone); their
/// records may start with bare words, so "the next keyword" cannot end them.
const UNTIL_EMPTY_RECORD: [&str; 12] = [
    "FAULTS", "MULTFLT", "NNC", "EDITNNC", "MULTREGT", "EQUALREG", "ADDREG", "MULTIREG", "COPYREG",
    "OPERATE", "OPERATER", "THPRES",
];

/// Keywords read with a meaning of their own (besides sections and
/// [`UNTIL_EMPTY_RECORD`]): a property by one of these names would not read back.
const HANDLED: [&str; 24] = [
    "END", "TITLE", "INCLUDE", "SPECGRID", "DIMENS", "COORD", "ZCORN", "ACTNUM", "DXV", "DYV",
    "DZV", "MAPAXES", "GRIDUNIT", "METRIC", "FIELD", "LAB", "MAPUNITS", "GDORIENT", "BOX",
    "ENDBOX", "EQUALS", "MULTIPLY", "ADD", "COPY",
];

/// Does the reader give `kw` a meaning other than "a per-cell property"?
pub(super) fn is_special(kw: &str) -> bool {
    HANDLED.contains(&kw) || UNTIL_EMPTY_RECORD.contains(&kw) || Section::from_keyword(kw).is_some()
}

/// The sections of a `.DATA` deck; `Top` is before any section keyword, which is all
/// of a plain GRDECL file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Section {
    Top,
    Runspec,
    Grid,
    Edit,
    Props,
    Regions,
    Solution,
    Summary,
    Schedule,
}

impl Section {
    fn from_keyword(kw: &str) -> Option<Section> {
        Some(match kw {
            "RUNSPEC" => Section::Runspec,
            "GRID" => Section::Grid,
            "EDIT" => Section::Edit,
            "PROPS" => Section::Props,
            "REGIONS" => Section::Regions,
            "SOLUTION" => Section::Solution,
            "SUMMARY" => Section::Summary,
            "SCHEDULE" => Section::Schedule,
            _ => return None,
        })
    }

    fn reads(self) -> bool {
        matches!(self, Section::Top | Section::Grid | Section::Props)
    }
}

/// One file being read, for error messages.
struct Src<'a> {
    path: &'a Path,
    bytes: &'a [u8],
    /// The file map `bytes` are, when they are one.
    pages: Pages<'a>,
}

impl Src<'_> {
    fn err(&self, at: usize, keyword: &str, message: impl Into<String>) -> Error {
        Error::Text {
            path: self.path.to_path_buf(),
            line: line_at(self.bytes, at),
            keyword: keyword.to_string(),
            message: message.into(),
        }
    }

    fn truncated(&self, kw: &Token, keyword: &str) -> Error {
        self.err(
            kw.at,
            keyword,
            "data not terminated by '/' before the end of the file",
        )
    }
}

/// One item of a short record: its text, `None` when defaulted (`3*`).
struct Item<'a> {
    text: Option<&'a [u8]>,
    at: usize,
}

/// Everything a deck has said so far.
pub(super) struct Deck<'o> {
    options: &'o ReadOptions,
    root: PathBuf,
    root_dir: PathBuf,
    /// Canonical paths of the files being read, outermost first (cycle detection).
    open: Vec<PathBuf>,
    bytes_seen: usize,
    /// Values the deck may allocate whatever its length.
    floor: usize,
    spent: usize,
    section: Section,
    ended: bool,
    cells: Option<Cells>,
    region: Option<Region>,
    vectors: BTreeMap<String, Vec<f64>>,
    coord: Option<Vec<f64>>,
    zcorn: Option<Vec<f32>>,
    mapaxes: Option<MapAxes>,
    units: Option<Units>,
    warnings: Vec<String>,
}

/// Reads the deck `bytes`, which is the file `path` (mapped as `pages` when it is).
pub(super) fn parse(
    path: &Path,
    bytes: &[u8],
    pages: Pages,
    options: &ReadOptions,
) -> Result<CornerPointGrid> {
    let mut deck = Deck::new(path, bytes, options, None);
    deck.run(path, bytes, pages)?;
    deck.finish()
}

/// Reads the per-cell arrays of a property deck (no grid keywords needed) for a grid
/// of `dims`, e.g. the PORO file that goes with an EGRID.
pub(super) fn parse_properties(
    path: &Path,
    bytes: &[u8],
    pages: Pages,
    dims: Dims,
) -> Result<BTreeMap<String, Vec<f32>>> {
    let options = ReadOptions::default();
    let mut deck = Deck::new(path, bytes, &options, Some(Cells::new(dims)));
    deck.floor = MIN_BUDGET.max(dims.cell_count().saturating_mul(PROPERTY_ARRAYS));
    deck.run(path, bytes, pages)?;
    Ok(deck.cells.map(|c| c.arrays).unwrap_or_default())
}

impl<'o> Deck<'o> {
    fn new(path: &Path, bytes: &[u8], options: &'o ReadOptions, cells: Option<Cells>) -> Self {
        let root_dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        Deck {
            options,
            root: path.to_path_buf(),
            root_dir,
            open: vec![identity(path)],
            bytes_seen: bytes.len(),
            floor: MIN_BUDGET,
            spent: 0,
            section: Section::Top,
            ended: false,
            cells,
            region: None,
            vectors: BTreeMap::new(),
            coord: None,
            zcorn: None,
            mapaxes: None,
            units: None,
            warnings: Vec::new(),
        }
    }
}

/// A file's identity for cycle detection: its canonical path when it exists.
fn identity(path: &Path) -> PathBuf {
    std::fs::canonicalize(path)
        .or_else(|_| std::path::absolute(path))
        .unwrap_or_else(|_| path.to_path_buf())
}

impl Deck<'_> {
    /// How many values the deck may allocate: grows with the text read, so that no
    /// count in a small file can make the reader allocate much.
    fn limit(&self) -> usize {
        self.floor
            .max(self.bytes_seen.saturating_mul(VALUES_PER_BYTE))
    }

    fn left(&self) -> usize {
        self.limit().saturating_sub(self.spent)
    }

    /// Accounts for `n` values allocated or written.
    fn charge(&mut self, n: usize, src: &Src, at: usize, kw: &str) -> Result<()> {
        if n > self.left() {
            return Err(src.err(
                at,
                kw,
                format!(
                    "the deck's arrays would exceed {} values, more than {} bytes of text can describe",
                    self.limit(),
                    self.bytes_seen
                ),
            ));
        }
        self.spent += n;
        Ok(())
    }

    fn dims(&self) -> Option<Dims> {
        self.cells.as_ref().map(|c| c.dims)
    }

    /// Walks one file.
    fn run(&mut self, path: &Path, bytes: &[u8], pages: Pages) -> Result<()> {
        let content = Content::of(bytes);
        if content != Content::Text {
            return Err(Error::Content {
                path: path.to_path_buf(),
                message: format!("{}, not a text deck", content.describe()),
            });
        }
        let src = Src { path, bytes, pages };
        let mut lex = Lexer::new(bytes);
        let mut last = String::new();
        while !self.ended {
            let Some(tok) = lex.next_token() else { break };
            if !self.section.reads() {
                self.skim(&src, &mut lex, tok)?;
                continue;
            }
            let kw = match tok.kind {
                Kind::Word => keyword(tok.text(bytes)),
                _ => None,
            };
            let Some(kw) = kw else {
                let what = match tok.kind {
                    Kind::Slash => "/".to_string(),
                    _ => shown(&bytes[tok.at..tok.end.max(tok.at + 1).min(bytes.len())]),
                };
                let (context, after) = if last.is_empty() {
                    (what.clone(), String::new())
                } else {
                    (last.clone(), format!(" after the data of {last}"))
                };
                return Err(src.err(
                    tok.at,
                    &context,
                    format!("'{what}' is not a keyword{after} (is a '/' missing or extra?)"),
                ));
            };
            self.keyword(&src, &mut lex, &kw, tok)?;
            last = kw;
        }
        Ok(())
    }

    /// Skim mode: only keywords at the start of a line matter.
    fn skim(&mut self, src: &Src, lex: &mut Lexer, tok: Token) -> Result<()> {
        if !tok.line_start || tok.kind != Kind::Word {
            return Ok(());
        }
        let Some(kw) = keyword(tok.text(src.bytes)) else {
            return Ok(());
        };
        if let Some(section) = Section::from_keyword(&kw) {
            self.section = section;
            lex.skip_lines(1);
            return Ok(());
        }
        match kw.as_str() {
            "END" => self.ended = true,
            "TITLE" => {
                lex.skip_lines(2);
            }
            "DIMENS" if self.section == Section::Runspec => self.specgrid(src, lex, &kw, tok)?,
            "METRIC" | "FIELD" | "LAB" if self.section == Section::Runspec => {
                self.units = unit_system(&kw);
            }
            _ => {}
        }
        Ok(())
    }

    /// Read mode: one keyword and its data.
    fn keyword(&mut self, src: &Src, lex: &mut Lexer, kw: &str, tok: Token) -> Result<()> {
        if let Some(section) = Section::from_keyword(kw) {
            self.section = section;
            lex.skip_lines(1);
            return Ok(());
        }
        match kw {
            "END" => self.ended = true,
            "TITLE" => {
                lex.skip_lines(2);
            }
            "INCLUDE" => self.include(src, lex, tok)?,
            "SPECGRID" | "DIMENS" => self.specgrid(src, lex, kw, tok)?,
            "COORD" => {
                let len = self
                    .need_dims(src, kw, &tok)?
                    .coord_len()
                    .unwrap_or(usize::MAX);
                self.coord = Some(self.exact::<f64>(src, lex, kw, &tok, len)?);
            }
            "ZCORN" => {
                let len = self
                    .need_dims(src, kw, &tok)?
                    .zcorn_len()
                    .unwrap_or(usize::MAX);
                self.zcorn = Some(self.exact::<f32>(src, lex, kw, &tok, len)?);
            }
            "DXV" | "DYV" | "DZV" => {
                let d = self.need_dims(src, kw, &tok)?;
                let len = match kw {
                    "DXV" => d.nx,
                    "DYV" => d.ny,
                    _ => d.nz,
                };
                let v = self.exact::<f64>(src, lex, kw, &tok, len)?;
                self.vectors.insert(kw.to_string(), v);
            }
            "MAPAXES" => self.mapaxes(src, lex, kw, &tok)?,
            "GRIDUNIT" => {
                let items = record(src, lex, kw, &tok, 3)?;
                let unit = items
                    .first()
                    .and_then(|i| i.text)
                    .ok_or_else(|| src.err(tok.at, kw, "no unit given"))?;
                let name = String::from_utf8_lossy(unit);
                self.units = Some(Units::parse(&name).ok_or_else(|| {
                    src.err(tok.at, kw, format!("unknown unit '{}'", shown(unit)))
                })?);
            }
            "METRIC" | "FIELD" | "LAB" => self.units = unit_system(kw),
            "MAPUNITS" | "GDORIENT" => skip_record(src, lex, kw, &tok)?,
            "BOX" => {
                let d = self.need_dims(src, kw, &tok)?;
                let items = record(src, lex, kw, &tok, 6)?;
                self.region = Some(region(src, kw, &tok, &items, Region::all(d), d)?);
            }
            "ENDBOX" => self.region = None,
            "EQUALS" | "MULTIPLY" | "ADD" | "COPY" => self.edits(src, lex, kw, &tok)?,
            _ if UNTIL_EMPTY_RECORD.contains(&kw) => skip_until_empty_record(src, lex, kw, &tok)?,
            _ => self.array(src, lex, kw, tok)?,
        }
        Ok(())
    }

    fn need_dims(&self, src: &Src, kw: &str, tok: &Token) -> Result<Dims> {
        self.dims()
            .ok_or_else(|| src.err(tok.at, kw, "comes before SPECGRID or DIMENS"))
    }

    /// SPECGRID `nx ny nz [numres] [T|F]` or DIMENS `nx ny nz`.
    fn specgrid(&mut self, src: &Src, lex: &mut Lexer, kw: &str, tok: Token) -> Result<()> {
        let items = record(src, lex, kw, &tok, 5)?;
        let mut n = [0usize; 3];
        for (a, slot) in n.iter_mut().enumerate() {
            let item = items
                .get(a)
                .ok_or_else(|| src.err(tok.at, kw, "needs nx ny nz"))?;
            *slot = positive(src, kw, item)?;
        }
        let dims = Dims::new(n[0], n[1], n[2]).map_err(|e| src.err(tok.at, kw, e.to_string()))?;
        let values = dims.zcorn_len().unwrap_or(usize::MAX);
        if values > self.limit() {
            return Err(src.err(
                tok.at,
                kw,
                format!(
                    "{} x {} x {} cells need {values} corner depths, more than a deck of {} bytes can describe (at most {})",
                    n[0],
                    n[1],
                    n[2],
                    self.bytes_seen,
                    self.limit()
                ),
            ));
        }
        match self.dims() {
            Some(old) if old != dims => Err(src.err(
                tok.at,
                kw,
                format!(
                    "{} x {} x {} differs from the {} x {} x {} given before",
                    n[0], n[1], n[2], old.nx, old.ny, old.nz
                ),
            )),
            Some(_) => Ok(()),
            None => {
                self.cells = Some(Cells::new(dims));
                Ok(())
            }
        }
    }

    /// Numeric data of exactly `len` values, all finite, no defaults (COORD, ZCORN,
    /// DXV ...).
    fn exact<T: Num>(
        &mut self,
        src: &Src,
        lex: &mut Lexer,
        kw: &str,
        tok: &Token,
        len: usize,
    ) -> Result<Vec<T>> {
        match lex.peek() {
            Some(t) if !is_keyword(&t, src.bytes) => {}
            _ => return Err(src.err(tok.at, kw, "has no data")),
        }
        let start = lex.pos;
        let end = find_slash(src.bytes, start, src.pages).ok_or_else(|| src.truncated(tok, kw))?;
        let spec = Spec {
            cap: len.min(self.left()),
            default: None,
            finite: true,
        };
        let values = numbers::parse(src.bytes, start, end, &spec, src.pages)
            .map_err(|e| src.err(e.offset, kw, e.message))?;
        lex.pos = end + 1;
        if values.len() != len {
            return Err(src.err(
                tok.at,
                kw,
                format!("has {} values, the grid needs {len}", values.len()),
            ));
        }
        self.charge(len, src, tok.at, kw)?;
        Ok(values)
    }

    fn mapaxes(&mut self, src: &Src, lex: &mut Lexer, kw: &str, tok: &Token) -> Result<()> {
        let items = record(src, lex, kw, tok, 6)?;
        if items.len() != 6 {
            return Err(src.err(tok.at, kw, format!("has {} values, needs 6", items.len())));
        }
        let mut v = [0f64; 6];
        for (slot, item) in v.iter_mut().zip(&items) {
            *slot = item
                .text
                .and_then(parse_token::<f64>)
                .filter(|x| x.is_finite())
                .ok_or_else(|| src.err(item.at, kw, "not a finite number"))?;
        }
        self.mapaxes = Some(MapAxes::from_values(v));
        Ok(())
    }

    /// INCLUDE `'file'` `/`: the path is relative to the root deck's folder.
    fn include(&mut self, src: &Src, lex: &mut Lexer, tok: Token) -> Result<()> {
        const KW: &str = "INCLUDE";
        let b = src.bytes;
        lex.skip_blank();
        let at = lex.pos;
        let (name, terminated) = if b.get(at) == Some(&b'\'') {
            match lex.next_token() {
                Some(
                    t @ Token {
                        kind: Kind::Quoted { closed: true },
                        ..
                    },
                ) => (t.text(b), false),
                _ => return Err(src.err(at, KW, "unterminated quoted file name")),
            }
        } else {
            // A bare name may hold directories (`a/b.inc`): it runs to whitespace,
            // and a slash glued to its end is the terminator.
            let mut j = at;
            while j < b.len() && !is_sep(b[j]) && !comment_at(b, j) {
                j += 1;
            }
            lex.pos = j;
            match b[at..j].strip_suffix(b"/") {
                Some(name) => (name, true),
                None => (&b[at..j], false),
            }
        };
        if name.is_empty() {
            return Err(src.err(tok.at, KW, "no file name"));
        }
        if !terminated && lex.next_token().map(|t| t.kind) != Some(Kind::Slash) {
            return Err(src.err(tok.at, KW, "file name not followed by '/'"));
        }
        let path = self.root_dir.join(String::from_utf8_lossy(name).as_ref());
        let file = match open(&path) {
            Ok(f) => f,
            Err(e) if self.options.grid_only => {
                self.warnings.push(format!(
                    "{}:{}: INCLUDE '{}' skipped: {e}",
                    src.path.display(),
                    line_at(b, tok.at),
                    path.display()
                ));
                return Ok(());
            }
            Err(e) => {
                return Err(src.err(tok.at, KW, format!("cannot read '{}': {e}", path.display())));
            }
        };
        let id = identity(&path);
        if self.open.contains(&id) {
            let chain: Vec<String> = self
                .open
                .iter()
                .chain([&id])
                .map(|p| p.display().to_string())
                .collect();
            return Err(src.err(tok.at, KW, format!("include cycle: {}", chain.join(" -> "))));
        }
        if self.open.len() >= MAX_INCLUDE_DEPTH {
            return Err(src.err(
                tok.at,
                KW,
                format!("INCLUDE files nested deeper than {MAX_INCLUDE_DEPTH}"),
            ));
        }
        // SAFETY: the map is only read, and lives until `run` returns. Another
        // process truncating the file while we read it is the accepted risk of every
        // memory-mapped reader.
        let map = unsafe { Mmap::map(&file) }.map_err(|e| Error::io(&path, e))?;
        self.bytes_seen = self.bytes_seen.saturating_add(map.len());
        self.open.push(id);
        // A file that is not a text deck is named at this INCLUDE (`run` tells).
        let result = self.run(&path, &map, Pages::of(&map)).map_err(|e| match e {
            Error::Content { message, .. } => {
                src.err(tok.at, KW, format!("'{}' is {message}", path.display()))
            }
            e => e,
        });
        self.open.pop();
        result
    }

    /// EQUALS / MULTIPLY / ADD (`'NAME' value box`) and COPY (`'FROM' 'TO' box`),
    /// one record each until an empty record.
    fn edits(&mut self, src: &Src, lex: &mut Lexer, kw: &str, tok: &Token) -> Result<()> {
        let dims = self.need_dims(src, kw, tok)?;
        loop {
            match lex.peek() {
                None => return Err(src.truncated(tok, kw)),
                Some(t) if t.kind == Kind::Slash => {
                    lex.next_token();
                    return Ok(());
                }
                Some(_) => {}
            }
            let items = record(src, lex, kw, tok, 8)?;
            let name = |i: usize| -> Result<String> {
                let item = items
                    .get(i)
                    .ok_or_else(|| src.err(tok.at, kw, "record too short"))?;
                item.text
                    .and_then(keyword)
                    .ok_or_else(|| src.err(item.at, kw, "expected an array name"))
            };
            let target = name(0)?;
            let (operand, dst) = if kw == "COPY" {
                (0.0, name(1)?)
            } else {
                let item = items
                    .get(1)
                    .ok_or_else(|| src.err(tok.at, kw, "record too short"))?;
                let v = item
                    .text
                    .and_then(parse_token::<f64>)
                    .ok_or_else(|| src.err(item.at, kw, "expected a number"))?;
                (v, target.clone())
            };
            let default = self.region.unwrap_or(Region::all(dims));
            let r = region(src, kw, tok, &items[2..], default, dims)?;
            let wanted = |n: &str| !self.options.grid_only || GEOMETRY.contains(&n);
            if !wanted(&dst) {
                continue;
            }
            let new_array = self
                .cells
                .as_ref()
                .is_none_or(|c| c.needs_allocation(&dst, r));
            let cost = r.len() + if new_array { dims.cell_count() } else { 0 };
            self.charge(cost, src, tok.at, kw)?;
            let Some(cells) = self.cells.as_mut() else {
                continue;
            };
            let v = operand as f32;
            let done = match kw {
                "EQUALS" => {
                    cells.equals(&dst, v, r);
                    Ok(())
                }
                "MULTIPLY" => cells.update(&dst, r, |x| x * v),
                "ADD" => cells.update(&dst, r, |x| x + v),
                _ => cells.copy(&target, &dst, r),
            };
            done.map_err(|m| src.err(tok.at, kw, m))?;
        }
    }

    /// A keyword with per-cell data (known arrays), or any other keyword (a
    /// property when its data fits the grid, otherwise skipped).
    fn array(&mut self, src: &Src, lex: &mut Lexer, kw: &str, tok: Token) -> Result<()> {
        let known = KNOWN_ARRAYS.contains(&kw);
        let b = src.bytes;
        let first = lex.peek();
        let starts_numeric = first.is_some_and(|t| t.kind == Kind::Word && !is_keyword(&t, b));
        let Some(dims) = self.dims() else {
            if known {
                return Err(src.err(tok.at, kw, "comes before SPECGRID or DIMENS"));
            }
            return skip_records(src, lex, kw, &tok);
        };
        if !starts_numeric {
            if known {
                return Err(src.err(tok.at, kw, "has no numeric data"));
            }
            return skip_records(src, lex, kw, &tok);
        }
        let start = lex.pos;
        let end = find_slash(b, start, src.pages).ok_or_else(|| src.truncated(&tok, kw))?;
        if self.options.grid_only && !GEOMETRY.contains(&kw) {
            lex.pos = end + 1;
            return skip_records(src, lex, kw, &tok);
        }
        let all = Region::all(dims);
        let region = self.region.unwrap_or(all);
        let spec = Spec {
            cap: region.len().min(self.left()),
            default: Some(if kw == "ACTNUM" { 1.0 } else { f32::NAN }),
            // Sizes and tops are checked when the geometry is built; an infinite
            // property value is a value (EQUALS and MULTIPLY can make one too).
            finite: false,
        };
        let values = match numbers::parse(b, start, end, &spec, src.pages) {
            Ok(v) => v,
            Err(e) if known => return Err(src.err(e.offset, kw, e.message)),
            Err(_) => {
                lex.pos = start;
                return skip_records(src, lex, kw, &tok);
            }
        };
        lex.pos = end + 1;
        let more = lex.peek().is_some_and(|t| !is_keyword(&t, b));
        let top_layer = region == all
            && ["DX", "DY", "DZ", "TOPS"].contains(&kw)
            && values.len() == dims.nx * dims.ny;
        let target = if top_layer {
            Region::top_layer(dims)
        } else {
            region
        };
        if more || values.len() != target.len() {
            if known {
                let what = if more {
                    "more than one record".to_string()
                } else {
                    format!("{} values", values.len())
                };
                return Err(src.err(
                    tok.at,
                    kw,
                    format!(
                        "has {what}, the grid{} needs {}",
                        if region == all { "" } else { "'s BOX" },
                        region.len()
                    ),
                ));
            }
            return skip_records(src, lex, kw, &tok);
        }
        let Some(cells) = self.cells.as_ref() else {
            return Ok(());
        };
        let extra = if cells.needs_allocation(kw, target) {
            dims.cell_count()
        } else {
            0
        };
        self.charge(values.len() + extra, src, tok.at, kw)?;
        if let Some(cells) = self.cells.as_mut() {
            cells.assign(kw, target, values);
        }
        Ok(())
    }

    /// The grid the deck describes.
    fn finish(mut self) -> Result<CornerPointGrid> {
        let root = self.root.clone();
        let Some(mut cells) = self.cells.take() else {
            return Err(Error::model(
                &root,
                "SPECGRID",
                "no SPECGRID or DIMENS in the deck",
            ));
        };
        let dims = cells.dims;
        let (coord, zcorn, block) = match (self.coord.take(), self.zcorn.take()) {
            (Some(c), Some(z)) => (c, z, false),
            (None, None) if block::present(&cells.arrays, &self.vectors) => {
                if block::cost(dims).is_none_or(|c| c > self.left()) {
                    return Err(Error::model(
                        &root,
                        "DX",
                        format!(
                            "a block-centred grid of {} cells is more than a deck of {} bytes can describe",
                            dims.cell_count(),
                            self.bytes_seen
                        ),
                    ));
                }
                let (c, z) = block::to_corner_point(dims, &cells.arrays, &self.vectors)
                    .map_err(|(kw, m)| Error::model(&root, &kw, m))?;
                (c, z, true)
            }
            (Some(_), None) => return Err(Error::model(&root, "ZCORN", "no ZCORN in the deck")),
            (None, Some(_)) => return Err(Error::model(&root, "COORD", "no COORD in the deck")),
            (None, None) => {
                return Err(Error::model(
                    &root,
                    "ZCORN",
                    "no ZCORN and COORD (nor DX/DY/DZ/TOPS) in the deck",
                ));
            }
        };
        let actnum = cells
            .arrays
            .remove("ACTNUM")
            .map(|a| a.iter().map(|&v| v != 0.0).collect());
        let mut grid = CornerPointGrid::from_arrays(dims, coord, zcorn, actnum)
            .map_err(|e| Error::model(&root, "", e.to_string()))?;
        grid.mapaxes = self.mapaxes;
        grid.units = self.units.unwrap_or_default();
        grid.warnings = std::mem::take(&mut self.warnings);
        if !self.options.grid_only {
            for (name, values) in cells.arrays {
                if block && ["DX", "DY", "DZ", "TOPS"].contains(&name.as_str()) {
                    continue;
                }
                let array = Array3::from_shape_vec((dims.nz, dims.ny, dims.nx), values)
                    .map_err(|e| Error::model(&root, &name, e.to_string()))?;
                grid.set_property(&name, array)
                    .map_err(|e| Error::model(&root, &name, e.to_string()))?;
            }
        }
        Ok(grid)
    }
}

/// The units a RUNSPEC unit-system keyword implies.
fn unit_system(kw: &str) -> Option<Units> {
    match kw {
        "LAB" => Some(Units::Centimetres),
        other => Units::parse(other),
    }
}

/// Opens an INCLUDE file, refusing what is not a regular file (a FIFO or a device
/// would block or never end).
fn open(path: &Path) -> std::io::Result<File> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(std::io::Error::other("not a regular file"));
    }
    File::open(path)
}

/// One short record (SPECGRID, BOX, an EQUALS line ...), up to its `/`, with
/// repeats expanded: `3*` is three defaulted items, `2*7` two items `7`. More than
/// `max` items means the terminator is missing.
fn record<'a>(
    src: &Src<'a>,
    lex: &mut Lexer,
    kw: &str,
    tok: &Token,
    max: usize,
) -> Result<Vec<Item<'a>>> {
    let b = src.bytes;
    let mut items = Vec::new();
    loop {
        let t = lex.next_token().ok_or_else(|| src.truncated(tok, kw))?;
        match t.kind {
            Kind::Slash => return Ok(items),
            Kind::Quoted { closed: false } => {
                return Err(src.err(t.at, kw, "unterminated quoted string"));
            }
            Kind::Quoted { closed: true } => items.push(Item {
                text: Some(t.text(b)),
                at: t.at,
            }),
            Kind::Word => {
                let text = t.text(b);
                let star = text.iter().position(|&c| c == b'*');
                match star {
                    Some(s) if s > 0 && text[..s].iter().all(u8::is_ascii_digit) => {
                        let n = text[..s]
                            .iter()
                            .try_fold(0usize, |n, &d| {
                                n.checked_mul(10)?.checked_add(usize::from(d - b'0'))
                            })
                            .filter(|&n| n >= 1 && n <= max.saturating_sub(items.len()))
                            .ok_or_else(|| {
                                src.err(t.at, kw, format!("bad repeat '{}'", shown(text)))
                            })?;
                        let value = (s + 1 < text.len()).then(|| &text[s + 1..]);
                        items.extend((0..n).map(|_| Item {
                            text: value,
                            at: t.at,
                        }));
                    }
                    _ => items.push(Item {
                        text: Some(text),
                        at: t.at,
                    }),
                }
            }
        }
        if items.len() > max {
            return Err(src.err(
                tok.at,
                kw,
                format!("more than {max} items before '/' (is the '/' missing?)"),
            ));
        }
    }
}

/// A positive integer item.
fn positive(src: &Src, kw: &str, item: &Item) -> Result<usize> {
    let text = item.text.unwrap_or_default();
    let n = text.iter().try_fold(0usize, |n, &d| {
        d.is_ascii_digit()
            .then_some(())
            .and_then(|_| n.checked_mul(10)?.checked_add(usize::from(d - b'0')))
    });
    match n {
        Some(n) if n > 0 && !text.is_empty() => Ok(n),
        _ => Err(src.err(
            item.at,
            kw,
            format!("'{}' is not a positive integer", shown(text)),
        )),
    }
}

/// A box from up to six items `i1 i2 j1 j2 k1 k2` (1-based, inclusive), missing or
/// defaulted ones taken from `default`.
fn region(
    src: &Src,
    kw: &str,
    tok: &Token,
    items: &[Item],
    default: Region,
    dims: Dims,
) -> Result<Region> {
    if items.len() > 6 {
        return Err(src.err(tok.at, kw, "more than six box bounds"));
    }
    let mut bounds = [None; 6];
    for (slot, item) in bounds.iter_mut().zip(items) {
        if item.text.is_some() {
            *slot = Some(positive(src, kw, item)?);
        }
    }
    Region::from_bounds(bounds, default, dims).map_err(|m| src.err(tok.at, kw, m))
}

/// Skips tokens up to and including the `/` that ends a record.
fn skip_record(src: &Src, lex: &mut Lexer, kw: &str, tok: &Token) -> Result<()> {
    loop {
        let t = lex.next_token().ok_or_else(|| src.truncated(tok, kw))?;
        match t.kind {
            Kind::Slash => return Ok(()),
            Kind::Quoted { closed: false } => {
                return Err(src.err(t.at, kw, "unterminated quoted string"));
            }
            _ => {}
        }
    }
}

/// Skips the records of a keyword whose data is not read: they end at the next
/// keyword or the end of the file.
fn skip_records(src: &Src, lex: &mut Lexer, kw: &str, tok: &Token) -> Result<()> {
    loop {
        match lex.peek() {
            None => return Ok(()),
            Some(t) if is_keyword(&t, src.bytes) => return Ok(()),
            Some(_) => skip_record(src, lex, kw, tok)?,
        }
    }
}

/// Skips records up to and including an empty one (FAULTS, MULTFLT, ...).
fn skip_until_empty_record(src: &Src, lex: &mut Lexer, kw: &str, tok: &Token) -> Result<()> {
    loop {
        match lex.peek().map(|t| t.kind) {
            None => return Err(src.truncated(tok, kw)),
            Some(Kind::Slash) => {
                lex.next_token();
                return Ok(());
            }
            Some(_) => skip_record(src, lex, kw, tok)?,
        }
    }
}
