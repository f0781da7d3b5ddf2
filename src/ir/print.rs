//! Text form of the IR, for the REPL's `:ir` and for tests.

use super::{Function, Inst, Value};
use crate::vocab::func::Func;
use std::fmt::Write as _;

/// Prints a function: one instruction per line, IF arms indented, then the outputs.
pub fn print(f: &Function) -> String {
    let mut out = String::new();
    let consts: Vec<String> = f
        .insts
        .iter()
        .enumerate()
        .filter_map(|(i, inst)| match inst {
            Inst::Const(c) => Some(format!("v{i} = {c:?}")),
            _ => None,
        })
        .collect();
    if !consts.is_empty() {
        let _ = writeln!(out, "const {}", consts.join(", "));
    }
    block(f, &f.body, 0, &mut out);
    let outs: Vec<String> = f.outputs.iter().map(|v| format!("v{v}")).collect();
    let _ = writeln!(out, "return {}", outs.join(", "));
    out
}

fn block(f: &Function, list: &[Value], indent: usize, out: &mut String) {
    for &v in list {
        let pad = "  ".repeat(indent);
        let text = match f.inst(v) {
            Inst::Const(c) => format!("{c:?}"),
            Inst::Var(s) => format!("var[{s}]"),
            Inst::Time => "time".into(),
            Inst::Mode => "mode".into(),
            Inst::Measure(s) => format!("measure[{s}]"),
            Inst::Neg(a) => format!("neg v{a}"),
            Inst::Add(a, b) => format!("add v{a}, v{b}"),
            Inst::Sub(a, b) => format!("sub v{a}, v{b}"),
            Inst::Mul(a, b) => format!("mul v{a}, v{b}"),
            Inst::Div(a, b) => format!("div v{a}, v{b}"),
            Inst::Sqrt(a) => format!("sqrt v{a}"),
            Inst::Call(func, args) => {
                let args: Vec<String> = args.iter().map(|a| format!("v{a}")).collect();
                format!("call {} {}", func.symbol(), args.join(", "))
            }
            Inst::Spline {
                kind,
                x,
                z,
                spline,
                iord,
            } => format!("spline {kind:?}[{spline}] v{x}, v{z}, iord {iord}"),
            Inst::IfExtra { of, index } => format!("result {} of v{of}", index + 1),
            Inst::Select {
                cmp,
                a,
                b,
                then,
                otherwise,
            } => format!("select v{a} {} v{b} ? v{then} : v{otherwise}", cmp.symbol()),
            Inst::Partial { func, wrt, args } => {
                let args: Vec<String> = args.iter().map(|a| format!("v{a}")).collect();
                format!("partial[{wrt}] {} {}", func.symbol(), args.join(", "))
            }
            Inst::If { test, arms } => {
                let _ = writeln!(out, "{pad}v{v} = if v{test}");
                for (label, arm) in ["<0", "=0", ">0"].iter().zip(arms.iter()) {
                    let _ = writeln!(out, "{pad}  {label}:");
                    block(f, &arm.insts, indent + 2, out);
                    let results: Vec<String> = std::iter::once(&arm.result)
                        .chain(&arm.extra)
                        .map(|r| format!("v{r}"))
                        .collect();
                    let _ = writeln!(out, "{pad}    yield {}", results.join(", "));
                }
                continue;
            }
        };
        let _ = writeln!(out, "{pad}v{v} = {text}");
    }
}

/// Output `index` of `f` as one expression in the language's notation (shared
/// subexpressions repeated), for the REPL's `:deriv`. `name` names variable slots.
/// Derivative code uses two forms the language lacks: `∂F/∂k(args)` (partial of library
/// function F in its k-th argument, from 1) and `(a < b ? c : d)` (a select). Longer than
/// `limit` characters gives `None`.
pub fn expression(
    f: &Function,
    index: usize,
    name: &dyn Fn(u32) -> String,
    limit: usize,
) -> Option<String> {
    let mut out = String::new();
    let v = *f.outputs.get(index)?;
    expr(f, v, None, name, &mut out, limit).then_some(out)
}

