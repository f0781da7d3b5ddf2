//! Checks of constant arguments against each library function's domain (spec §5 and
//! decisions 5–6): STEP-family and SWEEP x0 < x1 (and SWEEP's dx > 0), IMPACT and
//! BISTOP parameters, MOD by zero.
//! Only arguments that are constants after folding can be checked here; the runtime
//! gives NaN for the others, which evaluation reports.

use crate::diag::{Code, Diagnostic, Span};
use crate::vocab::func::Func;

/// (argument index, condition it must meet, what the condition says).
type Bound = (usize, fn(f64) -> bool, &'static str);

/// Diagnostics for the constant arguments of a call: `arg(i)` is argument `i`'s value if
/// it is a constant, `at(i)` its span. Allocates only to report a problem.
pub fn constant_arguments(
    func: Func,
    arg: impl Fn(usize) -> Option<f64>,
    at: impl Fn(usize) -> Span,
    call: &Span,
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let name = || format!("{func:?}").to_ascii_uppercase();
    // (argument index, condition, what it must be) for the simple sign conditions.
    // x0 (argument i0) must be less than x1 (argument i1).
    let mut ordered = |i0: usize, i1: usize, help: &str| {
        if let (Some(x0), Some(x1)) = (arg(i0), arg(i1)) {
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
                        format!("{}: {why} ({x0:?} and {x1:?})", name()),
                    )
                    .with_label(at(i0), "x0")
                    .with_label(at(i1), "x1")
                    .with_help(help),
                );
            }
        }
    };
    let bounds: &[Bound] = match func {
        Func::Step | Func::Step5 | Func::Havsin => {
            ordered(1, 3, "the step needs x0 < x1");
            &[]
        }
        // SWEEP(x, a, x0, f0, x1, f1, dx): the runtime gives NaN for x0 >= x1 or dx <= 0.
        Func::Sweep => {
            ordered(2, 4, "the frequency ramps from x0 to x1: it needs x0 < x1");
            &[(6, |dx| dx > 0.0, "the fade-in dx must be > 0")]
        }
        Func::Impact => &[
            (3, |k| k >= 0.0, "the stiffness k must be >= 0"),
            (4, |e| e > 0.0, "the exponent e must be > 0"),
            (5, |c| c >= 0.0, "the damping cmax must be >= 0"),
            (6, |d| d > 0.0, "the penetration d must be > 0"),
        ],
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
            &[
                (4, |k| k >= 0.0, "the stiffness k must be >= 0"),
                (5, |e| e > 0.0, "the exponent e must be > 0"),
                (6, |c| c >= 0.0, "the damping cmax must be >= 0"),
                (7, |d| d > 0.0, "the penetration d must be > 0"),
            ]
        }
        Func::Mod => &[(1, |d| d != 0.0, "the divisor must not be 0")],
        _ => &[],
    };
    for &(i, ok, what) in bounds {
        if let Some(v) = arg(i).filter(|&v| !ok(v)) {
            out.push(Diagnostic::error(
                Code::Domain,
                at(i),
                format!("{}: {what}, found {v:?}", name()),
            ));
        }
    }
    out
}
