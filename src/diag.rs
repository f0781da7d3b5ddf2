//! Diagnostics: the one error/warning type every stage of mbfx reports, and its renderer.
//!
//! Every stage (lexer, parser, checker, `.adm` reader, run time) produces [`Diagnostic`]s
//! holding byte-range spans into the text they read. Only [`render`] turns spans into
//! `file:line:column` and a caret frame (via ariadne). Codes are stable: tests and users
//! match on them, and docs/language.md lists them.

use std::ops::Range;

/// Byte range into the source text a diagnostic is about.
pub type Span = Range<usize>;

/// How serious a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Severity {
    /// Reported; the input is still accepted.
    Warning,
    /// The input is rejected.
    Error,
}

/// Stable diagnostic codes. The numeric families: `E01xx` lexical, `E02xx` syntax,
/// `E03xx`/`W03xx` semantic checks, `W04xx`/`E04xx` evaluation, `E05xx` input and command line,
/// `E06xx`/`W06xx` dataset (`.adm`) statements and command files, `E07xx`/`W07xx` the
/// multibody analysis, `E08xx` a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Code {
    /// A character that starts no token.
    UnexpectedChar,
    /// A malformed number such as `1.5D3`, `10DTOR` or `1.2.3`.
    BadNumber,
    /// A blank between a function name and its `(`.
    BlankBeforeParen,
    /// `<`, `==`, `.LT.`, `&&` and friends, which the language does not have.
    RelationalOperator,
    /// `* *`: a power operator split by a blank.
    SplitPower,
    /// A token the grammar did not expect here.
    UnexpectedToken,
    /// The input ended in the middle of an expression.
    UnexpectedEnd,
    /// A `)` or `]` with no opening partner.
    Unmatched,
    /// Nothing to evaluate.
    EmptyExpression,
    /// Two values side by side with no operator between them.
    MissingOperator,
    /// Parentheses, calls or operators nested past the limit.
    TooDeep,
    /// A function name the builtins table does not know.
    UnknownFunction,
    /// A bare name that is no constant and no user variable.
    UnknownName,
    /// Wrong number of arguments.
    Arity,
    /// An ID or integer code that is not an integer literal or is out of range.
    IntegerArgument,
    /// Scalar where a vector is needed or the reverse.
    Type,
    /// An arithmetic IF nested more than nine deep.
    IfTooDeep,
    /// A constant argument outside the function's domain (STEP x0 >= x1, IMPACT d <= 0, ...).
    Domain,
    /// A measure or element reference that needs a loaded model.
    NeedsModel,
    /// A function of the language that mbfx does not evaluate (yet).
    Unsupported,
    /// A constant written as a call or a function written without arguments.
    Misuse,
    /// A data element (SPLINE, VARIABLE, ...) that the model does not define.
    UndefinedElement,
    /// Units of measure that do not go together: a length added to a velocity, the sine
    /// of a length, a length where a force is expected (a warning only).
    UnitMismatch,
    /// An expression evaluated to NaN or an infinity.
    NonFinite,
    /// An arithmetic IF whose test is NaN: no branch can be chosen.
    NanIfTest,
    /// A file that cannot be read.
    Io,
    /// A file that is not valid UTF-8 (or contains bytes mbfx cannot read).
    Encoding,
    /// A bad command-line value (`--var`, `--time`).
    CommandLine,
    /// A dataset read in spite of its encoding: bytes that are not UTF-8 (read as
    /// Latin-1) or NUL bytes (read as blanks).
    EncodingRepaired,
    /// A malformed dataset statement.
    Statement,
    /// A dataset statement or argument mbfx does not handle: reported, never dropped silently.
    UnsupportedStatement,
    /// Two dataset statements of one kind with the same id.
    DuplicateId,
    /// A dataset statement without an argument it needs.
    MissingArgument,
    /// A dataset argument with a value of the wrong kind, count or range.
    BadArgument,
    /// A dataset that connects its elements in a way the model forbids (no or several
    /// GROUND parts, joint markers on one part, a floating marker where a fixed one is
    /// needed).
    Topology,
    /// A number in a dataset beyond the range of `f64` (`1E400`).
    NonFiniteNumber,
    /// Mass properties the equations of motion cannot use: a negative mass, an inertia
    /// tensor that is not positive semi-definite, zero inertia on a part with mass.
    MassProperties,
    /// Principal moments of inertia that break the triangle inequality: no real body has
    /// them, but they are positive and the equations of motion can use them.
    ImplausibleInertia,
    /// More errors than are worth showing for one expression.
    TooManyErrors,
    /// A command-file (`.acf`) command mbfx cannot carry out: it changes the model during
    /// the run or asks for an analysis mbfx does not have. The run does not start.
    UnsupportedCommand,
    /// A value set from outside the dataset (`--set`, `Model.with_values`) that does not
    /// apply: no such statement, a field it does not take, a value it refuses.
    BadSetting,
    /// A model whose constraints cannot all be satisfied at assembly.
    Assembly,
    /// Constraints that contradict each other (conflicting, not redundant).
    Conflicting,
    /// A model the multibody core could not analyse (a construct it does not support yet).
    NotAnalysed,
    /// A model that cannot be simulated as built (a massless part free to move, a force
    /// element the dynamics cannot evaluate, inconsistent initial conditions).
    CannotSimulate,
    /// The integration failed: the corrector diverged, the step fell below HMIN, or the
    /// equations of motion became singular.
    Integration,
    /// A force or state became NaN or infinite during a run.
    NonFiniteForce,
    /// The caller interrupted a run (a Python Ctrl-C, a C caller's flag): the rows before
    /// the interruption were delivered.
    Interrupted,
    /// No static equilibrium within MAXIT iterations.
    NoEquilibrium,
    /// A static equilibrium (or the search for one) along a neutral or unstable
    /// direction: a mechanism no spring holds, or an equilibrium that is not stable.
    Unstable,
    /// The static iteration stayed cut to TLIMIT or ALIMIT to the end.
    StepLimit,
    /// A kinematic analysis of a model with degrees of freedom left.
    FreeDegrees,
}

