//! How a dimension reads in a message: its name where it has one ("a velocity") and its
//! unit in the dataset's UNITS ("millimeter/second"), e.g. "a velocity
//! (millimeter/second)", "a force (newton)", "a torque (newton-millimeter)".
//!
//! A dimension with mass is written with the force unit when that is shorter (a
//! stiffness is newton/meter, not kilogram/second^2): datasets name a force unit, and
//! Adams's UCF keeps it apart from mass·length/time².

use super::dim::{reduce, Base, Dim};
use std::borrow::Cow;

/// The names of a dataset's units, lower case (`newton`, `kilogram`, `millimeter`,
/// `second`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnitNames {
    /// The force unit.
    pub force: Cow<'static, str>,
    /// The mass unit.
    pub mass: Cow<'static, str>,
    /// The length unit.
    pub length: Cow<'static, str>,
    /// The time unit.
    pub time: Cow<'static, str>,
}

impl UnitNames {
    /// SI: newton, kilogram, meter, second (a dataset without UNITS).
    pub const SI: UnitNames = UnitNames {
        force: Cow::Borrowed("newton"),
        mass: Cow::Borrowed("kilogram"),
        length: Cow::Borrowed("meter"),
        time: Cow::Borrowed("second"),
    };

    /// Names as a dataset writes them (any case); a name left out is the SI one.
    pub fn from_dataset(
        force: Option<&str>,
        mass: Option<&str>,
        length: Option<&str>,
        time: Option<&str>,
    ) -> UnitNames {
        let name = |n: Option<&str>, si: Cow<'static, str>| {
            n.map_or(si, |n| Cow::Owned(n.to_ascii_lowercase()))
        };
        let si = UnitNames::SI;
        UnitNames {
            force: name(force, si.force),
            mass: name(mass, si.mass),
            length: name(length, si.length),
            time: name(time, si.time),
        }
    }
}

/// Dimensions with a name, with the article they take.
pub(super) const NAMED: &[(Dim, &str)] = &[
    (Dim::NONE, "a dimensionless quantity"),
    (Dim::LENGTH, "a length"),
    (Dim::of(0, 2, 0, 0), "an area"),
    (Dim::of(0, 3, 0, 0), "a volume"),
    (Dim::TIME, "a time"),
    (Dim::of(0, 0, -1, 0), "a frequency"),
    (Dim::VELOCITY, "a velocity"),
    (Dim::ACCELERATION, "an acceleration"),
    (Dim::MASS, "a mass"),
    (Dim::FORCE, "a force"),
    (Dim::TORQUE, "a torque"),
    (Dim::ANGLE, "an angle"),
    (Dim::ANGULAR_VELOCITY, "an angular velocity"),
    (Dim::ANGULAR_ACCELERATION, "an angular acceleration"),
    (Dim::of(1, 0, -2, 0), "a stiffness"),
    (Dim::of(1, 0, -1, 0), "a damping coefficient"),
    (Dim::of(1, 2, -2, -1), "a torsional stiffness"),
    (Dim::of(1, 2, -1, -1), "a torsional damping coefficient"),
    (Dim::of(1, 1, -1, 0), "a momentum"),
    (Dim::of(1, -1, -2, 0), "a pressure"),
    (Dim::of(1, 2, -3, 0), "a power"),
    (Dim::of(1, 2, 0, 0), "a moment of inertia"),
];

/// "a velocity (millimeter/second)"; without unit names "a velocity (length/time)"; a
/// dimension without a name "a quantity in meter^2/second".
pub fn describe(d: Dim, names: Option<&UnitNames>) -> String {
    let unit = unit(d, names);
    match NAMED.iter().find(|(n, _)| *n == d) {
        // Without unit names a base is its own unit: "a length", not "a length (length)".
        Some((_, name)) if unit.is_empty() || name.ends_with(unit.as_str()) => (*name).to_string(),
        Some((_, name)) => format!("{name} ({unit})"),
        None => format!("a quantity in {unit}"),
    }
}

