//! `mbfx run MODEL.adm --end T …` and `mbfx run ANALYSIS.acf`: the command line's shell
//! over [`crate::session::request::run`], which checks the options, reads the command
//! file and the dataset, runs the simulation and words its failures. This module turns
//! the arguments into a [`RunRequest`] and prints what comes back: the output rows as CSV
//! (header `time`, the probes in the order given, then the REQUEST components; each number
//! the shortest text that reads back to its bits, [`super::number`]), a progress bar on stderr when it is a terminal, a summary at
//! the end, and `--plot` draws the columns against time. `--verbose` adds an Adams-like
//! step table on stderr at each output time. A failure is a diagnostic at the statement
//! of the element it names, with the time and the cause; the rows before it are written;
//! the exit code is 1.

use super::number::Shortest;
use super::output::{Named, Output, Stop};
use super::progress::Progress;
use super::Dim;
use crate::diag::{render, Code, Diagnostic, SourceFile};
use crate::session::request::{
    self, parse_probe, Built, Formulation, LinearRequest, RunObserver, RunRequest, Started,
};
use crate::session::run::{Method, TableRow};
use std::fs::File;
use std::io::{self, BufWriter, Write};
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

/// `--estimate-error` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum EstimateArg {
    /// A second run from the start at ERROR/10, compared at the output times.
    Rerun,
    /// The error carried through the steps by the method's linearization.
    Steps,
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
    /// Output rows from each method's continuous extension instead of steps landed on
    /// every output time (INTEGRATOR/INTERPOLATE = ON): many rows cost about what few do.
    /// With --animate it is the animation's instead: frames at FPS per second of model
    /// time (default 60, at most 10,000 frames) from the continuous extension, the rows
    /// left as without it.
    #[arg(long, value_name = "FPS", num_args = 0..=1, require_equals = true)]
    interpolate: Option<Option<f64>>,
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
    /// Set one value of the dataset without editing it: KIND/ID.FIELD=VALUE, e.g.
    /// SPRINGDAMPER/1.K=2E4 or SFORCE/1.FUNCTION=EXPR; repeatable.
    #[arg(long = "set", value_name = "KIND/ID.FIELD=VALUE")]
    set: Vec<String>,
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
    /// Exit with code 3 when the run finishes with an accuracy warning or leaves physics
    /// of the dataset out (for scripts and CI: a warned answer fails the job without being
    /// an error).
    #[arg(long)]
    strict: bool,
    /// Estimate the answer's error and warn past 10×ERROR. `rerun` (the flag alone): run
    /// again from the start at ERROR/10 and compare the output columns at the output
    /// times (each over its largest magnitude, at least 1); the second run costs about
    /// 1.6 times the first. `steps`: carry the error through the steps by the method's
    /// own linearization, one more residual and two back-substitutions a step (GSTIFF
    /// and WSTIFF; about +30 to +45 % CPU); the summary says "estimated error".
    #[arg(long = "estimate-error", value_name = "HOW", num_args = 0..=1, require_equals = true, default_missing_value = "rerun")]
    estimate_error: Option<EstimateArg>,
    /// Find the static equilibrium first (SIMULATE/STATICS, under the dataset's
    /// EQUILIBRIUM settings): the dynamics start from it; without --end it is the run.
    #[arg(long, conflicts_with = "kinematics")]
    statics: bool,
    /// Solve a model without degrees of freedom from its constraints at each output
    /// time instead of integrating (SIMULATE/KINEMATICS).
    #[arg(long)]
    kinematics: bool,
    /// Linearize where the run ends (LINEAR/EIGENSOL) and print the modes: frequencies,
    /// damping ratios, eigenvalues. With =FILE, also write FILE_modes.csv and
    /// FILE_shapes.csv. Without --end, at the start (after --statics: at equilibrium).
    #[arg(long, value_name = "FILE", num_args = 0..=1, require_equals = true)]
    linear: Option<Option<String>>,
    #[command(flatten)]
    animate: super::animate::AnimateArgs,
}

