//! Marker frames at the state of the system, as duals over the local directions of the
//! parts they sit on ([`dual_frame`], with the [`PartSlots`] table saying which part
//! each block of directions belongs to) or as plain values ([`value_frame`]); measures
//! and force elements are computed from them.

use crate::mbd::dual::{D, N, PARTS, PER_PART, V};
use crate::mbd::handles::PartHandle;
use crate::mbd::measure_set::M;
use crate::mbd::system::System;
use crate::vocab::math::Vec3;

/// A marker frame as duals: origin, axes, velocity of the origin, angular velocity.
#[derive(Clone, Copy)]
pub(crate) struct Frame<T> {
    pub r: V<T>,
    pub axes: [V<T>; 3],
    pub vel: V<T>,
    pub w: V<T>,
}

/// A marker frame as duals over local directions.
pub(crate) type DFrame = Frame<D>;

/// Which part each block of a dual's local directions belongs to: several duals that
/// share one table can be combined (a force element's frames and the measures its
/// expressions read).
#[derive(Clone, Copy, Debug, Default)]
pub struct PartSlots {
    /// The part of each block (None: free).
    pub parts: [Option<PartHandle>; PARTS],
}

impl PartSlots {
    /// The slot of `part` (None for ground, which has no directions), taking a free one
    /// the first time; Err when all are taken by other parts.
    pub(super) fn slot(&mut self, sys: &System, part: PartHandle) -> Result<Option<usize>, ()> {
        if sys.part(part).index.is_none() {
            return Ok(None);
        }
        if let Some(s) = self.parts.iter().position(|x| *x == Some(part)) {
            return Ok(Some(s));
        }
        let s = self.parts.iter().position(|x| x.is_none()).ok_or(())?;
        self.parts[s] = Some(part);
        Ok(Some(s))
    }

    /// Calls `pos(col, g)` and `vel(col, g)` for every system column a dual's gradient
    /// `g` reaches (velocity-level columns, 2D or 3D layout).
    pub fn scatter(
        &self,
        sys: &System,
        g: &[f64; N],
        pos: &mut dyn FnMut(usize, f64),
        vel: &mut dyn FnMut(usize, f64),
    ) {
        for (s, p) in self.parts.iter().enumerate() {
            let Some(p) = *p else { continue };
            for c in 0..6 {
                if let Some(col) = sys.col(p, c) {
                    let (gp, gv) = (g[PER_PART * s + c], g[PER_PART * s + 6 + c]);
                    if gp != 0.0 {
                        pos(col, gp);
                    }
                    if gv != 0.0 {
                        vel(col, gv);
                    }
                }
            }
        }
    }
}

/// The frame of marker `mk` (ground when None) as duals over the directions of its
/// part's slot in `slots`; None when no slot is free.
pub(crate) fn dual_frame(sys: &System, mk: M, slots: &mut PartSlots) -> Option<DFrame> {
    let f = sys.frame(mk);
    let p = sys.part(f.part);
    let slot = slots.slot(sys, f.part).ok()?;
    let axes = [0, 1, 2].map(|c| Vec3::from(f.rot.column(c)));
    let vel = p.v + p.w.cross(&f.a);
    let mut fr = DFrame {
        r: V::c(f.r),
        axes: axes.map(V::c),
        vel: V::c(vel),
        w: V::c(p.w),
    };
    if let Some(s) = slot {
        let b = PER_PART * s;
        origin_grad(&mut fr.r, b, &f.a);
        for (dual, u) in fr.axes.iter_mut().zip(&axes) {
            axis_grad(dual, b, u);
        }
        for c in 0..3 {
            let ec = e(c);
            let rot_a = ec.cross(&f.a);
            for x in 0..3 {
                fr.vel.0[x].g[b + 3 + c] = p.w.cross(&rot_a)[x];
                fr.vel.0[x].g[b + 6 + c] = ec[x];
                fr.vel.0[x].g[b + 9 + c] = rot_a[x];
                fr.w.0[x].g[b + 9 + c] = ec[x];
            }
        }
    }
    Some(fr)
}

