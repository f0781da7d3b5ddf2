//! The syntax tree's arena is in post order: every node comes after its children, the
//! root is the last node, and every other node is the child of exactly one. The units
//! check relies on it (it visits the arena in index order instead of recursing), for
//! trees of both parsers, on generated expressions and on the whole corpus.

use crate::support::{shared, valid_expr};
use mbfx::syntax::ast::Ast;
use mbfx::syntax::parser::{parse, parse_recovering, Parsed};
use proptest::prelude::*;

/// Why the tree of `parsed` breaks the post order, if it does.
fn post_order_broken(parsed: &Parsed) -> Option<String> {
    let root = parsed.root? as usize;
    let ast: &Ast = &parsed.ast;
    if root + 1 != ast.nodes.len() {
        return Some(format!("root {root} of {} nodes", ast.nodes.len()));
    }
    let mut parents = vec![0u32; ast.nodes.len()];
    for id in 0..ast.nodes.len() as u32 {
        for child in ast.children(id) {
            if child >= id {
                return Some(format!("node {id} has child {child}"));
            }
            parents[child as usize] += 1;
        }
    }
    let orphan = (0..root).find(|&i| parents[i] != 1)?;
    Some(format!("node {orphan} has {} parents", parents[orphan]))
}

proptest! {
    #[test]
    fn both_parsers_build_the_arena_in_post_order(src in valid_expr()) {
        for parsed in [parse(&src), parse_recovering(&src)] {
            let broken = post_order_broken(&parsed);
            prop_assert!(broken.is_none(), "{src}: {}", broken.unwrap_or_default());
        }
    }
}

#[test]
fn corpus_trees_are_in_post_order() {
    for file in ["expressions.txt", "expressions-cmd.txt"] {
        let path = shared().join("corpus").join(file);
        let text =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        for expr in text
            .lines()
            .filter_map(|l| l.split_once('\t'))
            .map(|(_, e)| e)
        {
            for parsed in [parse(expr), parse_recovering(expr)] {
                if parsed.diagnostics.is_empty() {
                    assert_eq!(post_order_broken(&parsed), None, "{expr}");
                }
            }
        }
    }
}
