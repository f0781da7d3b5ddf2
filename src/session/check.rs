//! `mbfx check` of a dataset as one call, for the CLI and the Python module alike: read
//! the text, analyse the model ([`crate::mbd::pipeline::analyze_model`]: 2D or 3D, assembly, degrees of
//! freedom, redundancy) and word the report. Out come plain figures and text: nothing of
//! the model or the multibody core leaves, so the result may cross threads.

use super::{analyze_model, report, DimRequest};
use crate::diag::Diagnostic;
use crate::mbd::system::Dimension;

/// What checking a dataset found.
pub struct Checked {
    /// The reader's diagnostics, in file order.
    pub diagnostics: Vec<Diagnostic>,
    /// The analysis: None when the reader found errors (the model is incomplete).
    pub analysis: Option<Result<Figures, Refused>>,
    /// The report `mbfx check` prints: the model's summary, then what the analysis
    /// found (or where it stopped).
    pub report: String,
    /// The dataset's title (its first line).
    pub title: String,
    /// PART ids, ground included, in file order.
    pub parts: Vec<u32>,
    /// MARKER ids, each with the part it is on, in file order.
    pub markers: Vec<(u32, u32)>,
    /// Elements the model holds (markers and settings included).
    pub elements: usize,
    /// The GRAPHICS statements, listed ([`super::graphics`]).
    pub graphics: Vec<super::graphics::Listed>,
}

/// The figures of an analysis, in numbers and Adams' words.
pub struct Figures {
    /// 2 or 3: the dimension the system was built in.
    pub dimension: u8,
    /// Why that dimension, in words.
    pub dimension_reason: String,
    /// Degrees of freedom (from the rank of the constraint Jacobian).
    pub dof: usize,
    /// The Gruebler count (coordinates minus equations, redundant ones included).
    pub gruebler: i64,
    /// Scalar constraint equations.
    pub equations: usize,
    /// One line per redundant equation, in Adams Solver's words.
    pub redundant: Vec<String>,
    /// A lighter element that would avoid each redundancy, one line per element.
    pub advice: Vec<String>,
}

/// Where the analysis stopped.
pub struct Refused {
    /// Its diagnostics, pointing into the dataset.
    pub diagnostics: Vec<Diagnostic>,
    /// The failure in words.
    pub why: String,
}

/// Reads the dataset `text` (called `name` in the report) and analyses its model in the
/// dimension `asked`.
pub fn check(name: &str, text: &str, asked: DimRequest) -> Checked {
    let read = crate::model::read_model(text);
    let model = &read.model;
    let (analysis, multibody) = if read.has_errors() {
        (None, Vec::new())
    } else {
        match analyze_model(model, asked) {
            Ok(a) => {
                let r = &a.redundancy;
                let figures = Figures {
                    dimension: match a.system.dim {
                        Dimension::Two => 2,
                        Dimension::Three => 3,
                    },
                    dimension_reason: a.system.dim_reason.clone(),
                    dof: r.dof(),
                    gruebler: r.grubler(),
                    equations: r.equations,
                    redundant: r
                        .adams_message(Some("model"))
                        .lines()
                        .filter_map(|l| l.strip_prefix(" -  "))
                        .map(|l| l.trim().to_string())
                        .collect(),
                    advice: r.advice_message().lines().map(str::to_string).collect(),
                };
                (Some(Ok(figures)), report::sections(&a, asked))
            }
            Err(f) => {
                let refused = Refused {
                    diagnostics: report::diagnostics(&f, model),
                    why: f.to_string(),
                };
                (Some(Err(refused)), report::failure_sections(&f, asked))
            }
        }
    };
    let mut sections = vec![crate::model::report::summary(model)];
    sections.extend(multibody);
    Checked {
        report: crate::model::report::format_report(name, &sections),
        title: model.title.clone(),
        parts: model.parts.iter().map(|p| p.el.id).collect(),
        markers: model.markers.iter().map(|m| (m.el.id, m.part)).collect(),
        graphics: super::graphics::list(model),
        elements: model.element_counts().iter().map(|(_, n)| n).sum::<usize>()
            + model.settings.len(),
        analysis,
        diagnostics: read.diagnostics,
    }
}
