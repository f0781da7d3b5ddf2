//! `mbfx run MODEL.adm --end T …` and `mbfx run ANALYSIS.acf` ([`super::acf`]): simulates
//! a dataset ([`crate::session::run`]) and writes the output rows as CSV (header `time`, the probes in the order given, then the
//! REQUEST components; numbers as `{:?}` prints an f64), a progress bar on stderr when
//! it is a terminal, a summary at the end, and `--plot` draws the columns against time.
//! `--verbose` adds an Adams-like step table on stderr at each output time. A failure is
//! a diagnostic at the statement of the element it names, with the time and the cause;
//! the rows before it are written; the exit code is 1.

use super::output::{Named, Output, Stop};
use super::Dim;
use crate::diag::{Code, Diagnostic, SourceFile};
use crate::mbd::dynamics::{Culprit, DynError};
use crate::mbd::error::MbdError;
use crate::mbd::expr::ExprError;
use crate::model::integrator_settings::Formulation;
use crate::session::files::read_dataset;
use crate::session::run::{Method, RunFailure, RunSpec, Segment, Simulation, Summary, TableRow};
use crate::session::{report, DimRequest};
use std::io::Write;
use std::path::PathBuf;

/// `--integrator` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum IntegratorArg {
    /// Adams GSTIFF: BDF of order 1-6 with a fixed leading coefficient (--formulation),
    /// the default as in Adams.
    Gstiff,
    /// Adams WSTIFF: BDF of order 1-6 with variable coefficients (--formulation).
    Wstiff,
    /// Adams HHT on the index-3 DAE (ALPHA −0.3 unless --alpha), error-controlled.
    Hht,
    /// Generalized-α on the index-3 DAE (ρ∞ 0.9 unless --rho-inf, as Exudyn).
    Galpha,
    /// Plain Newmark (the dataset's BETA and GAMMA, else 0.36 and 0.7), error-controlled.
    Newmark,
    /// Explicit Dormand–Prince 8(5,3) on the index-1 equations, projected onto the
    /// constraints after each step: high accuracy at tight ERROR on non-stiff models.
    Dopri853,
}

/// `--error-per` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ErrorPer {
    /// ERROR bounds each step's local error, as in Adams.
    Step,
    /// ERROR bounds the error of the whole run (tolerance proportionality).
    Run,
}

/// `--formulation` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FormulationArg {
    /// Index 3: position constraints, positions under error control (Adams' default).
    I3,
    /// Stabilized index 2: velocity constraints too, velocities under error control.
    Si2,
}

