//! The directions the kept constraints leave free, named the way a user would fix them:
//! which part moves, along or about which axis, and which constraint element lets it.
//! The static solver names a neutral or unstable direction with it, the kinematic
//! analysis the degrees of freedom that keep a model from being fully driven.
//!
//! Directions are worked in scaled coordinates s (δq = D·s, D = the model length for a
//! translation and 1 for a rotation), so a translation and a rotation compare.

use super::dynamics::{Culprit, Dynamics};
use super::rows::Row;
use super::system::PartHandle;
use crate::vocab::math::{DMat, DVec, Vec3};

/// A singular value of the scaled Jacobian below this fraction of the largest counts as
/// zero.
const RANK_TOL: f64 = 1e-9;

/// One free direction, named.
#[derive(Clone, Debug, PartialEq)]
pub struct Freedom {
    /// The coordinate that moves most (`PART/3 rotation about z`).
    pub coordinate: String,
    /// The element that lets it move (the constraint between the moving part and the
    /// rest whose markers move apart most), else the part no constraint holds.
    pub culprit: Option<Culprit>,
}

impl std::fmt::Display for Freedom {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.culprit {
            Some(Culprit::Element(_)) => write!(
                f,
                "{}, which {} leaves free",
                self.coordinate,
                self.culprit
                    .as_ref()
                    .map_or(String::new(), |c| c.to_string())
            ),
            _ => write!(f, "{}, held by no constraint", self.coordinate),
        }
    }
}

/// The scale of column `c` (velocity layout): the model length for a translation, 1 for
/// a rotation.
pub fn column_scale(d: &Dynamics, c: usize) -> f64 {
    let bs = d.sys.dim.cols();
    match c % bs < d.sys.dim.axes() {
        true => d.sys.length,
        false => 1.0,
    }
}

/// An orthonormal basis of the null space of the kept rows' Jacobian (from the last
/// [`Dynamics::eval_constraints`] with Jacobian), in scaled coordinates, one column per
/// free direction.
pub fn null_space(d: &Dynamics) -> DMat {
    let n = d.n;
    if n == 0 {
        return DMat::zeros(0, 0);
    }
    let svd = scaled_jacobian(d).svd(false, true);
    let Some(vt) = svd.v_t else {
        return DMat::zeros(n, 0);
    };
    let top = svd.singular_values.max();
    let free: Vec<usize> = (0..svd.singular_values.len())
        .filter(|&k| svd.singular_values[k] <= RANK_TOL * top.max(f64::MIN_POSITIVE))
        .collect();
    let mut out = DMat::zeros(n, free.len());
    for (k, &i) in free.iter().enumerate() {
        out.set_column(k, &vt.row(i).transpose());
    }
    out
}

/// The kept rows' Jacobian (from the last [`Dynamics::eval_constraints`] with
/// Jacobian) in scaled coordinates, rows scaled as their residuals are, padded with
/// zero rows to a square so that its SVD gives every right singular vector.
pub fn scaled_jacobian(d: &Dynamics) -> DMat {
    let mut j = DMat::zeros(d.n.max(d.m), d.n);
    for (r, c, x) in d.jac.entries() {
        let (e, q) = d.rows[r];
        j[(r, c)] += x * d.sys.row_scale(e, q) * column_scale(d, c);
    }
    j
}

/// The basis `basis` (columns, scaled coordinates) recombined so that each direction
/// moves one coordinate the others leave still (Gauss–Jordan with full pivoting), the
/// directions named one per coordinate.
pub fn describe_all(d: &Dynamics, basis: &DMat) -> Vec<Freedom> {
    let (b, _) = independent(basis);
    (0..b.ncols())
        .map(|k| describe(d, &b.column(k).into_owned()))
        .collect()
}

/// The basis `basis` (n × k, columns) recombined by Gauss–Jordan with full pivoting so
/// that direction j moves coordinate `coords[j]` by 1 and the other chosen coordinates
/// not at all: the chosen coordinates are independent ones, the rest follow them. The
/// pivots are the largest entries left, so the recombination is as well conditioned as
/// the basis allows. Returns the recombined basis and the chosen coordinates.
pub fn independent(basis: &DMat) -> (DMat, Vec<usize>) {
    let (b, coords) = pivot_candidates(basis.transpose(), 0);
    (b.transpose(), coords)
}

/// A preferred candidate's pivot is taken above this fraction of the best other one at
/// the same step: below it, the preferred candidate is nearly a combination of those
/// already chosen and the recombination would be ill-conditioned.
pub const PREFERENCE: f64 = 1e-3;

