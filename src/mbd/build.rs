//! From a [`Model`] to a [`System`]: parts, markers, JOINT, JPRIM, GCON and MOTION
//! through the library constructors, then the choice of 2D or 3D. Expressions become
//! [`ExprFn`]s through an [`ExprCompiler`]: the integration plugs in the compiled IR
//! derivative; [`super::expr::InterpretOnly`] evaluates values alone.

use super::error::MbdError;
use super::expr::{ExprCompiler, ExprError, ExprFn, Integrated, Integration::*};
use super::forces::{angle_of, ForceElement, ForceLaw, ForceSet, Scalar, Source};
use super::handles::{MarkerHandle, PartHandle};
use super::measure_set::Measure;
use super::output_slot::OutputSlot;
use super::planar::Dim;
use super::states::{DiffState, StateExpr, StateSet};
use super::system::System;
use crate::model::elements::{Expr, Id, Model, MotionAxis, MotionLevel, MotionTarget, Named};
use crate::model::inertia::mass_properties;
use crate::model::states::Statement;
use crate::vocab::elements::{ElementKind, ElementRef, ForceKind};
use crate::vocab::math::Vec3;
use std::collections::HashMap;

fn elref(kind: ElementKind, n: &Named) -> ElementRef {
    ElementRef {
        kind,
        id: n.id,
        name: n.name.clone(),
    }
}

impl System {
    /// Resolves the model's measure slots `slots` (as an expression's
    /// [`ExprFn::slots`] lists them) to measures of the system; only these are ever
    /// computed. Returns the measure index of each slot, in order.
    pub fn resolve_slots(&mut self, model: &Model, slots: &[u32]) -> Result<Vec<usize>, MbdError> {
        let mut map = Vec::with_capacity(slots.len());
        for &s in slots {
            let slot = model
                .measures
                .get(s as usize)
                .ok_or(MbdError::UnknownMeasureSlot(s))?;
            map.push(self.resolve_measure(model, slot)?);
        }
        Ok(map)
    }

    /// Resolves the measure slot `slot` of `model` to a measure of the system and returns
    /// its index; a design variable's VARVAL takes the VARIABLE's value from `model`.
    pub fn resolve_measure(
        &mut self,
        model: &Model,
        slot: &crate::model::elements::MeasureSlot,
    ) -> Result<usize, MbdError> {
        // DIF, DIF1 and ARYVAL of an LSE's or TFSISO's arrays read the state values.
        if let Some(channel) = model.states.channel(&slot.name, &slot.ids, &model.arrays) {
            return Ok(self.measures.add(Measure::State {
                channel: channel as u32,
            }));
        }
        let m = Measure::resolve(slot, &|id| self.marker_or_ground(id))?;
        if let Measure::Design { id } = m {
            let value = Id::try_from(id)
                .ok()
                .and_then(|v| model.design_value(v))
                .ok_or(MbdError::Variable(id))?;
            self.measures.set_design(id, value);
        }
        Ok(self.measures.add(m))
    }

