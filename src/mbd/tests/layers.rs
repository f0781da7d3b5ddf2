//! The layers of the core, as the module doc of [`crate::mbd`] lists them, enforced on the
//! sources: every file of `src/mbd` refers only to modules of its own layer or of lower
//! ones. A reference is a path in code (`crate::mbd::x`, `super::x` resolved to the
//! module it names, a name the root re-exports to the module that defines it); comments,
//! literals and `#[cfg(test)]` modules do not count, since a test may build a whole system.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The layers, lowest first, with their top-level modules of `src/mbd`.
const LAYERS: &[(&str, &[&str])] = &[
    (
        "vocabulary",
        &[
            "compiled",
            "dense",
            "dual",
            "equations",
            "error",
            "expr",
            "handles",
            "inertia",
            "normal",
            "redundancy",
            "sparse",
        ],
    ),
    ("system", &["measure_set", "rows", "system"]),
    ("measures", &["measures", "output_slot"]),
    (
        "constraints and forces",
        &["constraints", "forces", "fused_rows"],
    ),
    ("build", &["assembly", "build", "planar"]),
    (
        "dynamics",
        &[
            "dynamics",
            "freedom",
            "kinematics",
            "linear",
            "rewind",
            "statics",
        ],
    ),
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|(_, ms)| ms.contains(&module))
}

fn mbd_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src/mbd")
}

/// `src` with comments and string and character literals blanked out, every other
/// character kept in place (so braces still balance and line numbers still hold).
fn code_only(src: &str) -> String {
    let c: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(src.len());
    let blank = |out: &mut String, ch: char| out.push(if ch == '\n' { '\n' } else { ' ' });
    let mut i = 0;
    while i < c.len() {
        let next = c.get(i + 1).copied();
        if c[i] == '/' && next == Some('/') {
            while i < c.len() && c[i] != '\n' {
                blank(&mut out, c[i]);
                i += 1;
            }
        } else if c[i] == '/' && next == Some('*') {
            let mut depth = 0;
            loop {
                if i + 1 < c.len() && c[i] == '/' && c[i + 1] == '*' {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if i + 1 < c.len() && c[i] == '*' && c[i + 1] == '/' {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else if i < c.len() {
                    blank(&mut out, c[i]);
                    i += 1;
                } else {
                    break;
                }
            }
        } else if c[i] == 'r' && matches!(next, Some('#' | '"')) && !ident_char(&c, i) {
            // A raw string r#"…"#: ends at a quote followed by as many hashes.
            let mut j = i + 1;
            while c.get(j) == Some(&'#') {
                j += 1;
            }
            if c.get(j) != Some(&'"') {
                out.push(c[i]);
                i += 1;
                continue;
            }
            let hashes = j - i - 1;
            let mut end = j + 1;
            while end < c.len()
                && !(c[end] == '"' && (1..=hashes).all(|h| c.get(end + h) == Some(&'#')))
            {
                end += 1;
            }
            let end = (end + 1 + hashes).min(c.len());
            c[i..end].iter().for_each(|&ch| blank(&mut out, ch));
            i = end;
        } else if c[i] == '"' {
            blank(&mut out, c[i]);
            i += 1;
            while i < c.len() && c[i] != '"' {
                let step = if c[i] == '\\' { 2 } else { 1 };
                c[i..(i + step).min(c.len())]
                    .iter()
                    .for_each(|&ch| blank(&mut out, ch));
                i += step;
            }
            if i < c.len() {
                blank(&mut out, c[i]);
                i += 1;
            }
        } else if c[i] == '\'' && is_char_literal(&c[i..]) {
            // 'x', or '\n', '\'', '\u{…}': the closing quote after the escaped character.
            let from = if c[i + 1] == '\\' { i + 3 } else { i + 2 };
            let end = from
                + c[from.min(c.len())..]
                    .iter()
                    .position(|&ch| ch == '\'')
                    .unwrap_or(0)
                + 1;
            c[i..end.min(c.len())]
                .iter()
                .for_each(|&ch| blank(&mut out, ch));
            i = end;
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

/// Whether the character before `i` continues an identifier (so `r` at `i` is not a
/// raw-string prefix).
fn ident_char(c: &[char], i: usize) -> bool {
    i > 0 && (c[i - 1].is_alphanumeric() || c[i - 1] == '_')
}

/// `'x'` or `'\n'` (a character literal) rather than a lifetime `'a`.
fn is_char_literal(c: &[char]) -> bool {
    match c.get(1) {
        Some('\\') => true,
        Some(_) => c.get(2) == Some(&'\''),
        None => false,
    }
}

#[derive(Debug, PartialEq)]
enum Tok {
    Ident(String),
    Path,
    Punct(char),
}

fn tokens(code: &str) -> Vec<Tok> {
    let c: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        if c[i].is_alphabetic() || c[i] == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push(Tok::Ident(c[start..i].iter().collect()));
        } else if c[i] == ':' && c.get(i + 1) == Some(&':') {
            out.push(Tok::Path);
            i += 2;
        } else {
            if !c[i].is_whitespace() {
                out.push(Tok::Punct(c[i]));
            }
            i += 1;
        }
    }
    out
}

/// `code` without its `#[cfg(test)] mod name { … }` blocks, and the names of the modules
/// declared `#[cfg(test)] mod name;` (files that are tests).
fn without_tests(code: &str) -> (String, Vec<String>) {
    let (mut out, mut test_files) = (String::new(), Vec::new());
    let mut rest = code;
    while let Some(at) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..at]);
        let after = &rest[at + "#[cfg(test)]".len()..];
        // Other attributes (`#[path = …]`) may come between.
        let mut decl = after.trim_start();
        while decl.starts_with("#[") {
            decl = decl[decl.find(']').map_or(decl.len(), |k| k + 1)..].trim_start();
        }
        let decl = decl
            .trim_start_matches("pub(crate) ")
            .trim_start_matches("pub ");
        let Some(item) = decl.strip_prefix("mod ") else {
            rest = after;
            continue;
        };
        let name: String = item
            .chars()
            .take_while(|ch| ch.is_alphanumeric() || *ch == '_')
            .collect();
        let body = item[name.len()..].trim_start();
        let skipped = code.len() - body.len();
        if body.starts_with(';') {
            test_files.push(name);
            rest = &code[skipped + 1..];
            continue;
        }
        let mut depth = 0;
        let mut end = body.len();
        for (k, ch) in body.char_indices() {
            depth += match ch {
                '{' => 1,
                '}' => -1,
                _ => 0,
            };
            if depth == 0 && ch == '}' {
                end = k + 1;
                break;
            }
        }
        rest = &code[skipped + end..];
    }
    out.push_str(rest);
    (out, test_files)
}