impl Code {
    /// The stable code string (`E0103`, `W0401`, ...).
    pub fn as_str(self) -> &'static str {
        use Code::*;
        match self {
            UnexpectedChar => "E0101",
            BadNumber => "E0102",
            BlankBeforeParen => "E0103",
            RelationalOperator => "E0104",
            SplitPower => "E0105",
            UnexpectedToken => "E0201",
            UnexpectedEnd => "E0202",
            Unmatched => "E0203",
            EmptyExpression => "E0204",
            MissingOperator => "E0205",
            TooDeep => "E0206",
            UnknownFunction => "E0301",
            UnknownName => "E0302",
            Arity => "E0303",
            IntegerArgument => "E0304",
            Type => "E0305",
            IfTooDeep => "E0306",
            Domain => "E0307",
            NeedsModel => "E0308",
            Unsupported => "E0309",
            Misuse => "E0310",
            UndefinedElement => "E0311",
            UnitMismatch => "W0312",
            NonFinite => "W0401",
            NanIfTest => "E0402",
            Io => "E0501",
            Encoding => "E0502",
            CommandLine => "E0503",
            EncodingRepaired => "W0504",
            Statement => "E0601",
            UnsupportedStatement => "W0602",
            DuplicateId => "E0603",
            MissingArgument => "E0604",
            BadArgument => "E0605",
            Topology => "E0606",
            NonFiniteNumber => "E0607",
            MassProperties => "E0608",
            ImplausibleInertia => "W0609",
            UnsupportedCommand => "E0610",
            BadSetting => "E0611",
            TooManyErrors => "E0207",
            Assembly => "E0701",
            Conflicting => "E0702",
            NotAnalysed => "W0703",
            CannotSimulate => "E0801",
            Integration => "E0802",
            NonFiniteForce => "E0803",
            Interrupted => "E0804",
            NoEquilibrium => "E0805",
            Unstable => "E0806",
            StepLimit => "E0807",
            FreeDegrees => "E0808",
        }
    }
}

