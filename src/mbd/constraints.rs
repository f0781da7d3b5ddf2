//! Constraint elements: each is a set of scalar equations between two marker frames.
//! The six primitive equations of multibody spec §4.1 (d·e_J = 0 and u_I·w_J = 0) are
//! differentiated by hand; every JOINT of §4.2, every JPRIM and Exudyn's 2D prismatic
//! joint (§6.4) is a constructor that lists primitives, not a separate code path.
//! RACKPIN, SCREW and MOTION are linear combinations of measures minus a drive g(t);
//! GCON is an expression of measures. Rows carry their [`EquationLabel`].

use super::equations::{Equation, EquationLabel};
use super::error::MbdError;
use super::expr::ExprFn;
use super::handles::{ElementHandle, MarkerHandle, PartHandle};
use super::measure_set::Measure;
use super::rows::{Element, Equ, Row};
use super::system::{Dimension, System};
use crate::vocab::elements::{ElementKind, ElementRef, JointType, JprimType};
use crate::vocab::math::Vec3;
use std::f64::consts::PI;

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

/// The primitive equations of a JOINT or JPRIM type (spec §4.2), in Adams label order.
pub fn primitive_set(kind: ElementKind) -> &'static [Equation] {
    use Equation::*;
    const XYZ: &[Equation] = &[XDelta, YDelta, ZDelta];
    match kind {
        ElementKind::Joint(t) => match t {
            JointType::Fixed => &[XDelta, YDelta, ZDelta, ZiXj, ZiYj, XiYj],
            JointType::Revolute => &[XDelta, YDelta, ZDelta, ZiXj, ZiYj],
            JointType::Spherical => XYZ,
            JointType::Translational => &[XDelta, YDelta, ZiXj, ZiYj, XiYj],
            JointType::Cylindrical => &[XDelta, YDelta, ZiXj, ZiYj],
            JointType::Planar => &[ZDelta, ZiXj, ZiYj],
            JointType::Hooke => &[XDelta, YDelta, ZDelta, XiYj],
            JointType::Universal => &[XDelta, YDelta, ZDelta, ZiZj],
            JointType::Convel => &[XDelta, YDelta, ZDelta, Convel],
            JointType::Rackpin => &[Rackpin],
            JointType::Screw => &[Screw],
        },
        ElementKind::Jprim(t) => match t {
            JprimType::Atpoint => XYZ,
            JprimType::Inline => &[XDelta, YDelta],
            JprimType::Inplane => &[ZDelta],
            JprimType::Orientation => &[ZiXj, ZiYj, XiYj],
            JprimType::ParallelAxes => &[ZiXj, ZiYj],
            JprimType::Perpendicular => &[ZiZj],
        },
        ElementKind::Prismatic2d => &[YDelta, XiYj],
        ElementKind::Gcon => &[Gcon],
        ElementKind::Motion => &[Motion],
        ElementKind::Force(_) => &[],
    }
}

fn axis(c: usize) -> Vec3 {
    let mut v = Vec3::zeros();
    v[c] = 1.0;
    v
}

impl System {
    fn check_pair(&self, e: &ElementRef, i: MarkerHandle, j: MarkerHandle) -> Result<(), MbdError> {
        for m in [i, j] {
            if self.marker(m).floating {
                return Err(MbdError::Floating(
                    e.clone(),
                    self.marker(m).id.unwrap_or(0) as i64,
                ));
            }
        }
        if self.marker(i).part == self.marker(j).part {
            return Err(MbdError::SamePart(e.clone()));
        }
        Ok(())
    }

    /// Adds an element with its equations.
    pub fn add_element(&mut self, elref: ElementRef, eqs: Vec<Equ>) -> ElementHandle {
        self.elements.push(Element { elref, eqs });
        ElementHandle(self.elements.len() as u32 - 1)
    }

    fn primitives(
        &mut self,
        elref: ElementRef,
        i: MarkerHandle,
        j: MarkerHandle,
    ) -> Result<ElementHandle, MbdError> {
        self.check_pair(&elref, i, j)?;
        let eqs = primitive_set(elref.kind)
            .iter()
            .map(|&eq| self.primitive(eq, i, j))
            .collect::<Result<_, _>>()?;
        Ok(self.add_element(elref, eqs))
    }

    /// One primitive equation of spec §4.1 (plus Zi.Zj and CONVEL's x_I·y_J + y_I·x_J,
    /// whose two terms are UVX(I, J)-type measures).
    fn primitive(
        &mut self,
        eq: Equation,
        i: MarkerHandle,
        j: MarkerHandle,
    ) -> Result<Equ, MbdError> {
        use Equation::*;
        let along = |c| Row::Along {
            i,
            j,
            dir: axis(c),
            sign: 1.0,
        };
        let dot = |a, b| Row::Dot {
            i,
            j,
            a: axis(a),
            b: axis(b),
        };
        let row = match eq {
            XDelta => along(0),
            YDelta => along(1),
            ZDelta => along(2),
            ZiXj => dot(2, 0),
            ZiYj => dot(2, 1),
            XiYj => dot(0, 1),
            ZiZj => dot(2, 2),
            Convel => {
                let (i, k) = (Some(i), Some(j));
                let xy = self.measures.add(Measure::UnitVec {
                    i,
                    k,
                    axis: 0,
                    comp: 1,
                });
                let yx = self.measures.add(Measure::UnitVec {
                    i,
                    k,
                    axis: 1,
                    comp: 0,
                });
                Row::Measured {
                    terms: vec![(1.0, xy), (1.0, yx)],
                    drive: None,
                }
            }
            Rackpin | Screw | Gcon | Motion => return Err(MbdError::NotPrimitive(eq.label())),
        };
        Ok(Equ::new(row, eq, matches!(eq, XDelta | YDelta | ZDelta)))
    }

