//! Command files that change the model between SIMULATE commands (issue 26 §4): a joint
//! or a MOTION switched off, an SFORCE's FUNCTION, a MOTION's, a VFORCE component, a
//! VARIABLE and ACCGRAV redefined.
//! Each run continues one CSV, and every stretch is checked against its closed form
//! from the state the change starts it at; a column reading an element switched off
//! holds 0. Bad changes are errors at their place in the command file.

use super::{mbfx, scratch_dir, Run};
use std::path::{Path, PathBuf};

/// Runs `acf` (as run.acf) beside `model` (as m.adm) with `probes`; the CSV's header and
/// rows.
fn run(model: &str, acf: &str, probes: &[&str]) -> (Run, Vec<String>, Vec<Vec<f64>>) {
    let dir = scratch_dir("model-changes");
    std::fs::write(dir.join("m.adm"), model).expect("write the model");
    std::fs::write(dir.join("run.acf"), acf).expect("write the command file");
    let csv = dir.join("out.csv");
    let mut args: Vec<String> = ["run", "--color", "never"].map(String::from).to_vec();
    args.push(dir.join("run.acf").display().to_string());
    args.extend(["--csv".to_string(), csv.display().to_string()]);
    for p in probes {
        args.extend(["--probe".to_string(), p.to_string()]);
    }
    let r = mbfx(&args);
    let (header, rows) = read_csv(&csv);
    (r, header, rows)
}

fn read_csv(csv: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let Ok(text) = std::fs::read_to_string(csv) else {
        return (Vec::new(), Vec::new());
    };
    let mut lines = text.lines();
    let header = lines
        .next()
        .map(|h| h.split(',').map(String::from).collect())
        .unwrap_or_default();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().expect("a number")).collect())
        .collect();
    (header, rows)
}

/// (t, x, y) of marker 20 from the origin at each of the `count` rows of a run that
/// succeeds.
fn positions(model: &str, acf: &str, count: usize) -> Vec<(f64, f64, f64)> {
    let (r, h, rows) = run(model, acf, &["x=DX(20,10)", "y=DY(20,10)"]);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert_eq!(rows.len(), count);
    let (x, y) = (col(&h, "x"), col(&h, "y"));
    rows.iter().map(|r| (r[0], r[x], r[y])).collect()
}

/// Fails with `what` unless `got` is within `tol` of `want`.
fn near(got: f64, want: f64, tol: f64, what: String) {
    assert!((got - want).abs() < tol, "{what}: {got} vs {want}");
}

/// The column named `name`.
fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

/// A 2 kg pendulum (Izz 0.1 about its CM, 1 m from the pin at the origin) held
/// horizontal at rest, gravity −9.81 along y; `extra` holds more statements.
fn pendulum(extra: &str) -> String {
    format!(
        "pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
         PART/2, MASS = 2, CM = 20, IP = 0.1, 0.1, 0.1\nMARKER/20, PART = 2, QP = 1, 0, 0\n\
         MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 10\nACCGRAV/JGRAV = -9.81\n{extra}END\n"
    )
}

const G: f64 = 9.81;
const MASS: f64 = 2.0;
/// The pendulum's inertia about the pin: m L² + Izz.
const I_PIN: f64 = MASS * 1.0 + 0.1;