    /// Builds the system of `model` in the dimension `dim` allows.
    pub fn from_model(
        model: &Model,
        dim: Dim,
        exprs: &dyn ExprCompiler,
    ) -> Result<System, MbdError> {
        let mut sys = System::new();
        let mut parts: HashMap<Id, PartHandle> = HashMap::new();
        for p in &model.parts {
            let h = if p.ground {
                System::GROUND
            } else {
                // The CM is the part's reference point (inertia.rs).
                let props = mass_properties(model, p);
                let h = sys.add_part(
                    Some(p.el.id),
                    p.position + p.orientation * props.cm,
                    p.orientation,
                );
                let part = sys.part_mut(h);
                (part.mass, part.inertia, part.cm_offset) = (props.mass, props.inertia, props.cm);
                h
            };
            sys.part_mut(h).id = Some(p.el.id);
            sys.part_mut(h).name = p.el.name.clone();
            parts.insert(p.el.id, h);
        }
        let mut markers: HashMap<Id, MarkerHandle> = HashMap::new();
        for m in &model.markers {
            let part = *parts.get(&m.part).ok_or(MbdError::UnknownPart(m.part))?;
            let s = m.position - sys.part(part).cm_offset;
            let h = sys.add_marker(Some(m.el.id), part, s, m.orientation);
            sys.markers[h.0 as usize].floating = m.floating;
            markers.insert(m.el.id, h);
        }
        let marker = |id: Id| {
            markers
                .get(&id)
                .copied()
                .ok_or(MbdError::UnknownMarker(id as i64))
        };
        // Initial velocities: VX.. of the CM (global), WX.. in CM (or WM) marker axes.
        for p in model.parts.iter().filter(|p| !p.ground) {
            let h = parts[&p.el.id];
            let frame_of = |m: Option<Id>| {
                m.and_then(|id| markers.get(&id).copied())
                    .map(|m| sys.frame(Some(m)))
            };
            let wframe = frame_of(p.wm.or(p.cm));
            let wl = Vec3::from(p.angular_velocity.map(|x| x.unwrap_or(0.0)));
            let w = wframe.map_or(sys.part(h).rot * wl, |f| f.rot * wl);
            let vcm = Vec3::from(p.velocity.map(|x| x.unwrap_or(0.0)));
            // The reference point is the CM when there is one, else the BCS origin
            // (where VX.. then apply).
            sys.set_part_velocity(h, vcm, w);
        }
        for j in &model.joints {
            let param = j.pd.or(j.pitch).unwrap_or(0.0);
            sys.joint(
                elref(ElementKind::Joint(j.kind), &j.el),
                j.kind,
                marker(j.i)?,
                marker(j.j)?,
                param,
            )?;
        }
        for j in &model.jprims {
            sys.jprim(
                elref(ElementKind::Jprim(j.kind), &j.el),
                j.kind,
                marker(j.i)?,
                marker(j.j)?,
            )?;
        }
        // The GCONs' and displacement MOTIONs' expressions, fused once all are built.
        let mut fused = Vec::new();
        for g in &model.gcons {
            let e = model.inline_variables(&g.function).map_err(|s| {
                MbdError::Expression(elref(ElementKind::Gcon, &g.el), ExprError::Other(s))
            })?;
            let f = exprs.compile(&e);
            let map = sys.resolve_slots(model, f.slots())?;
            let h = sys.gcon(elref(ElementKind::Gcon, &g.el), f, map)?;
            fused.push((h.0 as usize, e.function));
        }
        for m in &model.motions {
            let r = elref(ElementKind::Motion, &m.el);
            let measure = match m.target {
                MotionTarget::Joint { joint, rotation } => {
                    let j = model.joints.iter().find(|j| j.el.id == joint).ok_or(
                        MbdError::UnknownMotionJoint {
                            motion: m.el.id,
                            joint: joint as i64,
                        },
                    )?;
                    let (i, jm) = (Some(marker(j.i)?), Some(marker(j.j)?));
                    if rotation {
                        Measure::Angle { i, j: jm, axis: 2 }
                    } else {
                        Measure::Disp {
                            i,
                            j: jm,
                            k: jm,
                            comp: 2,
                        }
                    }
                }
                MotionTarget::Markers { i, j, axis } => {
                    let (i, j) = (Some(marker(i)?), Some(marker(j)?));
                    match axis {
                        MotionAxis::X => Measure::Disp {
                            i,
                            j,
                            k: j,
                            comp: 0,
                        },
                        MotionAxis::Y => Measure::Disp {
                            i,
                            j,
                            k: j,
                            comp: 1,
                        },
                        MotionAxis::Z => Measure::Disp {
                            i,
                            j,
                            k: j,
                            comp: 2,
                        },
                        MotionAxis::B1 => Measure::Body123 { i, j, which: 0 },
                        MotionAxis::B2 => Measure::Body123 { i, j, which: 1 },
                        MotionAxis::B3 => Measure::Body123 { i, j, which: 2 },
                    }
                }
            };
            let e = model
                .inline_variables_keeping(&m.function, false)
                .map_err(|s| MbdError::Expression(r.clone(), ExprError::Other(s)))?;
            let f = exprs.compile(&e);
            // VELOCITY and ACCELERATION: the displacement is f integrated from the
            // initial conditions (`expr::Integrated` says why at position level).
            let (icdisp, icvel) = (m.icdisp.unwrap_or(0.0), m.icvel.unwrap_or(0.0));
            let drive: Box<dyn ExprFn> = match m.level {
                MotionLevel::Displacement => f,
                MotionLevel::Velocity => Box::new(Integrated::new(f, Once, icdisp, icvel)),
                MotionLevel::Acceleration => Box::new(Integrated::new(f, Twice, icdisp, icvel)),
            };
            let h = sys.motion(r, measure, drive)?;
            // (a drive reading measures has no slots filled for it there: not fused)
            if m.level == MotionLevel::Displacement && e.function.uses.measures.is_empty() {
                fused.push((h.0 as usize, e.function));
            }
        }
        sys.fuse_rows(exprs, &fused);
        sys.gravity = model.gravity;
        sys.ucf = model.units.ucf;
        sys.prepare(dim);
        Ok(sys)
    }
}

