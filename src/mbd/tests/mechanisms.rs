//! Assembly of mechanisms with closed-form geometry, redundancy counts of
//! reference-problems §5, failures named the Adams way.

use super::*;
use crate::mbd::assembly::AssemblyOptions;
use crate::mbd::expr::Closure;
use crate::mbd::measure_set::Measure;
use crate::mbd::planar::Dim;
use crate::mbd::system::{Dimension, PartHandle, System};
use crate::mbd::AssemblyError;
use crate::vocab::elements::{ElementKind, ElementRef, JointType, JprimType};
use crate::vocab::math::{Mat3, Vec3};
use std::f64::consts::PI;

#[test]
fn pendulum_assembles_from_a_tilted_perturbed_pose() {
    let mut sys = System::new();
    let p = sys.add_part(Some(2), Vec3::new(1.1, 0.2, 0.05), rot(0.03, -0.02, 0.1));
    let i = sys.add_marker(Some(20), p, Vec3::new(-1.0, 0.0, 0.0), Mat3::identity());
    let j = ground_marker(&mut sys, Vec3::zeros(), Mat3::identity());
    rev(&mut sys, 1, i, j);
    sys.prepare(Dim::Auto);
    assert_eq!(sys.dim, Dimension::Three);
    assert!(
        sys.dim_reason.contains("no axis normal"),
        "{}",
        sys.dim_reason
    );
    let rep = sys.assemble(&AssemblyOptions::default()).unwrap();
    let part = sys.part(p);
    // The link of length 1 hangs from the pivot, in the z = 0 plane, axis along Z.
    assert!((part.r.norm() - 1.0).abs() < 1e-9);
    assert!(part.r.z.abs() < 1e-9);
    let z = part.rot * Vec3::z();
    assert!((z.z.abs() - 1.0).abs() < 1e-9);
    assert!(rep.residual < 1e-10 && rep.moves[0].translation > 0.05);
}

struct SliderCrank {
    sys: System,
    crank: PartHandle,
    slider: PartHandle,
}

const A: f64 = 0.3;
const B: f64 = 1.0;

fn slider_crank(dim: Dim) -> SliderCrank {
    let mut sys = System::new();
    let th = PI / 6.0 + 0.1;
    let crank = sys.add_part(Some(2), Vec3::new(0.01, -0.02, 0.0), rz(th));
    let tip = Vec3::new(A * th.cos(), A * th.sin(), 0.0);
    let rod = sys.add_part(Some(3), tip + Vec3::new(0.03, 0.02, 0.0), rz(-0.1));
    let slider = sys.add_part(Some(4), Vec3::new(1.3, 0.04, 0.0), Mat3::identity());
    let o = ground_marker(&mut sys, Vec3::zeros(), Mat3::identity());
    let c0 = sys.add_marker(Some(20), crank, Vec3::zeros(), Mat3::identity());
    let c1 = sys.add_marker(Some(21), crank, Vec3::new(A, 0.0, 0.0), Mat3::identity());
    let r0 = sys.add_marker(Some(30), rod, Vec3::zeros(), Mat3::identity());
    let r1 = sys.add_marker(Some(31), rod, Vec3::new(B, 0.0, 0.0), Mat3::identity());
    let s0 = sys.add_marker(Some(40), slider, Vec3::zeros(), Mat3::identity());
    // z_J along global X: the slider travels along X.
    let ry = rot(0.0, PI / 2.0, 0.0);
    let s1 = sys.add_marker(Some(41), slider, Vec3::zeros(), ry);
    let g1 = ground_marker(&mut sys, Vec3::zeros(), ry);
    rev(&mut sys, 1, c0, o);
    rev(&mut sys, 2, r0, c1);
    rev(&mut sys, 3, s0, r1);
    let t = ElementRef {
        kind: ElementKind::Joint(JointType::Translational),
        id: 4,
        name: None,
    };
    sys.joint(t, JointType::Translational, s1, g1, 0.0).unwrap();
    sys.motion(
        er(1),
        Measure::Angle {
            i: Some(c0),
            j: Some(o),
            axis: 2,
        },
        time_fn(PI / 6.0, 2.0),
    )
    .unwrap();
    sys.prepare(dim);
    SliderCrank { sys, crank, slider }
}

