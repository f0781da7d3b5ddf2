//! Second derivatives ([`super::hessian`]) of every library function with a first
//! derivative, against their analytic formulas written out here (not values printed by
//! mbfx), at several points; interpreter ≡ JIT on the Hessian code.

use super::{hessian, DerivError, Input};
use crate::check::{compile, Expect, Variables};
use crate::context::Context;
use crate::interp::Program;
use crate::jit::Jit;
use crate::vocab::func::Func;
use core::f64::consts::{LN_10, PI};

const X: Input = Input::Var(0);
const Y: Input = Input::Var(1);
const T: Input = Input::Time;

fn ir(src: &str) -> crate::ir::Function {
    let mut scope = Variables::new();
    scope.define("x");
    scope.define("y");
    compile(src, &scope, Expect::Scalar)
        .unwrap_or_else(|d| panic!("{src}: {d:?}"))
        .function
}

/// The Hessian of `src` in `wrt` at (x, y, t), row by row, from both back ends (which
/// must agree bit for bit).
fn hess(src: &str, wrt: &[Input], x: f64, y: f64, t: f64) -> Vec<Vec<f64>> {
    let h = hessian(&ir(src), wrt).unwrap_or_else(|e| panic!("{src}: {e}"));
    let k = wrt.len();
    let n = h.outputs.len();
    assert_eq!(n, (1 + k) * (1 + k), "{src}");
    let vars = [x, y];
    let ctx = Context::new(t, &vars);
    let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
    let jit = Jit::new().unwrap().compile(&h).unwrap();
    Program::new(h).eval_into(&ctx, &mut a);
    jit.eval_into(&ctx, &mut b);
    for (p, q) in a.iter().zip(&b) {
        assert!(
            p.to_bits() == q.to_bits() || (p.is_nan() && q.is_nan()),
            "{src}"
        );
    }
    (0..k)
        .map(|i| (0..k).map(|j| a[(1 + k) + (1 + i) * k + j]).collect())
        .collect()
}

fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
        "{what}: {got} vs {want} (error {:e})",
        got - want
    );
}

/// d²/dx² of each one-argument case against its formula at several points.
#[test]
fn second_derivatives_of_one_argument_functions() {
    type Case = (&'static str, fn(f64) -> f64, &'static [f64]);
    let inside: &[f64] = &[-0.8, -0.3, 0.1, 0.45, 0.9];
    let positive: &[f64] = &[0.05, 0.4, 1.0, 2.5, 7.0];
    let wide: &[f64] = &[-2.7, -1.0, 0.0, 0.6, 1.9, 4.2];
    let cases: [Case; 25] = [
        ("SIN(x)", |x| -x.sin(), wide),
        ("COS(x)", |x| -x.cos(), wide),
        (
            "TAN(x)",
            |x| 2.0 * x.tan() * (1.0 + x.tan().powi(2)),
            inside,
        ),
        ("SINH(x)", f64::sinh, wide),
        ("COSH(x)", f64::cosh, wide),
        (
            "TANH(x)",
            |x| -2.0 * x.tanh() * (1.0 - x.tanh().powi(2)),
            wide,
        ),
        ("EXP(x)", f64::exp, wide),
        ("LOG(x)", |x| -1.0 / (x * x), positive),
        ("LOG10(x)", |x| -1.0 / (x * x * LN_10), positive),
        ("SQRT(x)", |x| -0.25 / x.powf(1.5), positive),
        ("ASIN(x)", |x| x / (1.0 - x * x).powf(1.5), inside),
        ("ACOS(x)", |x| -x / (1.0 - x * x).powf(1.5), inside),
        ("ATAN(x)", |x| -2.0 * x / (1.0 + x * x).powi(2), wide),
        ("x**2.5", |x| 2.5 * 1.5 * x.powf(0.5), positive),
        ("x**3", |x| 6.0 * x, wide),
        ("ABS(x**3)", |x| 6.0 * x.abs(), wide),
        ("AINT(x)*x + ANINT(x)", |_| 0.0, &[-2.7, -1.2, 0.6, 1.9]),
        ("MOD(x*x, 0.7)", |_| 2.0, &[-2.7, -1.2, 0.6, 1.9]),
        (
            "SIN(COS(x))",
            |x| -(x.cos().sin()) * x.sin().powi(2) - x.cos().cos() * x.cos(),
            wide,
        ),
        (
            "SHF(x, 0.2, 1.5, 3, 0.4, 7)",
            |x| -1.5 * 9.0 * (3.0 * (x - 0.2) - 0.4).sin(),
            wide,
        ),
        ("POLY(x, 1, 1, 2, 3, 4)", |x| 6.0 + 24.0 * (x - 1.0), wide),
        // 1 + 2t + 3·T2 + 4·T3 = 1 + 2t + 3(2t² − 1) + 4(4t³ − 3t).
        (
            "CHEBY(x, 0.5, 1, 2, 3, 4)",
            |x| 12.0 + 96.0 * (x - 0.5),
            wide,
        ),
        (
            "FORCOS(x, 0.1, 2, 1, 3, 5)",
            |x| {
                let t = x - 0.1;
                -12.0 * (2.0 * t).cos() - 80.0 * (4.0 * t).cos()
            },
            wide,
        ),
        (
            "FORSIN(x, 0.1, 2, 1, 3, 5)",
            |x| {
                let t = x - 0.1;
                -12.0 * (2.0 * t).sin() - 80.0 * (4.0 * t).sin()
            },
            wide,
        ),
        // IMPACT lowered (constant parameters), no damping: k·(x1 − x)^e in contact.
        (
            "IMPACT(x, 0, 1, 100, 2.5, 0, 0.1)",
            |x| {
                if x < 1.0 {
                    100.0 * 2.5 * 1.5 * (1.0 - x).powf(0.5)
                } else {
                    0.0
                }
            },
            &[-0.5, 0.2, 0.7, 1.3],
        ),
    ];
    for (src, want, points) in cases {
        for &x in points {
            let h = hess(src, &[X], x, 0.0, 0.0);
            close(h[0][0], want(x), &format!("{src} at x = {x}"));
        }
    }
}