impl System {
    /// The force elements of `model` (SFORCE, VFORCE, VTORQUE, GFORCE, SPRINGDAMPER,
    /// BUSHING, BEAM, FIELD) with their expressions compiled by `exprs` (VARIABLEs inlined). Gravity
    /// is the system's own ([`System::gravity`]).
    pub fn forces_from_model(
        &mut self,
        model: &Model,
        exprs: &dyn ExprCompiler,
    ) -> Result<ForceSet, MbdError> {
        self.forces_with_meshes(model, exprs, &HashMap::new())
    }

    /// [`System::forces_from_model`] with the CONTACTs' EXTERNAL geometries given their
    /// meshes (keyed by GRAPHICS id; the session reads the files).
    pub fn forces_with_meshes(
        &mut self,
        model: &Model,
        exprs: &dyn ExprCompiler,
        meshes: &HashMap<Id, crate::collide::TriMesh>,
    ) -> Result<ForceSet, MbdError> {
        use crate::model::elements::VectorForceKind;
        let marker = |sys: &System, id: Id| {
            sys.marker_by_id(id)
                .ok_or(MbdError::UnknownMarker(id as i64))
        };
        let mut set = ForceSet::default();
        let force_ref = |kind: ForceKind, n: &Named| ElementRef {
            kind: ElementKind::Force(kind),
            id: n.id,
            name: n.name.clone(),
        };
        for f in &model.sforces {
            let r = force_ref(ForceKind::Sforce, &f.el);
            let s = self.scalar(
                model,
                exprs,
                &r,
                &f.function,
                (&mut set.solution, &mut set.names),
            )?;
            let law = if f.rotation {
                ForceLaw::Torque {
                    f: s,
                    action_only: f.action_only,
                }
            } else {
                ForceLaw::Line {
                    f: s,
                    action_only: f.action_only,
                }
            };
            let (i, j) = (marker(self, f.i)?, marker(self, f.j)?);
            set.elements.push(ForceElement::new(r, i, Some(j), law));
        }
        for f in &model.vector_forces {
            let kind = match f.kind {
                VectorForceKind::Vforce => ForceKind::Vforce,
                VectorForceKind::Vtorque => ForceKind::Vtorque,
                VectorForceKind::Gforce => ForceKind::Gforce,
            };
            let r = force_ref(kind, &f.el);
            let (solution, names) = (&mut set.solution, &mut set.names);
            let mut three = |xs: &Option<[Expr; 3]>| -> Result<Option<Box<[Scalar; 3]>>, MbdError> {
                let Some(xs) = xs else { return Ok(None) };
                let [a, b, c] = xs;
                Ok(Some(Box::new([
                    self.scalar(model, exprs, &r, a, (solution, names))?,
                    self.scalar(model, exprs, &r, b, (solution, names))?,
                    self.scalar(model, exprs, &r, c, (solution, names))?,
                ])))
            };
            let (force, torque) = (three(&f.force)?, three(&f.torque)?);
            let rm = if f.rm == 0 {
                None
            } else {
                Some(marker(self, f.rm)?)
            };
            let (i, j) = (marker(self, f.i)?, marker(self, f.jfloat)?);
            let law = ForceLaw::Vector { force, torque, rm };
            set.elements.push(ForceElement::new(r, i, Some(j), law));
        }
        for f in &model.spring_dampers {
            let r = force_ref(ForceKind::Springdamper, &f.el);
            let (i, j) = (marker(self, f.i)?, marker(self, f.j)?);
            let law = if f.rotation {
                ForceLaw::RotSpring {
                    k: f.stiffness,
                    c: f.damping,
                    angle: f.free_length,
                    preload: f.preload,
                    angle_measure: self.measures.add(angle_of(i, Some(j), 2)),
                }
            } else {
                ForceLaw::Spring {
                    k: f.stiffness,
                    c: f.damping,
                    length: f.free_length,
                    preload: f.preload,
                }
            };
            set.elements.push(ForceElement::new(r, i, Some(j), law));
        }
        for b in &model.bushings {
            let r = force_ref(ForceKind::Bushing, &b.el);
            let (i, j) = (marker(self, b.i)?, marker(self, b.j)?);
            let angles = [0, 1, 2].map(|a| self.measures.add(angle_of(i, Some(j), a)));
            let law = ForceLaw::Bushing {
                k: b.k,
                c: b.c,
                kt: b.kt,
                ct: b.ct,
                force: b.force,
                torque: b.torque,
                angles,
            };
            set.elements.push(ForceElement::new(r, i, Some(j), law));
        }
        set.states = self.states_from_model(model, exprs)?;
        let linear = (model.beams.iter())
            .map(|b| {
                (
                    ForceKind::Beam,
                    &b.el,
                    b.i,
                    b.j,
                    crate::mbd::forces::beam_law(b),
                )
            })
            .chain(model.fields.iter().map(|f| {
                let law = crate::mbd::forces::field::Linear6 {
                    k: *f.k,
                    c: *f.c,
                    length: f.length,
                    preload: f.preload,
                };
                (ForceKind::Field, &f.el, f.i, f.j, law)
            }));
        for (kind, el, i, j, law) in linear {
            let r = force_ref(kind, el);
            let (i, j) = (marker(self, i)?, marker(self, j)?);
            let angles = [0, 1, 2].map(|a| self.measures.add(angle_of(i, Some(j), a)));
            let law = ForceLaw::Field {
                law: Box::new(law),
                angles,
            };
            set.elements.push(ForceElement::new(r, i, Some(j), law));
        }
        for f in &model.frictions {
            let mut el = self.joint_friction(model, f, (&mut set.solution, &mut set.names))?;
            // Its stiction deformation joins the state elements' block.
            if let (ForceLaw::Friction(law), Some(j)) = (&mut el.law, el.j) {
                if law.stiction.is_some() {
                    let label = format!("FRICTION/{}", f.el.id);
                    let base = set.states.add_stiction(label, (**law).clone(), (el.i, j));
                    if let Some(s) = &mut law.stiction {
                        s.channel = base;
                    }
                }
            }
            set.elements.push(el);
        }
        set.fuse(exprs);
        set.contacts = super::contacts::ContactSet::from_model(self, model, meshes)?;
        Ok(set)
    }

