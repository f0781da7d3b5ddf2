//! INTERPOLATE = ON (issue 25 §4): output times inside a step take the method's continuous
//! extension instead of cutting the step. Truth from outside the code: the A01 pendulum's
//! closed form (elliptic functions, `reference::a01_exact`) at a thousand rows for
//! every family, and the IMPACT block's reference rows (`examples/scenes/truth/`). The
//! interpolated rows must be as accurate as stepped rows at the same ERROR, many rows must
//! cost about the steps of few, and the statement and the command line both turn it on.

use crate::a01::max_position_error as a01_error;
use crate::adams::models_dir;
use crate::run::{named, probe_args, Csv};
use std::path::{Path, PathBuf};
use std::process::Command;

/// One run: its rows, accepted steps, and rows the summary says were interpolated.
struct Ran {
    csv: Csv,
    steps: usize,
    interpolated: usize,
    stderr: String,
}

/// `mbfx run MODEL ARGS… --csv -`, which must succeed.
fn ran(model: &Path, args: &[&str], probes: &[(&str, &str)]) -> Ran {
    let probes = probe_args(&named(probes));
    let out = Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .arg("run")
        .arg(model)
        .args(args)
        .args(&probes)
        .args(["--csv", "-"])
        .output()
        .expect("runs mbfx");
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{args:?}: {stderr}");
    // "<integrator>: N steps (M rejected), …" and "K rows interpolated inside steps …".
    let number_before = |what: &str| -> Option<usize> {
        let line = stderr.lines().find(|l| l.contains(what))?;
        let head = &line[..line.find(what)?];
        head.rsplit([' ', ':'])
            .find(|w| !w.is_empty())?
            .parse()
            .ok()
    };
    Ran {
        csv: Csv::parse(&String::from_utf8(out.stdout).expect("UTF-8 CSV")),
        steps: number_before(" steps (").expect("a summary"),
        interpolated: number_before(" rows interpolated").unwrap_or(0),
        stderr,
    }
}

fn a01() -> PathBuf {
    models_dir().join("a01_pendulum.adm")
}

fn impact_block() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/impact_block_k1e5.adm")
}

/// Each family with the flags and ERROR it runs A01 at.
const FAMILIES: [(&[&str], &str); 6] = [
    (&["--integrator", "dopri853"], "1e-8"),
    (&["--integrator", "dopri853", "--cartesian"], "1e-8"),
    (&["--integrator", "gstiff"], "1e-6"),
    (&["--integrator", "wstiff", "--formulation", "si2"], "1e-6"),
    (&["--integrator", "hht"], "1e-5"),
    (&["--integrator", "galpha"], "1e-5"),
];

#[test]
fn interpolated_rows_follow_the_pendulums_closed_form_for_every_family() {
    let probes = [("x", "DX(201,101)"), ("y", "DY(201,101)")];
    for (flags, error) in FAMILIES {
        let run = |dt: &str, interpolate: bool| {
            let mut args = vec!["--end", "2.5", "--output-step", dt, "--error", error];
            args.extend(flags);
            if interpolate {
                args.push("--interpolate");
            }
            ran(&a01(), &args, &probes)
        };
        // A thousand rows from the extensions, against twenty-five stepped ones.
        let dense = run("0.0025", true);
        let stepped = run("0.1", false);
        assert_eq!(dense.csv.time().len(), 1001, "{flags:?}");
        assert!(dense.interpolated >= 990, "{flags:?}: {}", dense.stderr);
        let (e_dense, e_stepped) = (a01_error(&dense.csv), a01_error(&stepped.csv));
        // As accurate as stepping (the same steps' error, plus the extension's, within
        // ERROR of the 1 m link), and so within the method's own accuracy.
        let e: f64 = error.parse().unwrap();
        assert!(
            e_dense <= 2.0 * e_stepped + 10.0 * e,
            "{flags:?}: interpolated {e_dense:.3e} against stepped {e_stepped:.3e}"
        );
    }
}

