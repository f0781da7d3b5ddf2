//! The REPL: [`Repl`] is a plain struct that answers one input at a time (tested without a
//! terminal); [`run_terminal`] wraps it in rustyline with history, multi-line input
//! (continuation commas, open brackets) and tab completion of names and commands.

use crate::check::{units, Expect};
use crate::diag::{render, Diagnostic, SourceFile};
use crate::interp::Program;
use crate::model::scope::WithVariables;
use crate::session::evaluate::{EvalError, Evaluation, Evaluator};
use crate::session::loaded::LoadedModel;
use crate::session::run::Engine;
use crate::session::DimRequest;
use crate::syntax::{parser, print};
use crate::vocab::builtins;
use std::fmt::Write as _;

const HELP: &str = "\
expressions are evaluated as you type them, e.g. STEP(0.25, 0, 0, 1, 1)
:let NAME = EXPR   define or change a variable
:set time = EXPR   set the value of TIME (also: :set mode = EXPR)
:vars              list variables
:ast EXPR          show the syntax tree
:ir EXPR           show the IR the back ends run
:clif EXPR         show the Cranelift IR the JIT compiles (after branch-free lowering)
:asm EXPR          show the machine instructions the JIT emits for EXPR
:time EXPR         ns per evaluation, interpreter vs JIT (at most 0.5 s each), and the JIT's compile time
:deriv EXPR NAME   the partial derivative of EXPR with respect to variable NAME (or TIME)
:units EXPR        the physical dimension of EXPR (in the loaded model's UNITS) and its unit warnings
:load FILE.adm     load a model: expressions may then read its measures (DX, VZ, UVZ, ...)
                   at the assembled configuration; :load alone unloads it
:parts, :markers   the loaded model's parts and markers at that configuration
:help [NAME]       this text, or a function's signature and meaning
:quit              leave (also Ctrl-D)
continue a line with a comma in column one of the next line";

const COMMANDS: &[&str] = &[
    ":let", ":set", ":vars", ":ast", ":ir", ":clif", ":asm", ":time", ":deriv", ":units", ":load",
    ":parts", ":markers", ":help", ":quit",
];

/// A listing the JIT makes of a compiled expression (`Jit::clif`, `Jit::asm`).
type JitListing =
    fn(&mut crate::jit::Jit, &crate::ir::Function) -> Result<String, crate::jit::JitError>;

/// REPL state: what expressions are evaluated against (variables, TIME and MODE, the
/// model of `:load`; the interpreter evaluates) and whether the session is over.
pub struct Repl {
    e: Evaluator,
    /// Set by `:quit`.
    pub done: bool,
}

impl Default for Repl {
    fn default() -> Self {
        Self::new()
    }
}

impl Repl {
    /// A REPL on the interpreter, with no variables yet.
    pub fn new() -> Self {
        Repl {
            e: Evaluator::new(Engine::Interp),
            done: false,
        }
    }

    /// Names to complete: builtins, variables and commands.
    pub fn completions(&self) -> Vec<String> {
        let mut names: Vec<String> = builtins::all_names().map(str::to_string).collect();
        names.extend(self.e.variables().names().iter().cloned());
        names.extend(COMMANDS.iter().map(|c| c.to_string()));
        names
    }

    /// Compiles `text`, rendering diagnostics (spans relative to `text`) on failure.
    fn compile(&mut self, text: &str) -> Result<(Program, String), String> {
        let source = SourceFile::new("<repl>", text);
        match self.e.compile(text, Expect::Any) {
            Ok(c) => Ok((Program::new(c.function), rendered(&c.warnings, &source))),
            Err(d) => Err(render(&d, &source, false)),
        }
    }

    /// Evaluates `text`: its value and the warnings rendered, or why it has none.
    fn evaluate(&mut self, text: &str) -> Result<(Vec<f64>, String), String> {
        let source = SourceFile::new("<repl>", text);
        match self.e.evaluate(text, Expect::Any) {
            Ok(Evaluation {
                values,
                mut warnings,
                fault,
            }) => {
                warnings.extend(fault);
                Ok((values, rendered(&warnings, &source)))
            }
            Err(failed) => Err(failure_text(&failed, &source)),
        }
    }

    /// Answers one input (possibly several physical lines joined by `\n`). A line that
    /// starts with a comma continues the previous one as in a dataset; any other line of a
    /// multi-line input (the REPL waited because a bracket was open) joins with a blank.
    pub fn eval_line(&mut self, input: &str) -> String {
        let joined = join_lines(input);
        let line = joined.as_str();
        let trimmed = line.trim();
        if trimmed.is_empty() {
            return String::new();
        }
        let Some(command) = trimmed.strip_prefix(':') else {
            return match self.evaluate(line) {
                Ok((v, notes)) => format!("{notes}{}", super::eval::format_value(&v)),
                Err(e) => e,
            };
        };
        let (word, rest) = command
            .split_once(char::is_whitespace)
            .unwrap_or((command, ""));
        let rest = rest.trim();
        match word.to_ascii_lowercase().as_str() {
            "quit" | "q" | "exit" => {
                self.done = true;
                String::new()
            }
            "help" | "h" => help(rest),
            "vars" => {
                let mut out = format!("TIME = {:?}\nMODE = {:?}", self.e.time, self.e.mode);
                for (n, v) in self.e.values() {
                    let _ = write!(out, "\n{n} = {v:?}");
                }
                out
            }
            "let" => self.let_(rest),
            "set" => self.set(rest),
            "ast" => {
                let parsed = parser::parse(rest);
                match parsed.root {
                    Some(root) if parsed.diagnostics.is_empty() => format!(
                        "{}\n{}",
                        print::print(&parsed.ast, root),
                        parsed.ast.sexpr(root)
                    ),
                    _ => render(&parsed.diagnostics, &SourceFile::new("<repl>", rest), false),
                }
            }
            "ir" => match self.compile(rest) {
                Ok((p, w)) => format!("{w}{}", crate::ir::print::print(p.function()).trim_end()),
                Err(e) => e,
            },
            "clif" => self.jit_listing(rest, crate::jit::Jit::clif),
            "asm" => self.jit_listing(rest, crate::jit::Jit::asm),
            "time" => match self.compile(rest) {
                Ok((p, _)) => self.time_(&p),
                Err(e) => e,
            },
            "deriv" => self.deriv(rest),
            "units" => self.units(rest),
            "load" => self.load(rest),
            "parts" => self.listing(parts_table),
            "markers" => self.listing(markers_table),
            other => format!("unknown command :{other}; type :help"),
        }
    }

    /// What the JIT's `show` (`Jit::clif`, `Jit::asm`) lists for expression `rest`.
    fn jit_listing(&mut self, rest: &str, show: JitListing) -> String {
        match self.compile(rest) {
            Ok((p, _)) => match self.e.jit().and_then(|j| show(j, p.function())) {
                Ok(text) => text.trim_end().to_string(),
                Err(e) => format!("error: {e}"),
            },
            Err(e) => e,
        }
    }

    /// The loaded model's unit names; none without a model (messages then name the
    /// bases: "a velocity (length/time)").
    fn unit_names(&self) -> Option<&units::UnitNames> {
        self.e.model().map(|m| &m.read.scope().unit_names)
    }

    /// `:units EXPR`: the dimension of EXPR in the loaded model's units (user variables
    /// and numbers are free), after its unit warnings; its errors when it does not check.
    fn units(&mut self, rest: &str) -> String {
        if let Err(e) = self.compile(rest) {
            return e;
        }
        let source = SourceFile::new("<repl>", rest);
        let names = self.unit_names();
        let with_model;
        let scope: &dyn crate::check::Scope = match self.e.model() {
            Some(m) => {
                with_model = WithVariables {
                    model: m.read.scope(),
                    variables: self.e.variables(),
                };
                &with_model
            }
            None => self.e.variables(),
        };
        match units::infer_text(rest, scope, names) {
            Ok((d, warnings)) => format!(
                "{}{}",
                rendered(&warnings, &source),
                units::summary(d, names)
            ),
            Err(d) => render(&d, &source, false),
        }
    }

    /// `:let NAME = EXPR`, or `:let NAME: DIMENSION = EXPR` (`:let v: m/s = 2`), which
    /// also gives the variable a dimension for the units check.
    fn let_(&mut self, rest: &str) -> String {
        let Some((name, expr)) = rest.split_once('=') else {
            return "usage: :let NAME = EXPR  or  :let NAME: DIMENSION = EXPR".to_string();
        };
        let (name, dim) = match name.split_once(':') {
            Some((name, dim)) => match units::parse::parse(dim) {
                Ok(d) => (name, Some(d)),
                Err(why) => return why,
            },
            None => (name, None),
        };
        let name = name.trim().to_ascii_uppercase();
        if let Err(bad) = crate::check::scope::check_variable_name(&name) {
            return format!("{}; {}", bad.message(&name), bad.help());
        }
        match self.evaluate(expr) {
            Ok((v, notes)) if v.len() == 1 => {
                self.e.set_variable(&name, v[0]);
                let unit = match dim {
                    Some(d) => {
                        self.e.set_dim(&name, d);
                        format!(", {}", units::describe(d, self.unit_names()))
                    }
                    None => String::new(),
                };
                format!("{notes}{name} = {:?}{unit}", v[0])
            }
            Ok(_) => "variables hold scalars; this is a vector".to_string(),
            Err(e) => e,
        }
    }

    fn set(&mut self, rest: &str) -> String {
        let Some((name, expr)) = rest.split_once('=') else {
            return "usage: :set time = EXPR  or  :set mode = EXPR".to_string();
        };
        let value = match self.evaluate(expr) {
            Ok((v, _)) if v.len() == 1 => v[0],
            Ok(_) => return "TIME and MODE are scalars".to_string(),
            Err(e) => return e,
        };
        match name.trim().to_ascii_lowercase().as_str() {
            "time" => self.e.time = value,
            "mode" => self.e.mode = value,
            other => return format!("cannot set `{other}`; use :let for variables"),
        }
        format!("{} = {value:?}", name.trim().to_ascii_uppercase())
    }
}

impl Repl {
    /// `:load FILE`: reads, assembles and analyses a dataset (2D when planar).
    fn load(&mut self, path: &str) -> String {
        if path.is_empty() {
            return match self.e.set_model(None) {
                Some(_) => "model unloaded".into(),
                None => "usage: :load FILE.adm".into(),
            };
        }
        match super::eval::load_model(std::path::Path::new(path), DimRequest::Auto, false) {
            Ok(m) => {
                let line = format!("loaded {path}: {}", m.summary());
                self.e.set_model(Some(m));
                line
            }
            Err(text) => {
                let mut answer = text.trim_end().to_string();
                if self.e.model().is_some() {
                    answer.push_str(
                        "\nthe model loaded before stays loaded (`:load` alone unloads it)",
                    );
                }
                answer
            }
        }
    }

    fn listing(&self, table: fn(&LoadedModel) -> String) -> String {
        match self.e.model() {
            Some(m) => table(m),
            None => "no model loaded; use :load FILE.adm".into(),
        }
    }

    /// `:time EXPR`: median ns per evaluation of both back ends, and compile µs. Each
    /// engine is measured for at most [`TIME_BUDGET`] seconds after one first evaluation,
    /// so a huge expression answers in about a second instead of running a fixed count.
    fn time_(&mut self, p: &Program) -> String {
        use std::hint::black_box;
        use std::time::Instant;
        let jit = match self.e.jit() {
            Ok(j) => j,
            Err(e) => return format!("error: {e}"),
        };
        let t0 = Instant::now();
        let code = match jit.compile(p.function()) {
            Ok(c) => c,
            Err(e) => return format!("error: {e}"),
        };
        let compile_us = t0.elapsed().as_secs_f64() * 1e6;
        let n = p.function().outputs.len();
        let timed = self.e.in_context(p.function(), |ctx| {
            let mut out = vec![0.0; n];
            let mut per_eval = |f: &mut dyn FnMut(&mut [f64])| {
                let t = Instant::now();
                f(black_box(&mut out));
                let (samples, batch) = time_plan(t.elapsed().as_secs_f64());
                let mut ns: Vec<f64> = (0..samples)
                    .map(|_| {
                        let t = Instant::now();
                        for _ in 0..batch {
                            f(black_box(&mut out));
                        }
                        t.elapsed().as_secs_f64() * 1e9 / batch as f64
                    })
                    .collect();
                ns.sort_by(f64::total_cmp);
                (ns[ns.len() / 2], samples * batch)
            };
            let interp = per_eval(&mut |o| p.eval_into(black_box(ctx), o));
            (interp, per_eval(&mut |o| code.eval_into(black_box(ctx), o)))
        });
        let ((interp, n_interp), (jit, n_jit)) = match timed {
            Ok(times) => times,
            Err(e) => return format!("error: {e}"),
        };
        format!(
            "interp {interp:.1} ns/eval, jit {jit:.1} ns/eval ({:.1}× faster); jit compile \
             {compile_us:.0} µs\n(medians over {n_interp} and {n_jit} evaluations, at most \
             {TIME_BUDGET} s per engine)",
            interp / jit
        )
    }

    /// `:deriv EXPR NAME`: ∂EXPR/∂NAME as an expression, and its value here.
    fn deriv(&mut self, rest: &str) -> String {
        use crate::ir::deriv::{gradient, Input};
        let Some((expr, var)) = rest.trim_end().rsplit_once(char::is_whitespace) else {
            return "usage: :deriv EXPR NAME".into();
        };
        let input = if var.eq_ignore_ascii_case("TIME") {
            Input::Time
        } else {
            match self
                .e
                .variables()
                .names()
                .iter()
                .position(|n| n.eq_ignore_ascii_case(var))
            {
                Some(slot) => Input::Var(slot as u32),
                None => {
                    return format!("`{var}` is not a variable; define it with :let {var} = ...")
                }
            }
        };
        let (p, _) = match self.compile(expr) {
            Ok(c) => c,
            Err(e) => return e,
        };
        let g = match gradient(p.function(), &[input]) {
            Ok(g) => g,
            Err(e) => return format!("error: {e}"),
        };
        let names = self.e.variables().names().to_vec();
        let name = |s: u32| {
            names
                .get(s as usize)
                .cloned()
                .unwrap_or_else(|| format!("var[{s}]"))
        };
        let n = p.function().outputs.len();
        let program = Program::new(g);
        let mut values = vec![0.0; program.function().outputs.len()];
        if let Err(e) = self.e.in_context(program.function(), |ctx| {
            program.eval_into(ctx, &mut values)
        }) {
            return format!("error: {e}");
        }
        let mut lines = Vec::new();
        for i in 0..n {
            let text = crate::ir::print::expression(program.function(), n + i, &name, 4000)
                .unwrap_or_else(|| "(too long to print; see :ir)".into());
            lines.push(format!(
                "{text}
  = {:?} here",
                values[n + i]
            ));
        }
        lines.join("\n")
    }
}

/// `:parts`: each part's id, name and assembled pose (origin, 3-1-3 angles in degrees).
fn parts_table(m: &LoadedModel) -> String {
    let mut out = format!(
        "{:<10} {:<12} {:>12} {:>12} {:>12} {:>10} {:>10} {:>10}",
        "PART", "name", "x", "y", "z", "psi", "theta", "phi"
    );
    for p in m.part_poses() {
        let [x, y, z] = p.origin;
        let [psi, theta, phi] = p.euler_313_degrees;
        let _ = write!(
            out,
            "\n{:<10} {:<12} {:>12.6} {:>12.6} {:>12.6} {:>10.4} {:>10.4} {:>10.4}",
            p.id.map_or("-".into(), |id| id.to_string()),
            p.name.as_deref().unwrap_or(""),
            x,
            y,
            z,
            psi,
            theta,
            phi
        );
    }
    out
}

/// `:markers`: each marker's id, part and assembled global origin.
fn markers_table(m: &LoadedModel) -> String {
    let mut out = format!(
        "{:<10} {:<10} {:<12} {:>12} {:>12} {:>12}",
        "MARKER", "PART", "name", "x", "y", "z"
    );
    for k in m.marker_places() {
        let [x, y, z] = k.origin;
        let _ = write!(
            out,
            "\n{:<10} {:<10} {:<12} {:>12.6} {:>12.6} {:>12.6}",
            k.id.map_or("-".into(), |id| id.to_string()),
            k.part.map_or("-".into(), |id| id.to_string()),
            k.name.as_deref().unwrap_or(""),
            x,
            y,
            z
        );
    }
    out
}

fn help(name: &str) -> String {
    if name.is_empty() {
        return HELP.to_string();
    }
    let upper = name.to_ascii_uppercase();
    if upper == "IF" {
        return "IF(e1: e2, e3, e4): e2 if e1 < 0, e3 if e1 = 0, e4 if e1 > 0; only that branch is evaluated".to_string();
    }
    match builtins::lookup(&upper) {
        Some(b) => b.doc.to_string(),
        None => format!("no builtin named {upper}"),
    }
}

/// Diagnostics rendered without colour (nothing for none).
fn rendered(diags: &[Diagnostic], source: &SourceFile) -> String {
    if diags.is_empty() {
        return String::new();
    }
    render(diags, source, false)
}

/// Why an expression has no value, as the REPL answers it.
fn failure_text(failed: &EvalError, source: &SourceFile) -> String {
    let mut text = rendered(failed.diagnostics(), source);
    if let Some(why) = failed.failure() {
        text.push_str(&format!("error: {why}"));
    }
    text
}

/// Joins the physical lines of one REPL input: `\n,` continuations stay for the lexer,
/// other line breaks become blanks.
fn join_lines(input: &str) -> String {
    let mut out = String::with_capacity(input.len());
    for (i, line) in input.split('\n').enumerate() {
        if i > 0 {
            let continued = line.trim_start().starts_with(',');
            out.push(if continued { '\n' } else { ' ' });
        }
        out.push_str(line);
    }
    out
}

/// True when an input should continue on another line: a bracket is still open, or the
/// line ends with a comma (an argument list broken at its comma).
pub fn needs_more(input: &str) -> bool {
    if input.trim_start().starts_with(':') && !input.trim_start().starts_with(":let") {
        return false;
    }
    let mut depth = 0i64;
    for b in input.bytes() {
        match b {
            b'(' | b'[' => depth += 1,
            b')' | b']' => depth -= 1,
            _ => {}
        }
    }
    depth > 0 || input.trim_end().ends_with(',')
}

mod terminal {
    //! rustyline glue: completion and multi-line validation.
    use rustyline::completion::{Completer, Pair};
    use rustyline::highlight::Highlighter;
    use rustyline::hint::Hinter;
    use rustyline::validate::{ValidationContext, ValidationResult, Validator};
    use rustyline::{Context, Helper};
    use std::cell::RefCell;
    use std::rc::Rc;

    pub struct ReplHelper {
        pub names: Rc<RefCell<Vec<String>>>,
    }

    impl Completer for ReplHelper {
        type Candidate = Pair;

        fn complete(
            &self,
            line: &str,
            pos: usize,
            _: &Context<'_>,
        ) -> rustyline::Result<(usize, Vec<Pair>)> {
            let start = line[..pos]
                .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':'))
                .map_or(0, |i| i + 1);
            let word = line[start..pos].to_ascii_uppercase();
            let candidates = self
                .names
                .borrow()
                .iter()
                .filter(|n| !word.is_empty() && n.to_ascii_uppercase().starts_with(&word))
                .map(|n| Pair {
                    display: n.clone(),
                    replacement: n.clone(),
                })
                .collect();
            Ok((start, candidates))
        }
    }

    impl Hinter for ReplHelper {
        type Hint = String;
    }

    impl Highlighter for ReplHelper {}

    impl Validator for ReplHelper {
        fn validate(&self, ctx: &mut ValidationContext) -> rustyline::Result<ValidationResult> {
            Ok(if super::needs_more(ctx.input()) {
                ValidationResult::Incomplete
            } else {
                ValidationResult::Valid(None)
            })
        }
    }

    impl Helper for ReplHelper {}
}

