//! Each solid against its geometry: a cylinder's vertices at RADIUS and its enclosed
//! volume against the inscribed prism's and πr²L, a sector's against its area, an
//! ellipsoid's against 4/3·πabc, a box's span, outward unit normals, and the inertia
//! ellipsoid of a uniform solid ellipsoid part against its semi-axes.

use super::{assert_normals_agree, item, scene_of, triangles, v, volume};
use crate::scene::build::apply;
use crate::scene::{Motion, Options, Role};
use crate::vocab::math::Vec3;
use std::f64::consts::PI;

/// Ground with a marker turned and moved, so local frames are tested too.
const GROUND: &str = "PART/1, GROUND\nMARKER/11, PART = 1, QP = 1, 2, 3, REULER = 30D, 20D, 10D";

fn shape(graphic: &str) -> (crate::scene::Scene, crate::scene::Mesh) {
    let s = scene_of(&format!("{GROUND}\n{graphic}"), &Options::default());
    let it = item(&s, "GRAPHICS/5").clone();
    assert_eq!(it.role, Role::Graphic);
    assert_eq!(it.motion, Motion::Rigid);
    // The item sits at the marker's pose in the BCS (ground's BCS is global).
    let want = Vec3::new(1.0, 2.0, 3.0);
    assert!((Vec3::from(it.local.translation) - want).norm() < 1e-12);
    let m = s.meshes[it.mesh].clone();
    (s, m)
}

#[test]
fn a_cylinders_vertices_lie_at_its_radius_and_its_volume_is_the_prisms() {
    for (length, sides) in [(2.0, 20), (-0.6, 3), (5.0, 256)] {
        let (_, m) = shape(&format!(
            "GRAPHICS/5, CYLINDER, CM = 11, LENGTH = {length}, RADIUS = 0.5, SIDES = {sides}"
        ));
        for p in &m.positions {
            let p = v(*p);
            let r = p.xy().norm();
            assert!(r.abs() < 1e-6 || (r - 0.5).abs() < 1e-6, "radius {r}");
            assert!(p.z.abs() < 1e-6 || (p.z - length).abs() < 1e-6, "z {}", p.z);
        }
        assert_normals_agree(&m);
        // The inscribed regular prism: n triangles of area r² sin(2π/n)/2, times |L|.
        let n = f64::from(sides);
        let prism = n / 2.0 * 0.25 * (2.0 * PI / n).sin() * length.abs();
        let vol = volume(&m);
        assert!((vol - prism).abs() < 1e-5 * prism, "{vol} vs {prism}");
        // πr²L within the facet error 1 − sin(2π/n)/(2π/n).
        let exact = PI * 0.25 * length.abs();
        assert!(exact - vol <= exact * (1.0 - (2.0 * PI / n).sin() / (2.0 * PI / n)) + 1e-6);
    }
}

#[test]
fn a_swept_cylinder_is_a_closed_sector() {
    // RANGLE = 270D: a non-convex sector of 12 sides; its area is 12 triangles of
    // r² sin(Δ)/2 with Δ = 270°/12.
    let (_, m) =
        shape("GRAPHICS/5, CYLINDER, CM = 11, LENGTH = 1, RADIUS = 2, SIDES = 12, RANGLE = 270D");
    assert_normals_agree(&m);
    let delta = 1.5 * PI / 12.0;
    let want = 12.0 / 2.0 * 4.0 * delta.sin();
    assert!(
        (volume(&m) - want).abs() < 1e-5 * want,
        "{} vs {want}",
        volume(&m)
    );
    // Every vertex within the sweep: angles in [0, 270°].
    for p in &m.positions {
        let a = f64::from(p[1]).atan2(f64::from(p[0])).rem_euclid(2.0 * PI);
        assert!(
            a <= 1.5 * PI + 1e-5 || v(*p).xy().norm() < 1e-6,
            "angle {a}"
        );
    }
}

#[test]
fn a_frustums_volume_is_the_truncated_pyramids() {
    let (_, m) =
        shape("GRAPHICS/5, FRUSTUM, CM = 11, LENGTH = -3, TOP = 1, BOTTOM = 2, SIDES = 64");
    assert_normals_agree(&m);
    // V = h/3 (A₁ + A₂ + √(A₁A₂)) with the inscribed polygons' areas.
    let poly = |r: f64| 64.0 / 2.0 * r * r * (2.0 * PI / 64.0).sin();
    let (a1, a2) = (poly(2.0), poly(1.0));
    let want = 3.0 / 3.0 * (a1 + a2 + (a1 * a2).sqrt());
    assert!((volume(&m) - want).abs() < 1e-5 * want);
    let top = m.positions.iter().map(|p| p[2]).fold(f32::MAX, f32::min);
    assert!((top + 3.0).abs() < 1e-6, "negative LENGTH goes along -z");
}

