//! The state elements' rows and columns of a linearization (issue 40 §3): with s states x
//! (DIFF, LSE, TFSISO) beside the minimal coordinates z, the state matrix on (z, ż, x) is
//!
//! ```text
//! [ 0              I              0           ]
//! [ −M̃⁻¹·K̃        −M̃⁻¹·C̃        M̃⁻¹·Tᵀ·Q_x  ]
//! [ ẋ_q·T          ẋ_v·T          ẋ_x         ]
//! ```
//!
//! where Q_x = ∂Q/∂x (the forces that read the states; K̃ and C̃ take the forces' path
//! through the states' q- and v-dependent values too), and ẋ_q, ẋ_v, ẋ_x the partials of
//! the states' rates as their equations give them (an IMPLICIT DIFF's through its
//! residual). Each comes from central differences of the state block's own solve and of
//! the forces, the block being small and its equations the user's; the mechanical
//! partials stay analytic.

use crate::mbd::dynamics::{DynError, Dynamics};
use crate::vocab::math::{DMat, DVec};

/// The relative step of the central differences.
const STEP: f64 = 1e-6;

/// The state elements' part of a linearization.
#[derive(Clone, Debug, Default)]
pub struct StateCoupling {
    /// Tᵀ·∂Q/∂x (f × s).
    pub force: DMat,
    /// ∂ẋ/∂q·T (s × f).
    pub dq: DMat,
    /// ∂ẋ/∂v·T (s × f).
    pub dv: DMat,
    /// ∂ẋ/∂x (s × s).
    pub dx: DMat,
    /// What the forces' path through the state values adds to K̃ (f × f): −Tᵀ·Q_w·∂w/∂q·T.
    pub stiffness: DMat,
    /// What it adds to C̃: −Tᵀ·Q_w·∂w/∂v·T.
    pub damping: DMat,
    /// Each state named (`DIFF/3`, `LSE/2 x1`).
    pub names: Vec<String>,
}

impl StateCoupling {
    /// How many states.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
}

/// The rates of the states at `d`'s current state (its committed states as they stand).
fn rates(d: &mut Dynamics) -> Result<DVec, DynError> {
    d.solve_states()?;
    Ok(DVec::from_vec(d.forces.states.rates(&d.sys)))
}

/// The state values the forces read (x, ẋ, u, y) and the rates, solved at `d`'s current
/// state.
fn values(d: &mut Dynamics) -> Result<(DVec, DVec), DynError> {
    let r = rates(d)?;
    Ok((DVec::from_column_slice(&d.sys.measures.states), r))
}

/// ∂Q/∂(state values) (n × values) at `d`'s state: each value moved on its own, the
/// state solve frozen.
fn force_partials(d: &mut Dynamics) -> Result<DMat, DynError> {
    let (n, w) = (d.n, d.sys.measures.states.len());
    let mut out = DMat::zeros(n, w);
    d.forces.states.frozen = true;
    let mut found = Ok(());
    for c in 0..w {
        let v = d.sys.measures.states[c];
        let e = STEP * v.abs().max(1.0);
        let at = |d: &mut Dynamics, x: f64| -> Result<DVec, DynError> {
            d.sys.measures.states[c] = x;
            d.eval_forces(false)?;
            Ok(d.gen.q.clone())
        };
        match (at(d, v + e), at(d, v - e)) {
            (Ok(p), Ok(m)) => out.set_column(c, &((p - m) / (2.0 * e))),
            (Err(err), _) | (_, Err(err)) => found = Err(err),
        }
        d.sys.measures.states[c] = v;
        if found.is_err() {
            break;
        }
    }
    d.forces.states.frozen = false;
    found.map(|()| out)
}

