//! The work-precision grid: every scene × method × tolerance (the Test Set ladder, or
//! halving fixed steps for a fixed-step method), measured one point at a time, with a
//! CPU budget per method so one slow method cannot eat the run; the points as CSV (the
//! format the peer scripts also write) and the cheapest method per accuracy level.

use super::point::{measure, Control, Options, Point, Status, Variant};
use super::scene::{Group, Scene};
use std::fmt::Write as _;

/// The Test Set ladder rtol = 10^−(2+m/2) between `loose` and `tight` (inclusive, to
/// rounding), loosest first.
pub fn ladder(loose: f64, tight: f64) -> Vec<f64> {
    let (a, b) = (-loose.log10(), -tight.log10());
    let mut out = Vec::new();
    let mut m = (2.0 * a).ceil() as i32;
    while f64::from(m) / 2.0 <= b + 1e-9 {
        out.push(10f64.powf(-f64::from(m) / 2.0));
        m += 1;
    }
    out
}

/// Parses `--errors`: `A..B` (the ladder between them) or a comma-separated list.
pub fn parse_errors(text: &str) -> Result<Vec<f64>, String> {
    let num = |s: &str| -> Result<f64, String> {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v > 0.0 && *v < 1.0)
            .ok_or_else(|| format!("`{s}` is not a tolerance in (0, 1)"))
    };
    if let Some((a, b)) = text.split_once("..") {
        let (a, b) = (num(a)?, num(b)?);
        let l = ladder(a.max(b), a.min(b));
        if l.is_empty() {
            return Err(format!("no ladder tolerance lies in {text}"));
        }
        Ok(l)
    } else {
        text.split(',').map(num).collect()
    }
}

/// What the grid runs.
#[derive(Clone, Debug)]
pub struct Grid {
    /// The methods.
    pub variants: Vec<Variant>,
    /// Tolerances for error-controlled methods, loosest first.
    pub errors: Vec<f64>,
    /// Halvings of the output step a fixed-step method tries at most.
    pub halvings: u32,
    /// Once one run of a method on a scene takes longer than this (s), its tighter
    /// settings are skipped.
    pub budget: f64,
    /// Engine, dimension and repetition of each point.
    pub options: Options,
}

/// The settings a method runs at on a scene, loosest first.
pub fn controls(grid: &Grid, scene: &Scene, v: &Variant) -> Vec<Control> {
    if v.fixed {
        (0..=grid.halvings)
            .map(|k| {
                Control::FixedStep(
                    scene
                        .hmax
                        .unwrap_or(scene.output_step * scene.stride() as f64)
                        / f64::from(1u32 << k),
                )
            })
            .collect()
    } else {
        grid.errors.iter().map(|&e| Control::Tolerance(e)).collect()
    }
}

/// Runs `grid` on one scene, handing each point to `each` as it is measured. A method
/// stops climbing its ladder after a run over the budget, or once its error is below
/// 1e-13 (rounding: tighter settings chart nothing new).
pub fn run_scene(
    scene: &Scene,
    grid: &Grid,
    each: &mut dyn FnMut(&Point),
) -> Result<Vec<Point>, String> {
    let text = scene.dataset_text()?;
    let mut points = Vec::new();
    for v in &grid.variants {
        for c in controls(grid, scene, v) {
            let p = measure(scene, &text, *v, c, grid.options);
            each(&p);
            let done = p.cpu > grid.budget || p.errors.worst().is_some_and(|e| e < 1e-13);
            points.push(p);
            if done {
                break;
            }
        }
    }
    Ok(points)
}

/// The CSV header every points file has (mbfx's and the peers').
pub const HEADER: [&str; 14] = [
    "scene",
    "method",
    "formulation",
    "control",
    "setting",
    "error_position",
    "error_reaction",
    "cpu_s",
    "steps",
    "rejected",
    "newton_iterations",
    "factorizations",
    "expression_evaluations",
    "status",
];

/// The columns mbfx's points files add after [`HEADER`] (a peer's file has neither): the
/// kinds of each run's accuracy warnings, its local errors' sum in ERRORs, and its
/// global error estimate in ERRORs with the CPU that took (empty when not asked for).
pub const WARNINGS: [&str; 4] = ["warnings", "error_sum", "error_estimate", "estimate_cpu_s"];

/// The column mbfx's points files add after [`WARNINGS`]: the CPU of the run reading
/// positions only ([`Point::cpu_position`]; empty where the scene reads nothing else).
pub const CPU_POSITION: [&str; 1] = ["cpu_position_s"];

/// The column mbfx's points files add after [`CPU_POSITION`]: the global error estimate
/// the integrator carried through the steps, in ERRORs (empty where it carries none).
pub const GLOBAL_ESTIMATE: [&str; 1] = ["global_estimate"];

