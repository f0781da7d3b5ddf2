//! Tests of the core with truth from outside the code: the worked examples of
//! expr-language §6, closed-form mechanism geometry (pendulum, slider-crank, four-bar),
//! the DOF table of multibody spec §4.2 and the redundancy counts of reference-problems
//! §5, and central finite differences as the oracle for every Jacobian.

use super::assembly::AssemblyOptions;
use super::equations::{ElementKind, ElementRef, JointType, JprimType};
use super::expr::{Closure, ExprFn};
use super::math::{DMat, Mat3, Vec3};
use super::measures::Measure;
use super::planar::Dim;
use super::system::{Dimension, MarkerHandle, System};
use super::AssemblyError;
use proptest::prelude::*;
use std::f64::consts::PI;

fn rz(a: f64) -> Mat3 {
    *nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), a).matrix()
}

fn rot(x: f64, y: f64, z: f64) -> Mat3 {
    *nalgebra::Rotation3::from_scaled_axis(Vec3::new(x, y, z)).matrix()
}

fn er(id: u32) -> ElementRef {
    ElementRef {
        kind: ElementKind::Gcon,
        id,
        name: None,
    }
}

/// g(t) = g0 + rate·t with its derivative.
fn time_fn(g0: f64, rate: f64) -> Box<dyn ExprFn> {
    Box::new(Closure {
        slots: vec![],
        f: move |t: f64, _: &[f64]| g0 + rate * t,
        g: move |_: f64, _: &[f64], _: &mut [f64]| rate,
    })
}

fn dense(t: &super::sparse::Triplets) -> DMat {
    let mut m = DMat::zeros(t.nrows, t.ncols);
    for &(r, c, v) in &t.entries {
        m[(r as usize, c as usize)] += v;
    }
    m
}

fn rank(m: &DMat) -> usize {
    if m.nrows() == 0 {
        return 0;
    }
    let s = m.clone().svd(false, false).singular_values;
    let tol = 1e-9 * s.max().max(1.0);
    s.iter().filter(|&&x| x > tol).count()
}

fn ground_marker(sys: &mut System, at: Vec3, r: Mat3) -> MarkerHandle {
    sys.add_marker(None, System::GROUND, at, r)
}

// ---------------------------------------------------------------- measures

#[test]
fn displacement_worked_example_of_the_spec() {
    // expr-language §6.1: k rotated +90° about z, i at (1, 2, 3), j at the origin.
    let mut sys = System::new();
    let i = ground_marker(&mut sys, Vec3::new(1.0, 2.0, 3.0), Mat3::identity());
    let j = ground_marker(&mut sys, Vec3::zeros(), Mat3::identity());
    let k = ground_marker(&mut sys, Vec3::new(5.0, -1.0, 2.0), rz(PI / 2.0));
    let (i, j, k) = (Some(i), Some(j), Some(k));
    let cases = [
        (Measure::Disp { i, j, k, comp: 0 }, 2.0),
        (Measure::Disp { i, j, k, comp: 1 }, -1.0),
        (Measure::Disp { i, j, k, comp: 2 }, 3.0),
        (
            Measure::Disp {
                i,
                j: None,
                k: None,
                comp: 0,
            },
            1.0,
        ),
        (Measure::Dist { i, j }, 3.7416573867739413),
    ];
    for (m, want) in cases {
        let n = sys.measures.add(m);
        let got = sys.measures.eval(&sys, n).value();
        assert!((got - want).abs() < 1e-14, "{m:?}: {got} vs {want}");
    }
}

