//! How far a pair may move against each other in one step before it could pass through
//! unseen: the gap between their bounding boxes and their thicknesses at the last
//! [`World::update`]. The core bounds a step by it (continuous collision's conservative
//! bound), since onset is a switch seen only at the ends of a step: a step that carries a
//! ball clean through a floor shows it apart at both.

use super::World;
use crate::vocab::math::Vec3;
use parry3d_f64::bounding_volume::Aabb;

/// What a pair may travel in one step, and the arms its rotations turn through.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reach {
    /// The distance between the pair's bounding boxes (0 when they overlap).
    pub gap: f64,
    /// The sum of the two shapes' half-thicknesses (the half-width of each across its
    /// thinnest direction): moving the gap plus this much cannot carry one through the
    /// other.
    pub thickness: f64,
}

impl World {
    /// The pair's [`Reach`] at the last update; `None` for a pair that names no
    /// geometries or before the first update.
    pub fn reach(&self, pair: usize) -> Option<Reach> {
        let (i, j) = self.pair(pair)?;
        if !self.placed {
            return None;
        }
        Some(Reach {
            gap: box_gap(&self.boxes[i], &self.boxes[j]),
            thickness: self.half_thickness(i) + self.half_thickness(j),
        })
    }

    /// The pair's geometries (I's, J's), as [`World::arm`] takes them.
    pub fn pair_geometries(&self, pair: usize) -> Option<(usize, usize)> {
        self.pair(pair)
    }

    /// The farthest distance of geometry `g`'s bounding box from `point` (global): the
    /// arm through which the part's rotation moves it.
    pub fn arm(&self, g: usize, point: &Vec3) -> f64 {
        let Some(b) = self.boxes.get(g) else {
            return 0.0;
        };
        let (lo, hi) = (b.mins, b.maxs);
        let far = |k: usize| (point[k] - lo[k]).abs().max((hi[k] - point[k]).abs());
        Vec3::new(far(0), far(1), far(2)).norm()
    }

    /// parry's CCD thickness of the shape; for a mesh, which parry gives none, the
    /// thinnest half-width of its own bounding box (too thick for a thin wall lying
    /// across the box's diagonal: said in docs/contact.md).
    fn half_thickness(&self, g: usize) -> f64 {
        let shape = &self.geometries[g].shape;
        let t = shape.ccd_thickness();
        if t > 0.0 {
            t
        } else {
            shape.compute_local_aabb().half_extents().min_element()
        }
    }
}

/// The Euclidean distance between two boxes (0 when they overlap).
fn box_gap(a: &Aabb, b: &Aabb) -> f64 {
    let d = (a.mins - b.maxs)
        .max(b.mins - a.maxs)
        .max(parry3d_f64::math::Vector::ZERO);
    d.length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::math::Vector;

    #[test]
    fn the_gap_of_boxes_is_their_distance() {
        let a = Aabb::new(Vector::new(0.0, 0.0, 0.0), Vector::new(1.0, 1.0, 1.0));
        let b = Aabb::new(Vector::new(4.0, 5.0, 0.5), Vector::new(5.0, 6.0, 2.0));
        assert!((box_gap(&a, &b) - 5.0).abs() < 1e-15);
        assert_eq!(box_gap(&a, &a), 0.0);
    }
}
