//! Adams command files (`.acf`) as a run's input: [`read`] reads one
//! ([`crate::model::commands`]) and finds the dataset it names (beside the command file
//! unless the path is absolute, `.adm` added when the name has no extension);
//! [`segments`] turns its INTEGRATOR and SIMULATE commands into the run's
//! [`Segment`]s, or one segment to an end time the caller gives. Every shell runs a
//! command file through [`super::request::run`], which calls both; they print nothing.

use super::files::read_dataset;
use super::plan;
use super::run::Segment;
use crate::diag::{Code, Diagnostic, SourceFile};
use crate::model::commands::{read_commands, Analysis, CommandFile, Step};
use crate::model::equilibrium_settings::EquilibriumStatement;
use crate::model::integrator_settings::IntegratorStatement;
use std::path::{Path, PathBuf};

/// A command file read, and where its dataset is.
pub struct Commands {
    /// The command file's name and text (spans of its diagnostics point into it).
    pub source: SourceFile,
    /// Its commands; `file.diagnostics` holds its warnings (errors refuse it in [`read`]).
    pub file: CommandFile,
    /// The dataset it names, resolved against the command file's folder.
    pub model: PathBuf,
}

/// A command file that cannot be run: its diagnostics (its warnings among them, in
/// order) and the text they point into.
pub struct Refused {
    /// The command file (or the file that could not be read).
    pub source: SourceFile,
    /// What is wrong, errors and warnings.
    pub diagnostics: Vec<Diagnostic>,
}

/// True when `path` names a command file (`.acf`, any case).
pub fn is_command_file(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("acf"))
}

/// `name` with `.adm` added when its last component (after `/` or `\`) has no extension.
fn with_extension(name: &str) -> String {
    let last = name.rsplit(['/', '\\']).next().unwrap_or(name);
    if last.contains('.') {
        name.to_string()
    } else {
        format!("{name}.adm")
    }
}

/// Reads the command file at `path` and finds its dataset. A file with errors, naming no
/// model, or naming one that does not exist is [`Refused`] (E0604 for no model, E0501 at
/// the name for a missing one), its warnings before the error.
pub fn read(path: &Path) -> Result<Commands, Box<Refused>> {
    let (text, warnings) = match read_dataset(path) {
        Ok(t) => t,
        Err(u) => {
            return Err(Box::new(Refused {
                source: u.source,
                diagnostics: vec![u.diagnostic],
            }))
        }
    };
    let source = SourceFile::new(path.display().to_string(), text);
    let mut file = read_commands(&source.text);
    file.diagnostics.splice(0..0, warnings);
    let refuse = |source, diagnostics| {
        Err(Box::new(Refused {
            source,
            diagnostics,
        }))
    };
    if file.has_errors() {
        return refuse(source, file.diagnostics);
    }
    let Some(name) = &file.model else {
        let d = Diagnostic::error(Code::MissingArgument, 0..0, "the command file names no model")
            .with_help("put the dataset's file name on line 1 (and the output name on line 2), or write FILE/MODEL = NAME");
        let mut all = file.diagnostics;
        all.push(d);
        return refuse(source, all);
    };
    let written = PathBuf::from(with_extension(&name.value));
    let model = match path.parent() {
        Some(dir) if written.is_relative() => dir.join(&written),
        _ => written,
    };
    if !model.is_file() {
        let d = Diagnostic::error(
            Code::Io,
            name.span.clone(),
            format!("the model {} does not exist", model.display()),
        )
        .with_help("the dataset's name is read relative to the command file's folder");
        let mut all = file.diagnostics;
        all.push(d);
        return refuse(source, all);
    }
    Ok(Commands {
        source,
        file,
        model,
    })
}

/// The message when neither the command file nor the caller says when to end.
pub const NO_SIMULATION: &str =
    "the command file has no SIMULATE or LINEAR command: give --end (and --output-step)";

