//! Evaluating the system's measures ([`MeasureSet`]): each measure's value and its
//! derivatives from the marker frames, unwrapped angles, and the slot values an
//! expression reads.

use super::frames::{
    axis_value, dual_axes, dual_frame, dual_origin, point_velocity, value_frame, DFrame, Frame,
    PartSlots,
};
use crate::mbd::dual::{Scalar, D, J2, PER_PART, V};
use crate::mbd::measure_set::M;
use crate::mbd::measure_set::{Evaluated, Measure, MeasureSet};
use crate::mbd::system::System;
use crate::vocab::math::Vec3;
use std::f64::consts::PI;

impl Evaluated {
    /// The measure's value.
    pub fn value(&self) -> f64 {
        self.d.v
    }

    /// Calls `pos(col, ∂/∂q_col)` and `vel(col, ∂/∂v_col)` for every system column the
    /// measure depends on (velocity-level columns, 2D or 3D layout).
    pub fn scatter(
        &self,
        sys: &System,
        pos: &mut dyn FnMut(usize, f64),
        vel: &mut dyn FnMut(usize, f64),
    ) {
        PartSlots { parts: self.parts }.scatter(sys, &self.d.g, pos, vel);
    }
}

impl MeasureSet {
    /// Adds a measure and returns its index.
    pub fn add(&mut self, m: Measure) -> usize {
        if let Some(i) = self.list.iter().position(|x| *x == m) {
            return i;
        }
        self.list.push(m);
        self.refs.push(f64::NAN);
        self.axes.push(None);
        self.list.len() - 1
    }

    /// Sets design variable `id` to `value`: every [`Measure::Design`] of it reads
    /// `value` from now on.
    pub fn set_design(&mut self, id: i64, value: f64) {
        match self.design.iter_mut().find(|(i, _)| *i == id) {
            Some(d) => d.1 = value,
            None => self.design.push((id, value)),
        }
    }

    /// The value of design variable `id` (NaN when it was never set).
    pub fn design(&self, id: i64) -> f64 {
        self.design
            .iter()
            .find(|(i, _)| *i == id)
            .map_or(f64::NAN, |d| d.1)
    }

    /// State value `channel` (NaN before the first state solve writes it).
    pub fn state(&self, channel: u32) -> f64 {
        self.states
            .get(channel as usize)
            .copied()
            .unwrap_or(f64::NAN)
    }

    /// The design variables the measures read, with their values.
    pub fn designs(&self) -> &[(i64, f64)] {
        &self.design
    }

    /// Gives an unwrapped measure without a reference yet the reference `value` (a
    /// MOTION's target at assembly, so a drive to 200° is not read as −160°).
    pub fn seed(&mut self, n: usize, value: f64) {
        if self.list[n].unwrapped() && self.refs[n].is_nan() {
            self.refs[n] = value;
        }
    }

    /// Takes the unwrapping references of `other` (another system's measures over the
    /// same markers): measure n adopts `other`'s measure `same[n]` where it has one.
    pub fn adopt_unwrapping(&mut self, other: &MeasureSet, same: &[Option<usize>]) {
        for (n, k) in same.iter().enumerate() {
            if let (Some(k), true) = (k, n < self.refs.len()) {
                self.refs[n] = other.refs[*k];
                self.axes[n] = other.axes[*k];
            }
        }
    }

    /// Moves the unwrapping references to the current values (after an accepted state).
    pub fn commit(&mut self, sys: &System) {
        for n in 0..self.list.len() {
            if self.list[n].unwrapped() {
                if let Measure::IncAng { i, j, k } = self.list[n] {
                    if self.axes[n].is_none() {
                        let (a, b) = (
                            sys.frame(i).r - sys.frame(j).r,
                            sys.frame(k).r - sys.frame(j).r,
                        );
                        let c = a.cross(&b);
                        self.axes[n] = Some(if c.norm() > 0.0 {
                            c.normalize()
                        } else {
                            Vec3::z()
                        });
                    }
                }
                self.refs[n] = self.unwrapped_value(sys, n);
            }
        }
    }

    /// Value and derivatives of measure `n` at the current state.
    pub fn eval(&self, sys: &System, n: usize) -> Evaluated {
        let mut slots = PartSlots::default();
        // A measure reads at most four markers, so four part slots always suffice.
        let d = self
            .eval_in(sys, n, &mut slots)
            .expect("a measure touches at most PARTS parts");
        Evaluated {
            d,
            parts: slots.parts,
        }
    }

