//! `mbfx fmu`: a dataset exported as an FMI 2.0 co-simulation FMU. The dataset is read
//! and its interface chosen ([`interface`]: PINPUT/POUTPUT, or the VARIABLEs named),
//! with the units the checker infers ([`units`]); [`description`] writes the
//! `modelDescription.xml` and [`package`] the zip, with the slave library (crate
//! `mbfx-fmi` in `fmu/`, built beside the `mbfx` executable) and, in `resources/`, the
//! dataset and the settings the library runs it with
//! ([`crate::session::fmu_settings`]). The library steps the dataset through
//! [`crate::session`]'s stepping API; nothing here runs it.

pub mod description;
pub mod interface;
pub mod package;
pub mod units;

use crate::diag::{Diagnostic, SourceFile};
use crate::model::read_model;
use crate::session::fmu_settings::{
    input_name, FmuSettings, FmuVariable, DATASET_FILE, FORMAT, SETTINGS_FILE,
};
use crate::session::stepping::Stepping;
use package::Entry;
use std::path::{Path, PathBuf};

/// The environment variable that names the slave library when it is not beside `mbfx`.
pub const LIBRARY_VARIABLE: &str = "MBFX_FMI_LIBRARY";

/// The slave library's file name as cargo builds it.
pub const LIBRARY_FILE: &str = "libmbfx_fmi.so";

/// What `mbfx fmu` is asked.
#[derive(Clone, Debug, Default)]
pub struct ExportRequest {
    /// The dataset (.adm).
    pub dataset: PathBuf,
    /// The input VARIABLEs (None: the dataset's PINPUT).
    pub inputs: Option<Vec<String>>,
    /// The output VARIABLEs (None: the dataset's POUTPUT).
    pub outputs: Option<Vec<String>>,
    /// The FMU to write.
    pub destination: PathBuf,
    /// The slave library to put in the FMU.
    pub library: PathBuf,
    /// The integrator, as `mbfx run --integrator` spells it.
    pub integrator: Option<String>,
    /// ERROR.
    pub error: Option<f64>,
    /// DefaultExperiment's stop time.
    pub end: Option<f64>,
    /// DefaultExperiment's step size.
    pub output_step: Option<f64>,
}

/// Why no FMU was written.
pub enum ExportError {
    /// The dataset cannot be read, or has errors: its diagnostics, to render against it.
    Dataset(Box<DatasetErrors>),
    /// Anything else, in words: an unknown name, no library, a file not written.
    Message(String),
}

impl From<String> for ExportError {
    fn from(s: String) -> ExportError {
        ExportError::Message(s)
    }
}

/// A dataset's errors, with its text to render them against.
pub struct DatasetErrors {
    /// The dataset, for rendering.
    pub source: SourceFile,
    /// What is wrong, at its place.
    pub diagnostics: Vec<Diagnostic>,
}

/// What was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Exported {
    /// The settings the FMU carries (its variables, GUID, identifier).
    pub settings: FmuSettings,
}

