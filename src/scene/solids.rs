//! The closed solids as triangle meshes in their marker's frame: BOX (a corner at the
//! origin), CYLINDER and FRUSTUM (bottom centre at the origin, axis along z, swept by
//! RANGLE), ELLIPSOID (centred, semi-axes along x, y, z), and PLANE's flat rectangle.
//! Flat faces carry their face normal, the ellipsoid its smooth surface normal; all
//! point outward.

use super::tessellate::Builder;
use crate::vocab::math::Vec3;
use std::f64::consts::TAU;

/// Facets of a cylinder or frustum when SIDES is not given (chosen, as Adams View's
/// default side count).
pub const DEFAULT_SIDES: u32 = 20;
/// Facets around an ellipsoid's z axis; it has half as many from pole to pole.
pub const ELLIPSOID_SLICES: u32 = 32;

/// The box spanning `[0, X] × [0, Y] × [0, Z]` (a negative extent spans `[X, 0]`).
pub fn cuboid(extent: [f64; 3]) -> Builder {
    let lo = Vec3::from_fn(|i, _| extent[i].min(0.0));
    let hi = Vec3::from_fn(|i, _| extent[i].max(0.0));
    centred_cuboid(lo, hi)
}

/// The box between corners `lo` and `hi` (componentwise `lo ≤ hi`).
pub fn centred_cuboid(lo: Vec3, hi: Vec3) -> Builder {
    let mut b = Builder::default();
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for (side, sign) in [(lo[axis], -1.0), (hi[axis], 1.0)] {
            let corner = |cu: f64, cv: f64| {
                let mut p = Vec3::zeros();
                p[axis] = side;
                p[u] = cu;
                p[v] = cv;
                p
            };
            let mut n = Vec3::zeros();
            n[axis] = sign;
            b.flat(
                &[
                    corner(lo[u], lo[v]),
                    corner(hi[u], lo[v]),
                    corner(hi[u], hi[v]),
                    corner(lo[u], hi[v]),
                ],
                n,
            );
        }
    }
    b
}

/// The flat rectangle between corners `lo` and `hi` of one z (a PLANE), its two faces
/// (+z and −z) so either side shows.
pub fn rectangle(lo: Vec3, hi: Vec3) -> Builder {
    let mut b = Builder::default();
    let corners = [
        lo,
        Vec3::new(hi.x, lo.y, lo.z),
        Vec3::new(hi.x, hi.y, lo.z),
        Vec3::new(lo.x, hi.y, lo.z),
    ];
    // `flat` winds each face to its normal: the same corners serve both.
    b.flat(&corners, Vec3::z());
    b.flat(&corners, -Vec3::z());
    b
}

/// A frustum from radius `bottom` at z = 0 to radius `top` at z = `length` (negative:
/// along −z), with `sides` flat sides over the angle `sweep` from +x about +z (a full
/// turn when `sweep` is 2π or more; a sector otherwise, closed by its two radial faces).
pub fn frustum(length: f64, bottom: f64, top: f64, sides: u32, sweep: f64) -> Builder {
    let sweep = if sweep > 0.0 { sweep.min(TAU) } else { TAU };
    let full = sweep >= TAU;
    let n = sides.max(1);
    let dir = |k: u32| {
        let a = sweep * f64::from(k) / f64::from(n);
        Vec3::new(a.cos(), a.sin(), 0.0)
    };
    let z = Vec3::z() * length;
    // Which way is out along the axis (LENGTH = 0: a disc, its faces up and down).
    let sign = if length < 0.0 { -1.0 } else { 1.0 };
    let mut b = Builder::default();
    let (mut bottom_cap, mut top_cap) = (vec![Vec3::zeros()], vec![z]);
    for k in 0..n {
        let (d0, d1) = (dir(k), dir(k + 1));
        let quad = [d0 * bottom, d1 * bottom, d1 * top + z, d0 * top + z];
        // The facet's plane holds its chord t and its slant s; t × s points out when
        // LENGTH > 0, so the sign of LENGTH turns it.
        let mid = (d0 + d1) / 2.0;
        let t = d1 - d0;
        let s = mid * (top - bottom) + z;
        b.flat(&quad, t.cross(&s) * sign);
        bottom_cap.push(d0 * bottom);
        top_cap.push(d0 * top + z);
    }
    bottom_cap.push(dir(n) * bottom);
    top_cap.push(dir(n) * top + z);
    let up = Vec3::z() * sign;
    b.flat(&bottom_cap, -up);
    b.flat(&top_cap, up);
    if !full {
        let face = |d: Vec3| [Vec3::zeros(), d * bottom, d * top + z, z];
        b.flat(&face(dir(0)), -Vec3::y());
        let end = dir(n);
        b.flat(&face(end), Vec3::new(-end.y, end.x, 0.0));
    }
    b
}

/// The ellipsoid centred at the origin with semi-axes `semi` along x, y, z, cut into
/// `slices` around z and `slices / 2` from pole to pole, with smooth normals.
pub fn ellipsoid(semi: [f64; 3], slices: u32) -> Builder {
    let [a, b, c] = semi;
    let stacks = (slices / 2).max(2);
    let at = |i: u32, j: u32| {
        let theta = TAU * f64::from(i) / f64::from(slices);
        let phi = std::f64::consts::PI * f64::from(j) / f64::from(stacks);
        let u = Vec3::new(phi.sin() * theta.cos(), phi.sin() * theta.sin(), phi.cos());
        // The gradient of x²/a² + y²/b² + z²/c² at (a·u.x, b·u.y, c·u.z).
        let normal = Vec3::new(u.x / a, u.y / b, u.z / c);
        (Vec3::new(a * u.x, b * u.y, c * u.z), normal)
    };
    let mut out = Builder::default();
    for j in 0..stacks {
        for i in 0..slices {
            let q = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
            for tri in [[0, 1, 2], [0, 2, 3]] {
                out.triangle(tri.map(|k| q[k].0), tri.map(|k| q[k].1));
            }
        }
    }
    out
}
