//! Argument parsing of one `.adm` statement: flags, `KEY = v1, v2` and `KEY = a:b:c`
//! lists, free-text arguments and expression arguments (see [`super::statement`] for the
//! rules). Errors are `E0601` diagnostics; the parser then skips to the next separator.

use super::cursor::Cursor;
use super::keywords::{is_expression_argument, is_text_argument};
use super::lines::is_blank;
use super::statement::{ArgValue, Argument, Item, ItemKind};
use crate::diag::{Code, Diagnostic, Span};

/// Parses the arguments that follow a statement's head, up to the end of the statement.
pub(super) fn parse_arguments(
    c: &mut Cursor,
    canonical: Option<&str>,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Argument> {
    let mut args = Vec::new();
    while c.skip_separators() {
        if let Some(arg) = parse_argument(c, canonical, diags) {
            args.push(arg);
        }
    }
    args
}

fn parse_argument(
    c: &mut Cursor,
    canonical: Option<&str>,
    diags: &mut Vec<Diagnostic>,
) -> Option<Argument> {
    let start = c.pos;
    let line = c.line();
    let name = c.read_name().to_ascii_uppercase();
    if name.is_empty() {
        diags.push(Diagnostic::error(
            Code::Statement,
            c.char_span(),
            format!("expected an argument name, found {}", c.describe()),
        ));
        c.skip_to_separator();
        return None;
    }
    let name_span = start..c.pos;
    c.skip_blanks();
    let mut arg = Argument {
        name,
        name_span: name_span.clone(),
        value: ArgValue::Flag,
        span: name_span,
        line,
        is_user_call: false,
    };
    match c.peek() {
        None | Some(b',' | b'\\') => return Some(arg),
        Some(b'=') => c.bump(),
        Some(_) => {
            diags.push(Diagnostic::error(
                Code::Statement,
                c.char_span(),
                format!(
                    "expected `=` or `,` after `{}`, found {}",
                    arg.name,
                    c.describe()
                ),
            ));
            c.skip_to_separator();
            return None;
        }
    }
    let head = start..c.pos;
    let end = if is_expression_argument(canonical, &arg.name) {
        let span = expression(c);
        if span.is_empty() {
            return missing_value(diags, head, &arg.name);
        }
        arg.is_user_call = is_user_call(&c.text[span.clone()]);
        let end = span.end;
        arg.value = ArgValue::Expression(span);
        end
    } else if is_text_argument(canonical, &arg.name) {
        c.skip_blanks();
        let from = c.pos;
        let to = c.trimmed_piece_end();
        c.skip_to_piece_end();
        arg.value = ArgValue::List(vec![Item {
            kind: ItemKind::Text,
            text: c.text[from..to].to_string(),
            span: from..to,
        }]);
        to.max(head.end)
    } else {
        let reported = diags.len();
        let items = list(c, diags);
        let Some(last) = items.last() else {
            if diags.len() > reported {
                return None;
            }
            return missing_value(diags, head, &arg.name);
        };
        let end = last.span.end;
        arg.value = ArgValue::List(items);
        end
    };
    arg.span = start..end;
    Some(arg)
}

fn missing_value(diags: &mut Vec<Diagnostic>, head: Span, name: &str) -> Option<Argument> {
    diags.push(
        Diagnostic::error(Code::Statement, head, format!("`{name}=` has no value"))
            .with_help("write a value after `=` or remove the argument"),
    );
    None
}

/// Scans an expression after `=`: to a `\` (consumed), a comma outside brackets, or the
/// end of the statement. Returns its span without surrounding blanks (empty if none).
/// When the line ends right after `=`, the expression starts on the next line unless that
/// line holds another `KEY =`.
fn expression(c: &mut Cursor) -> Span {
    c.skip_blanks();
    if c.peek().is_none() {
        let mark = c.mark();
        if !c.next_piece() {
            return c.pos..c.pos;
        }
        c.skip_blanks();
        if c.at_assignment() || c.peek().is_none() {
            c.reset(mark);
            return c.pos..c.pos;
        }
    }
    let start = c.pos;
    let mut end = start;
    let mut depth = 0usize;
    loop {
        match c.peek() {
            None if c.next_piece() => {}
            None => break,
            Some(b'\\') => {
                c.bump();
                break;
            }
            Some(b',') if depth == 0 => break,
            Some(b) => {
                match b {
                    b'(' | b'[' => depth += 1,
                    b')' | b']' => depth = depth.saturating_sub(1),
                    _ => {}
                }
                if !is_blank(b) {
                    end = c.pos + 1;
                }
                c.bump();
            }
        }
    }
    start..end
}

/// `USER(…)` in place of an expression (any case, blanks before `(` tolerated).
fn is_user_call(expr: &str) -> bool {
    expr.get(..4)
        .is_some_and(|head| head.eq_ignore_ascii_case("USER"))
        && expr[4..].trim_start().starts_with('(')
}

/// Parses `v1, v2, …` (items separated by commas, possibly across continuation lines,
/// and starting on the next line when the line ends after `=`) or `a:b:c`. After a
/// comma the list goes on with a number, a quoted string or a word that cannot be an
/// argument ([`continues_list`]). Empty when the value is missing.
fn list(c: &mut Cursor, diags: &mut Vec<Diagnostic>) -> Vec<Item> {
    let mut items = Vec::new();
    c.skip_blanks();
    if c.peek().is_none() {
        // `, KMATRIX =` then the numbers on the next lines (FAST).
        let mark = c.mark();
        if c.next_piece() {
            c.skip_blanks();
        }
        if !starts_item(c.peek(), c.peek2()) {
            c.reset(mark);
        }
    }
    if matches!(c.peek(), None | Some(b',' | b'\\')) {
        return items;
    }
    loop {
        if let Some(item) = item(c, diags) {
            items.push(item);
        }
        c.skip_blanks();
        match c.peek() {
            Some(b':') => {
                c.bump();
                c.skip_blanks();
            }
            None | Some(b',') => {
                let mark = c.mark();
                if c.peek().is_some() {
                    c.bump();
                    c.skip_blanks();
                }
                if c.peek().is_none() && c.next_piece() {
                    c.skip_blanks();
                }
                if !continues_list(c) {
                    c.reset(mark);
                    return items;
                }
            }
            Some(b'\\') => return items,
            Some(_) => {
                diags.push(Diagnostic::error(
                    Code::Statement,
                    c.char_span(),
                    format!("unexpected {} in a list of values", c.describe()),
                ));
                c.skip_to_separator();
                return items;
            }
        }
    }
}

/// After a separator inside a list: true when the next item belongs to the list. A
/// number or a quoted string does; so does a word that cannot be an argument
/// (`adrill_solver::gse_update` in `INTERFACE = a::b, c::d`); a keyword that is followed
/// by `=`, a separator or the line end is the statement's next argument.
fn continues_list(c: &mut Cursor) -> bool {
    if starts_item(c.peek(), c.peek2()) {
        return true;
    }
    let mark = c.mark();
    let name = !c.read_name().is_empty();
    c.skip_blanks();
    let argument = matches!(c.peek(), None | Some(b'=' | b',' | b'\\'));
    c.reset(mark);
    name && !argument
}

/// True when a number or a quoted string starts with these two bytes.
fn starts_item(b: Option<u8>, next: Option<u8>) -> bool {
    let digit_or_dot = |b: Option<u8>| b.is_some_and(|b| b.is_ascii_digit() || b == b'.');
    match b {
        Some(b'"') => true,
        Some(b'+' | b'-') => digit_or_dot(next),
        b => digit_or_dot(b),
    }
}

/// One list item: a quoted string, or the text up to the next `,`, `:`, `\`, `=` or line
/// end (blanks inside kept: `Solid Rectangular`; `::` inside kept: `lib::name`).
fn item(c: &mut Cursor, diags: &mut Vec<Diagnostic>) -> Option<Item> {
    let start = c.pos;
    if c.peek() == Some(b'"') {
        c.bump();
        while c.peek().is_some_and(|b| b != b'"') {
            c.bump();
        }
        if c.peek().is_none() {
            diags.push(
                Diagnostic::error(Code::Statement, start..c.pos, "unterminated string")
                    .with_help("close the string with `\"` on the same line"),
            );
            return None;
        }
        c.bump();
        return Some(Item {
            kind: ItemKind::Quoted,
            text: c.text[start + 1..c.pos - 1].to_string(),
            span: start..c.pos,
        });
    }
    let mut end = start;
    loop {
        match c.peek() {
            None | Some(b',' | b'\\' | b'=') => break,
            Some(b':') if c.peek2() != Some(b':') => break,
            Some(b':') => {
                c.bump();
                c.bump();
                end = c.pos;
            }
            Some(b) => {
                c.bump();
                if !is_blank(b) {
                    end = c.pos;
                }
            }
        }
    }
    if end == start {
        diags.push(Diagnostic::error(
            Code::Statement,
            c.char_span(),
            format!("expected a value, found {}", c.describe()),
        ));
        return None;
    }
    let text = &c.text[start..end];
    let kind = match number(text) {
        Some((value, degrees)) => {
            if !value.is_finite() {
                diags.push(
                    Diagnostic::error(
                        Code::NonFiniteNumber,
                        start..end,
                        format!("`{text}` is beyond the range of numbers (about ±1.8E308)"),
                    )
                    .with_help("write a finite value"),
                );
            }
            ItemKind::Number { value, degrees }
        }
        None => ItemKind::Word,
    };
    Some(Item {
        kind,
        text: text.to_string(),
        span: start..end,
    })
}

/// Reads a dataset number: `[+-]` mantissa, optional exponent, optional `D` (degrees).
/// Returns the value as written and whether it is in degrees.
pub(super) fn number(text: &str) -> Option<(f64, bool)> {
    let b = text.as_bytes();
    let digits = |mut i: usize| {
        while b.get(i).is_some_and(u8::is_ascii_digit) {
            i += 1;
        }
        i
    };
    let mut i = usize::from(matches!(b.first(), Some(b'+' | b'-')));
    let int_end = digits(i);
    let mut mantissa = int_end - i;
    i = int_end;
    if b.get(i) == Some(&b'.') {
        let frac_end = digits(i + 1);
        mantissa += frac_end - i - 1;
        i = frac_end;
    }
    if mantissa == 0 {
        return None;
    }
    if matches!(b.get(i), Some(b'e' | b'E')) {
        let sign = usize::from(matches!(b.get(i + 1), Some(b'+' | b'-')));
        let exp_end = digits(i + 1 + sign);
        if exp_end == i + 1 + sign {
            return None;
        }
        i = exp_end;
    }
    let value: f64 = text[..i].parse().ok()?;
    match &b[i..] {
        [] => Some((value, false)),
        [b'd' | b'D'] => Some((value, true)),
        _ => None,
    }
}
