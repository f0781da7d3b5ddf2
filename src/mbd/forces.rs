//! Applied forces (multibody spec §7): SFORCE (translational, rotational, ACTIONONLY),
//! VFORCE, VTORQUE, GFORCE, SPRINGDAMPER, BUSHING, and ACCGRAV with the units-consistency
//! factor. Each element is evaluated as duals (the `dual` module) over the local directions
//! of the parts it reads (its markers and the markers of the measures its expressions
//! read, one shared [`PartSlots`] table), so the generalized force Q and its exact
//! Jacobians ∂Q/∂q and ∂Q/∂v come out of one evaluation. Expression magnitudes enter with
//! their compiled gradient ∂f/∂measure chained with the measures' duals: no finite
//! differences.
//!
//! Generalized forces are per moving part at its reference point (the CM): the force F
//! and the moment about the CM, global axes; a force applied at a marker adds the moment
//! of its arm.
//!
//! An expression that calls IMPACT or BISTOP also carries their switching functions
//! ([`ContactProbe`]), which the step control watches ([`ForceSet::switches`]).
//!
//! An expression may also read what only the solution gives (Adams allows it): an
//! acceleration, a reaction, another force's value ([`Source::Solution`]). Those values
//! are filled in by the dynamics before each evaluation and held fixed within it (no
//! derivative), so the equations of motion solve them by iteration; forces that read
//! each other's values are evaluated in dependency order ([`ForceSet::order`]).

use super::dual::{Scalar as ScalarT, D, N, PER_PART, V};
use super::error::MbdError;
use super::expr::{ExprError, ExprFn, FusedFn};
use super::measure_set::{Measure, M};
use super::measures::{dual_frame, value_frame, Frame, PartSlots};
use super::output_slot::OutputSlot;
use super::system::{MarkerHandle, PartHandle, System};
use crate::vocab::elements::ElementRef;
use crate::vocab::math::{DVec, Vec3};
use contact::ContactProbe;

pub mod contact;
mod input_partials;

/// Where the value of an expression's slot comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Source {
    /// A kinematic measure (index into the system's measures): value and dual.
    Measure(usize),
    /// A value of the solution (index into [`ForceSet::solution`]): an acceleration, a
    /// reaction or a force, fixed within one evaluation.
    Solution(usize),
}

/// An expression of the model: `map[k]` is where its k-th slot is read from.
pub struct Scalar {
    /// The compiled expression with its gradient.
    pub f: Box<dyn ExprFn>,
    /// Where each slot of `f` is read from.
    pub map: Vec<Source>,
    /// Buffers of an evaluation (measure duals, gradient), reused; the slot values live
    /// in the system's one array ([`crate::mbd::system::ExprScratch`]).
    scratch: std::cell::RefCell<(Vec<D>, Vec<f64>)>,
    /// The switching functions of its contact calls, when it has any.
    probe: Option<ContactProbe>,
    /// Its IR, for [`ForceSet::fuse`] (None once fused or when not given).
    ir: Option<crate::ir::Function>,
    /// Its output in the set's fused evaluation, and where its value and partials
    /// start in the fused gradients ([`ForceSet::fuse`]).
    fused: Option<usize>,
    fused_gradient: Option<usize>,
}

impl Scalar {
    /// An expression reading its slots from `map`, with its buffers allocated.
    pub fn new(f: Box<dyn ExprFn>, map: Vec<Source>) -> Scalar {
        let n = map.len();
        Scalar {
            f,
            map,
            scratch: std::cell::RefCell::new((Vec::with_capacity(n), vec![0.0; n])),
            probe: None,
            ir: None,
            fused: None,
            fused_gradient: None,
        }
    }

    /// The same expression with its IR kept for [`ForceSet::fuse`].
    pub fn with_ir(mut self, function: crate::ir::Function) -> Scalar {
        self.ir = Some(function);
        self
    }

    /// The same expression with the switching functions of the IMPACT and BISTOP calls
    /// in `function`, its IR.
    pub fn watching(mut self, function: &crate::ir::Function) -> Scalar {
        self.probe = ContactProbe::of(function);
        self
    }

    /// Appends the switching values at the state of `sys` (nothing without contact
    /// calls); solution values are those of the last evaluation, `solved`.
    fn switches(&self, sys: &System, solved: &[f64], out: &mut Vec<f64>) {
        let Some(probe) = &self.probe else { return };
        let mut scratch = sys.scratch.borrow_mut();
        let vals = scratch.slots_to(self.f.slots().last().copied());
        for (&src, &slot) in self.map.iter().zip(self.f.slots()) {
            vals[slot as usize] = match src {
                Source::Measure(m) => measure_value(sys, m),
                Source::Solution(k) => solved[k],
            };
        }
        probe.eval(sys.time, vals, out);
    }

    /// The solution values it reads (indices into [`ForceSet::solution`]).
    fn solution_reads(&self) -> impl Iterator<Item = usize> + '_ {
        self.map.iter().filter_map(|s| match s {
            Source::Solution(k) => Some(*k),
            Source::Measure(_) => None,
        })
    }
}

/// Measure `m`'s value alone, unwrapped as its dual would be: plain numbers where the
/// dual carries a gradient over four parts (the same operations on the values).
pub(crate) fn measure_value(sys: &System, m: usize) -> f64 {
    sys.measures.unwrapped_value(sys, m)
}