    /// The state elements of `model` (DIFF, LSE, TFSISO) with their expressions compiled
    /// by `exprs` (VARIABLEs inlined): a DIFF's FUNCTION, and each LSE or TFSISO input's
    /// VARIABLE. They may read kinematic measures, time and state values, and what only
    /// the dynamics gives (reactions, forces, accelerations), listed in the set's
    /// [`StateSet::solution`]. A failure names the statement at fault.
    pub fn states_from_model(
        &mut self,
        model: &Model,
        exprs: &dyn ExprCompiler,
    ) -> Result<StateSet, MbdError> {
        let mut set = StateSet::default();
        let compile =
            |sys: &mut System, set: &mut StateSet, place: Statement, label: &str, e: &Expr| {
                let fail = |s: String| MbdError::State(place, format!("{label}: {s}"));
                let e = model.inline_variables(e).map_err(fail)?;
                let f = exprs.compile(&e);
                let mut map = Vec::with_capacity(f.slots().len());
                for &s in f.slots() {
                    let read = (&mut set.solution, &mut set.names);
                    map.push(
                        sys.slot_source(model, s, read)
                            .map_err(|e| fail(e.to_string()))?,
                    );
                }
                Ok::<_, MbdError>(StateExpr { f, map })
            };
        for d in &model.states.diffs {
            let statement = Statement::new("DIFF", d.el.id);
            let label = statement.to_string();
            let f = compile(self, &mut set, statement, &label, &d.function)?;
            set.add_diff(DiffState {
                label,
                statement,
                f,
                implicit: d.implicit,
                static_hold: d.static_hold,
                ic: (d.ic, d.ic_rate.unwrap_or(0.0)),
            });
        }
        let systems = model
            .states
            .linear_systems(&model.arrays)
            .map_err(|(place, why)| MbdError::State(place, why))?;
        for s in systems {
            let mut inputs = Vec::with_capacity(s.m);
            for (j, &v) in s.inputs.iter().enumerate() {
                let label = format!("{}: input {} (VARIABLE/{v})", s.label, j + 1);
                // A VARIABLE that is not there is the U array's fault.
                let u_array = s.arrays[1].map_or(s.statement, |u| Statement::new("ARRAY", u));
                let var = model.variable(v).ok_or_else(|| {
                    MbdError::State(u_array, format!("{label} is not in the dataset"))
                })?;
                let place = Statement::new("VARIABLE", v);
                inputs.push(compile(self, &mut set, place, &label, &var.function)?);
            }
            set.add_linear(s, inputs);
        }
        Ok(set)
    }

