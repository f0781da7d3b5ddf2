//! The mesh builder every shape uses: triangles whose winding is made to agree with the
//! outward normal they are given (so a negative LENGTH or a negative BOX extent needs no
//! special case), lines, and the clamps that keep bad values from making a mesh.

use super::{Mesh, Topology};
use crate::vocab::math::Vec3;

/// The fewest and the most facets a round shape is cut into: below 3 there is no
/// polygon, and a huge SIDES must not exhaust memory.
pub const FACETS: std::ops::RangeInclusive<u32> = 3..=256;

/// A facet count: `asked` (SIDES, SEG) when given and finite, else `default`, clamped
/// to [`FACETS`].
pub fn facets(asked: Option<u32>, default: u32) -> u32 {
    asked
        .unwrap_or(default)
        .clamp(*FACETS.start(), *FACETS.end())
}

/// Whether `x` is positive and finite (false for NaN).
pub fn positive(x: f64) -> bool {
    x > 0.0 && x.is_finite()
}

/// Whether every value is finite.
pub fn finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

/// Triangles (with one unit normal per vertex) or lines, grown face by face.
#[derive(Default)]
pub struct Builder {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    indices: Vec<u32>,
}

fn f32s(v: Vec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

impl Builder {
    /// A flat convex polygon (corners in order, either way round) facing `outward`:
    /// fanned into triangles that share its unit normal. A polygon of no area, or one
    /// with a non-finite corner, is left out.
    pub fn flat(&mut self, corners: &[Vec3], outward: Vec3) {
        let n = outward.normalize();
        if corners.len() < 3 || !n.iter().all(|c| c.is_finite()) {
            return;
        }
        for k in 1..corners.len() - 1 {
            self.triangle([corners[0], corners[k], corners[k + 1]], [n; 3]);
        }
    }

    /// One triangle with a unit normal per corner (a smooth surface's): wound so that
    /// its face normal agrees with their mean. Degenerate ones are left out.
    pub fn triangle(&mut self, mut p: [Vec3; 3], mut n: [Vec3; 3]) {
        let face = (p[1] - p[0]).cross(&(p[2] - p[0]));
        let mean = n[0] + n[1] + n[2];
        let area2 = face.norm();
        if !positive(area2) || !mean.iter().all(|c| c.is_finite()) {
            return;
        }
        if face.dot(&mean) < 0.0 {
            p.swap(1, 2);
            n.swap(1, 2);
        }
        for (pk, nk) in p.iter().zip(n.iter()) {
            self.indices.push(self.positions.len() as u32);
            self.positions.push(f32s(*pk));
            self.normals.push(f32s(nk.normalize()));
        }
    }

    /// A line segment (for [`Builder::lines`]).
    pub fn segment(&mut self, a: Vec3, b: Vec3) {
        if !(finite(a.as_slice()) && finite(b.as_slice())) {
            return;
        }
        for p in [a, b] {
            self.indices.push(self.positions.len() as u32);
            self.positions.push(f32s(p));
        }
    }

    /// Adds `other`'s triangles or lines moved by `offset`.
    pub fn append(&mut self, other: Builder, offset: Vec3) {
        let base = self.positions.len() as u32;
        let d = f32s(offset);
        (self.positions).extend(
            other
                .positions
                .iter()
                .map(|p| [p[0] + d[0], p[1] + d[1], p[2] + d[2]]),
        );
        self.normals.extend(other.normals);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }

    /// Whether nothing was added.
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }

    /// The vertices with equal position and normal merged into one (the builder adds
    /// three per triangle): a smooth surface's vertices are shared by up to six
    /// triangles, a flat polygon's by its fan, so a file holds several times fewer.
    fn welded(self) -> Self {
        let mut index = std::collections::HashMap::new();
        let mut out = Builder::default();
        for &i in &self.indices {
            let p = self.positions[i as usize];
            let n = self.normals.get(i as usize).copied();
            let key = (p.map(f32::to_bits), n.map(|n| n.map(f32::to_bits)));
            let k = *index.entry(key).or_insert_with(|| {
                out.positions.push(p);
                out.normals.extend(n);
                out.positions.len() as u32 - 1
            });
            out.indices.push(k);
        }
        out
    }

    /// The triangles as a mesh.
    pub fn triangles(self, color: [f32; 4]) -> Mesh {
        let welded = self.welded();
        Mesh {
            positions: welded.positions,
            normals: welded.normals,
            indices: welded.indices,
            topology: Topology::Triangles,
            color,
        }
    }

    /// The segments as a mesh of lines.
    pub fn lines(self, color: [f32; 4]) -> Mesh {
        let welded = self.welded();
        Mesh {
            positions: welded.positions,
            normals: Vec::new(),
            indices: welded.indices,
            topology: Topology::Lines,
            color,
        }
    }
}

/// A polyline through `points` (closed: a line loop), or `None` when a point is not
/// finite or there are fewer than two.
pub fn polyline(points: &[Vec3], closed: bool, color: [f32; 4]) -> Option<Mesh> {
    if points.len() < 2 || !points.iter().all(|p| finite(p.as_slice())) {
        return None;
    }
    Some(Mesh {
        positions: points.iter().map(|p| f32s(*p)).collect(),
        normals: Vec::new(),
        indices: (0..points.len() as u32).collect(),
        topology: if closed {
            Topology::LineLoop
        } else {
            Topology::LineStrip
        },
        color,
    })
}
