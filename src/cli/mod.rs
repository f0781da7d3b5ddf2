//! Command-line interface (clap): `mbfx eval`, `mbfx check`, `mbfx run`, `mbfx repl`,
//! `mbfx bench`, `mbfx study`, `mbfx fmu`.
//!
//! Each command is a thin shell over library calls; all of them print diagnostics to
//! stderr and return exit code 1 on any error, 0 otherwise (DESIGN.md, CLI contract).
//! Every command writes through [`output::Output`] and returns `Result<i32, Stop>`; the
//! outcome becomes the exit code in one place ([`output::finish`]), so no write can
//! panic and a closed pipe ends the program quietly.

mod animate;
mod bench;
mod check_file;
mod eval;
mod fmu;
mod number;
pub mod output;
mod plot;
mod progress;
pub mod repl;
mod run;
mod study;

use output::{Output, Stop};

use clap::{Parser, Subcommand, ValueEnum};

/// When to colour diagnostics.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Color {
    /// Colour when stderr is a terminal and NO_COLOR is not set.
    Auto,
    /// Always colour.
    Always,
    /// Never colour.
    Never,
}

impl Color {
    /// Resolves `auto` against whether stderr is a terminal.
    pub fn enabled(self) -> bool {
        use std::io::IsTerminal;
        match self {
            Color::Always => true,
            Color::Never => false,
            Color::Auto => {
                std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none()
            }
        }
    }
}

/// Which back end evaluates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Engine {
    /// The bytecode interpreter.
    Interp,
    /// The Cranelift JIT (machine code; the default).
    Jit,
}

impl From<Engine> for crate::session::run::Engine {
    fn from(e: Engine) -> Self {
        match e {
            Engine::Interp => crate::session::run::Engine::Interp,
            Engine::Jit => crate::session::run::Engine::Jit,
        }
    }
}

/// `--dim`: which dimension a dataset's multibody system is built in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Dim {
    /// 2D (an error when the scene is not planar).
    #[value(name = "2")]
    Two,
    /// 3D, whatever the scene.
    #[value(name = "3")]
    Three,
}

impl Dim {
    /// The session's request for an optional `--dim` (none: 2D when the scene is planar).
    pub fn request(dim: Option<Dim>) -> crate::session::DimRequest {
        use crate::session::DimRequest;
        match dim {
            None => DimRequest::Auto,
            Some(Dim::Two) => DimRequest::Two,
            Some(Dim::Three) => DimRequest::Three,
        }
    }
}

#[derive(Parser)]
#[command(
    name = "mbfx",
    version,
    about = "Compiler and runtime for the Adams FUNCTION expression language"
)]
struct Cli {
    /// Colour diagnostics.
    #[arg(long, value_enum, default_value = "auto", global = true)]
    color: Color,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Evaluate one expression and print its value.
    Eval(eval::EvalArgs),
    /// Check a file of expressions (one per line) or an .adm dataset.
    Check(check_file::CheckArgs),
    /// Simulate a dataset (or an Adams command file naming one): CSV of probes and
    /// requests over time, a summary, a plot.
    Run(Box<run::RunArgs>),
    /// Interactive evaluation.
    Repl,
    /// Speed against accuracy: work-precision charts, the stability suite, scaling.
    #[command(subcommand)]
    Bench(bench::BenchCommand),
    /// Run a design study file (TOML) on Dask: `python3 -m mbfx.study` of the Python
    /// module (MBFX_PYTHON names the interpreter).
    Study(study::StudyArgs),
    /// Export a dataset as an FMI 2.0 co-simulation FMU (inputs and outputs: the
    /// dataset's PINPUT and POUTPUT, or the VARIABLEs named).
    Fmu(Box<fmu::FmuArgs>),
}

/// Runs the CLI with the process arguments; returns the exit code.
pub fn main() -> i32 {
    run(std::env::args_os())
}

/// Runs the CLI with the given arguments (the first is the program name).
pub fn run<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() { 1 } else { 0 };
        }
    };
    let mut o = Output::stdio(cli.color.enabled());
    let outcome: Result<i32, Stop> = match cli.command {
        Command::Eval(a) => eval::run(&a, &mut o),
        Command::Check(a) => check_file::run(&a, &mut o),
        Command::Run(a) => run::run(&a, &mut o),
        Command::Repl => repl::run_terminal(&mut o),
        Command::Bench(c) => bench::run(&c, &mut o),
        Command::Study(a) => study::run(&a, &mut o),
        Command::Fmu(a) => fmu::run(&a, &mut o),
    };
    output::finish(outcome, &mut o)
}
