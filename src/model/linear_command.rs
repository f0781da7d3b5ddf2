//! The LINEAR command of a command file: `LINEAR/EIGENSOL` (the modes about where the
//! run stands) or `LINEAR/STATEMAT` (the state matrices), with COORDS, NOVECTOR,
//! NODAMPIN, FILE and FORMAT, and for STATEMAT the plant's inputs and outputs (PINPUT,
//! POUTPUT: the ids of the dataset's PINPUT and POUTPUT statements, which give B, C and
//! D). The energy tables (ENERGY, KINETIC, …) are warned about as any argument nothing
//! reads.

use super::integrator_settings::Given;
use super::statement::ItemKind;
use super::stmt_args::Args;
use crate::diag::{Code, Span};

/// What a LINEAR command asks for.
#[derive(Clone, Debug, PartialEq)]
pub struct Linear {
    /// STATEMAT (the state matrix and its states) rather than EIGENSOL (the modes).
    pub statemat: bool,
    /// COORDS = first[, last]: the modes whose shapes are written, numbered from 1 by
    /// rising frequency (None: every mode's).
    pub coords: Option<(usize, usize)>,
    /// The mode shapes are computed (NOVECTOR not given).
    pub vectors: bool,
    /// Damping is kept (NODAMPIN not given).
    pub damping: bool,
    /// FILE: the base name of the files written (None: the modes are only printed).
    pub file: Option<Given<String>>,
    /// PINPUT = id: the dataset's PINPUT statement whose VARIABLEs are the inputs.
    pub pinput: Option<Given<u32>>,
    /// POUTPUT = id: the dataset's POUTPUT statement whose VARIABLEs are the outputs.
    pub poutput: Option<Given<u32>>,
    /// The command.
    pub span: Span,
}

impl Linear {
    /// LINEAR/EIGENSOL with every default: the modes with their shapes, damping kept,
    /// written to `file` when given (`mbfx run --linear`).
    pub fn eigensol(file: Option<String>) -> Linear {
        Linear {
            statemat: false,
            coords: None,
            vectors: true,
            damping: true,
            file: file.map(|value| Given { value, span: 0..0 }),
            pinput: None,
            poutput: None,
            span: 0..0,
        }
    }
}

/// The kinds of LINEAR, with their shortest abbreviations.
const KINDS: [(&str, usize); 2] = [("EIGENSOL", 3), ("STATEMAT", 3)];

/// Reads a LINEAR command's arguments (its errors go to `a`); None when it has errors.
pub fn read_linear(a: &mut Args) -> Option<Linear> {
    let kind = a.choice(&KINDS);
    let [pinput, poutput] =
        ["PINPUT", "POUTPUT"].map(|name| a.id(name, 3).map(|(value, span)| Given { value, span }));
    let coords = coords(a);
    let vectors = !a.flag("NOVECTOR", 3);
    let damping = !a.flag("NODAMPIN", 3);
    let file = a.find("FILE", 3).and_then(|arg| match arg.items() {
        [one] if matches!(one.kind, ItemKind::Word | ItemKind::Text | ItemKind::Quoted) => {
            Some(Given {
                value: one.text.clone(),
                span: one.span.clone(),
            })
        }
        _ => {
            let span = arg.span.clone();
            a.error(Code::BadArgument, span, "FILE takes one file name".into());
            None
        }
    });
    if let Some((format, span)) = a.word("FORMAT", 3) {
        if !format.eq_ignore_ascii_case("MATLAB") {
            a.error(
                Code::UnsupportedCommand,
                span,
                format!("FORMAT = {format}: mbfx writes the MATLAB format (plain text matrices NumPy reads too)"),
            );
        }
    }
    let Some(kind) = kind else {
        a.missing("EIGENSOL or STATEMAT");
        return None;
    };
    let statemat = KINDS[kind].0 == "STATEMAT";
    if statemat && file.is_none() {
        a.missing("FILE = name (the base name of the state-matrix files)");
    }
    if let Some(io) = pinput.as_ref().or(poutput.as_ref()).filter(|_| !statemat) {
        let span = io.span.clone();
        a.error(
            Code::BadArgument,
            span,
            "PINPUT and POUTPUT belong to LINEAR/STATEMAT (the B, C and D matrices)".into(),
        );
    }
    if a.diags.iter().any(|d| d.is_error()) {
        return None;
    }
    Some(Linear {
        statemat,
        coords,
        vectors,
        damping,
        file,
        pinput,
        poutput,
        span: a.stmt.span.clone(),
    })
}

/// COORDS = first[, last], whole numbers from 1, first ≤ last.
fn coords(a: &mut Args) -> Option<(usize, usize)> {
    let arg = a.find("COORDS", 3)?;
    let values = a.numbers_of(arg)?;
    let whole = |x: f64| x >= 1.0 && x.fract() == 0.0 && x < 1e9;
    let pair = match values.as_slice() {
        [x] if whole(*x) => Some((*x as usize, *x as usize)),
        [x, y] if whole(*x) && whole(*y) && x <= y => Some((*x as usize, *y as usize)),
        _ => None,
    };
    if pair.is_none() {
        let span = arg.span.clone();
        a.error(
            Code::BadArgument,
            span,
            "COORDS takes one or two mode numbers from 1, the first not above the second".into(),
        );
    }
    pair
}
