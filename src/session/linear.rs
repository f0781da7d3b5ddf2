//! A run's linear analyses (LINEAR/EIGENSOL, LINEAR/STATEMAT, `mbfx run --linear`):
//! the model linearized where the run stands ([`crate::mbd::linear`]), its modes, the
//! table `mbfx run` prints, and the files FILE names, written when the analysis runs:
//!
//! - EIGENSOL: `FILE_modes.csv` (one row a mode: number, natural and damped frequency in
//!   Hz, damping ratio, the eigenvalue's real and imaginary parts, the coordinate that
//!   moves most) and, unless NOVECTOR, `FILE_shapes.csv` (one row per mode and
//!   coordinate of the model: the shape's real and imaginary parts, the dominant
//!   coordinate at 1), for the modes COORDS names;
//! - STATEMAT: `FILE.a`, the state matrix as plain text rows (MATLAB's `load`, NumPy's
//!   `loadtxt`), and `FILE.st`, its states one per line (each minimal coordinate, then
//!   each one's rate), as Adams' MATLAB format names them; with PINPUT and POUTPUT also
//!   `FILE.b`, `FILE.c`, `FILE.d` and the inputs' and outputs' names in `FILE.pi` and
//!   `FILE.po` ([`crate::mbd::linear::plant`]).

use super::plant::Plant;
use crate::mbd::dynamics::{DynError, Dynamics};
use crate::mbd::error::MbdError;
use crate::mbd::linear::plant::{inputs_outputs, InputsOutputs};
use crate::mbd::linear::{self, modes::Mode, Linearized};
use crate::model::linear_command::Linear;
use crate::vocab::math::DMat;
use std::fmt::Write as _;
use std::path::PathBuf;

/// One linear analysis done.
#[derive(Clone, Debug)]
pub struct LinearReport {
    /// What was asked.
    pub command: Linear,
    /// The linearized equations.
    pub linearized: Linearized,
    /// The modes, by rising frequency.
    pub modes: Vec<Mode>,
    /// The state matrix (STATEMAT).
    pub state_matrix: Option<DMat>,
    /// B, C and D, with the inputs' and outputs' names (STATEMAT with PINPUT or
    /// POUTPUT).
    pub plant: Option<(InputsOutputs, Vec<String>, Vec<String>)>,
    /// The files written.
    pub files: Vec<PathBuf>,
}

/// Runs the linear analysis `command` on `d` where it stands (its inputs and outputs
/// from `plant`) and writes its files.
pub fn analyse(
    d: &mut Dynamics,
    plant: &Plant,
    command: &Linear,
) -> Result<LinearReport, DynError> {
    let io = match command.pinput.is_some() || command.poutput.is_some() {
        true => Some(plant.resolve(command).map_err(MbdError::Plant)?),
        false => None,
    };
    let lin = linear::linearize(d, command.damping)?;
    let modes = linear::modes::modes(&lin, command.vectors)?;
    let state_matrix = match command.statemat {
        true => Some(lin.state_matrix()?),
        false => None,
    };
    let plant = match io {
        Some((inputs, outputs)) => {
            let m = inputs_outputs(&lin, d, &inputs, &outputs)?;
            let inputs = inputs.iter().map(|id| format!("VARIABLE/{id}")).collect();
            let outputs = outputs.iter().map(|o| o.name.clone()).collect();
            Some((m, inputs, outputs))
        }
        None => None,
    };
    let mut report = LinearReport {
        command: command.clone(),
        linearized: lin,
        modes,
        state_matrix,
        plant,
        files: Vec::new(),
    };
    if let Some(base) = &command.file {
        report.files =
            write_files(&report, &base.value).map_err(|e| DynError::Output(e.to_string()))?;
    }
    Ok(report)
}

/// Whether mode `number` is one COORDS asks the shape of.
fn wanted(command: &Linear, number: usize) -> bool {
    command
        .coords
        .is_none_or(|(first, last)| (first..=last).contains(&number))
}

