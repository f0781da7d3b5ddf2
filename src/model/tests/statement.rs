//! Unit tests of the statement layer on small hand-written datasets: framing of
//! expressions (continuation lines, `\`, comments, abbreviations), line endings, NUL
//! bytes, view names, value lists, malformed statements and inputs that must not panic.

use crate::diag::{Code, Diagnostic, Severity};
use crate::model::statement::{read_statements, ArgValue, ItemKind, Statement};

/// Reads `text`, asserting no diagnostics.
fn clean(text: &str) -> Vec<Statement> {
    let (stmts, diags) = read_statements(text);
    assert!(diags.is_empty(), "{diags:#?}");
    stmts
}

/// The text of every expression argument, as (name, expression text).
fn exprs(text: &str) -> Vec<(String, &str)> {
    clean(text)
        .iter()
        .flat_map(|s| s.args.iter())
        .filter_map(|a| Some((a.name.clone(), &text[a.expr_span()?])))
        .collect()
}

fn errors(text: &str) -> Vec<Diagnostic> {
    read_statements(text).1
}

#[test]
fn continuation_lines_stay_inside_the_expression_span() {
    let text = "title\nMOTION/1, JOINT=1, FUNCTION=STEP(TIME,0,0,\n, 1,100)\nEND\n";
    assert_eq!(
        exprs(text),
        [("FUNCTION".to_string(), "STEP(TIME,0,0,\n, 1,100)")]
    );
}

#[test]
fn expression_may_start_on_the_next_line() {
    let text = "t\nSFORCE/1\n, FUNCTION =\n, -5*AZ(1,2)+\n,-1*WZ(1,2,2)\n!\nEND";
    assert_eq!(exprs(text)[0].1, "-5*AZ(1,2)+\n,-1*WZ(1,2,2)");
    let text = "t\nSFORCE/1, FUNCTION =\n, I = 3\n";
    let d = errors(text);
    assert_eq!(d.len(), 1, "{d:?}");
    assert_eq!((d[0].code, d[0].span.clone()), (Code::Statement, 12..22));
}

#[test]
fn backslash_ends_an_expression_and_the_next_argument_follows() {
    let text = "t\nREQUEST/1\n, F2 = AZ(87,205)\\\n, F3 = DZ(80,99,99)\n";
    let got = exprs(text);
    assert_eq!(got[0], ("F2".to_string(), "AZ(87,205)"));
    assert_eq!(got[1], ("F3".to_string(), "DZ(80,99,99)"));
}

#[test]
fn backslash_chain_on_one_line() {
    let text = "t\nGFORCE/1, I=1, JFLOAT=2, RM=1, FX = 0\\ FY = 0\\ FZ = 0\\\n";
    let names: Vec<_> = exprs(text)
        .into_iter()
        .map(|(n, e)| format!("{n}={e}"))
        .collect();
    assert_eq!(names, ["FX=0", "FY=0", "FZ=0"]);
    let stmts = clean(text);
    assert_eq!(stmts[0].args.len(), 6);
}

#[test]
fn slash_is_division_not_a_terminator() {
    let text = "t\nVFORCE/1, FX=-10*VX(1,2,2,2)/\n,2\n";
    assert_eq!(exprs(text)[0].1, "-10*VX(1,2,2,2)/\n,2");
}

#[test]
fn comment_after_an_expression_is_not_part_of_it() {
    let text = "t\nVARIABLE/1, FUNCTION=1+2 ! three\nVARIABLE/2, FUNCTION=1+\n, 2 ! two \n";
    let got = exprs(text);
    assert_eq!(got[0].1, "1+2");
    assert_eq!(got[1].1, "1+\n, 2");
}

#[test]
fn function_abbreviations_hold_expressions() {
    let text = "t\nGCON/1, I=3, FUN=UVZ(3)*UVZ(4)-1\nDIFF/1, FU=-DIF(1), IC=1\nDIFF/2, func = 2\n";
    let got = exprs(text);
    let names: Vec<_> = got.iter().map(|(n, e)| format!("{n}={e}")).collect();
    assert_eq!(names, ["FUN=UVZ(3)*UVZ(4)-1", "FU=-DIF(1)", "FUNC=2"]);
    let stmts = clean(text);
    assert_eq!(stmts[1].args[1].items()[0].as_f64(), Some(1.0));
}

