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
