//! The multibody sections of the model report `mbfx check` prints (2D or 3D and why,
//! degrees of freedom, assembly, redundant constraints), and the diagnostics of a failed
//! analysis or run, placed on the statement of the element at fault.

use super::stopped::Stopped;
use super::{Analysis, DimRequest, Failure};
use crate::diag::{Code, Diagnostic, Span};
use crate::mbd::assembly::AssemblyError;
use crate::mbd::dynamics::{Culprit, DynError};
use crate::mbd::error::MbdError;
use crate::mbd::expr::ExprError;
use crate::mbd::redundancy::AnalysisError;
use crate::mbd::statics::Failure as StaticFailure;
use crate::mbd::system::{Dimension, System};
use crate::model::elements::{Model, Named};
use crate::model::report::ReportSection;
use crate::model::states::Statement;
use crate::vocab::elements::{ElementKind, ElementRef};

/// `built in 2D: why` (or 3D), from the system's reason.
fn dimension_line(system: &System, asked: DimRequest) -> String {
    let d = match system.dim {
        Dimension::Two => "2D",
        Dimension::Three => "3D",
    };
    let why = system
        .dim_reason
        .split_once(": ")
        .map_or(system.dim_reason.as_str(), |(_, w)| w);
    let why = if asked == DimRequest::Three {
        "asked for with --dim 3"
    } else {
        why
    };
    format!("built in {d}: {why}")
}

/// The sections of a successful analysis: scene, degrees of freedom, assembly,
/// redundant constraints.
pub fn sections(a: &Analysis, asked: DimRequest) -> Vec<ReportSection> {
    let r = &a.redundancy;
    let per = r.columns.checked_div(r.moving_parts).unwrap_or(0);
    let dof = vec![
        format!(
            "Gruebler count {} ({per}·{} moving parts − {} equations)",
            r.grubler(),
            r.moving_parts,
            r.equations
        ),
        format!(
            "actual {} (rank {} of {} equations; {} redundant)",
            r.dof(),
            r.rank,
            r.equations,
            r.redundant.len()
        ),
    ];
    let s = &a.assembly;
    let biggest = s
        .moves
        .iter()
        .max_by(|x, y| x.translation.total_cmp(&y.translation));
    let turned = s
        .moves
        .iter()
        .max_by(|x, y| x.rotation.total_cmp(&y.rotation));
    let part = |id: Option<u32>| id.map_or("a part".to_string(), |i| format!("PART/{i}"));
    let mut assembly = vec![format!(
        "assembled at t = 0 in {} iterations; largest residual {:.3e} (positions), {:.3e} (velocities)",
        s.iterations, s.residual, s.velocity_residual
    )];
    match (biggest, turned) {
        (Some(m), Some(t)) => assembly.push(format!(
            "largest part move {:.3e} ({}), largest rotation {:.3e} rad ({})",
            m.translation,
            part(m.id),
            t.rotation,
            part(t.id)
        )),
        _ => assembly.push("no moving parts".into()),
    }
    let mut redundant: Vec<String> = r
        .adams_message(Some("model"))
        .lines()
        .map(String::from)
        .collect();
    redundant.extend(r.advice_message().lines().map(String::from));
    if redundant.is_empty() {
        redundant.push("none".into());
    }
    vec![
        ReportSection {
            title: "multibody".into(),
            lines: vec![dimension_line(&a.system, asked)],
        },
        ReportSection {
            title: "degrees of freedom".into(),
            lines: dof,
        },
        ReportSection {
            title: "assembly".into(),
            lines: assembly,
        },
        ReportSection {
            title: "redundant constraints".into(),
            lines: redundant,
        },
    ]
}

/// The scene section of a failed analysis, when a system was built.
pub fn failure_sections(f: &Failure, asked: DimRequest) -> Vec<ReportSection> {
    f.system()
        .map(|s| ReportSection {
            title: "multibody".into(),
            lines: vec![dimension_line(s, asked)],
        })
        .into_iter()
        .collect()
}

