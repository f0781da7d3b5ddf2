//! Linearization about an operating point (Adams' LINEAR): the equations of motion
//! M·a = Q(q, v, t) − Φ_qᵀ·λ with Φ(q, t) = 0, perturbed about the state where the run
//! stands, give
//!
//! ```text
//! M·δa + C·δv + K·δq + Φ_qᵀ·δλ = 0,     Φ_q·δq = 0,
//! C = −∂Q/∂v,    K = −∂Q/∂q + ∂(Φ_qᵀ·λ)/∂q (λ held),
//! ```
//!
//! in the velocity layout (a part's translation and its rotation vector in global axes).
//! Every partial is the analytic one the static solver uses: the force Jacobians from
//! the compiled derivatives of the expressions, the constraint forces' tangent from
//! [`super::statics::tangent`]. The constraints are eliminated by moving only along
//! their Jacobian's null space, δq = T·z: T's columns span it, recombined
//! ([`joint_coords`]) so that each minimal coordinate zₖ is a joint's own coordinate
//! (`JOINT/1 rotation`, `JOINT/4 translation`) where the joints span the motion, else one
//! of the model's own (`PART/2 rotation about z`), and the others follow it. Then
//!
//! ```text
//! M̃·z̈ + C̃·ż + K̃·z = 0,     M̃ = Tᵀ·M·T,  C̃ = Tᵀ·C·T,  K̃ = Tᵀ·K·T,
//! ```
//!
//! whose state matrix A = [[0, I], [−M̃⁻¹·K̃, −M̃⁻¹·C̃]] on x = (z, ż) gives the modes
//! ([`modes`]). The reduction is exact at rest (v = 0, a = 0: a static equilibrium);
//! at an operating point that moves, the partials of the inertial terms (centripetal,
//! gyroscopic, M(q)·a) and of the constraints' velocity terms are not included, and
//! the result says so ([`Linearized::moving`]). Rows of MOTIONs and GCONs add their
//! Jacobian but not their second derivative (as in statics).

pub mod joint_coords;
pub mod modes;
pub mod plant;
pub mod states;

use super::dynamics::{DynError, Dynamics};
use super::freedom::{column_part, column_scale, coordinate_name, null_space};
use super::statics::tangent;
use super::system::{PartHandle, System};
use crate::vocab::math::DMat;
use joint_coords::Chosen;

/// Scaled velocities (1/s) below this count as rest.
const REST_VELOCITY: f64 = 1e-9;

/// Scaled accelerations (1/s²) below this count as rest: what a static equilibrium to
/// a tight IMBALANCE leaves.
const REST_ACCELERATION: f64 = 1e-6;

/// One minimal coordinate: a joint's own coordinate ([`joint_coords`]) or a coordinate
/// of the model (velocity layout).
#[derive(Clone, Debug, PartialEq)]
pub struct Coordinate {
    /// Its column in the velocity layout (None: a joint's coordinate).
    pub column: Option<usize>,
    /// Its part (a joint's: its I marker's).
    pub part: PartHandle,
    /// What it is, named (`JOINT/1 rotation`, `PART/2 rotation about z`).
    pub name: String,
    /// The model length for a translation, 1 for a rotation.
    pub scale: f64,
}

/// The linearized equations in minimal coordinates.
#[derive(Clone, Debug)]
pub struct Linearized {
    /// Simulation time of the operating point.
    pub time: f64,
    /// The minimal coordinates z, in order.
    pub coords: Vec<Coordinate>,
    /// T (n × f): the model's coordinates move by T·z (model units: a translation in
    /// length units, a rotation in radians).
    pub basis: DMat,
    /// M̃ = Tᵀ·M·T.
    pub mass: DMat,
    /// C̃ = Tᵀ·C·T (zero when damping is left out).
    pub damping: DMat,
    /// K̃ = Tᵀ·K·T.
    pub stiffness: DMat,
    /// Every column of the velocity layout, named (`PART/2 x translation`).
    pub columns: Vec<String>,
    /// Each column's scale: the model length for a translation, 1 for a rotation.
    pub scale: Vec<f64>,
    /// The operating point moves (velocities or accelerations not zero): the inertial
    /// partials are left out (see the module comment).
    pub moving: bool,
    /// The largest velocity and acceleration at the operating point, scaled
    /// (translations over the model length): 1/s and 1/s².
    pub rest: (f64, f64),
    /// The state elements' rows and columns ([`states`]; empty without any).
    pub states: states::StateCoupling,
}