#[test]
fn angles_and_unit_vectors_on_known_rotations() {
    let mut sys = System::new();
    let p = sys.add_part(None, Vec3::zeros(), rz(PI / 6.0));
    let i = Some(sys.add_marker(None, p, Vec3::zeros(), Mat3::identity()));
    // expr-language §6.2: i rotated +30° about ground z.
    for (axis, want) in [(2, PI / 6.0), (0, 0.0), (1, 0.0)] {
        let n = sys.measures.add(Measure::Angle { i, j: None, axis });
        assert!((sys.measures.eval(&sys, n).value() - want).abs() < 1e-15);
    }
    // UVX(i) = (cos 30°, sin 30°, 0).
    let n = sys.measures.add(Measure::UnitVec {
        i,
        k: None,
        axis: 0,
        comp: 1,
    });
    assert!((sys.measures.eval(&sys, n).value() - 0.5).abs() < 1e-15);
    // REULER (30°, 40°, 50°) read back by PSI, THETA, PHI (spec §2.4 convention).
    let (a, b, c) = (30f64.to_radians(), 40f64.to_radians(), 50f64.to_radians());
    let r313 = rz(a) * rot(b, 0.0, 0.0) * rz(c);
    let m = Some(sys.add_marker(None, System::GROUND, Vec3::zeros(), r313));
    for (which, want) in [(0, a), (1, b), (2, c)] {
        let n = sys.measures.add(Measure::Euler313 {
            i: m,
            j: None,
            which,
        });
        assert!((sys.measures.eval(&sys, n).value() - want).abs() < 1e-14);
    }
    // YAW, PITCH, ROLL: Rz(yaw)·Ry(−pitch)·Rx(roll).
    let (y, pt, rl) = (0.3, 0.2, -0.4);
    let r321 = rz(y) * rot(0.0, -pt, 0.0) * rot(rl, 0.0, 0.0);
    let m = Some(sys.add_marker(None, System::GROUND, Vec3::zeros(), r321));
    for (which, want) in [(0, y), (1, pt), (2, rl)] {
        let n = sys.measures.add(Measure::Euler321 {
            i: m,
            j: None,
            which,
        });
        assert!((sys.measures.eval(&sys, n).value() - want).abs() < 1e-14);
    }
    // B1, B2, B3: Rx·Ry·Rz.
    let (b1, b2, b3) = (0.5, -0.3, 1.2);
    let r123 = rot(b1, 0.0, 0.0) * rot(0.0, b2, 0.0) * rz(b3);
    let m = Some(sys.add_marker(None, System::GROUND, Vec3::zeros(), r123));
    for (which, want) in [(0, b1), (1, b2), (2, b3)] {
        let n = sys.measures.add(Measure::Body123 {
            i: m,
            j: None,
            which,
        });
        assert!((sys.measures.eval(&sys, n).value() - want).abs() < 1e-14);
    }
}

#[test]
fn az_unwraps_through_plus_minus_pi() {
    let mut sys = System::new();
    let p = sys.add_part(None, Vec3::zeros(), Mat3::identity());
    let i = Some(sys.add_marker(None, p, Vec3::zeros(), Mat3::identity()));
    let n = sys.measures.add(Measure::Angle {
        i,
        j: None,
        axis: 2,
    });
    let mut measures = std::mem::take(&mut sys.measures);
    // Turn by 0.5 rad steps to 3.5 turns' worth of angle, committing after each step.
    for step in 1..=44 {
        sys.apply_increment(&[0.0, 0.0, 0.0, 0.0, 0.0, 0.5]);
        let got = measures.eval(&sys, n).value();
        assert!((got - 0.5 * step as f64).abs() < 1e-9, "step {step}: {got}");
        measures.commit(&sys);
    }
    // Back through −π the other way.
    for step in (0..44).rev() {
        sys.apply_increment(&[0.0, 0.0, 0.0, 0.0, 0.0, -0.5]);
        measures.commit(&sys);
        assert!((measures.eval(&sys, n).value() - 0.5 * step as f64).abs() < 1e-9);
    }
}

