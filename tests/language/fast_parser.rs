//! Differential tests of the hand-written fast parser (`src/syntax/fast.rs`) against the
//! LALRPOP grammar, the grammar of record: on generated valid expressions, on generated
//! token soup (mostly invalid), on every corpus expression and on deep nesting, the fast
//! parser accepts exactly what the grammar accepts without an error, and builds the very
//! same tree (nodes in the same order, same spans and depths, same argument lists).

use crate::support::{shared, valid_expr};
use mbfx::syntax::ast::{Ast, Builder, NodeId};
use mbfx::syntax::{fast, lexer, parser};
use proptest::prelude::*;

/// The tree the LALRPOP grammar builds for `src`, if it parses without any diagnostic.
fn grammar_tree(src: &str) -> Option<(Ast, NodeId)> {
    let p = parser::parse_recovering(src);
    match p.root {
        Some(root) if p.diagnostics.is_empty() => Some((p.ast, root)),
        _ => None,
    }
}

/// Runs the fast parser alone on `src`; `None` when the lexer reported an error (the fast
/// path never sees such input), `Some(Err)` when the fast parser rejects the tokens.
fn fast_tree(src: &str) -> Option<Result<(Builder, NodeId), fast::Reject>> {
    let lexed = lexer::lex(src);
    if !lexed.diagnostics.is_empty() || lexed.aborted || lexed.tokens.is_empty() {
        return None;
    }
    let mut b = Builder::new();
    let root = fast::parse(&lexed.tokens, &mut b, &mut Vec::new());
    Some(root.map(|r| (b, r)))
}

/// Asserts that the fast parser and the grammar agree on `src`: both reject it, or both
/// accept it with identical trees. Returns whether it was accepted.
fn agree(src: &str) -> Result<bool, TestCaseError> {
    let Some(fast) = fast_tree(src) else {
        return Ok(false);
    };
    let grammar = grammar_tree(src);
    match (fast, grammar) {
        (Err(_), None) => Ok(false),
        (Ok((b, root)), Some((ast, groot))) => {
            prop_assert_eq!(root, groot, "root of {:?}", src);
            prop_assert_eq!(&b.ast.nodes, &ast.nodes, "nodes of {:?}", src);
            prop_assert_eq!(&b.ast.args, &ast.args, "arguments of {:?}", src);
            Ok(true)
        }
        (Ok(_), None) => Err(TestCaseError::fail(format!(
            "fast parser accepts {src:?}, the grammar does not"
        ))),
        (Err(_), Some(_)) => Err(TestCaseError::fail(format!(
            "the grammar accepts {src:?}, the fast parser does not"
        ))),
    }
}

/// Sequences of tokens in any order: mostly invalid, sometimes valid.
fn soup() -> impl Strategy<Value = String> {
    prop::collection::vec(
        prop::sample::select(vec![
            "1", "2.5", "x", "F(", "IF(", "(", ")", "[", "]", ",", ":", "+", "-", "*", "/", "**",
            "%", " ",
        ]),
        1..14,
    )
    .prop_map(|t| t.concat())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn fast_parser_builds_the_grammars_tree(src in valid_expr()) {
        prop_assert!(agree(&src)?, "generated text should parse: {}", src);
    }

    #[test]
    fn fast_parser_accepts_exactly_what_the_grammar_accepts(src in soup()) {
        agree(&src)?;
    }
}

/// The fast path reaches the same trees and diagnostics as the grammar on every corpus
/// expression (those with errors fall back to the grammar, which reports them).
#[test]
fn fast_parser_agrees_on_the_corpus() {
    let mut accepted = 0;
    let mut total = 0;
    for file in ["expressions.txt", "expressions-cmd.txt"] {
        let path = shared().join("corpus").join(file);
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{e}"));
        for (_, src) in text.lines().filter_map(|l| l.split_once('\t')) {
            total += 1;
            accepted += usize::from(agree(src).unwrap_or_else(|e| panic!("{e}")));
            let (fast, grammar) = (parser::parse(src), parser::parse_recovering(src));
            assert_eq!(fast.diagnostics, grammar.diagnostics, "{src}");
            assert_eq!(fast.root, grammar.root, "{src}");
            assert_eq!(fast.ast.nodes, grammar.ast.nodes, "{src}");
        }
    }
    // Nearly all of the corpus is valid syntax: the comparison is not vacuous.
    assert!(accepted * 10 > total * 9, "{accepted} of {total} accepted");
}

/// Long sign and power chains are parsed in loops and bracket nesting up to the lexer's
/// limit recurses on a growing stack: neither overflows, and the trees agree.
#[test]
fn fast_parser_survives_deep_input() {
    let depth = 5000;
    for src in [
        format!("{}1", "-".repeat(depth)),
        format!("{}1", "-+".repeat(depth)),
        format!("2{}", "**2".repeat(depth)),
        format!("2{}", "**-2".repeat(depth)),
        format!("1{}", "+1".repeat(depth)),
        format!("{}1{}", "(".repeat(1000), ")".repeat(1000)),
        format!("{}1{}", "F(".repeat(1000), ")".repeat(1000)),
    ] {
        assert!(agree(&src).expect("agree"), "{}", &src[..20]);
    }
}
