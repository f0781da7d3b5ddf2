//! State elements (issue 40 §3) against closed forms written here: DIFF (explicit and
//! IMPLICIT), LSE and TFSISO step responses, a force driven by a DIFF, STATIC_HOLD in
//! statics, and the wiper plant of the corpus, which lacks only DIFF; the states under
//! each integrator's own error control (their error falls with ERROR, a stiff DIFF takes
//! long steps) and a PI-controlled pendulum at its closed-form rest. The datasets are
//! under `tests/data/states/`, each with its closed form in its title line.

use crate::run::{integrator_args, named, run_probed, run_raw};
use mbfx::session::request::{run, RunRequest};
use std::path::PathBuf;

/// The BDF, the second-order family and the explicit method.
const INTEGRATORS: [&str; 4] = ["gstiff", "hht", "galpha", "dopri853"];

fn data(file: &str) -> PathBuf {
    crate::run::test_data("states").join(file)
}

/// A probe's column name, its expression and its closed form in time.
type Probe<'a> = (&'a str, &'a str, &'a dyn Fn(f64) -> f64);

/// Runs `file` 0–`end` at 0.05 s with `integrator` at ERROR `error`, probing `probes`;
/// each probe's column against its closed form within `tol`.
fn check(file: &str, (integrator, error): (&str, &str), end: &str, probes: &[Probe], tol: f64) {
    let mut args = vec!["--end", end, "--output-step", "0.05", "--error", error];
    args.extend(integrator_args(integrator));
    let pairs: Vec<(&str, &str)> = probes.iter().map(|(n, e, _)| (*n, *e)).collect();
    let csv = run_probed(&data(file), &args, &named(&pairs));
    let t = csv.time();
    assert!(t.len() > 10, "{file}: {} rows", t.len());
    for (name, expr, exact) in probes {
        let got = csv.col(name);
        let worst = t
            .iter()
            .zip(&got)
            .map(|(&t, &g)| (g - exact(t)).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < tol,
            "{file} with {integrator}: {expr} is off its closed form by {worst:e} (tolerance {tol:e})"
        );
    }
}

#[test]
fn diff_states_follow_exp_sin_and_an_implicit_quadratic_with_every_integrator_family() {
    for integrator in INTEGRATORS {
        check(
            "diff_closed_forms.adm",
            (integrator, "1e-6"),
            "2",
            &[
                ("decay", "DIF(1)", &|t| (-t / 0.5).exp()),
                ("sine", "DIF(2)", &|t: f64| t.sin()),
                ("cosine", "DIF1(2)", &|t: f64| t.cos()),
                ("quadratic", "DIF(3)", &|t| 1.0 + t * t),
                ("rate", "DIF1(3)", &|t| 2.0 * t),
            ],
            1e-4,
        );
    }
}

#[test]
fn lse_and_tfsiso_follow_their_analytic_step_responses() {
    let lag = |t: f64| 1.0 - (-2.0 * t).exp();
    // ωn²/(s² + 2ζωn·s + ωn²), unit step from rest.
    let (wn, zeta) = (2.0f64, 0.5f64);
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let second = move |t: f64| {
        1.0 - (-zeta * wn * t).exp()
            * ((wd * t).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * t).sin())
    };
    for integrator in INTEGRATORS {
        check(
            "linear_step_responses.adm",
            (integrator, "1e-6"),
            "4",
            &[
                ("lse_lag", "ARYVAL(13, 1)", &lag),
                ("lse_lag_state", "ARYVAL(11, 1)", &lag),
                ("lse_input", "ARYVAL(12, 1)", &|_| 1.0),
                ("lse_second", "ARYVAL(23, 1)", &second),
                ("tf_lag", "ARYVAL(33, 1)", &lag),
                ("tf_second", "ARYVAL(43, 1)", &second),
            ],
            1e-4,
        );
    }
}

#[test]
fn a_force_driven_by_a_diff_state_oscillates_at_its_closed_form() {
    // 2·z̈ = −50·(z − z₀) with ż(0) = 1: z − z₀ = 0.2·sin(5t), and DIF(1) is that too.
    for integrator in INTEGRATORS {
        check(
            "diff_drives_force.adm",
            (integrator, "1e-7"),
            "2",
            &[
                ("z", "DZ(20, 10)", &|t: f64| 0.2 * (5.0 * t).sin()),
                ("y", "DIF(1)", &|t: f64| 0.2 * (5.0 * t).sin()),
            ],
            // 0.15 % of the amplitude: HHT's own period error over ten swings.
            3e-4,
        );
    }
}