/// A file of `src/mbd` and its module path below `mbd`.
struct Source {
    path: PathBuf,
    module: Vec<String>,
    code: String,
}

/// Every library file of `src/mbd` (files that are `#[cfg(test)]` modules left out).
fn sources() -> Vec<Source> {
    let mut out = Vec::new();
    let mut dirs = vec![(mbd_dir(), Vec::<String>::new())];
    while let Some((dir, module)) = dirs.pop() {
        // The file that declares the directory's modules (`#[cfg(test)] mod tests;`).
        let owner = match dir.with_extension("rs") {
            file if !module.is_empty() && file.exists() => file,
            _ => dir.join("mod.rs"),
        };
        let tests = match std::fs::read_to_string(&owner) {
            Ok(src) => without_tests(&code_only(&src)).1,
            Err(_) => Vec::new(),
        };
        let mut entries: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for path in entries {
            let stem = path.file_stem().unwrap().to_string_lossy().to_string();
            if tests.contains(&stem) {
                continue;
            }
            let mut sub = module.clone();
            if path.is_dir() {
                sub.push(stem);
                dirs.push((path, sub));
            } else if path.extension().is_some_and(|e| e == "rs") {
                if stem != "mod" {
                    sub.push(stem);
                }
                let src = std::fs::read_to_string(&path).unwrap();
                let code = without_tests(&code_only(&src)).0;
                out.push(Source {
                    path,
                    module: sub,
                    code,
                });
            }
        }
    }
    out
}

/// The top-level modules of `src/mbd` that `code`, in module `here`, refers to;
/// `exports` maps a name the root re-exports to its module. A name that is neither
/// comes back as it is (and so has no layer).
fn referred(code: &str, here: &[String], exports: &HashMap<String, String>) -> Vec<String> {
    let toks = tokens(code);
    let ident = |k: usize| match toks.get(k) {
        Some(Tok::Ident(s)) => Some(s.as_str()),
        _ => None,
    };
    let mut out = Vec::new();
    let mut k = 0;
    while k < toks.len() {
        let preceded_by_path = k > 0 && toks[k - 1] == Tok::Path;
        // The head: crate::mbd::, or super:: (repeated), resolved to a module path.
        let (mut base, mut at) = match ident(k) {
            Some("crate")
                if !preceded_by_path
                    && toks.get(k + 1) == Some(&Tok::Path)
                    && ident(k + 2) == Some("mbd")
                    && toks.get(k + 3) == Some(&Tok::Path) =>
            {
                (Vec::new(), k + 4)
            }
            Some("super") if !preceded_by_path && toks.get(k + 1) == Some(&Tok::Path) => {
                let mut base = here.to_vec();
                let mut at = k;
                while ident(at) == Some("super") && toks.get(at + 1) == Some(&Tok::Path) {
                    base.pop();
                    at += 2;
                }
                (base, at)
            }
            _ => {
                k += 1;
                continue;
            }
        };
        // Below the root, the first segment is the module; at the root, the next name.
        let mut names = Vec::new();
        if base.is_empty() {
            if let Some(name) = ident(at) {
                names.push(name.to_string());
            } else if toks.get(at) == Some(&Tok::Punct('{')) {
                let mut depth = 0;
                let mut first = true;
                while at < toks.len() {
                    match &toks[at] {
                        Tok::Punct('{') => {
                            depth += 1;
                            first = depth == 1;
                        }
                        Tok::Punct('}') => {
                            depth -= 1;
                            if depth == 0 {
                                break;
                            }
                        }
                        Tok::Punct(',') if depth == 1 => first = true,
                        Tok::Ident(s) if first && depth == 1 => {
                            if s != "self" {
                                names.push(s.clone());
                            }
                            first = false;
                        }
                        _ => {}
                    }
                    at += 1;
                }
            }
        } else {
            names.push(base.remove(0));
        }
        for name in names {
            out.push(exports.get(&name).cloned().unwrap_or(name));
        }
        k = at.max(k + 1);
    }
    out
}

