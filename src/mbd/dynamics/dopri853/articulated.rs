//! The joint accelerations of a planar tree in O(N): Featherstone's articulated-body
//! algorithm (*Rigid Body Dynamics Algorithms*, 2008, §7.3) in the plane, where a motion
//! or a force is a 3-vector at a part's centre — (aₓ, a_y, α) and (fₓ, f_y, τ) in the 2D
//! layout — and a part's inertia the 3×3 diag(m, m, I_c).
//!
//! Each joint k carries its child part c from its parent p (or ground) as
//!
//! ```text
//! A_c = T(d)·A_p + s·θ̈ₖ + β,   T(d) = [1 0 −d_y; 0 1 d_x; 0 0 1],   d = r_c − r_p,
//! ```
//!
//! s the motion the joint's rate gives the child's centre and β the velocity-product
//! acceleration of the joint alone (the tree's kinematics computes d, s and β). Three
//! passes solve what the dense normal equations Bᵀ·M·B·θ̈ = Bᵀ·(Q − M·b) solve:
//! inward, each part's articulated inertia Iᴬ and bias force pᴬ (starting from M and
//! −Q), the joint's U = Iᴬ·s, D = sᵀ·U, u = −sᵀ·pᴬ and what the parent sees through it,
//! Tᵀ·(Iᴬ − U·Uᵀ/D)·T and Tᵀ·(pᴬ + Iᵃ·β + U·u/D); outward, θ̈ₖ = (u − Uᵀ·A′)/D with
//! A′ = T·A_p + β. In 2D a part's centroidal inertia is constant and there is no
//! gyroscopic term, so every velocity product is in β.

/// One joint's kinematic link, at the current state.
#[derive(Clone, Copy, Debug, Default)]
pub struct Link {
    /// From the parent's centre to the child's (ground: the origin), plane axes.
    pub d: [f64; 2],
    /// The child's centre's motion per unit joint rate.
    pub s: [f64; 3],
    /// The child's centre's acceleration from the joint's velocity products alone.
    pub beta: [f64; 3],
}

/// A symmetric 3×3 matrix by its upper triangle: (00, 01, 02, 11, 12, 22).
type Sym3 = [f64; 6];

