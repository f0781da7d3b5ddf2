//! The force set's value path with every marker frame built once an evaluation
//! ([`FrameCache`]): the markers the elements act between and the markers of the
//! displacement and velocity measures their fused expressions read, each frame built
//! once (one 3×3 product and one cross product), then the measures and the loads read
//! from them. The general path built a marker's frame for each measure and each element
//! that read it: on the IMPACT block, five 3×3 marker-frame products a stage for one
//! SFORCE and its DY and VY (issue 42). The numbers are the general path's bit for bit:
//! the same operations on the same values, only not repeated.
//!
//! Values only (explicit integrators, residuals); the Jacobians' dual path is unchanged.

use crate::mbd::measure_set::{Measure, M};
use crate::mbd::measures::{value_frame, Frame};
use crate::mbd::system::System;

/// Where a fused slot's value comes from: a displacement or velocity component from
/// cached frames (indices into [`FrameCache::frames`]), or the measure itself.
#[derive(Clone, Copy, Debug)]
enum SlotRead {
    /// DX, DY, DZ: (r_i − r_j)·axis_k.
    Disp {
        i: usize,
        j: usize,
        k: usize,
        comp: usize,
    },
    /// VX, VY, VZ in ground's frame of differentiation: (ṙ_i − ṙ_j)·axis_k.
    Vel {
        i: usize,
        j: usize,
        k: usize,
        comp: usize,
    },
    /// Any other measure, by its own value.
    Measure(usize),
}

/// The frames of the markers a force set reads, built once an evaluation.
pub(super) struct FrameCache {
    /// Each marker read, once.
    markers: Vec<M>,
    /// Their frames at the last [`FrameCache::fill`].
    frames: Vec<Frame<f64>>,
    /// Per element, the indices of its I and J frames.
    elements: Vec<(usize, usize)>,
    /// Per fused (slot, measure) pair, in its order, how to read it.
    reads: Vec<SlotRead>,
}

impl FrameCache {
    /// The cache for elements acting between `ends` (I, J) whose fused expressions read
    /// the measures of `slots` ((slot, measure) pairs) of `sys`.
    pub(super) fn new(sys: &System, ends: &[(M, M)], slots: &[(u32, usize)]) -> FrameCache {
        let mut markers: Vec<M> = Vec::new();
        let mut index = |mk: M| match markers.iter().position(|&x| x == mk) {
            Some(k) => k,
            None => {
                markers.push(mk);
                markers.len() - 1
            }
        };
        let elements = ends.iter().map(|&(i, j)| (index(i), index(j))).collect();
        let reads = slots
            .iter()
            .map(|&(_, m)| match sys.measures.list[m] {
                Measure::Disp { i, j, k, comp } if comp < 3 => SlotRead::Disp {
                    i: index(i),
                    j: index(j),
                    k: index(k),
                    comp: comp as usize,
                },
                Measure::Vel {
                    i,
                    j,
                    k,
                    l: None,
                    comp,
                } if comp < 3 => SlotRead::Vel {
                    i: index(i),
                    j: index(j),
                    k: index(k),
                    comp: comp as usize,
                },
                _ => SlotRead::Measure(m),
            })
            .collect();
        let frames = markers.iter().map(|&mk| value_frame(sys, mk)).collect();
        FrameCache {
            markers,
            frames,
            elements,
            reads,
        }
    }

    /// Builds every frame at the state of `sys`.
    pub(super) fn fill(&mut self, sys: &System) {
        for (f, &mk) in self.frames.iter_mut().zip(&self.markers) {
            *f = value_frame(sys, mk);
        }
    }

    /// Writes each fused slot's value into `vals` (`slots` as given to
    /// [`FrameCache::new`]), from the frames of the last fill: the operations of
    /// [`crate::mbd::measure_set::MeasureSet::value`] on the same numbers.
    pub(super) fn slot_values(&self, sys: &System, slots: &[(u32, usize)], vals: &mut [f64]) {
        let f = &self.frames;
        for (&(slot, _), read) in slots.iter().zip(&self.reads) {
            vals[slot as usize] = match *read {
                SlotRead::Disp { i, j, k, comp } => f[i].r.sub(&f[j].r).dot(&f[k].axes[comp]),
                SlotRead::Vel { i, j, k, comp } => f[i].vel.sub(&f[j].vel).dot(&f[k].axes[comp]),
                SlotRead::Measure(m) => super::inputs::measure_value(sys, m),
            };
        }
    }

    /// Element `k`'s I and J frames at the last fill.
    pub(super) fn ends(&self, k: usize) -> (&Frame<f64>, &Frame<f64>) {
        let (i, j) = self.elements[k];
        (&self.frames[i], &self.frames[j])
    }

    /// Whether the cache was made for `n` elements and `slots` fused pairs (a set whose
    /// elements or fusion changed after [`FrameCache::new`] falls back to the general
    /// path).
    pub(super) fn fits(&self, n: usize, slots: usize) -> bool {
        self.elements.len() == n && self.reads.len() == slots
    }
}

