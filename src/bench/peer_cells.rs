//! The peers' stability cells: `stability.csv` written by `benches/peers/`
//! (`case,scene,peer,method,formulation,setting,error,status,verdict,note`), judged again
//! here by the suite's own rule so that a peer's cell means what an mbfx cell means.

use super::stability::{Case, Verdict};
use super::wp::read_columns;
use std::fmt::Write as _;
use std::path::Path;

/// One peer run of one case.
#[derive(Clone, Debug)]
pub struct PeerCell {
    /// The case's index in the suite.
    pub case: usize,
    /// `exudyn-…` or `mujoco-…`.
    pub method: String,
    /// How the peer models the scene (its own element names).
    pub formulation: String,
    /// The peer's setting, in its own words (`rtol 1e-6`, `h 2e-3 (default)`).
    pub setting: String,
    /// The judged error, when the run finished.
    pub error: Option<f64>,
    /// `ok`, `failed: …`, `crashed: …` or `unsupported: …`.
    pub status: String,
    /// What the script saw beside the result (the peer's warnings).
    pub note: String,
    /// The verdict by the suite's rule.
    pub verdict: Verdict,
}

impl PeerCell {
    /// The column this cell belongs to: method and formulation.
    pub fn column(&self) -> String {
        format!("{} ({})", self.method, self.formulation)
    }
}

/// Reads `path`. `stops[i]` says whether case `i`'s truth is that the run must stop.
/// A row naming an unknown case is an error (the suite and the script disagree).
pub fn read(path: &Path, cases: &[Case], stops: &[bool]) -> Result<Vec<PeerCell>, String> {
    let names = [
        "case",
        "method",
        "formulation",
        "setting",
        "error",
        "status",
        "verdict",
        "note",
    ];
    let at = |line: usize, e: String| format!("{}: row {line}: {e}", path.display());
    let mut cells = Vec::new();
    for (line, f) in read_columns(path, names)? {
        let [id, method, formulation, setting, error, status, verdict, note] = f;
        let index = cases
            .iter()
            .position(|c| c.id == id)
            .ok_or_else(|| at(line, format!("no case `{id}` in the suite")))?;
        let err = match error.as_str() {
            "" => None,
            e => Some(
                e.parse::<f64>()
                    .map_err(|_| at(line, format!("error `{e}`")))?,
            ),
        };
        let warned = verdict == Verdict::FailedNamed.name();
        cells.push(PeerCell {
            case: index,
            verdict: judge(&status, err, warned, cases[index].tolerance, stops[index]),
            method,
            formulation,
            setting,
            error: err,
            status,
            note,
        });
    }
    Ok(cells)
}

/// The suite's rule for a peer's run. `warned`: the script saw the peer say the run
/// went wrong although it finished.
pub fn judge(
    status: &str,
    error: Option<f64>,
    warned: bool,
    tolerance: f64,
    must_stop: bool,
) -> Verdict {
    if status.starts_with("unsupported") {
        Verdict::Unsupported
    } else if status.starts_with("crashed") {
        Verdict::Crashed
    } else if status != "ok" {
        Verdict::FailedNamed
    } else if !must_stop && error.is_some_and(|e| e <= 10.0 * tolerance) {
        Verdict::Accurate
    } else if warned {
        Verdict::FailedNamed
    } else {
        Verdict::WrongSilently
    }
}

/// The peers' matrix as markdown: one row per case, one column per method and
/// formulation; a cell is the verdict, the error and the setting.
pub fn markdown(cases: &[Case], cells: &[PeerCell]) -> String {
    let mut columns: Vec<String> = Vec::new();
    for c in cells {
        if !columns.contains(&c.column()) {
            columns.push(c.column());
        }
    }
    let mut s = String::from("| case |");
    for c in &columns {
        let _ = write!(s, " {c} |");
    }
    s += "\n|---|";
    s += &"---|".repeat(columns.len());
    s += "\n";
    for (i, case) in cases.iter().enumerate() {
        let row: Vec<&PeerCell> = cells.iter().filter(|c| c.case == i).collect();
        if row.is_empty() {
            continue;
        }
        let _ = write!(s, "| {} |", case.id);
        for col in &columns {
            let found: Vec<String> = row
                .iter()
                .filter(|c| c.column() == *col)
                .map(|c| {
                    let e = c.error.map_or(String::new(), |e| format!(" ({e:.0e})"));
                    format!("{}{e}, {}", c.verdict.name(), c.setting)
                })
                .collect();
            let _ = write!(s, " {} |", found.join("; "));
        }
        s += "\n";
    }
    s
}

/// What each peer's failed, crashed or unsupported cell said (and what the script saw).
pub fn details(cases: &[Case], cells: &[PeerCell]) -> String {
    let mut s = String::new();
    for c in cells {
        // an accurate cell needs no words; a silent one said none
        if matches!(c.verdict, Verdict::Accurate | Verdict::WrongSilently) {
            continue;
        }
        let why = if c.note.is_empty() {
            c.status.clone()
        } else {
            format!("{} ({})", c.status, c.note)
        };
        let _ = writeln!(
            s,
            "- {} / {}, {}: {why}",
            cases[c.case].id,
            c.column(),
            c.setting
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_peer_is_judged_by_the_suites_rule() {
        // tolerance 1e-3: accurate up to 1e-2
        assert_eq!(
            judge("ok", Some(9e-3), false, 1e-3, false),
            Verdict::Accurate
        );
        assert_eq!(
            judge("ok", Some(2e-2), false, 1e-3, false),
            Verdict::WrongSilently
        );
        assert_eq!(
            judge("ok", Some(2e-2), true, 1e-3, false),
            Verdict::FailedNamed
        );
        assert_eq!(
            judge("ok", None, false, 1e-3, false),
            Verdict::WrongSilently
        );
        // a lock-up must stop: finishing accurately up to it is still wrong
        assert_eq!(
            judge("ok", Some(0.0), false, 1e-6, true),
            Verdict::WrongSilently
        );
        assert_eq!(
            judge("failed: Newton", None, false, 1e-6, true),
            Verdict::FailedNamed
        );
        assert_eq!(
            judge("crashed: SIGSEGV", None, false, 1e-6, false),
            Verdict::Crashed
        );
        assert_eq!(
            judge("unsupported: no IMPACT", None, false, 1e-6, false),
            Verdict::Unsupported
        );
    }
}