    /// Where slot `s` of an expression is read from: a kinematic measure of the system,
    /// or a value only the dynamics gives (an acceleration, a reaction, a force),
    /// appended to `solution` once, with its name as written into `names`.
    fn slot_source(
        &mut self,
        model: &Model,
        s: u32,
        (solution, names): (&mut Vec<OutputSlot>, &mut Vec<String>),
    ) -> Result<Source, MbdError> {
        match self.resolve_slots(model, &[s]) {
            Ok(m) => Ok(Source::Measure(m[0])),
            Err(MbdError::NeedsDynamics(..)) => {
                let o = OutputSlot::resolve(self, model, s)?;
                let k = solution.iter().position(|x| *x == o).unwrap_or_else(|| {
                    solution.push(o);
                    let ms = &model.measures[s as usize];
                    let ids: Vec<String> = ms.ids.iter().map(|x| x.to_string()).collect();
                    names.push(format!("{}({})", ms.name, ids.join(", ")));
                    solution.len() - 1
                });
                Ok(Source::Solution(k))
            }
            Err(err) => Err(err),
        }
    }

    /// The force element of FRICTION `f`: between its joint's markers, reading the
    /// joint's reaction on I in J's axes as six solution values appended to `solution`.
    fn joint_friction(
        &mut self,
        model: &Model,
        f: &crate::model::friction::Friction,
        (solution, names): (&mut Vec<OutputSlot>, &mut Vec<String>),
    ) -> Result<ForceElement, MbdError> {
        use crate::mbd::forces::friction::{FrictionJoint, JointFriction};
        let fail = |why| MbdError::FrictionJoint {
            friction: f.el.id,
            joint: i64::from(f.joint),
            why,
        };
        let joint = (model.joints.iter())
            .find(|j| j.el.id == f.joint)
            .ok_or(fail("does not exist"))?;
        let slips = FrictionJoint::of(joint.kind).ok_or(fail(
            "is of a type friction does not act in (revolute, translational, cylindrical, \
             spherical, Hooke, universal)",
        ))?;
        let element = (self.elements.iter())
            .position(|e| e.elref.id == f.joint && matches!(e.elref.kind, ElementKind::Joint(_)))
            .ok_or(fail("is not among the system's constraints"))?;
        let marker = |sys: &System, id: Id| {
            sys.marker_by_id(id)
                .ok_or(MbdError::UnknownMarker(id as i64))
        };
        let (i, j) = (marker(self, joint.i)?, marker(self, joint.j)?);
        let reaction = [2u8, 3, 4, 6, 7, 8].map(|comp| {
            solution.push(OutputSlot::ElementForce {
                constraint: true,
                element,
                jflag: false,
                comp,
                rm: Some(j),
            });
            names.push(format!("JOINT({}, 0, {comp}, {})", f.joint, joint.j));
            solution.len() - 1
        });
        let (fi, fj) = (self.frame(Some(i)), self.frame(Some(j)));
        let travel0 = (fi.r - fj.r).dot(&fj.rot.column(2));
        let law = JointFriction::new(f, slips, reaction, travel0);
        let r = ElementRef {
            kind: ElementKind::Force(ForceKind::Friction),
            id: f.el.id,
            name: f.el.name.clone(),
        };
        Ok(ForceElement::new(
            r,
            i,
            Some(j),
            ForceLaw::Friction(Box::new(law)),
        ))
    }

    /// A force expression compiled with its derivative, its measures resolved: marker
    /// measures through the system's measure set, accelerations and forces appended to
    /// `solution` (the dynamics fills them in).
    fn scalar(
        &mut self,
        model: &Model,
        exprs: &dyn ExprCompiler,
        r: &ElementRef,
        e: &Expr,
        (solution, names): (&mut Vec<OutputSlot>, &mut Vec<String>),
    ) -> Result<Scalar, MbdError> {
        let e = model
            .inline_variables(e)
            .map_err(|s| MbdError::Expression(r.clone(), ExprError::Other(s)))?;
        let f = exprs.compile(&e);
        let other =
            |err: MbdError| MbdError::Expression(r.clone(), ExprError::Other(err.to_string()));
        let mut map = Vec::with_capacity(f.slots().len());
        for &s in f.slots() {
            let read = (&mut *solution, &mut *names);
            map.push(self.slot_source(model, s, read).map_err(other)?);
        }
        Ok(Scalar::new(f, map)
            .watching(&e.function)
            .with_ir(e.function))
    }
}