    /// The value of measure `n` at the current state, not unwrapped: the value of
    /// [`MeasureSet::jet`] without its derivatives (a force law's inputs when no
    /// Jacobian is asked for).
    pub fn value(&self, sys: &System, n: usize) -> f64 {
        let m = self.list[n];
        // Displacements and velocities (in ground's frame of differentiation), the
        // measures force laws read most, from the few vectors they need: the same
        // operations on the same numbers as through whole frames.
        match m {
            Measure::Design { id } => return self.design(id),
            Measure::State { channel } => return self.state(channel),
            Measure::Disp { i, j, k, comp } if comp < 3 => {
                let (a, b) = (sys.origin(i).0, sys.origin(j).0);
                let d = V([a.x - b.x, a.y - b.y, a.z - b.z]);
                return d.dot(&axis_value(sys, k, comp));
            }
            Measure::Vel {
                i,
                j,
                k,
                l: None,
                comp,
            } if comp < 3 => {
                let (a, b) = (point_velocity(sys, i), point_velocity(sys, j));
                let d = V([a.x - b.x, a.y - b.y, a.z - b.z]);
                return d.dot(&axis_value(sys, k, comp));
            }
            _ => {}
        }
        let frames = m.markers().map(|mk| value_frame(sys, mk));
        self.raw(n, &m, &frames)
    }

    /// The value of measure `n` at the current state, unwrapped as [`MeasureSet::eval`]
    /// unwraps it (the same operations on the same numbers, without the derivatives).
    pub fn unwrapped_value(&self, sys: &System, n: usize) -> f64 {
        let raw = self.value(sys, n);
        let r = self.refs[n];
        match self.list[n].unwrapped() && r.is_finite() {
            true => raw + 2.0 * PI * ((r - raw) / (2.0 * PI)).round(),
            false => raw,
        }
    }

    /// Measure `n` with its first and second time derivatives along the current motion
    /// with every part's acceleration zero (its value is not unwrapped): what the
    /// acceleration-level constraint right-hand side needs.
    pub fn jet(&self, sys: &System, n: usize) -> J2 {
        let m = self.list[n];
        if let Measure::Design { id } = m {
            return J2::c(self.design(id));
        }
        if let Measure::State { channel } = m {
            return J2::c(self.state(channel));
        }
        let frames = m.markers().map(|mk| {
            let f = sys.frame(mk);
            let p = sys.part(f.part);
            let w = p.w;
            let jet = |x: Vec3, d: Vec3, dd: Vec3| {
                V([0, 1, 2].map(|c| J2 {
                    v: x[c],
                    d: d[c],
                    dd: dd[c],
                }))
            };
            let wa = w.cross(&f.a);
            let axes = [0, 1, 2].map(|c| {
                let u = Vec3::from(f.rot.column(c));
                jet(u, w.cross(&u), w.cross(&w.cross(&u)))
            });
            Frame {
                r: jet(f.r, p.v + wa, w.cross(&wa)),
                axes,
                vel: jet(p.v + wa, w.cross(&wa), w.cross(&w.cross(&wa))),
                w: jet(w, Vec3::zeros(), Vec3::zeros()),
            }
        });
        self.raw(n, &m, &frames)
    }

    /// Measure `n` as a dual over the local directions of `slots`, which it extends with
    /// the parts it reads (shared with other duals of one force element). None when the
    /// parts do not fit in the slots.
    pub(crate) fn eval_in(&self, sys: &System, n: usize, slots: &mut PartSlots) -> Option<D> {
        let m = self.list[n];
        if let Measure::Design { id } = m {
            return Some(D::c(self.design(id)));
        }
        if let Measure::State { channel } = m {
            return Some(D::c(self.state(channel)));
        }
        // The measures that read only origins and axes get those alone (a whole dual frame
        // is 7 KB, an angle reads three of its eighteen vectors): the same values and
        // derivatives as through `raw` on whole frames, the markers taken in its order.
        let raw = match m {
            Measure::Angle { i, j, axis } => angle(sys, i, j, axis, slots)?,
            Measure::Disp { i, j, k, comp } => {
                let (ri, rj) = (dual_origin(sys, i, slots)?, dual_origin(sys, j, slots)?);
                let [u] = dual_axes(sys, k, [comp as usize], slots)?;
                ri.sub(&rj).dot(&u)
            }
            Measure::Dist { i, j } => {
                let (ri, rj) = (dual_origin(sys, i, slots)?, dual_origin(sys, j, slots)?);
                ri.sub(&rj).norm()
            }
            Measure::UnitVec { i, k, axis, comp } => {
                let [a] = dual_axes(sys, i, [axis as usize], slots)?;
                let [b] = dual_axes(sys, k, [comp as usize], slots)?;
                a.dot(&b)
            }
            _ => return self.eval_by_frames(sys, n, slots),
        };
        Some(self.unwrap(n, &m, raw))
    }