#[derive(clap::Args)]
pub struct RunArgs {
    /// The dataset (.adm), or an Adams command file (.acf) naming one.
    model: PathBuf,
    /// End time [required for a dataset; for a command file, it replaces its SIMULATE
    /// commands].
    #[arg(long)]
    end: Option<f64>,
    /// Output step DT: one row at every k·DT and at the end time [default: the command
    /// file's DTOUT, else END/100].
    #[arg(long = "output-step", value_name = "DT")]
    output_step: Option<f64>,
    /// The integrator [default: the dataset's INTEGRATOR, else gstiff, as Adams].
    #[arg(long, value_enum)]
    integrator: Option<IntegratorArg>,
    /// Local error tolerance per step (ERROR) [default: the dataset's, else 1e-3].
    #[arg(long)]
    error: Option<f64>,
    /// Largest step (HMAX) [default: the output step].
    #[arg(long)]
    hmax: Option<f64>,
    /// First step (HINIT) [default: HMAX/20].
    #[arg(long)]
    hinit: Option<f64>,
    /// Smallest step before the run fails (HMIN) [default: 1e-6·HMAX].
    #[arg(long)]
    hmin: Option<f64>,
    /// What ERROR bounds: each step's local error (as Adams), or the whole run's error
    /// (each step held to ERROR·h/T, so the answer's error falls with ERROR).
    #[arg(long = "error-per", value_enum, default_value = "step")]
    error_per: ErrorPer,
    /// dopri853: keep to the Cartesian index-1 form (three coordinates a part and the
    /// constraints) even on a planar tree of joints, which it otherwise integrates in its
    /// joint coordinates.
    #[arg(long)]
    cartesian: bool,
    /// Fixed steps of at most H (no error control; each output interval is split evenly).
    #[arg(long = "fixed-step", value_name = "H")]
    fixed_step: Option<f64>,
    /// HHT ALPHA in [−1/3, 0].
    #[arg(long, allow_hyphen_values = true)]
    alpha: Option<f64>,
    /// The BDF formulation [default: the dataset's INTEGRATOR, else i3].
    #[arg(long, value_enum)]
    formulation: Option<FormulationArg>,
    /// The highest BDF order, 1 to 6 (KMAX) [default: the dataset's, else 6].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=6))]
    kmax: Option<u32>,
    /// Generalized-α spectral radius ρ∞ in [0, 1].
    #[arg(long = "rho-inf")]
    rho_inf: Option<f64>,
    /// Build in 2D (an error when the scene is not planar) or 3D [default: 2D when planar].
    #[arg(long, value_enum, value_name = "2|3")]
    dim: Option<Dim>,
    /// Which back end evaluates the model's expressions.
    #[arg(long, value_enum, default_value = "jit")]
    engine: super::Engine,
    /// An output column NAME=EXPR (any expression of the model's scope); repeatable.
    #[arg(long = "probe", value_name = "NAME=EXPR")]
    probes: Vec<String>,
    /// Where the CSV goes: a file, or - for standard output [default: -].
    #[arg(long, value_name = "FILE|-")]
    csv: Option<String>,
    /// Draw the probes (or the request columns) against time: FILE.svg or FILE.png.
    #[arg(long, value_name = "FILE")]
    plot: Option<PathBuf>,
    /// Print a step table on stderr at each output time (time, step size, cumulative
    /// steps, Newton iterations, integration order, CPU time), as Adams does.
    #[arg(long, short)]
    verbose: bool,
}

fn command_line_error(msg: String, o: &mut Output) -> Result<i32, Stop> {
    let d = Diagnostic::error(Code::CommandLine, 0..0, msg);
    o.diagnostics(&[d], &SourceFile::new("command line", ""))?;
    Err(Stop::Failed)
}

/// The diagnostic code of a dynamics failure.
fn code_of(e: &DynError) -> Code {
    match e {
        DynError::DroppedViolated { .. } => Code::Conflicting,
        DynError::NotFinite { .. } => Code::NonFiniteForce,
        DynError::Model(MbdError::Expression(_, ExprError::NotFinite { .. })) => {
            Code::NonFiniteForce
        }
        DynError::Newton { .. } | DynError::StepTooSmall { .. } | DynError::Singular { .. } => {
            Code::Integration
        }
        DynError::Model(_)
        | DynError::Massless { .. }
        | DynError::Structure
        | DynError::Output(_) => Code::CannotSimulate,
    }
}

