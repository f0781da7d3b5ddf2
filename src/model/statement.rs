//! Statement layer of the `.adm` reader: turns a dataset text into [`Statement`]s
//! (`KEYWORD/id, ARG=value, FLAG, …`) with byte spans into the original text, plus
//! diagnostics (`E0601` malformed statement, `W0602` statement mbfx does not know).
//!
//! Line 1 is the title. `!` starts a comment; an `adams_view_name='…'` comment names the
//! next statement. A line whose first non-blank character is `,` continues the statement
//! before it; `;` ends a statement. Reading stops at `END`. Expression arguments
//! (FUNCTION, F1..F8, FX..TZ, see [`super::keywords::EXPRESSION_ARGUMENTS`]) keep the raw
//! byte range of the expression, continuation lines included: the expression lexer skips
//! the line breaks, continuation commas and comments itself. An expression ends at a `\`,
//! at a comma outside parentheses (real files write `F8=JOINT(1,0,8,0),C=…`; such a comma
//! can never belong to an expression), or at the end of the statement; `/` never ends one
//! (spec decision 9). The reader never panics and never stops at the first error.

use super::args::parse_arguments;
use super::cursor::{trim_end, Cursor};
use super::keywords::{lookup_statement, Lookup};
use super::lines::{pieces, view_name, Piece, PieceKind};
use crate::diag::{Code, Diagnostic, Span};

pub use super::lines::title_span;

/// One dataset statement.
#[derive(Clone, Debug, PartialEq)]
pub struct Statement {
    /// The keyword as written, upper-cased (`JOI` stays `JOI`).
    pub keyword: String,
    /// Byte range of the keyword.
    pub keyword_span: Span,
    /// The statement the keyword names (`JOINT` for `JOI`), or `None` when mbfx does not
    /// know it (already reported as `W0602`).
    pub canonical: Option<&'static str>,
    /// The id after the `/`, when written.
    pub id: Option<i64>,
    /// Byte range of the id.
    pub id_span: Option<Span>,
    /// The arguments, in file order.
    pub args: Vec<Argument>,
    /// The whole statement, continuation lines included, without trailing comments.
    pub span: Span,
    /// 1-based line of the keyword.
    pub line: usize,
    /// From the `adams_view_name='…'` comment before the statement.
    pub view_name: Option<String>,
}

impl Statement {
    /// The first argument whose written name is `full` or an abbreviation of it at least
    /// `min_len` long (case-insensitive).
    pub fn arg(&self, full: &str, min_len: usize) -> Option<&Argument> {
        self.args
            .iter()
            .find(|a| super::keywords::abbreviates(&a.name, full, min_len))
    }

    /// `JOINT/3`-style label for messages: the view name when there is one.
    pub fn label(&self) -> String {
        match (&self.view_name, self.id) {
            (Some(name), _) => name.clone(),
            (None, Some(id)) => format!("{}/{id}", self.keyword),
            (None, None) => self.keyword.clone(),
        }
    }
}

/// One argument of a statement.
#[derive(Clone, Debug, PartialEq)]
pub struct Argument {
    /// The name as written, upper-cased; it may be abbreviated (`FUN`).
    pub name: String,
    /// Byte range of the name.
    pub name_span: Span,
    /// What follows the name.
    pub value: ArgValue,
    /// Name and value.
    pub span: Span,
    /// 1-based line of the name.
    pub line: usize,
    /// The value is an expression written `USER(r1, …)`: a user subroutine call, which
    /// mbfx does not run (spec §7).
    pub is_user_call: bool,
}

impl Argument {
    /// The expression's byte range, for an expression argument.
    pub fn expr_span(&self) -> Option<Span> {
        match &self.value {
            ArgValue::Expression(span) => Some(span.clone()),
            _ => None,
        }
    }

    /// The items of a list value (empty for flags and expressions).
    pub fn items(&self) -> &[Item] {
        match &self.value {
            ArgValue::List(items) => items,
            _ => &[],
        }
    }
}

