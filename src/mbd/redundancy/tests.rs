//! Tests of the redundancy analysis. Truth comes from outside the code: the expected counts
//! of reference-problems §5.1 (four-bar, N-four-bar, Bricard), Jacobians built in
//! [`super::fixtures`] straight from the spec's equations, the message format quoted in
//! multibody spec §5.1, the joint table of §4.2, and a dense SVD (nalgebra) as rank oracle.

use proptest::prelude::*;

use super::fixtures::{bricard, n_four_bar, Mechanism};
use super::*;
use crate::mbd::equations::{Equation, EquationLabel};
use crate::vocab::elements::{ElementRef, JointType, JprimType};
use crate::vocab::math::{DMat, Vec3};

/// Dense copy of a triplet matrix (duplicates summed).
fn dense(t: &Triplets) -> DMat {
    let mut m = DMat::zeros(t.nrows, t.ncols);
    for &(r, c, v) in &t.entries {
        m[(r as usize, c as usize)] += v;
    }
    m
}

/// Numerical rank by SVD, relative to the largest singular value.
fn svd_rank(m: &DMat) -> usize {
    if m.nrows() == 0 || m.ncols() == 0 {
        return 0;
    }
    let s = m.clone().svd(false, false).singular_values;
    let top = s.max();
    s.iter().filter(|&&v| v > 1e-9 * top).count()
}

/// The rows `rows` of `m` as a matrix.
fn rows_of(m: &DMat, rows: &[usize]) -> DMat {
    DMat::from_fn(rows.len(), m.ncols(), |i, j| m[(rows[i], j)])
}

/// The validity guarantee, checked by SVD: kept rows independent, and the whole matrix no
/// higher in rank than the kept rows (so every dropped row depends on them).
fn assert_valid(jacobian: &Triplets, report: &Report) {
    let a = dense(jacobian);
    let kept = report.kept_rows();
    assert_eq!(kept.len(), report.rank);
    assert_eq!(
        svd_rank(&rows_of(&a, &kept)),
        kept.len(),
        "kept rows are independent"
    );
    assert_eq!(svd_rank(&a), report.rank, "rank agrees with the SVD");
}

fn run(m: &Mechanism) -> Report {
    let report = m
        .analyze(&Options::default())
        .expect("consistent mechanism");
    assert_valid(&m.jacobian(), &report);
    report
}

const Z_OUT_OF_PLANE: [Equation; 3] = [Equation::ZDelta, Equation::ZiXj, Equation::ZiYj];

#[test]
fn parallelogram_four_bar_in_3d_has_three_redundant_equations() {
    // reference-problems §5.2: 3 moving parts, 4 revolutes, Grübler −2, DOF 1, 3 redundant.
    let r = run(&n_four_bar(1, 3, 0.3, 1.0, 1.0));
    assert_eq!((r.columns, r.equations, r.rank), (18, 20, 17));
    assert_eq!((r.grubler(), r.dof(), r.redundant.len()), (-2, 1, 3));
    // The loop-closing joint (JOINT/4) loses its out-of-plane equations.
    assert!(r.redundant.iter().all(|x| x.label.element == 3));
    let mut dropped: Vec<Equation> = r.redundant.iter().map(|x| x.label.equation).collect();
    dropped.reverse();
    assert_eq!(dropped, Z_OUT_OF_PLANE);
    assert!(r.largest_distance() <= r.tolerance);
}

#[test]
fn four_bar_in_2d_has_no_redundant_equation() {
    let r = run(&n_four_bar(1, 2, 0.3, 1.0, 1.0));
    assert_eq!((r.columns, r.equations, r.rank), (9, 8, 8));
    assert_eq!((r.grubler(), r.dof(), r.redundant.len()), (1, 1, 0));
    assert_eq!(r.adams_message(Some("model")), "");
}

#[test]
fn n_four_bar_40_in_3d_has_120_redundant_equations() {
    // reference-problems §5.1: 2N+1 bodies, 3N+1 revolutes, Grübler 1 − 3N, DOF 1, 3N redundant.
    let r = run(&n_four_bar(40, 3, 0.3, 1.0, 1.0));
    assert_eq!((r.grubler(), r.dof(), r.redundant.len()), (1 - 120, 1, 120));
    // Every window's closing joint keeps a JPRIM INLINE.
    assert_eq!(r.advice.len(), 40);
    for a in &r.advice {
        assert_eq!(a.dropped, Z_OUT_OF_PLANE);
        assert_eq!(
            a.lighter,
            Lighter::Replace(vec![ElementKind::Jprim(JprimType::Inline)])
        );
    }
}

