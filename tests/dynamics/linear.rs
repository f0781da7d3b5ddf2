//! Linearization and modes (issue 26 §3) against closed forms and an independent
//! formulation: a compound pendulum (ω² = m·g·d/(I + m·d²)), a spring-mass-damper
//! (λ = −c/2m ± i·√(k/m − (c/2m)²)), a double pendulum (the two roots of the quadratic
//! det(K − ω²·M) = 0 in its joint angles) and a planar chain of N rods hanging at rest
//! (the generalized eigenproblem of its mass and stiffness matrices in absolute angles,
//! written here from the Lagrangian and solved by a Cholesky reduction). Every model is
//! linearized after a static equilibrium, in 2D and in 3D (different coordinates and
//! constraint rows), and must agree to 12 significant digits. A command file's
//! LINEAR/STATEMAT writes a state matrix whose entries the closed form gives.

use mbfx::session::linear::LinearReport;
use mbfx::session::request::LinearRequest as Linear;
use mbfx::session::request::{run, RunRequest};
use mbfx::session::DimRequest;
use nalgebra::{DMatrix, SymmetricEigen};

const G: f64 = 9.81;

/// Significant digits asked of every frequency (the goal).
const DIGITS: f64 = 1e-12;

/// Runs `text` to its static equilibrium and linearizes there: the linear report.
fn linearized(text: &str, dim: DimRequest) -> LinearReport {
    let mut r = RunRequest::dataset("linear.adm", text);
    (r.statics, r.dim) = (true, dim);
    r.linear = Some(Linear::eigensol(None));
    let mut sink = |_: &[f64]| -> std::io::Result<()> { Ok(()) };
    let done = run(&r, &mut sink, None).unwrap_or_else(|f| panic!("{}", f.cause));
    let mut linear = done.summary.linear;
    assert_eq!(linear.len(), 1);
    linear.remove(0)
}

/// The undamped natural frequencies (rad/s) of the report's modes.
fn omegas(r: &LinearReport) -> Vec<f64> {
    r.modes.iter().map(|m| m.eigenvalue.norm()).collect()
}

fn assert_close(got: &[f64], want: &[f64], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?} vs {want:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            ((g - w) / w).abs() < DIGITS,
            "{what}: {g} vs {w} (relative {:e})",
            (g - w) / w
        );
    }
}

const DIMS: [DimRequest; 2] = [DimRequest::Auto, DimRequest::Three];

#[test]
fn a_compound_pendulum_swings_at_the_square_root_of_m_g_d_over_its_inertia_about_the_pin() {
    let (m, d, i) = (2.0, 1.5, 0.5);
    let text = format!(
        "pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
         PART/2, MASS = {m}, CM = 20, IP = {i}, {i}, {i}\nMARKER/20, PART = 2, QP = 0, -{d}, 0\n\
         MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 10\nACCGRAV/JGRAV = -{G}\nEND\n"
    );
    let w = (m * G * d / (i + m * d * d)).sqrt();
    for dim in DIMS {
        let r = linearized(&text, dim);
        assert_eq!(r.linearized.freedom(), 1, "{dim:?}");
        assert_close(&omegas(&r), &[w], &format!("{dim:?}"));
        let mode = &r.modes[0];
        assert!(mode.eigenvalue.re.abs() < 1e-12 * w, "{mode:?}");
        assert!((mode.natural_hz - w / (2.0 * std::f64::consts::PI)).abs() < 1e-12 * w);
        // The shape: the CM moves sideways by d per radian of swing, not vertically.
        let shape = mode.shape.as_ref().expect("shapes");
        let at = |name: &str| {
            let k = r.linearized.columns.iter().position(|c| c == name);
            shape[k.unwrap_or_else(|| panic!("{name} in {:?}", r.linearized.columns))]
        };
        let (x, y, rz) = (
            at("PART/2 x translation"),
            at("PART/2 y translation"),
            at("PART/2 rotation about z"),
        );
        assert!((x / rz - d).norm() < 1e-12, "{dim:?}: {x} / {rz}");
        assert!(y.norm() < 1e-12, "{dim:?}: {y}");
    }
}

