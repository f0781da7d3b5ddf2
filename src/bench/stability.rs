//! The stability suite: scenes where integration methods are known to fail, each run
//! by every method, and each cell judged **accurate** (error within 10× the asked
//! tolerance), **failed, named** (the run stopped with a diagnostic naming time, cause
//! and element, or finished but its own monitors said it went wrong) or **wrong,
//! silently** (reported success with a larger error). The matrix is written as
//! markdown and as an SVG heat map.

use super::peer_cells::PeerCell;
use super::point::{measure, variant_named, Control, Options, Point, Status};
use super::scene::{Group, Scene};
use crate::font::font;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// One row of the suite: a scene, what it tests, and the setting every method runs at.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    /// The case's name (the peers' cells name their case by it).
    pub id: &'static str,
    /// The scene's name.
    pub scene: &'static str,
    /// What fails there, in words.
    pub what: &'static str,
    /// The methods.
    pub methods: &'static [&'static str],
    /// Their tolerance (with fixed steps: the ERROR the local error monitor compares
    /// with, and the accuracy the cell is judged by).
    pub tolerance: f64,
    /// The fixed step of the fixed-step methods.
    pub step: Option<f64>,
}

const CONTROLLED: &[&str] = &[
    "gstiff",
    "gstiff-si2",
    "wstiff",
    "hht",
    "galpha",
    "dopri853",
    "gstiff-run",
    "dopri853-run",
];
const FIXED: &[&str] = &["hht-fixed", "galpha-fixed"];

/// The suite.
pub const CASES: &[Case] = &[
    Case {
        id: "cart_pole",
        scene: "cart_pole",
        what: "light cart-pole: near-singular mass matrix, a 1 µs spike at each vertical crossing",
        methods: CONTROLLED,
        tolerance: 1e-6,
        step: None,
    },
    Case {
        id: "cart_pole_fixed",
        scene: "cart_pole",
        what: "light cart-pole, fixed steps",
        methods: FIXED,
        tolerance: 1e-3,
        step: Some(1e-3),
    },
    Case {
        id: "a02_n1",
        scene: "a02_n1",
        what: "A02 four-bar through its singular positions (branch jumping)",
        methods: CONTROLLED,
        tolerance: 1e-6,
        step: None,
    },
    Case {
        id: "a02_n40",
        scene: "a02_n40",
        what: "A02 with N = 40: rank drops by 40 at each horizontal crossing",
        methods: CONTROLLED,
        tolerance: 1e-6,
        step: None,
    },
    Case {
        id: "a02_n1_3d",
        scene: "a02_n1_3d",
        what: "the redundant 3D four-bar (3 redundant equations dropped)",
        methods: CONTROLLED,
        tolerance: 1e-6,
        step: None,
    },
    Case {
        id: "andrews_loose",
        scene: "andrews",
        what: "Andrews' squeezer in index 3 at a loose tolerance",
        methods: CONTROLLED,
        tolerance: 1e-3,
        step: None,
    },
    Case {
        id: "a01_rho1",
        scene: "a01_pendulum",
        what: "generalized-α with ρ∞ = 1 on the index-3 pendulum",
        methods: &["galpha-rho1", "galpha"],
        tolerance: 1e-6,
        step: None,
    },
    Case {
        id: "a01_rho1_fixed",
        scene: "a01_pendulum",
        what: "generalized-α with ρ∞ = 1 on the index-3 pendulum, fixed steps",
        methods: &["galpha-rho1-fixed", "galpha-fixed", "hht-fixed"],
        tolerance: 1e-3,
        step: Some(1e-2),
    },
    Case {
        id: "k1e9_loose",
        scene: "impact_stiff_k1e9",
        what: "stiff IMPACT (k = 1e9) at a loose tolerance",
        methods: CONTROLLED,
        tolerance: 1e-3,
        step: None,
    },
    Case {
        id: "k1e9_fixed",
        scene: "impact_stiff_k1e9",
        what: "stiff IMPACT (k = 1e9), large fixed steps",
        methods: FIXED,
        tolerance: 1e-3,
        step: Some(1e-2),
    },
    Case {
        id: "contact_fixed",
        scene: "impact_block_k1e5",
        what: "fixed steps across contact",
        methods: FIXED,
        tolerance: 1e-3,
        step: Some(1e-3),
    },
    Case {
        id: "motion_lockup",
        scene: "motion_lockup",
        what: "a MOTION driven through a lock-up position",
        methods: CONTROLLED,
        tolerance: 1e-6,
        step: None,
    },
];

/// How a cell came out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Error within 10× the asked tolerance.
    Accurate,
    /// Stopped with a diagnostic, or finished with a warning saying it went wrong.
    FailedNamed,
    /// Reported success with a larger error.
    WrongSilently,
    /// The process died (a peer's segmentation fault): not silent, but nothing named.
    Crashed,
    /// The method cannot build or run the scene (a peer's limitation).
    Unsupported,
}

