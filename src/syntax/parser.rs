//! Parser glue: lexes, then parses valid input with the hand-written fast path
//! ([`fast`]) and anything it rejects with the LALRPOP grammar (`grammar/function.lalrpop`,
//! generated at build time and run by `syntax::driver`), the grammar of
//! record. LALRPOP's errors are converted into diagnostics in exactly one function,
//! `Diagnoser::diagnose`. The LALRPOP parser recovers from errors, so one run reports
//! every syntax error it finds; neither parser panics.
//! A [`Session`] keeps the buffers between expressions.

use crate::diag::{Code, Diagnostic};
use crate::syntax::ast::{Ast, Builder, NodeId};
use crate::syntax::driver::{Expected, SyntaxError};
use crate::syntax::fast;
use crate::syntax::lexer::{self, Lexed, Tok};
use lalrpop_util::{lalrpop_mod, ErrorRecovery, ParseError};

lalrpop_mod!(
    #[allow(clippy::all, clippy::pedantic, unused)]
    grammar,
    "/function.rs"
);

/// Deepest syntax tree accepted. Operator chains (`1+1+…`) make trees as deep as they are
/// long; passes over the tree grow their stack on demand, and this bound keeps their
/// memory in proportion (decision 11).
pub const MAX_TREE_DEPTH: u32 = 20_000;

/// An error the parser recovered from.
pub type Recovered = ErrorRecovery<usize, Tok, SyntaxError>;

/// A parsed expression with every lexical and syntax diagnostic found.
pub struct Parsed {
    /// The tree.
    pub ast: Ast,
    /// `None` when nothing could be parsed (empty input, nesting limit, ...).
    pub root: Option<NodeId>,
    /// Every lexical and syntax diagnostic.
    pub diagnostics: Vec<Diagnostic>,
}

/// Lexes and parses one expression: valid input through the fast parser, anything with an
/// error through the recovering one, which reports every error.
pub fn parse(src: &str) -> Parsed {
    Session::new().parse(src, true).into_parsed()
}

/// Parses with the recovering parser only (the one that reports every error). Both parsers
/// build the same trees; `tests/language/fast_parser.rs` checks it.
pub fn parse_recovering(src: &str) -> Parsed {
    Session::new().parse(src, false).into_parsed()
}

/// The buffers of the front end's lexing and parsing, kept between expressions so that a
/// caller compiling many of them allocates only while the buffers grow.
#[derive(Default)]
pub struct Session {
    lexed: Lexed,
    builder: Builder,
    frames: Vec<fast::Frame>,
    open: Vec<u32>,
}

/// The outcome of [`Session::parse`]: the tree stays in the session.
pub struct Outcome<'s> {
    /// The tree, borrowed from the session.
    pub ast: &'s mut Ast,
    /// `None` when nothing could be parsed (empty input, nesting limit, ...).
    pub root: Option<NodeId>,
    /// Every lexical and syntax diagnostic.
    pub diagnostics: Vec<Diagnostic>,
}

impl Outcome<'_> {
    fn into_parsed(self) -> Parsed {
        Parsed {
            ast: std::mem::take(self.ast),
            root: self.root,
            diagnostics: self.diagnostics,
        }
    }
}

