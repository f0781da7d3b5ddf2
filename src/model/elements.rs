//! The user-facing model: what an `.adm` dataset declares, in Adams terms (ids,
//! `adams_view_name` names, byte spans into the file), with every number converted to
//! what it means (degrees to radians, REULER/ZP/XP to a rotation matrix) but nothing
//! assembled yet. The reader fills a [`Model`]; the multibody core ([`crate::mbd`]) builds
//! its system from one. Elements refer to each other by Adams id; the reader has checked
//! that every id they name exists.
//!
//! Expressions (`FUNCTION=`, `FX=`, ...) are checked and lowered to IR with the model as
//! their scope: every measure call they make (`DX(2,1)`, `UVZ(3)`, `VARVAL(5)`) is a slot
//! in [`Model::measures`], which the core fills before it evaluates them.

use crate::diag::Span;
use crate::ir::Function;
use crate::vocab::elements::{JointType, JprimType};
use crate::vocab::math::{Mat3, Vec3};

/// An Adams element id (`PART/2` has id 2).
pub type Id = u32;

/// What every element carries: its id, its `adams_view_name` (when the dataset gives
/// one) and the span of its statement in the file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Named {
    /// The Adams id.
    pub id: Id,
    /// The `adams_view_name`, when the dataset gives one.
    pub name: Option<String>,
    /// Byte range of the statement in the dataset.
    pub span: Span,
}

/// A whole dataset.
#[derive(Clone, Debug, Default)]
pub struct Model {
    /// Line 1 of the file.
    pub title: String,
    /// UNITS, with the units-consistency factor.
    pub units: Units,
    /// PART statements, ground included, in file order.
    pub parts: Vec<Part>,
    /// MARKER statements.
    pub markers: Vec<Marker>,
    /// JOINT statements.
    pub joints: Vec<Joint>,
    /// JPRIM statements.
    pub jprims: Vec<Jprim>,
    /// GCON statements.
    pub gcons: Vec<Gcon>,
    /// MOTION statements.
    pub motions: Vec<Motion>,
    /// SFORCE statements.
    pub sforces: Vec<Sforce>,
    /// VFORCE, VTORQUE and GFORCE.
    pub vector_forces: Vec<VectorForce>,
    /// SPRINGDAMPER statements.
    pub spring_dampers: Vec<SpringDamper>,
    /// BUSHING statements.
    pub bushings: Vec<Bushing>,
    /// CONTACT statements (issue 40 §1).
    pub contacts: Vec<super::contact::Contact>,
    /// BEAM statements.
    pub beams: Vec<super::beams::Beam>,
    /// FIELD statements.
    pub fields: Vec<super::beams::Field>,
    /// FRICTION statements (joint friction).
    pub frictions: Vec<super::friction::Friction>,
    /// VARIABLE statements (read by `VARVAL`).
    pub variables: Vec<Variable>,
    /// PINPUT and POUTPUT statements.
    pub plants: Vec<PlantVariables>,
    /// In file order; an expression's AKISPL/CUBSPL spline index is a position here.
    pub splines: Vec<SplineData>,
    /// ARRAY statements (read by `ARYVAL`).
    pub arrays: Vec<Array>,
    /// DIFF, LSE, TFSISO and the MATRIX data they read (issue 40 §3).
    pub states: super::states::StateElements,
    /// ACCGRAV in model length/time², global axes (zero when absent).
    pub gravity: Vec3,
    /// REQUEST statements.
    pub requests: Vec<Request>,
    /// INTEGRATOR, OUTPUT, RESULTS and similar settings statements, kept as written.
    pub settings: Vec<Setting>,
    /// The INTEGRATOR statement, typed (several merge in file order).
    pub integrator: Option<super::integrator_settings::IntegratorStatement>,
    /// The EQUILIBRIUM statement, typed (several merge in file order).
    pub equilibrium: Option<super::equilibrium_settings::EquilibriumStatement>,
    /// The KINEMATICS statement, typed (several merge in file order).
    pub kinematics: Option<super::kinematics_settings::KinematicsStatement>,
    /// GRAPHICS statements of the kinds mbfx reads, in file order (shapes to draw only).
    pub graphics: Vec<super::graphics::Graphic>,
    /// The measure every expression slot reads (index = slot of [`crate::ir::Inst::Measure`]).
    pub measures: Vec<MeasureSlot>,
    /// What the reader left out, one entry per kind in the order of their names: a run
    /// must say what of the dataset's physics its results lack.
    pub ignored: Vec<Ignored>,
}