#[test]
fn slider_crank_positions_and_velocities_match_the_closed_form() {
    let (th, w) = (PI / 6.0, 2.0);
    let root = (B * B - A * A * th.sin().powi(2)).sqrt();
    let x = A * th.cos() + root;
    let xdot = -A * w * th.sin() - A * A * w * th.sin() * th.cos() / root;
    for dim in [Dim::Auto, Dim::Three] {
        let mut m = slider_crank(dim);
        let want = if dim == Dim::Auto {
            Dimension::Two
        } else {
            Dimension::Three
        };
        assert_eq!(m.sys.dim, want, "{}", m.sys.dim_reason);
        m.sys.assemble(&AssemblyOptions::default()).unwrap();
        let s = m.sys.part(m.slider);
        assert!(
            (s.r.x - x).abs() < 1e-9 && s.r.y.abs() < 1e-9,
            "{dim:?}: {}",
            s.r
        );
        assert!((s.v.x - xdot).abs() < 1e-8, "{dim:?}: {} vs {xdot}", s.v.x);
        let c = m.sys.part(m.crank);
        assert!(((c.rot * Vec3::x()).y.atan2((c.rot * Vec3::x()).x) - th).abs() < 1e-9);
        assert!((c.w.z - w).abs() < 1e-8);
    }
}

#[test]
fn slider_crank_redundancy_counts_in_3d_and_2d() {
    // 3D: 3 revolutes + 1 translational + MOTION = 21 rows on 18 columns, 0 DOF.
    let m = slider_crank(Dim::Three);
    let j = dense(&m.sys.jacobian(true).unwrap());
    assert_eq!((j.nrows(), j.ncols(), rank(&j)), (21, 18, 18));
    // 2D: 2 + 2 + 2 + 2 + 1 rows on 9 columns, none redundant.
    let m = slider_crank(Dim::Auto);
    let j = dense(&m.sys.jacobian(true).unwrap());
    assert_eq!((j.nrows(), j.ncols(), rank(&j)), (9, 9, 9));
}

/// Four-bar: ground pivots A = (0, 0) and D = (d, 0), crank a, coupler b, rocker c.
fn four_bar(d: f64, motion: Option<f64>, dim: Dim) -> (System, [PartHandle; 3]) {
    four_bar_in(Mat3::identity(), d, motion, dim)
}

/// [`four_bar`] turned as a whole by the rotation `g`.
fn four_bar_in(g: Mat3, d: f64, motion: Option<f64>, dim: Dim) -> (System, [PartHandle; 3]) {
    let (a, b, c) = (0.4, 1.0, 0.7);
    let th = 60f64.to_radians();
    let (bx, by) = (a * th.cos(), a * th.sin());
    let (cx, cy) = circle_intersection(bx, by, b, d, 0.0, c);
    // No intersection (an impossible four-bar): start from a guess.
    let (cx, cy) = if cx.is_finite() {
        (cx, cy)
    } else {
        (d / 2.0, 0.5)
    };
    let mut sys = System::new();
    let mut part = |id, at: Vec3, angle: f64| sys.add_part(Some(id), g * at, g * rz(angle));
    let crank = part(2, Vec3::new(0.02, -0.01, 0.0), th + 0.08);
    let coupler = part(
        3,
        Vec3::new(bx - 0.03, by + 0.04, 0.0),
        (cy - by).atan2(cx - bx) - 0.07,
    );
    let rocker = part(4, Vec3::new(d + 0.02, 0.03, 0.0), (cy).atan2(cx - d) + 0.06);
    let ga = ground_marker(&mut sys, Vec3::zeros(), g);
    let gd = ground_marker(&mut sys, g * Vec3::new(d, 0.0, 0.0), g);
    let k0 = sys.add_marker(None, crank, Vec3::zeros(), Mat3::identity());
    let k1 = sys.add_marker(None, crank, Vec3::new(a, 0.0, 0.0), Mat3::identity());
    let c0 = sys.add_marker(None, coupler, Vec3::zeros(), Mat3::identity());
    let c1 = sys.add_marker(None, coupler, Vec3::new(b, 0.0, 0.0), Mat3::identity());
    let r0 = sys.add_marker(None, rocker, Vec3::zeros(), Mat3::identity());
    let r1 = sys.add_marker(None, rocker, Vec3::new(c, 0.0, 0.0), Mat3::identity());
    rev(&mut sys, 1, k0, ga);
    rev(&mut sys, 2, c0, k1);
    rev(&mut sys, 3, r1, c1);
    rev(&mut sys, 4, r0, gd);
    if let Some(angle) = motion {
        sys.motion(
            er(1),
            Measure::Angle {
                i: Some(k0),
                j: Some(ga),
                axis: 2,
            },
            time_fn(angle, 0.0),
        )
        .unwrap();
    }
    sys.prepare(dim);
    (sys, [crank, coupler, rocker])
}

