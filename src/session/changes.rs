//! A command file's changes to the model ([`crate::model::command_changes`]) checked
//! against the dataset and applied to it: [`resolve`] finds the elements a change names
//! and compiles its new expressions in the dataset's scope (diagnostics point into the
//! command file), [`Resolved::apply`] puts it into the model and the set of inactive
//! elements, and [`effective`] is the model the run builds from: the dataset without its
//! inactive elements. The run resolves every change before it starts, so a bad one stops
//! it before the first row, and again where it applies it.

use crate::check::{Expect, Variables};
use crate::diag::{Code, Diagnostic};
use crate::ir::Function;
use crate::model::command_changes::{Change, Element, Ids, ModelChange, MotionDrive};
use crate::model::elements::{Expr, Id, Model, MotionTarget, VectorForceKind};
use crate::model::ModelRead;
use std::collections::BTreeSet;

/// The elements switched off, by kind and id.
pub type Inactive = BTreeSet<(Element, Id)>;

/// A change with its elements found and its expressions compiled.
#[derive(Clone, Debug)]
pub enum Resolved {
    /// Elements switched on (`active`) or off.
    Switch {
        /// ACTIVATE rather than DEACTIVATE.
        active: bool,
        /// The elements.
        targets: Vec<(Element, Id)>,
    },
    /// New expressions for `kind`/`id`: (argument, lowered expression).
    Redefine {
        /// The element's kind.
        kind: Element,
        /// Its id.
        id: Id,
        /// FUNCTION, or FX … TZ, with the new expression.
        functions: Vec<(&'static str, Function)>,
        /// A MOTION's new drive settings.
        drive: Option<MotionDrive>,
    },
    /// ACCGRAV's components given.
    Gravity([Option<f64>; 3]),
}

/// What applying a change did to the model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Applied {
    /// Something changed: the system must be built again.
    pub rebuild: bool,
    /// Constraint elements were switched: assembly and a redundancy analysis again.
    pub constraints: bool,
    /// A VARIABLE has a new expression: what reads it (output columns too) changes.
    pub variables: bool,
}

impl Applied {
    /// Both changes' effects.
    pub fn and(self, other: Applied) -> Applied {
        Applied {
            rebuild: self.rebuild || other.rebuild,
            constraints: self.constraints || other.constraints,
            variables: self.variables || other.variables,
        }
    }
}

/// The ids of the elements of `kind` in `model`.
fn ids_of(model: &Model, kind: Element) -> Vec<Id> {
    let vector = |k: VectorForceKind| -> Vec<Id> {
        (model.vector_forces.iter())
            .filter(|f| f.kind == k)
            .map(|f| f.el.id)
            .collect()
    };
    match kind {
        Element::Joint => model.joints.iter().map(|e| e.el.id).collect(),
        Element::Jprim => model.jprims.iter().map(|e| e.el.id).collect(),
        Element::Gcon => model.gcons.iter().map(|e| e.el.id).collect(),
        Element::Motion => model.motions.iter().map(|e| e.el.id).collect(),
        Element::Sforce => model.sforces.iter().map(|e| e.el.id).collect(),
        Element::Vforce => vector(VectorForceKind::Vforce),
        Element::Vtorque => vector(VectorForceKind::Vtorque),
        Element::Gforce => vector(VectorForceKind::Gforce),
        Element::SpringDamper => model.spring_dampers.iter().map(|e| e.el.id).collect(),
        Element::Bushing => model.bushings.iter().map(|e| e.el.id).collect(),
        Element::Variable => model.variables.iter().map(|e| e.el.id).collect(),
    }
}

