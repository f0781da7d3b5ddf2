//! Planar scenes: decides whether a system can run in 2D (two translations and a
//! rotation per part in the global XY, ZX or YZ plane) with the same results as in 3D,
//! and says why in words.
//!
//! The scene is planar in the plane normal to axis n when gravity and every initial
//! velocity lie in the plane, every part has a BCS axis along n, every marker a constraint reads
//! has each axis along or across n, and every constraint row at the input configuration
//! is either in-plane (no derivative along δr_n or the two in-plane rotations) or
//! out-of-plane (no derivative along the in-plane translations or δθ_n) and then already
//! satisfied. With the marker-axis condition an out-of-plane row keeps its value
//! under any planar motion, so dropping it loses nothing; an in-plane row of the 2D
//! system is the 3D row restricted to the planar columns. Exudyn's 2D joints are what
//! remains: a REVOLUTE keeps X Delta and Y Delta, a TRANSLATIONAL with z_J in the plane
//! keeps one transverse Delta and Xi.Yj or Zi.Xj, the equations of the 2D prismatic joint.

use super::error::{element_name, MbdError};
use super::expr::ExprCompiler;
use super::handles::MarkerHandle;
use super::redundancy::{self, Problem};
use super::rows::Row;
use super::sparse::Triplets;
use super::system::{Dimension, System};
use crate::model::elements::Model;

/// Which dimension to build.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Dim {
    /// 2D when the scene is planar, else 3D.
    #[default]
    Auto,
    /// 3D whatever the scene.
    Three,
}

const TOL: f64 = 1e-9;

/// Builds the system of `model` in the dimension `dim` allows, keeping a 2D build only
/// when its constraints also hold every out-of-plane freedom ([`unlocked_out_of_plane`],
/// checked on the 3D build); otherwise the 3D system, whose `dim_reason` says why.
pub fn build(model: &Model, dim: Dim, exprs: &dyn ExprCompiler) -> Result<System, MbdError> {
    let mut system = System::from_model(model, dim, exprs)?;
    if system.dim == Dimension::Two {
        let mut three = System::from_model(model, Dim::Three, exprs)?;
        // A plane whose out-of-plane freedoms are free (a slide along its normal) may
        // leave another plane that holds them: try the rest before 3D.
        let mut skip = Vec::new();
        let mut first_why = None;
        while system.dim == Dimension::Two {
            let Some(why) = unlocked_out_of_plane(&three, system.normal) else {
                break;
            };
            first_why.get_or_insert(why);
            skip.push(system.normal);
            system.plan(Some(&skip));
        }
        if let (Dimension::Three, Some(why)) = (system.dim, first_why) {
            three.dim_reason = format!("3D: {why}");
            system = three;
        }
    }
    Ok(system)
}

/// Why a scene the core found planar must still be built in 3D, if it must: a 2D build
/// leaves out every out-of-plane force, which is only right when the constraints lock
/// each moving part's out-of-plane freedoms (translation along the normal, rotations
/// about the two in-plane axes). Otherwise the out-of-plane forces move the parts out of
/// the plane: chrono's Distance cases (a GCON on DM) and Universal cases (a HOOKE
/// pendulum swinging in the plane the detector did not choose) do so in Adams. The test:
/// the rank of the 3D constraint Jacobian (`three`) restricted to the out-of-plane
/// columns of the plane with normal axis `normal` equals their number.
pub fn unlocked_out_of_plane(three: &System, normal: usize) -> Option<String> {
    let parts = three.moving_parts();
    let out = [normal, 3 + (normal + 1) % 3, 3 + (normal + 2) % 3];
    let full = three.jacobian(true).ok()?;
    let mut j = Triplets::new(full.nrows, 3 * parts);
    // Entries of rounding size (1e-16 where an axis is exactly across the plane) are
    // zeros: the analysis equilibrates columns and would read them as full entries.
    for &(r, c, x) in full.entries.iter().filter(|e| e.2.abs() > 1e-10) {
        let (part, k) = (c as usize / 6, c as usize % 6);
        if let Some(p) = out.iter().position(|&o| o == k) {
            j.push(r as usize, 3 * part + p, x);
        }
    }
    let (labels, elements) = (three.labels(), three.element_refs());
    let problem = Problem::new(&j, &labels, &elements, parts, 2);
    let rank = redundancy::analyze(&problem, &redundancy::Options::default())
        .ok()?
        .rank;
    let plane = PLANES[normal];
    (rank < 3 * parts).then(|| {
        format!(
            "the scene lies in the global {plane} plane, but {} of its {} out-of-plane freedoms are not held by constraints (out-of-plane forces would move the parts out of the plane)",
            3 * parts - rank,
            3 * parts
        )
    })
}