    /// Measure `n` through whole dual frames, the formula of [`MeasureSet::raw`] for
    /// every measure ([`MeasureSet::eval_in`] takes shortcuts for some; the tests hold
    /// them to these bits).
    pub(crate) fn eval_by_frames(
        &self,
        sys: &System,
        n: usize,
        slots: &mut PartSlots,
    ) -> Option<D> {
        let m = self.list[n];
        let mk = m.markers();
        let mut frame = |i: usize| dual_frame(sys, mk[i], slots);
        // Only the frames the formula reads, built in place: unread ground frames and
        // copies through options cost more than the formula.
        Some(match m.frames_read() {
            2 => self.compute(n, &m, &[frame(0)?, frame(1)?]),
            3 => self.compute(n, &m, &[frame(0)?, frame(1)?, frame(2)?]),
            _ => self.compute(n, &m, &[frame(0)?, frame(1)?, frame(2)?, frame(3)?]),
        })
    }

    /// The raw (not unwrapped) value of measure `n` from its frames, in duals or jets.
    fn raw<T: Scalar>(&self, n: usize, m: &Measure, f: &[Frame<T>]) -> T {
        use Measure::*;
        // Rotation of i relative to j: R[a][b] = axis_j[a] · axis_i[b].
        let rel = |fi: &Frame<T>, fj: &Frame<T>, a: usize, b: usize| fj.axes[a].dot(&fi.axes[b]);
        match *m {
            Disp { comp, .. } => f[0].r.sub(&f[1].r).dot(&f[2].axes[comp as usize]),
            Dist { .. } => f[0].r.sub(&f[1].r).norm(),
            Angle { axis, .. } => {
                let (i, j) = (&f[0], &f[1]);
                match axis {
                    0 => (-i.axes[2].dot(&j.axes[1])).atan2(i.axes[2].dot(&j.axes[2])),
                    1 => i.axes[2].dot(&j.axes[0]).atan2(i.axes[2].dot(&j.axes[2])),
                    _ => i.axes[0].dot(&j.axes[1]).atan2(i.axes[0].dot(&j.axes[0])),
                }
            }
            Euler313 { which, .. } => {
                let r = |a, b| rel(&f[0], &f[1], a, b);
                // At θ = 0 or π only ψ ± φ is defined: φ = 0 and ψ carries the whole turn,
                // as the reader's inverse of REULER (`model::frames::euler_313`). Without
                // this, identity frames gave ψ = atan2(0, −0) = π.
                let singular = r(0, 2).val().hypot(r(1, 2).val()) < 1e-12;
                match which {
                    0 if singular => r(1, 0).atan2(r(0, 0)),
                    0 => r(0, 2).atan2(-r(1, 2)),
                    1 => r(2, 2).acos(),
                    _ if singular => T::c(0.0),
                    _ => r(2, 0).atan2(r(2, 1)),
                }
            }
            Euler321 { which, .. } => {
                let r = |a, b| rel(&f[0], &f[1], a, b);
                match which {
                    0 => r(1, 0).atan2(r(0, 0)),
                    1 => r(2, 0).asin(),
                    _ => r(2, 1).atan2(r(2, 2)),
                }
            }
            Body123 { which, .. } => {
                let r = |a, b| rel(&f[0], &f[1], a, b);
                match which {
                    0 => (-r(1, 2)).atan2(r(2, 2)),
                    1 => r(0, 2).asin(),
                    _ => (-r(0, 1)).atan2(r(0, 0)),
                }
            }
            UnitVec { axis, comp, .. } => f[0].axes[axis as usize].dot(&f[1].axes[comp as usize]),
            IncAng { .. } => {
                let (a, b) = (f[0].r.sub(&f[1].r), f[2].r.sub(&f[1].r));
                let c = a.cross(&b);
                let axis = self.axes[n].unwrap_or_else(|| {
                    let cv = c.value();
                    if cv.norm() > 0.0 {
                        cv.normalize()
                    } else {
                        Vec3::z()
                    }
                });
                c.dot(&V::c(axis)).atan2(a.dot(&b))
            }
            Vel { comp, .. } => rel_vel(f).dot(&f[2].axes[comp as usize]),
            VelMag { .. } => rel_vel_l(f, 2).norm(),
            VelRad { .. } => {
                let d = f[0].r.sub(&f[1].r);
                let dn = d.norm();
                let w = rel_vel_l(f, 2);
                let s = w.dot(&d);
                s * dn.recip()
            }
            AngVel { comp, .. } => f[0].w.sub(&f[1].w).dot(&f[2].axes[comp as usize]),
            AngVelMag { .. } => f[0].w.sub(&f[1].w).norm(),
            Design { id } => T::c(self.design(id)),
            State { channel } => T::c(self.state(channel)),
            PinionAngle { .. } => {
                let (i, j) = (&f[0], &f[1]);
                let s = i.axes[0].dot(&i.axes[2].cross(&j.axes[2]));
                s.atan2(i.axes[0].dot(&j.axes[2]))
            }
        }
    }

