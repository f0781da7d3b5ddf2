//! The builtins table: every name the language knows (spec §3–§6), with its arity,
//! argument kinds, result type, meaning and a one-line doc.
//!
//! One table serves the lexer (is this a function name?), the checker (arity, kinds,
//! types), both back ends (which runtime function), the model's measure slots, the REPL's
//! `:help` and completion, and the "did you mean" hints.

use super::func::Func;
use rustc_hash::FxHashMap;
use std::sync::OnceLock;

/// What kind of argument a parameter takes (spec §2.5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    /// Any scalar expression.
    Scalar,
    /// A vector expression.
    Vector,
    /// An integer literal naming a marker or element; `0` means ground where allowed.
    Id,
    /// An integer literal code in a range (`iord`, `comp`, `jflag`, `nseq`, `method`).
    Code(i64, i64),
}

/// Result type of an expression (spec §2.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    /// A number.
    Scalar,
    /// A 3-vector (the `*XYZ` measures).
    Vector,
}

/// What the marker or element a measure reads must have been computed to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Needs {
    /// Marker positions and orientations.
    Position,
    /// Velocities.
    Velocity,
    /// Accelerations.
    Acceleration,
    /// Forces and reactions.
    Force,
    /// An element's state (`VARVAL`, `ARYVAL`, ...).
    State,
}

/// What a name means.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Role {
    /// A numeric constant.
    Constant(f64),
    /// `TIME`.
    Time,
    /// `MODE`.
    Mode,
    /// A library function of `mbfx-runtime`.
    Function(Func),
    /// AKISPL / CUBSPL: interpolation of host-supplied SPLINE data.
    Spline(SplineKind),
    /// `MAG(v)`: Euclidean norm of a vector.
    Mag,
    /// A measure of the model (spec §6): checked here, evaluated by the multibody core.
    Measure(Needs),
    /// A name of the language that mbfx does not evaluate; the text says why.
    Unsupported(&'static str),
}

/// Which spline fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SplineKind {
    /// `AKISPL`: Akima spline.
    Akima,
    /// `CUBSPL`: cubic spline.
    Cubic,
}

/// One entry of the table.
#[derive(Clone, Copy, Debug)]
pub struct Builtin {
    /// The name, upper case.
    pub name: &'static str,
    /// Parameters; the first `required` must be given, the rest may be left off the end.
    pub params: &'static [Param],
    /// How many of `params` must be given.
    pub required: usize,
    /// A trailing list of 1 to 31 scalar coefficients (POLY, CHEBY, FORCOS, FORSIN).
    pub coefficients: bool,
    /// Scalar or vector.
    pub result: Ty,
    /// What the name stands for.
    pub role: Role,
    /// One line for `:help` and hints.
    pub doc: &'static str,
}

impl Builtin {
    /// True for names written with an argument list.
    pub fn is_callable(&self) -> bool {
        !matches!(self.role, Role::Constant(_) | Role::Time | Role::Mode)
    }

    /// The most arguments the call may take.
    pub fn max_args(&self) -> usize {
        if self.coefficients {
            self.params.len() + MAX_COEFFICIENTS
        } else {
            self.params.len()
        }
    }

    /// The fewest arguments the call may take.
    pub fn min_args(&self) -> usize {
        self.required + usize::from(self.coefficients)
    }

    /// A signature line for messages and `:help`, e.g. `STEP(x, x0, h0, x1, h1)`.
    pub fn signature(&self) -> String {
        if !self.is_callable() {
            return self.name.to_string();
        }
        let names = self
            .doc
            .split_once(": ")
            .map(|(sig, _)| sig.to_string())
            .unwrap_or_else(|| self.name.to_string());
        names
    }
}

/// Most coefficients POLY, CHEBY, FORCOS and FORSIN accept (spec §5.6–5.8).
pub const MAX_COEFFICIENTS: usize = 31;

use Param::{Code, Id, Scalar as S, Vector as V};