#[test]
fn a_pendulum_whose_motion_is_switched_off_swings_from_rest() {
    // MOTION/1 holds the joint at its assembled angle; at t1 = 0.2 it is switched off and
    // the pendulum falls from rest at the horizontal: ½·I·ω² = m·g·(−y) thereafter, and
    // until then the drive holds the gravity moment m·g·L (its reaction TZ).
    let model = pendulum("MOTION/1, JOINT = 1, FUNCTION = 0\n");
    let acf = "m\nout\nINTEGRATOR/HHT, ERROR = 1e-9\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.02\n\
               DEACTIVATE/MOTION, ID = 1\nSIMULATE/DYNAMIC, END = 0.8, DTOUT = 0.02\nSTOP\n";
    let probes = ["y=DY(20,10)", "w=WZ(20,10)", "tz=MOTION(1,0,8,0)"];
    let (r, h, rows) = run(&model, acf, &probes);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert_eq!(rows.len(), 41, "one CSV, no row twice");
    let (y, w, tz) = (col(&h, "y"), col(&h, "w"), col(&h, "tz"));
    for row in &rows {
        let t = row[0];
        let energy = 0.5 * I_PIN * row[w] * row[w] + MASS * G * row[y];
        // (HHT damps a little: within 1e-6 of m·g·L.)
        assert!(energy.abs() < 2e-5, "t = {t}: energy {energy}");
        if t <= 0.2 + 1e-12 {
            assert!(
                row[y].abs() < 1e-9 && row[w].abs() < 1e-9,
                "t = {t}: {row:?}"
            );
            near(
                row[tz].abs(),
                MASS * G,
                1e-6,
                format!("t = {t}: drive torque"),
            );
        } else {
            // The drive is switched off: its reaction column holds 0.
            assert_eq!(row[tz], 0.0, "t = {t}");
        }
    }
    let last = rows.last().expect("rows");
    assert!(last[y] < -0.5, "the pendulum fell: {last:?}");
}

#[test]
fn a_pendulum_whose_joint_is_switched_off_flies_on_a_parabola() {
    // The pendulum swings from the horizontal (½·I·ω² = m·g·(−y)); at t1 = 0.3 its
    // revolute joint is switched off: from the state there, its CM follows
    // x1 + vx1·τ, y1 + vy1·τ − g·τ²/2 and it keeps turning at ω1. The joint's reaction
    // column holds 0 afterwards.
    let acf = "m\nout\nINTEGRATOR/HHT, ERROR = 1e-9\nSIMULATE/DYNAMIC, END = 0.3, DTOUT = 0.02\n\
               DEACTIVATE/JOINT, ID = 1\nSIMULATE/DYNAMIC, END = 0.7, DTOUT = 0.02\nSTOP\n";
    let probes = [
        "x=DX(20,10)",
        "y=DY(20,10)",
        "vx=VX(20,10)",
        "vy=VY(20,10)",
        "w=WZ(20,10)",
        "fy=JOINT(1,0,3,0)",
    ];
    let (r, h, rows) = run(&pendulum(""), acf, &probes);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert_eq!(rows.len(), 36);
    let [x, y, vx, vy, w, fy] = ["x", "y", "vx", "vy", "w", "fy"].map(|n| col(&h, n));
    let t1 = 0.3;
    let at_change = rows
        .iter()
        .find(|r| (r[0] - t1).abs() < 1e-12)
        .expect("a row at the change")
        .clone();
    for row in rows.iter().filter(|r| r[0] <= t1 + 1e-12) {
        let energy = 0.5 * I_PIN * row[w] * row[w] + MASS * G * row[y];
        assert!(energy.abs() < 2e-5, "t = {}: energy {energy}", row[0]);
        assert!((row[x].hypot(row[y]) - 1.0).abs() < 1e-9, "{row:?}");
        // At the release, the pin carries m·g·(1 − m·L²/I) = 0.934 N.
        assert!(row[fy].abs() > 0.9, "the joint holds: {row:?}");
    }
    for row in rows.iter().filter(|r| r[0] > t1 + 1e-12) {
        let tau = row[0] - t1;
        let want = [
            (x, at_change[x] + at_change[vx] * tau),
            (y, at_change[y] + at_change[vy] * tau - 0.5 * G * tau * tau),
            (vy, at_change[vy] - G * tau),
            (w, at_change[w]),
        ];
        for (c, v) in want {
            near(row[c], v, 1e-6, format!("t = {}: {}", row[0], h[c]));
        }
        assert_eq!(row[fy], 0.0, "t = {}", row[0]);
    }
}

/// A 1 kg slider on a rail along x (its CM marker 20), held by an SFORCE of stiffness
/// 100 towards x = 1, released at rest at x = 1.2.
const SPRING: &str = "spring\nPART/1, GROUND\nMARKER/10, PART = 1\n\
    MARKER/11, PART = 1, REULER = 90D, 90D, 0\n\
    PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = 1.2, 0, 0\n\
    MARKER/20, PART = 2\nMARKER/21, PART = 2, REULER = 90D, 90D, 0\n\
    JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
    SFORCE/1, TRANSLATION, I = 20, J = 10, FUNCTION = -100*(DM(20,10) - 1)\nEND\n";

