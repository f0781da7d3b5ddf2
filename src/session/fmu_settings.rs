//! What an exported FMU carries beside its dataset (`resources/settings.toml`): the
//! integrator and ERROR it runs with, and each FMI variable with the value reference the
//! `modelDescription.xml` gives it, its causality and its start value. `mbfx fmu` writes
//! it (`crate::fmu_export`) and the FMU's slave library (`fmu/`, crate `mbfx-fmi`) reads
//! it back at `fmi2Instantiate`, so the two agree on one text and nothing of the model
//! has to be read twice to know the interface.

use super::request::RunRequest;
use super::run::Method;
use serde::{Deserialize, Serialize};

/// The settings file's name inside the FMU's `resources/` folder.
pub const SETTINGS_FILE: &str = "settings.toml";

/// The dataset's name inside the FMU's `resources/` folder.
pub const DATASET_FILE: &str = "model.adm";

/// The version of this file's layout; a slave refuses another.
pub const FORMAT: u32 = 1;

/// The settings of one exported FMU.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FmuSettings {
    /// [`FORMAT`] when written.
    pub format: u32,
    /// The GUID of the `modelDescription.xml` (`fmi2Instantiate` checks it).
    pub guid: String,
    /// The FMI model identifier (the library's file name without `.so`).
    pub model_identifier: String,
    /// The integrator, as `mbfx run --integrator` spells it (None: the dataset's
    /// INTEGRATOR, else GSTIFF).
    pub integrator: Option<String>,
    /// ERROR (None: the dataset's, else 1e-3); `fmi2SetupExperiment`'s tolerance, when
    /// defined, takes its place.
    pub error: Option<f64>,
    /// The FMI variables in value-reference order: the inputs, then the outputs.
    pub variables: Vec<FmuVariable>,
}

/// One FMI ScalarVariable.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FmuVariable {
    /// The FMI name.
    pub name: String,
    /// The FMI value reference.
    pub reference: u32,
    /// An input (causality input), else an output.
    pub input: bool,
    /// The VARIABLE statement's id in the dataset.
    pub variable: u32,
    /// An input's start value (its VARIABLE's IC, else 0); 0 for an output.
    pub start: f64,
}

impl FmuSettings {
    /// The file's text.
    pub fn to_text(&self) -> String {
        toml::to_string(self).unwrap_or_else(|e| format!("# cannot be written: {e}\n"))
    }

    /// Reads the file's text; the error says what is wrong with it.
    pub fn parse(text: &str) -> Result<FmuSettings, String> {
        let s: FmuSettings = toml::from_str(text).map_err(|e| format!("{SETTINGS_FILE}: {e}"))?;
        if s.format != FORMAT {
            return Err(format!(
                "{SETTINGS_FILE} has format {}, this library reads {FORMAT}: export the FMU again",
                s.format
            ));
        }
        Ok(s)
    }

    /// The inputs, in value-reference order.
    pub fn inputs(&self) -> impl Iterator<Item = &FmuVariable> {
        self.variables.iter().filter(|v| v.input)
    }

    /// The outputs, in value-reference order.
    pub fn outputs(&self) -> impl Iterator<Item = &FmuVariable> {
        self.variables.iter().filter(|v| !v.input)
    }

    /// The stepping request that runs `dataset` (named `name` in messages) as the FMU
    /// does: its integrator, ERROR `error` when given (an importer's tolerance), else the
    /// settings'.
    pub fn request(
        &self,
        name: &str,
        dataset: &str,
        error: Option<f64>,
    ) -> Result<RunRequest, String> {
        let mut request = RunRequest::dataset(name, dataset);
        request.method = self.integrator.as_deref().map(method).transpose()?;
        request.error = error.or(self.error);
        Ok(request)
    }
}

/// The input `v` as the stepping API names it (`VARIABLE/id`: any design variable).
pub fn input_name(v: &FmuVariable) -> String {
    format!("VARIABLE/{}", v.variable)
}

/// The integrator `name` spells, as `mbfx run --integrator` does.
fn method(name: &str) -> Result<Method, String> {
    Ok(match name {
        "gstiff" => Method::Gstiff,
        "wstiff" => Method::Wstiff,
        "hht" => Method::Hht,
        "galpha" => Method::Galpha,
        "newmark" => Method::Newmark,
        "dopri853" => Method::Dopri853,
        _ => {
            return Err(format!(
                "{SETTINGS_FILE}: integrator {name:?} is not one mbfx has"
            ))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_settings_read_back_as_written_and_another_format_is_refused() {
        let s = FmuSettings {
            format: FORMAT,
            guid: "{0}".into(),
            model_identifier: "plant".into(),
            integrator: Some("hht".into()),
            error: Some(1e-5),
            variables: vec![FmuVariable {
                name: "u".into(),
                reference: 0,
                input: true,
                variable: 1,
                start: 0.25,
            }],
        };
        assert_eq!(FmuSettings::parse(&s.to_text()), Ok(s.clone()));
        let other = s.to_text().replace("format = 1", "format = 2");
        let e = FmuSettings::parse(&other).unwrap_err();
        assert!(e.contains("format 2"), "{e}");
    }
}
