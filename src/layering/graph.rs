//! The crate's files as a graph: each library file of `src/` (test modules left out) with
//! its module path, the paths it writes resolved to the file that defines what they name
//! (through the imports of the module they pass, so a re-export leads to its source),
//! and the strongly connected components of that graph (Tarjan).

use super::scan::{code_only, without_tests, written_paths, WrittenPath};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// A module path below the crate root (`["mbd", "dynamics", "setup"]`).
pub type ModPath = Vec<String>;

/// One library file of the crate.
pub struct File {
    /// Relative to the repository (`src/mbd/system.rs`).
    pub path: PathBuf,
    /// The source as written, for quoting lines.
    pub text: String,
    /// The paths it writes.
    pub written: Vec<WrittenPath>,
}

/// A reference from one file to another, at the line that makes it.
#[derive(Clone, Debug)]
pub struct Edge {
    pub to: ModPath,
    pub line: usize,
}

/// The crate's files and what each refers to.
pub struct Crate {
    pub files: BTreeMap<ModPath, File>,
    /// Per file, the files it refers to (first line of each), itself left out.
    pub edges: BTreeMap<ModPath, Vec<Edge>>,
}

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every `.rs` file below `dir` (relative to the repository), sorted.
pub fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut dirs = vec![repo().join(dir)];
    while let Some(d) = dirs.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|e| e == "rs") {
                out.push(p.strip_prefix(repo()).unwrap().to_path_buf());
            }
        }
    }
    out.sort();
    out
}

/// The module path of `src/<file>` (`mod.rs` names its folder; `lib.rs` is the root).
fn module_of(rel: &Path) -> ModPath {
    let mut m: ModPath = rel
        .strip_prefix("src")
        .unwrap()
        .with_extension("")
        .iter()
        .map(|s| s.to_string_lossy().to_string())
        .collect();
    if m.last().is_some_and(|s| s == "mod" || s == "lib") {
        m.pop();
    }
    m
}

impl Crate {
    /// The library's files (`src/main.rs`, a crate of its own, left out).
    pub fn read() -> Crate {
        let mut cleaned = BTreeMap::new();
        let mut tests = BTreeSet::new();
        for rel in rust_files(Path::new("src")) {
            if rel == Path::new("src/main.rs") {
                continue;
            }
            let text = std::fs::read_to_string(repo().join(&rel)).unwrap();
            let (code, test_files) = without_tests(&code_only(&text));
            let module = module_of(&rel);
            for t in test_files {
                let mut m = module.clone();
                m.push(t);
                tests.insert(m);
            }
            cleaned.insert(module, (rel, text, code));
        }
        let is_test = |m: &ModPath| (1..=m.len()).any(|n| tests.contains(&m[..n]));
        let files: BTreeMap<ModPath, File> = cleaned
            .into_iter()
            .filter(|(m, _)| !is_test(m))
            .map(|(m, (path, text, code))| {
                let written = written_paths(&code, &[]);
                (
                    m,
                    File {
                        path,
                        text,
                        written,
                    },
                )
            })
            .collect();
        let mut c = Crate {
            files,
            edges: BTreeMap::new(),
        };
        let names = c.imported_names();
        let mut edges = BTreeMap::new();
        for (m, f) in &c.files {
            let mut out: Vec<Edge> = Vec::new();
            for w in &f.written {
                let Some(abs) = c.absolute(m, &w.segments) else {
                    continue;
                };
                let Some(to) = c.file_of(&abs, &names, 0) else {
                    continue;
                };
                if &to != m && !out.iter().any(|e| e.to == to) {
                    out.push(Edge { to, line: w.line });
                }
            }
            edges.insert(m.clone(), out);
        }
        c.edges = edges;
        c
    }

    /// `segments` as written in module `here`, made absolute; None for a path into
    /// another crate (or a name only a `use` brought in, whose `use` is its own path).
    fn absolute(&self, here: &ModPath, segments: &[String]) -> Option<ModPath> {
        let (first, rest) = segments.split_first()?;
        match first.as_str() {
            "crate" => Some(rest.to_vec()),
            "self" => Some(here.iter().chain(rest).cloned().collect()),
            "super" => {
                let mut base = here.clone();
                let mut s = segments;
                while s.first().is_some_and(|x| x == "super") {
                    base.pop()?;
                    s = &s[1..];
                }
                Some(base.into_iter().chain(s.iter().cloned()).collect())
            }
            _ => {
                let mut child = here.clone();
                child.push(first.clone());
                self.files
                    .contains_key(&child)
                    .then(|| here.iter().chain(segments).cloned().collect())
            }
        }
    }