#[test]
fn n_four_bar_40_in_2d_has_none() {
    let r = run(&n_four_bar(40, 2, 0.3, 1.0, 1.0));
    assert_eq!((r.grubler(), r.dof(), r.redundant.len()), (1, 1, 0));
}

#[test]
fn n_four_bar_400_in_3d_scales() {
    // The bench's large case: 1200 redundant out of 6005 equations, without a dense oracle.
    let m = n_four_bar(400, 3, 0.3, 1.0, 1.0);
    let r = m.analyze(&Options::default()).unwrap();
    assert_eq!((r.equations, r.dof(), r.redundant.len()), (6005, 1, 1200));
    // Fill stays local: a few times the Jacobian's own non-zeros.
    assert!(
        r.factor_entries < 4 * m.jacobian().entries.len(),
        "{}",
        r.factor_entries
    );
}

#[test]
fn horizontal_n_four_bar_loses_n_more() {
    // reference-problems §4.2, §5.1: at the horizontal position the DOF jump from 1 to
    // N + 1 (in 2D and 3D), on top of the 3N structural redundancies in 3D.
    let horizontal = std::f64::consts::FRAC_PI_2;
    let r = run(&n_four_bar(5, 3, horizontal, 1.0, 1.0));
    assert_eq!((r.dof(), r.redundant.len()), (6, 15 + 5));
    let r = run(&n_four_bar(5, 2, horizontal, 1.0, 1.0));
    assert_eq!((r.dof(), r.redundant.len()), (6, 5));
}

#[test]
fn bricard_has_one_redundant_equation() {
    // reference-problems §4.4: 5 rods, 6 revolutes, Grübler 0, true mobility 1.
    let r = run(&bricard());
    assert_eq!((r.columns, r.equations), (30, 30));
    assert_eq!((r.grubler(), r.dof(), r.redundant.len()), (0, 1, 1));
}

#[test]
fn millimetre_model_gives_the_same_rows_as_metre_model() {
    let metres = run(&n_four_bar(3, 3, 0.3, 1.0, 1.0)).redundant_rows();
    // Rows scaled by the model length, and rows left in millimetres: same decision.
    let scaled = run(&n_four_bar(3, 3, 0.3, 1000.0, 1000.0)).redundant_rows();
    let raw = run(&n_four_bar(3, 3, 0.3, 1000.0, 1.0)).redundant_rows();
    assert_eq!(metres.len(), 9);
    assert_eq!(scaled, metres);
    assert_eq!(raw, metres);
}

#[test]
fn adams_message_lists_elements_then_equations_in_descending_order() {
    // Two windows: JOINT_4 closes the first loop, JOINT_7 the second (fixture order).
    let mut m = n_four_bar(2, 3, 0.3, 1.0, 1.0);
    for c in &mut m.constraints {
        c.element.name = Some(format!("JOINT_{}", c.element.id));
    }
    let r = run(&m);
    let header = "Degree-of-freedom analysis identified redundant constraints in the model:";
    let mut expected = format!("{header}\n{}\n", "-".repeat(73));
    for joint in [7, 4] {
        for eq in ["Zi.Yj", "Zi.Xj", "Z Delta"] {
            expected +=
                &format!(" -  deactivating constraint equation  {eq} in model.JOINT_{joint}\n");
        }
    }
    assert_eq!(r.adams_message(Some("model")), expected);
    assert!(r
        .older_message()
        .starts_with("JOINT_7 unnecessarily removes Rotation Between Zi and Yj\n"));
    // Without a name the element is written as in the dataset.
    assert!(run(&n_four_bar(1, 3, 0.3, 1.0, 1.0))
        .adams_message(None)
        .ends_with(" -  deactivating constraint equation  Z Delta in JOINT/4\n"));
}

#[test]
fn four_bar_advice_names_inline() {
    let r = run(&n_four_bar(1, 3, 0.3, 1.0, 1.0));
    assert_eq!(
        r.advice_message(),
        "JOINT/4 (REVOLUTE) → JPRIM INLINE would remove these 3 redundant equations \
         (Z Delta, Zi.Xj, Zi.Yj)\n"
    );
}