#[test]
fn depth_zero_comma_ends_an_expression() {
    let text = "t\nREQUEST/05, F7=JOINT(1,0,7,0)\\F8=JOINT(1,0,8,0),C=RForce X Y: Z (a)\n";
    let stmts = clean(text);
    let args = &stmts[0].args;
    assert_eq!(&text[args[1].expr_span().unwrap()], "JOINT(1,0,8,0)");
    assert_eq!(args[2].name, "C");
    let c = &args[2].items()[0];
    assert_eq!(
        (c.kind, c.text.as_str()),
        (ItemKind::Text, "RForce X Y: Z (a)")
    );
}

#[test]
fn crlf_line_endings() {
    let text = "t\r\nSFORCE/1\r\n, I = 1\r\n, FUNCTION = 1 +\r\n, 2\r\nEND\r\n";
    let stmts = clean(text);
    assert_eq!(&text[stmts[0].args[1].expr_span().unwrap()], "1 +\r\n, 2");
    assert_eq!(stmts[0].span, 3..text.find("2\r\nEND").unwrap() + 1);
    assert_eq!(stmts[1].keyword, "END");
}

#[test]
fn nul_bytes_are_blanks_with_one_warning() {
    let text = "t\nSTRING/31\n, STRING = \0\0\0\nMARKER/1\0, PART=2\0\0\n";
    let (stmts, diags) = read_statements(text);
    assert_eq!(diags.len(), 1, "{diags:?}");
    assert_eq!(
        (diags[0].code, diags[0].severity),
        (Code::EncodingRepaired, Severity::Warning)
    );
    assert_eq!(stmts.len(), 2);
    assert_eq!(stmts[0].args[0].items()[0].text, "");
    assert_eq!(stmts[1].args[0].items()[0].as_integer(), Some(2));
}

#[test]
fn tabs_and_leading_blanks() {
    let text = "t\n\tPART/1\t,\tMASS\t=\t2\n   ,  CM = 3\n";
    let stmts = clean(text);
    let names: Vec<_> = stmts[0].args.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["MASS", "CM"]);
}

#[test]
fn view_name_comment_names_the_next_statement_only() {
    let text = "t\n!   adams_view_name='JOINT_2'\nJOINT/2, REVOLUTE\n, I = 1, J = 2\nJOINT/3\n";
    let stmts = clean(text);
    assert_eq!(stmts[0].view_name.as_deref(), Some("JOINT_2"));
    assert_eq!(stmts[0].label(), "JOINT_2");
    assert_eq!(stmts[1].view_name, None);
    assert_eq!(stmts[1].label(), "JOINT/3");
}

#[test]
fn reuler_is_a_three_item_list_in_degrees() {
    let text = "t\nMARKER/0101, PART = 01, QP = 1.0, -2.5E-3, .4, REULER = 90D, 180D, 0D\n";
    let stmts = clean(text);
    let m = &stmts[0];
    assert_eq!((m.id, m.keyword.as_str()), (Some(101), "MARKER"));
    let reuler = m.arg("REULER", 6).unwrap();
    let items = reuler.items();
    assert_eq!(items.len(), 3);
    assert!(items
        .iter()
        .all(|i| matches!(i.kind, ItemKind::Number { degrees: true, .. })));
    assert_eq!(items[1].as_f64(), Some(std::f64::consts::PI));
    assert_eq!(&text[items[1].span.clone()], "180D");
    let qp: Vec<_> = m
        .arg("QP", 2)
        .unwrap()
        .items()
        .iter()
        .map(|i| i.as_f64())
        .collect();
    assert_eq!(qp, [Some(1.0), Some(-2.5e-3), Some(0.4)]);
}