/// A 2 kg block on a vertical rail hanging from a spring-damper (K = 500, C = 3).
const SPRING_MASS_DAMPER: &str = "spring-mass-damper\nPART/1, GROUND\nMARKER/10, PART = 1\n\
     MARKER/11, PART = 1, REULER = 0, -90D, 0\n\
     PART/2, MASS = 2, CM = 20, IP = 0.1, 0.1, 0.1\nMARKER/20, PART = 2, QP = 0, -1, 0\n\
     MARKER/21, PART = 2, QP = 0, -1, 0, REULER = 0, -90D, 0\n\
     JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
     SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 500, C = 3, LENGTH = 1\n\
     ACCGRAV/JGRAV = -9.81\nEQUILIBRIUM/ERROR = 1e-12, IMBALANCE = 1e-10\nEND\n";

#[test]
fn a_spring_mass_damper_has_its_damped_frequency_and_damping_ratio() {
    let (m, k, c) = (2.0f64, 500.0f64, 3.0f64);
    let wn = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    let (re, im) = (-c / (2.0 * m), (k / m - (c / (2.0 * m)).powi(2)).sqrt());
    for dim in DIMS {
        let r = linearized(SPRING_MASS_DAMPER, dim);
        let mode = &r.modes[0];
        assert_eq!(r.modes.len(), 1, "{dim:?}");
        assert_close(&[mode.eigenvalue.norm()], &[wn], "ωn");
        assert_close(&[mode.damping_ratio], &[zeta], "ζ");
        assert_close(&[mode.eigenvalue.re], &[re], "Re λ");
        assert_close(&[mode.eigenvalue.im], &[im], "Im λ (damped)");
        // NODAMPIN leaves the damper out: the undamped frequency, no decay.
        let mut req = RunRequest::dataset("smd.adm", SPRING_MASS_DAMPER);
        (req.statics, req.dim) = (true, dim);
        let mut undamped = Linear::eigensol(None);
        undamped.damping = false;
        req.linear = Some(undamped);
        let mut sink = |_: &[f64]| -> std::io::Result<()> { Ok(()) };
        let done = run(&req, &mut sink, None).unwrap_or_else(|f| panic!("{}", f.cause));
        let l = &done.summary.linear[0].modes[0];
        assert_close(&[l.eigenvalue.im], &[wn], "undamped");
        assert!(l.eigenvalue.re.abs() < 1e-12 * wn);
    }
}

/// Two rods in a vertical plane: rod 1 (m1, I1 about its CM, CM d1 below the pin,
/// length l1) pinned to ground at the origin, rod 2 (m2, I2, CM d2 below its pin)
/// pinned to rod 1's end.
fn double_pendulum(m1: f64, i1: f64, d1: f64, l1: f64, m2: f64, i2: f64, d2: f64) -> String {
    format!(
        "double pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
         PART/2, MASS = {m1}, CM = 20, IP = {i1}, {i1}, {i1}\nMARKER/20, PART = 2, QP = 0, -{d1}, 0\n\
         MARKER/21, PART = 2\nMARKER/22, PART = 2, QP = 0, -{l1}, 0\n\
         PART/3, MASS = {m2}, CM = 30, IP = {i2}, {i2}, {i2}\n\
         MARKER/30, PART = 3, QP = 0, -{}, 0\nMARKER/31, PART = 3, QP = 0, -{l1}, 0\n\
         JOINT/1, REVOLUTE, I = 21, J = 10\nJOINT/2, REVOLUTE, I = 31, J = 22\n\
         ACCGRAV/JGRAV = -{G}\nEND\n",
        l1 + d2
    )
}

