//! Evaluation speed: the eight expressions of `shared/bench/expressions.md`, side by side in
//! one run, as `native` (hand-written Rust behind a function pointer), `jit` (mbfx's
//! Cranelift JIT, the eight compiled in one module and bound to the (x, v, t) layout, so
//! each call is only the call, as native's), `interp` (mbfx's interpreter),
//! `fasteval` (compiled `Instruction`, callback namespace) and `evalexpr` (precompiled
//! `Node`, `HashMapContext`). evalexpr-jit is left out: it builds on Cranelift 0.121 and
//! evalexpr 12, a second copy of both next to mbfx's (minutes of build; the project pins
//! Cranelift 0.135). STEP, IMPACT, BISTOP, POLY, IF and ATAN2 are
//! custom functions of the peers, all calling the native kernels below.
//!
//! Inputs: 65 536 (x, v, t) triples from a fixed seed, x in [0, 2], v in [-2, 2],
//! t in [-0.5, 1.5]; once in drawn order (unpredictable branches) and once with each column
//! sorted (predictable branches). One criterion iteration evaluates the whole set
//! (`Throughput::Elements`). After criterion, a median timing loop of its own gives the
//! ns/eval table with ratios to native and geometric means.
//!
//! Run: `cargo bench --bench eval` (`-- NAME` for the expressions whose name holds NAME).

use criterion::{Criterion, SamplingMode, Throughput};
use evalexpr::{
    build_operator_tree, ContextWithMutableFunctions, ContextWithMutableVariables,
    DefaultNumericTypes, EvalexprError, EvalexprResult, Function, HashMapContext, Node, Value,
};
use fasteval::{Compiler, Evaler, Instruction, Slab};
use mbfx::check::{compile, Expect, Variables};
use mbfx::context::Context;
use mbfx::interp::Program;
use mbfx::jit::{Bound, Jit};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::f64::consts::PI;
use std::hint::black_box;
use std::time::{Duration, Instant};

/// Number of input triples (expressions.md).
const N: usize = 65_536;
/// Passes of the median timing loop ...
const REPS: usize = 15;
/// ... or fewer, down to [`MIN_REPS`], once the passes have taken this long (evalexpr's
/// slowest expressions need 0.7 s a pass): keeps the whole bench near 2.5 minutes.
const REPS_BUDGET: Duration = Duration::from_millis(1500);
const MIN_REPS: usize = 5;
/// Inputs on which the five implementations must agree before timing.
const AGREE: usize = 512;

type Native = fn(&[f64; 3]) -> f64;

/// One benchmark expression in each implementation's syntax.
struct Expr {
    name: &'static str,
    mbfx: &'static str,
    native: Native,
    fasteval: &'static str,
    evalexpr: &'static str,
}

