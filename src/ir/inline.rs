//! Inlining of functions in place of measure slots: how a model's `VARVAL(id)` becomes the
//! expression of its VARIABLE/id.
//!
//! [`inline_measures`] rebuilds a function with every `Measure(slot)` for which `with`
//! gives a (scalar) function replaced by that function's instructions, recursively (a
//! VARIABLE may read another). The substituted code reads the slots of the functions it
//! came from, which share the model's slot table. Everything downstream (derivatives, the
//! JIT, the set of measures computed) then sees plain measures. The inlined instructions
//! take the span of the measure call they replace, so a run-time diagnostic points at the
//! `VARVAL` the user wrote.

use super::builder::Builder;
use super::rebuild::{constants, copy, copy_if, if_extra, UNSET};
use super::{Function, Inst, Value};
use crate::diag::Span;
use rustc_hash::FxHashMap;

/// Deepest chain of functions reading functions (VARIABLE reading VARIABLE ...).
pub const MAX_INLINE_DEPTH: usize = 64;

/// Why a substitution cannot be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum InlineError {
    /// The slot's function reads itself, through the slots listed (first to last).
    Cycle(Vec<u32>),
    /// The chain of functions is deeper than [`MAX_INLINE_DEPTH`].
    TooDeep,
}

/// `f` with the measure slots `with` maps replaced by their functions.
pub fn inline_measures<'a>(
    f: &Function,
    with: &dyn Fn(u32) -> Option<&'a Function>,
) -> Result<Function, InlineError> {
    let mut b = Builder::new();
    let mut active = Vec::new();
    let m = body(f, &mut b, with, &mut active, None)?;
    let outputs: Vec<Value> = f.outputs.iter().map(|&o| m[o as usize]).collect();
    Ok(b.finish(&outputs))
}

/// Rebuilds `f`'s body into `b`; returns the value map. `span`, when given, replaces every
/// span (inlined code).
fn body<'a>(
    f: &Function,
    b: &mut Builder,
    with: &dyn Fn(u32) -> Option<&'a Function>,
    active: &mut Vec<u32>,
    span: Option<&Span>,
) -> Result<Vec<Value>, InlineError> {
    let mut m = constants(f, b, span);
    let mut ifs = FxHashMap::default();
    let mut walk = Walk {
        f,
        with,
        active,
        span,
        ifs: &mut ifs,
    };
    walk.list(b, &mut m, &f.body)?;
    Ok(m)
}

struct Walk<'w, 'a> {
    f: &'w Function,
    with: &'w dyn Fn(u32) -> Option<&'a Function>,
    active: &'w mut Vec<u32>,
    span: Option<&'w Span>,
    ifs: &'w mut FxHashMap<Value, Vec<Value>>,
}

impl Walk<'_, '_> {
    fn list(
        &mut self,
        b: &mut Builder,
        m: &mut [Value],
        values: &[Value],
    ) -> Result<(), InlineError> {
        for &v in values {
            let span = self.span.unwrap_or(&self.f.spans[v as usize]).clone();
            let new = match self.f.inst(v) {
                Inst::Measure(slot) => match (self.with)(*slot) {
                    Some(g) => self.inline(b, *slot, g, &span)?,
                    None => b.measure(*slot, span),
                },
                Inst::If { test, arms } => {
                    let walk =
                        |b: &mut Builder, m: &mut [Value], insts: &[Value]| self.list(b, m, insts);
                    let results = copy_if(b, m, *test, arms, span, walk)?;
                    let first = results[0];
                    self.ifs.insert(v, results);
                    first
                }
                Inst::IfExtra { of, index } => if_extra(self.ifs, *of, *index),
                inst => copy(b, inst, span, m),
            };
            m[v as usize] = new;
        }
        Ok(())
    }

    /// Emits `g` (the function of `slot`) here; its value.
    fn inline(
        &mut self,
        b: &mut Builder,
        slot: u32,
        g: &Function,
        span: &Span,
    ) -> Result<Value, InlineError> {
        if let Some(at) = self.active.iter().position(|&s| s == slot) {
            return Err(InlineError::Cycle(self.active[at..].to_vec()));
        }
        if self.active.len() >= MAX_INLINE_DEPTH {
            return Err(InlineError::TooDeep);
        }
        self.active.push(slot);
        let m = body(g, b, self.with, self.active, Some(span))?;
        self.active.pop();
        Ok(g.outputs.first().map_or(UNSET, |&o| m[o as usize]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::context::Context;
    use crate::interp::Program;

    /// A function of measure slots written as `M0`, `M1`, ... through the builder.
    fn measures_fn(build: impl FnOnce(&mut Builder) -> Value) -> Function {
        let mut b = Builder::new();
        let out = build(&mut b);
        b.finish(&[out])
    }

    #[test]
    fn slots_become_their_functions_recursively() {
        use super::super::builder::Arith;
        let s = Span::default();
        // f = M0 * 2 + M1; slot 0 is g = M2 + 1; slot 2 is h = M3 * M3; slot 1 stays.
        let f = measures_fn(|b| {
            let (m0, m1, two) = (
                b.measure(0, s.clone()),
                b.measure(1, s.clone()),
                b.constant(2.0, s.clone()),
            );
            let p = b.arith(Arith::Mul, m0, two, s.clone());
            b.arith(Arith::Add, p, m1, s.clone())
        });
        let g = measures_fn(|b| {
            let (m2, one) = (b.measure(2, s.clone()), b.constant(1.0, s.clone()));
            b.arith(Arith::Add, m2, one, s.clone())
        });
        let h = measures_fn(|b| {
            let m3 = b.measure(3, s.clone());
            b.arith(Arith::Mul, m3, m3, s.clone())
        });
        let with = |slot: u32| match slot {
            0 => Some(&g),
            2 => Some(&h),
            _ => None,
        };
        let inlined = inline_measures(&f, &with).unwrap();
        assert_eq!(inlined.uses.measures, vec![1, 3]);
        let measures = [f64::NAN, 5.0, f64::NAN, 3.0];
        let v = Program::new(inlined).eval(&Context::new(0.0, &[]).with_measures(&measures));
        // (3·3 + 1)·2 + 5
        assert_eq!(v, 25.0);
    }

    #[test]
    fn a_function_reading_itself_is_a_cycle() {
        let s = Span::default();
        let f = measures_fn(|b| b.measure(0, s.clone()));
        let g = measures_fn(|b| b.measure(1, s.clone()));
        let h = measures_fn(|b| b.measure(0, s.clone()));
        let with = |slot: u32| match slot {
            0 => Some(&g),
            1 => Some(&h),
            _ => None,
        };
        assert_eq!(
            inline_measures(&f, &with).err(),
            Some(InlineError::Cycle(vec![0, 1]))
        );
    }
}
