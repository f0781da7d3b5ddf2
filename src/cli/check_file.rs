//! `mbfx check FILE`: check every expression of an expression file (one per line,
//! continuation lines honoured), or read an `.adm` dataset into a model (every statement
//! and expression checked against it), analyse it with the multibody core
//! ([`crate::session`]: 2D or 3D, assembly, degrees of freedom, redundancy) and print the
//! model report; report all diagnostics. An expression file's diagnostics are written
//! as each expression is checked, so a big file reports while it is read.

use super::output::{Output, Stop};
use super::Dim;
use crate::check::{self, Expect, Scope};
use crate::diag::{Code, Diagnostic, Severity, SourceFile};
use crate::session;
use crate::session::evaluate::Evaluator;
use crate::session::files::{read_dataset, read_text};
use std::ops::Range;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct CheckArgs {
    /// User variables the expressions may read, NAME=VALUE; repeatable.
    #[arg(long = "var", value_name = "NAME=VALUE")]
    vars: Vec<String>,
    /// For a dataset: build the multibody system in 2D (an error when the scene is not
    /// planar) or 3D; by default 2D when the scene is planar.
    #[arg(long, value_enum, value_name = "2|3")]
    dim: Option<Dim>,
    /// An expression file or an .adm dataset.
    file: PathBuf,
}

/// Byte ranges of the logical expressions of an expression file: one per line, a line
/// whose first non-blank character is `,` continuing the previous one; blank lines and
/// `!` comment lines are skipped.
pub fn logical_lines(text: &str) -> Vec<Range<usize>> {
    let mut out: Vec<Range<usize>> = Vec::new();
    let mut start = 0;
    for line in text.split_inclusive('\n') {
        let end = start + line.len();
        let body = line.trim_end_matches(['\n', '\r']);
        let trimmed = body.trim_start_matches([' ', '\t']);
        let body_end = start + body.len();
        if trimmed.starts_with(',') && !out.is_empty() {
            if let Some(last) = out.last_mut() {
                last.end = body_end;
            }
        } else if !trimmed.trim().is_empty() && !trimmed.starts_with('!') {
            out.push(start..body_end);
        }
        start = end;
    }
    out
}

/// Checks every expression of an expression file, handing each expression's diagnostics
/// (spans into the whole text) to `report` as soon as it is checked; returns the number
/// of expressions.
pub fn check_expressions<E>(
    text: &str,
    scope: &dyn Scope,
    mut report: impl FnMut(&[Diagnostic]) -> Result<(), E>,
) -> Result<usize, E> {
    let ranges = logical_lines(text);
    for r in &ranges {
        let found = match check::compile(&text[r.clone()], scope, Expect::Any) {
            Ok(c) => c.warnings,
            Err(d) => d,
        };
        if !found.is_empty() {
            let shifted: Vec<Diagnostic> = found.into_iter().map(|d| d.shifted(r.start)).collect();
            report(&shifted)?;
        }
    }
    Ok(ranges.len())
}

/// The first line of an expression file that opens a dataset statement (`PART/2, ...`:
/// a statement keyword, `/` and an id), as (line number, the keyword and id), for the
/// hint that a file not named `.adm` looks like a dataset.
fn dataset_statement(text: &str) -> Option<(usize, &str)> {
    use crate::model::keywords::{lookup_statement, Lookup};
    text.lines().enumerate().find_map(|(i, line)| {
        let line = line.trim_start();
        let (word, rest) = line.split_once('/')?;
        let id_len = rest.bytes().take_while(u8::is_ascii_digit).count();
        let known = matches!(lookup_statement(word.trim_end()), Lookup::Known(_));
        (known && id_len > 0).then(|| (i + 1, &line[..word.len() + 1 + id_len]))
    })
}

fn is_dataset(path: &std::path::Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("adm"))
}

/// Errors and warnings reported so far.
#[derive(Default)]
struct Tally {
    errors: usize,
    warnings: usize,
}

impl Tally {
    fn count(&mut self, diags: &[Diagnostic]) {
        let errors = diags
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .count();
        self.errors += errors;
        self.warnings += diags.len() - errors;
    }
}

pub fn run(a: &CheckArgs, o: &mut Output) -> Result<i32, Stop> {
    let mut inputs = Evaluator::new(super::Engine::Interp.into());
    super::eval::define_variables(&a.vars, &mut inputs, o)?;
    let scope = inputs.variables();
    let dataset = is_dataset(&a.file);
    let read = if dataset {
        read_dataset(&a.file)
    } else {
        read_text(&a.file).map(|t| (t, Vec::new()))
    };
    let (text, early) = match read {
        Ok(t) => t,
        Err(u) => {
            o.diagnostics(&[u.diagnostic], &u.source)?;
            return Err(Stop::Failed);
        }
    };
    let source_name = a.file.display().to_string();
    if !dataset && a.dim.is_some() {
        let d = Diagnostic::error(
            Code::CommandLine,
            0..0,
            format!("--dim applies to .adm datasets; {source_name} is read as an expression file"),
        )
        .with_help("a file is read as a dataset when its name ends in .adm");
        o.diagnostics(&[d], &SourceFile::textless("--dim"))?;
        return Err(Stop::Failed);
    }
    let source = SourceFile::new(source_name.clone(), text);
    let mut tally = Tally::default();
    tally.count(&early);
    o.diagnostics(&early, &source)?;
    let summary = if dataset {
        let checked = session::check::check(&source_name, &source.text, Dim::request(a.dim));
        let mut diags = checked.diagnostics;
        if let Some(Err(refused)) = checked.analysis {
            diags.splice(0..0, refused.diagnostics);
        }
        tally.count(&diags);
        o.diagnostics(&diags, &source)?;
        o.out().write_all(checked.report.as_bytes())?;
        format!("{} elements", checked.elements)
    } else {
        let n = check_expressions(&source.text, scope, |diags| {
            tally.count(diags);
            o.diagnostics(diags, &source)
        })?;
        if tally.errors > 0 {
            if let Some((line, head)) = dataset_statement(&source.text) {
                writeln!(
                    o.err(),
                    "hint: this looks like an .adm dataset (line {line} starts with `{head}`); \
                     a file is read as a dataset when its name ends in .adm"
                )?;
            }
        }
        format!("{n} expressions")
    };
    let Tally { errors, warnings } = tally;
    writeln!(
        o.out(),
        "{source_name}: {summary}; {errors} errors, {warnings} warnings"
    )?;
    Ok(i32::from(errors > 0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn continuation_lines_join_and_comments_skip() {
        let text = "1+1\n! note\n\nSTEP(TIME,0,0,\n, 1,100)\n  , +1\n2\n";
        let lines: Vec<&str> = logical_lines(text).into_iter().map(|r| &text[r]).collect();
        assert_eq!(lines, ["1+1", "STEP(TIME,0,0,\n, 1,100)\n  , +1", "2"]);
    }
}