/// How an element turns its inputs into loads.
pub enum ForceLaw {
    /// SFORCE TRANSLATION: f along the line from J to I at I (f > 0 pushes apart); the
    /// reaction at J unless action-only, where f acts along z_J at I alone.
    Line {
        /// The force magnitude.
        f: Scalar,
        /// ACTIONONLY: no reaction at J.
        action_only: bool,
    },
    /// SFORCE ROTATION: torque f·z_J on I's part, −f·z_J on J's unless action-only.
    Torque {
        /// The torque magnitude.
        f: Scalar,
        /// ACTIONONLY: no reaction on J's part.
        action_only: bool,
    },
    /// VFORCE, VTORQUE, GFORCE: components in RM axes at I; the reaction at the
    /// floating marker, which sits on I (no moment arm between them).
    Vector {
        /// FX FY FZ (None for a VTORQUE).
        force: Option<Box<[Scalar; 3]>>,
        /// TX TY TZ (None for a VFORCE).
        torque: Option<Box<[Scalar; 3]>>,
        /// RM: the frame the components are resolved in.
        rm: M,
    },
    /// SPRINGDAMPER TRANSLATION: f = −c·ḋ − k·(d − length) + preload along the line.
    Spring {
        /// K: stiffness.
        k: f64,
        /// C: damping.
        c: f64,
        /// LENGTH: free length.
        length: f64,
        /// FORCE: preload.
        preload: f64,
    },
    /// SPRINGDAMPER ROTATION: t = −c·θ̇ − k·(θ − angle) + preload about z_J, θ = AZ(I, J)
    /// (the measure `angle_measure`, unwrapped).
    RotSpring {
        /// KT: rotational stiffness.
        k: f64,
        /// CT: rotational damping.
        c: f64,
        /// ANGLE: free angle.
        angle: f64,
        /// TORQUE: preload.
        preload: f64,
        /// Index of the AZ(I, J) measure in the system's measures.
        angle_measure: usize,
    },
    /// BUSHING: per component in J axes, F = −K·d − C·ḋ + F₀ and T = −KT·θ − CT·ω + T₀
    /// with θ the AX, AY, AZ measures (`angles`), applied at I; the reaction on J.
    Bushing {
        /// K: stiffness per J axis.
        k: Vec3,
        /// C: damping per J axis.
        c: Vec3,
        /// KT: rotational stiffness per J axis.
        kt: Vec3,
        /// CT: rotational damping per J axis.
        ct: Vec3,
        /// FORCE: preload force per J axis.
        force: Vec3,
        /// TORQUE: preload torque per J axis.
        torque: Vec3,
        /// Indices of the AX, AY, AZ measures of I relative to J.
        angles: [usize; 3],
    },
}

/// One force element.
pub struct ForceElement {
    /// The Adams element, for messages and outputs.
    pub elref: ElementRef,
    /// The I marker, where the action applies.
    pub i: MarkerHandle,
    /// J, or JFLOAT for the vector forces.
    pub j: Option<MarkerHandle>,
    /// How the element computes its loads.
    pub law: ForceLaw,
    /// The parts the element's duals read (set by [`ForceSet::prepare`]).
    pub slots: PartSlots,
}

impl ForceElement {
    /// An element whose part slots [`ForceSet::prepare`] fills later.
    pub fn new(elref: ElementRef, i: MarkerHandle, j: Option<MarkerHandle>, law: ForceLaw) -> Self {
        ForceElement {
            elref,
            i,
            j,
            law,
            slots: PartSlots::default(),
        }
    }
}

/// The loads one element applies at a state, global axes: force and moment about the I
/// marker's origin on I's part; force and moment about the point `j_at` on J's part.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Loads {
    /// Force and moment on I's part.
    pub on_i: (Vec3, Vec3),
    /// Force and moment on J's part (about `j_at`).
    pub on_j: (Vec3, Vec3),
    /// The point J's moment is taken about, global coordinates.
    pub j_at: Vec3,
}

/// The model's applied forces and gravity.
#[derive(Default)]
pub struct ForceSet {
    /// The elements, in model order.
    pub elements: Vec<ForceElement>,
    /// The loads of each element at the last evaluation.
    pub loads: Vec<Loads>,
    /// The solution values the expressions read ([`Source::Solution`]), and their values
    /// at the last evaluation.
    pub solution: Vec<OutputSlot>,
    /// The values of `solution` at the last evaluation.
    pub solved: Vec<f64>,
    /// Each solution value as the expression wrote it (`JOINT(1, 0, 2, 0)`).
    pub names: Vec<String>,
    /// Per element, the solution values its expressions read.
    pub reads: Vec<Vec<usize>>,
    /// The order of evaluation: an element reading another's force comes after it.
    pub order: Vec<usize>,
    /// Every expression's value in one call, when the compiler fuses and no expression
    /// reads the solution ([`ForceSet::fuse`]).
    fused: Option<Fused>,
}

/// What an element's expressions read besides the state: the solution values
/// ([`ForceSet::solved`]) and the set's fused values at this state, when it has them.
struct Inputs<'a> {
    solved: &'a [f64],
    /// The fused values, or with Jacobians the fused values and partials.
    fused: Option<&'a [f64]>,
    /// The design variable an input-partials evaluation differentiates along
    /// ([`ForceSet::input_partials`]).
    seed: Option<i64>,
}

/// The fused evaluation of a set's expressions: the function of their values and, when
/// every one has a derivative, the function of their values and partials (f, ∂f/∂slot,
/// ∂f/∂t each); the (slot, measure) pairs they read (each filled once a state); and
/// their outputs at the last evaluation.
struct Fused {
    f: Box<dyn FusedFn>,
    gradients: Option<Box<dyn FusedFn>>,
    slots: Vec<(u32, usize)>,
    values: std::cell::RefCell<Vec<f64>>,
    partials: std::cell::RefCell<Vec<f64>>,
}

