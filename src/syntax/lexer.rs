//! Lexer: turns expression text into `(start, Tok, end)` triples for the LALRPOP parser.
//!
//! Two layers. `Raw` is the logos token set (numbers, names, operators, blanks,
//! continuation joins, comments). [`lex`] then walks the raw tokens once and applies the
//! rules that need a neighbour: a name directly followed by `(` is a call (a blank in
//! between is diagnosed, spec §1.4); a number must not run into a letter or digit
//! (`1.5D3`, `10DTOR`, decision 4); `* *` is not a power; relational operators get a hint;
//! a line break is a blank when the next line that is neither blank nor a whole-line `!`
//! comment continues the expression (a comma first) or the text ends there, and an error
//! otherwise; bracket depth is limited (decision 11). The lexer never stops at an error:
//! it records a diagnostic and hands the parser a placeholder token so every error is
//! reported. Spans are byte offsets into the text given (callers shift them for `.adm` files).

use crate::diag::{Code, Diagnostic};
use crate::syntax::ast::Names;
use logos::Logos;

/// Deepest nesting of `(`, `[` and calls accepted (decision 11: at least 1000).
pub const MAX_BRACKET_DEPTH: usize = 1024;

/// The raw token set, as logos recognises it.
#[derive(Logos, Clone, Copy, Debug, PartialEq)]
enum Raw {
    /// Blanks; a byte-order mark counts as one (editors put it at the start of files).
    #[regex(r"[ \t\x0C\u{FEFF}]+")]
    Blank,
    /// A line break followed by optional blanks and a comma in column one: the
    /// statement continues (spec §1.5.1), and the join counts as one blank.
    #[regex(r"\r?\n[ \t]*,")]
    Continuation,
    #[regex(r"\r?\n")]
    Newline,
    /// `!` stops reading the line (spec §1.5.2).
    #[regex(r"![^\n]*", allow_greedy = true)]
    Comment,
    #[regex(r"([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+-]?[0-9]+)?[dD]?")]
    Number,
    /// Plain names and Adams View dotted names (`.model.part.marker`).
    #[regex(r"\.?[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*")]
    Name,
    #[token("+")]
    Plus,
    #[token("-")]
    Minus,
    #[token("*")]
    Star,
    #[token("**")]
    Pow,
    #[token("/")]
    Slash,
    #[token("%")]
    Percent,
    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    #[token("[")]
    LBracket,
    #[token("]")]
    RBracket,
    #[token(",")]
    Comma,
    #[token(":")]
    Colon,
    #[regex(r"<|>|<=|>=|==|=|/=|<>|&&|\|\||&|\|")]
    #[regex(r"\.([lL][tTeE]|[gG][tTeE]|[eE][qQ]|[nN][eE]|[aA][nN][dD]|[oO][rR]|[nN][oO][tT])\.")]
    Relational,
    #[token("^")]
    Caret,
    #[token("\\")]
    Backslash,
}

/// Tokens as the parser sees them. `Copy` and lifetime-free: names are kept in
/// [`Lexed::names`] and referred to by index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tok {
    /// A number literal.
    Num(f64),
    /// A bare name (constant or variable); index into [`Lexed::names`].
    Name(u32),
    /// A name directly followed by `(`: a function call.
    Call(u32),
    /// `IF(`: the arithmetic IF.
    If,
    /// `+`.
    Plus,
    /// `-`.
    Minus,
    /// `*`.
    Star,
    /// `**`.
    Pow,
    /// `/`.
    Slash,
    /// `%`: cross product.
    Percent,
    /// `(`.
    LParen,
    /// `)`.
    RParen,
    /// `[`.
    LBracket,
    /// `]`.
    RBracket,
    /// `,`.
    Comma,
    /// `:`.
    Colon,
    /// A relational or logical operator: already diagnosed, parsed as a binary operator
    /// so that the rest of the expression is still checked.
    Relational,
    /// Something that already produced a lexical diagnostic; parses as a value.
    Invalid,
}

/// The result of lexing one expression.
pub struct Lexed {
    /// `(start, token, end)` triples with byte offsets, as LALRPOP reads them.
    pub tokens: Vec<(usize, Tok, usize)>,
    /// Upper-cased names, indexed by [`Tok::Name`] and [`Tok::Call`].
    pub names: Names,
    /// Lexical errors, in order.
    pub diagnostics: Vec<Diagnostic>,
    /// True when lexing stopped early (bracket depth exceeded): the tokens are incomplete
    /// and the parser must not run.
    pub aborted: bool,
}

/// Value of a number literal: the digits as an `f64`, times π/180 with a `D` suffix.
pub fn number_value(text: &str) -> f64 {
    match text.as_bytes().last() {
        // The suffix is ASCII, so slicing it off keeps a char boundary.
        Some(b'd' | b'D') => parse_digits(&text[..text.len() - 1]) * (std::f64::consts::PI / 180.0),
        _ => parse_digits(text),
    }
}