/// Gauss–Jordan with full pivoting on the rows of `b` (k × candidates: each candidate's
/// value along each direction), choosing one candidate per row; the first `preferred`
/// candidates are taken at every step where one reaches [`PREFERENCE`] of the best other
/// pivot. Returns `b` with the chosen candidates' columns made the identity, and those
/// candidates in order (fewer than k when the rows run out of rank).
pub fn pivot_candidates(mut b: DMat, preferred: usize) -> (DMat, Vec<usize>) {
    let k = b.nrows();
    let mut used = vec![false; b.ncols()];
    let mut coords = Vec::with_capacity(k);
    for row in 0..k {
        // The largest remaining entry of rows row.. among `cols` picks a pivot.
        let best_in = |cols: std::ops::Range<usize>, b: &DMat| {
            let mut best = (row, 0, 0.0f64);
            for r in row..k {
                for c in cols.clone().filter(|&c| !used[c]) {
                    if b[(r, c)].abs() > best.2 {
                        best = (r, c, b[(r, c)].abs());
                    }
                }
            }
            best
        };
        let (first, other) = (best_in(0..preferred, &b), best_in(preferred..b.ncols(), &b));
        let (r, c, top) = match first.2 > 0.0 && first.2 >= PREFERENCE * other.2 {
            true => first,
            false => other,
        };
        if top == 0.0 {
            break;
        }
        b.swap_rows(row, r);
        used[c] = true;
        coords.push(c);
        let p = b[(row, c)];
        let pivot = b.row(row) / p;
        b.set_row(row, &pivot);
        for other in (0..k).filter(|&o| o != row) {
            let f = b[(other, c)];
            if f != 0.0 {
                let sub = b.row(row) * f;
                let mut target = b.row_mut(other);
                target -= sub;
            }
        }
    }
    (b, coords)
}

/// The part whose block holds column `col` of the velocity layout.
pub fn column_part(d: &Dynamics, col: usize) -> Option<PartHandle> {
    let index = col / d.sys.dim.cols();
    d.sys
        .parts
        .iter()
        .position(|p| p.index == Some(index))
        .map(|h| PartHandle(h as u32))
}

/// Names the direction `s` (scaled coordinates): its largest coordinate, and the
/// constraint element on that coordinate's part whose markers it moves apart most.
pub fn describe(d: &Dynamics, s: &DVec) -> Freedom {
    let col = s.iamax();
    let part = column_part(d, col);
    let Some(part) = part else {
        return Freedom {
            coordinate: format!("column {col}"),
            culprit: None,
        };
    };
    let coordinate = coordinate_name(d, part, col);
    // δq per part: (δr, δθ) in global axes.
    let dq: DVec = DVec::from_iterator(d.n, (0..d.n).map(|c| s[c] * column_scale(d, c)));
    let motion = |h: PartHandle| -> (Vec3, Vec3) {
        let mut out = [0.0; 6];
        for (k, x) in out.iter_mut().enumerate() {
            if let Some(c) = d.sys.col(h, k) {
                *x = dq[c];
            }
        }
        (
            Vec3::new(out[0], out[1], out[2]),
            Vec3::new(out[3], out[4], out[5]),
        )
    };
    // Per constraint element on the part: the relative motion (δv, δω) of its two
    // parts at its I marker's origin; the one that moves most lets the direction go.
    let mut best: Option<(usize, Vec3, Vec3, f64)> = None;
    for (e, el) in d.sys.elements.iter().enumerate() {
        let Some((i, j)) = el.eqs.iter().find_map(|q| match &q.row {
            Row::Along { i, j, .. } | Row::Dot { i, j, .. } => Some((*i, *j)),
            _ => None,
        }) else {
            continue;
        };
        let (pi, pj) = (d.sys.marker(i).part, d.sys.marker(j).part);
        if pi != part && pj != part {
            continue;
        }
        let at = d.sys.frame(Some(i)).r;
        let point = |h: PartHandle| {
            let (dr, dth) = motion(h);
            (dr + dth.cross(&(at - d.sys.part(h).r)), dth)
        };
        let ((vi, wi), (vj, wj)) = (point(pi), point(pj));
        let (dv, dw) = (vi - vj, wi - wj);
        let score = dv.norm() / d.sys.length + dw.norm();
        if best.as_ref().is_none_or(|b| score > b.3) {
            best = Some((e, dv, dw, score));
        }
    }
    let Some((e, dv, dw, _)) = best else {
        return Freedom {
            coordinate,
            culprit: d.sys.part(part).id.map(Culprit::Part),
        };
    };
    // Named as the element lets it move: a rotation when that dominates at its marker
    // (a pendulum's CM moves too, but it turns about its pin).
    const AXES: [&str; 3] = ["x", "y", "z"];
    let coordinate = match dw.norm() * d.sys.length >= dv.norm() {
        true => format!("{} rotation about {}", part_name(d, part), AXES[dw.iamax()]),
        false => format!("{} {} translation", part_name(d, part), AXES[dv.iamax()]),
    };
    Freedom {
        coordinate,
        culprit: Some(Culprit::Element(d.sys.elements[e].elref.clone())),
    }
}

/// `PART/3`, or `part 3` for one the model does not name.
pub fn part_name(d: &Dynamics, h: PartHandle) -> String {
    d.sys
        .part(h)
        .id
        .map_or(format!("part {}", h.0), |id| format!("PART/{id}"))
}

/// Column `col` of the velocity layout, on part `part`, named: `PART/3 rotation about z`.
pub fn coordinate_name(d: &Dynamics, part: PartHandle, col: usize) -> String {
    let c = col % d.sys.dim.cols();
    format!("{} {}", part_name(d, part), component_name(d, c))
}

/// What column `c` of a part's block (velocity layout) moves: `x translation`,
/// `rotation about z`, …
pub fn component_name(d: &Dynamics, c: usize) -> String {
    const AXES: [&str; 3] = ["x", "y", "z"];
    let comps = d.sys.column_components();
    let k = comps[c];
    match k < 3 {
        true => format!("{} translation", AXES[k]),
        false => format!("rotation about {}", AXES[k - 3]),
    }
}
