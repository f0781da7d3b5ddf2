//! Reactions out of the plane in 2D runs: a planar scene runs in 2D, where its
//! out-of-plane equations are left out, yet the revolute of
//! `tests/models/pendulum_out_of_plane_loads.adm` carries an out-of-plane force (GFORCE
//! along z) and the in-plane moments a product of inertia needs. Checked against Euler's
//! equations about the CM, and against the same run built in 3D.

use crate::adams::models_dir;
use crate::run::{named, run_probed};

const MASS: f64 = 2.0;
const G: f64 = 9.81;
const IZZ: f64 = 0.3;
/// IXZ as the dataset gives it: the tensor entry is −IXZ (multibody spec §2.2).
const IXZ: f64 = 0.05;
const FZ: f64 = 5.0;

fn run(dim: &str) -> crate::run::Csv {
    let model = models_dir().join("pendulum_out_of_plane_loads.adm");
    let args = [
        "--end",
        "1",
        "--output-step",
        "0.1",
        "--error",
        "1e-9",
        "--dim",
        dim,
    ];
    let probes = named(&[
        ("th", "AZ(20,10)"),
        ("w", "WZ(20)"),
        ("al", "WDTZ(20)"),
        ("fy", "JOINT(1,0,3,0)"),
        ("fz", "JOINT(1,0,4,0)"),
        ("tx", "JOINT(1,0,6,0)"),
        ("ty", "JOINT(1,0,7,0)"),
    ]);
    run_probed(&model, &args, &probes)
}

#[test]
fn a_2d_run_reports_the_out_of_plane_reactions_eulers_equations_give() {
    let csv = run("2");
    let [th, w, al, fy, fz, tx, ty] = ["th", "w", "al", "fy", "fz", "tx", "ty"].map(|c| csv.col(c));
    // At rest at t = 0: α = −m·g·L/(IZZ + m·L²), and the y force makes m·(α·L + g).
    let a0 = -MASS * G / (IZZ + MASS);
    assert!((al[0] - a0).abs() < 1e-9 * a0.abs(), "α(0) = {}", al[0]);
    assert!((fy[0] - MASS * (a0 + G)).abs() < 1e-9, "fy(0) = {}", fy[0]);
    for k in 0..th.len() {
        let (s, c) = th[k].sin_cos();
        // The angular momentum about the CM, in-plane part: ω·(J₀₂, J₁₂) with the
        // tensor's products −IXZ turned by θ; its rate plus the moment of the pivot's
        // z force about the CM, arm (−cos θ, −sin θ, 0), is the joint's torque.
        let hx = -IXZ * al[k] * c + IXZ * w[k] * w[k] * s;
        let hy = -IXZ * al[k] * s - IXZ * w[k] * w[k] * c;
        let (want_tx, want_ty) = (hx - FZ * s, hy + FZ * c);
        let t = csv.rows[k][0];
        assert!((fz[k] + FZ).abs() < 1e-9, "fz({t}) = {}", fz[k]);
        assert!(
            (tx[k] - want_tx).abs() < 1e-7,
            "tx({t}) = {} vs {want_tx}",
            tx[k]
        );
        assert!(
            (ty[k] - want_ty).abs() < 1e-7,
            "ty({t}) = {} vs {want_ty}",
            ty[k]
        );
    }
}

#[test]
fn the_2d_and_3d_runs_give_the_same_reactions() {
    let (two, three) = (run("2"), run("3"));
    for c in ["fy", "fz", "tx", "ty"] {
        let (a, b) = (two.col(c), three.col(c));
        let top = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!((x - y).abs() < 1e-8 * top, "{c} row {k}: 2D {x}, 3D {y}");
        }
    }
}
