//! Interpreter ≡ JIT ≡ lane evaluator on generated expressions: every function of the language, IFs
//! nested up to nine deep, vectors, depth up to 12, at edge inputs (±0, subnormals, huge
//! values, ±∞, NaN). The interpreter calls the runtime for every library function; the
//! JIT runs the branch-free lowering, so this also checks the lowering against the runtime.
//! The lane evaluator runs each batch's inputs as columns in one block.
//!
//! The units check (issue 24) is held to the same standard: with it and without, the IR
//! and both engines' bits are the same.
//!
//! Each proptest case draws a seed for a batch of [`PER_CASE`] expressions, compiled
//! together into one JIT module (compilation would otherwise dominate), each evaluated on
//! [`INPUTS`] input sets: [`SHARDS`] × [`CASES`] × [`PER_CASE`] = 200 000 expressions.

use super::support::{ir, same, VARS};
use mbfx::check::units::{Dim, UnitNames};
use mbfx::context::Context;
use mbfx::interp::Program;
use mbfx::jit::Jit;
use mbfx::lanes::{Column, Lanes};
use proptest::prelude::*;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

const CASES: u32 = 500;
/// Test functions sharing the cases, so the test harness runs them on every core.
const SHARDS: u32 = 4;
const PER_CASE: usize = 100;
const INPUTS: usize = 6;
const MAX_DEPTH: usize = 12;
const MAX_IFS: usize = 9;

/// Edge values for inputs and constants.
const EDGES: [f64; 16] = [
    0.0,
    -0.0,
    5e-324,
    -2.2250738585072014e-308,
    1.0,
    -1.0,
    0.5,
    2.0,
    -3.0,
    1e308,
    -1e300,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::NAN,
    0.1,
    1.5,
];

/// Constants as text: edge values the language can write (∞ and NaN by expressions).
const CONSTS: [&str; 14] = [
    "0",
    "(-0)",
    "1",
    "0.5",
    "2",
    "3",
    "1.5",
    "1E-310",
    "1E308",
    "(-1E300)",
    "PI",
    "(1E308*10)",
    "SQRT(-1)",
    "(-2.5)",
];

/// Functions with a fixed arity.
const FIXED: [(&str, usize); 31] = [
    ("ABS", 1),
    ("ACOS", 1),
    ("ASIN", 1),
    ("ATAN", 1),
    ("COS", 1),
    ("SIN", 1),
    ("TAN", 1),
    ("COSH", 1),
    ("SINH", 1),
    ("TANH", 1),
    ("EXP", 1),
    ("LOG", 1),
    ("LOG10", 1),
    ("SQRT", 1),
    ("AINT", 1),
    ("ANINT", 1),
    ("ATAN2", 2),
    ("MOD", 2),
    ("SIGN", 2),
    ("DIM", 2),
    ("MAX", 2),
    ("MIN", 2),
    ("STEP", 5),
    ("STEP5", 5),
    ("HAVSIN", 5),
    ("IMPACT", 7),
    ("BISTOP", 8),
    ("SHF", 6),
    ("SWEEP", 7),
    ("MAG", 0),
    ("IF", 0),
];

struct Gen {
    rng: StdRng,
    ifs: usize,
    nodes: usize,
}

impl Gen {
    fn leaf(&mut self) -> String {
        match self.rng.random_range(0..10) {
            0..=4 => VARS[self.rng.random_range(0..3)].to_string(),
            5 => "TIME".into(),
            _ => CONSTS[self.rng.random_range(0..CONSTS.len())].to_string(),
        }
    }

