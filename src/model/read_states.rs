//! Readers of the state elements (issue 40 §3) into [`super::states::StateElements`]:
//! DIFF, LSE, TFSISO and the MATRIX data LSE reads. GSE is refused by name: its equations
//! come from compiled user subroutines (GSE_DERIV, GSE_OUTPUT) whatever the statement
//! says, which mbfx cannot run.

use super::elements::Id;
use super::reader::Reader;
use super::states::{Diff, Lse, Matrix, Tfsiso};
use super::stmt_args::Args;
use crate::diag::{Code, Diagnostic};

/// `DIFF/id, FUNCTION = e, IC = x0[, ẋ0][, IMPLICIT][, STATIC_HOLD]`.
pub fn diff(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let implicit = a.flag("IMPLICIT", 3);
    let static_hold = a.flag("STATIC_HOLD", 3);
    let ic = a.numbers("IC", 2, 1..=2).unwrap_or_default();
    if let Some(function) = r.required_expr(a, "FUNCTION", 2) {
        r.model.states.diffs.push(Diff {
            el,
            function,
            ic: ic.first().copied().unwrap_or(0.0),
            ic_rate: ic.get(1).copied(),
            implicit,
            static_hold,
        });
    }
}

/// `MATRIX/id, FULL = RORDER | CORDER, ROWS, COLUMNS, VALUES` or `SPARSE, ROWS, COLUMNS,
/// I, J, VALUES`; `FILE =` is refused.
pub fn matrix(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    if let Some(arg) = a.find("FILE", 2) {
        let msg = format!(
            "{} reads its values from a file, which mbfx does not",
            a.label
        );
        a.error(Code::BadArgument, arg.span.clone(), msg);
        a.find("NAME", 2);
        return;
    }
    let rows = a.required_number("ROWS", 1);
    let cols = a.required_number("COLUMNS", 1);
    let values = a.numbers("VALUES", 1, 1..=usize::MAX);
    let sparse = a.flag("SPARSE", 1);
    let full = a.word("FULL", 2).map(|(w, s)| (w.to_ascii_uppercase(), s));
    let (Some(rows), Some(cols), Some(values)) = (rows, cols, values) else {
        if a.stmt.arg("VALUES", 1).is_none() {
            a.missing("VALUES = …");
        }
        return;
    };
    let span = a.stmt.keyword_span.clone();
    let size = |v: f64| (v >= 1.0 && v.fract() == 0.0 && v <= 1e6).then_some(v as usize);
    let (Some(nr), Some(nc)) = (size(rows), size(cols)) else {
        let msg = format!(
            "{}: ROWS and COLUMNS must be positive whole numbers",
            a.label
        );
        return a.error(Code::BadArgument, span, msg);
    };
    let mut dense = vec![0.0; nr * nc];
    if sparse {
        let (Some(i), Some(j)) = (
            a.numbers("I", 1, 1..=usize::MAX),
            a.numbers("J", 1, 1..=usize::MAX),
        ) else {
            return a.missing("I = … and J = … (SPARSE)");
        };
        if i.len() != values.len() || j.len() != values.len() {
            let msg = format!("{}: I, J and VALUES must be as long", a.label);
            return a.error(Code::BadArgument, span, msg);
        }
        for ((&i, &j), &v) in i.iter().zip(&j).zip(&values) {
            match (size(i), size(j)) {
                (Some(i), Some(j)) if i <= nr && j <= nc => dense[(i - 1) * nc + j - 1] = v,
                _ => {
                    let msg = format!("{}: entry ({i}, {j}) is outside {nr}×{nc}", a.label);
                    return a.error(Code::BadArgument, span, msg);
                }
            }
        }
    } else {
        if values.len() != nr * nc {
            let msg = format!(
                "{}: {nr}×{nc} needs {} VALUES, found {}",
                a.label,
                nr * nc,
                values.len()
            );
            return a.error(Code::BadArgument, span, msg);
        }
        match full.as_ref().map(|(w, s)| (w.as_str(), s.clone())) {
            Some(("CORDER", _)) => {
                for c in 0..nc {
                    for k in 0..nr {
                        dense[k * nc + c] = values[c * nr + k];
                    }
                }
            }
            None | Some(("RORDER", _)) => dense = values,
            Some((_, s)) => {
                let msg = format!("{}: FULL is RORDER or CORDER", a.label);
                return a.error(Code::BadArgument, s, msg);
            }
        }
    }
    r.model.states.matrices.push(Matrix {
        el,
        rows: nr,
        cols: nc,
        values: dense,
    });
}

/// `LSE/id, X = id, A = id[, U = id, B = id][, Y = id, C = id[, D = id]][, IC = id]
/// [, STATIC_HOLD]`.
pub fn lse(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let id = |a: &mut Args, k: &str| a.id(k, 1).map(|x| x.0);
    let (x, am) = (a.required_id("X", 1), a.required_id("A", 1));
    let (u, y, ic) = (id(a, "U"), id(a, "Y"), id(a, "IC"));
    let (b, c, d) = (id(a, "B"), id(a, "C"), id(a, "D"));
    let static_hold = a.flag("STATIC_HOLD", 3);
    let span = a.stmt.keyword_span.clone();
    for (matrix, array, what) in [
        (b, u, "B needs U"),
        (c, y, "C needs Y"),
        (d, u, "D needs U"),
    ] {
        if matrix.is_some() && array.is_none() {
            let msg = format!("{}: {what}", a.label);
            return a.error(Code::MissingArgument, span, msg);
        }
    }
    let (Some(x), Some(am)) = (x, am) else { return };
    r.model.states.lses.push(Lse {
        el,
        x: x.0,
        u,
        y,
        ic,
        a: am.0,
        b,
        c,
        d,
        static_hold,
    });
}

