//! The command-line contract (DESIGN.md, "CLI contract"), tested on the built `mbfx`
//! binary: what `eval` prints and its exit codes, `check` on expression files and on every
//! `.adm` dataset of the shared corpus, help, and the REPL with no terminal.
//!
//! Every run has a time limit and must not panic (a Rust panic exits with code 101).

mod common;

/// `mbfx run ANALYSIS.acf`.
#[path = "cli/acf.rs"]
mod acf;

/// Accuracy warnings against a closed form, `--estimate-error` and `--strict`.
#[path = "cli/accuracy.rs"]
mod accuracy;

/// Physics the model leaves out: named by every run, `--strict` exits 3.
#[path = "cli/ignored.rs"]
mod ignored;

/// `mbfx fmu`: the FMU's parts and the export's diagnostics.
#[path = "cli/fmu.rs"]
mod fmu;

/// `mbfx run --kinematics`: internal steps, a lock-up named.
#[path = "cli/kinematics.rs"]
mod kinematics;

/// `mbfx run --linear` and LINEAR commands.
#[path = "cli/linear.rs"]
mod linear;

/// Command files that change the model between SIMULATE commands.
#[path = "cli/model_changes.rs"]
mod model_changes;

/// `mbfx run --set`.
#[path = "cli/set.rs"]
mod set;

/// State elements: faults at their statements, the corpus' drill strings.
#[path = "cli/states.rs"]
mod states;

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What one run of `mbfx` did.
struct Run {
    code: i32,
    stdout: String,
    stderr: String,
    took: Duration,
}

impl Run {
    fn describe(&self) -> String {
        format!(
            "exit {} after {:?}\n--- stdout\n{}--- stderr\n{}",
            self.code, self.took, self.stdout, self.stderr
        )
    }
}

/// A run may take this long before it is killed and the test fails.
const KILL_AFTER: Duration = Duration::from_secs(30);

/// Runs `mbfx` with `args`, feeding `stdin` (closed when `None`), with `HOME` pointing at
/// a scratch directory (the REPL keeps its history there).
fn mbfx_with_input<S: AsRef<std::ffi::OsStr>>(args: &[S], stdin: Option<&str>) -> Run {
    let home = scratch_dir("home");
    let mut child = Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .args(args)
        .env("HOME", &home)
        .env_remove("NO_COLOR")
        .stdin(if stdin.is_some() {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start mbfx");
    let started = Instant::now();
    if let (Some(text), Some(mut pipe)) = (stdin, child.stdin.take()) {
        pipe.write_all(text.as_bytes()).expect("write stdin");
    }
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_end(&mut bytes);
            }
            String::from_utf8_lossy(&bytes).into_owned()
        })
    };
    let out = drain(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let err = drain(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for mbfx") {
            break status;
        }
        if started.elapsed() > KILL_AFTER {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "mbfx {:?} did not finish within {KILL_AFTER:?}",
                args_text(args)
            );
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    Run {
        code: status.code().unwrap_or(-1),
        stdout: out.join().expect("stdout reader"),
        stderr: err.join().expect("stderr reader"),
        took: started.elapsed(),
    }
}

fn mbfx<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Run {
    mbfx_with_input(args, None)
}

fn args_text<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Vec<String> {
    args.iter()
        .map(|a| a.as_ref().to_string_lossy().into_owned())
        .collect()
}

/// A fresh directory under the target's scratch space, unique per call.
fn scratch_dir(what: &str) -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("cli-{}-{what}-{n}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("create a scratch directory");
    dir
}

/// Writes `bytes` to a new file named `name` in a fresh scratch directory.
fn scratch_file(name: &str, bytes: &[u8]) -> PathBuf {
    let path = scratch_dir("file").join(name);
    std::fs::write(&path, bytes).expect("write a scratch file");
    path
}

fn eval(args: &[&str]) -> Run {
    let mut all = vec!["eval", "--color", "never"];
    all.extend_from_slice(args);
    mbfx(&all)
}

fn check(path: &Path) -> Run {
    mbfx(&[
        "check".as_ref(),
        "--color".as_ref(),
        "never".as_ref(),
        path.as_os_str(),
    ])
}

// ---------------------------------------------------------------------------------------
// mbfx eval

#[test]
fn eval_prints_the_value_and_nothing_else() {
    let cases: &[(&[&str], &str)] = &[
        (&["1+2"], "3.0"),
        (&["-2**2"], "-4.0"),
        (&["2**3**2"], "512.0"),
        (&["[1,2,3]%[4,5,6]"], "[-3.0, 6.0, -3.0]"),
        (&["[1,2,3]"], "[1.0, 2.0, 3.0]"),
        (&["0.1+0.2"], "0.30000000000000004"),
        (&["-1"], "-1.0"),
        (&["--time", "0.5", "STEP(TIME,0,0,1,100)"], "50.0"),
        (&["--time", "-1", "TIME"], "-1.0"),
        (&["--time", "PI/2", "SIN(TIME)"], "1.0"),
        (&["--var", "x=2", "--var", "Y=3", "x*y"], "6.0"),
        (&["--var", "x=PI/2", "SIN(x)"], "1.0"),
        (&["--var", "x=-1", "X"], "-1.0"),
        (&["sin(1)"], "0.8414709848078965"),
    ];
    for (args, want) in cases {
        let r = eval(args);
        assert_eq!(
            (r.code, r.stdout.as_str(), r.stderr.as_str()),
            (0, format!("{want}\n").as_str(), ""),
            "eval {args:?}\n{}",
            r.describe()
        );
    }
}

