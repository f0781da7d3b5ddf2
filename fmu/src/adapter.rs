//! The one place the FMU meets mbfx's stepping API ([`mbfx::session::stepping`]): a
//! [`Plant`] is the dataset opened for stepping with the FMU's settings, its inputs and
//! outputs addressed by their position in the settings' lists.
//!
//! Inputs are set as `VARIABLE/id` (any design variable, PINPUT or not). Each output is
//! read from the stepping's POUTPUT column of its VARIABLE when it has one, so the FMU
//! gives the bits a stepping loop in Python or C reads; an output the dataset's POUTPUT
//! does not list is a probe `VARVAL(id)`. No END is given: HMAX and HINIT follow the
//! first communication step, as a stepping without an output step does.

use mbfx::session::fmu_settings::{input_name, FmuSettings};
use mbfx::session::stepping::{Snapshot, Stepping};

/// A dataset opened for stepping.
pub struct Plant {
    stepping: Stepping,
    /// Each input's name as the stepping takes it (`VARIABLE/id`).
    inputs: Vec<String>,
    /// Each output's column among the stepping's outputs.
    outputs: Vec<usize>,
}

/// A snapshot of a [`Plant`] (`fmi2GetFMUstate`).
pub struct PlantState(Snapshot);

/// The probe of an output the POUTPUT columns may lack.
fn probe_name(reference: u32) -> String {
    format!("fmu output {reference}")
}

impl Plant {
    /// Opens `dataset` (named `name` in messages) with `settings`, ERROR `error` when
    /// given (else the settings').
    pub fn open(
        dataset: &str,
        name: &str,
        settings: &FmuSettings,
        error: Option<f64>,
    ) -> Result<Plant, String> {
        let mut request = settings.request(name, dataset, error)?;
        request.probes = settings
            .outputs()
            .map(|v| (probe_name(v.reference), format!("VARVAL({})", v.variable)))
            .collect();
        let stepping = Stepping::new(&request).map_err(|f| f.cause)?;
        let names = stepping.output_names();
        let column = |wanted: &str| names.iter().position(|n| n == wanted);
        let outputs = settings
            .outputs()
            .map(|v| {
                column(&v.name)
                    .or_else(|| column(&format!("VARIABLE/{}", v.variable)))
                    .or_else(|| column(&probe_name(v.reference)))
                    .ok_or_else(|| format!("output {} is not among the stepping's", v.name))
            })
            .collect::<Result<_, _>>()?;
        Ok(Plant {
            inputs: settings.inputs().map(input_name).collect(),
            stepping,
            outputs,
        })
    }

    /// The model time.
    pub fn time(&self) -> f64 {
        self.stepping.time()
    }

    /// Integrates to `t`; a failure is worded as `mbfx run` words it.
    pub fn advance(&mut self, t: f64) -> Result<(), String> {
        self.stepping.advance(t).map_err(|e| {
            let f = self.stepping.failure(e);
            match (f.time, &f.element) {
                (Some(t), Some(el)) => format!("at t = {t}, {el}: {}", f.cause),
                (Some(t), None) => format!("at t = {t}: {}", f.cause),
                _ => f.cause,
            }
        })
    }

    /// Sets input `i` (its position among the settings' inputs), holding from now on.
    pub fn set_input(&mut self, i: usize, value: f64) -> Result<(), String> {
        let name = self.inputs.get(i).ok_or("no such input")?;
        self.stepping.set_input(name, value)
    }

    /// Output `i` (its position among the settings' outputs) at the current time.
    pub fn output(&self, i: usize) -> f64 {
        self.outputs
            .get(i)
            .and_then(|&k| self.stepping.outputs().get(k))
            .copied()
            .unwrap_or(f64::NAN)
    }

    /// A snapshot to come back to.
    pub fn snapshot(&self) -> PlantState {
        PlantState(self.stepping.state())
    }

    /// Back to `snapshot` (a failure to start again there comes with the next advance).
    pub fn restore(&mut self, snapshot: &PlantState) -> Result<(), String> {
        self.stepping.restore(&snapshot.0);
        Ok(())
    }
}
