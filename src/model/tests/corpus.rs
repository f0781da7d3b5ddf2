//! Corpus oracle: for every `.adm` file under `shared/corpus/adams`, the expression
//! arguments the statement layer finds must match the rows that the reference script
//! wrote to `shared/corpus/expressions-occurrences.tsv` (line of the argument, statement,
//! id, argument name, expression text with continuation joins normalised). Where the two
//! disagree on purpose, [`KNOWN_DIFFERENCES`] lists each row with its reason.

use super::corpus_files::adm_files;
use crate::model::{decode, expression_arguments, read_statements};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One extracted expression: line, statement, id, argument, normalised text.
type Row = (usize, String, Option<i64>, String, String);

/// Rows on which mbfx and the reference script disagree on purpose.
struct Known {
    /// Path relative to `shared/corpus`.
    path: &'static str,
    /// The rows concerned: argument lines in this range.
    lines: std::ops::RangeInclusive<usize>,
    /// The reference has these rows and mbfx does not (`true`), or the reverse.
    reference_only: bool,
    /// How many rows.
    rows: usize,
    reason: &'static str,
}

const KNOWN_DIFFERENCES: &[Known] = &[Known {
    path: "adams/alex-marinov__mbdyn/contrib/a2m/samples/monster.adm",
    lines: 389..=usize::MAX,
    reference_only: true,
    rows: 28,
    reason: "a synthetic MBDyn translator test made of four datasets pasted together: \
             Adams stops reading at the first END (line 388, multibody spec §1.1), \
             the reference script read on",
}];

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus")
}

/// Collapses a continuation join (line break, blanks, comma) and every blank run to one
/// blank.
fn normalise(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    while let Some(ch) = chars.next() {
        if ch == '\n' {
            while chars.peek().is_some_and(|c| matches!(c, ' ' | '\t' | '\r')) {
                chars.next();
            }
            if chars.peek() == Some(&',') {
                chars.next();
            }
            out.push(' ');
        } else if ch.is_whitespace() || ch == '\0' {
            out.push(' ');
        } else {
            out.push(ch);
        }
    }
    out.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn reference_rows() -> BTreeMap<String, Vec<Row>> {
    let path = corpus_dir().join("expressions-occurrences.tsv");
    let tsv = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut rows: BTreeMap<String, Vec<Row>> = BTreeMap::new();
    for line in tsv.lines().skip(1) {
        let f: Vec<&str> = line.split('\t').collect();
        assert_eq!(f.len(), 6, "bad TSV row {line:?}");
        if !f[0].ends_with(".adm") {
            continue;
        }
        let row = (
            f[1].parse().expect("line number"),
            f[2].to_string(),
            f[3].parse().ok(),
            f[4].to_string(),
            normalise(f[5]),
        );
        rows.entry(f[0].to_string()).or_default().push(row);
    }
    rows
}

fn our_rows(path: &Path) -> Vec<Row> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let (text, _) = decode(&bytes);
    let (stmts, _) = read_statements(&text);
    expression_arguments(&stmts)
        .into_iter()
        .map(|e| {
            let expr = normalise(&text[e.span.clone()]);
            (e.line, e.statement, e.id, e.argument, expr)
        })
        .collect()
}

fn is_known(path: &str, line: usize, reference_only: bool) -> Option<&'static Known> {
    KNOWN_DIFFERENCES
        .iter()
        .find(|k| k.path == path && k.reference_only == reference_only && k.lines.contains(&line))
}

/// Counts of each row.
fn counted(rows: Vec<Row>) -> BTreeMap<Row, i64> {
    let mut map = BTreeMap::new();
    for row in rows {
        *map.entry(row).or_insert(0) += 1;
    }
    map
}

#[test]
fn expressions_match_the_reference_extraction() {
    let root = corpus_dir();
    let mut reference = reference_rows();
    let files = adm_files(&root.join("adams"));
    assert_eq!(files.len(), 75, "corpus changed: update this test");
    let mut problems = Vec::new();
    let mut known_rows: BTreeMap<&str, usize> = BTreeMap::new();
    let mut total = 0;
    for path in &files {
        let rel = path
            .strip_prefix(&root)
            .map(|p| p.to_string_lossy().replace('\\', "/"))
            .unwrap_or_default();
        let ours = our_rows(path);
        total += ours.len();
        let mut diff = counted(ours);
        for row in reference.remove(&rel).unwrap_or_default() {
            *diff.entry(row).or_insert(0) -= 1;
        }
        for (row, n) in diff.into_iter().filter(|(_, n)| *n != 0) {
            let reference_only = n < 0;
            match is_known(&rel, row.0, reference_only) {
                Some(k) => *known_rows.entry(k.reason).or_default() += n.unsigned_abs() as usize,
                None => {
                    let side = if reference_only { "reference" } else { "mbfx" };
                    problems.push(format!("{rel}: only in {side} ({n:+}): {row:?}"));
                }
            }
        }
    }
    assert!(
        reference.is_empty(),
        "TSV rows for missing files: {:?}",
        reference.keys()
    );
    assert!(
        problems.is_empty(),
        "{} differences:\n{}",
        problems.len(),
        problems.join("\n")
    );
    for k in KNOWN_DIFFERENCES {
        let rows = known_rows.get(k.reason).copied().unwrap_or(0);
        assert_eq!(rows, k.rows, "known difference in {}: {}", k.path, k.reason);
    }
    assert_eq!(total, 2851 - 28, "expression count changed");
}

#[test]
fn corpus_reads_without_errors_except_the_synthetic_files() {
    let root = corpus_dir();
    let files = adm_files(&root.join("adams"));
    let mut with_errors = Vec::new();
    for path in &files {
        let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        let (text, _) = decode(&bytes);
        let (_, diags) = read_statements(&text);
        if diags.iter().any(|d| d.is_error()) {
            let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
            with_errors.push(name.unwrap_or_default());
        }
    }
    // MBDyn's translator samples (alex-marinov/mbdyn contrib/a2m/samples, PROVENANCE.md):
    // the synthetic parser tests continue statements without the leading comma, and the
    // edited export `bipendolo.adm` lost its title line, so its line 2 continues nothing.
    let synthetic = [
        "bipendolo.adm",
        "monster.adm",
        "pm02.adm",
        "prova.adm",
        "prova_marker01.adm",
    ];
    with_errors.retain(|n| !synthetic.contains(&n.as_str()));
    assert!(with_errors.is_empty(), "{with_errors:?}");
}