/// `examples/slider.adm`: slider BCS at the origin; marker 21 at QP = (0.3, 0, 0) with
/// REULER = 90D, 90D, 0D (z along global x, spec §2.4), marker 11 on ground at the origin
/// with the same orientation; the dataset is already assembled, so the measures are
/// these numbers.
#[test]
fn eval_with_a_model_reads_its_measures_at_the_assembled_configuration() {
    let model = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/slider.adm");
    let cases: &[(&[&str], &str)] = &[
        (&["DX(21, 11)"], "0.3"),
        (&["DM(21, 11)*2"], "0.6"),
        (&["--dim", "3", "DZ(21, 11, 11)"], "0.3"),
        (&["--engine", "interp", "DXYZ(22)"], "[0.3, 0.0, 0.0]"),
        (&["--var", "k=10", "k*DX(22)"], "3.0"),
        (&["--time", "2", "TIME + VX(21, 11)"], "2.0"),
    ];
    for (args, want) in cases {
        let mut all = vec!["--model", model];
        all.extend_from_slice(args);
        let r = eval(&all);
        assert_eq!(
            (r.code, r.stdout.as_str()),
            (0, format!("{want}\n").as_str()),
            "eval {all:?}\n{}",
            r.describe()
        );
    }
    let r = eval(&["--model", model, "DX(99)"]);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(
        r.stderr.contains("E0311") && r.stderr.contains("<expr>:1:4"),
        "{}",
        r.describe()
    );
    let bad = scratch_file("no_ground.adm", b"no ground\nPART/2, MASS = 1\nEND\n");
    let r = eval(&["--model", bad.to_str().unwrap(), "1"]);
    assert_eq!((r.code, r.stdout.as_str()), (1, ""), "{}", r.describe());
    assert!(r.stderr.contains("E0606"), "{}", r.describe());
}

#[test]
fn eval_of_a_non_finite_value_prints_it_and_warns() {
    for (expr, value, code) in [
        ("1/0", "inf", "W0401"),
        ("LOG(0)", "-inf", "W0401"),
        ("SQRT(-1)", "NaN", "W0401"),
        ("1E999", "inf", "W0401"),
    ] {
        let r = eval(&[expr]);
        assert_eq!(r.code, 0, "{expr}\n{}", r.describe());
        assert_eq!(r.stdout, format!("{value}\n"), "{expr}\n{}", r.describe());
        assert!(
            r.stderr.contains(&format!("[{code}]")),
            "{expr}\n{}",
            r.describe()
        );
        assert!(r.stderr.contains("<expr>:1:"), "{expr}\n{}", r.describe());
    }
}

#[test]
fn eval_of_an_if_with_a_nan_test_is_an_error() {
    // Decision 2: a NaN test selects no branch, a run-time error naming the IF.
    let r = eval(&["2*IF(0/0:1,2,3)"]);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert_eq!(r.stdout, "", "{}", r.describe());
    assert!(r.stderr.contains("[E0402] Error"), "{}", r.describe());
    assert!(r.stderr.contains("<expr>:1:3"), "{}", r.describe());
    // Issue 11 §4: a NaN test that comes from an input is the same error, at the IF, with
    // the input marked (it used to be only a W0401 warning at the input).
    let r = eval(&["--var", "a=0/0", "IF(a:1,2,3)"]);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert_eq!(r.stdout, "", "{}", r.describe());
    assert!(r.stderr.contains("[E0402] Error"), "{}", r.describe());
    assert!(r.stderr.contains("<expr>:1:1"), "{}", r.describe());
    assert!(
        r.stderr.contains("the first non-finite value"),
        "{}",
        r.describe()
    );
    assert!(!r.stderr.contains("W0401"), "{}", r.describe());
}