/// The intersection of circles (x1, y1, r1) and (x2, y2, r2) with the larger y.
fn circle_intersection(x1: f64, y1: f64, r1: f64, x2: f64, y2: f64, r2: f64) -> (f64, f64) {
    let (dx, dy) = (x2 - x1, y2 - y1);
    let d = (dx * dx + dy * dy).sqrt();
    let l = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
    let h = (r1 * r1 - l * l).sqrt();
    let (mx, my) = (x1 + l * dx / d, y1 + l * dy / d);
    let p = (mx - h * dy / d, my + h * dx / d);
    let q = (mx + h * dy / d, my - h * dx / d);
    if p.1 > q.1 {
        p
    } else {
        q
    }
}

#[test]
fn four_bar_assembles_onto_the_circle_intersection_in_2d_and_3d() {
    let th = 60f64.to_radians();
    let (bx, by) = (0.4 * th.cos(), 0.4 * th.sin());
    let (cx, cy) = circle_intersection(bx, by, 1.0, 1.0, 0.0, 0.7);
    let mut poses = Vec::new();
    for dim in [Dim::Auto, Dim::Three] {
        let (mut sys, [crank, coupler, rocker]) = four_bar(1.0, Some(th), dim);
        sys.assemble(&AssemblyOptions::default()).unwrap();
        let tip = |p: PartHandle, l: f64| sys.part(p).r + sys.part(p).rot * Vec3::new(l, 0.0, 0.0);
        let b = tip(crank, 0.4);
        assert!((b - Vec3::new(bx, by, 0.0)).norm() < 1e-9, "{dim:?} B {b}");
        assert!(
            (tip(coupler, 1.0) - Vec3::new(cx, cy, 0.0)).norm() < 1e-9,
            "{dim:?}"
        );
        assert!(
            (tip(rocker, 0.7) - Vec3::new(cx, cy, 0.0)).norm() < 1e-9,
            "{dim:?}"
        );
        poses.push([crank, coupler, rocker].map(|p| (sys.part(p).r, sys.part(p).rot)));
    }
    // The 3D build and the 2D build agree.
    for (a, b) in poses[0].iter().zip(&poses[1]) {
        assert!((a.0 - b.0).norm() < 1e-9);
        assert!(a.1.angle_to(&b.1) < 1e-9);
    }
}

#[test]
fn planar_four_bar_has_three_redundant_equations_in_3d_and_none_in_2d() {
    // reference-problems §5.1.
    let (sys, _) = four_bar(1.0, None, Dim::Three);
    let j = dense(&sys.jacobian(true).unwrap());
    assert_eq!(j.nrows() - rank(&j), 3);
    assert_eq!(j.ncols() - rank(&j), 1, "one DOF");
    let (sys, _) = four_bar(1.0, None, Dim::Auto);
    assert_eq!(sys.dim, Dimension::Two, "{}", sys.dim_reason);
    let j = dense(&sys.jacobian(true).unwrap());
    assert_eq!((j.nrows(), rank(&j), j.ncols()), (8, 8, 9));
}

#[test]
fn impossible_four_bar_names_the_violated_joints() {
    // Ground link 3 is longer than crank + coupler + rocker = 2.1.
    let (mut sys, _) = four_bar(3.0, None, Dim::Auto);
    match sys.assemble(&AssemblyOptions::default()) {
        Err(e @ AssemblyError::NotAssembled { .. }) => {
            let AssemblyError::NotAssembled { violated, .. } = &e else {
                unreachable!()
            };
            assert!(!violated.is_empty());
            let text = e.to_string();
            assert!(
                text.contains("JOINT/") && text.contains("(REVOLUTE)") && text.contains("Delta"),
                "{text}"
            );
        }
        other => panic!("expected a failure, got {other:?}"),
    }
}

