//! Orders of convergence measured on a scene with exact truth (A01): each fixed-step
//! method over halving steps (the slope of log error against log h), and the BDF with
//! its highest order held at k = 1…6 under error control (the slope of log error
//! against log steps, negated: a run's global error gathers its steps' local errors,
//! so it falls as steps^(−k)). Fitted over the points between the rounding floor and
//! the pre-asymptotic regime, which the table states.

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
}

/// Errors inside this band are fitted: below it rounding takes over, above it the
/// step is not yet asymptotic.
const BAND: (f64, f64) = (1e-11, 5e-2);

fn usable(points: &[Point], x: impl Fn(&Point) -> f64) -> Vec<(f64, f64)> {
    points
        .iter()
        .filter(|p| p.status == Status::Ok)
        .filter_map(|p| Some((x(p), p.errors.position?)))
        .filter(|&(_, e)| e > BAND.0 && e < BAND.1)
        .collect()
}

/// Each fixed-step method and the halvings of the output step it runs at.
const FIXED: &[(&str, &[u32])] = &[
    ("hht-fixed", &[4, 5, 6, 7, 8, 9]),
    ("galpha-fixed", &[4, 5, 6, 7, 8, 9]),
    ("newmark-fixed", &[9, 10, 11, 12]),
    ("dopri853-fixed", &[1, 2, 3, 4, 5]),
];

/// The ERROR ladder of the BDF at KMAX = k: four tolerances a decade (one run's error
/// scatters about the trend as the order selection switches, so a fit over few points
/// is noisy), tight enough that the start-up steps at low order weigh little.
fn gstiff_errors(k: u32) -> Vec<f64> {
    let decades: (i32, i32) = match k {
        1 => (7, 9),
        2 => (6, 9),
        _ => (6, 12),
    };
    (4 * decades.0..=4 * decades.1)
        .map(|j| 10f64.powf(-f64::from(j) / 4.0))
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
        let points = usable(&pts, |p| p.control.value());
        out.push(Order {
            method: name.to_string(),
            theory: f64::from(v.order),
            measured: slope(&points),
            points,
        });
    }
    let gstiff = variant_named("gstiff").ok_or("no gstiff")?;
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
        let points = usable(&pts, |p| p.stats.steps as f64);
        out.push(Order {
            method: format!("gstiff KMAX = {k}"),
            theory: f64::from(k),
            measured: slope(&points).map(|s| -s),
            points,
        });
    }
    Ok(out)
}

/// The orders as a markdown section.
pub fn markdown(scene: &Scene, orders: &[Order]) -> String {
    let mut s = format!(
        "\n## Orders of convergence on {}\n\nFixed-step methods: slope of log error against log h; the BDF at KMAX = k under error control: slope of log error against log steps, negated. Points with errors between {:e} and {:e} are fitted.\n\n| method | theory | measured | off by | points |\n|---|---|---|---|---|\n",
        scene.name, BAND.0, BAND.1
    );
    for o in orders {
        let (m, off) = match o.measured {
            Some(m) => (format!("{m:.2}"), format!("{:.2}", (m - o.theory).abs())),
            None => ("—".into(), "—".into()),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {m} | {off} | {} |",
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
