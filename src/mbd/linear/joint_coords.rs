//! The joints' own coordinates, offered to a linearization as its minimal coordinates
//! (issue 41 §4): an engineer reads a revolute's mode in its rotation and a
//! translational's in its travel, not in whichever part coordinate moves most.
//!
//! Each joint that leaves motion free gives one linear functional of the velocities per
//! free direction, its rate: for a rotation about an axis u (global) the relative
//! angular velocity (ω_I − ω_J)·u; for a translation of I's origin along u fixed in J,
//! u·(v_I + ω_I×s_I − v_J − ω_J×s_J) + (r_I − r_J)·(ω_J×u), with s the marker's offset
//! from its part's reference point. Restricted to the constraints' null space, these are
//! exactly the joint coordinates' first variations.
//!
//! [`choose`] picks the minimal coordinates by Gaussian elimination on the null space,
//! taking a joint coordinate at every pivot where one is independent enough and a model
//! coordinate only where none is (a free part, a GCON), so that δq = T·z with z the
//! chosen coordinates themselves.

use crate::mbd::dynamics::Dynamics;
use crate::mbd::error::element_name;
use crate::mbd::freedom::pivot_candidates;
use crate::mbd::rows::Row;
use crate::mbd::system::{MarkerHandle, PartHandle};
use crate::vocab::elements::{ElementKind, JointType};
use crate::vocab::math::{DMat, DVec, Vec3};

/// One joint's own coordinate.
pub struct JointCoordinate {
    /// `JOINT/1 rotation`, `JOINT/4 translation`, `JOINT/5 rotation about its x`.
    pub name: String,
    /// Its rate as a functional of the velocities (velocity layout, model units).
    pub row: DVec,
    /// The model length for a translation, 1 for a rotation.
    pub scale: f64,
    /// The part of the joint's I marker.
    pub part: PartHandle,
}

/// One chosen minimal coordinate: a joint's (index into the joint coordinates) or a
/// model column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Chosen {
    /// A joint coordinate.
    Joint(usize),
    /// A column of the velocity layout.
    Column(usize),
}

/// The free coordinates of every joint of `d` that has any.
pub fn joint_coordinates(d: &Dynamics) -> Vec<JointCoordinate> {
    let sys = &d.sys;
    let mut out = Vec::new();
    for el in &sys.elements {
        let ElementKind::Joint(kind) = el.elref.kind else {
            continue;
        };
        let Some((i, j)) = el.eqs.iter().find_map(|q| match &q.row {
            Row::Along { i, j, .. } | Row::Dot { i, j, .. } => Some((*i, *j)),
            _ => None,
        }) else {
            continue;
        };
        let (fi, fj) = (sys.frame(Some(i)), sys.frame(Some(j)));
        let (xi, zi) = (fi.rot.column(0).into_owned(), fi.rot.column(2).into_owned());
        let xj: Vec3 = fj.rot.column(0).into_owned();
        let (yj, zj): (Vec3, Vec3) = (fj.rot.column(1).into_owned(), fj.rot.column(2).into_owned());
        let name = element_name(&el.elref);
        let free: Vec<(String, Motion)> = match kind {
            JointType::Revolute => vec![("rotation".into(), Motion::Turn(zj))],
            JointType::Translational => vec![("translation".into(), Motion::Slide(zj))],
            JointType::Cylindrical => vec![
                ("translation".into(), Motion::Slide(zj)),
                ("rotation".into(), Motion::Turn(zj)),
            ],
            JointType::Spherical => vec![
                ("rotation about its x".into(), Motion::Turn(xj)),
                ("rotation about its y".into(), Motion::Turn(yj)),
                ("rotation about its z".into(), Motion::Turn(zj)),
            ],
            JointType::Planar => vec![
                ("x translation".into(), Motion::Slide(xj)),
                ("y translation".into(), Motion::Slide(yj)),
                ("rotation".into(), Motion::Turn(zj)),
            ],
            JointType::Universal => vec![
                ("rotation about I's z".into(), Motion::Turn(zi)),
                ("rotation about J's z".into(), Motion::Turn(zj)),
            ],
            JointType::Hooke => vec![
                ("rotation about I's x".into(), Motion::Turn(xi)),
                ("rotation about J's y".into(), Motion::Turn(yj)),
            ],
            _ => Vec::new(),
        };
        for (what, motion) in free {
            let row = rate_row(d, i, j, motion);
            if row.amax() == 0.0 {
                // A direction the layout does not have (out of plane in 2D).
                continue;
            }
            out.push(JointCoordinate {
                name: format!("{name} {what}"),
                row,
                scale: match motion {
                    Motion::Turn(_) => 1.0,
                    Motion::Slide(_) => sys.length,
                },
                part: sys.marker(i).part,
            });
        }
    }
    out
}

