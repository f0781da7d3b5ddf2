//! The switching functions of IMPACT and BISTOP (spec expr-language §5.4–5.5): where a
//! force expression calls them, the signed quantities whose zeros are the instants their
//! force changes branch. [`ContactProbe`] finds the calls in a force's IR once, keeps a
//! program that computes just their arguments, and turns the arguments at a state into
//! switching values for the step control ([`crate::mbd::dynamics::events::Events`]).
//!
//! Each value is positive on the side where the branch acts and NaN where the switch
//! means nothing (the clamp of a contact that is not touching):
//! - contact: the penetration, x1 − x below the lower stop, x − x2 above BISTOP's upper
//!   one (the runtime's `x < x1` and `x > x2`);
//! - clamp, while in contact: the unclamped force pushing away from the stop,
//!   k·p^e − STEP(x, x1 − d, cmax, x1, 0)·ẋ below, k·p^e + STEP(x, x2, 0, x2 + d, cmax)·ẋ
//!   above (the runtime's `f > 0` and `f < 0`).
//!
//! The kinks of the damping STEP at a penetration of d are left alone: the force stays
//! C¹ there, which a second-order method does not notice.
//!
//! Calls inside an arithmetic IF's arms are not watched (their arguments exist only on
//! one arm); neither are calls whose arguments read splines or user variables, which the
//! probe's context does not carry (their values come out NaN and are ignored).

use crate::context::Context;
use crate::interp::Program;
use crate::ir::builder::collect_uses;
use crate::ir::{Function, Inst, Uses, Value};
use crate::vocab::func::Func;
use mbfx_runtime::step;
use std::cell::RefCell;

/// Which law a watched call evaluates.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Law {
    Impact,
    Bistop,
}

impl Law {
    /// How many arguments the call takes and how many switches it has.
    fn arity(self) -> usize {
        match self {
            Law::Impact => 7,
            Law::Bistop => 8,
        }
    }

    fn switches(self) -> usize {
        match self {
            Law::Impact => 2,
            Law::Bistop => 4,
        }
    }
}

/// The IMPACT and BISTOP calls of one force expression and a program computing their
/// arguments.
pub struct ContactProbe {
    /// The laws in call order; the program's outputs are their arguments, concatenated.
    laws: Vec<Law>,
    program: Program,
    /// The argument values of the last evaluation.
    args: RefCell<Vec<f64>>,
}

impl ContactProbe {
    /// The probe of the expression `f`, None when it calls neither law at its top level.
    pub fn of(f: &Function) -> Option<ContactProbe> {
        let (mut laws, mut outputs) = (Vec::new(), Vec::new());
        for &v in &f.body {
            let Inst::Call(func, args) = f.inst(v) else {
                continue;
            };
            let law = match func {
                Func::Impact => Law::Impact,
                Func::Bistop => Law::Bistop,
                _ => continue,
            };
            if args.len() == law.arity() {
                laws.push(law);
                outputs.extend_from_slice(args);
            }
        }
        if laws.is_empty() {
            return None;
        }
        let n = outputs.len();
        Some(ContactProbe {
            laws,
            program: Program::new(arguments_of(f, outputs)),
            args: RefCell::new(vec![f64::NAN; n]),
        })
    }

    /// How many switching values [`ContactProbe::eval`] gives.
    pub fn count(&self) -> usize {
        self.laws.iter().map(|l| l.switches()).sum()
    }

    /// Appends the switching values at time `t` with the measure slots `measures` (as
    /// the force expression reads them) to `out`.
    pub fn eval(&self, t: f64, measures: &[f64], out: &mut Vec<f64>) {
        let mut args = self.args.borrow_mut();
        self.program
            .eval_into(&Context::new(t, &[]).with_measures(measures), &mut args);
        let mut rest = &args[..];
        for &law in &self.laws {
            let (a, tail) = rest.split_at(law.arity());
            rest = tail;
            match law {
                Law::Impact => lower(a[0], a[1], a[2], [a[3], a[4], a[5], a[6]], out),
                Law::Bistop => {
                    let (x, xd, x1, x2) = (a[0], a[1], a[2], a[3]);
                    let law = [a[4], a[5], a[6], a[7]];
                    lower(x, xd, x1, law, out);
                    upper(x, xd, x2, law, out);
                }
            }
        }
    }
}

/// The switches of the stop below x1: penetration x1 − x, and in contact the unclamped
/// force k·p^e − STEP(x, x1 − d, cmax, x1, 0)·ẋ.
fn lower(x: f64, xd: f64, x1: f64, [k, e, cmax, d]: [f64; 4], out: &mut Vec<f64>) {
    let p = x1 - x;
    out.push(p);
    out.push(if p > 0.0 {
        k * p.powf(e) - step(x, x1 - d, cmax, x1, 0.0) * xd
    } else {
        f64::NAN
    });
}

