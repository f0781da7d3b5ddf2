//! Planar scenes: decides whether a system can run in 2D (x, y, θ per part in the
//! global XY plane) with the same results as in 3D, and says why in words.
//!
//! The scene is planar when gravity and every initial velocity lie in the XY plane,
//! every part's z axis is ±Z, every marker a constraint reads has each axis along or
//! across Z, and every constraint row at the input configuration is either in-plane (no
//! derivative along z, θx, θy) or out-of-plane (no derivative along x, y, θz) and then
//! already satisfied. With the marker-axis condition an out-of-plane row keeps its value
//! under any planar motion, so dropping it loses nothing; an in-plane row of the 2D
//! system is the 3D row restricted to the planar columns. Exudyn's 2D joints are what
//! remains: a REVOLUTE keeps X Delta and Y Delta, a TRANSLATIONAL with z_J in the plane
//! keeps one transverse Delta and Xi.Yj or Zi.Xj, the equations of the 2D prismatic joint.

use super::constraints::Row;
use super::error::element_name;
use super::system::{Dimension, MarkerHandle, System};

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

impl System {
    /// Fixes the model length and the dimension once every part, marker and element is
    /// in. Call it at the input configuration, before assembly.
    pub fn prepare(&mut self, dim: Dim) {
        self.length = self.characteristic_length();
        self.dim = Dimension::Three;
        for el in &mut self.elements {
            for q in &mut el.eqs {
                q.active = true;
            }
        }
        match self.planar(dim) {
            Ok(drop) => {
                let kept = self.rows().count() - drop.len();
                for &(e, q) in &drop {
                    self.elements[e].eqs[q].active = false;
                }
                self.dim = Dimension::Two;
                for p in &mut self.parts {
                    p.theta = 0.0;
                }
                self.dim_reason = format!(
                    "2D: every part stays in the global XY plane ({kept} in-plane equations; {} out-of-plane equations are satisfied identically and left out)",
                    drop.len()
                );
            }
            Err(why) => self.dim_reason = format!("3D: {why}"),
        }
    }

    fn part_word(&self, h: super::system::PartHandle) -> String {
        match self.part(h).id {
            Some(id) => format!("PART/{id}"),
            None => format!("part #{}", h.0),
        }
    }

    /// The rows to drop in 2D, or why the scene is not planar.
    fn planar(&self, dim: Dim) -> Result<Vec<(usize, usize)>, String> {
        if dim == Dim::Three {
            return Err("forced by the Dim option".into());
        }
        if self.gravity.z.abs() > TOL * self.gravity.norm().max(1.0) {
            return Err("gravity has a component along global Z".into());
        }
        for (i, p) in self
            .parts
            .iter()
            .enumerate()
            .filter(|(_, p)| p.index.is_some())
        {
            let h = super::system::PartHandle(i as u32);
            let rz = p.rot.to_rotation_matrix().into_inner()[(2, 2)];
            if (rz.abs() - 1.0).abs() > TOL {
                return Err(format!(
                    "{} is tilted out of the global XY plane",
                    self.part_word(h)
                ));
            }
            if p.input_v.z.abs() > TOL || p.input_w.x.abs() > TOL || p.input_w.y.abs() > TOL {
                return Err(format!(
                    "{} has an initial velocity out of the XY plane",
                    self.part_word(h)
                ));
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
                    let z = rot[(2, c)].abs();
                    z > TOL && (z - 1.0).abs() > TOL
                }) {
                    let id = self
                        .marker(m)
                        .id
                        .map_or("a marker".into(), |i| format!("MARKER/{i}"));
                    return Err(format!(
                        "{id} of {} has an axis oblique to global Z",
                        element_name(&el.elref)
                    ));
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
                if matches!(k, 0 | 1 | 5) {
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
                return Err(format!(
                    "{} ({label}) couples in-plane and out-of-plane motion",
                    element_name(&el.elref)
                ));
            }
            let scale = if el.eqs[q].translational {
                1.0 / self.length
            } else {
                1.0
            };
            if (ev.value * scale).abs() > TOL {
                return Err(format!(
                    "{} ({label}) is violated out of the XY plane",
                    element_name(&el.elref)
                ));
            }
            drop.push((e, q));
        }
        Ok(drop)
    }
}