/// The segments of the run: the command file's SIMULATE commands under the INTEGRATOR
/// and EQUILIBRIUM in force at each (the dataset's, then the file's commands), or, when
/// `end` is given, the static equilibria the file asks for first and then one stretch
/// to `end` of the analysis its first other SIMULATE runs (dynamics by default; its
/// output step `output_step`, else that SIMULATE's, else END/100). `output_step` alone
/// replaces every stretch's. [`NO_SIMULATION`] when neither the file nor the caller
/// says when to end.
pub fn segments(
    file: &CommandFile,
    dataset: Option<&IntegratorStatement>,
    equilibrium: Option<&EquilibriumStatement>,
    end: Option<f64>,
    output_step: Option<f64>,
) -> Result<Vec<Segment>, String> {
    let mut segments = plan::segments(dataset, equilibrium, &file.steps);
    if let Some(end) = end {
        // The static equilibria before the first stretch stay; the stretch runs to `end`
        // under the settings in force at the first SIMULATE that is not one of them.
        let points = segments
            .iter()
            .take_while(|s| s.kind == Analysis::Statics && s.output_step == 0.0)
            .count();
        let first = segments.get(points).cloned();
        let integrator = match &first {
            Some(s) => s.integrator.clone(),
            None => merged(dataset, &file.steps),
        };
        let dt = output_step
            .or(first.as_ref().map(|s| s.output_step))
            .unwrap_or(end / 100.0);
        segments.truncate(points);
        segments.push(Segment {
            end,
            output_step: dt,
            integrator,
            kind: first.as_ref().map_or(Analysis::Dynamic, |s| s.kind),
            changes: first.as_ref().map_or(Vec::new(), |s| s.changes.clone()),
            equilibrium: first.and_then(|s| s.equilibrium),
            linear: None,
        });
    } else if let Some(dt) = output_step {
        for s in segments.iter_mut().filter(|s| s.output_step > 0.0) {
            s.output_step = dt;
        }
    }
    if segments.is_empty() {
        return Err(NO_SIMULATION.into());
    }
    Ok(segments)
}

/// The summary note saying the command file's output files are not written, when it
/// names them (line 2).
pub fn output_note(file: &CommandFile) -> Option<String> {
    file.output.as_ref().map(|out| {
        format!(
            "the command file's output files ({}.req, .res, …) are not written; the CSV goes to --csv (standard output by default)",
            out.value
        )
    })
}

/// The dataset's INTEGRATOR with the INTEGRATOR commands of `steps` put over it.
fn merged(dataset: Option<&IntegratorStatement>, steps: &[Step]) -> Option<IntegratorStatement> {
    steps
        .iter()
        .fold(dataset.cloned(), |acc, s| match (acc, s) {
            (Some(a), Step::Integrator(s)) => Some(a.merged(s)),
            (None, Step::Integrator(s)) => Some((**s).clone()),
            (acc, Step::Simulate(_) | Step::Equilibrium(_) | Step::Linear(_) | Step::Change(_)) => {
                acc
            }
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extension_is_added_only_when_absent() {
        assert_eq!(with_extension("Test02_ADAMS"), "Test02_ADAMS.adm");
        assert_eq!(
            with_extension("test_Revolute_Case01.adm"),
            "test_Revolute_Case01.adm"
        );
        assert_eq!(
            with_extension(r"C:\Users\ben.thornton\code\test"),
            r"C:\Users\ben.thornton\code\test.adm"
        );
        assert_eq!(with_extension("../m.v2/model"), "../m.v2/model.adm");
    }

    #[test]
    fn the_command_line_end_replaces_the_simulations() {
        let f = read_commands(
            "m.adm\nout\nint/hht, err=1e-6\nsim/dyn, end=1, dtout=0.1\nsim/dyn, end=2, dtout=0.5\n",
        );
        let s = segments(&f, None, None, None, None).expect("segments");
        assert_eq!(
            s.iter().map(|s| (s.end, s.output_step)).collect::<Vec<_>>(),
            [(1.0, 0.1), (2.0, 0.5)]
        );
        let s = segments(&f, None, None, Some(3.0), None).expect("segments");
        assert_eq!(
            s.iter().map(|s| (s.end, s.output_step)).collect::<Vec<_>>(),
            [(3.0, 0.1)]
        );
        let e = s[0]
            .integrator
            .as_ref()
            .and_then(|i| i.error.as_ref())
            .map(|e| e.value);
        assert_eq!(e, Some(1e-6));
        let s = segments(&f, None, None, None, Some(0.05)).expect("segments");
        assert!(s.iter().all(|s| s.output_step == 0.05));
        let none = read_commands("m.adm\nout\nSTOP\n");
        assert!(segments(&none, None, None, None, None).is_err());
        let s = segments(&none, None, None, Some(2.0), None).expect("segments");
        assert_eq!(
            s.iter().map(|s| (s.end, s.output_step)).collect::<Vec<_>>(),
            [(2.0, 0.02)]
        );
    }

    #[test]
    fn a_command_file_naming_a_missing_model_is_refused_at_the_name() {
        let dir = std::env::temp_dir().join(format!("mbfx-acf-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch folder");
        let path = dir.join("a.acf");
        std::fs::write(&path, "nowhere\nout\nsim/dyn, end=1, steps=10\n").expect("write");
        let Err(refused) = read(&path) else {
            panic!("the model is not there")
        };
        let d = refused.diagnostics.last().expect("a diagnostic");
        assert_eq!(d.code, Code::Io);
        assert_eq!(&refused.source.text[d.span.clone()], "nowhere");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
