//! A model's CONTACTs into a [`ContactSet`]: every GRAPHICS they name becomes one
//! geometry of one world (shared by the contacts naming it), every I × J combination of a
//! contact a watched pair; a planar system queries in its plane. A pair with a
//! stand-in geometry that overlaps at the assembled start is held out until it
//! separates.

use super::{ContactForce, ContactSet, ContactValues, HeldOut, Pair};
use crate::collide::{Geometry, Space, TriMesh, World};
use crate::mbd::error::MbdError;
use crate::mbd::handles::PartHandle;
use crate::mbd::system::{Dimension, System};
use crate::model::elements::{Id, Model};
use crate::vocab::math::Vec3;
use std::cell::RefCell;
use std::collections::HashMap;

impl ContactSet {
    /// The contacts of `model` over the parts of `sys`; an EXTERNAL geometry takes its
    /// mesh from `meshes` (keyed by GRAPHICS id). A CONTACT with a GRAPHICS that cannot
    /// be a contact geometry (on a flexible body, an EXTERNAL without a mesh), or with I
    /// and J geometries on one part, is left out, the reason in
    /// [`ContactSet::left_out`].
    pub fn from_model(
        sys: &System,
        model: &Model,
        meshes: &HashMap<Id, TriMesh>,
    ) -> Result<ContactSet, MbdError> {
        if model.contacts.is_empty() {
            return Ok(ContactSet::default());
        }
        let parts: HashMap<Id, PartHandle> = (sys.parts.iter().enumerate())
            .filter_map(|(k, p)| Some((p.id?, PartHandle(k as u32))))
            .collect();
        let mut geometries: Vec<Geometry> = Vec::new();
        let mut index: HashMap<Id, usize> = HashMap::new();
        let mut pairs = Vec::new();
        let mut watched = Vec::new();
        let mut contacts = Vec::new();
        let mut left_out = Vec::new();
        for c in &model.contacts {
            let k = contacts.len();
            let (kept_geometries, kept_pairs) = (geometries.len(), pairs.len());
            let built = watch(
                model,
                meshes,
                &parts,
                c,
                k,
                (&mut geometries, &mut index),
                (&mut pairs, &mut watched),
            );
            if let Err(why) = built {
                // Forget what this contact added: the geometries it alone named too.
                geometries.truncate(kept_geometries);
                index.retain(|_, at| *at < kept_geometries);
                pairs.truncate(kept_pairs);
                watched.truncate(kept_pairs);
                left_out.push((c.el.id, why));
            }
            // A contact left out keeps its place (outputs address contacts by their
            // position in the model) and, watching no pair, reads zero.
            contacts.push(ContactForce {
                id: c.el.id,
                normal: c.normal,
                friction: c.friction,
                last: ContactValues::default(),
            });
        }
        let space = match sys.dim {
            Dimension::Three => Space::Three,
            Dimension::Two => {
                let (a, b, n) = sys.plane_axes();
                let axis = |c: usize| {
                    let mut v = Vec3::zeros();
                    v[c] = 1.0;
                    v
                };
                // The plane the parts move in: through the first moving part's
                // reference point (every part keeps its out-of-plane coordinate).
                let level = sys
                    .parts
                    .iter()
                    .find(|p| p.index.is_some())
                    .map_or(0.0, |p| p.r[n]);
                Space::Plane {
                    origin: axis(n) * level,
                    a: axis(a),
                    b: axis(b),
                }
            }
        };
        let held = vec![false; watched.len()];
        let mut set = ContactSet {
            contacts,
            pairs: watched,
            world: Some(RefCell::new(World::new(geometries, pairs, space))),
            parts,
            left_out,
            incidents: RefCell::new(Vec::new()),
            candidates: RefCell::new(Vec::new()),
            statics: false,
            held,
            held_at_start: Vec::new(),
            held_out: Vec::new(),
        };
        set.hold_overlapping_stand_ins(sys);
        set.held_at_start.clone_from(&set.held);
        Ok(set)
    }

    /// Holds out every pair with a stand-in geometry that overlaps at the state of `sys`
    /// (the assembled start): a placeholder box is not the user's geometry, so its
    /// overlap there is its own artefact, not a contact to push apart at once.
    fn hold_overlapping_stand_ins(&mut self, sys: &System) {
        let Some(world) = &self.world else { return };
        let with_stand_in: Vec<usize> = {
            let w = world.borrow();
            let g = w.geometries();
            (w.pairs().iter().enumerate())
                .filter(|(_, &(i, j))| g[i].stand_in || g[j].stand_in)
                .map(|(k, _)| k)
                .collect()
        };
        if with_stand_in.is_empty() {
            return;
        }
        self.place(sys);
        let w = world.borrow();
        let mut incidents = Vec::new();
        for k in with_stand_in {
            w.incidents(k, &mut incidents);
            if incidents.is_empty() {
                continue;
            }
            self.held[k] = true;
            let (i, j) = w.pairs()[k];
            self.held_out.push(HeldOut {
                contact: self.contacts[self.pairs[k].contact].id,
                graphics: (w.geometries()[i].graphic, w.geometries()[j].graphic),
                depth: incidents.iter().map(|c| c.depth).fold(0.0, f64::max),
            });
        }
    }
}

/// The geometries being gathered (each once) and the GRAPHICS id of each.
type Gathered<'a> = (&'a mut Vec<Geometry>, &'a mut HashMap<Id, usize>);

/// The world's pairs and the set's pairs being gathered.
type Watched<'a> = (&'a mut Vec<(usize, usize)>, &'a mut Vec<Pair>);

/// Adds the geometries and pairs of CONTACT `c` (the `k`-th kept); why not, when one of
/// its GRAPHICS cannot be a contact geometry or I and J share a part (what it added is
/// then for the caller to drop).
fn watch(
    model: &Model,
    meshes: &HashMap<Id, TriMesh>,
    parts: &HashMap<Id, PartHandle>,
    c: &crate::model::contact::Contact,
    k: usize,
    (geometries, index): Gathered,
    (pairs, watched): Watched,
) -> Result<(), String> {
    let mut side = |ids: &[Id]| -> Result<Vec<usize>, String> {
        let mut out = Vec::with_capacity(ids.len());
        for &g in ids {
            let at = match index.get(&g) {
                Some(&at) => at,
                None => {
                    geometries.push(Geometry::of(model, g, meshes).map_err(|e| e.to_string())?);
                    index.insert(g, geometries.len() - 1);
                    geometries.len() - 1
                }
            };
            out.push(at);
        }
        Ok(out)
    };
    let (is, js) = (side(&c.igeom)?, side(&c.jgeom)?);
    let part = |g: usize| {
        let id = geometries[g].part;
        parts
            .get(&id)
            .copied()
            .ok_or(format!("PART/{id} does not exist"))
    };
    for &gi in &is {
        for &gj in &js {
            let (pi, pj) = (part(gi)?, part(gj)?);
            if pi == pj {
                return Err(format!(
                    "GRAPHICS/{} and GRAPHICS/{} move with one part",
                    geometries[gi].graphic, geometries[gj].graphic
                ));
            }
            pairs.push((gi, gj));
            watched.push(Pair {
                contact: k,
                i: pi,
                j: pj,
            });
        }
    }
    Ok(())
}