/// `TFSISO/id, NUMERATOR = …, DENOMINATOR = …, X = id, U = id, Y = id[, STATIC_HOLD]`.
pub fn tfsiso(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let numerator = a.numbers("NUMERATOR", 1, 1..=usize::MAX);
    let denominator = a.numbers("DENOMINATOR", 1, 2..=usize::MAX);
    let ids: Vec<Option<Id>> = ["X", "U", "Y"]
        .iter()
        .map(|k| a.required_id(k, 1).map(|x| x.0))
        .collect();
    let static_hold = a.flag("STATIC_HOLD", 3);
    for (key, v) in [("NUMERATOR", &numerator), ("DENOMINATOR", &denominator)] {
        if v.is_none() && a.stmt.arg(key, 1).is_none() {
            a.missing(&format!("{key} = coefficients"));
        }
    }
    let (Some(numerator), Some(denominator), [Some(x), Some(u), Some(y)]) =
        (numerator, denominator, ids.as_slice())
    else {
        return;
    };
    r.model.states.tfsisos.push(Tfsiso {
        el,
        numerator,
        denominator,
        x: *x,
        u: *u,
        y: *y,
        static_hold,
    });
}

/// The diagnostic a GSE gets before it joins the statements left out.
pub fn gse_refused(a: &Args) -> Diagnostic {
    Diagnostic::warning(
        Code::UnsupportedStatement,
        a.stmt.keyword_span.clone(),
        format!(
            "{}: a GSE's equations come from compiled user subroutines (GSE_DERIV, \
             GSE_OUTPUT, …), which mbfx cannot run; it is left out",
            a.label
        ),
    )
}

#[cfg(test)]
mod tests {
    use crate::diag::Code;
    use crate::model::reader::read_model;

    const BASE: &str = "t\nPART/1, GROUND\nMARKER/10, PART = 1\n";

    #[test]
    fn matrices_read_in_row_order_whatever_their_layout() {
        let text = format!(
            "{BASE}MATRIX/1, FULL = RORDER, ROWS = 2, COLUMNS = 3, VALUES = 1, 2, 3, 4, 5, 6\n\
             MATRIX/2, FULL = CORDER, ROWS = 2, COLUMNS = 3, VALUES = 1, 4, 2, 5, 3, 6\n\
             MATRIX/3, SPARSE, ROWS = 2, COLUMNS = 3, I = 2, 1, J = 3, 1, VALUES = 6, 1\nEND\n"
        );
        let r = read_model(&text);
        assert!(!r.has_errors(), "{:#?}", r.diagnostics);
        let m = &r.model.states.matrices;
        assert_eq!(m[0].values, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(m[1].values, m[0].values);
        assert_eq!(m[2].values, [1.0, 0.0, 0.0, 0.0, 0.0, 6.0]);
        // MATRIX is data: read, and neither warned nor left out.
        assert!(r.model.ignored.is_empty(), "{:?}", r.model.ignored);
    }

    #[test]
    fn bad_state_statements_are_errors_at_their_place_never_panics() {
        for (extra, code, at) in [
            (
                "MATRIX/1, FILE = a.mtx, NAME = A",
                Code::BadArgument,
                "FILE = a.mtx",
            ),
            (
                "MATRIX/1, FULL = RORDER, ROWS = 2, COLUMNS = 2, VALUES = 1, 2, 3",
                Code::BadArgument,
                "MATRIX",
            ),
            (
                "MATRIX/1, SPARSE, ROWS = 2, COLUMNS = 2, I = 3, J = 1, VALUES = 1",
                Code::BadArgument,
                "MATRIX",
            ),
            ("LSE/1, X = 2", Code::MissingArgument, "LSE"),
            ("LSE/1, X = 2, A = 3, B = 4", Code::MissingArgument, "LSE"),
            ("DIFF/1, IC = 0", Code::MissingArgument, "DIFF"),
            (
                "TFSISO/1, NUMERATOR = 1, X = 1, U = 2, Y = 3",
                Code::MissingArgument,
                "TFSISO",
            ),
        ] {
            let text = format!("{BASE}{extra}\nEND\n");
            let r = read_model(&text);
            let found = r
                .diagnostics
                .iter()
                .find(|d| d.code == code)
                .unwrap_or_else(|| panic!("{extra}: no {code:?} in {:#?}", r.diagnostics));
            assert!(
                text[found.span.clone()].starts_with(at),
                "{extra}: at `{}`",
                &text[found.span.clone()]
            );
        }
    }

    #[test]
    fn gse_is_refused_by_name_and_stays_among_what_is_left_out() {
        let r = read_model(&format!("{BASE}GSE/4, NS = 2, NO = 1\nEND\n"));
        assert!(r.diagnostics.iter().any(|d| d
            .message
            .contains("GSE/4: a GSE's equations come from compiled user subroutines")));
        let gse = r
            .model
            .ignored
            .iter()
            .find(|i| i.kind == "GSE")
            .expect("GSE left out");
        assert!(gse.physical);
    }

    #[test]
    fn a_diff_reads_its_ic_pair_and_flags() {
        let text = format!(
            "{BASE}DIFF/7, IMPLICIT, STATIC_HOLD, IC = 1.5, -2, FUNCTION = DIF1(7) + DIF(7)\nEND\n"
        );
        let r = read_model(&text);
        assert!(!r.has_errors(), "{:#?}", r.diagnostics);
        let d = &r.model.states.diffs[0];
        assert_eq!((d.el.id, d.ic, d.ic_rate), (7, 1.5, Some(-2.0)));
        assert!(d.implicit && d.static_hold);
        assert!(r.model.ignored.is_empty(), "{:?}", r.model.ignored);
    }
}
