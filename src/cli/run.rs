//! `mbfx run MODEL.adm --end T …`: simulates a dataset ([`crate::session::run`]) and
//! writes the output rows as CSV (header `time`, the probes in the order given, then the
//! REQUEST components; numbers as `{:?}` prints an f64), a progress bar on stderr when
//! it is a terminal, a summary at the end, and `--plot` draws the columns against time.
//! A failure is a diagnostic at the statement of the element it names, with the time and
//! the cause; the rows before it are written; the exit code is 1.

use super::output::{Named, Output, Stop};
use super::Dim;
use crate::diag::{Code, Diagnostic, SourceFile};
use crate::mbd::dynamics::{Culprit, DynError};
use crate::mbd::error::MbdError;
use crate::mbd::expr::ExprError;
use crate::session::files::read_dataset;
use crate::session::run::{Method, RunFailure, RunSpec, Simulation, Summary};
use crate::session::{report, DimRequest};
use std::io::Write;
use std::path::PathBuf;

/// `--integrator` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum IntegratorArg {
    /// Adams HHT on the index-3 DAE (ALPHA −0.3 unless --alpha), error-controlled.
    Hht,
    /// Generalized-α on the index-3 DAE (ρ∞ 0.9 unless --rho-inf, as Exudyn).
    Galpha,
}

#[derive(clap::Args)]
pub struct RunArgs {
    /// The dataset (.adm).
    model: PathBuf,
    /// End time.
    #[arg(long)]
    end: f64,
    /// Output step DT: one row at every k·DT and at the end time [default: END/100].
    #[arg(long = "output-step", value_name = "DT")]
    output_step: Option<f64>,
    /// The integrator [default: the dataset's INTEGRATOR, else hht].
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
    /// Fixed steps of at most H (no error control; each output interval is split evenly).
    #[arg(long = "fixed-step", value_name = "H")]
    fixed_step: Option<f64>,
    /// HHT ALPHA in [−1/3, 0].
    #[arg(long, allow_hyphen_values = true)]
    alpha: Option<f64>,
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
    let dt = a.output_step.unwrap_or(a.end / 100.0);
    if !(a.end.is_finite() && a.end > 0.0) {
        return command_line_error(format!("--end {} must be a positive time", a.end), o);
    }
    if !(dt.is_finite() && dt > 0.0) {
        return command_line_error(format!("--output-step {dt} must be a positive time"), o);
    }
    for (name, x) in [
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
    let name = a.model.display().to_string();
    let (text, warnings) = match read_dataset(&a.model) {
        Ok(t) => t,
        Err(u) => {
            o.diagnostics(&[u.diagnostic], &u.source)?;
            return Err(Stop::Failed);
        }
    };
    let mut spec = RunSpec::new(a.end, dt);
    spec.method = a.integrator.map(|m| match m {
        IntegratorArg::Hht => Method::Hht,
        IntegratorArg::Galpha => Method::Galpha,
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
    let header = sim.header();
    let mut file = match a.csv.as_deref() {
        None | Some("-") => None,
        Some(path) => match std::fs::File::create(path) {
            Ok(f) => Some(Named::new(std::io::BufWriter::new(f), path)),
            Err(e) => return command_line_error(format!("cannot write {path}: {e}"), o),
        },
    };
    let (mut rows, keep_rows) = (Vec::new(), a.plot.is_some());
    let progress = super::progress::Progress::new(a.end);
    // The first write error: a closed pipe ends the run quietly, others fail it.
    let mut io_error: Option<std::io::Error> = None;
    let (summary, failed) = {
        let writer: &mut dyn Write = match &mut file {
            Some(f) => f,
            None => o.out(),
        };
        let mut csv = csv::Writer::from_writer(writer);
        let result = match csv.write_record(&header) {
            Err(e) => {
                io_error = Some(e.into());
                (None, None)
            }
            Ok(()) => {
                let (s, f) = sim.run(&mut |row| {
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
                });
                (Some(s), f)
            }
        };
        if let Err(e) = csv.flush() {
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
    if let Some(s) = &summary {
        write!(o.err(), "{}", summary_text(s))?;
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

/// The end-of-run summary.
pub fn summary_text(s: &Summary) -> String {
    let st = &s.stats;
    let mut out = format!(
        "{}: {} steps ({} rejected), {} Newton iterations, {} Jacobian evaluations, {} factorizations, {} expression evaluations, {:.3} s CPU{}\nlargest constraint residual {:.3e}\n",
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
    out
}
