//! Adams' semantics for a pair's contact: one incident per connected intersection
//! region. The narrow phase hands back touching points (a manifold per pair of convex
//! pieces); this file groups them into regions and reduces each region to one
//! [`Incident`]: its deepest penetration, its depth-weighted mean normal and the
//! area centroid of its points seen along that normal.

use super::Incident;
use crate::vocab::math::Vec3;
use std::collections::HashMap;

/// One penetrating point of the narrow phase, global axes.
#[derive(Clone, Copy, Debug)]
pub struct Touch {
    /// Midway between the two surfaces' deepest points.
    pub point: Vec3,
    /// Unit normal from J into I.
    pub normal: Vec3,
    /// Penetration, > 0.
    pub depth: f64,
    /// The manifold it came from: points of one manifold are one region.
    pub manifold: usize,
    /// The triangle of I's mesh it lies on (`None` when I is not a mesh).
    pub triangle_i: Option<u32>,
    /// The triangle of J's mesh it lies on.
    pub triangle_j: Option<u32>,
}

/// Groups `touches` into connected regions and appends one incident per region to
/// `out`. Two touches are one region when they share a manifold or lie on triangles of
/// one mesh that share a vertex (`mesh_i`, `mesh_j`: the welded triangles of each
/// side, empty for a convex solid; for a mesh in convex pieces, each piece's links,
/// shared by neighbouring pieces) — so a U-shaped mesh standing on a box on both legs
/// gives two incidents, and a ball on the shared edge of two triangles one.
pub fn incidents<A: AsRef<[u32]>, B: AsRef<[u32]>>(
    touches: &[Touch],
    mesh_i: &[A],
    mesh_j: &[B],
    out: &mut Vec<Incident>,
) {
    if touches.is_empty() {
        return;
    }
    let mut sets = Sets::new(touches.len());
    let mut first_of_manifold: HashMap<usize, usize> = HashMap::new();
    // (side, welded vertex) → the first touch on a triangle using it.
    let mut first_at_vertex: HashMap<(u8, u32), usize> = HashMap::new();
    for (k, t) in touches.iter().enumerate() {
        let first = *first_of_manifold.entry(t.manifold).or_insert(k);
        sets.join(first, k);
        let sides = [
            (
                0u8,
                t.triangle_i
                    .and_then(|i| mesh_i.get(i as usize))
                    .map(AsRef::as_ref),
            ),
            (
                1,
                t.triangle_j
                    .and_then(|i| mesh_j.get(i as usize))
                    .map(AsRef::as_ref),
            ),
        ];
        for (side, keys) in sides {
            let Some(keys) = keys else {
                continue;
            };
            for &v in keys {
                let first = *first_at_vertex.entry((side, v)).or_insert(k);
                sets.join(first, k);
            }
        }
    }
    let mut region_of_root: HashMap<usize, usize> = HashMap::new();
    let mut regions: Vec<Region> = Vec::new();
    for (k, t) in touches.iter().enumerate() {
        let root = sets.root(k);
        let r = *region_of_root.entry(root).or_insert_with(|| {
            regions.push(Region::default());
            regions.len() - 1
        });
        regions[r].add(t);
    }
    out.extend(regions.iter().map(Region::incident));
}

/// The touches of one region.
#[derive(Default)]
struct Region {
    points: Vec<Vec3>,
    /// Σ point·depth and Σ depth: the depth-weighted mean point.
    weighted: Vec3,
    depth_sum: f64,
    normal_sum: Vec3,
    deepest: Option<Touch>,
}

impl Region {
    fn add(&mut self, t: &Touch) {
        self.points.push(t.point);
        self.weighted += t.point * t.depth;
        self.depth_sum += t.depth;
        self.normal_sum += t.normal * t.depth;
        if self.deepest.is_none_or(|d| t.depth > d.depth) {
            self.deepest = Some(*t);
        }
    }

