//! The FMI unit of a dimension the units checker inferred (`crate::check::units`): its
//! name as the checker's messages spell it in the dataset's UNITS ("newton",
//! "meter/second", "newton/millimeter") and its `BaseUnit`, the exponents of kg, m, s and
//! rad with the factor that turns one dataset unit into SI, so that a tool importing the
//! FMU can convert. Only whole exponents have a `BaseUnit` (FMI's are integers).

use crate::check::units::{self, Base, Dim, UnitNames};
use crate::model::elements::Units;
use crate::model::units::{si_value, Quantity};

/// One `<Unit>` of `UnitDefinitions`.
#[derive(Clone, Debug, PartialEq)]
pub struct FmiUnit {
    /// The unit's name, as the checker writes it (`newton/meter`); `1` for a
    /// dimensionless quantity.
    pub name: String,
    /// The exponents of kg, m, s and rad (FMI's `BaseUnit` attributes), zeros left out.
    pub exponents: Vec<(&'static str, i32)>,
    /// The value in SI of one unit of this name (`BaseUnit factor`).
    pub factor: f64,
}

/// The FMI unit of `dim` in the dataset's `units`; None when an exponent is not whole or
/// a unit name is not one mbfx knows the SI value of.
pub fn fmi_unit(dim: Dim, units: &Units) -> Option<FmiUnit> {
    let names = UnitNames::from_dataset(
        units.force.as_deref(),
        units.mass.as_deref(),
        units.length.as_deref(),
        units.time.as_deref(),
    );
    let whole = |b: Base| match dim.exponent(b) {
        (n, 1) => Some(n),
        _ => None,
    };
    let (m, l, t, a) = (
        whole(Base::Mass)?,
        whole(Base::Length)?,
        whole(Base::Time)?,
        whole(Base::Angle)?,
    );
    let si = |q: Quantity, name: &str| si_value(q, name);
    let (force, mass, length, time) = (
        si(Quantity::Force, &names.force)?,
        si(Quantity::Mass, &names.mass)?,
        si(Quantity::Length, &names.length)?,
        si(Quantity::Time, &names.time)?,
    );
    // The same choice `units::names::unit` makes for the name: a quantity with mass is
    // written with the force unit when that is shorter (F = M·L·T⁻²), and its factor must
    // be that name's, since with a UCF other than 1 the two differ.
    let with_force = [m, l - m, t + 2 * m];
    let size = |e: &[i32]| e.iter().map(|x| x.unsigned_abs()).sum::<u32>();
    let factor = if m != 0 && size(&with_force) <= size(&[m, l, t]) {
        force.powi(with_force[0]) * length.powi(with_force[1]) * time.powi(with_force[2])
    } else {
        mass.powi(m) * length.powi(l) * time.powi(t)
    };
    let name = units::names::unit(dim, Some(&names));
    let exponents = [("kg", m), ("m", l), ("s", t), ("rad", a)]
        .into_iter()
        .filter(|(_, e)| *e != 0)
        .collect();
    Some(FmiUnit {
        name: if name.is_empty() { "1".into() } else { name },
        exponents,
        factor,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn units(force: &str, mass: &str, length: &str, time: &str) -> Units {
        Units {
            force: Some(force.into()),
            mass: Some(mass.into()),
            length: Some(length.into()),
            time: Some(time.into()),
            ucf: 1.0,
        }
    }

    #[test]
    fn si_units_have_factor_one_and_the_si_exponents() {
        let si = Units::default();
        let f = fmi_unit(Dim::FORCE, &si).expect("a force");
        assert_eq!(f.name, "newton");
        assert_eq!(f.exponents, vec![("kg", 1), ("m", 1), ("s", -2)]);
        assert_eq!(f.factor, 1.0);
        let v = fmi_unit(Dim::VELOCITY, &si).expect("a velocity");
        assert_eq!((v.name.as_str(), v.factor), ("meter/second", 1.0));
        assert_eq!(fmi_unit(Dim::NONE, &si).expect("a ratio").name, "1");
    }

    #[test]
    fn a_stiffness_in_newton_per_millimeter_is_a_thousand_newton_per_meter() {
        // MMKS: N, kg, mm, s (UCF 1000): the stiffness is spelled with the force unit, so
        // its factor is 1 N / 1 mm = 1000 N/m, not 1 kg/s².
        let mmks = units("NEWTON", "KILOGRAM", "MILLIMETER", "SECOND");
        let k = fmi_unit(Dim::of(1, 0, -2, 0), &mmks).expect("a stiffness");
        assert_eq!(k.name, "newton/millimeter");
        assert_eq!(k.exponents, vec![("kg", 1), ("s", -2)]);
        assert!((k.factor - 1000.0).abs() < 1e-9, "{}", k.factor);
        let len = fmi_unit(Dim::LENGTH, &mmks).expect("a length");
        assert_eq!((len.name.as_str(), len.factor), ("millimeter", 1e-3));
    }

    #[test]
    fn a_half_power_has_no_fmi_unit() {
        let half = Dim::LENGTH.pow(0.5).expect("sqrt of a length");
        assert_eq!(fmi_unit(half, &Units::default()), None);
    }
}
