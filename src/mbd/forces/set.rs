//! The model's set of force elements: preparing it (the parts each reads, the order
//! elements that read each other's forces are evaluated in), fusing its expressions into
//! one call, and evaluating every element into Q.

use super::element::{ForceElement, ForceLaw};
use super::frame_cache::FrameCache;
use super::generalized::Generalized;
use super::inputs::{measure_value, Inputs, Source};
use super::law::Loads;
use super::order::order;
use crate::mbd::error::MbdError;
use crate::mbd::expr::FusedFn;
use crate::mbd::measures::{dual_frame, PartSlots};
use crate::mbd::output_slot::OutputSlot;
use crate::mbd::system::System;

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
    /// The CONTACT forces (issue 40), evaluated by the dynamics after the elements.
    pub contacts: crate::mbd::contacts::ContactSet,
    /// Every expression's value in one call, when the compiler fuses and no expression
    /// reads the solution ([`ForceSet::fuse`]).
    fused: Option<Fused>,
    /// The state elements (DIFF, LSE, TFSISO) whose values the forces may read: solved
    /// before the forces at each evaluation ([`crate::mbd::states`]).
    pub states: crate::mbd::states::StateSet,
    /// The value path's marker frames, each built once an evaluation (made by
    /// [`ForceSet::prepare`] for a fused set).
    pub(super) frames: Option<FrameCache>,
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
        match (&self.frames, jacobians) {
            (Some(cache), false) => cache.slot_values(sys, &fz.slots, vals),
            _ => {
                for &(slot, m) in &fz.slots {
                    vals[slot as usize] = measure_value(sys, m);
                }
            }
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
        self.contacts.switches(sys, out);
    }

    /// Whether an expression reads the solution (accelerations, reactions, forces).
    pub fn reads_solution(&self) -> bool {
        !self.solution.is_empty()
    }

    /// Whether a force law reads reactions with its derivative by them
    /// ([`Generalized::ds`]): joint friction.
    pub fn differentiates_reactions(&self) -> bool {
        (self.elements.iter()).any(|e| matches!(e.law, ForceLaw::Friction(_)))
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
        self.frames = self.fused.as_ref().map(|fz| {
            let ends: Vec<_> = self.elements.iter().map(|e| (Some(e.i), e.j)).collect();
            FrameCache::new(sys, &ends, &fz.slots)
        });
        self.loads = vec![Loads::default(); self.elements.len()];
        self.solved = vec![0.0; self.solution.len()];
        self.reads = self
            .elements
            .iter()
            .map(ForceElement::solution_reads)
            .collect();
        let n = self.elements.len();
        let deps: Vec<Vec<usize>> = (0..n).map(|k| depends_on(self, k)).collect();
        self.order = order(&deps).map_err(|circle| {
            let named = circle.iter().map(|&e| self.elements[e].elref.clone());
            MbdError::ForceCycle(named.collect())
        })?;
        Ok(())
    }

    /// Forgets the last evaluation's loads and solution values, as [`ForceSet::prepare`]
    /// leaves them: a run from the start of a set prepared before reads nothing of the
    /// last run.
    pub fn forget_state(&mut self) {
        self.loads = vec![Loads::default(); self.elements.len()];
        self.solved = vec![0.0; self.solution.len()];
        self.states.forget_state();
        self.contacts.forget_state();
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
        let n = self.elements.len();
        let cached = match (&mut self.frames, &self.fused, jacobians) {
            (Some(cache), Some(fz), false) if cache.fits(n, fz.slots.len()) => {
                cache.fill(sys);
                true
            }
            _ => false,
        };
        self.eval_fused(sys, jacobians);
        for k in 0..n {
            match cached {
                true => self.eval_element_cached(k, sys, out)?,
                false => self.eval_element(k, sys, out, jacobians)?,
            }
        }
        Ok(())
    }

    /// Element `k`'s values into `out` from the frame cache (filled at this state): what
    /// [`ForceSet::eval_element`] gives without Jacobians, its frames not rebuilt.
    fn eval_element_cached(
        &mut self,
        k: usize,
        sys: &System,
        out: &mut Generalized,
    ) -> Result<(), MbdError> {
        let friction = matches!(self.elements[k].law, ForceLaw::Friction(_));
        let (Some(cache), Some(fz), false) = (&self.frames, &self.fused, friction) else {
            return self.eval_element(k, sys, out, false);
        };
        let values = fz.values.borrow();
        let inputs = Inputs {
            solved: &self.solved,
            fused: Some(values.as_slice()),
            seed: None,
        };
        let el = &self.elements[k];
        let (fi, fj) = cache.ends(k);
        self.loads[k] = el.eval_framed::<f64>(sys, &inputs, out, (fi, fj), el.slots)?;
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
        let el = &self.elements[k];
        self.loads[k] = el.eval(sys, &inputs, out, jacobians)?;
        if let ForceLaw::Friction(law) = &el.law {
            law.reaction_partials(el, sys, &self.solved, out);
        }
        Ok(())
    }
}

/// The elements of `set` it reads the force of, for element `k` (after
/// [`ForceSet::reads`] is filled).
fn depends_on(set: &ForceSet, k: usize) -> Vec<usize> {
    let mut out = Vec::new();
    for &s in &set.reads[k] {
        match set.solution[s] {
            OutputSlot::ElementForce {
                constraint: false,
                element,
                ..
            } => out.push(element),
            OutputSlot::MarkerForce { i, j, .. } => {
                // Every force element acting between i and j, either way round
                // (as `Dynamics::marker_load` sums them).
                out.extend(set.elements.iter().enumerate().filter_map(|(e, el)| {
                    let between = (el.i == i && el.j == j) || (el.j == Some(i) && j == Some(el.i));
                    between.then_some(e)
                }));
            }
            _ => {}
        }
    }
    out
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