/// One message about a place in a source text.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// The stable code (`E0402`, `W0602`, ...).
    pub code: Code,
    /// Error or warning.
    pub severity: Severity,
    /// The primary place; the caret points here.
    pub span: Span,
    /// What is wrong, short and lower case.
    pub message: String,
    /// Secondary places with a short label each.
    pub labels: Vec<(Span, String)>,
    /// Further facts, one line each.
    pub notes: Vec<String>,
    /// What to do about it.
    pub help: Option<String>,
}

impl Diagnostic {
    /// An error at `span`, with no labels, notes or help yet.
    pub fn error(code: Code, span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            code,
            severity: Severity::Error,
            span,
            message: message.into(),
            labels: Vec::new(),
            notes: Vec::new(),
            help: None,
        }
    }

    /// A warning at `span`, with no labels, notes or help yet.
    pub fn warning(code: Code, span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Warning,
            ..Diagnostic::error(code, span, message)
        }
    }

    /// Sets the help line.
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// Adds a note.
    pub fn with_note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    /// Adds a secondary place with its label.
    pub fn with_label(mut self, span: Span, label: impl Into<String>) -> Self {
        self.labels.push((span, label.into()));
        self
    }

    /// Moves every span by `offset` bytes: used when an expression was read out of a
    /// larger text (an `.adm` statement) so that messages point into the whole file.
    pub fn shifted(mut self, offset: usize) -> Self {
        self.span = self.span.start + offset..self.span.end + offset;
        for (span, _) in &mut self.labels {
            *span = span.start + offset..span.end + offset;
        }
        self
    }

    /// Whether the diagnostic is an error.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// True when any diagnostic in the list is an error.
pub fn has_errors(diags: &[Diagnostic]) -> bool {
    diags.iter().any(Diagnostic::is_error)
}

/// A named source text, with the line starts needed to turn byte offsets into
/// line and column numbers.
pub struct SourceFile {
    /// The file name messages show.
    pub name: String,
    /// The whole text.
    pub text: String,
    line_starts: Vec<usize>,
    /// ariadne's own line index of the text, built on the first rendered frame and kept:
    /// building it per diagnostic made many diagnostics on a big file quadratic (40 000
    /// in a 320 KB file took 24 s).
    frames: std::cell::OnceCell<ariadne::Source<String>>,
    /// No text stands behind it (a command-line option, an unreadable file): its
    /// diagnostics show no frame.
    textless: bool,
}

impl SourceFile {
    /// A source named `name` holding `text`, with its line index built.
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> Self {
        let text = text.into();
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        SourceFile {
            name: name.into(),
            text,
            line_starts,
            frames: std::cell::OnceCell::new(),
            textless: false,
        }
    }

    /// A copy of its name and text (and whether it has text), without the frame cache.
    pub fn duplicate(&self) -> SourceFile {
        SourceFile {
            textless: self.textless,
            ..SourceFile::new(self.name.clone(), self.text.clone())
        }
    }

    /// A source with no text to show, named `name` (a command-line option, a file that
    /// could not be read): diagnostics about it are one line, without a frame.
    pub fn textless(name: impl Into<String>) -> Self {
        SourceFile {
            textless: true,
            ..SourceFile::new(name, "")
        }
    }

    /// 1-based line and column (in bytes) of a byte offset. (Rendered frames count
    /// columns in characters, as ariadne does.)
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let line = self.line_starts.partition_point(|&s| s <= offset) - 1;
        (line + 1, offset - self.line_starts[line] + 1)
    }
}

/// Lines longer than this are shown as a window around the span instead of whole, so a
/// megabyte-long expression does not print a megabyte per diagnostic.
const LONG_LINE: usize = 400;

/// Bytes of context on each side of the span in a long-line window.
const WINDOW: usize = 60;

