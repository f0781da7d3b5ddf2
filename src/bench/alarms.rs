//! Whether a run's accuracy warnings mean something (issue 25 §3): over a bench's
//! points, the false alarms (runs scored accurate that warned) and the detection (runs
//! scored wrong that warned or stopped with a named failure).
//!
//! A tolerance-controlled run is accurate when its error against the truth (positions
//! where the scene scores them, else reactions) is at most 10·ERROR, the stability
//! suite's rule; fixed-step runs have no ERROR to hold and are left out.

use super::wp::Row;
use crate::session::run::ACCUMULATED_WARNING;
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// The kind of each accuracy warning of a run's summary, joined by `;` (`error-sum`,
/// `energy`, `fixed-step`, `drift`, `estimate`, `other`): what the points file keeps of
/// them.
pub fn kinds(warnings: &[String]) -> String {
    let kind = |w: &String| {
        if w.starts_with("the steps' local error estimates") {
            "error-sum"
        } else if w.starts_with("the energy changed") {
            "energy"
        } else if w.starts_with("fixed steps") {
            "fixed-step"
        } else if w.starts_with("the constraints drifted") {
            "drift"
        } else if w.starts_with("the answer's error is estimated") {
            "estimate"
        } else if w.starts_with("the estimated global error") {
            "global"
        } else {
            "other"
        }
    };
    warnings.iter().map(kind).collect::<Vec<_>>().join(";")
}

/// Which of a run's warnings count: a run by default, with `--estimate-error` (the
/// second run) or with `--estimate-error=steps` (the carried estimate).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// What `mbfx run` prints by default: every warning but the estimates', and the
    /// local errors' sum where the estimates took its place.
    Default,
    /// Every warning but the carried estimate's.
    Estimated,
    /// Every warning but the second run's, and the local errors' sum where the run
    /// carried no estimate (a method that has none).
    Carried,
}

impl View {
    /// Whether `r` warned, as this view counts.
    pub fn warned(self, r: &Row) -> bool {
        let kinds = r.warnings.split(';').filter(|k| !k.is_empty());
        // An estimated run does not print the sum's warning; without the estimate it
        // would have, past the same threshold.
        let sum = (r.error_estimate.is_some() || r.global_estimate.is_some())
            && r.error_sum.is_some_and(|s| s > ACCUMULATED_WARNING);
        let mut kinds = kinds;
        match self {
            View::Estimated => kinds.any(|k| k != "global"),
            View::Default => sum || kinds.any(|k| k != "estimate" && k != "global"),
            View::Carried => {
                let uncarried = r.global_estimate.is_none() && sum;
                uncarried || kinds.any(|k| k != "estimate")
            }
        }
    }
}

/// How a run is judged against its ERROR.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Judged {
    /// Error at most 10·ERROR.
    Accurate,
    /// Reached its end with a larger error (or none to score).
    Wrong,
    /// Stopped with a named failure.
    Failed,
}

/// The judgement of `r`, or None for a run with no ERROR (fixed steps).
pub fn judge(r: &Row) -> Option<Judged> {
    if r.control != "tolerance" {
        return None;
    }
    if !r.ok() {
        return Some(Judged::Failed);
    }
    Some(match error(r).is_some_and(|e| e <= 10.0 * r.setting) {
        true => Judged::Accurate,
        false => Judged::Wrong,
    })
}

/// The error a run is judged by: positions where the scene scores them, else reactions.
fn error(r: &Row) -> Option<f64> {
    r.error_position.or(r.error_reaction)
}

/// The counts of one method (or of all).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Accurate runs.
    pub accurate: usize,
    /// Accurate runs that warned.
    pub false_alarms: usize,
    /// Runs that finished wrong or stopped.
    pub wrong: usize,
    /// Of those, the ones that warned or stopped with a named failure.
    pub detected: usize,
}

impl Tally {
    /// Counts `r`, its warnings as `view` counts them.
    pub fn add(&mut self, r: &Row, view: View) {
        let warned = view.warned(r);
        match judge(r) {
            None => {}
            Some(Judged::Accurate) => {
                self.accurate += 1;
                self.false_alarms += usize::from(warned);
            }
            Some(Judged::Failed) => {
                self.wrong += 1;
                self.detected += 1;
            }
            Some(Judged::Wrong) => {
                self.wrong += 1;
                self.detected += usize::from(warned);
            }
        }
    }
}