/// A point as it is charted: mbfx's own or a peer's, read back from CSV.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The scene.
    pub scene: String,
    /// The curve it belongs to (`gstiff`, `gstiff@3d`, `exudyn-generalized-alpha`, ...).
    pub method: String,
    /// `i3`, `si2` or `-`.
    pub formulation: String,
    /// `tolerance` or `fixed-step`.
    pub control: String,
    /// The tolerance or step.
    pub setting: f64,
    /// Position error.
    pub error_position: Option<f64>,
    /// Reaction error.
    pub error_reaction: Option<f64>,
    /// CPU time, s.
    pub cpu: f64,
    /// CPU time of the run reading positions only, s, where it differs from `cpu`'s run.
    pub cpu_position: Option<f64>,
    /// Counters (None where a peer does not report them).
    pub counters: [Option<usize>; 5],
    /// `ok` or `failed: why`.
    pub status: String,
    /// The kinds of the run's accuracy warnings (see [`super::alarms::kinds`]), `;`
    /// between them; empty when it gave none (and for a peer's run).
    pub warnings: String,
    /// The accepted steps' local error estimates added up, in units of ERROR (None for
    /// a peer's run).
    pub error_sum: Option<f64>,
    /// The global error estimate in units of ERROR (`bench wp --estimate-error`).
    pub error_estimate: Option<f64>,
    /// The CPU the estimate's second run took, s.
    pub estimate_cpu: Option<f64>,
    /// The global error estimate the steps carried, in units of ERROR (None where the
    /// method carries none, and for a peer's run).
    pub global_estimate: Option<f64>,
}

impl Row {
    /// The row of a measured point; `tag` marks a variation of the method (`3d`,
    /// `interp`) in the curve's name.
    pub fn of(p: &Point, tag: Option<&str>) -> Row {
        Row {
            scene: p.scene.clone(),
            method: match tag {
                Some(t) => format!("{}@{t}", p.variant.name),
                None => p.variant.name.to_string(),
            },
            formulation: p.variant.formulation_name().to_string(),
            control: p.control.kind().to_string(),
            setting: p.control.value(),
            error_position: p.errors.position,
            error_reaction: p.errors.reaction,
            cpu: p.cpu,
            cpu_position: p.cpu_position,
            counters: [
                Some(p.stats.steps),
                Some(p.stats.rejected),
                Some(p.stats.newton_iterations),
                Some(p.stats.factorizations),
                Some(p.stats.expression_evaluations),
            ],
            status: match &p.status {
                Status::Ok => "ok".into(),
                Status::Failed(why) => format!("failed: {why}"),
            },
            warnings: super::alarms::kinds(&p.warnings),
            error_sum: Some(p.stats.error_sum),
            error_estimate: p.estimate.map(|e| e.error),
            estimate_cpu: p.estimate.map(|e| e.cpu_seconds),
            global_estimate: p.stats.global_error,
        }
    }

    /// The error of a group.
    pub fn error(&self, g: Group) -> Option<f64> {
        match g {
            Group::Position => self.error_position,
            Group::Reaction => self.error_reaction,
        }
    }

    /// The CPU time that pays for a group's error: positions alone, where a run that
    /// reads only them was measured, else the run's.
    pub fn cpu_of(&self, g: Group) -> f64 {
        match g {
            Group::Position => self.cpu_position.unwrap_or(self.cpu),
            Group::Reaction => self.cpu,
        }
    }

    /// Whether the run reached its end.
    pub fn ok(&self) -> bool {
        self.status == "ok"
    }
}

/// Writes rows as CSV with [`HEADER`].
pub fn write_csv(path: &std::path::Path, rows: &[Row]) -> Result<(), String> {
    let fail = |e: csv::Error| format!("{}: {e}", path.display());
    let mut w = csv::Writer::from_path(path).map_err(fail)?;
    let mut header = HEADER.to_vec();
    header.extend(WARNINGS);
    header.extend(CPU_POSITION);
    header.extend(GLOBAL_ESTIMATE);
    w.write_record(&header).map_err(fail)?;
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:e}"));
    for r in rows {
        let mut rec = vec![
            r.scene.clone(),
            r.method.clone(),
            r.formulation.clone(),
            r.control.clone(),
            format!("{:e}", r.setting),
            opt(r.error_position),
            opt(r.error_reaction),
            format!("{:e}", r.cpu),
        ];
        rec.extend(
            r.counters
                .iter()
                .map(|c| c.map_or(String::new(), |c| c.to_string())),
        );
        rec.push(r.status.clone());
        rec.push(r.warnings.clone());
        rec.push(opt(r.error_sum));
        rec.push(opt(r.error_estimate));
        rec.push(opt(r.estimate_cpu));
        rec.push(opt(r.cpu_position));
        rec.push(opt(r.global_estimate));
        w.write_record(&rec).map_err(fail)?;
    }
    w.flush().map_err(|e| format!("{}: {e}", path.display()))
}