#[test]
fn twenty_thousand_interpolated_rows_take_the_steps_of_twenty() {
    for method in ["dopri853", "gstiff", "hht"] {
        let run = |dt: &str| {
            let args = [
                "--end",
                "2",
                "--output-step",
                dt,
                "--error",
                "1e-6",
                "--hmin",
                "1e-10",
                // Adams' default HINIT is the output step's twentieth: the same first
                // step for both, so that only the interpolated rows differ.
                "--hinit",
                "0.005",
                "--integrator",
                method,
                "--interpolate",
            ];
            ran(&impact_block(), &args, &[("y", "DY(201,101)")])
        };
        let (few, many) = (run("0.1"), run("1e-4"));
        assert_eq!(many.csv.time().len(), 20_001);
        // (A first step 1000 times shorter changes the step sequence by 5 %, either
        // way, with the contacts' switches located where it happens to lead.)
        assert!(
            many.steps == few.steps,
            "{method}: {} steps for 20 000 rows, {} for 20",
            many.steps,
            few.steps
        );
    }
}

/// The IMPACT block's reference rows (time, y) from its truth file.
fn impact_truth() -> Vec<(f64, f64)> {
    let path = impact_block().with_extension("toml");
    let t: toml::Table = std::fs::read_to_string(path).unwrap().parse().unwrap();
    t["at"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r["time"].as_float().unwrap(), r["y"].as_float().unwrap()))
        .collect()
}

/// Largest |y − truth| over the truth's times (each a row of the run).
fn impact_error(csv: &Csv) -> f64 {
    let (t, y) = (csv.time(), csv.col("y"));
    impact_truth()
        .iter()
        .map(|&(tt, yt)| {
            let k = (0..t.len())
                .min_by(|&a, &b| (t[a] - tt).abs().total_cmp(&(t[b] - tt).abs()))
                .unwrap();
            assert!((t[k] - tt).abs() < 1e-9, "no row at {tt}");
            (y[k] - yt).abs()
        })
        .fold(0.0, f64::max)
}

#[test]
fn interpolated_rows_through_contact_follow_the_impact_blocks_truth() {
    // The truth's times fall inside steps (only the end is landed on); the contact's
    // switches are still located, so no extension spans one.
    for (method, error) in [("dopri853", 1e-6), ("gstiff", 1e-6), ("hht", 1e-6)] {
        let run = |dt: &str, interpolate: bool| {
            let e = error.to_string();
            let mut args = vec![
                "--end",
                "2",
                "--output-step",
                dt,
                "--error",
                &e,
                "--hmin",
                "1e-10",
                "--integrator",
                method,
            ];
            if interpolate {
                args.push("--interpolate");
            }
            let r = ran(&impact_block(), &args, &[("y", "DY(201,101)")]);
            impact_error(&r.csv)
        };
        let (e_dense, e_stepped) = (run("0.001", true), run("0.25", false));
        // y spans 0.1 m: ERROR scaled by the model's length (1 m here).
        assert!(
            e_dense <= 2.0 * e_stepped + 10.0 * error,
            "{method}: interpolated {e_dense:.3e} against stepped {e_stepped:.3e}"
        );
    }
}

#[test]
fn interpolate_on_in_the_dataset_is_honoured_and_off_is_the_default() {
    let text = std::fs::read_to_string(a01()).unwrap();
    let dir = std::env::temp_dir().join(format!("mbfx-dense-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let probes = [("x", "DX(201,101)")];
    let args = ["--end", "1", "--output-step", "0.01"];
    for (statement, interpolated) in [
        ("INTEGRATOR/GSTIFF, ERROR = 1E-6, INTERPOLATE = ON\n", true),
        ("INTEGRATOR/HHT, ERROR = 1E-5, INTERPOLATE = OFF\n", false),
        ("INTEGRATOR/HHT, ERROR = 1E-5\n", false),
    ] {
        let path = dir.join("a01.adm");
        std::fs::write(
            &path,
            text.replacen("\nEND", &format!("\n{statement}END"), 1),
        )
        .unwrap();
        let r = ran(&path, &args, &probes);
        assert!(
            !r.stderr.contains("INTERPOLATE is not honoured"),
            "{}",
            r.stderr
        );
        assert_eq!(
            r.interpolated > 0,
            interpolated,
            "{statement}: {}",
            r.stderr
        );
        assert_eq!(r.csv.time().len(), 101);
        // A command file's INTEGRATOR command turns it on for the SIMULATE after it.
        let acf = dir.join("a01.acf");
        std::fs::write(
            &acf,
            "a01.adm\nout\nintegrator/interpolate = on\nsimulate/dynamic, end = 1, dtout = 0.01\nstop\n",
        )
        .unwrap();
        let r = ran(&acf, &[], &probes);
        assert!(r.interpolated > 0, "{}", r.stderr);
    }
    std::fs::remove_dir_all(&dir).ok();
}