/// The switches of BISTOP's stop above x2: penetration x − x2, and in contact the
/// unclamped force's magnitude toward x2, k·p^e + STEP(x, x2, 0, x2 + d, cmax)·ẋ.
fn upper(x: f64, xd: f64, x2: f64, [k, e, cmax, d]: [f64; 4], out: &mut Vec<f64>) {
    let p = x - x2;
    out.push(p);
    out.push(if p > 0.0 {
        k * p.powf(e) + step(x, x2, 0.0, x2 + d, cmax) * xd
    } else {
        f64::NAN
    });
}

/// `f` reduced to the instructions `outputs` need, with those as its outputs (all of
/// `f`'s body when they need an IF, whose arms read values of their own).
fn arguments_of(f: &Function, outputs: Vec<Value>) -> Function {
    let mut need = vec![false; f.insts.len()];
    for &o in &outputs {
        need[o as usize] = true;
    }
    let mut branches = false;
    for &v in f.body.iter().rev() {
        if !need[v as usize] {
            continue;
        }
        match f.inst(v) {
            Inst::If { .. } | Inst::IfExtra { .. } => branches = true,
            inst => inst.each_operand(|a| need[a as usize] = true),
        }
    }
    if branches {
        return Function {
            outputs,
            ..f.clone()
        };
    }
    let body = f.body.iter().copied().filter(|&v| need[v as usize]);
    let mut g = Function {
        insts: f.insts.clone(),
        spans: f.spans.clone(),
        body: body.collect(),
        outputs,
        uses: Uses::default(),
    };
    g.uses = collect_uses(&g);
    g
}

#[cfg(test)]
mod tests {
    //! The switching values at the spec's examples (expr-language §5.4–5.5). Measures
    //! of the checking scope all read slot 0, so ẋ comes in as TIME.
    use super::*;
    use crate::check::{compile, EveryIdExists, Expect};

    /// The probe of `text`, which must call a contact law.
    fn probe(text: &str) -> ContactProbe {
        let checked = compile(text, &EveryIdExists, Expect::Scalar).expect("valid");
        ContactProbe::of(&checked.function).expect("calls a contact law")
    }

    fn values(p: &ContactProbe, x: f64, xd: f64) -> Vec<f64> {
        let mut out = Vec::new();
        p.eval(xd, &[x], &mut out);
        assert_eq!(out.len(), p.count());
        out
    }

    #[test]
    fn impact_switches_on_contact_and_on_the_clamp() {
        let p = probe("IMPACT(DX(2,1), TIME, 1, 1E5, 1.5, 100, 0.1)");
        // In contact and pushing: 1118.034 + 100 (spec §5.4).
        let v = values(&p, 0.95, -2.0);
        assert!((v[0] - 0.05).abs() < 1e-15);
        assert!((v[1] - 1218.0339887498967).abs() < 1e-9, "{}", v[1]);
        // The discriminating case: clamped, the unclamped force −381.966.
        let v = values(&p, 0.95, 30.0);
        assert!((v[1] + 381.96601125010625).abs() < 1e-9, "{}", v[1]);
        // Off the stop (x = x1 is off): no clamp to speak of.
        let v = values(&p, 1.0, -5.0);
        assert!(v[0] == 0.0 && v[1].is_nan());
    }

    #[test]
    fn bistop_switches_at_both_stops() {
        let p = probe("BISTOP(DX(2,1), TIME, -2, 2, 1000, 2, 10, 0.1)");
        // Above x2, pushing back: −(−2.5 − 5) = 7.5; moving in fast, clamped: −47.5.
        let v = values(&p, 2.05, 1.0);
        assert!(v[0] < 0.0 && v[1].is_nan());
        assert!(
            (v[2] - 0.05).abs() < 1e-15 && (v[3] - 7.5).abs() < 1e-12,
            "{v:?}"
        );
        assert!((values(&p, 2.05, -10.0)[3] + 47.5).abs() < 1e-12);
        // Below x1: the lower stop's, as IMPACT's.
        let v = values(&p, -2.05, -1.0);
        assert!(
            (v[0] - 0.05).abs() < 1e-15 && (v[1] - 7.5).abs() < 1e-12,
            "{v:?}"
        );
        assert!(v[2] < 0.0 && v[3].is_nan());
    }

    #[test]
    fn the_probe_computes_only_the_arguments() {
        // The spline elsewhere in the expression is not needed (the probe's context has
        // no splines): the switching values are still there.
        let p = probe("IMPACT(DX(2,1), TIME, 1, 1E5, 1.5, 100, 0.1) + AKISPL(TIME, 0, 1)");
        assert!(p.program.uses().splines.is_empty());
        assert!((values(&p, 0.95, -2.0)[1] - 1218.0339887498967).abs() < 1e-9);
        // Two calls: their switches in call order.
        let p =
            probe("IMPACT(DX(2,1), TIME, 1, 1E5, 1.5, 0, 0.1) - IMPACT(DX(2,1), 0, 0, 1, 1, 0, 1)");
        assert_eq!(p.count(), 4);
        assert!(ContactProbe::of(
            &compile("DX(2,1)", &EveryIdExists, Expect::Scalar)
                .unwrap()
                .function
        )
        .is_none());
    }
}
