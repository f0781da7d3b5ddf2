//! The dimension of each measure of the language (spec §6): what a DX, a WZ or an
//! `SFORCE(id, jflag, comp, rm)` returns, in the dataset's UNITS.
//!
//! Measures whose value is a user's number (ARYVAL, DIF, PINVAL, SENVAL, ...) and those
//! whose meaning is not established (ORIENT) have no fixed dimension: they are free like
//! a number. VARVAL takes its VARIABLE's dimension, which only the model knows (see
//! [`crate::check::Scope::varval_dim`]).

use super::dim::Dim;
use crate::vocab::builtins::{Builtin, BUILTINS};
use std::sync::OnceLock;

/// What a measure's dimension depends on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// Always this dimension.
    Fixed(Dim),
    /// `NAME(id, jflag, comp, rm)`: a force for comp 1 to 4, a torque for 5 to 8.
    Component,
    /// VARVAL: its VARIABLE's.
    Variable,
    /// None of its own (a user's number, or meaning not established).
    Free,
}

/// The [`Kind`] of a measure of the builtins table, from a table built once (the units
/// check asks for every measure call it meets; comparing names each time would cost).
pub fn kind(b: &'static Builtin) -> Kind {
    static KINDS: OnceLock<Vec<Kind>> = OnceLock::new();
    let kinds = KINDS.get_or_init(|| BUILTINS.iter().map(|b| kind_of(b.name)).collect());
    // `b` is an element of BUILTINS: its index is its offset.
    let offset = (b as *const Builtin as usize).wrapping_sub(BUILTINS.as_ptr() as usize);
    let index = offset / std::mem::size_of::<Builtin>();
    match kinds.get(index) {
        Some(k) if std::ptr::eq(&BUILTINS[index], b) => *k,
        _ => kind_of(b.name),
    }
}

/// The dimension of component `comp` of an element's force, `NAME(id, jflag, comp, rm)`:
/// 1 to 4 a force, 5 to 8 a torque (spec §6.8).
pub fn component(comp: i64) -> Option<Dim> {
    match comp {
        1..=4 => Some(Dim::FORCE),
        5..=8 => Some(Dim::TORQUE),
        // CONTACT's own: normal and friction force, penetration, slip speed.
        9 | 10 => Some(Dim::FORCE),
        11 => Some(Dim::LENGTH),
        12 => Some(Dim::VELOCITY),
        _ => None,
    }
}

/// The kind of the measure `name` (upper case).
fn kind_of(name: &str) -> Kind {
    Kind::Fixed(match name {
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
        "SFORCE" | "VFORCE" | "VTORQ" | "GFORCE" | "BUSH" | "BEAM" | "FIELD" | "FRICTION"
        | "SPDP" | "NFORCE" | "JOINT" | "JPRIM" | "MOTION" | "CVCV" | "PTCV" | "CONTACT" => {
            return Kind::Component;
        }
        "VARVAL" => return Kind::Variable,
        _ => return Kind::Free,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vocab::builtins::Role;

    fn of(name: &str) -> Kind {
        kind(crate::vocab::builtins::lookup(name).expect("a builtin"))
    }

    #[test]
    fn element_force_components_are_forces_then_torques() {
        assert_eq!(component(1), Some(Dim::FORCE));
        assert_eq!(component(4), Some(Dim::FORCE));
        assert_eq!(component(5), Some(Dim::TORQUE));
        assert_eq!(component(8), Some(Dim::TORQUE));
        // CONTACT's own components: normal and friction force, penetration, slip speed.
        assert_eq!(component(9), Some(Dim::FORCE));
        assert_eq!(component(11), Some(Dim::LENGTH));
        assert_eq!(component(12), Some(Dim::VELOCITY));
        assert_eq!(component(13), None);
        assert_eq!(of("JOINT"), Kind::Component);
        assert_eq!(of("DZ"), Kind::Fixed(Dim::LENGTH));
        assert_eq!(of("VARVAL"), Kind::Variable);
    }

    /// Every measure is in the catalogue or deliberately free: a new measure in the
    /// builtins table must be placed here.
    #[test]
    fn every_measure_is_classified() {
        const FREE: &[&str] = &[
            "ARYVAL", "DIF", "DIF1", "ORIENT", "PINVAL", "POUVAL", "SENVAL", "VARVAL",
        ];
        for b in BUILTINS {
            if matches!(b.role, Role::Measure(_)) {
                let free = matches!(kind(b), Kind::Free | Kind::Variable);
                assert_eq!(free, FREE.contains(&b.name), "{}", b.name);
            }
        }
    }
}
