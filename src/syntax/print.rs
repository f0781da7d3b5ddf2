//! Pretty printer: writes a syntax tree back as expression text with the fewest
//! parentheses that keep its structure, so `parse(print(parse(s)))` equals `parse(s)`.

use crate::syntax::ast::{Ast, BinOp, Kind, NodeId, UnOp};

/// Binding strength of a printed form: a child weaker than its slot needs parentheses.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Level {
    Sum = 1,
    Product = 2,
    Unary = 3,
    Primary = 5,
}

fn level(ast: &Ast, id: NodeId) -> Level {
    match &ast.node(id).kind {
        Kind::Binary(BinOp::Add | BinOp::Sub, ..) => Level::Sum,
        Kind::Binary(BinOp::Mul | BinOp::Div | BinOp::Cross, ..) => Level::Product,
        // A power prints as `base ** exponent` and may stand wherever a unary form may.
        Kind::Unary(..) | Kind::Binary(BinOp::Pow, ..) => Level::Unary,
        Kind::Num(v) if *v < 0.0 => Level::Unary,
        _ => Level::Primary,
    }
}

/// Prints the tree rooted at `root`.
pub fn print(ast: &Ast, root: NodeId) -> String {
    let mut out = String::new();
    write_node(ast, root, &mut out);
    out
}

fn write_child(ast: &Ast, id: NodeId, min: Level, out: &mut String) {
    if level(ast, id) < min {
        out.push('(');
        write_node(ast, id, out);
        out.push(')');
    } else {
        write_node(ast, id, out);
    }
}

fn write_list(ast: &Ast, ids: &[NodeId], out: &mut String) {
    for (i, &a) in ids.iter().enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        write_node(ast, a, out);
    }
}

fn write_node(ast: &Ast, id: NodeId, out: &mut String) {
    crate::stack::guard(|| match &ast.node(id).kind {
        Kind::Num(v) => write_number(*v, out),
        Kind::Name(n) => out.push_str(ast.name(*n)),
        Kind::Error => out.push_str("<error>"),
        Kind::Call { name, args, .. } => {
            out.push_str(ast.name(*name));
            out.push('(');
            write_list(ast, ast.call_args(*args), out);
            out.push(')');
        }
        Kind::If([t, a, b, c]) => {
            out.push_str("IF(");
            write_node(ast, *t, out);
            out.push_str(": ");
            write_list(ast, &[*a, *b, *c], out);
            out.push(')');
        }
        Kind::Vector(parts) => {
            out.push('[');
            write_list(ast, parts, out);
            out.push(']');
        }
        Kind::Unary(op, a) => {
            out.push(if *op == UnOp::Neg { '-' } else { '+' });
            write_child(ast, *a, Level::Unary, out);
        }
        Kind::Binary(BinOp::Pow, a, b) => {
            write_child(ast, *a, Level::Primary, out);
            out.push_str("**");
            write_child(ast, *b, Level::Unary, out);
        }
        Kind::Binary(op, a, b) => {
            let (left, right) = match op {
                BinOp::Add | BinOp::Sub => (Level::Sum, Level::Product),
                _ => (Level::Product, Level::Unary),
            };
            write_child(ast, *a, left, out);
            out.push(' ');
            out.push_str(op.symbol());
            out.push(' ');
            write_child(ast, *b, right, out);
        }
    })
}

/// Numbers print in Rust's shortest round-trip form, which the lexer reads back exactly;
/// an overflowed literal (infinite) prints as one that overflows again.
fn write_number(v: f64, out: &mut String) {
    if v.is_infinite() {
        out.push_str("1E999");
    } else {
        out.push_str(&format!("{v:?}"));
    }
}
