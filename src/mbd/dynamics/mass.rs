//! The mass matrix M/UCF, block diagonal per moving part ([`Mat3Block`]): 3D (m, R·J·Rᵀ)
//! or 2D (m, J about the normal), constant where it cannot change, and its products with
//! vectors; with Φ_qᵀ·λ, the constraint forces.

use super::blocks::Mat3Block;
use super::setup::Dynamics;
use crate::mbd::system::Dimension;
use crate::vocab::math::{DVec, Mat3, Vec3};

impl Dynamics {
    /// R·J·Rᵀ of part `p` divided by UCF (1 in SI models: then not divided, nine
    /// divisions saved a part, the same bits).
    #[inline(always)]
    pub(super) fn inertia_over_ucf(&self, p: &crate::mbd::system::Part) -> Mat3 {
        match self.sys.ucf {
            1.0 => p.inertia_global(),
            u => p.inertia_global() / u,
        }
    }

    /// The mass matrix block of moving part `i` over its columns, divided by UCF.
    #[inline(always)]
    pub fn mass_block(&self, p: &crate::mbd::system::Part) -> Mat3Block {
        let u = self.sys.ucf;
        match self.sys.dim {
            Dimension::Three => Mat3Block::Three(p.mass / u, self.inertia_over_ucf(p)),
            Dimension::Two => {
                // n·(R·J·Rᵀ)·n = (Rᵀn)·J·(Rᵀn).
                let n = p
                    .rot
                    .inverse_transform_vector(&Vec3::ith(self.sys.normal, 1.0));
                Mat3Block::Two(p.mass / u, n.dot(&(p.inertia * n)) / u)
            }
        }
    }

    /// Whether the mass blocks never change: in 2D, and in 3D when every moving part's
    /// inertia is isotropic.
    pub(super) fn mass_is_constant(&self) -> bool {
        self.sys.dim == Dimension::Two || self.isotropic
    }

    /// Every moving part's mass block (divided by UCF) at the current state, in part
    /// order. In 2D (and for isotropic parts) they never change and are computed once.
    pub fn mass_blocks(&self) -> std::borrow::Cow<'_, [Mat3Block]> {
        if let Some(b) = &self.constant_mass {
            return std::borrow::Cow::Borrowed(b);
        }
        // sized up front: a filtered collect grows by reallocation, a copy each time
        let mut blocks = Vec::with_capacity(self.sys.parts.len());
        blocks.extend(
            self.sys
                .parts
                .iter()
                .filter(|p| p.index.is_some())
                .map(|p| self.mass_block(p)),
        );
        std::borrow::Cow::Owned(blocks)
    }

    /// w·M·x added to `out` (x in the velocity layout), M given by its `blocks`.
    pub fn add_blocks_times(&self, blocks: &[Mat3Block], w: f64, x: &[f64], out: &mut DVec) {
        let bs = self.sys.dim.cols();
        for (i, blk) in blocks.iter().enumerate() {
            let b = i * bs;
            match *blk {
                Mat3Block::Three(m, j) => {
                    for c in 0..3 {
                        out[b + c] += w * m * x[b + c];
                    }
                    let t = j * Vec3::new(x[b + 3], x[b + 4], x[b + 5]);
                    for c in 0..3 {
                        out[b + 3 + c] += w * t[c];
                    }
                }
                Mat3Block::Two(m, j) => {
                    out[b] += w * m * x[b];
                    out[b + 1] += w * m * x[b + 1];
                    out[b + 2] += w * j * x[b + 2];
                }
            }
        }
    }

    /// M·x / UCF added to `out` (x in the velocity layout), M at the current state.
    pub fn add_mass_times(&self, x: &[f64], out: &mut DVec) {
        self.add_blocks_times(&self.mass_blocks(), 1.0, x, out);
    }

    /// w·M / UCF added to the top-left n × n of the dense matrix `a`, M at the current
    /// state (the static Newton matrix and the linearization want it whole).
    pub fn add_mass_matrix(&self, w: f64, a: &mut crate::vocab::math::DMat) {
        let bs = self.sys.dim.cols();
        for (i, b) in self.mass_blocks().iter().enumerate() {
            let c = i * bs;
            match *b {
                Mat3Block::Three(mass, j) => {
                    for r in 0..3 {
                        a[(c + r, c + r)] += w * mass;
                        for k in 0..3 {
                            a[(c + 3 + r, c + 3 + k)] += w * j[(r, k)];
                        }
                    }
                }
                Mat3Block::Two(mass, j) => {
                    a[(c, c)] += w * mass;
                    a[(c + 1, c + 1)] += w * mass;
                    a[(c + 2, c + 2)] += w * j;
                }
            }
        }
    }

    /// Φ_qᵀ·λ added to `out`, with the Φ_q of the last [`Dynamics::eval_constraints`].
    pub fn add_constraint_forces(&self, lambda: &DVec, out: &mut DVec) {
        self.jac.add_transpose_times(lambda.as_slice(), 1.0, out);
    }

    /// The equations of motion's residual M·a + Φ_qᵀ·λ − Q (M the mass blocks) into
    /// `out`, from the last evaluations of the constraints and forces.
    pub fn motion_residual(&self, a: &[f64], lambda: &DVec, out: &mut DVec) {
        out.fill(0.0);
        self.add_constraint_forces(lambda, out);
        *out -= &self.gen.q;
        self.add_blocks_times(&self.mass_blocks(), 1.0, a, out);
    }
}
