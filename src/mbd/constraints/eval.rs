//! Constraint rows evaluated at the state of the system: the six primitive equations
//! resolved to their parts ([`Primitive`]) and differentiated by hand, the measured,
//! GCON and MOTION rows through the measures' duals; each row's value with its
//! derivatives ([`RowEval`]), and the row order and labels the solvers read.

use crate::mbd::equations::EquationLabel;
use crate::mbd::error::MbdError;
use crate::mbd::handles::PartHandle;
use crate::mbd::rows::Row;
use crate::mbd::system::{Dimension, System};
use crate::vocab::elements::ElementRef;
use crate::vocab::math::Vec3;

/// A row's derivative over one part: δr x y z, δθ x y z (global).
pub type PartDerivative = (PartHandle, [f64; 6]);

/// A marker pair's offsets on their parts (part coordinates) and an axis: the data of a
/// row (r_I − r_J)·axis.
#[derive(Clone, Copy, Debug)]
pub struct PointAxis {
    /// The I marker's part.
    pub pi: PartHandle,
    /// The I marker's origin, I-part coordinates.
    pub si: Vec3,
    /// The J marker's part.
    pub pj: PartHandle,
    /// The J marker's origin, J-part coordinates.
    pub sj: Vec3,
    /// The axis: J-part coordinates for [`Primitive::Along`], global for [`Primitive::Fixed`].
    pub axis: Vec3,
}

/// A primitive equation with its markers resolved to their parts: offsets and axes in
/// part coordinates, so an evaluation reads only the two parts' poses.
#[derive(Clone, Copy, Debug)]
pub enum Primitive {
    /// (r_I − r_J)·(R_J·axis): J's axis (times the row's sign) in part coordinates.
    Along(PointAxis),
    /// (r_I − r_J)·axis with a constant global axis: one row of a point coincidence
    /// whose basis stays put instead of turning with J (the dynamics freezes it so the
    /// geometric stiffness falls on each part alone: `dynamics::stiffness`).
    Fixed(PointAxis),
    /// (R_I·u)·(R_J·w), u and w in part coordinates.
    Dot {
        /// The I part.
        pi: PartHandle,
        /// The I vector, I-part coordinates.
        u: Vec3,
        /// The J part.
        pj: PartHandle,
        /// The J vector, J-part coordinates.
        w: Vec3,
    },
}

impl Primitive {
    /// The I and the J part.
    pub fn parts(&self) -> (PartHandle, PartHandle) {
        match *self {
            Primitive::Along(PointAxis { pi, pj, .. })
            | Primitive::Fixed(PointAxis { pi, pj, .. })
            | Primitive::Dot { pi, pj, .. } => (pi, pj),
        }
    }
}

/// Value and derivatives of one row: ∂/∂q and ∂/∂v over velocity-level columns, ∂/∂t.
#[derive(Clone, Debug, Default)]
pub struct RowEval {
    /// The row's value (zero when the equation holds).
    pub value: f64,
    /// ∂/∂q as (column, value).
    pub dq: Vec<(usize, f64)>,
    /// ∂/∂v as (column, value).
    pub dv: Vec<(usize, f64)>,
    /// ∂/∂t.
    pub dt: f64,
}

impl System {
    /// The element refs, indexed like [`EquationLabel::element`].
    pub fn element_refs(&self) -> Vec<ElementRef> {
        self.elements.iter().map(|e| e.elref.clone()).collect()
    }

    /// One label per active row, in row order.
    pub fn labels(&self) -> Vec<EquationLabel> {
        self.rows()
            .map(|(e, q)| EquationLabel {
                element: e,
                equation: self.elements[e].eqs[q].label,
            })
            .collect()
    }

    /// (element, equation) of every active row, in row order.
    pub fn rows(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.elements.iter().enumerate().flat_map(|(e, el)| {
            el.eqs
                .iter()
                .enumerate()
                .filter(|(_, q)| q.active)
                .map(move |(q, _)| (e, q))
        })
    }

    /// True when the row's equation depends on time (a MOTION's drive, a GCON reading
    /// TIME).
    pub fn row_reads_time(&self, e: usize, q: usize) -> bool {
        match &self.elements[e].eqs[q].row {
            Row::Measured { drive, .. } => drive.is_some(),
            Row::Gcon { f, .. } => f.reads_time(),
            _ => false,
        }
    }

    /// True when the row reads velocities (a non-holonomic GCON).
    pub fn row_reads_velocity(&self, e: usize, q: usize) -> bool {
        match &self.elements[e].eqs[q].row {
            Row::Gcon { map, .. } => map.iter().any(|&m| self.measures.list[m].reads_velocity()),
            _ => false,
        }
    }