fn pct(a: usize, b: usize) -> String {
    match b {
        0 => "—".to_string(),
        _ => format!("{:.1} %", 100.0 * a as f64 / b as f64),
    }
}

/// The table of one view: per method and in all, then the wrong runs it missed.
fn view_table(rows: &[Row], view: View) -> String {
    let mut by_method: BTreeMap<&str, Tally> = BTreeMap::new();
    let mut all = Tally::default();
    for r in rows {
        by_method.entry(&r.method).or_default().add(r, view);
        all.add(r, view);
    }
    let mut out = String::from(
        "| method | accurate runs | false alarms | wrong or stopped | detected |\n\
         |---|---:|---:|---:|---:|\n",
    );
    let mut line = |name: &str, t: &Tally| {
        let _ = writeln!(
            out,
            "| {name} | {} | {} ({}) | {} | {} ({}) |",
            t.accurate,
            t.false_alarms,
            pct(t.false_alarms, t.accurate),
            t.wrong,
            t.detected,
            pct(t.detected, t.wrong)
        );
    };
    for (m, t) in &by_method {
        line(m, t);
    }
    line("**all**", &all);
    let missed: Vec<&Row> = rows
        .iter()
        .filter(|r| judge(r) == Some(Judged::Wrong) && !view.warned(r))
        .collect();
    if !missed.is_empty() {
        out += "\nWrong without a warning (the estimate: when one was made, in the error's units):\n\n| scene | method | ERROR | error | estimate |\n|---|---|---:|---:|---:|\n";
        for r in missed.iter().take(MISSED_LISTED) {
            let e = error(r).map_or("—".into(), |e| format!("{e:.2e}"));
            let est = r
                .error_estimate
                .map_or("—".into(), |x| format!("{:.2e}", x * r.setting));
            let _ = writeln!(
                out,
                "| {} | {} | {:e} | {e} | {est} |",
                r.scene, r.method, r.setting
            );
        }
        if missed.len() > MISSED_LISTED {
            let _ = writeln!(
                out,
                "\n… and {} more (each scene's CSV has them all).",
                missed.len() - MISSED_LISTED
            );
        }
    }
    out
}

/// The missed runs a table lists at most.
const MISSED_LISTED: usize = 30;

/// The q-quantile of `v` (sorted here), None when empty.
fn quantile(v: &mut [f64], q: f64) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    let k = ((v.len() as f64 - 1.0) * q).round() as usize;
    v.get(k).copied()
}

/// How the estimate compares with the error, and what it cost: the ratio estimate /
/// error over finished runs, its CPU against the runs'.
fn estimate_section(rows: &[Row]) -> String {
    let est: Vec<&Row> = rows.iter().filter(|r| r.error_estimate.is_some()).collect();
    let mut ratio: Vec<f64> = est
        .iter()
        .filter_map(|r| Some(r.error_estimate? * r.setting / error(r).filter(|e| *e > 0.0)?))
        .collect();
    let mut cost: Vec<f64> = est
        .iter()
        .filter_map(|r| Some(r.estimate_cpu? / r.cpu))
        .filter(|c| c.is_finite())
        .collect();
    let total = |f: &dyn Fn(&Row) -> f64| est.iter().map(|r| f(r)).sum::<f64>();
    let share = total(&|r| r.estimate_cpu.unwrap_or(0.0)) / total(&|r| r.cpu);
    let not_made = rows
        .iter()
        .filter(|r| r.ok() && r.control == "tolerance" && r.error_estimate.is_none())
        .count();
    let q = |v: &mut [f64], p| quantile(v, p).map_or("—".into(), |x| format!("{x:.3}"));
    format!(
        "\nThe estimate against the error (estimate / error over {} finished runs with one): \
         5th percentile {}, median {}, 95th percentile {}. Finished error-controlled runs \
         left without an estimate (a fully driven model, or the second run stopped): {not_made}. Its CPU: {:.1} % of \
         the runs' in all; per run, median {:.1} %, 95th percentile {:.1} %.\n",
        ratio.len(),
        q(&mut ratio, 0.05),
        q(&mut ratio, 0.5),
        q(&mut ratio, 0.95),
        100.0 * share,
        100.0 * quantile(&mut cost, 0.5).unwrap_or(f64::NAN),
        100.0 * quantile(&mut cost, 0.95).unwrap_or(f64::NAN),
    )
}