/// Statements of one kind the model leaves out (see [`super::report::ignored_warning`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Ignored {
    /// The statement kind (`FRICTION`), or the keyword as written for one mbfx does not
    /// know; for [`Omission::UserCall`], `USER`.
    pub kind: String,
    /// Why they are left out.
    pub why: Omission,
    /// Whether leaving them out can change the motion (see
    /// [`super::reader::QUIET_STATEMENTS`]): a run warns about these only.
    pub physical: bool,
    /// Each statement's label (`FRICTION/3 (name)`) and 1-based line, in file order
    /// (never empty).
    pub statements: Vec<(String, usize)>,
    /// Byte range of the first statement's keyword.
    pub span: Span,
}

/// Why the reader left statements out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Omission {
    /// A statement kind outside the mbfx subset (CONTACT, FRICTION, ...).
    Unsupported,
    /// A keyword mbfx does not know at all.
    Unknown,
    /// Elements of a modelled kind whose values a `USER(…)` subroutine computes, which
    /// exists only compiled for Adams.
    UserCall,
}

impl Ignored {
    /// How many statements.
    pub fn count(&self) -> usize {
        self.statements.len()
    }

    /// The first statement's line.
    pub fn line(&self) -> usize {
        self.statements.first().map_or(0, |s| s.1)
    }
}

/// UNITS and the units-consistency factor: Force·UCF = Mass·Acceleration (spec §2.1).
#[derive(Clone, Debug, PartialEq)]
pub struct Units {
    /// FORCE unit name as written (`NEWTON`, ...), None when UNITS leaves it out.
    pub force: Option<String>,
    /// MASS unit name as written.
    pub mass: Option<String>,
    /// LENGTH unit name as written.
    pub length: Option<String>,
    /// TIME unit name as written.
    pub time: Option<String>,
    /// UCF: Force·UCF = Mass·Acceleration (1 for consistent units).
    pub ucf: f64,
}

impl Default for Units {
    fn default() -> Self {
        Units {
            force: None,
            mass: None,
            length: None,
            time: None,
            ucf: 1.0,
        }
    }
}

/// PART (spec §2.2). Pose of the body coordinate system (BCS) in global coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Id, view name and span.
    pub el: Named,
    /// GROUND: the fixed part, which has no coordinates.
    pub ground: bool,
    /// None for a massless part.
    pub mass: Option<f64>,
    /// CM: the centre-of-mass marker.
    pub cm: Option<Id>,
    /// IM: the marker about whose origin and in whose axes IP is given (CM when None).
    pub im: Option<Id>,
    /// Ixx, Iyy, Izz, Ixy, Ixz, Iyz as written (products are +∫xy dm, spec §2.2).
    pub ip: [f64; 6],
    /// QG: BCS origin in global coordinates.
    pub position: Vec3,
    /// REULER (or ZG/XG): columns are the BCS axes in global coordinates.
    pub orientation: Mat3,
    /// VX, VY, VZ: initial CM velocity along global axes, each None when not given.
    pub velocity: [Option<f64>; 3],
    /// WX, WY, WZ: initial angular velocity (CM-marker axes, or the VM/WM markers').
    pub angular_velocity: [Option<f64>; 3],
    /// VM: the marker whose velocity VX, VY, VZ give, as written (the build applies
    /// them at the CM).
    pub vm: Option<Id>,
    /// WM: the marker whose axes WX, WY, WZ are given in (CM when None).
    pub wm: Option<Id>,
    /// EXACT: coordinates the initial-conditions solver must not move (X Y Z PSI THETA PHI).
    pub exact: [bool; 6],
}

/// MARKER (spec §2.3).
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    /// Id, view name and span.
    pub el: Named,
    /// The part the marker is attached to.
    pub part: Id,
    /// QP: origin in the part's BCS.
    pub position: Vec3,
    /// REULER or ZP/XP: columns are the marker axes in BCS coordinates.
    pub orientation: Mat3,
    /// FLOATING: a marker whose pose the force or joint using it sets, not QP/REULER.
    pub floating: bool,
}

