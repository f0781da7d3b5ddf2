//! The whole expression corpus (`../shared/corpus/expressions.txt` from `.adm` files and
//! `expressions-cmd.txt` from Adams View `.cmd` files) parses and checks. Measures are
//! checked against a scope in which every marker and element exists (their evaluation
//! belongs to the multibody core). Every expression that does not check is matched to a
//! listed reason; an unexplained failure, or a listed reason that no longer occurs, fails.
//! Compiling the corpus in one reused session gives what fresh sessions give.

use crate::support::shared;
use mbfx::check::{compile, EveryIdExists, Expect, Session};
use mbfx::diag::{Code, Diagnostic};
use std::collections::BTreeMap;

/// True when the text holds an Adams View dotted name (`.model.part.marker`): a `.`
/// followed by a letter that does not continue a number or a name.
fn has_view_name(expr: &str) -> bool {
    let b = expr.as_bytes();
    (0..b.len()).any(|i| {
        b[i] == b'.'
            && b.get(i + 1)
                .is_some_and(|c| c.is_ascii_alphabetic() || *c == b'_')
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'))
    })
}

/// Files of MBDyn's a2m translator that test its error handling: deliberately invalid.
const INVALID_SAMPLES: &[&str] = &[
    "alex-marinov__mbdyn/contrib/a2m/samples/prova.adm",
    "alex-marinov__mbdyn/contrib/a2m/samples/monster.adm",
    "alex-marinov__mbdyn/contrib/a2m/samples/pm03.adm",
];

/// Why a corpus expression may legitimately fail, decided from its text and diagnostics.
fn reason(origin: &str, expr: &str, diags: &[Diagnostic]) -> Option<&'static str> {
    if INVALID_SAMPLES.iter().any(|f| origin.contains(f)) {
        return Some("MBDyn a2m samples: deliberately invalid input (unknown names and functions, `^`, IF without `:`)");
    }
    let codes: Vec<Code> = diags
        .iter()
        .filter(|d| d.is_error())
        .map(|d| d.code)
        .collect();
    let upper = expr.to_ascii_uppercase();
    let view_names = has_view_name(expr);
    if upper.contains("USER(") && codes.iter().all(|c| *c == Code::Unsupported) {
        return Some("USER(...) calls a user subroutine, which mbfx does not run (spec §7)");
    }
    if view_names
        && codes.iter().all(|c| {
            matches!(
                c,
                Code::IntegerArgument | Code::UnknownName | Code::TooManyErrors
            )
        })
    {
        return Some("Adams View dialect: markers and design variables written as .model.names need View's symbol table");
    }
    None
}

fn check_file(name: &str, min_lines: usize) -> BTreeMap<&'static str, usize> {
    let path = shared().join("corpus").join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reasons = BTreeMap::new();
    let mut unexplained = Vec::new();
    let mut count = 0;
    for line in text.lines() {
        let Some((origin, expr)) = line.split_once('\t') else {
            continue;
        };
        count += 1;
        if let Err(diags) = compile(expr, &EveryIdExists, Expect::Any) {
            match reason(origin, expr, &diags) {
                Some(r) => *reasons.entry(r).or_insert(0) += 1,
                None => unexplained.push(format!(
                    "{origin}: {expr}\n    {}",
                    diags
                        .iter()
                        .map(|d| format!("{} {}", d.code.as_str(), d.message))
                        .collect::<Vec<_>>()
                        .join("; ")
                )),
            }
        }
    }
    assert!(count >= min_lines, "{name}: only {count} expressions read");
    assert!(
        unexplained.is_empty(),
        "{name}: {} unexplained failures:\n{}",
        unexplained.len(),
        unexplained.join("\n")
    );
    reasons
}

#[test]
fn adm_corpus_expressions_check() {
    let reasons = check_file("expressions.txt", 1000);
    // Each listed reason must still occur: a reason nothing needs any more is dropped.
    let found: Vec<&str> = reasons.keys().map(|r| &r[..10]).collect();
    assert_eq!(found, ["MBDyn a2m ", "USER(...) "], "{reasons:?}");
}

#[test]
fn view_corpus_expressions_check() {
    let reasons = check_file("expressions-cmd.txt", 270);
    for r in reasons.keys() {
        assert!(
            r.starts_with("Adams View dialect") || r.starts_with("USER"),
            "{r}"
        );
    }
}

/// `compile` reuses one session's buffers for every expression; reusing them changes no
/// result: the whole corpus, compiled in sequence in one session, gives exactly what a
/// fresh session gives for each expression (IR, spans, warnings, or diagnostics).
#[test]
fn reusing_a_session_changes_no_result() {
    let mut session = Session::new();
    let mut compared = 0;
    for file in ["expressions.txt", "expressions-cmd.txt"] {
        let path = shared().join("corpus").join(file);
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{e}"));
        for (_, expr) in text.lines().filter_map(|l| l.split_once('\t')) {
            let reused = session.compile(expr, &EveryIdExists, Expect::Any);
            let fresh = Session::new().compile(expr, &EveryIdExists, Expect::Any);
            assert_eq!(format!("{reused:?}"), format!("{fresh:?}"), "{expr}");
            compared += 1;
        }
    }
    assert!(compared > 1000, "only {compared} expressions");
}
