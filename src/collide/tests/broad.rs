//! The broad phase: only pairs whose bounding boxes overlap are candidates.

use super::initial;
use crate::collide::{Geometry, Space, World};
use std::collections::HashMap;
use std::fmt::Write;

#[test]
fn a_thousand_spheres_spread_out_give_only_the_near_pairs() {
    // Spheres of radius 0.3 on a unit grid 10 × 10 × 10; every sphere in an even
    // column moves 0.45 along x, so it lies 0.55 from its odd neighbour (boxes overlap:
    // 0.55 < 0.6) and 1.45 from the other. Near pairs: 5 per row, 100 rows.
    let (n, r, shift) = (10usize, 0.3, 0.45);
    let mut text = String::from("spheres\nPART/1, GROUND\n");
    let mut ids = Vec::new();
    for k in 0..n * n * n {
        let (i, j, l) = (k % n, (k / n) % n, k / (n * n));
        let x = i as f64 + if i % 2 == 0 { shift } else { 0.0 };
        let id = 2 + k as u32;
        writeln!(
            text,
            "PART/{id}, MASS=1, CM={id}, IP=1,1,1, QG={x},{j},{l}\nMARKER/{id}, PART={id}\n\
             GRAPHICS/{id}, ELLIPSOID, CM={id}, XSCALE={d}, YSCALE={d}, ZSCALE={d}",
            d = 2.0 * r
        )
        .unwrap();
        ids.push(id);
    }
    text.push_str("END\n");
    let m = crate::model::read_model(&text).model;
    let geometries: Vec<Geometry> = ids
        .iter()
        .map(|&id| Geometry::of(&m, id, &HashMap::new()).unwrap())
        .collect();
    let count = geometries.len();
    let mut pairs = Vec::new();
    for a in 0..count {
        for b in a + 1..count {
            pairs.push((a, b));
        }
    }
    let mut expected: Vec<usize> = Vec::new();
    for (k, &(a, b)) in pairs.iter().enumerate() {
        let same_row = a / n == b / n;
        if same_row && a % 2 == 0 && b == a + 1 {
            expected.push(k);
        }
    }
    assert_eq!(expected.len(), 500);
    let mut w = World::new(geometries, pairs, Space::Three);
    w.update(&initial(&m));
    let mut found = Vec::new();
    w.candidates(&mut found);
    assert_eq!(found, expected);
    // And each near pair overlaps by 0.6 − 0.55.
    for &k in &expected[..5] {
        assert!((w.separation(k) + (2.0 * r - (1.0 - shift))).abs() < 1e-9);
    }
}

/// The cost figure of docs/contact.md: `update + candidates + incidents` per step for
/// N spheres at a fixed density in a box, N = 10, 100, 1000, and the log-log slope of
/// time against N (the goal is about N log N: a slope a little above 1).
/// `cargo test --release --lib cost_per_step -- --ignored --nocapture`.
#[test]
#[ignore = "a timing figure, not a check"]
fn cost_per_step_against_n() {
    use crate::collide::{Incident, Pose};
    use crate::vocab::math::{Mat3, Vec3};
    let mut figures = Vec::new();
    for n in [10usize, 100, 1000] {
        // Radius 0.3, one sphere per unit cube on average: side n^(1/3).
        let side = (n as f64).cbrt();
        let mut text = String::from("spheres\nPART/1, GROUND\n");
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * side
        };
        for k in 0..n {
            let id = 2 + k;
            let (x, y, z) = (next(), next(), next());
            writeln!(
                text,
                "PART/{id}, MASS=1, CM={id}, IP=1,1,1, QG={x},{y},{z}\nMARKER/{id}, PART={id}\n\
                 GRAPHICS/{id}, ELLIPSOID, CM={id}, XSCALE=0.6, YSCALE=0.6, ZSCALE=0.6"
            )
            .unwrap();
        }
        text.push_str("END\n");
        let m = crate::model::read_model(&text).model;
        let geometries: Vec<Geometry> = (0..n)
            .map(|k| Geometry::of(&m, 2 + k as u32, &HashMap::new()).unwrap())
            .collect();
        let pairs = (0..n)
            .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
            .collect();
        let mut w = World::new(geometries, pairs, Space::Three);
        let (mut found, mut touching) = (Vec::new(), Vec::<Incident>::new());
        let steps = 200;
        let start = std::time::Instant::now();
        let mut contacts = 0;
        for s in 0..steps {
            // Every part moves a little each step, as in a run.
            let shift = 1e-3 * s as f64;
            let pose = |id: u32| {
                let p = m.part(id).unwrap();
                Pose {
                    r: p.position + Vec3::new(shift, 0.0, 0.0),
                    rot: Mat3::identity(),
                }
            };
            w.update(&pose);
            w.candidates(&mut found);
            for &k in &found {
                w.incidents(k, &mut touching);
                contacts += touching.len();
            }
        }
        let per_step = start.elapsed().as_secs_f64() / steps as f64;
        eprintln!(
            "N = {n}: {:.3} ms per step, {} contacts per step",
            per_step * 1e3,
            contacts / steps
        );
        figures.push((n as f64, per_step));
    }
    let slope = |(n0, t0): (f64, f64), (n1, t1): (f64, f64)| (t1 / t0).ln() / (n1 / n0).ln();
    eprintln!(
        "log-log slope: {:.2} (10→100), {:.2} (100→1000), {:.2} (10→1000)",
        slope(figures[0], figures[1]),
        slope(figures[1], figures[2]),
        slope(figures[0], figures[2])
    );
}
