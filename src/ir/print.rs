//! Text form of the IR, for the REPL's `:ir` and for tests.

use super::{Function, Inst, Value};
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
