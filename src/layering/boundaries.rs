//! The crate's two doors, enforced on the sources: the dataset layer (`src/model`) knows
//! nothing of the multibody core it feeds, and the Python and C crates reach the library
//! through `mbfx::session` (and the diagnostics of `mbfx::diag`) alone, so no shell holds
//! logic another would have to copy. The animation's layers (`scene`, `gltf`, `viewer`)
//! read downwards only.

use super::graph::{repo, rust_files, Crate};
use super::scan::{code_only, without_tests, written_paths};
use std::path::Path;

#[test]
fn the_model_never_refers_to_the_core() {
    let c = Crate::read();
    let mut wrong = Vec::new();
    for (from, edges) in c
        .edges
        .iter()
        .filter(|(m, _)| m.first().is_some_and(|s| s == "model"))
    {
        for e in edges
            .iter()
            .filter(|e| e.to.first().is_some_and(|s| s == "mbd"))
        {
            wrong.push(c.quote(from, e));
        }
    }
    assert!(
        wrong.is_empty(),
        "src/model reads datasets and must not import src/mbd:\n{}",
        wrong.join("\n")
    );
}

/// What the animation's layers may read: the scene is drawn from the model alone, the
/// glTF writer from the scene, and the page from nothing of the crate; the session
/// records the poses and hands them down.
const DRAWING: [(&str, &[&str]); 4] = [
    ("scene", &["model", "vocab"]),
    ("collide", &["model", "vocab", "diag"]),
    ("gltf", &["scene"]),
    ("viewer", &[]),
];

#[test]
fn the_drawing_layers_read_the_model_and_nothing_above_it() {
    let c = Crate::read();
    let mut wrong = Vec::new();
    for (module, allowed) in DRAWING {
        for (from, edges) in c
            .edges
            .iter()
            .filter(|(m, _)| m.first().is_some_and(|s| s == module))
        {
            for e in edges.iter().filter(|e| {
                e.to.first()
                    .is_some_and(|s| s != module && !allowed.contains(&s.as_str()))
            }) {
                wrong.push(c.quote(from, e));
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "src/scene reads only the model, src/gltf only the scene, src/viewer nothing:\n{}",
        wrong.join("\n")
    );
}

/// The modules of `mbfx` a shell may name.
const DOORS: [&str; 2] = ["session", "diag"];

#[test]
fn the_python_and_c_crates_go_through_session_alone() {
    let mut wrong = Vec::new();
    for dir in ["python/src", "capi/src", "fmu/src"] {
        for rel in rust_files(Path::new(dir)) {
            let text = std::fs::read_to_string(repo().join(&rel)).unwrap();
            let (code, _) = without_tests(&code_only(&text));
            for w in written_paths(&code, &["mbfx"]) {
                let through = match w.segments.as_slice() {
                    [head, module, ..] if head == "mbfx" => DOORS.contains(&module.as_str()),
                    [head] if head == "mbfx" => false,
                    _ => true,
                };
                if !through {
                    let line = text.lines().nth(w.line - 1).unwrap_or("").trim();
                    wrong.push(format!("{}:{}: {line}", rel.display(), w.line));
                }
            }
        }
    }
    wrong.dedup();
    assert!(
        wrong.is_empty(),
        "the Python, C and FMU crates may name only mbfx::session and mbfx::diag:\n{}",
        wrong.join("\n")
    );
}
