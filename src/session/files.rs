//! Input files as text: an expression file must be UTF-8; a dataset is read as UTF-8 with
//! any other byte taken as Latin-1 and a warning ([`crate::model::decode`]). A file that
//! cannot be read is an [`Unreadable`] carrying the diagnostic that says why, ready to be
//! rendered by whoever asked for the file (`mbfx check`, `mbfx run`, `eval --model`, the
//! REPL's `:load`).

use crate::diag::{Code, Diagnostic, SourceFile};
use std::path::Path;

/// A file that could not be read as text, with the diagnostic that says why.
pub struct Unreadable {
    /// The file (its text as far as it could be read), for rendering the diagnostic.
    pub source: SourceFile,
    /// Why the file could not be read.
    pub diagnostic: Diagnostic,
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, Box<Unreadable>> {
    let name = path.display().to_string();
    std::fs::read(path).map_err(|e| {
        Box::new(Unreadable {
            diagnostic: Diagnostic::error(Code::Io, 0..0, format!("cannot read {name}: {e}")),
            source: SourceFile::textless(name.clone()),
        })
    })
}

/// Reads an expression file as UTF-8 text, or explains why it cannot be read.
pub fn read_text(path: &Path) -> Result<String, Box<Unreadable>> {
    let bytes = read_bytes(path)?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let lossy = String::from_utf8_lossy(e.as_bytes()).into_owned();
        Box::new(Unreadable {
            source: SourceFile::new(path.display().to_string(), lossy),
            diagnostic: Diagnostic::error(
                Code::Encoding,
                at..at + 1,
                "the file is not valid UTF-8 text",
            )
            .with_help("expressions are ASCII text"),
        })
    })
}

/// Reads a dataset: bytes that are not UTF-8 are read as Latin-1 with a warning (some
/// generated `.adm` files carry Latin-1 comments), which comes back beside the text.
pub fn read_dataset(path: &Path) -> Result<(String, Vec<Diagnostic>), Box<Unreadable>> {
    let bytes = read_bytes(path)?;
    let (text, warning) = crate::model::decode(&bytes);
    Ok((text.into_owned(), warning.into_iter().collect()))
}