/// The statement span of element `e` in `model` (0..0 when it is not found).
pub(crate) fn element_span(model: &Model, e: &ElementRef) -> Span {
    let span = match e.kind {
        ElementKind::Joint(_) => model
            .joints
            .iter()
            .find(|j| j.el.id == e.id)
            .map(|j| &j.el.span),
        ElementKind::Jprim(_) => model
            .jprims
            .iter()
            .find(|j| j.el.id == e.id)
            .map(|j| &j.el.span),
        ElementKind::Gcon => model
            .gcons
            .iter()
            .find(|g| g.el.id == e.id)
            .map(|g| &g.el.span),
        ElementKind::Motion => model
            .motions
            .iter()
            .find(|m| m.el.id == e.id)
            .map(|m| &m.el.span),
        ElementKind::Prismatic2d => None,
        ElementKind::Force(k) => {
            use crate::vocab::elements::ForceKind;
            fn find<'a>(
                mut list: impl Iterator<Item = &'a crate::model::elements::Named>,
                id: u32,
            ) -> Option<Span> {
                list.find(|n| n.id == id).map(|n| n.span.clone())
            }
            return match k {
                ForceKind::Sforce => find(model.sforces.iter().map(|f| &f.el), e.id),
                ForceKind::Vforce | ForceKind::Vtorque | ForceKind::Gforce => {
                    find(model.vector_forces.iter().map(|f| &f.el), e.id)
                }
                ForceKind::Springdamper => find(model.spring_dampers.iter().map(|f| &f.el), e.id),
                ForceKind::Bushing => find(model.bushings.iter().map(|f| &f.el), e.id),
                ForceKind::Beam => find(model.beams.iter().map(|f| &f.el), e.id),
                ForceKind::Field => find(model.fields.iter().map(|f| &f.el), e.id),
                ForceKind::Friction => find(model.frictions.iter().map(|f| &f.el), e.id),
            }
            .unwrap_or(0..0);
        }
    };
    span.cloned().unwrap_or(0..0)
}

/// The statement span of a state element's fault (its DIFF, LSE or TFSISO, or the
/// ARRAY, MATRIX or VARIABLE at fault; 0..0 when `model` has none of that id).
pub(crate) fn statement_span(model: &Model, s: Statement) -> Span {
    fn find<'a>(mut list: impl Iterator<Item = &'a Named>, id: u32) -> Option<Span> {
        list.find(|n| n.id == id).map(|n| n.span.clone())
    }
    let states = &model.states;
    match s.keyword {
        "DIFF" => find(states.diffs.iter().map(|d| &d.el), s.id),
        "LSE" => find(states.lses.iter().map(|l| &l.el), s.id),
        "TFSISO" => find(states.tfsisos.iter().map(|t| &t.el), s.id),
        "MATRIX" => find(states.matrices.iter().map(|m| &m.el), s.id),
        "ARRAY" => find(model.arrays.iter().map(|a| &a.el), s.id),
        "VARIABLE" => find(model.variables.iter().map(|v| &v.el), s.id),
        _ => None,
    }
    .unwrap_or(0..0)
}

/// The span of an [`MbdError`]: its element's statement, or its state statement's.
fn model_error_span(e: &MbdError, model: &Model) -> Span {
    match (e.element(), e.state_statement()) {
        (Some(el), _) => element_span(model, el),
        (None, Some(s)) => statement_span(model, s),
        (None, None) => 0..0,
    }
}

/// Notes shown at most; the rest are counted.
const MAX_NOTES: usize = 8;

/// A diagnostic whose first line is the message and whose further lines are notes.
fn multi_line(code: Code, span: Span, text: &str, warning: bool) -> Diagnostic {
    let mut lines = text.lines();
    let first = lines.next().unwrap_or_default();
    let mut d = if warning {
        Diagnostic::warning(code, span, first)
    } else {
        Diagnostic::error(code, span, first)
    };
    let rest: Vec<&str> = lines.collect();
    for l in rest.iter().take(MAX_NOTES) {
        d = d.with_note(l.trim());
    }
    if rest.len() > MAX_NOTES {
        d = d.with_note(format!("… and {} more", rest.len() - MAX_NOTES));
    }
    d
}

/// The span of the first conflicting equation's element.
fn conflict_span(error: &AnalysisError, model: &Model) -> Option<Span> {
    match error {
        AnalysisError::Conflicting { report, conflicts } => conflicts
            .first()
            .map(|c| element_span(model, &report.elements[c.label.element])),
        AnalysisError::Shape(_) => None,
    }
}

