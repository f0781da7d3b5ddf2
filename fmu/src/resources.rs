//! The FMU's `resources/` folder, which the importer names by a URI in `fmi2Instantiate`
//! (`file:///tmp/unzipped/resources`, or `file:/...` as some tools write it): the
//! dataset and the settings `mbfx fmu` put there.

use mbfx::session::fmu_settings::{FmuSettings, DATASET_FILE, SETTINGS_FILE};
use std::path::PathBuf;

/// The folder a `file:` URI names (percent-escapes decoded).
pub fn folder(uri: &str) -> Result<PathBuf, String> {
    let rest = uri
        .strip_prefix("file://localhost/")
        .map(|r| format!("/{r}"))
        .or_else(|| uri.strip_prefix("file://").map(str::to_string))
        .or_else(|| uri.strip_prefix("file:").map(str::to_string))
        .ok_or_else(|| format!("fmuResourceLocation {uri:?} is not a file: URI"))?;
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (
            bytes[i],
            bytes.get(i + 1).copied(),
            bytes.get(i + 2).copied(),
        ) {
            (b'%', Some(h), Some(l)) if hex(h).is_some() && hex(l).is_some() => {
                out.push((hex(h).unwrap_or(0) * 16 + hex(l).unwrap_or(0)) as u8);
                i += 3;
            }
            (b, _, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    let path =
        String::from_utf8(out).map_err(|_| format!("fmuResourceLocation {uri:?} is not UTF-8"))?;
    Ok(PathBuf::from(path))
}

/// The settings and the dataset's text in the resources folder at `uri`.
pub fn read(uri: &str) -> Result<(FmuSettings, String), String> {
    let dir = folder(uri)?;
    let read = |name: &str| {
        std::fs::read_to_string(dir.join(name))
            .map_err(|e| format!("cannot read {}: {e}", dir.join(name).display()))
    };
    let settings = FmuSettings::parse(&read(SETTINGS_FILE)?)?;
    Ok((settings, read(DATASET_FILE)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uri_forms_importers_write_name_the_same_folder() {
        for uri in [
            "file:///tmp/a%20b/resources",
            "file:/tmp/a%20b/resources",
            "file://localhost/tmp/a%20b/resources",
        ] {
            assert_eq!(
                folder(uri),
                Ok(PathBuf::from("/tmp/a b/resources")),
                "{uri}"
            );
        }
        assert!(folder("/tmp/x").is_err());
    }
}