#[test]
fn an_ellipsoids_scales_are_its_diameters() {
    let (_, m) = shape("GRAPHICS/5, ELLIPSOID, CM = 11, XSCALE = 6, YSCALE = 4, ZSCALE = 2");
    assert_normals_agree(&m);
    let exact = 4.0 / 3.0 * PI * 3.0 * 2.0 * 1.0;
    let vol = volume(&m);
    // Inscribed: a little less, within 3 % at 32 × 16 facets.
    assert!(vol < exact && vol > 0.97 * exact, "{vol} vs {exact}");
    for (k, semi) in [3.0, 2.0, 1.0].iter().enumerate() {
        let reach = m.positions.iter().map(|p| p[k].abs()).fold(0.0, f32::max);
        assert!((f64::from(reach) - semi).abs() < 1e-5, "axis {k}: {reach}");
    }
    // On the surface: x²/a² + y²/b² + z²/c² = 1.
    for p in &m.positions {
        let p = v(*p);
        let f = (p.x / 3.0).powi(2) + (p.y / 2.0).powi(2) + p.z.powi(2);
        assert!((f - 1.0).abs() < 1e-5);
    }
}

#[test]
fn a_box_spans_its_corner_and_extents_with_outward_normals() {
    let (_, m) = shape("GRAPHICS/5, BOX, CORNER = 11, X = 50, Y = -50, Z = 200");
    assert_normals_agree(&m);
    for (k, (lo, hi)) in [(0.0, 50.0), (-50.0, 0.0), (0.0, 200.0)].iter().enumerate() {
        let min = m.positions.iter().map(|p| p[k]).fold(f32::MAX, f32::min);
        let max = m.positions.iter().map(|p| p[k]).fold(f32::MIN, f32::max);
        assert_eq!((f64::from(min), f64::from(max)), (*lo, *hi), "axis {k}");
    }
    assert!((volume(&m) - 50.0 * 50.0 * 200.0).abs() < 1.0);
    // Outward: each face's normal points away from the box's centre.
    let centre = Vec3::new(25.0, -25.0, 100.0);
    for [a, b, c] in triangles(&m) {
        let n = (b - a).cross(&(c - a));
        assert!(n.dot(&((a + b + c) / 3.0 - centre)) > 0.0);
    }
}

#[test]
fn bad_sizes_draw_nothing_with_a_note_and_huge_sides_are_clamped() {
    let s = scene_of(
        &format!(
            "{GROUND}\nGRAPHICS/5, ELLIPSOID, CM = 11, XSCALE = 0, YSCALE = 1, ZSCALE = 1\n\
             GRAPHICS/6, CIRCLE, CM = 11, RADIUS = 0\n\
             GRAPHICS/7, CYLINDER, CM = 11, LENGTH = 1, RADIUS = 1, SIDES = 100000"
        ),
        &Options::default(),
    );
    let drawn: Vec<&str> = s.items.iter().map(|i| i.name.as_str()).collect();
    assert_eq!(drawn, ["GRAPHICS/7"]);
    assert!(s
        .notes
        .iter()
        .any(|n| n.starts_with("GRAPHICS/5 (ELLIPSOID) not drawn")));
    assert!(s
        .notes
        .iter()
        .any(|n| n.starts_with("GRAPHICS/6 (CIRCLE) not drawn")));
    // 256 sides at most: 256 mantle quads and two caps of 256 triangles.
    let m = &s.meshes[s.items[0].mesh];
    assert_eq!(m.indices.len(), 3 * (2 * 256 + 2 * 256));
}

#[test]
fn the_glyph_of_a_uniform_ellipsoid_part_gives_back_its_semi_axes() {
    // A solid ellipsoid of mass 2 and semi-axes 3, 2, 1 along its CM marker's x, y, z,
    // the marker turned: Ixx = m(b² + c²)/5 = 2, Iyy = m(a² + c²)/5 = 4, Izz = 5.2.
    let s = scene_of(
        "PART/1, GROUND\nPART/2, MASS = 2, CM = 21, IP = 2, 4, 5.2, QG = 1, 1, 1\n\
         MARKER/21, PART = 2, QP = 0.5, 0, 0, REULER = 40D, 30D, 20D",
        &Options::default(),
    );
    let it = item(&s, "glyph PART/2 inertia");
    assert_eq!(it.role, Role::Glyph);
    let m = &s.meshes[it.mesh];
    assert_normals_agree(m);
    let part = &s.parts[it.part].input;
    let cm = apply(part, Vec3::new(0.5, 0.0, 0.0));
    let world: Vec<Vec3> = (m.positions.iter())
        .map(|p| apply(part, apply(&it.local, v(*p))))
        .collect();
    let far = world.iter().map(|p| (p - cm).norm()).fold(0.0, f64::max);
    let near = world
        .iter()
        .map(|p| (p - cm).norm())
        .fold(f64::MAX, f64::min);
    assert!(
        (far - 3.0).abs() < 1e-5 && (near - 1.0).abs() < 1e-5,
        "{far} {near}"
    );
    // The farthest point lies along the CM marker's x axis (global: R_part · R_marker x).
    let marker_x = {
        let read = crate::model::read_model(
            "t\nPART/1, GROUND\nMARKER/21, PART = 1, REULER = 40D, 30D, 20D\nEND\n",
        );
        read.model
            .marker_pose(21)
            .expect("marker")
            .1
            .column(0)
            .into_owned()
    };
    let tip = world
        .iter()
        .max_by(|a, b| (*a - cm).norm().total_cmp(&(*b - cm).norm()));
    let along = (tip.expect("vertices") - cm)
        .normalize()
        .dot(&marker_x)
        .abs();
    assert!((along - 1.0).abs() < 1e-6, "{along}");
}