/// The diagnostics of a failed analysis (the reader's, for a dataset with errors). An
/// unsupported construct is a warning: the dataset is valid, the core cannot analyse it
/// yet.
pub fn diagnostics(f: &Failure, model: &Model) -> Vec<Diagnostic> {
    let text = f.to_string();
    match f {
        Failure::Read(d) => d.clone(),
        Failure::Build(e) => {
            let span = model_error_span(e, model);
            vec![multi_line(Code::NotAnalysed, span, &text, true)]
        }
        Failure::NotPlanar(_) => vec![multi_line(Code::CommandLine, 0..0, &text, false)],
        Failure::Assembly {
            conflict: Some(c), ..
        } => {
            let span = conflict_span(c, model).unwrap_or(0..0);
            vec![multi_line(Code::Conflicting, span, &text, false)]
        }
        Failure::Assembly { error, .. } => {
            let (code, violated) = match error {
                AssemblyError::NotAssembled { violated, .. } => (Code::Assembly, &violated[..]),
                AssemblyError::Conflicting { violated } => (Code::Conflicting, &violated[..]),
                AssemblyError::Model(_) => (Code::NotAnalysed, &[][..]),
            };
            let span = violated
                .first()
                .map_or(0..0, |v| element_span(model, &v.element));
            vec![multi_line(code, span, &text, code == Code::NotAnalysed)]
        }
        Failure::Redundancy { error, .. } => {
            let span = match error {
                AnalysisError::Conflicting { report, conflicts } => {
                    conflicts.first().map_or(0..0, |c| {
                        element_span(model, &report.elements[c.label.element])
                    })
                }
                AnalysisError::Shape(_) => 0..0,
            };
            vec![multi_line(Code::Conflicting, span, &text, false)]
        }
    }
}

/// The diagnostic code of a dynamics failure: E0702 a dropped row violated, E0803 a
/// non-finite force, E0802 the integration failed, E0804 the caller interrupted it, E0801
/// anything else the model cannot be simulated for.
pub fn code_of(e: &Stopped) -> Code {
    match e {
        Stopped::Dynamics(e) => match e {
            DynError::DroppedViolated { .. } => Code::Conflicting,
            DynError::NotFinite { .. } => Code::NonFiniteForce,
            DynError::Model(MbdError::Expression(_, ExprError::NotFinite { .. })) => {
                Code::NonFiniteForce
            }
            DynError::Newton { .. } | DynError::StepTooSmall { .. } | DynError::Singular { .. } => {
                Code::Integration
            }
            DynError::Interrupted { .. } => Code::Interrupted,
            DynError::Model(_)
            | DynError::Massless { .. }
            | DynError::Structure
            | DynError::Output(_) => Code::CannotSimulate,
        },
        Stopped::Statics(f) => match f.as_ref() {
            StaticFailure::NoEquilibrium { .. } => Code::NoEquilibrium,
            StaticFailure::Unstable { .. } => Code::Unstable,
            StaticFailure::Limited { .. } => Code::StepLimit,
        },
        Stopped::FreeDegrees(_) => Code::FreeDegrees,
        Stopped::Kinematics(_) => Code::Integration,
        Stopped::Change { .. } => Code::CannotSimulate,
    }
}

/// The statement span of the element or part a dynamics failure names (0..0 when it
/// names none, or one `model` does not have).
pub fn culprit_span(e: &Stopped, model: &Model) -> Span {
    match e.culprit() {
        Some(Culprit::Element(el)) => element_span(model, &el),
        Some(Culprit::Part(id)) => model.part(id).map_or(0..0, |p| p.el.span.clone()),
        None => match e.dynamics() {
            Some(DynError::Model(m)) => model_error_span(m, model),
            _ => 0..0,
        },
    }
}

/// A dynamics failure as an error at the statement of the element (or part) it names,
/// its message the failure's own wording (with the time, when it has one).
pub fn failure_diagnostic(e: &Stopped, model: &Model) -> Diagnostic {
    Diagnostic::error(code_of(e), culprit_span(e, model), e.to_string())
}