    /// A scalar expression at `depth` (the root is depth 1).
    fn scalar(&mut self, depth: usize) -> String {
        self.nodes += 1;
        let stop =
            depth >= MAX_DEPTH || self.nodes > 16 || self.rng.random_bool(depth as f64 / 14.0);
        if stop {
            return self.leaf();
        }
        let d = depth + 1;
        match self.rng.random_range(0..12) {
            0..=3 => {
                let op = ["+", "-", "*", "/", "**"][self.rng.random_range(0..5)];
                let rhs = if op == "**" && self.rng.random_bool(0.5) {
                    ["2", "3", "(-1)", "0", "4", "0.5"][self.rng.random_range(0..6)].to_string()
                } else {
                    self.scalar(d)
                };
                format!("({} {op} {rhs})", self.scalar(d))
            }
            4 => format!("-{}", self.scalar(d)),
            5 if self.ifs < MAX_IFS => self.if_(d),
            6 => self.vector_scalar(d),
            7 => {
                let name = ["POLY", "CHEBY", "FORCOS", "FORSIN"][self.rng.random_range(0..4)];
                let fixed = if name.starts_with("FOR") { 3 } else { 2 };
                let n = fixed + self.rng.random_range(1..5);
                let args: Vec<String> = (0..n).map(|_| self.scalar(d)).collect();
                format!("{name}({})", args.join(", "))
            }
            _ => {
                let (name, arity) = FIXED[self.rng.random_range(0..FIXED.len() - 2)];
                let args: Vec<String> = (0..arity).map(|_| self.arg(name, d)).collect();
                format!("{name}({})", args.join(", "))
            }
        }
    }

    /// An argument, biased towards the shapes that reach a function's interior (a plain
    /// variable next to ordered constants).
    fn arg(&mut self, name: &str, d: usize) -> String {
        if matches!(name, "IMPACT" | "BISTOP" | "STEP" | "STEP5" | "HAVSIN")
            && self.rng.random_bool(0.5)
        {
            return ["0", "1", "0.1", "2", "1E5", "1.5", "x", "y"][self.rng.random_range(0..8)]
                .into();
        }
        self.scalar(d)
    }

    fn if_(&mut self, d: usize) -> String {
        self.ifs += 1;
        let parts: Vec<String> = (0..4).map(|_| self.scalar(d)).collect();
        self.ifs -= 1;
        format!("IF({}: {}, {}, {})", parts[0], parts[1], parts[2], parts[3])
    }

    fn vector(&mut self, d: usize) -> String {
        let c: Vec<String> = (0..3).map(|_| self.scalar(d + 1)).collect();
        let v = format!("[{}, {}, {}]", c[0], c[1], c[2]);
        match self.rng.random_range(0..4) {
            0 => format!("({v} % [{}, 1, -2])", self.scalar(d + 1)),
            1 => format!("({} * {v})", self.scalar(d + 1)),
            2 => format!("({v} / {})", self.scalar(d + 1)),
            _ => v,
        }
    }

    fn vector_scalar(&mut self, d: usize) -> String {
        if self.rng.random_bool(0.5) {
            format!("MAG({})", self.vector(d))
        } else {
            format!("({} * {})", self.vector(d), self.vector(d))
        }
    }

    /// A whole expression: usually a scalar, sometimes a vector, sometimes nine nested IFs.
    fn expr(&mut self) -> String {
        self.nodes = 0;
        match self.rng.random_range(0..20) {
            0 => self.vector(1),
            1 => {
                let mut e = self.scalar(10);
                for _ in 0..MAX_IFS {
                    let (t, o, p) = (self.leaf(), self.leaf(), self.leaf());
                    e = format!("IF({t} - 0.5: {o}, {e}, {p} * 2)");
                }
                e
            }
            _ => self.scalar(1),
        }
    }

    fn input(&mut self) -> f64 {
        if self.rng.random_bool(0.6) {
            EDGES[self.rng.random_range(0..EDGES.len())]
        } else {
            self.rng.random_range(-3.0..3.0)
        }
    }
}

