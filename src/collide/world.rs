//! The contact world: every geometry placed at a state, a broad phase (parry's BVH,
//! rebuilt at each update) that finds the pairs whose bounding boxes overlap, and the
//! narrow phase that gives one pair's separation and incidents (two closed meshes in
//! their convex pieces).

use super::convert::{compose, from_parry, pose_to_parry};
use super::planar::{self, Plane, Section};
use super::regions::{self, Touch};
use super::{Geometry, Incident, Pose, Space};
use crate::model::elements::Id;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Pose as Pose3;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use parry3d_f64::query::{
    ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher, QueryDispatcher,
};
use parry3d_f64::shape::SharedShape;
use std::collections::HashMap;

mod reach;
pub use reach::Reach;

/// The geometries of a model's contacts, the pairs to watch, and where they are.
pub struct World {
    geometries: Vec<Geometry>,
    pairs: Vec<(usize, usize)>,
    space: Space,
    /// Global pose of each geometry's parry shape (after [`World::update`]).
    poses: Vec<Pose3>,
    /// Global bounding box of each geometry.
    boxes: Vec<Aabb>,
    bvh: Bvh,
    /// The tree no longer matches `boxes` (an update moved them): rebuilt by the next
    /// [`World::candidates`], so an update that only reads boxes (the step bound's
    /// reach) does not pay for a tree.
    bvh_stale: bool,
    workspace: BvhWorkspace,
    /// The pairs (their indices) watched between two geometries, keyed (low, high).
    pairs_of: HashMap<(usize, usize), Vec<usize>>,
    /// Whether `update` has run since the geometries were placed.
    placed: bool,
    /// The plane of a planar world.
    plane: Option<Plane>,
    /// Each geometry's section by the plane (taken at the first update), and its 2D
    /// pose: `None` for a geometry queried in 3D.
    sections: Vec<Option<(Section, planar::Pose2)>>,
    /// The convex pieces of each closed, non-convex mesh that a mesh–mesh pair watches
    /// (`None` otherwise): two surfaces' manifolds see only where they cross, pieces
    /// see how deep they overlap.
    solids: Vec<Option<Solid>>,
}

/// A closed mesh as convex pieces (parry's compound of its V-HACD decomposition), and
/// which pieces touch: `links[p]` lists ids shared by the pieces next to piece p.
struct Solid {
    shape: SharedShape,
    links: Vec<Vec<u32>>,
}

impl Solid {
    /// The convex pieces of mesh `g` (held as triangles).
    fn of(g: &Geometry) -> Option<Solid> {
        let mesh = g.shape.as_trimesh()?;
        let shape = SharedShape::convex_decomposition(mesh.vertices(), mesh.indices());
        let pieces = shape.as_compound()?.shapes();
        // Pieces of one solid meet face to face: boxes grown by 10⁻⁹ of the mesh's
        // size that overlap are neighbours.
        let grow = 1e-9 * mesh.local_aabb().extents().length();
        let boxes: Vec<Aabb> = (pieces.iter())
            .map(|(pose, piece)| piece.compute_aabb(pose).loosened(grow))
            .collect();
        let mut links = vec![Vec::new(); boxes.len()];
        let mut next = 0u32;
        for a in 0..boxes.len() {
            links[a].push(next);
            next += 1;
            for b in a + 1..boxes.len() {
                if boxes[a].intersects(&boxes[b]) {
                    links[a].push(next);
                    links[b].push(next);
                    next += 1;
                }
            }
        }
        Some(Solid { shape, links })
    }
}

impl World {
    /// A world of `geometries` watching `pairs` (indices into `geometries`: I, J) in
    /// `space`. A pair naming a geometry past the list is kept and never touches.
    pub fn new(geometries: Vec<Geometry>, pairs: Vec<(usize, usize)>, space: Space) -> World {
        let mut pairs_of: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
        for (k, &(i, j)) in pairs.iter().enumerate() {
            pairs_of.entry((i.min(j), i.max(j))).or_default().push(k);
        }
        let n = geometries.len();
        let mut solids: Vec<Option<Solid>> = (0..n).map(|_| None).collect();
        for &(i, j) in &pairs {
            let closed = |k: usize| geometries.get(k).is_some_and(|g| g.is_mesh() && g.closed);
            if i != j && closed(i) && closed(j) {
                for k in [i, j] {
                    if solids[k].is_none() {
                        solids[k] = Solid::of(&geometries[k]);
                    }
                }
            }
        }
        World {
            solids,
            geometries,
            pairs,
            space,
            poses: vec![Pose3::IDENTITY; n],
            boxes: vec![Aabb::new_invalid(); n],
            bvh: Bvh::new(),
            bvh_stale: false,
            workspace: BvhWorkspace::default(),
            pairs_of,
            placed: false,
            plane: match space {
                Space::Three => None,
                Space::Plane { origin, a, b } => Some(Plane { origin, a, b }),
            },
            sections: vec![None; n],
        }
    }

