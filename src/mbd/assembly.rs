//! Assembly: the configuration that satisfies every constraint, found from the input
//! positions by damped Gauss–Newton (Levenberg–Marquardt) with minimum-norm steps, then
//! the velocities closest to the input ones that satisfy Φ_q v = −Φ_t (and any
//! non-holonomic GCON). MOTIONs and GCONs are evaluated at [`System::time`].
//!
//! Steps are taken in scaled variables (δr / L, δθ) on rows scaled the same way
//! (translational rows / L, spec §5.3), so a millimetre model behaves like a metre one.
//! Redundant rows are harmless: the step is the least-squares step of least norm, which
//! also leaves the free coordinates where the user put them. Rows the redundancy analysis
//! dropped can be passed in [`AssemblyOptions::dropped`]; they are left out of the solve
//! and checked afterwards (a violated dropped row is a conflict, not a redundancy).

use super::equations::Equation;
use super::error::{element_name, MbdError};
use super::handles::PartHandle;
use super::normal::min_norm;
use super::rows::Row;
use super::sparse::Triplets;
use super::system::{Dimension, System};
use crate::model::elements::Id;
use crate::vocab::elements::ElementRef;
use crate::vocab::math::{DVec, Quat, Vec3};
use std::fmt;

/// Settings of [`System::assemble`].
#[derive(Clone, Debug)]
pub struct AssemblyOptions {
    /// Largest scaled residual accepted (translational rows in model lengths / L).
    pub tol: f64,
    /// The most Newton iterations before assembly gives up.
    pub max_iter: usize,
    /// Row indices (as in [`System::labels`]) the redundancy analysis removed.
    pub dropped: Vec<usize>,
}

impl Default for AssemblyOptions {
    fn default() -> Self {
        AssemblyOptions {
            tol: 1e-10,
            max_iter: 60,
            dropped: Vec::new(),
        }
    }
}

/// How far assembly moved a part from its input pose.
#[derive(Clone, Debug, PartialEq)]
pub struct PartMove {
    /// The moved part.
    pub part: PartHandle,
    /// Its Adams PART id.
    pub id: Option<Id>,
    /// |r − r_input| (model length).
    pub translation: f64,
    /// Angle of R·R_inputᵀ (radians).
    pub rotation: f64,
}

/// What assembly did.
#[derive(Clone, Debug)]
pub struct AssemblyReport {
    /// Newton iterations taken.
    pub iterations: usize,
    /// Largest scaled position residual at the end.
    pub residual: f64,
    /// Largest scaled velocity-constraint residual at the end.
    pub velocity_residual: f64,
    /// Per moving part, how far it moved.
    pub moves: Vec<PartMove>,
}

/// One equation that is not satisfied.
#[derive(Clone, Debug, PartialEq)]
pub struct Violation {
    /// The element the equation belongs to.
    pub element: ElementRef,
    /// The equation's Adams label.
    pub equation: Equation,
    /// Its scaled residual.
    pub residual: f64,
}

/// Why assembly stopped.
#[derive(Clone, Debug)]
pub enum AssemblyError {
    /// The constraints could not all be satisfied.
    NotAssembled {
        /// Newton iterations taken.
        iterations: usize,
        /// Largest scaled residual at the end.
        residual: f64,
        /// The equations left unsatisfied.
        violated: Vec<Violation>,
    },
    /// Equations the redundancy analysis dropped are violated: conflicting, not redundant.
    Conflicting {
        /// The dropped equations that are violated.
        violated: Vec<Violation>,
    },
    /// An element or expression could not be evaluated.
    Model(MbdError),
}

impl From<MbdError> for AssemblyError {
    fn from(e: MbdError) -> Self {
        AssemblyError::Model(e)
    }
}

fn list(v: &[Violation]) -> String {
    v.iter()
        .map(|x| {
            format!(
                "\n  {}: {} off by {:.3e}",
                element_name(&x.element),
                x.equation.label(),
                x.residual
            )
        })
        .collect()
}

