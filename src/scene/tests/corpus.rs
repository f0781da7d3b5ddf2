//! The corpus census: every dataset of `shared/corpus/adams` drawn, the kinds and
//! placeholders of each printed, and the totals checked against a plain text scan of
//! the files (GRAPHICS statements up to each file's first END, by kind word).

use crate::model::{decode, read_model};
use crate::scene::{build, Options, Role};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.adm` file below `dir`, sorted. (The model's tests load the shared lister of
/// tests/common as a module already; clippy refuses a second copy.)
fn adm_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display())) {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path
                .extension()
                .is_some_and(|x| x.eq_ignore_ascii_case("adm"))
            {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The kinds that become `Role::Graphic` items (CURVE is not drawn, EXTERNAL without a
/// mesh is a placeholder, FORCE an arrow).
const DRAWN: [&str; 8] = [
    "BOX",
    "CYLINDER",
    "FRUSTUM",
    "ELLIPSOID",
    "CIRCLE",
    "ARC",
    "OUTLINE",
    "SPDP",
];
/// The other kinds the scan recognises.
const OTHERS: [&str; 3] = ["FORCE", "CURVE", "EXTERNAL"];

/// GRAPHICS statements per kind in `text`, by scanning lines: a statement starts at a
/// line `GRAPHICS/…` and continues on lines starting with `,`; its kind is its first
/// comma-separated word that names one (`OUTLINE = …` for an outline). Comments after
/// `!` are dropped; the dataset ends at the first line `END`.
fn scan(text: &str) -> BTreeMap<&'static str, usize> {
    let mut statements: Vec<String> = Vec::new();
    let mut open = false;
    for line in text.lines() {
        let line = line.split('!').next().unwrap_or("").trim();
        if line.eq_ignore_ascii_case("END") {
            break;
        }
        if line.starts_with(',') && open {
            statements.last_mut().expect("open").push_str(line);
        } else {
            open = line.to_ascii_uppercase().starts_with("GRAPHICS/");
            if open {
                statements.push(line.to_string());
            }
        }
    }
    let mut counts = BTreeMap::new();
    for s in statements {
        let kind = s.split(',').skip(1).find_map(|w| {
            let word = w
                .split('=')
                .next()
                .unwrap_or("")
                .trim()
                .to_ascii_uppercase();
            DRAWN.iter().chain(&OTHERS).find(|k| **k == word)
        });
        if let Some(k) = kind {
            *counts.entry(*k).or_default() += 1;
        }
    }
    counts
}

#[test]
fn every_corpus_dataset_is_drawn_and_the_counts_match_a_text_scan() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/adams");
    let files = adm_files(&corpus);
    assert!(files.len() >= 70, "only {} files", files.len());
    let (mut scanned, mut graphic_ids, mut placeholders, mut arrows) = (BTreeMap::new(), 0, 0, 0);
    let mut with_graphics = 0;
    let mut notes = Vec::new();
    let mut vertices = 0;
    for path in &files {
        let text = decode(&std::fs::read(path).expect("corpus file"))
            .0
            .into_owned();
        let read = read_model(&text);
        let s = build(&read.model, &Options::default())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let counts = scan(&text);
        for (k, n) in &counts {
            *scanned.entry(*k).or_insert(0) += n;
        }
        with_graphics += usize::from(!counts.is_empty());
        let ids: BTreeSet<&str> = (s.items.iter())
            .filter(|i| i.role == Role::Graphic)
            .filter_map(|i| i.name.split(' ').next())
            .collect();
        let boxes = s
            .items
            .iter()
            .filter(|i| i.role == Role::Placeholder)
            .count();
        let arrow_items = s.items.iter().filter(|i| i.role == Role::Arrow).count();
        let glyph_items = s.items.iter().filter(|i| i.role == Role::Glyph).count();
        graphic_ids += ids.len();
        placeholders += boxes;
        arrows += arrow_items;
        assert!(s.extent > 0.0 && s.extent.is_finite(), "{}", path.display());
        let rel = path
            .strip_prefix(&corpus)
            .unwrap_or(path)
            .display()
            .to_string();
        println!(
            "{rel}: {counts:?}; {} graphics, {boxes} placeholders, {arrow_items} arrows, \
             {glyph_items} glyphs; extent {:.4}",
            ids.len(),
            s.extent
        );
        notes.extend(s.notes.iter().map(|n| format!("{rel}: {n}")));
        vertices += s.meshes.iter().map(|m| m.positions.len()).sum::<usize>();
    }
    println!("notes:\n{}", notes.join("\n"));
    println!("{vertices} vertices in all");
    let scanned_of = |k: &str| scanned.get(k).copied().unwrap_or(0);
    let drawable: usize = DRAWN.iter().map(|k| scanned_of(k)).sum();
    let not_drawn = |kinds: &[&str]| {
        (notes.iter())
            .filter(|n| {
                kinds
                    .iter()
                    .any(|k| n.contains(&format!("({k}) not drawn")))
            })
            .count()
    };
    assert_eq!(graphic_ids + not_drawn(&DRAWN), drawable, "{scanned:?}");
    assert_eq!(
        placeholders + not_drawn(&["EXTERNAL"]),
        scanned_of("EXTERNAL")
    );
    assert_eq!(arrows + not_drawn(&["FORCE"]), scanned_of("FORCE"));
    // What is left out: the CURVE (its data is not read) and the EXTERNAL on a
    // flexible body's marker in adams_vscode's test.adm (docs/models.md "GRAPHICS").
    assert_eq!(not_drawn(&DRAWN), 0, "{notes:#?}");
    assert_eq!(not_drawn(&["EXTERNAL", "FORCE"]), 1, "{notes:#?}");
    assert_eq!(with_graphics, 67, "datasets with GRAPHICS (issue 39)");
}