impl Session {
    /// A session with empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// Lexes and parses `src`, replacing the tree of the previous expression. With
    /// `fast_first`, valid input takes the hand-written parser ([`fast`]); anything it
    /// rejects is parsed by the LALRPOP grammar, which reports every error.
    pub fn parse(&mut self, src: &str, fast_first: bool) -> Outcome<'_> {
        lexer::lex_into(src, &mut self.lexed);
        let b = &mut self.builder;
        b.clear();
        let lexed = &mut self.lexed;
        // The lexer's names become the tree's; the swap keeps both buffers for reuse.
        std::mem::swap(&mut b.ast.names, &mut lexed.names);
        let mut diagnostics = std::mem::take(&mut lexed.diagnostics);
        let tokens = &lexed.tokens;
        let root = if lexed.aborted {
            None
        } else if tokens.is_empty() {
            if diagnostics.is_empty() {
                diagnostics.push(
                    Diagnostic::error(Code::EmptyExpression, 0..src.len(), "empty expression")
                        .with_help("write a value, e.g. 0"),
                );
            }
            None
        } else if let Some(root) = (fast_first && diagnostics.is_empty())
            .then(|| fast::parse(tokens, b, &mut self.frames).ok())
            .flatten()
        {
            finish(&b.ast, root, src, &mut diagnostics)
        } else {
            // An error (or no fast path): parse with recovery to report every error there is.
            let names = std::mem::take(&mut b.ast.names);
            b.clear();
            b.ast.names = names;
            let result = grammar::ExprParser::new().parse(b, tokens.iter().copied());
            let mut diagnoser = Diagnoser::new(src, tokens, &mut self.open);
            for r in b.recovered.drain(..) {
                diagnostics.push(diagnoser.diagnose(r.error));
            }
            match result {
                Ok(root) => finish(&b.ast, root, src, &mut diagnostics),
                Err(e) => {
                    diagnostics.push(diagnoser.diagnose(e));
                    tidy(&mut diagnostics);
                    None
                }
            }
        };
        Outcome {
            ast: &mut b.ast,
            root,
            diagnostics,
        }
    }
}

/// Applies the tree-depth limit and tidies the diagnostics; the root, if within the limit.
fn finish(ast: &Ast, root: NodeId, src: &str, diagnostics: &mut Vec<Diagnostic>) -> Option<NodeId> {
    let depth = ast.node(root).depth;
    if depth > MAX_TREE_DEPTH {
        diagnostics.push(
            Diagnostic::error(
                Code::TooDeep,
                0..src.len(),
                format!("expression nests {depth} operations deep; the limit is {MAX_TREE_DEPTH}"),
            )
            .with_help("split the expression, e.g. into VARIABLE statements"),
        );
        // Recovered errors may stand beside it (thousands, in a long line of garbage).
        tidy(diagnostics);
        return None;
    }
    tidy(diagnostics);
    Some(root)
}

/// Orders diagnostics by position, drops duplicates and follow-on errors, and caps them.
fn tidy(diagnostics: &mut Vec<Diagnostic>) {
    if diagnostics.is_empty() {
        return;
    }
    diagnostics.sort_by_key(|d| d.span.start);
    diagnostics.dedup_by(|a, b| a.span == b.span && a.code == b.code);
    // A parse error at or after an invalid token repeats the lexer's error for it.
    diagnostics.retain(|d| {
        !d.message
            .starts_with("unexpected input after an earlier error")
    });
    crate::diag::cap(diagnostics);
}

/// Human spelling of a token for messages.
fn describe(tok: Tok) -> &'static str {
    match tok {
        Tok::Num(_) => "a number",
        Tok::Name(_) => "a name",
        Tok::Call(_) => "a function call",
        Tok::If => "IF",
        Tok::Plus => "`+`",
        Tok::Minus => "`-`",
        Tok::Star => "`*`",
        Tok::Pow => "`**`",
        Tok::Slash => "`/`",
        Tok::Percent => "`%`",
        Tok::LParen => "`(`",
        Tok::RParen => "`)`",
        Tok::LBracket => "`[`",
        Tok::RBracket => "`]`",
        Tok::Comma => "`,`",
        Tok::Colon => "`:`",
        Tok::Relational => "a relational operator",
        Tok::Invalid => "an invalid token",
    }
}

/// Appends a token as the user wrote it, for messages: the power operator also stands for
/// `^` and `* *` (already diagnosed by the lexer), which a message must not call `**`.
fn push_written(out: &mut String, tok: Tok, src: &str, span: std::ops::Range<usize>) {
    match (tok, src.get(span)) {
        (Tok::Pow, Some(text)) if text != "**" => {
            out.push('`');
            out.push_str(text);
            out.push('`');
        }
        _ => out.push_str(describe(tok)),
    }
}

