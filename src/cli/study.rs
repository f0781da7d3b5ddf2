//! `mbfx study STUDY.toml`: a design study for people who do not write Python. The
//! studies live in the Python module (`mbfx.study`, on Dask), so this command is the one
//! line `python3 -m mbfx.study STUDY.toml ...`: it hands its arguments over and, on Unix,
//! becomes that process, so Ctrl-C, the progress bar and the exit code are Python's own.
//! `MBFX_PYTHON` names the interpreter (one whose environment has `pip install .[study]`).

use super::output::{Output, Stop};
use std::ffi::OsString;
use std::process::Command;

#[derive(clap::Args)]
pub struct StudyArgs {
    /// The study file and its options (`mbfx study STUDY.toml --help` lists them).
    #[arg(trailing_var_arg = true, allow_hyphen_values = true, required = true)]
    args: Vec<OsString>,
}

/// Runs `python -m mbfx.study` with `a`'s arguments.
pub fn run(a: &StudyArgs, o: &mut Output<'_>) -> Result<i32, Stop> {
    let python = std::env::var_os("MBFX_PYTHON").unwrap_or_else(|| "python3".into());
    let shown = python.to_string_lossy().into_owned();
    // Asked first, so that a missing module gets the way to install it rather than a
    // traceback.
    let found = Command::new(&python)
        .args([
            "-c",
            "import importlib.util as u, sys; sys.exit(u.find_spec('mbfx') is None)",
        ])
        .status();
    let why = match found {
        Err(e) => format!("cannot start {shown}: {e}"),
        Ok(s) if !s.success() => format!("{shown} has no module mbfx"),
        Ok(_) => return hand_over(&python, &a.args, o),
    };
    writeln!(
        o.err(),
        "error: mbfx study: {why}\n  = help: studies run in the Python module: install it with \
         `pip install '.[study,plot]'` in the repository (docs/python.md), or set MBFX_PYTHON \
         to the python of an environment that has it"
    )?;
    Err(Stop::Failed)
}

/// Becomes `python -m mbfx.study ARGS` (Unix), or runs it and returns its exit code.
fn hand_over(python: &OsString, args: &[OsString], o: &mut Output<'_>) -> Result<i32, Stop> {
    let mut command = Command::new(python);
    command.args(["-m", "mbfx.study"]).args(args);
    o.flush()?;
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        let e = command.exec(); // returns only on failure
        writeln!(o.err(), "error: mbfx study: cannot run {python:?}: {e}")?;
        Err(Stop::Failed)
    }
    #[cfg(not(unix))]
    match command.status() {
        Ok(s) => Ok(s.code().unwrap_or(1)),
        Err(e) => {
            writeln!(o.err(), "error: mbfx study: cannot run {python:?}: {e}")?;
            Err(Stop::Failed)
        }
    }
}
