//! Interpreter ≡ JIT on every corpus expression that checks (`../shared/corpus/`),
//! compiled as one JIT module per file, with measures, TIME and a SPLINE supplied at
//! several values.

use super::support::same;
use mbfx::check::{compile, EveryIdExists, Expect};
use mbfx::context::Context;
use mbfx::interp::Program;
use mbfx::jit::Jit;
use mbfx_runtime::Spline;

fn corpus(name: &str) -> Vec<(String, mbfx::ir::Function)> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/corpus")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .filter_map(|l| l.split_once('\t'))
        .filter_map(|(_, e)| {
            compile(e, &EveryIdExists, Expect::Any)
                .ok()
                .map(|c| (e.to_string(), c.function))
        })
        .collect()
}

#[test]
fn corpus_expressions_agree_bit_for_bit() {
    let xs: Vec<f64> = (0..8).map(|i| f64::from(i) * 0.5 - 1.0).collect();
    let ys: Vec<f64> = xs.iter().map(|x| x * x - 0.5 * x).collect();
    let splines = [Spline::new(xs, vec![0.0], ys).expect("valid spline")];
    let mut jit = Jit::new().unwrap();
    let mut total = 0;
    for (file, min) in [("expressions.txt", 900), ("expressions-cmd.txt", 25)] {
        let exprs = corpus(file);
        assert!(
            exprs.len() >= min,
            "{file}: only {} expressions check",
            exprs.len()
        );
        let refs: Vec<_> = exprs.iter().map(|(_, f)| f).collect();
        let compiled = jit.compile_batch(&refs).unwrap();
        for ((src, f), c) in exprs.iter().zip(&compiled) {
            let p = Program::new(f.clone());
            let n = f.outputs.len();
            let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
            for (t, m) in [
                (0.0, [0.0, 0.0, 0.0]),
                (0.37, [0.25, -1.5, 2.0]),
                (2.5, [-0.75, 3.0, -0.0]),
                (-1.0, [1e-3, 1e3, 7.0]),
            ] {
                let ctx = Context::new(t, &[])
                    .with_measures(&m)
                    .with_splines(&splines);
                p.eval_into(&ctx, &mut a);
                c.eval_into(&ctx, &mut b);
                assert!(
                    a.iter().zip(&b).all(|(x, y)| same(*x, *y)),
                    "{file}: {src} at t={t}, m={m:?}: {a:?} vs {b:?}"
                );
            }
            total += 1;
        }
    }
    assert!(total >= 925, "{total}");
}
