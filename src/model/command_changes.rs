//! Command-file commands that change the model between SIMULATE commands, read into
//! [`ModelChange`]s for the run to apply ([`crate::session::changes`]):
//!
//! - `ACTIVATE/kind, ID = id` (or `RANGE = first, last`) and `DEACTIVATE/…` of the
//!   elements mbfx models (JOINT, JPRIM, GCON, MOTION, SFORCE, VFORCE, VTORQUE, GFORCE,
//!   SPRINGDAMPER, BUSHING); any other kind (SENSOR, CONTACT, …) is refused, naming it;
//! - `VARIABLE/id, FUNCTION = e`, `MOTION/id, FUNCTION = e`, `SFORCE/id, FUNCTION = e`
//!   and `VFORCE/VTORQUE/GFORCE/id, FX = e …`: new expressions for an element of the
//!   dataset; a MOTION may also change what its FUNCTION gives (DISPLACEMENT, VELOCITY,
//!   ACCELERATION) and its ICDISP and ICVEL; any other argument is refused at itself;
//! - `ACCGRAV/IGRAV = g, JGRAV = g, KGRAV = g`: the components given replace gravity's.
//!
//! The reader knows the command file alone: whether the ids exist, and whether the
//! expressions check against the dataset, is the run's to say (with spans into the
//! command file, which a [`NewFunction`] keeps).

use super::elements::{Id, MotionLevel};
use super::lines::Piece;
use super::statement::ArgValue;
use super::stmt_args::Args;
use crate::diag::{Code, Span};

/// The kinds of element a command file may switch or redefine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Element {
    /// JOINT.
    Joint,
    /// JPRIM.
    Jprim,
    /// GCON.
    Gcon,
    /// MOTION.
    Motion,
    /// SFORCE.
    Sforce,
    /// VFORCE.
    Vforce,
    /// VTORQUE.
    Vtorque,
    /// GFORCE.
    Gforce,
    /// SPRINGDAMPER.
    SpringDamper,
    /// BUSHING.
    Bushing,
    /// VARIABLE (redefined only: Adams does not switch VARIABLEs).
    Variable,
}

impl Element {
    /// The Adams statement name.
    pub fn name(self) -> &'static str {
        match self {
            Element::Joint => "JOINT",
            Element::Jprim => "JPRIM",
            Element::Gcon => "GCON",
            Element::Motion => "MOTION",
            Element::Sforce => "SFORCE",
            Element::Vforce => "VFORCE",
            Element::Vtorque => "VTORQUE",
            Element::Gforce => "GFORCE",
            Element::SpringDamper => "SPRINGDAMPER",
            Element::Bushing => "BUSHING",
            Element::Variable => "VARIABLE",
        }
    }

    /// Whether it holds constraint equations (switching it needs a new redundancy
    /// analysis and assembly).
    pub fn constrains(self) -> bool {
        matches!(
            self,
            Element::Joint | Element::Jprim | Element::Gcon | Element::Motion
        )
    }

    /// The kind a command's canonical name stands for.
    fn of_command(name: &str) -> Option<Element> {
        SWITCHABLE
            .iter()
            .chain([&Element::Variable])
            .copied()
            .find(|e| e.name() == name)
    }
}

/// The kinds ACTIVATE and DEACTIVATE take.
const SWITCHABLE: [Element; 10] = [
    Element::Joint,
    Element::Jprim,
    Element::Gcon,
    Element::Motion,
    Element::Sforce,
    Element::Vforce,
    Element::Vtorque,
    Element::Gforce,
    Element::SpringDamper,
    Element::Bushing,
];

/// Which elements an ACTIVATE or DEACTIVATE names.
#[derive(Clone, Debug, PartialEq)]
pub enum Ids {
    /// `ID = id`.
    One(Id),
    /// `RANGE = first, last`: every element of the kind with an id in between.
    Range(Id, Id),
}

/// A new expression for one argument of an element, as the command file writes it.
#[derive(Clone, Debug, PartialEq)]
pub struct NewFunction {
    /// The argument, canonical: FUNCTION, or FX FY FZ TX TY TZ.
    pub argument: &'static str,
    /// The expression's text: the command file's bytes from `start`, with the `&`,
    /// continuation commas and comments between its lines blanked (same length, so a
    /// diagnostic's span shifted by `start` points into the command file).
    pub text: String,
    /// Where the expression starts in the command file.
    pub start: usize,
}