/// Writes the FMU `request` asks for.
pub fn export(request: &ExportRequest) -> Result<Exported, ExportError> {
    let (text, _) = crate::session::files::read_dataset(&request.dataset).map_err(|u| {
        ExportError::Dataset(Box::new(DatasetErrors {
            source: u.source,
            diagnostics: vec![u.diagnostic],
        }))
    })?;
    let read = read_model(&text);
    if read.has_errors() {
        return Err(ExportError::Dataset(Box::new(DatasetErrors {
            source: SourceFile::new(request.dataset.display().to_string(), text),
            diagnostics: read
                .diagnostics
                .into_iter()
                .filter(Diagnostic::is_error)
                .collect(),
        })));
    }
    let interface = interface::resolve(
        &read,
        &text,
        request.inputs.as_deref(),
        request.outputs.as_deref(),
    )?;
    let library = std::fs::read(&request.library).map_err(|e| {
        format!(
            "cannot read the FMU's library {}: {e}; build it with `cargo build --release -p \
             mbfx-fmi`, or name it with {LIBRARY_VARIABLE}",
            request.library.display()
        )
    })?;
    let identifier = model_identifier(&request.destination);
    let mut settings = FmuSettings {
        format: FORMAT,
        guid: String::new(),
        model_identifier: identifier.clone(),
        integrator: request.integrator.clone(),
        error: request.error,
        variables: interface
            .inputs
            .iter()
            .map(|p| (p, true))
            .chain(interface.outputs.iter().map(|p| (p, false)))
            .enumerate()
            .map(|(reference, (p, input))| FmuVariable {
                name: p.name.clone(),
                reference: reference as u32,
                input,
                variable: p.variable,
                start: p.start,
            })
            .collect(),
    };
    runs(&settings, &request.dataset, &text)?;
    settings.guid = guid(&[text.as_bytes(), settings.to_text().as_bytes()]);
    let title = read.model.title.trim();
    let header = description::Header {
        model_name: if title.is_empty() { &identifier } else { title },
        model_identifier: &identifier,
        guid: &settings.guid,
        stop_time: request.end,
        step_size: request.output_step,
        tolerance: request.error,
    };
    let xml = description::model_description(&header, &interface, &read.model.units);
    let entries = [
        entry("modelDescription.xml", xml.into_bytes(), false),
        entry(&format!("binaries/linux64/{identifier}.so"), library, true),
        entry(
            &format!("resources/{DATASET_FILE}"),
            text.into_bytes(),
            false,
        ),
        entry(
            &format!("resources/{SETTINGS_FILE}"),
            settings.to_text().into_bytes(),
            false,
        ),
    ];
    package::write_fmu(&request.destination, &entries)?;
    Ok(Exported { settings })
}

/// Whether the FMU will start: the dataset builds and assembles for stepping under the
/// settings, and each input is a design variable the stepping can set (one that a MOTION
/// or GCON reads, or that nothing reads, is refused), so that a fault is told here and
/// not by an importer's first call.
fn runs(settings: &FmuSettings, dataset: &Path, text: &str) -> Result<(), String> {
    let name = dataset.display().to_string();
    let request = settings.request(&name, text, None)?;
    let mut stepping = Stepping::new(&request)
        .map_err(|f| format!("the dataset does not start stepping: {}", f.cause))?;
    for v in settings.inputs() {
        stepping
            .set_input(&input_name(v), v.start)
            .map_err(|e| format!("input {} cannot be set: {e}", v.name))?;
    }
    Ok(())
}

fn entry(path: &str, bytes: Vec<u8>, executable: bool) -> Entry {
    Entry {
        path: path.to_string(),
        bytes,
        executable,
    }
}

/// The FMI model identifier for an FMU written to `destination`: its file stem made a C
/// identifier (the standard's rule: it names the library and prefixes its functions).
pub fn model_identifier(destination: &Path) -> String {
    let stem = destination
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut id: String = stem
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if !id.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        id.insert(0, '_');
    }
    id
}

/// A GUID made from `parts` (two 64-bit FNV-1a hashes): the same dataset and settings
/// give the same GUID, so exporting twice gives the same file.
fn guid(parts: &[&[u8]]) -> String {
    let fnv = |offset: u64| {
        let mut h = offset;
        for p in parts {
            for &b in *p {
                h ^= u64::from(b);
                h = h.wrapping_mul(0x0100_0000_01b3);
            }
            // Separates the parts, so that moving a byte between them changes the GUID.
            h = (h ^ 0xff).wrapping_mul(0x0100_0000_01b3);
        }
        h
    };
    let (a, b) = (fnv(0xcbf2_9ce4_8422_2325), fnv(0x6c62_272e_07bb_0142));
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_identifier_is_a_c_name_made_from_the_file_stem() {
        assert_eq!(model_identifier(Path::new("out/plant.fmu")), "plant");
        assert_eq!(model_identifier(Path::new("my-plant 2.fmu")), "my_plant_2");
        assert_eq!(model_identifier(Path::new("2dof.fmu")), "_2dof");
    }

    #[test]
    fn the_guid_has_the_guid_layout_and_follows_its_parts() {
        let g = guid(&[b"a", b"b"]);
        assert_eq!(g.len(), 38, "{g}");
        assert_eq!(g.matches('-').count(), 4, "{g}");
        assert_eq!(g, guid(&[b"a", b"b"]));
        assert_ne!(g, guid(&[b"ab", b""]));
    }
}
