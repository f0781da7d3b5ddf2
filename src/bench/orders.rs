//! Orders of convergence measured on a scene with exact truth (A01): each fixed-step
//! method over halving steps (the slope of log error against log h), and the BDF with
//! its highest order held at k = 1…6 under error control with ERROR per run (the slope
//! of log error against log steps, negated: a run's global error gathers its steps'
//! local errors, so it falls as steps^(−k)). Fitted over the points between the
//! rounding floor and the pre-asymptotic regime, which the table states.

use super::chart::slope;
use super::point::{measure, variant_named, Control, Options, Point, Status};
use super::scene::Scene;
use std::fmt::Write as _;

/// One measured order.
#[derive(Clone, Debug)]
pub struct Order {
    /// The method (with `KMAX = k` for the BDF).
    pub method: String,
    /// What theory says.
    pub theory: f64,
    /// The fitted slope (None: fewer than two usable points).
    pub measured: Option<f64>,
    /// The points fitted: (h or steps, error).
    pub points: Vec<(f64, f64)>,
    /// The BDF: the share of the fitted runs' steps taken at order k (None: a
    /// fixed-order method).
    pub at_kmax: Option<f64>,
}

/// Errors inside this band are fitted: below it rounding takes over, above it the
/// step is not yet asymptotic.
const BAND: (f64, f64) = (1e-11, 5e-2);

/// The runs fitted, finished with their error inside [`BAND`], as (x, error).
fn usable(points: &[Point], x: impl Fn(&Point) -> f64) -> Vec<(&Point, (f64, f64))> {
    points
        .iter()
        .filter(|p| p.status == Status::Ok)
        .filter_map(|p| Some((p, (x(p), p.errors.position?))))
        .filter(|&(_, (_, e))| e > BAND.0 && e < BAND.1)
        .collect()
}

/// Each fixed-step method and the halvings of the output step it runs at.
const FIXED: &[(&str, &[u32])] = &[
    ("hht-fixed", &[4, 5, 6, 7, 8, 9]),
    ("galpha-fixed", &[4, 5, 6, 7, 8, 9]),
    ("newmark-fixed", &[9, 10, 11, 12]),
    ("dopri853-fixed", &[1, 2, 3, 4, 5]),
];

/// The ERROR ladder of the BDF at KMAX = k, ERROR per run: ten tolerances a decade.
/// One run's error scatters about the trend by a factor of up to two as the step and
/// order selection switch, so the slope needs many points; KMAX 1 and 2 stop where a
/// run would take millions of steps.
fn gstiff_errors(k: u32) -> Vec<f64> {
    let decades: (i32, i32) = match k {
        1 => (4, 5),
        2 => (3, 8),
        _ => (3, 12),
    };
    (10 * decades.0..=10 * decades.1)
        .map(|j| 10f64.powf(-f64::from(j) / 10.0))
        .collect()
}

/// How many runs [`measure_orders`] makes.
pub fn run_count() -> usize {
    FIXED.iter().map(|(_, h)| h.len()).sum::<usize>()
        + (1..=6).map(|k| gstiff_errors(k).len()).sum::<usize>()
}

/// Measures every order on `scene`, handing each run to `each`.
pub fn measure_orders(scene: &Scene, each: &mut dyn FnMut(&Point)) -> Result<Vec<Order>, String> {
    let text = scene.dataset_text()?;
    let o = Options {
        repeat_budget: 0.0,
        ..Options::default()
    };
    let base = scene.output_step * scene.stride() as f64;
    let mut out = Vec::new();
    for &(name, halvings) in FIXED {
        let v = variant_named(name).ok_or_else(|| format!("no method {name}"))?;
        let mut pts = Vec::new();
        for &k in halvings {
            let p = measure(
                scene,
                &text,
                v,
                Control::FixedStep(base / f64::from(1u32 << k)),
                o,
            );
            each(&p);
            pts.push(p);
        }
        let points: Vec<(f64, f64)> = usable(&pts, |p| p.control.value())
            .into_iter()
            .map(|(_, xy)| xy)
            .collect();
        out.push(Order {
            method: name.to_string(),
            theory: f64::from(v.order),
            measured: slope(&points),
            points,
            at_kmax: None,
        });
    }
    // ERROR per run: the answer's error then follows ERROR (tolerance proportionality,
    // the usual setting of a convergence study), and the ladder spaces the runs evenly
    // in error. Per step (Adams' meaning) the same ladder fits 6.3–6.4 at KMAX 6 on
    // A01 and scatters more (docs/bench.md, Orders of convergence).
    let gstiff = variant_named("gstiff-run").ok_or("no gstiff-run")?;
    for k in 1..=6u32 {
        let errors = gstiff_errors(k);
        let mut pts = Vec::new();
        for &e in &errors {
            let p = measure(
                scene,
                &text,
                gstiff,
                Control::Tolerance(e),
                Options { kmax: Some(k), ..o },
            );
            each(&p);
            pts.push(p);
        }
        let fitted = usable(&pts, |p| p.stats.steps as f64);
        let (at_k, all) = fitted.iter().fold((0, 0), |(a, n), (p, _)| {
            (
                a + p.stats.steps_at_order[k as usize - 1],
                n + p.stats.steps,
            )
        });
        let points: Vec<(f64, f64)> = fitted.into_iter().map(|(_, xy)| xy).collect();
        out.push(Order {
            method: format!("gstiff KMAX = {k}"),
            theory: f64::from(k),
            measured: slope(&points).map(|s| -s),
            points,
            at_kmax: (all > 0).then(|| at_k as f64 / all as f64),
        });
    }
    Ok(out)
}

/// The orders as a markdown section.
pub fn markdown(scene: &Scene, orders: &[Order]) -> String {
    let mut s = format!(
        "\n## Orders of convergence on {}\n\nFixed-step methods: slope of log error against log h; the BDF at KMAX = k under error control with ERROR per run (ten tolerances a decade): slope of log error against log steps, negated. Points with errors between {:e} and {:e} are fitted.\n\n| method | theory | measured | off by | points | steps at order k |\n|---|---|---|---|---|---|\n",
        scene.name, BAND.0, BAND.1
    );
    for o in orders {
        let (m, off) = match o.measured {
            Some(m) => (format!("{m:.2}"), format!("{:.2}", (m - o.theory).abs())),
            None => ("—".into(), "—".into()),
        };
        let share = o
            .at_kmax
            .map_or("—".into(), |x| format!("{:.1} %", 100.0 * x));
        let _ = writeln!(
            s,
            "| {} | {} | {m} | {off} | {} | {share} |",
            o.method,
            o.theory,
            o.points.len()
        );
    }
    s += "\nThe points fitted (h or steps: error):\n\n";
    for o in orders {
        let pts: Vec<String> = o
            .points
            .iter()
            .map(|(x, e)| format!("{x:.4e}: {e:.3e}"))
            .collect();
        let _ = writeln!(s, "- {}: {}", o.method, pts.join(", "));
    }
    s
}
