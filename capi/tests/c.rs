//! C programs against the library cargo built for this test run: `capi/tests/c/api_test.c`
//! (every function and error path of `include/mbfx.h`) and `capi/tests/c/simulation_test.c`
//! (a dataset stepped, against `mbfx run`'s rows), linked with the static library,
//! and `examples/embed.c` (docs/c-api.md's example), built with the exact command its header
//! comment gives (the shared library). Each is compiled with the system C compiler (`$CC`,
//! else `cc`) as strict C99 with warnings as errors, run, and judged by its exit code.
//!
//! Cargo builds every crate type of the library (`libmbfx_c.a`, `libmbfx_c.so`, the rlib)
//! in one rustc run before it builds the integration tests, into `target/<profile>/deps/`,
//! the directory of this test's own executable (`target/<profile>/deps/c-<hash>`).

use std::path::{Path, PathBuf};
use std::process::Command;

/// What a Rust static library needs from the system on Linux (`cargo rustc -p mbfx-capi
/// --crate-type staticlib -- --print native-static-libs`).
const NATIVE_LIBS: &[&str] = &[
    "-lgcc_s",
    "-lutil",
    "-lrt",
    "-lpthread",
    "-lm",
    "-ldl",
    "-lc",
];

/// The directories cargo put the library in for this run: `target/<profile>/deps` (where
/// `cargo test` leaves it, as a dependency of the tests) and `target/<profile>` (where
/// `cargo build` copies it).
fn library_dirs() -> Vec<PathBuf> {
    let exe = std::env::current_exe().expect("the test knows its own path");
    let deps = exe
        .parent()
        .expect("the test runs from target/<profile>/deps");
    let mut dirs = vec![deps.to_path_buf()];
    dirs.extend(deps.parent().map(Path::to_path_buf));
    dirs
}

/// The repository root (`include/`, `examples/`).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("capi/ is in the repository")
        .to_path_buf()
}

/// The library file `name` cargo built for this run.
fn library(name: &str) -> PathBuf {
    let dirs = library_dirs();
    dirs.iter()
        .map(|d| d.join(name))
        .find(|p| p.is_file())
        .unwrap_or_else(|| {
            panic!(
                "{name} is in none of {dirs:?}: cargo builds it with the tests (crate-type \
                 in capi/Cargo.toml); `cargo build -p mbfx-capi` in this profile builds it too"
            )
        })
}

/// The C compiler and the flags both programs are built with.
fn cc() -> Command {
    let mut cmd = Command::new(std::env::var_os("CC").unwrap_or_else(|| "cc".into()));
    cmd.args([
        "-std=c99",
        "-O1",
        "-Wall",
        "-Wextra",
        "-pedantic",
        "-Werror",
    ]);
    cmd
}

/// Runs `cmd`, failing the test with its output when it fails; returns its stdout.
fn run(mut cmd: Command, what: &str) -> String {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot start {what} ({cmd:?}): {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "{what} failed ({}):\n{cmd:?}\n--- stdout\n{stdout}\n--- stderr\n{stderr}",
        out.status
    );
    stdout
}

/// A fresh path for a built program.
fn program(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("capi-c");
    std::fs::create_dir_all(&dir).expect("the target's tmp dir is writable");
    dir.join(name)
}

#[test]
fn the_c_api_test_passes() {
    let exe = program("api_test");
    let mut build = cc();
    build
        .arg(format!(
            "-DMBFX_EXPECTED_VERSION=\"{}\"",
            env!("CARGO_PKG_VERSION")
        ))
        .arg("-I")
        .arg(root().join("include"))
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/c/api_test.c"))
        .arg(library("libmbfx_c.a"))
        .args(NATIVE_LIBS)
        .arg("-o")
        .arg(&exe);
    run(build, "compiling api_test.c");
    let stdout = run(Command::new(&exe), "api_test");
    let last = stdout.lines().last().unwrap_or("");
    let counts: Vec<usize> = last
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|n| n.parse().ok())
        .collect();
    assert!(
        last.ends_with(" failed") && counts.len() == 2 && counts[0] > 200 && counts[1] == 0,
        "api_test: {last}"
    );
}

#[test]
fn the_embedding_example_builds_and_matches_the_closed_form() {
    let source = root().join("examples/embed.c");
    let text = std::fs::read_to_string(&source).expect("examples/embed.c");
    // The build command the example's comment gives, with its paths made absolute.
    assert!(
        text.contains("cc -std=c99 -O2 -Iinclude examples/embed.c -Ltarget/release -lmbfx_c"),
        "examples/embed.c documents how it is built"
    );
    let lib_dir = library("libmbfx_c.so")
        .parent()
        .expect("a directory")
        .to_path_buf();
    let exe = program("embed");
    let mut build = cc();
    build
        .arg("-I")
        .arg(root().join("include"))
        .arg(&source)
        .arg("-L")
        .arg(&lib_dir)
        .arg("-lmbfx_c")
        .arg(format!("-Wl,-rpath,{}", lib_dir.display()))
        .arg("-lm")
        .arg("-o")
        .arg(&exe);
    run(build, "compiling examples/embed.c");
    let stdout = run(Command::new(&exe), "examples/embed.c");
    assert!(
        stdout.contains("undamped") && stdout.contains("damped"),
        "{stdout}"
    );
}

#[test]
fn the_c_simulation_test_steps_as_run_runs() {
    use mbfx::session::request::{run as run_dataset, RunRequest};
    use mbfx::session::run::Method;
    // The rows `mbfx run` gives, which the C program must step to bit for bit.
    // A pendulum with a PINPUT torque TORQUE and a POUTPUT angle ANGLE.
    let dataset = root().join("examples/pendulum_pinput.adm");
    let mut request = RunRequest::file(&dataset);
    (request.end, request.output_step) = (Some(2.0), Some(0.02));
    request.method = Some(Method::Gstiff);
    request.probes = vec![
        ("angle".into(), "AZ(21, 10)".into()),
        ("wz".into(), "WZ(21, 10)".into()),
    ];
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut sink = |row: &[f64]| -> std::io::Result<()> {
        rows.push(row.to_vec());
        Ok(())
    };
    run_dataset(&request, &mut sink, None).expect("the pendulum runs");
    // Shortest round-trip decimals: strtod reads back the same bits.
    let mut text = format!("{} 3\n", rows.len());
    for r in &rows {
        let line: Vec<String> = r.iter().map(|x| format!("{x:e}")).collect();
        text.push_str(&line.join(" "));
        text.push('\n');
    }
    let dir = program("simulation_data");
    std::fs::create_dir_all(&dir).expect("the target's tmp dir is writable");
    let expected = dir.join("rows.txt");
    std::fs::write(&expected, text).expect("written");
    let exe = program("simulation_test");
    let mut build = cc();
    build
        .arg("-I")
        .arg(root().join("include"))
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/c/simulation_test.c"))
        .arg(library("libmbfx_c.a"))
        .args(NATIVE_LIBS)
        .arg("-o")
        .arg(&exe);
    run(build, "compiling simulation_test.c");
    let mut test = Command::new(&exe);
    test.arg(&dataset)
        .arg(&expected)
        .arg(root().join("examples/scenes/cart_pole.adm"));
    let stdout = run(test, "simulation_test");
    let last = stdout.lines().last().unwrap_or("");
    assert!(last.ends_with(" 0 failed"), "simulation_test: {stdout}");
}