/// The fields of every record of the CSV file at `path` under the columns `names`
/// (found by the header; trimmed, "" where a record is short), each with its line in
/// the file; or why the file, a record or a column could not be read.
pub fn read_columns<const N: usize>(
    path: &std::path::Path,
    names: [&str; N],
) -> Result<Vec<(usize, [String; N])>, String> {
    let at = |e: String| format!("{}: {e}", path.display());
    let mut r = csv::Reader::from_path(path).map_err(|e| at(e.to_string()))?;
    let header = r.headers().map_err(|e| at(e.to_string()))?.clone();
    let mut idx = [0; N];
    for (i, name) in idx.iter_mut().zip(names) {
        *i = header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| at(format!("no `{name}` column")))?;
    }
    r.records()
        .enumerate()
        .map(|(line, rec)| {
            let rec = rec.map_err(|e| at(e.to_string()))?;
            Ok((
                line + 2,
                idx.map(|k| rec.get(k).unwrap_or("").trim().to_string()),
            ))
        })
        .collect()
}

/// Reads a points CSV (mbfx's or a peer's) by its header's names.
pub fn read_csv(path: &std::path::Path) -> Result<Vec<Row>, String> {
    let mut rows = Vec::new();
    let extra: Vec<[String; 4]> = match read_columns(path, WARNINGS) {
        Ok(w) => w.into_iter().map(|(_, w)| w).collect(),
        Err(_) => Vec::new(), // a peer's file
    };
    // (Files written before the column have none.)
    let cpu_position: Vec<Option<f64>> = match read_columns(path, CPU_POSITION) {
        Ok(c) => c.into_iter().map(|(_, [c])| c.parse().ok()).collect(),
        Err(_) => Vec::new(),
    };
    let global: Vec<Option<f64>> = match read_columns(path, GLOBAL_ESTIMATE) {
        Ok(c) => c.into_iter().map(|(_, [c])| c.parse().ok()).collect(),
        Err(_) => Vec::new(),
    };
    for (k, (line, f)) in read_columns(path, HEADER)?.into_iter().enumerate() {
        let float = |k: usize| -> Result<Option<f64>, String> {
            let s = &f[k];
            if s.is_empty() {
                return Ok(None);
            }
            s.parse::<f64>()
                .map(Some)
                .map_err(|_| format!("{}: row {line}: `{s}` is not a number", path.display()))
        };
        let count = |k: usize| f[k].parse::<usize>().ok();
        rows.push(Row {
            scene: f[0].clone(),
            method: f[1].clone(),
            formulation: f[2].clone(),
            control: f[3].clone(),
            setting: float(4)?.unwrap_or(f64::NAN),
            error_position: float(5)?,
            error_reaction: float(6)?,
            cpu: float(7)?.unwrap_or(f64::NAN),
            counters: [count(8), count(9), count(10), count(11), count(12)],
            status: f[13].clone(),
            warnings: extra.get(k).map(|e| e[0].clone()).unwrap_or_default(),
            error_sum: extra.get(k).and_then(|e| e[1].parse().ok()),
            error_estimate: extra.get(k).and_then(|e| e[2].parse().ok()),
            estimate_cpu: extra.get(k).and_then(|e| e[3].parse().ok()),
            cpu_position: cpu_position.get(k).copied().flatten(),
            global_estimate: global.get(k).copied().flatten(),
        });
    }
    Ok(rows)
}

/// The cheapest finished run whose `group` error is at most `level`.
pub fn cheapest(rows: &[Row], group: Group, level: f64) -> Option<&Row> {
    rows.iter()
        .filter(|r| r.ok() && r.error(group).is_some_and(|e| e <= level))
        .filter(|r| r.cpu_of(group).is_finite())
        .min_by(|a, b| a.cpu_of(group).total_cmp(&b.cpu_of(group)))
}

