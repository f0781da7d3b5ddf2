//! The corpus census: a .glb from a short run (one 1 ms step; `--end` must be positive)
//! of every corpus dataset with GRAPHICS that `mbfx run` accepts, each clean under the
//! Khronos validator; printed per dataset, the GRAPHICS kinds it writes (read from the
//! dataset's text, not from the code under test), the items drawn by role and the
//! placeholders, read back from the .glb. A dataset `mbfx run` refuses (a USER routine, an
//! error in the dataset) gets the .glb of its scene at the input poses, with no frames,
//! written through the library: what is drawn does not depend on the run.

use crate::validator::validate;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "../common/mod.rs"]
#[allow(dead_code)]
mod common;

const KINDS: [&str; 13] = [
    "BOX",
    "CYLINDER",
    "FRUSTUM",
    "ELLIPSOID",
    "CIRCLE",
    "ARC",
    "OUTLINE",
    "SPDP",
    "FORCE",
    "CURVE",
    "EXTERNAL",
    "TORUS",
    "POINT",
];

/// GRAPHICS kinds in `text` (statements joined across continuation lines), counted.
fn kinds(text: &str) -> BTreeMap<String, usize> {
    let mut statements: Vec<String> = Vec::new();
    for line in text.lines() {
        let line = line.split('!').next().unwrap_or("");
        if line.trim_start().starts_with(',') {
            if let Some(last) = statements.last_mut() {
                last.push_str(line);
            }
        } else {
            statements.push(line.to_string());
        }
    }
    let mut out = BTreeMap::new();
    for s in statements
        .iter()
        .filter(|s| s.trim_start().to_ascii_uppercase().starts_with("GRAPHICS/"))
    {
        let upper = s.to_ascii_uppercase();
        let kind = (upper.split([',', ' ', '\t']))
            .map(str::trim)
            .find(|t| KINDS.contains(t))
            .unwrap_or("?");
        *out.entry(kind.to_string()).or_insert(0) += 1;
    }
    out
}

/// Items by role in a .glb (its nodes' extras).
fn roles(glb: &[u8]) -> BTreeMap<String, usize> {
    let doc = gltf::Gltf::from_slice(glb).expect("the gltf crate reads it");
    let mut out = BTreeMap::new();
    for n in doc.nodes() {
        if let Some(e) = n.extras() {
            let v: serde_json::Value = serde_json::from_str(e.get()).expect("JSON extras");
            if let Some(role) = v["mbfx"]["role"].as_str() {
                *out.entry(role.to_string()).or_insert(0) += 1;
            }
        }
    }
    out
}

#[test]
fn every_corpus_dataset_with_graphics_animates_validator_clean() {
    let corpus = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/adams");
    assert!(corpus.is_dir(), "the shared corpus at {}", corpus.display());
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("animate-census");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    let mut written: Vec<(PathBuf, PathBuf, BTreeMap<String, usize>)> = Vec::new();
    let mut refused = Vec::new();
    let mut with_graphics = 0;
    for (k, adm) in common::adm_files(&corpus).iter().enumerate() {
        let text = String::from_utf8_lossy(&std::fs::read(adm).expect("readable")).into_owned();
        let kinds = kinds(&text);
        if kinds.is_empty() {
            continue;
        }
        with_graphics += 1;
        let glb = dir.join(format!("{k:03}.glb"));
        let out = Command::new(env!("CARGO_BIN_EXE_mbfx"))
            .args(["run"])
            .arg(adm)
            .args(["--end", "1e-3", "--output-step", "1e-3", "--csv"])
            .arg(dir.join("rows.csv"))
            .arg("--animate")
            .arg(&glb)
            .output()
            .expect("mbfx runs");
        match glb.exists() {
            true => written.push((adm.clone(), glb, kinds)),
            false => {
                let err = String::from_utf8_lossy(&out.stderr);
                let why = err
                    .lines()
                    .find(|l| l.contains("Error"))
                    .unwrap_or("")
                    .to_string();
                let bytes = std::fs::read(adm).expect("readable");
                let read = mbfx::model::read_model(&mbfx::model::decode(&bytes).0);
                let scene = mbfx::scene::build(&read.model, &mbfx::scene::Options::default())
                    .expect("a scene at the input poses");
                let frames = mbfx::scene::Frames::default();
                std::fs::write(&glb, mbfx::gltf::glb(&scene, &frames)).expect("written");
                written.push((adm.clone(), glb, kinds));
                refused.push((adm.clone(), why));
            }
        }
    }
    let rel = |p: &Path| p.strip_prefix(&corpus).unwrap_or(p).display().to_string();
    let files: Vec<&Path> = written.iter().map(|(_, g, _)| g.as_path()).collect();
    let reports = validate(&files);
    let mut failures = Vec::new();
    println!("dataset | GRAPHICS kinds | items by role | errors");
    for ((adm, glb, kinds), report) in written.iter().zip(&reports) {
        let roles = roles(&std::fs::read(glb).unwrap());
        println!("{} | {kinds:?} | {roles:?} | {}", rel(adm), report.errors);
        if report.errors > 0 {
            failures.push(format!("{}: {:?}", rel(adm), report.messages));
        }
    }
    for (adm, why) in &refused {
        println!(
            "{} | not run (its scene at the input poses): {why}",
            rel(adm)
        );
    }
    println!(
        "{with_graphics} datasets with GRAPHICS: {} .glb files, {} of them animated, {} \
         the scene at its input poses (not accepted by mbfx run)",
        written.len(),
        written.len() - refused.len(),
        refused.len()
    );
    assert!(failures.is_empty(), "validator errors: {failures:#?}");
    assert_eq!(written.len(), with_graphics, "a .glb for every dataset");
    assert!(refused.len() * 4 < with_graphics, "most datasets animate");
}