/// The piecewise ones (lowered to selects before differentiating) and the steps.
#[test]
fn second_derivatives_of_piecewise_functions_and_steps() {
    for x in [-1.3, -0.2, 0.35, 0.8, 1.6] {
        let sq = 2.0;
        let cases: [(&str, f64, f64); 7] = [
            ("SIGN(x*x, 1)", 0.5, sq),
            ("SIGN(x*x, -1)", 0.5, -sq),
            ("MAX(x*x, 0.5)", 0.0, if x * x >= 0.5 { sq } else { 0.0 }),
            ("MIN(x*x, 0.5)", 0.0, if x * x <= 0.5 { sq } else { 0.0 }),
            ("DIM(x*x, 0.5)", 0.0, if x * x > 0.5 { sq } else { 0.0 }),
            (
                "STEP(x, 0, 0, 1, 5)",
                0.0,
                if (0.0..=1.0).contains(&x) {
                    5.0 * (6.0 - 12.0 * x)
                } else {
                    0.0
                },
            ),
            (
                "STEP5(x, 0, 0, 1, 1)",
                0.0,
                if (0.0..=1.0).contains(&x) {
                    60.0 * x - 180.0 * x * x + 120.0 * x.powi(3)
                } else {
                    0.0
                },
            ),
        ];
        for (src, _, want) in cases {
            close(
                hess(src, &[X], x, 0.0, 0.0)[0][0],
                want,
                &format!("{src} at {x}"),
            );
        }
        let havsin = if (0.0..=1.0).contains(&x) {
            PI * PI * (PI * x).cos()
        } else {
            0.0
        };
        close(
            hess("HAVSIN(x, 0, 0, 1, 2)", &[X], x, 0.0, 0.0)[0][0],
            havsin,
            &format!("HAVSIN at {x}"),
        );
    }
}