#[test]
fn a_double_pendulum_has_the_two_roots_of_its_frequency_equation() {
    let (m1, i1, d1, l1, m2, i2, d2) = (1.0, 0.1, 0.5, 1.0, 1.5, 0.05, 0.4);
    // In the absolute angles θ1, θ2: M = [[I1 + m1 d1² + m2 l1², m2 l1 d2],
    // [m2 l1 d2, I2 + m2 d2²]], K = diag(g (m1 d1 + m2 l1), g m2 d2); det(K − ω² M) = 0
    // is a ω⁴ + b ω² + c = 0.
    let (ma, mb, mc) = (
        i1 + m1 * d1 * d1 + m2 * l1 * l1,
        m2 * l1 * d2,
        i2 + m2 * d2 * d2,
    );
    let (ka, kc) = (G * (m1 * d1 + m2 * l1), G * m2 * d2);
    let (a, b, c) = (ma * mc - mb * mb, -(ka * mc + kc * ma), ka * kc);
    // The larger root first, then the smaller from the product (no cancellation).
    let big = (-b + (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    let small = c / (a * big);
    let want = [small.sqrt(), big.sqrt()];
    for dim in DIMS {
        let r = linearized(&double_pendulum(m1, i1, d1, l1, m2, i2, d2), dim);
        assert_eq!(r.linearized.freedom(), 2, "{dim:?}");
        assert_close(&omegas(&r), &want, &format!("{dim:?}"));
    }
}

/// N uniform rods (mass m, length l) hanging in a chain from a pin at the origin.
fn chain(n: usize, m: f64, l: f64) -> String {
    let i = m * l * l / 12.0;
    let mut t = String::from("chain\nPART/1, GROUND\nMARKER/10, PART = 1\n");
    for k in 1..=n {
        let p = 10 * (k + 1);
        let top = (k - 1) as f64 * l;
        t += &format!(
            "PART/{}, MASS = {m}, CM = {p}, IP = {i}, {i}, {i}\n\
             MARKER/{p}, PART = {}, QP = 0, -{}, 0\nMARKER/{}, PART = {}, QP = 0, -{top}, 0\n\
             MARKER/{}, PART = {}, QP = 0, -{}, 0\n",
            k + 1,
            k + 1,
            top + l / 2.0,
            p + 1,
            k + 1,
            p + 2,
            k + 1,
            top + l
        );
        // Joint k: rod k's top to rod k−1's bottom (ground's origin for the first).
        let j = if k == 1 { 10 } else { 10 * k + 2 };
        t += &format!("JOINT/{k}, REVOLUTE, I = {}, J = {j}\n", p + 1);
    }
    t + &format!("ACCGRAV/JGRAV = -{G}\nEND\n")
}

/// The chain's frequencies from its Lagrangian in absolute angles θ_j, linearized at
/// rest: rod i's CM moves sideways by Σ_{j<i} l·θ_j + (l/2)·θ_i, so
/// M_jk = Σ_i m·a_ij·a_ik + I·δ_jk with a_ij = l (j < i), l/2 (j = i), 0 (j > i); its
/// height gives K_jj = m·g·l·(N − 1 − j + 1/2). ω² are the eigenvalues of L⁻¹·K·L⁻ᵀ
/// with M = L·Lᵀ.
fn chain_frequencies(n: usize, m: f64, l: f64) -> Vec<f64> {
    let a = |i: usize, j: usize| match j.cmp(&i) {
        std::cmp::Ordering::Less => l,
        std::cmp::Ordering::Equal => l / 2.0,
        std::cmp::Ordering::Greater => 0.0,
    };
    let inertia = m * l * l / 12.0;
    let mass = DMatrix::from_fn(n, n, |j, k| {
        (0..n).map(|i| m * a(i, j) * a(i, k)).sum::<f64>() + if j == k { inertia } else { 0.0 }
    });
    let stiffness = DMatrix::from_fn(n, n, |j, k| match j == k {
        true => m * G * l * ((n - 1 - j) as f64 + 0.5),
        false => 0.0,
    });
    let chol = mass.cholesky().expect("M is positive definite");
    let linv = chol.l().try_inverse().expect("L is regular");
    let s = &linv * stiffness * linv.transpose();
    let s = (&s + s.transpose()) * 0.5;
    let mut w: Vec<f64> = SymmetricEigen::new(s)
        .eigenvalues
        .iter()
        .map(|x| x.sqrt())
        .collect();
    w.sort_by(f64::total_cmp);
    w
}

#[test]
fn a_hanging_chain_of_rods_has_the_frequencies_of_its_lagrangian() {
    let (n, m, l) = (6, 0.8, 0.5);
    let want = chain_frequencies(n, m, l);
    for dim in DIMS {
        let r = linearized(&chain(n, m, l), dim);
        assert_eq!(r.linearized.freedom(), n, "{dim:?}");
        assert_close(&omegas(&r), &want, &format!("{dim:?}"));
    }
}

#[test]
fn a_command_file_writes_the_state_matrix_and_the_modes() {
    let dir = std::env::temp_dir().join(format!("mbfx-linear-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch");
    std::fs::write(dir.join("smd.adm"), SPRING_MASS_DAMPER).expect("dataset");
    let base = dir.join("out").join("smd");
    let acf = dir.join("lin.acf");
    std::fs::write(
        &acf,
        format!(
            "smd.adm\nout\nSIMULATE/STATICS\nLINEAR/EIGENSOL, FILE = {0}\nLINEAR/STATEMAT, FILE = {0}, FORMAT = MATLAB\nSTOP\n",
            base.display()
        ),
    )
    .expect("command file");
    let mut sink = |_: &[f64]| -> std::io::Result<()> { Ok(()) };
    let done =
        run(&RunRequest::file(&acf), &mut sink, None).unwrap_or_else(|f| panic!("{}", f.cause));
    assert_eq!(done.summary.linear.len(), 2);
    let text = done.summary.text();
    assert!(
        text.contains(
            "linear analysis at time 0: 1 degree(s) of freedom (JOINT/1 (TRANSLATIONAL) translation)"
        ),
        "{text}"
    );
    // A = [[0, 1], [−k/m, −c/m]] on the joint's travel along z_J, which REULER = 0, −90D, 0
    // turns onto global +y: the travel is PART/2's y.
    let a: Vec<Vec<f64>> = std::fs::read_to_string(format!("{}.a", base.display()))
        .expect("the .a file")
        .lines()
        .map(|l| {
            l.split_whitespace()
                .map(|x| x.parse().expect("a number"))
                .collect()
        })
        .collect();
    let want = [[0.0, 1.0], [-250.0, -1.5]];
    for (row, w) in a.iter().zip(want) {
        for (x, y) in row.iter().zip(w) {
            assert!((x - y).abs() <= 1e-12 * y.abs().max(1.0), "{a:?}");
        }
    }
    let states = std::fs::read_to_string(format!("{}.st", base.display())).expect("the .st file");
    assert_eq!(
        states,
        "JOINT/1 (TRANSLATIONAL) translation\nd/dt JOINT/1 (TRANSLATIONAL) translation\n"
    );
    let modes = std::fs::read_to_string(format!("{}_modes.csv", base.display())).expect("modes");
    let mut lines = modes.lines();
    assert_eq!(
        lines.next(),
        Some("mode,natural_hz,damped_hz,damping_ratio,real,imag,dominant")
    );
    let row: Vec<&str> = lines.next().expect("one mode").split(',').collect();
    let hz: f64 = row[1].parse().expect("a number");
    assert!((hz - 250f64.sqrt() / (2.0 * std::f64::consts::PI)).abs() < 1e-12 * hz);
    assert_eq!(row[6], "JOINT/1 (TRANSLATIONAL) translation");
    let shapes = std::fs::read_to_string(format!("{}_shapes.csv", base.display())).expect("shapes");
    assert!(
        shapes.contains("1,JOINT/1 (TRANSLATIONAL) translation,1e0,0e0\n")
            && shapes.contains("1,PART/2 y translation,1e0,0e0\n"),
        "{shapes}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_moving_operating_point_is_said_to_be_approximate() {
    // The spring-mass-damper released off equilibrium and linearized at t = 0.05,
    // moving.
    let mut r = RunRequest::dataset("smd.adm", SPRING_MASS_DAMPER);
    r.end = Some(0.05);
    r.linear = Some(Linear::eigensol(None));
    let mut sink = |_: &[f64]| -> std::io::Result<()> { Ok(()) };
    let done = run(&r, &mut sink, None).unwrap_or_else(|f| panic!("{}", f.cause));
    assert!(done.summary.linear[0].linearized.moving);
    assert!(done
        .summary
        .text()
        .contains("the operating point is not at rest"));
    // After the statics it is at rest and says nothing.
    let r = linearized(SPRING_MASS_DAMPER, DimRequest::Auto);
    assert!(!r.linearized.moving, "{}", r.text());
    assert!(!r.text().contains("operating point is not at rest"));
}

/// Runs command file `acf` (beside `dataset`, written as `m.adm`) in a scratch folder;
/// the run's result and the folder.
fn run_command_file(
    dataset: &str,
    acf: &str,
) -> (
    Result<mbfx::session::request::RunDone, Box<mbfx::session::request::RunFailed>>,
    std::path::PathBuf,
) {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "mbfx-plant-{}-{}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).expect("scratch");
    std::fs::write(dir.join("m.adm"), dataset).expect("dataset");
    let path = dir.join("lin.acf");
    std::fs::write(
        &path,
        acf.replace("BASE", &dir.join("plant").display().to_string()),
    )
    .expect("command file");
    let mut sink = |_: &[f64]| -> std::io::Result<()> { Ok(()) };
    (run(&RunRequest::file(&path), &mut sink, None), dir)
}

fn read_matrix(path: &std::path::Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .lines()
        .map(|l| {
            l.split_whitespace()
                .map(|x| x.parse().expect("a number"))
                .collect()
        })
        .collect()
}

fn assert_matrix(got: &[Vec<f64>], want: &[&[f64]], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?}");
    for (g, w) in got.iter().zip(want) {
        assert_eq!(g.len(), w.len(), "{what}: {got:?}");
        for (x, y) in g.iter().zip(w.iter()) {
            assert!(
                (x - y).abs() <= DIGITS * y.abs().max(1.0),
                "{what}: {got:?} vs {want:?}"
            );
        }
    }
}

const PLANT_COMMANDS: &str = "m.adm\nout\nSIMULATE/STATICS\n\
    LINEAR/STATEMAT, FILE = BASE, PINPUT = 1, POUTPUT = 2\nSTOP\n";

#[test]
fn a_force_input_and_state_outputs_give_b_c_and_d() {
    // The spring-mass-damper pushed up by SFORCE/2 = u (from a ground marker below the
    // block, so the line of action is +y); outputs y1 = DY(20), the CM's height, and
    // y2 = VY(20) + 2·u. On x = (y, ẏ): B = [0; 1/m], C = [[1, 0], [0, 1]], D = [0; 2].
    let dataset = SPRING_MASS_DAMPER.replace(
        "END\n",
        "MARKER/12, PART = 1, QP = 0, -10, 0\n\
         SFORCE/2, TRANSLATION, I = 20, J = 12, FUNCTION = VARVAL(1)\n\
         VARIABLE/1, FUNCTION = 0\nVARIABLE/2, FUNCTION = DY(20)\n\
         VARIABLE/3, FUNCTION = VY(20) + 2*VARVAL(1)\n\
         PINPUT/1, VARIABLES = 1\nPOUTPUT/2, VARIABLES = 2, 3\nEND\n",
    );
    let (done, dir) = run_command_file(&dataset, PLANT_COMMANDS);
    let done = done.unwrap_or_else(|f| panic!("{}", f.cause));
    assert!(
        done.summary.text().contains("inputs VARIABLE/1"),
        "{}",
        done.summary.text()
    );
    let m = 2.0;
    assert_matrix(
        &read_matrix(&dir.join("plant.a")),
        &[&[0.0, 1.0], &[-250.0, -1.5]],
        "A",
    );
    assert_matrix(
        &read_matrix(&dir.join("plant.b")),
        &[&[0.0], &[1.0 / m]],
        "B",
    );
    assert_matrix(
        &read_matrix(&dir.join("plant.c")),
        &[&[1.0, 0.0], &[0.0, 1.0]],
        "C",
    );
    assert_matrix(&read_matrix(&dir.join("plant.d")), &[&[0.0], &[2.0]], "D");
    let names = |ext: &str| std::fs::read_to_string(dir.join(format!("plant.{ext}"))).expect(ext);
    assert_eq!(names("pi"), "VARIABLE/1\n");
    assert_eq!(names("po"), "VARIABLE/2\nVARIABLE/3\n");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_torque_input_reaches_the_pendulum_through_its_coordinates() {
    // A compound pendulum (m, d, I about the CM) driven by a torque u about the pin.
    // With the state's coordinate z and its angle θ = z·∂θ/∂z, the linearized equation
    // is I_pin·θ̈ = −m·g·d·θ + u: in any coordinate, B's lower entry is
    // (∂z/∂θ)/I_pin and C for the output AZ is (∂θ/∂z, 0), in the revolute's own
    // rotation (z = θ).
    let (m, d, i) = (2.0, 1.5, 0.5);
    let dataset = format!(
        "pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
         PART/2, MASS = {m}, CM = 20, IP = {i}, {i}, {i}\nMARKER/20, PART = 2, QP = 0, -{d}, 0\n\
         MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 10\nACCGRAV/JGRAV = -{G}\n\
         SFORCE/1, ROTATION, I = 21, J = 10, FUNCTION = VARVAL(1)\n\
         VARIABLE/1, FUNCTION = 0\nVARIABLE/2, FUNCTION = AZ(21, 10)\n\
         PINPUT/1, VARIABLES = 1\nPOUTPUT/2, VARIABLES = 2\nEND\n"
    );
    let (done, dir) = run_command_file(&dataset, PLANT_COMMANDS);
    done.unwrap_or_else(|f| panic!("{}", f.cause));
    let states = std::fs::read_to_string(dir.join("plant.st")).expect("states");
    assert_eq!(states.lines().next(), Some("JOINT/1 (REVOLUTE) rotation"));
    let dz_dtheta = 1.0;
    let pin = i + m * d * d;
    let w2 = m * G * d / pin;
    assert_matrix(
        &read_matrix(&dir.join("plant.a")),
        &[&[0.0, 1.0], &[-w2, 0.0]],
        "A",
    );
    assert_matrix(
        &read_matrix(&dir.join("plant.b")),
        &[&[0.0], &[dz_dtheta / pin]],
        "B",
    );
    assert_matrix(
        &read_matrix(&dir.join("plant.c")),
        &[&[1.0 / dz_dtheta, 0.0]],
        "C",
    );
    assert_matrix(&read_matrix(&dir.join("plant.d")), &[&[0.0]], "D");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_input_that_is_not_a_constant_is_named() {
    let dataset = SPRING_MASS_DAMPER.replace(
        "END\n",
        "SFORCE/2, TRANSLATION, I = 20, J = 10, FUNCTION = VARVAL(1)\n\
         VARIABLE/1, FUNCTION = TIME\nVARIABLE/2, FUNCTION = DY(20)\n\
         PINPUT/1, VARIABLES = 1\nPOUTPUT/2, VARIABLES = 2\nEND\n",
    );
    let (done, dir) = run_command_file(&dataset, PLANT_COMMANDS);
    let Err(failed) = done else {
        panic!("VARIABLE/1 is a function of time")
    };
    assert!(
        failed
            .cause
            .contains("LINEAR/STATEMAT: VARIABLE/1 (an input) has a FUNCTION of time"),
        "{}",
        failed.cause
    );
    let missing = run_command_file(
        SPRING_MASS_DAMPER,
        "m.adm\nout\nLINEAR/STATEMAT, FILE = BASE, POUTPUT = 7\nSTOP\n",
    );
    let Err(failed) = missing.0 else {
        panic!("there is no POUTPUT/7")
    };
    assert!(
        failed.cause.contains("POUTPUT/7 is not in the dataset"),
        "{}",
        failed.cause
    );
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&missing.1);
}

/// The names of the report's minimal coordinates.
fn coordinate_names(r: &LinearReport) -> Vec<&str> {
    r.linearized
        .coords
        .iter()
        .map(|c| c.name.as_str())
        .collect()
}

/// The minimal coordinates are the joints' own (issue 41 §4): a torsion pendulum's mode
/// is its revolute's rotation, and a double pendulum's modes are shapes in its two
/// revolutes' rotations (the second relative to the first), the ratio of which the
/// eigenvector of (K − ω²·M)·θ = 0 in absolute angles gives.
#[test]
fn modes_are_named_and_shaped_in_the_joints_own_coordinates() {
    // An inverted pendulum (CM 1 m above the pin) held up by a torsion spring.
    let torsion = "torsion pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 1, CM = 20, IP = 0.1, 0.1, 0.1\nMARKER/20, PART = 2, QP = 0, 1, 0\n\
        MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 10\n\
        SPRINGDAMPER/1, ROTATION, I = 21, J = 10, KT = 20\nACCGRAV/JGRAV = -9.81\nEND\n";
    let (m1, i1, d1, l1, m2, i2, d2) = (1.0, 0.1, 0.5, 1.0, 1.5, 0.05, 0.4);
    let (ma, mb) = (i1 + m1 * d1 * d1 + m2 * l1 * l1, m2 * l1 * d2);
    let ka = G * (m1 * d1 + m2 * l1);
    for dim in DIMS {
        let r = linearized(torsion, dim);
        let names = coordinate_names(&r);
        assert_eq!(names, ["JOINT/1 (REVOLUTE) rotation"], "{dim:?}");
        assert_eq!(r.modes[0].dominant, "JOINT/1 (REVOLUTE) rotation");
        // ω² = (KT − m·g·d)/(I + m·d²).
        assert_close(&omegas(&r), &[(10.19f64 / 1.1).sqrt()], "torsion");

        let r = linearized(&double_pendulum(m1, i1, d1, l1, m2, i2, d2), dim);
        let names = coordinate_names(&r);
        assert_eq!(
            names,
            ["JOINT/1 (REVOLUTE) rotation", "JOINT/2 (REVOLUTE) rotation"],
            "{dim:?}"
        );
        for mode in &r.modes {
            let w2 = mode.eigenvalue.norm_sqr();
            // Absolute angles: θ2/θ1 = (ka − ω²·ma)/(ω²·mb); JOINT/2 turns by θ2 − θ1.
            let want = (ka - w2 * ma) / (w2 * mb) - 1.0;
            let z = mode.coordinates.as_ref().expect("shapes");
            let got = (z[1] / z[0]).re;
            assert!(
                ((got - want) / want).abs() < 1e-9 && (z[1] / z[0]).im.abs() < 1e-9,
                "{dim:?} mode {}: {got} vs {want}",
                mode.number
            );
            // The coordinate that moves most names the mode and moves by 1.
            let top = usize::from(z[1].norm() > z[0].norm());
            assert_eq!(mode.dominant, names[top]);
            assert!((z[top] - 1.0).norm() < 1e-12);
        }
    }
}