fn parse_digits(text: &str) -> f64 {
    // Integers of up to 15 digits (IDs, most constants) are exact in an f64.
    if text.len() <= 15 {
        let mut n = 0u64;
        for b in text.bytes() {
            if !b.is_ascii_digit() {
                n = u64::MAX;
                break;
            }
            n = n * 10 + u64::from(b - b'0');
        }
        if n != u64::MAX {
            return n as f64;
        }
    }
    if let Some(v) = short_decimal(text) {
        return v;
    }
    // The regex admits only forms Rust's parser accepts ("1.", ".5", "1.E2" included).
    text.parse().unwrap_or(f64::NAN)
}

/// Value of a decimal of at most 15 significant digits and a decimal exponent within
/// ±22 (IDs and nearly every constant), without the general parser: the digits as an
/// integer are exact in an f64, and so is 10^k for k <= 22, so one IEEE multiplication or
/// division gives the correctly rounded value (Clinger's fast path). `None` otherwise.
fn short_decimal(text: &str) -> Option<f64> {
    let bytes = text.as_bytes();
    let (mut mantissa, mut digits, mut scale, mut point) = (0u64, 0u32, 0i32, false);
    let mut i = 0;
    while let Some(&b) = bytes.get(i) {
        match b {
            b'0'..=b'9' => {
                // Leading zeros are not significant.
                if mantissa != 0 || b != b'0' {
                    digits += 1;
                }
                mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
                scale -= i32::from(point);
            }
            b'.' if !point => point = true,
            b'e' | b'E' => break,
            _ => return None,
        }
        i += 1;
    }
    if digits > 15 {
        return None;
    }
    if i < bytes.len() {
        let exp = text[i + 1..].parse::<i32>().ok()?;
        scale = scale.checked_add(exp)?;
    }
    let m = mantissa as f64;
    match scale {
        0..=22 => Some(m * POWERS_OF_TEN[scale as usize]),
        -22..=-1 => Some(m / POWERS_OF_TEN[(-scale) as usize]),
        _ => None,
    }
}

/// 10^0 to 10^22, each exact in an f64.
const POWERS_OF_TEN: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

fn is_word_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b == b'.'
}

impl Lexed {
    /// Empty buffers, for [`lex_into`] to fill.
    pub fn new() -> Self {
        Lexed {
            tokens: Vec::new(),
            names: Names::default(),
            diagnostics: Vec::new(),
            aborted: false,
        }
    }
}

impl Default for Lexed {
    fn default() -> Self {
        Self::new()
    }
}

/// Lexes `src`. Never fails: problems become diagnostics plus [`Tok::Invalid`].
pub fn lex(src: &str) -> Lexed {
    let mut out = Lexed::new();
    lex_into(src, &mut out);
    out
}

