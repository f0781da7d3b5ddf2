//! `mbfx eval`: compile one expression, evaluate it once, print the value.

use super::output::{Output, Stop};
use super::Engine;
use crate::check::{self, Expect, Variables};
use crate::context::Context;
use crate::diag::{has_errors, render, Code, Diagnostic, SourceFile};
use crate::interp::Program;

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
    /// An .adm dataset: the expression may read its measures (DX, VZ, UVZ, ...), taken
    /// at the assembled configuration at t = 0.
    #[arg(long, value_name = "FILE")]
    model: Option<std::path::PathBuf>,
    /// With --model: build the system in 2D (an error when the scene is not planar) or 3D;
    /// by default 2D when the scene is planar.
    #[arg(long, value_name = "2|3", value_parser = ["2", "3"], requires = "model")]
    dim: Option<String>,
    /// The expression.
    #[arg(allow_hyphen_values = true)]
    expr: String,
}

/// `--dim` as the session's request.
pub fn dim_request(dim: Option<&str>) -> crate::session::DimRequest {
    use crate::session::DimRequest;
    match dim {
        Some("2") => DimRequest::Two,
        Some("3") => DimRequest::Three,
        _ => DimRequest::Auto,
    }
}

/// Loads `path` as a model for expressions; the error is the rendered diagnostics (or
/// message) saying what stops it.
pub fn load_model(
    path: &std::path::Path,
    dim: crate::session::DimRequest,
    color: bool,
) -> Result<crate::session::loaded::LoadedModel, String> {
    let (text, mut diags) = match super::check_file::read_dataset(path) {
        Ok(t) => t,
        Err(u) => return Err(render(&[u.diagnostic], &u.source, color)),
    };
    let source = SourceFile::new(path.display().to_string(), text.as_str());
    let (read, failure) = match crate::session::loaded::LoadedModel::load(&text, dim) {
        // The dataset's own warnings belong to `mbfx check`, not to each evaluation.
        Ok(m) => return Ok(m),
        Err(failed) => *failed,
    };
    match failure {
        crate::session::Failure::Read(d) => diags.extend(d),
        f => {
            diags.extend(crate::session::report::diagnostics(&f, &read.model));
            if !has_errors(&diags) {
                return Err(format!("error: {f}\n"));
            }
        }
    }
    Err(render(&diags, &source, color))
}

/// Evaluates a constant expression given on the command line (`--time`, `--var` values).
pub fn constant(text: &str, what: &str, o: &mut Output) -> Result<f64, Stop> {
    command_line_value(text, what, (&Variables::new(), &[]), 0.0, o)
}

/// Evaluates a command-line value that may read the variables defined so far and TIME.
fn command_line_value(
    text: &str,
    what: &str,
    (scope, values): (&Variables, &[f64]),
    time: f64,
    o: &mut Output,
) -> Result<f64, Stop> {
    let source = SourceFile::new(what, text);
    match check::compile(text, scope, Expect::Scalar) {
        Ok(c) => Ok(Program::new(c.function).eval(&Context::new(time, values))),
        Err(diags) => {
            o.diagnostics(&diags, &source)?;
            Err(Stop::Failed)
        }
    }
}

/// Parses `--var` arguments into a scope and the slot values. A value may read the
/// variables given before it and TIME (`time`, the `--time` value); a name given twice
/// (names are case-insensitive: `a` and `A`) is an error.
pub fn variables(
    specs: &[String],
    time: f64,
    o: &mut Output,
) -> Result<(Variables, Vec<f64>), Stop> {
    let mut scope = Variables::new();
    let mut values = Vec::new();
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
        if scope.names().iter().any(|n| n.eq_ignore_ascii_case(name)) {
            let d = Diagnostic::error(
                Code::CommandLine,
                0..name.len(),
                format!("`{name}` is given twice (names are case-insensitive)"),
            )
            .with_help("give each variable once");
            o.diagnostics(&[d], &source)?;
            return Err(Stop::Failed);
        }
        let what = format!("--var {name}");
        let v = command_line_value(value, &what, (&scope, &values), time, o)?;
        scope.define(name);
        values.push(v);
    }
    Ok((scope, values))
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

/// The warning (or, for a NaN IF test, the note) for a non-finite result.
pub fn fault_diagnostic(p: &Program, ctx: &Context) -> Option<Diagnostic> {
    let f = p.first_fault(ctx)?;
    Some(if f.nan_if_test {
        let d = Diagnostic::error(
            Code::NanIfTest,
            f.span,
            "the test of this IF is NaN, so no branch applies",
        )
        .with_note("decision 2: a NaN test selects no branch; the expression has no value");
        match f.cause {
            Some(cause) => d.with_label(cause, "the first non-finite value, before the IF"),
            None => d,
        }
    } else {
        Diagnostic::warning(
            Code::NonFinite,
            f.span,
            format!("this subexpression is {:?}", f.value),
        )
        .with_note("the result follows IEEE arithmetic; a simulation stops at the first such value")
    })
}

pub fn run(a: &EvalArgs, o: &mut Output) -> Result<i32, Stop> {
    let time = constant(&a.time, "--time", o)?;
    let (scope, values) = variables(&a.vars, time, o)?;
    let source = SourceFile::new("<expr>", a.expr.as_str());
    let mut model = match &a.model {
        Some(path) => match load_model(path, dim_request(a.dim.as_deref()), o.color) {
            Ok(m) => Some(m),
            Err(text) => {
                o.err().write_all(text.as_bytes())?;
                return Err(Stop::Failed);
            }
        },
        None => None,
    };
    let compiled = match model.as_mut() {
        Some(m) => m.compile(&a.expr, &scope),
        None => check::compile(&a.expr, &scope, Expect::Any),
    };
    let checked = match compiled {
        Ok(c) => c,
        Err(diags) => {
            o.diagnostics(&diags, &source)?;
            return Err(Stop::Failed);
        }
    };
    o.diagnostics(&checked.warnings, &source)?;
    let measures = match model.as_mut().map(|m| m.measures_for(&checked.function)) {
        Some(Ok(m)) => m,
        Some(Err(e)) => {
            writeln!(o.err(), "error: {e}")?;
            return Err(Stop::Failed);
        }
        None => Vec::new(),
    };
    let splines = model.as_ref().map_or(&[][..], |m| m.splines());
    let ctx = Context::new(time, &values)
        .with_measures(&measures)
        .with_splines(splines);
    let mut out = vec![0.0; checked.function.outputs.len()];
    if a.engine == Engine::Jit {
        match crate::jit::Jit::new().and_then(|mut j| j.compile(&checked.function)) {
            Ok(code) => code.eval_into(&ctx, &mut out),
            Err(e) => {
                writeln!(o.err(), "error: {e}")?;
                return Err(Stop::Failed);
            }
        }
    }
    // The interpreter evaluates (`--engine interp`) and, on a non-finite result, traces
    // where it came from: both engines give the same bits.
    let program = Program::new(checked.function);
    if a.engine == Engine::Interp {
        program.eval_into(&ctx, &mut out);
    }
    let fault = out
        .iter()
        .any(|v| !v.is_finite())
        .then(|| fault_diagnostic(&program, &ctx))
        .flatten();
    // A NaN IF test is an error (decision 2); any other non-finite value is printed with
    // a warning (decision 7).
    if let Some(d) = fault.as_ref().filter(|d| d.is_error()) {
        o.diagnostics(std::slice::from_ref(d), &source)?;
        return Err(Stop::Failed);
    }
    writeln!(o.out(), "{}", format_value(&out))?;
    o.diagnostics(fault.as_slice(), &source)?;
    Ok(0)
}
