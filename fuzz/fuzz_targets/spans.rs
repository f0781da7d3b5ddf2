//! The span invariant the fuzz targets check, shared by their bodies as
//! `crate::spans`: every crate that includes a body (the targets, `tests/fuzz_seeds.rs`,
//! `examples/profile.rs`) includes this file once at its root with `#[path]`.

use mbfx::diag::Diagnostic;

/// Asserts that every span of `diags` (primary and label spans) lies within `src`, on
/// character boundaries; `stage` names the stage that reported them.
pub fn check_spans(src: &str, diags: &[Diagnostic], stage: &str) {
    let len = src.len();
    for d in diags {
        let spans = std::iter::once(&d.span).chain(d.labels.iter().map(|(s, _)| s));
        for s in spans {
            assert!(
                s.start <= s.end && s.end <= len,
                "{stage}: span {s:?} outside the input (len {len}) in {src:?}: {d:?}"
            );
            assert!(
                src.is_char_boundary(s.start) && src.is_char_boundary(s.end),
                "{stage}: span {s:?} splits a character in {src:?}: {d:?}"
            );
        }
    }
}