#[test]
fn dropped_rows_are_left_out_and_checked_afterwards() {
    // Dropping the 3 redundant out-of-plane rows of the last revolute still assembles.
    let (mut sys, _) = four_bar(1.0, Some(1.0), Dim::Three);
    let labels = sys.labels();
    let last: Vec<usize> = (0..labels.len())
        .filter(|&r| {
            labels[r].element == 3
                && labels[r].equation != crate::mbd::equations::Equation::XDelta
                && labels[r].equation != crate::mbd::equations::Equation::YDelta
        })
        .collect();
    assert_eq!(last.len(), 3);
    let opts = AssemblyOptions {
        dropped: last,
        ..Default::default()
    };
    sys.assemble(&opts).unwrap();
    // Dropping an independent row that the input violates is a conflict.
    let (mut sys, _) = four_bar(1.0, Some(1.0), Dim::Three);
    let opts = AssemblyOptions {
        dropped: vec![0],
        ..Default::default()
    };
    assert!(matches!(
        sys.assemble(&opts),
        Err(AssemblyError::Conflicting { .. })
    ));
}

#[test]
fn gcon_distance_moves_the_point_radially() {
    // ORIENTATION + INPLANE hold a part's rotation and z; GCON DM(i, j) − 1.5 = 0 with a
    // hand-written gradient. The minimum-norm steps move the part along the radius.
    let mut sys = System::new();
    let p = sys.add_part(None, Vec3::new(1.0, 0.3, 0.0), Mat3::identity());
    let i = sys.add_marker(None, p, Vec3::zeros(), Mat3::identity());
    let j = ground_marker(&mut sys, Vec3::zeros(), Mat3::identity());
    sys.jprim(er(1), JprimType::Orientation, i, j).unwrap();
    sys.jprim(er(2), JprimType::Inplane, i, j).unwrap();
    let dm = sys.measures.add(Measure::Dist {
        i: Some(i),
        j: Some(j),
    });
    let f = Closure {
        slots: vec![0],
        f: |_: f64, m: &[f64]| m[0] - 1.5,
        g: |_: f64, _: &[f64], g: &mut [f64]| {
            g[0] = 1.0;
            0.0
        },
    };
    sys.gcon(er(1), Box::new(f), vec![dm]).unwrap();
    sys.prepare(Dim::Three);
    sys.assemble(&AssemblyOptions::default()).unwrap();
    let want = Vec3::new(1.0, 0.3, 0.0).normalize() * 1.5;
    let err = (sys.part(p).r - want).norm();
    assert!(
        err < 1e-9,
        "{:?} off by {err}, residual {}",
        sys.part(p).r,
        sys.residual().unwrap()
    );
}

#[test]
fn forced_3d_says_why() {
    let (sys, _) = four_bar(1.0, None, Dim::Three);
    assert_eq!(sys.dim, Dimension::Three);
    assert!(sys.dim_reason.contains("forced"));
}

#[test]
fn screw_travel_follows_the_pitch() {
    // CYLINDRICAL + SCREW (PITCH 0.2) + MOTION of the rotation to 1 rad: the travel
    // along z_J is PITCH·θ/2π.
    let mut sys = System::new();
    let p = sys.add_part(None, Vec3::new(0.02, -0.01, 0.3), rot(0.01, 0.02, 0.7));
    let i = sys.add_marker(None, p, Vec3::zeros(), Mat3::identity());
    let j = ground_marker(&mut sys, Vec3::zeros(), Mat3::identity());
    let cyl = ElementRef {
        kind: ElementKind::Gcon,
        id: 1,
        name: None,
    };
    sys.joint(cyl.clone(), JointType::Cylindrical, i, j, 0.0)
        .unwrap();
    sys.joint(cyl, JointType::Screw, i, j, 0.2).unwrap();
    let az = Measure::Angle {
        i: Some(i),
        j: Some(j),
        axis: 2,
    };
    sys.motion(er(1), az, time_fn(1.0, 0.5)).unwrap();
    sys.prepare(Dim::Auto);
    sys.assemble(&AssemblyOptions::default()).unwrap();
    let part = sys.part(p);
    assert!((part.r.z - 0.2 / (2.0 * PI)).abs() < 1e-10, "{}", part.r);
    assert!((part.r.x.abs() + part.r.y.abs()) < 1e-10);
    // Velocities: ω_z = 0.5, travel rate PITCH·ω/2π.
    assert!((part.w.z - 0.5).abs() < 1e-9 && (part.v.z - 0.1 / (2.0 * PI)).abs() < 1e-9);
}

