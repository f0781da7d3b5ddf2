//! The forces' derivative by the multipliers, ∂Q/∂λ, for the force laws that read a
//! joint's reaction with their derivative by it (joint friction, [`Generalized::ds`]):
//! ∂Q/∂s chained with ∂s/∂λ, the reaction's own derivative, which is linear in λ (the
//! joint's rows of −Φ_qᵀ·λ on one part, its moment shifted to the marker, resolved in
//! a frame). The Newton matrix takes −w_l·∂Q/∂λ beside w_l·Φ_qᵀ
//! ([`super::fill::Fill::factor`]), so the friction–reaction loop is solved by Newton
//! rather than by repetition.
//!
//! [`Generalized::ds`]: crate::mbd::forces::Generalized::ds

use super::setup::Dynamics;
use crate::mbd::output_slot::OutputSlot;
use crate::vocab::math::Vec3;

impl Dynamics {
    /// ∂Q/∂λ at the last force evaluation as Newton-matrix entries (row, column n + r,
    /// value) into the scratch's `loop_jacobian`, which the next factorization takes
    /// (empty when no force differentiates a reaction).
    pub(super) fn loop_jacobian(&mut self) {
        let mut out = std::mem::take(&mut self.scratch.loop_jacobian);
        out.clear();
        let ds = &self.gen.ds;
        if !ds.is_empty() {
            let mut slots: Vec<usize> = ds.iter().map(|e| e.1).collect();
            slots.sort_unstable();
            slots.dedup();
            let partials: Vec<Vec<(usize, f64)>> =
                slots.iter().map(|&s| self.reaction_rows(s)).collect();
            for &(row, s, x) in ds {
                let Ok(k) = slots.binary_search(&s) else {
                    continue;
                };
                out.extend(partials[k].iter().map(|&(r, y)| (row, self.n + r, x * y)));
            }
        }
        self.scratch.loop_jacobian = out;
    }

