//! The system in motion ([`Dynamics`]) and its construction: the kept and dropped
//! constraint rows, the parts each row reads ([`row_parts`]), the Newton matrix's
//! pattern and factors, the rows' resolved primitives, the constant mass blocks.

use super::blocks::Mat3Block;
use super::failure::DynError;
use super::resolved::{self, ResolvedRow};
use super::stats::Stats;
use super::workspace::{Factors, Scratch};
use super::{fill, jacobian, schur};
use crate::mbd::constraints::Primitive;
use crate::mbd::forces::{ForceSet, Generalized};
use crate::mbd::rows::Row;
use crate::mbd::sparse::{Pattern, SparseLu};
use crate::mbd::system::{PartHandle, System};
use crate::vocab::math::{DVec, Mat3};

/// The system in motion.
pub struct Dynamics {
    /// The assembled system at the current state.
    pub sys: System,
    /// The applied forces and gravity.
    pub forces: ForceSet,
    /// Kept constraint rows (element, equation), in multiplier order.
    pub rows: Vec<(usize, usize)>,
    /// Rows the redundancy analysis dropped: checked, not solved.
    pub dropped: Vec<(usize, usize)>,
    /// Velocity-level columns and kept rows.
    pub n: usize,
    /// Kept constraint rows (length of λ).
    pub m: usize,
    /// Accelerations (v̇, ω̇ per part, the velocity layout) and multipliers.
    pub a: DVec,
    /// Lagrange multipliers, one per kept row.
    pub lambda: DVec,
    /// Counters of the run.
    pub stats: Stats,
    /// The global error the integrator carries at the accepted state (positions in the
    /// velocity layout, then velocities; `Integrator::global_error`): empty when it
    /// carries none.
    pub carried: Vec<f64>,
    /// The Newton matrix's factors, and the saddle-point matrix's of the outputs'
    /// reconciliation: separate, so an output does not cost the integrator its
    /// factorization.
    pub(super) factors: Vec<Factors>,
    /// Counts factorizations, so an integrator can tell whether the factors it reuses
    /// are still its own.
    pub factor_generation: u64,
    /// Scratch: generalized forces and their Jacobians.
    pub(crate) gen: Generalized,
    /// Φ and Φ_q of the kept rows at the last evaluation.
    pub(crate) phi: DVec,
    pub(crate) jac: jacobian::Jacobian,
    /// Per kept row, its primitive equation resolved, with the Jacobian slots of its I
    /// and J parts (None for ground): the rows evaluated without looking anything up.
    pub(super) prims: Vec<ResolvedRow>,
    /// The geometric stiffness of the last Newton factorization ([`super::stiffness`]).
    pub(super) geo: Vec<(usize, usize, f64)>,
    /// Scratch of the geometric stiffness: one rotational block per moving part.
    pub(super) geo_blocks: Vec<Mat3>,
    /// The rows whose Jacobian can vanish (all but the `Along` primitives, whose
    /// direction is a unit vector), and the Jacobian's largest entry at the last
    /// factorization, their scale.
    pub(super) may_vanish: Vec<usize>,
    pub(super) jac_top: f64,
    /// The mass blocks when they never change: in 2D, and in 3D when every moving
    /// part's inertia is isotropic.
    pub(super) constant_mass: Option<Vec<Mat3Block>>,
    /// Buffers of one row's evaluation, reused.
    pub(super) row_scratch: crate::mbd::constraints::RowEval,
    /// Where the Newton matrix's entries go ([`fill::Fill`]).
    pub(super) fill: fill::Fill,
    /// Every moving part's inertia is isotropic (the 3D mass blocks then never change).
    pub(super) isotropic: bool,
    /// Scratch of the saddle-point solves.
    pub(super) scratch: Scratch,
}

/// The parts a constraint row reads (its markers', or its measures' markers').
pub fn row_parts(sys: &System, e: usize, q: usize) -> Vec<PartHandle> {
    let mut out = Vec::new();
    let mut add = |m: Option<crate::mbd::system::MarkerHandle>| {
        let p = sys.frame(m).part;
        if !out.contains(&p) {
            out.push(p);
        }
    };
    match &sys.elements[e].eqs[q].row {
        Row::Along { i, j, .. } | Row::Dot { i, j, .. } => {
            add(Some(*i));
            add(Some(*j));
        }
        Row::Measured { terms, .. } => {
            for &(_, m) in terms {
                for mk in sys.measures.list[m].markers() {
                    add(mk);
                }
            }
        }
        Row::Gcon { map, .. } => {
            for &m in map {
                for mk in sys.measures.list[m].markers() {
                    add(mk);
                }
            }
        }
    }
    out
}