#[test]
fn velocity_measures_worked_example_and_spin() {
    // expr-language §6.3: i at (3, 4, 0) moving (1, 0, 0), j fixed at the origin.
    let mut sys = System::new();
    let p = sys.add_part(None, Vec3::new(3.0, 4.0, 0.0), Mat3::identity());
    let i = Some(sys.add_marker(None, p, Vec3::zeros(), Mat3::identity()));
    let j = Some(ground_marker(&mut sys, Vec3::zeros(), Mat3::identity()));
    sys.set_part_velocity(p, Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 2.0));
    let k = Some(ground_marker(&mut sys, Vec3::zeros(), rz(PI / 2.0)));
    let cases = [
        (Measure::VelRad { i, j, l: None }, 0.6),
        (Measure::VelMag { i, j, l: None }, 1.0),
        (
            Measure::Vel {
                i,
                j,
                k: None,
                l: None,
                comp: 0,
            },
            1.0,
        ),
        (
            Measure::Vel {
                i,
                j,
                k: None,
                l: None,
                comp: 1,
            },
            0.0,
        ),
        // In k (x_k = ground y), the velocity (1, 0, 0) has y_k component −1.
        (
            Measure::Vel {
                i,
                j,
                k,
                l: None,
                comp: 1,
            },
            -1.0,
        ),
        (
            Measure::AngVel {
                i,
                j,
                k: None,
                comp: 2,
            },
            2.0,
        ),
        (Measure::AngVelMag { i, j }, 2.0),
        // Seen from i's own spinning frame, j's origin moves: d/dt|_i (r_i − r_j) =
        // v − ω × d = (1, 0, 0) − (0, 0, 2) × (3, 4, 0) = (9, −6, 0).
        (
            Measure::Vel {
                i,
                j,
                k: None,
                l: i,
                comp: 0,
            },
            9.0,
        ),
        (
            Measure::Vel {
                i,
                j,
                k: None,
                l: i,
                comp: 1,
            },
            -6.0,
        ),
    ];
    for (m, want) in cases {
        let n = sys.measures.add(m);
        let got = sys.measures.eval(&sys, n).value();
        assert!((got - want).abs() < 1e-14, "{m:?}: {got} vs {want}");
    }
}

/// Every measure kind's derivatives against central differences of its value.
fn measure_fd(sys: &mut System, m: Measure) {
    let n = sys.measures.add(m);
    let ncols = sys.ncols();
    let ev = sys.measures.eval(sys, n);
    let (mut gq, mut gv) = (vec![0.0; ncols], vec![0.0; ncols]);
    ev.scatter(sys, &mut |c, x| gq[c] += x, &mut |c, x| gv[c] += x);
    let h = 1e-6;
    for c in 0..ncols {
        let snap = sys.snapshot();
        let mut dx = vec![0.0; ncols];
        dx[c] = h;
        sys.apply_increment(&dx);
        let fp = sys.measures.eval(sys, n).value();
        sys.restore(&snap);
        dx[c] = -h;
        sys.apply_increment(&dx);
        let fm = sys.measures.eval(sys, n).value();
        sys.restore(&snap);
        let fd = (fp - fm) / (2.0 * h);
        assert!(
            (fd - gq[c]).abs() < 1e-5 * (1.0 + fd.abs()),
            "{m:?} q col {c}: fd {fd} vs {}",
            gq[c]
        );
        let v0 = sys.v();
        let mut v = v0.clone();
        v[c] += h;
        sys.set_v(&v);
        let fp = sys.measures.eval(sys, n).value();
        v[c] -= 2.0 * h;
        sys.set_v(&v);
        let fm = sys.measures.eval(sys, n).value();
        sys.set_v(&v0);
        let fd = (fp - fm) / (2.0 * h);
        assert!(
            (fd - gv[c]).abs() < 1e-5 * (1.0 + fd.abs()),
            "{m:?} v col {c}: fd {fd} vs {}",
            gv[c]
        );
    }
}