const EXPRS: [Expr; 8] = [
    Expr {
        name: "arith",
        mbfx: "3*x**3 - 2*x*v + v**2/(1 + t*t) - 4.5*x + 7",
        native: arith,
        fasteval: "3*x^3 - 2*x*v + v^2/(1 + t*t) - 4.5*x + 7",
        evalexpr: "3*x^3 - 2*x*v + v^2/(1 + t*t) - 4.5*x + 7",
    },
    Expr {
        name: "trig",
        mbfx: "SIN(2*PI*t)*COS(x) + ATAN2(v, x)",
        native: trig,
        fasteval: "sin(2*pi()*t)*cos(x) + atan2(v, x)",
        evalexpr: "math::sin(2*pi*t)*math::cos(x) + math::atan2(v, x)",
    },
    Expr {
        name: "step",
        mbfx: "STEP(t, 0, 0, 1, 5)",
        native: step_expr,
        fasteval: "step(t, 0, 0, 1, 5)",
        evalexpr: "step(t, 0, 0, 1, 5)",
    },
    Expr {
        name: "impact",
        mbfx: "IMPACT(x, v, 1, 1e5, 1.5, 50, 0.1)",
        native: impact_expr,
        fasteval: "impact(x, v, 1, 1e5, 1.5, 50, 0.1)",
        evalexpr: "impact(x, v, 1, 1e5, 1.5, 50, 0.1)",
    },
    Expr {
        name: "bistop",
        mbfx: "BISTOP(x, v, 0.5, 1.5, 1e5, 1.5, 50, 0.1)",
        native: bistop_expr,
        fasteval: "bistop(x, v, 0.5, 1.5, 1e5, 1.5, 50, 0.1)",
        evalexpr: "bistop(x, v, 0.5, 1.5, 1e5, 1.5, 50, 0.1)",
    },
    Expr {
        name: "if3",
        mbfx: "IF(x - 1: -x*v, 0, IF(v: x + t, x, IF(t - 0.5: x*t, t, v*x - t)))",
        native: if3_expr,
        fasteval: "if3(x - 1, -x*v, 0, if3(v, x + t, x, if3(t - 0.5, x*t, t, v*x - t)))",
        evalexpr: "if3(x - 1, -x*v, 0, if3(v, x + t, x, if3(t - 0.5, x*t, t, v*x - t)))",
    },
    Expr {
        name: "poly",
        mbfx: "POLY(x, 0, 1, 2, 3, 4)",
        native: poly_expr,
        fasteval: "poly(x, 0, 1, 2, 3, 4)",
        evalexpr: "poly(x, 0, 1, 2, 3, 4)",
    },
    Expr {
        name: "long",
        mbfx: "(x*v - 2.5*t)/(1 + x*x + v*v) + 3*SIN(x*t) - COS(v)*EXP(-0.5*t) \
               + SQRT(ABS(x*v*t) + 1) - MIN(x, v)*MAX(t, 0.5) \
               + (x - v)*(x + v)*(t - 1)/(2 + t*t) + 0.25*x**2 - 0.125*v**3 \
               + ABS(x - 1)*v - t/3 + 0.001*x*v*t",
        native: long_expr,
        // fasteval has no sqrt or exp: its own `^` is its fastest form of both.
        fasteval: "(x*v - 2.5*t)/(1 + x*x + v*v) + 3*sin(x*t) - cos(v)*e()^(-0.5*t) \
                   + (abs(x*v*t) + 1)^0.5 - min(x, v)*max(t, 0.5) \
                   + (x - v)*(x + v)*(t - 1)/(2 + t*t) + 0.25*x^2 - 0.125*v^3 \
                   + abs(x - 1)*v - t/3 + 0.001*x*v*t",
        evalexpr: "(x*v - 2.5*t)/(1 + x*x + v*v) + 3*math::sin(x*t) \
                   - math::cos(v)*math::exp(-0.5*t) + math::sqrt(math::abs(x*v*t) + 1) \
                   - min(x, v)*max(t, 0.5) + (x - v)*(x + v)*(t - 1)/(2 + t*t) \
                   + 0.25*x^2 - 0.125*v^3 + math::abs(x - 1)*v - t/3 + 0.001*x*v*t",
    },
];

// ---- Native kernels, written from the formulas of spec §5 (IMPACT and BISTOP clamped).

/// STEP (spec §5.1): cubic step from h0 at x0 to h1 at x1.
#[inline]
fn step(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    if x <= x0 {
        h0
    } else if x >= x1 {
        h1
    } else {
        let d = (x - x0) / (x1 - x0);
        h0 + (h1 - h0) * d * d * (3.0 - 2.0 * d)
    }
}

/// IMPACT (spec §5.4), clamped so the force never pulls.
#[inline]
fn impact(x: f64, xd: f64, x1: f64, k: f64, e: f64, cmax: f64, d: f64) -> f64 {
    if x < x1 {
        let f = k * (x1 - x).powf(e) - step(x, x1 - d, cmax, x1, 0.0) * xd;
        f.max(0.0)
    } else {
        0.0
    }
}

/// BISTOP (spec §5.5), both outer branches clamped.
#[allow(clippy::too_many_arguments)] // the Adams signature has eight arguments
#[inline]
fn bistop(x: f64, xd: f64, x1: f64, x2: f64, k: f64, e: f64, cmax: f64, d: f64) -> f64 {
    if x < x1 {
        let f = k * (x1 - x).powf(e) - step(x, x1 - d, cmax, x1, 0.0) * xd;
        f.max(0.0)
    } else if x > x2 {
        let f = -k * (x - x2).powf(e) - step(x, x2, 0.0, x2 + d, cmax) * xd;
        f.min(0.0)
    } else {
        0.0
    }
}

/// POLY (spec §5.6): sum of a_j (x - x0)^j, by Horner's rule.
#[inline]
fn poly(x: f64, x0: f64, a: &[f64]) -> f64 {
    let u = x - x0;
    a.iter().rev().fold(0.0, |acc, &c| acc * u + c)
}

