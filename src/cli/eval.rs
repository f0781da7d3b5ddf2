//! `mbfx eval`: one expression evaluated once ([`crate::session::evaluate`]), its value
//! printed; also the command-line inputs (`--time`, `--var`) other commands share.

use super::output::{Output, Stop};
use super::{Dim, Engine};
use crate::check::{units, Expect};
use crate::diag::{render, Code, Diagnostic, SourceFile};
use crate::session::evaluate::{EvalError, Evaluator};
use crate::session::loaded::LoadedModel;
use crate::session::DimRequest;
use std::path::Path;

#[derive(clap::Args)]
pub struct EvalArgs {
    /// Back end.
    #[arg(long, value_enum, default_value = "jit")]
    engine: Engine,
    /// Value of TIME (any constant expression).
    #[arg(long, default_value = "0", allow_hyphen_values = true)]
    time: String,
    /// A user variable, NAME=VALUE (VALUE is any constant expression); repeatable.
    #[arg(long = "var", value_name = "NAME=VALUE", allow_hyphen_values = true)]
    vars: Vec<String>,
    /// The dimension of a `--var`, NAME=DIMENSION (`v=velocity`, `k=N/m`, `w=rad/s`):
    /// the expression is then checked for units of measure (warning W0312); repeatable.
    #[arg(long = "unit", value_name = "NAME=DIMENSION")]
    units: Vec<String>,
    /// An .adm dataset: the expression may read its measures (DX, VZ, UVZ, ...), taken
    /// at the assembled configuration at t = 0.
    #[arg(long, value_name = "FILE")]
    model: Option<std::path::PathBuf>,
    /// With --model: build the system in 2D (an error when the scene is not planar) or 3D;
    /// by default 2D when the scene is planar.
    #[arg(long, value_enum, value_name = "2|3", requires = "model")]
    dim: Option<Dim>,
    /// The expression.
    #[arg(allow_hyphen_values = true)]
    expr: String,
}

/// Loads `path` as the model expressions read; the error is the rendered diagnostics (or
/// message) saying what stops it.
pub fn load_model(path: &Path, dim: DimRequest, color: bool) -> Result<LoadedModel, String> {
    LoadedModel::open(path, dim).map_err(|e| {
        let mut text = render(&e.diagnostics, &e.source, color);
        if let Some(why) = &e.failure {
            text.push_str(&format!("error: {why}\n"));
        }
        text
    })
}

/// The value of a command-line input (`--time`, a `--var` value) under `what`: a scalar
/// that may read TIME and the variables `e` holds.
fn command_line_value(
    text: &str,
    what: &str,
    e: &mut Evaluator,
    o: &mut Output,
) -> Result<f64, Stop> {
    match e.evaluate(text, Expect::Scalar) {
        Ok(v) => Ok(v.values[0]),
        Err(failed) => {
            report(&failed, &SourceFile::new(what, text), o)?;
            Err(Stop::Failed)
        }
    }
}

/// Writes why an expression has no value: its diagnostics, and any failure beside them.
fn report(failed: &EvalError, source: &SourceFile, o: &mut Output) -> Result<(), Stop> {
    o.diagnostics(failed.diagnostics(), source)?;
    if let Some(why) = failed.failure() {
        writeln!(o.err(), "error: {why}")?;
    }
    Ok(())
}

/// Defines the variables of `--var` specs (NAME=VALUE) in `e`. A value may read the
/// variables given before it and TIME; a name given twice (names are case-insensitive:
/// `a` and `A`) is an error.
pub fn define_variables(specs: &[String], e: &mut Evaluator, o: &mut Output) -> Result<(), Stop> {
    for spec in specs {
        let source = SourceFile::new("--var", spec.as_str());
        let Some((name, value)) = spec.split_once('=') else {
            let d = Diagnostic::error(Code::CommandLine, 0..spec.len(), "expected NAME=VALUE")
                .with_help("e.g. --var x=1.5");
            o.diagnostics(&[d], &source)?;
            return Err(Stop::Failed);
        };
        let name = name.trim();
        if let Err(bad) = crate::check::scope::check_variable_name(name) {
            let d = Diagnostic::error(Code::CommandLine, 0..name.len(), bad.message(name))
                .with_help(bad.help());
            o.diagnostics(&[d], &source)?;
            return Err(Stop::Failed);
        }
        if e.values().any(|(n, _)| n.eq_ignore_ascii_case(name)) {
            let d = Diagnostic::error(
                Code::CommandLine,
                0..name.len(),
                format!("`{name}` is given twice (names are case-insensitive)"),
            )
            .with_help("give each variable once");
            o.diagnostics(&[d], &source)?;
            return Err(Stop::Failed);
        }
        let v = command_line_value(value, &format!("--var {name}"), e, o)?;
        e.set_variable(name, v);
    }
    Ok(())
}