#[test]
fn prismatic_2d_joint_slides_along_its_axis() {
    // Exudyn's 2D prismatic joint through the library API: the slider keeps its x (the
    // free coordinate, which the minimum-norm steps leave alone) and loses its y offset
    // and rotation.
    let mut sys = System::new();
    let p = sys.add_part(None, Vec3::new(0.7, 0.1, 0.0), rz(0.05));
    let i = sys.add_marker(None, p, Vec3::zeros(), Mat3::identity());
    let j = ground_marker(&mut sys, Vec3::zeros(), Mat3::identity());
    sys.prismatic_2d(er(1), i, j, Vec3::x(), Vec3::y()).unwrap();
    sys.set_part_velocity(p, Vec3::new(0.3, 0.4, 0.0), Vec3::new(0.0, 0.0, 0.2));
    sys.prepare(Dim::Auto);
    assert_eq!(sys.dim, Dimension::Two, "{}", sys.dim_reason);
    assert_eq!(sys.labels().len(), 2);
    sys.assemble(&AssemblyOptions::default()).unwrap();
    let part = sys.part(p);
    // The rotation is undone about the marker origin, so x moves only by second-order
    // terms of the first step: y = 0, angle 0 exactly; x near its input.
    assert!(part.r.y.abs() < 1e-12 && part.rot.angle() < 1e-12);
    assert!((part.r.x - 0.7).abs() < 1e-2);
    // Velocity closest to the input: the sliding speed is kept, the rest removed.
    assert!((part.v.x - 0.3).abs() < 1e-12 && part.v.y.abs() < 1e-12 && part.w.z.abs() < 1e-12);
}

#[test]
fn non_holonomic_gcon_sets_the_velocity() {
    // GCON VX(i) − 0.5 = 0 (Pfaffian, spec §4.3): the velocity solve meets it and leaves
    // the other input velocities alone.
    let mut sys = System::new();
    let p = sys.add_part(None, Vec3::new(0.2, 0.0, 0.0), Mat3::identity());
    let i = sys.add_marker(None, p, Vec3::new(0.5, 0.0, 0.0), Mat3::identity());
    sys.set_part_velocity(p, Vec3::new(0.0, 0.7, 0.0), Vec3::zeros());
    let vx = sys.measures.add(Measure::Vel {
        i: Some(i),
        j: None,
        k: None,
        l: None,
        comp: 0,
    });
    let f = Closure {
        slots: vec![0],
        f: |_: f64, m: &[f64]| m[0] - 0.5,
        g: |_: f64, _: &[f64], g: &mut [f64]| {
            g[0] = 1.0;
            0.0
        },
    };
    sys.gcon(er(1), Box::new(f), vec![vx]).unwrap();
    sys.prepare(Dim::Auto);
    let rep = sys.assemble(&AssemblyOptions::default()).unwrap();
    let part = sys.part(p);
    assert!(
        (part.v.x - 0.5).abs() < 1e-12 && (part.v.y - 0.7).abs() < 1e-12,
        "{}",
        part.v
    );
    assert!(rep.velocity_residual < 1e-12);
}