/// Writes value `v` (or, with `extra = Some(i)`, extra result i of the IF `v`); false once
/// `out` passes `limit`.
fn expr(
    f: &Function,
    v: Value,
    extra: Option<usize>,
    name: &dyn Fn(u32) -> String,
    out: &mut String,
    limit: usize,
) -> bool {
    if out.len() > limit {
        return false;
    }
    let mut sub = |v: Value, out: &mut String| expr(f, v, None, name, out, limit);
    let list =
        |args: &[Value], out: &mut String, sub: &mut dyn FnMut(Value, &mut String) -> bool| {
            for (i, &a) in args.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                if !sub(a, out) {
                    return false;
                }
            }
            true
        };
    let bin = |a: Value,
               op: &str,
               b: Value,
               out: &mut String,
               sub: &mut dyn FnMut(Value, &mut String) -> bool| {
        out.push('(');
        let ok = sub(a, out);
        out.push_str(op);
        let ok = ok && sub(b, out);
        out.push(')');
        ok
    };
    match f.inst(v) {
        Inst::Const(c) if *c < 0.0 || (*c == 0.0 && c.is_sign_negative()) => {
            let _ = write!(out, "({c:?})");
            true
        }
        Inst::Const(c) => {
            let _ = write!(out, "{c:?}");
            true
        }
        Inst::Var(s) => {
            out.push_str(&name(*s));
            true
        }
        Inst::Time => {
            out.push_str("TIME");
            true
        }
        Inst::Mode => {
            out.push_str("MODE");
            true
        }
        Inst::Measure(s) => {
            let _ = write!(out, "measure[{s}]");
            true
        }
        Inst::Neg(a) => {
            out.push_str("(-");
            let ok = sub(*a, out);
            out.push(')');
            ok
        }
        Inst::Add(a, b) => bin(*a, " + ", *b, out, &mut sub),
        Inst::Sub(a, b) => bin(*a, " - ", *b, out, &mut sub),
        Inst::Mul(a, b) => bin(*a, "*", *b, out, &mut sub),
        Inst::Div(a, b) => bin(*a, "/", *b, out, &mut sub),
        Inst::Sqrt(a) => {
            out.push_str("SQRT(");
            let ok = sub(*a, out);
            out.push(')');
            ok
        }
        Inst::Call(func, args) => {
            let _ = write!(out, "{}(", adams_name(*func));
            let ok = list(args, out, &mut sub);
            out.push(')');
            ok
        }
        Inst::Partial { func, wrt, args } => {
            let _ = write!(out, "∂{}/∂{}(", adams_name(*func), wrt + 1);
            let ok = list(args, out, &mut sub);
            out.push(')');
            ok
        }
        Inst::Spline {
            kind,
            x,
            z,
            spline,
            iord,
        } => {
            let _ = write!(out, "{kind:?}SPL[{spline}](");
            let ok = list(&[*x, *z], out, &mut sub);
            let _ = write!(out, ", {iord})");
            ok
        }
        Inst::Select {
            cmp,
            a,
            b,
            then,
            otherwise,
        } => {
            out.push('(');
            let mut ok = sub(*a, out);
            let _ = write!(out, " {} ", cmp.symbol());
            ok = ok && sub(*b, out);
            out.push_str(" ? ");
            ok = ok && sub(*then, out);
            out.push_str(" : ");
            ok = ok && sub(*otherwise, out);
            out.push(')');
            ok
        }
        Inst::If { test, arms } => {
            out.push_str("IF(");
            let mut ok = sub(*test, out);
            for (i, arm) in arms.iter().enumerate() {
                out.push_str(if i == 0 { ": " } else { ", " });
                let r = match extra {
                    Some(e) => arm.extra.get(e).copied().unwrap_or(arm.result),
                    None => arm.result,
                };
                ok = ok && sub(r, out);
            }
            out.push(')');
            ok
        }
        Inst::IfExtra { of, index } => expr(f, *of, Some(*index as usize), name, out, limit),
    }
}

/// The language's name of a runtime function (`mbfx_step` → `STEP`).
fn adams_name(func: Func) -> String {
    match func {
        Func::Pow | Func::PowLibm => "POW".into(),
        _ => func
            .symbol()
            .trim_start_matches("mbfx_")
            .to_ascii_uppercase(),
    }
}
