//! Where `--geometry` finds EXTERNAL meshes: an argument `GRAPHICS/ID=FILE`, or a TOML
//! file mapping many at once, paths relative to the TOML file:
//!
//! ```toml
//! [geometry]
//! "GRAPHICS/12" = "parts/link.stl"
//! "GRAPHICS/13" = "parts/crank.glb"
//! ```

use super::SceneError;
use std::path::{Path, PathBuf};

/// The EXTERNAL meshes one `--geometry` argument gives: `GRAPHICS/ID=FILE` (or
/// `ID=FILE`), or the path of a `.toml` map read with [`read_map`].
pub fn geometry_arg(arg: &str) -> Result<Vec<(u32, PathBuf)>, SceneError> {
    match arg.split_once('=') {
        Some((key, file)) => Ok(vec![(
            graphic_id(key.trim(), arg)?,
            PathBuf::from(file.trim()),
        )]),
        None if arg.to_ascii_lowercase().ends_with(".toml") => read_map(Path::new(arg)),
        None => Err(SceneError(format!(
            "--geometry {arg}: expected GRAPHICS/ID=FILE or a .toml file mapping them"
        ))),
    }
}

/// The `[geometry]` table of the TOML file `path`, each path made relative to the
/// file's directory.
pub fn read_map(path: &Path) -> Result<Vec<(u32, PathBuf)>, SceneError> {
    let fail = |why: String| SceneError(format!("{}: {why}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| fail(e.to_string()))?;
    let doc: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| fail(e.message().to_string()))?;
    let table = match doc.get("geometry") {
        Some(toml::Value::Table(t)) => t,
        Some(_) => return Err(fail("`geometry` is not a table".into())),
        None => return Err(fail("no [geometry] table".into())),
    };
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut out = Vec::new();
    for (key, value) in table {
        let id = graphic_id(key, &path.display().to_string())?;
        let Some(file) = value.as_str() else {
            return Err(fail(format!("`{key}` is not a file name (a string)")));
        };
        out.push((id, dir.join(file)));
    }
    Ok(out)
}

/// The id of `GRAPHICS/12` (or `12`); `whole` names the argument in the error.
fn graphic_id(key: &str, whole: &str) -> Result<u32, SceneError> {
    let digits = match key.split_once('/') {
        Some((kind, id)) if kind.trim().eq_ignore_ascii_case("GRAPHICS") => id,
        Some(_) => "",
        None => key,
    };
    digits.trim().parse().map_err(|_| {
        SceneError(format!(
            "{whole}: `{key}` names no graphic (write GRAPHICS/ID)"
        ))
    })
}
