//! The result of the redundancy analysis and its wording: the counts, the redundant
//! equations in Adams' message format (multibody spec §5.1), the lighter-element advice and
//! the conflict error.

use std::fmt;

use super::catalogue::{
    element_name, element_title, elements_with, equation_order, is_lowerable, older_phrase,
};
use super::offer::Outcome;
use super::problem::{Options, Problem};
use crate::mbd::equations::{Equation, EquationLabel};
use crate::vocab::elements::{ElementKind, ElementRef};

/// The header Adams Solver prints above the deactivated equations.
const ADAMS_HEADER: &str =
    "Degree-of-freedom analysis identified redundant constraints in the model:";

/// One redundant (deactivated) equation.
#[derive(Clone, Debug, PartialEq)]
pub struct Redundant {
    /// Its row in the Jacobian.
    pub row: usize,
    /// What the equation is and which element it belongs to.
    pub label: EquationLabel,
    /// Its relative distance to the span of the kept rows (at most the tolerance): the
    /// certificate that dropping it loses nothing.
    pub distance: f64,
}

/// What would remove an element's redundant equations.
#[derive(Clone, Debug, PartialEq)]
pub enum Lighter {
    /// All the element's equations are redundant: it can go.
    Remove,
    /// Each of these elements (same markers) imposes exactly the kept equations.
    Replace(Vec<ElementKind>),
    /// No single JOINT or JPRIM keeps exactly these equations (or the element is a GCON,
    /// MOTION or 2D prismatic joint that has no lighter form).
    None,
}

/// The advice for one element with redundant equations.
#[derive(Clone, Debug, PartialEq)]
pub struct Advice {
    /// Index of the element in the problem's element list.
    pub element: usize,
    /// Equations it keeps and drops, in Adams' equation order.
    pub kept: Vec<Equation>,
    /// The redundant ones.
    pub dropped: Vec<Equation>,
    /// What would impose only the kept equations.
    pub lighter: Lighter,
}

/// A redundant equation that the assembled configuration violates.
#[derive(Clone, Debug, PartialEq)]
pub struct Conflict {
    /// Its row in the Jacobian.
    pub row: usize,
    /// What the equation is and which element it belongs to.
    pub label: EquationLabel,
    /// Its scaled residual at the assembled configuration.
    pub residual: f64,
    /// Whether the residual is of its velocity equation (Φ_q v + Φ_t) rather than Φ.
    pub velocity: bool,
}

/// The outcome of [`super::analyze`].
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// 2 or 3.
    pub dim: usize,
    /// Moving parts (column blocks).
    pub moving_parts: usize,
    /// Velocity coordinates (6 or 3 per moving part).
    pub columns: usize,
    /// Scalar constraint equations (rows).
    pub equations: usize,
    /// Rank of the Jacobian: independent equations.
    pub rank: usize,
    /// The redundant equations in Adams' message order: descending element, then
    /// descending equation order within an element.
    pub redundant: Vec<Redundant>,
    /// One entry per element with redundant equations, in element order.
    pub advice: Vec<Advice>,
    /// The elements the labels point into (for wording).
    pub elements: Vec<ElementRef>,
    /// The tolerance the rank decisions used.
    pub tolerance: f64,
    /// Non-zeros stored by the factorisation (fill included).
    pub factor_entries: usize,
}