#[test]
fn check_of_a_file_with_invalid_utf8_is_an_error_not_a_panic() {
    let dir = std::env::temp_dir().join(format!("mbfx-cli-utf8-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("bad.txt");
    std::fs::write(&path, b"1+1\n2+\xff\n").expect("write");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .args(["check", "--color", "never"])
        .arg(&path)
        .output()
        .expect("run mbfx");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("[E0502] Error"), "{stderr}");
    assert!(stderr.contains("bad.txt:2:3"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn eval_rejects_bad_vars_and_times() {
    let cases: &[(&[&str], &str, &str)] = &[
        (&["--var", "x", "1"], "E0503", "--var:1:1"),
        (&["--var", "1x=2", "1"], "E0503", "--var:1:1"),
        (&["--var", "sin=1", "1"], "E0503", "--var:1:1"),
        (&["--var", "PI=1", "1"], "E0503", "--var:1:1"),
        (&["--var", "x=1+", "x"], "E0202", "--var x:1:3"),
        (&["--var", "x=[1,2,3]", "x"], "E0305", "--var x:1:1"),
        (&["--time", "x", "1"], "E0302", "--time:1:1"),
        (&["--time", "", "1"], "E0204", "--time:1:1"),
        // Names are case-insensitive: `a` and `A` are one variable, given twice.
        (&["--var", "a=1", "--var", "A=2", "a"], "E0503", "--var:1:1"),
        // A value reads only the variables given before it.
        (
            &["--var", "a=b", "--var", "b=1", "a"],
            "E0302",
            "--var a:1:1",
        ),
    ];
    for (args, code, place) in cases {
        let r = eval(args);
        assert_eq!(r.code, 1, "{args:?}\n{}", r.describe());
        assert_eq!(r.stdout, "", "{args:?}\n{}", r.describe());
        assert!(
            r.stderr.contains(&format!("[{code}] Error")) && r.stderr.contains(place),
            "{args:?}: expected {code} at {place}\n{}",
            r.describe()
        );
    }
}

/// Issue 11 §4: a `--var` value may read earlier variables and TIME (the `--time` value).
#[test]
fn var_values_read_earlier_variables_and_time() {
    for (args, want) in [
        (&["--var", "b=1", "--var", "a=b+1", "a"][..], "2.0\n"),
        (&["--var", "a=TIME", "--time", "3", "a"], "3.0\n"),
        (
            &["--time", "0.5", "--var", "w=2*TIME", "--var", "v=w*w", "v"],
            "1.0\n",
        ),
    ] {
        let r = eval(args);
        assert_eq!(
            (r.code, r.stdout.as_str()),
            (0, want),
            "{args:?}\n{}",
            r.describe()
        );
    }
}

/// Issue 24: `--unit` gives a `--var` a dimension, and the expression is checked for
/// units of measure: a warning on stderr, the value unchanged on stdout.
#[test]
fn eval_with_units_warns_where_quantities_do_not_fit() {
    let r = eval(&[
        "--var", "x=1", "--var", "v=2", "--unit", "x=length", "--unit", "v=m/s", "x + v",
    ]);
    assert_eq!(
        (r.code, r.stdout.as_str()),
        (0, "3.0\n"),
        "{}",
        r.describe()
    );
    assert!(
        r.stderr
            .contains("[W0312] Warning: `x + v` adds a length to a velocity (length/time)")
            && r.stderr.contains("<expr>:1:1"),
        "{}",
        r.describe()
    );
    // A length plus a velocity times a time is a length: no warning.
    let r = eval(&[
        "--var",
        "x=1",
        "--var",
        "v=2",
        "--unit",
        "x=m",
        "--unit",
        "v=m/s",
        "x + v*TIME",
    ]);
    assert_eq!(
        (r.code, r.stdout.as_str(), r.stderr.as_str()),
        (0, "1.0\n", "")
    );
    // Without --unit nothing is checked.
    let r = eval(&["--var", "x=1", "SIN(x) + TIME"]);
    assert_eq!((r.code, r.stderr.as_str()), (0, ""), "{}", r.describe());
    // With a model, in the dataset's units (examples/slider.adm: meter and second).
    let r = eval(&["--model", "examples/slider.adm", "DX(21,11) + VX(21,11)"]);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert!(
        r.stderr
            .contains("adds a length (meter) to a velocity (meter/second)"),
        "{}",
        r.describe()
    );
    for (args, place) in [
        (
            &["--var", "x=1", "--unit", "x=furlong", "x"][..],
            "--unit:1:3",
        ),
        (&["--var", "x=1", "--unit", "y=m", "x"], "--unit:1:1"),
        (&["--var", "x=1", "--unit", "x", "x"], "--unit:1:1"),
        (
            &["--var", "x=1", "--unit", "x=m", "--unit", "X=s", "x"],
            "--unit:1:1",
        ),
    ] {
        let r = eval(args);
        assert_eq!(
            (r.code, r.stdout.as_str()),
            (1, ""),
            "{args:?}\n{}",
            r.describe()
        );
        assert!(
            r.stderr.contains("[E0503] Error") && r.stderr.contains(place),
            "{args:?}: expected E0503 at {place}\n{}",
            r.describe()
        );
    }
}

#[test]
fn eval_of_a_bad_expression_exits_1_with_the_code_and_place() {
    let cases = [
        ("1+", "E0202", "<expr>:1:3"),
        ("", "E0204", "<expr>:1:1"),
        ("@", "E0101", "<expr>:1:1"),
        ("1.5D3", "E0102", "<expr>:1:1"),
        ("SIN (1)", "E0103", "<expr>:1:1"),
        ("1 < 2", "E0104", "<expr>:1:3"),
        ("2* *3", "E0105", "<expr>:1:2"),
        ("1+*2", "E0201", "<expr>:1:3"),
        ("SIN(1))", "E0203", "<expr>:1:7"),
        ("2 3", "E0205", "<expr>:1:3"),
        ("12\n,34", "E0205", "<expr>:2:2"),
        ("STEP(TIME,0,0,\n, 1 2, 100)", "E0205", "<expr>:2:5"),
        ("STPE(1,0,0,1,1)", "E0301", "<expr>:1:1"),
        ("x", "E0302", "<expr>:1:1"),
        ("MAX(1,2,3)", "E0303", "<expr>:1:1"),
        ("DX(1.5)", "E0304", "<expr>:1:4"),
        ("SIN([1,2,3])", "E0305", "<expr>:1:5"),
        ("STEP(TIME,1,0,1,1)", "E0307", "<expr>:1:1"),
        ("DX(1,2)", "E0308", "<expr>:1:1"),
        ("USER(1)", "E0309", "<expr>:1:1"),
        ("PI()", "E0310", "<expr>:1:1"),
    ];
    for (expr, code, place) in cases {
        let r = eval(&[expr]);
        assert_eq!(r.code, 1, "{expr:?}\n{}", r.describe());
        assert_eq!(r.stdout, "", "{expr:?}\n{}", r.describe());
        assert!(
            r.stderr.contains(&format!("[{code}] Error")) && r.stderr.contains(place),
            "{expr:?}: expected {code} at {place}\n{}",
            r.describe()
        );
    }
    // A deep expression is an error, not a crash.
    let deep = format!("{}1{}", "(".repeat(10_000), ")".repeat(10_000));
    let r = eval(&[&deep]);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(r.stderr.contains("[E0206] Error"), "{}", r.describe());
}

#[test]
fn color_never_and_piped_auto_give_no_ansi_escapes() {
    for args in [
        &["eval", "--color", "never", "SIN (1) + @"][..],
        &["eval", "--color", "never", "1/0"],
        &["--color", "never", "eval", "1+"],
        // `auto` colours only a terminal; the test's stderr is a pipe.
        &["eval", "1+"],
    ] {
        let r = mbfx(args);
        assert!(!r.stderr.is_empty(), "{args:?}\n{}", r.describe());
        assert!(
            !r.stderr.contains('\x1b') && !r.stdout.contains('\x1b'),
            "{args:?}\n{}",
            r.describe()
        );
    }
    // And the check can see escapes when there are some.
    let r = mbfx(&["eval", "--color", "always", "1+"]);
    assert!(r.stderr.contains('\x1b'), "{}", r.describe());
}

// ---------------------------------------------------------------------------------------
// mbfx check FILE (expression files)

#[test]
fn check_of_a_good_expression_file() {
    let text = concat!(
        "! constants and steps\n",
        "1 + 2\n",
        "\n",
        "STEP(TIME, 0, 0,\n",
        ", 1, 100)\n",
        "   ! an indented comment\n",
        "\t\n",
        "2*PI\r\n",
        "[1,2,3]%[4,5,6]",
    );
    let path = scratch_file("good.txt", text.as_bytes());
    let r = check(&path);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert_eq!(
        r.stdout,
        format!("{}: 4 expressions; 0 errors, 0 warnings\n", path.display()),
        "{}",
        r.describe()
    );
    assert_eq!(r.stderr, "", "{}", r.describe());
}

#[test]
fn check_points_at_the_bad_line_of_the_file() {
    let text = "1 + 2\n! comment\n\nSTEP(TIME, 0, 0,\n, 1, 100)\n2 * SIN (1)\n3\n";
    let path = scratch_file("one bad line.txt", text.as_bytes());
    let r = check(&path);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert_eq!(
        r.stdout,
        format!("{}: 4 expressions; 1 errors, 0 warnings\n", path.display()),
        "{}",
        r.describe()
    );
    assert!(r.stderr.contains("[E0103] Error"), "{}", r.describe());
    assert!(
        r.stderr.contains(&format!("{}:6:5", path.display())),
        "{}",
        r.describe()
    );
    assert!(r.stderr.contains(" 6 | 2 * SIN (1)"), "{}", r.describe());

    // An error on a continuation line is reported on that line of the file.
    let text = "1\nSTEP(TIME, 0, 0,\n, 1 2, 100)\n";
    let path = scratch_file("continued.txt", text.as_bytes());
    let r = check(&path);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(r.stderr.contains("[E0205] Error"), "{}", r.describe());
    assert!(
        r.stderr.contains(&format!("{}:3:5", path.display())),
        "{}",
        r.describe()
    );

    // Several bad lines: every one is reported and counted.
    let text = "1+\n2 3\nFOO(1)\n4\n";
    let path = scratch_file("three bad lines.txt", text.as_bytes());
    let r = check(&path);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(
        r.stdout
            .ends_with(": 4 expressions; 3 errors, 0 warnings\n"),
        "{}",
        r.describe()
    );
    for (code, place) in [("E0202", ":1:3"), ("E0205", ":2:3"), ("E0301", ":3:1")] {
        let at = format!("{}{place}", path.display());
        assert!(
            r.stderr.contains(code) && r.stderr.contains(&at),
            "{code} at {at}\n{}",
            r.describe()
        );
    }
}

#[test]
fn check_of_an_empty_file_finds_no_expressions() {
    let path = scratch_file("empty.txt", b"");
    let r = check(&path);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert!(
        r.stdout
            .ends_with(": 0 expressions; 0 errors, 0 warnings\n"),
        "{}",
        r.describe()
    );
}

#[test]
fn check_of_a_file_with_nul_bytes_fails_cleanly() {
    let path = scratch_file("nul.txt", b"1+1\n2\x003\n\x00\n");
    let r = check(&path);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(r.stderr.contains("[E0101] Error"), "{}", r.describe());
    assert!(
        r.stderr.contains(&format!("{}:2:2", path.display())),
        "{}",
        r.describe()
    );
}

#[test]
fn check_of_a_missing_file_or_a_directory_is_e0501() {
    let dir = scratch_dir("missing");
    for path in [
        dir.join("no such file.txt"),
        dir.join("no such model.adm"),
        dir.clone(),
    ] {
        let r = check(&path);
        assert_eq!(r.code, 1, "{}\n{}", path.display(), r.describe());
        assert_eq!(r.stdout, "", "{}", r.describe());
        assert!(r.stderr.contains("[E0501] Error"), "{}", r.describe());
    }
    let adm_dir = dir.join("a directory.adm");
    std::fs::create_dir_all(&adm_dir).expect("create a directory");
    let r = check(&adm_dir);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(r.stderr.contains("[E0501] Error"), "{}", r.describe());
}

#[test]
fn check_of_a_dataset_with_latin1_bytes_warns_and_reads_it() {
    let path = scratch_file(
        "latin1.adm",
        b"title\nPART/1, GROUND\n! caf\xe9\nVARIABLE/1, FUNCTION = 1 + 2\nEND\n",
    );
    let r = check(&path);
    assert_eq!(r.code, 0, "{}", r.describe());
    // A warning has a W code (issue 11 §4: it was `[E0502] Warning`).
    assert!(r.stderr.contains("[W0504] Warning"), "{}", r.describe());
    assert!(
        r.stderr.contains(&format!("{}:3:6", path.display())),
        "{}",
        r.describe()
    );
    assert!(
        r.stdout.ends_with("0 errors, 1 warnings\n"),
        "{}",
        r.describe()
    );
}

// ---------------------------------------------------------------------------------------
// mbfx check on the shared .adm corpus

/// Datasets that must fail `mbfx check`, with the reason. All are samples of MBDyn's a2m
/// translator that test its error handling; every other `.adm` of the corpus must pass.
/// (`src/model/model_corpus_tests.rs` pins the exact error codes of each.)
const INVALID_DATASETS: &[(&str, &str)] = &[
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/bipendolo.adm",
        "an edited export that lost its title line, so line 2 continues no statement",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/bipendololeo.adm",
        "a GFORCE without FY and FZ, and JFLOAT markers that are not FLOATING",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/mark.adm",
        "four MARKER lines only: no GROUND, and the PARTs they name do not exist",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/monster.adm",
        "unknown function COSIN and undefined names (X)",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/pm02.adm",
        "statements continued without a continuation comma, and `^` as a power",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/pm03.adm",
        "expressions measure markers the dataset does not define",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/prova.adm",
        "garbage arguments (`%&(MASS=2,)`) and statements continued without a comma",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/prova_beam00.adm",
        "markers without PART and no GROUND",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/prova_beam01.adm",
        "a BEAM alone: no GROUND part",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/prova_marker01.adm",
        "statements continued without a continuation comma",
    ),
];

#[test]
fn check_of_every_corpus_dataset() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/adams");
    let files = common::adm_files(&root);
    assert!(files.len() >= 70, "only {} .adm files", files.len());
    assert!(
        files.iter().any(|f| f.to_string_lossy().contains(' ')),
        "the corpus should include paths with spaces"
    );
    let mut problems = Vec::new();
    let mut failed_as_listed = 0;
    for file in &files {
        let rel = file
            .strip_prefix(&root)
            .expect("under the corpus root")
            .to_string_lossy()
            .replace('\\', "/");
        let r = check(file);
        let listed = INVALID_DATASETS.iter().find(|(f, _)| *f == rel);
        let expected = if listed.is_some() { 1 } else { 0 };
        if r.code != expected {
            problems.push(format!("{rel}: expected exit {expected}\n{}", r.describe()));
        } else if listed.is_some() {
            failed_as_listed += 1;
        }
        if r.took > Duration::from_secs(5) {
            problems.push(format!("{rel}: took {:?}", r.took));
        }
        let summary = format!("{}: ", file.display());
        // The model report comes first; the summary line is the last line.
        let last = r.stdout.lines().last().unwrap_or("");
        if !(last.starts_with(&summary) && last.contains(" errors, ")) {
            problems.push(format!("{rel}: no summary line\n{}", r.describe()));
        }
        if r.stderr.contains("panicked") {
            problems.push(format!("{rel}: panicked\n{}", r.describe()));
        }
    }
    for (f, _) in INVALID_DATASETS {
        if !files.iter().any(|p| p.ends_with(f)) {
            problems.push(format!("{f}: listed as invalid but not in the corpus"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert_eq!(failed_as_listed, INVALID_DATASETS.len());
}

#[test]
fn check_of_a_model_prints_its_summary() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/slider.adm");
    let r = check(&path);
    assert_eq!(r.code, 0, "{}", r.describe());
    // Counts from the file itself: 2 PART, 3 MARKER, 1 JOINT, 2 SFORCE, 1 VARIABLE, 1 REQUEST.
    for want in [
        "elements: PART 2, MARKER 3, JOINT 1, SFORCE 2, VARIABLE 1, REQUEST 1",
        "units: force NEWTON, mass KILOGRAM, length METER, time SECOND; UCF = 1",
        "gravity: (0, 0, 0)",
    ] {
        assert!(r.stdout.contains(want), "{want}\n{}", r.describe());
    }
    assert!(
        r.stdout.ends_with("0 errors, 0 warnings\n"),
        "{}",
        r.describe()
    );
}

#[test]
fn a_build_failure_points_at_the_element_not_the_title() {
    // An SFORCE reading five moving parts: the force Jacobian holds four, so the run
    // stops before its first step, at the SFORCE's statement (line 14).
    let mut text = String::from("many parts\nPART/1, GROUND\nMARKER/10, PART = 1\n");
    for p in 2..=6 {
        text += &format!(
            "PART/{p}, MASS = 1, CM = {p}0, IP = 1, 1, 1, QG = {}, 0, 0\nMARKER/{p}0, PART = {p}\n",
            p - 2
        );
    }
    text += "SFORCE/1, TRANSLATION, I = 20, J = 30, FUNCTION = DX(40) + DX(50) + DX(60)\nEND\n";
    let path = scratch_file("five_parts.adm", text.as_bytes());
    let r = mbfx(&["run", path.to_str().unwrap(), "--end", "1", "--csv", "-"]);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(
        r.stderr
            .contains("SFORCE/1: it reads more than four moving parts"),
        "{}",
        r.describe()
    );
    assert!(
        r.stderr.contains(&format!("{}:14:1", path.display())),
        "{}",
        r.describe()
    );
}

#[test]
fn check_of_a_bad_model_points_at_the_reference() {
    let path = scratch_file(
        "bad_model.adm",
        b"title\nUNITS/LENGTH = MILLIMETER\nPART/1, GROUND\nMARKER/11, PART = 1\n\
          ! adams_view_name='Joint_4'\nJOINT/4, REVOLUTE, I = 11, J = 99\n\
          GRAPHICS/1, POINT, RM = 11\nEND\n",
    );
    let r = check(&path);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(
        r.stderr.contains("[E0311] Error: MARKER/99"),
        "{}",
        r.describe()
    );
    assert!(r.stderr.contains("JOINT/4 (Joint_4)"), "{}", r.describe());
    assert!(
        r.stderr.contains(&format!("{}:6:32", path.display())),
        "{}",
        r.describe()
    );
    assert!(
        r.stderr.contains("[W0602] Warning: GRAPHICS"),
        "{}",
        r.describe()
    );
    assert!(r.stdout.contains("UCF = 1000"), "{}", r.describe());
    assert!(
        r.stdout.ends_with("1 errors, 1 warnings\n"),
        "{}",
        r.describe()
    );
}

// ---------------------------------------------------------------------------------------
// Help, bad subcommands, the REPL without a terminal

#[test]
fn help_and_version_exit_0() {
    for args in [
        &["--help"][..],
        &["eval", "--help"],
        &["check", "--help"],
        &["help", "eval"],
        &["--version"],
    ] {
        let r = mbfx(args);
        assert_eq!(r.code, 0, "{args:?}\n{}", r.describe());
        assert!(!r.stdout.is_empty(), "{args:?}\n{}", r.describe());
    }
    let r = mbfx(&["eval", "--help"]);
    assert!(r.stdout.contains("--var"), "{}", r.describe());
}

#[test]
fn bad_command_lines_exit_nonzero_without_panicking() {
    for args in [
        &["frobnicate"][..],
        &[],
        &["eval"],
        &["check"],
        &["eval", "--time"],
        &["eval", "--color", "purple", "1"],
        &["eval", "--engine", "gpu", "1"],
        &["eval", "1", "2"],
    ] {
        let r = mbfx(args);
        assert!(r.code != 0 && r.code != 101, "{args:?}\n{}", r.describe());
        assert!(!r.stderr.contains("panicked"), "{args:?}\n{}", r.describe());
        assert!(!r.stderr.is_empty(), "{args:?}\n{}", r.describe());
    }
}

#[test]
fn repl_without_a_terminal_ends_at_end_of_input() {
    for input in [None, Some(""), Some("1+2\n"), Some("1+2\n:quit\n")] {
        let r = mbfx_with_input(&["repl"], input);
        assert_eq!(r.code, 0, "{input:?}\n{}", r.describe());
        assert!(
            r.took < Duration::from_secs(10),
            "{input:?}\n{}",
            r.describe()
        );
        assert!(
            !r.stderr.contains("panicked"),
            "{input:?}\n{}",
            r.describe()
        );
    }
}

// ---------------------------------------------------------------------------------------
// Output that cannot be written (issue 11 §1)

/// Where one standard stream of a run goes.
enum Sink {
    /// A pipe whose reading end is already closed: every write fails with EPIPE.
    ClosedPipe,
    /// `/dev/full`: every write fails with ENOSPC.
    Full,
    /// Read by the test.
    Captured,
}

impl Sink {
    fn stdio(&self) -> Stdio {
        match self {
            Sink::ClosedPipe => {
                let (reader, writer) = std::io::pipe().expect("a pipe");
                drop(reader);
                Stdio::from(writer)
            }
            Sink::Full => Stdio::from(
                std::fs::OpenOptions::new()
                    .write(true)
                    .open("/dev/full")
                    .expect("open /dev/full"),
            ),
            Sink::Captured => Stdio::piped(),
        }
    }
}

/// Runs `mbfx` with stdout and stderr sent to the given sinks; returns the exit code and
/// what the captured stream (if any) received.
fn mbfx_into(args: &[&str], stdout: Sink, stderr: Sink) -> (i32, String) {
    let child = Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .args(args)
        .env("HOME", scratch_dir("home"))
        .stdin(Stdio::null())
        .stdout(stdout.stdio())
        .stderr(stderr.stdio())
        .spawn()
        .expect("start mbfx");
    let out = child.wait_with_output().expect("wait for mbfx");
    let captured = [out.stdout, out.stderr].concat();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&captured).into_owned(),
    )
}

#[test]
fn a_closed_pipe_ends_every_command_quietly() {
    let many = scratch_file("many.txt", "SIN (1)\n".repeat(5_000).as_bytes());
    let many = many.to_str().expect("a UTF-8 path");
    let slider = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/slider.adm");
    let expressions = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/expressions.txt");
    // stdout closed: values, reports and summaries are not wanted any more.
    for args in [
        &["eval", "SIN(1)"][..],
        &["eval", "[1, 2, 3]"],
        &["check", slider],
        &["check", expressions],
        &["check", many],
    ] {
        let (code, stderr) = mbfx_into(args, Sink::ClosedPipe, Sink::Captured);
        assert_eq!(code, 0, "{args:?}\n{stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}\n{stderr}");
        assert!(!stderr.contains("Broken pipe"), "{args:?}\n{stderr}");
    }
    // stderr closed: the diagnostics (here 5 000 frames, far more than a pipe buffers).
    for args in [&["eval", "SIN (1)"][..], &["check", many]] {
        let (code, stdout) = mbfx_into(args, Sink::Captured, Sink::ClosedPipe);
        assert_eq!(code, 0, "{args:?}\n{stdout}");
        assert!(stdout.is_empty(), "{args:?}\n{stdout}");
    }
    // The REPL's banner and answers.
    let mut child = Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .arg("repl")
        .env("HOME", scratch_dir("home"))
        .stdin(Stdio::piped())
        .stdout(Sink::ClosedPipe.stdio())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start mbfx repl");
    if let Some(mut input) = child.stdin.take() {
        let _ = input.write_all(b"1+1\n2+2\n");
    }
    let out = child.wait_with_output().expect("wait for mbfx repl");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn a_full_disk_is_one_diagnostic_and_exit_1() {
    if !Path::new("/dev/full").exists() {
        return;
    }
    let slider = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/slider.adm");
    let expressions = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/expressions.txt");
    for args in [
        &["eval", "SIN(1)"][..],
        &["check", slider],
        &["check", expressions],
    ] {
        let (code, stderr) = mbfx_into(args, Sink::Full, Sink::Captured);
        assert_eq!(code, 1, "{args:?}\n{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}\n{stderr}");
        assert!(
            stderr.starts_with("mbfx: cannot write to stdout: No space left on device"),
            "{args:?}\n{stderr}"
        );
    }
    // Diagnostics to a full stderr: nothing can be said, but the exit code says it.
    let (code, stdout) = mbfx_into(&["eval", "SIN (1)"], Sink::Captured, Sink::Full);
    assert_eq!(code, 1, "{stdout}");
}

#[test]
fn the_cli_prints_only_through_its_output() {
    // `print!` and friends panic when a write fails; the CLI writes through
    // `cli::output::Output` instead. Any new use in the binary's code fails here.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("src/main.rs")];
    let mut dirs = vec![root.join("src/cli")];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).expect("list src/cli") {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    assert!(files.len() > 3, "{files:?}");
    for file in files {
        let text = std::fs::read_to_string(&file).expect("read a source file");
        for mac in ["println!(", "print!(", "eprintln!(", "eprint!(", "dbg!("] {
            assert!(
                !text.contains(mac),
                "{} uses `{mac}`: write through cli::output::Output",
                file.display()
            );
        }
    }
}

#[test]
fn many_diagnostics_cost_time_linear_in_their_number() {
    // Each frame used to index the whole file again: 10 000 blank-before-parenthesis
    // errors took 1.1 s and 40 000 took 24 s. Linear, the four-times file takes about four
    // times as long (0.08 s and 0.25 s here); the bound leaves room for a busy machine.
    let time = |n: usize| {
        let file = scratch_file("blanks.txt", "SIN (1)\n".repeat(n).as_bytes());
        let r = check(&file);
        assert_eq!(r.code, 1, "{}", r.stdout);
        assert!(
            r.stdout.ends_with(&format!("{n} errors, 0 warnings\n")),
            "{}",
            r.stdout
        );
        r.took
    };
    let small = time(10_000);
    let big = time(40_000);
    assert!(
        big < (small * 8).max(Duration::from_secs(3)),
        "10 000 errors in {small:?}, 40 000 in {big:?}"
    );
}

#[test]
fn repl_answers_an_input_still_open_at_end_of_input() {
    // Issue 11 §4: `SIN(1` and then the end of input was dropped silently, while a
    // trailing `1+` was reported.
    for input in ["SIN(1", "SIN(1\n", "1+1\nSIN(1,\n"] {
        let r = mbfx_with_input(&["repl"], Some(input));
        assert_eq!(r.code, 0, "{input:?}\n{}", r.describe());
        assert!(
            r.stdout.contains("[E0202] Error: missing `)`"),
            "{input:?}\n{}",
            r.describe()
        );
    }
}

#[test]
fn repl_reports_a_line_that_is_not_utf8_and_goes_on() {
    // Issue 11 §4: the session used to end silently at such a line.
    let mut child = Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .arg("repl")
        .env("HOME", scratch_dir("home"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start mbfx repl");
    if let Some(mut input) = child.stdin.take() {
        input
            .write_all(b"1+1\n\xff\xfe 2\n2+2\n")
            .expect("write stdin");
    }
    let out = child.wait_with_output().expect("wait for mbfx repl");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    let answers: Vec<&str> = stdout.lines().skip(1).collect();
    assert_eq!(answers.len(), 3, "{stdout}");
    assert!(answers[0].ends_with("2.0"), "{stdout}");
    assert!(answers[1].contains("E0502"), "{stdout}");
    assert!(answers[2].ends_with("4.0"), "{stdout}");
}

#[test]
fn control_characters_of_the_input_never_reach_the_terminal() {
    // Issue 11 §4: `mbfx eval $'\x1b[31m1'` echoed the escape sequence into the terminal.
    for expr in ["\u{1b}[31m1", "1 + \u{7}2", "SIN(\u{200b}1)"] {
        let r = eval(&[expr]);
        assert_eq!(r.code, 1, "{expr:?}\n{}", r.describe());
        assert!(
            !r.stderr.contains(['\u{1b}', '\u{7}', '\u{200b}']),
            "{expr:?}\n{:?}",
            r.stderr
        );
    }
}

#[test]
fn check_says_when_an_expression_file_looks_like_a_dataset_and_refuses_dim() {
    // Issue 11 §4: `slider.dataset` was read as 61 bad expressions with no hint, and
    // `--dim` on an expression file was ignored.
    let text = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/slider.adm"))
        .expect("read the example");
    let path = scratch_file("slider.dataset", &text);
    let r = check(&path);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(
        r.stderr
            .contains("hint: this looks like an .adm dataset (line 9 starts with `PART/1`)"),
        "{}",
        r.describe()
    );
    let expressions = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/expressions.txt");
    let r = mbfx(&["check", "--color", "never", "--dim", "2", expressions]);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(
        r.stderr
            .contains("[E0503] Error: --dim applies to .adm datasets"),
        "{}",
        r.describe()
    );
    // A good expression file gives no hint.
    let r = check(Path::new(expressions));
    assert!(!r.stderr.contains("hint:"), "{}", r.describe());
}

#[test]
fn comment_lines_may_stand_between_continuation_lines() {
    // Issue 11 §4: `1`, a `!` comment line, then `, +1` was refused with a help asking for
    // the comma in column one that the input had. A dataset's reader skips comment lines
    // between a statement's lines; expressions now do too, in files and datasets alike.
    let file = scratch_file("continued.txt", b"1\n! a note\n, +1\n");
    let r = check(&file);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert!(
        r.stdout.ends_with("1 expressions; 0 errors, 0 warnings\n"),
        "{}",
        r.describe()
    );
    let dataset = scratch_file(
        "continued.adm",
        b"comment lines inside a FUNCTION\nPART/1, GROUND\nMARKER/10, PART = 1\n\
          PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
          JOINT/1, TRANSLATIONAL, I = 20, J = 10\n\
          SFORCE/1, TRANSLATION, I = 20, J = 10, FUNCTION = 1\n! a note\n\n, + 1\nEND\n",
    );
    let r = check(&dataset);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert!(!r.stderr.contains("E0101"), "{}", r.describe());
}

#[test]
fn dim_takes_2_or_3_on_every_command() {
    // `--dim` is one clap value enum for check, run and eval: the same spellings, the same
    // refusal of anything else, listed in each command's help.
    let slider = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/slider.adm");
    for args in [
        &["check", "--dim", "4", slider][..],
        &["run", slider, "--end", "1", "--dim", "two"],
        &["eval", "--model", slider, "--dim", "3D", "1"],
    ] {
        let r = mbfx(args);
        assert_eq!(r.code, 1, "{args:?}\n{}", r.describe());
        assert!(
            r.stderr.contains("[possible values: 2, 3]"),
            "{args:?}\n{}",
            r.describe()
        );
    }
    for command in ["check", "run", "eval"] {
        let r = mbfx(&[command, "--help"]);
        assert!(
            r.stdout.contains("--dim <2|3>"),
            "{command}\n{}",
            r.describe()
        );
    }
    let r = eval(&["--model", slider, "--dim", "3", "DX(21, 11)"]);
    assert_eq!(
        (r.code, r.stdout.as_str()),
        (0, "0.3\n"),
        "{}",
        r.describe()
    );
}

/// `--strict` turns an accuracy warning into exit code 3 (for scripts and CI) and leaves
/// a quiet run at 0: the slider at its default ERROR warns that its local errors add up
/// past 10·ERROR; the fully driven slider-crank has nothing to integrate and no warning.
#[test]
fn run_strict_exits_3_on_an_accuracy_warning_only() {
    let slider = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/slider.adm");
    let crank = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/scenes/slider_crank_driven.adm"
    );
    let base = ["--end", "2", "--output-step", "0.1", "--csv", "-"];
    let warned = mbfx(&[&["run", slider][..], &base].concat());
    assert_eq!(warned.code, 0, "{}", warned.describe());
    assert!(warned.stderr.contains("add up to"), "{}", warned.describe());
    let strict = mbfx(&[&["run", slider, "--strict"][..], &base].concat());
    assert_eq!(strict.code, 3, "{}", strict.describe());
    assert_eq!(strict.stdout, warned.stdout, "the rows are the same");
    let quiet = mbfx(&[&["run", crank, "--strict"][..], &base].concat());
    assert_eq!(quiet.code, 0, "{}", quiet.describe());
    assert!(!quiet.stderr.contains("warning:"), "{}", quiet.describe());
}

/// A pendulum with `GCON/1, FUNCTION = TIME`: the GCON reads no coordinate, so its
/// position Jacobian is zero and it holds at t = 0 (TIME = 0), but its velocity equation
/// asks 0·v + d(TIME)/dt = 1 = 0. No run can honour it: `check` names it as a conflict
/// at velocities (E0702, exit 1), not as a redundant constraint to remove.
#[test]
fn check_names_a_constraint_that_holds_now_but_not_over_time() {
    let pendulum = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/scenes/a01_pendulum.adm"
    ))
    .expect("the A01 scene");
    let text = pendulum.replace("ACCGRAV", "GCON/1, I = 201, FUNCTION = TIME\nACCGRAV");
    assert_ne!(text, pendulum);
    let r = check(&scratch_file("gcon_time.adm", text.as_bytes()));
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(
        r.stderr
            .contains("[E0702] Error: conflicting, not redundant: Gcon of GCON/1")
            && r.stderr
                .contains("its velocity equation is violated by 1e0"),
        "{}",
        r.describe()
    );
    assert!(!r.stdout.contains("remove it"), "{}", r.describe());
}
