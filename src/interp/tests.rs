//! Unit tests of the fast-mode instruction forms: every fused pair, the specialised calls
//! and the inputs loaded up front give the bits of the plain (trace-mode) program and of
//! the JIT, at edge inputs; and the forms are really picked.

use super::compile::{compile, Mode};
use super::op::Op;
use super::Program;
use crate::check::{compile as check, Expect, Variables};
use crate::context::Context;
use crate::ir::Function;
use crate::jit::Jit;

/// Inputs for x, y, z, TIME and one measure: ±0, ±1, subnormal, huge, ±∞, NaN and
/// values inside the steps' and contact functions' ranges.
const EDGES: [f64; 14] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    5e-324,
    1e308,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::NAN,
    0.25,
    0.95,
    1.02,
    -2.5,
    0.5,
];

fn ir(src: &str) -> Function {
    let mut scope = Variables::new();
    for v in ["x", "y", "z"] {
        scope.define(v);
    }
    check(src, &scope, Expect::Any)
        .unwrap_or_else(|d| panic!("{src}: {d:?}"))
        .function
}

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// Fast program, plain program and JIT agree on `src` over a grid of edge inputs.
fn agree(jit: &mut Jit, src: &str) -> Program {
    let f = ir(src);
    let fast = Program::new(f.clone());
    let plain = compile(f.clone(), Mode::Trace);
    let code = jit.compile(&f).unwrap();
    let n = f.outputs.len();
    for (i, &x) in EDGES.iter().enumerate() {
        for &y in &EDGES {
            let z = EDGES[(i * 5 + 3) % EDGES.len()];
            let t = EDGES[(i * 7 + 1) % EDGES.len()];
            let vars = [x, y, z];
            let ctx = Context::new(t, &vars);
            let (mut a, mut b, mut c) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            fast.eval_into(&ctx, &mut a);
            plain.eval_into(&ctx, &mut b);
            code.eval_into(&ctx, &mut c);
            for k in 0..n {
                assert!(
                    same(a[k], b[k]) && same(a[k], c[k]),
                    "{src} at x, y, z, t = {x}, {y}, {z}, {t}: fast {a:?}, plain {b:?}, jit {c:?}"
                );
            }
        }
    }
    fast
}

/// The discriminant name of an op (`MulAdd`, `Step`, ...).
fn kind(op: &Op) -> String {
    let s = format!("{op:?}");
    s.split([' ', '(', '{']).next().unwrap_or("").to_string()
}

#[test]
fn every_fused_pair_gives_the_plain_bits() {
    let mut jit = Jit::new().unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for inner in ["+", "-", "*", "/"] {
        for outer in ["+", "-", "*", "/"] {
            for src in [
                format!("(x {inner} y) {outer} z"),
                format!("z {outer} (x {inner} y)"),
            ] {
                let p = agree(&mut jit, &src);
                assert_eq!(p.ops.len(), 1, "{src} is one fused op: {:?}", p.ops);
                seen.insert(kind(&p.ops[0]));
            }
        }
    }
    // Four inner operations under + and × (either side), and under − and ÷ on each side.
    assert_eq!(seen.len(), 24, "{seen:?}");
}

#[test]
fn fusion_chains_and_both_operands_left_out() {
    let mut jit = Jit::new().unwrap();
    // Both operands of the product are single-use sums: one is fused, one plain.
    let p = agree(&mut jit, "(x + y) * (z - x)");
    assert_eq!(p.ops.len(), 2, "{:?}", p.ops);
    // A chain: each fused op feeds the next as a register.
    let p = agree(&mut jit, "3*x**3 - 2*x*y + y**2/(1 + z*z) - 4.5*x + 7");
    assert!(p.ops.len() <= 8, "{:?}", p.ops);
    // A value read twice, an output, an IF test and an arm result are never folded.
    agree(&mut jit, "(x*y) + (x*y)*z");
    agree(&mut jit, "[x*y, x*y + z, z/x]");
    agree(&mut jit, "IF(x*y - z: x + y, y*z, (x - 1)*z + y)");
    // Across IF arms, inside arms, and with TIME.
    agree(
        &mut jit,
        "IF(x: (y + z)*x, TIME*2 + 1, IF(y - 0.5: z/(x + y), TIME, x*y - z*TIME))",
    );
}