    /// The geometries, in the order `new` took them.
    pub fn geometries(&self) -> &[Geometry] {
        &self.geometries
    }

    /// The pairs watched (I, J geometry indices), in the order `new` took them.
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// The space the queries run in.
    pub fn space(&self) -> Space {
        self.space
    }

    /// Places every geometry from the global pose of its part's BCS; the broad phase is
    /// rebuilt when next asked for candidates.
    pub fn update(&mut self, part_pose: &dyn Fn(Id) -> Pose) {
        let first = !self.placed;
        for (k, g) in self.geometries.iter().enumerate() {
            let part = part_pose(g.part);
            if !(part.r.iter().chain(part.rot.iter())).all(|v| v.is_finite()) {
                // A state with a NaN (a failing step) keeps the geometry where it was:
                // the core rejects the state; the broad phase must not be fed a NaN.
                continue;
            }
            let frame = compose(&part, &g.frame);
            self.poses[k] = pose_to_parry(&compose(&frame, &g.fix));
            self.boxes[k] = g.shape.compute_aabb(&self.poses[k]);
            let Some(plane) = &self.plane else {
                continue;
            };
            if first {
                self.sections[k] =
                    Section::of(g, &frame, plane).map(|s| (s, planar::Pose2::IDENTITY));
            }
            if let Some((section, pose)) = &mut self.sections[k] {
                *pose = section.pose(&frame, plane);
            }
        }
        self.bvh_stale = true;
        self.placed = true;
    }