#[test]
fn a_spring_whose_function_is_redefined_takes_its_new_frequency() {
    // x − 1 = 0.2·cos(10 t) until t1 = 0.5; then the stiffness is 400 (FUNCTION given
    // across two lines), so x − 1 = A·cos(20 τ) + B·sin(20 τ) from the state at t1.
    let acf = "m\nout\nINTEGRATOR/HHT, ERROR = 1e-10\nSIMULATE/DYNAMIC, END = 0.5, DTOUT = 0.01\n\
               SFORCE/1 &\n, FUNCTION = -400*(DM(20,10) &\n  - 1)\n\
               SIMULATE/DYNAMIC, END = 1.5, DTOUT = 0.01\nSTOP\n";
    let (r, h, rows) = run(SPRING, acf, &["x=DX(20,10)"]);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert_eq!(rows.len(), 151);
    let x = col(&h, "x");
    let t1 = 0.5f64;
    let (a, b) = (
        0.2 * (10.0 * t1).cos(),
        -0.2 * 10.0 * (10.0 * t1).sin() / 20.0,
    );
    for row in &rows {
        let t = row[0];
        let want = match t <= t1 + 1e-12 {
            true => 1.0 + 0.2 * (10.0 * t).cos(),
            false => 1.0 + a * (20.0 * (t - t1)).cos() + b * (20.0 * (t - t1)).sin(),
        };
        near(row[x], want, 1e-5, format!("t = {t}: x"));
    }
}

/// A free 1 kg part at the origin, gravity (0.5, −9.81, 0); `extra` holds more
/// statements.
fn free_part(extra: &str) -> String {
    format!(
        "free\nPART/1, GROUND\nMARKER/10, PART = 1\n\
         PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
         ACCGRAV/IGRAV = 0.5, JGRAV = -9.81\n{extra}END\n"
    )
}

#[test]
fn gravity_redefined_bends_the_parabola() {
    // y = −9.81·t²/2 until t1 = 0.5, then y1 + v1·τ − 1.62·τ²/2; ACCGRAV names JGRAV
    // alone, so x = 0.5·t²/2 throughout.
    let acf = "m\nout\nINTEGRATOR/HHT, ERROR = 1e-10\nSIMULATE/DYNAMIC, END = 0.5, DTOUT = 0.05\nACCGRAV/JGRAV = -1.62\n\
               SIMULATE/DYNAMIC, END = 1.0, DTOUT = 0.05\nSTOP\n";
    let (r, h, rows) = run(&free_part(""), acf, &["x=DX(20,10)", "y=DY(20,10)"]);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert_eq!(rows.len(), 21);
    let (x, y) = (col(&h, "x"), col(&h, "y"));
    let t1 = 0.5;
    let (y1, v1) = (-0.5 * 9.81 * t1 * t1, -9.81 * t1);
    for row in &rows {
        let t: f64 = row[0];
        let want_y = match t <= t1 + 1e-12 {
            true => -0.5 * 9.81 * t * t,
            false => y1 + v1 * (t - t1) - 0.5 * 1.62 * (t - t1).powi(2),
        };
        near(row[y], want_y, 1e-8, format!("t = {t}: y"));
        near(row[x], 0.25 * t * t, 1e-8, format!("t = {t}: x"));
    }
}

