//! One FMU instance, as safe Rust: the FMI 2.0 co-simulation state machine (instantiated,
//! initialization mode, stepping, terminated, error) over a [`Plant`], the values set for
//! its inputs, and the experiment's settings. The C entry points (`entry`, `cosim`) check
//! their pointers and call these methods; every refusal is an `Err` with the message the
//! importer's logger gets.

use crate::adapter::{Plant, PlantState};
use mbfx::session::fmu_settings::{FmuSettings, DATASET_FILE};

/// Where the instance is in the standard's state machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// After `fmi2Instantiate` or `fmi2Reset`: inputs may be set, the experiment set up.
    Instantiated,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    Initialization,
    /// Stepping (`fmi2DoStep`).
    Stepping,
    /// After `fmi2Terminate`: values may be read.
    Terminated,
    /// After a failed step or an internal error: values may be read, then `fmi2Reset`.
    Error,
}

/// A variable of the FMU, by value reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Port {
    /// The `i`-th input.
    Input(usize),
    /// The `i`-th output.
    Output(usize),
}

/// One instance of the FMU.
pub struct Instance {
    /// The settings from `resources/settings.toml`.
    settings: FmuSettings,
    /// The dataset's text from `resources/model.adm`.
    dataset: String,
    /// The port of each value reference (the settings' variables, in order).
    ports: Vec<Port>,
    /// The inputs' values as last set (their start values at first).
    inputs: Vec<f64>,
    /// The model, from `fmi2EnterInitializationMode` on.
    plant: Option<Plant>,
    /// `fmi2SetupExperiment`'s tolerance, when defined: the run's ERROR.
    tolerance: Option<f64>,
    /// `fmi2SetupExperiment`'s stop time, when defined.
    stop_time: Option<f64>,
    /// Where the instance is.
    pub phase: Phase,
}

/// A snapshot of an instance (`fmi2GetFMUstate`).
pub struct State {
    plant: PlantState,
    inputs: Vec<f64>,
    phase: Phase,
}

impl Instance {
    /// An instance of the FMU whose settings and dataset are `settings` and `dataset`,
    /// for an importer that expects the GUID `guid`.
    pub fn new(settings: FmuSettings, dataset: String, guid: &str) -> Result<Instance, String> {
        if guid != settings.guid {
            return Err(format!(
                "the GUID {guid} is not this FMU's ({}): the modelDescription.xml and the \
                 resources come from different exports",
                settings.guid
            ));
        }
        let mut ports = Vec::with_capacity(settings.variables.len());
        let (mut inputs, mut outputs) = (0, 0);
        for (k, v) in settings.variables.iter().enumerate() {
            if v.reference as usize != k {
                return Err(format!(
                    "settings.toml: variable {} has value reference {}, expected {k}",
                    v.name, v.reference
                ));
            }
            ports.push(match v.input {
                true => Port::Input(inputs),
                false => Port::Output(outputs),
            });
            (inputs, outputs) = if v.input {
                (inputs + 1, outputs)
            } else {
                (inputs, outputs + 1)
            };
        }
        let mut instance = Instance {
            inputs: Vec::new(),
            settings,
            dataset,
            ports,
            plant: None,
            tolerance: None,
            stop_time: None,
            phase: Phase::Instantiated,
        };
        instance.reset();
        Ok(instance)
    }

    /// `fmi2Reset`: back to just instantiated, the inputs at their start values.
    pub fn reset(&mut self) {
        self.inputs = self.settings.inputs().map(|v| v.start).collect();
        (self.plant, self.tolerance, self.stop_time) = (None, None, None);
        self.phase = Phase::Instantiated;
    }

    /// `fmi2SetupExperiment`.
    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<(), String> {
        self.expect(&[Phase::Instantiated], "fmi2SetupExperiment")?;
        if start_time != 0.0 {
            return Err(format!(
                "startTime = {start_time}: an Adams dataset's time starts at 0, so must the experiment"
            ));
        }
        if let Some(t) = tolerance.filter(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(format!("tolerance = {t} must be a positive number"));
        }
        if let Some(t) = stop_time.filter(|t| t.is_nan() || *t < 0.0) {
            return Err(format!("stopTime = {t} must not be negative"));
        }
        (self.tolerance, self.stop_time) = (tolerance, stop_time);
        Ok(())
    }

    /// `fmi2EnterInitializationMode`: the dataset is built, the inputs set on it.
    pub fn enter_initialization(&mut self) -> Result<(), String> {
        self.expect(&[Phase::Instantiated], "fmi2EnterInitializationMode")?;
        let name = format!("resources/{DATASET_FILE}");
        let mut plant = Plant::open(&self.dataset, &name, &self.settings, self.tolerance)?;
        for (i, &v) in self.inputs.iter().enumerate() {
            plant.set_input(i, v)?;
        }
        self.plant = Some(plant);
        self.phase = Phase::Initialization;
        Ok(())
    }