/// `change` checked against the dataset of `read`: the warnings of its expressions with
/// it, or every error (spans into the command file). Compiling adds the measures the new
/// expressions read to the model's slots, as an expression typed later does.
pub fn resolve(
    read: &mut ModelRead,
    change: &ModelChange,
) -> Result<(Resolved, Vec<Diagnostic>), Vec<Diagnostic>> {
    match &change.change {
        Change::Gravity(g) => Ok((Resolved::Gravity(*g), Vec::new())),
        Change::Switch {
            active,
            kind,
            ids,
            ids_span,
        } => {
            let known = ids_of(&read.model, *kind);
            let targets: Vec<(Element, Id)> = match ids {
                Ids::One(id) => known
                    .iter()
                    .filter(|k| *k == id)
                    .map(|&k| (*kind, k))
                    .collect(),
                Ids::Range(lo, hi) => (known.iter())
                    .filter(|k| (lo..=hi).contains(k))
                    .map(|&k| (*kind, k))
                    .collect(),
            };
            if targets.is_empty() {
                let what = match ids {
                    Ids::One(id) => format!("{}/{id} is not defined in the dataset", kind.name()),
                    Ids::Range(lo, hi) => format!(
                        "no {} of the dataset has an id from {lo} to {hi}",
                        kind.name()
                    ),
                };
                let d = Diagnostic::error(Code::UndefinedElement, ids_span.clone(), what);
                return Err(vec![d]);
            }
            Ok((
                Resolved::Switch {
                    active: *active,
                    targets,
                },
                Vec::new(),
            ))
        }
        Change::Redefine {
            kind,
            id,
            id_span,
            functions,
            drive,
        } => {
            let (mut errors, mut warnings) = (Vec::new(), Vec::new());
            if !ids_of(&read.model, *kind).contains(id) {
                let d = Diagnostic::error(
                    Code::UndefinedElement,
                    id_span.clone(),
                    format!("{}/{id} is not defined in the dataset", kind.name()),
                )
                .with_help("a command file gives new expressions to the dataset's elements; it cannot add elements");
                errors.push(d);
            }
            let mut compiled = Vec::new();
            for f in functions {
                match read.compile(&f.text, &Variables::new(), Expect::Scalar) {
                    Ok(c) => {
                        warnings.extend(c.warnings.into_iter().map(|d| d.shifted(f.start)));
                        compiled.push((f.argument, c.function));
                    }
                    Err(found) => errors.extend(found.into_iter().map(|d| d.shifted(f.start))),
                }
            }
            if errors.iter().any(Diagnostic::is_error) {
                errors.extend(warnings);
                return Err(errors);
            }
            let r = Resolved::Redefine {
                kind: *kind,
                id: *id,
                functions: compiled,
                drive: *drive,
            };
            Ok((r, warnings))
        }
    }
}

impl Resolved {
    /// Puts the change into `model` (new expressions, gravity) and `inactive`.
    pub fn apply(self, model: &mut Model, inactive: &mut Inactive) -> Applied {
        match self {
            Resolved::Gravity(g) => {
                let before = model.gravity;
                for (k, v) in g.into_iter().enumerate() {
                    if let Some(v) = v {
                        model.gravity[k] = v;
                    }
                }
                Applied {
                    rebuild: model.gravity != before,
                    ..Applied::default()
                }
            }
            Resolved::Switch { active, targets } => {
                let mut done = Applied::default();
                for t in targets {
                    let switched = match active {
                        true => inactive.remove(&t),
                        false => inactive.insert(t),
                    };
                    if switched {
                        done.rebuild = true;
                        done.constraints |= t.0.constrains();
                    }
                }
                done
            }
            Resolved::Redefine {
                kind,
                id,
                functions,
                drive,
            } => {
                let mut rebuild = false;
                let motion = model.motions.iter_mut().find(|m| m.el.id == id);
                if let (Some(dr), Some(m)) = (drive, motion) {
                    let before = (m.level, m.icdisp, m.icvel);
                    m.level = dr.level.unwrap_or(m.level);
                    m.icdisp = dr.icdisp.or(m.icdisp);
                    m.icvel = dr.icvel.or(m.icvel);
                    rebuild |= (m.level, m.icdisp, m.icvel) != before;
                }
                for (argument, function) in functions {
                    // (The same expression again, as a change made before the first
                    // SIMULATE is when the run starts, changes nothing.)
                    let Some(slot) = expression_of(model, kind, id, argument) else {
                        continue;
                    };
                    if format!("{:?}", slot.function) != format!("{function:?}") {
                        slot.function = function;
                        rebuild = true;
                    }
                }
                Applied {
                    rebuild,
                    constraints: false,
                    variables: rebuild && kind == Element::Variable,
                }
            }
        }
    }
}