/// Compiles a batch from `seed`, evaluates both back ends, returns the first mismatch.
fn run_batch(jit: &mut Jit, seed: u64) -> Result<usize, String> {
    let mut g = Gen {
        rng: StdRng::seed_from_u64(seed),
        ifs: 0,
        nodes: 0,
    };
    let mut srcs = Vec::with_capacity(PER_CASE);
    let mut fs = Vec::with_capacity(PER_CASE);
    while fs.len() < PER_CASE {
        let src = g.expr();
        // Constant arguments outside a function's domain are check-time errors: skip them.
        if let Ok(f) = ir(&src) {
            srcs.push(src);
            fs.push(f);
        }
    }
    let refs: Vec<_> = fs.iter().collect();
    let compiled = jit.compile_batch(&refs).map_err(|e| e.to_string())?;
    let inputs: Vec<[f64; 4]> = (0..INPUTS)
        .map(|_| [g.input(), g.input(), g.input(), g.input()])
        .collect();
    // The inputs as columns, for the lane evaluator: all of them in one block, so an IF
    // meets lanes that pick different arms.
    let column = |k: usize| inputs.iter().map(|inp| inp[k]).collect::<Vec<f64>>();
    let (xs, ys, zs, ts) = (column(0), column(1), column(2), column(3));
    let columns = [
        Column::Values(&xs),
        Column::Values(&ys),
        Column::Values(&zs),
    ];
    for ((src, f), c) in srcs.iter().zip(fs).zip(&compiled) {
        let lanes =
            Lanes::new(&f).ok_or_else(|| format!("{src}: the lane evaluator refused it"))?;
        let p = Program::new(f);
        let n = p.function().outputs.len();
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        let mut by_lanes = vec![0.0; n * INPUTS];
        if !lanes.eval(&columns, Column::Values(&ts), INPUTS, &mut by_lanes) {
            return Err(format!("{src}: the lane evaluator refused the columns"));
        }
        for (inp, l) in inputs.iter().zip(by_lanes.chunks_exact(n)) {
            let ctx = Context::new(inp[3], &inp[..3]);
            p.eval_into(&ctx, &mut a);
            c.eval_into(&ctx, &mut b);
            if !a.iter().zip(&b).all(|(x, y)| same(*x, *y)) {
                return Err(format!(
                    "{src} at x,y,z,t = {inp:?}: interp {a:?}, jit {b:?}"
                ));
            }
            if !a.iter().zip(l).all(|(x, y)| same(*x, *y)) {
                return Err(format!(
                    "{src} at x,y,z,t = {inp:?}: interp {a:?}, lanes {l:?}"
                ));
            }
        }
    }
    Ok(srcs.len())
}

thread_local! {
    static JIT: std::cell::RefCell<Jit> = std::cell::RefCell::new(Jit::new().expect("host supported"));
}

fn agree(seed: u64) -> Result<(), TestCaseError> {
    let r = JIT.with(|j| run_batch(&mut j.borrow_mut(), seed));
    prop_assert!(r.is_ok(), "{}", r.err().unwrap_or_default());
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: CASES, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn interpreter_and_jit_agree_bit_for_bit_1(seed in any::<u64>()) { agree(seed)?; }
    #[test]
    fn interpreter_and_jit_agree_bit_for_bit_2(seed in any::<u64>()) { agree(seed)?; }
    #[test]
    fn interpreter_and_jit_agree_bit_for_bit_3(seed in any::<u64>()) { agree(seed)?; }
    #[test]
    fn interpreter_and_jit_agree_bit_for_bit_4(seed in any::<u64>()) { agree(seed)?; }
}

#[test]
fn the_shards_cover_200_000_expressions() {
    assert_eq!(SHARDS * CASES * PER_CASE as u32, 200_000);
}

