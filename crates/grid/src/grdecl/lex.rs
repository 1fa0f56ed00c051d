//! Tokens of a text deck, straight from the bytes.
//!
//! Decks are not reliably UTF-8 (comments in Latin-1 are common, see the `ø` in the
//! SPE10 deck), so everything here works on `&[u8]` and never allocates per token.
//! Only the keyword level goes through [`Lexer`]; bulk numeric data is read by
//! [`super::numbers`], which shares the byte classes defined here.

use memchr::memchr;

/// Bytes that separate tokens: ASCII whitespace and the comma, which decks use as
/// a separator too.
#[inline]
pub(super) fn is_sep(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r' | b',' | 0x0b | 0x0c)
}

/// Does a `--` comment (running to the end of the line) start at `i`?
#[inline]
pub(super) fn comment_at(b: &[u8], i: usize) -> bool {
    b.get(i) == Some(&b'-') && b.get(i + 1) == Some(&b'-')
}

/// The position of the next newline at or after `i`, or the end of the bytes.
#[inline]
pub(super) fn line_end(b: &[u8], i: usize) -> usize {
    let i = i.min(b.len());
    memchr(b'\n', &b[i..]).map_or(b.len(), |p| i + p)
}

/// 1-based line number of byte `offset`. Only computed when reporting an error, so
/// the hot paths never count lines.
pub(super) fn line_at(b: &[u8], offset: usize) -> usize {
    1 + memchr::memchr_iter(b'\n', &b[..offset.min(b.len())]).count()
}

/// A token's bytes for a message: lossy UTF-8, control characters escaped, cut to
/// 40 characters so a megabyte of garbage does not end up in an error.
pub(super) fn shown(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(40)]);
    let mut s: String = text.escape_debug().collect();
    if bytes.len() > 40 {
        s.push_str("...");
    }
    s
}

/// What a token is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// The record terminator `/`.
    Slash,
    /// A `'quoted'` string; `closed` is false when the line ended before the quote
    /// did (strings never span lines in a deck).
    Quoted { closed: bool },
    /// Anything else: a keyword, a number, a repeat `3*` or `2*0.5`, a bare word.
    Word,
}

/// One token: `text` is its content (without quotes), `at` where it starts in the
/// file (for line numbers), `line_start` whether it is the first token of its line.
#[derive(Clone, Copy, Debug)]
pub(super) struct Token {
    pub kind: Kind,
    pub at: usize,
    pub start: usize,
    pub end: usize,
    pub line_start: bool,
}

impl Token {
    pub fn text<'a>(&self, bytes: &'a [u8]) -> &'a [u8] {
        &bytes[self.start..self.end]
    }
}

/// A cursor over one file's bytes.
#[derive(Clone)]
pub(super) struct Lexer<'a> {
    pub bytes: &'a [u8],
    pub pos: usize,
}

impl<'a> Lexer<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Lexer { bytes, pos: 0 }
    }

    /// Skips separators and comments. Returns whether the next token starts a line
    /// (a newline was crossed, or this is the start of the file).
    pub fn skip_blank(&mut self) -> bool {
        let b = self.bytes;
        let mut newline = self.pos == 0;
        let mut i = self.pos;
        while i < b.len() {
            let c = b[i];
            if c == b'\n' {
                newline = true;
                i += 1;
            } else if is_sep(c) {
                i += 1;
            } else if comment_at(b, i) {
                i = line_end(b, i);
            } else {
                break;
            }
        }
        self.pos = i;
        newline
    }

    /// The next token, `None` at the end of the file.
    pub fn next_token(&mut self) -> Option<Token> {
        let line_start = self.skip_blank();
        let b = self.bytes;
        let at = self.pos;
        let c = *b.get(at)?;
        let (kind, start, end, pos) = match c {
            b'/' => (Kind::Slash, at, at + 1, at + 1),
            b'\'' => {
                let eol = line_end(b, at + 1);
                match memchr(b'\'', &b[at + 1..eol]) {
                    Some(q) => (
                        Kind::Quoted { closed: true },
                        at + 1,
                        at + 1 + q,
                        at + 2 + q,
                    ),
                    None => (Kind::Quoted { closed: false }, at + 1, eol, eol),
                }
            }
            _ => {
                let mut j = at + 1;
                while j < b.len() && !ends_word(b, j) {
                    j += 1;
                }
                (Kind::Word, at, j, j)
            }
        };
        self.pos = pos;
        Some(Token {
            kind,
            at,
            start,
            end,
            line_start,
        })
    }

    /// The next token without consuming it.
    pub fn peek(&self) -> Option<Token> {
        self.clone().next_token()
    }

    /// Ignores the rest of this line and the `n - 1` lines after it. Stops on the
    /// last newline, so the token after it is still seen to start a line.
    pub fn skip_lines(&mut self, n: usize) {
        let mut p = self.pos;
        for k in 0..n {
            if k > 0 {
                p = (p + 1).min(self.bytes.len());
            }
            p = line_end(self.bytes, p);
        }
        self.pos = p;
    }
}