impl Verdict {
    /// The name in the matrix.
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Accurate => "accurate",
            Verdict::FailedNamed => "failed, named",
            Verdict::WrongSilently => "wrong, silently",
            Verdict::Crashed => "crashed",
            Verdict::Unsupported => "unsupported",
        }
    }
}

/// Judges a run against the case's tolerance: positions when the scene scores them,
/// else reactions. An accurate run is accurate even if its monitors were cautious; an
/// inaccurate one is named when it stopped or warned. A scene whose truth is that the
/// run must stop (a lock-up) counts a run that reached its end without a warning as
/// wrong.
pub fn judge(p: &Point, tolerance: f64, must_stop: bool) -> Verdict {
    let e = p.errors.of(Group::Position).or(p.errors.reaction);
    let accurate = e.is_some_and(|e| e <= 10.0 * tolerance);
    match (&p.status, p.warnings.is_empty()) {
        (Status::Failed(_), _) => Verdict::FailedNamed,
        (Status::Ok, _) if accurate && !must_stop => Verdict::Accurate,
        (Status::Ok, false) => Verdict::FailedNamed,
        (Status::Ok, true) => Verdict::WrongSilently,
    }
}

/// One judged cell.
#[derive(Clone, Debug)]
pub struct Cell {
    /// The case's index in the suite.
    pub case: usize,
    /// The run.
    pub point: Point,
    /// Its verdict.
    pub verdict: Verdict,
}

/// Whether a scene's truth is that the run must stop (its `source` says so with the
/// words "must stop").
pub fn must_stop(scene: &Scene) -> bool {
    scene.source.contains("must stop")
}

/// Runs one case on its scene, handing each cell to `each`; `estimate` asks each
/// error-controlled run for its global error estimate (`mbfx run --estimate-error`).
pub fn run_case(
    index: usize,
    case: &Case,
    scene: &Scene,
    estimate: bool,
    each: &mut dyn FnMut(&Cell),
) -> Result<Vec<Cell>, String> {
    let text = scene.dataset_text()?;
    let stop = must_stop(scene);
    let mut cells = Vec::new();
    for name in case.methods {
        let v = variant_named(name).ok_or_else(|| format!("no method `{name}`"))?;
        let control = match (v.fixed, case.step) {
            (true, Some(h)) => Control::FixedStep(h),
            (true, None) => return Err(format!("{name} is fixed-step but the case has no step")),
            (false, _) => Control::Tolerance(case.tolerance),
        };
        // A fixed-step run's local error monitor compares with the case's tolerance.
        let o = Options {
            repeat_budget: 0.0,
            error: Some(case.tolerance),
            estimate,
            ..Options::default()
        };
        let point = measure(scene, &text, v, control, o);
        let cell = Cell {
            case: index,
            verdict: judge(&point, case.tolerance, stop),
            point,
        };
        each(&cell);
        cells.push(cell);
    }
    Ok(cells)
}

/// The matrix as markdown: one row per case, one column per method.
pub fn markdown(cases: &[Case], cells: &[Cell]) -> String {
    let mut methods: Vec<&str> = Vec::new();
    for c in cells {
        if !methods.contains(&c.point.variant.name) {
            methods.push(c.point.variant.name);
        }
    }
    let mut s = String::from("| scene | what fails there | setting |");
    for m in &methods {
        let _ = write!(s, " {m} |");
    }
    s += "\n|---|---|---|";
    s += &"---|".repeat(methods.len());
    s += "\n";
    for (i, case) in cases.iter().enumerate() {
        let row: Vec<&Cell> = cells.iter().filter(|c| c.case == i).collect();
        if row.is_empty() {
            continue;
        }
        let setting = match case.step {
            Some(h) if row.iter().all(|c| c.point.variant.fixed) => format!("h = {h:e}"),
            _ => format!("ERROR {:e}", case.tolerance),
        };
        let _ = write!(s, "| {} | {} | {setting} |", case.scene, case.what);
        for m in &methods {
            match row.iter().find(|c| c.point.variant.name == *m) {
                Some(c) => {
                    let e = c
                        .point
                        .errors
                        .position
                        .or(c.point.errors.reaction)
                        .map_or(String::new(), |e| format!(" ({e:.0e})"));
                    let _ = write!(s, " {}{e} |", c.verdict.name());
                }
                None => s += " |",
            }
        }
        s += "\n";
    }
    s
}

/// Every cell's detail: the diagnostic or warning of a named failure.
pub fn details(cases: &[Case], cells: &[Cell]) -> String {
    let mut s = String::new();
    for c in cells {
        let why = match (&c.point.status, c.point.warnings.first()) {
            (Status::Failed(w), _) => w.clone(),
            (Status::Ok, Some(w)) => format!("finished, warned: {w}"),
            (Status::Ok, None) => continue,
        };
        let _ = writeln!(
            s,
            "- {} / {}: {why}",
            cases[c.case].scene, c.point.variant.name
        );
    }
    s
}