const S1: &[Param] = &[S];
const S2: &[Param] = &[S, S];
const S3: &[Param] = &[S; 3];
const S5: &[Param] = &[S; 5];
const S6: &[Param] = &[S; 6];
const S7: &[Param] = &[S; 7];
const S8: &[Param] = &[S; 8];
const ID1: &[Param] = &[Id];
const ID2: &[Param] = &[Id, Id];
const ID3: &[Param] = &[Id, Id, Id];
const ID4: &[Param] = &[Id, Id, Id, Id];
const ELEMENT: &[Param] = &[Id, Code(0, 1), Code(1, 8), Id];
const NFORCE: &[Param] = &[Id, Id, Code(1, 8), Id];
/// CONTACT(id, jflag, comp, rm): comps 9..12 are mbfx's normal force, friction force,
/// penetration and slip speed.
const CONTACT: &[Param] = &[Id, Code(0, 1), Code(1, 12), Id];
const SPLINE: &[Param] = &[S, S, Id, Code(0, 2)];
const ID_SEQ: &[Param] = &[Id, Code(1, i64::MAX)];

const fn b(
    name: &'static str,
    params: &'static [Param],
    required: usize,
    result: Ty,
    role: Role,
    doc: &'static str,
) -> Builtin {
    Builtin {
        name,
        params,
        required,
        coefficients: false,
        result,
        role,
        doc,
    }
}

const fn f(name: &'static str, params: &'static [Param], func: Func, doc: &'static str) -> Builtin {
    b(
        name,
        params,
        params.len(),
        Ty::Scalar,
        Role::Function(func),
        doc,
    )
}

const fn series(
    name: &'static str,
    params: &'static [Param],
    func: Func,
    doc: &'static str,
) -> Builtin {
    Builtin {
        coefficients: true,
        ..f(name, params, func, doc)
    }
}

const fn c(name: &'static str, role: Role, doc: &'static str) -> Builtin {
    b(name, &[], 0, Ty::Scalar, role, doc)
}

const fn m(
    name: &'static str,
    params: &'static [Param],
    required: usize,
    result: Ty,
    needs: Needs,
    doc: &'static str,
) -> Builtin {
    b(name, params, required, result, Role::Measure(needs), doc)
}

const fn unsupported(name: &'static str, params: &'static [Param], why: &'static str) -> Builtin {
    b(name, params, 0, Ty::Scalar, Role::Unsupported(why), why)
}

use Needs::{Acceleration as A, Force as F, Position as P, State as St, Velocity as Vel};
use Ty::{Scalar as Sc, Vector as Ve};