pub fn run(a: &RunArgs, o: &mut Output) -> Result<i32, Stop> {
    if let Some(end) = a.end {
        if !(end.is_finite() && end > 0.0) {
            return command_line_error(format!("--end {end} must be a positive time"), o);
        }
    }
    for (name, x) in [
        ("--output-step", a.output_step),
        ("--error", a.error),
        ("--hmax", a.hmax),
        ("--hinit", a.hinit),
        ("--hmin", a.hmin),
        ("--fixed-step", a.fixed_step),
    ] {
        if let Some(x) = x {
            if !(x.is_finite() && x > 0.0) {
                return command_line_error(format!("{name} {x} must be a positive number"), o);
            }
        }
    }
    if let Some(alpha) = a.alpha {
        if !(-1.0 / 3.0..=0.0).contains(&alpha) {
            return command_line_error(format!("--alpha {alpha} must lie in [-1/3, 0]"), o);
        }
    }
    if let Some(rho) = a.rho_inf {
        if !(0.0..=1.0).contains(&rho) {
            return command_line_error(format!("--rho-inf {rho} must lie in [0, 1]"), o);
        }
    }
    // A command file names the dataset and says how long to run; a dataset needs --end.
    let commands = if super::acf::is_command_file(&a.model) {
        Some(super::acf::read(&a.model, o)?)
    } else if a.end.is_none() {
        return command_line_error(
            format!(
                "--end is required to run a dataset ({}); a command file (.acf) may give it instead",
                a.model.display()
            ),
            o,
        );
    } else {
        None
    };
    if let Some(c) = commands.as_ref().filter(|_| a.end.is_none()) {
        if c.file.simulations().next().is_none() {
            let msg =
                "the command file has no SIMULATE/DYNAMIC command: give --end (and --output-step)";
            let d = Diagnostic::error(Code::MissingArgument, 0..0, msg);
            o.diagnostics(&[d], &c.source)?;
            return Err(Stop::Failed);
        }
    }
    let model_path = commands
        .as_ref()
        .map_or(a.model.clone(), |c| c.model.clone());
    let mut probes = Vec::new();
    for p in &a.probes {
        match p.split_once('=') {
            Some((n, e)) if !n.trim().is_empty() => {
                probes.push((n.trim().to_string(), e.to_string()))
            }
            _ => {
                return command_line_error(
                    format!("--probe {p}: expected NAME=EXPR, e.g. --probe x=DX(2,1)"),
                    o,
                )
            }
        }
    }
    let name = model_path.display().to_string();
    let (text, warnings) = match read_dataset(&model_path) {
        Ok(t) => t,
        Err(u) => {
            o.diagnostics(&[u.diagnostic], &u.source)?;
            return Err(Stop::Failed);
        }
    };
    // Replaced by the segments' own end and output step below.
    let mut spec = RunSpec::new(a.end.unwrap_or(1.0), a.output_step.unwrap_or(1.0));
    spec.method = a.integrator.map(|m| match m {
        IntegratorArg::Hht => Method::Hht,
        IntegratorArg::Galpha => Method::Galpha,
        IntegratorArg::Newmark => Method::Newmark,
        IntegratorArg::Dopri853 => Method::Dopri853,
        IntegratorArg::Gstiff => Method::Gstiff,
        IntegratorArg::Wstiff => Method::Wstiff,
    });
    spec.kmax = a.kmax;
    spec.error_per_run = a.error_per == ErrorPer::Run;
    spec.cartesian = a.cartesian;
    spec.formulation = a.formulation.map(|f| match f {
        FormulationArg::I3 => Formulation::I3,
        FormulationArg::Si2 => Formulation::Si2,
    });
    (spec.error, spec.hmax, spec.hinit, spec.hmin) = (a.error, a.hmax, a.hinit, a.hmin);
    (spec.fixed_step, spec.alpha, spec.rho_inf) = (a.fixed_step, a.alpha, a.rho_inf);
    spec.dim = Dim::request(a.dim);
    spec.engine = a.engine.into();
    let source = SourceFile::new(name.clone(), text.clone());
    o.diagnostics(&warnings, &source)?;
    let mut sim = match Simulation::new(&text, spec, &probes) {
        Ok(s) => s,
        Err(RunFailure::Diagnostics {
            probe: None,
            diagnostics,
        }) => {
            o.diagnostics(&diagnostics, &source)?;
            return Err(Stop::Failed);
        }
        Err(RunFailure::Diagnostics {
            probe: Some(p),
            diagnostics,
        }) => {
            let text = probes.iter().find(|(n, _)| *n == p).map_or("", |(_, e)| e);
            o.diagnostics(&diagnostics, &SourceFile::new(format!("--probe {p}"), text))?;
            return Err(Stop::Failed);
        }
        Err(RunFailure::Analysis(f)) => {
            let model = crate::model::read_model(&text).model;
            let mut diags = report::diagnostics(&f, &model);
            for d in &mut diags {
                d.severity = crate::diag::Severity::Error;
            }
            o.diagnostics(&diags, &source)?;
            return Err(Stop::Failed);
        }
        Err(RunFailure::Dynamics(e)) => {
            // Simulation::new kept its model to itself: read it again for the span.
            let model = crate::model::read_model(&text).model;
            report_failure(&e, &source, &model, o)?;
            return Err(Stop::Failed);
        }
    };
    if a.dim.is_none() && sim.spec.dim == DimRequest::Auto {
        writeln!(o.err(), "{}", sim.dynamics.sys.dim_reason)?;
    }
    let dataset_integrator = sim.read.model.integrator.clone();
    if let Some(i) = &dataset_integrator {
        o.diagnostics(&i.warnings, &source)?;
    }
    let segments = match &commands {
        None => {
            let end = a.end.unwrap_or_default();
            vec![Segment {
                end,
                output_step: a.output_step.unwrap_or(end / 100.0),
                integrator: dataset_integrator,
            }]
        }
        Some(c) => {
            match super::acf::segments(&c.file, dataset_integrator.as_ref(), a.end, a.output_step) {
                Ok(s) => s,
                Err(msg) => {
                    let d = Diagnostic::error(Code::MissingArgument, 0..0, msg);
                    o.diagnostics(&[d], &c.source)?;
                    return Err(Stop::Failed);
                }
            }
        }
    };
    let end = segments.last().map_or(0.0, |s| s.end);
    let header = sim.header();
    let mut file = match a.csv.as_deref() {
        None | Some("-") => None,
        Some(path) => match std::fs::File::create(path) {
            Ok(f) => Some(Named::new(std::io::BufWriter::new(f), path)),
            Err(e) => return command_line_error(format!("cannot write {path}: {e}"), o),
        },
    };
    let (mut rows, keep_rows) = (Vec::new(), a.plot.is_some());
    let progress = super::progress::Progress::new(end);
    // The first write error: a closed pipe ends the run quietly, others fail it.
    let mut io_error: Option<std::io::Error> = None;
    let (summary, failed) = {
        let (stdout, stderr) = o.both();
        let writer: &mut dyn Write = match &mut file {
            Some(f) => f,
            None => stdout,
        };
        // The step table's write errors end the run the way the CSV's do.
        let mut table_error: Option<std::io::Error> = None;
        if a.verbose {
            if let Err(e) = stderr.write_all(TABLE_HEADER.as_bytes()) {
                table_error = Some(e);
            }
        }
        let mut table_row = |r: &TableRow| {
            if table_error.is_none() {
                if let Err(e) = stderr.write_all(table_line(r).as_bytes()) {
                    table_error = Some(e);
                }
            }
        };
        let table: Option<&mut dyn FnMut(&TableRow)> = if a.verbose {
            Some(&mut table_row)
        } else {
            None
        };
        let mut csv = csv::Writer::from_writer(writer);
        let result = match csv.write_record(&header) {
            Err(e) => {
                io_error = Some(e.into());
                (None, None)
            }
            Ok(()) => {
                let (s, f) = sim.run_segments(
                    &segments,
                    &mut |row| {
                        progress.at(row[0]);
                        if keep_rows {
                            rows.push(row.to_vec());
                        }
                        let w = csv.write_record(row.iter().map(|x| format!("{x:?}")));
                        w.map_err(|e| {
                            let e = std::io::Error::from(e);
                            let copy = std::io::Error::new(e.kind(), e.to_string());
                            io_error.get_or_insert(e);
                            copy
                        })
                    },
                    table,
                );
                (Some(s), f)
            }
        };
        if let Err(e) = csv.flush() {
            io_error.get_or_insert(e);
        }
        if let Some(e) = table_error {
            io_error.get_or_insert(e);
        }
        result
    };
    progress.finish();
    if let Some(f) = &mut file {
        if let Err(e) = f.flush() {
            io_error.get_or_insert(e);
        }
    }
    if let Some(e) = io_error {
        return Err(Stop::Io(e));
    }
    if let Some(mut s) = summary {
        if let Some(out) = commands.as_ref().and_then(|c| c.file.output.as_ref()) {
            s.notes.push(format!(
                "the command file's output files ({}.req, .res, …) are not written; the CSV goes to --csv (standard output by default)",
                out.value
            ));
        }
        write!(o.err(), "{}", summary_text(&s))?;
    }
    if let (Some(path), false) = (&a.plot, rows.is_empty()) {
        if let Err(e) = super::plot::draw(path, &header, &rows, probes.len()) {
            return command_line_error(
                format!("the plot {} could not be drawn: {e}", path.display()),
                o,
            );
        }
    }
    if let Some(e) = failed {
        report_failure(&e, &source, &sim.read.model, o)?;
        return Err(Stop::Failed);
    }
    Ok(0)
}