impl RunArgs {
    /// The session's request for these arguments.
    fn request(&self) -> RunRequest {
        let mut r = RunRequest::file(&self.model);
        (r.end, r.output_step) = (self.end, self.output_step);
        r.method = self.integrator.map(|m| match m {
            IntegratorArg::Hht => Method::Hht,
            IntegratorArg::Galpha => Method::Galpha,
            IntegratorArg::Newmark => Method::Newmark,
            IntegratorArg::Dopri853 => Method::Dopri853,
            IntegratorArg::Gstiff => Method::Gstiff,
            IntegratorArg::Wstiff => Method::Wstiff,
        });
        (r.error, r.hmax, r.hinit, r.hmin) = (self.error, self.hmax, self.hinit, self.hmin);
        r.error_per_run = self.error_per == ErrorPer::Run;
        r.cartesian = self.cartesian;
        // With --animate, --interpolate is the animation's frame rate.
        r.interpolate = self.interpolate.is_some() && self.animate.animate.is_none();
        r.estimate_error = self.estimate_error == Some(EstimateArg::Rerun);
        r.carry_error = self.estimate_error == Some(EstimateArg::Steps);
        (r.fixed_step, r.alpha, r.rho_inf) = (self.fixed_step, self.alpha, self.rho_inf);
        r.formulation = self.formulation.map(|f| match f {
            FormulationArg::I3 => Formulation::I3,
            FormulationArg::Si2 => Formulation::Si2,
        });
        r.kmax = self.kmax;
        r.dim = Dim::request(self.dim);
        r.engine = self.engine.into();
        r.probes = self.probes.iter().map(|p| parse_probe(p)).collect();
        r.set.clone_from(&self.set);
        (r.statics, r.kinematics) = (self.statics, self.kinematics);
        r.linear = self.linear.clone().map(LinearRequest::eigensol);
        r
    }
}

fn command_line_error(msg: String, o: &mut Output) -> Result<i32, Stop> {
    let d = Diagnostic::error(Code::CommandLine, 0..0, msg);
    o.diagnostics(&[d], &SourceFile::textless(request::COMMAND_LINE))?;
    Err(Stop::Failed)
}

/// Where the CSV goes: standard output, or the `--csv` file.
enum Target<'o> {
    Stdout(&'o mut dyn Write),
    File(Named<BufWriter<File>>),
}

impl Write for Target<'_> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self {
            Target::Stdout(w) => w.write(buf),
            Target::File(f) => f.write(buf),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match self {
            Target::Stdout(w) => w.flush(),
            Target::File(f) => f.flush(),
        }
    }
}

/// The run's observer: prints warnings and the step table on stderr, the rows as CSV,
/// and keeps the first write error (a closed pipe ends the run quietly, others fail it)
/// to report once the session has returned.
struct Printer<'o> {
    args: &'o RunArgs,
    err: &'o mut dyn Write,
    color: bool,
    /// Standard output until the CSV takes it.
    stdout: Option<&'o mut dyn Write>,
    csv: Option<BufWriter<Target<'o>>>,
    /// The row being written ([`Shortest::line`]).
    line: Vec<u8>,
    progress: Option<Progress>,
    /// The rows, kept for `--plot`.
    rows: Vec<Vec<f64>>,
    /// The first write error of the CSV or a diagnostic.
    io_error: Option<io::Error>,
    /// The step table's first write error: it does not stop the run, but ends it the
    /// way the CSV's do.
    table_error: Option<io::Error>,
    /// The `--csv` file could not be created.
    refused: Option<String>,
    /// Scratch for the rows' numbers.
    numbers: Shortest,
}

impl Printer<'_> {
    /// Keeps `e` (the first one) and gives the session a copy that stops the run.
    fn keep(&mut self, e: io::Error) -> io::Error {
        let copy = io::Error::new(e.kind(), e.to_string());
        self.io_error.get_or_insert(e);
        copy
    }

    /// Flushes the CSV and clears the progress bar: the rows kept for the plot, the
    /// first write error, and why the `--csv` file could not be created.
    fn finish(self) -> (Vec<Vec<f64>>, Option<io::Error>, Option<String>) {
        let mut io_error = self.io_error;
        if let Some(mut csv) = self.csv {
            // Through the CSV's buffer and the file's (a `--csv` file's writer flushes it).
            if let Err(e) = csv.flush() {
                io_error.get_or_insert(e);
            }
            if let Some(e) = self.table_error {
                io_error.get_or_insert(e);
            }
            if let Some(p) = &self.progress {
                p.finish();
            }
        }
        (self.rows, io_error, self.refused)
    }
}