/// The unit of `d` from the unit names ("newton-meter", "meter/second^2", "radian"), or
/// from the names of the bases without them ("length/time"); empty for dimensionless.
pub fn unit(d: Dim, names: Option<&UnitNames>) -> String {
    let [m, l, t, a] = Base::ALL.map(|b| d.raw(b));
    // With force F = M·L·T⁻²: M^m L^l T^t = F^m L^(l−m) T^(t+2m).
    let with_force = [m, l - m, t + 2 * m];
    let size = |e: &[i32]| e.iter().map(|x| x.unsigned_abs() as u64).sum::<u64>();
    let use_force = m != 0 && size(&with_force) <= size(&[m, l, t]);
    let label = |base: &'static str, unit: Option<&Cow<'static, str>>| match unit {
        Some(u) => u.to_string(),
        None => base.to_string(),
    };
    let n = names;
    let factors: [(String, i32); 4] = if use_force {
        [
            (label("force", n.map(|n| &n.force)), with_force[0]),
            (label("length", n.map(|n| &n.length)), with_force[1]),
            (label("time", n.map(|n| &n.time)), with_force[2]),
            (label("angle", n.map(|_| &RADIAN)), a),
        ]
    } else {
        [
            (label("mass", n.map(|n| &n.mass)), m),
            (label("length", n.map(|n| &n.length)), l),
            (label("time", n.map(|n| &n.time)), t),
            (label("angle", n.map(|_| &RADIAN)), a),
        ]
    };
    let side = |positive: bool| {
        let parts: Vec<String> = factors
            .iter()
            .filter(|(_, e)| (*e > 0) == positive && *e != 0)
            .map(|(name, e)| power(name, e.abs()))
            .collect();
        parts.join("-")
    };
    let (num, den) = (side(true), side(false));
    match (num.is_empty(), den.is_empty()) {
        (_, true) => num,
        (true, false) => format!("1/{den}"),
        (false, false) => format!("{num}/{den}"),
    }
}

const RADIAN: Cow<'static, str> = Cow::Borrowed("radian");

/// `name`, `name^2` or `name^(1/2)` for an exponent in units of 1/DEN.
fn power(name: &str, e: i32) -> String {
    match reduce(e) {
        (1, 1) => name.to_string(),
        (n, 1) => format!("{name}^{n}"),
        (n, d) => format!("{name}^({n}/{d})"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mmks() -> UnitNames {
        UnitNames::from_dataset(Some("NEWTON"), Some("KILOGRAM"), Some("MILLIMETER"), None)
    }

    #[test]
    fn named_dimensions_read_with_the_dataset_units() {
        let n = mmks();
        assert_eq!(describe(Dim::LENGTH, Some(&n)), "a length (millimeter)");
        assert_eq!(
            describe(Dim::VELOCITY, Some(&n)),
            "a velocity (millimeter/second)"
        );
        assert_eq!(describe(Dim::FORCE, Some(&n)), "a force (newton)");
        assert_eq!(
            describe(Dim::TORQUE, Some(&n)),
            "a torque (newton-millimeter)"
        );
        assert_eq!(describe(Dim::ANGLE, Some(&n)), "an angle (radian)");
        assert_eq!(
            describe(Dim::ANGULAR_VELOCITY, Some(&n)),
            "an angular velocity (radian/second)"
        );
        assert_eq!(
            describe(Dim::ACCELERATION, Some(&n)),
            "an acceleration (millimeter/second^2)"
        );
        assert_eq!(describe(Dim::MASS, Some(&n)), "a mass (kilogram)");
        assert_eq!(
            describe(Dim::of(1, 0, -2, 0), Some(&n)),
            "a stiffness (newton/millimeter)"
        );
        assert_eq!(describe(Dim::NONE, Some(&n)), "a dimensionless quantity");
    }

    #[test]
    fn without_unit_names_the_bases_are_named() {
        assert_eq!(describe(Dim::VELOCITY, None), "a velocity (length/time)");
        assert_eq!(describe(Dim::of(0, 0, -1, 0), None), "a frequency (1/time)");
        assert_eq!(describe(Dim::LENGTH, None), "a length");
        assert_eq!(describe(Dim::ANGLE, None), "an angle");
    }

    #[test]
    fn unnamed_and_fractional_dimensions_show_their_unit() {
        let half = Dim::LENGTH.pow(0.5).expect("on the grid");
        assert_eq!(
            describe(half, Some(&UnitNames::SI)),
            "a quantity in meter^(1/2)"
        );
        let d = Dim::of(0, 2, -1, 0);
        assert_eq!(
            describe(d, Some(&UnitNames::SI)),
            "a quantity in meter^2/second"
        );
    }
}