/// A dynamics failure as a diagnostic at the statement of the element (or part) it names.
fn report_failure(
    e: &DynError,
    source: &SourceFile,
    model: &crate::model::Model,
    o: &mut Output,
) -> std::io::Result<()> {
    let span = match e.culprit() {
        Some(Culprit::Element(el)) => report::element_span(model, &el),
        Some(Culprit::Part(id)) => model.part(id).map_or(0..0, |p| p.el.span.clone()),
        None => 0..0,
    };
    let d = Diagnostic::error(code_of(e), span, e.to_string());
    o.diagnostics(&[d], source)
}

/// The step table's header (`mbfx run --verbose`), Adams' columns without the function
/// evaluations.
const TABLE_HEADER: &str = "   Simulation       Step    Cumulative     Newton  Integration        CPU\n         Time       Size         Steps Iterations        Order   time (s)\n";

/// One line of the step table.
fn table_line(r: &TableRow) -> String {
    let order = r.order.map_or("-".to_string(), |k| k.to_string());
    format!(
        "{:>13} {:>10} {:>13} {:>10} {:>12} {:>10.3}\n",
        fortran_e(r.time, 6),
        fortran_e(r.step, 3),
        r.steps,
        r.newton_iterations,
        order,
        r.cpu_seconds
    )
}