/// Q and its Jacobians over velocity-level columns: `dq` holds ∂Q/∂q, `dv` ∂Q/∂v as
/// (row, column, value) entries (repeats add up).
#[derive(Clone, Debug, Default)]
pub struct Generalized {
    /// Q: the generalized force per velocity-level column.
    pub q: DVec,
    /// ∂Q/∂q entries (row, column, value).
    pub dq: Vec<(usize, usize, f64)>,
    /// ∂Q/∂v entries (row, column, value).
    pub dv: Vec<(usize, usize, f64)>,
}

impl Generalized {
    /// A zero Q of `n` columns with no Jacobian entries.
    pub fn new(n: usize) -> Self {
        Generalized {
            q: DVec::zeros(n),
            dq: Vec::new(),
            dv: Vec::new(),
        }
    }

    /// Zeroes Q and drops the Jacobian entries, keeping the capacity.
    pub fn clear(&mut self) {
        self.q.fill(0.0);
        self.dq.clear();
        self.dv.clear();
    }
}

/// A dual from a value and its gradient.
fn dual(v: f64, g: [f64; N]) -> D {
    D { v, g }
}

fn scale_v<T: ScalarT>(v: &V<T>, s: T) -> V<T> {
    V([v.0[0] * s, v.0[1] * s, v.0[2] * s])
}

fn add_v<T: ScalarT>(a: &V<T>, b: &V<T>) -> V<T> {
    V([a.0[0] + b.0[0], a.0[1] + b.0[1], a.0[2] + b.0[2]])
}

fn neg_v<T: ScalarT>(a: &V<T>) -> V<T> {
    V([-a.0[0], -a.0[1], -a.0[2]])
}

/// Σ xₖ·axisₖ: components in a frame's axes to global.
fn in_axes<T: ScalarT>(axes: &[V<T>; 3], x: [T; 3]) -> V<T> {
    let mut out = scale_v(&axes[0], x[0]);
    for k in 1..3 {
        out = add_v(&out, &scale_v(&axes[k], x[k]));
    }
    out
}

/// The numbers a force element is evaluated in: duals over its part slots (value and
/// ∂/∂q, ∂/∂v) when the Jacobians are asked for, plain values otherwise. Both run the
/// same operations on the values, so they agree bit for bit.
trait Num: ScalarT {
    fn scale(self, s: f64) -> Self;
    /// Marker `mk`'s frame (ground when None), extending `slots` with its part.
    fn frame(sys: &System, mk: M, slots: &mut PartSlots) -> Frame<Self>;
    /// Measure `m` (in the parts of `slots`, which it extends).
    fn measure(sys: &System, m: usize, slots: &mut PartSlots) -> Self;
    /// The reference point of `part`.
    fn reference(sys: &System, part: PartHandle, slots: &PartSlots) -> V<Self>;
    /// Expression `s` of element `el` (solution and fused values from `inputs`).
    fn expression(
        el: &ForceElement,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
        slots: &mut PartSlots,
    ) -> Result<Self, MbdError>;
    /// Adds `x` to row `row` of Q (and its derivatives to Q's Jacobians).
    fn load(x: &Self, row: usize, sys: &System, slots: &PartSlots, out: &mut Generalized);
}

impl Num for D {
    fn scale(self, s: f64) -> D {
        D::scale(self, s)
    }

    fn frame(sys: &System, mk: M, slots: &mut PartSlots) -> Frame<D> {
        dual_frame(sys, mk, slots).expect("prepared")
    }

    fn measure(sys: &System, m: usize, slots: &mut PartSlots) -> D {
        sys.measures.eval_in(sys, m, slots).expect("prepared")
    }

    fn reference(sys: &System, part: PartHandle, slots: &PartSlots) -> V<D> {
        let mut p: V = V::c(sys.part(part).r);
        if let Some(s) = slots.parts.iter().position(|x| *x == Some(part)) {
            for c in 0..3 {
                p.0[c].g[PER_PART * s + c] = 1.0;
            }
        }
        p
    }

    fn expression(
        el: &ForceElement,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
        slots: &mut PartSlots,
    ) -> Result<D, MbdError> {
        el.scalar_dual(sys, inputs, s, slots)
    }

    fn load(x: &D, row: usize, sys: &System, slots: &PartSlots, out: &mut Generalized) {
        out.q[row] += x.v;
        slots.scatter(
            sys,
            &x.g,
            &mut |col, g| out.dq.push((row, col, g)),
            &mut |col, g| out.dv.push((row, col, g)),
        );
    }
}

impl Num for f64 {
    fn scale(self, s: f64) -> f64 {
        self * s
    }

    fn frame(sys: &System, mk: M, _: &mut PartSlots) -> Frame<f64> {
        value_frame(sys, mk)
    }

    fn measure(sys: &System, m: usize, _: &mut PartSlots) -> f64 {
        measure_value(sys, m)
    }

    fn reference(sys: &System, part: PartHandle, _: &PartSlots) -> V<f64> {
        V::c(sys.part(part).r)
    }

    fn expression(
        el: &ForceElement,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
        _: &mut PartSlots,
    ) -> Result<f64, MbdError> {
        el.scalar_value(sys, inputs, s)
    }

    fn load(x: &f64, row: usize, _: &System, _: &PartSlots, out: &mut Generalized) {
        out.q[row] += x;
    }
}

