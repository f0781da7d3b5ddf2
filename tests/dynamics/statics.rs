//! Static equilibrium (issue 26 §1) against closed forms: every expected value comes
//! from the mechanics (a formula, or a scalar equation solved here by bisection or a
//! small Newton of the test's own), never from mbfx's output. Each model runs in 2D and
//! in 3D (the 3D constraint rows and their tangents differ), and the named failures
//! (no equilibrium within MAXIT, a limit that holds every step, a neutral or unstable
//! direction) carry their codes and name the coordinate and element.

use mbfx::session::request::{run, RunDone, RunFailed, RunRequest};
use mbfx::session::DimRequest;
use std::f64::consts::PI;
use std::path::PathBuf;

const G: f64 = 9.81;

/// Tight settings: the closed forms are checked to 1e-9.
const TIGHT: &str = "EQUILIBRIUM/ERROR = 1e-12, IMBALANCE = 1e-10\n";

/// Runs `text` with `--statics` (and `--end` when given), probes `probes`; the rows.
pub(crate) fn statics(
    text: &str,
    end: Option<f64>,
    probes: &[(&str, &str)],
    dim: DimRequest,
) -> Result<(Vec<Vec<f64>>, RunDone), Box<RunFailed>> {
    let mut r = RunRequest::dataset("statics.adm", text);
    (r.statics, r.end, r.dim) = (true, end, dim);
    r.probes = probes
        .iter()
        .map(|(n, e)| (n.to_string(), e.to_string()))
        .collect();
    let mut rows = Vec::new();
    let mut sink = |row: &[f64]| -> std::io::Result<()> {
        rows.push(row.to_vec());
        Ok(())
    };
    let done = run(&r, &mut sink, None)?;
    Ok((rows, done))
}