/// Arithmetic IF (spec §2.4) on already evaluated arms (the peers' custom function).
#[inline]
fn if3(test: f64, neg: f64, zero: f64, pos: f64) -> f64 {
    if test < 0.0 {
        neg
    } else if test == 0.0 {
        zero
    } else if test > 0.0 {
        pos
    } else {
        f64::NAN
    }
}

fn arith(p: &[f64; 3]) -> f64 {
    let [x, v, t] = *p;
    3.0 * (x * x * x) - 2.0 * x * v + v * v / (1.0 + t * t) - 4.5 * x + 7.0
}

fn trig(p: &[f64; 3]) -> f64 {
    let [x, v, t] = *p;
    (2.0 * PI * t).sin() * x.cos() + v.atan2(x)
}

fn step_expr(p: &[f64; 3]) -> f64 {
    step(p[2], 0.0, 0.0, 1.0, 5.0)
}

fn impact_expr(p: &[f64; 3]) -> f64 {
    impact(p[0], p[1], 1.0, 1e5, 1.5, 50.0, 0.1)
}

fn bistop_expr(p: &[f64; 3]) -> f64 {
    bistop(p[0], p[1], 0.5, 1.5, 1e5, 1.5, 50.0, 0.1)
}

/// The nested IF, with only the taken arms evaluated (as the language defines it).
fn if3_expr(p: &[f64; 3]) -> f64 {
    let [x, v, t] = *p;
    let inner = |t: f64| {
        let u = t - 0.5;
        if u < 0.0 {
            x * t
        } else if u == 0.0 {
            t
        } else if u > 0.0 {
            v * x - t
        } else {
            f64::NAN
        }
    };
    let middle = || {
        if v < 0.0 {
            x + t
        } else if v == 0.0 {
            x
        } else if v > 0.0 {
            inner(t)
        } else {
            f64::NAN
        }
    };
    let u = x - 1.0;
    if u < 0.0 {
        -x * v
    } else if u == 0.0 {
        0.0
    } else if u > 0.0 {
        middle()
    } else {
        f64::NAN
    }
}

fn poly_expr(p: &[f64; 3]) -> f64 {
    poly(p[0], 0.0, &[1.0, 2.0, 3.0, 4.0])
}

fn long_expr(p: &[f64; 3]) -> f64 {
    let [x, v, t] = *p;
    (x * v - 2.5 * t) / (1.0 + x * x + v * v) + 3.0 * (x * t).sin() - v.cos() * (-0.5 * t).exp()
        + ((x * v * t).abs() + 1.0).sqrt()
        - x.min(v) * t.max(0.5)
        + (x - v) * (x + v) * (t - 1.0) / (2.0 + t * t)
        + 0.25 * (x * x)
        - 0.125 * (v * v * v)
        + (x - 1.0).abs() * v
        - t / 3.0
        + 0.001 * x * v * t
}

// ---- Peers' custom functions.

/// fasteval's namespace: the variables of `p`, then the custom functions.
#[inline]
fn fasteval_lookup(p: &[f64; 3], name: &str, a: &[f64]) -> Option<f64> {
    Some(match (name, a.len()) {
        ("x", 0) => p[0],
        ("v", 0) => p[1],
        ("t", 0) => p[2],
        ("atan2", 2) => a[0].atan2(a[1]),
        ("step", 5) => step(a[0], a[1], a[2], a[3], a[4]),
        ("impact", 7) => impact(a[0], a[1], a[2], a[3], a[4], a[5], a[6]),
        ("bistop", 8) => bistop(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]),
        ("if3", 4) => if3(a[0], a[1], a[2], a[3]),
        ("poly", n) if n >= 3 => poly(a[0], a[1], &a[2..]),
        _ => return None,
    })
}

/// The arguments of an evalexpr function call as numbers, without cloning the tuple.
fn evalexpr_args<const K: usize>(
    arg: &Value<DefaultNumericTypes>,
) -> Result<[f64; K], EvalexprError<DefaultNumericTypes>> {
    let Value::Tuple(items) = arg else {
        return Err(EvalexprError::expected_tuple(arg.clone()));
    };
    if items.len() != K {
        return Err(EvalexprError::expected_fixed_len_tuple(K, arg.clone()));
    }
    let mut out = [0.0; K];
    for (o, v) in out.iter_mut().zip(items) {
        *o = v.as_number()?;
    }
    Ok(out)
}