#[test]
fn a_cylinder_of_no_length_is_a_disc() {
    // The FAST certification datasets draw tower sections so.
    let (_, m) = shape("GRAPHICS/5, CYLINDER, CM = 11, LENGTH = 0, RADIUS = 1, SIDES = 4");
    assert_normals_agree(&m);
    // Two faces of 4 triangles, one facing +z, one −z, each of area 2 (the square).
    let tris = triangles(&m);
    assert_eq!(tris.len(), 8);
    let area = |dir: f64| -> f64 {
        (tris.iter())
            .map(|[a, b, c]| (b - a).cross(&(c - a)) / 2.0)
            .filter(|n| n.z * dir > 0.0)
            .map(|n| n.norm())
            .sum()
    };
    assert!((area(1.0) - 2.0).abs() < 1e-6 && (area(-1.0) - 2.0).abs() < 1e-6);
}

#[test]
fn a_circle_by_rm_takes_the_distance_from_cms_z_axis_and_an_arc_sweeps_rangle() {
    // CM at (1,2,3) with z turned by REULER; RM on another part, placed 3 along CM's x
    // and 4 along CM's z: 3 from the axis (the 4 along it does not count).
    let read = crate::model::read_model(&format!("t\n{GROUND}\nEND\n"));
    let (o, axes) = read.model.marker_pose(11).expect("marker 11");
    let rm = o + axes.column(0) * 3.0 + axes.column(2) * 4.0;
    let s = scene_of(
        &format!(
            "{GROUND}\nPART/2, MASS = 1, CM = 21, IP = 1, 1, 1\nMARKER/21, PART = 2, QP = {}, {}, {}\n\
             GRAPHICS/5, CIRCLE, CM = 11, RM = 21, SEG = 8\n\
             GRAPHICS/6, ARC, CM = 11, RADIUS = 2, RANGLE = 90D, SEG = 6",
            rm.x, rm.y, rm.z
        ),
        &Options::default(),
    );
    let circle = &s.meshes[item(&s, "GRAPHICS/5").mesh];
    assert_eq!(
        (circle.topology, circle.positions.len()),
        (crate::scene::Topology::LineLoop, 8)
    );
    for p in &circle.positions {
        let p = v(*p);
        assert!((p.xy().norm() - 3.0).abs() < 1e-5 && p.z == 0.0, "{p}");
    }
    let arc = &s.meshes[item(&s, "GRAPHICS/6").mesh];
    assert_eq!(
        (arc.topology, arc.positions.len()),
        (crate::scene::Topology::LineStrip, 7)
    );
    let first = v(arc.positions[0]);
    let last = v(arc.positions[6]);
    assert!((first - Vec3::new(2.0, 0.0, 0.0)).norm() < 1e-6, "{first}");
    assert!((last - Vec3::new(0.0, 2.0, 0.0)).norm() < 1e-6, "{last}");
}

#[test]
fn a_plane_is_its_rectangle_seen_from_both_sides() {
    let (_, m) = shape("GRAPHICS/5, PLANE, RM = 11, XMIN = -1, XMAX = 3, YMIN = 0.5, YMAX = 2");
    assert_normals_agree(&m);
    for p in &m.positions {
        let p = v(*p);
        assert!(p.z.abs() < 1e-12, "z {}", p.z);
        assert!(
            (-1.0..=3.0).contains(&p.x) && (0.5..=2.0).contains(&p.y),
            "{p}"
        );
    }
    // Each face covers the 4 × 1.5 rectangle once: its triangles' areas, signed by
    // which way they face, add up to the area up (+z) and down (−z).
    let (mut up, mut down) = (0.0, 0.0);
    for [a, b, c] in triangles(&m) {
        let z = (b - a).cross(&(c - a)).z / 2.0;
        if z > 0.0 {
            up += z;
        } else {
            down -= z;
        }
    }
    assert!(
        (up - 6.0).abs() < 1e-9 && (down - 6.0).abs() < 1e-9,
        "{up} {down}"
    );
}