#[test]
fn statics_holds_static_hold_states_at_their_ic_and_settles_the_others() {
    let text = std::fs::read_to_string(data("static_hold.adm")).unwrap();
    let mut r = RunRequest::dataset("static_hold.adm", &text);
    r.statics = true;
    r.probes = named(&[("z", "DZ(20, 10)"), ("held", "DIF(1)"), ("free", "DIF(2)")]);
    let mut rows = Vec::new();
    let mut sink = |row: &[f64]| -> std::io::Result<()> {
        rows.push(row.to_vec());
        Ok(())
    };
    run(&r, &mut sink, None).unwrap_or_else(|e| panic!("statics failed: {e:?}"));
    let row = rows.last().expect("a row");
    // −100·z + 3 + 2·1 − 1·9.81 = 0.
    let z = (3.0 + 2.0 - 9.81) / 100.0;
    assert!((row[1] - z).abs() < 1e-8, "z = {} vs {z}", row[1]);
    assert!((row[2] - 3.0).abs() < 1e-12, "held DIFF at {}", row[2]);
    assert!((row[3] - 1.0).abs() < 1e-8, "free DIFF at {}", row[3]);
}

#[test]
fn the_wiper_plant_runs_with_its_diff_and_no_not_modelled_warning() {
    let model = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(
        "../shared/corpus/adams/Dinh-Hao-Nguyen__MSCAdams_Wiper_Project/ControlSimulink/Controls_Plant_5.adm",
    );
    let out = run_raw(
        &model,
        &[
            "--end",
            "0.2",
            "--output-step",
            "0.01",
            "--probe",
            "e=DIF(1)",
            "--probe",
            "w=WZ(99)",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("not modelled"), "{stderr}");
    // DIFF/1 integrates VARVAL(29) = 20 − WZ(99): its rate is read back the same.
    let csv = crate::run::Csv::parse(&String::from_utf8_lossy(&out.stdout));
    let (t, e) = (csv.time(), csv.col("e"));
    assert_eq!(e[0], 0.0, "IC = 0");
    assert!(e.iter().all(|v| v.is_finite()));
    // The integral of 20 − ω: ω starts at rest, so over the first rows e ≈ 20·t.
    assert!(
        (e[1] - 20.0 * t[1]).abs() < 0.05 * 20.0 * t[1],
        "e = {} at {}",
        e[1],
        t[1]
    );
}

#[test]
fn an_lse_controlled_pendulum_linearizes_with_the_controller_state_in_a() {
    // J·θ̈ = −m·g·d·θ − y, ẋ = a·x + b·θ, y = c·x + dd·θ (LSE/1 on u = AZ), J = i + m·d².
    let (m, d, i, g) = (2.0, 1.5, 0.5, 9.81);
    let (a, b, c, dd) = (-3.0, 2.0, 4.0, 10.0);
    let text = format!(
        "LSE-controlled pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
         PART/2, MASS = {m}, CM = 20, IP = {i}, {i}, {i}\nMARKER/20, PART = 2, QP = 0, -{d}, 0\n\
         MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 10\nACCGRAV/JGRAV = -{g}\n\
         VARIABLE/1, FUNCTION = AZ(21, 10)\n\
         ARRAY/11, X\nARRAY/12, U, VARIABLES = 1\nARRAY/13, Y\n\
         MATRIX/1, FULL = RORDER, ROWS = 1, COLUMNS = 1, VALUES = {a}\n\
         MATRIX/2, FULL = RORDER, ROWS = 1, COLUMNS = 1, VALUES = {b}\n\
         MATRIX/3, FULL = RORDER, ROWS = 1, COLUMNS = 1, VALUES = {c}\n\
         MATRIX/4, FULL = RORDER, ROWS = 1, COLUMNS = 1, VALUES = {dd}\n\
         LSE/1, X = 11, U = 12, Y = 13, A = 1, B = 2, C = 3, D = 4\n\
         SFORCE/1, ROTATIONAL, I = 21, J = 10, FUNCTION = -ARYVAL(13, 1)\nEND\n"
    );
    let j = i + m * d * d;
    // On (θ, θ̇, x); a coordinate z = s·θ (the CM's x translation, s = d, or the rotation,
    // s = 1) scales A by diag(s, s, 1).
    let want = |s: f64| {
        [
            [0.0, 1.0, 0.0],
            [-(m * g * d + dd) / j, 0.0, -c * s / j],
            [b / s, 0.0, a],
        ]
    };
    for dim in [
        mbfx::session::DimRequest::Auto,
        mbfx::session::DimRequest::Three,
    ] {
        let mut r = RunRequest::dataset("lse_pendulum.adm", &text);
        (r.statics, r.dim) = (true, dim);
        r.linear = Some(mbfx::session::request::LinearRequest::eigensol(None));
        let mut sink = |_: &[f64]| -> std::io::Result<()> { Ok(()) };
        let done = run(&r, &mut sink, None).unwrap_or_else(|f| panic!("{}", f.cause));
        let lin = &done.summary.linear[0].linearized;
        let names = lin.state_names();
        // The revolute's own rotation is the coordinate (issue 41 §4).
        assert_eq!(names[0], "JOINT/1 (REVOLUTE) rotation", "{dim:?}");
        let scale = 1.0;
        assert_eq!(
            names[1..],
            [format!("d/dt {}", names[0]), "LSE/1 x1".into()]
        );
        let got = lin.state_matrix().unwrap();
        for (r, row) in want(scale).iter().enumerate() {
            for (k, w) in row.iter().enumerate() {
                let e = got[(r, k)];
                assert!(
                    (e - w).abs() < 1e-7 * (1.0 + w.abs()),
                    "{dim:?}: A[{r}][{k}] = {e} vs {w}\n{got}"
                );
            }
        }
    }
}

/// The steps of a run from its summary line ("gstiff: N steps (M rejected), …").
fn steps(stderr: &str) -> usize {
    stderr
        .lines()
        .find_map(|l| l.split_once(" steps (").map(|(a, _)| a.to_string()))
        .and_then(|a| a.rsplit(' ').next().map(str::to_string))
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no step count in {stderr}"))
}

/// The largest error of `ẋ = −x` (exp) and `ẋ = cos t` (sin), and of the second's rate
/// (cos), over rows every 0.25 s to t = 5 from the continuous extension (so the steps
/// are error control's alone), with `integrator` at ERROR `error`.
fn diff_error(integrator: &str, error: &str) -> f64 {
    let mut args = vec!["--end", "5", "--output-step", "0.25", "--interpolate"];
    args.extend(["--error", error]);
    args.extend(integrator_args(integrator));
    let pairs = [("x", "DIF(1)"), ("s", "DIF(2)"), ("c", "DIF1(2)")];
    let csv = run_probed(&data("diff_exp_sin.adm"), &args, &named(&pairs));
    let t = csv.time();
    assert_eq!(t.len(), 21, "{integrator} at {error}");
    let (x, s, c) = (csv.col("x"), csv.col("s"), csv.col("c"));
    (0..t.len())
        .map(|i| {
            let e = [x[i] - (-t[i]).exp(), s[i] - t[i].sin(), c[i] - t[i].cos()];
            e.iter().fold(0.0f64, |m, v| m.max(v.abs()))
        })
        .fold(0.0, f64::max)
}

#[test]
fn diff_errors_fall_with_error_under_gstiff_and_dopri853() {
    // Each integrator holds the states to its own local error: the answer's error stays
    // within a few ERROR (the steps' errors add up over the run) and falls with ERROR
    // nearly in proportion (BDF of order up to 6, DOP853 of order 8). A second-order
    // rule of the states alone (the trapezoidal companion, h³ per step) would fall as
    // ERROR^(2/3): 464× over these four decades, short of the 1000× asked.
    for integrator in ["gstiff", "dopri853"] {
        let errors: Vec<f64> = ["1e-4", "1e-6", "1e-8"]
            .iter()
            .map(|e| diff_error(integrator, e))
            .collect();
        for (e, tol) in errors.iter().zip([1e-4, 1e-6, 1e-8]) {
            assert!(
                *e < 10.0 * tol,
                "{integrator} at ERROR {tol:e}: error {e:e} (all: {errors:?})"
            );
        }
        assert!(
            errors[0] > 1000.0 * errors[2],
            "{integrator}: the error falls from {:e} to {:e} only",
            errors[0],
            errors[2]
        );
    }
}

#[test]
fn a_stiff_diff_under_gstiff_takes_long_steps_and_tracks_sin() {
    // ẋ = −10⁶·(x − sin t): after a transient of 10⁻⁶ s, x = sin t − 10⁻⁶·cos t + O(10⁻¹²).
    let args = ["--end", "5", "--output-step", "0.5", "--error", "1e-6"];
    let mut all: Vec<&str> = args.to_vec();
    all.extend(["--integrator", "gstiff", "--probe", "x=DIF(1)"]);
    let out = run_raw(&data("stiff_diff.adm"), &all);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let csv = crate::run::Csv::parse(&String::from_utf8_lossy(&out.stdout));
    let (t, x) = (csv.time(), csv.col("x"));
    assert_eq!(t.len(), 11);
    for (&t, &x) in t.iter().zip(&x).skip(1) {
        let exact = t.sin() - 1e-6 * t.cos();
        assert!((x - exact).abs() < 1e-7, "x({t}) = {x} vs {exact}");
    }
    // An L-stable method's steps follow sin t, not the 10⁻⁶ s time constant: a few
    // hundred over 5 s at most (an explicit method would need millions).
    let n = steps(&stderr);
    assert!(n < 300, "{n} steps\n{stderr}");
}

/// DIF(1) and AZ(21, 10) at the end of a run of a pendulum dataset with `integrator`
/// (end, output step, ERROR).
fn at_end(file: &str, integrator: &str, (end, step, error): (&str, &str, &str)) -> (f64, f64) {
    let mut args = vec!["--end", end, "--output-step", step, "--error", error];
    args.extend(integrator_args(integrator));
    let pairs = [("x", "DIF(1)"), ("th", "AZ(21, 10)")];
    let csv = run_probed(&data(file), &args, &named(&pairs));
    let (x, th) = (csv.col("x"), csv.col("th"));
    (x[x.len() - 1], th[th.len() - 1])
}

#[test]
fn a_pi_controlled_pendulum_comes_to_rest_at_its_closed_form() {
    // J·θ̈ = −m·g·d·sin θ + 100·(0.5 − θ) − 20·θ̇ + 50·x, ẋ = 0.5 − θ: the integral
    // action brings θ to 0.5, where 50·x holds the weight: x = m·g·d·sin(0.5)/50.
    let (m, g, d) = (2.0, 9.81, 1.5);
    let x_rest = m * g * d * 0.5f64.sin() / 50.0;
    for integrator in ["gstiff", "hht", "dopri853"] {
        let (x, th) = at_end("pi_pendulum.adm", integrator, ("25", "0.5", "1e-6"));
        assert!((th - 0.5).abs() < 1e-4, "{integrator}: θ = {th}");
        assert!(
            (x - x_rest).abs() < 1e-4,
            "{integrator}: x = {x} vs {x_rest}"
        );
    }
}

#[test]
fn a_pendulum_driven_through_a_fast_actuator_state_comes_to_rest_at_its_closed_form() {
    // The torque is the state x of a 1 ms lag on a PD law, ẋ = (u − x)/0.001: the
    // coupling the Newton matrix's border carries (without it the iteration contracts
    // poorly and the steps fail). At rest x = u = 2000·(0.5 − θ) holds the weight,
    // m·g·d·sin θ: θ from that equation by Newton here.
    let (m, g, d) = (2.0, 9.81, 1.5);
    let mut th = 0.5f64;
    for _ in 0..50 {
        let r = 2000.0 * (0.5 - th) - m * g * d * th.sin();
        th -= r / (-2000.0 - m * g * d * th.cos());
    }
    for integrator in ["gstiff", "hht"] {
        let (x, got) = at_end("lag_pendulum.adm", integrator, ("5", "0.1", "1e-4"));
        assert!((got - th).abs() < 1e-6, "{integrator}: θ = {got} vs {th}");
        let torque = 2000.0 * (0.5 - th);
        assert!(
            (x - torque).abs() < 1e-3,
            "{integrator}: x = {x} vs {torque}"
        );
    }
}

#[test]
fn kinematics_integrates_a_diff_along_the_prescribed_motion() {
    // z = t² prescribed, ẋ = z: x = t³/3. The states follow the output times by the
    // trapezoidal rule, whose error over 0–2 s at 0.1 s is 2·h²/12·x⃛ = 0.0033.
    let args = ["--kinematics", "--end", "2", "--output-step", "0.1"];
    let pairs = [("x", "DIF(1)")];
    let csv = run_probed(&data("kinematics_diff.adm"), &args, &named(&pairs));
    let (t, x) = (csv.time(), csv.col("x"));
    assert_eq!(t.len(), 21);
    for (&t, &x) in t.iter().zip(&x) {
        let exact = t * t * t / 3.0;
        assert!(
            (x - exact).abs() <= 0.0034 * t / 2.0 + 1e-12,
            "x({t}) = {x} vs {exact}"
        );
    }
}

/// The response of the lag ẋ = (u − x)/τ from x(0) = 0 to u = B·sin(ωt).
fn lagged_sine(b: f64, w: f64, tau: f64, t: f64) -> f64 {
    let wt = w * tau;
    b * ((w * t).sin() - wt * (w * t).cos() + wt * (-t / tau).exp()) / (1.0 + wt * wt)
}

#[test]
fn a_diff_lags_joint_reactions_a_constant_and_a_sinusoidal_one() {
    // JOINT/1 holds both parts up: FY = (2 + 3)·9.81. JOINT/2 carries PART/3 (m = 3)
    // with the slider pushed by 10·sin(2t) along z: FZ = 3·10·sin(2t)/5. Each DIFF is the
    // lag ẋ = (u − x)/0.5 of one.
    let tau = 0.5;
    let weight = 5.0 * 9.81;
    // (HHT is second order: its states' error at ERROR 1e-8 adds up to 2.3e-5 on the
    // 49 N lag, at 1e-9 to 5e-6.)
    for (integrator, error) in [("gstiff", "1e-8"), ("hht", "1e-9")] {
        check(
            "filter_reaction.adm",
            (integrator, error),
            "3",
            &[
                ("lift", "JOINT(1, 0, 3, 10)", &|_| weight),
                ("held", "DIF(1)", &|t: f64| {
                    weight * (1.0 - (-t / tau).exp())
                }),
                ("push", "JOINT(2, 0, 4, 10)", &|t: f64| {
                    6.0 * (2.0 * t).sin()
                }),
                ("lagged", "DIF(2)", &|t| lagged_sine(6.0, 2.0, tau, t)),
            ],
            1e-5,
        );
    }
}

#[test]
fn a_force_reading_a_lag_of_its_own_joints_reaction_settles_at_the_closed_form() {
    // FY = m·g − 3·x is the reaction, ẋ = (FY − x)/τ: ẋ = (m·g − 4·x)/τ, so
    // x = m·g/4·(1 − e^(−4t/τ)). A loop of gain 3 through the reaction: it converges
    // only as Newton, with ∂ẋ/∂λ in the matrix.
    let (mg, tau) = (2.0 * 9.81, 0.5);
    let rest = mg / 4.0;
    for (integrator, error) in [("gstiff", "1e-8"), ("hht", "1e-9")] {
        check(
            "loop_reaction.adm",
            (integrator, error),
            "3",
            &[
                ("x", "DIF(1)", &|t: f64| {
                    rest * (1.0 - (-4.0 * t / tau).exp())
                }),
                ("reaction", "JOINT(1, 0, 3, 10)", &|t: f64| {
                    mg - 3.0 * rest * (1.0 - (-4.0 * t / tau).exp())
                }),
            ],
            1e-5,
        );
        // At rest, to 1e-6: e^(−24) is far below it.
        let mut args = vec!["--end", "3", "--output-step", "0.5", "--error", error];
        args.extend(integrator_args(integrator));
        let csv = run_probed(
            &data("loop_reaction.adm"),
            &args,
            &named(&[("x", "DIF(1)")]),
        );
        let x = *csv.col("x").last().expect("rows");
        assert!((x - rest).abs() < 1e-6, "{integrator}: x = {x} vs {rest}");
    }
}

#[test]
fn dopri853_lags_a_joint_reaction_too() {
    // DOP853 solves the reactions at each stage; the states read them there. The
    // constant reaction of filter_reaction.adm's JOINT/1 under DOP853.
    let weight = 5.0 * 9.81;
    check(
        "filter_reaction.adm",
        ("dopri853", "1e-8"),
        "3",
        &[("held", "DIF(1)", &|t: f64| {
            weight * (1.0 - (-t / 0.5).exp())
        })],
        1e-5,
    );
}

#[test]
fn kinematics_integrates_a_diff_of_a_motions_reaction() {
    // z = t² driven on the 2 kg slider: the MOTION pushes with m·a = 4 along z, the
    // joint holds m·g = 19.62 in y; ẋ₁ = FZ and ẋ₂ = FY integrate to 4t and 19.62·t
    // (any rule integrates a constant exactly).
    let args = ["--kinematics", "--end", "1", "--output-step", "0.1"];
    let pairs = [("push", "DIF(1)"), ("lift", "DIF(2)")];
    let csv = run_probed(&data("kinematics_reaction.adm"), &args, &named(&pairs));
    let (t, push, lift) = (csv.time(), csv.col("push"), csv.col("lift"));
    assert_eq!(t.len(), 11);
    for k in 0..t.len() {
        assert!(
            (push[k] - 4.0 * t[k]).abs() < 1e-9,
            "x1({}) = {}",
            t[k],
            push[k]
        );
        assert!(
            (lift[k] - 19.62 * t[k]).abs() < 1e-9,
            "x2({}) = {}",
            t[k],
            lift[k]
        );
    }
}
