//! Physical-line layer of the command-file (`.acf`) reader: groups the lines after the
//! header into one [`Piece`] list per command, for the same cursor and argument parser
//! the dataset statements use. The command language continues a command with `&` at the
//! end of a line (multibody spec §1.3); the next line may start with the `,` before its
//! first argument or not (`integrator/gstiff, &` then `error = 1.0e-4`). A line whose
//! first non-blank character is `,` also continues the command before it, as in a
//! dataset. `!` starts a comment; blank and comment lines may stand between continued
//! lines. Positions are byte offsets into the whole file.

use super::lines::{is_blank, Piece, PieceKind};
use std::ops::Range;

/// The readable part of the line at `range`: without its comment, line ending and
/// surrounding blanks (empty when there is none).
pub(super) fn readable(text: &str, range: Range<usize>) -> Range<usize> {
    let bytes = text.as_bytes();
    let mut quoted = false;
    let mut end = range.end;
    for (i, &b) in bytes.iter().enumerate().take(range.end).skip(range.start) {
        match b {
            b'"' => quoted = !quoted,
            b'!' if !quoted => {
                end = i;
                break;
            }
            _ => {}
        }
    }
    let mut start = range.start;
    while start < end && is_blank(bytes[start]) {
        start += 1;
    }
    while end > start && is_blank(bytes[end - 1]) {
        end -= 1;
    }
    start..end
}

/// The byte ranges of the lines of `text` from offset `from` on, with their 1-based
/// numbers (`first` is the number of the line at `from`).
pub(super) fn lines(text: &str, from: usize, first: usize) -> Vec<(Range<usize>, usize)> {
    let mut out = Vec::new();
    let mut start = from;
    let mut line = first;
    while start < text.len() {
        let end = text[start..].find('\n').map_or(text.len(), |i| start + i);
        out.push((start..end, line));
        start = end + 1;
        line += 1;
    }
    out
}

/// The commands from offset `from` (line number `first`) on, each as its pieces.
pub(super) fn command_groups(text: &str, from: usize, first: usize) -> Vec<Vec<Piece>> {
    let bytes = text.as_bytes();
    let mut groups: Vec<Vec<Piece>> = Vec::new();
    // The last line ended with `&`: the next readable line continues the command.
    let mut open = false;
    for (range, line) in lines(text, from, first) {
        let r = readable(text, range);
        if r.is_empty() {
            continue;
        }
        let continued = r.end > r.start && bytes[r.end - 1] == b'&';
        let mut end = if continued { r.end - 1 } else { r.end };
        while end > r.start && is_blank(bytes[end - 1]) {
            end -= 1;
        }
        let comma = bytes[r.start] == b',';
        let piece = if (open || comma) && !groups.is_empty() {
            let content = if comma { r.start + 1 } else { r.start };
            Piece {
                kind: PieceKind::Continuation { comma: r.start },
                range: content..end.max(content),
                line,
                closed: false,
            }
        } else {
            groups.push(Vec::new());
            Piece {
                kind: PieceKind::Head,
                range: r.start..end,
                line,
                closed: false,
            }
        };
        if let Some(g) = groups.last_mut() {
            g.push(piece);
        }
        open = continued;
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(text: &str) -> Vec<Vec<&str>> {
        command_groups(text, 0, 1)
            .iter()
            .map(|g| g.iter().map(|p| &text[p.range.clone()]).collect())
            .collect()
    }

    #[test]
    fn ampersands_join_lines_with_or_without_a_comma() {
        // projectchrono/chrono data/adams/*.acf and bthornton191/adamspy test/files/test.acf.
        let chrono =
            "output/noseparator\r\nintegrator/gstiff, &\r\n\terror = 1.0e-4, hmax=1e-5\r\nstop";
        assert_eq!(
            texts(chrono),
            [
                vec!["output/noseparator"],
                vec!["integrator/gstiff,", "error = 1.0e-4, hmax=1e-5"],
                vec!["stop"]
            ]
        );
        let adamspy = "INTEGRATOR/ &\n, HHT &\n! a comment\n, ERROR = 1.0E-05\n!\nsim/stat\n";
        assert_eq!(
            texts(adamspy),
            [
                vec!["INTEGRATOR/", " HHT", " ERROR = 1.0E-05"],
                vec!["sim/stat"]
            ]
        );
    }

    #[test]
    fn a_leading_comma_continues_and_comments_end_lines() {
        let t = "SIMULATE/DYNAMIC ! run\n, END = 1 ! one second\n\nSTOP";
        assert_eq!(
            texts(t),
            [vec!["SIMULATE/DYNAMIC", " END = 1"], vec!["STOP"]]
        );
    }
}
