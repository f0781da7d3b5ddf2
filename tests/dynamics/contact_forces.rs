//! CONTACT forces between geometries (issue 40 §1) against closed forms written here, on
//! the small datasets `tests/data/contact_*.adm`: a sphere and a lying cylinder at rest
//! at (m g / k)^(1/e), a POISSON rebound near ε²·h, a block stopping after
//! v0²/(2 μ g) in 3D and in the plane, a block that sticks below tan θ = μs and slides
//! above, a ball whose free flight takes large steps, and the corpus' CONTACT datasets.

use crate::run::{last, named, run_probed, run_raw, test_data as data, Csv};
use std::path::{Path, PathBuf};

const G: f64 = 9.80665;

/// `mbfx run` of `name` to `end` at output step `dt` with `extra` arguments, probing the
/// CM's y and x (marker 20) and its x velocity.
fn run(name: &str, end: &str, dt: &str, extra: &[&str]) -> Csv {
    let mut args = vec!["--end", end, "--output-step", dt];
    args.extend_from_slice(extra);
    let probes = named(&[("y", "DY(20)"), ("x", "DX(20)"), ("vx", "VX(20)")]);
    run_probed(&data(name), &args, &probes)
}

/// The steps and CPU seconds `mbfx run` reports in its summary.
fn steps_and_cpu(stderr: &str) -> (usize, f64) {
    let line = (stderr.lines())
        .find(|l| l.contains(" steps (") && l.contains(" s CPU"))
        .unwrap_or_else(|| panic!("no summary in\n{stderr}"));
    let steps = line.split(" steps (").next().unwrap();
    let steps = steps.rsplit(' ').next().unwrap().parse().unwrap();
    let cpu = line.split(" s CPU").next().unwrap();
    let cpu = cpu.rsplit(' ').next().unwrap().parse().unwrap();
    (steps, cpu)
}

#[test]
fn a_sphere_rests_at_the_static_depth_of_the_impact_law() {
    // m = 1, k = 1E5, e = 1.5: g = (m g / k)^(1/e).
    let want = (G / 1e5).powf(1.0 / 1.5);
    let csv = run("contact_sphere_rest.adm", "1", "0.01", &["--error", "1e-5"]);
    let depth = 0.1 - last(&csv.col("y"));
    assert!((depth - want).abs() < 1e-2 * want, "{depth} {want}");
    // The columns: the same penetration, and the normal force carries the weight.
    assert!((last(&csv.col("CONTACT1.PEN")) - want).abs() < 1e-2 * want);
    assert!((last(&csv.col("CONTACT1.FN")) - G).abs() < 1e-3 * G);
    assert_eq!(last(&csv.col("CONTACT1.FF")), 0.0);
}

#[test]
fn a_lying_cylinder_rests_at_the_static_depth_as_one_incident() {
    // m = 2, k = 1E6, e = 1.2: one incident along the whole line of contact carries all
    // of the weight (Adams' semantics); were each contact point its own incident, the
    // depth would be smaller.
    let want = (2.0 * G / 1e6).powf(1.0 / 1.2);
    let csv = run(
        "contact_cylinder_rest.adm",
        "1",
        "0.01",
        &["--error", "1e-5"],
    );
    let depth = 0.05 - last(&csv.col("y"));
    assert!((depth - want).abs() < 2e-2 * want, "{depth} {want}");
    assert!((last(&csv.col("CONTACT1.FN")) - 2.0 * G).abs() < 1e-3 * 2.0 * G);
}

#[test]
fn a_poisson_contact_returns_the_drop_times_the_restitution_squared() {
    // Dropped from 0.5 m (the sphere's bottom), ε = 0.8: the rebound's apex is ε²·h.
    let csv = run(
        "contact_poisson_drop.adm",
        "1",
        "0.001",
        &["--error", "1e-6"],
    );
    let (t, y) = (csv.time(), csv.col("y"));
    let hit = (y.iter()).position(|&y| y < 0.1).expect("it lands");
    let apex = y[hit..].iter().copied().fold(f64::MIN, f64::max) - 0.1;
    let want = 0.8f64.powi(2) * 0.5;
    assert!(
        (apex - want).abs() < 2e-2 * want,
        "apex {apex} at t ≤ {}",
        t[t.len() - 1]
    );
}

/// The distance a block sliding at 2 m/s with μ = 0.3 takes to stop: v0²/(2 μ g).
fn stopping_distance() -> f64 {
    2.0f64.powi(2) / (2.0 * 0.3 * G)
}

