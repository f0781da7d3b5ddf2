//! BEAM and FIELD, Adams' linear six-component force elements (issue 40 §4), as the
//! model holds them and as the reader reads them. Both act between a fixed I and a fixed
//! J marker with a 6×6 stiffness on the deflection of I relative to J in J's axes (x, y,
//! z and the AX, AY, AZ angles) and a 6×6 damping on the relative velocities: a FIELD
//! gives its matrices, a BEAM its section (Timoshenko's stiffness, built by the core).
//!
//! Matrices are read as Adams writes them, by columns (KMATRIX r1..r36: r1..r6 is the
//! first column); BEAM's CMATRIX is the lower triangle by columns (21 values).

use super::elements::{Id, Named};
use super::reader::Reader;
use super::stmt_args::Args;
use crate::diag::{Code, Diagnostic};

/// A 6×6 matrix over (x, y, z, ax, ay, az), `m[row][col]`.
pub type Mat6 = [[f64; 6]; 6];

/// BEAM: a massless elastic beam from J (x along x_J) to I at x = LENGTH.
#[derive(Clone, Debug, PartialEq)]
pub struct Beam {
    /// Id, view name and span.
    pub el: Named,
    /// The I marker (the beam's free end).
    pub i: Id,
    /// The J marker (the beam's root; x_J is its neutral axis).
    pub j: Id,
    /// LENGTH: undeformed length along x_J.
    pub length: f64,
    /// AREA: cross-section area.
    pub area: f64,
    /// IXX: torsional constant; IYY, IZZ: area moments about y_J and z_J.
    pub ixx: f64,
    /// IYY.
    pub iyy: f64,
    /// IZZ.
    pub izz: f64,
    /// ASY, ASZ: shear area ratios (0: no shear deflection).
    pub asy: f64,
    /// ASZ.
    pub asz: f64,
    /// EMODULUS: Young's modulus.
    pub emodulus: f64,
    /// GMODULUS: shear modulus.
    pub gmodulus: f64,
    /// The damping: CRATIO × K, or CMATRIX.
    pub damping: BeamDamping,
}

/// How a BEAM's damping matrix is given.
#[derive(Clone, Debug, PartialEq)]
pub enum BeamDamping {
    /// CRATIO: the damping matrix is this ratio times the stiffness matrix.
    Ratio(f64),
    /// CMATRIX: the damping matrix itself (symmetric).
    Matrix(Box<Mat6>),
}

/// FIELD: F = −K·(X − LENGTH) − C·V + FORCE in J's axes, on I; the reaction on J.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// Id, view name and span.
    pub el: Named,
    /// The I marker.
    pub i: Id,
    /// The J marker.
    pub j: Id,
    /// KMATRIX.
    pub k: Box<Mat6>,
    /// CMATRIX, or CRATIO × KMATRIX.
    pub c: Box<Mat6>,
    /// LENGTH: the deflection at which the field gives FORCE (x, y, z, ax, ay, az).
    pub length: [f64; 6],
    /// FORCE and TORQUE: the preload at LENGTH, J axes.
    pub preload: [f64; 6],
}

/// The shortest abbreviation of the keyword arguments read here (IXX, IYY and IZZ are
/// written IX, IY, IZ too).
const MIN: usize = 3;

/// The shortest abbreviation of `key`.
fn min_of(key: &str) -> usize {
    if key.starts_with('I') {
        2
    } else {
        MIN.min(key.len())
    }
}

/// A number that must be given and positive (`E0605` at the value otherwise).
fn positive(a: &mut Args, key: &str) -> Option<f64> {
    let v = a.required_number(key, min_of(key))?;
    if v > 0.0 {
        return Some(v);
    }
    let span = a
        .stmt
        .arg(key, min_of(key))
        .map_or(a.stmt.keyword_span.clone(), |arg| arg.span.clone());
    let msg = format!("{key} of {} must be positive, found {v}", a.label);
    a.error(Code::BadArgument, span, msg);
    None
}

/// An optional number that must not be negative.
fn not_negative(a: &mut Args, key: &str) -> Option<f64> {
    let v = a.number(key, min_of(key)).unwrap_or(0.0);
    if v >= 0.0 {
        return Some(v);
    }
    let span = a
        .stmt
        .arg(key, min_of(key))
        .map_or(a.stmt.keyword_span.clone(), |arg| arg.span.clone());
    let msg = format!("{key} of {} must not be negative, found {v}", a.label);
    a.error(Code::BadArgument, span, msg);
    None
}

/// A full 6×6 matrix given by columns (36 values).
fn by_columns(values: &[f64]) -> Mat6 {
    let mut m = [[0.0; 6]; 6];
    for (n, v) in values.iter().enumerate() {
        m[n % 6][n / 6] = *v;
    }
    m
}

/// A symmetric 6×6 matrix from its lower triangle by columns (21 values).
fn lower_by_columns(values: &[f64]) -> Mat6 {
    let mut m = [[0.0; 6]; 6];
    let pairs = (0..6).flat_map(|col| (col..6).map(move |row| (row, col)));
    for ((row, col), v) in pairs.zip(values) {
        m[row][col] = *v;
        m[col][row] = *v;
    }
    m
}