/// Does a bare word end at `j`: a separator, a slash (`1 2 3/` is legal), a quote or
/// a comment.
#[inline]
fn ends_word(b: &[u8], j: usize) -> bool {
    let c = b[j];
    is_sep(c) || c == b'/' || c == b'\'' || comment_at(b, j)
}

/// The keyword a word spells, upper case: a letter, then letters, digits, `_`, `-` or
/// `+` (`MULTX-`), at most 8 in all, as Eclipse keywords are.
pub(super) fn keyword(word: &[u8]) -> Option<String> {
    let ok = (1..=8).contains(&word.len())
        && word[0].is_ascii_alphabetic()
        && word
            .iter()
            .all(|&c| c.is_ascii_alphanumeric() || matches!(c, b'_' | b'-' | b'+'));
    ok.then(|| String::from_utf8_lossy(word).to_ascii_uppercase())
}

/// Is this token a keyword (a bare word that spells one)?
pub(super) fn is_keyword(t: &Token, bytes: &[u8]) -> bool {
    t.kind == Kind::Word && keyword(t.text(bytes)).is_some()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tokens(s: &str) -> Vec<(Kind, String, bool)> {
        let mut lex = Lexer::new(s.as_bytes());
        std::iter::from_fn(|| lex.next_token())
            .map(|t| {
                (
                    t.kind,
                    String::from_utf8_lossy(t.text(s.as_bytes())).into_owned(),
                    t.line_start,
                )
            })
            .collect()
    }

    #[test]
    fn words_slashes_quotes_and_comments() {
        let t = tokens("ZCORN -- a comment / with slash\n 1,2 3*4 5/ 'a b' 'open\nX--c\n");
        let texts: Vec<&str> = t.iter().map(|t| t.1.as_str()).collect();
        assert_eq!(
            texts,
            ["ZCORN", "1", "2", "3*4", "5", "/", "a b", "open", "X"]
        );
        assert_eq!(t[5].0, Kind::Slash);
        assert_eq!(t[6].0, Kind::Quoted { closed: true });
        assert_eq!(t[7].0, Kind::Quoted { closed: false });
        let starts: Vec<bool> = t.iter().map(|t| t.2).collect();
        assert_eq!(
            starts,
            [true, true, false, false, false, false, false, false, true]
        );
    }

    #[test]
    fn keywords_are_short_identifiers() {
        assert_eq!(keyword(b"multx-").as_deref(), Some("MULTX-"));
        assert_eq!(keyword(b"SWATINIT").as_deref(), Some("SWATINIT"));
        assert!(keyword(b"COMPARATIVE").is_none());
        assert!(keyword(b"1*").is_none());
        assert!(keyword(b"\xff").is_none());
    }

    #[test]
    fn lines_and_shown_text() {
        let b = b"a\nb\n\nc";
        assert_eq!(line_at(b, 0), 1);
        assert_eq!(line_at(b, 2), 2);
        assert_eq!(line_at(b, 5), 4);
        assert_eq!(shown(b"\xffab\n"), "\u{fffd}ab\\n");
        assert!(shown(&[b'x'; 100]).ends_with("..."));
    }

    #[test]
    fn skipped_lines_keep_the_next_token_at_a_line_start() {
        let mut lex = Lexer::new(
            b"TITLE
DIMENS of it
DIMENS",
        );
        lex.next_token();
        lex.skip_lines(2);
        let t = lex.next_token().unwrap();
        assert!(t.line_start && t.at == 19);
    }
}
