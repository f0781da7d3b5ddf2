//! Physical dimensions: exponents over the base quantities mass, length, time and angle,
//! and their algebra (products, quotients, constant powers, comparison).
//!
//! Force is not a base: a force is M·L·T⁻² whatever the dataset's UNITS call its unit
//! (Adams's UCF makes the force unit a name of its own, not another dimension). Angle is a
//! base so that an angle can be named and told from a length or a time, but it is the
//! radian's dimension, which SI counts as 1: two dimensions that differ only in their
//! power of angle [agree](Dim::agrees) (ω = v/r is an angular velocity, ω·r a velocity), and
//! a transcendental function accepts a [dimensionless](Dim::is_dimensionless) argument or
//! an angle alike.
//!
//! Exponents are rational: `SQRT` halves them and `**0.5` or `**(1/3)` scale them. They
//! are stored as integer multiples of 1/[`DEN`] (every fraction whose denominator divides
//! 60: halves, thirds, quarters, fifths, sixths, ...), 15 bits each, packed in one
//! non-zero `u64`: a `Dim` and an `Option<Dim>` are 8 bytes, which the units check's
//! table of node dimensions reads and writes once per node. A power that leaves that grid
//! or range has no dimension here, and the caller treats it as unknown.

use std::num::NonZeroU64;

/// Exponents are multiples of `1/DEN`.
pub const DEN: i32 = 60;

/// Bits per exponent, and the largest magnitude one may take (in units of 1/[`DEN`]).
const BITS: u32 = 15;
const LIMIT: i32 = (1 << (BITS - 1)) - 1;
const MASK: u64 = (1 << BITS) - 1;
/// Always set, so that a dimension is never zero (the niche `Option<Dim>` uses).
const TAG: u64 = 1 << 63;
/// The bits of mass, length and time (angle left out: see [`Dim::agrees`]).
const MLT: u64 = (1 << (3 * BITS)) - 1;

/// A base quantity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Base {
    /// Mass.
    Mass,
    /// Length.
    Length,
    /// Time.
    Time,
    /// Plane angle.
    Angle,
}

impl Base {
    /// Every base, in the order of [`Dim`]'s exponents.
    pub const ALL: [Base; 4] = [Base::Mass, Base::Length, Base::Time, Base::Angle];
}

/// A dimension: the exponents of mass, length, time and angle, in units of 1/[`DEN`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Dim(NonZeroU64);

impl Dim {
    /// A dimension with integer exponents of mass, length, time and angle.
    pub const fn of(mass: i32, length: i32, time: i32, angle: i32) -> Dim {
        match Dim::pack([mass * DEN, length * DEN, time * DEN, angle * DEN]) {
            Some(d) => d,
            None => panic!("exponent out of range"),
        }
    }

    /// Dimensionless.
    pub const NONE: Dim = Dim::of(0, 0, 0, 0);
    /// Mass.
    pub const MASS: Dim = Dim::of(1, 0, 0, 0);
    /// Length.
    pub const LENGTH: Dim = Dim::of(0, 1, 0, 0);
    /// Time.
    pub const TIME: Dim = Dim::of(0, 0, 1, 0);
    /// Angle.
    pub const ANGLE: Dim = Dim::of(0, 0, 0, 1);
    /// Velocity, L·T⁻¹.
    pub const VELOCITY: Dim = Dim::of(0, 1, -1, 0);
    /// Acceleration, L·T⁻².
    pub const ACCELERATION: Dim = Dim::of(0, 1, -2, 0);
    /// Angular velocity, A·T⁻¹.
    pub const ANGULAR_VELOCITY: Dim = Dim::of(0, 0, -1, 1);
    /// Angular acceleration, A·T⁻².
    pub const ANGULAR_ACCELERATION: Dim = Dim::of(0, 0, -2, 1);
    /// Force, M·L·T⁻².
    pub const FORCE: Dim = Dim::of(1, 1, -2, 0);
    /// Torque, M·L²·T⁻².
    pub const TORQUE: Dim = Dim::of(1, 2, -2, 0);

    /// Packs exponents (units of 1/DEN); `None` when one is out of range.
    const fn pack(e: [i32; 4]) -> Option<Dim> {
        let mut bits = TAG;
        let mut i = 0;
        while i < 4 {
            if e[i] > LIMIT || e[i] < -LIMIT {
                return None;
            }
            bits |= ((e[i] as u64) & MASK) << (BITS * i as u32);
            i += 1;
        }
        match NonZeroU64::new(bits) {
            Some(n) => Some(Dim(n)),
            None => None,
        }
    }

    /// The exponents, in units of 1/DEN.
    fn unpack(self) -> [i32; 4] {
        let bits = self.0.get();
        [0, 1, 2, 3].map(|i| {
            let field = ((bits >> (BITS * i)) & MASK) as i32;
            // Sign-extend the 15-bit field.
            (field << (32 - BITS)) >> (32 - BITS)
        })
    }