/// The root of `f` in [a, b] (a sign change) by bisection to the last bit.
fn bisect(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let fa = f(a);
    assert!(fa * f(b) < 0.0, "no sign change in [{a}, {b}]");
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if m == a || m == b {
            break;
        }
        if (f(m) < 0.0) == (fa < 0.0) {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

/// A 2 kg block on a vertical rail hanging from a spring (K = 500, free length 1)
/// whose top is at the origin; released at the free length.
fn hanging(extra: &str) -> String {
    format!(
        "hanging spring-mass\nPART/1, GROUND\nMARKER/10, PART = 1\n\
         MARKER/11, PART = 1, REULER = 0, -90D, 0\nMARKER/12, PART = 1, QP = 0, -10, 0\n\
         PART/2, MASS = 2, CM = 20, IP = 0.1, 0.1, 0.1\nMARKER/20, PART = 2, QP = 0, -1, 0\n\
         MARKER/21, PART = 2, QP = 0, -1, 0, REULER = 0, -90D, 0\n\
         JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
         SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 500, C = 3, LENGTH = 1\n\
         ACCGRAV/JGRAV = -{G}\n{TIGHT}{extra}END\n"
    )
}

#[test]
fn hanging_spring_mass_stretches_by_m_g_over_k() {
    let y = -1.0 - 2.0 * G / 500.0;
    for dim in [DimRequest::Auto, DimRequest::Three] {
        let probes = [("y", "DY(20)"), ("f", "SPDP(1, 0, 3, 0)")];
        let (rows, done) = statics(&hanging(""), None, &probes, dim).expect("equilibrium");
        assert_eq!(rows.len(), 1, "one row: the equilibrium");
        assert!(
            (rows[0][1] - y).abs() < 1e-12,
            "{dim:?}: y {} vs {y}",
            rows[0][1]
        );
        // The spring holds the weight: its force on the block is +m g along y.
        assert!(
            (rows[0][2] - 2.0 * G).abs() < 1e-9,
            "{dim:?}: {}",
            rows[0][2]
        );
        let eq = &done.summary.equilibria[0];
        assert!(eq.iterations <= 3, "{eq:?}");
        assert!(eq.imbalance < 1e-10);
        assert!(done.summary.text().contains("static equilibrium at time 0"));
    }
}

#[test]
fn the_dynamics_start_from_the_equilibrium_and_stay_there() {
    // Released at the equilibrium, the damped block does not move.
    let y = -1.0 - 2.0 * G / 500.0;
    let (rows, _) = statics(
        &hanging(""),
        Some(1.0),
        &[("y", "DY(20)")],
        DimRequest::Auto,
    )
    .expect("run");
    assert_eq!(rows.len(), 101);
    for r in &rows {
        assert!((r[1] - y).abs() < 1e-9, "t = {}: {} vs {y}", r[0], r[1]);
    }
}

#[test]
fn a_quasi_static_run_follows_a_growing_load() {
    // SFORCE/2 pulls the block down with 10·TIME: y(t) = −1 − (m g + 10 t)/k.
    let text = hanging("SFORCE/2, TRANSLATION, I = 20, J = 12, FUNCTION = -10*TIME\n");
    let dir = std::env::temp_dir().join(format!("mbfx-quasi-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch");
    std::fs::write(dir.join("m.adm"), &text).expect("dataset");
    let acf = dir.join("q.acf");
    std::fs::write(
        &acf,
        "m.adm\nout\nEQUILIBRIUM/ERROR = 1e-12, IMBALANCE = 1e-10\nSIMULATE/STATICS, END = 1, STEPS = 4\nSTOP\n",
    )
    .expect("command file");
    let mut r = RunRequest::file(&acf);
    r.probes = vec![("y".into(), "DY(20)".into())];
    let mut rows = Vec::new();
    let mut sink = |row: &[f64]| -> std::io::Result<()> {
        rows.push(row.to_vec());
        Ok(())
    };
    let done = run(&r, &mut sink, None).expect("quasi-static run");
    let times: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(times, [0.0, 0.25, 0.5, 0.75, 1.0]);
    for r in &rows {
        let y = -1.0 - (2.0 * G + 10.0 * r[0]) / 500.0;
        assert!((r[1] - y).abs() < 1e-12, "t = {}: {} vs {y}", r[0], r[1]);
    }
    assert_eq!(done.summary.equilibria.len(), 5);
    assert!(done.summary.text().contains("5 static equilibria"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// An inverted pendulum (1 kg, CM 1 m above a pin at the origin) held by a torsion
/// spring k·θ about the pin, θ from upright, started at `theta0`.
fn torsion_pendulum(k: f64, theta0: f64, extra: &str) -> String {
    format!(
        "torsion pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
         PART/2, MASS = 1, CM = 20, IP = 0.01, 0.01, 0.01, REULER = {theta0}, 0, 0\n\
         MARKER/20, PART = 2, QP = 0, 1, 0\nMARKER/21, PART = 2\n\
         JOINT/1, REVOLUTE, I = 21, J = 10\n\
         SFORCE/1, ROTATION, I = 21, J = 10, FUNCTION = -{k}*AZ(21, 10)\n\
         ACCGRAV/JGRAV = -{G}\n{TIGHT}{extra}END\n"
    )
}

#[test]
fn a_pendulum_held_by_a_torsion_spring_where_k_theta_equals_m_g_l_sin_theta() {
    // The gravity moment about the pin is m g L sin θ (tipping), the spring's −k θ.
    // With m g L = 2k the upright position is unstable and the equilibrium is the root
    // of k θ = m g L sin θ in (0, π).
    let k = G / 2.0;
    let theta = bisect(|t| k * t - G * t.sin(), 0.5, 3.0);
    for dim in [DimRequest::Auto, DimRequest::Three] {
        let (rows, done) = statics(
            &torsion_pendulum(k, 1.5, ""),
            None,
            &[
                ("theta", "AZ(21, 10)"),
                ("x", "DX(20)"),
                ("torque", "SFORCE(1, 0, 8, 0)"),
            ],
            dim,
        )
        .expect("equilibrium");
        let r = &rows[0];
        assert!(
            (r[1] - theta).abs() < 1e-9,
            "{dim:?}: θ {} vs {theta}",
            r[1]
        );
        assert!(
            (r[2] + theta.sin()).abs() < 1e-9,
            "{dim:?}: x {} vs {}",
            r[2],
            -theta.sin()
        );
        assert!((r[3] + k * theta).abs() < 1e-8, "{dim:?}: torque {}", r[3]);
        let eq = &done.summary.equilibria[0];
        // ALIMIT (10°) holds the first steps: 0.4 rad to go.
        assert!(eq.limited >= 1 && eq.iterations < 15, "{eq:?}");
    }
}

#[test]
fn an_unstable_equilibrium_is_named() {
    // Upright, the spring too weak (k < m g L): an equilibrium, but unstable.
    let text = torsion_pendulum(G / 2.0, 0.0, "");
    let f = refused(statics(&text, None, &[], DimRequest::Auto));
    assert_eq!(f.code.as_str(), "E0806", "{}", f.cause);
    assert!(
        f.cause.contains("unstable along PART/2 rotation about z"),
        "{}",
        f.cause
    );
    assert!(f.cause.contains("JOINT/1"), "{}", f.cause);
    // The diagnostic points at the element's statement.
    let shown = f.render(false);
    assert!(shown.contains("JOINT/1, REVOLUTE"), "{shown}");
}

#[test]
fn a_mechanism_no_spring_holds_is_neutral() {
    // The pendulum with neither spring nor gravity: any angle is an equilibrium.
    let text = torsion_pendulum(0.0, 0.3, "").replace(&format!("ACCGRAV/JGRAV = -{G}\n"), "");
    let f = refused(statics(&text, None, &[], DimRequest::Auto));
    assert_eq!(f.code.as_str(), "E0806", "{}", f.cause);
    assert!(
        f.cause.contains(
            "nothing holds PART/2 rotation about z, which JOINT/1 (REVOLUTE) leaves free"
        ),
        "{}",
        f.cause
    );
    // A block on a rail under gravity without its spring: no equilibrium anywhere.
    let text = hanging("").replace("K = 500", "K = 0");
    let f = refused(statics(&text, None, &[], DimRequest::Auto));
    assert_eq!(f.code.as_str(), "E0806", "{}", f.cause);
    assert!(f.cause.contains("PART/2 y translation"), "{}", f.cause);
    assert!(f.cause.contains("JOINT/1 (TRANSLATIONAL)"), "{}", f.cause);
}

#[test]
fn maxit_and_the_step_limits_are_named_failures() {
    let k = G / 2.0;
    // ALIMIT = 2°: eight iterations cover 0.28 rad of the 0.4 needed.
    let text = torsion_pendulum(k, 1.5, "EQUILIBRIUM/MAXIT = 8, ALIMIT = 2D\n");
    let f = refused(statics(&text, None, &[], DimRequest::Auto));
    assert_eq!(f.code.as_str(), "E0807", "{}", f.cause);
    assert!(f.cause.contains("ALIMIT"), "{}", f.cause);
    assert!(f.cause.contains("PART/2 rotation about z"), "{}", f.cause);
    // No limit in the way, one iteration: the imbalance left is named.
    let text = torsion_pendulum(k, 1.5, "EQUILIBRIUM/MAXIT = 1, ALIMIT = 90D\n");
    let f = refused(statics(&text, None, &[], DimRequest::Auto));
    assert_eq!(f.code.as_str(), "E0805", "{}", f.cause);
    assert!(f.cause.contains("MAXIT = 1"), "{}", f.cause);
    assert!(f.cause.contains("PART/2"), "{}", f.cause);
}

/// The crank–slider of `examples/scenes/slider_crank_driven.adm` (r = 0.1, l = 0.4)
/// without its drive or gravity: a torsion spring k·θ on the crank and a constant force
/// F pushing the slider toward the crank. Set up at crank angle `theta0`.
fn slider_crank(k: f64, force: f64, theta0: f64) -> String {
    let (r, l) = (0.1f64, 0.4f64);
    let (bx, by) = (r * theta0.cos(), r * theta0.sin());
    let c = bx + (l * l - by * by).sqrt();
    format!(
        "slider-crank statics\nPART/1, GROUND\nMARKER/101, PART = 1\n\
         MARKER/102, PART = 1, REULER = 90D, 90D, 0D\nMARKER/103, PART = 1, QP = 10, 0, 0\n\
         PART/2, MASS = 1, CM = 201, IP = 1E-5, 8.3E-4, 8.3E-4\n\
         MARKER/201, PART = 2, QP = {}, {}, 0\nMARKER/202, PART = 2\nMARKER/203, PART = 2, QP = {bx}, {by}, 0\n\
         PART/3, MASS = 2, CM = 301, IP = 1E-5, 0.027, 0.027\n\
         MARKER/301, PART = 3, QP = {}, {}, 0\nMARKER/302, PART = 3, QP = {bx}, {by}, 0\n\
         MARKER/303, PART = 3, QP = {c}, 0, 0\n\
         PART/4, MASS = 0.5, CM = 401, IP = 1E-4, 1E-4, 1E-4\nMARKER/401, PART = 4, QP = {c}, 0, 0\n\
         MARKER/402, PART = 4, QP = {c}, 0, 0\nMARKER/403, PART = 4, QP = {c}, 0, 0, REULER = 90D, 90D, 0D\n\
         JOINT/1, REVOLUTE, I = 202, J = 101\nJOINT/2, REVOLUTE, I = 302, J = 203\n\
         JOINT/3, REVOLUTE, I = 303, J = 402\nJOINT/4, TRANSLATIONAL, I = 403, J = 102\n\
         SFORCE/1, ROTATION, I = 202, J = 101, FUNCTION = -{k}*(AZ(202, 101) + {theta0})\n\
         SFORCE/2, TRANSLATION, I = 401, J = 103, FUNCTION = {force}\n{TIGHT}END\n",
        bx / 2.0,
        by / 2.0,
        (bx + c) / 2.0,
        by / 2.0,
    )
}

#[test]
fn a_slider_crank_balances_a_constant_force_against_a_spring() {
    // Virtual work: −k θ δθ − F δx_C = 0 with x_C = r cos θ + √(l² − r² sin² θ), so
    // k θ = F r sin θ (1 + r cos θ / √(l² − r² sin² θ)).
    let (r, l, k, force, theta0) = (0.1f64, 0.4f64, 1.0, 20.0, 1.6);
    let xc = |t: f64| r * t.cos() + (l * l - (r * t.sin()).powi(2)).sqrt();
    let balance = |t: f64| {
        k * t - force * r * t.sin() * (1.0 + r * t.cos() / (l * l - (r * t.sin()).powi(2)).sqrt())
    };
    let theta = bisect(balance, 1.0, 2.5);
    for dim in [DimRequest::Auto, DimRequest::Three] {
        let (rows, _) = statics(
            &slider_crank(k, force, theta0),
            None,
            &[("theta", "AZ(202, 101)"), ("x", "DX(401)")],
            dim,
        )
        .expect("equilibrium");
        let got = rows[0][1] + theta0;
        assert!((got - theta).abs() < 1e-9, "{dim:?}: θ {got} vs {theta}");
        assert!(
            (rows[0][2] - xc(theta)).abs() < 1e-10,
            "{dim:?}: x {}",
            rows[0][2]
        );
    }
}

/// A chain of `n` links (1 kg, 0.5 m, CM at the middle) pinned end to end from a pin
/// at the origin, laid out along +x, each pin with a torsion spring k on the relative
/// angle (free when straight); gravity −y.
fn spring_chain(n: usize, k: f64) -> String {
    let len = 0.5;
    let mut t = String::from("spring chain\nPART/1, GROUND\nMARKER/10, PART = 1\n");
    for i in 1..=n {
        let (p, x0) = (i + 1, (i - 1) as f64 * len);
        t += &format!(
            "PART/{p}, MASS = 1, CM = {p}0, IP = 0.001, 0.02, 0.02\n\
             MARKER/{p}0, PART = {p}, QP = {}, 0, 0\nMARKER/{p}1, PART = {p}, QP = {x0}, 0, 0\n\
             MARKER/{p}2, PART = {p}, QP = {}, 0, 0\n",
            x0 + len / 2.0,
            x0 + len
        );
        let j = match i {
            1 => "10".to_string(),
            _ => format!("{}2", p - 1),
        };
        t += &format!(
            "JOINT/{i}, REVOLUTE, I = {p}1, J = {j}\n\
             SFORCE/{i}, ROTATION, I = {p}1, J = {j}, FUNCTION = -{k}*AZ({p}1, {j})\n"
        );
    }
    t + &format!("ACCGRAV/JGRAV = -{G}\n{TIGHT}END\n")
}

/// The chain's equilibrium angles from the horizontal, by Newton on the potential
/// V(φ) = Σ ½k(φᵢ − φᵢ₋₁)² + Σ m g yⱼ, yⱼ = Σ_{i<j} L sin φᵢ + (L/2) sin φⱼ, its
/// gradient and Hessian written out.
fn chain_angles(n: usize, k: f64) -> Vec<f64> {
    let (len, m) = (0.5, 1.0);
    let mut phi = vec![0.0f64; n];
    for _ in 0..100 {
        // ∂V/∂φᵢ = k(ψᵢ − ψᵢ₊₁) + m g L cos φᵢ (½ + (n − 1 − i)).
        let weight = |i: usize| m * G * len * (0.5 + (n - 1 - i) as f64);
        let mut grad = vec![0.0; n];
        let mut hess = vec![vec![0.0; n]; n];
        for i in 0..n {
            let psi = phi[i] - if i == 0 { 0.0 } else { phi[i - 1] };
            grad[i] += k * psi;
            hess[i][i] += k;
            if i > 0 {
                grad[i - 1] -= k * psi;
                hess[i - 1][i - 1] += k;
                hess[i][i - 1] -= k;
                hess[i - 1][i] -= k;
            }
            grad[i] += weight(i) * phi[i].cos();
            hess[i][i] -= weight(i) * phi[i].sin();
        }
        // Gaussian elimination on the small system.
        let mut a = hess;
        let mut b: Vec<f64> = grad.iter().map(|g| -g).collect();
        for c in 0..n {
            let p = (c..n)
                .max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))
                .unwrap_or(c);
            a.swap(c, p);
            b.swap(c, p);
            for r in c + 1..n {
                let f = a[r][c] / a[c][c];
                let pivot = a[c].clone();
                for (x, p) in a[r][c..].iter_mut().zip(&pivot[c..]) {
                    *x -= f * p;
                }
                b[r] -= f * b[c];
            }
        }
        let mut step = vec![0.0; n];
        for r in (0..n).rev() {
            let s: f64 = (r + 1..n).map(|c| a[r][c] * step[c]).sum();
            step[r] = (b[r] - s) / a[r][r];
        }
        for i in 0..n {
            phi[i] += step[i];
        }
        if step.iter().all(|s| s.abs() < 1e-15) {
            break;
        }
    }
    phi
}

#[test]
fn a_planar_chain_held_by_torsion_springs_settles_where_the_potential_is_least() {
    let (n, k) = (4, 40.0);
    let want = chain_angles(n, k);
    assert!(
        want.iter().all(|a| *a < -0.05 && *a > -PI / 2.0),
        "{want:?}"
    );
    let probes: Vec<(String, String)> = (1..=n)
        .map(|i| (format!("phi{i}"), format!("AZ({}0)", i + 1)))
        .collect();
    let probes: Vec<(&str, &str)> = probes
        .iter()
        .map(|(a, b)| (a.as_str(), b.as_str()))
        .collect();
    for dim in [DimRequest::Auto, DimRequest::Three] {
        let (rows, done) = statics(&spring_chain(n, k), None, &probes, dim).expect("equilibrium");
        for i in 0..n {
            assert!(
                (rows[0][i + 1] - want[i]).abs() < 1e-9,
                "{dim:?} link {}: {} vs {}",
                i + 1,
                rows[0][i + 1],
                want[i]
            );
        }
        // Every pin is reported, the first carrying the chain's weight.
        let eq = &done.summary.equilibria[0];
        assert_eq!(eq.reactions.len(), n);
        assert!(
            (eq.reactions[0].force.y - n as f64 * G).abs() < 1e-8,
            "{eq:?}"
        );
    }
}

#[test]
fn the_corpus_statics_command_file_hangs_its_pendulum_below_the_pin() {
    // adams_rescale: a rod (40.6 lbm, CM at (3, 5.5)) pinned at (0, 12) with a ball
    // (26.7 lbm, CM at (6, −1)) fixed to it; SIMULATE/STATIC, then 5 s of dynamics. At
    // equilibrium the combined CM hangs straight below the pin: the start turned about
    // the pin by the angle that takes the CM's offset to (0, −|c|); then nothing moves.
    let acf = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/corpus/adams/bthornton191__adams_rescale/models/rescale_analysis.acf");
    if !acf.is_file() {
        eprintln!("skipped: the shared corpus is not beside the repository");
        return;
    }
    let (m2, m3) = (40.60564164f64, 26.71217658f64);
    let pin = (0.0f64, 12.0f64);
    let (p7, p8) = ((3.0f64, 5.5f64), (6.0f64, -1.0f64));
    let c = (
        (m2 * (p7.0 - pin.0) + m3 * (p8.0 - pin.0)) / (m2 + m3),
        (m2 * (p7.1 - pin.1) + m3 * (p8.1 - pin.1)) / (m2 + m3),
    );
    let turn = (-PI / 2.0) - c.1.atan2(c.0);
    let at = |p: (f64, f64)| {
        let (x, y) = (p.0 - pin.0, p.1 - pin.1);
        (
            pin.0 + x * turn.cos() - y * turn.sin(),
            pin.1 + x * turn.sin() + y * turn.cos(),
        )
    };
    let (w7, w8) = (at(p7), at(p8));
    let mut r = RunRequest::file(&acf);
    r.probes = ["x7=DX(7)", "y7=DY(7)", "x8=DX(8)", "y8=DY(8)"]
        .iter()
        .map(|p| mbfx::session::request::parse_probe(p))
        .collect();
    let mut rows = Vec::new();
    let mut sink = |row: &[f64]| -> std::io::Result<()> {
        rows.push(row.to_vec());
        Ok(())
    };
    let done = run(&r, &mut sink, None).expect("the command file runs");
    assert_eq!(rows.len(), 501);
    assert_eq!(done.summary.equilibria.len(), 1);
    for row in &rows {
        for (k, want) in [w7.0, w7.1, w8.0, w8.1].into_iter().enumerate() {
            // ERROR 1e-4 (Adams' default, relative to the 14-inch model) at the
            // equilibrium, then the dynamics hold it.
            assert!(
                (row[k + 1] - want).abs() < 1e-6,
                "t = {}: column {} is {} vs {want}",
                row[0],
                k + 1,
                row[k + 1]
            );
        }
    }
}

/// The failure of a run expected to fail.
fn refused<T>(r: Result<T, Box<RunFailed>>) -> Box<RunFailed> {
    match r {
        Ok(_) => panic!("the run was expected to fail"),
        Err(f) => f,
    }
}

#[test]
fn ground_alone_and_a_free_body_do_not_panic() {
    // Nothing moves: ground is its own equilibrium, one row.
    let (rows, done) =
        statics("g\nPART/1, GROUND\nEND\n", None, &[], DimRequest::Auto).expect("ground alone");
    assert_eq!(rows.len(), 1);
    assert!(done.summary.text().contains("no part moves"));
    // A body under gravity held by nothing: neutral, named as held by no constraint.
    let text = "free\nPART/1, GROUND\nPART/2, MASS = 1, CM = 20, IP = 1, 1, 1\n\
                MARKER/20, PART = 2\nACCGRAV/JGRAV = -9.81\nEND\n";
    let f = refused(statics(text, None, &[], DimRequest::Auto));
    assert_eq!(f.code.as_str(), "E0806", "{}", f.cause);
    assert!(f.cause.contains("held by no constraint"), "{}", f.cause);
}
