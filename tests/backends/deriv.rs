//! Derivatives generated from the IR: against analytic formulas, against central finite
//! differences on generated smooth expressions, and interpreter ≡ JIT on the gradient code.

use super::support::{ir, same};
use mbfx::context::Context;
use mbfx::interp::Program;
use mbfx::ir::deriv::{gradient, Input};
use mbfx::jit::Jit;
use proptest::prelude::*;

const X: Input = Input::Var(0);
const Y: Input = Input::Var(1);

/// Value and partials of `src` at (x, y, z, t) from both back ends, which must agree.
fn grad_at(src: &str, wrt: &[Input], v: [f64; 3], t: f64) -> Vec<f64> {
    let g = gradient(&ir(src).unwrap(), wrt).unwrap();
    let n = g.outputs.len();
    let c = Jit::new().unwrap().compile(&g).unwrap();
    let ctx = Context::new(t, &v);
    let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
    Program::new(g).eval_into(&ctx, &mut a);
    c.eval_into(&ctx, &mut b);
    assert!(
        a.iter().zip(&b).all(|(p, q)| same(*p, *q)),
        "{src}: {a:?} vs {b:?}"
    );
    a
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
}

#[test]
fn analytic_derivatives() {
    let (x, y, t) = (0.7, -1.3, 0.4);
    let cases: Vec<(&str, Vec<Input>, Vec<f64>)> = vec![
        (
            "3*x**3 - 2*x*y",
            vec![X, Y],
            vec![9.0 * x * x - 2.0 * y, -2.0 * x],
        ),
        (
            "SIN(x)*y + TIME**2",
            vec![X, Y, Input::Time],
            vec![x.cos() * y, x.sin(), 2.0 * t],
        ),
        ("x / y", vec![X, Y], vec![1.0 / y, -x / (y * y)]),
        ("SQRT(x*x + y*y)", vec![X], vec![x / (x * x + y * y).sqrt()]),
        (
            "ATAN2(y, x)",
            vec![X, Y],
            vec![-y / (x * x + y * y), x / (x * x + y * y)],
        ),
        (
            "EXP(-x)*COS(2*y)",
            vec![Y],
            vec![-2.0 * (-x).exp() * (2.0 * y).sin()],
        ),
        // STEP(x, 0, 0, 1, 5) inside: 5·6Δ(1−Δ) with Δ = x.
        ("STEP(x, 0, 0, 1, 5)", vec![X], vec![30.0 * x * (1.0 - x)]),
        ("POLY(x, 1, 2, 3, 4)", vec![X], vec![3.0 + 8.0 * (x - 1.0)]),
        // IF takes the active arm's derivative: x > 0 → 3·x²·y.
        (
            "IF(x: -x, 0, x**3*y)",
            vec![X, Y],
            vec![3.0 * x * x * y, x * x * x],
        ),
        ("MAX(x, y)*MIN(x, y)", vec![X, Y], vec![y, x]),
        ("ABS(y) + DIM(x, y)", vec![X, Y], vec![1.0, -1.0 - 1.0]),
        ("[x, y, 0] * [y, x, 1]", vec![X], vec![2.0 * y]),
    ];
    for (src, wrt, want) in cases {
        let got = grad_at(src, &wrt, [x, y, 0.0], t);
        assert_eq!(got.len(), 1 + wrt.len(), "{src}");
        for (i, (g, w)) in got[1..].iter().zip(&want).enumerate() {
            assert!(close(*g, *w), "{src} ∂{i}: {g} vs {w}");
        }
    }
}

#[test]
fn measures_and_vectors_and_kinks() {
    // A measure slot is an input like a variable.
    let g = gradient(&ir("x*x").unwrap(), &[Input::Measure(0), X]).unwrap();
    let mut out = [0.0; 3];
    Program::new(g).eval_into(&Context::new(0.0, &[3.0]), &mut out);
    assert_eq!(out, [9.0, 0.0, 6.0]);
    // Vector outputs: values, then each component's partials.
    let got = grad_at("[x*y, x, 2*y]", &[X, Y], [2.0, 3.0, 0.0], 0.0);
    assert_eq!(got, vec![6.0, 2.0, 6.0, 3.0, 2.0, 1.0, 0.0, 0.0, 2.0]);
    // At a kink the active branch: IF test = 0 takes the zero arm; MAX tie takes a1.
    assert_eq!(
        grad_at("IF(x: -x, 5*x, x)", &[X], [0.0; 3], 0.0),
        vec![0.0, 5.0]
    );
    assert_eq!(
        grad_at("MAX(x, y)", &[X, Y], [1.0, 1.0, 0.0], 0.0),
        vec![1.0, 1.0, 0.0]
    );
    // A NaN IF test: value and partials NaN.
    assert!(grad_at("IF(x: 1, 2, y)", &[Y], [f64::NAN, 1.0, 0.0], 0.0)
        .iter()
        .all(|v| v.is_nan()));
}

