//! The KINEMATICS statement read into typed settings, as [`super::equilibrium_settings`]
//! reads EQUILIBRIUM: HMAX (the largest step of a kinematic analysis) and ERROR (how far
//! its prediction may miss the solved positions), each checked where it is written
//! (`E0605` at the value). What Adams' kinematic solver also takes and mbfx does not
//! honour (MAXIT, ALIMIT, TLIMIT, AERROR, AMAXIT, PATTERN, APATTERN) is a `W0602`
//! warning at the argument. The kinematic analysis (`mbd::kinematics`) takes the
//! values through the session.

use super::integrator_settings::{real, unhonoured_arguments, Given};
use super::stmt_args::Args;
use crate::diag::Diagnostic;

/// A KINEMATICS statement, typed. `None`: not written (Adams' default, or an earlier
/// statement's value, applies).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct KinematicsStatement {
    /// HMAX: the largest step.
    pub hmax: Option<Given<f64>>,
    /// ERROR: the largest miss of a step's prediction (translations relative to the model
    /// length, rotations in radians).
    pub error: Option<Given<f64>>,
    /// The `W0602` warnings about what is not honoured (also among the reader's
    /// diagnostics).
    pub warnings: Vec<Diagnostic>,
}

/// Arguments of Adams' KINEMATICS that mbfx reads but does not honour, with why.
const UNHONOURED: [(&str, usize, &str); 7] = [
    (
        "MAXIT",
        3,
        "Newton runs to rounding, and a step that does not converge is halved",
    ),
    (
        "ALIMIT",
        3,
        "a step turns no part by more than 30 degrees, and Newton's corrections are not limited",
    ),
    ("TLIMIT", 3, "Newton's corrections are not limited"),
    (
        "AERROR",
        3,
        "accelerations are solved directly from one linear system",
    ),
    (
        "AMAXIT",
        3,
        "accelerations are solved directly from one linear system",
    ),
    ("PATTERN", 3, "the Jacobian is evaluated at every iteration"),
    (
        "APATTERN",
        3,
        "accelerations are solved directly from one linear system",
    ),
];

/// Reads the arguments of a KINEMATICS statement; errors and warnings go to `a.diags`
/// (unknown arguments are left for `Args::finish` to report).
pub fn read_kinematics(a: &mut Args) -> KinematicsStatement {
    let positive = |x: f64| x > 0.0;
    let mut s = KinematicsStatement {
        hmax: real(a, "HMAX", 3, positive, "a positive step"),
        error: real(a, "ERROR", 3, positive, "a positive tolerance"),
        warnings: Vec::new(),
    };
    s.warnings = unhonoured_arguments(a, "KINEMATICS", &UNHONOURED);
    s
}

impl KinematicsStatement {
    /// A second statement after this one: its values over this one's, the warnings of
    /// both kept.
    pub fn then(self, later: KinematicsStatement) -> KinematicsStatement {
        KinematicsStatement {
            hmax: later.hmax.or(self.hmax),
            error: later.error.or(self.error),
            warnings: [self.warnings, later.warnings].concat(),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::model::read_model;

    #[test]
    fn hmax_and_error_are_read() {
        let r = read_model("t\nPART/1, GROUND\nKINEMATICS/HMAX = 0.01, ERROR = 1e-6\nEND\n");
        assert!(!r.has_errors(), "{:?}", r.diagnostics);
        let s = r.model.kinematics.expect("the statement");
        assert_eq!(s.hmax.map(|g| g.value), Some(0.01));
        assert_eq!(s.error.map(|g| g.value), Some(1e-6));
    }

    #[test]
    fn bad_values_are_errors_at_the_value_and_maxit_a_warning() {
        let text = "t\nPART/1, GROUND\nKINEMATICS/HMAX = -1, ERROR = 0, MAXIT = 10\nEND\n";
        let r = read_model(text);
        let errors: Vec<&str> = r
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| &text[d.span.clone()])
            .collect();
        assert_eq!(errors, ["-1", "0"]);
        assert!(r
            .diagnostics
            .iter()
            .any(|d| !d.is_error() && d.message.contains("KINEMATICS/MAXIT")));
    }
}
