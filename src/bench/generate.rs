//! The generated scenes of `examples/scenes/` (their truth files carry a `[generate]`
//! table instead of a dataset): the IFToMM A02 N four-bar mechanism
//! (reference-problems.md §4.2), the planar N-link chain and the planar binary tree of the
//! chain's rods (the scaling bench's branched case), written as `.adm` text for any
//! N. The benches size the model with N while the truth stays the same kind (exact for the
//! four-bar, converged for the chain). Nothing here runs a model: the text goes to
//! `mbfx run` like any dataset.

use std::fmt::Write;

/// The dataset of scene `kind` (`"four_bar"`, `"chain"` or `"tree"`) with `n` windows or
/// links; `None`
/// for another kind or for `n = 0`.
pub fn generate(kind: &str, n: usize) -> Option<String> {
    match kind {
        _ if n == 0 => None,
        "four_bar" => Some(four_bar(n)),
        "chain" => Some(chain(n)),
        "tree" => Some(tree(n)),
        _ => None,
    }
}

/// A02's links: 1 m, 1 kg, g = 9.81, θ̇(0) = 1 rad/s (§4.2).
const BAR_LENGTH: f64 = 1.0;
const BAR_MASS: f64 = 1.0;
const BAR_OMEGA0: f64 = 1.0;

/// The A02 N four-bar mechanism with `n` parallelogram windows (§4.2), upright and turning
/// at θ̇ = 1 rad/s, statement for statement as `tests/models/a02/a02_n{N}.adm`.
///
/// Numbering: crank `i` (0..=N) is PART/(2+i), coupler `j` (1..=N) is PART/(N+2+j); part
/// `p` has the markers p·100+1 (CM), p·100+2 (lower or left pin), p·100+3 (upper or right
/// pin); the ground pins are MARKER/(110+i) at (i, 0, 0). B0, the top of the first crank,
/// is MARKER/203. JOINT/1..=N+1 pin the cranks to ground, the next 2N the couplers.
pub fn four_bar(n: usize) -> String {
    let (l, m, w0) = (BAR_LENGTH, BAR_MASS, BAR_OMEGA0);
    let inertia = m * l * l / 12.0;
    let crank = |i: usize| 2 + i;
    let coupler = |j: usize| n + 2 + j;
    let mut s = String::new();
    line(
        &mut s,
        format_args!(
            "IFToMM A02 N four-bar mechanism, N = {n} (reference-problems.md section 4.2)"
        ),
    );
    for text in [
        "! N parallelogram windows of 2N+1 uniform links (1 m, 1 kg, I = m*L**2/12 about the",
        "! CM; Ixx and Iyy do not enter the planar motion), g = 9.81 in -y. N+1 cranks stand",
        "! upright on revolute joints to ground at x = 0, 1, ..., N; N couplers join their",
        "! tops. Initial velocity: theta' = 1 rad/s (B0, the top of the first crank, at",
        "! +1 m/s along x). Written by src/bench/generate.rs (four_bar); the exact solution",
        "! J*theta'' = C*sin(theta) is in tests/dynamics/a02.rs and examples/scenes/truth/.",
        "UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND",
        "!",
        "PART/1, GROUND",
        "MARKER/101, PART = 1, QP = 0, 0, 0",
    ] {
        line(&mut s, format_args!("{text}"));
    }
    for i in 0..=n {
        line(
            &mut s,
            format_args!("MARKER/{}, PART = 1, QP = {i}, 0, 0", 110 + i),
        );
    }
    // One part: its comment, mass, CM velocity (along x) and spin, and the CM marker.
    let part = |s: &mut String, p: usize, what: &str, cm: [f64; 2], v: f64, wz: f64| {
        line(s, format_args!("! {what}"));
        let spin = if wz == 0.0 {
            String::new()
        } else {
            format!(", WZ = {wz:?}")
        };
        line(
            s,
            format_args!(
                "PART/{p}, MASS = {m:?}, CM = {}, IP = {inertia:?}, {inertia:?}, {inertia:?}\n\
                 , VX = {v:?}{spin}",
                p * 100 + 1
            ),
        );
        let [x, y] = cm;
        line(
            s,
            format_args!("MARKER/{}, PART = {p}, QP = {x:?}, {y:?}, 0", p * 100 + 1),
        );
    };
    let pin = |s: &mut String, id: usize, p: usize, x: f64, y: f64| {
        line(
            s,
            format_args!("MARKER/{id}, PART = {p}, QP = {x:?}, {y:?}, 0"),
        );
    };
    for i in 0..=n {
        let (p, x) = (crank(i), i as f64);
        let what = format!("crank {i}");
        part(&mut s, p, &what, [x, l / 2.0], w0 * l / 2.0, -w0);
        pin(&mut s, p * 100 + 2, p, x, 0.0);
        pin(&mut s, p * 100 + 3, p, x, l);
    }
    for j in 1..=n {
        let (p, x) = (coupler(j), (j - 1) as f64);
        let what = format!("coupler {j}");
        part(&mut s, p, &what, [x + l / 2.0, l], w0 * l, 0.0);
        pin(&mut s, p * 100 + 2, p, x, l);
        pin(&mut s, p * 100 + 3, p, x + l, l);
    }
    line(&mut s, format_args!("!"));
    let mut pairs = Vec::with_capacity(3 * n + 1);
    for i in 0..=n {
        pairs.push((crank(i) * 100 + 2, 110 + i));
    }
    for j in 1..=n {
        let c = coupler(j) * 100;
        pairs.push((c + 2, crank(j - 1) * 100 + 3));
        pairs.push((c + 3, crank(j) * 100 + 3));
    }
    for (k, (i, j)) in pairs.into_iter().enumerate() {
        line(
            &mut s,
            format_args!("JOINT/{}, REVOLUTE, I = {i}, J = {j}", k + 1),
        );
    }
    line(&mut s, format_args!("!\nACCGRAV/JGRAV = -9.81\nEND"));
    s
}