    fn compute(&self, n: usize, m: &Measure, f: &[DFrame]) -> D {
        self.unwrap(n, m, self.raw(n, m, f))
    }

    /// `raw` taken within π of measure `n`'s reference when the measure is unwrapped.
    fn unwrap(&self, n: usize, m: &Measure, raw: D) -> D {
        let r = self.refs[n];
        if m.unwrapped() && r.is_finite() {
            let k = ((r - raw.v) / (2.0 * PI)).round();
            D {
                v: raw.v + 2.0 * PI * k,
                g: raw.g,
            }
        } else {
            raw
        }
    }
}

impl System {
    /// Evaluates the measures `map` (from [`System::resolve_slots`]) and writes each
    /// value to `out[slot]` for the matching entry of `slots`, the array an expression's
    /// evaluation context reads. Returns the evaluations, derivatives included.
    pub fn fill_slots(&self, map: &[usize], slots: &[u32], out: &mut [f64]) -> Vec<Evaluated> {
        let evs: Vec<Evaluated> = map.iter().map(|&m| self.measures.eval(self, m)).collect();
        for (ev, &s) in evs.iter().zip(slots) {
            out[s as usize] = ev.value();
        }
        evs
    }
}

/// AX, AY, AZ (`axis` 0, 1, 2) of marker i relative to j as a dual, by hand: the angle
/// is atan2(s a·b, a·c) with a an axis of i and b, c axes of j, and turning i's part
/// about e_k moves a by e_k × a, so ∂/∂θ_i = (X s (a × b) − Y (a × c))/(X² + Y²) with
/// Y = s a·b, X = a·c, and ∂/∂θ_j is its negative. Through dual frames the same
/// derivatives took ~5,000 instructions a call (three 49-number axes a part, products
/// of 48-entry gradients), the slider-crank MOTION row's whole cost; by hand they equal
/// them to rounding (the tests hold them to 1e-12), the value bit for bit.
fn angle(sys: &System, i: M, j: M, axis: u8, slots: &mut PartSlots) -> Option<D> {
    let (ka, kb, kc, s) = match axis {
        0 => (2, 1, 2, -1.0),
        1 => (2, 0, 2, 1.0),
        _ => (0, 1, 0, 1.0),
    };
    let (fi, fj) = (sys.frame(i), sys.frame(j));
    // The slots in the order the dual frames took them: i's part, then j's.
    let si = slots.slot(sys, fi.part).ok()?;
    let sj = slots.slot(sys, fj.part).ok()?;
    let col =
        |r: &crate::vocab::math::Mat3, k: usize| -> V<f64> { V([r[(0, k)], r[(1, k)], r[(2, k)]]) };
    let (a, b, c) = (col(&fi.rot, ka), col(&fj.rot, kb), col(&fj.rot, kc));
    let y = match s < 0.0 {
        true => -a.dot(&b),
        false => a.dot(&b),
    };
    let x = a.dot(&c);
    let r2 = y * y + x * x;
    let (p, q) = (x / r2, -y / r2);
    let (ab, ac) = (a.cross(&b), a.cross(&c));
    let mut out = D::c(y.atan2(x));
    for k in 0..3 {
        let gi = p * (s * ab.0[k]) + q * ac.0[k];
        if let Some(si) = si {
            out.g[PER_PART * si + 3 + k] += gi;
        }
        if let Some(sj) = sj {
            out.g[PER_PART * sj + 3 + k] -= gi;
        }
    }
    Some(out)
}

/// d/dt|_l (r_i − r_j) with frames [i, j, k, l].
fn rel_vel<T: Scalar>(f: &[Frame<T>]) -> V<T> {
    rel_vel_l(f, 3)
}

/// d/dt|_l (r_i − r_j) = ṙ_i − ṙ_j − ω_l × (r_i − r_j), with l = f[li].
fn rel_vel_l<T: Scalar>(f: &[Frame<T>], li: usize) -> V<T> {
    let d = f[0].r.sub(&f[1].r);
    f[0].vel.sub(&f[1].vel).sub(&f[li].w.cross(&d))
}
