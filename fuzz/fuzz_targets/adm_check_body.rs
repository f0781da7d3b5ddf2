//! Body of the `adm_check` fuzz target, shared with the stable replay test
//! (`tests/fuzz_seeds.rs` includes this file with `#[path]`). Plain Rust: no libfuzzer
//! dependency.
//!
//! Any input bytes are read as an `.adm` dataset the way `mbfx check FILE.adm` reads one:
//! decoded (bytes that are not UTF-8 read as Latin-1), read into a model with every
//! statement and expression checked, and, when the read has no errors, built, assembled
//! and analysed for redundancy by the multibody core (the JIT evaluating the GCON and
//! MOTION functions), then reported. Invariants:
//! - nothing panics;
//! - every diagnostic span (and label span), the reader's and the analysis's, lies within
//!   the decoded text, on character boundaries;
//! - a read with errors is never analysed, and a failed analysis says why in at least one
//!   diagnostic (an error, or the W0703 of a model the core cannot analyse) or report
//!   section;
//! - the report and the diagnostics render.

use crate::spans::check_spans;
use mbfx::diag::{has_errors, render, Diagnostic, SourceFile};
use mbfx::model::{decode, read_model};
use mbfx::session::{report, DimRequest};

/// Runs every check on raw fuzzer bytes.
pub fn check_bytes(data: &[u8]) {
    let (text, warning) = decode(data);
    let text: &str = &text;
    let mut diags: Vec<Diagnostic> = warning.into_iter().collect();
    let read = read_model(text);
    diags.extend(read.diagnostics.iter().cloned());
    check_spans(text, &diags, "read");
    let mut sections = vec![mbfx::model::report::summary(&read.model)];
    if !has_errors(&read.diagnostics) {
        match mbfx::mbd::pipeline::analyze_model(&read.model, DimRequest::Auto) {
            Ok(analysis) => sections.extend(report::sections(&analysis, DimRequest::Auto)),
            Err(failure) => {
                let found = report::diagnostics(&failure, &read.model);
                check_spans(text, &found, "analysis");
                let words = report::failure_sections(&failure, DimRequest::Auto);
                assert!(
                    !found.is_empty() || !words.is_empty(),
                    "a failed analysis with no diagnostic and no report: {failure}\n{text:?}"
                );
                sections.extend(words);
                diags.extend(found);
            }
        }
    }
    let file = SourceFile::new("fuzz.adm", text);
    let _ = std::hint::black_box(render(&diags, &file, false));
    let _ = std::hint::black_box(mbfx::model::report::format_report("fuzz.adm", &sections));
}