/// The chain's rods: l = 1/10 m (positions are written as i/20 m, each rounded once to
/// the double nearest the decimal), m = 0.1 kg.
const RODS_PER_METRE: f64 = 10.0;
const ROD_MASS: f64 = 0.1;

/// The planar chain of `n` uniform rods (l = 0.1 m, m = 0.1 kg, Izz = m·l²/12 about the CM,
/// IP = Izz/100, Izz, Izz), pinned end to end and to ground at the origin, released at rest
/// lying horizontal along +x under g = 9.81 in −y.
///
/// Numbering: rod k (1..=N) is PART/(k+1) from x = (k−1)·l to k·l, with the markers
/// p01 (CM), p02 (start) and p03 (end) for p = k+1; JOINT/k is the revolute at the rod's
/// start (I = the previous rod's p03, or ground MARKER/102 at the origin for the first;
/// J = p02). The tip is MARKER/(N+1)03.
pub fn chain(n: usize) -> String {
    let m = ROD_MASS;
    // m·l²/12 and its hundredth, each one division (8.333333333333334e-5, not the
    // 8.333333333333336e-5 of 0.1·0.1·0.1/12).
    let izz = m / (12.0 * RODS_PER_METRE * RODS_PER_METRE);
    let ixx = m / (1200.0 * RODS_PER_METRE * RODS_PER_METRE);
    let mut s = String::new();
    line(
        &mut s,
        format_args!("Planar chain of N = {n} rods pinned end to end, falling from rest"),
    );
    for text in [
        "! N uniform rods of l = 0.1 m and m = 0.1 kg (Izz = m*l**2/12 about the CM; Ixx =",
        "! Izz/100 about the rod's axis and Iyy = Izz do not enter the planar motion) on",
        "! revolute joints about global z, the first pinned to ground at the origin. Released",
        "! at rest lying horizontal along +x, g = 9.81 in -y; SI units. Rod k is PART/(k+1)",
        "! from x = (k-1)*l to k*l with the markers p01 (CM), p02 (start), p03 (end); the tip",
        "! is MARKER/(N+1)03. Written by src/bench/generate.rs (chain).",
        "UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND",
        "!",
        "PART/1, GROUND",
        "MARKER/101, PART = 1, QP = 0, 0, 0",
        "MARKER/102, PART = 1, QP = 0, 0, 0",
    ] {
        line(&mut s, format_args!("{text}"));
    }
    // x = i·l/2 at the i-th half rod, as one division (0.3, not 3·0.1 = 0.30000000000000004).
    let half = |i: usize| i as f64 / (2.0 * RODS_PER_METRE);
    for k in 1..=n {
        let p = k + 1;
        line(&mut s, format_args!("! rod {k}"));
        line(
            &mut s,
            format_args!(
                "PART/{p}, MASS = {m:?}, CM = {}, IP = {ixx:?}, {izz:?}, {izz:?}",
                p * 100 + 1
            ),
        );
        for (marker, at) in [(1, 2 * k - 1), (2, 2 * k - 2), (3, 2 * k)] {
            line(
                &mut s,
                format_args!(
                    "MARKER/{}, PART = {p}, QP = {:?}, 0, 0",
                    p * 100 + marker,
                    half(at)
                ),
            );
        }
    }
    line(&mut s, format_args!("!"));
    for k in 1..=n {
        let i = if k == 1 { 102 } else { k * 100 + 3 };
        let j = (k + 1) * 100 + 2;
        line(
            &mut s,
            format_args!("JOINT/{k}, REVOLUTE, I = {i}, J = {j}"),
        );
    }
    line(&mut s, format_args!("!\nACCGRAV/JGRAV = -9.81\nEND"));
    s
}

