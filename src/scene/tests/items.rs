//! Which items a dataset gets: OUTLINE rigid on one part and stretching across two,
//! SPDP stretching from I to J, FORCE arrows, CURVE's note, EXTERNAL placeholders sized
//! by the part's inertia (and their one note), glyphs for parts with nothing to draw
//! and with `--glyphs`, and the extent.

use super::{item, names, scene_of, v};
use crate::scene::{Anchor, ArrowSource, Motion, Options, Role, Topology};
use crate::vocab::math::Vec3;

/// Ground, a moving part 2 with two markers, a moving part 3 with one, a joint.
const BODIES: &str = "PART/1, GROUND\nMARKER/11, PART = 1\nMARKER/12, PART = 1, QP = 4, 0, 0\n\
PART/2, MASS = 12, CM = 21, IP = 1, 1, 1, QG = 0, 1, 0\nMARKER/21, PART = 2\nMARKER/22, PART = 2, QP = 1, 0, 0\n\
PART/3, MASS = 1, CM = 31, IP = 1, 1, 1\nMARKER/31, PART = 3, QP = 2, 0, 0\n\
JOINT/1, REVOLUTE, I = 21, J = 11\nSFORCE/4, I = 22, J = 12, FUNCTION = 1";

#[test]
fn an_outline_is_rigid_on_one_part_and_stretches_across_two() {
    let s = scene_of(
        &format!("{BODIES}\nGRAPHICS/5, OUTLINE = 11, 12\nGRAPHICS/6, OUTLINE = 21, 22, 31"),
        &Options::default(),
    );
    let one = item(&s, "GRAPHICS/5");
    assert_eq!((one.part, &one.motion), (0, &Motion::Rigid));
    assert_eq!(s.meshes[one.mesh].topology, Topology::Lines);
    let on_2 = item(&s, "GRAPHICS/6 on PART/2");
    let m = &s.meshes[on_2.mesh];
    let seg: Vec<Vec3> = m
        .indices
        .iter()
        .map(|&i| v(m.positions[i as usize]))
        .collect();
    assert_eq!(seg, [Vec3::zeros(), Vec3::x()]);
    let across = item(&s, "GRAPHICS/6 segment 2 (MARKER/22 to MARKER/31)");
    assert_eq!(
        across.motion,
        Motion::Stretch {
            from: Anchor {
                part: 1,
                point: [1.0, 0.0, 0.0]
            },
            to: Anchor {
                part: 2,
                point: [2.0, 0.0, 0.0]
            },
        }
    );
    let unit: Vec<Vec3> = s.meshes[across.mesh]
        .positions
        .iter()
        .map(|p| v(*p))
        .collect();
    assert_eq!(unit, [Vec3::zeros(), Vec3::z()]);
}

#[test]
fn a_spring_damper_stretches_from_i_to_j() {
    // I at (0,1,0) on part 2, J at (4,0,0) on ground: the input length is √17.
    let s = scene_of(
        &format!("{BODIES}\nGRAPHICS/5, SPDP, I = 21, J = 12, COILS = 5, DA = 0.5, DB = 0.3, DC = 0.2, LC = 1, LD = 2"),
        &Options::default(),
    );
    let spring = item(&s, "GRAPHICS/5");
    let want = Motion::Stretch {
        from: Anchor {
            part: 1,
            point: [0.0; 3],
        },
        to: Anchor {
            part: 0,
            point: [4.0, 0.0, 0.0],
        },
    };
    assert_eq!(spring.motion, want);
    let helix = &s.meshes[spring.mesh];
    assert_eq!(helix.topology, Topology::LineStrip);
    for p in &helix.positions {
        assert!((v(*p).xy().norm() - 0.25).abs() < 1e-6);
    }
    let turns = (helix.positions.windows(2))
        .map(|w| {
            let (a, b) = (v(w[0]), v(w[1]));
            (b.y.atan2(b.x) - a.y.atan2(a.x)).rem_euclid(std::f64::consts::TAU)
        })
        .sum::<f64>()
        / std::f64::consts::TAU;
    assert!((turns - 5.0).abs() < 1e-4, "{turns}");
    let damper = item(&s, "GRAPHICS/5 damper");
    assert_eq!(damper.motion, want);
    // Radii DB/2 and DC/2; heights LC, LD as fractions of √17 from each end.
    let l = 17f64.sqrt();
    let m = &s.meshes[damper.mesh];
    for p in &m.positions {
        let p = v(*p);
        let at_i = p.z <= 1.0 / l + 1e-6;
        let r = p.xy().norm();
        let radius = if at_i { 0.15 } else { 0.1 };
        assert!(r < 1e-6 || (r - radius).abs() < 1e-6, "{p}");
        assert!(at_i || p.z >= 1.0 - 2.0 / l - 1e-6, "{p}");
    }
}

