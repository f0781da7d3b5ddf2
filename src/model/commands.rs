//! The command-file (`.acf`) reader: what `mbfx run ANALYSIS.acf` runs. An Adams command
//! file starts with a header, then holds commands, one per line or continued with `&`
//! (`command_lines`), until `STOP`:
//!
//! - line 1 names the dataset (`test_Revolute_Case01.adm`, or `Test02_ADAMS`, to which
//!   `.adm` is added) and line 2 the base name of Adams' output files; or line 1 is blank
//!   (or already a command) and a `FILE/MODEL = NAME` command names the dataset;
//! - `INTEGRATOR/…` and `EQUILIBRIUM/…` are read as the dataset statements are
//!   ([`super::integrator_settings`], [`super::equilibrium_settings`]) and apply to the
//!   SIMULATE commands after them;
//! - `SIMULATE/DYNAMIC` (or TRANSIENT), `END = t` or `DURATION = d`, and `DTOUT = dt` or
//!   `STEPS = n`: a stretch of dynamics from where the last one stopped;
//!   `SIMULATE/KINEMATICS` with the same arguments: a fully driven model solved from its
//!   constraints at each output time; `SIMULATE/STATICS`: one static equilibrium where
//!   the run stands, or with END and STEPS (DTOUT) a quasi-static sequence of them;
//! - `LINEAR/EIGENSOL` and `LINEAR/STATEMAT` ([`super::linear_command`]): the modes or
//!   the state matrices where the run stands;
//! - ACTIVATE, DEACTIVATE, ACCGRAV and new expressions for VARIABLE, MOTION, SFORCE,
//!   VFORCE, VTORQUE and GFORCE change the model for the SIMULATE commands after them
//!   ([`super::command_changes`]);
//! - commands that only set what mbfx does not have (OUTPUT, IC, KINEMATICS, …) are
//!   warnings; commands that change the model otherwise (JOINT, PART, SENSOR, …) or
//!   run an analysis mbfx does not have (SIMULATE/INITIAL_CONDITIONS) are `E0610`
//!   errors at the command, so such a file does not run at all.
//!
//! Every malformed line is a diagnostic at its place; the reader never stops at the first.

use super::command_changes::{read_change, ModelChange};
use super::command_lines::{command_groups, lines, readable};
use super::cursor::Cursor;
use super::equilibrium_settings::{read_equilibrium, EquilibriumStatement};
use super::integrator_settings::{read_integrator, Given, IntegratorStatement};
use super::keywords::Keyword;
use super::linear_command::{read_linear, Linear};
use super::lines::Piece;
use super::statement::{read_id, ItemKind, Statement};
use super::stmt_args::Args;
use crate::diag::{has_errors, Code, Diagnostic, Span};

/// One step of a command file that the run carries out, in order.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// An INTEGRATOR command: it changes what it names for the SIMULATE commands after it.
    Integrator(Box<IntegratorStatement>),
    /// An EQUILIBRIUM command: it changes what it names for the static analyses after it.
    Equilibrium(Box<EquilibriumStatement>),
    /// A SIMULATE command.
    Simulate(Simulate),
    /// A LINEAR command: the modes or the state matrix where the run stands.
    Linear(Box<Linear>),
    /// A command that changes the model for the SIMULATE commands after it (ACTIVATE,
    /// DEACTIVATE, VARIABLE, MOTION, SFORCE, …, ACCGRAV).
    Change(Box<ModelChange>),
}

/// What a SIMULATE command runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Analysis {
    /// DYNAMICS or TRANSIENT: integration.
    #[default]
    Dynamic,
    /// STATICS: a static equilibrium, or with END a sequence of them (quasi-static).
    Statics,
    /// KINEMATICS: a fully driven model solved from its constraints at each output time.
    Kinematics,
    /// LINEAR: the modes or the state matrix where the run stands (no time passes).
    Linear,
}

/// `SIMULATE/kind`: from where the last one stopped to `end`, a row every
/// `output_step`. A SIMULATE/STATICS without END is one equilibrium where the run
/// stands: `end` is that time and `output_step` 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Simulate {
    /// What it runs.
    pub kind: Analysis,
    /// END: the simulation time the stretch stops at.
    pub end: f64,
    /// The time between output rows (from STEPS or DTOUT); 0 for one equilibrium.
    pub output_step: f64,
    /// The command.
    pub span: Span,
}

/// A command file read.
#[derive(Clone, Debug, Default)]
pub struct CommandFile {
    /// The dataset as the file names it (no extension added), where it names it.
    pub model: Option<Given<String>>,
    /// The base name of Adams' output files (line 2), which mbfx does not write.
    pub output: Option<Given<String>>,
    /// The INTEGRATOR and SIMULATE commands, in file order.
    pub steps: Vec<Step>,
    /// Everything the reader reported, in file order.
    pub diagnostics: Vec<Diagnostic>,
}