/// The planar binary tree of `n` of the chain's rods (l = 0.1 m, m = 0.1 kg), released at
/// rest under g = 9.81 in −y: rod 1 is pinned to ground at the origin along +x, and rod k
/// (k ≥ 2) to the end of rod ⌊k/2⌋, along +x when k is even and along −y when odd (the
/// rods may overlap: nothing touches). Numbering as the chain's: rod k is PART/(k+1)
/// with the markers p01 (CM), p02 (start), p03 (end); JOINT/k is its revolute.
pub fn tree(n: usize) -> String {
    let m = ROD_MASS;
    let l = 1.0 / RODS_PER_METRE;
    let izz = m / (12.0 * RODS_PER_METRE * RODS_PER_METRE);
    let small = m / (1200.0 * RODS_PER_METRE * RODS_PER_METRE);
    let mut s = String::new();
    line(
        &mut s,
        format_args!("Planar binary tree of N = {n} rods, rod k pinned to the end of rod k/2"),
    );
    line(
        &mut s,
        format_args!(
            "! Written by src/bench/generate.rs (tree).\n\
             UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
             PART/1, GROUND\nMARKER/101, PART = 1, QP = 0, 0, 0\nMARKER/102, PART = 1, QP = 0, 0, 0"
        ),
    );
    // Each rod's start and end; a rod along −y has its small inertia about y.
    let mut ends: Vec<([f64; 2], [f64; 2])> = Vec::with_capacity(n + 1);
    ends.push(([0.0; 2], [0.0; 2]));
    for k in 1..=n {
        let start = if k == 1 { [0.0; 2] } else { ends[k / 2].1 };
        let down = k > 1 && k % 2 == 1;
        let end = if down {
            [start[0], start[1] - l]
        } else {
            [start[0] + l, start[1]]
        };
        ends.push((start, end));
        let p = k + 1;
        let (ixx, iyy) = if down { (izz, small) } else { (small, izz) };
        line(
            &mut s,
            format_args!(
                "PART/{p}, MASS = {m:?}, CM = {}, IP = {ixx:?}, {iyy:?}, {izz:?}",
                p * 100 + 1
            ),
        );
        let cm = [(start[0] + end[0]) / 2.0, (start[1] + end[1]) / 2.0];
        for (marker, at) in [(1, cm), (2, start), (3, end)] {
            line(
                &mut s,
                format_args!(
                    "MARKER/{}, PART = {p}, QP = {:?}, {:?}, 0",
                    p * 100 + marker,
                    at[0],
                    at[1]
                ),
            );
        }
    }
    for k in 1..=n {
        let i = if k == 1 { 102 } else { (k / 2 + 1) * 100 + 3 };
        let j = (k + 1) * 100 + 2;
        line(
            &mut s,
            format_args!("JOINT/{k}, REVOLUTE, I = {i}, J = {j}"),
        );
    }
    line(&mut s, format_args!("ACCGRAV/JGRAV = -9.81\nEND"));
    s
}