/// S·x for symmetric S.
fn sym_mul(m: &Sym3, x: [f64; 3]) -> [f64; 3] {
    [
        m[0] * x[0] + m[1] * x[1] + m[2] * x[2],
        m[1] * x[0] + m[3] * x[1] + m[4] * x[2],
        m[2] * x[0] + m[4] * x[1] + m[5] * x[2],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// T(d)·x: the motion x at the parent's centre seen at the child's.
fn transfer(d: [f64; 2], x: [f64; 3]) -> [f64; 3] {
    [x[0] - d[1] * x[2], x[1] + d[0] * x[2], x[2]]
}

/// The force-transfer column n = (−d_y, d_x, 0): T = 1 + n·e₃ᵀ.
fn lever(d: [f64; 2]) -> [f64; 3] {
    [-d[1], d[0], 0.0]
}

/// The buffers of the algorithm, per part.
#[derive(Default)]
pub struct Articulated {
    inertia: Vec<Sym3>,
    force: Vec<[f64; 3]>,
    u_vec: Vec<[f64; 3]>,
    d_inv: Vec<f64>,
    u: Vec<f64>,
    acc: Vec<[f64; 3]>,
}

/// A joint whose articulated inertia along its axis is not positive (a massless part at
/// the end of a branch).
#[derive(Debug)]
pub struct Degenerate;

impl Articulated {
    /// Buffers for `parts` parts.
    pub fn new(parts: usize) -> Articulated {
        Articulated {
            inertia: vec![[0.0; 6]; parts],
            force: vec![[0.0; 3]; parts],
            u_vec: vec![[0.0; 3]; parts],
            d_inv: vec![0.0; parts],
            u: vec![0.0; parts],
            acc: vec![[0.0; 3]; parts],
        }
    }

    /// θ̈ into `out` (joint order): joint k carries part `child(k)` from `parent(k)`
    /// through `links[k]`, parents before children; part i has mass and centroidal
    /// inertia `mass(i)` and the applied load `load(i)` (force and torque at its centre).
    /// Without `bias`, β is taken as zero: then `out` is the x of Bᵀ·M·B·x = Bᵀ·g for
    /// loads g, as a projection needs.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        links: &[Link],
        child: impl Fn(usize) -> usize,
        parent: impl Fn(usize) -> Option<usize>,
        mass: impl Fn(usize) -> (f64, f64),
        load: impl Fn(usize) -> [f64; 3],
        bias: bool,
        out: &mut [f64],
    ) -> Result<(), Degenerate> {
        let beta = |k: usize| if bias { links[k].beta } else { [0.0; 3] };
        for (i, (ia, pa)) in self.inertia.iter_mut().zip(&mut self.force).enumerate() {
            let (m, j) = mass(i);
            *ia = [m, 0.0, 0.0, m, 0.0, j];
            let q = load(i);
            *pa = [-q[0], -q[1], -q[2]];
        }
        // Inward: leaves first, each joint's articulated body handed to its parent.
        for k in (0..links.len()).rev() {
            let (c, l) = (child(k), &links[k]);
            let ia = self.inertia[c];
            let uv = sym_mul(&ia, l.s);
            let dd = dot(l.s, uv);
            if !(dd > 0.0 && dd.is_finite()) {
                return Err(Degenerate);
            }
            let d_inv = 1.0 / dd;
            let u = -dot(l.s, self.force[c]);
            self.u_vec[c] = uv;
            self.d_inv[c] = d_inv;
            self.u[c] = u;
            let Some(p) = parent(k) else { continue };
            // Iᵃ = Iᴬ − U·Uᵀ/D, pᵃ = pᴬ + Iᵃ·β + U·u/D.
            let mut low = ia;
            let idx = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];
            for (e, &(r, col)) in idx.iter().enumerate() {
                low[e] -= uv[r] * uv[col] * d_inv;
            }
            let lb = sym_mul(&low, beta(k));
            let pc = self.force[c];
            let pa: [f64; 3] = std::array::from_fn(|r| pc[r] + lb[r] + uv[r] * u * d_inv);
            // Tᵀ·Iᵃ·T = Iᵃ + e₃·wᵀ + w·e₃ᵀ + (nᵀ·w)·e₃·e₃ᵀ with w = Iᵃ·n.
            let n = lever(l.d);
            let w = sym_mul(&low, n);
            let ip = &mut self.inertia[p];
            for (e, &(r, col)) in idx.iter().enumerate() {
                ip[e] += low[e];
                if col == 2 {
                    ip[e] += w[r];
                }
                if r == 2 {
                    ip[e] += w[col];
                }
            }
            ip[5] += dot(n, w);
            let fp = &mut self.force[p];
            fp[0] += pa[0];
            fp[1] += pa[1];
            fp[2] += pa[2] + dot(n, pa);
        }
        // Outward: ground does not move; each joint's rate from its parent's motion.
        for k in 0..links.len() {
            let (c, l) = (child(k), &links[k]);
            let ap = parent(k).map_or([0.0; 3], |p| self.acc[p]);
            let b = beta(k);
            let t = transfer(l.d, ap);
            let a: [f64; 3] = std::array::from_fn(|r| t[r] + b[r]);
            let acc = (self.u[c] - dot(self.u_vec[c], a)) * self.d_inv[c];
            out[k] = acc;
            self.acc[c] = std::array::from_fn(|r| a[r] + l.s[r] * acc);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A single pendulum: a rod of mass m, inertia I about its centre, pinned at distance
    /// a from it, at angle 0 (centre straight along +x from the pin) under g in −y:
    /// (I + m·a²)·θ̈ = −m·g·a, the closed form of the compound pendulum.
    #[test]
    fn compound_pendulum_from_rest() {
        let (m, j, a, g) = (2.0, 0.3, 0.7, 9.81);
        // Revolute at the origin, child's centre at (a, 0): s = ω × (r_c − pin) = (0, a, 1).
        let link = Link {
            d: [a, 0.0],
            s: [0.0, a, 1.0],
            beta: [0.0; 3],
        };
        let mut alg = Articulated::new(1);
        let mut out = [0.0];
        alg.solve(
            &[link],
            |_| 0,
            |_| None,
            |_| (m, j),
            |_| [0.0, -m * g, 0.0],
            true,
            &mut out,
        )
        .unwrap();
        let want = -m * g * a / (j + m * a * a);
        assert!(
            (out[0] - want).abs() < 1e-14 * want.abs(),
            "{} {want}",
            out[0]
        );
    }

    /// A massless joint axis (a part of no mass and no inertia, alone on its branch) is
    /// reported, not divided by.
    #[test]
    fn massless_leaf_is_degenerate() {
        let link = Link {
            d: [1.0, 0.0],
            s: [0.0, 1.0, 1.0],
            beta: [0.0; 3],
        };
        let mut alg = Articulated::new(1);
        let mut out = [0.0];
        let r = alg.solve(
            &[link],
            |_| 0,
            |_| None,
            |_| (0.0, 0.0),
            |_| [0.0; 3],
            true,
            &mut out,
        );
        assert!(r.is_err());
    }
}
