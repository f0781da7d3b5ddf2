//! The model report `mbfx check MODEL.adm` prints: titled sections of lines. The reader
//! supplies the summary (element counts, units, gravity); the multibody core adds its
//! own sections (degrees of freedom, redundant constraints, 2D/3D) through the same type.

use super::elements::{Model, VectorForceKind};

/// One titled block of the report.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportSection {
    pub title: String,
    pub lines: Vec<String>,
}

/// Element counts per statement kind (only kinds present), units and gravity.
pub fn summary(model: &Model) -> ReportSection {
    let forces = |k: VectorForceKind| model.vector_forces.iter().filter(|f| f.kind == k).count();
    let counts = [
        ("PART", model.parts.len()),
        ("MARKER", model.markers.len()),
        ("JOINT", model.joints.len()),
        ("JPRIM", model.jprims.len()),
        ("GCON", model.gcons.len()),
        ("MOTION", model.motions.len()),
        ("SFORCE", model.sforces.len()),
        ("VFORCE", forces(VectorForceKind::Vforce)),
        ("VTORQUE", forces(VectorForceKind::Vtorque)),
        ("GFORCE", forces(VectorForceKind::Gforce)),
        ("SPRINGDAMPER", model.spring_dampers.len()),
        ("BUSHING", model.bushings.len()),
        ("VARIABLE", model.variables.len()),
        ("SPLINE", model.splines.len()),
        ("ARRAY", model.arrays.len()),
        ("REQUEST", model.requests.len()),
    ];
    let listed: Vec<String> = counts
        .iter()
        .filter(|(_, n)| *n > 0)
        .map(|(k, n)| format!("{k} {n}"))
        .collect();
    let u = &model.units;
    let name = |n: &Option<String>| n.clone().unwrap_or_else(|| "-".into());
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
        format!(
            "units: force {}, mass {}, length {}, time {}; UCF = {}",
            name(&u.force),
            name(&u.mass),
            name(&u.length),
            name(&u.time),
            u.ucf
        ),
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