/// Gives the variables of `--unit` specs (NAME=DIMENSION) their dimensions in `e`; each
/// must name a `--var`, once.
fn define_units(specs: &[String], e: &mut Evaluator, o: &mut Output) -> Result<(), Stop> {
    for (k, spec) in specs.iter().enumerate() {
        let source = SourceFile::new("--unit", spec.as_str());
        let fail = |d: Diagnostic, o: &mut Output| {
            o.diagnostics(&[d], &source)?;
            Err(Stop::Failed)
        };
        let Some((name, dim)) = spec.split_once('=') else {
            let d = Diagnostic::error(Code::CommandLine, 0..spec.len(), "expected NAME=DIMENSION")
                .with_help("e.g. --unit v=velocity or --unit k=N/m");
            return fail(d, o);
        };
        let name_span = 0..name.len();
        let name = name.trim();
        let given_before = specs[..k].iter().any(|s| {
            s.split_once('=')
                .is_some_and(|(n, _)| n.trim().eq_ignore_ascii_case(name))
        });
        if given_before {
            let d = Diagnostic::error(
                Code::CommandLine,
                name_span,
                format!("`{name}` is given a dimension twice"),
            );
            return fail(d, o);
        }
        let dim = match units::parse::parse(dim) {
            Ok(d) => d,
            Err(why) => {
                let at = spec.len() - dim.len()..spec.len();
                return fail(Diagnostic::error(Code::CommandLine, at, why), o);
            }
        };
        if !e.set_dim(name, dim) {
            let d = Diagnostic::error(
                Code::CommandLine,
                name_span,
                format!("`{name}` is not a variable: give it a value with --var {name}=VALUE"),
            );
            return fail(d, o);
        }
    }
    Ok(())
}

/// Formats a value the way the CLI contract says: `{:?}` of an f64, vectors as `[x, y, z]`.
pub fn format_value(out: &[f64]) -> String {
    match out {
        [v] => format!("{v:?}"),
        vs => {
            let parts: Vec<String> = vs.iter().map(|v| format!("{v:?}")).collect();
            format!("[{}]", parts.join(", "))
        }
    }
}

pub fn run(a: &EvalArgs, o: &mut Output) -> Result<i32, Stop> {
    // Command-line inputs are constants: the interpreter evaluates them.
    let mut e = Evaluator::new(Engine::Interp.into());
    e.time = command_line_value(&a.time, "--time", &mut e, o)?;
    define_variables(&a.vars, &mut e, o)?;
    define_units(&a.units, &mut e, o)?;
    e.engine = a.engine.into();
    if let Some(path) = &a.model {
        match load_model(path, Dim::request(a.dim), o.color) {
            Ok(m) => e.set_model(Some(m)),
            Err(text) => {
                o.err().write_all(text.as_bytes())?;
                return Err(Stop::Failed);
            }
        };
    }
    let source = SourceFile::new("<expr>", a.expr.as_str());
    match e.evaluate(&a.expr, Expect::Any) {
        Ok(v) => {
            o.diagnostics(&v.warnings, &source)?;
            writeln!(o.out(), "{}", format_value(&v.values))?;
            o.diagnostics(v.fault.as_slice(), &source)?;
            Ok(0)
        }
        Err(failed) => {
            report(&failed, &source, o)?;
            Err(Stop::Failed)
        }
    }
}
