//! `mbfx run ANALYSIS.acf` (issue 9 item 4): every command file of the shared corpus runs
//! or fails with a diagnostic naming what mbfx does not support (the outcome class of each
//! file is read off the file itself), a chrono command file gives the same CSV as the
//! dataset run with the command file's settings on the command line, SIMULATE commands
//! continue one another, and `--verbose` prints a step table.

use super::{mbfx, scratch_dir, Run};
use std::path::{Path, PathBuf};

/// What running a corpus command file does.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Outcome {
    /// Exit 0 with a CSV.
    Runs,
    /// E0610 whose message starts with this command (the first it refuses).
    Refused(&'static str),
    /// The command file is read, but its dataset cannot be run: exit 1 with this
    /// message (the first failure; the comments say what lies behind it).
    Fails(&'static str),
    /// E0501 naming the dataset the file asks for, which is not beside it.
    NoModel,
}

use Outcome::*;

/// The drill-string analyses' first failure: their first SIMULATE/STATIC, at a DIFF
/// integrating a velocity (ẋ = VZ) without STATIC_HOLD, which statics cannot fix.
const DRILL: &str = "[E0801] Error: DIFF/8002: statics cannot fix its state from ẋ = 0";

/// The FAST certification datasets' first failure.
const FAST: &str = "[E0801] Error: SFORCE/2010 'YawActuator_SF': it reads VARVAL(2011), and VARIABLE/2011 has no FUNCTION mbfx can evaluate";

/// The corpus' command files other than chrono's, with what each uses (from its text).
const COMMAND_FILES: &[(&str, Outcome)] = &[
    ("bthornton191__adams_docker/test/docker_test.acf", Runs),
    // SIMULATE/STATIC before the dynamics (a pendulum with a ball, hanging at rest).
    (
        "bthornton191__adams_rescale/models/rescale_analysis.acf",
        Runs,
    ),
    // The same commands, naming rescale_model, which is not beside it.
    (
        "bthornton191__adams_rescale/models/rescale_analysis_from_batch.acf",
        NoModel,
    ),
    // VARIABLE commands redefine the drill string's inputs (read and checked); its DIFFs
    // lag joint reactions (issue 40 §3), and the first SIMULATE/STATIC stops at DIFF/8002
    // (ẋ = VZ, no STATIC_HOLD: ẋ = 0 does not fix it); behind that its 47 GFORCEs and
    // VARIABLEs call USER subroutines (adrill_solver's StringForces, BitForces,
    // HoleCurveSub, Output4D) that exist only compiled.
    (
        "bthornton191__adamspy/test/existing_drillsim/test_analysis_1.acf",
        Fails(DRILL),
    ),
    // ACTIVATE/JOINT before SIMULATE/STATIC (a no-op: it is active) and DEACTIVATE after
    // it run; no stable equilibrium is found because the ten solid-to-solid CONTACTs that
    // hold the lobes take their geometry from a Parasolid file
    // (camelot_1_pull0_offset0.xmt_txt) that is not in the corpus: placeholder boxes
    // stand in for the lobes (issue 40 §1), and overlap at the start, so they are held
    // out until they separate: nothing holds a lobe on its revolute joint.
    (
        "bthornton191__adamspy/test/existing_model/camelot_1_pull0_offset0.acf",
        Fails("[E0806] Error: at time 0: the equilibrium found is unstable along PART/7"),
    ),
    (
        "bthornton191__adamspy/test/files/analysis_with_spikes/test_analysis_with_spikes.acf",
        Runs,
    ),
    (
        "bthornton191__adamspy/test/files/generic_model/generic_model.acf",
        Runs,
    ),
    // accg/kgrav=0, VARIABLE and MOTION redefinitions are read; DEACTIVATE/SENSOR and
    // DEACTIVATE/CONTACT switch elements mbfx does not model (and no dataset is beside
    // them).
    (
        "bthornton191__adamspy/test/files/real_analysis_with_spikes/FRS5_doe_8_LAUL_analysis.acf",
        Refused("DEACTIVATE/SENSOR"),
    ),
    (
        "bthornton191__adamspy/test/files/real_analysis_with_spikes_2/FRS5_doe_1_LAUL_analysis.acf",
        Refused("DEACTIVATE/SENSOR"),
    ),
    // The drill string again (as existing_drillsim's); this one redefines VARIABLE/1102,
    // which its dataset does not have.
    (
        "bthornton191__adamspy/test/files/test.acf",
        Fails("[E0311] Error: VARIABLE/1102 is not defined in the dataset"),
    ),
    (
        "bthornton191__adamspy/test/files/test_analysis_1.acf",
        Fails(DRILL),
    ),
    (
        "bthornton191__aview_hpc/test/_test_installed/test.acf",
        Runs,
    ),
    // file/model=C:\Users\…\test: a Windows path.
    ("bthornton191__aview_hpc/test/models/test.acf", NoModel),
    ("bthornton191__aview_hpc/test/models/test_2.acf", Runs),
    // DEACTIVATE/MOTION and DEACTIVATE/JOINT between the two SIMULATE commands (read);
    // the dataset's yaw actuator reads VARIABLE/2011, a USER subroutine of FAST's
    // compiled Adams interface.
    (
        "old-NWTC__FAST/CertTest/Old_Adams_files/Test02_ADAMS.acf",
        Fails(FAST),
    ),
    (
        "old-NWTC__FAST/CertTest/Old_Adams_files/Test06_ADAMS.acf",
        Fails(FAST),
    ),
    (
        "old-NWTC__FAST/CertTest/Old_Adams_files/Test09_ADAMS.acf",
        Fails(FAST),
    ),
    (
        "old-NWTC__FAST/CertTest/Old_Adams_files/Test11_ADAMS.acf",
        Fails(FAST),
    ),
    (
        "old-NWTC__FAST/CertTest/Old_Adams_files/Test14_ADAMS.acf",
        Fails(FAST),
    ),
    // MOTION/3150 made a VELOCITY motion and back to DISPLACEMENT, DEACTIVATEs,
    // SIMULATE/STATICS and LINEAR/EIGENSOL (all read); REQUEST/1 is given a USER
    // subroutine (and the dataset is Test14_ADAMS's, with FAST's).
    (
        "old-NWTC__FAST/CertTest/Old_Adams_files/Test14_ADAMS_LIN.acf",
        Refused("REQUEST: FUNCTION = USER(…) calls a user subroutine"),
    ),
];

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/adams")
}

