//! Checks of constant arguments against each library function's domain (spec §5 and
//! decisions 5–6): STEP-family x0 < x1, IMPACT and BISTOP parameters, MOD by zero.
//! Only arguments that are constants after folding can be checked here; the runtime
//! gives NaN for the others, which evaluation reports.

use crate::diag::{Code, Diagnostic, Span};
use crate::ir::Func;

/// (argument index, condition it must meet, what the condition says).
type Bound = (usize, fn(f64) -> bool, &'static str);

/// Diagnostics for the constant arguments of a call (`None` = not constant).
pub fn constant_arguments(
    func: Func,
    args: &[Option<f64>],
    spans: &[Span],
    call: &Span,
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let arg = |i: usize| args.get(i).copied().flatten();
    let at = |i: usize| spans.get(i).cloned().unwrap_or_else(|| call.clone());
    let name = format!("{func:?}").to_ascii_uppercase();
    // (argument index, condition, what it must be) for the simple sign conditions.
    let mut bounds: Vec<Bound> = Vec::new();
    match func {
        Func::Step | Func::Step5 | Func::Havsin => {
            if let (Some(x0), Some(x1)) = (arg(1), arg(3)) {
                if x0 >= x1 {
                    let why = if x0 == x1 {
                        "x0 equals x1"
                    } else {
                        "x0 is greater than x1"
                    };
                    out.push(
                        Diagnostic::error(
                            Code::Domain,
                            call.clone(),
                            format!("{name}: {why} ({x0:?} and {x1:?})"),
                        )
                        .with_label(at(1), "x0")
                        .with_label(at(3), "x1")
                        .with_help("the step needs x0 < x1"),
                    );
                }
            }
        }
        Func::Impact => {
            bounds.push((3, |k| k >= 0.0, "the stiffness k must be >= 0"));
            bounds.push((4, |e| e > 0.0, "the exponent e must be > 0"));
            bounds.push((5, |c| c >= 0.0, "the damping cmax must be >= 0"));
            bounds.push((6, |d| d > 0.0, "the penetration d must be > 0"));
        }
        Func::Bistop => {
            if let (Some(x1), Some(x2)) = (arg(2), arg(3)) {
                if x1 >= x2 {
                    out.push(
                        Diagnostic::error(
                            Code::Domain,
                            call.clone(),
                            format!("BISTOP: x1 must be less than x2 ({x1:?} and {x2:?})"),
                        )
                        .with_label(at(2), "x1")
                        .with_label(at(3), "x2"),
                    );
                }
            }
            bounds.push((4, |k| k >= 0.0, "the stiffness k must be >= 0"));
            bounds.push((5, |e| e > 0.0, "the exponent e must be > 0"));
            bounds.push((6, |c| c >= 0.0, "the damping cmax must be >= 0"));
            bounds.push((7, |d| d > 0.0, "the penetration d must be > 0"));
        }
        Func::Mod => bounds.push((1, |d| d != 0.0, "the divisor must not be 0")),
        _ => {}
    }
    for (i, ok, what) in bounds {
        if let Some(v) = arg(i).filter(|&v| !ok(v)) {
            out.push(Diagnostic::error(
                Code::Domain,
                at(i),
                format!("{name}: {what}, found {v:?}"),
            ));
        }
    }
    out
}