#[test]
fn a_variable_redefined_changes_the_force_that_reads_it() {
    // An SFORCE pushes the free part along z with VARVAL(1): 2 until t1 = 0.5, then
    // 2 + 8·(t − 0.5) (no gravity); z = t² and then z1 + v1·τ + τ² + 4τ³/3. The REQUEST
    // column reading VARVAL(1) follows the new expression too.
    let model = free_part(
        "VARIABLE/1, FUNCTION = 2\n\
         SFORCE/1, TRANSLATION, ACTIONONLY, I = 20, J = 10, FUNCTION = VARVAL(1)\n\
         REQUEST/1, F2 = VARVAL(1)\n",
    )
    .replace("ACCGRAV/IGRAV = 0.5, JGRAV = -9.81\n", "");
    let acf = "m\nout\nINTEGRATOR/HHT, ERROR = 1e-10\nSIMULATE/DYNAMIC, END = 0.5, DTOUT = 0.05\n\
               VARIABLE/1, FUNCTION = 2 + 8*(TIME - 0.5)\n\
               SIMULATE/DYNAMIC, END = 1.0, DTOUT = 0.05\nSTOP\n";
    let (r, h, rows) = run(&model, acf, &["z=DZ(20,10)"]);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert_eq!(rows.len(), 21);
    let (z, v) = (col(&h, "z"), col(&h, "REQ1.F2"));
    let t1 = 0.5;
    for row in &rows {
        let t: f64 = row[0];
        let tau = t - t1;
        let (want_z, want_v) = match t <= t1 + 1e-12 {
            true => (t * t, 2.0),
            false => (
                t1 * t1 + 2.0 * t1 * tau + tau * tau + 4.0 * tau.powi(3) / 3.0,
                2.0 + 8.0 * tau,
            ),
        };
        near(row[z], want_z, 1e-6, format!("t = {t}: z"));
        near(row[v], want_v, 1e-12, format!("t = {t}: VARVAL(1)"));
    }
}

#[test]
fn a_swinging_pendulum_under_new_gravity_keeps_its_new_energy() {
    // g = 9.81 until t1 = 0.3, then 3: from the state at t1, ½·I·ω² + m·g₂·y keeps its
    // value, on the circle. (A 2D part rebuilt away from its input orientation: it once
    // took its θ twice, which this pins.)
    let acf = "m\nout\nINTEGRATOR/HHT, ERROR = 1e-9\nSIMULATE/DYNAMIC, END = 0.3, DTOUT = 0.02\n\
               ACCGRAV/JGRAV = -3\nSIMULATE/DYNAMIC, END = 0.9, DTOUT = 0.02\nSTOP\n";
    let probes = ["x=DX(20,10)", "y=DY(20,10)", "w=WZ(20,10)"];
    let (r, h, rows) = run(&pendulum(""), acf, &probes);
    assert_eq!(r.code, 0, "{}", r.describe());
    let [x, y, w] = ["x", "y", "w"].map(|n| col(&h, n));
    let energy = |row: &[f64], g: f64| 0.5 * I_PIN * row[w] * row[w] + MASS * g * row[y];
    let t1 = 0.3;
    let at = rows.iter().find(|r| (r[0] - t1).abs() < 1e-12).expect("t1");
    let e1 = energy(at, 3.0);
    for row in &rows {
        let (g, e) = match row[0] <= t1 + 1e-12 {
            true => (G, 0.0),
            false => (3.0, e1),
        };
        near(energy(row, g), e, 2e-5, format!("t = {}: energy", row[0]));
        near(
            row[x].hypot(row[y]),
            1.0,
            1e-9,
            format!("t = {}: radius", row[0]),
        );
    }
}

#[test]
fn a_static_equilibrium_after_a_drive_is_switched_off_hangs_the_pendulum() {
    // Held at −0.3 rad by MOTION/1, then released: SIMULATE/STATICS finds it hanging
    // straight down, the pin carrying m·g and the drive nothing.
    let model = pendulum("MOTION/1, JOINT = 1, FUNCTION = -0.3\n");
    let acf = "m\nout\nSIMULATE/DYNAMIC, END = 0.1, DTOUT = 0.05\nDEACTIVATE/MOTION, ID = 1\n\
               SIMULATE/STATICS\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\nSTOP\n";
    let probes = [
        "x=DX(20,10)",
        "y=DY(20,10)",
        "fy=JOINT(1,0,3,0)",
        "tz=MOTION(1,0,8,0)",
    ];
    let (r, h, rows) = run(&model, acf, &probes);
    assert_eq!(r.code, 0, "{}", r.describe());
    let [x, y, fy, tz] = ["x", "y", "fy", "tz"].map(|n| col(&h, n));
    let held = &rows[0];
    near(held[y], (-0.3f64).sin(), 1e-9, "held: y".into());
    near(
        held[tz].abs(),
        MASS * G * 0.3f64.cos(),
        1e-6,
        "held: torque".into(),
    );
    let last = rows.last().expect("rows");
    near(last[x], 0.0, 1e-9, "hanging: x".into());
    near(last[y], -1.0, 1e-9, "hanging: y".into());
    near(last[fy].abs(), MASS * G, 1e-6, "hanging: pin force".into());
    assert_eq!(last[tz], 0.0);
}