/// The coordinate plane normal to axis 0, 1, 2.
const PLANES: [&str; 3] = ["YZ", "ZX", "XY"];

impl System {
    /// Fixes the model length and the dimension once every part, marker and element is
    /// in. Call it at the input configuration, before assembly.
    pub fn prepare(&mut self, dim: Dim) {
        self.length = self.characteristic_length();
        if dim == Dim::Three {
            self.plan(None);
        } else {
            self.plan(Some(&[]));
        }
    }

    /// Chooses the plane, skipping the normals in `skip` (None: 3D, forced).
    fn plan(&mut self, skip: Option<&[usize]>) {
        self.dim = Dimension::Three;
        for el in &mut self.elements {
            for q in &mut el.eqs {
                q.active = true;
            }
        }
        let planar = match skip {
            None => Err("forced by the Dim option".to_string()),
            Some(skip) => self.planar(skip),
        };
        match planar {
            Ok((normal, drop)) => {
                let kept = self.rows().count() - drop.len();
                for &(e, q) in &drop {
                    self.elements[e].eqs[q].active = false;
                }
                self.dim = Dimension::Two;
                self.normal = normal;
                for p in &mut self.parts {
                    p.theta = 0.0;
                }
                self.dim_reason = format!(
                    "2D: every part stays in the global {} plane ({kept} in-plane equations; {} out-of-plane equations are satisfied identically and left out)",
                    PLANES[normal],
                    drop.len()
                );
            }
            Err(why) => self.dim_reason = format!("3D: {why}"),
        }
    }

    /// The plane normal and the rows to drop in 2D, or why the scene is not planar. Tries
    /// the plane normal to most joint axes first, then the others (none in `skip`); when
    /// none fits, the reason given is the one for the plane of the joint axes.
    fn planar(&self, skip: &[usize]) -> Result<(usize, Vec<(usize, usize)>), String> {
        let first = self.joint_axis_normal();
        let mut why = String::new();
        for normal in [first, 2, 1, 0].into_iter().filter(|n| !skip.contains(n)) {
            match self.planar_in(normal) {
                Ok(drop) => return Ok((normal, drop)),
                Err(w) if normal == first && why.is_empty() => why = w,
                Err(_) => {}
            }
        }
        Err(why)
    }

    /// The global axis most elements' J-marker z axes lie along (Z when none does).
    fn joint_axis_normal(&self) -> usize {
        let mut votes = [0usize; 3];
        for el in &self.elements {
            if let Some(Row::Along { j, .. } | Row::Dot { j, .. }) = el.eqs.first().map(|q| &q.row)
            {
                let z = self.frame(Some(*j)).rot.column(2).into_owned();
                if let Some(k) = (0..3).find(|&k| (z[k].abs() - 1.0).abs() <= TOL) {
                    votes[k] += 1;
                }
            }
        }
        let best = votes.iter().copied().max().unwrap_or(0);
        if best == 0 || votes[2] == best {
            2
        } else if votes[1] == best {
            1
        } else {
            0
        }
    }

    fn part_word(&self, h: super::handles::PartHandle) -> String {
        match self.part(h).id {
            Some(id) => format!("PART/{id}"),
            None => format!("part #{}", h.0),
        }
    }

