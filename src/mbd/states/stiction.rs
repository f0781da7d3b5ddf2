//! Joint friction's stiction deformations as states of the block (issue 40 §2): one
//! state per slip component of each FRICTION with stiction, δ̇ = f(δ, slip), its law
//! in [`crate::mbd::forces::stiction`]. The integrators carry them as they carry a
//! DIFF, with their error control and in the bordered Newton matrix; the friction reads
//! δ from the state values.
//!
//! In statics the joint is held where statics starts: the state's equation there is
//! δ = δc + Δs(q) (its value at the start plus the slip since), and the friction
//! reads that same δ from the pose as duals, so the equilibrium's Jacobian has the
//! stiction spring in it.

use super::{Committed, Mode, StateSet};
use crate::mbd::forces::friction::{JointFriction, Stiction, POSE_LEN};
use crate::mbd::handles::MarkerHandle;
use crate::mbd::system::System;

/// The stiction deformation of one FRICTION.
pub(crate) struct StictionState {
    /// `FRICTION/1`.
    pub(crate) label: String,
    /// The friction's law, its stiction's channels set.
    pub(crate) law: JointFriction,
    /// The joint's I and J markers.
    pub(crate) markers: (MarkerHandle, MarkerHandle),
    /// Statics' anchor (δc, the pose) once statics has started; None in a run.
    pub(crate) anchor: Option<Vec<f64>>,
}

impl StictionState {
    fn stiction(&self) -> Stiction {
        self.law
            .stiction
            .expect("a stiction state's law has stiction")
    }
}

impl StateSet {
    /// Adds the stiction deformation of FRICTION `label` with law `law` (which has
    /// stiction) between `markers`; its channels follow the ones before. Returns where
    /// they start, for the force element's copy of the law.
    pub(crate) fn add_stiction(
        &mut self,
        label: String,
        mut law: JointFriction,
        markers: (MarkerHandle, MarkerHandle),
    ) -> usize {
        let base = self.channels;
        let d = law.slips();
        if let Some(s) = &mut law.stiction {
            s.channel = base;
        }
        self.channels += Stiction::channels(d);
        self.stiction.push(StictionState {
            label,
            law,
            markers,
            anchor: None,
        });
        base
    }

    /// How many stiction states.
    pub(super) fn stiction_len(&self) -> usize {
        self.stiction.iter().map(|s| s.law.slips()).sum()
    }

    /// The stiction states' names: `FRICTION/1 δ1`.
    pub(super) fn stiction_names(&self, out: &mut Vec<String>) {
        for s in &self.stiction {
            out.extend((1..=s.law.slips()).map(|c| format!("{} δ{c}", s.label)));
        }
    }

    /// The FRICTION stiction state `k` (counted among the stiction states) belongs to.
    pub(super) fn stiction_label(&self, mut k: usize) -> Option<String> {
        for s in &self.stiction {
            let d = s.law.slips();
            if k < d {
                return Some(s.label.clone());
            }
            k -= d;
        }
        None
    }

    /// The state whose value channel `channel` is among the stiction states, counting
    /// from `k`.
    pub(super) fn stiction_state_of_channel(&self, channel: usize, mut k: usize) -> Option<usize> {
        for s in &self.stiction {
            let (st, d) = (s.stiction(), s.law.slips());
            if (st.x(0)..st.x(d)).contains(&channel) {
                return Some(k + channel - st.channel);
            }
            k += d;
        }
        None
    }

    /// The layout entries (x channel, ẋ channel, STATIC_HOLD, initial x, initial ẋ) of
    /// the stiction states: they start undeformed.
    pub(super) fn stiction_layout(&self, out: &mut Vec<(usize, usize, bool, f64, f64)>) {
        for s in &self.stiction {
            let (st, d) = (s.stiction(), s.law.slips());
            for c in 0..d {
                out.push((st.x(c), st.rate(d, c), false, 0.0, 0.0));
            }
        }
    }

    /// The residuals of the stiction states, the first being state `k`, at unknowns `z`
    /// (their x and ẋ already written into `sys`'s state values), into `r`: δ̇'s law
    /// minus the rate in a run, the held deformation minus x in statics (its anchor
    /// taken at the first statics evaluation, from `base`).
    pub(super) fn stiction_residual(
        &mut self,
        sys: &mut System,
        base: &Committed,
        (mut k, z): (usize, &[f64]),
        r: &mut [f64],
    ) {
        let mode = self.mode;
        for s in &mut self.stiction {
            let (st, d) = (s.law.stiction.expect("stiction"), s.law.slips());
            let values = &mut sys.measures.states;
            if mode == Mode::Dynamic {
                s.anchor = None;
                values[st.flag(d)] = 0.0;
                let delta: Vec<f64> = (0..d).map(|c| values[st.x(c)]).collect();
                let rate = s.law.deformation_rate_at(sys, &st, s.markers, &delta);
                for c in 0..d {
                    r[k + c] = rate[c] - sys.measures.states[st.rate(d, c)];
                }
                k += d;
                continue;
            }
            let anchor = s.anchor.get_or_insert_with(|| {
                let mut a = Vec::with_capacity(d + POSE_LEN);
                a.extend_from_slice(&base.x[k..k + d]);
                s.law.pose_at(sys, s.markers, &mut a);
                a
            });
            let values = &mut sys.measures.states;
            values[st.flag(d)] = 1.0;
            values[st.anchor(d)..st.anchor(d) + anchor.len()].copy_from_slice(anchor);
            let held = s.law.held_at(sys, &st, s.markers, anchor);
            for c in 0..d {
                r[k + c] = z[k + c] - held[c];
            }
            k += d;
        }
    }
}
