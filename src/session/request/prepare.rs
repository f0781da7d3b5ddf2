//! The simulation a request runs: the dataset read, the `--set` values applied, and a
//! simulation kept from the last run reused when only design values change, else one
//! built (its failures worded as the run's).

use super::{RunFailed, RunRequest};
use crate::diag::{Diagnostic, Severity, SourceFile};
use crate::model::command_changes::ModelChange;
use crate::model::overrides::Settings;
use crate::session::files::read_dataset;
use crate::session::prepared;
use crate::session::report;
use crate::session::run::{RunFailure, Simulation};

/// `text` with `values` (`KIND/ID.FIELD=VALUE`, as `--set` takes them) set in it; the
/// refusal points into the values, one a line (the text returned with it).
pub fn set_values(values: &[String], text: &str) -> Result<String, (String, Vec<Diagnostic>)> {
    let settings = Settings::parse(values)?;
    settings
        .apply(text)
        .map_err(|d| (settings.text().to_string(), d))
}

/// The `--set` values as [`Settings::parse`] read them, or its refusal.
pub(super) type Parsed = Result<Settings, (String, Vec<Diagnostic>)>;

/// `text` with the `--set` values (`parsed`) applied; a refusal points into the settings,
/// shown as a source named `--set`, one a line.
pub(super) fn apply_settings(parsed: Parsed, text: String) -> Result<String, Box<RunFailed>> {
    let refused = |t: &str, diagnostics: Vec<Diagnostic>| {
        RunFailed::new(SourceFile::new("--set", t), diagnostics)
    };
    let settings = parsed.map_err(|(t, d)| refused(&t, d))?;
    if settings.is_empty() {
        return Ok(text);
    }
    settings
        .apply(&text)
        .map_err(|d| refused(settings.text(), d))
}

/// A copy of `source` (its name and text) to keep in a failure.
pub(super) fn copy(source: &SourceFile) -> SourceFile {
    source.duplicate()
}

/// Whether `sim`'s expressions read design variable `id` as an input: setting it then
/// needs no new build. (A design variable only a MOTION reads is compiled in, and one
/// nothing reads changes nothing; either way the run builds the edited dataset.)
pub(super) fn reads_design(sim: &Simulation, id: i64) -> bool {
    sim.designs().iter().any(|&(d, _)| d == id)
}

/// The simulation for `request` on the dataset `text`, its source, whether it may be
/// kept for the next run of `key` ([`prepared`]) and whether it is a kept one. When the settings only give design
/// variables numbers, the simulation kept for `key` runs again with those values, or one
/// is built from `text` as written and given them; otherwise the settings are applied to
/// the text (refusals as E0611) and the edited text is built.
pub(super) fn simulation_for(
    request: &RunRequest,
    key: Option<&RunRequest>,
    name: String,
    text: String,
    initial: &[ModelChange],
) -> Result<(Simulation, SourceFile, bool, bool), Box<RunFailed>> {
    let parsed = Settings::parse(&request.set);
    let design = parsed.as_ref().ok().filter(|s| s.only_design());
    if let (Some(key), Some(settings)) = (key, design) {
        if let Some(mut sim) = prepared::take(key) {
            match settings.design_values(|id| reads_design(&sim, id)) {
                Some(values) if sim.rewind(&values).is_ok() => {
                    return Ok((sim, SourceFile::new(name, text), true, true));
                }
                // Not design values of this dataset: kept for other runs.
                _ => prepared::keep(key.clone(), sim),
            }
        }
        let source = SourceFile::new(name.clone(), text.clone());
        let mut sim = build(request, &text, &source, initial)?;
        match settings.design_values(|id| reads_design(&sim, id)) {
            Some(values) if values.is_empty() => return Ok((sim, source, true, false)),
            Some(values) if sim.rewind(&values).is_ok() => return Ok((sim, source, true, false)),
            _ => {}
        }
    }
    let text = apply_settings(parsed, text)?;
    let source = SourceFile::new(name, text);
    let sim = build(request, source.text.as_str(), &source, initial)?;
    Ok((sim, source, false, false))
}

/// Reads the dataset at `path`: its name, its text and the warnings of its encoding.
pub(super) fn read_file(
    path: &std::path::Path,
) -> Result<(String, String, Vec<Diagnostic>), Box<RunFailed>> {
    match read_dataset(path) {
        Ok((text, warnings)) => Ok((path.display().to_string(), text, warnings)),
        Err(u) => Err(RunFailed::new(u.source, vec![u.diagnostic])),
    }
}

/// The simulation of `text` (the text of `source`) for `request`, or why it cannot be
/// built: the reader's diagnostics, a probe's, the analysis' (all errors), or a dynamics
/// failure at its element. `initial` are the command file's changes before its first
/// SIMULATE ([`Simulation::with_changes`]).
pub(super) fn build(
    request: &RunRequest,
    text: &str,
    source: &SourceFile,
    initial: &[ModelChange],
) -> Result<Simulation, Box<RunFailed>> {
    match Simulation::with_changes(text, request.spec(), &request.probes, initial) {
        Ok(sim) => Ok(sim),
        Err(RunFailure::Diagnostics {
            probe: None,
            diagnostics,
        }) => Err(RunFailed::new(copy(source), diagnostics)),
        Err(RunFailure::Diagnostics {
            probe: Some(p),
            diagnostics,
        }) => {
            let expr = request
                .probes
                .iter()
                .find(|(n, _)| *n == p)
                .map_or("", |(_, e)| e.as_str());
            let probe = SourceFile::new(format!("--probe {p}"), expr);
            let mut f = RunFailed::new(probe, diagnostics);
            f.probe = Some(p);
            Err(f)
        }
        Err(RunFailure::Analysis(failure)) => {
            let model = crate::model::read_model(text).model;
            let mut diagnostics = report::diagnostics(&failure, &model);
            for d in &mut diagnostics {
                d.severity = Severity::Error;
            }
            Err(RunFailed::new(copy(source), diagnostics))
        }
        Err(RunFailure::Dynamics(e)) => {
            // Simulation::new kept its model to itself: read it again for the span.
            let model = crate::model::read_model(text).model;
            Err(RunFailed::dynamics(e.into(), copy(source), &model))
        }
    }
}