    /// The rows to drop for motion in the plane normal to axis `n`, or why not.
    fn planar_in(&self, n: usize) -> Result<Vec<(usize, usize)>, String> {
        let (a, b) = ((n + 1) % 3, (n + 2) % 3);
        let plane = PLANES[n];
        let axis = ["X", "Y", "Z"][n];
        if self.gravity[n].abs() > TOL * self.gravity.norm().max(1.0) {
            return Err(format!("gravity has a component along global {axis}"));
        }
        for (i, p) in self
            .parts
            .iter()
            .enumerate()
            .filter(|(_, p)| p.index.is_some())
        {
            let h = super::handles::PartHandle(i as u32);
            // Some BCS axis along the normal (kinematics would not need it, but a body
            // turned obliquely would leave the plane under its own inertia).
            let r = p.rot.to_rotation_matrix().into_inner();
            if !(0..3).any(|c| (r[(n, c)].abs() - 1.0).abs() <= TOL) {
                let why = format!(
                    "{} has no axis normal to the global {plane} plane",
                    self.part_word(h)
                );
                return Err(why);
            }
            if p.input_v[n].abs() > TOL || p.input_w[a].abs() > TOL || p.input_w[b].abs() > TOL {
                let why = format!(
                    "{} has an initial velocity out of the {plane} plane",
                    self.part_word(h)
                );
                return Err(why);
            }
        }
        let mut drop = Vec::new();
        for (e, q) in self.rows() {
            let el = &self.elements[e];
            let markers: Vec<MarkerHandle> = match &el.eqs[q].row {
                Row::Along { i, j, .. } | Row::Dot { i, j, .. } => vec![*i, *j],
                Row::Measured { terms, .. } => terms
                    .iter()
                    .flat_map(|t| self.measures.list[t.1].markers())
                    .flatten()
                    .collect(),
                Row::Gcon { map, .. } => map
                    .iter()
                    .flat_map(|&m| self.measures.list[m].markers())
                    .flatten()
                    .collect(),
            };
            for m in markers {
                let rot = self.frame(Some(m)).rot;
                if (0..3).any(|c| {
                    let z = rot[(n, c)].abs();
                    z > TOL && (z - 1.0).abs() > TOL
                }) {
                    let id = self
                        .marker(m)
                        .id
                        .map_or("a marker".into(), |i| format!("MARKER/{i}"));
                    let why = format!(
                        "{id} of {} has an axis oblique to global {axis}",
                        element_name(&el.elref)
                    );
                    return Err(why);
                }
            }
            let ev = self.eval_row(e, q).map_err(|x| x.to_string())?;
            let entries = if self.row_reads_velocity(e, q) {
                &ev.dv
            } else {
                &ev.dq
            };
            let (mut inp, mut outp) = (0.0f64, 0.0f64);
            for &(c, x) in entries {
                let k = c % 6;
                let scaled = if k < 3 { x * self.length } else { x };
                if k == a || k == b || k == 3 + n {
                    inp = inp.max(scaled.abs());
                } else {
                    outp = outp.max(scaled.abs());
                }
            }
            let label = el.eqs[q].label.label();
            if outp <= TOL {
                continue;
            }
            if inp > TOL {
                let why = format!(
                    "{} ({label}) couples motion in and out of the {plane} plane",
                    element_name(&el.elref)
                );
                return Err(why);
            }
            let scale = if el.eqs[q].translational {
                1.0 / self.length
            } else {
                1.0
            };
            if (ev.value * scale).abs() > TOL {
                let why = format!(
                    "{} ({label}) is violated out of the {plane} plane",
                    element_name(&el.elref)
                );
                return Err(why);
            }
            // Satisfied now is not satisfied identically when the equation moves with
            // time: it drives motion out of the plane.
            if self.row_reads_time(e, q) {
                let why = format!(
                    "{} ({label}) depends on time and drives motion out of the {plane} plane",
                    element_name(&el.elref)
                );
                return Err(why);
            }
            drop.push((e, q));
        }
        Ok(drop)
    }
}