#[test]
fn a_sliding_block_stops_after_v0_squared_over_2_mu_g_in_3d() {
    let csv = run("contact_block_slide_3d.adm", "1", "0.01", &["--dim", "3"]);
    let x = last(&csv.col("x"));
    assert!(
        (x - stopping_distance()).abs() < 1e-2 * stopping_distance(),
        "{x}"
    );
    assert!(last(&csv.col("vx")).abs() < 1e-3);
}

#[test]
fn a_sliding_block_stops_after_v0_squared_over_2_mu_g_in_the_plane() {
    let csv = run("contact_block_slide_2d.adm", "1", "0.01", &["--dim", "2"]);
    let x = last(&csv.col("x"));
    assert!(
        (x - stopping_distance()).abs() < 1e-2 * stopping_distance(),
        "{x}"
    );
}

#[test]
fn a_block_sticks_below_the_static_angle_and_slides_above() {
    // μs = 0.5: tan 20° = 0.364 holds (it creeps below the stiction velocity, 1 mm/s, as
    // Adams' friction has no true stiction); tan 30° = 0.577 does not, and the block
    // accelerates at g (sin θ − μd cos θ) with μd = 0.4.
    let csv = run("contact_incline_20.adm", "1", "0.01", &[]);
    assert!(
        last(&csv.col("vx")).abs() < 1e-3,
        "{}",
        last(&csv.col("vx"))
    );
    assert!(last(&csv.col("x")).abs() < 1e-3);
    let csv = run("contact_incline_30.adm", "1", "0.01", &[]);
    let th = 30f64.to_radians();
    let want = 0.5 * G * (th.sin() - 0.4 * th.cos());
    let x = last(&csv.col("x"));
    assert!((x - want).abs() < 2e-2 * want, "{x} {want}");
}

