//! Measure and constraint Jacobians against central differences, and the DOF each
//! element removes (multibody spec §4.2).

use super::*;
use crate::mbd::expr::Closure;
use crate::mbd::measure_set::Measure;
use crate::mbd::planar::Dim;
use crate::mbd::system::{MarkerHandle, System};
use crate::vocab::elements::{ElementKind, ElementRef, JointType, JprimType};
use crate::vocab::math::{Mat3, Vec3};
use proptest::prelude::*;

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
