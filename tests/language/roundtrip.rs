//! Property: printing a parsed expression and parsing the text again gives the same tree
//! (parse ∘ print ∘ parse = parse), over generated expressions of every syntactic form.

use mbfx::syntax::{parser, print};
use proptest::prelude::*;

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        (0u32..1000).prop_map(|n| n.to_string()),
        (0u32..1000, 0u32..1000).prop_map(|(a, b)| format!("{a}.{b}")),
        (0u32..100).prop_map(|n| format!(".{n}")),
        (1u32..10, -20i32..20).prop_map(|(a, e)| format!("{a}E{e}")),
        (0u32..360).prop_map(|n| format!("{n}D")),
        Just("1.387778781E-014".to_string()),
    ]
}

fn leaf() -> impl Strategy<Value = String> {
    prop_oneof![
        number(),
        prop::sample::select(vec!["x", "v", "t", "TIME", "PI", "dtor", "Rtod", "MODE"])
            .prop_map(String::from),
    ]
}

fn expr() -> impl Strategy<Value = String> {
    leaf().prop_recursive(6, 64, 4, |inner| {
        prop_oneof![
            (
                inner.clone(),
                prop::sample::select(vec!["+", "-", "*", "/", "**", "%"]),
                inner.clone()
            )
                .prop_map(|(a, op, b)| format!("{a}{op}{b}")),
            (prop::sample::select(vec!["-", "+"]), inner.clone())
                .prop_map(|(s, a)| format!("{s}{a}")),
            inner.clone().prop_map(|a| format!("({a})")),
            (inner.clone(), inner.clone(), inner.clone(), inner.clone())
                .prop_map(|(a, b, c, d)| format!("IF({a}: {b}, {c}, {d})")),
            (inner.clone(), inner.clone(), inner.clone())
                .prop_map(|(a, b, c)| format!("[{a}, {b}, {c}]")),
            (
                prop::sample::select(vec!["SIN", "max", "STEP", "POLY", "Atan2", "DX"]),
                prop::collection::vec(inner, 1..5)
            )
                .prop_map(|(f, args)| format!("{f}({})", args.join(","))),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn print_then_parse_gives_the_same_tree(src in expr()) {
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
