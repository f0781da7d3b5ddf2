//! The EQUILIBRIUM statement (in a dataset) and command (in a command file) read into
//! typed settings, as [`super::integrator_settings`] reads INTEGRATOR: ERROR, IMBALANCE,
//! MAXIT, STABILITY, TLIMIT and ALIMIT (`10D` in degrees, or radians), each checked
//! where it is written (`E0605` at the value). What Adams' static solver also takes and
//! mbfx does not honour (PATTERN, the DYNAMIC method and its settings, METHOD) is a
//! `W0602` warning at the argument. The static solver (`mbd::statics`) takes the
//! values through [`EquilibriumStatement::settings`], as [`EquilibriumSettings`].

use super::integrator_settings::{integer, real, single, unhonoured_arguments, Given};
use super::statement::ItemKind;
use super::stmt_args::Args;
use crate::diag::{Code, Diagnostic};

/// EQUILIBRIUM's settings as the static solver takes them (`mbd::statics::Settings`): the
/// values written, Adams Solver C++ defaults for the rest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EquilibriumSettings {
    /// ERROR: convergence needs every correction below it (translations relative to the
    /// model length, rotations in radians) and every constraint residual (scaled alike).
    pub error: f64,
    /// IMBALANCE: convergence needs every force (and torque) imbalance below it, model
    /// units.
    pub imbalance: f64,
    /// MAXIT: the most Newton iterations.
    pub maxit: usize,
    /// STABILITY: the fraction of the mass and damping matrices added to the Newton
    /// matrix (it keeps a direction without stiffness factorable).
    pub stability: f64,
    /// TLIMIT: the largest translation of any part in one iteration, model length units.
    pub tlimit: f64,
    /// ALIMIT: the largest rotation of any part in one iteration, radians.
    pub alimit: f64,
}

impl Default for EquilibriumSettings {
    fn default() -> Self {
        EquilibriumSettings {
            error: 1e-4,
            imbalance: 1e-4,
            maxit: 25,
            stability: 1e-5,
            tlimit: 20.0,
            alimit: 10f64.to_radians(),
        }
    }
}

/// An EQUILIBRIUM statement or command, typed. `None`: not written (Adams' default, or
/// an earlier statement's value, applies).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EquilibriumStatement {
    /// ERROR: the largest relative correction at convergence.
    pub error: Option<Given<f64>>,
    /// IMBALANCE: the largest force imbalance at convergence.
    pub imbalance: Option<Given<f64>>,
    /// MAXIT: the most Newton iterations.
    pub maxit: Option<Given<u32>>,
    /// STABILITY: the fraction of the mass and damping matrices added to the stiffness.
    pub stability: Option<Given<f64>>,
    /// TLIMIT: the largest translation per iteration (model length units).
    pub tlimit: Option<Given<f64>>,
    /// ALIMIT: the largest rotation per iteration, radians.
    pub alimit: Option<Given<f64>>,
    /// The `W0602` warnings about what is not honoured (also among the reader's
    /// diagnostics).
    pub warnings: Vec<Diagnostic>,
}

/// Arguments of Adams' EQUILIBRIUM that mbfx reads but does not honour, with why.
const UNHONOURED: [(&str, usize, &str); 8] = [
    ("PATTERN", 3, "the Jacobian is evaluated at every iteration"),
    (
        "DYNAMIC",
        3,
        "mbfx finds equilibrium by Newton on the static equations only",
    ),
    ("STATIC", 4, "it is the only method mbfx has"),
    ("GLOBAL_DAMPING", 3, "it belongs to the DYNAMIC method"),
    ("SETTLING_TIME", 3, "it belongs to the DYNAMIC method"),
    ("ACCELERATION_ERROR", 3, "it belongs to the DYNAMIC method"),
    (
        "KINETIC_ENERGY_ERROR",
        3,
        "it belongs to the DYNAMIC method",
    ),
    ("METHOD", 3, "mbfx has one static method"),
];