    /// `fmi2ExitInitializationMode`.
    pub fn exit_initialization(&mut self) -> Result<(), String> {
        self.expect(&[Phase::Initialization], "fmi2ExitInitializationMode")?;
        self.phase = Phase::Stepping;
        Ok(())
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> Result<(), String> {
        self.expect(&[Phase::Stepping], "fmi2Terminate")?;
        self.phase = Phase::Terminated;
        Ok(())
    }

    /// `fmi2DoStep`: integrates from `t` (which must be the model's time) to `t + h`.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), String> {
        self.expect(&[Phase::Stepping], "fmi2DoStep")?;
        let stop_time = self.stop_time;
        let plant = self.plant_mut()?;
        let now = plant.time();
        if !(h >= 0.0 && h.is_finite()) {
            return Err(format!(
                "communicationStepSize = {h} must be a positive number"
            ));
        }
        // The importer's time may be a sum of steps, a few ulps off the model's.
        let at_now = (t - now).abs() <= 1e-9 * now.abs().max(h).max(1e-300);
        if !at_now {
            return Err(format!(
                "currentCommunicationPoint = {t} is not the model's time {now}: restore a \
                 state (fmi2SetFMUstate) to step from an earlier time"
            ));
        }
        // The step ends where the importer's clock says, t + h: a master that counts its
        // time as k·h lands on the same times as a stepping loop in Python or C that
        // advances to t + h.
        let to = t + h;
        if let Some(stop) = stop_time.filter(|&s| to > s * (1.0 + 1e-12) + 1e-300) {
            return Err(format!(
                "a step to {to} passes the stopTime {stop} of fmi2SetupExperiment"
            ));
        }
        if h == 0.0 {
            return Ok(());
        }
        let advanced = plant.advance(to);
        if advanced.is_err() {
            self.phase = Phase::Error;
        }
        advanced
    }

    /// The model time (the last communication point reached), or 0 before initialization.
    pub fn time(&self) -> f64 {
        self.plant.as_ref().map_or(0.0, Plant::time)
    }

    /// `fmi2GetReal`: the value of each of `refs` into `values`.
    pub fn get_real(&self, refs: &[u32], values: &mut [f64]) -> Result<(), String> {
        for (r, out) in refs.iter().zip(values.iter_mut()) {
            *out = match self.port(*r)? {
                Port::Input(i) => self.inputs[i],
                Port::Output(i) => match (&self.plant, self.phase) {
                    (Some(p), _) => p.output(i),
                    (None, _) => {
                        return Err(format!(
                            "output {} has no value before fmi2EnterInitializationMode",
                            self.name(*r)
                        ))
                    }
                },
            };
        }
        Ok(())
    }

    /// `fmi2SetReal`: sets inputs, which hold from the current time.
    pub fn set_real(&mut self, refs: &[u32], values: &[f64]) -> Result<(), String> {
        self.expect(
            &[Phase::Instantiated, Phase::Initialization, Phase::Stepping],
            "fmi2SetReal",
        )?;
        for (&r, &v) in refs.iter().zip(values) {
            let Port::Input(i) = self.port(r)? else {
                return Err(format!(
                    "{} is an output: only inputs can be set",
                    self.name(r)
                ));
            };
            if !v.is_finite() {
                return Err(format!("{} = {v}: an input must be finite", self.name(r)));
            }
            if let Some(p) = self.plant.as_mut() {
                p.set_input(i, v)?;
            }
            self.inputs[i] = v;
        }
        Ok(())
    }

    /// `fmi2GetFMUstate`: a snapshot of the model and the inputs.
    pub fn state(&self) -> Result<State, String> {
        let plant = self.plant.as_ref().ok_or_else(|| {
            "fmi2GetFMUstate: there is no state before fmi2EnterInitializationMode".to_string()
        })?;
        Ok(State {
            plant: plant.snapshot(),
            inputs: self.inputs.clone(),
            phase: self.phase,
        })
    }

    /// `fmi2SetFMUstate`: back to `state`.
    pub fn restore(&mut self, state: &State) -> Result<(), String> {
        let plant = self.plant_mut()?;
        plant.restore(&state.plant)?;
        for (i, &v) in state.inputs.iter().enumerate() {
            plant.set_input(i, v)?;
        }
        self.inputs.clone_from(&state.inputs);
        self.phase = state.phase;
        Ok(())
    }

    fn plant_mut(&mut self) -> Result<&mut Plant, String> {
        self.plant
            .as_mut()
            .ok_or_else(|| "the model is not initialized: call fmi2EnterInitializationMode".into())
    }

    fn port(&self, r: u32) -> Result<Port, String> {
        self.ports.get(r as usize).copied().ok_or_else(|| {
            format!(
                "value reference {r} is not a variable of this FMU (it has 0 to {})",
                self.ports.len().saturating_sub(1)
            )
        })
    }

    fn name(&self, r: u32) -> &str {
        self.settings
            .variables
            .get(r as usize)
            .map_or("?", |v| v.name.as_str())
    }

    /// Refuses a call made in a phase the standard does not allow it in.
    fn expect(&self, allowed: &[Phase], call: &str) -> Result<(), String> {
        match allowed.contains(&self.phase) {
            true => Ok(()),
            false => Err(format!(
                "{call} is not allowed now (the instance is {}){}",
                describe(self.phase),
                match self.phase {
                    Phase::Error => ": call fmi2Reset",
                    _ => "",
                }
            )),
        }
    }
}

fn describe(phase: Phase) -> &'static str {
    match phase {
        Phase::Instantiated => "instantiated, not initialized",
        Phase::Initialization => "in initialization mode",
        Phase::Stepping => "stepping",
        Phase::Terminated => "terminated",
        Phase::Error => "in error after a failed call",
    }
}
