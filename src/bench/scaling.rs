//! Cost against model size: the generated planar chain, binary tree and N-four-bar,
//! built in 2D and in 3D, each run by each method asked (GSTIFF and dopri853 by default)
//! at one tolerance; CPU per step and per simulated second against N, with the
//! least-squares slope on log-log axes (1 is linear cost).

use super::chart::{self, Axes, Curve};
use super::generate::generate;
use super::point::{Control, Variant};
use crate::session::run::{RunSpec, Simulation};
use crate::session::DimRequest;
use std::fmt::Write as _;
use std::path::Path;

/// One measured size.
#[derive(Clone, Debug)]
pub struct Sample {
    /// The method's name.
    pub method: &'static str,
    /// `chain`, `tree` or `four_bar`.
    pub kind: &'static str,
    /// 2 or 3.
    pub dim: u8,
    /// The size.
    pub n: usize,
    /// Accepted steps.
    pub steps: usize,
    /// CPU of the run, s.
    pub cpu: f64,
    /// Simulated time, s.
    pub end: f64,
    /// Why it stopped early, if it did.
    pub failure: Option<String>,
}

impl Sample {
    /// CPU per accepted step.
    pub fn per_step(&self) -> f64 {
        self.cpu / self.steps.max(1) as f64
    }

    /// CPU per simulated second.
    pub fn per_second(&self) -> f64 {
        self.cpu / self.end
    }
}

/// Runs `kind` at size `n` in `dim` for `end` seconds with `v` at `control`.
pub fn sample(
    kind: &'static str,
    n: usize,
    dim: u8,
    end: f64,
    v: Variant,
    control: Control,
) -> Sample {
    let mut s = Sample {
        method: v.name,
        kind,
        dim,
        n,
        steps: 0,
        cpu: f64::NAN,
        end,
        failure: None,
    };
    let Some(text) = generate(kind, n) else {
        s.failure = Some(format!("cannot generate `{kind}` of size {n}"));
        return s;
    };
    let mut spec = RunSpec::new(end, end);
    spec.method = Some(v.method);
    spec.formulation = v.formulation;
    spec.dim = if dim == 2 {
        DimRequest::Two
    } else {
        DimRequest::Three
    };
    match control {
        Control::Tolerance(e) => spec.error = Some(e),
        Control::FixedStep(h) => spec.fixed_step = Some(h),
    }
    let mut sim = match Simulation::new(&text, spec, &[]) {
        Ok(sim) => sim,
        Err(f) => {
            s.failure = Some(super::point::describe(&f));
            return s;
        }
    };
    let (summary, failure) = sim.run(&mut |_| Ok(()));
    s.steps = summary.stats.steps;
    s.cpu = summary.cpu_seconds;
    s.failure = failure.map(|e| e.to_string());
    s
}

/// The sizes of each kind the scaling chart runs.
pub const SIZES: &[(&str, &[usize])] = &[
    ("chain", &[10, 30, 100, 300, 1000, 3000]),
    ("tree", &[10, 30, 100, 300, 1000, 3000]),
    ("four_bar", &[1, 2, 5, 10, 20, 40]),
];

/// The largest N run in 3D: there dopri853 integrates Cartesian coordinates (joint
/// coordinates are planar only), and a 3D tree of 3,000 bodies takes minutes a method.
pub const MAX_3D: usize = 300;

/// The sizes of `sizes` run in `dim`.
pub fn sizes_in(sizes: &[usize], dim: u8) -> impl Iterator<Item = usize> + '_ {
    sizes
        .iter()
        .copied()
        .filter(move |&n| dim == 2 || n <= MAX_3D)
}

