//! The static Newton iteration on (q, λ). At each iterate, with v = 0 and a = 0,
//!
//! ```text
//! [ s·M/UCF − s·∂Q/∂v − ∂Q/∂q + ∂(Φ_qᵀλ)/∂q   Φ_qᵀ ] [δq]   [ Q − Φ_qᵀλ ]
//! [ Φ_q                                       0    ] [δλ] = [ −Φ        ]
//! ```
//!
//! (s = STABILITY; a non-holonomic row constrains the step, Φ_v·δq = 0, and has no
//! residual), factored dense (LU with partial pivoting; the models statics is asked of
//! have tens of parts, not thousands). The step is scaled down as a whole until no part
//! moves more than TLIMIT or turns more than ALIMIT, then damped by Deuflhard's
//! restricted monotonicity test: a trial step α is kept when the next simplified Newton
//! correction, A⁻¹·F(q + α·δ) with the same factors, is at most (1 − α/4) of this one,
//! measured over the coordinates in scaled units (translations over the model length).
//! Convergence needs the force imbalance below IMBALANCE, and the correction and the
//! constraint residual below ERROR; the last correction is applied.

use super::outcome::{Failure, Reaction, Report, StaticsError};
use super::{stability, tangent};
use crate::mbd::dynamics::{DynError, Dynamics, Singularity};
use crate::mbd::error::element_name;
use crate::mbd::freedom::{column_part, column_scale, coordinate_name};
use crate::model::equilibrium_settings::EquilibriumSettings;
use crate::vocab::math::{DMat, DVec};

/// Halvings of the damping factor before a step is taken anyway.
const HALVINGS: usize = 10;

/// The residual at one iterate and where its largest force imbalance is.
struct Residual {
    /// [Q − Φ_qᵀλ; −Φ] (zero on non-holonomic rows).
    f: DVec,
    /// max |Q − Φ_qᵀλ| and its column.
    imbalance: (f64, usize),
    /// The largest scaled residual of the position rows.
    constraint: f64,
}

/// Finds the static equilibrium of `d` at its current time from its current
/// configuration, velocities set to zero; `d.lambda` starts the multipliers and holds
/// the equilibrium's on return, `d.a` is zero. Fails with [`StaticsError::Failed`] naming
/// what kept it from an equilibrium, or the direction along which the equilibrium found
/// is not stable.
///
/// The state elements solve ẋ = 0 inside every evaluation, those with STATIC_HOLD held
/// where they stand ([`crate::mbd::states::Mode::Static`]); the equilibrium's states are
/// committed for the run that follows.
pub fn equilibrium(d: &mut Dynamics, s: &EquilibriumSettings) -> Result<Report, StaticsError> {
    use crate::mbd::states::Mode;
    d.forces.states.set_mode(Mode::Static);
    // A CONTACT with COULOMB_FRICTION = DYNAMICS_ONLY has no friction here.
    d.forces.contacts.statics = true;
    let mut found = solve_equilibrium(d, s);
    d.forces.contacts.statics = false;
    if found.is_ok() {
        if let Err(e) = d.commit_states() {
            found = Err(e.into());
        }
    }
    d.forces.states.set_mode(Mode::Dynamic);
    found
}