impl RunObserver for Printer<'_> {
    fn warnings(&mut self, diagnostics: &[Diagnostic], source: &SourceFile) -> io::Result<()> {
        let text = render(diagnostics, source, self.color);
        self.err
            .write_all(text.as_bytes())
            .map_err(|e| self.keep(e))
    }

    fn built(&mut self, built: &Built<'_>) -> io::Result<()> {
        if self.args.dim.is_none() {
            writeln!(self.err, "{}", built.dim_reason).map_err(|e| self.keep(e))?;
        }
        Ok(())
    }

    fn started(&mut self, started: &Started<'_>) -> io::Result<()> {
        let target = match self.args.csv.as_deref() {
            None | Some("-") => match self.stdout.take() {
                Some(w) => Target::Stdout(w),
                None => return Err(io::Error::other("standard output is taken")),
            },
            Some(path) => match File::create(path) {
                Ok(f) => Target::File(Named::new(BufWriter::new(f), path)),
                Err(e) => {
                    self.refused = Some(format!("cannot write {path}: {e}"));
                    return Err(io::Error::new(e.kind(), "the CSV file cannot be created"));
                }
            },
        };
        self.progress = Some(Progress::new(started.end));
        if self.args.verbose {
            if let Err(e) = self.err.write_all(TABLE_HEADER.as_bytes()) {
                self.table_error = Some(e);
            }
        }
        // The header through a CSV writer (a name may need quoting), the rows straight.
        let mut csv = BufWriter::new(target);
        let mut header = csv::Writer::from_writer(&mut csv);
        let written = header.write_record(started.header).map_err(io::Error::from);
        let written = written.and_then(|()| header.flush());
        drop(header);
        self.csv = Some(csv);
        written.map_err(|e| self.keep(e))
    }

    fn row(&mut self, row: &[f64]) -> io::Result<()> {
        if let Some(p) = &self.progress {
            p.at(row[0]);
        }
        if self.args.plot.is_some() || self.args.animate.animate.is_some() {
            self.rows.push(row.to_vec());
        }
        let Some(csv) = &mut self.csv else {
            return Ok(());
        };
        self.line.clear();
        self.numbers.line(row, &mut self.line);
        let w = csv.write_all(&self.line);
        w.map_err(|e| self.keep(e))
    }

    fn wants_table(&self) -> bool {
        self.args.verbose
    }

    fn table(&mut self, row: &TableRow) {
        if self.table_error.is_none() {
            if let Err(e) = self.err.write_all(table_line(row).as_bytes()) {
                self.table_error = Some(e);
            }
        }
    }
}

pub fn run(a: &RunArgs, o: &mut Output) -> Result<i32, Stop> {
    let mut req = a.request();
    let animate = match a.animate.request(a.interpolate) {
        Ok(x) => x,
        Err(msg) => return command_line_error(msg, o),
    };
    req.animation = animate.as_ref().map(|(_, r)| r.clone());
    req.geometry = match a.animate.geometry() {
        Ok(g) => g,
        Err(msg) => return command_line_error(msg, o),
    };
    let color = o.color;
    let (stdout, err) = o.both();
    let mut printer = Printer {
        args: a,
        err,
        color,
        stdout: Some(stdout),
        csv: None,
        progress: None,
        rows: Vec::new(),
        io_error: None,
        table_error: None,
        refused: None,
        numbers: Shortest::default(),
        line: Vec::new(),
    };
    let result = request::run(&req, &mut printer, None);
    let (rows, io_error, refused) = printer.finish();
    if let Some(msg) = refused {
        return command_line_error(msg, o);
    }
    if let Some(e) = io_error {
        return Err(Stop::Io(e));
    }
    let (summary, header, animation, failure) = match result {
        Ok(done) => (Some(done.summary), done.header, done.animation, None),
        Err(mut f) => (
            f.summary.take(),
            f.header.take().unwrap_or_default(),
            f.animation.take(),
            Some(f),
        ),
    };
    // The animation (of what was recorded up to a failure, too, as the CSV keeps its
    // rows), its notes once.
    if let (Some((kind, _)), Some(anim), Some(path)) = (animate, animation, &a.animate.animate) {
        for n in anim.notes() {
            writeln!(o.err(), "note: {n}")?;
        }
        if let Err(e) = super::animate::write(path, kind, &anim, &header, &rows) {
            return command_line_error(format!("cannot write {}: {e}", path.display()), o);
        }
    }
    let warned = summary.as_ref().is_some_and(|s| !s.warnings.is_empty());
    if let Some(s) = summary {
        write!(o.err(), "{}", s.text())?;
    }
    if let (Some(path), false) = (&a.plot, rows.is_empty()) {
        if let Err(e) = super::plot::draw(path, &header, &rows, req.probes.len()) {
            return command_line_error(
                format!("the plot {} could not be drawn: {e}", path.display()),
                o,
            );
        }
    }
    if let Some(f) = failure {
        o.diagnostics(&f.diagnostics, &f.source)?;
        return Err(Stop::Failed);
    }
    Ok(if a.strict && warned { STRICT_WARNED } else { 0 })
}