/// The markdown table of the cheapest method per accuracy level of one scene, for each
/// group it scores: mbfx's best, and beside it the best peer's when peers ran.
pub fn summary_table(scene: &Scene, rows: &[Row]) -> String {
    let mut s = String::new();
    let is_peer = |r: &Row| r.method.starts_with("exudyn") || r.method.starts_with("mujoco");
    let ours: Vec<Row> = rows.iter().filter(|r| !is_peer(r)).cloned().collect();
    let peers: Vec<Row> = rows.iter().filter(|r| is_peer(r)).cloned().collect();
    for g in scene.groups() {
        let _ = writeln!(s, "\n{} error ({}):\n", g.name(), scene.title);
        if peers.is_empty() {
            let _ = writeln!(s, "| error ≤ | cheapest method | setting | CPU s | steps |");
            let _ = writeln!(s, "|---|---|---|---|---|");
        } else {
            let _ = writeln!(
                s,
                "| error ≤ | cheapest mbfx method | setting | CPU s | best peer | setting | CPU s | peer / mbfx |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
        }
        for k in 2..=12 {
            let level = 10f64.powi(-k);
            let a = cheapest(&ours, g, level);
            let b = cheapest(&peers, g, level);
            if a.is_none() && b.is_none() {
                continue;
            }
            let cell = |r: Option<&Row>| match r {
                Some(r) => format!("{} | {:.0e} | {:.3e}", label(r), r.setting, r.cpu_of(g)),
                None => "— | | ".to_string(),
            };
            if peers.is_empty() {
                let steps = a
                    .and_then(|r| r.counters[0])
                    .map_or(String::new(), |n| n.to_string());
                let _ = writeln!(s, "| 1e-{k} | {} | {steps} |", cell(a));
            } else {
                let ratio = match (a, b) {
                    (Some(a), Some(b)) => format!("{:.1}×", b.cpu_of(g) / a.cpu_of(g)),
                    _ => "—".into(),
                };
                let _ = writeln!(s, "| 1e-{k} | {} | {} | {ratio} |", cell(a), cell(b));
            }
        }
    }
    s
}

/// A curve's label: the method, with its formulation when that is not in the name.
pub fn label(r: &Row) -> String {
    if r.formulation == "-" || r.method.contains(&r.formulation) || r.formulation == "i3" {
        r.method.clone()
    } else {
        format!("{} ({})", r.method, r.formulation)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ladder_is_the_test_sets() {
        let l = ladder(1e-2, 1e-10);
        assert_eq!(l.len(), 17);
        assert!((l[1] / 10f64.powf(-2.5) - 1.0).abs() < 1e-12);
        assert!((l[16] / 1e-10 - 1.0).abs() < 1e-12);
        assert_eq!(parse_errors("1e-3,1e-6").unwrap(), vec![1e-3, 1e-6]);
        assert_eq!(parse_errors("1e-4..1e-3").unwrap().len(), 3);
        assert!(parse_errors("2..1e-3").is_err());
    }

    #[test]
    fn csv_round_trips_and_cheapest_picks_by_cpu() {
        let row = |m: &str, e: f64, cpu: f64| Row {
            scene: "a01".into(),
            method: m.into(),
            formulation: "-".into(),
            control: "tolerance".into(),
            setting: 1e-6,
            error_position: Some(e),
            error_reaction: Some(e),
            cpu,
            // hht's positions alone cost a tenth of its run with the reactions.
            cpu_position: (m == "hht").then_some(cpu / 10.0),
            counters: [Some(3), None, Some(1), Some(2), Some(0)],
            status: "ok".into(),
            warnings: if m == "x" {
                "error-sum".into()
            } else {
                String::new()
            },
            error_sum: Some(12.5),
            error_estimate: (m == "x").then_some(3.5),
            estimate_cpu: (m == "x").then_some(2e-5),
            global_estimate: (m == "x").then_some(0.25),
        };
        let rows = vec![
            row("hht", 1e-7, 0.5),
            row("gstiff", 5e-7, 0.1),
            row("x", 1e-3, 1e-4),
        ];
        let path = std::env::temp_dir().join(format!("mbfx-wp-{}.csv", std::process::id()));
        write_csv(&path, &rows).unwrap();
        let back = read_csv(&path).unwrap();
        let _ = std::fs::remove_file(&path);
        assert_eq!(back, rows);
        // Positions are charged the run that reads them alone, reactions the full one.
        let cheapest_at = |g, level| cheapest(&rows, g, level).unwrap().method.as_str();
        assert_eq!(cheapest_at(Group::Position, 1e-6), "hht");
        assert_eq!(cheapest_at(Group::Reaction, 1e-6), "gstiff");
        assert_eq!(cheapest_at(Group::Reaction, 2e-7), "hht");
        assert_eq!(cheapest_at(Group::Position, 1e-2), "x");
        assert!(cheapest(&rows, Group::Position, 1e-8).is_none());
        assert_eq!(rows[0].cpu_of(Group::Position), 0.05);
        assert_eq!(rows[0].cpu_of(Group::Reaction), 0.5);
    }
}