/// Appends `args` and a newline (writing to a `String` cannot fail).
fn line(s: &mut String, args: std::fmt::Arguments) {
    let _ = s.write_fmt(args);
    s.push('\n');
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The statements of a dataset: its lines without the title and the comments.
    fn statements(text: &str) -> Vec<&str> {
        text.lines()
            .skip(1)
            .filter(|l| !l.trim_start().starts_with('!'))
            .collect()
    }

    /// How many statements of a dataset start with `keyword`.
    fn count(text: &str, keyword: &str) -> usize {
        text.lines().filter(|l| l.starts_with(keyword)).count()
    }

    #[test]
    fn four_bar_1_has_the_statements_of_the_a02_n1_dataset() {
        let want = include_str!("../../tests/models/a02/a02_n1.adm");
        assert_eq!(statements(&four_bar(1)), statements(want));
        assert_eq!(four_bar(1).lines().next(), want.lines().next());
    }

    #[test]
    fn four_bar_4_has_the_statements_of_the_a02_n4_dataset() {
        let want = include_str!("../../tests/models/a02/a02_n4.adm");
        assert_eq!(statements(&four_bar(4)), statements(want));
    }

    #[test]
    fn four_bar_has_2n_plus_1_links_and_3n_plus_1_revolutes() {
        for n in [1, 2, 40] {
            let text = four_bar(n);
            // The ground is PART/1 too.
            assert_eq!(count(&text, "PART/"), 2 * n + 2, "N = {n}");
            assert_eq!(count(&text, "JOINT/"), 3 * n + 1, "N = {n}");
            assert!(text.contains("MARKER/203, PART = 2, QP = 0.0, 1.0, 0"));
            assert!(text.ends_with("ACCGRAV/JGRAV = -9.81\nEND\n"));
        }
    }

    #[test]
    fn tree_hangs_rod_k_from_the_end_of_rod_k_over_2() {
        let text = tree(7);
        assert_eq!(count(&text, "PART/"), 8);
        assert_eq!(count(&text, "JOINT/"), 7);
        // Rods 2 and 3 hang from rod 1's end (x = 0.1): 2 along +x, 3 along −y.
        assert!(text.contains("JOINT/2, REVOLUTE, I = 203, J = 302\n"));
        assert!(text.contains("JOINT/3, REVOLUTE, I = 203, J = 402\n"));
        assert!(text.contains("JOINT/7, REVOLUTE, I = 403, J = 802\n"));
        assert!(text.contains("MARKER/302, PART = 3, QP = 0.1, 0.0, 0\n"));
        assert!(text.contains("MARKER/403, PART = 4, QP = 0.1, -0.1, 0\n"));
        // Rod 7 (odd, down) from rod 3's end (0.1, −0.1) to (0.1, −0.2).
        assert!(text.contains("MARKER/803, PART = 8, QP = 0.1, -0.2, 0\n"));
        assert!(text.ends_with("ACCGRAV/JGRAV = -9.81\nEND\n"));
    }

    #[test]
    fn chain_has_n_rods_n_revolutes_and_its_tip_at_n_l() {
        let text = chain(100);
        assert_eq!(count(&text, "PART/"), 101);
        assert_eq!(count(&text, "JOINT/"), 100);
        assert!(text.contains("JOINT/1, REVOLUTE, I = 102, J = 202\n"));
        assert!(text.contains("JOINT/100, REVOLUTE, I = 10003, J = 10102\n"));
        assert!(text.contains("MARKER/10103, PART = 101, QP = 10.0, 0, 0\n"));
        assert!(text.contains("MARKER/5103, PART = 51, QP = 5.0, 0, 0\n"));
        // Rod 3: CM at 0.25, start 0.2, end 0.3, each the double nearest to the decimal.
        assert!(text.contains("MARKER/401, PART = 4, QP = 0.25, 0, 0\n"));
        assert!(text.contains("MARKER/402, PART = 4, QP = 0.2, 0, 0\n"));
        assert!(text.contains("MARKER/403, PART = 4, QP = 0.3, 0, 0\n"));
        assert!(text.contains(
            "PART/2, MASS = 0.1, CM = 201, IP = 8.333333333333333e-7, \
             8.333333333333334e-5, 8.333333333333334e-5\n"
        ));
    }

    #[test]
    fn generate_knows_the_three_kinds() {
        assert_eq!(generate("four_bar", 2), Some(four_bar(2)));
        assert_eq!(generate("chain", 3), Some(chain(3)));
        assert_eq!(generate("tree", 3), Some(tree(3)));
        assert_eq!(generate("chain", 0), None);
        assert_eq!(generate("ladder", 3), None);
    }

    /// Writes the generated scenes of `examples/scenes/` into the folder named by
    /// `MBFX_GENERATE_DIR` (e.g. to run them with `mbfx run`); does nothing without it.
    #[test]
    fn writes_the_generated_scenes_when_asked() {
        let Some(dir) = std::env::var_os("MBFX_GENERATE_DIR") else {
            return;
        };
        let dir = std::path::PathBuf::from(dir);
        for (kind, n) in [
            ("four_bar", 1),
            ("four_bar", 2),
            ("four_bar", 40),
            ("chain", 100),
        ] {
            let text = generate(kind, n).unwrap();
            std::fs::write(dir.join(format!("{kind}_n{n}.adm")), text).unwrap();
        }
    }
}
