//! Body of the `parse_check` fuzz target, shared with the stable replay test
//! (`tests/fuzz_seeds.rs` includes this file with `#[path]`), so both run exactly the same
//! checks. Plain Rust: no libfuzzer dependency.
//!
//! Invariants checked on any input bytes (invalid UTF-8 is replaced lossily):
//! - parsing, checking, lowering, rendering diagnostics, compiling for the interpreter and
//!   evaluating never panic (each input renders up to three of its diagnostics, see
//!   [`render_some`]);
//! - every diagnostic span (and label span) lies within the input: `start <= end <= len`,
//!   on character boundaries;
//! - a rejected expression carries at least one error, an accepted one none;
//! - an accepted expression has 1 or 3 outputs and evaluates (to any f64) at a few fixed
//!   points, including NaN and infinite inputs.
//!
//! Each input is parsed once. Input the parser rejects stops there: `compile` would
//! return the same parse diagnostics under any scope (it runs the same parser first), and
//! the recovering parser is by far the dearest stage on bad input, so running it once
//! per input instead of three times keeps the fuzzer fast. Input that parses is checked
//! twice: with the variables x, v, t alone (measures are errors, as outside a model), and
//! with a scope in which every measure and SPLINE exists, so measure and vector
//! expressions reach lowering and evaluation too.

use crate::spans::check_spans;
use mbfx::check::{
    compile, EveryIdExists, Expect, MeasureCall, MeasureValue, Scope, SplineInfo, Variables,
};
use mbfx::context::Context;
use mbfx::diag::{has_errors, render, Diagnostic, SourceFile};
use mbfx::interp::Program;
use mbfx::syntax::parser::Session;
use std::cell::RefCell;

/// Points (x, v, t) at which an accepted expression is evaluated; t is also the time.
const POINTS: [[f64; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [1.0, -1.0, 0.5],
    [-2.5, 1e3, 7.0],
    [f64::NAN, 1.0, -0.0],
    [f64::INFINITY, f64::NEG_INFINITY, 1e-300],
];

/// Runs every check on raw fuzzer bytes.
pub fn check_bytes(data: &[u8]) {
    match std::str::from_utf8(data) {
        Ok(src) => check_str(src),
        Err(_) => check_str(&String::from_utf8_lossy(data)),
    }
}

/// Measure values of the model scope's context (slots 0, 1, 2).
const MEASURES: [f64; 3] = [0.25, -1.5, 2.0];

/// The variables x, v, t (slots 0, 1, 2) plus every measure and SPLINE.
struct ModelScope(Variables);

impl Scope for ModelScope {
    fn variable(&self, name: &str) -> Option<u32> {
        self.0.variable(name)
    }
    fn variable_names(&self) -> Vec<String> {
        self.0.variable_names()
    }
    fn spline(&self, id: i64) -> Option<SplineInfo> {
        EveryIdExists.spline(id)
    }
    fn measure(&self, call: &MeasureCall) -> Result<MeasureValue, Diagnostic> {
        EveryIdExists.measure(call)
    }
}

/// Runs every check on one expression text.
pub fn check_str(src: &str) {
    thread_local! {
        static PARSER: RefCell<Session> = RefCell::default();
    }
    let rejected = PARSER.with(|p| {
        let mut parser = p.borrow_mut();
        let parsed = parser.parse(src, true);
        check_spans(src, &parsed.diagnostics, "parse");
        if parsed.root.is_none() {
            assert!(
                has_errors(&parsed.diagnostics),
                "no tree and no error: {src:?}: {:?}",
                parsed.diagnostics
            );
        }
        let rejected = has_errors(&parsed.diagnostics);
        if rejected {
            render_some(src, &parsed.diagnostics);
        }
        rejected
    });
    if rejected {
        return;
    }

    let mut vars = Variables::new();
    for name in ["x", "v", "t"] {
        vars.define(name);
    }
    check_compiled(src, &vars, &[], true);
    check_compiled(src, &ModelScope(vars), &MEASURES, false);
}

/// Checks, lowers and evaluates `src` under `scope`; `measures` fills the context.
/// `rendered` also renders the diagnostics (once per input is enough: it is the slow part).
fn check_compiled(src: &str, scope: &dyn Scope, measures: &[f64], rendered: bool) {
    match compile(src, scope, Expect::Any) {
        Err(diags) => {
            check_spans(src, &diags, "compile");
            assert!(
                diags.iter().any(Diagnostic::is_error),
                "rejected without an error: {src:?}: {diags:?}"
            );
            if rendered {
                render_some(src, &diags);
            }
        }
        Ok(checked) => {
            check_spans(src, &checked.warnings, "compile warnings");
            assert!(
                !checked.warnings.iter().any(Diagnostic::is_error),
                "accepted with an error: {src:?}: {:?}",
                checked.warnings
            );
            if rendered {
                render_some(src, &checked.warnings);
            }
            let n = checked.function.outputs.len();
            assert!(n == 1 || n == 3, "{n} outputs for {src:?}");
            let _ = mbfx::ir::print::print(&checked.function);
            let program = Program::new(checked.function);
            let mut out = [0.0; 3];
            for vars in &POINTS {
                let ctx = Context::new(vars[2], vars).with_measures(measures);
                let _ = std::hint::black_box(program.eval(&ctx));
                program.eval_into(&ctx, &mut out[..n]);
                let _ = std::hint::black_box(program.first_fault(&ctx));
            }
        }
    }
}

/// Renders diagnostics the way the CLI does (exercises the caret frames): the first, the
/// last (where the end-of-input error and the count of hidden errors stand) and one
/// chosen by the input's length, so that across inputs every place in the list is
/// rendered. Frames are rendered one by one, and each depends only on the text and its
/// own diagnostic. Rendering all of them cost more than everything else the target does
/// under the sanitizer (ariadne writes a frame one character at a time, each
/// instrumented, and a rejected input has up to 20 frames of the same line).
fn render_some(src: &str, diags: &[Diagnostic]) {
    let file = SourceFile::new("fuzz", src);
    let n = diags.len();
    let picks = [0, src.len() % n.max(1), n.saturating_sub(1)];
    for (i, &k) in picks.iter().enumerate() {
        if k < n && !picks[..i].contains(&k) {
            let _ = std::hint::black_box(render(&diags[k..=k], &file, false));
        }
    }
}