/// Every lowered function at every combination of edge values of its arguments (STEP and
/// friends with 5 arguments: 16⁵ combinations; the contact functions on a grid that keeps
/// the run short), against the interpreter, which calls the runtime.
#[test]
fn lowering_equals_runtime_on_edge_grids() {
    let mut jit = Jit::new().unwrap();
    let grid = |n: usize| -> Vec<Vec<f64>> {
        let mut out = vec![vec![]];
        for _ in 0..n {
            out = out
                .into_iter()
                .flat_map(|p| {
                    EDGES.iter().map(move |&e| {
                        let mut q = p.clone();
                        q.push(e);
                        q
                    })
                })
                .collect();
        }
        out
    };
    for (name, arity) in [
        ("MIN", 2),
        ("MAX", 2),
        ("DIM", 2),
        ("SIGN", 2),
        ("STEP", 3),
        ("STEP5", 3),
        ("HAVSIN", 3),
        ("POLY", 3),
    ] {
        // The first `arity` arguments vary over the grid through x, y, z; STEP-like take
        // constants for the rest (a fixed x0 < x1 keeps the grid valid), POLY three terms.
        let src = match name {
            "STEP" | "STEP5" | "HAVSIN" => format!("{name}(x, y, z, 1, -2)"),
            "POLY" => "POLY(x, y, z, 2, -0.5) + POLY(x, 1, z)".to_string(),
            _ => format!("{name}(x, y)"),
        };
        let f = ir(&src).unwrap();
        let c = jit.compile(&f).unwrap();
        let p = Program::new(f);
        for v in grid(arity) {
            let vars = [
                v[0],
                v.get(1).copied().unwrap_or(0.0),
                v.get(2).copied().unwrap_or(0.0),
            ];
            let ctx = Context::new(0.0, &vars);
            assert!(same(p.eval(&ctx), c.eval(&ctx)), "{src} at {vars:?}");
        }
    }
    for src in [
        "STEP(x, y, z, x*y, z - x)",
        "IMPACT(x, y, z, 1E5, 1.5, 50, 0.1)",
        "IMPACT(x, y, 1, z, 1.5, z, x)",
        "BISTOP(x, y, z, 1, 1E5, 1.5, 50, 0.1)",
        "BISTOP(x, y, -1, z, 1000, 2, 10, 0.1)",
        "BISTOP(x, 1, y, z, x, 1.5, 10, 0.5)",
        // Constant parameters: the JIT's lowering (a branch on contact, selects inside).
        "IMPACT(x, y, 1, 1E5, 1.5, 50, 0.1) + z",
        "IMPACT(x, y, 0, 1000, 2, 0, 2) + IMPACT(z, y, -1, 0, 0.5, 10, 1E-300)",
        "BISTOP(x, y, 0.5, 1.5, 1E5, 1.5, 50, 0.1) - z",
        "BISTOP(x, y, -1, 0, 1000, 2, 0, 2) + BISTOP(z, x, -1E300, 1E300, 1, 3, 1, 1)",
        // POLY about +0 skips the subtraction x − 0.
        "POLY(x, 0, y, z) + POLY(z, 0, 1.5) * POLY(y, -0, 2, x)",
        // Infinite contact positions stay runtime calls.
        "IMPACT(x, y, 1E999, 1, 1.5, 1, 0.1) + BISTOP(x, y, -1E999, z, 1, 1, 1, 1)",
    ] {
        let f = ir(src).unwrap();
        let c = jit.compile(&f).unwrap();
        let p = Program::new(f);
        for v in grid(3) {
            let ctx = Context::new(0.0, &v);
            assert!(same(p.eval(&ctx), c.eval(&ctx)), "{src} at {v:?}");
        }
    }
}

/// A seed whose batch once broke SSA dominance in the JIT: a value anchored across an IF
/// nested in another IF's arm was reloaded where the other arms could not see it
/// (`jit/anchor.rs`). The expression is also a regression test of its own below.
#[test]
fn nested_if_anchor_regression_seed() {
    agree(6216517326490059351).unwrap();
}

/// The user variables of [`support::scope`] with dimensions (x a length, y a velocity, z
/// a time) and units checked, as a dataset's measures would be.
struct Dimensioned(mbfx::check::Variables);