impl Dynamics {
    /// Sets up the dynamics of an assembled `sys` (velocities consistent) with its
    /// forces; `dropped` lists the rows (in [`System::rows`] order) the redundancy
    /// analysis removed.
    pub fn new(sys: System, mut forces: ForceSet, dropped: &[usize]) -> Result<Dynamics, DynError> {
        forces.prepare(&sys)?;
        Self::with_prepared(sys, forces, dropped)
    }

    /// [`Dynamics::new`] with `forces` prepared for `sys` already ([`ForceSet::prepare`]:
    /// it checks every element's parts fit its duals, which a rerun of the same system
    /// need not do again).
    pub fn with_prepared(
        sys: System,
        forces: ForceSet,
        dropped: &[usize],
    ) -> Result<Dynamics, DynError> {
        Self::with_factors(sys, forces, dropped, Vec::new())
    }

    /// [`Dynamics::with_prepared`] taking the LU solvers of `reuse` (another dynamics'
    /// [`Dynamics::take_factors`]) when their pattern is this system's: their symbolic
    /// analysis is kept, everything else made anew ([`SparseLu::forget`]).
    pub(crate) fn with_factors(
        sys: System,
        forces: ForceSet,
        dropped: &[usize],
        reuse: Vec<Factors>,
    ) -> Result<Dynamics, DynError> {
        let all: Vec<(usize, usize)> = sys.rows().collect();
        let (mut rows, mut drop) = (Vec::new(), Vec::new());
        for (k, r) in all.into_iter().enumerate() {
            if dropped.contains(&k) {
                drop.push(r);
            } else {
                rows.push(r);
            }
        }
        let (n, m) = (sys.ncols(), rows.len());
        let index = |p: PartHandle| sys.part(p).index;
        let row_parts: Vec<Vec<usize>> = rows
            .iter()
            .map(|&(e, q)| {
                row_parts(&sys, e, q)
                    .into_iter()
                    .filter_map(index)
                    .collect()
            })
            .collect();
        let pattern = Self::pattern(&sys, &forces, &row_parts);
        let jac = jacobian::Jacobian::new(sys.dim.cols(), &row_parts);
        let mut prims: Vec<ResolvedRow> = rows
            .iter()
            .enumerate()
            .map(|(r, &(e, q))| {
                let p = sys.resolved_primitive(e, q)?;
                let (pi, pj) = p.parts();
                let slot = |h: PartHandle| index(h).and_then(|i| jac.slot_of(r, i));
                Some((p, [slot(pi), slot(pj)]))
            })
            .collect();
        resolved::freeze_point_rows(&sys, &rows, &mut prims);
        let factors = |pattern: Pattern| -> Result<Factors, DynError> {
            Ok(Factors {
                values: vec![0.0; pattern.nnz()],
                lu: SparseLu::new(pattern).map_err(|_| DynError::Structure)?,
                schur: None,
                via_schur: false,
                regularised: true,
                schur_declined: false,
            })
        };
        let factors = match reuse.len() == 2 && reuse.iter().all(|f| *f.lu.pattern() == pattern) {
            true => reuse
                .into_iter()
                .map(|f| {
                    let mut lu = f.lu;
                    lu.forget();
                    Factors {
                        values: vec![0.0; pattern.nnz()],
                        lu,
                        schur: None,
                        via_schur: false,
                        regularised: true,
                        schur_declined: false,
                    }
                })
                .collect(),
            false => vec![factors(pattern.clone())?, factors(pattern)?],
        };
        let mut d = Dynamics {
            sys,
            forces,
            rows,
            dropped: drop,
            n,
            m,
            a: DVec::zeros(n),
            lambda: DVec::zeros(m),
            stats: Stats::default(),
            carried: Vec::new(),
            factors,
            factor_generation: 0,
            gen: Generalized::new(n),
            phi: DVec::zeros(m),
            may_vanish: (0..m)
                .filter(|&r| {
                    !matches!(
                        prims[r],
                        Some((Primitive::Along(_) | Primitive::Fixed(_), _))
                    )
                })
                .collect(),
            jac_top: 0.0,
            jac,
            prims,
            geo: Vec::new(),
            geo_blocks: Vec::new(),
            row_scratch: Default::default(),
            constant_mass: None,
            fill: fill::Fill::default(),
            isotropic: false,
            scratch: Scratch::default(),
        };
        d.fill = fill::Fill::new(&d.factors[0].lu, &d.sys, &d.jac);
        for f in 0..2 {
            d.factors[f].schur = d.schur_solver();
        }
        let isotropic = d
            .sys
            .parts
            .iter()
            .all(|p| p.index.is_none() || p.isotropic());
        d.isotropic = isotropic;
        if d.mass_is_constant() {
            d.constant_mass = Some(d.mass_blocks().into_owned());
        }
        d.check_massless()?;
        Ok(d)
    }