#[test]
fn a_motion_redefined_drives_its_new_function() {
    // θ = 0.5·t, then 0.1 − 0.3·(t − 0.2) from t1 = 0.2: the CM, 1 m from the pin, is at
    // (cos θ, sin θ) to the assembly's tolerance.
    let model = pendulum("MOTION/1, JOINT = 1, FUNCTION = 0.5*TIME\n");
    let acf = "m\nout\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\n\
               MOTION/1, FUNCTION = 0.1 - 0.3*(TIME - 0.2)\n\
               SIMULATE/DYNAMIC, END = 0.6, DTOUT = 0.05\nSTOP\n";
    for (t, x, y) in positions(&model, acf, 13) {
        let theta = match t <= 0.2 + 1e-12 {
            true => 0.5 * t,
            false => 0.1 - 0.3 * (t - 0.2),
        };
        near(x, theta.cos(), 1e-9, format!("t = {t}: x"));
        near(y, theta.sin(), 1e-9, format!("t = {t}: y"));
    }
}

#[test]
fn a_motion_changed_to_a_velocity_drive_integrates_it() {
    // θ = 0.5·t until t1 = 0.2, then `MOTION/1, VELOCITY, ICDISP = 0.16, FUNCTION = -0.3`:
    // a velocity drive is integrated from ICDISP at t = 0, θ = 0.16 − 0.3·t, which meets
    // the displacement drive at t1 (0.1) and goes on as 0.1 − 0.3·(t − 0.2).
    let model = pendulum("MOTION/1, JOINT = 1, FUNCTION = 0.5*TIME\n");
    let acf = "m\nout\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\n\
               MOTION/1, VELOCITY, ICDISP = 0.16, FUNCTION = -0.3\n\
               SIMULATE/DYNAMIC, END = 0.6, DTOUT = 0.05\nSTOP\n";
    for (t, x, y) in positions(&model, acf, 13) {
        let theta = match t <= 0.2 + 1e-12 {
            true => 0.5 * t,
            false => 0.16 - 0.3 * t,
        };
        near(x, theta.cos(), 1e-9, format!("t = {t}: x"));
        near(y, theta.sin(), 1e-9, format!("t = {t}: y"));
    }
}

#[test]
fn a_vforce_component_redefined_pushes_the_other_way() {
    // A VFORCE on the free part (no gravity) pushes along x with 2 N until t1 = 0.4;
    // then FY = 3 is written (FX keeps its 2): x = t², y = 1.5·τ².
    let model = free_part(
        "MARKER/11, PART = 1, FLOATING\n\
         VFORCE/1, I = 20, JFLOAT = 11, RM = 10, FX = 2\\ FY = 0\\ FZ = 0\n",
    )
    .replace("ACCGRAV/IGRAV = 0.5, JGRAV = -9.81\n", "");
    let acf = "m\nout\nINTEGRATOR/HHT, ERROR = 1e-10\nSIMULATE/DYNAMIC, END = 0.4, DTOUT = 0.05\n\
               VFORCE/1, FY = 3\nSIMULATE/DYNAMIC, END = 0.8, DTOUT = 0.05\nSTOP\n";
    for (t, x, y) in positions(&model, acf, 17) {
        let tau = (t - 0.4).max(0.0);
        near(x, t * t, 1e-8, format!("t = {t}: x"));
        near(y, 1.5 * tau * tau, 1e-8, format!("t = {t}: y"));
    }
}