/// [`equilibrium`]'s Newton iteration, the contacts told it is statics.
fn solve_equilibrium(d: &mut Dynamics, s: &EquilibriumSettings) -> Result<Report, StaticsError> {
    let (n, m) = (d.n, d.m);
    let zero = DVec::zeros(n);
    d.sys.set_v(&zero);
    // The multipliers start as the reactions of the state released at rest (the
    // consistent accelerations' [[M, Φ_qᵀ], [Φ_q, 0]]·[a; λ] = [Q; γ]): with λ = 0 the
    // constraint forces' tangent, which holds a pendulum's rotation, would be missing
    // from the first Newton matrix.
    if d.solve_accelerations().is_err() || d.lambda.len() != m {
        d.lambda = DVec::zeros(m);
    }
    d.a = zero.clone();
    d.store_accelerations();
    if n == 0 {
        // Nothing moves: ground alone is in equilibrium.
        return finish(d, 0, 0);
    }
    let scale: Vec<f64> = (0..n).map(|c| column_scale(d, c)).collect();
    let holonomic: Vec<bool> = d
        .rows
        .iter()
        .map(|&(e, q)| !d.sys.row_reads_velocity(e, q))
        .collect();
    let mut limited = 0;
    // Consecutive iterations cut to a limit, and the last one's (limit, value, column).
    let mut limited_run = 0;
    let mut last_limit = ("TLIMIT", s.tlimit, 0);
    for k in 0..=s.maxit {
        d.eval_constraints(true)?;
        d.eval_forces(true)?;
        d.check_forces()?;
        let res = residual(d, &holonomic);
        let a = newton_matrix(d, s.stability);
        let lu = a.lu();
        let mut delta = res.f.clone();
        if !lu.solve_mut(&mut delta) || delta.iter().any(|x| !x.is_finite()) {
            return Err(match stability::softest(d)? {
                Some(mode) => unstable(d, mode, false),
                None => StaticsError::Dynamics(DynError::Singular {
                    time: d.sys.time,
                    why: Singularity::Dependent,
                    culprit: d.singular_culprit(),
                }),
            });
        }
        let correction = (0..n)
            .map(|c| delta[c].abs() / scale[c])
            .fold(0.0, f64::max);
        if res.imbalance.0 <= s.imbalance && res.constraint <= s.error && correction <= s.error {
            apply(d, &delta, 1.0);
            d.commit_measures();
            return finish(d, k, limited);
        }
        if k == s.maxit {
            return Err(give_up(d, k, &res, limited_run, last_limit)?);
        }
        // The step limits: the whole step scaled so no part exceeds either.
        let (mut tmax, mut amax, mut tcol, mut acol) = (0.0f64, 0.0f64, 0, 0);
        let (bs, axes) = (d.sys.dim.cols(), d.sys.dim.axes());
        for c in 0..n {
            let x = delta[c].abs();
            if c % bs >= axes {
                if x > amax {
                    (amax, acol) = (x, c);
                }
            } else if x > tmax {
                (tmax, tcol) = (x, c);
            }
        }
        let (ft, fa) = (s.tlimit / tmax, s.alimit / amax);
        let cut = ft.min(fa).min(1.0);
        if cut < 1.0 {
            limited += 1;
            limited_run += 1;
            last_limit = match ft < fa {
                true => ("TLIMIT", s.tlimit, tcol),
                false => ("ALIMIT", s.alimit, acol),
            };
        } else {
            limited_run = 0;
        }
        damped_step(d, &lu, &delta, cut, &holonomic, &scale)?;
        d.commit_measures();
        d.stats.newton_iterations += 1;
    }
    unreachable!("the loop returns at k = MAXIT")
}

/// [Q − Φ_qᵀλ; −Φ] at the last evaluations.
fn residual(d: &Dynamics, holonomic: &[bool]) -> Residual {
    let (n, m) = (d.n, d.m);
    let mut forces = d.gen.q.clone();
    d.jac
        .add_transpose_times(d.lambda.as_slice(), -1.0, &mut forces);
    let mut f = DVec::zeros(n + m);
    f.rows_mut(0, n).copy_from(&forces);
    let mut constraint: f64 = 0.0;
    for r in (0..m).filter(|&r| holonomic[r]) {
        f[n + r] = -d.phi[r];
        constraint = constraint.max(d.scaled_residual(r));
    }
    let col = if n > 0 { forces.iamax() } else { 0 };
    let top = if n > 0 { forces[col].abs() } else { 0.0 };
    Residual {
        f,
        imbalance: (top, col),
        constraint,
    }
}

/// The static Newton matrix at the last evaluations (constraints and forces with their
/// Jacobians), with `stability` times the mass and damping matrices.
fn newton_matrix(d: &Dynamics, stability: f64) -> DMat {
    let (n, m) = (d.n, d.m);
    let mut a = DMat::zeros(n + m, n + m);
    if stability != 0.0 {
        d.add_mass_matrix(stability, &mut a);
        for &(r, c, x) in &d.gen.dv {
            a[(r, c)] -= stability * x;
        }
    }
    for &(r, c, x) in &d.gen.dq {
        a[(r, c)] -= x;
    }
    let mut k = DMat::zeros(n, n);
    tangent::add_constraint_tangent(d, d.lambda.as_slice(), &mut k);
    let mut top_left = a.view_mut((0, 0), (n, n));
    top_left += &k;
    for (r, c, x) in d.jac.entries() {
        a[(n + r, c)] += x;
        a[(c, n + r)] += x;
    }
    a
}

/// Moves `d` by `alpha` times the step `delta` (coordinates and multipliers).
fn apply(d: &mut Dynamics, delta: &DVec, alpha: f64) {
    let n = d.n;
    let dx: Vec<f64> = delta.iter().take(n).map(|x| alpha * x).collect();
    d.sys.apply_increment(&dx);
    for r in 0..d.m {
        d.lambda[r] += alpha * delta[n + r];
    }
}