/// The expression `argument` of `kind`/`id` in `model`, to be replaced.
fn expression_of<'m>(
    model: &'m mut Model,
    kind: Element,
    id: Id,
    argument: &str,
) -> Option<&'m mut Expr> {
    let component = |names: [&str; 3]| names.iter().position(|n| *n == argument);
    match kind {
        Element::Variable => (model.variables.iter_mut())
            .find(|v| v.el.id == id)
            .map(|v| &mut v.function),
        Element::Motion => (model.motions.iter_mut())
            .find(|v| v.el.id == id)
            .map(|v| &mut v.function),
        Element::Sforce => (model.sforces.iter_mut())
            .find(|v| v.el.id == id)
            .map(|v| &mut v.function),
        Element::Vforce | Element::Vtorque | Element::Gforce => {
            let f =
                (model.vector_forces.iter_mut()).find(|f| f.el.id == id && same(kind, f.kind))?;
            match (component(["FX", "FY", "FZ"]), component(["TX", "TY", "TZ"])) {
                (Some(k), _) => f.force.as_mut().map(|c| &mut c[k]),
                (_, Some(k)) => f.torque.as_mut().map(|c| &mut c[k]),
                _ => None,
            }
        }
        _ => None,
    }
}

/// Whether the command's kind is the statement's.
fn same(kind: Element, k: VectorForceKind) -> bool {
    matches!(
        (kind, k),
        (Element::Vforce, VectorForceKind::Vforce)
            | (Element::Vtorque, VectorForceKind::Vtorque)
            | (Element::Gforce, VectorForceKind::Gforce)
    )
}

/// Whether the measure slot `slot` of `model` reads the reaction or force of an element
/// in `inactive` (`JOINT(3, …)` with JOINT/3 switched off).
pub fn reads_inactive(model: &Model, slot: u32, inactive: &Inactive) -> bool {
    let Some(ms) = model.measures.get(slot as usize) else {
        return false;
    };
    let kind = match ms.name.as_str() {
        "JOINT" => Element::Joint,
        "JPRIM" => Element::Jprim,
        "MOTION" => Element::Motion,
        "SFORCE" => Element::Sforce,
        "VFORCE" => Element::Vforce,
        "VTORQ" => Element::Vtorque,
        "GFORCE" => Element::Gforce,
        "BUSH" => Element::Bushing,
        "SPDP" => Element::SpringDamper,
        _ => return false,
    };
    let id = ms.ids.first().and_then(|&id| Id::try_from(id).ok());
    id.is_some_and(|id| inactive.contains(&(kind, id)))
}