#[test]
fn advice_prefers_a_catalogue_element_over_the_greedy_choice() {
    // Bricard's one redundant equation: the remaining four must be a §4.2 element when
    // a valid choice exists; the only 4-equation subset of a REVOLUTE in the table is
    // CYLINDRICAL (X Delta, Y Delta, Zi.Xj, Zi.Yj), i.e. dropping Z Delta.
    let r = run(&bricard());
    let a = &r.advice[0];
    assert_eq!(a.dropped, [Equation::ZDelta]);
    assert_eq!(
        a.lighter,
        Lighter::Replace(vec![ElementKind::Joint(JointType::Cylindrical)])
    );
}

#[test]
fn gcon_is_kept_and_the_joint_equation_it_repeats_is_dropped() {
    // A GCON repeating JOINT/1's Z Delta (three GCONs DX, DY, DZ make a SPHERICAL, spec
    // §4.3; one of them repeats one equation). GCON rows are offered first, so JOINT/1
    // loses Z Delta and keeps X Delta, Y Delta, Zi.Xj, Zi.Yj: a CYLINDRICAL (§4.2).
    // JOINT/4 still loses its three out-of-plane equations: 4 redundant, DOF 1.
    let m = n_four_bar(1, 3, 0.3, 1.0, 1.0);
    let (mut j, mut labels, mut elements) = (m.jacobian(), m.labels(), m.elements());
    let z_delta = 2;
    assert_eq!(labels[z_delta].equation, Equation::ZDelta);
    let gcon_row = j.nrows;
    j.nrows += 1;
    let copied: Vec<_> = j
        .entries
        .iter()
        .filter(|e| e.0 as usize == z_delta)
        .copied()
        .collect();
    j.entries
        .extend(copied.into_iter().map(|(_, c, v)| (gcon_row as u32, c, v)));
    elements.push(ElementRef {
        kind: ElementKind::Gcon,
        id: 1,
        name: None,
    });
    labels.push(EquationLabel {
        element: elements.len() - 1,
        equation: Equation::Gcon,
    });
    let problem = Problem::new(&j, &labels, &elements, 3, 3);
    let r = analyze(&problem, &Options::default()).unwrap();
    assert_valid(&j, &r);
    assert_eq!((r.dof(), r.redundant.len()), (1, 4));
    assert!(!r.redundant_rows().contains(&gcon_row));
    assert_eq!(r.advice[0].element, 0);
    assert_eq!(r.advice[0].dropped, [Equation::ZDelta]);
    assert!(r.advice_message().starts_with(
        "JOINT/1 (REVOLUTE) → JOINT CYLINDRICAL would remove this redundant equation (Z Delta)\n"
    ));
}

#[test]
fn gcon_with_vanishing_gradient_is_redundant_and_can_go() {
    // Spec §4.2: a GCON UVZ(i)*UVZ(j) - 1 guarding against flipped axes has a zero gradient
    // at the aligned configuration, so Adams flags it redundant. Its row is empty here.
    let m = n_four_bar(1, 3, 0.3, 1.0, 1.0);
    let (mut j, mut labels, mut elements) = (m.jacobian(), m.labels(), m.elements());
    j.nrows += 1;
    elements.push(ElementRef {
        kind: ElementKind::Gcon,
        id: 9,
        name: None,
    });
    labels.push(EquationLabel {
        element: 4,
        equation: Equation::Gcon,
    });
    let r = analyze(
        &Problem::new(&j, &labels, &elements, 3, 3),
        &Options::default(),
    )
    .unwrap();
    assert_eq!((r.dof(), r.redundant.len()), (1, 4));
    assert_eq!(r.redundant[0].label.element, 4);
    assert_eq!(r.advice[1].lighter, Lighter::Remove);
    assert!(r
        .advice_message()
        .ends_with("GCON/9: all its equations are redundant (Gcon); remove it\n"));
}

