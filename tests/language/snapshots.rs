//! Diagnostic snapshots: every file of `tests/data/diagnostics/` is one expression (its
//! text without the final line break) that triggers one family of diagnostics; the
//! rendered report (`diag::render`, no colour) is compared with the insta snapshot
//! `snapshots/language__snapshots__<file stem>.snap`.
//!
//! A new bug in a diagnostic = a new file in `tests/data/diagnostics/`; name it after the
//! code it shows (`E0205_something.txt`) or `multi_...` for several at once. Create its
//! snapshot with `INSTA_UPDATE=always cargo test --release --test language snapshots`,
//! then read the `.snap` file: the code, message, `file:line:column` and the caret must
//! be right before it is checked in.
//!
//! Expressions are checked with the user variables x, v and t defined and no model, as
//! `mbfx eval --var` would; run-time warnings (W04xx) and command-line errors (E05xx) are
//! covered by `tests/cli.rs`.
//!
//! Unit warnings (W0312) likewise: every file of `tests/data/units/` is one expression
//! that breaks one rule of the units check, checked as a dataset without UNITS would
//! check it (every marker exists, SI unit names); its snapshot is
//! `language__snapshots__units_<file stem>.snap`.

use crate::support::xvt_scope;
use mbfx::check::{compile, EveryIdExists, Expect, Scope};
use mbfx::diag::{render, Code, Diagnostic, SourceFile};
use std::path::{Path, PathBuf};

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/diagnostics")
}

fn units_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/units")
}

fn snapshot_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/language/snapshots")
}

/// The input files of `dir`, sorted by name.
fn inputs(dir: PathBuf) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "txt"))
        .collect();
    files.sort();
    files
}

fn stem(path: &Path) -> String {
    path.file_stem()
        .and_then(|s| s.to_str())
        .expect("UTF-8 file name")
        .to_string()
}

/// Checks every input of `dir` in `scope`, hands its diagnostics to `expect` (which
/// asserts what they must be), and compares the rendered report with the snapshot
/// `<prefix><file stem>`.
fn check_snapshots(dir: PathBuf, scope: &dyn Scope, prefix: &str, expect: fn(&str, &[Diagnostic])) {
    let files = inputs(dir);
    assert!(files.len() >= 25, "only {} input files", files.len());
    for path in &files {
        let name = stem(path);
        let raw = std::fs::read_to_string(path).expect("input file");
        let text = raw.strip_suffix('\n').unwrap_or(&raw);
        let diags = match compile(text, scope, Expect::Any) {
            Ok(c) => c.warnings,
            Err(d) => d,
        };
        assert!(!diags.is_empty(), "{name}: no diagnostic for {text:?}");
        expect(&name, &diags);
        let file_name = path.file_name().and_then(|n| n.to_str()).unwrap_or("?");
        let rendered = render(&diags, &SourceFile::new(file_name, text), false);
        insta::with_settings!({
            description => text,
            omit_expression => true,
            prepend_module_to_snapshot => true,
        }, {
            insta::assert_snapshot!(format!("{prefix}{name}"), rendered);
        });
    }
}

#[test]
fn diagnostics_render_as_snapshotted() {
    check_snapshots(data_dir(), &xvt_scope(), "", |name, diags| {
        if let Some(code) = name.split('_').next().filter(|c| !c.starts_with("multi")) {
            assert_eq!(
                diags[0].code.as_str(),
                code,
                "{name}: the first diagnostic is not the one the file is named after"
            );
        } else {
            assert!(diags.len() > 1, "{name}: a multi_ file must show several");
        }
    });
}

#[test]
fn unit_warnings_render_as_snapshotted() {
    check_snapshots(units_dir(), &EveryIdExists, "units_", |name, diags| {
        assert!(
            diags.iter().all(|d| d.code == Code::UnitMismatch),
            "{name}: {diags:?}"
        );
    });
}

/// Every checked-in snapshot belongs to an input file (a renamed or deleted input must
/// take its snapshot along).
#[test]
fn no_orphan_snapshots() {
    let units = inputs(units_dir());
    let stems: Vec<String> = (inputs(data_dir()).iter().map(|p| stem(p)))
        .chain(units.iter().map(|p| format!("units_{}", stem(p))))
        .collect();
    let Ok(dir) = std::fs::read_dir(snapshot_dir()) else {
        return;
    };
    for entry in dir {
        let path = entry.expect("directory entry").path();
        let file = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let Some(case) = file
            .strip_prefix("language__snapshots__")
            .and_then(|f| f.strip_suffix(".snap"))
        else {
            continue;
        };
        assert!(
            stems.iter().any(|s| s == case),
            "{file} has no input file in tests/data/diagnostics or tests/data/units"
        );
    }
}