/// Takes the step `delta` cut to `cut`, damped until the restricted monotonicity test
/// passes (or [`HALVINGS`] halvings, when the smallest trial is taken).
fn damped_step(
    d: &mut Dynamics,
    lu: &nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    delta: &DVec,
    cut: f64,
    holonomic: &[bool],
    scale: &[f64],
) -> Result<(), DynError> {
    let n = d.n;
    let norm = |x: &DVec| {
        (0..n)
            .map(|c| (x[c] / scale[c]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let full = norm(delta);
    let base = d.snapshot();
    let lambda = d.lambda.clone();
    let time = d.sys.time;
    let zero = DVec::zeros(n);
    let mut alpha = cut;
    for tries in 0..=HALVINGS {
        let dx: Vec<f64> = delta.iter().take(n).map(|x| alpha * x).collect();
        d.set_state(&base, &dx, &zero, time);
        for r in 0..d.m {
            d.lambda[r] = lambda[r] + alpha * delta[n + r];
        }
        if tries == HALVINGS {
            break;
        }
        d.eval_constraints(true)?;
        d.eval_forces(false)?;
        let mut next = residual(d, holonomic).f;
        let solved = lu.solve_mut(&mut next) && next.iter().all(|x| x.is_finite());
        if solved && norm(&next) <= (1.0 - alpha / 4.0) * full {
            break;
        }
        alpha *= 0.5;
    }
    Ok(())
}

/// The report of a converged iteration after `k` iterations: the state re-evaluated,
/// its imbalance, the stability check, the reactions.
fn finish(d: &mut Dynamics, k: usize, limited: usize) -> Result<Report, StaticsError> {
    d.eval_constraints(true)?;
    d.eval_forces(true)?;
    let holonomic: Vec<bool> = d
        .rows
        .iter()
        .map(|&(e, q)| !d.sys.row_reads_velocity(e, q))
        .collect();
    let res = residual(d, &holonomic);
    let check = stability::check(d)?;
    if let stability::Verdict::Fails(mode) = check.verdict {
        return Err(unstable(d, mode, true));
    }
    let mut reactions = Vec::new();
    for (e, el) in d.sys.elements.iter().enumerate() {
        if !d.rows.iter().any(|&(x, _)| x == e) {
            continue;
        }
        let (force, torque) = d.constraint_load(e, false);
        reactions.push(Reaction {
            element: element_name(&el.elref),
            force,
            torque,
        });
    }
    Ok(Report {
        time: d.sys.time,
        iterations: k,
        limited,
        imbalance: res.imbalance.0,
        imbalance_at: coordinate(d, res.imbalance.1),
        residual: res.constraint,
        softest: check.softest,
        reactions,
    })
}

/// The failure after MAXIT iterations: a neutral or unstable direction at the last
/// iterate when there is one, else the limits when every last iteration was cut to one,
/// else the imbalance left.
fn give_up(
    d: &mut Dynamics,
    k: usize,
    res: &Residual,
    limited_run: usize,
    (limit, value, col): (&'static str, f64, usize),
) -> Result<StaticsError, DynError> {
    if let Some(mode) = stability::softest(d)? {
        return Ok(unstable(d, mode, false));
    }
    let time = d.sys.time;
    let failure = match limited_run >= k.clamp(1, 3) {
        true => Failure::Limited {
            time,
            iterations: k,
            limit,
            value,
            at: coordinate(d, col),
            part: part_id(d, col),
        },
        false => Failure::NoEquilibrium {
            time,
            iterations: k,
            imbalance: res.imbalance.0,
            at: coordinate(d, res.imbalance.1),
            part: part_id(d, res.imbalance.1),
        },
    };
    Ok(StaticsError::Failed(Box::new(failure)))
}

fn unstable(d: &Dynamics, mode: stability::Mode, converged: bool) -> StaticsError {
    StaticsError::Failed(Box::new(Failure::Unstable {
        time: d.sys.time,
        neutral: mode.neutral,
        converged,
        freedom: mode.freedom,
    }))
}

/// `PART/2 y translation` for velocity-layout column `col`.
fn coordinate(d: &Dynamics, col: usize) -> String {
    match column_part(d, col) {
        Some(h) => coordinate_name(d, h, col),
        None if d.n == 0 => "no part moves".to_string(),
        None => format!("column {col}"),
    }
}

fn part_id(d: &Dynamics, col: usize) -> Option<u32> {
    column_part(d, col).and_then(|h| d.sys.part(h).id)
}