/// Runs the REPL until `:quit` or end of input: with line editing when standard input is
/// a terminal, else reading it line by line ([`run_lines`]); returns the exit code.
pub fn run_terminal(o: &mut super::Output) -> Result<i32, super::Stop> {
    use rustyline::error::ReadlineError;
    use std::cell::RefCell;
    use std::io::IsTerminal;
    use std::rc::Rc;
    let mut repl = Repl::new();
    if !std::io::stdin().is_terminal() {
        writeln!(o.out(), "{}", banner())?;
        return run_lines(&mut repl, std::io::stdin().lock(), o);
    }
    let names = Rc::new(RefCell::new(repl.completions()));
    let Ok(mut editor) =
        rustyline::Editor::<terminal::ReplHelper, rustyline::history::DefaultHistory>::new()
    else {
        writeln!(o.err(), "mbfx repl: cannot open the terminal")?;
        return Err(super::Stop::Failed);
    };
    editor.set_helper(Some(terminal::ReplHelper {
        names: names.clone(),
    }));
    let history =
        std::env::var_os("HOME").map(|h| std::path::PathBuf::from(h).join(".mbfx_history"));
    if let Some(h) = &history {
        let _ = editor.load_history(h);
    }
    writeln!(o.out(), "{}", banner())?;
    loop {
        match editor.readline("mbfx> ") {
            Ok(line) => {
                let _ = editor.add_history_entry(line.as_str());
                reply(&mut repl, &line, o)?;
                *names.borrow_mut() = repl.completions();
                if repl.done {
                    break;
                }
            }
            Err(ReadlineError::Interrupted) => continue,
            // The reader has consumed the line: say so and read the next one.
            Err(ReadlineError::Io(e)) if e.kind() == std::io::ErrorKind::InvalidData => {
                writeln!(o.out(), "{NOT_UTF8}")?;
            }
            Err(_) => break,
        }
    }
    if let Some(h) = &history {
        let _ = editor.save_history(h);
    }
    Ok(0)
}