#[test]
fn a_joint_switched_off_and_on_again_reassembles() {
    // The joint is off for a while (the part flies off the pin) and on again: the run
    // reassembles the part onto the pin and the link keeps its length from then on.
    let acf = "m\nout\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\nDEACTIVATE/JOINT, ID = 1\n\
               SIMULATE/DYNAMIC, END = 0.3, DTOUT = 0.05\nACTIVATE/JOINT, ID = 1\n\
               SIMULATE/DYNAMIC, END = 0.6, DTOUT = 0.05\nSTOP\n";
    let (r, h, rows) = run(&pendulum(""), acf, &["x=DX(20,10)", "y=DY(20,10)"]);
    assert_eq!(r.code, 0, "{}", r.describe());
    let (x, y) = (col(&h, "x"), col(&h, "y"));
    for row in rows
        .iter()
        .filter(|r| r[0] <= 0.2 + 1e-12 || r[0] > 0.3 + 1e-12)
    {
        assert!((row[x].hypot(row[y]) - 1.0).abs() < 1e-6, "{row:?}");
    }
}

#[test]
fn a_change_that_cannot_be_assembled_stops_the_run_at_its_command() {
    // MOTION/2 turns the joint while MOTION/1 holds it: switched on at t = 0.1, the two
    // contradict each other. The rows before the change stay written.
    let model =
        pendulum("MOTION/1, JOINT = 1, FUNCTION = 0\nMOTION/2, JOINT = 1, FUNCTION = 0.5*TIME\n");
    let acf = "m\nout\nDEACTIVATE/MOTION, ID = 2\nSIMULATE/DYNAMIC, END = 0.1, DTOUT = 0.05\n\
               ACTIVATE/MOTION, ID = 2\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\nSTOP\n";
    let (r, _, rows) = run(&model, acf, &["y=DY(20,10)"]);
    assert_eq!(r.code, 1, "{}", r.describe());
    for want in ["run.acf:5:1", "change to the model at t = 0.1"] {
        assert!(r.stderr.contains(want), "{want}\n{}", r.describe());
    }
    assert!(!r.stderr.contains("panicked"), "{}", r.describe());
    assert_eq!(rows.len(), 3, "the rows up to the change");
}

/// The pendulum's folder with `acf` as run.acf.
fn pendulum_dir(acf: &str) -> PathBuf {
    let dir = scratch_dir("model-changes-errors");
    std::fs::write(
        dir.join("m.adm"),
        pendulum("MOTION/1, JOINT = 1, FUNCTION = 0\n"),
    )
    .expect("write");
    std::fs::write(dir.join("run.acf"), acf).expect("write");
    dir
}

#[test]
fn bad_changes_are_errors_at_their_place() {
    for (acf, want) in [
        (
            "m\nout\nSIMULATE/DYNAMIC, END = 0.1, DTOUT = 0.05\nDEACTIVATE/JOINT, ID = 99\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\n",
            ["run.acf:4:24", "JOINT/99 is not defined in the dataset"],
        ),
        (
            "m\nout\nDEACTIVATE/MOTION, RANGE = 5, 9\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\n",
            ["run.acf:3:20", "no MOTION of the dataset has an id from 5 to 9"],
        ),
        (
            "m\nout\nMOTION/1, &\n FUNCTION = 0.1*(TIME\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\n",
            ["run.acf:4:", "E0"],
        ),
        (
            "m\nout\nSFORCE/7, FUNCTION = 1\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\n",
            ["run.acf:3:8", "SFORCE/7 is not defined in the dataset"],
        ),
        (
            "m\nout\nDEACTIVATE/SENSOR, ID = 1\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\n",
            ["run.acf:3:1", "[E0610] Error: DEACTIVATE/SENSOR: mbfx has no SENSOR elements"],
        ),
        (
            "m\nout\nMOTION/1, JOINT = 1, FUNCTION = TIME\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\n",
            ["run.acf:3:11", "redefines only FUNCTION"],
        ),
    ] {
        let dir = pendulum_dir(acf);
        let csv = dir.join("out.csv");
        let r = mbfx(&[
            "run".as_ref(),
            "--color".as_ref(),
            "never".as_ref(),
            dir.join("run.acf").as_os_str(),
            "--csv".as_ref(),
            csv.as_os_str(),
        ]);
        assert_eq!(r.code, 1, "{acf}\n{}", r.describe());
        for w in want {
            assert!(r.stderr.contains(w), "{acf}: {w}\n{}", r.describe());
        }
        assert!(!r.stderr.contains("panicked"), "{}", r.describe());
        assert!(!csv.exists(), "{acf}: nothing is written");
    }
}
