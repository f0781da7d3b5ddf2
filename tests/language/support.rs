//! Shared helpers: compiling and evaluating with the interpreter, float comparison, a
//! generator of valid expressions.

use mbfx::check::{compile, Expect, Variables};
use mbfx::context::Context;
use mbfx::diag::Diagnostic;
use mbfx::interp::Program;
use proptest::prelude::*;

/// Scope with the variables x, v, t (slots 0, 1, 2).
pub fn xvt_scope() -> Variables {
    let mut s = Variables::new();
    for n in ["x", "v", "t"] {
        s.define(n);
    }
    s
}

/// Compiles `src` with variables x, v, t and evaluates every output at the given values.
pub fn eval(src: &str, vars: [f64; 3], time: f64) -> Result<Vec<f64>, Vec<Diagnostic>> {
    let checked = compile(src, &xvt_scope(), Expect::Any)?;
    let p = Program::new(checked.function);
    let mut out = vec![0.0; p.function().outputs.len()];
    p.eval_into(&Context::new(time, &vars), &mut out);
    Ok(out)
}

/// Distance in units in the last place between two finite doubles of the same sign.
pub fn ulps(a: f64, b: f64) -> u64 {
    if a == b {
        return 0;
    }
    if a.is_sign_negative() != b.is_sign_negative() {
        return u64::MAX;
    }
    a.to_bits().abs_diff(b.to_bits())
}

/// Root directory of the shared material (`../shared` beside the repository).
pub fn shared() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared")
}

fn blank() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec!["", "", "", " ", "  ", "\t"])
}

fn leaf() -> impl Strategy<Value = String> {
    prop_oneof![
        (0u32..1000).prop_map(|n| n.to_string()),
        (0u32..100, 0u32..1000).prop_map(|(a, b)| format!("{a}.{b}")),
        (0u32..100).prop_map(|n| format!(".{n}")),
        (1u32..10, -20i32..20).prop_map(|(a, e)| format!("{a}E{e}")),
        (0u32..360).prop_map(|n| format!("{n}D")),
        prop::sample::select(vec!["x", "TIME", "PI", "dtor", ".mod.part.mkr", "_a1"])
            .prop_map(String::from),
    ]
}

/// Valid expressions of every syntactic form, with blanks between tokens, for property
/// tests of the parser.
pub fn valid_expr() -> impl Strategy<Value = String> {
    leaf().prop_recursive(7, 96, 5, |inner| {
        prop_oneof![
            (
                inner.clone(),
                blank(),
                prop::sample::select(vec!["+", "-", "*", "/", "**", "%"]),
                blank(),
                inner.clone()
            )
                .prop_map(|(a, s, op, t, b)| format!("{a}{s}{op}{t}{b}")),
            (
                prop::collection::vec(prop::sample::select(vec!["-", "+", "- ", "+ "]), 1..4),
                inner.clone()
            )
                .prop_map(|(signs, a)| format!("{}{a}", signs.concat())),
            (inner.clone(), blank()).prop_map(|(a, s)| format!("({s}{a}{s})")),
            (inner.clone(), inner.clone(), inner.clone(), inner.clone())
                .prop_map(|(a, b, c, d)| format!("IF({a}:{b} ,{c}, {d})")),
            (inner.clone(), inner.clone(), inner.clone())
                .prop_map(|(a, b, c)| format!("[{a},{b}, {c}]")),
            (
                prop::sample::select(vec!["SIN", "max", "STEP", "POLY", "f", "DX"]),
                prop::collection::vec(inner, 0..5)
            )
                .prop_map(|(f, args)| format!("{f}({})", args.join(", "))),
        ]
    })
}
