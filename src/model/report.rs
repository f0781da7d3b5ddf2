//! The model report `mbfx check MODEL.adm` prints: titled sections of lines. The reader
//! supplies the summary (element counts, units, gravity); the multibody core adds its
//! own sections (degrees of freedom, redundant constraints, 2D/3D) through the same type.

use super::elements::Model;

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