impl SourceFile {
    /// `span` clamped to the text and widened to character boundaries.
    fn snap(&self, span: &Span) -> Span {
        let len = self.text.len();
        let mut start = span.start.min(len);
        let mut end = span.end.min(len).max(start);
        while !self.text.is_char_boundary(start) {
            start -= 1;
        }
        while !self.text.is_char_boundary(end) {
            end += 1;
        }
        start..end
    }

    /// The byte range of the line holding `offset`, without its line break.
    fn line_range(&self, offset: usize) -> Span {
        let (line, _) = self.line_col(offset);
        let start = self.line_starts[line - 1];
        let end = self
            .line_starts
            .get(line)
            .map_or(self.text.len(), |&next| next);
        let text = &self.text[start..end];
        start..start + text.trim_end_matches(['\n', '\r']).len()
    }
}

/// Renders diagnostics as text with ariadne: `[code] Error: message`, then a frame headed
/// `file:line:col` with a caret under the span. `color` adds ANSI colours. Spans are
/// snapped to character boundaries, so any span is safe to render.
pub fn render(diags: &[Diagnostic], file: &SourceFile, color: bool) -> String {
    let mut out = String::new();
    for d in diags {
        let primary = file.snap(&d.span);
        let line = file.line_range(primary.start);
        if file.textless {
            // Nothing to show (a command-line option's value, a missing file): a frame
            // would be an empty line with a caret under nothing.
            render_bare(d, &file.name, &mut out);
        } else if line.len() > LONG_LINE {
            render_window(d, file, primary, line, &mut out);
        } else {
            render_frame(d, file, primary, color, &mut out);
        }
    }
    out
}

fn render_frame(d: &Diagnostic, file: &SourceFile, primary: Span, color: bool, out: &mut String) {
    use ariadne::{CharSet, Config, IndexType, Label, Report, ReportKind, Source};
    let kind = match d.severity {
        Severity::Error => ReportKind::Error,
        Severity::Warning => ReportKind::Warning,
    };
    let name = file.name.as_str();
    let mut report = Report::build(kind, (name, primary.clone()))
        .with_config(
            Config::default()
                .with_color(color)
                .with_index_type(IndexType::Byte)
                .with_char_set(CharSet::Ascii),
        )
        .with_code(d.code.as_str())
        .with_message(&d.message)
        .with_label(Label::new((name, primary)).with_message("here"));
    for (span, text) in &d.labels {
        report = report.with_label(Label::new((name, file.snap(span))).with_message(text));
    }
    for note in &d.notes {
        report = report.with_note(note);
    }
    if let Some(help) = &d.help {
        report = report.with_help(help);
    }
    let mut buf = Vec::new();
    let source = file
        .frames
        .get_or_init(|| Source::from(visible(&file.text)));
    if report.finish().write((name, source), &mut buf).is_ok() {
        out.push_str(&String::from_utf8_lossy(&buf));
    }
}

/// How a frame's header names a severity.
fn severity_word(s: Severity) -> &'static str {
    match s {
        Severity::Error => "Error",
        Severity::Warning => "Warning",
    }
}

/// A diagnostic about a source with no text: its header naming the source, then its notes
/// and help.
fn render_bare(d: &Diagnostic, name: &str, out: &mut String) {
    use std::fmt::Write as _;
    let severity = severity_word(d.severity);
    let _ = writeln!(
        out,
        "[{}] {severity}: {} ({name})",
        d.code.as_str(),
        d.message
    );
    for note in &d.notes {
        let _ = writeln!(out, "   = Note: {note}");
    }
    if let Some(help) = &d.help {
        let _ = writeln!(out, "   = Help: {help}");
    }
}