/// A custom function of the evalexpr context.
type EvalexprFn = fn(
    &Value<DefaultNumericTypes>,
) -> EvalexprResult<Value<DefaultNumericTypes>, DefaultNumericTypes>;

fn evalexpr_context() -> HashMapContext<DefaultNumericTypes> {
    let mut c = HashMapContext::<DefaultNumericTypes>::new();
    let functions: [(&str, EvalexprFn); 5] = [
        ("step", |a| {
            let [x, x0, h0, x1, h1] = evalexpr_args(a)?;
            Ok(Value::Float(step(x, x0, h0, x1, h1)))
        }),
        ("impact", |a| {
            let [x, xd, x1, k, e, cmax, d] = evalexpr_args(a)?;
            Ok(Value::Float(impact(x, xd, x1, k, e, cmax, d)))
        }),
        ("bistop", |a| {
            let [x, xd, x1, x2, k, e, cmax, d] = evalexpr_args(a)?;
            Ok(Value::Float(bistop(x, xd, x1, x2, k, e, cmax, d)))
        }),
        ("if3", |a| {
            let [test, neg, zero, pos] = evalexpr_args(a)?;
            Ok(Value::Float(if3(test, neg, zero, pos)))
        }),
        ("poly", |a| {
            let [x, x0, a0, a1, a2, a3] = evalexpr_args(a)?;
            Ok(Value::Float(poly(x, x0, &[a0, a1, a2, a3])))
        }),
    ];
    for (name, f) in functions {
        c.set_function(name.to_string(), Function::new(f))
            .expect("set function");
    }
    for (name, value) in [("x", 0.0), ("v", 0.0), ("t", 0.0), ("pi", PI)] {
        c.set_value(name.to_string(), Value::Float(value))
            .expect("set value");
    }
    c
}

// ---- The five implementations of one expression.

#[derive(Clone, Copy, PartialEq, Eq)]
enum Imp {
    Native,
    Jit,
    Interp,
    Fasteval,
    Evalexpr,
}

const IMPS: [(Imp, &str); 5] = [
    (Imp::Native, "native"),
    (Imp::Jit, "jit"),
    (Imp::Interp, "interp"),
    (Imp::Fasteval, "fasteval"),
    (Imp::Evalexpr, "evalexpr"),
];

struct Compiled {
    native: Native,
    program: Program,
    jit: Bound<3>,
    slab: Slab,
    fasteval: Instruction,
    evalexpr: Node<DefaultNumericTypes>,
    context: HashMapContext<DefaultNumericTypes>,
}

impl Compiled {
    fn new(e: &Expr, jit: Bound<3>) -> Self {
        let mut scope = Variables::new();
        for name in ["x", "v", "t"] {
            scope.define(name);
        }
        let checked = checked(e);
        let mut slab = Slab::new();
        let fasteval = fasteval::Parser::new()
            .parse(e.fasteval, &mut slab.ps)
            .unwrap_or_else(|err| panic!("{}: fasteval rejects {:?}: {err}", e.name, e.fasteval))
            .from(&slab.ps)
            .compile(&slab.ps, &mut slab.cs);
        let evalexpr = build_operator_tree::<DefaultNumericTypes>(e.evalexpr)
            .unwrap_or_else(|err| panic!("{}: evalexpr rejects {:?}: {err}", e.name, e.evalexpr));
        Compiled {
            native: e.native,
            program: Program::new(checked.function),
            jit,
            slab,
            fasteval,
            evalexpr,
            context: evalexpr_context(),
        }
    }