impl ForceSet {
    /// Fuses every expression's value into one function of `exprs` (when it fuses and no
    /// expression reads the solution, whose values are filled in element by element):
    /// the values without Jacobians then come from one call a state, the measures it
    /// reads filled once.
    pub fn fuse(&mut self, exprs: &dyn crate::mbd::expr::ExprCompiler) {
        if self.reads_solution() {
            return;
        }
        let mut functions = Vec::new();
        let mut slots = Vec::new();
        for s in self.elements.iter().flat_map(|e| e.expressions()) {
            let Some(ir) = &s.ir else { return };
            functions.push(ir);
            for (&src, &slot) in s.map.iter().zip(s.f.slots()) {
                if let Source::Measure(m) = src {
                    slots.push((slot, m));
                }
            }
        }
        if functions.is_empty() {
            return;
        }
        let Some(f) = exprs.fuse(&functions) else {
            return;
        };
        // The partials in the slots each expression reads, then TIME (as its own
        // compiled gradient has them).
        let (gradients, offsets, width) = match crate::mbd::expr::fuse_partials(exprs, &functions) {
            Some((g, o, w)) => (Some(g), o, w),
            None => (None, Vec::new(), 0),
        };
        slots.sort_unstable();
        slots.dedup();
        let count = functions.len();
        let fused_gradients = gradients.is_some();
        for (k, s) in self
            .elements
            .iter_mut()
            .flat_map(|e| e.expressions_mut())
            .enumerate()
        {
            (s.fused, s.ir) = (Some(k), None);
            s.fused_gradient = fused_gradients.then(|| offsets[k]);
        }
        self.fused = Some(Fused {
            f,
            gradients,
            slots,
            values: std::cell::RefCell::new(vec![0.0; count]),
            partials: std::cell::RefCell::new(vec![0.0; width]),
        });
    }

    /// Every fused value (with `jacobians`, every value and partial) at the state of
    /// `sys` (nothing when the set is not fused).
    fn eval_fused(&self, sys: &System, jacobians: bool) {
        let Some(fz) = &self.fused else { return };
        let mut shared = sys.scratch.borrow_mut();
        let vals = shared.slots_to(fz.slots.last().map(|s| s.0));
        for &(slot, m) in &fz.slots {
            vals[slot as usize] = measure_value(sys, m);
        }
        match (jacobians, &fz.gradients) {
            (false, _) => fz.f.eval_into(sys.time, vals, &mut fz.values.borrow_mut()),
            (true, Some(g)) => g.eval_into(sys.time, vals, &mut fz.partials.borrow_mut()),
            (true, None) => {}
        }
    }

    /// How many compiled expressions one evaluation of every element runs.
    pub fn expression_count(&self) -> usize {
        self.elements.iter().map(|e| e.expressions().count()).sum()
    }

    /// Appends the switching values of every expression's contact calls at the state of
    /// `sys`, in a fixed order (positive where a branch acts, NaN where a switch means
    /// nothing there).
    pub fn switches(&self, sys: &System, out: &mut Vec<f64>) {
        for el in &self.elements {
            for s in el.expressions() {
                s.switches(sys, &self.solved, out);
            }
        }
    }

    /// Whether an expression reads the solution (accelerations, reactions, forces).
    pub fn reads_solution(&self) -> bool {
        !self.solution.is_empty()
    }

    /// Records the parts each element reads: its markers and its measures' markers.
    pub fn prepare(&mut self, sys: &System) -> Result<(), MbdError> {
        for el in &mut self.elements {
            let mut slots = PartSlots::default();
            let fits = dual_frame(sys, Some(el.i), &mut slots).is_some()
                && dual_frame(sys, el.j, &mut slots).is_some()
                && el
                    .measures()
                    .iter()
                    .all(|&m| sys.measures.eval_in(sys, m, &mut slots).is_some())
                && match &el.law {
                    ForceLaw::Vector { rm, .. } => dual_frame(sys, *rm, &mut slots).is_some(),
                    _ => true,
                };
            if !fits {
                return Err(MbdError::TooManyParts(el.elref.clone()));
            }
            el.slots = slots;
        }
        self.loads = vec![Loads::default(); self.elements.len()];
        self.solved = vec![0.0; self.solution.len()];
        self.reads = self
            .elements
            .iter()
            .map(|el| {
                let mut r: Vec<usize> = el.expressions().flat_map(|s| s.solution_reads()).collect();
                r.sort_unstable();
                r.dedup();
                r
            })
            .collect();
        self.order = super::force_order::order(self)?;
        Ok(())
    }

    /// Forgets the last evaluation's loads and solution values, as [`ForceSet::prepare`]
    /// leaves them: a run from the start of a set prepared before reads nothing of the
    /// last run.
    pub fn forget_state(&mut self) {
        self.loads = vec![Loads::default(); self.elements.len()];
        self.solved = vec![0.0; self.solution.len()];
    }

    /// Adds every element's generalized forces (and, with `jacobians`, their ∂/∂q and
    /// ∂/∂v) to `out`; gravity is added by the caller (it has no Jacobian). Solution
    /// values are those in [`ForceSet::solved`].
    pub fn eval(
        &mut self,
        sys: &System,
        out: &mut Generalized,
        jacobians: bool,
    ) -> Result<(), MbdError> {
        self.eval_fused(sys, jacobians);
        for k in 0..self.elements.len() {
            self.eval_element(k, sys, out, jacobians)?;
        }
        Ok(())
    }

