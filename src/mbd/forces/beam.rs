//! BEAM's stiffness (issue 40 §4): Timoshenko's linear beam from J (x along x_J) to I
//! at x = LENGTH, the 6×6 block of the free end I of the 12×12 element stiffness with
//! J clamped, in J's axes over (x, y, z, ax, ay, az):
//!
//! ```text
//! K11 = E·A/L                         K44 = G·IXX/L
//! K22 = 12·E·IZZ/(L³(1+Py))           K26 = K62 = −6·E·IZZ/(L²(1+Py))
//! K33 = 12·E·IYY/(L³(1+Pz))           K35 = K53 = +6·E·IYY/(L²(1+Pz))
//! K55 = (4+Pz)·E·IYY/(L(1+Pz))        K66 = (4+Py)·E·IZZ/(L(1+Py))
//! Py = 12·E·IZZ·ASY/(G·A·L²)          Pz = 12·E·IYY·ASZ/(G·A·L²)
//! ```
//!
//! (the signs of K26 and K35: a tip rotation about z_J bends the beam toward +y, one
//! about y_J toward −z). A cantilever under a tip load P along y then deflects
//! P·L³/(3·E·IZZ) + P·L·ASY/(G·A): bending plus shear. The damping is CRATIO × K or
//! the given CMATRIX.

use super::field::{Linear6, Mat6};
use crate::model::beams::{Beam, BeamDamping};

/// Timoshenko's free-end stiffness of `b` (module doc).
pub fn stiffness(b: &Beam) -> Mat6 {
    let (e, g, a, l) = (b.emodulus, b.gmodulus, b.area, b.length);
    let py = 12.0 * e * b.izz * b.asy / (g * a * l * l);
    let pz = 12.0 * e * b.iyy * b.asz / (g * a * l * l);
    let mut k = [[0.0; 6]; 6];
    k[0][0] = e * a / l;
    k[1][1] = 12.0 * e * b.izz / (l.powi(3) * (1.0 + py));
    k[2][2] = 12.0 * e * b.iyy / (l.powi(3) * (1.0 + pz));
    k[3][3] = g * b.ixx / l;
    k[4][4] = (4.0 + pz) * e * b.iyy / (l * (1.0 + pz));
    k[5][5] = (4.0 + py) * e * b.izz / (l * (1.0 + py));
    k[1][5] = -6.0 * e * b.izz / (l * l * (1.0 + py));
    k[5][1] = k[1][5];
    k[2][4] = 6.0 * e * b.iyy / (l * l * (1.0 + pz));
    k[4][2] = k[2][4];
    k
}

/// The linear law of `b`: its stiffness and damping, its length along x_J, no preload.
pub fn law(b: &Beam) -> Linear6 {
    let k = stiffness(b);
    let c = match &b.damping {
        BeamDamping::Ratio(r) => k.map(|row| row.map(|x| r * x)),
        BeamDamping::Matrix(m) => **m,
    };
    Linear6 {
        k,
        c,
        length: [b.length, 0.0, 0.0, 0.0, 0.0, 0.0],
        preload: [0.0; 6],
    }
}
