//! `.adm` datasets, the statement layer: [`read_statements`] splits a dataset into
//! statements (`KEYWORD/id, ARG=value, …`, continuation lines, comments, `adams_view_name`
//! names) with byte spans into the file, and [`expression_arguments`] lists the
//! FUNCTION-language expressions they hold as raw byte ranges for the expression lexer.
//! Keyword tables (statements, expression arguments, free-text arguments) live in
//! [`keywords`]; [`decode`] turns file bytes into the text these functions read. The
//! model layer builds parts, markers and forces from these statements.

mod args;
pub mod check;
mod cursor;
pub mod elements;
pub mod expressions;
pub mod keywords;
mod lines;
pub mod statement;

#[cfg(test)]
mod corpus_tests;
#[cfg(test)]
mod statement_tests;

pub use expressions::{expression_arguments, ExprArgument};
pub use keywords::{is_expression_argument, EXPRESSION_ARGUMENTS};
pub use lines::decode;
pub use statement::{read_statements, title_span, ArgValue, Argument, Item, ItemKind, Statement};
