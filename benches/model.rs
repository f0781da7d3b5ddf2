//! The whole-model pipeline on the largest corpus datasets: read (statements, every
//! expression checked and lowered: "load + compile"), then build the system and assemble
//! positions and velocities at t = 0, then the redundancy analysis. Two files: the largest
//! by size (adamspy `existing_drillsim/test_analysis_1.adm`, 299 kB) and the largest
//! system (FAST `Test14_ADAMS.adm`, 72 moving parts, 432 equations). Each is built in
//! the dimension the session chooses. After criterion, a
//! median of 21 runs of each stage is printed in ms.
//!
//! Run: `cargo bench --bench model`.

use criterion::Criterion;
use mbfx::mbd::compiled::CompiledExprs;
use mbfx::mbd::pipeline::{analyze_model, redundancy_of, DimRequest};
use mbfx::mbd::{AssemblyOptions, Dim, Dimension, System};
use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

const FILES: [&str; 2] = [
    "bthornton191__adamspy/test/existing_drillsim/test_analysis_1.adm",
    "old-NWTC__FAST/CertTest/Old_Adams_files/Test14_ADAMS.adm",
];

fn text(rel: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/corpus/adams")
        .join(rel);
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    mbfx::model::decode(&bytes).0.into_owned()
}

fn read(text: &str) -> mbfx::model::Model {
    let read = mbfx::model::read_model(text);
    assert!(!read.has_errors());
    read.model
}

/// Build in `dim` (the one the session chose) and assemble.
fn assemble(model: &mbfx::model::Model, dim: Dim) -> System {
    let mut sys = System::from_model(model, dim, &CompiledExprs::new()).expect("builds");
    sys.assemble(&AssemblyOptions::default())
        .expect("assembles");
    sys
}

fn median(mut f: impl FnMut()) -> Duration {
    let mut times: Vec<Duration> = (0..21)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed()
        })
        .collect();
    times.sort();
    times[10]
}

fn main() {
    let mut c = Criterion::default()
        .configure_from_args()
        .sample_size(20)
        .measurement_time(Duration::from_secs(3))
        .warm_up_time(Duration::from_secs(1));
    let mut figures = Vec::new();
    for rel in FILES {
        let name = rel.rsplit('/').next().unwrap();
        let src = text(rel);
        let model = read(&src);
        let session = analyze_model(&model, DimRequest::Auto).expect("analysed");
        let assembled = session.system;
        let dim = match assembled.dim {
            Dimension::Two => Dim::Auto,
            Dimension::Three => Dim::Three,
        };
        let mut g = c.benchmark_group(name);
        g.bench_function("read", |b| b.iter(|| read(black_box(&src))));
        g.bench_function("read+build+assemble", |b| {
            b.iter(|| assemble(&read(black_box(&src)), dim))
        });
        g.bench_function("whole session", |b| {
            b.iter(|| analyze_model(&read(black_box(&src)), DimRequest::Auto).is_ok())
        });
        g.finish();
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        let r = median(|| drop(black_box(read(&src))));
        let a = median(|| drop(black_box(assemble(&read(&src), dim))));
        let w = median(|| drop(black_box(analyze_model(&read(&src), DimRequest::Auto))));
        let red = median(|| drop(black_box(redundancy_of(&assembled))));
        figures.push(format!(
            "{name}: {} kB, {} moving parts in {:?}, {} equations: read {:.2} ms, read+build+assemble {:.2} ms, redundancy {:.2} ms, whole session {:.2} ms",
            src.len() / 1000,
            assembled.moving_parts(),
            assembled.dim,
            assembled.rows().count(),
            ms(r),
            ms(a),
            ms(red),
            ms(w)
        ));
    }
    c.final_summary();
    for f in figures {
        println!("{f}");
    }
}