/// Linearizes `d` about its current state; `damping` false leaves out C (Adams'
/// NODAMPIN). The multipliers are solved at the state first (a state reached by
/// dynamics or by statics alike). Fails when a free direction has no mass.
///
/// The state elements' states (DIFF, LSE, TFSISO) join as more states of A
/// ([`states`]).
pub fn linearize(d: &mut Dynamics, damping: bool) -> Result<Linearized, DynError> {
    let n = d.n;
    d.solve_accelerations()?;
    d.eval_constraints(true)?;
    d.eval_forces(true)?;
    let scale: Vec<f64> = (0..n).map(|c| column_scale(d, c)).collect();
    let v = d.sys.v();
    let largest =
        |x: &dyn Fn(usize) -> f64| (0..n).map(|c| x(c).abs() / scale[c]).fold(0.0, f64::max);
    let rest = (
        largest(&|c| v[c]),
        largest(&|c| d.a.get(c).copied().unwrap_or(0.0)),
    );
    let moving = rest.0 > REST_VELOCITY || rest.1 > REST_ACCELERATION;
    let mut m = DMat::zeros(n, n);
    d.add_mass_matrix(1.0, &mut m);
    let mut k = DMat::zeros(n, n);
    for &(r, c, x) in &d.gen.dq {
        k[(r, c)] -= x;
    }
    tangent::add_constraint_tangent(d, d.lambda.as_slice(), &mut k);
    let mut c = DMat::zeros(n, n);
    if damping {
        for &(r, col, x) in &d.gen.dv {
            c[(r, col)] -= x;
        }
    }
    // The null space in scaled coordinates (translations over the model length), then
    // recombined on the joints' own coordinates where they span it, else on the model's
    // coordinates, and brought back to model units.
    let joints = joint_coords::joint_coordinates(d);
    let (scaled, chosen) = joint_coords::choose(&null_space(d), &joints, &scale);
    let coords: Vec<Coordinate> = chosen
        .iter()
        .map(|&c| match c {
            Chosen::Joint(k) => Coordinate {
                column: None,
                part: joints[k].part,
                name: joints[k].name.clone(),
                scale: joints[k].scale,
            },
            Chosen::Column(col) => {
                let part = column_part(d, col).unwrap_or(System::GROUND);
                Coordinate {
                    column: Some(col),
                    part,
                    name: coordinate_name(d, part, col),
                    scale: scale[col],
                }
            }
        })
        .collect();
    let f = coords.len();
    let basis = DMat::from_fn(n, f, |r, j| scaled[(r, j)] * scale[r] / coords[j].scale);
    let columns = (0..n)
        .map(|col| coordinate_name(d, column_part(d, col).unwrap_or(System::GROUND), col))
        .collect();
    let reduce = |x: &DMat| basis.transpose() * x * &basis;
    let coupling = states::coupling(d, &basis, &scale)?;
    let (mut damping_r, mut stiffness_r) = (reduce(&c), reduce(&k));
    if !coupling.is_empty() {
        stiffness_r += &coupling.stiffness;
        if damping {
            damping_r += &coupling.damping;
        }
    }
    Ok(Linearized {
        time: d.sys.time,
        coords,
        mass: reduce(&m),
        damping: damping_r,
        stiffness: stiffness_r,
        basis,
        columns,
        scale,
        moving,
        rest,
        states: coupling,
    })
}

impl Linearized {
    /// The number of minimal coordinates (degrees of freedom).
    pub fn freedom(&self) -> usize {
        self.coords.len()
    }

    /// The state matrix A on x = (z, ż), then the state elements' states:
    /// [[0, I], [−M̃⁻¹·K̃, −M̃⁻¹·C̃]] bordered as [`states`] says. Fails when M̃ is
    /// singular (a free direction without mass), naming the part of that direction.
    pub fn state_matrix(&self) -> Result<DMat, DynError> {
        let (f, s) = (self.freedom(), self.states.len());
        if f == 0 {
            return Ok(match s {
                0 => DMat::zeros(0, 0),
                _ => self.states.dx.clone(),
            });
        }
        let lu = self.mass.clone().lu();
        let rhs = {
            let mut r = DMat::zeros(f, 2 * f + s);
            r.view_mut((0, 0), (f, f)).copy_from(&(-&self.stiffness));
            r.view_mut((0, f), (f, f)).copy_from(&(-&self.damping));
            if s > 0 {
                r.view_mut((0, 2 * f), (f, s)).copy_from(&self.states.force);
            }
            r
        };
        let lower = lu.solve(&rhs).filter(|x| x.iter().all(|v| v.is_finite()));
        let Some(lower) = lower else {
            let weakest =
                (0..f).min_by(|&a, &b| self.mass[(a, a)].abs().total_cmp(&self.mass[(b, b)].abs()));
            return Err(DynError::Massless {
                part: weakest.map_or_else(String::new, |k| self.coords[k].name.clone()),
                directions: 1,
            });
        };
        let mut a = DMat::zeros(2 * f + s, 2 * f + s);
        for i in 0..f {
            a[(i, f + i)] = 1.0;
        }
        a.view_mut((f, 0), (f, 2 * f + s)).copy_from(&lower);
        if s > 0 {
            let c = &self.states;
            a.view_mut((2 * f, 0), (s, f)).copy_from(&c.dq);
            a.view_mut((2 * f, f), (s, f)).copy_from(&c.dv);
            a.view_mut((2 * f, 2 * f), (s, s)).copy_from(&c.dx);
        }
        Ok(a)
    }

    /// The names of the states of [`Linearized::state_matrix`]: each coordinate, then
    /// each one's rate (`d/dt PART/2 rotation about z`), then the state elements'
    /// (`DIFF/3`, `LSE/2 x1`).
    pub fn state_names(&self) -> Vec<String> {
        let names = self.coords.iter().map(|c| c.name.clone());
        names
            .clone()
            .chain(names.map(|n| format!("d/dt {n}")))
            .chain(self.states.names.iter().cloned())
            .collect()
    }
}
