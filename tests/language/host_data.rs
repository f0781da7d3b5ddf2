//! Expressions over data the host supplies: SPLINE curves for AKISPL and CUBSPL (spec
//! §5.13), and dataset framing such as CRLF continuation lines.

use crate::support::ulps;
use mbfx::check::{compile, Expect, Variables};
use mbfx::context::Context;
use mbfx::interp::Program;
use mbfx_runtime::Spline;

/// Evaluates `src` with x = `x` and the given splines registered as SPLINE/1, /2, ...
fn eval_with_splines(src: &str, x: f64, splines: &[(Spline, bool)]) -> Result<f64, Vec<String>> {
    let mut scope = Variables::new();
    scope.define("x");
    for (i, (_, surface)) in splines.iter().enumerate() {
        scope.define_spline(i as i64 + 1, *surface);
    }
    let checked = compile(src, &scope, Expect::Scalar).map_err(|d| {
        d.iter()
            .map(|d| d.code.as_str().to_string())
            .collect::<Vec<_>>()
    })?;
    let data: Vec<Spline> = splines.iter().map(|(s, _)| s.clone()).collect();
    let vars = [x];
    Ok(Program::new(checked.function).eval(&Context::new(0.0, &vars).with_splines(&data)))
}

#[test]
fn splines_reproduce_linear_data_with_their_derivatives() {
    // Spec §5.13: any cubic or Akima fit is exact on linear data (y = 2x).
    let xs: Vec<f64> = (0..6).map(f64::from).collect();
    let ys: Vec<f64> = xs.iter().map(|x| 2.0 * x).collect();
    let line = Spline::new(xs, vec![0.0], ys).expect("valid spline");
    let data = [(line, false)];
    for f in ["AKISPL", "CUBSPL"] {
        let at = |src: String| eval_with_splines(&src, 2.5, &data).expect(&src);
        assert!(ulps(at(format!("{f}(x, 0, 1)")), 5.0) <= 4, "{f} value");
        assert!(
            (at(format!("{f}(x, 0, 1, 1)")) - 2.0).abs() < 1e-12,
            "{f} slope"
        );
        assert!(
            at(format!("{f}(x, 0, 1, 2)")).abs() < 1e-12,
            "{f} curvature"
        );
    }
}

#[test]
fn akispl_matches_the_view_table_at_its_knots_and_is_odd() {
    // The Adams View example table of spec §5.13: odd-symmetric data.
    let xs: Vec<f64> = (-4..=4).map(f64::from).collect();
    let ys = vec![-3.6, -2.5, -1.2, -0.4, 0.0, 0.4, 1.2, 2.5, 3.6];
    let table = Spline::new(xs, vec![0.0], ys).expect("valid spline");
    let data = [(table, false)];
    let at = |x: f64| eval_with_splines("AKISPL(x, 0, 1)", x, &data).expect("checks");
    assert_eq!(at(2.0), 1.2);
    assert_eq!(at(0.0), 0.0);
    assert!((at(-0.5) + at(0.5)).abs() < 1e-15);
}

#[test]
fn spline_references_are_checked() {
    let xs: Vec<f64> = (0..6).map(f64::from).collect();
    let line = Spline::new(xs.clone(), vec![0.0], xs).expect("valid spline");
    let data = [(line, false)];
    assert_eq!(
        eval_with_splines("AKISPL(x, 0, 2)", 1.0, &data),
        Err(vec!["E0311".into()])
    );
    assert_eq!(
        eval_with_splines("AKISPL(x, 0.5, 1, 1)", 1.0, &data),
        Err(vec!["E0307".into()])
    );
    assert_eq!(
        eval_with_splines("AKISPL(x, 0, 1, 3)", 1.0, &data),
        Err(vec!["E0304".into()])
    );
}

#[test]
fn crlf_continuation_lines_join() {
    // Spec §1.5.1 with Windows line ends: the statement continues after `\r\n,`.
    let mut scope = Variables::new();
    scope.define("x");
    let checked = compile("STEP(TIME,0,0,\r\n, 1,100)", &scope, Expect::Scalar).expect("checks");
    assert_eq!(
        Program::new(checked.function).eval(&Context::new(0.5, &[0.0])),
        50.0
    );
}