/// Every name of the language, sorted by name (so lookup is a binary search).
pub static BUILTINS: &[Builtin] = &[
    f("ABS", S1, Func::Abs, "ABS(a): absolute value |a|"),
    m("ACCM", ID3, 1, Sc, A, "ACCM(i[,j][,l]): magnitude of the acceleration of i relative to j"),
    m("ACCX", ID4, 1, Sc, A, "ACCX(i[,j][,k][,l]): x component in k of the acceleration of i relative to j"),
    m("ACCXYZ", ID4, 1, Ve, A, "ACCXYZ(i[,j][,k][,l]): acceleration of i relative to j, as a vector in k"),
    m("ACCY", ID4, 1, Sc, A, "ACCY(i[,j][,k][,l]): y component in k of the acceleration of i relative to j"),
    m("ACCZ", ID4, 1, Sc, A, "ACCZ(i[,j][,k][,l]): z component in k of the acceleration of i relative to j"),
    f("ACOS", S1, Func::Acos, "ACOS(a): arc cosine in [0, pi], |a| <= 1"),
    f("AINT", S1, Func::Aint, "AINT(a): a truncated toward zero"),
    b("AKISPL", SPLINE, 3, Sc, Role::Spline(SplineKind::Akima), "AKISPL(x, z, id[, iord]): Akima interpolation of SPLINE/id (z = 0 for a curve; iord = derivative order 0..2)"),
    f("ANINT", S1, Func::Anint, "ANINT(a): nearest whole number, halves away from zero"),
    m("ARYVAL", ID_SEQ, 2, Sc, St, "ARYVAL(id, nseq): nseq-th value of ARRAY/id"),
    f("ASIN", S1, Func::Asin, "ASIN(a): arc sine in [-pi/2, pi/2], |a| <= 1"),
    f("ATAN", S1, Func::Atan, "ATAN(a): arc tangent in (-pi/2, pi/2)"),
    f("ATAN2", S2, Func::Atan2, "ATAN2(y, x): angle of the point (x, y) in (-pi, pi]"),
    m("AX", ID2, 1, Sc, P, "AX(i[,j]): rotation of i about the x axis of j (unwrapped)"),
    m("AY", ID2, 1, Sc, P, "AY(i[,j]): rotation of i about the y axis of j (unwrapped)"),
    m("AZ", ID2, 1, Sc, P, "AZ(i[,j]): rotation of i about the z axis of j (unwrapped)"),
    m("BEAM", ELEMENT, 4, Sc, F, "BEAM(id, jflag, comp, rm): force component of BEAM/id"),
    f("BISTOP", S8, Func::Bistop, "BISTOP(x, dx, x1, x2, k, e, cmax, d): two-sided contact force outside [x1, x2]"),
    m("BUSH", ELEMENT, 4, Sc, F, "BUSH(id, jflag, comp, rm): force component of BUSHING/id"),
    series("CHEBY", S2, Func::Cheby, "CHEBY(x, x0, a0, ..., a30): Chebyshev series sum a_j T_j(x - x0)"),
    m("CONTACT", CONTACT, 4, Sc, F, "CONTACT(id, jflag, comp, rm): force component of CONTACT/id (9..12: normal force, friction force, penetration, slip speed)"),
    f("COS", S1, Func::Cos, "COS(a): cosine (radians)"),
    f("COSH", S1, Func::Cosh, "COSH(a): hyperbolic cosine"),
    b("CUBSPL", SPLINE, 3, Sc, Role::Spline(SplineKind::Cubic), "CUBSPL(x, z, id[, iord]): cubic-spline interpolation of SPLINE/id (z = 0 for a curve; iord = derivative order 0..2)"),
    unsupported("CURVE", &[S, Code(0, 2), Code(1, 3), Id], "CURVE(alpha, iord, comp, id): CURVE elements are not supported yet (their argument order is unverified)"),
    m("CVCV", ELEMENT, 4, Sc, F, "CVCV(id, jflag, comp, rm): reaction component of CVCV/id"),
    unsupported("DELAY", &[S, S, S, Id], "DELAY(e, delay, history[, id]): delayed values need a history buffer, not supported yet"),
    m("DIF", ID1, 1, Sc, St, "DIF(id): state of DIFF/id"),
    m("DIF1", ID1, 1, Sc, St, "DIF1(id): time derivative of the state of DIFF/id"),
    f("DIM", S2, Func::Dim, "DIM(a1, a2): positive difference, a1 - a2 if a1 > a2 else 0"),
    m("DM", ID2, 1, Sc, P, "DM(i[,j]): distance between markers i and j"),
    c("DTOR", Role::Constant(std::f64::consts::PI / 180.0), "DTOR: degrees to radians, pi/180"),
    m("DX", ID3, 1, Sc, P, "DX(i[,j][,k]): x component in k of the position of i relative to j"),
    m("DXYZ", ID3, 1, Ve, P, "DXYZ(i[,j][,k]): position of i relative to j, as a vector in k"),
    m("DY", ID3, 1, Sc, P, "DY(i[,j][,k]): y component in k of the position of i relative to j"),
    m("DZ", ID3, 1, Sc, P, "DZ(i[,j][,k]): z component in k of the position of i relative to j"),
    f("EXP", S1, Func::Exp, "EXP(a): e to the power a"),
    m("FIELD", ELEMENT, 4, Sc, F, "FIELD(id, jflag, comp, rm): force component of FIELD/id"),
    m("FM", ID2, 1, Sc, F, "FM(i[,j]): magnitude of the force at i from elements between i and j"),
    series("FORCOS", S3, Func::Forcos, "FORCOS(x, x0, w, a0, ..., a30): Fourier cosine series a0 + sum a_j cos(j w (x - x0))"),
    series("FORSIN", S3, Func::Forsin, "FORSIN(x, x0, w, a0, ..., a30): Fourier sine series a0 + sum a_j sin(j w (x - x0))"),
    m("FRICTION", ELEMENT, 4, Sc, F, "FRICTION(id, jflag, comp, rm): force component of FRICTION/id"),
    m("FX", ID3, 1, Sc, F, "FX(i[,j][,k]): x component in k of the force at i"),
    unsupported("FXFREQ", &[], "FXFREQ: flexible-body constants are not supported"),
    unsupported("FXMODE", &[], "FXMODE: flexible-body constants are not supported"),
    m("FXYZ", ID3, 1, Ve, F, "FXYZ(i[,j][,k]): force at i as a vector in k"),
    m("FY", ID3, 1, Sc, F, "FY(i[,j][,k]): y component in k of the force at i"),
    m("FZ", ID3, 1, Sc, F, "FZ(i[,j][,k]): z component in k of the force at i"),
    m("GFORCE", ELEMENT, 4, Sc, F, "GFORCE(id, jflag, comp, rm): force component of GFORCE/id"),
    f("HAVSIN", S5, Func::Havsin, "HAVSIN(x, x0, h0, x1, h1): haversine step from h0 at x0 to h1 at x1"),
    f("IMPACT", S7, Func::Impact, "IMPACT(x, dx, x1, k, e, cmax, d): one-sided contact force when x < x1"),
    m("INCANG", ID3, 3, Sc, P, "INCANG(i, j, k): included angle at j between j->i and j->k"),
    unsupported("INTERP", &[S, Code(1, 3), Id, Code(0, 2)], "INTERP(x, method, id[, iord]): time-series splines from DAC/RPC files are not supported"),
    unsupported("INVPSD", &[], "INVPSD: its signature is not established (spec §5.12)"),
    m("JOINT", ELEMENT, 4, Sc, F, "JOINT(id, jflag, comp, rm): reaction component of JOINT/id"),
    m("JPRIM", ELEMENT, 4, Sc, F, "JPRIM(id, jflag, comp, rm): reaction component of JPRIM/id"),
    f("LOG", S1, Func::Log, "LOG(a): natural logarithm, a > 0"),
    f("LOG10", S1, Func::Log10, "LOG10(a): base-10 logarithm, a > 0"),
    b("MAG", &[V], 1, Sc, Role::Mag, "MAG(v): magnitude of a vector"),
    f("MAX", S2, Func::Max, "MAX(a1, a2): the larger of two values"),
    f("MIN", S2, Func::Min, "MIN(a1, a2): the smaller of two values"),
    f("MOD", S2, Func::Mod, "MOD(a1, a2): remainder a1 - int(a1/a2)*a2, with the sign of a1"),
    c("MODE", Role::Mode, "MODE: analysis mode (1 kinematics, 3 initial conditions, 4 dynamics, 5 statics, 6 quasi-statics, 7 linear)"),
    m("MOTION", ELEMENT, 4, Sc, F, "MOTION(id, jflag, comp, rm): reaction component of MOTION/id"),
    m("NFORCE", NFORCE, 4, Sc, F, "NFORCE(id, marker, comp, rm): force component of NFORCE/id at a marker"),
    m("ORIENT", &[Code(0, 99), Code(1, 9), Id, Id], 3, Sc, P, "ORIENT(code, comp, i[, j]): component comp of the orientation of i relative to j in representation code (inferred from the chrono REQUESTs: code 27 = Euler parameters)"),
    m("PHI", ID2, 1, Sc, P, "PHI(i[,j]): third angle of the body-fixed 3-1-3 sequence of i relative to j"),
    c("PI", Role::Constant(std::f64::consts::PI), "PI: 3.141592653589793"),
    m("PINVAL", ID_SEQ, 2, Sc, St, "PINVAL(id, nseq): nseq-th input of PINPUT/id"),
    m("PITCH", ID2, 1, Sc, P, "PITCH(i[,j]): pitch (about -y) of the body-fixed 3-2-1 sequence of i relative to j"),
    series("POLY", S2, Func::Poly, "POLY(x, x0, a0, ..., a30): polynomial sum a_j (x - x0)^j"),
    m("POUVAL", ID_SEQ, 2, Sc, St, "POUVAL(id, nseq): nseq-th output of POUTPUT/id"),
    m("PSI", ID2, 1, Sc, P, "PSI(i[,j]): first angle of the body-fixed 3-1-3 sequence of i relative to j"),
    m("PTCV", ELEMENT, 4, Sc, F, "PTCV(id, jflag, comp, rm): reaction component of PTCV/id"),
    m("ROLL", ID2, 1, Sc, P, "ROLL(i[,j]): roll of the body-fixed 3-2-1 sequence of i relative to j"),
    c("RTOD", Role::Constant(180.0 / std::f64::consts::PI), "RTOD: radians to degrees, 180/pi"),
    m("SENVAL", ID1, 1, Sc, St, "SENVAL(id): value associated with SENSOR/id"),
    m("SFORCE", ELEMENT, 4, Sc, F, "SFORCE(id, jflag, comp, rm): force component of SFORCE/id"),
    f("SHF", S6, Func::Shf, "SHF(x, x0, a, w, phi, b): simple harmonic a sin(w (x - x0) - phi) + b"),
    f("SIGN", S2, Func::Sign, "SIGN(a1, a2): |a1| with the sign of a2 (a2 = 0 counts as positive)"),
    f("SIN", S1, Func::Sin, "SIN(a): sine (radians)"),
    f("SINH", S1, Func::Sinh, "SINH(a): hyperbolic sine"),
    m("SPDP", ELEMENT, 4, Sc, F, "SPDP(id, jflag, comp, rm): force component of SPRINGDAMPER/id"),
    f("SQRT", S1, Func::Sqrt, "SQRT(a): square root, a >= 0"),
    f("STEP", S5, Func::Step, "STEP(x, x0, h0, x1, h1): cubic step from h0 at x0 to h1 at x1"),
    f("STEP5", S5, Func::Step5, "STEP5(x, x0, h0, x1, h1): quintic step from h0 at x0 to h1 at x1"),
    f("SWEEP", S7, Func::Sweep, "SWEEP(x, a, x0, f0, x1, f1, dx): sine of amplitude a sweeping from f0 to f1"),
    f("TAN", S1, Func::Tan, "TAN(a): tangent (radians)"),
    f("TANH", S1, Func::Tanh, "TANH(a): hyperbolic tangent"),
    m("THETA", ID2, 1, Sc, P, "THETA(i[,j]): second angle of the body-fixed 3-1-3 sequence of i relative to j"),
    c("TIME", Role::Time, "TIME: the current simulation time"),
    m("TM", ID2, 1, Sc, F, "TM(i[,j]): magnitude of the torque at i"),
    unsupported("TRANS", &[], "TRANS: its semantics are not established (spec §6.9)"),
    m("TX", ID3, 1, Sc, F, "TX(i[,j][,k]): x component in k of the torque at i"),
    m("TXYZ", ID3, 1, Ve, F, "TXYZ(i[,j][,k]): torque at i as a vector in k"),
    m("TY", ID3, 1, Sc, F, "TY(i[,j][,k]): y component in k of the torque at i"),
    m("TZ", ID3, 1, Sc, F, "TZ(i[,j][,k]): z component in k of the torque at i"),
    unsupported("USER", &[], "USER(r1, ..., r30): user subroutines are not supported"),
    unsupported("UV", &[], "UV: its semantics are not established (spec §6.9)"),
    m("UVX", ID2, 1, Ve, P, "UVX(i[,k]): unit x axis of marker i, expressed in k"),
    m("UVY", ID2, 1, Ve, P, "UVY(i[,k]): unit y axis of marker i, expressed in k"),
    m("UVZ", ID2, 1, Ve, P, "UVZ(i[,k]): unit z axis of marker i, expressed in k"),
    m("VARVAL", ID1, 1, Sc, St, "VARVAL(id): current value of VARIABLE/id"),
    m("VFORCE", ELEMENT, 4, Sc, F, "VFORCE(id, jflag, comp, rm): force component of VFORCE/id"),
    m("VM", ID3, 1, Sc, Vel, "VM(i[,j][,l]): magnitude of the velocity of i relative to j"),
    m("VR", ID3, 1, Sc, Vel, "VR(i[,j][,l]): radial (separation) velocity of i relative to j"),
    m("VTORQ", ELEMENT, 4, Sc, F, "VTORQ(id, jflag, comp, rm): torque component of VTORQUE/id"),
    m("VX", ID4, 1, Sc, Vel, "VX(i[,j][,k][,l]): x component in k of the velocity of i relative to j"),
    m("VXYZ", ID4, 1, Ve, Vel, "VXYZ(i[,j][,k][,l]): velocity of i relative to j, as a vector in k"),
    m("VY", ID4, 1, Sc, Vel, "VY(i[,j][,k][,l]): y component in k of the velocity of i relative to j"),
    m("VZ", ID4, 1, Sc, Vel, "VZ(i[,j][,k][,l]): z component in k of the velocity of i relative to j"),
    m("WDTM", ID3, 1, Sc, A, "WDTM(i[,j][,l]): magnitude of the angular acceleration of i relative to j"),
    m("WDTX", ID4, 1, Sc, A, "WDTX(i[,j][,k][,l]): x component in k of the angular acceleration of i relative to j"),
    m("WDTXYZ", ID4, 1, Ve, A, "WDTXYZ(i[,j][,k][,l]): angular acceleration of i relative to j, as a vector in k"),
    m("WDTY", ID4, 1, Sc, A, "WDTY(i[,j][,k][,l]): y component in k of the angular acceleration of i relative to j"),
    m("WDTZ", ID4, 1, Sc, A, "WDTZ(i[,j][,k][,l]): z component in k of the angular acceleration of i relative to j"),
    m("WM", ID2, 1, Sc, Vel, "WM(i[,j]): magnitude of the angular velocity of i relative to j"),
    m("WX", ID3, 1, Sc, Vel, "WX(i[,j][,k]): x component in k of the angular velocity of i relative to j"),
    m("WXYZ", ID3, 1, Ve, Vel, "WXYZ(i[,j][,k]): angular velocity of i relative to j, as a vector in k"),
    m("WY", ID3, 1, Sc, Vel, "WY(i[,j][,k]): y component in k of the angular velocity of i relative to j"),
    m("WZ", ID3, 1, Sc, Vel, "WZ(i[,j][,k]): z component in k of the angular velocity of i relative to j"),
    m("YAW", ID2, 1, Sc, P, "YAW(i[,j]): yaw of the body-fixed 3-2-1 sequence of i relative to j"),
];

