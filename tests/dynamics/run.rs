//! `mbfx run` (DESIGN.md's CLI contract) against both truths: Adams' files for all chrono
//! cases and the exact reduced solutions for those that have one; plus the rack and pinion
//! (no Adams output: exact constant acceleration and energy), `--dim 2` ≡ `--dim 3` on planar
//! scenes and `--engine interp` ≡ JIT byte for byte. Ignored until `mbfx run` exists.

use crate::adams::{case, Case, Quantity, Table, CASES, QUANTITIES, ROUND_OFF};
use crate::exact::{models, G};
use crate::validate::{align_quaternions, deviations, failures, magnitudes, ColumnDeviation};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The output of `mbfx run … --csv -`: the header and the numbers, row by row.
pub struct Csv {
    pub header: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Csv {
    /// Parses the contract's CSV: a header whose first column is `time`, then rows of
    /// numbers as Rust's `{:?}` prints an `f64` (`0.01`, `-4.78373e-4`, `NaN`, `inf`).
    pub fn parse(text: &str) -> Csv {
        let mut lines = text.lines();
        let header: Vec<String> = lines
            .next()
            .unwrap_or_else(|| panic!("empty CSV"))
            .split(',')
            .map(str::to_owned)
            .collect();
        assert_eq!(header[0], "time", "first CSV column: {header:?}");
        let rows = lines
            .map(|l| {
                let row: Vec<f64> = l
                    .split(',')
                    .map(|s| s.parse().unwrap_or_else(|e| panic!("CSV `{s}`: {e}")))
                    .collect();
                assert_eq!(row.len(), header.len(), "CSV row `{l}`");
                row
            })
            .collect();
        Csv { header, rows }
    }

    pub fn time(&self) -> Vec<f64> {
        self.rows.iter().map(|r| r[0]).collect()
    }

    pub fn col(&self, name: &str) -> Vec<f64> {
        let i = self
            .header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no CSV column {name} in {:?}", self.header));
        self.rows.iter().map(|r| r[i]).collect()
    }

    /// Rows at k·dt from 0 (the contract), to `end` when given.
    pub fn assert_grid(&self, dt: f64, end: Option<f64>) {
        for (k, t) in self.time().iter().enumerate() {
            assert!(
                (t - k as f64 * dt).abs() < 1e-9 * (1.0 + t),
                "row {k} at t = {t}"
            );
        }
        if let Some(end) = end {
            assert_eq!(
                self.rows.last().map(|r| r[0]),
                Some(end),
                "last row exactly at T"
            );
        }
    }
}

/// The project's test dataset `tests/data/NAME`.
pub fn test_data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The last value of a column.
pub fn last(v: &[f64]) -> f64 {
    *v.last().expect("rows")
}

/// `mbfx run MODEL ARGS… --csv -`, whatever its outcome.
pub fn run_raw(model: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .arg("run")
        .arg(model)
        .args(args)
        .args(["--csv", "-"])
        .output()
        .expect("runs mbfx")
}

/// `mbfx run MODEL ARGS… --csv -`, which must succeed; its CSV.
pub fn run(model: &Path, args: &[&str]) -> Csv {
    let out = run_raw(model, args);
    assert!(
        out.status.success(),
        "mbfx run {} {}: {}\n{}",
        model.display(),
        args.join(" "),
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    Csv::parse(&String::from_utf8(out.stdout).expect("UTF-8 CSV"))
}

/// `--probe NAME=EXPR` pairs as arguments.
pub fn probe_args(probes: &[(String, String)]) -> Vec<String> {
    probes
        .iter()
        .flat_map(|(n, e)| ["--probe".to_owned(), format!("{n}={e}")])
        .collect()
}

/// `(name, expression)` pairs as owned probes.
pub fn named(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
    pairs
        .iter()
        .map(|(n, e)| (n.to_string(), e.to_string()))
        .collect()
}

/// `mbfx run MODEL ARGS… --probe …` (see [`run`]).
pub fn run_probed(model: &Path, args: &[&str], probes: &[(String, String)]) -> Csv {
    let probe_args = probe_args(probes);
    let mut all: Vec<&str> = args.to_vec();
    all.extend(probe_args.iter().map(String::as_str));
    run(model, &all)
}

/// 0–5 s at 0.01 s with `integrator` at `error`: the chrono runs' settings.
pub fn case_args<'a>(integrator: &'a str, error: &'a str) -> Vec<&'a str> {
    let mut args = vec!["--end", "5", "--output-step", "0.01", "--error", error];
    args.extend(integrator_args(integrator));
    args
}

/// [`case_args`] at the tight ERROR.
pub fn tight_args(integrator: &str) -> Vec<&str> {
    case_args(integrator, TIGHT_ERROR)
}

/// The command-line flags of an integrator named as in [`INTEGRATORS`]: `NAME` or
/// `NAME/FORMULATION` (`gstiff/si2`).
pub fn integrator_args(integrator: &str) -> Vec<&str> {
    match integrator.split_once('/') {
        Some((name, f)) => vec!["--integrator", name, "--formulation", f],
        None => vec!["--integrator", integrator],
    }
}

/// The probes that reproduce a case's eight files: the CM marker relative to ground, in
/// ground axes, and the reaction its REQUEST/05 measured.
pub fn case_probes(c: &Case) -> Vec<(String, String)> {
    let m = c.cm;
    let mut p: Vec<(String, String)> = Vec::new();
    let mut add = |n: &str, e: String| p.push((n.to_owned(), e));
    for (ax, d, v, a, w, wd) in [
        ("x", "DX", "VX", "ACCX", "WX", "WDTX"),
        ("y", "DY", "VY", "ACCY", "WY", "WDTY"),
        ("z", "DZ", "VZ", "ACCZ", "WZ", "WDTZ"),
    ] {
        add(&format!("pos_{ax}"), format!("{d}({m},101)"));
        add(&format!("vel_{ax}"), format!("{v}({m},101)"));
        add(&format!("acc_{ax}"), format!("{a}({m},101)"));
        add(&format!("avel_{ax}"), format!("{w}({m},101)"));
        add(&format!("aacc_{ax}"), format!("{wd}({m},101)"));
    }
    // Euler parameters as the chrono REQUEST/04 asks Adams for them (ORIENT code 27):
    // 3-1-3 angles lose ψ and φ apart at θ = 0, where several cases start.
    for k in 1..=4 {
        add(&format!("e{}", k - 1), format!("ORIENT(27,{k},{m},101)"));
    }
    for (i, ax) in ["x", "y", "z"].iter().enumerate() {
        add(&format!("rforce_{ax}"), c.reaction.force[i].to_owned());
        add(&format!("rtorque_{ax}"), c.reaction.torque[i].to_owned());
    }
    p
}

/// The columns of quantity `q` out of a run made with [`case_probes`].
pub fn csv_columns(csv: &Csv, q: Quantity) -> Vec<Vec<f64>> {
    let prefix = match q {
        Quantity::Pos => "pos",
        Quantity::Vel => "vel",
        Quantity::Acc => "acc",
        Quantity::Avel => "avel",
        Quantity::Aacc => "aacc",
        Quantity::Rforce => "rforce",
        Quantity::Rtorque => "rtorque",
        Quantity::Quat => {
            return (0..4).map(|i| csv.col(&format!("e{i}"))).collect();
        }
    };
    ["x", "y", "z"]
        .iter()
        .map(|ax| csv.col(&format!("{prefix}_{ax}")))
        .collect()
}

/// The integrators of issue 8 and the tight ERROR the Adams comparison runs at.
pub const INTEGRATORS: [&str; 3] = ["hht", "galpha", "gstiff"];
pub const TIGHT_ERROR: &str = "1e-12";

/// `mbfx run` over 0–5 s at 0.01 s with the case's probes, at the tight ERROR.
pub fn run_case(c: &Case, integrator: &str) -> Csv {
    run_case_at(c, integrator, TIGHT_ERROR)
}

/// [`run_case`] at `error`.
pub fn run_case_at(c: &Case, integrator: &str, error: &str) -> Csv {
    let csv = run_probed(&c.model(), &case_args(integrator, error), &case_probes(c));
    csv.assert_grid(0.01, Some(5.0));
    let names: Vec<&str> = csv.header[1..].iter().map(String::as_str).collect();
    let want: Vec<String> = case_probes(c).into_iter().map(|(n, _)| n).collect();
    assert_eq!(names[..want.len()], want, "probe columns in order");
    csv
}

/// Every column of a run against `truth` for each quantity.
fn compare(
    csv: &Csv,
    truth: impl Fn(Quantity) -> Table,
    bound: impl Fn(Quantity, f64, f64) -> f64,
) -> Vec<ColumnDeviation> {
    let time = csv.time();
    let mut out = Vec::new();
    for q in QUANTITIES {
        let t = truth(q);
        assert_eq!(t.time.len(), time.len());
        let mut mine = csv_columns(csv, q);
        if q == Quantity::Quat {
            align_quaternions(&mut mine, &t.cols);
        }
        out.extend(deviations(q, &time, &mine, &t, |m, a| bound(q, m, a)));
    }
    out
}

fn all_cases_match_adams(integrator: &str) {
    let mut bad = Vec::new();
    for c in &CASES {
        let csv = run_case(c, integrator);
        let devs = compare(&csv, |q| c.table(q), |q, m, a| q.adams_bound(m, a));
        bad.extend(failures(&format!("{integrator} {}", c.name), &devs));
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// At Adams' default ERROR = 1e-3 (issue 9): positions and Euler parameters within Adams'
/// 2e-3 of its own output (the files were written at ERROR 1e-4, HMAX 1e-5) for the cases
/// `which` selects; the other quantities are not asked for at that ERROR.
fn cases_match_adams_positions_at_default_error(integrator: &str, which: fn(&str) -> bool) {
    let mut bad = Vec::new();
    for c in CASES.iter().filter(|c| which(c.name)) {
        let csv = run_case_at(c, integrator, "1e-3");
        let devs = compare(
            &csv,
            |q| c.table(q),
            |q, m, a| match q {
                Quantity::Pos | Quantity::Quat => q.adams_bound(m, a),
                _ => f64::INFINITY,
            },
        );
        bad.extend(failures(&format!("{integrator} {} at 1e-3", c.name), &devs));
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// The two DISTANCE cases leave the body free to spin about the rod, and at ERROR 1e-3
/// the spin's phase wanders: see the ignored test below.
fn wanders_at_1e_3(name: &str) -> bool {
    matches!(name, "Distance_Case02" | "Distance_Case03")
}

#[test]
fn gstiff_at_adams_default_error_stays_within_2e_3_of_adams_positions() {
    cases_match_adams_positions_at_default_error("gstiff", |n| !wanders_at_1e_3(n));
}

#[test]
#[ignore = "fails: at ERROR 1e-3 GSTIFF I3 ends Distance_Case02 1.2 m and Distance_Case03 3e-2 m off Adams (SI2: 3e-3 and 9e-3); both pass at the tight ERROR"]
fn gstiff_at_adams_default_error_on_the_distance_cases() {
    cases_match_adams_positions_at_default_error("gstiff", wanders_at_1e_3);
}

#[test]
fn gstiff_matches_adams_on_every_chrono_case() {
    all_cases_match_adams("gstiff");
}

#[test]
fn gstiff_si2_matches_adams_on_every_chrono_case() {
    all_cases_match_adams("gstiff/si2");
}

#[test]
fn dopri853_matches_adams_on_every_chrono_case() {
    all_cases_match_adams("dopri853");
}

#[test]
fn hht_matches_adams_on_every_chrono_case() {
    all_cases_match_adams("hht");
}

#[test]
fn galpha_matches_adams_on_every_chrono_case() {
    all_cases_match_adams("galpha");
}

/// Beyond Adams: positions and Euler parameters within 1e-6 of the column's largest
/// magnitude, the rest within 1e-5 ([`Quantity::scale`] for components that are zero in
/// truth, [`ROUND_OFF`] for quantities that are).
pub fn exact_bound(q: Quantity, col_max: f64, q_max: f64) -> f64 {
    let rel = match q {
        Quantity::Pos | Quantity::Quat => 1e-6,
        _ => 1e-5,
    };
    rel * Quantity::scale(col_max, q_max) + ROUND_OFF
}

fn one_dof_cases_match_exact(integrator: &str) {
    let mut bad = Vec::new();
    for m in models() {
        let c = case(m.name);
        let csv = run_case(c, integrator);
        let time = csv.time();
        let all = m.all_columns(&time);
        let truth = |q: Quantity| {
            let cols = all.iter().find(|(p, _)| *p == q).unwrap().1.clone();
            Table {
                names: (0..cols.len()).map(|i| format!("{i}")).collect(),
                time: time.clone(),
                cols,
            }
        };
        let devs = compare(&csv, truth, exact_bound);
        bad.extend(failures(
            &format!("{integrator} {} vs exact", m.name),
            &devs,
        ));
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn hht_matches_the_exact_one_dof_solutions() {
    one_dof_cases_match_exact("hht");
}

#[test]
fn galpha_matches_the_exact_one_dof_solutions() {
    one_dof_cases_match_exact("galpha");
}

#[test]
fn gstiff_matches_the_exact_one_dof_solutions() {
    one_dof_cases_match_exact("gstiff");
}

#[test]
fn gstiff_si2_matches_the_exact_one_dof_solutions() {
    one_dof_cases_match_exact("gstiff/si2");
}

#[test]
fn wstiff_matches_the_exact_one_dof_solutions() {
    one_dof_cases_match_exact("wstiff");
}

/// The rack and pinion (no Adams output): the pinion (1 kg, I = 0.1 about the shaft,
/// global x) turns on a revolute at the origin, the rack (1 kg) slides on a vertical
/// translational joint, RACKPIN PD = 0.1 ties them: s = (PD/2)·θ. Lagrange with the one
/// coordinate s: (m_r + I/r²)·s̈ = m_r·g, so the rack falls with the constant
/// a = g·m_r / (m_r + I/r²) = g/41, and T + V is conserved.
#[test]
fn rackpinion_falls_at_g_over_41_and_conserves_energy() {
    let model = crate::adams::joints_dir().join("adams_models/test_RackPinion_Case01.adm");
    let (m_r, inertia, r) = (1.0, 0.1, 0.05);
    let a = G * m_r / (m_r + inertia / (r * r));
    let probes = named(&[
        ("z", "DZ(301,101)"),
        ("vz", "VZ(301,101)"),
        ("az", "ACCZ(301,101)"),
        ("w", "WX(201,101)"),
        ("y", "DY(301,101)"),
    ]);
    for integrator in INTEGRATORS {
        let csv = run_probed(&model, &tight_args(integrator), &probes);
        csv.assert_grid(0.01, Some(5.0));
        let (t, z, vz, az, w) = (
            csv.time(),
            csv.col("z"),
            csv.col("vz"),
            csv.col("az"),
            csv.col("w"),
        );
        let z0 = z[0];
        let fall = 0.5 * a * 25.0; // |Δz| at 5 s, the scale of every bound below
        for k in 0..t.len() {
            let ctx = format!("{integrator} t = {}", t[k]);
            assert!(
                (z[k] - (z0 - 0.5 * a * t[k] * t[k])).abs() < 1e-6 * fall,
                "{ctx}: z"
            );
            assert!((vz[k] + a * t[k]).abs() < 1e-5 * a * 5.0, "{ctx}: vz");
            assert!((az[k] + a).abs() < 1e-5 * a, "{ctx}: az");
            assert!(
                (vz[k].abs() - r * w[k].abs()).abs() < 1e-5 * a * 5.0,
                "{ctx}: gear"
            );
            let energy =
                0.5 * m_r * vz[k].powi(2) + 0.5 * inertia * w[k].powi(2) + m_r * G * (z[k] - z0);
            assert!(
                energy.abs() < 1e-6 * m_r * G * fall,
                "{ctx}: energy {energy:e}"
            );
        }
        let y = csv.col("y");
        assert!(
            y.iter().all(|v| (v - y[0]).abs() < 1e-9),
            "{integrator}: rack stays on its line"
        );
    }
}

/// Planar scenes run in 2D must give the 3D trajectories.
#[test]
fn dim_2_and_dim_3_agree_on_planar_scenes() {
    let scenes = [
        (case("Revolute_Case01").model(), 201),
        (crate::adams::models_dir().join("a01_pendulum.adm"), 201),
    ];
    for (model, cm) in scenes {
        for integrator in INTEGRATORS {
            let probes: Vec<(String, String)> = ["DX", "DY", "DZ"]
                .iter()
                .map(|d| (d.to_lowercase(), format!("{d}({cm},101)")))
                .collect();
            let runs: Vec<Csv> = ["2", "3"]
                .iter()
                .map(|dim| {
                    // Fixed steps with a corrector converged to its floor (ERROR sets the
                    // Newton tolerance): both builds take the same steps, so they must agree
                    // to rounding, not merely to the integration error. The two Newton
                    // matrices differ (the 3D one lacks the stiffness of the rows that are
                    // out of plane), so a looser corrector stops them at different points.
                    let mut args = vec![
                        "--end",
                        "5",
                        "--output-step",
                        "0.01",
                        "--integrator",
                        integrator,
                        "--fixed-step",
                        "1e-3",
                        "--error",
                        "1e-8",
                    ];
                    args.extend(["--dim", dim]);
                    run_probed(&model, &args, &probes)
                })
                .collect();
            assert_eq!(runs[0].rows.len(), runs[1].rows.len());
            for (a, b) in runs[0].rows.iter().zip(&runs[1].rows) {
                // Time and the probes (the REQUEST columns after them include angles at
                // ±π, where rounding picks either sign).
                for (x, y) in a.iter().zip(b).take(1 + probes.len()) {
                    assert!(
                        (x - y).abs() < 1e-9,
                        "{} {integrator}: {a:?} vs {b:?}",
                        model.display()
                    );
                }
            }
        }
    }
}

/// The interpreter and the JIT run the same IR through the same runtime: the CSV must be
/// the same bytes, on the scenes whose forces are expressions.
#[test]
fn engine_interp_and_jit_give_byte_identical_csv() {
    for name in ["RotSpring_Case01", "TranSpring_Case01", "Distance_Case02"] {
        let c = case(name);
        let mut args: Vec<String> = ["--end", "5", "--output-step", "0.01", "--error", "1e-5"]
            .map(str::to_owned)
            .to_vec();
        args.extend(probe_args(&case_probes(c)));
        let outs: Vec<Vec<u8>> = ["interp", "jit"]
            .iter()
            .map(|engine| {
                let mut a: Vec<&str> = args.iter().map(String::as_str).collect();
                a.extend(["--engine", engine]);
                let out = run_raw(&c.model(), &a);
                assert!(
                    out.status.success(),
                    "{name} {engine}: {}",
                    String::from_utf8_lossy(&out.stderr)
                );
                out.stdout
            })
            .collect();
        assert!(outs[0].len() > 100, "{name}: CSV");
        assert!(outs[0] == outs[1], "{name}: interp and jit CSVs differ");
    }
}

#[test]
fn the_csv_reader_takes_the_contracts_number_format() {
    // `{:?}` of f64: shortest round-trip, exponent without sign padding, NaN and inf.
    let csv = Csv::parse("time,a,b\n0.0,1e-7,-4.78373e-4\n0.01,NaN,inf\n0.02,-inf,2.0\n");
    csv.assert_grid(0.01, Some(0.02));
    assert_eq!(csv.col("a")[0], 1e-7);
    assert!(csv.col("a")[1].is_nan() && csv.col("b")[1] == f64::INFINITY);
    assert_eq!(format!("{:?}", -4.78373e-4_f64), "-0.000478373");
    assert_eq!("-0.000478373".parse::<f64>().unwrap(), -4.78373e-4);
    let _ = magnitudes(&[vec![1.0]]);
}

/// `--plot` writes the chart; `--csv FILE` the rows (201 at 0.01 s over 2 s, plus the header).
#[test]
fn plot_and_csv_files_are_written() {
    let dir = std::env::temp_dir().join(format!("mbfx-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (csv, svg, png) = (dir.join("s.csv"), dir.join("s.svg"), dir.join("s.png"));
    let model = crate::adams::models_dir().join("../../examples/slider.adm");
    for plot in [&svg, &png] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_mbfx"))
            .arg("run")
            .arg(&model)
            .args([
                "--end",
                "2",
                "--output-step",
                "0.01",
                "--probe",
                "x=DX(22,11)",
                "--csv",
                csv.to_str().unwrap(),
                "--plot",
                plot.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().count(), 202);
    assert!(text.starts_with("time,x,REQ1.F2"));
    let svg_text = std::fs::read_to_string(&svg).unwrap();
    // The probe's line (text is drawn as glyph outlines, not <text>).
    assert!(svg_text.starts_with("<svg") && svg_text.contains("<polyline"));
    let png_bytes = std::fs::read(&png).unwrap();
    assert_eq!(&png_bytes[1..4], b"PNG");
    // IHDR: 960 wide (src/cli/plot.rs), 8-bit RGB; a blank canvas would compress to a
    // few hundred bytes, the three panels' lines and text to far more.
    let be = |k: usize| u32::from_be_bytes(png_bytes[k..k + 4].try_into().unwrap());
    assert_eq!((&png_bytes[12..16], be(16)), (&b"IHDR"[..], 960));
    assert_eq!((png_bytes[24], png_bytes[25]), (8, 2));
    assert!(png_bytes.len() > 20_000, "{} bytes", png_bytes.len());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 24: a probe is checked for units in the dataset's units; a warning that points
/// into the probe's own text, and the run and its column go on unchanged.
#[test]
fn a_probe_whose_units_do_not_fit_warns_and_still_runs() {
    let model = crate::adams::models_dir().join("../../examples/slider.adm");
    let out = run_raw(
        &model,
        &[
            "--end",
            "0.1",
            "--probe",
            "bad=DX(21,11) + VX(21,11)",
            "--probe",
            "good=DX(21,11)",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("[W0312] Warning: `DX(21,11) + VX(21,11)` adds a length (meter) to a velocity (meter/second)")
            && stderr.contains("--probe bad:1:1"),
        "{stderr}"
    );
    assert!(!stderr.contains("--probe good"), "{stderr}");
    let csv = Csv::parse(&String::from_utf8(out.stdout).expect("UTF-8 CSV"));
    // At t = 0 the slider is at rest: the sum is the displacement.
    assert_eq!(csv.col("bad")[0], csv.col("good")[0]);
}