/// Full Hessians of two-argument functions and of series whose frequency or coefficients
/// vary, mixed partials included.
#[test]
fn mixed_second_derivatives() {
    for (x, y) in [(0.7, -1.3), (-0.4, 0.9), (2.0, 0.3), (1.1, 1.1)] {
        // ATAN2(y, x) in (y, x).
        let r4 = (x * x + y * y) * (x * x + y * y);
        let h = hess("ATAN2(y, x)", &[Y, X], x, y, 0.0);
        close(h[0][0], -2.0 * x * y / r4, "atan2 yy");
        close(h[0][1], (y * y - x * x) / r4, "atan2 yx");
        close(h[1][0], (y * y - x * x) / r4, "atan2 xy");
        close(h[1][1], 2.0 * x * y / r4, "atan2 xx");
        // a ** b with a > 0 in (a, b).
        let a = x.abs() + 0.2;
        let h = hess("(ABS(x) + 0.2)**y", &[X], x, y, 0.0);
        close(h[0][0], y * (y - 1.0) * a.powf(y - 2.0), "pow aa");
        let h = hess("x**y", &[X, Y], a, y, 0.0);
        close(h[0][0], y * (y - 1.0) * a.powf(y - 2.0), "pow aa");
        close(h[0][1], a.powf(y - 1.0) * (1.0 + y * a.ln()), "pow ab");
        close(h[1][1], a.powf(y) * a.ln().powi(2), "pow bb");
        // SHF(t, 0, 2, y, 0, 0) = 2·sin(y·t) in (y, t).
        let t = x;
        let h = hess("SHF(TIME, 0, 2, y, 0, 0)", &[Y, T], 0.0, y, t);
        close(h[0][0], -2.0 * t * t * (y * t).sin(), "shf ww");
        close(
            h[0][1],
            2.0 * (y * t).cos() - 2.0 * y * t * (y * t).sin(),
            "shf wt",
        );
        close(h[1][1], -2.0 * y * y * (y * t).sin(), "shf tt");
        // FORCOS(t, 0, y, 1, 3) = 1 + 3·cos(y·t).
        let h = hess("FORCOS(TIME, 0, y, 1, 3)", &[Y, T], 0.0, y, t);
        close(h[0][0], -3.0 * t * t * (y * t).cos(), "forcos ww");
        close(
            h[0][1],
            -3.0 * (y * t).sin() - 3.0 * y * t * (y * t).cos(),
            "forcos wt",
        );
        close(h[1][1], -3.0 * y * y * (y * t).cos(), "forcos tt");
        // Coefficients that vary: POLY = 1 + y·x, CHEBY = y·T2(x), FORSIN = y·sin x.
        let h = hess("POLY(x, 0, 1, y)", &[X, Y], x, y, 0.0);
        close(h[0][1], 1.0, "poly xy");
        close(h[1][1], 0.0, "poly yy");
        let h = hess("CHEBY(x, 0, 0, 0, y)", &[X, Y], x, y, 0.0);
        close(h[0][0], 4.0 * y, "cheby xx");
        close(h[0][1], 4.0 * x, "cheby xy");
        let h = hess("FORSIN(x, 0, 1, 0, y)", &[X, Y], x, y, 0.0);
        close(h[0][0], -y * x.sin(), "forsin xx");
        close(h[0][1], x.cos(), "forsin xy");
        // A motion's drive in time.
        let h = hess("0.1*SIN(2*PI*TIME)", &[T], 0.0, 0.0, t);
        close(h[0][0], -0.4 * PI * PI * (2.0 * PI * t).sin(), "drive");
    }
}

/// SWEEP(x, a, x0, f0, x1, f1, dx) = a·F·sin 2πφ: f″ = a·(F″S + 2F′S′ + F·S″), with
/// S′ = 2πφ′·cos 2πφ, S″ = 2πφ″·cos 2πφ − (2πφ′)²·sin 2πφ, the phase φ of the runtime's
/// documentation (quadratic between x0 and x1) and the fade F = STEP5(x, x0, 0, x0 + dx, 1)
/// (F′ = 30Δ²(1 − Δ)²/dx, F″ = 60Δ(1 − Δ)(1 − 2Δ)/dx², Δ = (x − x0)/dx); checked before,
/// in and after the fade, during and after the sweep.
#[test]
fn second_derivative_of_sweep() {
    let (a, x0, f0, x1, f1, dx): (f64, f64, f64, f64, f64, f64) = (1.5, 0.2, 1.0, 2.0, 3.0, 0.5);
    let c = (f1 - f0) / (2.0 * (x1 - x0));
    for x in [-0.3, 0.35, 0.6, 1.1, 1.7, 2.4] {
        let (phase, slope, curve) = if x <= x0 {
            (f0 * x, f0, 0.0)
        } else if x >= x1 {
            (f1 * x - (f1 - f0) / 2.0 * (x1 + x0), f1, 0.0)
        } else {
            let u = x - x0;
            (f0 * u + c * u * u + f0 * x0, f0 + 2.0 * c * u, 2.0 * c)
        };
        let (fade, fd, fdd) = if x <= x0 {
            (0.0, 0.0, 0.0)
        } else if x >= x0 + dx {
            (1.0, 0.0, 0.0)
        } else {
            let d = (x - x0) / dx;
            (
                d.powi(3) * (10.0 - 15.0 * d + 6.0 * d * d),
                30.0 * d * d * (1.0 - d).powi(2) / dx,
                60.0 * d * (1.0 - d) * (1.0 - 2.0 * d) / (dx * dx),
            )
        };
        let w = 2.0 * PI;
        let (s, co) = ((w * phase).sin(), (w * phase).cos());
        let sd = w * slope * co;
        let sdd = w * curve * co - (w * slope).powi(2) * s;
        let want = a * (fdd * s + 2.0 * fd * sd + fade * sdd);
        let got = hess("SWEEP(x, 1.5, 0.2, 1, 2, 3, 0.5)", &[X], x, 0.0, 0.0)[0][0];
        close(got, want, &format!("SWEEP at {x}"));
        // In (x, amplitude): ∂²/∂x∂a = f′/a.
        let h = hess("SWEEP(x, y, 0.2, 1, 2, 3, 0.5)", &[X, Y], x, a, 0.0);
        close(h[0][1], fd * s + fade * sd, &format!("SWEEP x, a at {x}"));
        close(h[1][1], 0.0, &format!("SWEEP a, a at {x}"));
    }
}