#[cfg(test)]
mod tests {
    //! The cached value path against the general one on random states, in 2D and in
    //! 3D: the same Q and loads, bit for bit.
    use crate::mbd::compiled::CompiledExprs;
    use crate::mbd::forces::Generalized;
    use crate::mbd::planar::Dim;
    use crate::mbd::system::{Dimension, System};
    use crate::model::read_model;
    use crate::vocab::math::DVec;

    /// Two free parts in the XY plane, markers turned about z and with z in the plane,
    /// forces reading displacements, velocities and angles (the last not cached).
    const PLANAR: &str = "planar cache\nPART/1, GROUND\n\
        MARKER/10, PART = 1, QP = 0.1, -0.2, 0, REULER = 0D, -90D, 0D\n\
        MARKER/11, PART = 1, QP = -0.4, 0.3, 0, REULER = 30D, 0D, 0D\n\
        PART/2, MASS = 2, CM = 20, IP = 1, 2, 3, QG = 0.1, 0.2, 0, VX = 0.3, WZ = 0.7\n\
        MARKER/20, PART = 2\nMARKER/21, PART = 2, QP = 0.5, -0.2, 0, REULER = 0D, -90D, 0D\n\
        MARKER/22, PART = 2, QP = 0.3, 0.1, 0, REULER = 25D, 0D, 0D\n\
        PART/3, MASS = 1, CM = 30, IP = 1, 1, 1, QG = 1.1, 0.4, 0, VY = 0.2, WZ = -0.3\n\
        MARKER/30, PART = 3\nMARKER/31, PART = 3, QP = 0.9, 0.6, 0, REULER = -40D, 0D, 0D\n\
        SFORCE/1, TRANSLATION, ACTIONONLY, I = 21, J = 10\n\
        , FUNCTION = IMPACT(DY(21, 10), VY(21, 10), 0.05, 1E5, 1.5, 50, 0.1)\n\
        SFORCE/2, TRANSLATION, I = 22, J = 31, FUNCTION = -50*(DX(22,31,11) - 1) - 3*VX(22,31,31) + 2*VY(22,31)\n\
        SFORCE/3, ROTATION, I = 22, J = 31, FUNCTION = -4*AZ(22,31) - 0.5*WZ(22,31,31) + DY(31,0,22)\n\
        SFORCE/4, ROTATION, ACTIONONLY, I = 31, J = 11, FUNCTION = VX(31,11,22)*DX(31,11)\n\
        SPRINGDAMPER/1, TRANSLATION, I = 21, J = 31, K = 30, C = 2, LENGTH = 0.8, FORCE = 1\n\
        SPRINGDAMPER/2, ROTATION, I = 22, J = 11, KT = 5, CT = 0.3, ANGLE = 0.1, TORQUE = 0.2\n\
        BUSHING/1, I = 20, J = 30, K = 10, 20, 30, C = 1, 2, 3, KT = 4, 5, 6, CT = 0.1, 0.2, 0.3\n\
        ACCGRAV/JGRAV = -9.81\nEND\n";

    /// A generator of numbers in [−1, 1) (a fixed LCG: the states repeat).
    fn numbers(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// Q and every element's loads as bits.
    fn bits(q: &DVec, loads: &[crate::mbd::forces::Loads]) -> Vec<u64> {
        let l = loads.iter().flat_map(|l| {
            [l.on_i.0, l.on_i.1, l.on_j.0, l.on_j.1, l.j_at]
                .into_iter()
                .flat_map(|v| [v.x, v.y, v.z])
        });
        q.iter().copied().chain(l).map(f64::to_bits).collect()
    }

    fn cached_equals_general(dim: Dim, expect: Dimension) {
        let read = read_model(PLANAR);
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        let exprs = CompiledExprs::new();
        let mut sys = System::from_model(&read.model, dim, &exprs).unwrap();
        assert_eq!(sys.dim, expect, "{}", sys.dim_reason);
        let mut cached = sys.forces_from_model(&read.model, &exprs).unwrap();
        let mut general = sys.forces_from_model(&read.model, &exprs).unwrap();
        cached.prepare(&sys).unwrap();
        general.prepare(&sys).unwrap();
        assert!(cached.frames.is_some(), "the set fuses, so it caches");
        general.frames = None;
        let mut x = numbers(7);
        let n = sys.ncols();
        for _ in 0..20 {
            sys.time = 0.5 * (x() + 1.0);
            let dx: Vec<f64> = (0..n).map(|_| 0.3 * x()).collect();
            sys.apply_increment(&dx);
            sys.set_v(&DVec::from_fn(n, |_, _| 2.0 * x()));
            let (mut a, mut b) = (Generalized::new(n), Generalized::new(n));
            cached.eval(&sys, &mut a, false).unwrap();
            general.eval(&sys, &mut b, false).unwrap();
            assert!(a.q.iter().any(|&v| v != 0.0));
            assert_eq!(bits(&a.q, &cached.loads), bits(&b.q, &general.loads));
        }
    }

    #[test]
    fn cached_frames_give_the_general_paths_bits_in_2d() {
        cached_equals_general(Dim::Auto, Dimension::Two);
    }

    #[test]
    fn cached_frames_give_the_general_paths_bits_in_3d() {
        cached_equals_general(Dim::Three, Dimension::Three);
    }
}