    /// A JOINT (spec §4.2). `param` is PD for RACKPIN, PITCH for SCREW, unused otherwise.
    pub fn joint(
        &mut self,
        elref: ElementRef,
        kind: JointType,
        i: MarkerHandle,
        j: MarkerHandle,
        param: f64,
    ) -> Result<ElementHandle, MbdError> {
        let elref = ElementRef {
            kind: ElementKind::Joint(kind),
            ..elref
        };
        let (mi, mj) = (Some(i), Some(j));
        match kind {
            JointType::Rackpin | JointType::Screw => {
                self.check_pair(&elref, i, j)?;
                // One equation on the travel of I along z_J and an unwrapped angle. RACKPIN:
                // −(r_I − r_J)·z_J − (PD/2)·θ, θ = rotation of x_I about z_I from z_J;
                // SCREW: (r_I − r_J)·z_J − PITCH·θ/2π, θ = AZ(I, J). The signs are
                // decisions (the spec marks them [RECALL]).
                let travel = self.measures.add(Measure::Disp {
                    i: mi,
                    j: mj,
                    k: mj,
                    comp: 2,
                });
                let (sign, angle, coef, label) = if kind == JointType::Rackpin {
                    (
                        -1.0,
                        Measure::PinionAngle { i: mi, j: mj },
                        -param / 2.0,
                        Equation::Rackpin,
                    )
                } else {
                    (
                        1.0,
                        Measure::Angle {
                            i: mi,
                            j: mj,
                            axis: 2,
                        },
                        -param / (2.0 * PI),
                        Equation::Screw,
                    )
                };
                let angle = self.measures.add(angle);
                let row = Row::Measured {
                    terms: vec![(sign, travel), (coef, angle)],
                    drive: None,
                };
                Ok(self.add_element(elref, vec![Equ::new(row, label, true)]))
            }
            _ => self.primitives(elref, i, j),
        }
    }

    /// A JPRIM (spec §4.2).
    pub fn jprim(
        &mut self,
        elref: ElementRef,
        kind: JprimType,
        i: MarkerHandle,
        j: MarkerHandle,
    ) -> Result<ElementHandle, MbdError> {
        self.primitives(
            ElementRef {
                kind: ElementKind::Jprim(kind),
                ..elref
            },
            i,
            j,
        )
    }

    /// Exudyn's 2D prismatic joint (spec §6.4) with marker 0 = I, marker 1 = J:
    /// (r_J − r_I)·(R_J n) = 0 (`Y Delta` with the default n = y) and
    /// (R_I t)·(R_J n) = 0 (`Xi.Yj` with the default t = x). `t` is the sliding axis in
    /// I's frame, `n` the normal in J's frame.
    pub fn prismatic_2d(
        &mut self,
        elref: ElementRef,
        i: MarkerHandle,
        j: MarkerHandle,
        t: Vec3,
        n: Vec3,
    ) -> Result<ElementHandle, MbdError> {
        let elref = ElementRef {
            kind: ElementKind::Prismatic2d,
            ..elref
        };
        self.check_pair(&elref, i, j)?;
        let eqs = vec![
            Equ::new(
                Row::Along {
                    i,
                    j,
                    dir: n,
                    sign: -1.0,
                },
                Equation::YDelta,
                true,
            ),
            Equ::new(Row::Dot { i, j, a: t, b: n }, Equation::XiYj, false),
        ];
        Ok(self.add_element(elref, eqs))
    }

    /// A GCON: f(t, measures) = 0, where `map[k]` is the measure index of the k-th slot
    /// `f` reads.
    pub fn gcon(
        &mut self,
        elref: ElementRef,
        f: Box<dyn ExprFn>,
        map: Vec<usize>,
    ) -> Result<ElementHandle, MbdError> {
        let elref = ElementRef {
            kind: ElementKind::Gcon,
            ..elref
        };
        if map.len() != f.slots().len() || map.iter().any(|&m| m >= self.measures.list.len()) {
            return Err(MbdError::GconSlots {
                id: elref.id,
                slots: f.slots().len(),
                measures: map.len(),
            });
        }
        let row = Row::Gcon { f, map };
        Ok(self.add_element(elref, vec![Equ::new(row, Equation::Gcon, false)]))
    }

    /// A displacement MOTION: measure − g(t) = 0.
    pub fn motion(
        &mut self,
        elref: ElementRef,
        measure: Measure,
        g: Box<dyn ExprFn>,
    ) -> Result<ElementHandle, MbdError> {
        let elref = ElementRef {
            kind: ElementKind::Motion,
            ..elref
        };
        let markers = match measure {
            Measure::Angle { i, j, .. }
            | Measure::Disp { i, j, .. }
            | Measure::Body123 { i, j, .. } => (i, j),
            _ => return Err(MbdError::MotionMeasure),
        };
        if let (Some(i), Some(j)) = markers {
            self.check_pair(&elref, i, j)?;
        }
        let translational = matches!(measure, Measure::Disp { .. });
        let m = self.measures.add(measure);
        let row = Row::Measured {
            terms: vec![(1.0, m)],
            drive: Some(g),
        };
        Ok(self.add_element(elref, vec![Equ::new(row, Equation::Motion, translational)]))
    }

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