fn write_files(r: &LinearReport, base: &str) -> std::io::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let mut put = |suffix: &str, text: String| -> std::io::Result<()> {
        let path = PathBuf::from(format!("{base}{suffix}"));
        if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        std::fs::write(&path, text)?;
        files.push(path);
        Ok(())
    };
    if let Some(a) = &r.state_matrix {
        put(".a", matrix_text(a))?;
        put(".st", lines(&r.linearized.state_names()))?;
        if let Some((m, inputs, outputs)) = &r.plant {
            put(".b", matrix_text(&m.b))?;
            put(".c", matrix_text(&m.c))?;
            put(".d", matrix_text(&m.d))?;
            put(".pi", lines(inputs))?;
            put(".po", lines(outputs))?;
        }
        return Ok(files);
    }
    let mut modes = String::from("mode,natural_hz,damped_hz,damping_ratio,real,imag,dominant\n");
    for m in &r.modes {
        let _ = writeln!(
            modes,
            "{},{:e},{:e},{:e},{:e},{:e},{}",
            m.number,
            m.natural_hz,
            m.damped_hz,
            m.damping_ratio,
            m.eigenvalue.re,
            m.eigenvalue.im,
            m.dominant
        );
    }
    put("_modes.csv", modes)?;
    if r.command.vectors {
        let mut shapes = String::from("mode,coordinate,real,imag\n");
        for m in r.modes.iter().filter(|m| wanted(&r.command, m.number)) {
            let Some(shape) = &m.shape else { continue };
            // The joints' own coordinates first, then every coordinate of the model.
            let joints = r
                .linearized
                .coords
                .iter()
                .zip(m.coordinates.iter().flatten());
            for (c, x) in joints.filter(|(c, _)| c.column.is_none()) {
                let _ = writeln!(shapes, "{},{},{:e},{:e}", m.number, c.name, x.re, x.im);
            }
            for (name, x) in r.linearized.columns.iter().zip(shape) {
                let _ = writeln!(shapes, "{},{name},{:e},{:e}", m.number, x.re, x.im);
            }
        }
        put("_shapes.csv", shapes)?;
    }
    Ok(files)
}

/// One name a line.
fn lines(names: &[String]) -> String {
    names.iter().map(|n| format!("{n}\n")).collect()
}

/// A matrix as rows of numbers separated by spaces, every digit kept.
fn matrix_text(a: &DMat) -> String {
    let mut out = String::new();
    for r in 0..a.nrows() {
        let row: Vec<String> = (0..a.ncols()).map(|c| format!("{:e}", a[(r, c)])).collect();
        out += &row.join(" ");
        out.push('\n');
    }
    out
}

impl LinearReport {
    /// The lines `mbfx run` prints: where, how many degrees of freedom, the modes table
    /// (or the state matrix's size), the files written.
    pub fn text(&self) -> String {
        let lin = &self.linearized;
        let mut out = format!(
            "linear analysis at time {}: {} degree(s) of freedom ({})\n",
            lin.time,
            lin.freedom(),
            lin.coords
                .iter()
                .map(|c| c.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        );
        if lin.moving {
            let (v, a) = lin.rest;
            out += &format!("note: the operating point is not at rest (largest velocity {v:.1e}/s, acceleration {a:.1e}/s², translations over the model length): the partials of the inertial terms (centripetal, gyroscopic, M(q)·a) are left out; linearize after SIMULATE/STATICS, with a tight EQUILIBRIUM/IMBALANCE, for exact modes\n");
        }
        if let Some(a) = &self.state_matrix {
            out += &format!("state matrix A: {0} × {0}\n", a.nrows());
            if let Some((m, inputs, outputs)) = &self.plant {
                out += &format!(
                    "B: {} × {} (inputs {}), C: {} × {} (outputs {}), D: {} × {}\n",
                    m.b.nrows(),
                    m.b.ncols(),
                    inputs.join(", "),
                    m.c.nrows(),
                    m.c.ncols(),
                    outputs.join(", "),
                    m.d.nrows(),
                    m.d.ncols()
                );
            }
        } else {
            out += &modes_table(&self.modes);
        }
        for f in &self.files {
            out += &format!("wrote {}\n", f.display());
        }
        out
    }
}

/// The modes as a table: number, frequencies, damping ratio, eigenvalue, dominant
/// coordinate.
pub fn modes_table(modes: &[Mode]) -> String {
    let mut out = format!(
        "{:>5} {:>16} {:>16} {:>13} {:>24} {:>24}  {}\n",
        "mode", "natural (Hz)", "damped (Hz)", "damping ratio", "real", "imaginary", "moves most"
    );
    for m in modes {
        let _ = writeln!(
            out,
            "{:>5} {:>16.9e} {:>16.9e} {:>13.6e} {:>24.15e} {:>24.15e}  {}",
            m.number,
            m.natural_hz,
            m.damped_hz,
            m.damping_ratio,
            m.eigenvalue.re,
            m.eigenvalue.im,
            m.dominant
        );
    }
    out
}