    /// Element `k`'s share of [`ForceSet::eval`].
    pub fn eval_element(
        &mut self,
        k: usize,
        sys: &System,
        out: &mut Generalized,
        jacobians: bool,
    ) -> Result<(), MbdError> {
        let fused = match (&self.fused, jacobians) {
            (Some(fz), false) => Some(fz.values.borrow()),
            (Some(fz), true) if fz.gradients.is_some() => Some(fz.partials.borrow()),
            _ => None,
        };
        let inputs = Inputs {
            solved: &self.solved,
            fused: fused.as_deref().map(Vec::as_slice),
            seed: None,
        };
        self.loads[k] = self.elements[k].eval(sys, &inputs, out, jacobians)?;
        Ok(())
    }
}

impl ForceElement {
    /// The element's expressions.
    pub fn expressions(&self) -> impl Iterator<Item = &Scalar> {
        let (one, three) = match &self.law {
            ForceLaw::Line { f, .. } | ForceLaw::Torque { f, .. } => (Some(f), None),
            ForceLaw::Vector { force, torque, .. } => (None, Some((force, torque))),
            _ => (None, None),
        };
        let three = three
            .into_iter()
            .flat_map(|(f, t)| f.iter().chain(t.iter()).flat_map(|b| b.iter()));
        one.into_iter().chain(three)
    }

    /// The element's expressions, mutable, in the order of [`ForceElement::expressions`].
    fn expressions_mut(&mut self) -> impl Iterator<Item = &mut Scalar> {
        let (one, three) = match &mut self.law {
            ForceLaw::Line { f, .. } | ForceLaw::Torque { f, .. } => (Some(f), None),
            ForceLaw::Vector { force, torque, .. } => (None, Some((force, torque))),
            _ => (None, None),
        };
        let three = three
            .into_iter()
            .flat_map(|(f, t)| f.iter_mut().chain(t.iter_mut()).flat_map(|b| b.iter_mut()));
        one.into_iter().chain(three)
    }

    /// The measures the element's expressions and laws read.
    fn measures(&self) -> Vec<usize> {
        let mut out: Vec<usize> = self
            .expressions()
            .flat_map(|s| s.map.iter())
            .filter_map(|s| match s {
                Source::Measure(m) => Some(*m),
                Source::Solution(_) => None,
            })
            .collect();
        match &self.law {
            ForceLaw::RotSpring { angle_measure, .. } => out.push(*angle_measure),
            ForceLaw::Bushing { angles, .. } => out.extend_from_slice(angles),
            _ => {}
        }
        out
    }

    /// An expression's value alone: the set's fused evaluation's when there is one, else
    /// from the measures' values (no duals, no gradient; solution values from `inputs`).
    fn scalar_value(&self, sys: &System, inputs: &Inputs, s: &Scalar) -> Result<f64, MbdError> {
        if let (Some(k), Some(values)) = (s.fused, inputs.fused) {
            let v = values[k];
            return match v.is_finite() {
                true => Ok(v),
                false => Err(MbdError::Expression(
                    self.elref.clone(),
                    ExprError::NotFinite {
                        value: v,
                        time: sys.time,
                    },
                )),
            };
        }
        self.with_slot_values(sys, inputs, s, |vals| s.f.value(sys.time, vals))
    }

    /// `f` of the slot values of expression `s` from the measures' values (solution
    /// values from `inputs`), its error named after the element.
    fn with_slot_values<R>(
        &self,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
        f: impl FnOnce(&[f64]) -> Result<R, ExprError>,
    ) -> Result<R, MbdError> {
        let slot_ids = s.f.slots();
        let mut shared = sys.scratch.borrow_mut();
        let vals = shared.slots_to(slot_ids.last().copied());
        for (&src, &slot) in s.map.iter().zip(slot_ids) {
            vals[slot as usize] = match src {
                Source::Measure(m) => measure_value(sys, m),
                Source::Solution(k) => inputs.solved[k],
            };
        }
        f(vals).map_err(|why| MbdError::Expression(self.elref.clone(), why))
    }

    /// An expression's value as a dual: f with ∂f/∂measure chained through the
    /// measures' duals (solution values from `solved`, constant).
    fn scalar_dual(
        &self,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
        slots: &mut PartSlots,
    ) -> Result<D, MbdError> {
        let (solved, fused) = (inputs.solved, inputs.fused);
        let slot_ids = s.f.slots();
        let mut shared = sys.scratch.borrow_mut();
        let vals = shared.slots_to(slot_ids.last().copied());
        let err = |why| MbdError::Expression(self.elref.clone(), why);
        let mut scratch = s.scratch.borrow_mut();
        let (duals, grad) = &mut *scratch;
        duals.clear();
        for (&src, &slot) in s.map.iter().zip(slot_ids) {
            let d = match src {
                Source::Measure(m) => sys
                    .measures
                    .eval_in(sys, m, slots)
                    .ok_or_else(|| MbdError::TooManyParts(self.elref.clone()))?,
                Source::Solution(k) => D::c(solved[k]),
            };
            vals[slot as usize] = d.v;
            duals.push(d);
        }
        let v = match (s.fused_gradient, fused) {
            // The set's one call computed f and its partials at this state.
            (Some(at), Some(out)) => {
                let k = duals.len();
                let finite = |x: f64| match x.is_finite() {
                    true => Ok(x),
                    false => Err(err(ExprError::NotFinite {
                        value: x,
                        time: sys.time,
                    })),
                };
                for (g, &x) in grad.iter_mut().zip(&out[at + 1..=at + k]) {
                    *g = finite(x)?;
                }
                finite(out[at + k + 1])?;
                finite(out[at])?
            }
            _ => s.f.value_gradient(sys.time, vals, grad).map_err(err)?.0,
        };
        let mut g = [0.0; N];
        for (d, &c) in duals.iter().zip(grad.iter()) {
            if c != 0.0 {
                for (x, y) in g.iter_mut().zip(d.g.iter()) {
                    *x += c * y;
                }
            }
        }
        Ok(dual(v, g))
    }

