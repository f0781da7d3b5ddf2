//! Redundancy analysis speed on the 3D A02 N-four-bar (reference-problems §4.2, §5.3):
//! N = 40 (81 parts, 605 equations, 120 redundant) and N = 400 (801 parts, 6005 equations,
//! 1200 redundant). The Jacobian is built once outside the timing; one iteration is one
//! `analyze` call (equilibration, ordering, sparse elimination, advice). After criterion a
//! median of its own prints the N = 400 / N = 40 time ratio: the size grows tenfold, so a
//! ratio near 10 means linear work (dense QR would be about 1000).
//!
//! Run: `cargo bench --bench redundancy`.

use criterion::Criterion;
use fixtures::n_four_bar;
use mbfx::mbd::redundancy::{analyze, Options, Problem};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// The reference mechanisms of the redundancy unit tests.
#[allow(dead_code, reason = "the bench uses one of the mechanisms")]
#[path = "../tests/common/redundancy_fixtures.rs"]
mod fixtures;

struct Case {
    n: usize,
    jacobian: mbfx::mbd::sparse::Triplets,
    labels: Vec<mbfx::mbd::equations::EquationLabel>,
    elements: Vec<mbfx::vocab::elements::ElementRef>,
    parts: usize,
}

impl Case {
    fn new(n: usize) -> Case {
        let m = n_four_bar(n, 3, 0.3, 1.0, 1.0);
        Case {
            n,
            jacobian: m.jacobian(),
            labels: m.labels(),
            elements: m.elements(),
            parts: m.centres.len(),
        }
    }

    fn run(&self) -> usize {
        let problem = Problem::new(&self.jacobian, &self.labels, &self.elements, self.parts, 3);
        let report = analyze(&problem, &Options::default()).expect("the N-four-bar is consistent");
        assert_eq!(report.redundant.len(), 3 * self.n);
        report.rank
    }

    /// Median wall time of one analysis over `reps` runs.
    fn median(&self, reps: usize) -> Duration {
        let mut times: Vec<Duration> = (0..reps)
            .map(|_| {
                let start = Instant::now();
                black_box(self.run());
                start.elapsed()
            })
            .collect();
        times.sort();
        times[reps / 2]
    }
}

fn main() {
    let cases = [Case::new(40), Case::new(400)];
    let mut c = Criterion::default()
        .configure_from_args()
        .measurement_time(Duration::from_secs(3));
    let mut group = c.benchmark_group("redundancy");
    for case in &cases {
        group.bench_function(format!("n_four_bar_{}", case.n), |b| {
            b.iter(|| black_box(case.run()))
        });
    }
    group.finish();
    c.final_summary();

    let small = cases[0].median(51);
    let large = cases[1].median(21);
    println!(
        "N-four-bar 3D: N = 40 {:.3} ms, N = 400 {:.3} ms, ratio {:.1} (limit 20)",
        small.as_secs_f64() * 1e3,
        large.as_secs_f64() * 1e3,
        large.as_secs_f64() / small.as_secs_f64()
    );
}