#[test]
fn lists_words_quotes_and_colons() {
    let text = "t\nPART/1, EXACT = X:Y:PSI, GROUND\nREQUEST/2, CNAMES = \"a\", \"\"\n, \"c\"\n\
                , ROUTINE = lib::f, TITLE=A:B\nSECTION/1\n, TYPE = Solid Rectangular\n";
    let stmts = clean(text);
    let exact: Vec<_> = stmts[0].args[0]
        .items()
        .iter()
        .map(|i| i.text.as_str())
        .collect();
    assert_eq!(exact, ["X", "Y", "PSI"]);
    assert_eq!(stmts[0].args[1].value, ArgValue::Flag);
    let cnames = stmts[1].args[0].items();
    assert_eq!(cnames.len(), 3);
    assert!(cnames.iter().all(|i| i.kind == ItemKind::Quoted));
    assert_eq!(stmts[1].args[1].items()[0].text, "lib::f");
    assert_eq!(stmts[1].args[2].items().len(), 2);
    assert_eq!(stmts[2].args[0].items()[0].text, "Solid Rectangular");
}

#[test]
fn singletons_and_semicolons() {
    let text = "t\nUNITS/FORCE = NEWTON, MASS = KILOGRAM\nACCGRAV/\n, JGRAV = -9806.65\n\
                OUTPUT/REQSAVE\nPART/1,MASS=40,CM=1;PART/2;\nEND\n";
    let stmts = clean(text);
    let heads: Vec<_> = stmts
        .iter()
        .map(|s| (s.keyword.as_str(), s.id, s.args.len()))
        .collect();
    assert_eq!(
        heads,
        [
            ("UNITS", None, 2),
            ("ACCGRAV", None, 1),
            ("OUTPUT", None, 1),
            ("PART", Some(1), 2),
            ("PART", Some(2), 0),
            ("END", None, 0)
        ]
    );
    assert_eq!(stmts[4].line, 6);
}

#[test]
fn abbreviated_statement_keywords_keep_their_spelling() {
    let stmts = clean("t\nJOI/1, REVOLUTE\nvari/2, fun = time\n");
    assert_eq!(
        (stmts[0].keyword.as_str(), stmts[0].canonical),
        ("JOI", Some("JOINT"))
    );
    assert_eq!(
        (stmts[1].keyword.as_str(), stmts[1].canonical),
        ("VARI", Some("VARIABLE"))
    );
    assert_eq!(stmts[1].args[0].name, "FUN");
}

#[test]
fn user_calls_are_marked() {
    let stmts = clean("t\nGFORCE/5, FUNCTION = user( 1, 2 )\\\n, ROUTINE = a::b\nVARIABLE/1, FUNCTION = USERX(1)\n");
    assert!(stmts[0].args[0].is_user_call);
    assert!(!stmts[1].args[0].is_user_call);
}

#[test]
fn reading_stops_at_end() {
    let (stmts, diags) = read_statements("t\nPART/1\nEND\n!c\n\nPART/2\n");
    assert_eq!(stmts.len(), 2);
    assert_eq!(diags.len(), 1);
    assert_eq!(diags[0].code, Code::UnsupportedStatement);
}

#[test]
fn malformed_statements_give_precise_errors() {
    let cases: &[(&str, &str, &str)] = &[
        ("t\nMARKER, PART=1\n", ",", "expected `/`"),
        ("t\nMARKER/, PART=1\n", "/", "missing id"),
        ("t\nMARKER/12A, PART=1\n", "12A", "malformed id"),
        (
            "t\nMARKER/99999999999999999999\n",
            "99999999999999999999",
            "too large",
        ),
        ("t\nPART/1, MASS=\n", "MASS=", "has no value"),
        ("t\nPART/1, MASS= , CM=2\n", "MASS=", "has no value"),
        ("t\nSFORCE/1, FUNCTION=\\\n", "FUNCTION=", "has no value"),
        ("t\nSFORCE/1, FUNCTION=\n", "FUNCTION=", "has no value"),
        ("t\nREQUEST/1, CNAMES = \"abc\n", "\"abc", "unterminated"),
        ("t\n, MASS = 1\n", ", MASS = 1", "no statement"),
        ("t\nPART/1, 12, MASS=1\n", "1", "argument name"),
        ("t\nPART/1, MASS 1\n", "1", "expected `=`"),
        ("t\nPART/1, MASS = 1 = 2\n", "=", "unexpected"),
        ("t\n MASS=4, CM=1\n", "=", "expected `/`"),
        ("t\n1,2,3\n", "1", "statement keyword"),
        ("t\nMAT/1\n", "MAT", "ambiguous"),
        ("t\nMARKER/1 PART=2\n", "P", "expected `,`"),
    ];
    for (text, at, what) in cases {
        let d = errors(text);
        assert_eq!(d.len(), 1, "{text:?}: {d:#?}");
        assert_eq!(d[0].code, Code::Statement, "{text:?}");
        assert!(d[0].message.contains(what), "{text:?}: {}", d[0].message);
        assert_eq!(&text[d[0].span.clone()], *at, "{text:?}: {}", d[0].message);
    }
}

