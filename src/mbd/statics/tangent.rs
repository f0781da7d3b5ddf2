//! The tangent of the constraint forces, ∂(Φ_qᵀ·λ)/∂q at fixed λ, for the static
//! Newton matrix: every primitive joint row in full, the parts it couples included
//! (the dynamics keeps only the share that falls on one part, `dynamics::stiffness`).
//!
//! A row's Jacobian is its gradient with respect to the increments the state moves by
//! (δr, and a rotation vector δθ turning R into exp(\[δθ\]×)·R, global axes), taken at
//! the moved state: its derivative is that of the gradient blocks, each a cross product
//! of vectors that turn with their parts (δu = δθ × u = −\[u\]×·δθ). With a = J's axis in
//! global axes, uᵢ and uⱼ the marker offsets, p = rᵢ + uᵢ − rⱼ, and the gradient blocks
//! of each primitive:
//!
//! - `Fixed` (axis e constant): ∂/∂rᵢ = e, ∂/∂θᵢ = uᵢ × e, ∂/∂rⱼ = −e, ∂/∂θⱼ = e × uⱼ;
//! - `Along` (a = Rⱼ·axis): a, uᵢ × a, −a, a × p;
//! - `Dot` (u = Rᵢ·a, w = Rⱼ·b): ∂/∂θᵢ = u × w, ∂/∂θⱼ = w × u.
//!
//! MOTION and GCON rows (measures, expressions) add no tangent here: Newton still
//! converges where they carry a reaction, only no longer quadratically.

use crate::mbd::constraints::Primitive;
use crate::mbd::dynamics::Dynamics;
use crate::mbd::system::PartHandle;
use crate::vocab::math::{DMat, Mat3, Vec3};

/// [v]×, the matrix of v × ·.
fn skew(v: &Vec3) -> Mat3 {
    v.cross_matrix()
}

/// Which of a part's two 3-vectors a block belongs to.
#[derive(Clone, Copy)]
enum Var {
    R(PartHandle),
    Th(PartHandle),
}

/// Adds λ·∂(row gradient)/∂q of every primitive kept row of `d` (its last constraint
/// evaluation's state) into the n × n top-left of `k`.
pub fn add_constraint_tangent(d: &Dynamics, lambda: &[f64], k: &mut DMat) {
    for (r, &l) in lambda.iter().enumerate().take(d.m) {
        if l == 0.0 {
            continue;
        }
        let Some(p) = d.primitive(r) else { continue };
        for (x, y, b) in blocks(d, &p) {
            add_block(d, k, x, y, &(b * l));
        }
    }
}

/// The (gradient variable, derivative variable, 3 × 3 block) triples of one primitive.
fn blocks(d: &Dynamics, p: &Primitive) -> Vec<(Var, Var, Mat3)> {
    let sys = &d.sys;
    match *p {
        Primitive::Fixed(pa) => {
            let (ui, uj) = (
                sys.part(pa.pi).rotation() * pa.si,
                sys.part(pa.pj).rotation() * pa.sj,
            );
            let e = skew(&pa.axis);
            vec![
                (Var::Th(pa.pi), Var::Th(pa.pi), e * skew(&ui)),
                (Var::Th(pa.pj), Var::Th(pa.pj), -e * skew(&uj)),
            ]
        }
        Primitive::Along(pa) => {
            let (bi, bj) = (sys.part(pa.pi), sys.part(pa.pj));
            let ui = bi.rotation() * pa.si;
            let a = bj.rotation() * pa.axis;
            let p = bi.r + ui - bj.r;
            let (ax, uix) = (skew(&a), skew(&ui));
            let (i, j) = (pa.pi, pa.pj);
            vec![
                (Var::R(i), Var::Th(j), -ax),
                (Var::R(j), Var::Th(j), ax),
                (Var::Th(i), Var::Th(i), ax * uix),
                (Var::Th(i), Var::Th(j), -uix * ax),
                (Var::Th(j), Var::R(i), ax),
                (Var::Th(j), Var::R(j), -ax),
                (Var::Th(j), Var::Th(i), -ax * uix),
                (Var::Th(j), Var::Th(j), skew(&p) * ax),
            ]
        }
        Primitive::Dot { pi, u, pj, w } => {
            let (u, w) = (sys.part(pi).rotation() * u, sys.part(pj).rotation() * w);
            let (ux, wx) = (skew(&u), skew(&w));
            vec![
                (Var::Th(pi), Var::Th(pi), wx * ux),
                (Var::Th(pi), Var::Th(pj), -ux * wx),
                (Var::Th(pj), Var::Th(pi), -wx * ux),
                (Var::Th(pj), Var::Th(pj), ux * wx),
            ]
        }
    }
}