/// JOINT (spec §2.5, §4.2).
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Id, view name and span.
    pub el: Named,
    /// REVOLUTE, SPHERICAL, TRANSLATIONAL, ...
    pub kind: JointType,
    /// The I marker.
    pub i: Id,
    /// The J marker.
    pub j: Id,
    /// PD of a RACKPIN.
    pub pd: Option<f64>,
    /// PITCH of a SCREW.
    pub pitch: Option<f64>,
    /// IC (displacement, velocity), or ICTRAN / ICROT of a CYLINDRICAL.
    pub ic: Option<[f64; 2]>,
    /// ICTRAN of a CYLINDRICAL: translational (displacement, velocity).
    pub ic_tran: Option<[f64; 2]>,
    /// ICROT of a CYLINDRICAL: rotational (displacement, velocity).
    pub ic_rot: Option<[f64; 2]>,
}

/// JPRIM (spec §4.2).
#[derive(Clone, Debug, PartialEq)]
pub struct Jprim {
    /// Id, view name and span.
    pub el: Named,
    /// INPLANE, PERPENDICULAR, ATPOINT, ...
    pub kind: JprimType,
    /// The I marker.
    pub i: Id,
    /// The J marker.
    pub j: Id,
}

/// An expression argument, checked and lowered with the model as its scope.
#[derive(Clone, Debug)]
pub struct Expr {
    /// Byte range of the expression's text in the dataset.
    pub span: Span,
    /// The lowered IR of the expression.
    pub function: Function,
}

/// GCON: drives `function` to zero (spec §4.3).
#[derive(Clone, Debug)]
pub struct Gcon {
    /// Id, view name and span.
    pub el: Named,
    /// Marker whose reaction is reported (ground when None).
    pub i: Option<Id>,
    /// The constraint expression, zero when the GCON holds.
    pub function: Expr,
}

/// What a MOTION drives (spec §4.5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionTarget {
    /// `JOINT=id` with ROTATION (true) or TRANSLATION (false).
    Joint {
        /// The driven joint.
        joint: Id,
        /// ROTATION rather than TRANSLATION.
        rotation: bool,
    },
    /// `I=, J=` with one component of I relative to J.
    Markers {
        /// The I marker.
        i: Id,
        /// The J marker.
        j: Id,
        /// The component of I relative to J that is driven.
        axis: MotionAxis,
    },
}

/// X, Y, Z (along J axes) or the body-1-2-3 angles B1, B2, B3 of I relative to J.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionAxis {
    /// Translation along x_J.
    X,
    /// Translation along y_J.
    Y,
    /// Translation along z_J.
    Z,
    /// First body-1-2-3 angle.
    B1,
    /// Second body-1-2-3 angle.
    B2,
    /// Third body-1-2-3 angle.
    B3,
}

/// What a MOTION's FUNCTION gives: DISPLACEMENT, VELOCITY or ACCELERATION.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionLevel {
    /// The function is the coordinate itself.
    Displacement,
    /// The function is the coordinate's rate, integrated once from ICDISP.
    Velocity,
    /// The function is the second derivative, integrated twice from ICDISP and ICVEL.
    Acceleration,
}

/// MOTION (spec §4.5).
#[derive(Clone, Debug)]
pub struct Motion {
    /// Id, view name and span.
    pub el: Named,
    /// The joint or marker component driven.
    pub target: MotionTarget,
    /// Whether FUNCTION gives the displacement, velocity or acceleration.
    pub level: MotionLevel,
    /// The driving expression of time.
    pub function: Expr,
    /// ICDISP: initial displacement (for VELOCITY and ACCELERATION motions).
    pub icdisp: Option<f64>,
    /// ICVEL: initial velocity (for ACCELERATION motions).
    pub icvel: Option<f64>,
}

/// SFORCE (spec §7).
#[derive(Clone, Debug)]
pub struct Sforce {
    /// Id, view name and span.
    pub el: Named,
    /// The I marker (action point).
    pub i: Id,
    /// The J marker (reaction point).
    pub j: Id,
    /// ROTATION (a torque about z_J) rather than TRANSLATION.
    pub rotation: bool,
    /// ACTIONONLY: no reaction is applied at J.
    pub action_only: bool,
    /// FUNCTION: the force (or torque) magnitude.
    pub function: Expr,
}

/// Which vector force statement a [`VectorForce`] comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VectorForceKind {
    /// VFORCE: three force components.
    Vforce,
    /// VTORQUE: three torque components.
    Vtorque,
    /// GFORCE: three force and three torque components.
    Gforce,
}

