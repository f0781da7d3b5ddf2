//! `.adm` datasets, the statement layer: [`read_statements`] splits a dataset into
//! statements (`KEYWORD/id, ARG=value, …`, continuation lines, comments, `adams_view_name`
//! names) with byte spans into the file, and [`expression_arguments`] lists the
//! FUNCTION-language expressions they hold as raw byte ranges for the expression lexer.
//! Keyword tables (statements, expression arguments, free-text arguments) live in
//! [`keywords`]; [`decode`] turns file bytes into the text these functions read.
//!
//! The model layer on top: [`read_model`] builds a [`elements::Model`] (parts, markers,
//! constraints, forces, data, outputs, [`graphics`]) from the statements, checking references and
//! lowering every expression with the model as its [`scope`]; [`report`] formats what
//! `mbfx check` prints about a model.
//!
//! Beside them: [`commands`] reads an Adams command file (`.acf`) with the same statement
//! parser, and [`integrator_settings`] and [`equilibrium_settings`] type the INTEGRATOR
//! and EQUILIBRIUM statements for both.

mod args;
pub mod beams;
pub mod command_changes;
mod command_lines;
pub mod commands;
pub mod contact;
mod cursor;
pub mod elements;
pub mod equilibrium_settings;
mod expected;
pub mod expressions;
pub mod frames;
pub mod friction;
pub mod graphics;
pub mod inertia;
pub mod integrator_settings;
pub mod keywords;
pub mod kinematics_settings;
pub mod linear_command;
mod lines;
mod motion_time;
pub mod overrides;
mod read_bodies;
mod read_contact;
mod read_data;
mod read_graphics;
mod read_links;
mod read_states;
pub mod reader;
pub mod report;
mod resolve;
pub mod scope;
pub mod statement;
pub mod states;
mod stmt_args;
pub mod units;
mod variable_dims;

#[cfg(test)]
mod tests;

pub use elements::Model;
pub use expressions::{expression_arguments, ExprArgument};
pub use keywords::{is_expression_argument, EXPRESSION_ARGUMENTS};
pub use lines::decode;
pub use reader::{read_model, ModelRead};
pub use statement::{read_statements, title_span, ArgValue, Argument, Item, ItemKind, Statement};