/// A free direction of a joint: a rotation about, or a translation of I along, a
/// global axis.
#[derive(Clone, Copy)]
enum Motion {
    Turn(Vec3),
    Slide(Vec3),
}

/// The rate of `motion` between markers `i` and `j` as a row over the velocity layout.
fn rate_row(d: &Dynamics, i: MarkerHandle, j: MarkerHandle, motion: Motion) -> DVec {
    let sys = &d.sys;
    let mut row = DVec::zeros(d.n);
    // Adds sign·(t·v_part + w·ω_part) for the part of marker m.
    let mut add = |m: MarkerHandle, t: Vec3, w: Vec3, sign: f64| {
        let part = sys.marker(m).part;
        for k in 0..3 {
            if let Some(c) = sys.col(part, k) {
                row[c] += sign * t[k];
            }
            if let Some(c) = sys.col(part, k + 3) {
                row[c] += sign * w[k];
            }
        }
    };
    match motion {
        Motion::Turn(u) => {
            add(i, Vec3::zeros(), u, 1.0);
            add(j, Vec3::zeros(), u, -1.0);
        }
        Motion::Slide(u) => {
            let (ri, rj) = (sys.frame(Some(i)).r, sys.frame(Some(j)).r);
            let si = ri - sys.part(sys.marker(i).part).r;
            let sj = rj - sys.part(sys.marker(j).part).r;
            add(i, u, si.cross(&u), 1.0);
            // −u·v_J − ω_J·(s_J×u) + ω_J·(u×(r_I − r_J)): J's axis turns with J.
            add(j, u, sj.cross(&u) - u.cross(&(ri - rj)), -1.0);
        }
    }
    row
}

/// Chooses the minimal coordinates on the null space `ns` (n × f, scaled coordinates:
/// δq = diag(`scale`)·s): a joint coordinate at each pivot where one is independent
/// enough ([`pivot_candidates`]), else a model column. Returns T in scaled coordinates (n × f,
/// the chosen coordinates' scaled values ẑ: s = T·ẑ) and what each column of T is.
pub fn choose(ns: &DMat, joints: &[JointCoordinate], scale: &[f64]) -> (DMat, Vec<Chosen>) {
    let (n, f, g) = (ns.nrows(), ns.ncols(), joints.len());
    // b = [ (H·ns)ᵀ | nsᵀ ]: the candidates' values along each null-space direction, the
    // joint coordinates' first (scaled: h = row∘scale / its own scale).
    let mut b = DMat::zeros(f, g + n);
    for (k, jc) in joints.iter().enumerate() {
        let h = DVec::from_iterator(n, (0..n).map(|c| jc.row[c] * scale[c] / jc.scale));
        let along = ns.transpose() * h;
        b.set_column(k, &along);
    }
    b.view_mut((0, g), (f, n)).copy_from(&ns.transpose());
    let (b, mut picked) = pivot_candidates(b, g);
    // In the joints' order, then the columns': a reading order that does not depend on
    // the pivots (b's rows follow the candidates they were pivoted on).
    let mut rows: Vec<usize> = (0..picked.len()).collect();
    rows.sort_by_key(|&r| picked[r]);
    let t = DMat::from_fn(n, rows.len(), |c, k| b[(rows[k], g + c)]);
    picked.sort_unstable();
    let chosen = picked
        .iter()
        .map(|&c| match c < g {
            true => Chosen::Joint(c),
            false => Chosen::Column(c - g),
        })
        .collect();
    (t, chosen)
}
