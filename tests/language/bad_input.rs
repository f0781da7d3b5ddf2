//! The bad-input catalogue: one line per malformed, hostile or extreme input, with the
//! code and the place of the first error it must produce (or the value it must have).
//!
//! For every case: nothing panics, the first error diagnostic has the expected code and
//! span, every span (primary and labels) lies inside the input on character boundaries,
//! the report renders, and the case finishes quickly. Each case runs in a fresh thread
//! with a 2 MiB stack (the default size of a test thread), so deep input is shown not to
//! need a big stack. Expressions are checked with the user variables x, v and t and no
//! model. Invalid UTF-8 cannot reach `compile` (it takes `&str`); `tests/cli.rs` feeds
//! such bytes to `mbfx check`.

use crate::support::xvt_scope;
use mbfx::check::{compile, Expect};
use mbfx::context::Context;
use mbfx::diag::{render, Diagnostic, SourceFile, Span};
use mbfx::interp::Program;
use std::time::{Duration, Instant};

/// Stack of the thread each case runs in.
const STACK: usize = 2 * 1024 * 1024;
/// Longest a case may take (the 1 MB expression takes well under a second in release).
const TIME_LIMIT: Duration = Duration::from_secs(5);

/// Where the first error must point.
#[derive(Clone, Copy, Debug)]
enum At {
    /// This byte range.
    Bytes(usize, usize),
    /// The first occurrence of this text.
    Text(&'static str),
    /// The occurrence of this text with this 0-based index.
    Nth(&'static str, usize),
    /// The empty span at the end of the input.
    End,
    /// The whole input.
    All,
}

use At::{All, Bytes, End, Nth, Text};

impl At {
    fn resolve(self, input: &str) -> Span {
        let nth = |needle: &str, n: usize| {
            let start = input
                .match_indices(needle)
                .nth(n)
                .unwrap_or_else(|| panic!("table error: {needle:?} #{n} not in the input"))
                .0;
            start..start + needle.len()
        };
        match self {
            Bytes(s, e) => s..e,
            Text(t) => nth(t, 0),
            Nth(t, n) => nth(t, n),
            End => input.len()..input.len(),
            All => 0..input.len(),
        }
    }
}

#[derive(Clone, Copy, Debug)]
enum Want {
    /// The first error has this code and span (and its help contains the text, if any).
    Error {
        code: &'static str,
        at: At,
        help: Option<&'static str>,
    },
    /// The expression compiles and evaluates (x = v = t = 0.5, TIME = 0.5) to a value
    /// that passes the test.
    Value(fn(f64) -> bool),
}

struct Case {
    name: &'static str,
    input: String,
    expect: Expect,
    want: Want,
}

impl Case {
    /// The help text of the first error must contain `text`.
    fn help(mut self, text: &'static str) -> Self {
        if let Want::Error { help, .. } = &mut self.want {
            *help = Some(text);
        }
        self
    }

    /// Check the expression where a scalar is required (`FUNCTION=` of an SFORCE).
    fn scalar(mut self) -> Self {
        self.expect = Expect::Scalar;
        self
    }

    /// Check the expression where a vector is required (`FXYZ=`).
    fn vector(mut self) -> Self {
        self.expect = Expect::Vector;
        self
    }
}

/// A case whose first error has `code` at `at`.
fn e(name: &'static str, input: impl Into<String>, code: &'static str, at: At) -> Case {
    Case {
        name,
        input: input.into(),
        expect: Expect::Any,
        want: Want::Error {
            code,
            at,
            help: None,
        },
    }
}

/// A case that is no error: it evaluates to a value passing `ok`.
fn v(name: &'static str, input: impl Into<String>, ok: fn(f64) -> bool) -> Case {
    Case {
        name,
        input: input.into(),
        expect: Expect::Any,
        want: Want::Value(ok),
    }
}

fn repeat(s: &str, n: usize) -> String {
    s.repeat(n)
}

/// `open` n times, then `middle`, then `close` n times.
fn nest(open: &str, middle: &str, close: &str, n: usize) -> String {
    format!("{}{middle}{}", open.repeat(n), close.repeat(n))
}

/// `1+1+…` of at least `bytes` bytes.
fn long_sum(bytes: usize) -> String {
    let mut s = String::with_capacity(bytes + 2);
    s.push('1');
    while s.len() < bytes {
        s.push_str("+1");
    }
    s
}

#[rustfmt::skip]
fn cases() -> Vec<Case> {
    let ten_ifs = nest("IF(1:0,0,", "7", ")", 10);
    let nine_ifs = nest("IF(1:0,0,", "7", ")", 9);
    let long_name = repeat("A", 100_000);
    vec![
        // E0101: characters that start no token.
        e("at_sign", "@", "E0101", Text("@")),
        e("semicolon", "1;2", "E0101", Text(";")),
        e("double_quote", "\"x\"", "E0101", Bytes(0, 1)).help("no strings"),
        e("single_quote", "'x'", "E0101", Bytes(0, 1)).help("no strings"),
        e("brace", "{1}", "E0101", Text("{")),
        e("dollar", "$x", "E0101", Text("$")),
        e("hash", "#1", "E0101", Text("#")),
        e("question_mark", "1 ? 2", "E0101", Text("?")),
        e("nul_byte", "1\x002", "E0101", Text("\0")),
        e("non_ascii_alone", "é", "E0101", Text("é")),
        e("non_ascii_after_name", "xé+1", "E0101", Text("é")),
        e("caret_power", "1^2", "E0101", Text("^")).help("**"),
        e("backslash", "1\\2", "E0101", Text("\\")),
        e("line_break", "1\n2", "E0101", Text("\n")).help("comma in column one"),
        e("crlf_line_break", "1+\r\n2", "E0101", Text("\r\n")),
        // Blank and comment lines pass over, then a line that does not continue: the help
        // (a comma in column one) is what the input lacks.
        e("comment_line_then_a_new_line", "1\n! note\n\n2", "E0101", Text("\n"))
            .help("comma in column one"),
        // E0102: malformed numbers.
        e("fortran_exponent", "1.5D3", "E0102", All).help("1.5E3"),
        e("fortran_exponent_lower", "2*1.5d3", "E0102", Text("1.5d3")),
        e("degrees_into_name", "10DTOR", "E0102", All),
        e("two_dots", "1.2.3", "E0102", All),
        e("exponent_without_digits", "1E", "E0102", All),
        e("number_into_name", "2*3x", "E0102", Text("3x")),
        // E0103: a blank between a function name and `(`.
        e("blank_before_paren", "SIN (1)", "E0103", Text("SIN ")),
        e("tab_before_paren", "MAX\t(1,2)", "E0103", Text("MAX\t")),
        e("blank_before_if_paren", "IF (1:2,3,4)", "E0103", Text("IF ")),
        e("name_broken_from_paren", "SIN\n,(1)", "E0103", Text("SIN\n")),
        e("name_broken_from_paren_by_a_comment", "SIN\n! note\n,(1)", "E0103", Text("SIN\n")),
        // E0104: relational and logical operators.
        e("less", "1 < 2", "E0104", Text("<")),
        e("greater", "1 > 2", "E0104", Text(">")),
        e("less_equal", "1 <= 2", "E0104", Text("<=")),
        e("greater_equal", "1 >= 2", "E0104", Text(">=")),
        e("equal_equal", "1 == 2", "E0104", Text("==")),
        e("equal", "1 = 2", "E0104", Text("=")),
        e("fortran_not_equal", "1 /= 2", "E0104", Text("/=")),
        e("basic_not_equal", "1 <> 2", "E0104", Text("<>")),
        e("and_and", "1 && 2", "E0104", Text("&&")),
        e("or_or", "1 || 2", "E0104", Text("||")),
        e("dot_lt", "1 .LT. 2", "E0104", Text(".LT.")).help("IF("),
        e("dot_ge", "1 .GE. 2", "E0104", Text(".GE.")),
        e("dot_and", "1 .AND. 2", "E0104", Text(".AND.")),
        e("dot_lt_lower_case", "x .lt. 2", "E0104", Text(".lt.")),
        e("relational_in_if", "IF(x < 1: 0, 0, 1)", "E0104", Text("<")),
        // E0105: `* *`.
        e("split_power", "2* *3", "E0105", Text("* *")),
        // E0201: a token the grammar does not expect.
        e("leading_star", "*2", "E0201", Text("*")),
        e("two_operators", "1+*2", "E0201", Text("*")),
        e("if_without_colon", "IF(1,2,3,4)", "E0201", Text(",")).help("IF(test:"),
        e("if_two_branches", "IF(1:2,3)", "E0201", Text(")")),
        e("if_four_branches", "IF(1:2,3,4,5)", "E0201", Nth(",", 2)),
        e("if_empty", "IF()", "E0201", Text(")")),
        e("empty_arguments", "f(,)", "E0201", Text(",")),
        e("two_component_vector", "[1,2]", "E0201", Text("]")),
        e("comma_in_parens", "(,)", "E0201", Text(",")),
        e("empty_parens", "()", "E0201", Text(")")),
        e("top_level_comma", "1,2", "E0201", Text(",")),
        e("lone_colon", ":", "E0201", All),
        e("mismatched_bracket", "(1]", "E0201", Text("]")),
        // E0202: the input ends inside an expression.
        e("unclosed_paren", "(1+2", "E0202", End).help("add `)`"),
        e("unclosed_call", "SIN(1", "E0202", End),
        e("trailing_plus", "1+", "E0202", End),
        e("unfinished_if", "IF(1:", "E0202", End),
        e("lone_minus", "-", "E0202", End),
        e("lone_power", "**", "E0201", Text("**")),
        e("trailing_power", "x**", "E0202", End),
        // E0203: closing brackets nobody opened.
        e("extra_close", "1)", "E0203", Text(")")),
        e("extra_close_after_call", "SIN(1))", "E0203", Nth(")", 1)),
        e("lone_bracket", "]", "E0203", All),
        e("many_closes", repeat(")", 100_000), "E0203", Bytes(0, 1)),
        // E0204: nothing to evaluate.
        e("empty", "", "E0204", All),
        e("blanks_only", "   ", "E0204", All),
        e("comment_only", "! x", "E0204", All),
        e("line_break_only", "\n", "E0204", All),
        // E0205: two values side by side.
        e("two_numbers", "2 3", "E0205", Text("3")),
        e("blank_in_number", "1 .5", "E0205", Text(".5")),
        e("blank_after_dot", "1. 5", "E0205", Text("5")),
        e("two_names", "x y", "E0205", Text("y")),
        e("number_broken_across_lines", "12\n,34", "E0205", Text("34")),
        // Errors inside deep brackets and under long chains of signs: recovery takes time
        // in proportion to the input (each of these took seconds while it copied the
        // parser stack for every state it tried).
        e("values_inside_1000_parens", format!("{}{}", repeat("(", 1000), repeat("1 ", 100_000)), "E0205", Bytes(1002, 1003)),
        e("errors_inside_1000_parens", format!("{}{}", repeat("(", 1000), repeat("x y +", 20_000)), "E0205", Bytes(1002, 1003)),
        e("errors_under_10000_signs", format!("{}x{}", repeat("-", 10_000), repeat(" y + x", 5_000)), "E0205", Bytes(10_002, 10_003)),
        e("brackets_inside_500_signed_parens", format!("{}x{}", repeat("(-", 500), repeat(" ]", 100_000)), "E0201", Bytes(1002, 1003)),
        e("commas_inside_1000_calls", format!("{}x{}", repeat("SIN(", 1000), repeat(" ,", 20_000)), "E0201", Bytes(4004, 4005)),
        e("number_then_call", "1 SIN(2)", "E0205", Text("SIN")),
        e("call_then_paren", "SIN(1)(2)", "E0205", Nth("(", 1)),
        e("if_without_parens", "IF 1", "E0205", Text("1")),
        // E0206: nesting past the limits, at any size.
        e("parens_10000", nest("(", "1", ")", 10_000), "E0206", Nth("(", 1024)),
        e("parens_1025", nest("(", "1", ")", 1025), "E0206", Nth("(", 1024)),
        e("brackets_10000", nest("[", "1", "]", 10_000), "E0206", Nth("[", 1024)),
        e("open_brackets_10000", repeat("[", 10_000), "E0206", Nth("[", 1024)),
        e("sin_calls_2000", nest("SIN(", "1", ")", 2000), "E0206", Nth("(", 1024)),
        e("sum_1_megabyte", long_sum(1_000_000), "E0206", All),
        e("sum_past_tree_limit", long_sum(40_001), "E0206", All),
        e("minus_signs_100000", format!("{}1", repeat("-", 100_000)), "E0206", All),
        e("powers_50000", format!("{}2", repeat("2**", 50_000)), "E0206", All),
        // Deep but within the limits: a value, on a 2 MiB stack.
        v("parens_1024", nest("(", "1", ")", 1024), |x| x == 1.0),
        v("sin_calls_1000", nest("SIN(", "1", ")", 1000), |x| x > 0.05 && x < 0.06),
        v("sum_at_tree_limit", long_sum(39_999), |x| x == 20_000.0),
        v("minus_signs_1000", format!("{}1", repeat("-", 1000)), |x| x == 1.0),
        v("minus_signs_1001", format!("{}1", repeat("-", 1001)), |x| x == -1.0),
        v("nine_nested_ifs", nine_ifs, |x| x == 7.0),
        // Issue 11 §4: a comment line between an expression's lines was refused with a
        // help asking for the comma the input already had. The dataset reader skips
        // comment and blank lines between a statement's lines, and so does the lexer.
        v("comment_line_between_continuations", "1\n! note\n, +1", |x| x == 2.0),
        v("blank_and_comment_lines_between_continuations", "1 +\r\n\r\n  ! a\r\n!b\r\n  , 1", |x| x == 2.0),
        v("comment_lines_after_an_expression", "1\n! note\n!", |x| x == 1.0),
        // Numbers at and past the range of f64.
        v("overflowing_literal_is_inf", "1E999", |x| x == f64::INFINITY),
        v("negative_overflow_is_minus_inf", "-1E999", |x| x == f64::NEG_INFINITY),
        v("inf_minus_inf_is_nan", "1E999-1E999", f64::is_nan),
        v("zero_over_zero_is_nan", "0/0", f64::is_nan),
        v("underflowing_literal_is_zero", "1E-999", |x| x == 0.0),
        v("hundred_thousand_digits", repeat("9", 100_000), |x| x == f64::INFINITY),
        v("long_fraction", format!("0.{}", repeat("1", 100_000)), |x| (x - 1.0 / 9.0).abs() < 1e-15),
        // E0301: unknown functions.
        e("misspelt_step", "STPE(1,0,0,1,1)", "E0301", Text("STPE")).help("did you mean `STEP`?"),
        e("unknown_function", "FOO(1)", "E0301", Text("FOO")),
        e("long_function_name", format!("{long_name}(1)"), "E0301", Bytes(0, 100_000)),
        // E0302: unknown names.
        e("unknown_name", "foo", "E0302", All),
        e("misspelt_time", "TIM", "E0302", All).help("did you mean `TIME`?"),
        e("view_name", ".model.part", "E0302", All),
        e("long_name", long_name, "E0302", All),
        // E0303: wrong number of arguments.
        e("step_two_arguments", "STEP(1,2)", "E0303", All),
        e("impact_one_argument", "IMPACT(1)", "E0303", All),
        e("max_three_arguments", "MAX(1,2,3)", "E0303", All),
        e("inner_call_arity", "MAX(MAX(1,2,3),4)", "E0303", Text("MAX(1,2,3)")),
        e("poly_no_coefficient", "POLY(x,0)", "E0303", All),
        e("poly_32_coefficients", format!("POLY(x,0{})", repeat(",1", 32)), "E0303", All),
        v("poly_31_coefficients", format!("POLY(x,0{})", repeat(",1", 31)), |x| x > 1.99 && x < 2.0),
        e("mag_no_argument", "MAG()", "E0303", All),
        e("sin_no_argument", "SIN()", "E0303", All),
        e("dx_four_arguments", "DX(1,2,3,4)", "E0303", All),
        // E0304: IDs and integer codes that are not integer literals in range.
        e("fractional_id", "DX(1.5)", "E0304", Text("1.5")),
        e("negative_id", "DX(-1)", "E0304", Text("-1")),
        e("variable_as_id", "DX(x)", "E0304", Text("x")),
        e("id_past_i32", "DX(2147483648)", "E0304", Text("2147483648")),
        e("iord_out_of_range", "AKISPL(1,0,1,3)", "E0304", Text("3")),
        e("nseq_zero", "ARYVAL(1,0)", "E0304", Text("0")),
        e("jflag_out_of_range", "BEAM(1,2,1,1)", "E0304", Text("2")),
        // E0305: scalar/vector type errors (spec §2.6, §8.5 V6-V7).
        e("vector_power", "[1,2,3]**2", "E0305", All),
        e("negated_vector_power", "-[1,2,3]**2", "E0305", Text("[1,2,3]**2")),
        e("scalar_over_vector", "1/[1,2,3]", "E0305", All),
        e("vector_over_vector", "[1,2,3]/[1,2,3]", "E0305", All),
        e("scalar_plus_vector", "1+[1,2,3]", "E0305", All),
        e("vector_minus_scalar", "[1,2,3]-1", "E0305", All),
        e("vector_cross_scalar", "[1,2,3]%1", "E0305", All),
        e("scalar_cross_scalar", "1%2", "E0305", All).help("MOD(a, b)"),
        e("dot_then_cross", "[1,0,0]*[0,1,0]%[0,0,1]", "E0305", All).help("v*(v%v)"),
        e("sin_of_vector", "SIN([1,2,3])", "E0305", Text("[1,2,3]")),
        e("vector_component", "[[1,2,3],2,3]", "E0305", Bytes(1, 8)),
        e("vector_if_test", "IF([1,2,3]:1,2,3)", "E0305", Text("[1,2,3]")),
        e("vector_if_branch", "IF(1:1,[1,2,3],3)", "E0305", Text("[1,2,3]")),
        e("mag_of_scalar", "MAG(1)", "E0305", Text("1")),
        e("vector_where_scalar_needed", "[1,2,3]", "E0305", All).scalar(),
        e("scalar_where_vector_needed", "1+2", "E0305", All).vector(),
        // E0306: a tenth nested IF; the span is the outermost IF.
        e("ten_nested_ifs", ten_ifs, "E0306", All),
        e("ten_ifs_in_test_position", nest("IF(", "1", ":1,2,3)", 10), "E0306", All),
        e("ten_ifs_inside_a_sum", format!("1+{}", nest("IF(1:0,0,", "7", ")", 10)), "E0306", Bytes(2, 103)),
        // E0307: constant arguments outside the domain.
        e("step_x0_equals_x1", "STEP(x,1,0,1,1)", "E0307", All),
        e("step_x0_above_x1", "STEP(x,2,0,1,1)", "E0307", All),
        e("step_folded_x0", "STEP(x,2-1,0,1,1)", "E0307", All),
        e("step5_x0_above_x1", "STEP5(x,3,0,2,1)", "E0307", All),
        e("havsin_x0_equals_x1", "HAVSIN(x,1,0,1,1)", "E0307", All),
        e("impact_zero_penetration", "IMPACT(x,v,1,1E5,1.5,100,0)", "E0307", Bytes(25, 26)),
        e("impact_negative_exponent", "IMPACT(x,v,1,1E5,-1.5,100,0.1)", "E0307", Text("-1.5")),
        e("impact_negative_stiffness", "IMPACT(x,v,1,-1,1.5,100,0.1)", "E0307", Text("-1")),
        e("impact_negative_damping", "IMPACT(x,v,1,1,1,-1,1)", "E0307", Text("-1")),
        e("bistop_x1_above_x2", "BISTOP(0,5,2,-2,1,1,1,1)", "E0307", All),
        e("bistop_negative_stiffness", "BISTOP(x,v,-1,1,-1,1,1,1)", "E0307", Nth("-1", 1)),
        e("bistop_zero_exponent", "BISTOP(x,v,-1,1,1,0,1,1)", "E0307", Text("0")),
        // SWEEP(x, a, x0, f0, x1, f1, dx) has STEP's x0 < x1 (issue 11 §4: it was NaN at
        // run time) and needs dx > 0.
        e("sweep_x0_above_x1", "SWEEP(0.5,1,1,10,0,1,0.1)", "E0307", All),
        e("sweep_x0_equals_x1", "SWEEP(x,1,2,10,2,1,0.1)", "E0307", All),
        e("sweep_zero_fade", "SWEEP(x,1,0,10,1,20,0)", "E0307", Bytes(20, 21)),
        e("mod_by_zero", "MOD(x,0)", "E0307", Text("0")),
        e("mod_by_folded_zero", "MOD(x,1-1)", "E0307", Text("1-1")),
        e("iord_on_surface", "AKISPL(x,0.5,1,1)", "E0307", Bytes(15, 16)),
        // E0308: measures need a model.
        e("dx_without_model", "DX(1,2)", "E0308", All),
        e("uvz_without_model", "UVZ(1)", "E0308", All),
        e("varval_without_model", "VARVAL(1)", "E0308", All),
        e("vector_measure_in_mag", "MAG(DXYZ(1,2))", "E0308", Text("DXYZ(1,2)")),
        e("force_without_model", "2*FX(1)", "E0308", Text("FX(1)")),
        // E0309: functions mbfx does not evaluate.
        e("user", "USER(1,2)", "E0309", All),
        e("delay", "DELAY(1,2,3)", "E0309", All),
        e("interp", "INTERP(1,1,1)", "E0309", All),
        e("curve", "CURVE(1,0,1,1)", "E0309", All),
        // E0310: constants called, functions not called.
        e("pi_called", "PI()", "E0310", All),
        e("time_called", "TIME(1)", "E0310", All),
        e("bare_sin", "SIN", "E0310", All),
        e("bare_if", "IF", "E0310", All),
        e("bare_sin_after_call", "SIN(1)+SIN", "E0310", Nth("SIN", 1)),
        // E0311: data elements the scope does not define.
        e("undefined_spline", "AKISPL(1,0,5)", "E0311", Text("5")),
    ]
}

/// Runs one case; returns what went wrong, if anything.
fn run(case: &Case) -> Result<(), String> {
    let src = case.input.as_str();
    let scope = xvt_scope();
    let result = compile(src, &scope, case.expect);
    let diags: Vec<Diagnostic> = match &result {
        Ok(c) => c.warnings.clone(),
        Err(d) => d.clone(),
    };
    for d in &diags {
        let spans = std::iter::once(&d.span).chain(d.labels.iter().map(|(s, _)| s));
        for s in spans {
            if !(s.start <= s.end && s.end <= src.len()) {
                return Err(format!(
                    "{} span {s:?} outside 0..{}",
                    d.code.as_str(),
                    src.len()
                ));
            }
            if !(src.is_char_boundary(s.start) && src.is_char_boundary(s.end)) {
                return Err(format!("{} span {s:?} splits a character", d.code.as_str()));
            }
        }
    }
    if src.len() <= 10_000 {
        let text = render(&diags, &SourceFile::new("case", src), false);
        if diags.iter().any(|d| !text.contains(d.code.as_str())) {
            return Err(format!("the rendering lacks a code:\n{text}"));
        }
    }
    match (case.want, result) {
        (Want::Error { code, at, help }, Err(diags)) => {
            let Some(first) = diags.iter().find(|d| d.is_error()) else {
                return Err("compile failed without an error".to_string());
            };
            let span = at.resolve(src);
            if first.code.as_str() != code || first.span != span {
                return Err(format!(
                    "expected {code} at {span:?}, got {} at {:?}: {}",
                    first.code.as_str(),
                    first.span,
                    first.message
                ));
            }
            if let Some(h) = help {
                if !first.help.as_deref().unwrap_or("").contains(h) {
                    return Err(format!("help {:?} lacks {h:?}", first.help));
                }
            }
            Ok(())
        }
        (Want::Error { code, .. }, Ok(_)) => Err(format!("expected {code}, but it compiled")),
        (Want::Value(ok), Ok(c)) => {
            let p = Program::new(c.function);
            let mut out = vec![0.0; p.function().outputs.len()];
            p.eval_into(&Context::new(0.5, &[0.5, 0.5, 0.5]), &mut out);
            match out[..] {
                [x] if ok(x) => Ok(()),
                _ => Err(format!("unexpected value {out:?}")),
            }
        }
        (Want::Value(_), Err(d)) => Err(format!(
            "expected a value, got {}: {}",
            d[0].code.as_str(),
            d[0].message
        )),
    }
}

#[test]
fn bad_input_catalogue() {
    let all = cases();
    assert!(all.len() >= 80, "only {} cases", all.len());
    let mut names: Vec<&str> = all.iter().map(|c| c.name).collect();
    names.sort_unstable();
    names
        .windows(2)
        .for_each(|w| assert_ne!(w[0], w[1], "duplicate case name"));
    let mut failures = Vec::new();
    for case in all {
        let name = case.name;
        let started = Instant::now();
        let outcome = std::thread::Builder::new()
            .name(name.to_string())
            .stack_size(STACK)
            .spawn(move || run(&case))
            .expect("spawn a case thread")
            .join();
        let took = started.elapsed();
        match outcome {
            Ok(Ok(())) if took <= TIME_LIMIT => {}
            Ok(Ok(())) => failures.push(format!("{name}: took {took:?}")),
            Ok(Err(why)) => failures.push(format!("{name}: {why}")),
            Err(_) => failures.push(format!("{name}: panicked")),
        }
    }
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Inputs with one mistake get exactly one error: no follow-on errors after a lexical
/// error (regression: `1;2` also reported a missing operator, `1e+` a second error).
#[test]
fn one_mistake_gives_one_error() {
    for (input, code, span) in [
        ("1e+", "E0102", 0..3),
        ("2*1E-", "E0102", 2..5),
        ("1;2", "E0101", 1..2),
        ("1\\2", "E0101", 1..2),
        ("1\u{0}2", "E0101", 1..2),
        ("$x + 1", "E0101", 0..1),
        ("[1,2,3", "E0202", 6..6),
    ] {
        let diags = compile(input, &xvt_scope(), Expect::Any).expect_err(input);
        let got: Vec<(&str, Span)> = diags
            .iter()
            .map(|d| (d.code.as_str(), d.span.clone()))
            .collect();
        assert_eq!(got, vec![(code, span)], "{input:?}");
    }
    let diags = compile("[1,2,3", &xvt_scope(), Expect::Any).expect_err("open bracket");
    assert!(
        diags[0].message.contains("missing `]`"),
        "{}",
        diags[0].message
    );
}

/// A line of garbage reports a bounded number of errors (regression: 10 kB of `@` printed
/// 200 MB of frames).
#[test]
fn errors_per_expression_are_capped() {
    let input = "@".repeat(10_000);
    let diags = compile(&input, &xvt_scope(), Expect::Any).expect_err("garbage");
    assert_eq!(diags.len(), mbfx::diag::MAX_DIAGNOSTICS);
    assert_eq!(diags.last().map(|d| d.code.as_str()), Some("E0207"));
    let text = render(&diags, &SourceFile::new("at", input.as_str()), false);
    assert!(text.len() < 20_000, "{} bytes of report", text.len());
    // Too deep, and an error every few tokens: the depth error first, the rest counted
    // (regression: all 20 001 were reported).
    let input = format!("{}x{}", repeat("-", 100_000), repeat(" y + x", 20_000));
    let diags = compile(&input, &xvt_scope(), Expect::Any).expect_err("too deep");
    assert_eq!(diags.len(), mbfx::diag::MAX_DIAGNOSTICS);
    assert_eq!(diags[0].code.as_str(), "E0206");
    assert_eq!(diags.last().map(|d| d.code.as_str()), Some("E0207"));
}