impl Report {
    pub(super) fn build(
        p: &Problem,
        options: &Options,
        rank: usize,
        factor_entries: usize,
        outcomes: Vec<(usize, Outcome)>,
    ) -> Report {
        let mut redundant = Vec::new();
        let mut advice = Vec::new();
        for (element, outcome) in outcomes {
            if outcome.dropped.is_empty() {
                continue;
            }
            let ordered = |rows: &mut Vec<usize>| {
                rows.sort_by_key(|&r| (equation_order(p.labels[r].equation), r));
                rows.iter()
                    .map(|&r| p.labels[r].equation)
                    .collect::<Vec<_>>()
            };
            let kept = ordered(&mut outcome.kept.clone());
            let dropped = ordered(&mut outcome.dropped.iter().map(|&(r, _)| r).collect());
            let kind = p.elements[element].kind;
            let lighter = if kept.is_empty() {
                Lighter::Remove
            } else if is_lowerable(kind) {
                match elements_with(p.dim, kind, &kept) {
                    found if found.is_empty() => Lighter::None,
                    found => Lighter::Replace(found),
                }
            } else {
                Lighter::None
            };
            advice.push(Advice {
                element,
                kept,
                dropped,
                lighter,
            });
            redundant.extend(
                outcome
                    .dropped
                    .into_iter()
                    .map(|(row, distance)| Redundant {
                        row,
                        label: p.labels[row],
                        distance,
                    }),
            );
        }
        advice.sort_by_key(|a| a.element);
        redundant.sort_by_key(|r| {
            std::cmp::Reverse((r.label.element, equation_order(r.label.equation), r.row))
        });
        Report {
            dim: p.dim,
            moving_parts: p.moving_parts,
            columns: p.jacobian.ncols,
            equations: p.jacobian.nrows,
            rank,
            redundant,
            advice,
            elements: p.elements.to_vec(),
            tolerance: options.tolerance,
            factor_entries,
        }
    }

    /// The redundant rows whose residual magnitude exceeds `tolerance` (a residual that is
    /// missing or not finite counts as exceeding it). Spec §5.3: the dropped equations are
    /// checked at assembly and again at every output step.
    pub fn conflicts(&self, residuals: &[f64], tolerance: f64) -> Vec<Conflict> {
        self.redundant
            .iter()
            .filter_map(|r| {
                let residual = residuals.get(r.row).copied().unwrap_or(f64::NAN);
                (residual.is_nan() || residual.abs() > tolerance).then_some(Conflict {
                    row: r.row,
                    label: r.label,
                    residual,
                    velocity: false,
                })
            })
            .collect()
    }

    /// Grübler's count: coordinates minus equations (6·parts − Σ in 3D, 3·parts − Σ in 2D).
    pub fn grubler(&self) -> i64 {
        self.columns as i64 - self.equations as i64
    }

    /// The true degrees of freedom: coordinates minus rank.
    pub fn dof(&self) -> usize {
        self.columns - self.rank
    }

    /// The redundant rows in increasing row order.
    pub fn redundant_rows(&self) -> Vec<usize> {
        let mut rows: Vec<usize> = self.redundant.iter().map(|r| r.row).collect();
        rows.sort_unstable();
        rows
    }

    /// The rows kept for the solve, in increasing order: full rank by construction.
    pub fn kept_rows(&self) -> Vec<usize> {
        let mut dropped = vec![false; self.equations];
        for r in &self.redundant {
            dropped[r.row] = true;
        }
        (0..self.equations).filter(|&r| !dropped[r]).collect()
    }

    /// The largest relative distance of a redundant row to the kept rows' span.
    pub fn largest_distance(&self) -> f64 {
        self.redundant.iter().fold(0.0, |m, r| m.max(r.distance))
    }

    fn element(&self, label: &EquationLabel) -> &ElementRef {
        &self.elements[label.element]
    }

    /// Adams Solver's report (spec §5.1 item 3): a header and one
    /// ` -  deactivating constraint equation  Zi.Xj in model.JOINT_2` line per redundant
    /// equation; `model.` is prefixed when `model` is given. Empty when nothing is redundant.
    pub fn adams_message(&self, model: Option<&str>) -> String {
        if self.redundant.is_empty() {
            return String::new();
        }
        let mut out = format!("{ADAMS_HEADER}\n{}\n", "-".repeat(ADAMS_HEADER.len()));
        for r in &self.redundant {
            let name = element_name(self.element(&r.label));
            let qualified = match model {
                Some(m) => format!("{m}.{name}"),
                None => name,
            };
            out += &format!(
                " -  deactivating constraint equation  {} in {qualified}\n",
                r.label.equation.label()
            );
        }
        out
    }