    /// Per module, the names its `use` lines bind (visible to its children through
    /// `super::`, and to all through `pub use`), each to the absolute path it names.
    fn imported_names(&self) -> HashMap<ModPath, HashMap<String, ModPath>> {
        let mut out: HashMap<ModPath, HashMap<String, ModPath>> = HashMap::new();
        for (m, f) in &self.files {
            for w in &f.written {
                let (Some(name), Some(abs)) = (&w.binds, self.absolute(m, &w.segments)) else {
                    continue;
                };
                out.entry(m.clone()).or_default().insert(name.clone(), abs);
            }
        }
        out
    }

    /// The file that defines what absolute path `abs` names: its longest prefix that is
    /// a file, followed through that module's imports when the next segment is one.
    fn file_of(
        &self,
        abs: &[String],
        names: &HashMap<ModPath, HashMap<String, ModPath>>,
        depth: usize,
    ) -> Option<ModPath> {
        let n = (0..=abs.len())
            .rev()
            .find(|&n| self.files.contains_key(&abs[..n]))?;
        let module = abs[..n].to_vec();
        if let (Some(next), true) = (abs.get(n), depth < 16) {
            if let Some(target) = names.get(&module).and_then(|ns| ns.get(next)) {
                let mut via: ModPath = target.clone();
                via.extend(abs[n + 1..].iter().cloned());
                if let Some(f) = self.file_of(&via, names, depth + 1) {
                    return Some(f);
                }
            }
        }
        Some(module)
    }

    /// `file:line: the line` for an edge, to quote in a failure.
    pub fn quote(&self, from: &ModPath, e: &Edge) -> String {
        let f = &self.files[from];
        let text = f.text.lines().nth(e.line - 1).unwrap_or("").trim();
        format!("{}:{}: {text}", f.path.display(), e.line)
    }

    /// The strongly connected components of the files for which `keep` holds, with
    /// more than one file, largest first.
    pub fn circles(&self, keep: impl Fn(&ModPath) -> bool) -> Vec<Vec<ModPath>> {
        let nodes: Vec<&ModPath> = self.files.keys().filter(|m| keep(m)).collect();
        let index: HashMap<&ModPath, usize> =
            nodes.iter().enumerate().map(|(i, m)| (*m, i)).collect();
        let succ: Vec<Vec<usize>> = nodes
            .iter()
            .map(|m| {
                self.edges[*m]
                    .iter()
                    .filter_map(|e| index.get(&e.to).copied())
                    .collect()
            })
            .collect();
        let mut t = Tarjan {
            succ: &succ,
            index: vec![None; nodes.len()],
            low: vec![0; nodes.len()],
            stack: Vec::new(),
            on_stack: vec![false; nodes.len()],
            next: 0,
            out: Vec::new(),
        };
        for v in 0..nodes.len() {
            if t.index[v].is_none() {
                t.visit(v);
            }
        }
        let mut out: Vec<Vec<ModPath>> = t
            .out
            .into_iter()
            .filter(|c| c.len() > 1)
            .map(|c| {
                let mut c: Vec<ModPath> = c.into_iter().map(|i| nodes[i].clone()).collect();
                c.sort();
                c
            })
            .collect();
        out.sort_by_key(|c| std::cmp::Reverse(c.len()));
        out
    }
}

/// Tarjan's strongly connected components (recursive: the crate's depth is small).
struct Tarjan<'a> {
    succ: &'a [Vec<usize>],
    index: Vec<Option<usize>>,
    low: Vec<usize>,
    stack: Vec<usize>,
    on_stack: Vec<bool>,
    next: usize,
    out: Vec<Vec<usize>>,
}

impl Tarjan<'_> {
    fn visit(&mut self, v: usize) {
        self.index[v] = Some(self.next);
        self.low[v] = self.next;
        self.next += 1;
        self.stack.push(v);
        self.on_stack[v] = true;
        for &w in &self.succ[v] {
            match self.index[w] {
                None => {
                    self.visit(w);
                    self.low[v] = self.low[v].min(self.low[w]);
                }
                Some(iw) if self.on_stack[w] => self.low[v] = self.low[v].min(iw),
                Some(_) => {}
            }
        }
        if Some(self.low[v]) == self.index[v] {
            let mut comp = Vec::new();
            while let Some(w) = self.stack.pop() {
                self.on_stack[w] = false;
                comp.push(w);
                if w == v {
                    break;
                }
            }
            self.out.push(comp);
        }
    }
}