    /// Evaluates every input into `out` with one implementation.
    fn run(&mut self, imp: Imp, inputs: &[[f64; 3]], out: &mut [f64]) {
        match imp {
            Imp::Native => native_pass(black_box(self.native), inputs, out),
            Imp::Jit => jit_pass(&self.jit, inputs, out),
            Imp::Interp => {
                let program = &self.program;
                for (o, p) in out.iter_mut().zip(inputs) {
                    *o = program.eval(&Context::new(p[2], p));
                }
            }
            Imp::Fasteval => {
                let (slab, instr) = (&self.slab, &self.fasteval);
                for (o, p) in out.iter_mut().zip(inputs) {
                    let mut ns = |name: &str, args: Vec<f64>| fasteval_lookup(p, name, &args);
                    *o = instr.eval(slab, &mut ns).unwrap_or(f64::NAN);
                }
            }
            Imp::Evalexpr => {
                let (node, ctx) = (&self.evalexpr, &mut self.context);
                for (o, p) in out.iter_mut().zip(inputs) {
                    for (name, value) in ["x", "v", "t"].into_iter().zip(p) {
                        // Same type as before, so this cannot fail.
                        let _ = ctx.set_value(name.to_string(), Value::Float(*value));
                    }
                    *o = node.eval_number_with_context(ctx).unwrap_or(f64::NAN);
                }
            }
        }
        black_box(out);
    }
}

/// The native loop, in a function of its own so its code (and alignment) does not
/// depend on the rest of `Bench::run`.
#[inline(never)]
fn native_pass(f: fn(&[f64; 3]) -> f64, inputs: &[[f64; 3]], out: &mut [f64]) {
    for (o, p) in out.iter_mut().zip(inputs) {
        *o = f(p);
    }
}

/// The JIT's loop, on its own as [`native_pass`] is.
#[inline(never)]
fn jit_pass(code: &Bound<3>, inputs: &[[f64; 3]], out: &mut [f64]) {
    for (o, p) in out.iter_mut().zip(inputs) {
        *o = code.eval(p, p[2]);
    }
}

/// The expression checked with variables x, v, t (slots 0, 1, 2).
fn checked(e: &Expr) -> mbfx::check::Checked {
    let mut scope = Variables::new();
    for name in ["x", "v", "t"] {
        scope.define(name);
    }
    compile(e.mbfx, &scope, Expect::Scalar)
        .unwrap_or_else(|d| panic!("{}: mbfx rejects {:?}: {d:?}", e.name, e.mbfx))
}

/// 65 536 triples from a fixed seed: x in [0, 2], v in [-2, 2], t in [-0.5, 1.5].
fn random_inputs() -> Vec<[f64; 3]> {
    let mut rng = StdRng::seed_from_u64(0x6d62_6678_6265_6e63);
    (0..N)
        .map(|_| {
            [
                rng.random_range(0.0..2.0),
                rng.random_range(-2.0..2.0),
                rng.random_range(-0.5..1.5),
            ]
        })
        .collect()
}

/// The same values with each column sorted on its own (predictable branches).
fn sorted_inputs(inputs: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let mut columns: Vec<Vec<f64>> = (0..3)
        .map(|i| inputs.iter().map(|p| p[i]).collect())
        .collect();
    for c in &mut columns {
        c.sort_by(f64::total_cmp);
    }
    (0..inputs.len())
        .map(|j| [columns[0][j], columns[1][j], columns[2][j]])
        .collect()
}

/// Fails when an implementation differs from native by more than 1e-9 relative.
fn assert_agreement(compiled: &mut [Compiled], inputs: &[[f64; 3]]) {
    let inputs = &inputs[..AGREE];
    for (e, c) in EXPRS.iter().zip(compiled) {
        let mut want = vec![0.0; AGREE];
        c.run(Imp::Native, inputs, &mut want);
        for &(imp, label) in &IMPS[1..] {
            let mut got = vec![0.0; AGREE];
            c.run(imp, inputs, &mut got);
            for (i, (&w, &g)) in want.iter().zip(&got).enumerate() {
                let ok = (w - g).abs() <= 1e-9 * w.abs().max(g.abs()) || (w.is_nan() && g.is_nan());
                assert!(
                    ok,
                    "{}: {label} gives {g} but native {w} at (x, v, t) = {:?}",
                    e.name, inputs[i]
                );
            }
        }
    }
}

/// Median ns per evaluation over [`REPS`] passes (at least [`MIN_REPS`] within
/// [`REPS_BUDGET`]), after one warm-up pass.
fn median_ns(c: &mut Compiled, imp: Imp, inputs: &[[f64; 3]], out: &mut [f64]) -> f64 {
    c.run(imp, inputs, out);
    let start = Instant::now();
    let mut ns = Vec::with_capacity(REPS);
    while ns.len() < MIN_REPS || (ns.len() < REPS && start.elapsed() < REPS_BUDGET) {
        let t0 = Instant::now();
        c.run(imp, inputs, out);
        ns.push(t0.elapsed().as_nanos() as f64 / inputs.len() as f64);
    }
    ns.sort_by(f64::total_cmp);
    ns[ns.len() / 2]
}

