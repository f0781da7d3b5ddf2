//! Measures against the worked examples of expr-language §6 and known rotations.

use super::*;
use crate::mbd::measure_set::Measure;
use crate::mbd::system::System;
use crate::vocab::math::{Mat3, Vec3};
use std::f64::consts::PI;

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
    // AX: i turned +0.3 about ground x (y_j toward y_i counter-clockwise); AY likewise.
    for (axis, r) in [(0u8, rot(0.3, 0.0, 0.0)), (1, rot(0.0, 0.3, 0.0))] {
        let m = Some(sys.add_marker(None, System::GROUND, Vec3::zeros(), r));
        let n = sys.measures.add(Measure::Angle {
            i: m,
            j: None,
            axis,
        });
        assert!((sys.measures.eval(&sys, n).value() - 0.3).abs() < 1e-15);
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
    // θ = 0: only ψ + φ is defined; ψ carries the whole turn and φ = 0 (as the reader's
    // REULER inverse). An identity marker reads 0, 0, 0 (it read ψ = π once).
    for turn in [0.0, 0.7] {
        let m = Some(sys.add_marker(None, System::GROUND, Vec3::zeros(), rz(turn)));
        for (which, want) in [(0, turn), (1, 0.0), (2, 0.0)] {
            let n = sys.measures.add(Measure::Euler313 {
                i: m,
                j: None,
                which,
            });
            assert!((sys.measures.eval(&sys, n).value() - want).abs() < 1e-14);
        }
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
    // Components: from the name for DY and WZ, from the slot for DXYZ and UVZ.
    let resolve = |name: &str, component: u8| {
        let slot = MeasureSlot {
            name: name.into(),
            ids: vec![5, 0, 0],
            component,
        };
        Measure::resolve(&slot, &marker).unwrap()
    };
    let (i, j, k) = (None, None, None);
    assert_eq!(resolve("DY", 0), Measure::Disp { i, j, k, comp: 1 });
    assert_eq!(resolve("DXYZ", 2), Measure::Disp { i, j, k, comp: 2 });
    assert_eq!(resolve("WZ", 0), Measure::AngVel { i, j, k, comp: 2 });
    assert_eq!(
        resolve("UVZ", 1),
        Measure::UnitVec {
            i,
            k,
            axis: 2,
            comp: 1
        }
    );
    assert_eq!(resolve("THETA", 0), Measure::Euler313 { i, j, which: 1 });
    let err = MeasureSlot {
        name: "ORIENT".into(),
        ids: vec![1],
        component: 0,
    };
    assert!(Measure::resolve(&err, &marker).is_err());
    // A VARVAL left after inlining is a design variable's; the system gives its value.
    assert_eq!(resolve("VARVAL", 0), Measure::Design { id: 5 });
}

/// `eval_in` builds angles, displacements, distances and unit-vector products from the
/// origins and axes they read; every value must be the bits of the whole dual frames'
/// formula, every derivative too except the angles' (by hand: to 1e-12 of the largest),
/// and the part slots taken in the same order.
#[test]
fn shortcut_duals_give_the_whole_frames_bits() {
    use crate::mbd::measures::PartSlots;
    let mut sys = System::new();
    let parts = [
        sys.add_part(None, Vec3::new(0.3, -0.2, 0.1), rot(0.4, -0.7, 1.1)),
        sys.add_part(None, Vec3::new(-1.1, 0.5, 0.9), rot(-0.2, 0.3, -2.5)),
        sys.add_part(None, Vec3::new(2.0, 1.5, -0.4), rot(1.3, 0.1, 0.6)),
    ];
    for (k, &p) in parts.iter().enumerate() {
        let f = k as f64 + 1.0;
        sys.set_part_velocity(
            p,
            Vec3::new(0.2 * f, -0.1, 0.3),
            Vec3::new(-0.4, 0.5 * f, 0.1),
        );
    }
    let mut markers = vec![None];
    for (k, &p) in parts.iter().enumerate() {
        let s = Vec3::new(0.1 * k as f64, -0.3, 0.25);
        markers.push(Some(sys.add_marker(
            None,
            p,
            s,
            rot(0.2, 0.9 - k as f64, 0.4),
        )));
    }
    let g = sys.add_marker(
        None,
        System::GROUND,
        Vec3::new(0.5, 0.2, -1.0),
        rot(0.3, 0.2, 0.1),
    );
    markers.push(Some(g));
    let mut list = Vec::new();
    for &i in &markers[1..] {
        for &j in &markers {
            for axis in 0..3 {
                list.push(Measure::Angle { i, j, axis });
                list.push(Measure::UnitVec {
                    i,
                    k: j,
                    axis,
                    comp: (axis + 1) % 3,
                });
                for &k in &markers[..3] {
                    list.push(Measure::Disp {
                        i,
                        j,
                        k,
                        comp: axis,
                    });
                }
            }
            list.push(Measure::Dist { i, j });
        }
    }
    for m in list {
        let n = sys.measures.add(m);
        let (mut a, mut b) = (PartSlots::default(), PartSlots::default());
        let fast = sys.measures.eval_in(&sys, n, &mut a).expect("slots");
        let whole = sys.measures.eval_by_frames(&sys, n, &mut b).expect("slots");
        assert_eq!(fast.v.to_bits(), whole.v.to_bits(), "{m:?}");
        // The angles' derivatives are by hand (cross products, not sums over dual
        // axes): equal to rounding, the others bit for bit.
        let scale = whole.g.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let tol = match m {
            Measure::Angle { .. } => 1e-12 * scale,
            _ => 0.0,
        };
        assert!(
            fast.g
                .iter()
                .zip(&whole.g)
                .all(|(x, y)| x.to_bits() == y.to_bits() || (x - y).abs() <= tol),
            "{m:?}"
        );
        assert_eq!(a.parts, b.parts, "{m:?}");
    }
}