/// A compact frame for a span on a very long line: the header, a window of the line
/// around the span, and carets under the span (at most one window wide).
fn render_window(d: &Diagnostic, file: &SourceFile, primary: Span, line: Span, out: &mut String) {
    use std::fmt::Write as _;
    let severity = severity_word(d.severity);
    let (row, col) = file.line_col(primary.start);
    let from = file
        .snap(&(primary.start.saturating_sub(WINDOW).max(line.start)..primary.start))
        .start;
    let to = file
        .snap(&(primary.end..(primary.end + WINDOW).min(line.end)))
        .end;
    let before = &file.text[from..primary.start];
    let marked = &file.text[primary.clone()];
    // A span longer than the window (E0206 marks a whole expression) shows its start only.
    let to = if to - primary.start > 2 * WINDOW {
        file.snap(&(primary.start..primary.start + 2 * WINDOW)).end
    } else {
        to
    };
    let lead = if from > line.start { "..." } else { "" };
    let tail = if to < line.end { "..." } else { "" };
    let _ = writeln!(out, "[{}] {severity}: {}", d.code.as_str(), d.message);
    let _ = writeln!(out, "   ,-[ {}:{row}:{col} ]", file.name);
    let _ = writeln!(out, "   | {lead}{}{tail}", visible(&file.text[from..to]));
    let carets = marked.chars().count().clamp(1, WINDOW);
    let pad = lead.len() + before.chars().count();
    let _ = writeln!(out, "   | {}{} here", " ".repeat(pad), "^".repeat(carets));
    for note in &d.notes {
        let _ = writeln!(out, "   | Note: {note}");
    }
    if let Some(help) = &d.help {
        let _ = writeln!(out, "   | Help: {help}");
    }
    let _ = writeln!(out, "---'");
}

/// `text` as a frame may show it: every control character other than a line break or a
/// tab (ESC, NUL, a lone carriage return, ...) and every invisible or direction-changing
/// format character (zero-width space, bidi overrides, line separators, BOM) becomes `?`
/// repeated to its UTF-8 length, so byte offsets, and so spans, stay valid, the terminal
/// receives no escape sequence, and no caret hides behind an invisible character.
fn visible(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    for (i, c) in text.char_indices() {
        let lone_cr = c == '\r' && bytes.get(i + 1) != Some(&b'\n');
        let control = c.is_control() && !matches!(c, '\n' | '\t' | '\r');
        let invisible = matches!(
            c,
            '\u{200b}'..='\u{200f}' | '\u{2028}'..='\u{202e}' | '\u{2060}'..='\u{2064}' | '\u{feff}'
        );
        if lone_cr || control || invisible {
            out.extend(std::iter::repeat_n('?', c.len_utf8()));
        } else {
            out.push(c);
        }
    }
    out
}

/// Most diagnostics reported for one expression; past it, one note says how many more
/// there were (a line of garbage must not print thousands of frames).
pub const MAX_DIAGNOSTICS: usize = 20;