    /// Adds the non-zero entries of `g` (δr x y z, δθ x y z) at `part`'s columns (the
    /// three of the plane in 2D); ground has none.
    fn push_part(&self, out: &mut Vec<(usize, f64)>, part: PartHandle, g: [f64; 6]) {
        let Some(i) = self.part(part).index else {
            return;
        };
        let bs = self.dim.cols();
        for (c, x) in self.column_components()[..bs]
            .iter()
            .map(|&k| g[k])
            .enumerate()
        {
            if x != 0.0 {
                out.push((i * bs + c, x));
            }
        }
    }

    /// A primitive row (`Along`, `Dot`): its value and, for the I and the J part, the
    /// derivative over δr x y z, δθ x y z (global). None for the other rows.
    pub fn primitive_blocks(&self, e: usize, q: usize) -> Option<(f64, [PartDerivative; 2])> {
        self.resolved_primitive(e, q)
            .map(|p| self.eval_primitive(&p))
    }

    /// Equation `q` of element `e` as a [`Primitive`], if it is one.
    pub fn resolved_primitive(&self, e: usize, q: usize) -> Option<Primitive> {
        match &self.elements[e].eqs[q].row {
            Row::Along { i, j, dir, sign } => {
                let (mi, mj) = (self.marker(*i), self.marker(*j));
                Some(Primitive::Along(PointAxis {
                    pi: mi.part,
                    si: mi.s,
                    pj: mj.part,
                    sj: mj.s,
                    axis: (mj.rot * dir) * *sign,
                }))
            }
            Row::Dot { i, j, a, b } => {
                let (mi, mj) = (self.marker(*i), self.marker(*j));
                Some(Primitive::Dot {
                    pi: mi.part,
                    u: mi.rot * a,
                    pj: mj.part,
                    w: mj.rot * b,
                })
            }
            _ => None,
        }
    }

    /// The value of a primitive and its derivative over each of its two parts.
    pub fn eval_primitive(&self, p: &Primitive) -> (f64, [PartDerivative; 2]) {
        let (mut gi, mut gj) = ([0.0; 6], [0.0; 6]);
        let value = self.eval_primitive_into(p, &mut gi, &mut gj);
        let (pi, pj) = match *p {
            Primitive::Along(ref p) | Primitive::Fixed(ref p) => (p.pi, p.pj),
            Primitive::Dot { pi, pj, .. } => (pi, pj),
        };
        (value, [(pi, gi), (pj, gj)])
    }

    /// The value of a primitive; its derivative over its I part's six components (δr,
    /// δθ) written into `gi`, over its J part's into `gj`. The dynamics' row loop passes
    /// the Jacobian's own blocks: derivatives returned through memory were stored and at
    /// once reloaded with wider loads, a store-forwarding stall each (a tenth of a 3D
    /// chain's step).
    #[inline(always)]
    pub fn eval_primitive_into(&self, p: &Primitive, gi: &mut [f64; 6], gj: &mut [f64; 6]) -> f64 {
        match *p {
            Primitive::Along(ref p) => self.eval_point_axis(p, true, gi, gj),
            Primitive::Fixed(ref p) => self.eval_point_axis(p, false, gi, gj),
            Primitive::Dot { pi, u, pj, w } => {
                let (u, w) = (self.part(pi).rotation() * u, self.part(pj).rotation() * w);
                let c = u.cross(&w);
                *gi = [0.0, 0.0, 0.0, c.x, c.y, c.z];
                *gj = [0.0, 0.0, 0.0, -c.x, -c.y, -c.z];
                u.dot(&w)
            }
        }
    }

    /// (r_I − r_J)·e with e = R_J·axis (`turning`) or e = axis, and its derivatives.
    #[inline(always)]
    fn eval_point_axis(
        &self,
        p: &PointAxis,
        turning: bool,
        gi: &mut [f64; 6],
        gj: &mut [f64; 6],
    ) -> f64 {
        let (bi, bj) = (self.part(p.pi), self.part(p.pj));
        let (ai, aj) = (bi.rotation() * p.si, bj.rotation() * p.sj);
        let d = (bi.r + ai) - (bj.r + aj);
        // A turning axis adds d × e to J's rotational derivative.
        let (e, arm_j) = match turning {
            true => (bj.rotation() * p.axis, aj + d),
            false => (p.axis, aj),
        };
        let (ti, tj) = (ai.cross(&e), -arm_j.cross(&e));
        *gi = [e.x, e.y, e.z, ti.x, ti.y, ti.z];
        *gj = [-e.x, -e.y, -e.z, tj.x, tj.y, tj.z];
        d.dot(&e)
    }

    /// Which component of a 3D derivative (δr x y z, δθ x y z) each of a part's columns
    /// holds, in column order: all six in 3D; the in-plane translations and the rotation
    /// about the normal in 2D (the first three entries).
    pub fn column_components(&self) -> [usize; 6] {
        match self.dim {
            Dimension::Three => [0, 1, 2, 3, 4, 5],
            Dimension::Two => {
                let (a, b, n) = self.plane_axes();
                [a, b, 3 + n, 3 + n, 3 + n, 3 + n]
            }
        }
    }