#[test]
fn a_force_is_an_arrow_at_its_marker_and_a_curve_a_note() {
    let s = scene_of(
        &format!("{BODIES}\nGRAPHICS/5, FORCE, ETYPE = SFORCE, EID = 4, EMARKER = 22\nCURVE/7, MATRIX = 1\nGRAPHICS/6, CURVE, CID = 7, CRM = 11"),
        &Options::default(),
    );
    let arrow = item(&s, "GRAPHICS/5");
    assert_eq!(arrow.role, Role::Arrow);
    assert_eq!(
        arrow.motion,
        Motion::Arrow {
            at: Anchor {
                part: 1,
                point: [1.0, 0.0, 0.0]
            },
            arrow: 0
        }
    );
    assert_eq!(
        s.arrows,
        [ArrowSource {
            etype: "SFORCE",
            eid: 4,
            emarker: 22
        }]
    );
    // Unit length along +z.
    let zs = s.meshes[arrow.mesh].positions.iter().map(|p| p[2]);
    let (lo, hi) = zs.fold((f32::MAX, f32::MIN), |(a, b), z| (a.min(z), b.max(z)));
    assert_eq!((lo, hi), (0.0, 1.0));
    assert!(!s.items.iter().any(|i| i.name.starts_with("GRAPHICS/6")));
    assert!(s.notes.iter().any(|n| n
        == "GRAPHICS/6 not drawn: mbfx does not read CURVE data (CURVE statements are ignored)"));
    // Part 2's only graphic is an arrow: it gets glyphs all the same.
    item(&s, "glyph PART/2 inertia");
}

#[test]
fn an_external_without_geometry_is_its_parts_inertia_box_said_once() {
    // Part 2: a uniform box 1 × 2 × 3 of mass 12: Ixx = m(b² + c²)/12 = 13, Iyy = 10,
    // Izz = 5. Part 3 has no mass: a cube of side extent/20.
    let s = scene_of(
        &format!(
            "{BODIES}\nPART/4, QG = 9, 9, 9\nMARKER/41, PART = 4\n\
             GRAPHICS/5, EXTERNAL, RM = 22, FILE = a.x_t\nGRAPHICS/6, EXTERNAL, RM = 31, FILE = b.x_t\n\
             GRAPHICS/7, EXTERNAL, RM = 41, FILE = c.x_t"
        )
        .replace("IP = 1, 1, 1, QG = 0, 1, 0", "IP = 13, 10, 5, QG = 0, 1, 0"),
        &Options::default(),
    );
    let boxed = item(&s, "GRAPHICS/5");
    assert_eq!((boxed.role, boxed.part), (Role::Placeholder, 1));
    let m = &s.meshes[boxed.mesh];
    let mut spans: Vec<f64> = (0..3)
        .map(|k| {
            let vals = m.positions.iter().map(|p| f64::from(p[k]));
            vals.clone().fold(f64::MIN, f64::max) - vals.fold(f64::MAX, f64::min)
        })
        .collect();
    spans.sort_by(f64::total_cmp);
    for (got, want) in spans.iter().zip([1.0, 2.0, 3.0]) {
        assert!((got - want).abs() < 1e-5, "{spans:?}");
    }
    let cube = item(&s, "GRAPHICS/7");
    let side = s.meshes[cube.mesh]
        .positions
        .iter()
        .map(|p| p[0])
        .fold(f32::MIN, f32::max)
        * 2.0;
    assert_eq!(cube.role, Role::Placeholder);
    assert!(side > 0.0);
    let said: Vec<&String> = s
        .notes
        .iter()
        .filter(|n| n.contains("placeholder"))
        .collect();
    assert_eq!(
        said,
        ["3 EXTERNAL graphics drawn as placeholder boxes: no --geometry given for them"]
    );
    // Parts with a placeholder get no glyph; the ground triad is there for none.
    assert!(
        !s.items.iter().any(|i| i.role == Role::Glyph),
        "{:#?}",
        names(&s)
    );
}

#[test]
fn glyphs_go_to_parts_with_nothing_drawn_and_to_all_with_the_option() {
    let body = format!(
        "{BODIES}\nGRAPHICS/5, CYLINDER, CM = 21, LENGTH = 1, RADIUS = 0.1\n\
         JOINT/2, SPHERICAL, I = 31, J = 12"
    );
    let s = scene_of(&body, &Options::default());
    let glyphs: Vec<String> = (s.items.iter())
        .filter(|i| i.role == Role::Glyph)
        .map(|i| i.name.clone())
        .collect();
    assert_eq!(
        glyphs,
        [
            "glyph PART/3 links",
            "glyph PART/3 inertia",
            "glyph spherical at MARKER/31",
            "glyph ground triad x",
            "glyph ground triad y",
            "glyph ground triad z",
        ]
    );
    let triad = item(&s, "glyph ground triad y");
    assert_eq!(s.meshes[triad.mesh].color, crate::scene::colors::AXES[1]);
    let all = scene_of(
        &body,
        &Options {
            glyphs: true,
            ..Options::default()
        },
    );
    for name in [
        "glyph PART/2 inertia",
        "glyph PART/2 links",
        "glyph PART/3 inertia",
    ] {
        item(&all, name);
    }
    let links = item(&all, "glyph PART/2 links");
    let m = &all.meshes[links.mesh];
    let ends: Vec<Vec3> = m
        .indices
        .iter()
        .map(|&i| v(m.positions[i as usize]))
        .collect();
    assert_eq!(
        ends,
        [Vec3::zeros(), Vec3::zeros()],
        "CM 21 to the joint's I marker 21"
    );
}

#[test]
fn the_extent_is_the_diagonal_of_what_is_drawn() {
    let s = scene_of(
        "PART/1, GROUND\nMARKER/11, PART = 1, QP = 5, 5, 5\nGRAPHICS/5, BOX, CORNER = 11, X = 1, Y = 2, Z = -2",
        &Options::default(),
    );
    assert_eq!(s.items.len(), 1);
    assert!((s.extent - 3.0).abs() < 1e-9, "{}", s.extent);
    let empty = scene_of("PART/1, GROUND", &Options::default());
    assert_eq!(empty.extent, 1.0);
}