#[test]
fn specialised_calls_give_the_runtime_bits() {
    let mut jit = Jit::new().unwrap();
    for (src, op) in [
        ("STEP(x, 0, -1, 1, 5)", "Step"),
        ("STEP5(x, -1, 2, 1.5, -3)", "StepFn"),
        ("HAVSIN(x, 0.25, 1, 1, 0)", "StepFn"),
        ("IMPACT(x, y, 1, 1E5, 1.5, 50, 0.1)", "Impact"),
        ("IMPACT(x, y, 0.5, 0, 2, 0, 1E-3)", "Impact"),
        ("BISTOP(x, y, 0.5, 1.5, 1E5, 1.5, 50, 0.1)", "Bistop"),
        ("BISTOP(x, y, -1, 1, 10, 1, 0, 2)", "Bistop"),
        ("POLY(x, 0, 1, 2, 3, 4)", "Poly"),
        ("POLY(x, y, -1.5)", "Poly"),
        ("ABS(x)", "Abs"),
        ("SQRT(x)", "Sqrt"),
    ] {
        let p = agree(&mut jit, src);
        let kinds: Vec<String> = p.ops.iter().map(kind).collect();
        assert_eq!(kinds, [op], "{src}");
    }
    // Parameters that are not constant stay plain calls.
    for src in [
        "STEP(x, y, 0, 1, 5)",
        "IMPACT(x, y, z, 1E5, 1.5, 50, 0.1)",
        "BISTOP(x, y, 0.5, z, 1E5, 1.5, 50, 0.1)",
        "POLY(x, 0, 1, y)",
    ] {
        let p = agree(&mut jit, src);
        assert!(
            !p.ops
                .iter()
                .any(|o| ["Step", "Impact", "Bistop", "Poly"].contains(&kind(o).as_str())),
            "{src}: {:?}",
            p.ops
        );
    }
}

#[test]
fn inputs_are_loaded_up_front_and_read_where_the_ir_reads_them_when_tracing() {
    let f = ir("IF(x: y, TIME, z*MODE)");
    let fast = Program::new(f.clone());
    assert!(!fast.ops.iter().any(|o| matches!(o, Op::Load { .. })));
    let plain = compile(f, Mode::Trace);
    assert_eq!(
        plain
            .ops
            .iter()
            .filter(|o| matches!(o, Op::Load { .. }))
            .count(),
        5
    );
    for x in [-1.0, 0.0, 1.0, f64::NAN] {
        let vars = [x, 3.0, 4.0];
        let ctx = Context::new(2.5, &vars).with_mode(7.0);
        assert!(same(fast.eval(&ctx), plain.eval(&ctx)));
    }
}

#[test]
fn measures_are_loaded_up_front() {
    let f = ir("x*2");
    // The model-free scope has no measures: add one to the IR by hand, x*2 + measure 1.
    let mut g = f;
    let m = g.insts.len() as u32;
    g.insts.push(crate::ir::Inst::Measure(1));
    g.spans.push(g.spans[0].clone());
    g.body.insert(0, m);
    let out = g.insts.len() as u32;
    g.insts.push(crate::ir::Inst::Add(g.outputs[0], m));
    g.spans.push(g.spans[0].clone());
    g.body.push(out);
    g.outputs = vec![out];
    g.uses.measures = vec![1];
    let fast = Program::new(g.clone());
    let plain = compile(g, Mode::Trace);
    let measures = [9.0, 0.5];
    let ctx = Context::new(0.0, &[1.25]).with_measures(&measures);
    assert_eq!(fast.eval(&ctx), 3.0);
    assert_eq!(plain.eval(&ctx), 3.0);
    // A context without the measure gives NaN, as before.
    assert!(fast.eval(&Context::new(0.0, &[1.25])).is_nan());
}

#[test]
fn ifs_test_differences_write_arm_results_in_place_and_leave_at_once() {
    let mut jit = Jit::new().unwrap();
    // if3 of the bench: every test is a difference or a variable, every computed arm
    // result lands in its IF's register, so only constant or input arms move.
    let p = agree(
        &mut jit,
        "IF(x - 1: -x*y, 0, IF(y: x + z, x, IF(z - 0.5: x*z, z, y*x - z)))",
    );
    let kinds: Vec<String> = p.ops.iter().map(kind).collect();
    assert_eq!(
        kinds.iter().filter(|k| *k == "IfSub").count(),
        2,
        "{kinds:?}"
    );
    assert_eq!(
        kinds.iter().filter(|k| *k == "Move").count(),
        3,
        "{kinds:?}"
    );
    // No jump lands on a jump.
    for op in &p.ops {
        if let Op::Jump { to } = *op {
            assert!(!matches!(p.ops.get(to as usize), Some(Op::Jump { .. })));
        }
    }
    // Arms that yield inputs, constants, values read elsewhere, extra results.
    for src in [
        "IF(x: y, TIME, z)",
        "IF(x - y: 1, y, -0)",
        "IF(x - y: x*y, x*y + 1, z) + x*y",
        "IF(x - y: IF(z: 1, x*y, 2), x + z, IF(y - 1: z, z*z, x - z))",
        "[IF(x: y, z, x), IF(x - z: x/y, TIME, 2), 3]",
        "IF(x*y - z: (x + y)*z, 0, x)",
    ] {
        agree(&mut jit, src);
    }
}