fn geomean(xs: &[f64]) -> f64 {
    (xs.iter().map(|x| x.ln()).sum::<f64>() / xs.len() as f64).exp()
}

/// Prints one table: ns/eval per implementation with its ratio to native, the JIT's and
/// the interpreter's speed-up over fasteval, and geometric means.
fn print_table(title: &str, names: &[&str], ns: &[[f64; 5]]) {
    println!("\n{title}");
    println!("| expr | native ns | jit ns (×native) | interp ns (×native) | fasteval ns (×native) | evalexpr ns (×native) | jit vs fasteval | interp vs fasteval |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    let mut ratios = vec![Vec::new(); 5];
    let (mut jit_up, mut interp_up) = (Vec::new(), Vec::new());
    for (name, row) in names.iter().zip(ns) {
        let mut line = format!("| {name} | {:.2} |", row[0]);
        for i in 1..5 {
            let r = row[i] / row[0];
            ratios[i].push(r);
            line += &format!(" {:.2} ({:.2}×) |", row[i], r);
        }
        jit_up.push(row[3] / row[1]);
        interp_up.push(row[3] / row[2]);
        println!("{line} {:.1}× | {:.2}× |", row[3] / row[1], row[3] / row[2]);
    }
    println!(
        "| geomean | 1 | {:.2}× | {:.1}× | {:.1}× | {:.1}× | {:.1}× | {:.2}× |",
        geomean(&ratios[1]),
        geomean(&ratios[2]),
        geomean(&ratios[3]),
        geomean(&ratios[4]),
        geomean(&jit_up),
        geomean(&interp_up)
    );
}

fn main() {
    let random = random_inputs();
    let sorted = sorted_inputs(&random);
    let functions: Vec<_> = EXPRS.iter().map(|e| checked(e).function).collect();
    let refs: Vec<_> = functions.iter().collect();
    let codes = Jit::new()
        .and_then(|mut j| j.compile_batch(&refs))
        .expect("the JIT compiles the eight expressions");
    let mut compiled: Vec<Compiled> = EXPRS
        .iter()
        .zip(codes)
        .map(|(e, code)| {
            let bound = code.bind().expect("the expressions read only x, v and t");
            Compiled::new(e, bound)
        })
        .collect();
    assert_agreement(&mut compiled, &random);
    println!(
        "eval: the five implementations agree to 1e-9 relative on {AGREE} inputs of each expression"
    );

    let mut criterion = Criterion::default()
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_millis(600))
        .sample_size(10)
        .configure_from_args();
    let mut out = vec![0.0; N];
    for (group_name, inputs) in [("eval/random", &random), ("eval/sorted", &sorted)] {
        let mut group = criterion.benchmark_group(group_name);
        group.throughput(Throughput::Elements(N as u64));
        group.sampling_mode(SamplingMode::Flat);
        for (e, c) in EXPRS.iter().zip(compiled.iter_mut()) {
            for &(imp, label) in &IMPS {
                group.bench_function(format!("{}/{label}", e.name), |b| {
                    b.iter(|| c.run(imp, inputs, &mut out))
                });
            }
        }
        group.finish();
    }
    criterion.final_summary();

    // The table takes criterion's filter too (`cargo bench --bench eval -- poly`): the
    // first argument that is not an option keeps the expressions whose name contains it.
    let filter = std::env::args().skip(1).find(|a| !a.starts_with('-'));

    for (title, inputs) in [
        ("random inputs", &random),
        ("sorted inputs (each column sorted)", &sorted),
    ] {
        let (names, ns): (Vec<&str>, Vec<[f64; 5]>) = EXPRS
            .iter()
            .zip(compiled.iter_mut())
            .filter(|(e, _)| filter.as_ref().is_none_or(|f| e.name.contains(f.as_str())))
            .map(|(e, c)| {
                let row = IMPS.map(|(imp, _)| median_ns(c, imp, inputs, &mut out));
                (e.name, row)
            })
            .unzip();
        print_table(
            &format!("eval, {title}: median of {MIN_REPS} to {REPS} passes over {N} triples, ns per evaluation"),
            &names,
            &ns,
        );
    }
}