/// Writes `scaling.svg` and `scaling.csv` into `dir` and returns the markdown section.
pub fn write(dir: &Path, samples: &[Sample], control: Control) -> Result<String, String> {
    let csv_path = dir.join("scaling.csv");
    let fail = |e: csv::Error| format!("{}: {e}", csv_path.display());
    let mut w = csv::Writer::from_path(&csv_path).map_err(fail)?;
    w.write_record([
        "method",
        "kind",
        "dim",
        "n",
        "steps",
        "cpu_s",
        "end_s",
        "cpu_per_step_s",
        "cpu_per_simulated_s",
        "status",
    ])
    .map_err(fail)?;
    for s in samples {
        w.write_record([
            s.method.to_string(),
            s.kind.to_string(),
            s.dim.to_string(),
            s.n.to_string(),
            s.steps.to_string(),
            format!("{:e}", s.cpu),
            format!("{:e}", s.end),
            format!("{:e}", s.per_step()),
            format!("{:e}", s.per_second()),
            s.failure
                .clone()
                .map_or("ok".into(), |f| format!("failed: {f}")),
        ])
        .map_err(fail)?;
    }
    w.flush()
        .map_err(|e| format!("{}: {e}", csv_path.display()))?;
    let mut methods: Vec<&str> = Vec::new();
    for s in samples {
        if !methods.contains(&s.method) {
            methods.push(s.method);
        }
    }
    let mut md = format!(
        "\n## Scaling\n\n{} at {} {:e}; CPU per accepted step against N, least-squares slope of log CPU against log N (1 = linear).\n\n| method | model | dim | N | steps | CPU per step | CPU per simulated s |\n|---|---|---|---|---|---|---|\n",
        methods.join(", "),
        control.kind(),
        control.value()
    );
    let mut per_step = Vec::new();
    let mut per_second = Vec::new();
    for (method, (kind, _), dim) in methods
        .iter()
        .flat_map(|m| SIZES.iter().map(move |k| (*m, k)))
        .flat_map(|(m, k)| [2u8, 3].map(|dim| (m, k, dim)))
    {
        {
            let this = |s: &&Sample| s.method == method && s.kind == *kind && s.dim == dim;
            let ok: Vec<&Sample> = samples
                .iter()
                .filter(this)
                .filter(|s| s.failure.is_none() && s.cpu > 0.0)
                .collect();
            if samples.iter().filter(this).count() == 0 {
                continue;
            }
            for s in samples.iter().filter(this) {
                let _ = writeln!(
                    md,
                    "| {method} | {kind} | {dim}D | {} | {} | {:.2e} s | {:.2e} s |{}",
                    s.n,
                    s.steps,
                    s.per_step(),
                    s.per_second(),
                    s.failure
                        .as_ref()
                        .map_or(String::new(), |f| format!(" failed: {f}"))
                );
            }
            let a: Vec<(f64, f64)> = ok.iter().map(|s| (s.n as f64, s.per_step())).collect();
            let b: Vec<(f64, f64)> = ok.iter().map(|s| (s.n as f64, s.per_second())).collect();
            let (sa, sb) = (chart::slope(&a), chart::slope(&b));
            let fmt = |s: Option<f64>| s.map_or("—".into(), |s| format!("{s:.2}"));
            let _ = writeln!(
                md,
                "| {method} | {kind} {dim}D slope | | | | {} | {} |",
                fmt(sa),
                fmt(sb)
            );
            let name = |what: Option<f64>| format!("{method} {kind} {dim}D (slope {})", fmt(what));
            per_step.push(Curve {
                name: name(sa),
                asked: vec![None; a.len()],
                points: a,
                peer: false,
            });
            per_second.push(Curve {
                name: name(sb),
                asked: vec![None; b.len()],
                points: b,
                peer: false,
            });
        }
    }
    chart::draw(
        &dir.join("scaling.svg"),
        &[
            (
                Axes {
                    title: "CPU per step against N",
                    x: "N",
                    y: "CPU per accepted step (s)",
                },
                per_step,
            ),
            (
                Axes {
                    title: "CPU per simulated second against N",
                    x: "N",
                    y: "CPU per simulated second (s)",
                },
                per_second,
            ),
        ],
    )?;
    Ok(md)
}
