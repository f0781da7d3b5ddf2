//! The acceleration-level right-hand side γ of the kept constraint rows: Φ_q·a = γ with
//! γ = −(Φ̈ at zero accelerations). The consistent accelerations and multipliers of
//! spec §6.1 phase 3 need it, at t = 0 and wherever an integrator reconciles.
//!
//! The primitive rows are differentiated twice by hand. For a marker point r = r_P + a
//! on a part moving with (v, ω) and no acceleration, r̈ = ω × (ω × a); a unit axis u
//! fixed on it has u̇ = ω × u, ü = ω × (ω × u). So
//! - `Along`, d·e with d = r_I − r_J, e an axis of J: Φ̈ = d̈·e + 2ḋ·ė + d·ë (d̈·e when
//!   the dynamics froze e, `dynamics::stiffness`);
//! - `Dot`, u·w with u on I and w on J: Φ̈ = ü·w + 2u̇·ẇ + u·ẅ.
//!
//! A non-holonomic GCON f(q, v, t) = 0 is differentiated once: γ = −(f_q·v + f_t).
//! Rows built on measures (GCON, MOTION, RACKPIN, SCREW, CONVEL) take the measures'
//! second time derivatives from jets ([`crate::mbd::measure_set::MeasureSet::jet`]) and the
//! expression's Hessian from the IR derivative applied twice (`ir::deriv::hessian`); where
//! mbfx has no second derivative (SWEEP in arguments other than x and its amplitude),
//! that is an error naming the element and the function, never a silently wrong γ. A VELOCITY
//! or ACCELERATION MOTION's drive is the integral of its function, so its g̈ is ḟ or f.

use super::setup::Dynamics;
use crate::mbd::constraints::Primitive;
use crate::mbd::error::MbdError;
use crate::mbd::expr::ExprError;
use crate::mbd::rows::Row;
use crate::mbd::system::{MarkerHandle, System};
use crate::vocab::math::{DVec, Vec3};

/// Position, velocity and zero-acceleration second derivative of a marker's origin, and
/// its part's angular velocity.
fn point(sys: &System, m: MarkerHandle) -> (Vec3, Vec3, Vec3, Vec3) {
    let f = sys.frame(Some(m));
    let p = sys.part(f.part);
    let w = p.w;
    (f.r, p.v + w.cross(&f.a), w.cross(&w.cross(&f.a)), w)
}

/// An axis `dir` (marker coordinates) of marker `m`: value, first and zero-acceleration
/// second derivative.
fn axis(sys: &System, m: MarkerHandle, dir: &Vec3) -> (Vec3, Vec3, Vec3) {
    let f = sys.frame(Some(m));
    let w = sys.part(f.part).w;
    let u = f.rot * dir;
    (u, w.cross(&u), w.cross(&w.cross(&u)))
}

/// γ for every kept row of `d` at the current state, into `out`.
pub fn gamma(d: &Dynamics, out: &mut DVec) -> Result<(), MbdError> {
    let sys = &d.sys;
    if out.len() != d.m {
        *out = DVec::zeros(d.m);
    }
    for (r, &(e, q)) in d.rows.iter().enumerate() {
        let name = |why: ExprError| match why {
            ExprError::NoDerivative(why) => MbdError::NoSecondDerivative(
                sys.elements[e].elref.clone(),
                sys.elements[e].eqs[q].label.label(),
                why,
            ),
            other => MbdError::Expression(sys.elements[e].elref.clone(), other),
        };
        // A frozen point row (`dynamics::stiffness`): d·e with e constant.
        if let (Row::Along { i, j, .. }, Some((Primitive::Fixed(p), _))) =
            (&sys.elements[e].eqs[q].row, &d.prims[r])
        {
            let (ai, aj) = (point(sys, *i).2, point(sys, *j).2);
            out[r] = -(ai - aj).dot(&p.axis);
            continue;
        }
        out[r] = match &sys.elements[e].eqs[q].row {
            Row::Along { i, j, dir, sign } => {
                let (ri, vi, ai, _) = point(sys, *i);
                let (rj, vj, aj, _) = point(sys, *j);
                let (ev, ed, edd) = axis(sys, *j, dir);
                let (dd, dv, da) = (ri - rj, vi - vj, ai - aj);
                -sign * (da.dot(&ev) + 2.0 * dv.dot(&ed) + dd.dot(&edd))
            }
            Row::Dot { i, j, a, b } => {
                let (u, ud, udd) = axis(sys, *i, a);
                let (w, wd, wdd) = axis(sys, *j, b);
                -(udd.dot(&w) + 2.0 * ud.dot(&wd) + u.dot(&wdd))
            }
            Row::Gcon { .. } if sys.row_reads_velocity(e, q) => {
                let ev = sys.eval_row(e, q)?;
                let v = sys.v();
                -(ev.dq.iter().map(|&(c, x)| x * v[c]).sum::<f64>() + ev.dt)
            }
            Row::Measured { terms, drive } => {
                let mut phi = 0.0;
                for &(c, m) in terms {
                    phi += c * sys.measures.jet(sys, m).dd;
                }
                if let Some(g) = drive {
                    phi -= g.second(sys.time, &[], &[]).map_err(&name)?;
                }
                -phi
            }
            Row::Gcon { f, map } => {
                // f(m(q), t): f̈ = Σ fᵢ·m̈ᵢ + dᵀ·H·d, d = (ṁ, 1).
                let slots = f.slots();
                let len = slots.last().map_or(0, |&s| s as usize + 1);
                let mut vals = vec![0.0; len];
                let mut dir = Vec::with_capacity(map.len());
                let mut acc = Vec::with_capacity(map.len());
                for (&m, &s) in map.iter().zip(slots) {
                    let j = sys.measures.jet(sys, m);
                    vals[s as usize] = j.v;
                    dir.push(j.d);
                    acc.push(j.dd);
                }
                let mut grad = vec![0.0; slots.len()];
                f.gradient(sys.time, &vals, &mut grad).map_err(&name)?;
                let curvature = f.second(sys.time, &vals, &dir).map_err(&name)?;
                -(grad.iter().zip(&acc).map(|(g, a)| g * a).sum::<f64>() + curvature)
            }
        };
    }
    Ok(())
}