impl fmt::Display for AssemblyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AssemblyError::NotAssembled { iterations, residual, violated } => write!(
                f,
                "the model cannot be assembled: after {iterations} iterations the largest constraint error is {residual:.3e}; violated:{}",
                list(violated)
            ),
            AssemblyError::Conflicting { violated } => write!(
                f,
                "conflicting constraints: equations removed as redundant are violated:{}",
                list(violated)
            ),
            AssemblyError::Model(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for AssemblyError {}

/// The largest |x|, infinite when any x is NaN (`f64::max` would skip it).
fn largest(xs: &[f64]) -> f64 {
    xs.iter().fold(0.0, |m, x| {
        if x.is_nan() {
            f64::INFINITY
        } else {
            m.max(x.abs())
        }
    })
}

/// A linearised set of rows: sparse rows over columns, right-hand sides.
struct Linear {
    rows: Vec<Vec<(usize, f64)>>,
    rhs: Vec<f64>,
}

impl System {
    /// 1/L for a translational row (model lengths), 1 for the rest (spec §5.3).
    pub(crate) fn row_scale(&self, e: usize, q: usize) -> f64 {
        if self.elements[e].eqs[q].translational {
            1.0 / self.length
        } else {
            1.0
        }
    }

    /// Scale of column `col` in the scaled Jacobian: L for δr, 1 for δθ.
    fn col_scale(&self, col: usize) -> f64 {
        let c = col % self.dim.cols();
        let translational = match self.dim {
            Dimension::Three => c < 3,
            Dimension::Two => c < 2,
        };
        if translational {
            self.length
        } else {
            1.0
        }
    }

    /// The constraint residual Φ over the active rows (unscaled).
    pub fn residual(&self) -> Result<DVec, MbdError> {
        let v: Result<Vec<f64>, MbdError> =
            self.rows().map(|(e, q)| self.row_value(e, q)).collect();
        Ok(DVec::from_vec(v?))
    }

    /// The velocity-level residual over the active rows (unscaled): Φ_q v + Φ_t for a
    /// holonomic row, the function itself for a non-holonomic one (it reads velocities).
    pub fn velocity_residual(&self) -> Result<DVec, MbdError> {
        let v = self.v();
        let rows: Vec<(usize, usize)> = self.rows().collect();
        let mut out = DVec::zeros(rows.len());
        for (r, &(e, q)) in rows.iter().enumerate() {
            let ev = self.eval_row(e, q)?;
            out[r] = match self.row_reads_velocity(e, q) {
                true => ev.value,
                false => ev.dq.iter().map(|&(c, x)| x * v[c]).sum::<f64>() + self.row_dt(e, q)?,
            };
        }
        Ok(out)
    }

    /// Φ_q over the active rows with velocity-level columns (6 per moving part in 3D,
    /// 3 in 2D). A non-holonomic GCON row holds ∂f/∂v instead. With `scaled`,
    /// translational rows are divided by [`System::length`] and δr columns multiplied by
    /// it (spec §5.3): the matrix is then unit-free, which the redundancy analysis needs.
    pub fn jacobian(&self, scaled: bool) -> Result<Triplets, MbdError> {
        let rows: Vec<(usize, usize)> = self.rows().collect();
        let mut t = Triplets::new(rows.len(), self.ncols());
        for (r, &(e, q)) in rows.iter().enumerate() {
            let ev = self.eval_row(e, q)?;
            let entries = if self.row_reads_velocity(e, q) {
                &ev.dv
            } else {
                &ev.dq
            };
            let rs = if scaled { self.row_scale(e, q) } else { 1.0 };
            for &(c, x) in entries {
                let cs = if scaled { self.col_scale(c) } else { 1.0 };
                t.push(r, c, x * rs * cs);
            }
        }
        Ok(t)
    }

    /// Scaled position rows (holonomic, not dropped): J and −Φ.
    fn position_system(&self, keep: &[bool]) -> Result<(Linear, f64), MbdError> {
        let mut lin = Linear {
            rows: Vec::new(),
            rhs: Vec::new(),
        };
        for (r, (e, q)) in self.rows().enumerate() {
            if !keep[r] {
                continue;
            }
            let ev = self.eval_row(e, q)?;
            let s = self.row_scale(e, q);
            lin.rows.push(
                ev.dq
                    .iter()
                    .map(|&(c, x)| (c, x * s * self.col_scale(c)))
                    .collect(),
            );
            lin.rhs.push(-ev.value * s);
        }
        let worst = largest(&lin.rhs);
        Ok((lin, worst))
    }

    pub(crate) fn snapshot(&self) -> Vec<(Vec3, Quat, f64)> {
        self.parts.iter().map(|p| (p.r, p.rot, p.theta)).collect()
    }

    pub(crate) fn restore(&mut self, s: &[(Vec3, Quat, f64)]) {
        for (p, &(r, rot, th)) in self.parts.iter_mut().zip(s) {
            (p.r, p.theta) = (r, th);
            p.set_rot(rot);
        }
    }

    fn violations(&self, tol: f64, only: Option<&[bool]>) -> Vec<Violation> {
        let mut out: Vec<Violation> = self
            .rows()
            .enumerate()
            .filter(|(r, _)| only.is_none_or(|o| o[*r]))
            .filter_map(|(_, (e, q))| {
                let v = self.row_value(e, q).ok()? * self.row_scale(e, q);
                (v.is_nan() || v.abs() > tol).then(|| Violation {
                    element: self.elements[e].elref.clone(),
                    equation: self.elements[e].eqs[q].label,
                    residual: v.abs(),
                })
            })
            .collect();
        out.sort_by(|a, b| b.residual.total_cmp(&a.residual));
        out
    }

    /// Assembles positions, then velocities. On success the measures' unwrapping
    /// references move to the assembled state.
    pub fn assemble(&mut self, opts: &AssemblyOptions) -> Result<AssemblyReport, AssemblyError> {
        let nrows = self.rows().count();
        let holonomic: Vec<bool> = self
            .rows()
            .map(|(e, q)| !self.row_reads_velocity(e, q))
            .collect();
        let mut keep = holonomic.clone();
        for &d in &opts.dropped {
            if d < nrows {
                keep[d] = false;
            }
        }
        self.seed_motion_angles()?;
        let n = self.ncols();
        let (mut lin, mut worst) = self.position_system(&keep)?;
        let mut mu = 1e-10;
        let mut iterations = 0;
        while worst > opts.tol && iterations < opts.max_iter {
            iterations += 1;
            let norm0: f64 = lin.rhs.iter().map(|x| x * x).sum();
            let snap = self.snapshot();
            let mut accepted = false;
            for _ in 0..12 {
                let Some(mut dx) = min_norm(n, &lin.rows, &lin.rhs, mu, 2) else {
                    mu *= 10.0;
                    continue;
                };
                for (c, x) in dx.iter_mut().enumerate() {
                    *x *= self.col_scale(c);
                }
                self.apply_increment(&dx);
                let (l2, w2) = self.position_system(&keep)?;
                let norm1: f64 = l2.rhs.iter().map(|x| x * x).sum();
                if norm1 < norm0 || w2 <= opts.tol {
                    (lin, worst) = (l2, w2);
                    mu = (mu * 0.1).max(1e-12);
                    accepted = true;
                    break;
                }
                self.restore(&snap);
                mu *= 10.0;
            }
            if !accepted {
                break;
            }
        }
        if worst > opts.tol {
            return Err(AssemblyError::NotAssembled {
                iterations,
                residual: worst,
                violated: self.violations(opts.tol, Some(&holonomic)),
            });
        }
        let dropped_mask: Vec<bool> = (0..nrows).map(|r| holonomic[r] && !keep[r]).collect();
        let conflicts = self.violations(opts.tol.max(1e-8), Some(&dropped_mask));
        if !conflicts.is_empty() {
            return Err(AssemblyError::Conflicting {
                violated: conflicts,
            });
        }
        let velocity_residual = self.assemble_velocities(&keep, &holonomic)?;
        let mut measures = std::mem::take(&mut self.measures);
        measures.commit(self);
        self.measures = measures;
        let moves = self
            .parts
            .iter()
            .enumerate()
            .filter(|(_, p)| p.index.is_some())
            .map(|(i, p)| PartMove {
                part: PartHandle(i as u32),
                id: p.id,
                // The BCS origin's move, as the dataset placed it (the reference point is
                // the CM, which a rotation also moves).
                translation: (p.bcs_origin() - (p.input_r - p.input_rot * p.cm_offset)).norm(),
                rotation: (p.rot * p.input_rot.inverse()).angle(),
            })
            .collect();
        Ok(AssemblyReport {
            iterations,
            residual: worst,
            velocity_residual,
            moves,
        })
    }

    /// Seeds the unwrapping reference of every driven angle with its target g(t).
    fn seed_motion_angles(&mut self) -> Result<(), MbdError> {
        let mut seeds = Vec::new();
        for el in &self.elements {
            for q in el.eqs.iter().filter(|q| q.active) {
                if let Row::Measured {
                    terms,
                    drive: Some(g),
                } = &q.row
                {
                    if let [(c, m)] = terms[..] {
                        let target = g
                            .value(self.time, &[])
                            .map_err(|s| MbdError::Expression(el.elref.clone(), s))?;
                        seeds.push((m, target / c));
                    }
                }
            }
        }
        for (m, v) in seeds {
            self.measures.seed(m, v);
        }
        Ok(())
    }

    /// Velocities closest (in scaled norm) to the input ones satisfying the velocity
    /// constraints of the kept rows. Returns the largest scaled residual.
    fn assemble_velocities(&mut self, keep: &[bool], holonomic: &[bool]) -> Result<f64, MbdError> {
        let n = self.ncols();
        for p in &mut self.parts {
            (p.v, p.w) = (p.input_v, p.input_w);
        }
        if self.dim == Dimension::Two {
            let (a, b, n) = self.plane_axes();
            for p in &mut self.parts {
                p.v[n] = 0.0;
                p.w[a] = 0.0;
                p.w[b] = 0.0;
            }
        }
        let rows: Vec<(usize, (usize, usize))> = self.rows().enumerate().collect();
        let (mut worst, mut first) = (0.0, None);
        for iter in 0..5 {
            let v = self.v();
            let mut lin = Linear {
                rows: Vec::new(),
                rhs: Vec::new(),
            };
            for &(r, (e, q)) in &rows {
                let nonholonomic = !holonomic[r];
                if !(keep[r] || nonholonomic) {
                    continue;
                }
                let ev = self.eval_row(e, q)?;
                let s = self.row_scale(e, q);
                let entries = if nonholonomic { &ev.dv } else { &ev.dq };
                // Holonomic: Φ_q v + Φ_t; non-holonomic: f(q, v, t) itself.
                let value = if nonholonomic {
                    ev.value
                } else {
                    entries.iter().map(|&(c, x)| x * v[c]).sum::<f64>() + self.row_dt(e, q)?
                };
                lin.rows.push(
                    entries
                        .iter()
                        .map(|&(c, x)| (c, x * s * self.col_scale(c)))
                        .collect(),
                );
                lin.rhs.push(-value * s);
            }
            worst = largest(&lin.rhs);
            let start = *first.get_or_insert(worst);
            // Linear rows converge in one solve plus refinement; non-holonomic ones in a
            // few Newton rounds.
            if worst <= 1e-14 * (1.0 + start) || lin.rows.is_empty() || iter == 4 {
                break;
            }
            let Some(dv) = min_norm(n, &lin.rows, &lin.rhs, 1e-10, 3) else {
                break;
            };
            let mut v = v;
            for (c, x) in dv.iter().enumerate() {
                v[c] += x * self.col_scale(c);
            }
            self.set_v(&v);
        }
        Ok(worst)
    }
}
