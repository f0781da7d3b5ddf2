//! BEAM and FIELD (issue 40 §4) against closed forms written here: a Timoshenko
//! cantilever's static tip deflections and rotations under end loads (bending plus
//! shear, axial, torsion), and a mass on a diagonal FIELD oscillating at the spring's
//! period 2π·√(m/k).

use crate::statics::statics;
use mbfx::session::request::{run, RunRequest};
use mbfx::session::DimRequest;
use std::f64::consts::PI;

// The cantilever: a short steel beam, where shear adds a few percent to bending.
const L: f64 = 0.2;
const E: f64 = 2.1e11;
const GM: f64 = 8.0e10;
const A: f64 = 1.0e-3;
const IXX: f64 = 4.0e-7;
const IYY: f64 = 3.0e-7;
const IZZ: f64 = 2.0e-7;
const ASY: f64 = 1.2;
const ASZ: f64 = 1.1;
// End loads: axial, the two shears, and a torque about the beam's axis.
const PX: f64 = 5000.0;
const PY: f64 = 40.0;
const PZ: f64 = -30.0;
const TX: f64 = 6.0;

fn cantilever() -> String {
    format!(
        "cantilever\nPART/1, GROUND\nMARKER/10, PART = 1\nMARKER/11, PART = 1, FLOATING\n\
         PART/2, MASS = 1, CM = 20, IP = 1E-3, 1E-3, 1E-3\nMARKER/20, PART = 2, QP = {L}, 0, 0\n\
         BEAM/1, I = 20, J = 10, LENGTH = {L}, AREA = {A}, IXX = {IXX}, IYY = {IYY}, IZZ = {IZZ}, \
         ASY = {ASY}, ASZ = {ASZ}, EMODULUS = {E}, GMODULUS = {GM}, CRATIO = 1E-4\n\
         GFORCE/1, I = 20, JFLOAT = 11, RM = 10, FX = {PX}\\ FY = {PY}\\ FZ = {PZ}\\ \
         TX = {TX}\\ TY = 0\\ TZ = 0\n\
         EQUILIBRIUM/ERROR = 1e-14, IMBALANCE = 1e-6\nEND\n"
    )
}

#[test]
fn a_timoshenko_cantilever_deflects_by_bending_plus_shear() {
    // Timoshenko: tip deflection P·L³/(3·E·I) + P·L/(κ·G·A) with κ = 1/AS, tip rotation
    // P·L²/(2·E·I) (shear does not turn the end); axial P·L/(E·A); twist T·L/(G·J).
    let y = PY * L.powi(3) / (3.0 * E * IZZ) + PY * L * ASY / (GM * A);
    let z = PZ * L.powi(3) / (3.0 * E * IYY) + PZ * L * ASZ / (GM * A);
    let rot_z = PY * L * L / (2.0 * E * IZZ);
    // A load along −z turns the end about +y.
    let rot_y = -PZ * L * L / (2.0 * E * IYY);
    let x = L + PX * L / (E * A);
    let twist = TX * L / (GM * IXX);
    let probes = [
        ("x", "DX(20, 10)"),
        ("y", "DY(20, 10)"),
        ("z", "DZ(20, 10)"),
        ("ax", "AX(20, 10)"),
        ("ay", "AY(20, 10)"),
        ("az", "AZ(20, 10)"),
        ("fy", "BEAM(1, 0, 3, 10)"),
        ("tz_j", "BEAM(1, 1, 8, 10)"),
    ];
    let (rows, _) = statics(&cantilever(), None, &probes, DimRequest::Three).expect("equilibrium");
    let got = &rows[0];
    let want = [x, y, z, twist, rot_y, rot_z];
    for (k, w) in want.iter().enumerate() {
        let rel = (got[k + 1] - w).abs() / w.abs();
        assert!(
            rel < 1e-7,
            "{}: {} vs {w} ({rel:e})",
            probes[k].0,
            got[k + 1]
        );
    }
    // The shear term is no rounding: it is a few percent of the bending.
    let shear = PY * L * ASY / (GM * A);
    assert!(shear / y > 0.02, "{}", shear / y);
    // The beam holds the load on I, and J carries the moment of its arm: T_z at J is
    // the load's moment about the root, L·PY (taken about J's origin, I at x ≈ L).
    assert!((got[7] + PY).abs() < 1e-6 * PY, "{}", got[7]);
    assert!(
        (got[8] - x * PY + y * PX).abs() < 1e-6 * L * PY,
        "{}",
        got[8]
    );
}

#[test]
fn a_mass_on_a_diagonal_field_oscillates_at_the_springs_period() {
    // m = 2 on K = diag(800, …) from x = 1.1 (LENGTH 1): x(t) − 1 = 0.1·cos(√(k/m)·t).
    let (m, k) = (2.0_f64, 800.0_f64);
    let kd: Vec<String> = (0..36)
        .map(|n| {
            if n % 7 == 0 {
                format!("{k}")
            } else {
                "0".into()
            }
        })
        .collect();
    let text = format!(
        "field oscillator\nPART/1, GROUND\nMARKER/10, PART = 1\n\
         PART/2, MASS = {m}, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2, QP = 1.1, 0, 0\n\
         FIELD/1, I = 20, J = 10, KMATRIX = {}, LENGTH = 1, 0, 0, 0, 0, 0\nEND\n",
        kd.join(", ")
    );
    let mut r = RunRequest::dataset("field.adm", &text);
    (r.end, r.output_step, r.error) = (Some(1.0), Some(1e-3), Some(1e-8));
    r.probes = vec![("x".into(), "DX(20, 10)".into())];
    let mut rows = Vec::new();
    let mut sink = |row: &[f64]| -> std::io::Result<()> {
        rows.push(row.to_vec());
        Ok(())
    };
    run(&r, &mut sink, None).expect("run");
    let w = (k / m).sqrt();
    for row in &rows {
        let want = 1.0 + 0.1 * (w * row[0]).cos();
        assert!(
            (row[1] - want).abs() < 1e-5,
            "t = {}: {} vs {want}",
            row[0],
            row[1]
        );
    }
    // And the period itself, from the upward zero crossings of x − 1.
    let ups: Vec<f64> = rows
        .windows(2)
        .filter(|p| p[0][1] < 1.0 && p[1][1] >= 1.0)
        .map(|p| p[0][0] + (1.0 - p[0][1]) / (p[1][1] - p[0][1]) * (p[1][0] - p[0][0]))
        .collect();
    assert!(ups.len() >= 2, "{ups:?}");
    let period = (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64;
    let want = 2.0 * PI * (m / k).sqrt();
    assert!((period - want).abs() < 1e-4 * want, "{period} vs {want}");
}