/// Lexes `src` into `out`, replacing what it held but keeping its buffers, so a caller
/// that lexes many expressions allocates only while its buffers grow.
pub fn lex_into(src: &str, out: &mut Lexed) {
    let bytes = src.as_bytes();
    out.tokens.clear();
    out.names.clear();
    out.diagnostics.clear();
    out.aborted = false;
    let mut raw = Raw::lexer(src);
    let mut depth = 0usize;
    // End of the last token that was not a blank: decides "directly followed by".
    let mut blank_since: Option<usize> = None;
    while let Some(item) = raw.next() {
        let span = raw.span();
        let (start, end) = (span.start, span.end);
        let kind = match item {
            Ok(k) => k,
            Err(()) => {
                let ch = src[start..].chars().next().unwrap_or('\u{fffd}');
                let end = start + ch.len_utf8();
                let what = if ch == '\0' {
                    "NUL byte".to_string()
                } else {
                    format!("character {ch:?}")
                };
                let mut d = Diagnostic::error(
                    Code::UnexpectedChar,
                    start..end,
                    format!("unexpected {what} in an expression"),
                );
                if ch == '"' || ch == '\'' {
                    d = d.with_help("expressions have no strings; names are written bare");
                }
                out.diagnostics.push(d);
                out.tokens.push((start, Tok::Invalid, end));
                if end > span.end {
                    raw.bump(end - span.end);
                }
                blank_since = None;
                continue;
            }
        };
        let tok = match kind {
            Raw::Blank | Raw::Continuation | Raw::Comment => {
                blank_since.get_or_insert(start);
                continue;
            }
            Raw::Newline => {
                // Blank lines and whole-line comments may stand between a line and its
                // continuation, as between a dataset statement's lines. The lexer moves
                // past them either way, so no line is scanned twice.
                let next = after_break(src, end);
                raw.bump(next.at() - end);
                if let AfterBreak::Other(_) = next {
                    out.diagnostics.push(
                        Diagnostic::error(
                            Code::UnexpectedChar,
                            start..end,
                            "line break inside an expression",
                        )
                        .with_help(
                            "continue an expression on the next line with a comma in column one",
                        ),
                    );
                    blank_since = None;
                } else {
                    blank_since.get_or_insert(start);
                }
                continue;
            }
            Raw::Number => {
                // A number running straight into letters, digits or a dot is malformed.
                let mut stop = end;
                while stop < bytes.len() && is_word_byte(bytes[stop]) {
                    stop += 1;
                    // An exponent sign belongs to the malformed number (`1e+`, `2E-x`).
                    if matches!(bytes[stop - 1], b'e' | b'E')
                        && matches!(bytes.get(stop), Some(b'+' | b'-'))
                    {
                        stop += 1;
                    }
                }
                if stop > end {
                    raw.bump(stop - end);
                    let text = &src[start..stop];
                    let mut d = Diagnostic::error(
                        Code::BadNumber,
                        start..stop,
                        format!("malformed number `{text}`"),
                    );
                    let tail = &src[end..stop];
                    if src[start..end].ends_with(['d', 'D'])
                        && tail.bytes().next().is_some_and(|b| b.is_ascii_digit())
                    {
                        d = d.with_help(
                            "`D` after a number means degrees; write the exponent with `E` (1.5E3)",
                        );
                    } else {
                        d = d.with_help("a number must be followed by an operator, `,` or `)`");
                    }
                    out.diagnostics.push(d);
                    out.tokens.push((start, Tok::Invalid, stop));
                    blank_since = None;
                    continue;
                }
                Tok::Num(number_value(&src[start..end]))
            }
            Raw::Name => {
                let text = &src[start..end];
                let idx = out.names.push(text);
                // A name directly followed by `(` is a call; with a blank in between it is
                // an error for a known function (spec §1.4), a missing operator otherwise.
                let rest = &src[end..];
                let direct = rest.starts_with('(');
                // Only a blank or line break after the name can hide a `(`.
                let spaced = !direct
                    && matches!(rest.as_bytes().first(), Some(b' ' | b'\t' | b'\r' | b'\n'))
                    && (rest.trim_start_matches([' ', '\t']).starts_with('(')
                        || continued_paren(rest));
                let spaced_call = spaced && {
                    let upper = out.names.get(idx);
                    let callable = crate::vocab::builtins::is_callable(upper);
                    if callable {
                        out.diagnostics.push(
                            Diagnostic::error(
                                Code::BlankBeforeParen,
                                start..end + (rest.len() - rest.trim_start().len()),
                                format!("blank between function name `{upper}` and `(`"),
                            )
                            .with_help(format!("write `{upper}(` with no blank")),
                        );
                    }
                    callable
                };
                let call = direct || spaced_call;
                if call && text.eq_ignore_ascii_case("IF") {
                    Tok::If
                } else if call {
                    Tok::Call(idx)
                } else {
                    Tok::Name(idx)
                }
            }
            Raw::Plus => Tok::Plus,
            Raw::Minus => Tok::Minus,
            Raw::Star => match out.tokens.last().copied() {
                // Logos already joins `**`; two stars reaching here had a blank between.
                Some((s, Tok::Star, _)) if blank_since.is_some() => {
                    out.diagnostics.push(
                        Diagnostic::error(Code::SplitPower, s..end, "`* *` is not an operator")
                            .with_help("write the power operator `**` without a blank"),
                    );
                    out.tokens.pop();
                    out.tokens.push((s, Tok::Pow, end));
                    blank_since = None;
                    continue;
                }
                _ => Tok::Star,
            },
            Raw::Pow => Tok::Pow,
            Raw::Slash => Tok::Slash,
            Raw::Percent => Tok::Percent,
            Raw::LParen | Raw::LBracket => {
                depth += 1;
                if depth > MAX_BRACKET_DEPTH {
                    out.diagnostics.push(
                        Diagnostic::error(
                            Code::TooDeep,
                            start..end,
                            format!("brackets nest deeper than {MAX_BRACKET_DEPTH} levels"),
                        )
                        .with_help("split the expression, e.g. into VARIABLE statements"),
                    );
                    out.aborted = true;
                    return;
                }
                if kind == Raw::LParen {
                    Tok::LParen
                } else {
                    Tok::LBracket
                }
            }
            Raw::RParen | Raw::RBracket => {
                depth = depth.saturating_sub(1);
                if kind == Raw::RParen {
                    Tok::RParen
                } else {
                    Tok::RBracket
                }
            }
            Raw::Comma => Tok::Comma,
            Raw::Colon => Tok::Colon,
            Raw::Relational => {
                out.diagnostics.push(
                    Diagnostic::error(
                        Code::RelationalOperator,
                        start..end,
                        format!(
                            "`{}`: relational and logical operators are not part of function expressions",
                            &src[start..end]
                        ),
                    )
                    .with_help("use IF(e1: e2, e3, e4), STEP, MIN, MAX, DIM or SIGN instead"),
                );
                Tok::Relational
            }
            Raw::Caret => {
                out.diagnostics.push(
                    Diagnostic::error(Code::UnexpectedChar, start..end, "`^` is not an operator")
                        .with_help("write powers with `**`"),
                );
                Tok::Pow
            }
            Raw::Backslash => {
                out.diagnostics.push(
                    Diagnostic::error(Code::UnexpectedChar, start..end, "unexpected `\\`")
                        .with_help("`\\` ends an expression only inside a dataset statement"),
                );
                Tok::Invalid
            }
        };
        blank_since = None;
        out.tokens.push((start, tok, end));
    }
}