    /// Adds the element's generalized forces to `out` (with ∂/∂q and ∂/∂v when
    /// `jacobians`) and returns its loads.
    fn eval(
        &self,
        sys: &System,
        inputs: &Inputs,
        out: &mut Generalized,
        jacobians: bool,
    ) -> Result<Loads, MbdError> {
        match jacobians {
            true => self.eval_as::<D>(sys, inputs, out),
            false => self.eval_as::<f64>(sys, inputs, out),
        }
    }

    fn eval_as<T: Num>(
        &self,
        sys: &System,
        inputs: &Inputs,
        out: &mut Generalized,
    ) -> Result<Loads, MbdError> {
        let mut slots = self.slots;
        let fi = T::frame(sys, Some(self.i), &mut slots);
        let fj = T::frame(sys, self.j, &mut slots);
        let zero: V<T> = V::c(Vec3::zeros());
        // (force at I, moment on I's part, force on J's part, moment on J's part), all
        // applied at I's origin except the line forces' reaction at J's.
        let (f_i, t_i, f_j, t_j, j_at_i) = match &self.law {
            ForceLaw::Line { f, action_only } => {
                let f = T::expression(self, sys, inputs, f, &mut slots)?;
                if *action_only {
                    (scale_v(&fj.axes[2], f), zero, zero, zero, true)
                } else {
                    let d = fi.r.sub(&fj.r);
                    let u = scale_v(&d, d.norm().recip());
                    let fv = scale_v(&u, f);
                    (fv, zero, neg_v(&fv), zero, false)
                }
            }
            ForceLaw::Torque { f, action_only } => {
                let f = T::expression(self, sys, inputs, f, &mut slots)?;
                let t = scale_v(&fj.axes[2], f);
                let tj = if *action_only { zero } else { neg_v(&t) };
                (zero, t, zero, tj, true)
            }
            ForceLaw::Vector { force, torque, rm } => {
                let frm = T::frame(sys, *rm, &mut slots);
                let comps = |xs: &Option<Box<[Scalar; 3]>>, slots: &mut PartSlots| match xs {
                    None => Ok(zero),
                    Some(xs) => {
                        let mut c = [T::c(0.0); 3];
                        for (k, x) in xs.iter().enumerate() {
                            c[k] = T::expression(self, sys, inputs, x, slots)?;
                        }
                        Ok::<V<T>, MbdError>(in_axes(&frm.axes, c))
                    }
                };
                let fv = comps(force, &mut slots)?;
                let tv = comps(torque, &mut slots)?;
                (fv, tv, neg_v(&fv), neg_v(&tv), true)
            }
            ForceLaw::Spring {
                k,
                c,
                length,
                preload,
            } => {
                let d = fi.r.sub(&fj.r);
                let len = d.norm();
                let u = scale_v(&d, len.recip());
                let rate = fi.vel.sub(&fj.vel).dot(&u);
                let f = rate.scale(-c) + (len - T::c(*length)).scale(-k) + T::c(*preload);
                let fv = scale_v(&u, f);
                (fv, zero, neg_v(&fv), zero, false)
            }
            ForceLaw::RotSpring {
                k,
                c,
                angle,
                preload,
                angle_measure,
            } => {
                let th = T::measure(sys, *angle_measure, &mut slots);
                let z = fj.axes[2];
                let rate = fi.w.sub(&fj.w).dot(&z);
                let t = rate.scale(-c) + (th - T::c(*angle)).scale(-k) + T::c(*preload);
                let tv = scale_v(&z, t);
                (zero, tv, zero, neg_v(&tv), true)
            }
            ForceLaw::Bushing {
                k,
                c,
                kt,
                ct,
                force,
                torque,
                angles,
            } => {
                let d = fi.r.sub(&fj.r);
                // Velocity of I relative to J as seen in J's frame.
                let vel = fi.vel.sub(&fj.vel).sub(&fj.w.cross(&d));
                let w = fi.w.sub(&fj.w);
                let mut fc = [T::c(0.0); 3];
                let mut tc = [T::c(0.0); 3];
                for a in 0..3 {
                    let ax = &fj.axes[a];
                    let th = T::measure(sys, angles[a], &mut slots);
                    fc[a] = d.dot(ax).scale(-k[a]) + vel.dot(ax).scale(-c[a]) + T::c(force[a]);
                    tc[a] = th.scale(-kt[a]) + w.dot(ax).scale(-ct[a]) + T::c(torque[a]);
                }
                let fv = in_axes(&fj.axes, fc);
                let tv = in_axes(&fj.axes, tc);
                (fv, tv, neg_v(&fv), neg_v(&tv), true)
            }
        };
        let pi = sys.marker(self.i).part;
        let pj = self.j.map_or(System::GROUND, |j| sys.marker(j).part);
        let at_j = if j_at_i { &fi } else { &fj };
        self.apply(sys, &slots, pi, &fi, &f_i, &t_i, out);
        self.apply(sys, &slots, pj, at_j, &f_j, &t_j, out);
        Ok(Loads {
            on_i: (f_i.value(), t_i.value()),
            on_j: (f_j.value(), t_j.value()),
            j_at: at_j.r.value(),
        })
    }