/// `x` as Adams prints reals: `1.000000E-02` (a sign and two exponent digits at least).
fn fortran_e(x: f64, digits: usize) -> String {
    let s = format!("{x:.digits$E}");
    match s.split_once('E') {
        Some((m, e)) => {
            let (sign, e) = e.strip_prefix('-').map_or(("+", e), |e| ("-", e));
            format!("{m}E{sign}{e:0>2}")
        }
        None => s,
    }
}

/// The end-of-run summary.
pub fn summary_text(s: &Summary) -> String {
    let st = &s.stats;
    let mut out = format!(
        "{}: {} steps ({} rejected), {} Newton iterations, {} Jacobian evaluations, {} factorizations, {} expression evaluations, {:.6} s CPU{}\nlargest constraint residual {:.3e}\n",
        s.integrator,
        st.steps,
        st.rejected,
        st.newton_iterations,
        st.jacobian_evaluations,
        st.factorizations,
        st.expression_evaluations,
        s.cpu_seconds,
        // Runs with contact switches say how many were located; others print as before.
        match st.events {
            0 => String::new(),
            n => format!(", {n} force switches located"),
        },
        s.max_residual
    );
    if let Some((e0, e1)) = s.energy {
        out += &format!(
            "energy (kinetic + gravity): {e0:.9e} at the start, {e1:.9e} at the end (change {:.3e})\n",
            e1 - e0
        );
    }
    for n in &s.notes {
        out += &format!("note: {n}\n");
    }
    for w in &s.warnings {
        out += &format!("warning: {w}\n");
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn reals_print_as_adams_prints_them() {
        assert_eq!(super::fortran_e(0.01, 6), "1.000000E-02");
        assert_eq!(super::fortran_e(5.0, 3), "5.000E+00");
        assert_eq!(super::fortran_e(-1.5e-123, 2), "-1.50E-123");
    }
}