#[test]
fn unknown_statements_are_warned_and_kept() {
    let (stmts, diags) = read_statements("t\nLEONARDO/50,PEPPINO=125\n");
    assert_eq!(stmts.len(), 1);
    assert_eq!((stmts[0].canonical, stmts[0].id), (None, Some(50)));
    assert_eq!(
        (diags[0].code, diags[0].severity),
        (Code::UnsupportedStatement, Severity::Warning)
    );
}

#[test]
fn bad_inputs_never_panic_and_spans_stay_inside() {
    let mut inputs: Vec<String> = [
        "",
        "title only",
        "t\n",
        "t\n\n\n",
        "\n,",
        "t\n,",
        "t\n/",
        "t\n=",
        "t\n\\",
        "t\n\"",
        "t\nA/",
        "t\nA/1,",
        "t\nA/1,B=",
        "t\nA/1,B=\"",
        "t\nA/1,B=(((",
        "t\nA/1,FUNCTION=(((\n,",
        "t\nA/1,FUNCTION=)))\\,,",
        "t\nPART/1,X=1:",
        "t\nPART/1,X=::",
        "t\nPART/1;;;;",
        "t\n;;\n,;",
        "t\né/1, é=é",
        "t\nPART/1, M=ü, F=\u{1F600}\\",
        "t\nFU/1,FU=\n,\n,\n",
        "t\nEND\n,\n",
        "t\r\r\n\r,\r",
        "t\n\0\0\0",
        "t\n!adams_view_name='\nPART/1",
        "t\nPART/-1",
        "t\nREQUEST/1, C=",
        "t\nSTRING/1, STRING=\"",
        "t\nPART/1, IP=1,\n,\n,2",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    inputs.push(format!("t\nVARIABLE/1, FUNCTION={}", "1+".repeat(500_000)));
    inputs.push(format!("t\nMARKER/1, QP={}", "1,".repeat(300_000)));
    inputs.push((0u8..=127).map(char::from).collect());
    inputs.push(
        (0u32..2000)
            .filter_map(|i| char::from_u32(i * 37 % 1200))
            .collect(),
    );
    // Deterministic pseudo-random strings over the characters the reader cares about.
    let alphabet: Vec<char> = "AF/=,\\;:!\"'()[]1.D  \n\r\t\0é".chars().collect();
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    for _ in 0..3000 {
        let mut s = String::from("t\n");
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        for k in 0..(seed % 48) {
            let i = (seed.rotate_left(k as u32 * 5) % alphabet.len() as u64) as usize;
            s.push(alphabet[i]);
        }
        inputs.push(s);
    }
    for text in &inputs {
        let (stmts, diags) = read_statements(text);
        let inside = |s: &std::ops::Range<usize>| {
            s.start <= s.end && s.end <= text.len() && text.get(s.clone()).is_some()
        };
        for d in &diags {
            assert!(inside(&d.span), "{text:?}: {d:?}");
        }
        for s in &stmts {
            assert!(inside(&s.span) && inside(&s.keyword_span), "{text:?}");
            for a in &s.args {
                assert!(inside(&a.span) && inside(&a.name_span), "{text:?}");
                if let Some(e) = a.expr_span() {
                    assert!(inside(&e), "{text:?}");
                }
                assert!(a.items().iter().all(|i| inside(&i.span)), "{text:?}");
            }
        }
    }
}