/// What a model-changing command does.
#[derive(Clone, Debug, PartialEq)]
pub enum Change {
    /// ACTIVATE (`active`) or DEACTIVATE of elements of one kind.
    Switch {
        /// ACTIVATE rather than DEACTIVATE.
        active: bool,
        /// Their kind.
        kind: Element,
        /// Which ones.
        ids: Ids,
        /// Where the id or range is written.
        ids_span: Span,
    },
    /// New expressions for the element `kind`/`id`.
    Redefine {
        /// Its kind.
        kind: Element,
        /// Its id.
        id: Id,
        /// Where the id is written.
        id_span: Span,
        /// The expressions given.
        functions: Vec<NewFunction>,
        /// A MOTION's new drive settings (None: none given).
        drive: Option<MotionDrive>,
    },
    /// ACCGRAV: the components given (global x, y, z; model units).
    Gravity([Option<f64>; 3]),
}

/// What a MOTION command gives besides its FUNCTION: what the function drives and the
/// initial conditions of a VELOCITY or ACCELERATION motion (each None: as before).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MotionDrive {
    /// DISPLACEMENT, VELOCITY or ACCELERATION.
    pub level: Option<MotionLevel>,
    /// ICDISP.
    pub icdisp: Option<f64>,
    /// ICVEL.
    pub icvel: Option<f64>,
}

/// The flags of a MOTION's level, as the dataset reader takes them.
const LEVELS: [(&str, usize, MotionLevel); 3] = [
    ("DISPLACEMENT", 1, MotionLevel::Displacement),
    ("VELOCITY", 1, MotionLevel::Velocity),
    ("ACCELERATION", 1, MotionLevel::Acceleration),
];

/// A MOTION command's DISPLACEMENT/VELOCITY/ACCELERATION, ICDISP and ICVEL (None when
/// it gives none of them); marks them read.
fn motion_drive(a: &mut Args) -> Option<MotionDrive> {
    let level = a
        .choice(&LEVELS.map(|(n, m, _)| (n, m)))
        .map(|k| LEVELS[k].2);
    let (icdisp, icvel) = (a.number("ICDISP", 3), a.number("ICVEL", 3));
    let drive = MotionDrive {
        level,
        icdisp,
        icvel,
    };
    (drive != MotionDrive::default()).then_some(drive)
}

/// One model-changing command of a command file.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelChange {
    /// What it does.
    pub change: Change,
    /// The command.
    pub span: Span,
}

/// The expression arguments each redefinable kind takes.
fn arguments_of(kind: Element) -> &'static [&'static str] {
    match kind {
        Element::Vforce => &["FX", "FY", "FZ"],
        Element::Vtorque => &["TX", "TY", "TZ"],
        Element::Gforce => &["FX", "FY", "FZ", "TX", "TY", "TZ"],
        _ => &["FUNCTION"],
    }
}

/// Reads the model-changing command `name` (canonical) whose arguments `a` holds;
/// `group` is its lines, `text` the whole command file. None after an error (in
/// `a.diags`).
pub(super) fn read_change(
    name: &str,
    text: &str,
    group: &[Piece],
    a: &mut Args,
) -> Option<ModelChange> {
    let span = a.stmt.span.clone();
    let change = match name {
        "ACTIVATE" | "DEACTIVATE" => switch(name == "ACTIVATE", a)?,
        "ACCGRAV" => {
            let g = ["IGRAV", "JGRAV", "KGRAV"].map(|k| a.number(k, 1));
            if g.iter().all(Option::is_none) {
                a.missing("IGRAV, JGRAV or KGRAV");
                return None;
            }
            Change::Gravity(g)
        }
        _ => redefine(Element::of_command(name)?, text, group, a)?,
    };
    Some(ModelChange { change, span })
}