/// What follows an argument's name.
#[derive(Clone, Debug, PartialEq)]
pub enum ArgValue {
    /// No `=`: a flag such as `REVOLUTE` or `GROUND`.
    Flag,
    /// `= v1, v2, …` or `= a:b:c`; free-text arguments hold one [`ItemKind::Text`] item.
    List(Vec<Item>),
    /// An expression: its byte range in the file, which may cross continuation lines.
    Expression(Span),
}

/// One value of a list.
#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    /// Number, word, quoted string, ...
    pub kind: ItemKind,
    /// As written (without the quotes of a quoted string).
    pub text: String,
    /// Byte range of the value.
    pub span: Span,
}

/// The kinds of list values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ItemKind {
    /// `1.0`, `-2.5E-3`, `0201`, `90D`: the value as written and whether a `D` (degrees)
    /// follows it.
    Number {
        /// The number, not yet converted from degrees.
        value: f64,
        /// A `D` follows it.
        degrees: bool,
    },
    /// A bare word: `TRANSLATION`, `steel`, `lib::name`, `Solid Rectangular`.
    Word,
    /// A `"…"` string.
    Quoted,
    /// Free text to the end of the line (`C=`, `COMMENT=`, `STRING=`).
    Text,
}

impl Item {
    /// The number in radians where a `D` suffix says degrees.
    pub fn as_f64(&self) -> Option<f64> {
        match self.kind {
            ItemKind::Number { value, degrees } => {
                Some(if degrees { value.to_radians() } else { value })
            }
            _ => None,
        }
    }

    /// The number as an integer, when written as one (`0201` is 201).
    pub fn as_integer(&self) -> Option<i64> {
        match self.kind {
            ItemKind::Number { degrees: false, .. } => self.text.parse().ok(),
            _ => None,
        }
    }
}

/// Reads every statement of a dataset text. Line 1 is the title ([`title_span`]).
pub fn read_statements(text: &str) -> (Vec<Statement>, Vec<Diagnostic>) {
    let (pieces, nul) = pieces(text);
    let mut diags = Vec::new();
    if let Some(span) = nul {
        diags.push(
            Diagnostic::warning(Code::EncodingRepaired, span, "NUL bytes in the dataset")
                .with_note("they are read as blanks"),
        );
    }
    let mut reader = Reader {
        text,
        stmts: Vec::new(),
        diags,
        group: Vec::new(),
        group_name: None,
        ended: false,
    };
    let mut pending_name = None;
    let mut closed = true;
    for piece in pieces {
        match piece.kind {
            PieceKind::Comment => {
                if let Some(name) = view_name(&text[piece.range.clone()]) {
                    pending_name = Some(name);
                }
            }
            PieceKind::Head => {
                reader.flush();
                if reader.ended {
                    reader.diags.push(Diagnostic::warning(
                        Code::UnsupportedStatement,
                        piece.range,
                        "text after END is ignored",
                    ));
                    return (reader.stmts, reader.diags);
                }
                closed = piece.closed;
                reader.group.push(piece);
                reader.group_name = pending_name.take();
            }
            PieceKind::Continuation { comma } => {
                if closed {
                    reader.diags.push(
                        Diagnostic::error(
                            Code::Statement,
                            comma..piece.range.end,
                            "continuation line with no statement to continue",
                        )
                        .with_help("a statement starts with `KEYWORD/id`"),
                    );
                } else {
                    closed = piece.closed;
                    reader.group.push(piece);
                }
            }
        }
    }
    reader.flush();
    (reader.stmts, reader.diags)
}

/// Collects the pieces of the statement being read and parses them when it is complete.
struct Reader<'a> {
    text: &'a str,
    stmts: Vec<Statement>,
    diags: Vec<Diagnostic>,
    group: Vec<Piece>,
    group_name: Option<String>,
    ended: bool,
}

impl Reader<'_> {
    fn flush(&mut self) {
        if self.group.is_empty() {
            return;
        }
        let group = std::mem::take(&mut self.group);
        let name = self.group_name.take();
        if let Some(stmt) = parse_statement(self.text, &group, name, &mut self.diags) {
            self.ended = stmt.canonical == Some("END");
            self.stmts.push(stmt);
        }
    }
}

