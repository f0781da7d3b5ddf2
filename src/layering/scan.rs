//! Rust sources read as the architecture tests need them: comments and literals blanked
//! (every other character kept in place, so line numbers hold), `#[cfg(test)]` modules cut
//! out, the rest split into tokens with their lines, and every path a file writes (`use`
//! trees expanded, paths in code) listed with the line it stands on.

/// `src` with comments and string and character literals blanked out, every other
/// character kept in place (so braces still balance and line numbers still hold).
pub fn code_only(src: &str) -> String {
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

/// `code` with its `#[cfg(test)] mod name { … }` blocks blanked (lines kept), and the
/// names of the modules declared `#[cfg(test)] mod name;` (files that are tests).
pub fn without_tests(code: &str) -> (String, Vec<String>) {
    let mut out = code.to_string();
    let mut test_files = Vec::new();
    let mut from = 0;
    while let Some(found) = code[from..].find("#[cfg(test)]") {
        let at = from + found;
        let after = at + "#[cfg(test)]".len();
        from = after;
        // Other attributes (`#[path = …]`) may come between.
        let mut decl = code[after..].trim_start();
        while decl.starts_with("#[") {
            decl = decl[decl.find(']').map_or(decl.len(), |k| k + 1)..].trim_start();
        }
        let decl = decl
            .trim_start_matches("pub(crate) ")
            .trim_start_matches("pub(super) ")
            .trim_start_matches("pub ");
        let Some(item) = decl.strip_prefix("mod ") else {
            continue;
        };
        let name: String = item
            .chars()
            .take_while(|ch| ch.is_alphanumeric() || *ch == '_')
            .collect();
        let body = item[name.len()..].trim_start();
        let body_at = code.len() - body.len();
        if body.starts_with(';') {
            test_files.push(name);
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
        let blanked: String = code[at..body_at + end]
            .chars()
            .map(|ch| if ch == '\n' { '\n' } else { ' ' })
            .collect();
        out.replace_range(at..body_at + end, &blanked);
        from = body_at + end;
    }
    (out, test_files)
}

/// A token of code that [`code_only`] has cleaned.
#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    Ident(String),
    /// `::`
    Path,
    Punct(char),
}

/// The tokens of `code`, each with its line (1-based).
pub fn tokens(code: &str) -> Vec<(Tok, usize)> {
    let c: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut line = 1;
    let mut i = 0;
    while i < c.len() {
        if c[i].is_alphabetic() || c[i] == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push((Tok::Ident(c[start..i].iter().collect()), line));
        } else if c[i] == ':' && c.get(i + 1) == Some(&':') {
            out.push((Tok::Path, line));
            i += 2;
        } else {
            if c[i] == '\n' {
                line += 1;
            } else if !c[i].is_whitespace() {
                out.push((Tok::Punct(c[i]), line));
            }
            i += 1;
        }
    }
    out
}

/// A path a file writes: its segments as written, the line, and the name it binds when
/// it is a `use` (the last segment, or the alias after `as`).
#[derive(Clone, Debug, PartialEq)]
pub struct WrittenPath {
    pub segments: Vec<String>,
    pub line: usize,
    pub binds: Option<String>,
}

/// Every path `code` writes: each leaf of each `use` tree (with the name it binds), and
/// each path in code that starts with `crate`, `super`, `self` or one of `roots`.
pub fn written_paths(code: &str, roots: &[&str]) -> Vec<WrittenPath> {
    let toks = tokens(code);
    let ident = |k: usize| match toks.get(k) {
        Some((Tok::Ident(s), _)) => Some(s.as_str()),
        _ => None,
    };
    let is = |k: usize, t: &Tok| toks.get(k).map(|(x, _)| x) == Some(t);
    let mut out = Vec::new();
    let mut k = 0;
    while k < toks.len() {
        let preceded_by_path = k > 0 && is(k - 1, &Tok::Path);
        if ident(k) == Some("use") && !preceded_by_path {
            let line = toks[k].1;
            let mut at = k + 1;
            if is(at, &Tok::Path) {
                at += 1; // `use ::x` names an external crate
            }
            use_tree(&toks, &mut at, Vec::new(), line, &mut out);
            k = at.max(k + 1);
            continue;
        }
        let head = ident(k).filter(|h| {
            !preceded_by_path
                && is(k + 1, &Tok::Path)
                && (["crate", "super", "self"].contains(h) || roots.contains(h))
        });
        if let Some(head) = head {
            let line = toks[k].1;
            let mut segments = vec![head.to_string()];
            let mut at = k + 1;
            while is(at, &Tok::Path) {
                match ident(at + 1) {
                    Some(name) => segments.push(name.to_string()),
                    None => break,
                }
                at += 2;
            }
            out.push(WrittenPath {
                segments,
                line,
                binds: None,
            });
            k = at;
            continue;
        }
        k += 1;
    }
    out
}

