//! Property: printing a parsed expression and parsing the text again gives the same tree
//! (parse ∘ print ∘ parse = parse), over generated expressions of every syntactic form.

use crate::support::valid_expr;
use mbfx::syntax::{parser, print};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn print_then_parse_gives_the_same_tree(src in valid_expr()) {
        let first = parser::parse(&src);
        prop_assert!(first.diagnostics.is_empty(), "generated text should parse: {src}: {:?}", first.diagnostics);
        let root = first.root.expect("root");
        let printed = print::print(&first.ast, root);
        let second = parser::parse(&printed);
        prop_assert!(second.diagnostics.is_empty(), "printed text should parse: {printed}");
        prop_assert_eq!(first.ast.sexpr(root), second.ast.sexpr(second.root.expect("root")), "{} -> {}", src, printed);
        // The fast parser (no error recovery) and the recovering one agree on valid input.
        let slow = parser::parse_recovering(&src);
        prop_assert_eq!(first.ast.sexpr(root), slow.ast.sexpr(slow.root.expect("root")));
    }
}

#[test]
fn printing_keeps_the_meaning_of_signs_and_powers() {
    for (src, want) in [
        ("-2**2", "-2.0**2.0"),
        ("(-2)**2", "(-2.0)**2.0"),
        ("2**-1", "2.0**-1.0"),
        ("2**3**2", "2.0**3.0**2.0"),
        ("(2**3)**2", "(2.0**3.0)**2.0"),
        ("a-(b-c)", "A - (B - C)"),
        ("(a-b)-c", "A - B - C"),
        ("a/(b*c)", "A / (B * C)"),
        ("IF(x:1,2,3)", "IF(X: 1.0, 2.0, 3.0)"),
    ] {
        let p = parser::parse(src);
        assert_eq!(print::print(&p.ast, p.root.expect("root")), want, "{src}");
    }
}
