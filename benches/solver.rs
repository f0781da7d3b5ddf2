//! The solver's hot paths on the planar 100-rod chain (issue 10's figure), built in 2D
//! and in 3D: one evaluation of the constraints with their Jacobian, of the forces with
//! theirs, one fill-and-factor of the Newton matrix, and one whole GSTIFF run of 0.1 s at
//! ERROR 1e-6. After criterion, a median of 21 runs of each prints the 3D / 2D ratio
//! side by side: what modelling a planar scene in 3D costs on each path.
//!
//! Run: `cargo bench --bench solver`.

use criterion::Criterion;
use mbfx::bench::generate::chain;
use mbfx::mbd::dynamics::Weights;
use mbfx::session::run::{Method, RunSpec, Simulation};
use mbfx::session::DimRequest;
use std::hint::black_box;
use std::time::{Duration, Instant};

const N: usize = 100;

fn simulation(dim: DimRequest, end: f64) -> Simulation {
    let mut spec = RunSpec::new(end, end);
    spec.method = Some(Method::Gstiff);
    spec.error = Some(1e-6);
    spec.dim = dim;
    let mut sim =
        Simulation::new(&chain(N), spec, &[]).unwrap_or_else(|_| panic!("the chain builds"));
    sim.dynamics
        .solve_accelerations()
        .expect("consistent accelerations");
    sim
}

const W: Weights = Weights {
    w_m: 1.0,
    w_k: 1e-6,
    w_c: 1e-3,
    w_l: 1.0,
};

/// One hot path, run on a prepared simulation.
type Path = Box<dyn Fn(&mut Simulation)>;

/// The paths, each as a closure over a prepared simulation.
fn paths() -> Vec<(&'static str, Path)> {
    vec![
        (
            "constraints+jacobian",
            Box::new(|s: &mut Simulation| s.dynamics.eval_constraints(true).expect("evaluates")),
        ),
        (
            "forces+jacobians",
            Box::new(|s: &mut Simulation| s.dynamics.eval_forces(true).expect("evaluates")),
        ),
        (
            "newton matrix fill+factor",
            Box::new(|s: &mut Simulation| {
                let lambda = s.dynamics.lambda.clone();
                s.dynamics.factor(W, &lambda).expect("factors")
            }),
        ),
    ]
}

fn median(reps: usize, mut f: impl FnMut()) -> Duration {
    let mut t: Vec<Duration> = (0..reps)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed()
        })
        .collect();
    t.sort();
    t[reps / 2]
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let dims = [("2d", DimRequest::Two), ("3d", DimRequest::Three)];
    for (name, path) in paths() {
        let mut g = c.benchmark_group(format!("chain{N} {name}"));
        for (d, dim) in dims {
            let mut sim = simulation(dim, 0.1);
            g.bench_function(d, |b| b.iter(|| path(black_box(&mut sim))));
        }
        g.finish();
    }
    let mut g = c.benchmark_group(format!("chain{N} gstiff 0.1 s"));
    g.sample_size(10);
    for (d, dim) in dims {
        g.bench_function(d, |b| {
            b.iter(|| {
                let mut sim = simulation(dim, 0.1);
                black_box(sim.run(&mut |_| Ok(())).0.stats.steps)
            })
        });
    }
    g.finish();
    println!("\nmedian of 21, 3D beside 2D (chain of {N} rods):");
    for (name, path) in paths() {
        let mut t = Vec::new();
        for (_, dim) in dims {
            let mut sim = simulation(dim, 0.1);
            t.push(median(21, || path(&mut sim)));
        }
        println!(
            "  {name:28} 2D {:>10.1?}  3D {:>10.1?}  3D/2D {:.2}",
            t[0],
            t[1],
            t[1].as_secs_f64() / t[0].as_secs_f64()
        );
    }
    let mut t = Vec::new();
    for (_, dim) in dims {
        t.push(median(5, || {
            let mut sim = simulation(dim, 0.1);
            black_box(sim.run(&mut |_| Ok(())));
        }));
    }
    println!(
        "  {:28} 2D {:>10.1?}  3D {:>10.1?}  3D/2D {:.2}",
        "gstiff run of 0.1 s (+build)",
        t[0],
        t[1],
        t[1].as_secs_f64() / t[0].as_secs_f64()
    );
}