/// A message made of `head`, the token as written, then `tail`: one allocation (every
/// error builds one, and garbage has hundreds).
fn message_with_token(head: &str, tok: Tok, src: &str, span: std::ops::Range<usize>) -> String {
    let mut out = String::with_capacity(96);
    out.push_str(head);
    push_written(&mut out, tok, src, span);
    out
}

/// True for tokens that can begin a value.
fn starts_value(tok: Tok) -> bool {
    matches!(
        tok,
        Tok::Num(_)
            | Tok::Name(_)
            | Tok::Call(_)
            | Tok::If
            | Tok::LParen
            | Tok::LBracket
            | Tok::Invalid
    )
}

/// True for tokens that can end a value.
fn ends_value(tok: Tok) -> bool {
    matches!(
        tok,
        Tok::Num(_) | Tok::Name(_) | Tok::RParen | Tok::RBracket | Tok::Invalid
    )
}

/// Appends the expected terminals in words ("; expected a value, an operator or `)`").
fn push_expected_words(out: &mut String, expected: Expected) {
    let mut words = [""; 7];
    let mut n = 0;
    for (t, w) in [
        (Tok::Num(0.0), "a value"),
        (Tok::Plus, "an operator"),
        (Tok::RParen, "`)`"),
        (Tok::RBracket, "`]`"),
        (Tok::Comma, "`,`"),
        (Tok::Colon, "`:`"),
        (Tok::LParen, "`(`"),
    ] {
        if expected.contains(t) {
            words[n] = w;
            n += 1;
        }
    }
    for (i, w) in words[..n].iter().enumerate() {
        out.push_str(match i {
            0 => "; expected ",
            _ if i + 1 == n => " or ",
            _ => ", ",
        });
        out.push_str(w);
    }
}

/// No bracket open (in [`Diagnoser::open`]).
const NONE: u32 = u32::MAX;

/// Turns the parser's errors for one input into diagnostics. What an error needs to know
/// of the tokens around it (the one before, the innermost open bracket) is looked up, not
/// scanned for, so an input with an error every few tokens stays linear.
struct Diagnoser<'a> {
    src: &'a str,
    tokens: &'a [(usize, Tok, usize)],
    /// For each token index `i` (and `tokens.len()`), the index of the innermost bracket
    /// still open before token `i`, or [`NONE`]; filled on first use.
    open: &'a mut Vec<u32>,
}

impl<'a> Diagnoser<'a> {
    fn new(src: &'a str, tokens: &'a [(usize, Tok, usize)], open: &'a mut Vec<u32>) -> Self {
        open.clear();
        Diagnoser { src, tokens, open }
    }

    /// Position of the innermost bracket still open at byte `at`, if any.
    fn open_bracket_before(&mut self, at: usize) -> Option<(usize, usize)> {
        if self.open.is_empty() {
            // A bracket's entry is the one enclosing it: popping follows those links.
            let mut top = NONE;
            for (i, &(_, t, _)) in self.tokens.iter().enumerate() {
                self.open.push(top);
                match t {
                    Tok::LParen | Tok::LBracket => top = i as u32,
                    Tok::RParen | Tok::RBracket if top != NONE => top = self.open[top as usize],
                    _ => {}
                }
            }
            self.open.push(top);
        }
        let i = self.tokens.partition_point(|&(s, _, _)| s < at);
        let open = self.open[i];
        (open != NONE).then(|| {
            let (s, _, e) = self.tokens[open as usize];
            (s, e)
        })
    }

    /// The token that ends at or before byte `at`, nearest to it.
    fn token_before(&self, at: usize) -> Option<Tok> {
        let i = self.tokens.partition_point(|&(_, _, e)| e <= at);
        i.checked_sub(1).map(|i| self.tokens[i].1)
    }