/// Two moving parts and a ground marker at random poses and velocities.
fn random_scene(x: &[f64]) -> (System, [MarkerHandle; 4]) {
    let mut sys = System::new();
    let p1 = sys.add_part(None, Vec3::new(x[0], x[1], x[2]), rot(x[3], x[4], x[5]));
    let p2 = sys.add_part(None, Vec3::new(x[6], x[7], x[8]), rot(x[9], x[10], x[11]));
    let m1 = sys.add_marker(
        None,
        p1,
        Vec3::new(x[12], x[13], x[14]),
        rot(x[15], x[16], x[17]),
    );
    let m2 = sys.add_marker(
        None,
        p2,
        Vec3::new(x[18], x[19], x[20]),
        rot(x[21], x[22], x[23]),
    );
    let m3 = sys.add_marker(
        None,
        p2,
        Vec3::new(x[24], x[25], x[0]),
        rot(x[1], x[5], x[9]),
    );
    let g = ground_marker(
        &mut sys,
        Vec3::new(x[2], x[7], x[13]),
        rot(x[3], x[8], x[17]),
    );
    sys.set_part_velocity(
        p1,
        Vec3::new(x[4], x[10], x[16]),
        Vec3::new(x[22], x[19], x[11]),
    );
    sys.set_part_velocity(
        p2,
        Vec3::new(x[6], x[12], x[20]),
        Vec3::new(x[14], x[23], x[25]),
    );
    (sys, [m1, m2, m3, g])
}

/// Residual Jacobian of every active row against central differences.
fn jacobian_fd(sys: &mut System) {
    let j = dense(&sys.jacobian(false).unwrap());
    let h = 1e-6;
    for c in 0..sys.ncols() {
        let snap = sys.snapshot();
        let mut dx = vec![0.0; sys.ncols()];
        dx[c] = h;
        sys.apply_increment(&dx);
        let fp = sys.residual().unwrap();
        sys.restore(&snap);
        dx[c] = -h;
        sys.apply_increment(&dx);
        let fm = sys.residual().unwrap();
        sys.restore(&snap);
        for r in 0..fp.len() {
            let fd = (fp[r] - fm[r]) / (2.0 * h);
            assert!(
                (fd - j[(r, c)]).abs() < 1e-5 * (1.0 + fd.abs()),
                "row {r} col {c}: fd {fd} vs {}",
                j[(r, c)]
            );
        }
    }
}

const JOINTS: [JointType; 11] = [
    JointType::Fixed,
    JointType::Revolute,
    JointType::Spherical,
    JointType::Translational,
    JointType::Cylindrical,
    JointType::Planar,
    JointType::Hooke,
    JointType::Universal,
    JointType::Convel,
    JointType::Rackpin,
    JointType::Screw,
];
const JPRIMS: [JprimType; 6] = [
    JprimType::Atpoint,
    JprimType::Inline,
    JprimType::Inplane,
    JprimType::Orientation,
    JprimType::ParallelAxes,
    JprimType::Perpendicular,
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    #[test]
    fn measure_derivatives_match_finite_differences(x in prop::array::uniform26(-1.2f64..1.2)) {
        let (mut sys, [m1, m2, m3, g]) = random_scene(&x);
        let (i, j, k, l) = (Some(m1), Some(m2), Some(m3), Some(g));
        let ms = [
            Measure::Disp { i, j, k, comp: 1 },
            Measure::Disp { i, j: l, k: None, comp: 2 },
            Measure::Dist { i, j },
            Measure::Angle { i, j, axis: 0 },
            Measure::Angle { i, j, axis: 1 },
            Measure::Angle { i, j, axis: 2 },
            Measure::Euler313 { i, j, which: 0 },
            Measure::Euler313 { i, j, which: 1 },
            Measure::Euler313 { i, j, which: 2 },
            Measure::Euler321 { i, j: k, which: 0 },
            Measure::Euler321 { i, j: k, which: 1 },
            Measure::Euler321 { i, j: k, which: 2 },
            Measure::Body123 { i, j, which: 0 },
            Measure::Body123 { i, j, which: 1 },
            Measure::Body123 { i, j, which: 2 },
            Measure::UnitVec { i, k, axis: 1, comp: 2 },
            Measure::IncAng { i, j: l, k },
            Measure::Vel { i, j, k, l, comp: 0 },
            Measure::Vel { i: k, j: l, k: i, l: j, comp: 2 },
            Measure::VelMag { i, j, l: k },
            Measure::VelRad { i, j, l },
            Measure::AngVel { i, j, k, comp: 1 },
            Measure::AngVelMag { i, j },
            Measure::PinionAngle { i, j },
        ];
        for m in ms {
            measure_fd(&mut sys, m);
        }
    }

    #[test]
    fn constraint_jacobians_match_finite_differences(x in prop::array::uniform26(-1.2f64..1.2)) {
        let (mut sys, [m1, m2, m3, g]) = random_scene(&x);
        for (n, t) in JOINTS.iter().enumerate() {
            sys.joint(er(n as u32), *t, m1, m2, 0.37).unwrap();
        }
        for (n, t) in JPRIMS.iter().enumerate() {
            sys.jprim(er(n as u32), *t, m3, g).unwrap();
        }
        sys.prismatic_2d(er(1), m1, g, Vec3::new(0.6, 0.8, 0.0), Vec3::new(0.0, 0.6, 0.8)).unwrap();
        let dm = sys.measures.add(Measure::Dist { i: Some(m1), j: Some(m3) });
        let dz = sys.measures.add(Measure::Disp { i: Some(m1), j: Some(g), k: Some(m2), comp: 2 });
        let f = Closure { slots: vec![0, 2], f: |_t: f64, m: &[f64]| m[0] * m[1] - 0.5, g: |_t: f64, m: &[f64], g: &mut [f64]| { g[0] = m[1]; g[1] = m[0]; 0.0 } };
        sys.gcon(er(1), Box::new(f), vec![dm, dz]).unwrap();
        sys.motion(er(1), Measure::Angle { i: Some(m1), j: Some(m2), axis: 2 }, time_fn(0.2, 1.0)).unwrap();
        sys.prepare(Dim::Three);
        jacobian_fd(&mut sys);
    }
}

