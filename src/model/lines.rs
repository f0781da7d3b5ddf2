//! Physical-line layer of the `.adm` reader: splits a dataset text (after its title line)
//! into the readable pieces that [`super::statement`] parses. Each physical line loses
//! its `!` comment and line ending; `;` splits a line into several statements; a line whose
//! first non-blank character is `,` continues the statement before it. NUL bytes, tabs
//! and carriage returns count as blanks. All positions are byte offsets into the text.

use crate::diag::{Code, Diagnostic};
use std::borrow::Cow;
use std::ops::Range;

/// True for the bytes the statement layer reads as blanks (NUL included: FAST writes
/// NUL-padded strings).
pub fn is_blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\0' | 0x0B | 0x0C)
}

/// What one readable piece of a line is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PieceKind {
    /// Starts a statement (a keyword is expected).
    Head,
    /// Continues the current statement; `comma` is the offset of its leading comma.
    Continuation { comma: usize },
    /// A whole-line comment; the range is the comment text after `!`.
    Comment,
}

/// The readable bytes of one physical line or of one `;`-separated part of it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Piece {
    pub kind: PieceKind,
    /// Readable bytes: after a continuation comma, before any comment, `;` or line end.
    pub range: Range<usize>,
    /// 1-based line number.
    pub line: usize,
    /// A `;` ended this piece: no continuation line may follow it.
    pub closed: bool,
}

/// The byte range of line 1, the title (without its line ending).
pub fn title_span(text: &str) -> Range<usize> {
    let end = text.find('\n').unwrap_or(text.len());
    let bytes = text.as_bytes();
    let mut e = end;
    while e > 0 && bytes[e - 1] == b'\r' {
        e -= 1;
    }
    0..e
}

/// Splits everything after the title line into pieces, skipping blank lines. Also returns
/// the span of the first run of NUL bytes, if any.
pub fn pieces(text: &str) -> (Vec<Piece>, Option<Range<usize>>) {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut nul = None;
    let mut start = match text.find('\n') {
        Some(i) => i + 1,
        None => return (out, None),
    };
    let mut line = 2;
    while start <= bytes.len() {
        let end = text[start..].find('\n').map_or(bytes.len(), |i| start + i);
        if nul.is_none() {
            if let Some(i) = bytes[start..end].iter().position(|&b| b == 0) {
                let n = bytes[start + i..end]
                    .iter()
                    .take_while(|&&b| b == 0)
                    .count();
                nul = Some(start + i..start + i + n);
            }
        }
        split_line(bytes, start..end, line, &mut out);
        start = end + 1;
        line += 1;
    }
    (out, nul)
}

/// Adds the pieces of one physical line.
fn split_line(bytes: &[u8], line_range: Range<usize>, line: usize, out: &mut Vec<Piece>) {
    let mut pos = line_range.start;
    let end = line_range.end;
    let mut first = true;
    loop {
        while pos < end && is_blank(bytes[pos]) {
            pos += 1;
        }
        if pos >= end {
            return;
        }
        if bytes[pos] == b'!' {
            if first {
                let mut e = end;
                while e > pos + 1 && bytes[e - 1] == b'\r' {
                    e -= 1;
                }
                out.push(Piece {
                    kind: PieceKind::Comment,
                    range: pos + 1..e,
                    line,
                    closed: false,
                });
            }
            return;
        }
        let (kind, content_start) = if first && bytes[pos] == b',' {
            (PieceKind::Continuation { comma: pos }, pos + 1)
        } else {
            (PieceKind::Head, pos)
        };
        let (stop, semicolon) = readable_end(bytes, content_start, end);
        out.push(Piece {
            kind,
            range: content_start..stop,
            line,
            closed: semicolon,
        });
        if !semicolon {
            return;
        }
        pos = stop + 1;
        first = false;
    }
}

/// Where the readable part starting at `start` stops: at a `!` or `;` outside double
/// quotes, or at the line end (trailing carriage returns removed). The flag tells a `;`.
fn readable_end(bytes: &[u8], start: usize, end: usize) -> (usize, bool) {
    let mut quoted = false;
    for (i, &b) in bytes.iter().enumerate().take(end).skip(start) {
        match b {
            b'"' => quoted = !quoted,
            b'!' if !quoted => return (i, false),
            b';' if !quoted => return (i, true),
            _ => {}
        }
    }
    let mut e = end;
    while e > start && bytes[e - 1] == b'\r' {
        e -= 1;
    }
    (e, false)
}

