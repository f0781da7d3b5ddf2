//! Whether a run's accuracy warnings mean something (issue 25 §3): over a bench's
//! points, the false alarms (runs scored accurate that warned) and the detection (runs
//! scored wrong that warned or stopped with a named failure).
//!
//! A tolerance-controlled run is accurate when its error against the truth (positions
//! where the scene scores them, else reactions) is at most 10·ERROR, the stability
//! suite's rule; fixed-step runs have no ERROR to hold and are left out.

use super::wp::Row;
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// The kind of each accuracy warning of a run's summary, joined by `;` (`error-sum`,
/// `energy`, `fixed-step`, `drift`, `other`): what the points file keeps of them.
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
        } else {
            "other"
        }
    };
    warnings.iter().map(kind).collect::<Vec<_>>().join(";")
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
    let e = r.error_position.or(r.error_reaction);
    Some(match e.is_some_and(|e| e <= 10.0 * r.setting) {
        true => Judged::Accurate,
        false => Judged::Wrong,
    })
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
    /// Counts `r`.
    pub fn add(&mut self, r: &Row) {
        let warned = !r.warnings.is_empty();
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

/// The markdown report: per method and in all, with the wrong runs no warning caught.
pub fn report(rows: &[Row]) -> String {
    let mut by_method: BTreeMap<&str, Tally> = BTreeMap::new();
    let mut all = Tally::default();
    for r in rows {
        by_method.entry(&r.method).or_default().add(r);
        all.add(r);
    }
    let pct = |a: usize, b: usize| match b {
        0 => "—".to_string(),
        _ => format!("{:.1} %", 100.0 * a as f64 / b as f64),
    };
    let mut out = String::from(
        "# Accuracy warnings: false alarms and detection\n\n\
         Every tolerance-controlled run of `mbfx bench wp`: accurate when its error is at \
         most 10·ERROR; a false alarm is an accurate run that printed an accuracy warning; \
         a wrong run is detected when it warned or stopped with a named failure \
         (goals: false alarms ≤ 5 % of accurate runs, detection 100 %).\n\n\
         | method | accurate runs | false alarms | wrong or stopped | detected |\n\
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
        .filter(|r| judge(r) == Some(Judged::Wrong) && r.warnings.is_empty())
        .collect();
    if !missed.is_empty() {
        out += "\nWrong without a warning:\n\n| scene | method | ERROR | error |\n|---|---|---:|---:|\n";
        for r in missed {
            let e = r.error_position.or(r.error_reaction);
            let e = e.map_or("—".into(), |e| format!("{e:.2e}"));
            let _ = writeln!(
                out,
                "| {} | {} | {:e} | {e} |",
                r.scene, r.method, r.setting
            );
        }
    }
    out
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
        t.add(&row("a", 5e-6, "ok", "")); // accurate, quiet
        t.add(&row("a", 9e-6, "ok", "error-sum")); // accurate (under 10·ERROR), a false alarm
        t.add(&row("a", 2e-5, "ok", "")); // wrong, silent
        t.add(&row("a", 2e-5, "ok", "energy")); // wrong, caught
        t.add(&row("a", 1e-9, "failed: E0802", "")); // stopped: caught
        let mut fixed = row("a", 1.0, "ok", "");
        fixed.control = "fixed-step".into();
        t.add(&fixed); // no ERROR: not counted
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