/// Axes `cols` of marker `mk`'s frame as [`dual_frame`] builds them (the same values and
/// derivatives), for formulas that read axes only.
pub(super) fn dual_axes<const K: usize>(
    sys: &System,
    mk: M,
    cols: [usize; K],
    slots: &mut PartSlots,
) -> Option<[V<D>; K]> {
    let f = sys.frame(mk);
    let slot = slots.slot(sys, f.part).ok()?;
    Some(cols.map(|c| {
        let u = Vec3::from(f.rot.column(c));
        let mut axis: V<D> = V::c(u);
        if let Some(s) = slot {
            axis_grad(&mut axis, PER_PART * s, &u);
        }
        axis
    }))
}

/// The origin of marker `mk` as [`dual_frame`] builds it (the same values and
/// derivatives), for formulas that read origins only.
pub(super) fn dual_origin(sys: &System, mk: M, slots: &mut PartSlots) -> Option<V<D>> {
    let (r, a, part) = sys.origin(mk);
    let slot = slots.slot(sys, part).ok()?;
    let mut origin: V<D> = V::c(r);
    if let Some(s) = slot {
        origin_grad(&mut origin, PER_PART * s, &a);
    }
    Some(origin)
}

/// An origin's derivatives in the part block starting at `b`: δr along e_c moves it by
/// e_c, δθ about e_c by e_c × a (`a` its offset from the part's reference point).
fn origin_grad(origin: &mut V<D>, b: usize, a: &Vec3) {
    for c in 0..3 {
        let (ec, rot_a) = (e(c), e(c).cross(a));
        for x in 0..3 {
            origin.0[x].g[b + c] = ec[x];
            origin.0[x].g[b + 3 + c] = rot_a[x];
        }
    }
}

/// An axis `u`'s derivatives in the part block starting at `b`: δθ about e_c turns it by
/// e_c × u.
fn axis_grad(axis: &mut V<D>, b: usize, u: &Vec3) {
    for c in 0..3 {
        let turned = e(c).cross(u);
        for x in 0..3 {
            axis.0[x].g[b + 3 + c] = turned[x];
        }
    }
}

/// The frame of marker `mk` (ground when None) as plain values.
pub(crate) fn value_frame(sys: &System, mk: M) -> Frame<f64> {
    let v3 = |x: Vec3| V([x[0], x[1], x[2]]);
    let f = sys.frame(mk);
    let p = sys.part(f.part);
    let w = p.w;
    Frame {
        r: v3(f.r),
        axes: [0, 1, 2].map(|c| v3(Vec3::from(f.rot.column(c)))),
        vel: v3(p.v + w.cross(&f.a)),
        w: v3(w),
    }
}

/// Axis `c` of marker `mk`'s frame (ground's when None), global.
pub(super) fn axis_value(sys: &System, mk: M, c: u8) -> V<f64> {
    match mk {
        None => V::c(e(c as usize)),
        Some(_) => {
            let u = Vec3::from(sys.frame(mk).rot.column(c as usize));
            V([u.x, u.y, u.z])
        }
    }
}

/// The velocity of marker `mk`'s origin (zero for ground), global. Kept out of line, as
/// it was before measures were split into files: inlined into `MeasureSet::value`, it
/// left no room there for [`System::origin`], and the IMPACT block's run took 1.3 % more
/// instructions (callgrind).
#[inline(never)]
pub(super) fn point_velocity(sys: &System, mk: M) -> Vec3 {
    if mk.is_none() {
        return Vec3::zeros();
    }
    let (_, a, part) = sys.origin(mk);
    let p = sys.part(part);
    p.v + p.w.cross(&a)
}

fn e(c: usize) -> Vec3 {
    let mut v = Vec3::zeros();
    v[c] = 1.0;
    v
}