/// The first line the REPL prints.
fn banner() -> String {
    format!(
        "mbfx {} — :help for help, :quit to leave",
        env!("CARGO_PKG_VERSION")
    )
}

/// Runs the REPL over `input` read line by line (standard input that is not a terminal):
/// lines join into one input while [`needs_more`] says so, as at the terminal, and an input
/// still open at the end of the text is answered too (`SIN(1` says its `)` is missing)
/// instead of being dropped. A line that is not UTF-8 is reported and skipped.
pub fn run_lines(
    repl: &mut Repl,
    mut input: impl std::io::BufRead,
    o: &mut super::Output,
) -> Result<i32, super::Stop> {
    let mut pending = String::new();
    let mut line = Vec::new();
    loop {
        line.clear();
        match input.read_until(b'\n', &mut line) {
            Ok(0) => break,
            Ok(_) => {}
            Err(e) => {
                writeln!(o.err(), "mbfx repl: cannot read the input: {e}")?;
                return Err(super::Stop::Failed);
            }
        }
        let text = line.strip_suffix(b"\n").unwrap_or(&line);
        let text = text.strip_suffix(b"\r").unwrap_or(text);
        let Ok(text) = std::str::from_utf8(text) else {
            writeln!(o.out(), "{NOT_UTF8}")?;
            continue;
        };
        if !pending.is_empty() {
            pending.push('\n');
        }
        pending.push_str(text);
        if needs_more(&pending) {
            continue;
        }
        reply(repl, &std::mem::take(&mut pending), o)?;
        if repl.done {
            return Ok(0);
        }
    }
    if !pending.is_empty() {
        reply(repl, &pending, o)?;
    }
    Ok(0)
}