    fn incident(&self) -> Incident {
        let deepest = self.deepest.expect("a region holds a touch");
        let n = self.normal_sum.norm();
        // Opposed normals cancel only in a region pinched from both sides; the deepest
        // point's normal is then the one to trust.
        let normal = if n > 1e-9 * deepest.depth.max(f64::MIN_POSITIVE) {
            self.normal_sum / n
        } else {
            deepest.normal
        };
        // A patch tilted against its solid is deeper on one side, as the intersection's
        // volume is: the point moves that way by the depth-weighted mean's offset from
        // the plain mean (zero on a level patch), so a block tilting on a face meets a
        // restoring moment at once rather than when a corner lifts.
        let mean = self.points.iter().sum::<Vec3>() / self.points.len() as f64;
        let tilt = match self.depth_sum > 0.0 {
            true => self.weighted / self.depth_sum - mean,
            false => Vec3::zeros(),
        };
        Incident {
            depth: deepest.depth,
            normal,
            point: area_centroid(&self.points, normal) + tilt,
        }
    }
}

/// The centroid of the polygon the points span seen along `normal` (the area
/// centroid of their convex hull in the plane normal to it; the middle of their extent
/// when they lie on a line; their mean height along the normal). The narrow phase
/// gives the corners of the contact patch and, inside it, its deepest point: the
/// hull drops the inner point, which a plain mean of the points would weigh.
pub fn area_centroid(points: &[Vec3], normal: Vec3) -> Vec3 {
    let n = points.len();
    let mean = points.iter().sum::<Vec3>() / n.max(1) as f64;
    if n < 3 {
        return mean;
    }
    let u = normal.cross(&if normal.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    });
    let u = u.normalize();
    let v = normal.cross(&u);
    let flat: Vec<[f64; 2]> = points
        .iter()
        .map(|p| [(p - mean).dot(&u), (p - mean).dot(&v)])
        .collect();
    let reach = flat.iter().map(|q| q[0].hypot(q[1])).fold(0.0, f64::max);
    if reach == 0.0 || !reach.is_finite() {
        return mean;
    }
    let hull = hull(&flat);
    let (mut area2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..hull.len() {
        let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
        let cross = a[0] * b[1] - b[0] * a[1];
        area2 += cross;
        cx += (a[0] + b[0]) * cross;
        cy += (a[1] + b[1]) * cross;
    }
    let [x, y] = if area2.abs() > 1e-9 * reach * reach {
        [cx / (3.0 * area2), cy / (3.0 * area2)]
    } else {
        // On a line: the middle of the extent along it.
        let far = flat
            .iter()
            .copied()
            .max_by(|a, b| a[0].hypot(a[1]).total_cmp(&b[0].hypot(b[1])))
            .unwrap_or([1.0, 0.0]);
        let d = [far[0] / reach, far[1] / reach];
        let t = flat.iter().map(|q| q[0] * d[0] + q[1] * d[1]);
        let (lo, hi) = t.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), t| {
            (l.min(t), h.max(t))
        });
        let mid = (lo + hi) / 2.0;
        [mid * d[0], mid * d[1]]
    };
    mean + u * x + v * y
}

/// The convex hull of plane points, counter-clockwise (Andrew's monotone chain).
fn hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut p = points.to_vec();
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let turn = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(2 * p.len());
    for pass in [p.clone(), p.into_iter().rev().collect()] {
        let start = out.len();
        for q in pass {
            while out.len() >= start + 2 && turn(out[out.len() - 2], out[out.len() - 1], q) <= 0.0 {
                out.pop();
            }
            out.push(q);
        }
        out.pop();
    }
    out
}

/// Disjoint sets over `0..n` (union by size, path halving).
struct Sets {
    parent: Vec<usize>,
    size: Vec<usize>,
}

impl Sets {
    fn new(n: usize) -> Self {
        Sets {
            parent: (0..n).collect(),
            size: vec![1; n],
        }
    }

    fn root(&mut self, mut k: usize) -> usize {
        while self.parent[k] != k {
            self.parent[k] = self.parent[self.parent[k]];
            k = self.parent[k];
        }
        k
    }

    fn join(&mut self, a: usize, b: usize) {
        let (mut a, mut b) = (self.root(a), self.root(b));
        if a == b {
            return;
        }
        if self.size[a] < self.size[b] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b] = a;
        self.size[a] += self.size[b];
    }
}