    /// ∂s/∂λ of solution value `s` as (kept row, value): a component of a constraint's
    /// reaction (`JOINT(id, jflag, 2…4 or 6…8, rm)`); nothing for what is not linear in λ
    /// (the magnitudes) or not a reaction.
    fn reaction_rows(&self, s: usize) -> Vec<(usize, f64)> {
        let OutputSlot::ElementForce {
            constraint: true,
            element,
            jflag,
            comp,
            rm,
        } = self.forces.solution[s]
        else {
            return Vec::new();
        };
        if comp == 1 || comp == 5 || comp > 8 {
            return Vec::new();
        }
        // As `constraint_load`: the load on the flagged marker's part, about that
        // marker, or the other side's reversed where that part is ground.
        let sys = &self.sys;
        let (i, j) = self.element_markers(element);
        let (me, other) = if jflag { (j, i) } else { (i, j) };
        let at = sys.frame(me).r;
        let (part, sign) = match sys.frame(me).part {
            p if sys.part(p).index.is_some() => (p, 1.0),
            _ => (sys.frame(other).part, -1.0),
        };
        let Some(index) = sys.part(part).index else {
            return Vec::new();
        };
        let axis: Vec3 = sys.frame(rm).rot.column(usize::from((comp - 2) % 4)).into();
        let arm = sys.part(part).r - at;
        let bs = self.jac.bs;
        // The component each of the part's columns carries.
        let comps: Vec<Option<usize>> = (0..bs)
            .map(|k| (0..6).find(|&c| sys.col(part, c) == Some(index * bs + k)))
            .collect();
        let mut out = Vec::new();
        for (r, &(e, _)) in self.rows.iter().enumerate() {
            let Some(slot) = (e == element).then(|| self.jac.slot_of(r, index)).flatten() else {
                continue;
            };
            // Row r's load on the part per unit λ_r: −(its Φ_q entries).
            let mut g = [0.0; 6];
            for (x, c) in self.jac.block(slot).iter().zip(&comps) {
                if let Some(c) = c {
                    g[*c] -= x;
                }
            }
            let f = Vec3::new(g[0], g[1], g[2]);
            let v = match comp <= 4 {
                true => f,
                false => Vec3::new(g[3], g[4], g[5]) + arm.cross(&f),
            };
            let y = sign * axis.dot(&v);
            if y != 0.0 {
                out.push((r, y));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    //! ∂Q/∂λ of joint friction against central differences of Q in the multipliers
    //! (the test oracle DESIGN.md allows), in every joint type friction acts in.
    use super::super::setup::Dynamics;
    use crate::mbd::compiled::CompiledExprs;
    use crate::mbd::planar::Dim;
    use crate::mbd::system::System;
    use crate::model::read_model;

    /// Five parts moving against ground, one joint with its friction each: cylindrical,
    /// revolute, spherical, translational, universal; the joint markers off the CMs and
    /// turned, so the reactions' arms and axes matter.
    const JOINTS: &str = "joints\nPART/1, GROUND\n\
        MARKER/1, PART = 1, QP = 0.1, 0.2, 0\n\
        MARKER/2, PART = 1, QP = 2.1, 0.2, 0, REULER = 0, 30D, 0\n\
        MARKER/3, PART = 1, QP = 4.1, 0.2, 0\n\
        MARKER/4, PART = 1, QP = 6.1, 0.2, 0, REULER = 20D, 90D, 0\n\
        MARKER/5, PART = 1, QP = 8.1, 0.2, 0, REULER = 0, 90D, 0\n\
        PART/2, MASS = 2, CM = 20, IP = 1, 2, 3, VX = 0.3, VZ = 0.5, WZ = 0.7, WX = 0.2\n\
        MARKER/20, PART = 2\nMARKER/21, PART = 2, QP = 0.1, 0.2, 0\n\
        PART/3, MASS = 2, CM = 30, IP = 1, 2, 3, QG = 2, 0, 0, WZ = 0.9, WY = -0.3\n\
        MARKER/30, PART = 3\nMARKER/31, PART = 3, QP = 0.1, 0.2, 0, REULER = 0, 30D, 0\n\
        PART/4, MASS = 2, CM = 40, IP = 1, 2, 3, QG = 4, 0, 0, WX = 0.4, WY = 0.5, WZ = -0.6\n\
        MARKER/40, PART = 4\nMARKER/41, PART = 4, QP = 0.1, 0.2, 0\n\
        PART/5, MASS = 2, CM = 50, IP = 1, 2, 3, QG = 6, 0, 0, VX = 0.2, VY = -0.1, VZ = 0.4\n\
        MARKER/50, PART = 5\nMARKER/51, PART = 5, QP = 0.1, 0.2, 0, REULER = 20D, 90D, 0\n\
        PART/6, MASS = 2, CM = 60, IP = 1, 2, 3, QG = 8, 0, 0, WX = 0.3, WY = 0.8, WZ = 0.1\n\
        MARKER/60, PART = 6\nMARKER/61, PART = 6, QP = 0.1, 0.2, 0, REULER = 90D, 90D, 0\n\
        JOINT/1, CYLINDRICAL, I = 21, J = 1\nJOINT/2, REVOLUTE, I = 31, J = 2\n\
        JOINT/3, SPHERICAL, I = 41, J = 3\nJOINT/4, TRANSLATIONAL, I = 51, J = 4\n\
        JOINT/5, UNIVERSAL, I = 61, J = 5\n\
        FRICTION/1, JOINT = 1, MU_STATIC = 0.3, MU_DYNAMIC = 0.2, STICTION_TRANSITION_VELOCITY = 2, FRICTION_FORCE_PRELOAD = 5, INITIAL_OVERLAP = 0.5, PIN_RADIUS = 0.3\n\
        FRICTION/2, JOINT = 2, MU_STATIC = 0.3, MU_DYNAMIC = 0.2, PIN_RADIUS = 0.3, FRICTION_ARM = 0.4, BENDING_REACTION_ARM = 0.6\n\
        FRICTION/3, JOINT = 3, MU_STATIC = 0.3, MU_DYNAMIC = 0.2, BALL_RADIUS = 0.2\n\
        FRICTION/4, JOINT = 4, MU_STATIC = 0.3, MU_DYNAMIC = 0.2, FRICTION_ARM = 0.5, INITIAL_OVERLAP = 0.3\n\
        FRICTION/5, JOINT = 5, MU_STATIC = 0.3, MU_DYNAMIC = 0.2, PIN_RADIUS = 0.2, BENDING_REACTION_ARM = 0.7\n\
        END\n";

    #[test]
    fn loop_jacobian_matches_central_differences_in_the_multipliers() {
        let read = read_model(JOINTS);
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        let exprs = CompiledExprs::new();
        let mut sys = System::from_model(&read.model, Dim::Three, &exprs).unwrap();
        let forces = sys.forces_from_model(&read.model, &exprs).unwrap();
        let mut d = Dynamics::new(sys, forces, &[]).unwrap();
        d.eval_constraints(true).unwrap();
        let (n, m) = (d.n, d.m);
        // Multipliers of both signs and several sizes, none zero (where the loads'
        // norms have no derivative).
        for r in 0..m {
            d.lambda[r] = ((r * 7) % 11) as f64 - 5.5 + 0.1 * r as f64;
        }
        d.eval_forces(false).unwrap();
        d.loop_jacobian();
        let mut k = vec![vec![0.0; m]; n];
        for &(r, c, x) in &d.scratch.loop_jacobian {
            k[r][c - n] += x;
        }
        // Every joint's rows load its own part: 5 parts' columns read some multiplier.
        let loaded = (0..5)
            .filter(|p| (6 * p..6 * p + 6).any(|r| k[r].iter().any(|&x| x != 0.0)))
            .count();
        assert_eq!(loaded, 5);
        let h = 1e-6;
        for c in 0..m {
            let mut q_at = |s: f64| {
                let mut e = d.lambda.clone();
                e[c] += s * h;
                let keep = std::mem::replace(&mut d.lambda, e);
                d.eval_forces(false).unwrap();
                d.lambda = keep;
                d.gen.q.clone()
            };
            let (up, down) = (q_at(1.0), q_at(-1.0));
            for r in 0..n {
                let fd = (up[r] - down[r]) / (2.0 * h);
                assert!(
                    (k[r][c] - fd).abs() < 1e-6 * (1.0 + fd.abs()),
                    "dQ{r}/dλ{c}: {} vs {fd}",
                    k[r][c]
                );
            }
        }
    }
}