    /// Value and derivatives of equation `q` of element `e` at the current state.
    pub fn eval_row(&self, e: usize, q: usize) -> Result<RowEval, MbdError> {
        self.eval_row_with(e, q, true)
    }

    /// The value of equation `q` of element `e` (no derivatives asked of expressions).
    pub fn row_value(&self, e: usize, q: usize) -> Result<f64, MbdError> {
        Ok(self.eval_row_with(e, q, false)?.value)
    }

    fn eval_row_with(&self, e: usize, q: usize, derivs: bool) -> Result<RowEval, MbdError> {
        let mut out = RowEval::default();
        self.eval_row_into(e, q, derivs, &mut out)?;
        Ok(out)
    }

    /// [`System::eval_row`] into `out`, reusing its buffers (the integrators' inner loop).
    pub fn eval_row_into(
        &self,
        e: usize,
        q: usize,
        derivs: bool,
        out: &mut RowEval,
    ) -> Result<(), MbdError> {
        out.value = 0.0;
        out.dt = 0.0;
        out.dq.clear();
        out.dv.clear();
        match &self.elements[e].eqs[q].row {
            Row::Along { .. } | Row::Dot { .. } => {
                let (value, sides) = self.primitive_blocks(e, q).expect("a primitive row");
                out.value = value;
                for (part, g) in sides {
                    self.push_part(&mut out.dq, part, g);
                }
            }
            Row::Measured { terms, drive } => {
                for &(c, m) in terms {
                    if !derivs {
                        // The value alone: the same operations on plain numbers, not on
                        // 7 KB dual frames (most rows a Newton iteration evaluates).
                        out.value += c * self.measures.unwrapped_value(self, m);
                        continue;
                    }
                    let ev = self.measures.eval(self, m);
                    out.value += c * ev.value();
                    ev.scatter(
                        self,
                        &mut |col, g| out.dq.push((col, c * g)),
                        &mut |col, g| out.dv.push((col, c * g)),
                    );
                }
                if let Some(g) = drive {
                    let el = &self.elements[e].elref;
                    let err = |s| MbdError::Expression(el.clone(), s);
                    // The dynamics' one call a state, when it made it (displacement
                    // drives); ∂g/∂t is not read here.
                    let val = match self.fused_row(e, false, &mut []) {
                        Some(row) => row.map_err(err)?.value,
                        None => g.value(self.time, &[]).map_err(err)?,
                    };
                    out.value -= val;
                    // ∂g/∂t is needed only by the velocity solve; it asks for it lazily.
                    out.dt = f64::NAN;
                }
            }
            Row::Gcon { f, map } => {
                let el = &self.elements[e].elref;
                let slots = f.slots();
                let mut guard = self.scratch.borrow_mut();
                let sc = &mut *guard;
                sc.slots_to(slots.last().copied());
                sc.evs.clear();
                for (&m, &s) in map.iter().zip(slots) {
                    if !derivs {
                        sc.slots[s as usize] = self.measures.unwrapped_value(self, m);
                        continue;
                    }
                    let ev = self.measures.eval(self, m);
                    sc.slots[s as usize] = ev.value();
                    sc.evs.push(ev);
                }
                let err = |s| MbdError::Expression(el.clone(), s);
                sc.grad.clear();
                sc.grad.resize(slots.len(), 0.0);
                // The dynamics' one call a state for every GCON, when it made it.
                if let Some(row) = self.fused_row(e, derivs, &mut sc.grad) {
                    let row = row.map_err(err)?;
                    out.value = row.value;
                    if !derivs {
                        return Ok(());
                    }
                    out.dt = row.dt;
                } else if !derivs {
                    out.value = f.value(self.time, &sc.slots).map_err(err)?;
                    return Ok(());
                } else {
                    (out.value, out.dt) = f
                        .value_gradient(self.time, &sc.slots, &mut sc.grad)
                        .map_err(err)?;
                }
                for (ev, &c) in sc.evs.iter().zip(&sc.grad) {
                    if c != 0.0 {
                        ev.scatter(
                            self,
                            &mut |col, g| out.dq.push((col, c * g)),
                            &mut |col, g| out.dv.push((col, c * g)),
                        );
                    }
                }
            }
        }
        Ok(())
    }

    /// ∂Φ/∂t of a row (−ġ for a MOTION, ∂f/∂t for a GCON, 0 for the rest).
    pub fn row_dt(&self, e: usize, q: usize) -> Result<f64, MbdError> {
        match &self.elements[e].eqs[q].row {
            Row::Measured { drive: Some(g), .. } => {
                let el = &self.elements[e].elref;
                g.gradient(self.time, &[], &mut [])
                    .map(|d| -d)
                    .map_err(|s| MbdError::Expression(el.clone(), s))
            }
            Row::Gcon { .. } => Ok(self.eval_row(e, q)?.dt),
            _ => Ok(0.0),
        }
    }
}