/// The name in an `adams_view_name='…'` comment, if the comment holds one.
pub fn view_name(comment: &str) -> Option<String> {
    const KEY: &str = "adams_view_name";
    let at = comment
        .as_bytes()
        .windows(KEY.len())
        .position(|w| w.eq_ignore_ascii_case(KEY.as_bytes()))?;
    let rest = comment[at + KEY.len()..].trim_start();
    let rest = rest.strip_prefix('=')?.trim_start();
    let quote = rest.chars().next().filter(|c| *c == '\'' || *c == '"')?;
    let body = &rest[1..];
    let close = body.find(quote)?;
    Some(body[..close].to_string())
}

/// Turns file bytes into text for [`super::read_statements`]. Valid UTF-8 is kept as is;
/// any other byte is read as Latin-1 (old Windows-written datasets have `kN\xb7m` in
/// strings), with one warning at the first such byte (spans refer to the returned text).
pub fn decode(bytes: &[u8]) -> (Cow<'_, str>, Option<Diagnostic>) {
    if let Ok(text) = std::str::from_utf8(bytes) {
        return (Cow::Borrowed(text), None);
    }
    let mut text = String::with_capacity(bytes.len() + 16);
    let mut first_bad = None;
    for chunk in bytes.utf8_chunks() {
        text.push_str(chunk.valid());
        for &b in chunk.invalid() {
            first_bad.get_or_insert(text.len()..text.len() + 2);
            text.push(char::from(b));
        }
    }
    let diag = first_bad.map(|span| {
        Diagnostic::warning(
            Code::EncodingRepaired,
            span,
            "the dataset is not valid UTF-8",
        )
        .with_note("bytes that are not UTF-8 are read as Latin-1")
    });
    (Cow::Owned(text), diag)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn title_is_skipped_and_lines_are_classified() {
        let text = "MARKER/1 title\r\nPART/1\r\n, MASS = 1 ! c\r\n\r\n! note\r\n  ,X=1";
        let (p, nul) = pieces(text);
        assert_eq!(nul, None);
        let kinds: Vec<_> = p
            .iter()
            .map(|p| (p.kind, &text[p.range.clone()], p.line))
            .collect();
        assert_eq!(kinds[0], (PieceKind::Head, "PART/1", 2));
        assert!(matches!(
            kinds[1],
            (PieceKind::Continuation { .. }, " MASS = 1 ", 3)
        ));
        assert_eq!(kinds[2], (PieceKind::Comment, " note", 5));
        assert!(matches!(
            kinds[3],
            (PieceKind::Continuation { comma: 52 }, "X=1", 6)
        ));
    }

    #[test]
    fn semicolons_split_statements_outside_quotes() {
        let text = "t\nPART/1;PART/2, C=\"a;b!\";\n";
        let (p, _) = pieces(text);
        let got: Vec<_> = p
            .iter()
            .map(|p| (&text[p.range.clone()], p.closed))
            .collect();
        assert_eq!(got, [("PART/1", true), ("PART/2, C=\"a;b!\"", true)]);
    }

    #[test]
    fn nul_bytes_are_blanks_and_reported_once() {
        let text = "t\nSTRING/31\n, STRING = \0\0\0\n, X=\0";
        let (p, nul) = pieces(text);
        assert_eq!(nul, Some(23..26));
        assert_eq!(p.len(), 3);
    }

    #[test]
    fn non_utf8_bytes_are_read_as_latin1() {
        let (text, diag) = decode(b"t\nSTRING/1, STRING = (kN\xb7m)\n");
        assert_eq!(text, "t\nSTRING/1, STRING = (kN\u{b7}m)\n");
        assert_eq!(diag.map(|d| d.span), Some(24..26));
        assert!(matches!(decode(b"ok"), (Cow::Borrowed("ok"), None)));
    }

    #[test]
    fn view_names_are_read_from_comments() {
        assert_eq!(
            view_name("   adams_view_name='JOINT_2'"),
            Some("JOINT_2".into())
        );
        assert_eq!(view_name(" ADAMS_VIEW_NAME = \"a.b\""), Some("a.b".into()));
        assert_eq!(view_name(" adams_view_units='length'"), None);
        assert_eq!(view_name(" adams_view_name='open"), None);
    }
}