/// Parses one statement from its pieces; `None` when its head is unreadable.
fn parse_statement(
    text: &str,
    group: &[Piece],
    view_name: Option<String>,
    diags: &mut Vec<Diagnostic>,
) -> Option<Statement> {
    let mut c = Cursor::new(text, group);
    c.skip_blanks();
    let start = c.pos;
    let line = c.line();
    let written = c.read_name();
    if written.is_empty() {
        diags.push(Diagnostic::error(
            Code::Statement,
            c.char_span(),
            format!("expected a statement keyword, found {}", c.describe()),
        ));
        return None;
    }
    let keyword = written.to_ascii_uppercase();
    let keyword_span = start..c.pos;
    let lookup = lookup_statement(&keyword);
    let kind = match &lookup {
        Lookup::Known(kind) => Some(*kind),
        _ => None,
    };
    let canonical = kind.map(|k| k.keyword.name);
    let end = group
        .last()
        .map_or(c.pos, |p| trim_end(text.as_bytes(), p.range.clone()));
    let mut stmt = Statement {
        keyword,
        keyword_span,
        canonical,
        id: None,
        id_span: None,
        args: Vec::new(),
        span: start..end.max(c.pos),
        line,
        view_name,
    };
    c.skip_blanks();
    if c.peek() != Some(b'/') {
        if canonical == Some("END") {
            return Some(stmt);
        }
        let mut d = Diagnostic::error(
            Code::Statement,
            c.char_span(),
            format!("expected `/` after `{}`", stmt.keyword),
        )
        .with_label(stmt.keyword_span.clone(), "statement keyword");
        if c.peek() == Some(b'=') {
            d = d.with_help("a continuation line must start with a comma");
        }
        diags.push(d);
        return None;
    }
    match lookup {
        Lookup::Known(_) => {}
        Lookup::Ambiguous(names) => diags.push(
            Diagnostic::error(
                Code::Statement,
                stmt.keyword_span.clone(),
                format!("ambiguous statement keyword `{}`", stmt.keyword),
            )
            .with_note(format!("it abbreviates {}", names.join(", ")))
            .with_help("write more letters of the keyword"),
        ),
        Lookup::Unknown => diags.push(Diagnostic::warning(
            Code::UnsupportedStatement,
            stmt.keyword_span.clone(),
            format!("unknown statement `{}`", stmt.keyword),
        )),
    }
    let slash = c.pos;
    c.bump();
    c.skip_blanks();
    if c.peek().is_some_and(|b| b.is_ascii_digit()) {
        read_id(&mut c, &mut stmt, diags);
    } else if kind.is_some_and(|k| k.has_id) {
        diags.push(
            Diagnostic::error(
                Code::Statement,
                slash..slash + 1,
                format!("missing id after `{}/`", stmt.keyword),
            )
            .with_help(format!("write `{}/id` with an integer id", stmt.keyword)),
        );
    }
    stmt.args = parse_arguments(&mut c, canonical, diags);
    Some(stmt)
}

/// Reads the integer id after `KEYWORD/` and checks that a separator follows it.
pub(super) fn read_id(c: &mut Cursor, stmt: &mut Statement, diags: &mut Vec<Diagnostic>) {
    let start = c.pos;
    while c
        .peek()
        .is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'.')
    {
        c.bump();
    }
    let span = start..c.pos;
    let written = &c.text[span.clone()];
    if !written.bytes().all(|b| b.is_ascii_digit()) {
        diags.push(Diagnostic::error(
            Code::Statement,
            span,
            format!("malformed id `{written}`: an id is an integer"),
        ));
        return;
    }
    match written.parse::<i64>() {
        Ok(id) => {
            stmt.id = Some(id);
            stmt.id_span = Some(span);
        }
        Err(_) => diags.push(Diagnostic::error(
            Code::Statement,
            span,
            format!("id `{written}` is too large"),
        )),
    }
    c.skip_blanks();
    if !matches!(c.peek(), None | Some(b',' | b'\\')) {
        diags.push(Diagnostic::error(
            Code::Statement,
            c.char_span(),
            format!("expected `,` after the id, found {}", c.describe()),
        ));
    }
}