/// Looks a name up (names are upper case; the lexer normalises them). The checker looks
/// up every name it meets, so this is a hash table built on first use rather than a
/// binary search of string comparisons.
pub fn lookup(name: &str) -> Option<&'static Builtin> {
    static INDEX: OnceLock<FxHashMap<&'static str, &'static Builtin>> = OnceLock::new();
    INDEX
        .get_or_init(|| BUILTINS.iter().map(|b| (b.name, b)).collect())
        .get(name)
        .copied()
}

/// True when `name` (upper case) is a function or measure written with `(`.
pub fn is_callable(name: &str) -> bool {
    name == "IF" || lookup(name).is_some_and(Builtin::is_callable)
}

/// Names the checker may suggest: every builtin plus `IF`.
pub fn all_names() -> impl Iterator<Item = &'static str> {
    BUILTINS.iter().map(|b| b.name).chain(std::iter::once("IF"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_sorted_and_unique() {
        for pair in BUILTINS.windows(2) {
            assert!(
                pair[0].name < pair[1].name,
                "{} !< {}",
                pair[0].name,
                pair[1].name
            );
        }
    }

    #[test]
    fn every_function_matches_its_runtime_arity() {
        for b in BUILTINS {
            if let Role::Function(func) = b.role {
                assert_eq!(b.params.len(), func.fixed_args(), "{}", b.name);
                assert_eq!(b.coefficients, func.is_variadic(), "{}", b.name);
                assert!(func.symbol().starts_with("mbfx_"));
            }
        }
    }

    #[test]
    fn docs_start_with_the_name() {
        for b in BUILTINS {
            assert!(b.doc.starts_with(b.name), "{}", b.name);
        }
    }
}