/// `--strict`'s exit code for a run that finished with a warning in its summary.
const STRICT_WARNED: i32 = 3;

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

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    /// `mbfx run`'s arguments alone.
    #[derive(Parser)]
    struct Args {
        #[command(flatten)]
        run: RunArgs,
    }

    fn request(args: &[&str]) -> RunRequest {
        let args = Args::try_parse_from(std::iter::once("run").chain(args.iter().copied()));
        args.map(|a| a.run.request())
            .unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn the_command_line_defaults_are_the_sessions() {
        let want = RunRequest {
            end: Some(2.0),
            ..RunRequest::file("m.adm")
        };
        assert_eq!(request(&["m.adm", "--end", "2"]), want);
    }

    #[test]
    fn the_estimate_is_the_second_run_or_the_steps() {
        let none = request(&["m.adm", "--end", "2"]);
        assert!(!none.carry_error && !none.estimate_error);
        let steps = request(&["m.adm", "--estimate-error=steps", "--end", "2"]);
        assert!(steps.carry_error && !steps.estimate_error);
        // The flag alone is the second run, and does not take the file for its value.
        let rerun = request(&["--estimate-error", "m.adm", "--end", "2"]);
        assert!(rerun.estimate_error && !rerun.carry_error);
    }

    #[test]
    fn every_option_reaches_the_request() {
        let r = request(&[
            "a.acf",
            "--end=3",
            "--output-step=0.5",
            "--integrator=hht",
            "--error=1e-5",
            "--hmax=0.1",
            "--hinit=0.01",
            "--hmin=1e-9",
            "--error-per=run",
            "--cartesian",
            "--interpolate",
            "--estimate-error=rerun",
            "--fixed-step=0.001",
            "--alpha=-0.2",
            "--formulation=si2",
            "--kmax=4",
            "--rho-inf=0.5",
            "--dim=3",
            "--engine=interp",
            "--probe",
            " x =DX(2)",
            "--probe",
            "bad",
        ]);
        let want = RunRequest {
            end: Some(3.0),
            output_step: Some(0.5),
            method: Some(Method::Hht),
            error: Some(1e-5),
            hmax: Some(0.1),
            hinit: Some(0.01),
            hmin: Some(1e-9),
            error_per_run: true,
            cartesian: true,
            interpolate: true,
            estimate_error: true,
            fixed_step: Some(0.001),
            alpha: Some(-0.2),
            formulation: Some(Formulation::Si2),
            kmax: Some(4),
            rho_inf: Some(0.5),
            dim: crate::session::DimRequest::Three,
            engine: crate::session::run::Engine::Interp,
            probes: vec![("x".into(), "DX(2)".into()), (String::new(), "bad".into())],
            ..RunRequest::file("a.acf")
        };
        assert_eq!(r, want);
    }

    #[test]
    fn reals_print_as_adams_prints_them() {
        assert_eq!(super::fortran_e(0.01, 6), "1.000000E-02");
        assert_eq!(super::fortran_e(5.0, 3), "5.000E+00");
        assert_eq!(super::fortran_e(-1.5e-123, 2), "-1.50E-123");
    }
}