    /// Adds force `f` applied at frame `at`'s origin and moment `t` to part `part`'s
    /// generalized force (moment about its reference point), with Jacobians when `T`
    /// carries them.
    #[allow(clippy::too_many_arguments)]
    fn apply<T: Num>(
        &self,
        sys: &System,
        slots: &PartSlots,
        part: PartHandle,
        at: &Frame<T>,
        f: &V<T>,
        t: &V<T>,
        out: &mut Generalized,
    ) {
        if sys.part(part).index.is_none() {
            return;
        }
        let arm = at.r.sub(&T::reference(sys, part, slots));
        let m = add_v(t, &arm.cross(f));
        for c in 0..6 {
            let Some(row) = sys.col(part, c) else {
                continue;
            };
            let q = if c < 3 { f.0[c] } else { m.0[c - 3] };
            T::load(&q, row, sys, slots, out);
        }
    }
}

/// The angle measure a rotational element reads: AX, AY or AZ of I relative to J.
pub fn angle_of(i: MarkerHandle, j: Option<MarkerHandle>, axis: u8) -> Measure {
    Measure::Angle {
        i: Some(i),
        j,
        axis,
    }
}

#[cfg(test)]
mod tests {
    //! Every force law's Q against its own definition at a known state, and its exact
    //! Jacobians against central differences of Q (the test oracle DESIGN.md allows).
    use crate::mbd::compiled::CompiledExprs;
    use crate::mbd::dynamics::Dynamics;
    use crate::mbd::planar::Dim;
    use crate::mbd::system::System;
    use crate::model::read_model;
    use crate::vocab::math::DVec;

    /// Two free parts in 3D, every force kind between them.
    const FORCES: &str = "forces\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 2, CM = 20, IP = 1, 2, 3, QG = 0.1, 0.2, 0.3, REULER = 10D, 20D, 30D, VX = 0.3, WZ = 0.7\n\
        MARKER/20, PART = 2\nMARKER/21, PART = 2, QP = 0.5, -0.2, 0.1, REULER = 5D, 10D, 15D\n\
        PART/3, MASS = 1, CM = 30, IP = 1, 1, 1, QG = 1.1, 0.4, -0.2, WX = -0.4, VY = 0.2\n\
        MARKER/30, PART = 3\nMARKER/31, PART = 3, QP = -0.3, 0.2, 0.0, REULER = 0, 12D, 0\n\
        MARKER/32, PART = 3, FLOATING\n\
        SFORCE/1, TRANSLATION, I = 21, J = 31, FUNCTION = -50*(DM(21,31) - 1) - 3*VR(21,31) + 0.1*TIME\n\
        SFORCE/2, ROTATION, I = 21, J = 31, FUNCTION = -4*AZ(21,31) - 0.5*WZ(21,31,31)\n\
        SFORCE/3, TRANSLATION, ACTIONONLY, I = 31, J = 21, FUNCTION = DX(31,21)*DY(21,31)\n\
        SPRINGDAMPER/1, TRANSLATION, I = 21, J = 31, K = 30, C = 2, LENGTH = 0.8, FORCE = 1\n\
        SPRINGDAMPER/2, ROTATION, I = 21, J = 31, KT = 5, CT = 0.3, ANGLE = 0.1, TORQUE = 0.2\n\
        BUSHING/1, I = 21, J = 31, K = 10, 20, 30, C = 1, 2, 3, KT = 4, 5, 6, CT = 0.1, 0.2, 0.3, FORCE = 0.1, 0.2, 0.3, TORQUE = 0.01, 0.02, 0.03\n\
        GFORCE/1, I = 21, JFLOAT = 32, RM = 31, FX = VX(21,31)\\ FY = 2*DZ(21,31)\\ FZ = 1\\ TX = WX(21,31)\\ TY = 0.5\\ TZ = DM(21,31)\\\n\
        END\n";

    fn dynamics() -> Dynamics {
        let read = read_model(FORCES);
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        let exprs = CompiledExprs::new();
        let mut sys = System::from_model(&read.model, Dim::Three, &exprs).unwrap();
        sys.time = 0.3;
        let forces = sys.forces_from_model(&read.model, &exprs).unwrap();
        assert_eq!(forces.elements.len(), 7);
        Dynamics::new(sys, forces, &[]).unwrap()
    }

    fn q_of(d: &mut Dynamics) -> DVec {
        d.eval_forces(false).unwrap();
        d.gen.q.clone()
    }

    /// Column `c` of the Jacobian `k` against the central difference of Q from the
    /// states `up` and `down`, ±h apart in coordinate `what` c.
    fn column_matches(k: &[Vec<f64>], c: usize, up: &DVec, down: &DVec, h: f64, what: &str) {
        for (r, row) in k.iter().enumerate() {
            let fd = (up[r] - down[r]) / (2.0 * h);
            assert!(
                (row[c] - fd).abs() < 1e-5 * (1.0 + fd.abs()),
                "dQ{r}/d{what}{c}: {} vs {fd}",
                row[c]
            );
        }
    }

    #[test]
    fn force_jacobians_match_central_differences() {
        let mut d = dynamics();
        d.eval_forces(true).unwrap();
        let n = d.n;
        let (mut kq, mut kv) = (vec![vec![0.0; n]; n], vec![vec![0.0; n]; n]);
        for &(r, c, x) in &d.gen.dq {
            kq[r][c] += x;
        }
        for &(r, c, x) in &d.gen.dv {
            kv[r][c] += x;
        }
        let base = d.snapshot();
        let v0 = d.sys.v();
        let h = 1e-6;
        for c in 0..n {
            let mut dx = vec![0.0; n];
            let mut at = |s: f64, d: &mut Dynamics| {
                dx[c] = s * h;
                d.set_state(&base, &dx, &v0, 0.3);
                q_of(d)
            };
            let (up, down) = (at(1.0, &mut d), at(-1.0, &mut d));
            column_matches(&kq, c, &up, &down, h, "q");
            let mut v = v0.clone();
            v[c] += h;
            d.set_state(&base, &vec![0.0; n], &v, 0.3);
            let up = q_of(&mut d);
            v[c] -= 2.0 * h;
            d.set_state(&base, &vec![0.0; n], &v, 0.3);
            let down = q_of(&mut d);
            column_matches(&kv, c, &up, &down, h, "v");
        }
    }