#[test]
fn violated_redundant_equation_is_a_conflict() {
    // reference-problems §5.5: mismatched ground pivots. Lift JOINT/4's ground marker out
    // of the plane by 0.01: its Z Delta is redundant but has residual −0.01.
    let mut m = n_four_bar(1, 3, 0.3, 1.0, 1.0);
    m.constraints[3].j.origin.z += 0.01;
    match m.analyze(&Options::default()) {
        Err(AnalysisError::Conflicting { conflicts, report }) => {
            assert_eq!(conflicts.len(), 1);
            assert_eq!(conflicts[0].label.element, 3);
            assert_eq!(conflicts[0].label.equation, Equation::ZDelta);
            assert!((conflicts[0].residual + 0.01).abs() < 1e-12);
            assert_eq!(report.redundant.len(), 3);
            let text = AnalysisError::Conflicting { report, conflicts }.to_string();
            assert!(
                text.starts_with("conflicting, not redundant: Z Delta of JOINT/4 (REVOLUTE)"),
                "{text}"
            );
        }
        other => panic!("expected a conflict, got {other:?}"),
    }
    // The same check at a later output step, from the report of a consistent assembly.
    let r = run(&n_four_bar(1, 3, 0.3, 1.0, 1.0));
    let mut later = vec![0.0; r.equations];
    assert!(r.conflicts(&later, 1e-6).is_empty());
    later[r.redundant[0].row] = 2e-6;
    assert_eq!(r.conflicts(&later, 1e-6).len(), 1);
    assert_eq!(r.conflicts(&[], 1e-6).len(), 3);
    // A misaligned hinge axis: JOINT/4's J marker tilted about its x axis.
    let mut m = n_four_bar(1, 3, 0.3, 1.0, 1.0);
    let tilt = nalgebra::Rotation3::from_axis_angle(&Vec3::x_axis(), 0.02);
    m.constraints[3].j.axes = tilt.matrix() * m.constraints[3].j.axes;
    assert!(matches!(
        m.analyze(&Options::default()),
        Err(AnalysisError::Conflicting { .. })
    ));
}

#[test]
fn malformed_input_is_an_error_not_a_panic() {
    let m = n_four_bar(1, 3, 0.3, 1.0, 1.0);
    let (j, labels, elements) = (m.jacobian(), m.labels(), m.elements());
    let problem = Problem::new(&j, &labels, &elements, 3, 3);
    let fails = |p: Problem| {
        matches!(
            analyze(&p, &Options::default()),
            Err(AnalysisError::Shape(_))
        )
    };
    assert!(analyze(&problem, &Options::default()).is_ok());
    assert!(fails(Problem {
        moving_parts: 2,
        ..problem
    }));
    assert!(fails(Problem { dim: 4, ..problem }));
    assert!(fails(Problem {
        labels: &labels[1..],
        ..problem
    }));
    assert!(fails(Problem {
        elements: &elements[..2],
        ..problem
    }));
    assert!(fails(Problem {
        residuals: Some(&[0.0]),
        ..problem
    }));
    let mut nan = j.clone();
    nan.entries[0].2 = f64::NAN;
    assert!(fails(Problem {
        jacobian: &nan,
        ..problem
    }));
}

/// A random sparse matrix B·C of rank at most k with small integer entries, its rows
/// labelled: row 0 a MOTION, the others REVOLUTE joints of up to five rows.
fn low_rank_case() -> impl Strategy<Value = (usize, usize, DMat)> {
    (1usize..=3, prop::bool::ANY, 1usize..=24, 1usize..=12).prop_flat_map(
        |(parts, planar, m, k)| {
            let dim = if planar { 2 } else { 3 };
            let n = parts * if planar { 3 } else { 6 };
            let entry = prop_oneof![3 => Just(0.0), 2 => (-3i32..=3).prop_map(f64::from)];
            (
                Just(dim),
                Just(parts),
                prop::collection::vec(entry.clone(), m * k),
                prop::collection::vec(entry, k * n),
            )
                .prop_map(move |(dim, parts, b, c)| {
                    let b = DMat::from_row_slice(m, k, &b);
                    let c = DMat::from_row_slice(k, n, &c);
                    (dim, parts, b * c)
                })
        },
    )
}

fn revolute_labelled(rows: usize) -> (Vec<EquationLabel>, Vec<ElementRef>) {
    let eqs = super::fixtures::revolute_equations(3);
    let mut elements = vec![ElementRef {
        kind: ElementKind::Motion,
        id: 1,
        name: None,
    }];
    let mut labels = vec![EquationLabel {
        element: 0,
        equation: Equation::Motion,
    }];
    for r in 1..rows {
        let k = (r - 1) % eqs.len();
        if k == 0 {
            elements.push(ElementRef {
                kind: ElementKind::Joint(JointType::Revolute),
                id: elements.len() as u32,
                name: None,
            });
        }
        labels.push(EquationLabel {
            element: elements.len() - 1,
            equation: eqs[k],
        });
    }
    (labels, elements)
}