/// A02 N-four-bar (reference-problems §4.2): N + 1 unit cranks pinned at x = 0..N, N
/// unit couplers joining their tops; every part starts near crank angle `theta`.
fn n_four_bar(n: usize, theta: f64, dim: Dim) -> (System, Vec<PartHandle>, Vec<PartHandle>) {
    let mut sys = System::new();
    let (mut cranks, mut couplers) = (Vec::new(), Vec::new());
    let up = rz(PI / 2.0 - theta);
    let jitter = |k: usize| 0.02 * ((k * 37 % 11) as f64 / 11.0 - 0.5);
    let mut tops = Vec::new();
    for k in 0..=n {
        let x = k as f64;
        let c = sys.add_part(
            None,
            Vec3::new(x + jitter(k), jitter(k + 3), 0.0),
            up * rz(jitter(k + 5)),
        );
        let bottom = sys.add_marker(None, c, Vec3::zeros(), Mat3::identity());
        tops.push(sys.add_marker(None, c, Vec3::x(), Mat3::identity()));
        let g = ground_marker(&mut sys, Vec3::new(x, 0.0, 0.0), Mat3::identity());
        rev(&mut sys, k as u32, bottom, g);
        cranks.push(c);
    }
    for k in 0..n {
        let at = Vec3::new(k as f64 + theta.sin() + jitter(k + 7), theta.cos(), 0.0);
        let c = sys.add_part(None, at, rz(jitter(k + 2)));
        let a = sys.add_marker(None, c, Vec3::zeros(), Mat3::identity());
        let b = sys.add_marker(None, c, Vec3::x(), Mat3::identity());
        rev(&mut sys, 1000 + k as u32, a, tops[k]);
        rev(&mut sys, 2000 + k as u32, b, tops[k + 1]);
        couplers.push(c);
    }
    sys.prepare(dim);
    (sys, cranks, couplers)
}

#[test]
fn n_four_bar_redundancy_counts_match_reference_problems() {
    // reference-problems §5.1: 3N redundant equations in 3D, none in 2D; 1 DOF.
    let n = 4;
    let (sys, _, _) = n_four_bar(n, 0.3, Dim::Three);
    let j = dense(&sys.jacobian(true).unwrap());
    assert_eq!(j.nrows() - rank(&j), 3 * n);
    assert_eq!(j.ncols() - rank(&j), 1);
    let (sys, _, _) = n_four_bar(n, 0.3, Dim::Auto);
    assert_eq!(sys.dim, Dimension::Two);
    let j = dense(&sys.jacobian(true).unwrap());
    assert_eq!((j.nrows() - rank(&j), j.ncols() - rank(&j)), (0, 1));
}

#[test]
fn forty_window_four_bar_assembles_onto_the_parallelogram() {
    // N = 40 in 3D: 81 parts, 605 equations of which 120 are redundant. Assembled, every
    // crank has one angle and every coupler is level (the parallelogram branch).
    for dim in [Dim::Three, Dim::Auto] {
        let (mut sys, cranks, couplers) = n_four_bar(40, 0.3, dim);
        let t0 = std::time::Instant::now();
        let rep = sys.assemble(&AssemblyOptions::default()).unwrap();
        eprintln!(
            "N = 40 four-bar ({:?}): {} iterations, {:?}",
            sys.dim,
            rep.iterations,
            t0.elapsed()
        );
        let angle = |p: PartHandle| {
            let x = sys.part(p).rot * Vec3::x();
            x.y.atan2(x.x)
        };
        let a0 = angle(cranks[0]);
        for &c in &cranks {
            assert!((angle(c) - a0).abs() < 1e-8, "{dim:?}");
        }
        for &c in &couplers {
            assert!(angle(c).abs() < 1e-8, "{dim:?}");
        }
        assert!((a0 - (PI / 2.0 - 0.3)).abs() < 0.05);
    }
}

#[test]
fn bricard_has_one_redundant_equation_and_one_dof() {
    // IFToMM A04 (reference-problems §4.4, §5.3): five unit rods and six revolutes whose
    // axes alternate y, z, x; Grübler gives 0 DOF, the true mobility is 1, so exactly one
    // equation is redundant.
    let pts = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 1.0),
        Vec3::new(0.0, -1.0, 1.0),
        Vec3::new(0.0, 0.0, 1.0),
    ];
    // z of the joint marker along the joint axis.
    let ax = |k: usize| match k % 3 {
        0 => rot(-PI / 2.0, 0.0, 0.0), // z → y
        1 => Mat3::identity(),         // z → z
        _ => rot(0.0, PI / 2.0, 0.0),  // z → x
    };
    let build = |jitter: f64| {
        let mut sys = System::new();
        let rods: Vec<_> = (0..5)
            .map(|k| {
                sys.add_part(
                    None,
                    pts[k] + Vec3::new(jitter, -jitter, jitter) * k as f64,
                    rot(jitter, 0.0, -jitter),
                )
            })
            .collect();
        for k in 0..6 {
            // Joint k joins rod k−1 (ground for k = 0) and rod k (ground for k = 5).
            let on = |sys: &mut System, r: Option<usize>| match r {
                Some(r) => sys.add_marker(None, rods[r], pts[k] - pts[r], ax(k)),
                None => ground_marker(sys, pts[k], ax(k)),
            };
            let i = on(&mut sys, (k < 5).then_some(k));
            let j = on(&mut sys, k.checked_sub(1));
            rev(&mut sys, k as u32 + 1, i, j);
        }
        sys.prepare(Dim::Auto);
        sys
    };
    let sys = build(0.0);
    assert_eq!(sys.dim, Dimension::Three);
    let j = dense(&sys.jacobian(true).unwrap());
    assert_eq!((j.nrows(), j.ncols(), rank(&j)), (30, 30, 29));
    // From perturbed positions it assembles; every joint closes.
    let mut sys = build(0.01);
    sys.assemble(&AssemblyOptions::default()).unwrap();
    assert!(sys.residual().unwrap().amax() < 1e-10);
}