    #[test]
    fn action_reaction_forces_balance() {
        // Without gravity and with only action-reaction elements between parts 2 and 3
        // (SFORCE/3 acts on I alone, so leave it out), the total force and the total
        // moment about the origin vanish.
        let text = FORCES.replace(
            "SFORCE/3, TRANSLATION, ACTIONONLY, I = 31, J = 21, FUNCTION = DX(31,21)*DY(21,31)\n",
            "",
        );
        let read = read_model(&text);
        let exprs = CompiledExprs::new();
        let mut sys = System::from_model(&read.model, Dim::Three, &exprs).unwrap();
        let forces = sys.forces_from_model(&read.model, &exprs).unwrap();
        let mut d = Dynamics::new(sys, forces, &[]).unwrap();
        d.eval_forces(false).unwrap();
        let (mut f, mut m) = (
            crate::vocab::math::Vec3::zeros(),
            crate::vocab::math::Vec3::zeros(),
        );
        for p in d.sys.parts.iter().filter(|p| p.index.is_some()) {
            let b = 6 * p.index.unwrap();
            let fp = crate::vocab::math::Vec3::new(d.gen.q[b], d.gen.q[b + 1], d.gen.q[b + 2]);
            let tp = crate::vocab::math::Vec3::new(d.gen.q[b + 3], d.gen.q[b + 4], d.gen.q[b + 5]);
            // Remove the gyroscopic moment −ω × (J ω), which is no applied force.
            let j = p.inertia_global();
            let gyro = -p.w.cross(&(j * p.w));
            f += fp;
            m += tp - gyro + p.r.cross(&fp);
        }
        assert!(f.norm() < 1e-12 && m.norm() < 1e-12, "{f} {m}");
    }
}

#[cfg(test)]
mod fused_tests {
    //! The fused evaluation ([`super::ForceSet::fuse`]) against each expression on its
    //! own: the same values, bit for bit, from one call.
    use super::*;
    use crate::mbd::compiled::CompiledExprs;
    use crate::mbd::expr::InterpretOnly;
    use crate::mbd::planar::Dim;
    use crate::model::read_model;

    const MODEL: &str = "fused\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        MARKER/11, PART = 1, FLOATING\n\
        PART/2, MASS = 2, CM = 20, IP = 1, 2, 3, QG = 0.1, 0.2, 0.3, VX = 0.3, WZ = 0.7\n\
        MARKER/20, PART = 2\n\
        SFORCE/1, TRANSLATION, I = 20, J = 10, FUNCTION = -50*(DM(20,10) - 1) - 3*VR(20,10)\n\
        SFORCE/2, ROTATION, I = 20, J = 10, FUNCTION = IMPACT(DX(20,10), VX(20,10), 0.5, 1E4, 1.5, 10, 0.1)\n\
        GFORCE/1, I = 20, JFLOAT = 11, RM = 10, FX = VX(20,10)\\ FY = 2*DZ(20,10)\\ FZ = SIN(TIME)\\ TX = WX(20,10)\\ TY = 0.5\\ TZ = DM(20,10)\\\n\
        END\n";

    /// Q (and with `jacobians` its Jacobian entries) as bits, the set fused when `fuse`
    /// (and the compiler fuses).
    fn q(exprs: &dyn crate::mbd::expr::ExprCompiler, fuse: bool, jacobians: bool) -> Vec<u64> {
        let read = read_model(MODEL);
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        let mut sys = System::from_model(&read.model, Dim::Three, exprs).unwrap();
        sys.time = 0.3;
        let mut forces = sys.forces_from_model(&read.model, exprs).unwrap();
        if !fuse {
            forces.fused = None;
        }
        forces.prepare(&sys).unwrap();
        let mut out = Generalized::new(sys.ncols());
        forces.eval(&sys, &mut out, jacobians).unwrap();
        let entries = out.dq.iter().chain(&out.dv).map(|e| e.2);
        out.q
            .iter()
            .copied()
            .chain(entries)
            .map(f64::to_bits)
            .collect()
    }

    #[test]
    fn fused_values_and_partials_are_each_expressions_own() {
        // CompiledExprs fuses values and partials (JIT and interpreter alike);
        // InterpretOnly does not fuse (and has no partials).
        let read = read_model(MODEL);
        let mut sys = System::from_model(&read.model, Dim::Three, &InterpretOnly).unwrap();
        let forces = sys.forces_from_model(&read.model, &InterpretOnly).unwrap();
        assert!(forces.fused.is_none());
        let fused = sys
            .forces_from_model(&read.model, &CompiledExprs::new())
            .unwrap();
        assert!(fused.fused.as_ref().is_some_and(|f| f.gradients.is_some()));
        let alone = q(&InterpretOnly, false, false);
        for exprs in [CompiledExprs::new(), CompiledExprs::interpreted()] {
            assert_eq!(q(&exprs, true, false), alone);
            assert_eq!(q(&exprs, true, true), q(&exprs, false, true));
        }
    }
}