/// Reads the `use` tree at `*at` (below `prefix`) up to its end, pushing every leaf.
fn use_tree(
    toks: &[(Tok, usize)],
    at: &mut usize,
    prefix: Vec<String>,
    line: usize,
    out: &mut Vec<WrittenPath>,
) {
    let mut path = prefix;
    loop {
        match toks.get(*at).map(|(t, _)| t) {
            Some(Tok::Ident(name)) => {
                path.push(name.clone());
                *at += 1;
                if let Some((Tok::Path, _)) = toks.get(*at) {
                    *at += 1;
                    continue;
                }
                let mut binds = path.last().cloned();
                if let Some((Tok::Ident(kw), _)) = toks.get(*at) {
                    if kw == "as" {
                        binds = match toks.get(*at + 1) {
                            Some((Tok::Ident(alias), _)) => Some(alias.clone()),
                            _ => None,
                        };
                        *at += 2;
                    }
                }
                if binds.as_deref() == Some("self") {
                    path.pop();
                    binds = path.last().cloned();
                }
                out.push(WrittenPath {
                    segments: path,
                    line,
                    binds,
                });
                return;
            }
            Some(Tok::Punct('*')) => {
                *at += 1;
                out.push(WrittenPath {
                    segments: path,
                    line,
                    binds: None,
                });
                return;
            }
            Some(Tok::Punct('{')) => {
                *at += 1;
                loop {
                    match toks.get(*at).map(|(t, _)| t) {
                        Some(Tok::Punct('}')) => {
                            *at += 1;
                            return;
                        }
                        Some(Tok::Punct(',')) => *at += 1,
                        None => return,
                        _ => {
                            let before = *at;
                            use_tree(toks, at, path.clone(), line, out);
                            if *at == before {
                                *at += 1;
                            }
                        }
                    }
                }
            }
            _ => return,
        }
    }
}

#[test]
fn use_trees_and_paths_are_read_with_their_lines() {
    let code = code_only(
        "use super::{a::B, c::{self, D as E}, f::*};\n\
         // use crate::hidden;\n\
         fn g() { crate::mbd::x::y(); let s = \"super::z\"; mbfx::jit::F }\n",
    );
    let found: Vec<(String, usize, Option<String>)> = written_paths(&code, &["mbfx"])
        .into_iter()
        .map(|p| (p.segments.join("::"), p.line, p.binds))
        .collect();
    let some = |s: &str| Some(s.to_string());
    assert_eq!(
        found,
        [
            ("super::a::B".to_string(), 1, some("B")),
            ("super::c".to_string(), 1, some("c")),
            ("super::c::D".to_string(), 1, some("E")),
            ("super::f".to_string(), 1, None),
            ("crate::mbd::x::y".to_string(), 3, None),
            ("mbfx::jit::F".to_string(), 3, None),
        ]
    );
}

#[test]
fn test_modules_are_cut_out_with_their_lines_kept() {
    let (code, files) =
        without_tests("a #[cfg(test)] mod t { use super::x; { } } b\n#[cfg(test)]\nmod tests;\nc");
    assert_eq!(files, ["tests"]);
    assert!(!code.contains("super::x") && code.contains('a') && code.contains('c'));
    assert_eq!(code.lines().count(), 4);
}