impl mbfx::check::Scope for Dimensioned {
    fn variable(&self, name: &str) -> Option<u32> {
        self.0.variable(name)
    }

    fn unit_names(&self) -> Option<&UnitNames> {
        static SI: UnitNames = UnitNames::SI;
        Some(&SI)
    }

    fn variable_dim(&self, name: &str) -> Option<Dim> {
        match name {
            "X" => Some(Dim::LENGTH),
            "Y" => Some(Dim::VELOCITY),
            "Z" => Some(Dim::TIME),
            _ => None,
        }
    }
}

/// Compiles a batch from `seed` with and without the units check: the same IR, and the
/// same bits from both engines with either. Returns how many unit warnings it met.
fn units_change_nothing(jit: &mut Jit, seed: u64) -> Result<usize, String> {
    use mbfx::check::{compile, Expect};
    let mut g = Gen {
        rng: StdRng::seed_from_u64(seed),
        ifs: 0,
        nodes: 0,
    };
    let (plain, dims) = (
        super::support::scope(),
        Dimensioned(super::support::scope()),
    );
    let mut fs = Vec::new();
    let mut warned = 0;
    while fs.len() < 2 * UNITS_PER_CASE {
        let src = g.expr();
        let (Ok(a), Ok(b)) = (
            compile(&src, &plain, Expect::Any),
            compile(&src, &dims, Expect::Any),
        ) else {
            continue;
        };
        let print = |f| mbfx::ir::print::print(f);
        if print(&a.function) != print(&b.function) {
            return Err(format!("{src}: the IR differs with units checked"));
        }
        warned += b.warnings.len() - a.warnings.len();
        fs.push((src.clone(), a.function));
        fs.push((src, b.function));
    }
    let refs: Vec<_> = fs.iter().map(|(_, f)| f).collect();
    let compiled = jit.compile_batch(&refs).map_err(|e| e.to_string())?;
    let inputs = [
        [g.input(), g.input(), g.input(), g.input()],
        [0.5, -2.0, 3.0, 1.25],
    ];
    for inp in inputs {
        let ctx = Context::new(inp[3], &inp[..3]);
        let mut values = Vec::new();
        for ((src, f), c) in fs.iter().zip(&compiled) {
            let n = f.outputs.len();
            let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
            Program::new(f.clone()).eval_into(&ctx, &mut a);
            c.eval_into(&ctx, &mut b);
            values.push((src, a, b));
        }
        for pair in values.chunks_exact(2) {
            let (src, a0, b0) = &pair[0];
            let (_, a1, b1) = &pair[1];
            let all = a0.iter().zip(b0).zip(a1.iter().zip(b1));
            if !all
                .into_iter()
                .all(|((w, x), (y, z))| same(*w, *x) && same(*w, *y) && same(*w, *z))
            {
                return Err(format!("{src} at {inp:?}: {a0:?} {b0:?} {a1:?} {b1:?}"));
            }
        }
    }
    Ok(warned)
}

/// Expressions per case of the units property.
const UNITS_PER_CASE: usize = 25;

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    /// Checking units reads the tree only: the IR and every value are the same, bit for
    /// bit and in both engines, with the check and without.
    #[test]
    fn checking_units_never_changes_a_value(seed in any::<u64>()) {
        let r = JIT.with(|j| units_change_nothing(&mut j.borrow_mut(), seed));
        prop_assert!(r.is_ok(), "{}", r.err().unwrap_or_default());
    }
}

/// The property above meets unit warnings (it is not vacuous): generated expressions
/// add a length to a velocity often enough.
#[test]
fn the_units_property_meets_unit_warnings() {
    let warned: usize = (0..8)
        .map(|seed| JIT.with(|j| units_change_nothing(&mut j.borrow_mut(), seed)))
        .map(|r| r.expect("no difference"))
        .sum();
    assert!(
        warned > 10,
        "only {warned} unit warnings in 200 expressions"
    );
}
