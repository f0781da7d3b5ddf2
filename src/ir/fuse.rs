//! One function from several: every function's instructions rebuilt into one builder,
//! its outputs after the previous function's. A host that evaluates many expressions at
//! one state (a model's forces) then makes one call instead of one per expression, with
//! the measure slots filled once; the builder shares what the expressions have in common
//! (the same measure, the same constant). Each output is computed by the same operations
//! as in its own function, so it has the same bits.

use super::builder::Builder;
use super::rebuild::{constants, copy, copy_if, if_extra};
use super::{Function, Inst, Value};
use rustc_hash::FxHashMap;

/// The function whose outputs are `functions`' outputs, in order.
pub fn fuse(functions: &[&Function]) -> Function {
    let mut b = Builder::new();
    let mut outputs = Vec::new();
    for f in functions {
        let mut m = constants(f, &mut b, None);
        let mut ifs = FxHashMap::default();
        walk(f, &mut b, &mut m, &mut ifs, &f.body);
        outputs.extend(f.outputs.iter().map(|&o| m[o as usize]));
    }
    b.finish(&outputs)
}

/// Rebuilds `values` of `f` into `b`, mapping old values to new ones in `m`.
fn walk(
    f: &Function,
    b: &mut Builder,
    m: &mut [Value],
    ifs: &mut FxHashMap<Value, Vec<Value>>,
    values: &[Value],
) {
    for &v in values {
        let span = f.spans[v as usize].clone();
        let new = match f.inst(v) {
            Inst::If { test, arms } => {
                let arm = |b: &mut Builder, m: &mut [Value], insts: &[Value]| {
                    walk(f, b, m, ifs, insts);
                    Ok::<(), std::convert::Infallible>(())
                };
                let Ok(results) = copy_if(b, m, *test, arms, span, arm);
                let first = results[0];
                ifs.insert(v, results);
                first
            }
            Inst::IfExtra { of, index } => if_extra(ifs, *of, *index),
            inst => copy(b, inst, span, m),
        };
        m[v as usize] = new;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::{compile, Expect, Variables};
    use crate::context::Context;
    use crate::interp::Program;

    #[test]
    fn a_fused_function_gives_each_output_of_its_parts_bit_for_bit() {
        let mut scope = Variables::new();
        scope.define("x");
        scope.define("y");
        let sources = [
            "SIN(x)*y + 1",
            "IF(x - y: x**2, 0, STEP(x, 0, 0, 1, y))",
            "IMPACT(x, y, 1, 1E5, 1.5, 50, 0.1)",
            "x/y",
        ];
        let fs: Vec<Function> = sources
            .iter()
            .map(|s| compile(s, &scope, Expect::Scalar).unwrap().function)
            .collect();
        let fused = fuse(&fs.iter().collect::<Vec<_>>());
        assert_eq!(fused.outputs.len(), sources.len());
        let jit = crate::jit::Jit::new().unwrap().compile(&fused).unwrap();
        for vars in [[0.3, 0.7], [0.9, 0.2], [-1.0, 4.0], [0.95, 0.0]] {
            let ctx = Context::new(0.0, &vars);
            let (mut a, mut b) = (vec![0.0; 4], vec![0.0; 4]);
            Program::new(fused.clone()).eval_into(&ctx, &mut a);
            jit.eval_into(&ctx, &mut b);
            for (k, f) in fs.iter().enumerate() {
                let alone = Program::new(f.clone()).eval(&ctx);
                let same =
                    |x: f64| x.to_bits() == alone.to_bits() || (x.is_nan() && alone.is_nan());
                assert!(
                    same(a[k]) && same(b[k]),
                    "{}: {} {} {alone}",
                    sources[k],
                    a[k],
                    b[k]
                );
            }
        }
    }
}