/// VFORCE (FX FY FZ), VTORQUE (TX TY TZ) or GFORCE (all six), resolved in RM.
#[derive(Clone, Debug)]
pub struct VectorForce {
    /// Id, view name and span.
    pub el: Named,
    /// VFORCE, VTORQUE or GFORCE.
    pub kind: VectorForceKind,
    /// The I marker, where the action applies.
    pub i: Id,
    /// JFLOAT: the floating marker where the reaction applies.
    pub jfloat: Id,
    /// RM: the marker whose axes the components are resolved in.
    pub rm: Id,
    /// FX FY FZ (None for a VTORQUE).
    pub force: Option<[Expr; 3]>,
    /// TX TY TZ (None for a VFORCE).
    pub torque: Option<[Expr; 3]>,
}

/// SPRINGDAMPER (spec §7).
#[derive(Clone, Debug, PartialEq)]
pub struct SpringDamper {
    /// Id, view name and span.
    pub el: Named,
    /// The I marker.
    pub i: Id,
    /// The J marker.
    pub j: Id,
    /// ROTATION (a torsion spring about z_J) rather than TRANSLATION.
    pub rotation: bool,
    /// K or KT.
    pub stiffness: f64,
    /// C or CT.
    pub damping: f64,
    /// LENGTH or ANGLE.
    pub free_length: f64,
    /// FORCE or TORQUE (preload).
    pub preload: f64,
}

/// BUSHING (spec §7).
#[derive(Clone, Debug, PartialEq)]
pub struct Bushing {
    /// Id, view name and span.
    pub el: Named,
    /// The I marker.
    pub i: Id,
    /// The J marker.
    pub j: Id,
    /// K: translational stiffness along x_J, y_J, z_J.
    pub k: Vec3,
    /// C: translational damping along x_J, y_J, z_J.
    pub c: Vec3,
    /// KT: rotational stiffness about x_J, y_J, z_J.
    pub kt: Vec3,
    /// CT: rotational damping about x_J, y_J, z_J.
    pub ct: Vec3,
    /// FORCE: preload force components.
    pub force: Vec3,
    /// TORQUE: preload torque components.
    pub torque: Vec3,
}

/// VARIABLE: a named expression others read with VARVAL.
#[derive(Clone, Debug)]
pub struct Variable {
    /// Id, view name and span.
    pub el: Named,
    /// The variable's expression.
    pub function: Expr,
    /// IC: the initial value, when given.
    pub ic: Option<f64>,
}

/// SPLINE data (X, Y, optional Z rows of Y per Z value).
#[derive(Clone, Debug, PartialEq)]
pub struct SplineData {
    /// Id, view name and span.
    pub el: Named,
    /// X: the abscissae, increasing.
    pub x: Vec<f64>,
    /// One row for a curve, one row per `z` value for a surface.
    pub y: Vec<Vec<f64>>,
    /// Z: the surface parameter values (empty for a curve).
    pub z: Vec<f64>,
    /// LINEAR_EXTRAPOLATE, as written (the fits do not read it).
    pub linear_extrapolate: bool,
}

/// PINPUT or POUTPUT: the VARIABLEs that are a plant's inputs or outputs (Adams
/// Controls; LINEAR/STATEMAT's B, C and D).
#[derive(Clone, Debug, PartialEq)]
pub struct PlantVariables {
    /// Id, view name and span.
    pub el: Named,
    /// POUTPUT (rather than PINPUT).
    pub output: bool,
    /// The VARIABLE ids, in order.
    pub variables: Vec<Id>,
}

/// ARRAY (kept for ARYVAL).
#[derive(Clone, Debug, PartialEq)]
pub struct Array {
    /// Id, view name and span.
    pub el: Named,
    /// X, U, Y, IC or empty, as written.
    pub kind: String,
    /// The NUMBERS list (a U array's VARIABLES ids).
    pub numbers: Vec<f64>,
}

/// REQUEST: either a standard measure set of I relative to J, or up to eight expressions.
#[derive(Clone, Debug)]
pub struct Request {
    /// Id, view name and span.
    pub el: Named,
    /// DISPLACEMENT, VELOCITY, ACCELERATION or FORCE with markers I, J, RM.
    pub standard: Option<(RequestKind, Id, Option<Id>, Option<Id>)>,
    /// F1..F8 (index 0..7).
    pub functions: Vec<(usize, Expr)>,
    /// COMMENT text, when given.
    pub comment: Option<String>,
}

/// The standard measure set a REQUEST reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RequestKind {
    /// DISPLACEMENT: position and orientation angles.
    Displacement,
    /// VELOCITY: translational and angular velocity.
    Velocity,
    /// ACCELERATION: translational and angular acceleration.
    Acceleration,
    /// FORCE: the force and torque between the markers.
    Force,
}