    /// Moves the measures' unwrapping references (angles past ±π) to the current state,
    /// an accepted one: a step, an equilibrium, a kinematic solution.
    pub fn commit_measures(&mut self) {
        let mut measures = std::mem::take(&mut self.sys.measures);
        measures.commit(&self.sys);
        self.sys.measures = measures;
    }

    /// Kept row `r`'s primitive joint equation, resolved to its parts (None for a
    /// MOTION, GCON or other measured row).
    pub(crate) fn primitive(&self, r: usize) -> Option<Primitive> {
        self.prims[r].map(|(p, _)| p)
    }

    /// The LU solvers, for a new dynamics of the same system
    /// ([`Dynamics::with_factors`]); this one is left without any and must not solve again.
    pub(crate) fn take_factors(&mut self) -> Vec<Factors> {
        std::mem::take(&mut self.factors)
    }

    /// The Newton matrix's pattern: each part's mass block, the blocks force elements
    /// couple, and the constraint rows over the columns of every part they read
    /// (`row_parts`, velocity-layout part indices).
    pub(super) fn pattern(sys: &System, forces: &ForceSet, row_parts: &[Vec<usize>]) -> Pattern {
        let n = sys.ncols();
        let bs = sys.dim.cols();
        let block = |p: PartHandle| sys.part(p).index.map(|i| i * bs);
        let mut pos = Vec::new();
        let dense = |pos: &mut Vec<(usize, usize)>, r0: usize, nr: usize, c0: usize| {
            for r in r0..r0 + nr {
                for c in c0..c0 + bs {
                    pos.push((r, c));
                }
            }
        };
        for i in 0..sys.moving_parts() {
            dense(&mut pos, i * bs, bs, i * bs);
        }
        for el in &forces.elements {
            let applied = [Some(sys.marker(el.i).part), Some(sys.frame(el.j).part)];
            for p in applied.into_iter().flatten().filter_map(block) {
                for q in el.slots.parts.into_iter().flatten().filter_map(block) {
                    dense(&mut pos, p, bs, q);
                }
            }
        }
        for (i, j) in forces.contacts.coupled_parts() {
            for p in [i, j].into_iter().filter_map(block) {
                for q in [i, j].into_iter().filter_map(block) {
                    dense(&mut pos, p, bs, q);
                }
            }
        }
        for (r, parts) in row_parts.iter().enumerate() {
            // The multiplier's diagonal holds the regularisation (Dynamics::factor).
            pos.push((n + r, n + r));
            for &i in parts {
                for c in i * bs..(i + 1) * bs {
                    pos.push((n + r, c));
                    pos.push((c, n + r));
                }
            }
        }
        Pattern::new(n + row_parts.len(), pos)
    }

    /// The Schur-complement solver, when the effective mass is block diagonal: no force
    /// element reads or loads more than one moving part.
    pub(super) fn schur_solver(&self) -> Option<schur::Schur> {
        let sys = &self.sys;
        let index = |p: PartHandle| sys.part(p).index;
        for el in &self.forces.elements {
            let mut touched = [Some(sys.marker(el.i).part), Some(sys.frame(el.j).part)]
                .into_iter()
                .chain(el.slots.parts)
                .flatten()
                .filter_map(index);
            let first = touched.next();
            if touched.any(|i| Some(i) != first) {
                return None;
            }
        }
        let both_move = |(i, j): (PartHandle, PartHandle)| index(i).is_some() && index(j).is_some();
        if self.forces.contacts.coupled_parts().any(both_move) {
            return None;
        }
        Some(schur::Schur::new(&self.jac, sys.moving_parts()))
    }
}