#[test]
fn a_ball_in_free_flight_takes_large_steps() {
    // Free flight for 0.45 s, then a stiff contact (k = 1E7): the steps shrink only
    // around the contact. With its contact's step everywhere (HMAX 1E-4) the run takes
    // at least the 10,000 steps of the second.
    let path = data("contact_ball_drop.adm");
    let args = ["--end", "1", "--output-step", "0.1"];
    let out = run_raw(&path, &args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (free, cpu) = steps_and_cpu(&String::from_utf8_lossy(&out.stderr));
    let out = run_raw(&path, &[&args[..], &["--hmax", "1e-4"]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (fine, fine_cpu) = steps_and_cpu(&String::from_utf8_lossy(&out.stderr));
    eprintln!(
        "ball drop: {free} steps, {cpu} s CPU; with HMAX 1E-4: {fine} steps, {fine_cpu} s CPU"
    );
    assert!(fine >= 10_000, "{fine}");
    assert!(free * 10 < fine, "{free} steps against {fine}");
}

/// The corpus dataset `rel`.
fn corpus(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/corpus/adams")
        .join(rel)
}

#[test]
fn the_corpus_contact_runs_with_its_contact_modelled() {
    // test_2.adm: a sphere (ELLIPSOID) and an EXTERNAL Parasolid body not in the corpus,
    // which a placeholder box stands in for, warned once.
    let path = corpus("bthornton191__aview_hpc/test/models/test_2.adm");
    let out = run_raw(&path, &["--end", "0.1", "--output-step", "0.01"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("not modelled"), "{stderr}");
    let placeholder = "EXTERNAL GRAPHICS/1 is a CONTACT geometry without a mesh";
    assert_eq!(stderr.matches(placeholder).count(), 1, "{stderr}");
    let csv = Csv::parse(&String::from_utf8_lossy(&out.stdout));
    assert!(csv
        .col("CONTACT1.FN")
        .iter()
        .all(|f| f.is_finite() && *f >= 0.0));
}

#[test]
fn contacts_left_out_keep_their_columns_at_zero() {
    // adams_vscode's test.adm: three CONTACTs whose geometry is on an FE_PART, left out
    // with a warning. Their columns address contacts by their place in the dataset: they
    // read zero (a run once panicked indexing past the contacts kept).
    let path = corpus("bthornton191__adams_vscode/test/files/test.adm");
    let out = run_raw(&path, &["--end", "0.01", "--output-step", "0.005"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let csv = Csv::parse(&String::from_utf8_lossy(&out.stdout));
    let columns: Vec<String> = (csv.header.iter())
        .filter(|n| n.starts_with("CONTACT"))
        .cloned()
        .collect();
    assert_eq!(columns.len(), 12, "{columns:?}");
    for name in columns {
        assert!(csv.col(&name).iter().all(|f| *f == 0.0), "{name}");
    }
}

/// N spheres in a square grid 0.5 m apart, 5 cm above a floor, each its own part and its
/// own CONTACT with the floor (IMPACT k = 1E5, e = 1.5).
fn spheres(n: usize) -> String {
    let side = (n as f64).sqrt().ceil() as usize;
    // The floor reaches 1 m past the grid on every side.
    let width = 0.5 * side as f64 + 2.0;
    let mut s = format!(
        "{n} spheres falling onto a floor\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         ACCGRAV/JGRAV = -9.80665\nPART/1, GROUND\nMARKER/1, PART = 1, QP = -1, -0.2, -1\n\
         GRAPHICS/1, BOX, CORNER = 1, X = {width}, Y = 0.2, Z = {width}\n"
    );
    for k in 0..n {
        let (x, z) = (0.5 * (k % side) as f64, 0.5 * (k / side) as f64);
        let id = k + 2;
        s += &format!(
            "PART/{id}, MASS = 1, CM = {id}, IP = 0.004, 0.004, 0.004, QG = {x}, 0.15, {z}\n\
             MARKER/{id}, PART = {id}\n\
             GRAPHICS/{id}, ELLIPSOID, CM = {id}, XSCALE = 0.2, YSCALE = 0.2, ZSCALE = 0.2\n\
             CONTACT/{id}, IGEOM = {id}, JGEOM = 1, IMPACT, STIFFNESS = 1E5, DAMPING = 100, DMAX = 1E-3, EXPONENT = 1.5\n"
        );
    }
    s + "END\n"
}

/// Runs N spheres onto the floor; checks that every one rests on its contact and returns
/// the CPU per step.
fn spheres_rest(n: usize) -> f64 {
    let path = std::env::temp_dir().join(format!("mbfx_contact_spheres_{n}.adm"));
    std::fs::write(&path, spheres(n)).unwrap();
    let out = run_raw(&path, &["--end", "0.3", "--output-step", "0.05"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "N = {n}: {stderr}");
    let (steps, cpu) = steps_and_cpu(&stderr);
    eprintln!(
        "N = {n}: {steps} steps, {cpu} s CPU, {:.3e} s a step",
        cpu / steps as f64
    );
    // Every sphere has landed and rests: its contact carries its weight.
    let csv = Csv::parse(&String::from_utf8_lossy(&out.stdout));
    for k in 0..n {
        let f = last(&csv.col(&format!("CONTACT{}.FN", k + 2)));
        assert!((f - G).abs() < 5e-2 * G, "N = {n}, sphere {k}: {f}");
    }
    cpu / steps as f64
}

#[test]
fn n_falling_spheres_each_rest_on_their_contact() {
    for n in [10, 100] {
        spheres_rest(n);
    }
}

/// Figures of issue 40 (`--ignored`): CPU per step against N and the log-log slope from
/// N = 10 to 1000 (N log N would be about 1.1 here; N² would be 2). Measured, not
/// asserted: see docs/status.md for the figures and the goal they miss.
#[test]
#[ignore]
fn figures_cost_per_step_of_n_falling_spheres() {
    let cost: Vec<(f64, f64)> = [10usize, 100, 1000]
        .into_iter()
        .map(|n| (n as f64, spheres_rest(n)))
        .collect();
    let slope = (cost[2].1 / cost[0].1).ln() / (cost[2].0 / cost[0].0).ln();
    eprintln!("log-log slope of the cost per step, N = 10 to 1000: {slope:.2}");
}

#[test]
fn no_step_carries_a_ball_through_the_floor() {
    // Dropped 0.1 m onto a floor 0.2 m thick with rows interpolated and no HMAX: a free
    // flight step of dopri853 grew to 0.3 s and carried the ball clean through, apart at
    // both ends of it (it ended 1.86 m below the floor). It must come to rest on the top
    // (y = 0) at the linear law's depth m·g/k.
    let want = 0.1 - G / 1e5;
    // (dopri853 at 1e-10 is the run that passed through; the implicit methods' steps
    // are bounded too, and must not suffer for it.)
    for (method, error) in [("dopri853", "1e-10"), ("gstiff", "1e-6"), ("hht", "1e-6")] {
        let csv = run(
            "contact_ball_long_steps.adm",
            "1",
            "1e-3",
            &["--integrator", method, "--error", error, "--interpolate"],
        );
        let y = csv.col("y");
        assert!(
            y.iter().all(|&y| y > 0.0),
            "{method}: below the floor's top"
        );
        assert!(
            (last(&y) - want).abs() < 1e-6,
            "{method}: {} {want}",
            last(&y)
        );
    }
}