/// The fixed I and J markers of a BEAM or FIELD.
fn markers(r: &mut Reader, a: &mut Args) -> Option<(Id, Id)> {
    use super::resolve::MarkerUse;
    let i = r.marker_ref(a, "I", 1, MarkerUse::Fixed, true);
    let j = r.marker_ref(a, "J", 1, MarkerUse::Fixed, true);
    Some((i?.0, j?.0))
}

/// BEAM/id, I, J, LENGTH, AREA, IXX, IYY, IZZ, EMODULUS, GMODULUS [, ASY, ASZ]
/// [, CRATIO | CMATRIX] [, FORMULATION].
pub(super) fn beam(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let ends = markers(r, a);
    let [length, area, ixx, iyy, izz, emodulus, gmodulus] = [
        "LENGTH", "AREA", "IXX", "IYY", "IZZ", "EMODULUS", "GMODULUS",
    ]
    .map(|k| positive(a, k));
    let [asy, asz] = ["ASY", "ASZ"].map(|k| not_negative(a, k));
    let cmatrix = a.numbers("CMATRIX", MIN, 21..=21);
    let cratio = not_negative(a, "CRATIO");
    let damping = match cmatrix {
        Some(m) => BeamDamping::Matrix(Box::new(lower_by_columns(&m))),
        None => BeamDamping::Ratio(cratio.unwrap_or(0.0)),
    };
    if let Some((form, span)) = a.word("FORMULATION", MIN) {
        if !form.eq_ignore_ascii_case("LINEAR") {
            a.diags.push(
                Diagnostic::warning(
                    Code::UnsupportedStatement,
                    span,
                    format!(
                        "FORMULATION = {form} of {}: mbfx models the LINEAR one",
                        a.label
                    ),
                )
                .with_note(
                    "Timoshenko's linear stiffness about J's axes, exact for small deflections; \
                     the nonlinear formulations also follow large ones",
                ),
            );
        }
    }
    let (Some((i, j)), Some(length), Some(area), Some(ixx), Some(iyy), Some(izz)) =
        (ends, length, area, ixx, iyy, izz)
    else {
        return;
    };
    let (Some(emodulus), Some(gmodulus), Some(asy), Some(asz)) = (emodulus, gmodulus, asy, asz)
    else {
        return;
    };
    r.model.beams.push(Beam {
        el,
        i,
        j,
        length,
        area,
        ixx,
        iyy,
        izz,
        asy,
        asz,
        emodulus,
        gmodulus,
        damping,
    });
}

/// FIELD/id, I, J, KMATRIX [, CMATRIX | CRATIO] [, LENGTH] [, FORCE [, TORQUE]]; a
/// FUNCTION = USER(…) field (FIESUB) is left out as every USER value is.
pub(super) fn field(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let ends = markers(r, a);
    let user = a.find("FUNCTION", 3).is_some_and(|f| f.is_user_call);
    let k = a.numbers("KMATRIX", MIN, 36..=36).map(|v| by_columns(&v));
    let c = a.numbers("CMATRIX", MIN, 36..=36).map(|v| by_columns(&v));
    let cratio = not_negative(a, "CRATIO");
    let length = a.numbers("LENGTH", MIN, 6..=6);
    // Adams gives FORCE as six values (three forces, three torques); three forces with
    // a TORQUE of three are read as well.
    let force = a.numbers("FORCE", MIN, 3..=6);
    let torque = a.vec3("TORQUE", MIN);
    if user {
        return;
    }
    let mut preload = [0.0; 6];
    if let Some(f) = &force {
        if f.len() != 3 && f.len() != 6 {
            let span = a.stmt.arg("FORCE", MIN).map(|x| x.span.clone());
            let msg = format!("FORCE of {} takes 3 or 6 numbers", a.label);
            a.error(Code::BadArgument, span.unwrap_or_default(), msg);
            return;
        }
        preload[..f.len()].copy_from_slice(f);
    }
    if let Some(t) = torque {
        preload[3..].copy_from_slice(t.as_slice());
    }
    let Some(k) = k else {
        if a.stmt.arg("KMATRIX", MIN).is_none() {
            a.missing("KMATRIX = 36 values");
        }
        return;
    };
    let c = match (c, cratio) {
        (Some(c), _) => c,
        (None, Some(ratio)) => k.map(|row| row.map(|x| ratio * x)),
        (None, None) => return,
    };
    let Some((i, j)) = ends else { return };
    let mut len = [0.0; 6];
    if let Some(l) = length {
        len.copy_from_slice(&l);
    }
    r.model.fields.push(Field {
        el,
        i,
        j,
        k: Box::new(k),
        c: Box::new(c),
        length: len,
        preload,
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrices_are_read_by_columns() {
        let v: Vec<f64> = (0..36).map(f64::from).collect();
        let m = by_columns(&v);
        assert_eq!(m[1][0], 1.0, "r2 is row 2 of column 1");
        assert_eq!(m[0][1], 6.0, "r7 starts column 2");
        let t: Vec<f64> = (0..21).map(f64::from).collect();
        let s = lower_by_columns(&t);
        assert_eq!((s[5][0], s[0][5]), (5.0, 5.0));
        assert_eq!((s[1][1], s[5][5]), (6.0, 20.0));
    }
}