// ---------------------------------------------------------------- DOF table

#[test]
fn each_element_removes_the_dof_of_the_spec_table() {
    // multibody spec §4.2, "Removes" column.
    let want_joint = [6, 5, 3, 5, 4, 3, 4, 4, 4, 1, 1];
    let want_jprim = [3, 2, 1, 3, 2, 1];
    let x: Vec<f64> = (0..26).map(|k| ((k * 7 + 3) as f64).sin()).collect();
    let count = |build: &dyn Fn(&mut System, MarkerHandle, MarkerHandle)| {
        let (mut sys, [m1, _, _, g]) = random_scene(&x);
        build(&mut sys, m1, g);
        sys.prepare(Dim::Three);
        let j = dense(&sys.jacobian(true).unwrap());
        (j.nrows(), rank(&j))
    };
    for (t, want) in JOINTS.iter().zip(want_joint) {
        let (rows, r) = count(&|s, a, b| {
            s.joint(er(1), *t, a, b, 0.2).unwrap();
        });
        assert_eq!((rows, r), (want, want), "{t:?}");
    }
    for (t, want) in JPRIMS.iter().zip(want_jprim) {
        let (rows, r) = count(&|s, a, b| {
            s.jprim(er(1), *t, a, b).unwrap();
        });
        assert_eq!((rows, r), (want, want), "{t:?}");
    }
    // Exudyn's 2D prismatic joint: 2 equations (spec §6.4).
    let (rows, r) = count(&|s, a, b| {
        s.prismatic_2d(er(1), a, b, Vec3::x(), Vec3::y()).unwrap();
    });
    assert_eq!((rows, r), (2, 2));
}

#[test]
fn same_part_markers_are_refused_with_the_element_named() {
    let mut sys = System::new();
    let p = sys.add_part(Some(2), Vec3::zeros(), Mat3::identity());
    let a = sys.add_marker(Some(20), p, Vec3::zeros(), Mat3::identity());
    let b = sys.add_marker(Some(21), p, Vec3::x(), Mat3::identity());
    let e = ElementRef {
        kind: ElementKind::Gcon,
        id: 7,
        name: Some("hinge".into()),
    };
    let err = sys
        .joint(e, JointType::Revolute, a, b, 0.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("JOINT/7 (REVOLUTE) 'hinge'"), "{err}");
}

// ---------------------------------------------------------------- assembly

fn rev(sys: &mut System, id: u32, i: MarkerHandle, j: MarkerHandle) {
    let e = ElementRef {
        kind: ElementKind::Joint(JointType::Revolute),
        id,
        name: None,
    };
    sys.joint(e, JointType::Revolute, i, j, 0.0).unwrap();
}