#[test]
fn a_motion_beyond_half_a_turn_is_reached_not_wrapped() {
    // MOTION of a revolute to 200°: the angle must come out as 200°, not −160° (AZ is
    // unwrapped, expr-language §6.2), and the crank tip sits at 200° on the unit circle.
    let mut sys = System::new();
    let p = sys.add_part(None, Vec3::zeros(), rz(190f64.to_radians()));
    let i = sys.add_marker(None, p, Vec3::zeros(), Mat3::identity());
    let j = ground_marker(&mut sys, Vec3::zeros(), Mat3::identity());
    rev(&mut sys, 1, i, j);
    let az = Measure::Angle {
        i: Some(i),
        j: Some(j),
        axis: 2,
    };
    sys.motion(er(1), az, time_fn(200f64.to_radians(), 0.0))
        .unwrap();
    sys.prepare(Dim::Auto);
    sys.assemble(&AssemblyOptions::default()).unwrap();
    let x = sys.part(p).rot * Vec3::x();
    let want = 200f64.to_radians();
    assert!((x - Vec3::new(want.cos(), want.sin(), 0.0)).norm() < 1e-10);
    let n = sys.measures.add(az);
    assert!((sys.measures.eval(&sys, n).value() - want).abs() < 1e-10);
}

#[test]
fn non_finite_pose_fails_assembly_instead_of_hanging_or_passing() {
    // Regression: nalgebra's iterative `from_matrix` never returned on a NaN matrix, and
    // a NaN residual compared as "not above tolerance".
    let mut sys = System::new();
    let p = sys.add_part(Some(2), Vec3::new(f64::NAN, 0.0, 0.0), rz(f64::NAN));
    let i = sys.add_marker(None, p, Vec3::zeros(), Mat3::identity());
    let j = ground_marker(&mut sys, Vec3::zeros(), Mat3::identity());
    rev(&mut sys, 1, i, j);
    sys.prepare(Dim::Auto);
    let err = sys.assemble(&AssemblyOptions::default()).unwrap_err();
    assert!(matches!(err, AssemblyError::NotAssembled { .. }), "{err}");
}

#[test]
fn four_bar_in_the_zx_and_yz_planes_runs_in_2d_with_the_3d_result() {
    let th = 60f64.to_radians();
    let (bx, by) = (0.4 * th.cos(), 0.4 * th.sin());
    let (cx, cy) = circle_intersection(bx, by, 1.0, 1.0, 0.0, 0.7);
    // Rx(90°) turns the XY plane into ZX (normal Y), Ry(90°) into YZ (normal X).
    for (g, plane) in [
        (rot(PI / 2.0, 0.0, 0.0), "ZX"),
        (rot(0.0, PI / 2.0, 0.0), "YZ"),
    ] {
        for dim in [Dim::Auto, Dim::Three] {
            let (mut sys, [_, coupler, _]) = four_bar_in(g, 1.0, Some(th), dim);
            if dim == Dim::Auto {
                assert_eq!(sys.dim, Dimension::Two, "{}", sys.dim_reason);
                assert!(sys.dim_reason.contains(plane), "{}", sys.dim_reason);
            }
            sys.assemble(&AssemblyOptions::default()).unwrap();
            let p = sys.part(coupler);
            let tip = p.r + p.rot * Vec3::x();
            assert!(
                (tip - g * Vec3::new(cx, cy, 0.0)).norm() < 1e-9,
                "{plane} {dim:?}"
            );
        }
    }
}