    /// The exponent of `base` as a reduced fraction (numerator, positive denominator).
    pub fn exponent(self, base: Base) -> (i32, i32) {
        reduce(self.raw(base))
    }

    /// The exponent of `base` in units of 1/[`DEN`].
    pub(super) fn raw(self, base: Base) -> i32 {
        self.unpack()[base as usize]
    }

    /// `self · other`; `None` past the range of the exponents.
    pub fn times(self, other: Dim) -> Option<Dim> {
        let (a, b) = (self.unpack(), other.unpack());
        Dim::pack([0, 1, 2, 3].map(|i| a[i] + b[i]))
    }

    /// `self / other`; `None` past the range of the exponents.
    pub fn per(self, other: Dim) -> Option<Dim> {
        let (a, b) = (self.unpack(), other.unpack());
        Dim::pack([0, 1, 2, 3].map(|i| a[i] - b[i]))
    }

    /// `self ** p` for a constant `p`; `None` when an exponent leaves the grid of
    /// 1/[`DEN`] or the range (or `p` is not finite).
    pub fn pow(self, p: f64) -> Option<Dim> {
        let mut e = [0; 4];
        for (out, n) in e.iter_mut().zip(self.unpack()) {
            let x = f64::from(n) * p;
            let r = x.round();
            // A power written as a decimal (0.3, 1/3) is exact only to rounding.
            if !r.is_finite() || (x - r).abs() > 1e-6 || r.abs() > f64::from(LIMIT) {
                return None;
            }
            *out = r as i32;
        }
        Dim::pack(e)
    }

    /// True when the two are the same dimension, counting an angle as dimensionless.
    pub fn agrees(self, other: Dim) -> bool {
        (self.0.get() ^ other.0.get()) & MLT == 0
    }

    /// True when dimensionless or a power of angle: what SIN, EXP, ... accept.
    pub fn is_dimensionless(self) -> bool {
        self.agrees(Dim::NONE)
    }
}

/// `n`/[`DEN`] as a reduced fraction (numerator, positive denominator).
pub fn reduce(n: i32) -> (i32, i32) {
    let g = gcd(n.unsigned_abs(), DEN as u32) as i32;
    (n / g, DEN / g)
}

fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn force_is_mass_times_acceleration() {
        assert_eq!(Dim::MASS.times(Dim::ACCELERATION), Some(Dim::FORCE));
        assert_eq!(Dim::FORCE.times(Dim::LENGTH), Some(Dim::TORQUE));
        assert_eq!(Dim::LENGTH.per(Dim::TIME), Some(Dim::VELOCITY));
        assert_eq!(Dim::ANGLE.per(Dim::TIME), Some(Dim::ANGULAR_VELOCITY));
    }

    #[test]
    fn powers_scale_exponents_including_fractions() {
        let area = Dim::LENGTH.pow(2.0);
        assert_eq!(area, Some(Dim::of(0, 2, 0, 0)));
        assert_eq!(area.and_then(|a| a.pow(0.5)), Some(Dim::LENGTH));
        let cube_root = Dim::of(0, 3, 0, 0).pow(1.0 / 3.0);
        assert_eq!(cube_root, Some(Dim::LENGTH));
        let root = Dim::LENGTH.pow(0.5).expect("on the grid");
        assert_eq!(root.exponent(Base::Length), (1, 2));
        assert_eq!(
            Dim::TIME.pow(-1.5).map(|d| d.exponent(Base::Time)),
            Some((-3, 2))
        );
    }

    #[test]
    fn powers_off_the_grid_or_out_of_range_have_no_dimension() {
        assert_eq!(Dim::LENGTH.pow(1.0 / 7.0), None);
        assert_eq!(Dim::LENGTH.pow(0.125), None);
        assert_eq!(Dim::LENGTH.pow(f64::NAN), None);
        assert_eq!(Dim::LENGTH.pow(1e12), None);
        assert_eq!(Dim::NONE.pow(1e12), Some(Dim::NONE));
        let big = Dim::LENGTH.pow(200.0).expect("in range");
        assert_eq!(big.times(big), None);
        assert_eq!(Dim::LENGTH.pow(-200.0).and_then(|d| d.times(d)), None);
    }

    #[test]
    fn a_dimension_and_an_optional_one_take_eight_bytes() {
        assert_eq!(std::mem::size_of::<Option<Dim>>(), 8);
        assert_eq!(Dim::of(-3, 2, -1, 1).exponent(Base::Mass), (-3, 1));
        assert_eq!(Dim::of(-3, 2, -1, 1).exponent(Base::Time), (-1, 1));
    }

    #[test]
    fn angle_agrees_with_a_pure_number_only() {
        assert!(Dim::ANGLE.agrees(Dim::NONE));
        assert!(Dim::ANGLE.is_dimensionless());
        assert!(Dim::ANGULAR_VELOCITY.agrees(Dim::VELOCITY.per(Dim::LENGTH).unwrap()));
        assert!(!Dim::LENGTH.is_dimensionless());
        assert!(!Dim::TIME.agrees(Dim::ANGLE));
    }
}