    /// The older Adams/View wording (spec §5.1 item 4), one line per redundant equation:
    /// `JOINT_7 unnecessarily removes Rotation Between Zi and Xj`.
    pub fn older_message(&self) -> String {
        self.redundant
            .iter()
            .map(|r| {
                format!(
                    "{} unnecessarily removes {}\n",
                    element_name(self.element(&r.label)),
                    older_phrase(r.label.equation)
                )
            })
            .collect()
    }

    /// One line of advice per element with redundant equations, e.g.
    /// `JOINT/4 (REVOLUTE) → JPRIM INLINE would remove these 3 redundant equations (Z Delta, Zi.Xj, Zi.Yj)`.
    pub fn advice_message(&self) -> String {
        let mut out = String::new();
        for a in &self.advice {
            let title = element_title(&self.elements[a.element]);
            let n = a.dropped.len();
            let these = if n == 1 {
                "this redundant equation".to_string()
            } else {
                format!("these {n} redundant equations")
            };
            let list = labels(&a.dropped);
            let line = match &a.lighter {
                Lighter::Remove => {
                    format!("{title}: all its equations are redundant ({list}); remove it")
                }
                Lighter::Replace(kinds) => {
                    let kinds: Vec<String> = kinds.iter().map(|&k| k.phrase()).collect();
                    format!(
                        "{title} → {} would remove {these} ({list})",
                        kinds.join(" or ")
                    )
                }
                Lighter::None => format!(
                    "{title}: {these} ({list}); no single JOINT or JPRIM keeps exactly {}",
                    labels(&a.kept)
                ),
            };
            out += &line;
            out.push('\n');
        }
        out
    }
}

fn labels(eqs: &[Equation]) -> String {
    eqs.iter().map(|e| e.label()).collect::<Vec<_>>().join(", ")
}

impl fmt::Display for Report {
    /// The summary the `check` command prints: counts, Adams' lines and the advice.
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        writeln!(
            f,
            "{} moving parts in {}D: {} coordinates, {} constraint equations, rank {}",
            self.moving_parts, self.dim, self.columns, self.equations, self.rank
        )?;
        writeln!(
            f,
            "Gruebler count {}, degrees of freedom {}, redundant equations {}",
            self.grubler(),
            self.dof(),
            self.redundant.len()
        )?;
        write!(f, "{}{}", self.adams_message(None), self.advice_message())
    }
}

/// Why the analysis could not give a report.
#[derive(Clone, Debug, PartialEq)]
pub enum AnalysisError {
    /// The Jacobian, labels, elements or residuals do not fit together.
    Shape(String),
    /// Redundant equations that the assembled configuration violates: the constraints
    /// contradict each other.
    Conflicting {
        /// The analysis, with the redundant equations.
        report: Box<Report>,
        /// The redundant equations that are violated.
        conflicts: Vec<Conflict>,
    },
}

impl fmt::Display for AnalysisError {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            AnalysisError::Shape(what) => write!(f, "malformed constraint system: {what}"),
            AnalysisError::Conflicting { report, conflicts } => {
                for (i, c) in conflicts.iter().enumerate() {
                    if i > 0 {
                        writeln!(f)?;
                    }
                    let violated = match c.velocity {
                        false => format!("is violated by {:e} at the assembled configuration", c.residual),
                        true => format!(
                            "its velocity equation is violated by {:e} at the assembled configuration \
                             (it holds now but cannot go on holding as time passes)",
                            c.residual
                        ),
                    };
                    write!(
                        f,
                        "conflicting, not redundant: {} of {} follows from the other constraints \
                         but {violated}",
                        c.label.equation.label(),
                        element_title(report.element(&c.label)),
                    )?;
                }
                Ok(())
            }
        }
    }
}

impl std::error::Error for AnalysisError {}