/// The names `src/mbd/mod.rs` re-exports (`pub use module::{…}`), each to its module.
fn root_exports() -> HashMap<String, String> {
    let src = std::fs::read_to_string(mbd_dir().join("mod.rs")).unwrap();
    let mut out = HashMap::new();
    for line in code_only(&src).lines() {
        let Some(path) = line.trim().strip_prefix("pub use ") else {
            continue;
        };
        let (module, names) = path.split_once("::").unwrap();
        for name in names.split(|ch: char| !(ch.is_alphanumeric() || ch == '_')) {
            if !name.is_empty() {
                out.insert(name.to_string(), module.to_string());
            }
        }
    }
    out
}

#[test]
fn every_module_has_one_layer() {
    let mut modules: Vec<String> = sources()
        .into_iter()
        .filter_map(|s| s.module.first().cloned())
        .collect();
    modules.sort();
    modules.dedup();
    for m in &modules {
        assert!(
            layer_of(m).is_some(),
            "src/mbd/{m} has no layer: add it to the module doc of mbd and to LAYERS here"
        );
    }
    for (layer, ms) in LAYERS {
        for m in *ms {
            assert!(modules.iter().any(|x| x == m), "{layer}: no module {m}");
        }
    }
    let all: Vec<&str> = LAYERS
        .iter()
        .flat_map(|(_, ms)| ms.iter().copied())
        .collect();
    for m in &all {
        assert_eq!(
            all.iter().filter(|x| *x == m).count(),
            1,
            "{m} in two layers"
        );
    }
}

#[test]
fn files_refer_only_to_their_layer_and_below() {
    let exports = root_exports();
    let mut wrong = Vec::new();
    for s in sources() {
        let Some(own) = s.module.first().and_then(|m| layer_of(m)) else {
            continue; // the root wires every layer; a module without one fails above
        };
        let mut refs = referred(&s.code, &s.module, &exports);
        refs.sort();
        refs.dedup();
        for r in refs {
            let file = s.path.strip_prefix(mbd_dir()).unwrap().display();
            match layer_of(&r) {
                Some(l) if l <= own => {}
                Some(l) => wrong.push(format!(
                    "{file} ({}) refers to {r} ({})",
                    LAYERS[own].0, LAYERS[l].0
                )),
                None => wrong.push(format!("{file} refers to {r}, which has no layer")),
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "a layer of mbd may refer only to itself and lower layers:\n{}",
        wrong.join("\n")
    );
}

/// The module doc of `mbd` numbers the layers as here, each with its modules in
/// backticks on its item's lines.
#[test]
fn the_module_doc_lists_the_layers() {
    let src = std::fs::read_to_string(mbd_dir().join("mod.rs")).unwrap();
    let doc: Vec<&str> = src
        .lines()
        .take_while(|l| l.starts_with("//!"))
        .map(|l| l.trim_start_matches("//!"))
        .collect();
    for (n, (layer, modules)) in LAYERS.iter().enumerate() {
        let head = format!(" {}. ", n + 1);
        let start = doc
            .iter()
            .position(|l| l.starts_with(&head))
            .unwrap_or_else(|| panic!("the mbd doc has no item {} ({layer})", n + 1));
        let item: String = std::iter::once(doc[start])
            .chain(
                doc[start + 1..]
                    .iter()
                    .copied()
                    .take_while(|l| l.starts_with("    ")),
            )
            .collect();
        assert!(
            item.to_lowercase().contains(layer),
            "item {}: {item}",
            n + 1
        );
        let mut listed: Vec<&str> = item.split('`').skip(1).step_by(2).collect();
        let mut want = modules.to_vec();
        listed.sort();
        want.sort();
        assert_eq!(listed, want, "the mbd doc's layer {}, {layer}", n + 1);
    }
}

#[test]
fn paths_resolve_to_modules() {
    let exports = HashMap::from([("System".to_string(), "system".to_string())]);
    let here = vec!["dynamics".to_string(), "outputs".to_string()];
    let code = code_only(
        "use super::Dynamics; // super::nothing\n\
         use crate::mbd::{rows::Row, System, self};\n\
         let s = \"super::forces\"; pub(super) fn f() {}\n\
         use super::super::measures::M;\n",
    );
    assert_eq!(
        referred(&code, &here, &exports),
        ["dynamics", "rows", "system", "measures"]
    );
    let (code, files) =
        without_tests("a #[cfg(test)] mod t { use super::x; { } } b\n#[cfg(test)]\nmod tests;\nc");
    assert_eq!(files, ["tests"]);
    assert!(!code.contains("super::x") && code.contains('a') && code.contains('c'));
}
