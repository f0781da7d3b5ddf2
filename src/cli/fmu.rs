//! `mbfx fmu MODEL.adm --inputs u --outputs y -o plant.fmu`: the command line's shell over
//! [`crate::fmu_export::export`], which writes the dataset as an FMI 2.0 co-simulation
//! FMU. This module turns the arguments into an [`ExportRequest`], finds the slave library
//! (`libmbfx_fmi.so` beside the `mbfx` executable, or where `MBFX_FMI_LIBRARY` says), and
//! prints what was written, or the diagnostics and exit 1 (docs/fmu.md).

use super::output::{Output, Stop};
use super::run::IntegratorArg;
use crate::fmu_export::{export, ExportError, ExportRequest, LIBRARY_FILE, LIBRARY_VARIABLE};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct FmuArgs {
    /// The dataset (.adm).
    model: PathBuf,
    /// The input VARIABLEs, by adams_view_name, VARIABLE/id or id, comma-separated
    /// [default: the dataset's PINPUT].
    #[arg(long, value_delimiter = ',', value_name = "NAMES")]
    inputs: Option<Vec<String>>,
    /// The output VARIABLEs, likewise [default: the dataset's POUTPUT].
    #[arg(long, value_delimiter = ',', value_name = "NAMES")]
    outputs: Option<Vec<String>>,
    /// The FMU to write (its file stem is the FMI model identifier).
    #[arg(short = 'o', long = "output", value_name = "FILE.fmu")]
    output: PathBuf,
    /// The integrator the FMU runs [default: the dataset's INTEGRATOR, else gstiff].
    #[arg(long, value_enum)]
    integrator: Option<IntegratorArg>,
    /// ERROR the FMU runs with [default: the dataset's, else 1e-3]; an importer's
    /// tolerance (fmi2SetupExperiment) takes its place.
    #[arg(long)]
    error: Option<f64>,
    /// The stop time of the FMU's DefaultExperiment.
    #[arg(long)]
    end: Option<f64>,
    /// The communication step of the FMU's DefaultExperiment.
    #[arg(long = "output-step", value_name = "DT")]
    output_step: Option<f64>,
}

/// Writes the FMU `a` asks for.
pub fn run(a: &FmuArgs, o: &mut Output<'_>) -> Result<i32, Stop> {
    for (flag, value) in [
        ("--error", a.error),
        ("--end", a.end),
        ("--output-step", a.output_step),
    ] {
        if let Some(v) = value.filter(|v| !(v.is_finite() && *v > 0.0)) {
            writeln!(
                o.err(),
                "error: mbfx fmu: {flag} {v} must be a positive number"
            )?;
            return Err(Stop::Failed);
        }
    }
    let Some(library) = library() else {
        writeln!(
            o.err(),
            "error: mbfx fmu: cannot find {LIBRARY_FILE} beside the mbfx executable\n  = help: \
             build it with `cargo build --release -p mbfx-fmi`, or set {LIBRARY_VARIABLE} to its path"
        )?;
        return Err(Stop::Failed);
    };
    let request = ExportRequest {
        dataset: a.model.clone(),
        inputs: a.inputs.clone(),
        outputs: a.outputs.clone(),
        destination: a.output.clone(),
        library,
        integrator: a.integrator.map(|m| {
            clap::ValueEnum::to_possible_value(&m)
                .map(|v| v.get_name().to_string())
                .unwrap_or_default()
        }),
        error: a.error,
        end: a.end,
        output_step: a.output_step,
    };
    match export(&request) {
        Ok(done) => {
            let names = |input: bool| {
                let v: Vec<&str> = done
                    .settings
                    .variables
                    .iter()
                    .filter(|v| v.input == input)
                    .map(|v| v.name.as_str())
                    .collect();
                if v.is_empty() {
                    "none".to_string()
                } else {
                    v.join(", ")
                }
            };
            writeln!(
                o.err(),
                "wrote {} (FMI 2.0 co-simulation, model identifier {}): inputs {}; outputs {}",
                a.output.display(),
                done.settings.model_identifier,
                names(true),
                names(false)
            )?;
            Ok(0)
        }
        Err(ExportError::Dataset(e)) => {
            o.diagnostics(&e.diagnostics, &e.source)?;
            writeln!(
                o.err(),
                "error: mbfx fmu: {} has errors: no FMU written",
                e.source.name
            )?;
            Err(Stop::Failed)
        }
        Err(ExportError::Message(m)) => {
            writeln!(o.err(), "error: mbfx fmu: {m}")?;
            Err(Stop::Failed)
        }
    }
}

/// The slave library: `MBFX_FMI_LIBRARY`, else `libmbfx_fmi.so` beside this executable.
fn library() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os(LIBRARY_VARIABLE) {
        return Some(PathBuf::from(p));
    }
    let exe = std::env::current_exe().ok()?;
    let beside = exe.parent()?.join(LIBRARY_FILE);
    beside.is_file().then_some(beside)
}
