//! The Khronos glTF validator (npm `gltf-validator`, pinned in tests/node) run by node
//! on .glb files: its error count per file. Missing packages fail the test with the
//! command that installs them; nothing is skipped.

use std::path::{Path, PathBuf};
use std::process::Command;

/// One file's report: errors, warnings, and the first error messages.
#[derive(Debug)]
pub struct Report {
    pub file: String,
    pub errors: u64,
    #[allow(dead_code)] // Shown by the Debug of a failing report.
    pub warnings: u64,
    pub messages: Vec<String>,
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The validator's report on each of `files`.
pub fn validate(files: &[&Path]) -> Vec<Report> {
    let modules = root().join("tests/node/node_modules");
    assert!(
        modules.join("gltf-validator").is_dir(),
        "the glTF validator is not installed: run `npm ci --prefix tests/node` (needs node and npm)"
    );
    let out = Command::new("node")
        .arg(root().join("tests/animate/validate.js"))
        .args(files)
        .env("NODE_PATH", &modules)
        .output()
        .expect("node runs (install Node 20: the glTF validator needs it)");
    assert!(
        out.status.success(),
        "the validator failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).expect("utf-8");
    let reports: Vec<Report> = text
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).expect("a JSON line");
            Report {
                file: v["file"].as_str().unwrap_or_default().to_string(),
                errors: v["errors"].as_u64().expect("errors"),
                warnings: v["warnings"].as_u64().expect("warnings"),
                messages: (v["messages"].as_array().expect("messages").iter())
                    .map(|m| m.as_str().unwrap_or_default().to_string())
                    .collect(),
            }
        })
        .collect();
    assert_eq!(reports.len(), files.len(), "one report per file: {text}");
    reports
}