    /// Converts one parser error into our diagnostic: the only place that knows LALRPOP's
    /// error type. Our driver reports [`SyntaxError`]s and extra tokens; the other
    /// variants are read the same way.
    fn diagnose(&mut self, e: ParseError<usize, Tok, SyntaxError>) -> Diagnostic {
        let error = match e {
            ParseError::User { error } => error,
            ParseError::UnrecognizedToken { token, expected } => SyntaxError::Unexpected {
                token,
                expected: Expected::from_names(&expected),
            },
            ParseError::UnrecognizedEof { location, expected } => SyntaxError::End {
                location,
                expected: Expected::from_names(&expected),
            },
            ParseError::ExtraToken { token } => return self.extra(token),
            ParseError::InvalidToken { location } => {
                return Diagnostic::error(
                    Code::UnexpectedToken,
                    location..location,
                    "invalid token",
                )
            }
        };
        match error {
            SyntaxError::End { location, expected } => self.end(location, expected),
            SyntaxError::Unexpected { token, expected } => self.unexpected(token, expected),
        }
    }

    fn end(&mut self, location: usize, expected: Expected) -> Diagnostic {
        let src = self.src;
        let at = location.min(src.len());
        if let Some((s, e)) = self.open_bracket_before(usize::MAX) {
            let close = if src[s..e].starts_with('[') { "]" } else { ")" };
            return Diagnostic::error(
                Code::UnexpectedEnd,
                at..at,
                format!("missing `{close}`: a bracket is still open at the end"),
            )
            .with_label(s..e, "opened here")
            .with_help(format!("add `{close}`"));
        }
        let mut message = String::from("expression ends too early");
        push_expected_words(&mut message, expected);
        Diagnostic::error(Code::UnexpectedEnd, at..at, message)
    }

    /// A closing bracket with no bracket open, whether unexpected or extra.
    fn unmatched(&mut self, (s, tok, e): (usize, Tok, usize)) -> Option<Diagnostic> {
        (matches!(tok, Tok::RParen | Tok::RBracket) && self.open_bracket_before(s).is_none()).then(
            || {
                Diagnostic::error(
                    Code::Unmatched,
                    s..e,
                    format!("unmatched {}: no bracket is open here", describe(tok)),
                )
                .with_help("remove it, or add the opening bracket")
            },
        )
    }

    fn extra(&mut self, token: (usize, Tok, usize)) -> Diagnostic {
        if let Some(d) = self.unmatched(token) {
            return d;
        }
        let (s, tok, e) = token;
        let mut message = message_with_token("unexpected ", tok, self.src, s..e);
        message.push_str(" after the end of the expression");
        Diagnostic::error(Code::UnexpectedToken, s..e, message)
    }

    fn unexpected(&mut self, token: (usize, Tok, usize), expected: Expected) -> Diagnostic {
        if let Some(d) = self.unmatched(token) {
            return d;
        }
        let (s, tok, e) = token;
        let prev = self.token_before(s);
        // An invalid token was already diagnosed by the lexer: no second error for it.
        let invalid = tok == Tok::Invalid || prev == Some(Tok::Invalid);
        if invalid {
            Diagnostic::error(
                Code::UnexpectedToken,
                s..e,
                "unexpected input after an earlier error",
            )
        } else if starts_value(tok) && prev.is_some_and(ends_value) {
            Diagnostic::error(
                Code::MissingOperator,
                s..e,
                format!("missing operator before {}", describe(tok)),
            )
            .with_help("two values need an operator between them (a blank cannot split a number)")
        } else if tok == Tok::Comma && expected.contains(Tok::Colon) {
            Diagnostic::error(Code::UnexpectedToken, s..e, "IF needs `:` after its test")
                .with_help("write IF(test: negative, zero, positive)")
        } else {
            let mut message = message_with_token("unexpected ", tok, self.src, s..e);
            push_expected_words(&mut message, expected);
            Diagnostic::error(Code::UnexpectedToken, s..e, message)
        }
    }
}
