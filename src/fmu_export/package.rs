//! The FMU file: a zip with `modelDescription.xml` at its root, the slave library in
//! `binaries/linux64/<modelIdentifier>.so` and the dataset and its settings in
//! `resources/`. It is written to a temporary file beside the destination and renamed
//! over it only once complete, so a failure leaves no half-written FMU behind.

use std::fs::File;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipWriter};

/// One file of the FMU: its path inside the zip and its bytes.
pub struct Entry {
    /// The path inside the zip (`resources/model.adm`).
    pub path: String,
    /// The contents.
    pub bytes: Vec<u8>,
    /// Whether it is executable (the shared library).
    pub executable: bool,
}

/// Writes `entries` as the zip file `destination`; the error names the file.
pub fn write_fmu(destination: &Path, entries: &[Entry]) -> Result<(), String> {
    let shown = destination.display();
    let temporary = temporary_beside(destination);
    let written = File::create(&temporary)
        .and_then(|file| write_zip(file, entries))
        .and_then(|()| std::fs::rename(&temporary, destination));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        format!("cannot write {shown}: {e}")
    })
}

/// A file name beside `destination` that no other writer uses (the process id).
fn temporary_beside(destination: &Path) -> PathBuf {
    let name = destination
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "fmu".into());
    destination.with_file_name(format!(".{name}.{}.partial", std::process::id()))
}

fn write_zip(file: File, entries: &[Entry]) -> io::Result<()> {
    let mut zip = ZipWriter::new(io::BufWriter::new(file));
    for e in entries {
        let options = SimpleFileOptions::default()
            .compression_method(CompressionMethod::Deflated)
            .unix_permissions(if e.executable { 0o755 } else { 0o644 });
        zip.start_file(e.path.as_str(), options)
            .map_err(io::Error::other)?;
        zip.write_all(&e.bytes)?;
    }
    let mut out = zip.finish().map_err(io::Error::other)?;
    out.flush()?;
    out.into_inner().map_err(|e| e.into_error())?.sync_all()
}