/// The model without its `inactive` elements, and without the MOTIONs of inactive
/// joints (a drive of a joint that is not there drives nothing).
pub fn effective(model: &Model, inactive: &Inactive) -> Model {
    let mut m = model.clone();
    let on = |kind: Element, id: Id| !inactive.contains(&(kind, id));
    m.joints.retain(|e| on(Element::Joint, e.el.id));
    m.jprims.retain(|e| on(Element::Jprim, e.el.id));
    m.gcons.retain(|e| on(Element::Gcon, e.el.id));
    m.motions.retain(|e| {
        let joint_on = match e.target {
            MotionTarget::Joint { joint, .. } => on(Element::Joint, joint),
            MotionTarget::Markers { .. } => true,
        };
        joint_on && on(Element::Motion, e.el.id)
    });
    m.sforces.retain(|e| on(Element::Sforce, e.el.id));
    m.vector_forces.retain(|e| {
        let kind = match e.kind {
            VectorForceKind::Vforce => Element::Vforce,
            VectorForceKind::Vtorque => Element::Vtorque,
            VectorForceKind::Gforce => Element::Gforce,
        };
        on(kind, e.el.id)
    });
    m.spring_dampers
        .retain(|e| on(Element::SpringDamper, e.el.id));
    m.bushings.retain(|e| on(Element::Bushing, e.el.id));
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::commands::{read_commands, Step};

    const MODEL: &str = "m\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
        JOINT/1, REVOLUTE, I = 20, J = 10\nMOTION/1, JOINT = 1, FUNCTION = TIME\n\
        SFORCE/2, ROTATION, I = 20, J = 10, FUNCTION = 1\nVARIABLE/3, FUNCTION = 2\n\
        ACCGRAV/JGRAV = -9.81\nEND\n";

    /// The command file's changes, resolved against MODEL and applied in order.
    fn applied(acf: &str) -> (Model, Inactive, Vec<Applied>) {
        let mut read = crate::model::read_model(MODEL);
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        let mut inactive = Inactive::new();
        let mut done = Vec::new();
        for step in read_commands(acf).steps {
            if let Step::Change(c) = step {
                let (r, _) = resolve(&mut read, &c).expect("resolves");
                done.push(r.apply(&mut read.model, &mut inactive));
            }
        }
        (read.model, inactive, done)
    }

    #[test]
    fn a_joint_switched_off_takes_its_motion_with_it() {
        let (model, inactive, done) =
            applied("m\nout\nDEACTIVATE/JOINT, ID = 1\nDEACTIVATE/SFORCE, RANGE = 1, 5\n");
        let m = effective(&model, &inactive);
        assert!(m.joints.is_empty() && m.motions.is_empty() && m.sforces.is_empty());
        assert_eq!(model.joints.len(), 1, "the dataset keeps every element");
        assert!(done[0].constraints && done[0].rebuild);
        assert!(!done[1].constraints && done[1].rebuild);
    }

    #[test]
    fn switching_twice_and_the_same_gravity_change_nothing() {
        let (_, inactive, done) = applied(
            "m\nout\nACTIVATE/JOINT, ID = 1\nDEACTIVATE/MOTION, ID = 1\nDEACTIVATE/MOTION, ID = 1\nACCGRAV/JGRAV = -9.81\nACCGRAV/IGRAV = 1\nVARIABLE/3, FUNCTION = 2*TIME\n",
        );
        let rebuilt: Vec<bool> = done.iter().map(|d| d.rebuild).collect();
        assert_eq!(rebuilt, [false, true, false, false, true, true]);
        assert!(done[5].variables);
        assert_eq!(inactive.len(), 1);
    }

    #[test]
    fn every_cut_of_a_command_file_is_read_and_resolved_without_a_panic() {
        // Bad input never panics, and every diagnostic points into the text.
        let full = "m\nout\nDEACTIVATE/JOINT, RANGE = 1, 3\nVARIABLE/3 &\n, FUNCTION = STEP(TIME, 0, 0, 1, 2) & ! ramp\n  + 1\nGFORCE/2, FX = 1\\ TZ = 2\nACCGRAV/IGRAV = 1, KGRAV = -2\nACTIVATE/SFORCE, ID = 2\nSFORCE/2, FUNCTION = DX(20,10)*-3\nsim/dyn, end=1, steps=2\n";
        for cut in (0..=full.len()).filter(|&k| full.is_char_boundary(k)) {
            let text = &full[..cut];
            let f = read_commands(text);
            let mut read = crate::model::read_model(MODEL);
            let mut all = f.diagnostics.clone();
            for step in &f.steps {
                if let Step::Change(c) = step {
                    match resolve(&mut read, c) {
                        Ok((_, w)) => all.extend(w),
                        Err(e) => all.extend(e),
                    }
                }
            }
            for d in &all {
                assert!(d.span.end <= text.len(), "{text:?}: {d:?}");
            }
        }
    }

    #[test]
    fn what_the_dataset_lacks_is_an_error_at_the_id() {
        let mut read = crate::model::read_model(MODEL);
        let text = "m\nout\nDEACTIVATE/GFORCE, ID = 2\nVFORCE/1, FX = 1\nSFORCE/2, FUNCTION = DX(20, 99)\n";
        for step in read_commands(text).steps {
            let Step::Change(c) = step else { continue };
            let Err(found) = resolve(&mut read, &c) else {
                panic!("{c:?} resolves");
            };
            let e = found.iter().find(|d| d.is_error()).expect("an error");
            let at = &text[e.span.clone()];
            assert!(["2", "1", "99"].contains(&at), "{at}: {}", e.message);
        }
    }
}