impl CommandFile {
    /// Whether any diagnostic is an error.
    pub fn has_errors(&self) -> bool {
        has_errors(&self.diagnostics)
    }

    /// The SIMULATE commands.
    pub fn simulations(&self) -> impl Iterator<Item = &Simulate> {
        self.steps.iter().filter_map(|s| match s {
            Step::Simulate(s) => Some(s),
            Step::Integrator(_) | Step::Equilibrium(_) | Step::Linear(_) | Step::Change(_) => None,
        })
    }
}

/// What mbfx does with a command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    File,
    Integrator,
    Equilibrium,
    Simulate,
    Linear,
    Stop,
    /// Sets something the run does not use: a warning saying why.
    Ignored(&'static str),
    /// Changes the model between SIMULATE commands ([`super::command_changes`]).
    Change,
    /// Changes the model or runs another analysis: an error saying why.
    Refused(&'static str),
}

const CHANGES_MODEL: &str = "changes the model in a way mbfx does not support (it honours ACTIVATE, DEACTIVATE, ACCGRAV and new expressions for VARIABLE, MOTION, SFORCE, VFORCE, VTORQUE and GFORCE)";

/// The commands of the Adams Solver command language (three letters abbreviate any).
const COMMANDS: &[(&str, Kind)] = &[
    ("ACCGRAV", Kind::Change),
    ("ACTIVATE", Kind::Change),
    ("ARRAY", Kind::Refused(CHANGES_MODEL)),
    ("BEAM", Kind::Refused(CHANGES_MODEL)),
    ("BUSHING", Kind::Refused(CHANGES_MODEL)),
    (
        "CONTROL",
        Kind::Refused("hands control to a user subroutine, which mbfx does not run"),
    ),
    ("DEACTIVATE", Kind::Change),
    (
        "DEBUG",
        Kind::Ignored("it sets Adams Solver's debugging output"),
    ),
    (
        "ENVIRONMENT",
        Kind::Ignored("it sets Adams Solver environment variables"),
    ),
    ("EQUILIBRIUM", Kind::Equilibrium),
    ("FIELD", Kind::Refused(CHANGES_MODEL)),
    ("FILE", Kind::File),
    ("FLEX_BODY", Kind::Refused(CHANGES_MODEL)),
    ("FRICTION", Kind::Refused(CHANGES_MODEL)),
    ("GCON", Kind::Refused(CHANGES_MODEL)),
    ("GFORCE", Kind::Change),
    ("HELP", Kind::Ignored("it is interactive")),
    (
        "IC",
        Kind::Ignored("mbfx assembles the initial conditions with its own tolerances"),
    ),
    ("INFO", Kind::Ignored("it is interactive")),
    ("INTEGRATOR", Kind::Integrator),
    ("JOINT", Kind::Refused(CHANGES_MODEL)),
    ("JPRIM", Kind::Refused(CHANGES_MODEL)),
    (
        "KINEMATICS",
        Kind::Ignored("it sets Adams' kinematic tolerances; mbfx solves positions to rounding"),
    ),
    ("LINEAR", Kind::Linear),
    (
        "LSOLVER",
        Kind::Ignored("mbfx chooses its own linear solver"),
    ),
    ("MARKER", Kind::Refused(CHANGES_MODEL)),
    ("MENU", Kind::Ignored("it is interactive")),
    ("MOTION", Kind::Change),
    (
        "OUTPUT",
        Kind::Ignored("it sets Adams' result files; mbfx writes the CSV of --csv"),
    ),
    ("PART", Kind::Refused(CHANGES_MODEL)),
    (
        "PREFERENCES",
        Kind::Ignored("it sets Adams Solver preferences"),
    ),
    (
        "RELOAD",
        Kind::Refused("reloads a saved state, which mbfx does not support"),
    ),
    ("REQUEST", Kind::Refused(CHANGES_MODEL)),
    (
        "RESULTS",
        Kind::Ignored("it sets Adams' result files; mbfx writes the CSV of --csv"),
    ),
    (
        "SAVE",
        Kind::Refused("saves the state for a later RELOAD, which mbfx does not support"),
    ),
    ("SENSOR", Kind::Refused(CHANGES_MODEL)),
    ("SFORCE", Kind::Change),
    ("SHOW", Kind::Ignored("it is interactive")),
    ("SIMULATE", Kind::Simulate),
    ("SPLINE", Kind::Refused(CHANGES_MODEL)),
    ("SPRINGDAMPER", Kind::Refused(CHANGES_MODEL)),
    ("STOP", Kind::Stop),
    ("STRING", Kind::Refused(CHANGES_MODEL)),
    ("VARIABLE", Kind::Change),
    ("VFORCE", Kind::Change),
    ("VTORQUE", Kind::Change),
];

/// The command a written keyword names: an exact spelling, or a unique prefix of at
/// least three letters.
fn lookup(written: &str) -> Result<(&'static str, Kind), Vec<&'static str>> {
    if let Some(&(name, kind)) = COMMANDS
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(written))
    {
        return Ok((name, kind));
    }
    let hits: Vec<&(&str, Kind)> = COMMANDS
        .iter()
        .filter(|(n, _)| {
            Keyword {
                name: n,
                min_len: 3,
            }
            .matches(written)
        })
        .collect();
    match hits.as_slice() {
        [&(name, kind)] => Ok((name, kind)),
        many => Err(many.iter().map(|(n, _)| *n).collect()),
    }
}

/// The kinds of SIMULATE, with their shortest abbreviations.
const SIMULATIONS: [(&str, usize); 5] = [
    ("DYNAMICS", 3),
    ("TRANSIENT", 3),
    ("STATICS", 3),
    ("KINEMATICS", 3),
    ("INITIAL_CONDITIONS", 3),
];

/// Reads a command file's text (decoded as a dataset is, see [`super::decode`]).
pub fn read_commands(text: &str) -> CommandFile {
    let mut file = CommandFile::default();
    let all = lines(text, 0, 1);
    // Where the commands start: after the header, or at line 1 when it is blank or
    // already a command (`file/model=…` written first).
    let mut from = (0, 1);
    if let Some((first, _)) = all.first() {
        let r = readable(text, first.clone());
        let head = &text[r.clone()];
        let is_command = head
            .split_once('/')
            .is_some_and(|(k, _)| lookup(k.trim()).is_ok())
            || lookup(head).is_ok_and(|(n, _)| n == "STOP");
        if r.is_empty() {
            from = all.get(1).map_or((text.len(), 2), |(l, n)| (l.start, *n));
        } else if !is_command {
            file.model = Some(Given {
                value: head.to_string(),
                span: r,
            });
            from = match all.get(1) {
                Some((second, _)) => {
                    let r = readable(text, second.clone());
                    if !r.is_empty() {
                        file.output = Some(Given {
                            value: text[r.clone()].to_string(),
                            span: r,
                        });
                    }
                    all.get(2).map_or((text.len(), 3), |(l, n)| (l.start, *n))
                }
                None => (text.len(), 2),
            };
        }
    }
    let mut reader = Reader {
        file,
        time: 0.0,
        stopped: None,
    };
    for group in command_groups(text, from.0, from.1) {
        if let Some(stop) = &reader.stopped {
            let span = group[0].range.clone();
            reader.file.diagnostics.push(
                Diagnostic::warning(
                    Code::UnsupportedStatement,
                    span,
                    "commands after STOP are not read",
                )
                .with_label(stop.clone(), "the command file stops here"),
            );
            break;
        }
        reader.command(text, &group);
    }
    // Changes after the last SIMULATE or LINEAR change nothing that runs: said, not
    // dropped silently.
    for step in reader.file.steps.iter().rev() {
        match step {
            Step::Simulate(_) | Step::Linear(_) => break,
            Step::Change(c) => reader.file.diagnostics.push(Diagnostic::warning(
                Code::UnsupportedStatement,
                c.span.clone(),
                "no SIMULATE or LINEAR command follows this change to the model: it changes nothing",
            )),
            Step::Integrator(_) | Step::Equilibrium(_) => {}
        }
    }
    reader.file.diagnostics.sort_by_key(|d| d.span.start);
    reader.file
}

/// The state of one read.
struct Reader {
    file: CommandFile,
    /// Where the last SIMULATE ended.
    time: f64,
    /// The STOP command, once read.
    stopped: Option<Span>,
}

impl Reader {
    fn command(&mut self, text: &str, group: &[Piece]) {
        let diags = &mut self.file.diagnostics;
        let mut c = Cursor::new(text, group);
        c.skip_blanks();
        let start = c.pos;
        let line = c.line();
        let written = c.read_name();
        if written.is_empty() {
            diags.push(Diagnostic::error(
                Code::Statement,
                c.char_span(),
                format!("expected a command, found {}", c.describe()),
            ));
            return;
        }
        let keyword_span = start..c.pos;
        let (name, kind) = match lookup(written) {
            Ok(hit) => hit,
            Err(names) => {
                let d = Diagnostic::error(
                    Code::Statement,
                    keyword_span,
                    format!("unknown command `{written}`"),
                );
                diags.push(if names.is_empty() {
                    d.with_help("mbfx reads the Adams Solver commands (SIMULATE, INTEGRATOR, FILE, STOP, …)")
                } else {
                    d.with_note(format!("it abbreviates {}", names.join(", ")))
                });
                return;
            }
        };
        let end = group.last().map_or(c.pos, |p| {
            super::cursor::trim_end(text.as_bytes(), p.range.clone())
        });
        let mut stmt = Statement {
            keyword: written.to_ascii_uppercase(),
            keyword_span,
            canonical: Some(name),
            id: None,
            id_span: None,
            args: Vec::new(),
            span: start..end.max(c.pos),
            line,
            view_name: None,
        };
        c.skip_blanks();
        if c.peek() == Some(b'/') {
            c.bump();
            c.skip_blanks();
            if c.peek().is_some_and(|b| b.is_ascii_digit()) {
                read_id(&mut c, &mut stmt, diags);
            }
            stmt.args = super::args::parse_arguments(&mut c, Some(name), diags);
        } else if kind != Kind::Stop {
            diags.push(
                Diagnostic::error(
                    Code::Statement,
                    c.char_span(),
                    format!("expected `/` after `{}`", stmt.keyword),
                )
                .with_label(stmt.keyword_span.clone(), "command"),
            );
            return;
        } else if c.peek().is_some() {
            diags.push(Diagnostic::error(
                Code::Statement,
                c.char_span(),
                format!("unexpected {} after STOP", c.describe()),
            ));
        }
        let mut a = Args::new(&stmt);
        match kind {
            Kind::Stop => self.stopped = Some(stmt.keyword_span.clone()),
            Kind::File => self.file_command(&mut a),
            Kind::Integrator => {
                let s = read_integrator(&mut a);
                self.file.steps.push(Step::Integrator(Box::new(s)));
            }
            Kind::Equilibrium => {
                let s = read_equilibrium(&mut a);
                self.file.steps.push(Step::Equilibrium(Box::new(s)));
            }
            Kind::Simulate => self.simulate(&mut a),
            Kind::Linear => {
                if let Some(l) = read_linear(&mut a) {
                    self.file.steps.push(Step::Linear(Box::new(l)));
                }
            }
            Kind::Change => {
                if let Some(c) = read_change(name, text, group, &mut a) {
                    self.file.steps.push(Step::Change(Box::new(c)));
                }
            }
            Kind::Ignored(why) => {
                for arg in &stmt.args {
                    a.find(&arg.name, arg.name.len());
                }
                a.diags.push(Diagnostic::warning(
                    Code::UnsupportedStatement,
                    stmt.span.clone(),
                    format!("{name} is not honoured: {why}"),
                ));
            }
            Kind::Refused(why) => {
                for arg in &stmt.args {
                    a.find(&arg.name, arg.name.len());
                }
                // A USER(…) expression is the reason no tool but Adams with the
                // compiled subroutine could run it: say that first.
                let user = stmt.args.iter().find(|arg| arg.is_user_call);
                let (span, message) = match user {
                    Some(arg) => (
                        arg.span.clone(),
                        format!("{name}: {} = USER(…) calls a user subroutine, which exists only compiled for Adams; mbfx cannot run it", arg.name),
                    ),
                    None => (stmt.span.clone(), format!("{name} {why}")),
                };
                a.error(Code::UnsupportedCommand, span, message);
            }
        }
        let found = a.finish();
        self.file.diagnostics.extend(found);
    }

    /// `FILE/MODEL = NAME`: the dataset, when the header did not name one. FILE/COMMAND
    /// (another command file) is refused.
    fn file_command(&mut self, a: &mut Args) {
        if let Some(arg) = a.find("COMMAND", 1) {
            let span = arg.span.clone();
            a.error(
                Code::UnsupportedCommand,
                span,
                "FILE/COMMAND reads another command file, which mbfx does not support".into(),
            );
        }
        let Some(arg) = a.find("MODEL", 1) else {
            return;
        };
        let Some(item) = arg.items().first().filter(|i| i.kind == ItemKind::Text) else {
            return;
        };
        let given = Given {
            value: item.text.clone(),
            span: item.span.clone(),
        };
        if let Some(first) = &self.file.model {
            let d = Diagnostic::error(
                Code::UnsupportedCommand,
                given.span,
                "a second model: mbfx runs the one dataset the command file names first",
            )
            .with_label(first.span.clone(), "first named here");
            a.diags.push(d);
        } else if self.file.simulations().next().is_some() {
            a.error(
                Code::UnsupportedCommand,
                given.span,
                "FILE/MODEL after a SIMULATE command changes the model during the run, which mbfx does not support".into(),
            );
        } else {
            self.file.model = Some(given);
        }
    }

    /// `SIMULATE/kind, END | DURATION, DTOUT | STEPS`: DYNAMIC (TRANSIENT) and
    /// KINEMATICS need an end and an output step; STATICS without END is one
    /// equilibrium, with END a quasi-static sequence. INITIAL_CONDITIONS is refused.
    fn simulate(&mut self, a: &mut Args) {
        let kind = a.choice(&SIMULATIONS);
        let at = a.stmt.keyword_span.clone();
        let analysis = match kind.map(|k| SIMULATIONS[k].0) {
            Some("DYNAMICS" | "TRANSIENT") => Some(Analysis::Dynamic),
            Some("STATICS") => Some(Analysis::Statics),
            Some("KINEMATICS") => Some(Analysis::Kinematics),
            Some(_) => {
                let span = a.stmt.span.clone();
                a.error(
                    Code::UnsupportedCommand,
                    span,
                    "SIMULATE/INITIAL_CONDITIONS: an initial-conditions analysis alone is not supported by mbfx (SIMULATE/DYNAMIC solves them first)".into(),
                );
                None
            }
            None => {
                let d = Diagnostic::error(
                    Code::MissingArgument,
                    at,
                    "SIMULATE needs DYNAMIC, TRANSIENT, STATICS, KINEMATICS or INITIAL_CONDITIONS",
                );
                a.diags.push(d);
                None
            }
        };
        let end = number(a, "END", 3);
        let duration = number(a, "DURATION", 3);
        let dtout = number(a, "DTOUT", 3);
        let steps = number(a, "STEPS", 3);
        let Some(analysis) = analysis else { return };
        if has_errors(&a.diags) {
            return;
        }
        let t0 = self.time;
        if analysis == Analysis::Statics && end.is_none() && duration.is_none() {
            // One equilibrium where the run stands; an output step has nothing to divide.
            if let Some((_, span)) = dtout.or(steps) {
                return a.error(
                    Code::BadArgument,
                    span,
                    "DTOUT and STEPS need END or DURATION (a quasi-static sequence); without them SIMULATE/STATICS is one equilibrium".into(),
                );
            }
            self.file.steps.push(Step::Simulate(Simulate {
                kind: analysis,
                end: t0,
                output_step: 0.0,
                span: a.stmt.span.clone(),
            }));
            return;
        }
        let end = match (end, duration) {
            (Some((_, s1)), Some((_, s2))) => return exclusive(a, s1, s2, "END", "DURATION"),
            (Some((t, span)), None) if t <= t0 || !t.is_finite() => {
                let msg = format!("END = {t} must lie after the time the run has reached, {t0}");
                return a.error(Code::BadArgument, span, msg);
            }
            (Some((t, _)), None) => t,
            (None, Some((d, span))) if d <= 0.0 || !d.is_finite() => {
                return a.error(
                    Code::BadArgument,
                    span,
                    format!("DURATION = {d} must be positive"),
                );
            }
            (None, Some((d, _))) => t0 + d,
            (None, None) => return a.missing("END = time or DURATION = time"),
        };
        let output_step = match (dtout, steps) {
            (Some((_, s1)), Some((_, s2))) => return exclusive(a, s1, s2, "DTOUT", "STEPS"),
            (Some((dt, span)), None) if dt <= 0.0 || !dt.is_finite() => {
                return a.error(
                    Code::BadArgument,
                    span,
                    format!("DTOUT = {dt} must be positive"),
                );
            }
            (Some((dt, _)), None) => dt,
            (None, Some((n, span))) if n < 1.0 || n.fract() != 0.0 || n > 1e9 => {
                let msg = format!("STEPS = {n} must be a whole number of output steps, at least 1");
                return a.error(Code::BadArgument, span, msg);
            }
            (None, Some((n, _))) => (end - t0) / n,
            (None, None) => return a.missing("DTOUT = step or STEPS = count"),
        };
        self.time = end;
        self.file.steps.push(Step::Simulate(Simulate {
            kind: analysis,
            end,
            output_step,
            span: a.stmt.span.clone(),
        }));
    }
}

/// A one-number argument with the span of its value.
fn number(a: &mut Args, full: &str, min: usize) -> Option<(f64, Span)> {
    let arg = a.find(full, min)?;
    let span = arg
        .items()
        .first()
        .map_or(arg.span.clone(), |i| i.span.clone());
    let values = a.numbers_of(arg)?;
    if values.len() != 1 {
        let msg = format!("{full} takes one number");
        a.error(Code::BadArgument, arg.span.clone(), msg);
        return None;
    }
    Some((values[0], span))
}

fn exclusive(a: &mut Args, first: Span, second: Span, x: &str, y: &str) {
    let d = Diagnostic::error(
        Code::BadArgument,
        second,
        format!("{x} and {y} exclude each other"),
    )
    .with_label(first, format!("{x} given here"));
    a.diags.push(d);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn errors(f: &CommandFile) -> Vec<(&str, Code)> {
        f.diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| (d.message.as_str(), d.code))
            .collect()
    }

    #[test]
    fn chrono_header_integrator_and_transient() {
        // projectchrono/chrono data/adams/test_Revolute_Case01.acf, as written (CRLF, tab,
        // no line end after stop).
        let text = "test_Revolute_Case01.adm\r\ntest_Revolute_Case01_ADAMS\r\noutput/noseparator\r\nintegrator/gstiff, &\r\n\terror = 1.0e-4, hmax=1e-5\r\nsimulate/transient, &\r\n\tend=5.0, dtout=1.0E-002\r\nstop";
        let f = read_commands(text);
        assert!(errors(&f).is_empty(), "{:?}", f.diagnostics);
        assert_eq!(
            f.model.as_ref().map(|m| m.value.as_str()),
            Some("test_Revolute_Case01.adm")
        );
        assert_eq!(
            f.output.as_ref().map(|m| m.value.as_str()),
            Some("test_Revolute_Case01_ADAMS")
        );
        let [Step::Integrator(i), Step::Simulate(s)] = f.steps.as_slice() else {
            panic!("{:?}", f.steps);
        };
        assert_eq!(i.error.as_ref().map(|e| e.value), Some(1e-4));
        assert_eq!(i.hmax.as_ref().map(|e| e.value), Some(1e-5));
        assert_eq!((s.end, s.output_step), (5.0, 0.01));
        // OUTPUT is warned about; GSTIFF runs.
        let warned: Vec<&str> = f
            .diagnostics
            .iter()
            .map(|d| &text[d.span.clone()])
            .collect();
        assert!(warned.contains(&"output/noseparator"), "{warned:?}");
        assert!(!warned.contains(&"gstiff"), "{warned:?}");
    }

    #[test]
    fn file_model_and_continuing_simulations() {
        // bthornton191 files: a blank line 1, FILE/MODEL, then commands; abbreviations
        // as in adamspy's FRS5 analyses.
        let text = "\nfile/model=generic_model\n! Insert ACF commands here:\nint/hht, err=1E-7, hmax=2.5E-4\nsim/dyn, end=1.5, dtout=.005\nsim/dyn, duration=0.5, steps=10\nSIMULATE/DYNAMICS, END = 3, DTOUT = 0.1\nstop\n";
        let f = read_commands(text);
        assert!(errors(&f).is_empty(), "{:?}", f.diagnostics);
        assert_eq!(
            f.model.as_ref().map(|m| m.value.as_str()),
            Some("generic_model")
        );
        assert!(f.output.is_none());
        let sims: Vec<(f64, f64)> = f.simulations().map(|s| (s.end, s.output_step)).collect();
        assert_eq!(sims, [(1.5, 0.005), (2.0, 0.05), (3.0, 0.1)]);
    }

    #[test]
    fn fast_header_without_extension() {
        let f = read_commands("Test02_ADAMS\r\nTest02_ADAMS\r\nSIMULATE/DYNAMICS, END = 4.0E-03, DTOUT = 4.0E-02\r\nSTOP\r\n");
        assert_eq!(
            f.model.as_ref().map(|m| m.value.as_str()),
            Some("Test02_ADAMS")
        );
        assert_eq!(f.simulations().count(), 1);
    }

    #[test]
    fn unsupported_commands_are_errors_at_the_command() {
        for (text, what, bad) in [
            (
                "m.adm\nout\nSIMULATE/INITIAL_CONDITIONS\nSTOP\n",
                "initial-conditions",
                "SIMULATE/INITIAL_CONDITIONS",
            ),
            (
                "m.adm\nout\nDEACTIVATE/SENSOR, ID=12\n",
                "mbfx has no SENSOR elements",
                "DEACTIVATE/SENSOR, ID=12",
            ),
            (
                "m.adm\nout\nJOINT/3, I = 1, J = 2\n",
                "JOINT changes the model",
                "JOINT/3, I = 1, J = 2",
            ),
            (
                "m.adm\nout\nMOTION/3, JOINT = 2, FUNCTION = TIME\n",
                "redefines only FUNCTION",
                "JOINT = 2",
            ),
            (
                "m.adm\nout\nVARIABLE/3, FUNCTION = USER(1)\n",
                "user subroutine",
                "USER(1)",
            ),
            (
                "m.adm\nout\nLINEAR/STATEMAT, FILE = lin, FORMAT = MATRIXX\n",
                "MATLAB format",
                "MATRIXX",
            ),
            (
                "\nfile/command=other.acf\n",
                "another command file",
                "command=other.acf",
            ),
        ] {
            let f = read_commands(text);
            let e = f
                .diagnostics
                .iter()
                .find(|d| d.is_error())
                .unwrap_or_else(|| panic!("{text}: no error"));
            assert_eq!(e.code, Code::UnsupportedCommand, "{text}");
            assert!(e.message.contains(what), "{text}: {}", e.message);
            assert_eq!(&text[e.span.clone()], bad, "{text}");
        }
    }

    #[test]
    fn linear_commands_read_their_arguments() {
        // old-NWTC__FAST Test14_ADAMS_LIN.acf's command, then a state matrix.
        let f = read_commands(
            "m.adm\nout\nSIMULATE/STATICS\nLINEAR/EIGENSOL, COORDS = 1, 25\nLIN/STATEMAT, FILE = out/plant, FORMAT = MATLAB, NODAMPIN, NOVECTOR\nSTOP\n",
        );
        assert!(errors(&f).is_empty(), "{:?}", f.diagnostics);
        let [Step::Simulate(_), Step::Linear(eig), Step::Linear(mat)] = f.steps.as_slice() else {
            panic!("{:?}", f.steps)
        };
        assert!(!eig.statemat && eig.vectors && eig.damping && eig.file.is_none());
        assert_eq!(eig.coords, Some((1, 25)));
        assert!(mat.statemat && !mat.vectors && !mat.damping && mat.coords.is_none());
        assert_eq!(
            mat.file.as_ref().map(|f| f.value.as_str()),
            Some("out/plant")
        );
    }

    #[test]
    fn malformed_lines_are_errors_at_their_place() {
        for (text, bad, code) in [
            ("m.adm\nout\nSIMULATE/DYNAMIC, END = 0, DTOUT = 0.1\n", "0", Code::BadArgument),
            ("m.adm\nout\nSIMULATE/DYNAMIC, END = 1, DTOUT = -1\n", "-1", Code::BadArgument),
            ("m.adm\nout\nSIMULATE/DYNAMIC, END = 1, STEPS = 2.5\n", "2.5", Code::BadArgument),
            ("m.adm\nout\nSIMULATE/DYNAMIC, END = 1\n", "SIMULATE", Code::MissingArgument),
            ("m.adm\nout\nSIMULATE/DYNAMIC, END = 1, DURATION = 1, DTOUT = 1\n", "1", Code::BadArgument),
            ("m.adm\nout\nSIMULATE/DYNAMIC, END = 2, DTOUT = 1\nSIMULATE/DYNAMIC, END = 1, DTOUT = 1\n", "1", Code::BadArgument),
            ("m.adm\nout\nFROBNICATE/1\n", "FROBNICATE", Code::Statement),
            ("m.adm\nout\nSIMULATE DYNAMIC\n", "D", Code::Statement),
            ("m.adm\nout\nINTEGRATOR/HHT, ALPHA = 0.5\n", "0.5", Code::BadArgument),
            ("m.adm\nout\nSIMULATE/DYNAMIC, END = 1, DTOUT = x\n", "x", Code::BadArgument),
            ("m.adm\nout\nLINEAR/STATEMAT\n", "LINEAR", Code::MissingArgument),
            ("m.adm\nout\nLINEAR/COORDS = 1\n", "LINEAR", Code::MissingArgument),
            ("m.adm\nout\nLINEAR/EIGENSOL, COORDS = 3, 1\n", "COORDS = 3, 1", Code::BadArgument),
            ("m.adm\nout\nLINEAR/EIGENSOL, COORDS = 0\n", "COORDS = 0", Code::BadArgument),
            ("m.adm\nout\nLINEAR/EIGENSOL, PINPUT = 1\n", "1", Code::BadArgument),
            ("m.adm\nout\nLINEAR/STATEMAT, FILE = a, POUTPUT = x\n", "x", Code::BadArgument),
        ] {
            let f = read_commands(text);
            let e = f
                .diagnostics
                .iter()
                .find(|d| d.is_error())
                .unwrap_or_else(|| panic!("{text}: no error in {:?}", f.diagnostics));
            assert_eq!(e.code, code, "{text}: {}", e.message);
            assert_eq!(&text[e.span.clone()], bad, "{text}: {}", e.message);
        }
    }

    #[test]
    fn statics_and_kinematics_are_read_with_equilibrium_settings() {
        // adams_rescale: SIMULATE/STATIC alone, then the dynamics from there.
        let f = read_commands("\nfile/model=m\nequil/maxit=500, stab=0.1, error=0.1, imbal=0.1, tlim=1.0, alim=2.0D\nSIMULATE/STATIC\nSIMULATE/DYNAMIC, END=5.0, DTOUT=1.0E-02\nsim/stat, end=6, steps=4\nsim/kin, dur=1, dtout=0.5\nstop\n");
        assert!(errors(&f).is_empty(), "{:?}", f.diagnostics);
        let sims: Vec<(Analysis, f64, f64)> = f
            .simulations()
            .map(|s| (s.kind, s.end, s.output_step))
            .collect();
        assert_eq!(
            sims,
            [
                (Analysis::Statics, 0.0, 0.0),
                (Analysis::Dynamic, 5.0, 0.01),
                (Analysis::Statics, 6.0, 0.25),
                (Analysis::Kinematics, 7.0, 0.5)
            ]
        );
        let Step::Equilibrium(e) = &f.steps[0] else {
            panic!("{:?}", f.steps[0]);
        };
        let s = e.settings();
        assert_eq!((s.maxit, s.tlimit), (500, 1.0));
        assert!((s.alimit - 2f64.to_radians()).abs() < 1e-15);
        // An output step without an end is an error at it.
        let text = "m.adm\nout\nSIMULATE/STATICS, STEPS = 4\n";
        let f = read_commands(text);
        let e = f
            .diagnostics
            .iter()
            .find(|d| d.is_error())
            .expect("an error");
        assert_eq!(&text[e.span.clone()], "4");
    }

    #[test]
    fn changes_to_the_model_are_read_in_order_between_simulations() {
        use crate::model::command_changes::{Change, Element, Ids};
        // adamspy's test.acf writes its VARIABLEs over `&` lines with leading commas.
        let text = "\nfile/model=m\nVARIABLE/1102 &\n, FUNCTION=VARVAL(11021) * & ! why\n, (STEP(TIME,0.0,0.0,15.0,500.0))\nsim/dyn, end=1, dtout=0.1\nDEACTIVATE/JOINT, RANGE = 1301, 1321\nact/motion, id=4\naccg/kgrav=0\nGFORCE/3, FX = 1\\ TZ = TIME\nsim/dyn, end=2, dtout=0.1\n";
        let f = read_commands(text);
        assert!(errors(&f).is_empty(), "{:?}", f.diagnostics);
        let changes: Vec<&Change> = f
            .steps
            .iter()
            .filter_map(|s| match s {
                Step::Change(c) => Some(&c.change),
                _ => None,
            })
            .collect();
        let [Change::Redefine {
            kind: Element::Variable,
            id: 1102,
            functions,
            ..
        }, Change::Switch {
            active: false,
            kind: Element::Joint,
            ids: Ids::Range(1301, 1321),
            ..
        }, Change::Switch {
            active: true,
            kind: Element::Motion,
            ids: Ids::One(4),
            ..
        }, Change::Gravity([None, None, Some(0.0)]), Change::Redefine {
            kind: Element::Gforce,
            functions: gforce,
            ..
        }] = changes.as_slice()
        else {
            panic!("{changes:?}");
        };
        // The expression's text keeps its place: the line joins are blanks.
        let e = &functions[0];
        assert_eq!(e.text.len(), text[e.start..].find(")\n").unwrap() + 1);
        assert_eq!(
            e.text.split_whitespace().collect::<String>(),
            "VARVAL(11021)*(STEP(TIME,0.0,0.0,15.0,500.0))"
        );
        let args: Vec<&str> = gforce.iter().map(|g| g.argument).collect();
        assert_eq!(args, ["FX", "TZ"]);
        assert_eq!(f.simulations().count(), 2);
        // A MOTION may change what its FUNCTION drives (old-NWTC__FAST's Test14_ADAMS_LIN).
        let f = read_commands("m\nout\nMOTION/3150, VELOCITY, ICDISP = 0\nMOTION/3150, DISPLACEMENT, FUNCTION = 3.141593E+00\nSIMULATE/STATICS\n");
        assert!(errors(&f).is_empty(), "{:?}", f.diagnostics);
        let drives: Vec<_> = (f.steps.iter())
            .filter_map(|s| match s {
                Step::Change(c) => match &c.change {
                    Change::Redefine {
                        drive, functions, ..
                    } => Some((*drive, functions.len())),
                    _ => None,
                },
                _ => None,
            })
            .collect();
        use crate::model::command_changes::MotionDrive;
        use crate::model::elements::MotionLevel;
        assert_eq!(
            drives,
            [
                (
                    Some(MotionDrive {
                        level: Some(MotionLevel::Velocity),
                        icdisp: Some(0.0),
                        icvel: None
                    }),
                    0
                ),
                (
                    Some(MotionDrive {
                        level: Some(MotionLevel::Displacement),
                        ..MotionDrive::default()
                    }),
                    1
                )
            ]
        );
        // A change no SIMULATE follows is a warning at it.
        let text = "m.adm\nout\nsim/dyn, end=1, dtout=0.1\nACCGRAV/JGRAV = -1\nSTOP\n";
        let f = read_commands(text);
        let [w] = f.diagnostics.as_slice() else {
            panic!("{:?}", f.diagnostics);
        };
        assert!(
            !w.is_error() && w.message.contains("changes nothing"),
            "{w:?}"
        );
        assert_eq!(&text[w.span.clone()], "ACCGRAV/JGRAV = -1");
    }

    #[test]
    fn commands_after_stop_are_not_read() {
        let f = read_commands("m.adm\nout\nSTOP\nSIMULATE/DYNAMIC, END = 1, DTOUT = 0.1\n");
        assert_eq!(f.simulations().count(), 0);
        assert!(f
            .diagnostics
            .iter()
            .any(|d| d.message.contains("after STOP")));
    }
}
