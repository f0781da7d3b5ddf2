//! A read position that walks the pieces of one `.adm` statement (its head line and its
//! continuation lines, see [`super::lines`]) as one stream. Moving from one piece to the
//! next steps over a line break and a continuation comma, which the argument parser
//! reads as a separator. Every stop is at an ASCII byte or a piece boundary, so slicing
//! the text there never splits a character.

use super::lines::{is_blank, Piece};
use std::ops::Range;

/// Position inside one statement's pieces.
pub(super) struct Cursor<'a> {
    pub text: &'a str,
    bytes: &'a [u8],
    pieces: &'a [Piece],
    piece: usize,
    /// Byte offset into `text`.
    pub pos: usize,
}

/// A saved position to come back to after looking ahead.
#[derive(Clone, Copy)]
pub(super) struct Mark(usize, usize);

impl<'a> Cursor<'a> {
    /// A cursor at the start of the first piece; `pieces` must not be empty.
    pub fn new(text: &'a str, pieces: &'a [Piece]) -> Self {
        let pos = pieces.first().map_or(0, |p| p.range.start);
        Cursor {
            text,
            bytes: text.as_bytes(),
            pieces,
            piece: 0,
            pos,
        }
    }

    fn piece_end(&self) -> usize {
        self.pieces
            .get(self.piece)
            .map_or(self.pos, |p| p.range.end)
    }

    /// The byte under the cursor, or `None` at the end of the current piece.
    pub fn peek(&self) -> Option<u8> {
        (self.pos < self.piece_end()).then(|| self.bytes[self.pos])
    }

    /// The byte after the one under the cursor, within the piece.
    pub fn peek2(&self) -> Option<u8> {
        (self.pos + 1 < self.piece_end()).then(|| self.bytes[self.pos + 1])
    }

    pub fn bump(&mut self) {
        if self.pos < self.piece_end() {
            self.pos += 1;
        }
    }

    /// Moves to the start of the next piece; false at the end of the statement.
    pub fn next_piece(&mut self) -> bool {
        match self.pieces.get(self.piece + 1) {
            Some(p) => {
                self.piece += 1;
                self.pos = p.range.start;
                true
            }
            None => false,
        }
    }

    /// 1-based line of the cursor.
    pub fn line(&self) -> usize {
        self.pieces.get(self.piece).map_or(0, |p| p.line)
    }

    pub fn mark(&self) -> Mark {
        Mark(self.piece, self.pos)
    }

    pub fn reset(&mut self, mark: Mark) {
        self.piece = mark.0;
        self.pos = mark.1;
    }

    pub fn skip_blanks(&mut self) {
        while self.peek().is_some_and(is_blank) {
            self.pos += 1;
        }
    }

    /// Skips blanks, commas, `\` and line breaks; false when the statement has ended.
    pub fn skip_separators(&mut self) -> bool {
        loop {
            self.skip_blanks();
            match self.peek() {
                Some(b',' | b'\\') => self.pos += 1,
                Some(_) => return true,
                None if self.next_piece() => {}
                None => return false,
            }
        }
    }

    /// Reads a keyword (`[A-Za-z_][A-Za-z0-9_]*`); empty when none starts here.
    pub fn read_name(&mut self) -> &'a str {
        let start = self.pos;
        if self
            .peek()
            .is_some_and(|b| b.is_ascii_alphabetic() || b == b'_')
        {
            while self
                .peek()
                .is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_')
            {
                self.pos += 1;
            }
        }
        &self.text[start..self.pos]
    }

    /// True when a keyword followed by `=` starts here (an assignment, never an expression).
    pub fn at_assignment(&mut self) -> bool {
        let mark = self.mark();
        let found = !self.read_name().is_empty() && {
            self.skip_blanks();
            self.peek() == Some(b'=')
        };
        self.reset(mark);
        found
    }

    /// Skips to the next comma or `\` outside parentheses, or to the end of the piece.
    pub fn skip_to_separator(&mut self) {
        let mut depth = 0usize;
        while let Some(b) = self.peek() {
            match b {
                b'(' | b'[' => depth += 1,
                b')' | b']' => depth = depth.saturating_sub(1),
                b',' | b'\\' if depth == 0 => return,
                _ => {}
            }
            self.pos += 1;
        }
    }

    /// End of the readable text of the current piece without trailing blanks.
    pub fn trimmed_piece_end(&self) -> usize {
        trim_end(self.bytes, self.pos..self.piece_end())
    }

    /// Moves to the end of the current piece.
    pub fn skip_to_piece_end(&mut self) {
        self.pos = self.piece_end();
    }

    /// The span of the character under the cursor (empty at the end of a piece).
    pub fn char_span(&self) -> Range<usize> {
        let len = match self.peek() {
            None => 0,
            Some(_) => self
                .text
                .get(self.pos..)
                .and_then(|s| s.chars().next())
                .map_or(1, char::len_utf8),
        };
        self.pos..self.pos + len
    }

    /// How an error message names what is under the cursor.
    pub fn describe(&self) -> String {
        match self.text.get(self.char_span()) {
            Some(s) if !s.is_empty() => format!("`{}`", s.escape_debug()),
            _ => "the end of the line".to_string(),
        }
    }
}

/// The end of `range` in `bytes` with trailing blanks removed.
pub(super) fn trim_end(bytes: &[u8], range: Range<usize>) -> usize {
    let mut end = range.end;
    while end > range.start && is_blank(bytes[end - 1]) {
        end -= 1;
    }
    end
}