/// The velocity-layout columns of a variable's three components (None: ground, or a
/// component the 2D layout does not have).
fn columns(d: &Dynamics, v: Var) -> [Option<usize>; 3] {
    let (h, first) = match v {
        Var::R(h) => (h, 0),
        Var::Th(h) => (h, 3),
    };
    std::array::from_fn(|k| d.sys.col(h, first + k))
}

fn add_block(d: &Dynamics, k: &mut DMat, x: Var, y: Var, b: &Mat3) {
    let (rows, cols) = (columns(d, x), columns(d, y));
    for (a, r) in rows.iter().enumerate() {
        let Some(r) = *r else { continue };
        for (c, col) in cols.iter().enumerate() {
            if let Some(col) = *col {
                k[(r, col)] += b[(a, c)];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::add_constraint_tangent;
    use crate::mbd::dynamics::Dynamics;
    use crate::vocab::math::{DMat, DVec};

    /// A spatial chain off its axes: a spherical joint, a revolute, a translational and
    /// a cylindrical joint between tilted parts, so every primitive (Fixed, Along, Dot)
    /// has rotations in all three axes.
    const CHAIN: &str = "tangent\nPART/1, GROUND\nMARKER/10, PART = 1, REULER = 10D, 20D, 30D\n\
        MARKER/11, PART = 1, QP = 2, 0.5, 0.1, REULER = 40D, 70D, 10D\n\
        PART/2, MASS = 1, CM = 20, IP = 1, 2, 3, REULER = 15D, 25D, 5D\n\
        MARKER/20, PART = 2, QP = 0.5, 0.2, 0.1\nMARKER/21, PART = 2, REULER = 10D, 20D, 30D\n\
        MARKER/22, PART = 2, QP = 1, 0.3, -0.2, REULER = 30D, 60D, 20D\n\
        PART/3, MASS = 1, CM = 30, IP = 1, 2, 3, QG = 1, 0.3, -0.2, REULER = 50D, 35D, 15D\n\
        MARKER/30, PART = 3, QP = 0.4, 0.1, 0.3\nMARKER/31, PART = 3, REULER = 30D, 60D, 20D\n\
        MARKER/32, PART = 3, QP = 0.8, 0.2, 0.4, REULER = 40D, 70D, 10D\n\
        JOINT/1, SPHERICAL, I = 21, J = 10\nJOINT/2, REVOLUTE, I = 31, J = 22\n\
        JOINT/3, CYLINDRICAL, I = 32, J = 11\nEND\n";

    /// The chain as placed (not assembled: the tangent holds at any state).
    fn dynamics() -> Dynamics {
        let read = crate::model::read_model(CHAIN);
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        let exprs = crate::mbd::compiled::CompiledExprs::new();
        let sys = crate::mbd::System::from_model(&read.model, crate::mbd::Dim::Three, &exprs)
            .expect("the chain builds");
        let forces = crate::mbd::forces::ForceSet::default();
        Dynamics::new(sys, forces, &[]).expect("dynamics")
    }

    /// Φ_qᵀλ at the state moved by `dx` from `base`.
    fn constraint_forces(
        d: &mut Dynamics,
        base: &crate::mbd::dynamics::Snapshot,
        dx: &[f64],
        lambda: &DVec,
    ) -> DVec {
        let v = DVec::zeros(d.n);
        d.set_state(base, dx, &v, 0.0);
        d.eval_constraints(true).expect("rows");
        let mut out = DVec::zeros(d.n);
        d.add_constraint_forces(lambda, &mut out);
        out
    }

    #[test]
    fn the_tangent_matches_central_differences_of_the_constraint_forces() {
        let mut d = dynamics();
        let (n, m) = (d.n, d.m);
        let lambda = DVec::from_iterator(m, (0..m).map(|r| 0.7 - 0.3 * r as f64));
        let base = d.snapshot();
        d.eval_constraints(true).expect("rows");
        let mut exact = DMat::zeros(n, n);
        add_constraint_tangent(&d, lambda.as_slice(), &mut exact);
        let h = 1e-6;
        let mut worst: f64 = 0.0;
        for c in 0..n {
            let mut dx = vec![0.0; n];
            dx[c] = h;
            let plus = constraint_forces(&mut d, &base, &dx, &lambda);
            dx[c] = -h;
            let minus = constraint_forces(&mut d, &base, &dx, &lambda);
            let fd = (plus - minus) / (2.0 * h);
            for r in 0..n {
                worst = worst.max((fd[r] - exact[(r, c)]).abs());
            }
        }
        assert!(worst < 1e-7, "tangent off by {worst:e}");
    }
}
