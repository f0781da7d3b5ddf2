//! The one place the FMU meets mbfx's stepping API (`mbfx::session::stepping`): a
//! [`Plant`] is the dataset opened for stepping with the FMU's settings, its inputs and
//! outputs addressed by their position in the settings' lists.

use mbfx::session::fmu_settings::FmuSettings;

/// A dataset opened for stepping.
pub struct Plant {
    _never: std::convert::Infallible,
}

/// A snapshot of a [`Plant`] (`fmi2GetFMUstate`).
pub struct Snapshot {
    _never: std::convert::Infallible,
}

impl Plant {
    /// Opens `dataset` (named `name` in messages) with `settings`, ERROR `error` when given.
    pub fn open(
        _dataset: &str,
        _name: &str,
        _settings: &FmuSettings,
        _error: Option<f64>,
    ) -> Result<Plant, String> {
        Err("the stepping API is not in this build".into())
    }

    /// The model time.
    pub fn time(&self) -> f64 {
        match self._never {}
    }

    /// Integrates to `t`.
    pub fn advance(&mut self, _t: f64) -> Result<(), String> {
        match self._never {}
    }

    /// Sets input `i` (its position among the settings' inputs), holding from now on.
    pub fn set_input(&mut self, _i: usize, _value: f64) -> Result<(), String> {
        match self._never {}
    }

    /// Output `i` (its position among the settings' outputs) at the current time.
    pub fn output(&self, _i: usize) -> f64 {
        match self._never {}
    }

    /// A snapshot to come back to.
    pub fn snapshot(&self) -> Snapshot {
        match self._never {}
    }

    /// Back to `snapshot`.
    pub fn restore(&mut self, _snapshot: &Snapshot) -> Result<(), String> {
        match self._never {}
    }
}