#[test]
fn functions_without_a_second_derivative_are_named() {
    let err = hessian(&ir("SWEEP(x, 1, 0, y, 5, 10, 0.5)"), &[X, Y]).unwrap_err();
    assert_eq!(err, DerivError::SecondOrder(Func::Sweep));
    assert_eq!(err.to_string(), "mbfx has no second derivative of SWEEP");
}

/// IMPACT and BISTOP whose parameters vary differentiate twice in them too, by calculus
/// on the contact law (spec expr-language §5.4–5.5), and are NaN where the runtime
/// refuses the parameters.
#[test]
fn contacts_with_varying_parameters_differentiate_twice() {
    // IMPACT(x, 0, 1, k = y, 2.5, 0, 0.1): y·(1 − x)^2.5 below x1 = 1, no damping.
    for (x, y) in [(0.3, 80.0), (0.9, 5.0), (1.2, 50.0)] {
        let h = hess("IMPACT(x, 0, 1, y, 2.5, 0, 0.1)", &[X, Y], x, y, 0.0);
        let p = (1.0 - x).max(0.0);
        let what = format!("IMPACT at x = {x}, k = {y}");
        close(h[0][0], y * 2.5 * 1.5 * p.powf(0.5), &what);
        close(h[0][1], -2.5 * p.powf(1.5), &what);
        close(h[1][0], -2.5 * p.powf(1.5), &what);
        close(h[1][1], 0.0, &what);
    }
    // Parameters the runtime refuses make the written-out function NaN, as the call is
    // (a NaN value stops the evaluation that reads it before any derivative is used).
    let value = |src: &str, y: f64| {
        let h = hessian(&ir(src), &[X, Y]).unwrap();
        let mut out = vec![0.0; h.outputs.len()];
        Program::new(h).eval_into(&Context::new(0.0, &[0.2, y]), &mut out);
        out[0]
    };
    assert!(value("IMPACT(x, 0, 1, y, 2.5, 0, 0.1)", -1.0).is_nan());
    assert!(value("IMPACT(x, 0, 1, 5, y, 0, 0.1)", 0.0).is_nan());
    // BISTOP(x, 0, −1, x2 = y, 100, 2, 0, 0.1): −100·(x − y)² above x2.
    for (x, y) in [(0.8, 0.5), (0.2, 0.5)] {
        let h = hess("BISTOP(x, 0, -1, y, 100, 2, 0, 0.1)", &[X, Y], x, y, 0.0);
        let s = if x > y { 200.0 } else { 0.0 };
        let what = format!("BISTOP at x = {x}, x2 = {y}");
        close(h[0][0], -s, &what);
        close(h[0][1], s, &what);
        close(h[1][1], -s, &what);
    }
    assert!(value("BISTOP(x, 0, -1, y, 100, 2, 0, 0.1)", -2.0).is_nan());
}

/// A spline differentiates twice in x: d²/dx² CUBSPL(x², 0, 1) = S″(x²)·4x² + S′(x²)·2,
/// with S′ and S″ from the runtime (iord 1 and 2).
#[test]
fn splines_differentiate_twice_in_x() {
    use mbfx_runtime::{cubspl, Spline};
    let xs: Vec<f64> = (0..8).map(|i| i as f64 * 0.5).collect();
    let ys: Vec<f64> = xs.iter().map(|x| (x * 1.3).sin() + 0.2 * x).collect();
    let spline = Spline::new(xs, vec![0.0], ys).unwrap();
    let mut scope = Variables::new();
    scope.define("x");
    scope.define_spline(1, false);
    let f = compile("CUBSPL(x*x, 0, 1)", &scope, Expect::Scalar)
        .unwrap()
        .function;
    let h = hessian(&f, &[X]).unwrap();
    let splines = [spline];
    for x in [0.3, 0.9, 1.4, 1.8] {
        let mut out = vec![0.0; h.outputs.len()];
        let vars = [x];
        let ctx = Context::new(0.0, &vars).with_splines(&splines);
        Program::new(h.clone()).eval_into(&ctx, &mut out);
        let u = x * x;
        let (d1, d2) = (
            cubspl(u, 0.0, &splines[0], 1),
            cubspl(u, 0.0, &splines[0], 2),
        );
        close(out[3], d2 * 4.0 * u + d1 * 2.0, &format!("CUBSPL at {x}"));
    }
}