    /// Cleared, then filled with the indices of the pairs whose bounding boxes overlap
    /// (ascending): the only pairs that can touch. Empty before the first `update`.
    pub fn candidates(&mut self, out: &mut Vec<usize>) {
        out.clear();
        if !self.placed {
            return;
        }
        if self.bvh_stale {
            // A rebuild is O(N log N) and keeps the tree tight however far the parts
            // moved (a refit would keep the old topology).
            self.bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &self.boxes);
            self.bvh_stale = false;
        }
        let pairs_of = &self.pairs_of;
        self.bvh
            .traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut |a, b| {
                let (a, b) = (a as usize, b as usize);
                if let Some(ks) = pairs_of.get(&(a.min(b), a.max(b))) {
                    out.extend_from_slice(ks);
                }
            });
        // A pair of one geometry with itself never overlaps anything but itself.
        out.sort_unstable();
        out.dedup();
    }

    /// Whether the pair is queried in the plane (parry2d on the sections) rather than
    /// in 3D: in a planar world once updated, when both sections are simple shapes.
    pub fn in_plane(&self, pair: usize) -> bool {
        self.pair(pair)
            .is_some_and(|(i, j)| self.sections_of(i, j).is_some())
    }

    /// The pair's geometries, or `None` for a pair that names none.
    fn pair(&self, pair: usize) -> Option<(usize, usize)> {
        let &(i, j) = self.pairs.get(pair)?;
        (i < self.geometries.len() && j < self.geometries.len() && i != j).then_some((i, j))
    }

    /// Cleared, then filled with one incident per connected intersection region of the
    /// pair's two geometries (none when they are apart).
    pub fn incidents(&self, pair: usize, out: &mut Vec<Incident>) {
        out.clear();
        let Some((i, j)) = self.pair(pair) else {
            return;
        };
        if !self.placed || !self.boxes[i].intersects(&self.boxes[j]) {
            return;
        }
        let touches = match self.sections_of(i, j) {
            Some((si, sj, plane)) => planar::touches(si, sj, plane, self.noise(i, j)),
            None => self.touches(i, j, 0.0),
        };
        match self.solids_of(i, j) {
            Some((a, b)) => regions::incidents(&touches, &a.links, &b.links, out),
            None => {
                let (gi, gj) = (&self.geometries[i], &self.geometries[j]);
                regions::incidents(&touches, &gi.triangles, &gj.triangles, out);
            }
        }
    }

    /// The convex pieces of both geometries of a mesh–mesh pair, when both are closed.
    fn solids_of(&self, i: usize, j: usize) -> Option<(&Solid, &Solid)> {
        Some((self.solids[i].as_ref()?, self.solids[j].as_ref()?))
    }

    /// The shapes pair (`i`, `j`) is queried with, and whether each is a composite whose
    /// touches name their triangle or piece.
    fn shapes(&self, i: usize, j: usize) -> (&SharedShape, &SharedShape, bool, bool) {
        match self.solids_of(i, j) {
            Some((a, b)) => (&a.shape, &b.shape, true, true),
            None => {
                let (gi, gj) = (&self.geometries[i], &self.geometries[j]);
                (&gi.shape, &gj.shape, gi.is_mesh(), gj.is_mesh())
            }
        }
    }

    /// The distance between the pair's geometries when apart (> 0), minus their deepest
    /// penetration when they overlap (< 0): the switching function whose sign change is
    /// contact onset or separation.
    pub fn separation(&self, pair: usize) -> f64 {
        let Some((i, j)) = self.pair(pair) else {
            return f64::INFINITY;
        };
        if let Some((si, sj, _)) = self.sections_of(i, j) {
            let d = planar::distance(si, sj);
            if d > 0.0 {
                return d;
            }
        }
        let (si, sj, _, _) = self.shapes(i, j);
        let pos12 = self.poses[i].inv_mul(&self.poses[j]);
        match DefaultQueryDispatcher.distance(&pos12, &**si, &**sj) {
            Ok(d) if d.distance > 0.0 => return d.distance,
            Ok(_) => {}
            Err(_) => {
                // Mesh against mesh: parry has no distance query, but its manifolds
                // with a prediction as wide as both boxes reach the closest triangles.
                let reach = self.boxes[i].merged(&self.boxes[j]).extents().length();
                let nearest = self
                    .points(i, j, reach)
                    .into_iter()
                    .map(|p| p.dist)
                    .fold(f64::INFINITY, f64::min);
                if nearest > 0.0 {
                    return nearest;
                }
            }
        }
        let mut found = Vec::new();
        self.incidents(pair, &mut found);
        -found.iter().map(|c| c.depth).fold(0.0, f64::max)
    }

    /// Round-off of a depth between `i` and `j`: 10⁻¹² of their bounding box.
    fn noise(&self, i: usize, j: usize) -> f64 {
        1e-12 * self.boxes[i].merged(&self.boxes[j]).extents().length()
    }

    /// The two sections of a pair queried in the plane, with the plane.
    #[allow(clippy::type_complexity)]
    fn sections_of(
        &self,
        i: usize,
        j: usize,
    ) -> Option<(
        (&Section, &planar::Pose2),
        (&Section, &planar::Pose2),
        &Plane,
    )> {
        let plane = self.plane.as_ref()?;
        let (si, pi) = self.sections[i].as_ref()?;
        let (sj, pj) = self.sections[j].as_ref()?;
        Some(((si, pi), (sj, pj), plane))
    }

    /// The narrow phase's points between geometries `i` and `j` closer than
    /// `prediction` (negative `dist`: penetrating), global.
    fn points(&self, i: usize, j: usize, prediction: f64) -> Vec<Point> {
        let (si, sj, parts_i, parts_j) = self.shapes(i, j);
        let (pi, pj) = (&self.poses[i], &self.poses[j]);
        let pos12 = pi.inv_mul(pj);
        let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
        let mut workspace = None;
        // Every pair of this layer's shapes has a manifold generator; an unsupported
        // pair would give no points (no contact), never a panic.
        let _ = DefaultQueryDispatcher.contact_manifolds(
            &pos12,
            &**si,
            &**sj,
            prediction,
            &mut manifolds,
            &mut workspace,
        );
        let mut out = Vec::new();
        for (m, manifold) in manifolds.iter().enumerate() {
            let sub = manifold.subshape_poses.as_deref();
            let sub1 = sub.and_then(|s| s.pos1).unwrap_or(Pose3::IDENTITY);
            let sub2 = sub.and_then(|s| s.pos2).unwrap_or(Pose3::IDENTITY);
            let (frame1, frame2) = (*pi * sub1, *pj * sub2);
            let n1 = frame1.rotation * manifold.local_n1;
            for c in &manifold.points {
                let p1 = frame1.transform_point(c.local_p1);
                let p2 = frame2.transform_point(c.local_p2);
                out.push(Point {
                    at: from_parry((p1 + p2) * 0.5),
                    // parry's normal points out of shape 1 (I) towards J: the force on
                    // I pushes the other way.
                    normal: -from_parry(n1),
                    dist: c.dist,
                    manifold: m,
                    sub1: parts_i.then_some(manifold.subshape1),
                    sub2: parts_j.then_some(manifold.subshape2),
                });
            }
        }
        out
    }

    /// The penetrating points between `i` and `j`. A depth within round-off of the
    /// pair's size (10⁻¹² of its bounding box) is no penetration: coplanar faces of two
    /// meshes (walls of stacked parts) touch there with arbitrary normals.
    fn touches(&self, i: usize, j: usize, prediction: f64) -> Vec<Touch> {
        let noise = self.noise(i, j);
        self.points(i, j, prediction)
            .into_iter()
            .filter(|p| p.dist < -noise)
            .map(|p| Touch {
                point: p.at,
                normal: p.normal,
                depth: -p.dist,
                manifold: p.manifold,
                triangle_i: p.sub1,
                triangle_j: p.sub2,
            })
            .collect()
    }
}

/// One point of a manifold, global.
struct Point {
    at: crate::vocab::math::Vec3,
    normal: crate::vocab::math::Vec3,
    dist: f64,
    manifold: usize,
    sub1: Option<u32>,
    sub2: Option<u32>,
}