/// Truncates `diags` to [`MAX_DIAGNOSTICS`], adding a final note that counts the rest.
pub fn cap(diags: &mut Vec<Diagnostic>) {
    if diags.len() > MAX_DIAGNOSTICS {
        let more = diags.len() - MAX_DIAGNOSTICS + 1;
        diags.truncate(MAX_DIAGNOSTICS - 1);
        let at = diags.last().map_or(0..0, |d| d.span.clone());
        diags.push(Diagnostic::error(
            Code::TooManyErrors,
            at,
            format!("{more} more errors in this expression are not shown"),
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_counts_from_one() {
        let f = SourceFile::new("f", "ab\ncd\n");
        assert_eq!(f.line_col(0), (1, 1));
        assert_eq!(f.line_col(1), (1, 2));
        assert_eq!(f.line_col(3), (2, 1));
        assert_eq!(f.line_col(6), (3, 1));
        assert_eq!(f.line_col(99), (3, 1));
    }

    #[test]
    fn spans_inside_characters_render_without_panicking() {
        let f = SourceFile::new("u.txt", "1+\u{fffd}+\u{e9}");
        for start in 0..f.text.len() {
            let d = Diagnostic::error(Code::UnexpectedChar, start..start + 1, "x");
            assert!(render(&[d], &f, false).contains("u.txt:1:"));
        }
    }

    #[test]
    fn long_lines_render_as_a_window() {
        let text = format!("{}@{}", "1+".repeat(5000), "+1".repeat(5000));
        let f = SourceFile::new("long", text);
        let d = Diagnostic::error(Code::UnexpectedChar, 10000..10001, "unexpected");
        let out = render(&[d], &f, false);
        assert!(out.len() < 600, "{out}");
        assert!(out.contains("long:1:10001"), "{out}");
        let frame: Vec<&str> = out.lines().collect();
        let caret = frame[3].find('^').expect("caret");
        assert_eq!(frame[2].as_bytes()[caret], b'@', "{out}");
    }

    #[test]
    fn snippets_show_no_control_or_invisible_characters() {
        // ESC starting a colour sequence, NUL, a zero-width space before the bad `@`.
        let f = SourceFile::new("c.txt", "\u{1b}[31m1 + \0 + \u{200b}@");
        let at = f.text.find('@').unwrap_or_default();
        let d = Diagnostic::error(Code::UnexpectedChar, at..at + 1, "unexpected");
        let out = render(&[d], &f, false);
        assert!(!out.contains(['\u{1b}', '\0', '\u{200b}']), "{out:?}");
        assert!(out.contains("?[31m1 + ? + ???@"), "{out}");
        // The pointer stands under the `@`.
        let lines: Vec<&str> = out.lines().collect();
        let quoted = lines
            .iter()
            .position(|l| l.contains("???@"))
            .unwrap_or_default();
        let caret = lines[quoted + 1].rfind('|').unwrap_or_default();
        assert_eq!(lines[quoted].find('@'), Some(caret), "{out}");
    }

    #[test]
    fn a_long_span_on_a_long_line_shows_its_start_only() {
        // E0206 marks a whole expression: a 2 MB line must not be echoed.
        let text = "1+".repeat(1_000_000) + "1";
        let f = SourceFile::new("deep", text.as_str());
        let d = Diagnostic::error(Code::TooDeep, 0..text.len(), "too deep");
        let out = render(&[d], &f, false);
        assert!(out.len() < 600, "{} bytes", out.len());
        assert!(out.contains("1+1+1+") && out.contains("..."), "{out}");
    }

    #[test]
    fn cap_keeps_a_bounded_list_and_counts_the_rest() {
        let mut diags: Vec<Diagnostic> = (0..50)
            .map(|i| Diagnostic::error(Code::UnexpectedChar, i..i + 1, "x"))
            .collect();
        cap(&mut diags);
        assert_eq!(diags.len(), MAX_DIAGNOSTICS);
        assert!(diags[MAX_DIAGNOSTICS - 1]
            .message
            .starts_with("31 more errors"));
    }

    #[test]
    fn a_diagnostic_about_no_text_has_no_frame() {
        let f = SourceFile::textless("command line");
        let d = Diagnostic::error(Code::CommandLine, 0..0, "--end 0 must be a positive time")
            .with_help("give --end a time in seconds");
        let text = render(&[d], &f, false);
        assert_eq!(
            text,
            "[E0503] Error: --end 0 must be a positive time (command line)\n   = Help: give --end a time in seconds\n"
        );
    }

    #[test]
    fn render_names_file_line_column_and_code() {
        let f = SourceFile::new("x.txt", "1+\nSIN (1)");
        let d = Diagnostic::error(Code::BlankBeforeParen, 6..7, "no blank allowed");
        let text = render(&[d], &f, false);
        assert!(
            text.starts_with("[E0103] Error: no blank allowed"),
            "{text}"
        );
        assert!(text.contains("x.txt:2:4"), "{text}");
        // The pointer stands under column 4 of the quoted line (after the 5-wide margin ` 2 | `).
        let pointer = text
            .lines()
            .find(|l| l.trim_end().ends_with("`-- here"))
            .unwrap_or_default();
        assert_eq!(pointer.find('`'), Some(5 + 3), "{text}");
    }
}
