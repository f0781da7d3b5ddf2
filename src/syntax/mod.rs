//! Front end: text → tokens ([`lexer`]) → syntax tree ([`parser`], [`ast`]), and back to
//! text ([`mod@print`]).

pub mod ast;
pub(crate) mod driver;
pub mod fast;
pub mod lexer;
pub mod parser;
pub mod print;
