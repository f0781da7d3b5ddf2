//! What the integration-test binaries (and, through `#[path]`, the model's unit tests)
//! share: the `.adm` (and `.acf`) files of the shared corpus.

use std::path::{Path, PathBuf};

/// Every `.adm` file below `dir`, sorted.
pub fn adm_files(dir: &Path) -> Vec<PathBuf> {
    files_with_extension(dir, "adm")
}

/// Every file below `dir` whose extension is `ext` (any case), sorted.
pub fn files_with_extension(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let entries = std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display()));
        for e in entries {
            let path = e.expect("directory entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path
                .extension()
                .is_some_and(|x| x.eq_ignore_ascii_case(ext))
            {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}