fn triplets(a: &DMat) -> Triplets {
    let mut t = Triplets::new(a.nrows(), a.ncols());
    for i in 0..a.nrows() {
        for j in 0..a.ncols() {
            t.push(i, j, a[(i, j)]);
        }
    }
    t
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn rank_and_redundant_rows_agree_with_svd((dim, parts, a) in low_rank_case(), scales in prop::collection::vec(-3i32..=3, 18)) {
        // Only matrices whose singular values separate clearly have a well-defined rank.
        let s = a.clone().svd(false, false).singular_values;
        let top = s.max();
        prop_assume!(top > 0.0 && s.iter().all(|&v| v > 1e-5 * top || v < 1e-11 * top));
        let (labels, elements) = revolute_labelled(a.nrows());
        let t = triplets(&a);
        let problem = Problem::new(&t, &labels, &elements, parts, dim);
        let r = analyze(&problem, &Options::default()).unwrap();
        prop_assert_eq!(r.rank, svd_rank(&a));
        prop_assert_eq!(r.redundant.len(), a.nrows() - r.rank);
        prop_assert_eq!(svd_rank(&rows_of(&a, &r.kept_rows())), r.rank);
        // The MOTION row is offered first: kept unless it is zero.
        prop_assert_eq!(r.redundant_rows().contains(&0), a.row(0).iter().all(|&v| v == 0.0));
        // Scaling columns by powers of ten (units) leaves the decision unchanged.
        let scaled = DMat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)] * 10f64.powi(scales[j]));
        let ts = triplets(&scaled);
        let rs = analyze(&Problem { jacobian: &ts, ..problem }, &Options::default()).unwrap();
        prop_assert_eq!(rs.redundant_rows(), r.redundant_rows());
    }
}

/// Any kind of label, equation and element, repeated entries and extreme magnitudes.
fn wild_case() -> impl Strategy<Value = (Triplets, Vec<EquationLabel>, Vec<ElementRef>, usize)> {
    let kinds = prop::sample::select(vec![
        ElementKind::Motion,
        ElementKind::Gcon,
        ElementKind::Prismatic2d,
        ElementKind::Joint(JointType::Revolute),
        ElementKind::Joint(JointType::Fixed),
        ElementKind::Jprim(JprimType::Inline),
    ]);
    let eqs = prop::sample::select(vec![
        Equation::XDelta,
        Equation::YDelta,
        Equation::ZDelta,
        Equation::ZiXj,
        Equation::ZiYj,
        Equation::XiYj,
        Equation::Gcon,
    ]);
    let value = prop_oneof![
        (-3i32..=3).prop_map(f64::from),
        Just(1e308),
        Just(-1e308),
        Just(1e-310),
        Just(1e-30),
    ];
    (1usize..=2, 0usize..=14, prop::collection::vec(kinds, 1..=4)).prop_flat_map(
        move |(parts, rows, kinds)| {
            let n = 6 * parts;
            let nel = kinds.len();
            (
                prop::collection::vec((0..rows.max(1) as u32, 0..n as u32, value.clone()), 0..=40),
                prop::collection::vec((0..nel, eqs.clone()), rows),
                Just(kinds),
                Just(parts),
            )
                .prop_map(move |(entries, labels, kinds, parts)| {
                    let mut t = Triplets::new(rows, n);
                    t.entries = entries
                        .into_iter()
                        .filter(|e| (e.0 as usize) < rows)
                        .collect();
                    let labels = labels
                        .into_iter()
                        .map(|(element, equation)| EquationLabel { element, equation })
                        .collect();
                    let elements = kinds
                        .into_iter()
                        .enumerate()
                        .map(|(i, kind)| ElementRef {
                            kind,
                            id: i as u32,
                            name: None,
                        })
                        .collect();
                    (t, labels, elements, parts)
                })
        },
    )
}

proptest! {
    #[test]
    fn any_input_gives_a_report_or_an_error((t, labels, elements, parts) in wild_case()) {
        match analyze(&Problem::new(&t, &labels, &elements, parts, 3), &Options::default()) {
            Ok(r) => {
                prop_assert_eq!(r.rank + r.redundant.len(), t.nrows);
                prop_assert!(r.rank <= t.ncols);
                let _ = (r.to_string(), r.older_message());
            }
            Err(e) => prop_assert!(matches!(e, AnalysisError::Shape(_)), "{e}"),
        }
    }
}