/// `ACTIVATE/kind, ID = id | RANGE = first, last` (and DEACTIVATE).
fn switch(active: bool, a: &mut Args) -> Option<Change> {
    let command = if active { "ACTIVATE" } else { "DEACTIVATE" };
    let Some(first) = a.stmt.args.first().filter(|f| f.value == ArgValue::Flag) else {
        a.missing("the kind of element first (JOINT, MOTION, SFORCE, …)");
        return None;
    };
    let Some(kind) = SWITCHABLE
        .iter()
        .copied()
        .find(|k| super::keywords::abbreviates(&first.name, k.name(), 3))
    else {
        let span = a.stmt.span.clone();
        let msg = format!(
            "{command}/{}: mbfx has no {} elements to switch (it switches JOINT, JPRIM, GCON, MOTION, SFORCE, VFORCE, VTORQUE, GFORCE, SPRINGDAMPER and BUSHING)",
            first.name, first.name
        );
        for arg in &a.stmt.args {
            a.find(&arg.name, arg.name.len());
        }
        a.error(Code::UnsupportedCommand, span, msg);
        return None;
    };
    a.flag(kind.name(), first.name.len());
    let one = a.id("ID", 2);
    let range = match a.find("RANGE", 3) {
        Some(arg) => {
            let values = a.numbers_of(arg)?;
            let ids: Vec<Id> = values
                .iter()
                .filter(|v| v.fract() == 0.0 && **v >= 0.0 && **v <= f64::from(Id::MAX))
                .map(|&v| v as Id)
                .collect();
            match ids.as_slice() {
                &[lo, hi] if ids.len() == values.len() && lo <= hi => {
                    Some((Ids::Range(lo, hi), arg.span.clone()))
                }
                _ => {
                    let msg = "RANGE takes two ids, the first no larger than the second".into();
                    a.error(Code::BadArgument, arg.span.clone(), msg);
                    return None;
                }
            }
        }
        None => None,
    };
    let (ids, ids_span) = match (one, range) {
        (Some((id, span)), None) => (Ids::One(id), span),
        (None, Some(r)) => r,
        (Some(_), Some((_, span))) => {
            a.error(
                Code::BadArgument,
                span,
                "ID and RANGE exclude each other".into(),
            );
            return None;
        }
        (None, None) => {
            a.missing("ID = id or RANGE = first, last");
            return None;
        }
    };
    Some(Change::Switch {
        active,
        kind,
        ids,
        ids_span,
    })
}

/// `KIND/id, FUNCTION = e` (or FX = e …): the new expressions, their text cleaned of the
/// command file's line joins.
fn redefine(kind: Element, text: &str, group: &[Piece], a: &mut Args) -> Option<Change> {
    let Some((id, id_span)) = a
        .stmt
        .id
        .and_then(|id| Id::try_from(id).ok())
        .zip(a.stmt.id_span.clone())
    else {
        a.missing(&format!("an id ({}/id)", kind.name()));
        return None;
    };
    let mut functions = Vec::new();
    let mut bad = false;
    let drive = match kind {
        Element::Motion => motion_drive(a),
        _ => None,
    };
    let drive_argument = |name: &str| {
        kind == Element::Motion
            && (LEVELS
                .iter()
                .any(|(n, m, _)| super::keywords::abbreviates(name, n, *m))
                || ["ICDISP", "ICVEL"]
                    .iter()
                    .any(|n| super::keywords::abbreviates(name, n, 3)))
    };
    for arg in &a.stmt.args {
        if drive_argument(&arg.name) {
            continue;
        }
        let known = arguments_of(kind)
            .iter()
            .find(|n| super::keywords::abbreviates(&arg.name, n, n.len().min(3)));
        a.find(&arg.name, arg.name.len());
        let (Some(&argument), Some(span)) = (known, arg.expr_span()) else {
            let msg = format!(
                "{}/{id}: mbfx redefines only {} in a command file, not {}",
                kind.name(),
                arguments_of(kind).join(", "),
                arg.name
            );
            a.error(Code::UnsupportedCommand, arg.span.clone(), msg);
            bad = true;
            continue;
        };
        if arg.is_user_call {
            let msg = "USER(...) calls a user subroutine, which mbfx cannot run".into();
            a.error(Code::UnsupportedCommand, span, msg);
            bad = true;
            continue;
        }
        functions.push(NewFunction {
            argument,
            text: joined(text, group, span.clone()),
            start: span.start,
        });
    }
    if functions.is_empty() && drive.is_none() && !bad {
        a.missing(&arguments_of(kind).join(" or "));
    }
    (!bad && (!functions.is_empty() || drive.is_some())).then_some(Change::Redefine {
        kind,
        id,
        drive,
        id_span,
        functions,
    })
}

/// The bytes of `span` with everything outside the command's pieces (`&` line joins,
/// continuation commas, comments, line ends) made blanks.
fn joined(text: &str, group: &[Piece], span: Span) -> String {
    let inside = |p: usize| group.iter().any(|g| g.range.contains(&p));
    let bytes: Vec<u8> = text.as_bytes()[span.clone()]
        .iter()
        .zip(span)
        .map(|(&b, p)| if inside(p) { b } else { b' ' })
        .collect();
    // Pieces start and end at ASCII bytes, so no character is cut.
    String::from_utf8(bytes).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}
