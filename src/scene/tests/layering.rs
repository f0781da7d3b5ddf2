//! The scene reads the model alone: its code names only `crate::model`, `crate::vocab`
//! and itself (not the core, `src/mbd`, nor the writers that read the scene). Doc
//! comments may mention the writers.

use std::path::Path;

#[test]
fn the_scene_imports_only_the_model_and_the_vocabulary() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/scene");
    let mut wrong = Vec::new();
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).expect("src/scene") {
        let path = entry.expect("an entry").path();
        if path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        files += 1;
        let text = std::fs::read_to_string(&path).expect("a source file");
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for (at, _) in code.match_indices("crate::") {
                let module: String = (code[at + 7..].chars())
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !["model", "vocab", "scene"].contains(&module.as_str()) {
                    wrong.push(format!("{}:{}: {}", path.display(), n + 1, line.trim()));
                }
            }
        }
    }
    assert!(files >= 10, "only {files} files read");
    assert!(
        wrong.is_empty(),
        "src/scene may import only crate::model and crate::vocab:\n{}",
        wrong.join("\n")
    );
}