/// Every `.acf` file below `dir`, relative to it, sorted.
fn acf_files(dir: &Path) -> Vec<String> {
    super::common::files_with_extension(dir, "acf")
        .iter()
        .map(|p| {
            let rel = p.strip_prefix(dir).expect("below the corpus");
            rel.to_string_lossy().replace('\\', "/")
        })
        .collect()
}

fn run_acf(path: &Path, extra: &[&str]) -> (Run, PathBuf) {
    let csv = scratch_dir("acf-csv").join("out.csv");
    let mut args = vec![
        "run".as_ref(),
        "--color".as_ref(),
        "never".as_ref(),
        path.as_os_str(),
        "--csv".as_ref(),
        csv.as_os_str(),
    ];
    args.extend(extra.iter().map(|s| -> &std::ffi::OsStr { s.as_ref() }));
    (mbfx(&args), csv)
}

#[test]
fn run_of_every_corpus_command_file() {
    let root = corpus();
    let files = acf_files(&root);
    assert_eq!(files.len(), 39, "{files:?}");
    let mut problems = Vec::new();
    for rel in &files {
        // Chrono keeps its command files in data/adams and the datasets they name in
        // data/testing/joints/adams_models: none is beside its command file.
        let expected = if rel.starts_with("projectchrono__chrono/") {
            NoModel
        } else {
            match COMMAND_FILES.iter().find(|(f, _)| f == rel) {
                Some((_, o)) => *o,
                None => {
                    problems.push(format!("{rel}: not in COMMAND_FILES"));
                    continue;
                }
            }
        };
        let (r, csv) = run_acf(&root.join(rel), &[]);
        let rows = std::fs::read_to_string(&csv).map_or(0, |t| t.lines().count());
        let ok = match expected {
            Runs => r.code == 0 && rows > 1,
            Refused(what) => {
                r.code == 1 && r.stderr.contains(&format!("[E0610] Error: {what}")) && rows == 0
            }
            // (No row: at most the header, written once the model is built.)
            Fails(what) => r.code == 1 && r.stderr.contains(what) && rows <= 1,
            NoModel => {
                let asked = Path::new(rel).with_extension("adm");
                let name = asked.file_name().map(|n| n.to_string_lossy().into_owned());
                r.code == 1
                    && r.stderr.contains("[E0501] Error: the model ")
                    // (aview_hpc and rescale_analysis_from_batch name another file.)
                    && name.is_some_and(|n| {
                        r.stderr.contains(&n)
                            || rel.contains("aview_hpc")
                            || r.stderr.contains("rescale_model.adm")
                    })
                    && rows == 0
            }
        };
        if !ok {
            problems.push(format!(
                "{rel}: expected {expected:?}, {rows} CSV lines\n{}",
                r.describe()
            ));
        }
        if r.stderr.contains("panicked") {
            problems.push(format!("{rel}: panicked\n{}", r.describe()));
        }
    }
    for (f, _) in COMMAND_FILES {
        if !files.iter().any(|p| p == f) {
            problems.push(format!("{f}: listed but not in the corpus"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The chrono revolute case's command file beside its dataset, in a scratch directory.
fn chrono_revolute() -> PathBuf {
    let chrono = corpus().join("projectchrono__chrono/data");
    let dir = scratch_dir("chrono-acf");
    for (from, name) in [
        ("adams", "test_Revolute_Case01.acf"),
        ("testing/joints/adams_models", "test_Revolute_Case01.adm"),
    ] {
        std::fs::copy(chrono.join(from).join(name), dir.join(name)).expect("copy");
    }
    dir
}

#[test]
fn a_chrono_command_file_gives_the_csv_of_its_dataset_run_with_its_settings() {
    let dir = chrono_revolute();
    let (acf, acf_csv) = run_acf(&dir.join("test_Revolute_Case01.acf"), &[]);
    assert_eq!(acf.code, 0, "{}", acf.describe());
    // The command file's settings, as it writes them: integrator/gstiff, error = 1.0e-4,
    // hmax=1e-5, simulate/transient, end=5.0, dtout=1.0E-002.
    let (adm, adm_csv) = run_acf(
        &dir.join("test_Revolute_Case01.adm"),
        &[
            "--end",
            "5.0",
            "--output-step",
            "1.0E-002",
            "--error",
            "1.0e-4",
            "--hmax",
            "1e-5",
        ],
    );
    assert_eq!(adm.code, 0, "{}", adm.describe());
    let (a, b) = (
        std::fs::read_to_string(acf_csv).expect("acf CSV"),
        std::fs::read_to_string(adm_csv).expect("adm CSV"),
    );
    assert_eq!(a.lines().count(), 502, "a header and 501 rows");
    assert!(a == b, "the CSVs differ");
    // What is not honoured is said, at its place in the command file.
    assert!(
        acf.stderr.contains("OUTPUT is not honoured") && !acf.stderr.contains("GSTIFF"),
        "{}",
        acf.describe()
    );
    assert!(
        acf.stdout.contains("gstiff") || acf.stderr.contains("gstiff"),
        "{}",
        acf.describe()
    );
    assert!(
        acf.stderr.contains("test_Revolute_Case01.acf:3:1"),
        "{}",
        acf.describe()
    );
}

/// The A01 pendulum (tests/models), its positions as probes.
fn pendulum_dir(acf: &str) -> PathBuf {
    let dir = scratch_dir("pendulum-acf");
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/models/a01_pendulum.adm");
    std::fs::copy(model, dir.join("a01_pendulum.adm")).expect("copy");
    std::fs::write(dir.join("run.acf"), acf).expect("write");
    dir
}

fn rows(csv: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(csv).expect("CSV");
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().expect("number")).collect())
        .collect()
}

const PROBES: [&str; 4] = ["--probe", "x=DX(201,101)", "--probe", "y=DY(201,101)"];

#[test]
fn simulate_commands_continue_in_time_without_a_repeated_row() {
    // Three stretches with two output steps; INTEGRATOR tightens ERROR for all.
    let dir = pendulum_dir(
        "a01_pendulum\nout\nINTEGRATOR/HHT, ERROR = 1e-9\nSIMULATE/DYNAMIC, END = 0.5, DTOUT = 0.05\nsim/dyn, duration = 0.3, steps = 3\n\
         simulate/transient, &\n  end = 1.0, dtout = 0.05\nSTOP\n",
    );
    let (r, csv) = run_acf(&dir.join("run.acf"), &PROBES);
    assert_eq!(r.code, 0, "{}", r.describe());
    let got = rows(&csv);
    let times: Vec<f64> = got.iter().map(|r| r[0]).collect();
    let mut want: Vec<f64> = (0..=10).map(|k| k as f64 * 0.05).collect();
    want.extend([0.6, 0.7, 0.8, 0.85, 0.9, 0.95, 1.0]);
    assert_eq!(times.len(), want.len(), "{times:?}");
    for (t, w) in times.iter().zip(&want) {
        assert!((t - w).abs() < 1e-12, "{times:?}");
    }
    // The first stretch is the dataset's run to 0.5 bit for bit; the rest stays on it
    // (the link keeps its length, and the run to 1.0 in one stretch agrees).
    let (one, one_csv) = run_acf(
        &dir.join("a01_pendulum.adm"),
        &[
            &PROBES[..],
            &[
                "--end",
                "1.0",
                "--output-step",
                "0.05",
                "--error",
                "1e-9",
                "--integrator",
                "hht",
            ],
        ]
        .concat(),
    );
    assert_eq!(one.code, 0, "{}", one.describe());
    let single = rows(&one_csv);
    for (g, s) in got.iter().zip(&single).take(10) {
        assert_eq!(g, s);
    }
    for g in &got {
        let radius = (g[1] * g[1] + g[2] * g[2]).sqrt();
        assert!((radius - 1.0).abs() < 1e-9, "{g:?}");
        if let Some(s) = single.iter().find(|s| (s[0] - g[0]).abs() < 1e-12) {
            assert!(
                (s[1] - g[1]).abs() < 1e-6 && (s[2] - g[2]).abs() < 1e-6,
                "{g:?} vs {s:?}"
            );
        }
    }
}

#[test]
fn verbose_prints_a_step_table_row_per_output_time() {
    let dir = pendulum_dir("a01_pendulum\nout\nSIMULATE/DYNAMIC, END = 0.2, DTOUT = 0.05\nSTOP\n");
    let (r, _) = run_acf(&dir.join("run.acf"), &["--verbose"]);
    assert_eq!(r.code, 0, "{}", r.describe());
    let table: Vec<&str> = r
        .stderr
        .lines()
        .skip_while(|l| !l.contains("Simulation"))
        .skip(2)
        .take_while(|l| !l.starts_with("gstiff:"))
        .collect();
    assert_eq!(table.len(), 5, "{}", r.stderr);
    assert!(
        table[0].trim_start().starts_with("0.000000E+00"),
        "{}",
        table[0]
    );
    assert!(
        table[4].trim_start().starts_with("2.000000E-01"),
        "{}",
        table[4]
    );
    // Columns: time, step, steps, Newton iterations, order (GSTIFF's, 1 to 6), CPU.
    let last: Vec<&str> = table[4].split_whitespace().collect();
    assert_eq!(last.len(), 6, "{}", table[4]);
    assert!(
        last[4].parse::<u32>().is_ok_and(|k| (1..=6).contains(&k)),
        "{}",
        table[4]
    );
}

#[test]
fn command_file_errors_point_into_the_file() {
    let dir = pendulum_dir("");
    for (acf, want) in [
        ("a01_pendulum\nout\nSTOP\n", "[E0604] Error: the command file has no SIMULATE or LINEAR command"),
        ("missing_model\nout\nSIMULATE/DYNAMIC, END = 1, DTOUT = 0.1\n", "run.acf:1:1"),
        ("a01_pendulum\nout\nSIMULATE/DYNAMIC, END = 1, DTOUT = 0.1 &\n, STEPS = 3\n", "run.acf:4:11"),
        ("a01_pendulum\nout\nINTEGRATOR/HHT, &\n  ALPHA = -0.9\nSIMULATE/DYNAMIC, END = 1, DTOUT = 0.1\n", "run.acf:4:11"),
    ] {
        std::fs::write(dir.join("run.acf"), acf).expect("write");
        let (r, csv) = run_acf(&dir.join("run.acf"), &[]);
        assert_eq!(r.code, 1, "{acf}\n{}", r.describe());
        assert!(r.stderr.contains(want), "{acf}: {want}\n{}", r.describe());
        assert!(!csv.exists(), "{acf}: nothing is written");
    }
    // --end stands in for the missing SIMULATE.
    std::fs::write(dir.join("run.acf"), "a01_pendulum\nout\nSTOP\n").expect("write");
    let (r, csv) = run_acf(&dir.join("run.acf"), &["--end", "0.1"]);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert_eq!(rows(&csv).len(), 101);
}