/// Reads the arguments of an EQUILIBRIUM statement or command; errors and warnings go
/// to `a.diags` (unknown arguments are left for `Args::finish` to report).
pub fn read_equilibrium(a: &mut Args) -> EquilibriumStatement {
    let positive = |x: f64| x > 0.0;
    let mut s = EquilibriumStatement {
        error: real(a, "ERROR", 3, positive, "a positive tolerance"),
        imbalance: real(a, "IMBALANCE", 3, positive, "a positive force"),
        maxit: integer(a, "MAXIT", 3, 1..=u32::MAX),
        stability: real(a, "STABILITY", 3, |x| x >= 0.0, "zero or positive"),
        tlimit: real(a, "TLIMIT", 3, positive, "a positive length"),
        alimit: angle(a, "ALIMIT", 3),
        warnings: Vec::new(),
    };
    s.warnings = unhonoured_arguments(a, "EQUILIBRIUM", &UNHONOURED);
    s
}

/// A positive angle: radians, or degrees with a `D`.
fn angle(a: &mut Args, full: &str, min: usize) -> Option<Given<f64>> {
    let arg = a.find(full, min)?;
    let item = single(a, arg, "one angle")?;
    let value = match item.kind {
        ItemKind::Number { .. } => item.as_f64(),
        _ => None,
    };
    match value {
        Some(v) if v > 0.0 && v.is_finite() => Some(Given {
            value: v,
            span: item.span.clone(),
        }),
        Some(v) if !v.is_finite() => None,
        _ => {
            let msg = format!("{full} = {} must be a positive angle", item.text);
            a.error(Code::BadArgument, item.span.clone(), msg);
            None
        }
    }
}

impl EquilibriumStatement {
    /// This statement with the values `later` writes put over it (a command changes what
    /// it names and keeps the rest).
    pub fn merged(&self, later: &EquilibriumStatement) -> EquilibriumStatement {
        fn pick<T: Clone>(a: &Option<Given<T>>, b: &Option<Given<T>>) -> Option<Given<T>> {
            b.clone().or_else(|| a.clone())
        }
        EquilibriumStatement {
            error: pick(&self.error, &later.error),
            imbalance: pick(&self.imbalance, &later.imbalance),
            maxit: pick(&self.maxit, &later.maxit),
            stability: pick(&self.stability, &later.stability),
            tlimit: pick(&self.tlimit, &later.tlimit),
            alimit: pick(&self.alimit, &later.alimit),
            warnings: Vec::new(),
        }
    }

    /// A second statement after this one: its values over this one's, the warnings of
    /// both kept.
    pub fn then(self, later: EquilibriumStatement) -> EquilibriumStatement {
        EquilibriumStatement {
            warnings: [self.warnings.clone(), later.warnings.clone()].concat(),
            ..self.merged(&later)
        }
    }

    /// The solver's settings: the values written, Adams' defaults for the rest.
    pub fn settings(&self) -> EquilibriumSettings {
        let d = EquilibriumSettings::default();
        let v = |g: &Option<Given<f64>>, x: f64| g.as_ref().map_or(x, |g| g.value);
        EquilibriumSettings {
            error: v(&self.error, d.error),
            imbalance: v(&self.imbalance, d.imbalance),
            maxit: self.maxit.as_ref().map_or(d.maxit, |m| m.value as usize),
            stability: v(&self.stability, d.stability),
            tlimit: v(&self.tlimit, d.tlimit),
            alimit: v(&self.alimit, d.alimit),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::model::read_model;

    #[test]
    fn values_are_read_and_defaults_fill_the_rest() {
        let r = read_model("t\nPART/1, GROUND\nEQUILIBRIUM/MAXIT = 40, TLIM = 0.5, ALIM = 2D, STAB = 0.1, IMB = 1e-6\nEND\n");
        assert!(!r.has_errors(), "{:?}", r.diagnostics);
        let s = r.model.equilibrium.expect("the statement").settings();
        assert_eq!(s.maxit, 40);
        assert_eq!((s.tlimit, s.stability, s.imbalance), (0.5, 0.1, 1e-6));
        assert!((s.alimit - 2f64.to_radians()).abs() < 1e-15);
        assert_eq!(s.error, 1e-4);
    }

    #[test]
    fn bad_values_are_errors_at_the_value_and_pattern_a_warning() {
        let text = "t\nPART/1, GROUND\nEQUILIBRIUM/MAXIT = 0, ALIMIT = -1, PATTERN = T:F\nEND\n";
        let r = read_model(text);
        let errors: Vec<&str> = r
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| &text[d.span.clone()])
            .collect();
        assert_eq!(errors, ["0", "-1"]);
        assert!(r
            .diagnostics
            .iter()
            .any(|d| !d.is_error() && d.message.contains("PATTERN")));
    }
}