/// True when `rest` (text after a name) is blanks, a continuation join, blanks, then `(`:
/// a function name broken from its `(` across lines (spec §8.1 L19).
fn continued_paren(rest: &str) -> bool {
    let rest = rest.trim_start_matches([' ', '\t']);
    let rest = rest.strip_prefix('\r').unwrap_or(rest);
    if !rest.starts_with('\n') {
        return false;
    }
    match after_break(rest, 1) {
        AfterBreak::Continuation(at) => rest[at..].trim_start_matches([' ', '\t']).starts_with('('),
        AfterBreak::End(_) | AfterBreak::Other(_) => false,
    }
}

/// What follows a line break inside an expression once blank lines and whole-line `!`
/// comments are passed over; each variant holds the byte offset where lexing resumes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum AfterBreak {
    /// The text ends: the expression ends at the break.
    End(usize),
    /// A continuation line (a comma first on the line); lexing resumes after that comma.
    Continuation(usize),
    /// A line that does not continue the expression; lexing resumes at its start.
    Other(usize),
}

impl AfterBreak {
    fn at(self) -> usize {
        match self {
            AfterBreak::End(at) | AfterBreak::Continuation(at) | AfterBreak::Other(at) => at,
        }
    }
}

/// Looks past the line break that ends just before `line_start` in `src`: skips blank
/// lines and lines whose first non-blank character is `!` (the dataset reader skips them
/// between a statement's lines too), and says what the first other line is.
fn after_break(src: &str, mut line_start: usize) -> AfterBreak {
    loop {
        let line_end = src[line_start..]
            .find('\n')
            .map_or(src.len(), |i| line_start + i);
        let line = &src[line_start..line_end];
        let body = line.trim_start_matches([' ', '\t']);
        if body.starts_with(',') {
            return AfterBreak::Continuation(line_start + (line.len() - body.len()) + 1);
        }
        if !(body.starts_with('!') || body.trim().is_empty()) {
            return AfterBreak::Other(line_start);
        }
        if line_end == src.len() {
            return AfterBreak::End(line_end);
        }
        line_start = line_end + 1;
    }
}

#[cfg(test)]
mod tests {
    use super::number_value;
    use proptest::prelude::*;

    fn decimal() -> impl Strategy<Value = String> {
        (
            prop::sample::select(vec!["", "0", "00", "7", "12", "123456789", "9007199254740"]),
            prop::option::of("[0-9]{0,9}"),
            prop::option::of((
                prop::sample::select(vec!["E", "e"]),
                -40i32..40,
                any::<bool>(),
            )),
        )
            .prop_filter_map("a number has a digit", |(int, frac, exp)| {
                let mut t = int.to_string();
                if let Some(f) = frac {
                    t.push('.');
                    t.push_str(&f);
                }
                if !t.bytes().any(|b| b.is_ascii_digit()) {
                    return None;
                }
                if let Some((e, x, plus)) = exp {
                    let sign = if plus && x >= 0 { "+" } else { "" };
                    t.push_str(&format!("{e}{sign}{x:03}"));
                }
                Some(t)
            })
    }

    proptest! {
        /// The short-decimal fast path gives the bits of Rust's correctly rounded parser.
        #[test]
        fn decimals_parse_to_the_correctly_rounded_value(text in decimal()) {
            let want: f64 = text.parse().expect("valid decimal");
            prop_assert_eq!(number_value(&text).to_bits(), want.to_bits(), "{}", text);
        }
    }

    #[test]
    fn decimals_at_the_edges_of_the_fast_path() {
        for text in [
            "999999999999999",
            "9999999999999999",
            "123456789012345678",
            "1E22",
            "1E23",
            "1.5E-22",
            "1.387778781E-014",
            "0.000000000000000000000001",
            "1.",
            ".5",
            "0",
        ] {
            let want: f64 = text.parse().expect("valid decimal");
            assert_eq!(number_value(text).to_bits(), want.to_bits(), "{text}");
        }
    }
}