/// A settings statement (INTEGRATOR, OUTPUT, RESULTS, EQUILIBRIUM, KINEMATICS, IC) with
/// its arguments as written (upper-case name, raw value text).
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    /// Upper-case statement name.
    pub statement: String,
    /// Byte range of the statement in the dataset.
    pub span: Span,
    /// `(NAME, value)` pairs in file order, names upper case, values raw text.
    pub args: Vec<(String, String)>,
}

/// One measure an expression reads, in the scope of the model: `name` is the builtin's
/// upper-case name (`DX`, `VR`, `UVZ`, `VARVAL`, ...), `ids` its integer arguments as
/// written (marker, element or variable ids, codes), `component` the index 0..3 of a
/// vector measure's component (0 for a scalar one). Equal calls share one slot.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct MeasureSlot {
    /// The builtin's upper-case name.
    pub name: String,
    /// Integer arguments as written.
    pub ids: Vec<i64>,
    /// Component index 0..3 of a vector measure (0 for a scalar one).
    pub component: u8,
}

impl Named {
    /// `JOINT/4 (Joint_4)`, or `JOINT/4` without a view name: how messages name it.
    pub fn display(&self, kind: &str) -> String {
        match &self.name {
            Some(name) => format!("{kind}/{} ({name})", self.id),
            None => format!("{kind}/{}", self.id),
        }
    }
}

impl Part {
    /// The inertia tensor about the IM (else CM) origin in IM axes, from IP with Adams'
    /// sign convention (spec §2.2: products are +∫xy dm, so they enter negated).
    pub fn inertia(&self) -> Mat3 {
        super::inertia::tensor(&self.ip)
    }
}

