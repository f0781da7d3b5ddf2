//! Expression arguments of a dataset: every FUNCTION-language expression that the
//! statements of an `.adm` file hold, in file order, with the byte range the expression
//! lexer should read. This is what the checker walks to compile a whole dataset.

use super::statement::Statement;
use std::ops::Range;

/// One expression argument of a dataset statement.
#[derive(Clone, Debug, PartialEq)]
pub struct ExprArgument {
    /// The statement keyword as written, upper-cased (`SFORCE`).
    pub statement: String,
    /// The statement's id (`SFORCE/3` has 3), when it has one.
    pub id: Option<i64>,
    /// The argument name as written, upper-cased (`FUNCTION`, `FUN`, `F2`, `FX`).
    pub argument: String,
    /// The expression's bytes in the file: no surrounding blanks, no terminating `\`, no
    /// trailing comment or line end. It may cross continuation lines.
    pub span: Range<usize>,
    /// 1-based line of the argument name.
    pub line: usize,
    /// From the `adams_view_name='…'` comment before the statement.
    pub view_name: Option<String>,
    /// Written `USER(…)`: a user subroutine call, not an expression mbfx evaluates.
    pub is_user_call: bool,
}

/// Every expression argument of the statements, in file order.
pub fn expression_arguments(stmts: &[Statement]) -> Vec<ExprArgument> {
    stmts
        .iter()
        .flat_map(|stmt| {
            stmt.args.iter().filter_map(move |arg| {
                Some(ExprArgument {
                    statement: stmt.keyword.clone(),
                    id: stmt.id,
                    argument: arg.name.clone(),
                    span: arg.expr_span()?,
                    line: arg.line,
                    view_name: stmt.view_name.clone(),
                    is_user_call: arg.is_user_call,
                })
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::read_statements;

    fn exprs(text: &str) -> Vec<(String, String, String)> {
        let (stmts, diags) = read_statements(text);
        assert!(diags.is_empty(), "{diags:?}");
        expression_arguments(&stmts)
            .into_iter()
            .map(|e| (e.statement, e.argument, text[e.span].to_string()))
            .collect()
    }

    #[test]
    fn expressions_come_in_file_order_with_their_statement() {
        let text = "t\nVARIABLE/1, FUNCTION = TIME\nGFORCE/2, FX = 0\\ FY = 1\\\nEND\n";
        let got = exprs(text);
        let want = [
            ("VARIABLE", "FUNCTION", "TIME"),
            ("GFORCE", "FX", "0"),
            ("GFORCE", "FY", "1"),
        ];
        assert_eq!(got.len(), want.len());
        for (g, w) in got.iter().zip(want) {
            assert_eq!((g.0.as_str(), g.1.as_str(), g.2.as_str()), w);
        }
    }

    #[test]
    fn user_calls_and_view_names_are_carried() {
        let text =
            "t\n! adams_view_name='drive'\nSFORCE/4, FUNCTION = USER(1,2)\\\n, ROUTINE = a::b\n";
        let (stmts, diags) = read_statements(text);
        assert!(diags.is_empty(), "{diags:?}");
        let e = expression_arguments(&stmts);
        assert_eq!(e.len(), 1);
        assert!(e[0].is_user_call);
        assert_eq!(e[0].view_name.as_deref(), Some("drive"));
        assert_eq!((e[0].id, e[0].line), (Some(4), 3));
        assert_eq!(&text[e[0].span.clone()], "USER(1,2)");
    }
}
