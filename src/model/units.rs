//! UNITS and the units-consistency factor (multibody spec §2.1): Adams never converts
//! input; Newton's law reads Force·UCF = Mass·Acceleration, with
//! UCF = F_unit / (M_unit·L_unit/T_unit²) when each unit is expressed in SI.

/// Which quantity a unit measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// Force (N in SI).
    Force,
    /// Mass (kg in SI).
    Mass,
    /// Length (m in SI).
    Length,
    /// Time (s in SI).
    Time,
}

/// Units Adams names, with their value in SI (N, kg, m, s).
const UNITS: &[(Quantity, &str, f64)] = &[
    (Quantity::Force, "NEWTON", 1.0),
    (Quantity::Force, "KNEWTON", 1.0e3),
    (Quantity::Force, "MILLINEWTON", 1.0e-3),
    (Quantity::Force, "DYNE", 1.0e-5),
    (Quantity::Force, "POUND_FORCE", 4.448_221_615_260_5),
    (Quantity::Force, "KPOUND_FORCE", 4_448.221_615_260_5),
    (Quantity::Force, "KILOGRAM_FORCE", 9.806_65),
    (Quantity::Force, "OUNCE_FORCE", 0.278_013_850_953_781_2),
    (Quantity::Mass, "KILOGRAM", 1.0),
    (Quantity::Mass, "GRAM", 1.0e-3),
    (Quantity::Mass, "TONNE", 1.0e3),
    (Quantity::Mass, "POUND_MASS", 0.453_592_37),
    (Quantity::Mass, "KPOUND_MASS", 453.592_37),
    (Quantity::Mass, "OUNCE_MASS", 0.028_349_523_125),
    (Quantity::Mass, "SLUG", 14.593_902_937_206_4),
    (Quantity::Length, "METER", 1.0),
    (Quantity::Length, "MILLIMETER", 1.0e-3),
    (Quantity::Length, "CENTIMETER", 1.0e-2),
    (Quantity::Length, "KILOMETER", 1.0e3),
    (Quantity::Length, "INCH", 0.0254),
    (Quantity::Length, "FOOT", 0.3048),
    (Quantity::Length, "MILE", 1_609.344),
    (Quantity::Time, "SECOND", 1.0),
    (Quantity::Time, "MILLISECOND", 1.0e-3),
    (Quantity::Time, "MINUTE", 60.0),
    (Quantity::Time, "HOUR", 3_600.0),
];

/// The value in SI of the unit `name` (any case) measuring `q`.
pub fn si_value(q: Quantity, name: &str) -> Option<f64> {
    UNITS
        .iter()
        .find(|(k, n, _)| *k == q && n.eq_ignore_ascii_case(name))
        .map(|(_, _, v)| *v)
}

/// `SYSTEM =` presets: force, mass, length and time unit names (spec §2.1).
pub fn system(name: &str) -> Option<[&'static str; 4]> {
    const SYSTEMS: &[(&str, [&str; 4])] = &[
        ("MKS", ["NEWTON", "KILOGRAM", "METER", "SECOND"]),
        ("MMKS", ["NEWTON", "KILOGRAM", "MILLIMETER", "SECOND"]),
        ("CGS", ["DYNE", "GRAM", "CENTIMETER", "SECOND"]),
        ("FPS", ["POUND_FORCE", "POUND_MASS", "FOOT", "SECOND"]),
        ("IPS", ["POUND_FORCE", "POUND_MASS", "INCH", "SECOND"]),
    ];
    SYSTEMS
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))
        .map(|(_, u)| *u)
}

/// UCF = F / (M·L/T²) from the SI values of the four units.
pub fn ucf(force: f64, mass: f64, length: f64, time: f64) -> f64 {
    force / (mass * length / (time * time))
}
