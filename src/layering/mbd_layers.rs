//! The layers of the core, as the module doc of [`crate::mbd`] lists them, enforced on the
//! sources: every file of `src/mbd` refers only to modules of its own layer or of lower
//! ones, the files inside `mbd::dynamics` likewise to their own sublayer (as the module
//! doc of `dynamics` lists them) or lower ones, and no two files of `src/mbd` refer to
//! each other through a circle, except a parent module and its own child.

use super::graph::{Crate, ModPath};

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
            "normal",
            "redundancy",
            "sparse",
        ],
    ),
    ("system", &["measure_set", "rows", "system"]),
    ("measures", &["measures", "output_slot"]),
    (
        "constraints and forces",
        &["constraints", "contacts", "forces", "fused_rows", "states"],
    ),
    ("build", &["assembly", "build", "pipeline", "planar"]),
    ("dynamics", &["dynamics"]),
    (
        "analyses",
        &["freedom", "kinematics", "linear", "rewind", "statics"],
    ),
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|(_, ms)| ms.contains(&module))
}

fn below_mbd(m: &ModPath) -> Option<&[String]> {
    m.split_first()
        .filter(|(head, _)| *head == "mbd")
        .map(|(_, rest)| rest)
}

/// The numbered items of a module doc (`//! 1. name: `a`, `b``, continued on lines
/// indented by four), each as (the item's text, the names it puts in backticks).
fn doc_items(src: &str) -> Vec<(String, Vec<String>)> {
    let doc: Vec<&str> = src
        .lines()
        .take_while(|l| l.starts_with("//!"))
        .map(|l| l.trim_start_matches("//!"))
        .collect();
    let mut out = Vec::new();
    for n in 1.. {
        let head = format!(" {n}. ");
        let Some(start) = doc.iter().position(|l| l.starts_with(&head)) else {
            break;
        };
        let item: String = std::iter::once(doc[start])
            .chain(
                doc[start + 1..]
                    .iter()
                    .copied()
                    .take_while(|l| l.starts_with("    ")),
            )
            .collect();
        let names = item
            .split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect();
        out.push((item, names));
    }
    out
}

fn read(path: &str) -> String {
    std::fs::read_to_string(super::graph::repo().join(path)).unwrap()
}

#[test]
fn every_module_has_one_layer() {
    let c = Crate::read();
    let mut modules: Vec<&String> = c
        .files
        .keys()
        .filter_map(|m| below_mbd(m).and_then(|r| r.first()))
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
    let c = Crate::read();
    let mut wrong = Vec::new();
    for (from, edges) in &c.edges {
        // The root wires every layer; a module without one fails above.
        let Some(own) = below_mbd(from)
            .and_then(|r| r.first())
            .and_then(|m| layer_of(m))
        else {
            continue;
        };
        for e in edges {
            let Some(to) = below_mbd(&e.to).and_then(|r| r.first()) else {
                continue;
            };
            match layer_of(to) {
                Some(l) if l <= own => {}
                Some(l) => wrong.push(format!(
                    "{} ({} refers to {to}, {})",
                    c.quote(from, e),
                    LAYERS[own].0,
                    LAYERS[l].0
                )),
                None => wrong.push(format!("{} (refers to {to}, no layer)", c.quote(from, e))),
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
    let items = doc_items(&read("src/mbd/mod.rs"));
    assert_eq!(items.len(), LAYERS.len(), "the mbd doc's numbered layers");
    for (n, ((layer, modules), (item, listed))) in LAYERS.iter().zip(&items).enumerate() {
        assert!(
            item.to_lowercase().contains(layer),
            "item {}: {item}",
            n + 1
        );
        let mut listed = listed.clone();
        let mut want: Vec<String> = modules.iter().map(|m| m.to_string()).collect();
        listed.sort();
        want.sort();
        assert_eq!(listed, want, "the mbd doc's layer {}, {layer}", n + 1);
    }
}

/// Inside `dynamics`, the sublayers its module doc numbers: every module of the folder in
/// exactly one, and each file refers only to its own sublayer and lower ones.
#[test]
fn dynamics_files_refer_only_to_their_sublayer_and_below() {
    let items = doc_items(&read("src/mbd/dynamics/mod.rs"));
    assert!(items.len() > 1, "the dynamics doc numbers no sublayers");
    let sublayer_of = |m: &str| items.iter().position(|(_, ms)| ms.iter().any(|x| x == m));
    let c = Crate::read();
    let inside = |m: &ModPath| -> Option<String> {
        match below_mbd(m)? {
            [d, child, ..] if d == "dynamics" => Some(child.clone()),
            _ => None,
        }
    };
    let mut wrong = Vec::new();
    for (from, edges) in &c.edges {
        let Some(child) = inside(from) else {
            continue;
        };
        let Some(own) = sublayer_of(&child) else {
            wrong.push(format!(
                "src/mbd/dynamics/{child} is in no sublayer of the dynamics doc"
            ));
            continue;
        };
        for e in edges {
            let Some(to) = inside(&e.to).filter(|to| *to != child) else {
                continue;
            };
            match sublayer_of(&to) {
                Some(l) if l <= own => {}
                _ => wrong.push(format!(
                    "{} (sublayer {} refers to {to}, sublayer {})",
                    c.quote(from, e),
                    own + 1,
                    sublayer_of(&to).map_or("none".to_string(), |l| (l + 1).to_string())
                )),
            }
        }
    }
    wrong.sort();
    wrong.dedup();
    assert!(
        wrong.is_empty(),
        "a sublayer of dynamics may refer only to itself and lower ones:\n{}",
        wrong.join("\n")
    );
}

/// No import circle in `src/mbd` of more than two files; two only where a parent module
/// and its own child share types.
#[test]
fn no_import_circles_in_the_core() {
    let c = Crate::read();
    let mut wrong = Vec::new();
    for circle in c.circles(|m| below_mbd(m).is_some()) {
        let parent_and_child = circle.len() == 2 && {
            let (a, b) = (&circle[0], &circle[1]);
            let (short, long) = if a.len() < b.len() { (a, b) } else { (b, a) };
            long.len() == short.len() + 1 && long.starts_with(short)
        };
        if parent_and_child {
            continue;
        }
        let mut lines = vec![format!("a circle of {} files:", circle.len())];
        for from in &circle {
            for e in c.edges[from].iter().filter(|e| circle.contains(&e.to)) {
                let quoted = format!("  {}", c.quote(from, e));
                if !lines.contains(&quoted) {
                    lines.push(quoted);
                }
            }
        }
        wrong.push(lines.join("\n"));
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
