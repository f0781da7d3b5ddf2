//! A lock-up or singular position named: where a kinematic analysis cannot go on, the
//! scaled constraint Jacobian's smallest singular value against its largest says
//! whether the constraints are losing rank there; its left singular vector weighs the
//! rows that become dependent (named by their elements, the most involved first), its
//! right singular vector is the direction the constraints no longer fix (named by
//! [`describe`]: part, coordinate, and the element that lets it move).

use super::error::LockUp;
use crate::mbd::dynamics::Dynamics;
use crate::mbd::freedom::{describe, scaled_jacobian};
use crate::vocab::elements::ElementKind;

/// Smallest over largest singular value of the scaled constraint Jacobian below which
/// the configuration where a kinematic analysis stopped counts as singular. The
/// redundancy analysis' own tolerance is 1e-8, for exact dependence; the analysis
/// stops a little before the singular position (at a dead centre the smallest singular
/// value falls as the square root of the distance in time), as the session's lock-up
/// diagnosis of a failed dynamics does.
pub const LOCK_UP_DISTANCE: f64 = 1e-3;

/// An element named among those whose equations become dependent when its rows carry
/// at least this share of the left singular vector's weight the most involved one
/// carries.
const INVOLVED: f64 = 0.05;

/// The lock-up at `d`'s configuration (positions solved at its time), or None when
/// the kept constraints are of full rank there (by [`LOCK_UP_DISTANCE`]).
pub fn diagnose(d: &mut Dynamics) -> Option<LockUp> {
    if d.n == 0 || d.eval_constraints(true).is_err() {
        return None;
    }
    let svd = scaled_jacobian(d).svd(true, true);
    let (u, vt) = (svd.u.as_ref()?, svd.v_t.as_ref()?);
    let s = &svd.singular_values;
    let top = s.max();
    let k = s.argmin().0;
    let distance = s[k] / top.max(f64::MIN_POSITIVE);
    // NaN (a Jacobian not finite) is no diagnosis either.
    if distance.is_nan() || distance > LOCK_UP_DISTANCE {
        return None;
    }
    // Each element's share of the dependent combination of rows.
    let mut weight: Vec<(usize, f64)> = Vec::new();
    for r in 0..d.m {
        let e = d.rows[r].0;
        let w = u[(r, k)] * u[(r, k)];
        match weight.iter_mut().find(|(x, _)| *x == e) {
            Some((_, total)) => *total += w,
            None => weight.push((e, w)),
        }
    }
    weight.sort_by(|a, b| b.1.total_cmp(&a.1));
    let most = weight.first().map_or(0.0, |w| w.1);
    let elements: Vec<_> = weight
        .iter()
        .filter(|(_, w)| *w >= INVOLVED * most)
        .map(|&(e, _)| d.sys.elements[e].elref.clone())
        .collect();
    let drive = elements
        .iter()
        .find(|e| e.kind == ElementKind::Motion)
        .cloned();
    Some(LockUp {
        time: d.sys.time,
        elements,
        free: describe(d, &vt.row(k).transpose()),
        distance,
        drive,
    })
}