/// The markdown report: per method and in all, with the wrong runs no warning caught;
/// again with the global error estimate when the runs made one.
pub fn report(rows: &[Row]) -> String {
    let mut out = String::from(
        "# Accuracy warnings: false alarms and detection\n\n\
         Every tolerance-controlled run of `mbfx bench wp`: accurate when its error is at \
         most 10·ERROR; a false alarm is an accurate run that printed an accuracy warning; \
         a wrong run is detected when it warned or stopped with a named failure \
         (goals: false alarms ≤ 5 % of accurate runs, detection 100 %).\n\n\
         ## By default (`mbfx run`)\n\n",
    );
    out += &view_table(rows, View::Default);
    if rows.iter().any(|r| r.error_estimate.is_some()) {
        out += "\n## With the global error estimate (`mbfx run --estimate-error`)\n\n";
        out += &view_table(rows, View::Estimated);
        out += &estimate_section(rows);
    }
    if rows.iter().any(|r| r.global_estimate.is_some()) {
        out +=
            "\n## With the error carried through the steps (`mbfx run --estimate-error=steps`)\n\n";
        out += "The methods that carry none (all but GSTIFF and WSTIFF) warn from the local errors' sum, as by default.\n\n";
        out += &view_table(rows, View::Carried);
        out += &carried_section(rows);
    }
    out
}

/// How the carried estimate compares with the error: the ratio estimate / error over
/// the finished runs that carried one.
fn carried_section(rows: &[Row]) -> String {
    let mut ratio: Vec<f64> = rows
        .iter()
        .filter(|r| r.ok() && r.control == "tolerance")
        .filter_map(|r| Some(r.global_estimate? * r.setting / error(r).filter(|e| *e > 0.0)?))
        .collect();
    let q = |v: &mut [f64], p| quantile(v, p).map_or("—".into(), |x| format!("{x:.3}"));
    format!(
        "\nThe carried estimate against the error (estimate / error over {} finished runs \
         with one): 5th percentile {}, 25th {}, median {}, 75th {}, 95th percentile {}.\n",
        ratio.len(),
        q(&mut ratio, 0.05),
        q(&mut ratio, 0.25),
        q(&mut ratio, 0.5),
        q(&mut ratio, 0.75),
        q(&mut ratio, 0.95),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(method: &str, error: f64, status: &str, warnings: &str) -> Row {
        Row {
            scene: "s".into(),
            method: method.into(),
            formulation: "-".into(),
            control: "tolerance".into(),
            setting: 1e-6,
            error_position: Some(error),
            error_reaction: None,
            cpu: 1e-3,
            cpu_position: None,
            counters: [None; 5],
            status: status.into(),
            warnings: warnings.into(),
            error_sum: None,
            error_estimate: None,
            estimate_cpu: None,
            global_estimate: None,
        }
    }

    #[test]
    fn warnings_are_kept_by_kind() {
        let w = [
            "the steps' local error estimates add up to 83×ERROR".to_string(),
            "the energy changed by 1e-3".to_string(),
        ];
        assert_eq!(kinds(&w), "error-sum;energy");
        assert_eq!(kinds(&[]), "");
    }

    #[test]
    fn a_tally_counts_alarms_against_the_ten_times_error_rule() {
        let mut t = Tally::default();
        t.add(&row("a", 5e-6, "ok", ""), View::Default); // accurate, quiet
        t.add(&row("a", 9e-6, "ok", "error-sum"), View::Default); // accurate (under 10·ERROR), a false alarm
        t.add(&row("a", 2e-5, "ok", ""), View::Default); // wrong, silent
        t.add(&row("a", 2e-5, "ok", "energy"), View::Default); // wrong, caught
        t.add(&row("a", 1e-9, "failed: E0802", ""), View::Default); // stopped: caught
        let mut fixed = row("a", 1.0, "ok", "");
        fixed.control = "fixed-step".into();
        t.add(&fixed, View::Default); // no ERROR: not counted
                                      // The carried estimate's warning counts in its own view only.
        let mut carried = row("a", 5e-6, "ok", "global");
        carried.global_estimate = Some(40.0);
        assert!(View::Carried.warned(&carried));
        assert!(!View::Default.warned(&carried) && !View::Estimated.warned(&carried));
        assert_eq!(
            t,
            Tally {
                accurate: 2,
                false_alarms: 1,
                wrong: 3,
                detected: 2
            }
        );
        let text = report(&[row("a", 2e-5, "ok", "")]);
        assert!(text.contains("| s | a | 1e-6 | 2.00e-5 |"), "{text}");
    }
}
