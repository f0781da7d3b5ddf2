//! The dimension of each measure of the language (spec §6): what a DX, a WZ or an
//! `SFORCE(id, jflag, comp, rm)` returns, in the dataset's UNITS.
//!
//! Measures whose value is a user's number (ARYVAL, DIF, PINVAL, SENVAL, ...) and those
//! whose meaning is not established (ORIENT) have no fixed dimension: they are free like
//! a number. VARVAL takes its VARIABLE's dimension, which only the model knows (see
//! [`crate::check::Scope::varval_dim`]).

use super::dim::Dim;

/// The dimension of the measure `name` (upper case) called with the integer arguments
/// `ids`; `None` when it has none of its own.
pub fn dimension(name: &str, ids: &[Option<i64>]) -> Option<Dim> {
    Some(match name {
        "DX" | "DY" | "DZ" | "DM" | "DXYZ" => Dim::LENGTH,
        "AX" | "AY" | "AZ" | "PSI" | "THETA" | "PHI" | "YAW" | "PITCH" | "ROLL" | "INCANG" => {
            Dim::ANGLE
        }
        // Unit vectors: direction cosines.
        "UVX" | "UVY" | "UVZ" => Dim::NONE,
        "VX" | "VY" | "VZ" | "VM" | "VR" | "VXYZ" => Dim::VELOCITY,
        "WX" | "WY" | "WZ" | "WM" | "WXYZ" => Dim::ANGULAR_VELOCITY,
        "ACCX" | "ACCY" | "ACCZ" | "ACCM" | "ACCXYZ" => Dim::ACCELERATION,
        "WDTX" | "WDTY" | "WDTZ" | "WDTM" | "WDTXYZ" => Dim::ANGULAR_ACCELERATION,
        "FX" | "FY" | "FZ" | "FM" | "FXYZ" => Dim::FORCE,
        "TX" | "TY" | "TZ" | "TM" | "TXYZ" => Dim::TORQUE,
        // NAME(id, jflag, comp, rm): comp 1 to 4 a force, 5 to 8 a torque (spec §6.8).
        "SFORCE" | "VFORCE" | "VTORQ" | "GFORCE" | "BUSH" | "BEAM" | "FIELD" | "FRICTION"
        | "SPDP" | "NFORCE" | "JOINT" | "JPRIM" | "MOTION" | "CVCV" | "PTCV" => {
            match ids.get(2).copied().flatten()? {
                1..=4 => Dim::FORCE,
                5..=8 => Dim::TORQUE,
                _ => return None,
            }
        }
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vocab::builtins::{Role, BUILTINS};

    #[test]
    fn element_force_components_are_forces_then_torques() {
        let call = |comp| dimension("JOINT", &[Some(3), Some(0), Some(comp), Some(0)]);
        assert_eq!(call(1), Some(Dim::FORCE));
        assert_eq!(call(4), Some(Dim::FORCE));
        assert_eq!(call(5), Some(Dim::TORQUE));
        assert_eq!(call(8), Some(Dim::TORQUE));
        assert_eq!(dimension("SFORCE", &[Some(1), Some(0)]), None);
    }

    /// Every measure is in the catalogue or deliberately free: a new measure in the
    /// builtins table must be placed here.
    #[test]
    fn every_measure_is_classified() {
        const FREE: &[&str] = &[
            "ARYVAL", "DIF", "DIF1", "ORIENT", "PINVAL", "POUVAL", "SENVAL", "VARVAL",
        ];
        let comp = [Some(1), Some(0), Some(2), Some(0)];
        for b in BUILTINS {
            if matches!(b.role, Role::Measure(_)) {
                let d = dimension(b.name, &comp);
                assert_eq!(d.is_none(), FREE.contains(&b.name), "{}", b.name);
            }
        }
    }
}