/// Answers one input on standard output (nothing for an input with no answer).
fn reply(repl: &mut Repl, input: &str, o: &mut super::Output) -> std::io::Result<()> {
    let answer = repl.eval_line(input);
    if answer.is_empty() {
        return Ok(());
    }
    writeln!(o.out(), "{answer}")
}

/// The answer to an input line that is not UTF-8 text.
const NOT_UTF8: &str = "[E0502] Error: the line is not valid UTF-8 text; it is skipped";

/// Seconds `:time` spends evaluating with each engine, at most.
pub const TIME_BUDGET: f64 = 0.5;

/// How `:time` samples an engine whose first evaluation took `first` seconds: up to seven
/// samples of up to 20 000 evaluations each, fewer and smaller when that would overrun
/// [`TIME_BUDGET`] (at least one sample of one evaluation).
fn time_plan(first: f64) -> (usize, usize) {
    const SAMPLES: usize = 7;
    const BATCH: usize = 20_000;
    let first = first.max(1e-9);
    let fits = (TIME_BUDGET / first).floor();
    // `fits` is at least 0 and small enough for usize once clamped below BATCH·SAMPLES.
    let fits = fits.min((BATCH * SAMPLES) as f64) as usize;
    let samples = fits.clamp(1, SAMPLES);
    let batch = (fits / samples).clamp(1, BATCH);
    (samples, batch)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_stays_within_its_budget() {
        // 1 ns per evaluation: the full plan, 7 × 20 000.
        assert_eq!(time_plan(1e-9), (7, 20_000));
        // 2⁻¹⁶ s: 32 768 evaluations fit in 0.5 s, as 7 samples of 4 681.
        assert_eq!(time_plan(1.0 / 65_536.0), (7, 4_681));
        // 0.125 s: four evaluations, one per sample.
        assert_eq!(time_plan(0.125), (4, 1));
        // Slower than the budget: one evaluation.
        assert_eq!(time_plan(3.0), (1, 1));
        for first in [1e-9, 1e-7, 1e-5, 1e-3, 0.05, 0.2, 2.0] {
            let (samples, batch) = time_plan(first);
            let spent = (samples * batch) as f64 * first;
            assert!(spent <= TIME_BUDGET.max(first) + 1e-12, "{first}: {spent}");
        }
    }

    #[test]
    fn evaluates_lets_and_commands() {
        let mut r = Repl::new();
        assert_eq!(r.eval_line("1 + 2"), "3.0");
        assert_eq!(r.eval_line(":let x = 2"), "X = 2.0");
        assert_eq!(r.eval_line("x**3"), "8.0");
        assert_eq!(r.eval_line(":set time = 0.5"), "TIME = 0.5");
        assert_eq!(r.eval_line("STEP(TIME,0,0,\n, 1,100)"), "50.0");
        assert_eq!(r.eval_line("STEP(TIME, 0, 0, 1,\n100)"), "50.0");
        assert!(r
            .eval_line(":help STEP")
            .starts_with("STEP(x, x0, h0, x1, h1)"));
        assert!(r.eval_line(":ir x*x").contains("mul"));
        assert!(r.eval_line(":clif x*x + 1").contains("fmul"));
        assert!(r.eval_line(":asm x*x + 1").contains("mulsd"));
        assert!(r.eval_line(":time x*x").contains("ns/eval"));
        // d(x³)/dx = 3x² = 12 at x = 2.
        assert!(r.eval_line(":deriv x**3 x").ends_with("= 12.0 here"));
        assert!(r
            .eval_line(":deriv SIN(TIME) TIME")
            .contains("= 0.8775825618903728 here"));
        assert_eq!(r.eval_line(":ast -2**2").lines().next(), Some("-2.0**2.0"));
        assert!(r.eval_line("SIN (1)").contains("E0103"));
        r.eval_line(":quit");
        assert!(r.done);
    }

    #[test]
    fn a_loaded_model_answers_measures_parts_and_markers() {
        // examples/slider.adm: marker 21 sits at QP = 0.3, 0, 0 on the slider, whose BCS
        // is at the origin; REULER = 90D, 90D, 0D turns z to the global x axis.
        let mut r = Repl::new();
        assert!(r
            .eval_line(":load examples/slider.adm")
            .starts_with("loaded"));
        assert_eq!(r.eval_line("DX(21, 11)"), "0.3");
        assert!(r.eval_line("UVZ(21)").starts_with("[1.0, "));
        r.eval_line(":let k = 2");
        assert_eq!(r.eval_line("k*DX(22, 11)"), "0.6");
        assert!(r.eval_line(":parts").lines().any(|l| l.starts_with("2 ")));
        assert!(r.eval_line(":markers").contains("rail_origin"));
        assert!(r.eval_line("DX(99)").contains("E0311"));
        assert_eq!(r.eval_line(":load"), "model unloaded");
        assert!(r.eval_line("DX(21, 11)").contains("E0308"));
        assert!(r.eval_line(":load no/such.adm").contains("E0501"));
        // A failed :load after a good one says that the good one stays.
        r.eval_line(":load examples/slider.adm");
        let failed = r.eval_line(":load no/such.adm");
        assert!(failed.contains("E0501"), "{failed}");
        assert!(
            failed.ends_with("stays loaded (`:load` alone unloads it)"),
            "{failed}"
        );
        assert_eq!(r.eval_line("DX(21, 11)"), "0.3");
        // :deriv and :time evaluate with the model's measures too (they read none before).
        assert!(r
            .eval_line(":deriv DX(21, 11)*TIME TIME")
            .ends_with("= 0.3 here"));
        assert!(r.eval_line(":time DX(21, 11)").contains("ns/eval"));
    }

    #[test]
    fn units_prints_the_dimension_and_the_unit_warnings() {
        let mut r = Repl::new();
        // No model: a length over a time is a velocity; numbers and variables are free.
        assert_eq!(r.eval_line(":units TIME*TIME"), "a quantity in time^2");
        r.eval_line(":let k = 2");
        assert!(r.eval_line(":units k*TIME").starts_with("free"));
        assert!(r.eval_line(":units SIN(").contains("E0202"));
        // examples/slider.adm is in meter and second; its markers 21, 22 and 11 exist.
        r.eval_line(":load examples/slider.adm");
        assert_eq!(
            r.eval_line(":units DX(21, 11)/TIME"),
            "a velocity (meter/second)"
        );
        assert_eq!(
            r.eval_line(":units FX(21)*DY(22, 11)"),
            "a torque (newton-meter)"
        );
        let mixed = r.eval_line(":units DX(21, 11) + VX(21, 11)");
        assert!(mixed.contains("[W0312]"), "{mixed}");
        assert!(
            mixed.contains("adds a length (meter) to a velocity (meter/second)"),
            "{mixed}"
        );
        assert!(
            mixed.ends_with("free: a number in it can give it any dimension"),
            "{mixed}"
        );
    }

    #[test]
    fn variables_given_a_dimension_are_checked_for_units() {
        let mut r = Repl::new();
        assert_eq!(r.eval_line(":let x: m = 1"), "X = 1.0, a length");
        assert_eq!(
            r.eval_line(":let v: velocity = 2"),
            "V = 2.0, a velocity (length/time)"
        );
        assert_eq!(r.eval_line(":units x/TIME"), "a velocity (length/time)");
        // A length plus a velocity warns, and still has its value.
        let sum = r.eval_line("x + v");
        assert!(sum.contains("[W0312]"), "{sum}");
        assert!(
            sum.contains("adds a length to a velocity (length/time)"),
            "{sum}"
        );
        assert!(sum.ends_with("3.0"), "{sum}");
        assert_eq!(r.eval_line("x + v*TIME"), "1.0");
        assert!(r
            .eval_line(":let w: furlong = 1")
            .contains("`furlong` is not a unit"));
        // Typed against a model, lines are checked in its units.
        r.eval_line(":load examples/slider.adm");
        let line = r.eval_line("DX(21, 11) + x + v*TIME");
        assert!(!line.contains("W0312"), "{line}");
        let line = r.eval_line("DX(21, 11) + v");
        assert!(
            line.contains("adds a length (meter) to a velocity (meter/second)"),
            "{line}"
        );
    }

    #[test]
    fn a_nan_if_test_is_an_error_with_no_value() {
        let mut r = Repl::new();
        let answer = r.eval_line("IF(0/0: 1, 2, 3)");
        assert!(answer.contains("[E0402] Error"), "{answer}");
        assert!(!answer.ends_with("NaN"), "{answer}");
        assert!(r.eval_line(":let a = IF(0/0: 1, 2, 3)").contains("E0402"));
        assert!(r.eval_line("a").contains("E0302"));
        // Any other non-finite value is printed, after its warning.
        let answer = r.eval_line("LOG(0)");
        assert!(answer.contains("[W0401] Warning"), "{answer}");
        assert!(answer.ends_with("-inf"), "{answer}");
    }

    /// What [`run_lines`] writes to standard output for `input`, and its exit code.
    fn answers(input: &str) -> (i32, String) {
        let mut out = Vec::new();
        let mut o = super::super::Output::new(Box::new(&mut out), Box::new(std::io::sink()), false);
        let code = run_lines(&mut Repl::new(), input.as_bytes(), &mut o);
        let code = super::super::output::finish(code, &mut o);
        drop(o);
        (code, String::from_utf8_lossy(&out).into_owned())
    }

    #[test]
    fn input_still_open_at_the_end_of_the_text_is_answered() {
        // Issue 11 §4: `SIN(1` then the end of input was dropped silently.
        let (code, out) = answers("SIN(1");
        assert_eq!(code, 0);
        assert!(out.contains("E0202"), "{out}");
        assert!(out.contains("missing `)`"), "{out}");
        let (_, out) = answers("1+1\nSTEP(TIME, 0, 0,\n, 1,");
        assert!(out.starts_with("2.0\n"), "{out}");
        assert!(out.contains("missing `)`"), "{out}");
        // Joined lines and :quit, as at the terminal; nothing after :quit is read.
        let (_, out) = answers("STEP(0.5, 0, 0,\n1, 100)\n:quit\nSIN(");
        assert_eq!(out, "50.0\n");
    }

    #[test]
    fn multi_line_input_waits_for_closing_brackets() {
        assert!(needs_more("STEP(TIME,0,0,"));
        assert!(needs_more("(1 + 2"));
        assert!(!needs_more("1 + 2"));
        assert!(!needs_more(":help"));
    }
}
