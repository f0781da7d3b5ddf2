//! Compile latency of the JIT, and its memory over many compile/drop cycles.
//!
//! 1. Per expression: µs from text to a callable (parse, check, lower, Cranelift, one
//!    module each), median over the corpus expressions that check.
//! 2. The whole corpus in one module: the median µs per expression inside the batch, and
//!    ms for all of it (parse, check, one `compile_batch` with one finalisation).
//! 3. Long expressions (issue 11 §2): ms to compile sums of 1 000 and 3 000 terms of
//!    IMPACT, of IFs whose arms call, and of IF/STEP/IMPACT in turn; compile time must
//!    grow linearly (the 3 000-IMPACT sum took 9.3 s before `jit/anchor.rs` and the
//!    contact budget of `ir::lower`).
//! 4. Memory: resident set after 1 000 and after 100 000 compile/evaluate/drop cycles of
//!    corpus expressions (one module each); the second must stay within 10 % of the first.
//!
//! Run: `cargo bench --bench compile` (about a minute; `-- --quick` skips the memory check).

use mbfx::check::{compile, EveryIdExists, Expect};
use mbfx::context::Context;
use mbfx::ir::Function;
use mbfx::jit::Jit;
use std::hint::black_box;
use std::time::Instant;

/// Checkable expressions of both corpus files, deduplicated.
fn corpus() -> Vec<String> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus");
    let mut out: Vec<String> = Vec::new();
    for file in ["expressions.txt", "expressions-cmd.txt"] {
        let text = std::fs::read_to_string(dir.join(file)).expect("corpus file");
        for (_, e) in text.lines().filter_map(|l| l.split_once('\t')) {
            if compile(e, &EveryIdExists, Expect::Any).is_ok() {
                out.push(e.to_string());
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

/// Resident set size in KiB, from /proc (0 where it is not available).
fn rss_kib() -> u64 {
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap_or_default();
    let pages: u64 = statm
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    pages * 4
}

/// Text to IR: lex, parse, check and lower one corpus expression.
fn check(e: &str) -> Function {
    compile(e, &EveryIdExists, Expect::Any)
        .expect("checks")
        .function
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

/// Term `i` of a long sum of kind `kind`, in TIME.
fn term(kind: &str, i: usize) -> String {
    let impact = format!("IMPACT(TIME, 1, {i}, 1E5, 1.5, 10, 0.1)");
    let branch = format!("IF(TIME - {i}: LOG(TIME + {}), 0, SIN(TIME*{i}))", i + 1);
    match (kind, i % 3) {
        ("IMPACT", _) | ("mixed", 2) => impact,
        ("IF", _) | ("mixed", 0) => branch,
        _ => format!("STEP(TIME, {i}, 0, {}, 1)", i + 1),
    }
}

/// Compile time of long sums (median of 3), and its growth from 1 000 to 3 000 terms.
fn long_expressions(jit: &mut Jit) {
    for kind in ["IMPACT", "IF", "mixed"] {
        let ms: Vec<f64> = [1000, 3000]
            .iter()
            .map(|&n| {
                let text: Vec<String> = (0..n).map(|i| term(kind, i)).collect();
                let f = check(&text.join(" + "));
                median(
                    (0..3)
                        .map(|_| {
                            let t0 = Instant::now();
                            black_box(jit.compile(&f).expect("compiles"));
                            t0.elapsed().as_secs_f64() * 1e3
                        })
                        .collect(),
                )
            })
            .collect();
        println!(
            "compile, long sums of {kind}: 1 000 terms {:.1} ms, 3 000 terms {:.1} ms ({:.2}× for 3× the terms)",
            ms[0],
            ms[1],
            ms[1] / ms[0]
        );
    }
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let exprs = corpus();
    let mut jit = Jit::new().expect("host supported");
    let ctx_m = [0.5, -0.25, 1.0];
    let ctx = Context::new(0.3, &[]).with_measures(&ctx_m);

    // 1. One expression, one module, text to callable.
    let mut each = Vec::with_capacity(exprs.len());
    for e in &exprs {
        let t0 = Instant::now();
        let f = check(e);
        let c = jit.compile(&f).expect("compiles");
        each.push(t0.elapsed().as_secs_f64() * 1e6);
        black_box(c.eval(&ctx));
    }
    println!(
        "compile, one module per expression: median {:.1} µs from text to callable ({} corpus expressions)",
        median(each),
        exprs.len()
    );

    // 2. The whole corpus in one module, median of 7 passes.
    let mut totals = Vec::new();
    let mut checks = Vec::new();
    let mut in_batch = Vec::new();
    for _ in 0..7 {
        let t0 = Instant::now();
        let fs: Vec<_> = exprs.iter().map(|e| check(e)).collect();
        let t1 = Instant::now();
        let refs: Vec<_> = fs.iter().collect();
        let compiled = jit.compile_batch(&refs).expect("compiles");
        totals.push(t0.elapsed().as_secs_f64() * 1e3);
        in_batch.push(median(jit.last_batch_times().to_vec()) * 1e6);
        checks.push(t1.duration_since(t0).as_secs_f64() * 1e3);
        black_box(compiled.iter().map(|c| c.eval(&ctx)).sum::<f64>());
    }
    let total = median(totals);
    println!(
        "compile, whole corpus in one module: median {:.1} µs per expression (lowering, translation, Cranelift; finalisation excluded)",
        median(in_batch)
    );
    println!(
        "compile, whole corpus in one module: {total:.1} ms for {} expressions ({:.1} µs each; parse+check {:.1} ms of it)",
        exprs.len(),
        total * 1e3 / exprs.len() as f64,
        median(checks)
    );

    // 3. Long expressions.
    long_expressions(&mut jit);

    // 4. Memory over compile/evaluate/drop cycles.
    if quick {
        return;
    }
    let fs: Vec<_> = exprs.iter().map(|e| check(e)).collect();
    let mut after_1000 = 0;
    let t0 = Instant::now();
    for i in 0..100_000 {
        let c = jit.compile(&fs[i % fs.len()]).expect("compiles");
        black_box(c.eval(&ctx));
        drop(c);
        if i + 1 == 1000 {
            after_1000 = rss_kib();
        }
    }
    let after = rss_kib();
    let growth = (after as f64 - after_1000 as f64) / after_1000 as f64 * 100.0;
    println!(
        "memory: resident {after_1000} KiB after 1 000 compile/drop cycles, {after} KiB after 100 000 ({growth:+.1} %, limit 10 %; {:.1} s)",
        t0.elapsed().as_secs_f64()
    );
    assert!(
        growth.abs() <= 10.0,
        "resident memory grew by {growth:.1} %"
    );
}