/// The coupling of `d`'s states with its coordinates moving along `basis` (T, model
/// units; `scale` each velocity-layout column's size): every partial by central
/// differences about the current state, which is restored (positions, velocities,
/// states) with its evaluations made again.
///
/// The forces read the state values (x, and the rates, inputs and outputs that depend on
/// q and v too) without a derivative, so their path through those values is added here:
/// Q_w = ∂Q/∂w over the values w, times ∂w/∂x, ∂w/∂q·T and ∂w/∂v·T, the last two into
/// K̃ and C̃.
pub fn coupling(d: &mut Dynamics, basis: &DMat, scale: &[f64]) -> Result<StateCoupling, DynError> {
    let s = d.forces.states.len();
    let (n, f) = (d.n, basis.ncols());
    if s == 0 {
        return Ok(StateCoupling::default());
    }
    // The states committed where the linearization stands: the differences move them.
    d.commit_states()?;
    let w = d.sys.measures.states.len();
    let mut c = StateCoupling {
        force: DMat::zeros(f, s),
        dq: DMat::zeros(s, f),
        dv: DMat::zeros(s, f),
        dx: DMat::zeros(s, s),
        stiffness: DMat::zeros(f, f),
        damping: DMat::zeros(f, f),
        names: d.forces.states.names(),
    };
    let reduced = basis.transpose() * force_partials(d)?;
    debug_assert_eq!(reduced.ncols(), w);
    let x0: Vec<f64> = d
        .forces
        .states
        .committed()
        .map(|(x, _)| x.to_vec())
        .unwrap_or_default();
    for (k, x) in x0.iter().enumerate() {
        let e = STEP * x.abs().max(1.0);
        d.forces.states.nudge(k, e);
        let (wp, rp) = values(d)?;
        d.forces.states.nudge(k, -2.0 * e);
        let (wm, rm) = values(d)?;
        d.forces.states.nudge(k, e);
        c.dx.set_column(k, &((rp - rm) / (2.0 * e)));
        c.force.set_column(k, &(&reduced * ((wp - wm) / (2.0 * e))));
    }
    let snap = d.snapshot();
    let v0 = d.sys.v();
    for j in 0..f {
        let col: DVec = basis.column(j).into_owned();
        let size = (0..n)
            .filter(|&r| col[r] != 0.0)
            .map(|r| scale[r])
            .fold(1.0, f64::max);
        let e = STEP * size;
        let moved = |d: &mut Dynamics, h: f64| -> Result<(DVec, DVec), DynError> {
            d.restore(&snap);
            let dx: Vec<f64> = col.iter().map(|x| x * h).collect();
            d.sys.apply_increment(&dx);
            values(d)
        };
        let ((wp, rp), (wm, rm)) = (moved(d, e)?, moved(d, -e)?);
        c.dq.set_column(j, &((rp - rm) / (2.0 * e)));
        c.stiffness
            .set_column(j, &(-(&reduced * ((wp - wm) / (2.0 * e)))));
        let sped = |d: &mut Dynamics, h: f64| -> Result<(DVec, DVec), DynError> {
            d.restore(&snap);
            d.sys.set_v(&(&v0 + &col * h));
            values(d)
        };
        let ((wp, rp), (wm, rm)) = (sped(d, e)?, sped(d, -e)?);
        c.dv.set_column(j, &((rp - rm) / (2.0 * e)));
        c.damping
            .set_column(j, &(-(&reduced * ((wp - wm) / (2.0 * e)))));
    }
    d.restore(&snap);
    d.eval_constraints(true)?;
    d.eval_forces(true)?;
    Ok(c)
}

/// ∂ẋ/∂u for the design variable `id` (a plant input), by central differences of the
/// states' solve at `d`'s state (restored).
pub fn input_rates(d: &mut Dynamics, id: i64) -> Result<DVec, DynError> {
    let u = d.sys.measures.design(id);
    let e = STEP * u.abs().max(1.0);
    d.sys.measures.set_design(id, u + e);
    let rp = rates(d)?;
    d.sys.measures.set_design(id, u - e);
    let rm = rates(d)?;
    d.sys.measures.set_design(id, u);
    rates(d)?;
    Ok((rp - rm) / (2.0 * e))
}