/// The matrix as an SVG heat map: green accurate, amber failed-named, red
/// wrong-silently; then one column per peer method (grey unsupported, purple crashed),
/// a cell striped when the peer ran the case in several formulations.
pub fn heat_map(
    path: &Path,
    cases: &[Case],
    cells: &[Cell],
    peers: &[PeerCell],
) -> Result<(), String> {
    font()?;
    // Each column: its name and, per case, the verdicts of its runs.
    let mut names: Vec<&str> = Vec::new();
    for n in cells.iter().map(|c| c.point.variant.name) {
        if !names.contains(&n) {
            names.push(n);
        }
    }
    let ours = names.len();
    for n in peers.iter().map(|p| p.method.as_str()) {
        if !names.contains(&n) {
            names.push(n);
        }
    }
    let mut columns: Vec<(&str, Vec<Vec<Verdict>>)> = names
        .iter()
        .map(|&n| (n, vec![Vec::new(); cases.len()]))
        .collect();
    let marks = cells
        .iter()
        .map(|c| (c.point.variant.name, c.case, c.verdict))
        .chain(peers.iter().map(|p| (p.method.as_str(), p.case, p.verdict)));
    for (name, case, verdict) in marks {
        if let Some(k) = names.iter().position(|n| *n == name) {
            columns[k].1[case].push(verdict);
        }
    }
    let rows: Vec<usize> = (0..cases.len())
        .filter(|&i| columns.iter().any(|(_, of)| !of[i].is_empty()))
        .collect();
    let (left, top, cw, ch, gap) = (360i32, 60i32, 120i32, 34i32, 24i32);
    let x_of = |k: usize| left + cw * k as i32 + if k >= ours { gap } else { 0 };
    // room for the last name, which may be wider than its column
    let w = (x_of(columns.len()) + 80) as u32;
    let h = (top + ch * rows.len() as i32 + 50) as u32;
    let root = SVGBackend::new(path, (w, h)).into_drawing_area();
    let err = |e: DrawingAreaErrorKind<_>| format!("{}: {e}", path.display());
    root.fill(&WHITE).map_err(err)?;
    let text = |s: &str, x: i32, y: i32, size: i32| {
        Text::new(s.to_string(), (x, y), ("sans-serif", size).into_font())
    };
    root.draw(&text(
        "Stability suite: which method fails where, and whether it says so",
        10,
        12,
        16,
    ))
    .map_err(err)?;
    if columns.len() > ours {
        root.draw(&text(
            "peers (a striped cell: one stripe per formulation)",
            x_of(ours),
            28,
            12,
        ))
        .map_err(err)?;
    }
    for (k, (name, _)) in columns.iter().enumerate() {
        // a peer's name without its prefix fits the column
        let short = name
            .strip_prefix("exudyn-")
            .map(|n| format!("exudyn {n}"))
            .or_else(|| name.strip_prefix("mujoco-").map(|n| format!("mujoco {n}")))
            .unwrap_or(name.to_string());
        root.draw(&text(
            &short,
            x_of(k) + 4,
            top - 20,
            if k >= ours { 10 } else { 12 },
        ))
        .map_err(err)?;
    }
    for (r, &i) in rows.iter().enumerate() {
        let y = top + ch * r as i32;
        let case = &cases[i];
        let label = match case.step {
            Some(hh)
                if cells
                    .iter()
                    .filter(|c| c.case == i)
                    .all(|c| c.point.variant.fixed) =>
            {
                format!("{} (h = {hh:e})", case.scene)
            }
            _ => format!("{} (ERROR {:e})", case.scene, case.tolerance),
        };
        root.draw(&text(&label, 6, y + 10, 12)).map_err(err)?;
        for (k, (_, of)) in columns.iter().enumerate() {
            let runs = &of[i];
            if runs.is_empty() {
                continue;
            }
            let x = x_of(k);
            let n = runs.len() as i32;
            for (s, verdict) in runs.iter().enumerate() {
                let color = match verdict {
                    Verdict::Accurate => RGBColor(120, 200, 120),
                    Verdict::FailedNamed => RGBColor(240, 190, 80),
                    Verdict::WrongSilently => RGBColor(220, 70, 60),
                    Verdict::Crashed => RGBColor(170, 120, 200),
                    Verdict::Unsupported => RGBColor(200, 200, 200),
                };
                let (y0, y1) = (
                    y + (ch - 3) * s as i32 / n,
                    y + (ch - 3) * (s as i32 + 1) / n,
                );
                root.draw(&Rectangle::new([(x, y0), (x + cw - 3, y1)], color.filled()))
                    .map_err(err)?;
            }
            let label = match runs.iter().all(|v| *v == runs[0]) {
                true if n > 1 => format!("{} ×{n}", runs[0].name()),
                true => runs[0].name().to_string(),
                false => format!("{n} formulations"),
            };
            root.draw(&text(&label, x + 4, y + 10, 11)).map_err(err)?;
        }
    }
    let legend_y = top + ch * rows.len() as i32 + 16;
    root.draw(&text(
        "green: error within 10× the tolerance; amber: stopped with a diagnostic or warned; red: reported success, wrong; purple: crashed; grey: cannot model it",
        6,
        legend_y,
        12,
    ))
    .map_err(err)?;
    root.present().map_err(err)
}