#[test]
fn pendulum_assembles_from_a_tilted_perturbed_pose() {
    let mut sys = System::new();
    let p = sys.add_part(Some(2), Vec3::new(1.1, 0.2, 0.05), rot(0.03, -0.02, 0.1));
    let i = sys.add_marker(Some(20), p, Vec3::new(-1.0, 0.0, 0.0), Mat3::identity());
    let j = ground_marker(&mut sys, Vec3::zeros(), Mat3::identity());
    rev(&mut sys, 1, i, j);
    sys.prepare(Dim::Auto);
    assert_eq!(sys.dim, Dimension::Three);
    assert!(sys.dim_reason.contains("tilted"), "{}", sys.dim_reason);
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
    crank: super::PartHandle,
    slider: super::PartHandle,
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
fn four_bar(d: f64, motion: Option<f64>, dim: Dim) -> (System, [super::PartHandle; 3]) {
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
    let crank = sys.add_part(Some(2), Vec3::new(0.02, -0.01, 0.0), rz(th + 0.08));
    let coupler = sys.add_part(
        Some(3),
        Vec3::new(bx - 0.03, by + 0.04, 0.0),
        rz((cy - by).atan2(cx - bx) - 0.07),
    );
    let rocker = sys.add_part(
        Some(4),
        Vec3::new(d + 0.02, 0.03, 0.0),
        rz((cy).atan2(cx - d) + 0.06),
    );
    let ga = ground_marker(&mut sys, Vec3::zeros(), Mat3::identity());
    let gd = ground_marker(&mut sys, Vec3::new(d, 0.0, 0.0), Mat3::identity());
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
        let tip =
            |p: super::PartHandle, l: f64| sys.part(p).r + sys.part(p).rot * Vec3::new(l, 0.0, 0.0);
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
                && labels[r].equation != super::equations::Equation::XDelta
                && labels[r].equation != super::equations::Equation::YDelta
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
fn acceleration_and_force_measures_wait_for_dynamics() {
    use crate::model::elements::MeasureSlot;
    let marker = |_: i64| Ok(None);
    for name in ["ACCX", "WDTZ", "FX", "JOINT"] {
        let slot = MeasureSlot {
            name: name.into(),
            ids: vec![1],
            component: 0,
        };
        let err = Measure::resolve(&slot, &marker).unwrap_err().to_string();
        assert!(err.contains("once dynamics exist"), "{err}");
    }
    let slot = MeasureSlot {
        name: "DX".into(),
        ids: vec![5, 0, 0],
        component: 0,
    };
    assert_eq!(
        Measure::resolve(&slot, &marker).unwrap(),
        Measure::Disp {
            i: None,
            j: None,
            k: None,
            comp: 0
        }
    );
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
fn n_four_bar(
    n: usize,
    theta: f64,
    dim: Dim,
) -> (System, Vec<super::PartHandle>, Vec<super::PartHandle>) {
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
        let angle = |p: super::PartHandle| {
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

// ---------------------------------------------------------------- from a Model

mod from_model {
    use super::*;
    use crate::check::{self, Expect, MeasureCall, MeasureValue, Scope};
    use crate::diag::Diagnostic;
    use crate::mbd::build::InterpretOnly;
    use crate::model::elements::{self as el, MeasureSlot, Model, Named};
    use std::cell::RefCell;

    /// A model scope that gives every measure call the next slot(s).
    #[derive(Default)]
    struct Slots(RefCell<Vec<MeasureSlot>>);

    impl Scope for Slots {
        fn variable(&self, _: &str) -> Option<u32> {
            None
        }

        fn measure(&self, call: &MeasureCall) -> Result<MeasureValue, Diagnostic> {
            let mut v = self.0.borrow_mut();
            let mut push = |component: u8| {
                v.push(MeasureSlot {
                    name: call.builtin.name.into(),
                    ids: call.ids.to_vec(),
                    component,
                });
                v.len() as u32 - 1
            };
            Ok(match call.builtin.result {
                check::builtins::Ty::Scalar => MeasureValue::Scalar(push(0)),
                check::builtins::Ty::Vector => MeasureValue::Vector([push(0), push(1), push(2)]),
            })
        }
    }

    fn named(id: u32) -> Named {
        Named {
            id,
            name: Some(format!("el_{id}")),
            span: 0..0,
        }
    }

    fn part(id: u32, ground: bool, at: Vec3) -> el::Part {
        el::Part {
            el: named(id),
            ground,
            mass: Some(1.0),
            cm: None,
            im: None,
            ip: [1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
            position: at,
            orientation: Mat3::identity(),
            velocity: [None; 3],
            angular_velocity: [None; 3],
            vm: None,
            wm: None,
            exact: [false; 6],
        }
    }

    fn marker(id: u32, part: u32, at: Vec3) -> el::Marker {
        el::Marker {
            el: named(id),
            part,
            position: at,
            orientation: Mat3::identity(),
            floating: false,
        }
    }

    /// The IFToMM A01 pendulum (reference-problems §4.1): unit link from the origin to
    /// P1 = (1, 0), gravity −y; the dataset places the part slightly off.
    fn pendulum() -> Model {
        let mut m = Model {
            parts: vec![
                part(1, true, Vec3::zeros()),
                part(2, false, Vec3::new(1.05, 0.1, 0.0)),
            ],
            markers: vec![
                marker(10, 1, Vec3::zeros()),
                marker(20, 2, Vec3::new(-1.0, 0.0, 0.0)),
            ],
            gravity: Vec3::new(0.0, -9.81, 0.0),
            ..Default::default()
        };
        m.joints.push(el::Joint {
            el: named(1),
            kind: JointType::Revolute,
            i: 20,
            j: 10,
            pd: None,
            pitch: None,
            ic: None,
            ic_tran: None,
            ic_rot: None,
        });
        m
    }

    #[test]
    fn pendulum_model_builds_in_2d_and_assembles() {
        let model = pendulum();
        let mut sys = System::from_model(&model, Dim::Auto, &InterpretOnly).unwrap();
        assert_eq!(sys.dim, Dimension::Two);
        assert!(sys.dim_reason.starts_with("2D"), "{}", sys.dim_reason);
        // REVOLUTE in 2D: X Delta and Y Delta only.
        assert_eq!(sys.labels().len(), 2);
        sys.assemble(&AssemblyOptions::default()).unwrap();
        let p = sys.part(super::super::PartHandle(1));
        assert!((p.r.norm() - 1.0).abs() < 1e-12 && p.id == Some(2));
        let sys = System::from_model(&model, Dim::Three, &InterpretOnly).unwrap();
        assert_eq!((sys.dim, sys.labels().len()), (Dimension::Three, 5));
        // Gravity out of the plane makes it 3D, with the reason.
        let mut tilted = pendulum();
        tilted.gravity = Vec3::new(0.0, -9.81, 1.0);
        let sys = System::from_model(&tilted, Dim::Auto, &InterpretOnly).unwrap();
        assert!(sys.dim_reason.contains("gravity"), "{}", sys.dim_reason);
    }

    #[test]
    fn gcon_without_a_derivative_says_what_is_missing() {
        let scope = Slots::default();
        let f = check::compile("DM(20, 10) - 1", &scope, Expect::Scalar)
            .unwrap()
            .function;
        let mut model = pendulum();
        model.joints.clear();
        model.measures = scope.0.into_inner();
        model.gcons.push(el::Gcon {
            el: named(5),
            i: Some(20),
            function: el::Expr {
                span: 0..0,
                function: f,
            },
        });
        let mut sys = System::from_model(&model, Dim::Three, &InterpretOnly).unwrap();
        // The value comes through the interpreter: DM = |(0.05, 0.1, 0)| at the input.
        let r = sys.residual().unwrap();
        assert!((r[0] - ((0.05f64.powi(2) + 0.01).sqrt() - 1.0)).abs() < 1e-14);
        let err = sys
            .assemble(&AssemblyOptions::default())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("GCON/5 'el_5'") && err.contains("derivative"),
            "{err}"
        );
    }

    /// Every expression becomes g(t) = 0.5 + t (stands in for the compiled derivative).
    struct Ramp;

    impl crate::mbd::build::ExprCompiler for Ramp {
        fn compile(&self, _: &el::Expr) -> Box<dyn ExprFn> {
            time_fn(0.5, 1.0)
        }
    }

    #[test]
    fn motions_of_a_model_drive_joint_and_marker_angles() {
        let expr = el::Expr {
            span: 0..0,
            function: Default::default(),
        };
        let motion = |target| el::Motion {
            el: named(3),
            target,
            level: el::MotionLevel::Displacement,
            function: expr.clone(),
            icdisp: None,
            icvel: None,
        };
        // JOINT ROTATION and the marker form B3 both drive the pendulum angle to 0.5 rad
        // (relative to the input angle 0, about z).
        for target in [
            el::MotionTarget::Joint {
                joint: 1,
                rotation: true,
            },
            el::MotionTarget::Markers {
                i: 20,
                j: 10,
                axis: el::MotionAxis::B3,
            },
        ] {
            let mut model = pendulum();
            model.motions.push(motion(target));
            let mut sys = System::from_model(&model, Dim::Auto, &Ramp).unwrap();
            sys.assemble(&AssemblyOptions::default()).unwrap();
            let p = sys.part(super::super::PartHandle(1));
            let x = p.rot * Vec3::x();
            assert!((x.y.atan2(x.x) - 0.5).abs() < 1e-10 && (p.w.z - 1.0).abs() < 1e-10);
            // The link hangs from the pivot: r = −R·(−1, 0, 0).
            assert!((p.r - x).norm() < 1e-10);
        }
    }

    #[test]
    fn part_velocities_are_given_at_the_cm_in_cm_axes() {
        // CM marker 21 at (0.5, 0, 0) on part 2, turned 90° about z: WX = 2 about the CM
        // x axis is ω = (0, 2, 0) globally; VX = 1 is the CM velocity, so the BCS origin
        // moves with v_cm − ω × (r_cm − r_origin) = (1, 0, 0) − (0, 2, 0) × (0.5, 0, 0).
        let mut model = pendulum();
        model.joints.clear();
        let mut cm = marker(21, 2, Vec3::new(0.5, 0.0, 0.0));
        cm.orientation = rz(PI / 2.0);
        model.markers.push(cm);
        model.parts[1].cm = Some(21);
        model.parts[1].velocity = [Some(1.0), None, None];
        model.parts[1].angular_velocity = [Some(2.0), None, None];
        let sys = System::from_model(&model, Dim::Auto, &InterpretOnly).unwrap();
        assert!(
            sys.dim_reason.contains("velocity out of the XY plane"),
            "{}",
            sys.dim_reason
        );
        let p = sys.part(super::super::PartHandle(1));
        assert!((p.w - Vec3::new(0.0, 2.0, 0.0)).norm() < 1e-15);
        assert!((p.v - Vec3::new(1.0, 0.0, 1.0)).norm() < 1e-15, "{}", p.v);
    }

    #[test]
    fn unknown_markers_and_unsupported_motions_are_errors() {
        let mut model = pendulum();
        model.joints[0].i = 99;
        let err = System::from_model(&model, Dim::Auto, &InterpretOnly)
            .err()
            .unwrap();
        assert_eq!(err.to_string(), "MARKER/99 does not exist");
        let mut model = pendulum();
        model.motions.push(el::Motion {
            el: named(3),
            target: el::MotionTarget::Joint {
                joint: 1,
                rotation: true,
            },
            level: el::MotionLevel::Velocity,
            function: el::Expr {
                span: 0..0,
                function: Default::default(),
            },
            icdisp: None,
            icvel: None,
        });
        let err = System::from_model(&model, Dim::Auto, &Ramp).err().unwrap();
        assert!(
            err.to_string().contains("only DISPLACEMENT motions"),
            "{err}"
        );
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
