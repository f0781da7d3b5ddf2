//! Front-end throughput: parse only, and parse + check (`compile`: lex, parse, check,
//! lower to IR), over every expression of the shared corpus
//! (`../shared/corpus/expressions.txt` from `.adm` files and `expressions-cmd.txt` from
//! Adams View `.cmd` files; second tab-separated column), read at run time. Checking uses a
//! scope in which every measure and SPLINE exists, as a model would supply. `compile` is
//! the public entry point every caller uses: it runs in the thread's session, which reuses
//! its buffers but does all the work for every expression (nothing is cached between
//! expressions or passes); each result, a `Function` or diagnostics, is built and dropped
//! inside the timed loop. Criterion reports bytes/s; a median timing loop of its own then
//! prints MB/s and µs per expression. The stage "parse+check, no units" runs the same
//! check in a scope that asks for no units check, so the two "parse+check" rows give the
//! units check's cost (issue 24).
//!
//! Run: `cargo bench --bench frontend`.

use criterion::{Criterion, Throughput};
use mbfx::check::units::UnitNames;
use mbfx::check::{compile, EveryIdExists, Expect, MeasureCall, MeasureValue, Scope, SplineInfo};
use mbfx::diag::Diagnostic;
use mbfx::syntax::parser::Session;
use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

/// One front-end stage run over a list of expressions.
type Stage = (&'static str, fn(&[String]));

/// Passes of the median timing loop.
const REPS: usize = 21;

/// The expressions (second tab-separated column) of one corpus file.
fn corpus(file: &str) -> Vec<String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/corpus")
        .join(file);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let exprs: Vec<String> = text
        .lines()
        .filter_map(|l| l.split_once('\t').map(|(_, e)| e.to_string()))
        .collect();
    assert!(!exprs.is_empty(), "{}: no expressions", path.display());
    exprs
}

fn parse_all(exprs: &[String]) {
    let mut session = Session::new();
    for e in exprs {
        let parsed = session.parse(black_box(e), true);
        black_box((parsed.root, parsed.diagnostics));
    }
}

fn check_all(exprs: &[String]) {
    for e in exprs {
        let _ = black_box(compile(black_box(e), &EveryIdExists, Expect::Any));
    }
}

/// [`EveryIdExists`] without the units check.
struct NoUnits;

impl Scope for NoUnits {
    fn variable(&self, name: &str) -> Option<u32> {
        EveryIdExists.variable(name)
    }

    fn spline(&self, id: i64) -> Option<SplineInfo> {
        EveryIdExists.spline(id)
    }

    fn measure(&self, call: &MeasureCall) -> Result<MeasureValue, Diagnostic> {
        EveryIdExists.measure(call)
    }

    fn unit_names(&self) -> Option<&UnitNames> {
        None
    }
}

fn check_all_without_units(exprs: &[String]) {
    for e in exprs {
        let _ = black_box(compile(black_box(e), &NoUnits, Expect::Any));
    }
}

/// Median seconds per pass of `f` over [`REPS`] passes, after one warm-up pass.
fn median_secs(f: impl Fn()) -> f64 {
    f();
    let mut s: Vec<f64> = (0..REPS)
        .map(|_| {
            let t0 = Instant::now();
            f();
            t0.elapsed().as_secs_f64()
        })
        .collect();
    s.sort_by(f64::total_cmp);
    s[REPS / 2]
}

fn main() {
    let adm = corpus("expressions.txt");
    let cmd = corpus("expressions-cmd.txt");
    let all: Vec<String> = adm.iter().chain(&cmd).cloned().collect();
    let sets = [
        ("expressions.txt", &adm),
        ("expressions-cmd.txt", &cmd),
        ("both", &all),
    ];
    let stages: [Stage; 3] = [
        ("parse only", parse_all),
        ("parse+check, no units", check_all_without_units),
        ("parse+check", check_all),
    ];

    let mut criterion = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .configure_from_args();
    let mut group = criterion.benchmark_group("frontend");
    for (set, exprs) in &sets {
        let bytes: usize = exprs.iter().map(String::len).sum();
        group.throughput(Throughput::Bytes(bytes as u64));
        for (stage, f) in stages {
            group.bench_function(format!("{set}/{stage}"), |b| b.iter(|| f(exprs)));
        }
    }
    group.finish();
    criterion.final_summary();

    println!("\nfrontend: median of {REPS} passes over the shared expression corpus");
    println!("| corpus | expressions | bytes | stage | MB/s | µs per expression |");
    println!("|---|---:|---:|---|---:|---:|");
    for (set, exprs) in &sets {
        let bytes: usize = exprs.iter().map(String::len).sum();
        for (stage, f) in stages {
            let secs = median_secs(|| f(exprs));
            println!(
                "| {set} | {} | {bytes} | {stage} | {:.1} | {:.2} |",
                exprs.len(),
                bytes as f64 / secs / 1e6,
                secs * 1e6 / exprs.len() as f64
            );
        }
    }
    println!("\nunits check: added time of parse+check, median of {PAIRS} paired passes");
    for (set, exprs) in &sets {
        println!("| {set} | {:+.1} % |", 100.0 * (units_ratio(exprs) - 1.0));
    }
}

/// Passes of the paired comparison.
const PAIRS: usize = 41;

/// The median, over [`PAIRS`] rounds, of the ratio of a pass with the units check to the
/// pass without it just before: pairing cancels the drift of a loaded machine that
/// separate medians of the two stages would take for a difference.
fn units_ratio(exprs: &[String]) -> f64 {
    let secs = |f: fn(&[String])| {
        let t0 = Instant::now();
        f(exprs);
        t0.elapsed().as_secs_f64()
    };
    secs(check_all);
    let mut ratios: Vec<f64> = (0..PAIRS)
        .map(|_| {
            let without = secs(check_all_without_units);
            secs(check_all) / without
        })
        .collect();
    ratios.sort_by(f64::total_cmp);
    ratios[PAIRS / 2]
}
