//! The simulation [`super::run`] would build for a request, without running it: for a
//! shell that steps it itself ([`crate::session::stepping`]), with `run`'s checks and
//! failures, and a stepping's failure worded as `run` words one.

use super::prepare::{apply_settings, build, read_file};
use super::{Input, RunFailed, RunRequest};
use crate::diag::{Code, Diagnostic, SourceFile};
use crate::model::Model;
use crate::session::run::Simulation;
use crate::session::stopped::Stopped;

/// A simulation built for a stepping caller ([`simulation`]).
pub struct BuiltSimulation {
    /// The simulation, at its start.
    pub simulation: Simulation,
    /// The dataset as built (its settings applied): what failures point into.
    pub source: SourceFile,
    /// The columns added before the request's probes (name, expression).
    pub columns: Vec<(String, String)>,
}

/// The simulation of `request`'s dataset, its `set` values applied, with the columns
/// `columns` gives for the model read (name, expression) before the request's probes;
/// the dataset's source (what a failure's spans point into) and those columns with it.
/// Refuses what [`super::run`] refuses (the numbers, the probes' names, the dataset, the
/// model), a probe named as one of `columns`, and a command file, whose SIMULATE
/// commands a stepping caller replaces.
pub fn simulation(
    request: &RunRequest,
    columns: &dyn Fn(&Model) -> Vec<(String, String)>,
) -> Result<BuiltSimulation, Box<RunFailed>> {
    request.validate().map_err(RunFailed::command_line)?;
    request.check_probes().map_err(RunFailed::command_line)?;
    let (name, text) = match &request.input {
        Input::Path(path) if crate::session::acf::is_command_file(path) => {
            return Err(refused(format!(
                "{} is a command file: stepping takes a dataset (.adm), and its caller says when to advance",
                path.display()
            )))
        }
        Input::Path(path) => {
            let (name, text, _) = read_file(path)?;
            (name, text)
        }
        Input::Dataset { name, text } => (name.clone(), text.clone()),
    };
    let text = apply_settings(crate::model::overrides::Settings::parse(&request.set), text)?;
    let source = SourceFile::new(name, text);
    let read = crate::model::read_model(&source.text);
    let extra = match read.has_errors() {
        // (The build says what is wrong.)
        true => Vec::new(),
        false => columns(&read.model),
    };
    if let Some((name, _)) =
        (request.probes.iter()).find(|(p, _)| extra.iter().any(|(c, _)| c == p))
    {
        return Err(refused(format!(
            "probe {name} has the name of one of the model's outputs: name it otherwise"
        )));
    }
    let mut with_columns = request.clone();
    with_columns.probes = extra.iter().chain(&request.probes).cloned().collect();
    let sim = build(&with_columns, source.text.as_str(), &source, &[])?;
    Ok(BuiltSimulation {
        simulation: sim,
        source,
        columns: extra,
    })
}

/// The request refused for `why` (E0503, no text to point into).
pub fn refused(why: String) -> Box<RunFailed> {
    RunFailed::command_line(Diagnostic::error(Code::CommandLine, 0..0, why))
}

/// A stepping's failure `e`, worded as [`super::run`] words a run's: at the element it
/// names in `sim`'s model, the spans into `source`.
pub fn failure(e: Stopped, source: &SourceFile, sim: &Simulation) -> Box<RunFailed> {
    RunFailed::dynamics(e, source.duplicate(), &sim.read.model)
}
