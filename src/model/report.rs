//! The model report `mbfx check MODEL.adm` prints: titled sections of lines. The reader
//! supplies the summary (element counts, graphics per kind, units, gravity); the
//! multibody core adds its own sections (degrees of freedom, redundant constraints,
//! 2D/3D) through the same type.

use super::elements::{Ignored, Model, Omission};
use crate::diag::{Code, Diagnostic};

/// One titled block of the report.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportSection {
    /// The section's heading.
    pub title: String,
    /// Its lines, without the heading.
    pub lines: Vec<String>,
}

/// Element counts per statement kind (only kinds present), units and gravity.
pub fn summary(model: &Model) -> ReportSection {
    let counts = model.element_counts();
    let listed: Vec<String> = counts
        .iter()
        .filter(|(_, n)| *n > 0)
        .map(|(k, n)| format!("{k} {n}"))
        .collect();
    let u = &model.units;
    let name = |n: &Option<String>| n.clone().unwrap_or_else(|| "(SI)".into());
    let g = model.gravity;
    let mut lines = vec![
        format!("title: {}", model.title),
        format!(
            "elements: {}",
            if listed.is_empty() {
                "none".to_string()
            } else {
                listed.join(", ")
            }
        ),
        if [&u.force, &u.mass, &u.length, &u.time]
            .iter()
            .all(|n| n.is_none())
        {
            format!("units: not given; UCF = {}", u.ucf)
        } else {
            format!(
                "units: force {}, mass {}, length {}, time {}; UCF = {}",
                name(&u.force),
                name(&u.mass),
                name(&u.length),
                name(&u.time),
                u.ucf
            )
        },
        format!("gravity: ({}, {}, {})", g.x, g.y, g.z),
        format!("measures read by expressions: {}", model.measures.len()),
    ];
    let graphics = super::graphics::counts_by_kind(&model.graphics);
    if !graphics.is_empty() {
        let listed: Vec<String> = (graphics.iter())
            .map(|(kind, n)| format!("{n} {kind}"))
            .collect();
        lines.push(format!("graphics: {}", listed.join(", ")));
    }
    if !model.settings.is_empty() {
        let names: Vec<&str> = model
            .settings
            .iter()
            .map(|s| s.statement.as_str())
            .collect();
        lines.push(format!("settings: {}", names.join(", ")));
    }
    ReportSection {
        title: "model".into(),
        lines,
    }
}

/// The report text: a header line naming the file, then each section.
pub fn format_report(file: &str, sections: &[ReportSection]) -> String {
    let mut out = format!("{file}\n");
    for s in sections {
        out.push_str(&format!("  {}:\n", s.title));
        for line in &s.lines {
            out.push_str(&format!("    {line}\n"));
        }
    }
    out
}

/// The `W0602` warning about statements the model leaves out: `mbfx check` prints it for
/// every kind outside the subset, a run for each [`Ignored::physical`] group.
pub fn ignored_warning(ignored: &Ignored) -> Diagnostic {
    let listed: Vec<String> = (ignored.statements.iter())
        .take(8)
        .map(|(label, line)| format!("{label} (line {line})"))
        .collect();
    let more = ignored.count().saturating_sub(listed.len());
    let mut note = listed.join(", ");
    if more > 0 {
        note.push_str(&format!(" and {more} more"));
    }
    let (n, kind) = (ignored.count(), &ignored.kind);
    let s = if n == 1 { "" } else { "s" };
    let message = match ignored.why {
        Omission::Unsupported => {
            format!("{kind} is outside the mbfx subset: {n} statement{s} ignored")
        }
        Omission::Unknown => format!("unknown statement `{kind}`: {n} statement{s} ignored"),
        Omission::UserCall => format!(
            "{n} statement{s} with a USER subroutine, which mbfx cannot run: {} left out",
            if n == 1 {
                "its value is"
            } else {
                "their values are"
            }
        ),
    };
    Diagnostic::warning(Code::UnsupportedStatement, ignored.span.clone(), message).with_note(note)
}

/// The run summary's line about the physics the model leaves out ("not modelled: 12
/// FRICTION, 1 CONTACT — ..."), the most numerous first; None when nothing physical is.
pub fn not_modelled(ignored: &[Ignored]) -> Option<String> {
    let mut physical: Vec<&Ignored> = ignored.iter().filter(|i| i.physical).collect();
    physical.sort_by_key(|i| std::cmp::Reverse(i.count()));
    let counts: Vec<String> = (physical.iter())
        .map(|i| match i.why {
            Omission::UserCall => {
                format!(
                    "{} USER subroutine{}",
                    i.count(),
                    if i.count() == 1 { "" } else { "s" }
                )
            }
            _ => format!("{} {}", i.count(), i.kind),
        })
        .collect();
    (!counts.is_empty()).then(|| {
        format!(
            "not modelled: {} — the results leave out their physics",
            counts.join(", ")
        )
    })
}