impl Model {
    /// How many elements of each statement kind the model holds, in a fixed order.
    pub fn element_counts(&self) -> [(&'static str, usize); 19] {
        let forces = |k: VectorForceKind| self.vector_forces.iter().filter(|f| f.kind == k).count();
        [
            ("PART", self.parts.len()),
            ("MARKER", self.markers.len()),
            ("JOINT", self.joints.len()),
            ("JPRIM", self.jprims.len()),
            ("GCON", self.gcons.len()),
            ("MOTION", self.motions.len()),
            ("SFORCE", self.sforces.len()),
            ("VFORCE", forces(VectorForceKind::Vforce)),
            ("VTORQUE", forces(VectorForceKind::Vtorque)),
            ("GFORCE", forces(VectorForceKind::Gforce)),
            ("SPRINGDAMPER", self.spring_dampers.len()),
            ("BUSHING", self.bushings.len()),
            ("BEAM", self.beams.len()),
            ("FIELD", self.fields.len()),
            ("FRICTION", self.frictions.len()),
            ("VARIABLE", self.variables.len()),
            ("SPLINE", self.splines.len()),
            ("ARRAY", self.arrays.len()),
            ("REQUEST", self.requests.len()),
        ]
    }

    /// The PART with Adams id `id`.
    pub fn part(&self, id: Id) -> Option<&Part> {
        self.parts.iter().find(|p| p.el.id == id)
    }

    /// The MARKER with Adams id `id`.
    pub fn marker(&self, id: Id) -> Option<&Marker> {
        self.markers.iter().find(|m| m.el.id == id)
    }

    /// The JOINT with Adams id `id`.
    pub fn joint(&self, id: Id) -> Option<&Joint> {
        self.joints.iter().find(|j| j.el.id == id)
    }

    /// The VARIABLE with Adams id `id`.
    pub fn variable(&self, id: Id) -> Option<&Variable> {
        self.variables.iter().find(|v| v.el.id == id)
    }

    /// The value of VARIABLE/id when it is a design variable: its FUNCTION reads nothing
    /// (no TIME, measure, spline or other VARIABLE) and has a finite value, such as
    /// `VARIABLE/1, FUNCTION = 1E5`. Expressions read a design variable as an input of
    /// their compiled code, so a run can change its value without compiling again.
    pub fn design_value(&self, id: Id) -> Option<f64> {
        let f = &self.variable(id)?.function.function;
        let u = &f.uses;
        if u.time || u.mode || !u.vars.is_empty() || !u.measures.is_empty() || !u.splines.is_empty()
        {
            return None;
        }
        let value =
            crate::interp::Program::new(f.clone()).eval(&crate::context::Context::new(0.0, &[]));
        value.is_finite().then_some(value)
    }

    /// `e` with every `VARVAL(id)` replaced by the expression of VARIABLE/id, recursively
    /// ([`crate::ir::inline`]): VARIABLEs are algebraic, so their value at a state is their
    /// expression's there, and derivatives then come through them. A VARIABLE reading
    /// itself (Adams' implicit VARIABLE, solved iteratively there) is an error naming the
    /// chain; a VARVAL whose VARIABLE mbfx does not hold (a USER subroutine) is left as is,
    /// and so is a design variable's ([`Model::design_value`]), which the compiled code
    /// reads as an input.
    pub fn inline_variables(&self, e: &Expr) -> Result<Expr, String> {
        self.inline_variables_keeping(e, true)
    }

    /// [`Model::inline_variables`], with design variables inlined as constants too unless
    /// `keep_design`: a MOTION's drive is a function of time alone.
    pub fn inline_variables_keeping(&self, e: &Expr, keep_design: bool) -> Result<Expr, String> {
        let with = |slot: u32| {
            let id = self.varval_id(slot)?;
            if keep_design && self.design_value(id).is_some() {
                return None;
            }
            Some(&self.variable(id)?.function.function)
        };
        let function = crate::ir::inline::inline_measures(&e.function, &with).map_err(|err| {
            use crate::ir::inline::InlineError;
            match err {
                InlineError::Cycle(slots) => {
                    let mut chain: Vec<String> = slots
                        .iter()
                        .filter_map(|&s| self.measures.get(s as usize)?.ids.first().copied())
                        .map(|id| format!("VARIABLE/{id}"))
                        .collect();
                    chain.extend(chain.first().cloned());
                    format!(
                        "{}: an implicit VARIABLE (it reads itself), which mbfx does not solve",
                        chain.join(" → ")
                    )
                }
                InlineError::TooDeep => format!(
                    "VARIABLEs read VARIABLEs more than {} deep",
                    crate::ir::inline::MAX_INLINE_DEPTH
                ),
            }
        })?;
        Ok(Expr {
            span: e.span.clone(),
            function,
        })
    }

    /// The VARIABLE id of measure slot `slot` when it is a `VARVAL`.
    fn varval_id(&self, slot: u32) -> Option<Id> {
        let m = self.measures.get(slot as usize)?;
        if m.name != "VARVAL" {
            return None;
        }
        Id::try_from(*m.ids.first()?).ok()
    }

    /// The design variables the constraints read (GCONs, and MOTIONs, which take them
    /// as constants): changing one moves the assembled configuration.
    pub fn constraint_designs(&self) -> Vec<Id> {
        let mut ids = Vec::new();
        let functions = self.gcons.iter().map(|g| &g.function);
        for f in functions.chain(self.motions.iter().map(|m| &m.function)) {
            let Ok(e) = self.inline_variables(f) else {
                continue;
            };
            for id in e
                .function
                .uses
                .measures
                .iter()
                .filter_map(|&s| self.varval_id(s))
            {
                if self.design_value(id).is_some() && !ids.contains(&id) {
                    ids.push(id);
                }
            }
        }
        ids
    }

    /// The SPLINE with Adams id `id`.
    pub fn spline(&self, id: Id) -> Option<&SplineData> {
        self.splines.iter().find(|s| s.el.id == id)
    }

    /// The SPLINE data fitted for evaluation, in the order of [`Model::splines`], which is
    /// the order of the spline slots expressions read (AKISPL, CUBSPL). Fails on data the
    /// fits cannot take (fewer than 4 X values), naming the SPLINE.
    pub fn runtime_splines(&self) -> Result<Vec<mbfx_runtime::Spline>, String> {
        self.splines
            .iter()
            .map(|s| {
                let zs = if s.z.is_empty() {
                    vec![0.0]
                } else {
                    s.z.clone()
                };
                mbfx_runtime::Spline::new(s.x.clone(), zs, s.y.concat())
                    .map_err(|e| format!("{}: {e}", s.el.display("SPLINE")))
            })
            .collect()
    }

    /// The GROUND part (the reader has checked there is exactly one when it reports no
    /// errors).
    pub fn ground(&self) -> Option<&Part> {
        self.parts.iter().find(|p| p.ground)
    }

    /// A marker's global pose: origin and axes (columns) in ground (spec §2.3:
    /// R_G = R_part·R_marker, r_G = r_part + R_part·QP), at the dataset's initial
    /// configuration.
    pub fn marker_pose(&self, id: Id) -> Option<(Vec3, Mat3)> {
        let m = self.marker(id)?;
        let p = self.part(m.part)?;
        Some((
            p.position + p.orientation * m.position,
            p.orientation * m.orientation,
        ))
    }
}