/// Generated smooth expressions of x and y: partials against central differences.
fn smooth(depth: u32) -> BoxedStrategy<String> {
    let leaf = prop_oneof![
        Just("x".to_string()),
        Just("y".to_string()),
        (1u32..9).prop_map(|c| format!("{}", f64::from(c) / 4.0)),
    ];
    leaf.prop_recursive(depth, 24, 3, |inner| {
        prop_oneof![
            // Division only by denominators bounded away from zero: a pole (`x/(y-y)`)
            // makes inner values infinite, where 0·∞ partials are NaN by IEEE rules.
            (inner.clone(), inner.clone(), 0..4usize).prop_map(|(a, b, op)| match op {
                3 => format!("({a} / (1 + {b}*{b}))"),
                _ => format!("({a} {} {b})", ["+", "-", "*"][op]),
            }),
            (inner.clone(), 0..7usize).prop_map(|(a, f)| {
                ["SIN", "COS", "ATAN", "TANH", "EXP", "SQRT", "LOG"][f].to_string()
                    + &match f {
                        4 => format!("(0.1*{a})"),
                        5 | 6 => format!("(1 + {a}*{a})"),
                        _ => format!("({a})"),
                    }
            }),
            (inner.clone(), inner.clone())
                .prop_map(|(a, b)| format!("STEP({a}, -1, 0.5, 1.5, 2)*{b}")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("IF({a}: {b}, 1, {b}*{b})")),
            (inner.clone(), inner).prop_map(|(a, b)| format!(
                "({a})**3 + POLY({b}, 0.5, 1, -2, 0.25) + ATAN2({a}, 2 + COS({b}))"
            )),
        ]
    })
    .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn partials_match_central_differences(src in smooth(4), x in -1.5f64..1.5, y in -1.5f64..1.5) {
        let f = ir(&src).unwrap();
        let p = Program::new(f.clone());
        let g = gradient(&f, &[X, Y]).unwrap();
        let gp = Program::new(g);
        let mut out = [0.0; 3];
        gp.eval_into(&Context::new(0.0, &[x, y]), &mut out);
        let at = |x: f64, y: f64| p.eval(&Context::new(0.0, &[x, y]));
        prop_assert!(same(out[0], at(x, y)));
        for (i, &d) in out[1..].iter().enumerate() {
            let at_step = |h: f64| {
                let (dx, dy) = if i == 0 { (h, 0.0) } else { (0.0, h) };
                at(x + dx, y + dy)
            };
            let h = 1e-5;
            let f = [at_step(h), at_step(-h), at_step(2.0 * h), at_step(-2.0 * h)];
            let central = (f[0] - f[1]) / (2.0 * h);
            let wide = (f[2] - f[3]) / (4.0 * h);
            // Rounding in f(x ± h) alone moves a difference quotient by about ε·|f|/h: a
            // large value with a small partial (x³ of a big inner sum) needs that margin.
            let scale = f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let noise = 8.0 * f64::EPSILON * scale / h;
            // The oracle holds only where the function is smooth at the scale of h: there
            // the central differences over h and 2h agree to O(h²). A kink or jump within
            // 2h (an IF switching, STEP's ends) moves them apart by about as much as it
            // moves the narrow one off the derivative, ten times the filter's tolerance
            // below the assertion's, so such cases are set aside rather than compared.
            let smooth_here = central.is_finite()
                && wide.is_finite()
                && (central - wide).abs() <= 1e-6 * (1.0 + central.abs()) + noise;
            prop_assume!(smooth_here);
            prop_assert!((d - central).abs() <= 1e-5 * (1.0 + central.abs()) + noise, "{src} ∂{i} at ({x}, {y}): {d} vs {central}");
        }
    }
}

/// docs/library.md's example: value and derivative compiled together.
#[test]
fn readme_example_value_and_gradient() {
    use mbfx::check::{compile, Expect, Variables};
    let mut scope = Variables::new();
    let x = scope.define("x");
    let f = compile("STEP(x, 0, 0, 1, 5) * x", &scope, Expect::Scalar)
        .expect("valid")
        .function;
    let mut jit = Jit::new().expect("a supported CPU");
    let code = jit.compile(&f).expect("compiles");
    assert_eq!(code.eval(&Context::new(0.0, &[0.5])), 1.25);
    let g = jit
        .compile(&gradient(&f, &[Input::Var(x)]).expect("differentiable"))
        .expect("compiles");
    let mut out = [0.0; 2];
    g.eval_into(&Context::new(0.0, &[0.5]), &mut out);
    // d/dx (STEP·x) = STEP'·x + STEP = 30·Δ(1−Δ)·x + 2.5 = 3.75 + 2.5 at x = 0.5.
    assert_eq!(out, [1.25, 6.25]);
}
