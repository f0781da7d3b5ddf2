//! Acceptance tests of the multibody pipeline on the shared `.adm` corpus
//! (`../shared/corpus/adams`): read → build → assemble at t = 0 → redundancy.
//!
//! Truth comes from outside the code: Adams' own output for chrono's joint tests (the
//! first row of `…_ADAMS_Pos/Vel/Avel/Quat.txt`), the redundancy table of multibody spec
//! §5.4 (counts Adams printed in its .msg files, and the spec author's independent
//! prototype), and the dataset's own positions for an assembled mechanism. Every corpus
//! file either passes or is listed here with the exact reason it cannot yet.

mod common;

use common::adm_files;
use mbfx::mbd::pipeline::{analyze_model, Analysis, DimRequest, Failure};
use mbfx::mbd::{Dimension, System};
use mbfx::model::Model;
use mbfx::vocab::math::{Mat3, Quat, Vec3};
use std::path::{Path, PathBuf};

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/adams")
}

fn read(path: &Path) -> Model {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (text, _) = mbfx::model::decode(&bytes);
    let read = mbfx::model::read_model(&text);
    assert!(!read.has_errors(), "{}: reader errors", path.display());
    read.model
}

fn analyze(path: &Path, dim: DimRequest) -> Analysis {
    analyze_model(&read(path), dim).unwrap_or_else(|f| panic!("{}: {f}", path.display()))
}

/// `path` ends with `tail` (as text: `adamspy/…` matches `bthornton191__adamspy/…`).
fn ends_with(path: &Path, tail: &str) -> bool {
    path.to_string_lossy().replace('\\', "/").ends_with(tail)
}

fn find(name: &str) -> PathBuf {
    let hits: Vec<PathBuf> = adm_files(&corpus())
        .into_iter()
        .filter(|p| ends_with(p, name))
        .collect();
    assert_eq!(hits.len(), 1, "{name}: {hits:?}");
    hits[0].clone()
}

// ---------------------------------------------------------------------------------
// Chrono's joint tests against Adams' reference output.

const CHRONO: &str = "projectchrono__chrono/data/testing/joints";

/// Dataset → Adams reference stem (directory/prefix), from chrono's test layout.
const CHRONO_REFERENCES: [(&str, Option<&str>); 19] = [
    (
        "test_Cylindrical_Case01",
        Some("cylindrical_joint/Cylindrical_Case01"),
    ),
    (
        "test_Cylindrical_Case02",
        Some("cylindrical_joint/Cylindrical_Case02"),
    ),
    (
        "test_Cylindrical_Case03",
        Some("cylindrical_joint/Cylindrical_Case03"),
    ),
    (
        "test_Distance_Case01",
        Some("distance_constraint/Distance_Case01"),
    ),
    (
        "test_Distance_Case02",
        Some("distance_constraint/Distance_Case02"),
    ),
    (
        "test_Distance_Case03",
        Some("distance_constraint/Distance_Case03"),
    ),
    (
        "test_Prismatic_Case01",
        Some("prismatic_joint/Prismatic_Case01"),
    ),
    (
        "test_Prismatic_Case02",
        Some("prismatic_joint/Prismatic_Case02"),
    ),
    (
        "test_Prismatic_Case03",
        Some("prismatic_joint/Prismatic_Case03"),
    ),
    // Chrono publishes no Adams output for its rack-and-pinion case (spec §0 item 6).
    ("test_RackPinion_Case01", None),
    (
        "test_Revolute_Case01",
        Some("revolute_joint/Revolute_Case01"),
    ),
    (
        "test_Revolute_Case02",
        Some("revolute_joint/Revolute_Case02"),
    ),
    (
        "test_RotSpring_Case01",
        Some("rotspring_force/RotSpring_Case01"),
    ),
    (
        "test_Spherical_Case01",
        Some("spherical_joint/Spherical_Case01"),
    ),
    (
        "test_Spherical_Case02",
        Some("spherical_joint/Spherical_Case02"),
    ),
    // Compared separately: the dataset does not describe chrono's Case01 set-up.
    ("test_TransSpring_Case01", None),
    (
        "test_Universal_Case01",
        Some("universal_joint/Universal_Case01"),
    ),
    (
        "test_Universal_Case02",
        Some("universal_joint/Universal_Case02"),
    ),
    (
        "test_Universal_Case03",
        Some("universal_joint/Universal_Case03"),
    ),
];

/// The first data row of an Adams reference file (after the `Time` header), time
/// included, and the column names.
fn first_row(path: &Path) -> (Vec<String>, Vec<f64>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(String::from)
        .collect();
    let row: Vec<f64> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(header.len(), row.len(), "{}", path.display());
    assert_eq!(header[0], "Time");
    assert_eq!(row[0], 0.0, "{}: first row is not t = 0", path.display());
    (header, row)
}

/// What chrono's REQUESTs 1, 2 and 4 measure: marker 201 relative to marker 101 (position,
/// velocity and angular velocity in 101's axes, Euler parameters of 201 in 101).
struct Measured {
    pos: Vec3,
    vel: Vec3,
    avel: Vec3,
    quat: Quat,
}

fn measure(sys: &System, i: u32, j: u32) -> Measured {
    let fi = sys.frame(Some(sys.marker_by_id(i).expect("marker I")));
    let fj = sys.frame(Some(sys.marker_by_id(j).expect("marker J")));
    let pi = sys.part(fi.part);
    let pj = sys.part(fj.part);
    let point_vel = |p: &mbfx::mbd::system::Part, a: Vec3| p.v + p.w.cross(&a);
    let rj_t = fj.rot.transpose();
    let rel: Mat3 = rj_t * fi.rot;
    Measured {
        pos: rj_t * (fi.r - fj.r),
        vel: rj_t * (point_vel(pi, fi.a) - point_vel(pj, fj.a)),
        avel: rj_t * (pi.w - pj.w),
        quat: Quat::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(rel)),
    }
}

const REFERENCE_TOL: f64 = 1e-6;

/// The one comparison held to a looser bound, and why: Adams' first row of
/// Universal_Case03 prints the CM at x = y = +1.414210E+00, while the dataset's own
/// `QP = 1.414213562373095, 1.414213562373095, 0` (MARKER/0201) is 3.6e-6 away. The dataset
/// is assembled as written (0 iterations), so the reference was not computed from these
/// exact coordinates; 1e-6 is not reachable from this file.
const LOOSER: (&str, &str, f64) = ("test_Universal_Case03", "position", 4e-6);

fn close(stem: &str, what: &str, ours: &[f64], adams: &[f64]) -> Result<(), String> {
    let tol = if (stem, what) == (LOOSER.0, LOOSER.1) {
        LOOSER.2
    } else {
        REFERENCE_TOL
    };
    let worst = ours
        .iter()
        .zip(adams)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    if worst <= tol {
        Ok(())
    } else {
        Err(format!("{what}: ours {ours:?}, Adams {adams:?}"))
    }
}

#[test]
fn chrono_joint_models_assemble_onto_adams_first_rows() {
    let dir = corpus().join(CHRONO);
    let files = adm_files(&dir.join("adams_models"));
    assert_eq!(files.len(), CHRONO_REFERENCES.len(), "{files:?}");
    let mut failures = Vec::new();
    let mut compared = 0;
    for ((stem, reference), dim) in CHRONO_REFERENCES
        .iter()
        .flat_map(|c| [(*c, DimRequest::Auto), (*c, DimRequest::Three)])
    {
        let path = dir.join("adams_models").join(format!("{stem}.adm"));
        let a = analyze(&path, dim);
        assert!(a.assembly.residual <= 1e-10, "{stem}");
        let Some(reference) = reference else {
            if stem == "test_RackPinion_Case01" {
                // No reference output: only the absence is asserted, so a file
                // appearing later makes this fail and be compared.
                let name = format!("{}_ADAMS_Pos.txt", stem.trim_start_matches("test_"));
                assert!(
                    !files_named(&dir, &name),
                    "{stem}: a reference appeared; compare it"
                );
            }
            continue;
        };
        let m = measure(&a.system, 201, 101);
        let file = |kind: &str| dir.join(format!("{reference}_ADAMS_{kind}.txt"));
        let (h, pos) = first_row(&file("Pos"));
        assert_eq!(h[1..], ["X_Pos", "Y_Pos", "Z_Pos"]);
        let (h, vel) = first_row(&file("Vel"));
        assert_eq!(h[1..], ["X_Vel", "Y_Vel", "Z_Vel"]);
        let (h, avel) = first_row(&file("Avel"));
        assert_eq!(h[1..], ["X_AngVel", "Y_AngVel", "Z_AngVel"]);
        let (h, quat) = first_row(&file("Quat"));
        assert_eq!(h[1..], ["e0", "e1", "e2", "e3"]);
        let q = m.quat.quaternion();
        let ours = [q.w, q.i, q.j, q.k];
        // q and −q are one orientation.
        let sign = if ours.iter().zip(&quat[1..]).map(|(a, b)| a * b).sum::<f64>() < 0.0 {
            -1.0
        } else {
            1.0
        };
        let ours_q: Vec<f64> = ours.iter().map(|x| sign * x).collect();
        for r in [
            close(stem, "position", m.pos.as_slice(), &pos[1..]),
            close(stem, "velocity", m.vel.as_slice(), &vel[1..]),
            close(stem, "angular velocity", m.avel.as_slice(), &avel[1..]),
            close(stem, "Euler parameters", &ours_q, &quat[1..]),
        ] {
            if let Err(e) = r {
                failures.push(format!("{stem} ({dim:?}): {e}"));
            }
        }
        compared += 1;
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert_eq!(compared, 2 * 17);
}

/// Every data row of an Adams reference file (time first).
fn all_rows(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("Time"))
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect()
}

#[test]
fn chrono_scenes_built_in_2d_stay_in_their_plane_in_adams() {
    // A scene built in 2D claims its parts never leave the plane. Adams' trajectory of
    // the CM (every row of …_ADAMS_Pos.txt) must then keep the normal coordinate.
    let dir = corpus().join(CHRONO);
    let mut wrong = Vec::new();
    let mut planar = 0;
    for (stem, reference) in CHRONO_REFERENCES {
        let Some(reference) = reference else { continue };
        let a = analyze(
            &dir.join("adams_models").join(format!("{stem}.adm")),
            DimRequest::Auto,
        );
        if a.system.dim != Dimension::Two {
            continue;
        }
        planar += 1;
        let n = a.system.normal;
        let rows = all_rows(&dir.join(format!("{reference}_ADAMS_Pos.txt")));
        let (lo, hi) = rows
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                (lo.min(r[1 + n]), hi.max(r[1 + n]))
            });
        if hi - lo > 1e-6 {
            wrong.push(format!(
                "{stem}: {}; Adams moves the CM from {lo} to {hi} along the normal",
                a.system.dim_reason
            ));
        }
    }
    assert!(planar > 0);
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn transspring_case01_dataset_does_not_match_its_reference() {
    // test_TransSpring_Case01.adm is a copy of another case: its title reads
    // `test_Distance_Case01`, its SFORCE acts between markers 204 and 205 that it never
    // defines, and it puts PART/2's CM (MARKER/201) at (0, 2, 0). Chrono's
    // TranSpring_Case01 reference starts at (0, 0, 0), so the t = 0 states cannot agree;
    // both facts are asserted so that a corrected dataset makes this test fail.
    let dir = corpus().join(CHRONO);
    let a = analyze(
        &dir.join("adams_models/test_TransSpring_Case01.adm"),
        DimRequest::Auto,
    );
    let m = measure(&a.system, 201, 101);
    let (_, pos) = first_row(&dir.join("transpring_force/TranSpring_Case01_ADAMS_Pos.txt"));
    assert_eq!(pos[1..], [0.0, 0.0, 0.0]);
    assert!(
        (m.pos - Vec3::new(0.0, 2.0, 0.0)).amax() <= 1e-12,
        "{:?}",
        m.pos
    );
}

fn files_named(dir: &Path, name: &str) -> bool {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .filter(|e| e.path().is_dir())
        .any(|d| d.path().join(name).exists())
}

// ---------------------------------------------------------------------------------
// Redundancy counts of multibody spec §5.4.

struct Expected {
    file: &'static str,
    moving_parts: usize,
    equations: Option<usize>,
    rank: Option<usize>,
    redundant: usize,
    dof: usize,
}

/// Spec §5.4: the table (Adams .msg counts) and the prototype's figures below it. Counted
/// in 3D (6 columns per moving part).
const SPEC_5_4: [Expected; 7] = [
    Expected {
        file: "adamspy/test/files/generic_model/generic_model.adm",
        moving_parts: 2,
        equations: Some(13),
        rank: Some(12),
        redundant: 1,
        dof: 0,
    },
    Expected {
        file: "ControlSimulink/Controls_Plant_5.adm",
        moving_parts: 15,
        equations: Some(111),
        rank: Some(89),
        redundant: 22,
        dof: 1,
    },
    Expected {
        file: "T_MSC_ADAMS/RD3.adm",
        moving_parts: 10,
        equations: Some(57),
        rank: Some(51),
        redundant: 6,
        dof: 9,
    },
    Expected {
        file: "RPRAdams/RPR3.adm",
        moving_parts: 11,
        equations: Some(88),
        rank: Some(63),
        redundant: 25,
        dof: 3,
    },
    Expected {
        file: "MultiBodySystemDynamics/test/LWR_6DOF_GRABER.adm",
        moving_parts: 7,
        equations: None,
        rank: None,
        redundant: 0,
        dof: 7,
    },
    // Its MOTION/1 reads VARVAL(192), a VARIABLE whose FUNCTION is 0.
    Expected {
        file: "bachelor-diploma/Only_AGV.adm",
        moving_parts: 15,
        equations: None,
        rank: None,
        redundant: 2,
        dof: 10,
    },
    Expected {
        file: "RL_with_Continuous_Action_Space/pendulum.adm",
        moving_parts: 2,
        equations: None,
        rank: None,
        redundant: 0,
        dof: 1,
    },
];

#[test]
fn redundancy_counts_reproduce_spec_5_4() {
    for e in &SPEC_5_4 {
        let a = analyze(&find(e.file), DimRequest::Three);
        let r = &a.redundancy;
        let got = (
            r.moving_parts,
            e.equations.map(|_| r.equations),
            e.rank.map(|_| r.rank),
            r.redundant.len(),
            r.dof(),
        );
        let want = (e.moving_parts, e.equations, e.rank, e.redundant, e.dof);
        assert_eq!(got, want, "{}: {r}", e.file);
        // The Adams-worded report has one line per redundant equation.
        let lines = r.adams_message(Some("model"));
        assert_eq!(
            lines.matches("deactivating constraint equation").count(),
            e.redundant
        );
        // Spec §5.2: the dropped set must be valid. Oracle: singular values of the dense
        // scaled Jacobian; the kept rows alone have full rank and the rank of all rows.
        let j = dense_jacobian(&a.system);
        let kept = r.kept_rows();
        let kept_j = j.select_rows(kept.iter());
        assert_eq!(svd_rank(&j), r.rank, "{}", e.file);
        assert_eq!(svd_rank(&kept_j), kept.len(), "{}", e.file);
    }
}

/// The equations Adams deactivated at its first degree-of-freedom analysis, read from
/// its .msg file: (element name, equation label).
fn adams_deactivated(msg: &str) -> Vec<(String, String)> {
    msg.lines()
        .skip_while(|l| !l.contains("Degree-of-freedom analysis identified redundant"))
        .skip(2)
        .map_while(|l| l.split_once("deactivating constraint equation"))
        .map(|(_, rest)| {
            let (label, element) = rest.trim().split_once(" in ").unwrap();
            let name = element.split_once('.').map_or(element, |(_, n)| n);
            (name.to_string(), label.trim().to_string())
        })
        .collect()
}

#[test]
fn adams_msg_reports_agree_with_the_analysis() {
    // Adams' own output for three corpus models: the count of deactivated equations is
    // ours, and removing exactly Adams' equations leaves a full-rank Jacobian of our rank
    // (spec §5.2: counts and validity must match, labels need not).
    for (adm, msg) in [
        (
            "adamspy/test/files/generic_model/generic_model.adm",
            "generic_model.msg",
        ),
        (
            "ControlSimulink/Controls_Plant_5.adm",
            "Controls_Plant_5.msg",
        ),
        ("T_MSC_ADAMS/RD3.adm", "RD3.msg"),
    ] {
        let path = find(adm);
        let text = std::fs::read_to_string(path.with_file_name(msg)).unwrap();
        let dropped = adams_deactivated(&text);
        let a = analyze(&path, DimRequest::Three);
        assert_eq!(dropped.len(), a.redundancy.redundant.len(), "{adm}");
        let (labels, refs) = (a.system.labels(), a.system.element_refs());
        let row_of = |(name, label): &(String, String)| {
            let rows: Vec<usize> = (0..labels.len())
                .filter(|&r| {
                    refs[labels[r].element].name.as_deref() == Some(name.as_str())
                        && labels[r].equation.label() == label
                })
                .collect();
            assert_eq!(rows.len(), 1, "{adm}: {label} in {name}");
            rows[0]
        };
        let removed: Vec<usize> = dropped.iter().map(row_of).collect();
        let kept: Vec<usize> = (0..labels.len()).filter(|r| !removed.contains(r)).collect();
        let j = dense_jacobian(&a.system);
        assert_eq!(kept.len(), a.redundancy.rank, "{adm}");
        assert_eq!(svd_rank(&j.select_rows(kept.iter())), kept.len(), "{adm}");
    }
}

fn dense_jacobian(sys: &System) -> nalgebra::DMatrix<f64> {
    let t = sys.jacobian(true).unwrap();
    let mut m = nalgebra::DMatrix::zeros(t.nrows, t.ncols);
    for &(r, c, x) in &t.entries {
        m[(r as usize, c as usize)] += x;
    }
    m
}

/// Numerical rank: singular values above 1e-9 of the largest.
fn svd_rank(m: &nalgebra::DMatrix<f64>) -> usize {
    let sv = m.clone().svd(false, false).singular_values;
    let top = sv.max();
    sv.iter().filter(|&&s| s > 1e-9 * top).count()
}

/// A pendulum of length 1 whose bob starts at (0.6, 0.8): GCON/1 holds
/// `VARVAL(2) - 1.4·DM = 0` with VARIABLE/2 = 2·VARVAL(1) − 0.2 and VARIABLE/1 = DX, so
/// the assembled bob has DX = (1.4 + 0.2)/2 = 0.8.
const VARIABLE_PENDULUM: &str = "pendulum with variables\nPART/1, GROUND\nMARKER/10, PART = 1\n\
    PART/2, MASS = 1, CM = 20\nMARKER/20, PART = 2, QP = 0.6, 0.8, 0\nMARKER/21, PART = 2\n\
    JOINT/1, REVOLUTE, I = 21, J = 10\nVARIABLE/1, FUNCTION = DX(20, 10)\n\
    VARIABLE/2, FUNCTION = 2*VARVAL(1) - 0.2\nGCON/1, FUNCTION = VARVAL(2) - 1.4*DM(20, 10)\nEND\n";

#[test]
fn gcons_read_variables_through_their_expressions() {
    for dim in [DimRequest::Auto, DimRequest::Three] {
        let a = mbfx::mbd::pipeline::analyze_dataset(VARIABLE_PENDULUM, dim).unwrap();
        assert_eq!((a.redundancy.redundant.len(), a.redundancy.dof()), (0, 0));
        let p = a.system.frame(a.system.marker_by_id(20)).r;
        assert!(
            (p[0] - 0.8).abs() < 1e-9 && (p[1] - 0.6).abs() < 1e-9,
            "{p:?}"
        );
    }
    // VARIABLE/1 reading VARIABLE/2 closes a loop: named, not solved.
    let cyclic = VARIABLE_PENDULUM.replace("DX(20, 10)\n", "DX(20, 10) + VARVAL(2)\n");
    let err = mbfx::mbd::pipeline::analyze_dataset(&cyclic, DimRequest::Auto)
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.contains("VARIABLE/2 → VARIABLE/1 → VARIABLE/2: an implicit VARIABLE"),
        "{err}"
    );
}

/// The pendulum of [`VARIABLE_PENDULUM`] held by a GCON on spline values: SPLINE/1 holds
/// y = x at five knots, which Akima's and the natural cubic fit both reproduce exactly,
/// so `AKISPL(DX, 0, 1) + CUBSPL(DX, 0, 1) = 1.6` puts the bob at DX = 0.8.
#[test]
fn gcons_read_splines() {
    let text = "pendulum on a spline\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 1, CM = 20\nMARKER/20, PART = 2, QP = 0.6, 0.8, 0\nMARKER/21, PART = 2\n\
        JOINT/1, REVOLUTE, I = 21, J = 10\n\
        SPLINE/1, X = 0, 0.25, 0.5, 0.75, 1, Y = 0, 0.25, 0.5, 0.75, 1\n\
        GCON/1, FUNCTION = AKISPL(DX(20, 10), 0, 1) + CUBSPL(DX(20, 10), 0, 1) - 1.6\nEND\n";
    for dim in [DimRequest::Auto, DimRequest::Three] {
        let a = mbfx::mbd::pipeline::analyze_dataset(text, dim).unwrap();
        let p = a.system.frame(a.system.marker_by_id(20)).r;
        assert!(
            (p[0] - 0.8).abs() < 1e-9 && (p[1] - 0.6).abs() < 1e-9,
            "{p:?}"
        );
    }
    // Three knots are too few for either fit (spec: at least 4): a reader error.
    let short = text.replace("0, 0.25, 0.5, 0.75, 1", "0, 0.5, 1");
    let read = mbfx::model::read_model(&short);
    let e = read
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .expect("an error");
    assert_eq!(e.message, "X takes at least 4 numbers, found 3");
}

#[test]
fn chrono_joint_models_have_no_redundant_equations() {
    // Spec §5.4: "All 19 chrono joint cases: 0 redundant".
    for path in adm_files(&corpus().join(CHRONO).join("adams_models")) {
        let a = analyze(&path, DimRequest::Three);
        assert!(a.redundancy.redundant.is_empty(), "{}", path.display());
    }
}

#[test]
fn generic_model_in_2d_keeps_the_dof_of_3d_without_the_redundant_equation() {
    // The planar build leaves out the out-of-plane rows, among them the one Adams
    // deactivates (Zi.Xj of JOINT_2), so nothing is redundant and the DOF stays 0.
    let a = analyze(
        &find("adamspy/test/files/generic_model/generic_model.adm"),
        DimRequest::Two,
    );
    assert_eq!(a.system.dim, Dimension::Two);
    assert_eq!((a.redundancy.redundant.len(), a.redundancy.dof()), (0, 0));
}

// ---------------------------------------------------------------------------------
// 2D and 3D builds of planar scenes.

/// Moves every moving part in the plane normal to global axis `normal` (0 = X, 1 = Y,
/// 2 = Z): a shift along the two in-plane axes and a turn about the normal.
fn perturb(model: &mut Model, scale: f64, normal: usize) {
    let (a, b) = ((normal + 1) % 3, (normal + 2) % 3);
    let axis = nalgebra::Unit::new_normalize(Vec3::ith(normal, 1.0));
    for (k, p) in model.parts.iter_mut().filter(|p| !p.ground).enumerate() {
        let s = scale * (1.0 + 0.37 * k as f64);
        p.position[a] += 0.8 * s;
        p.position[b] -= 0.5 * s;
        let turn = nalgebra::Rotation3::from_axis_angle(&axis, 0.3 * s / scale.max(1.0));
        p.orientation = turn.into_inner() * p.orientation;
    }
}

fn poses(sys: &System) -> Vec<(Vec3, Mat3)> {
    sys.parts
        .iter()
        .map(|p| (p.r, p.rot.to_rotation_matrix().into_inner()))
        .collect()
}

fn largest_pose_gap(a: &[(Vec3, Mat3)], b: &[(Vec3, Mat3)]) -> f64 {
    a.iter()
        .zip(b)
        .map(|((ra, ma), (rb, mb))| (ra - rb).amax().max((ma - mb).amax()))
        .fold(0.0, f64::max)
}

#[test]
fn planar_scenes_assemble_alike_in_2d_and_3d() {
    let files = [
        "adamspy/test/files/generic_model/generic_model.adm",
        "adams_rescale/models/rescale_analysis.adm",
        "adaptive_arm_simulink/Controls_Plant_1.adm",
        "adams_models/test_Revolute_Case01.adm",
    ];
    for f in files {
        let original = read(&find(f));
        let mut model = original.clone();
        // A small in-plane misplacement, in model lengths.
        let planar = analyze_model(&original, DimRequest::Two)
            .unwrap_or_else(|e| panic!("{f}: {e}"))
            .system;
        let length = planar.length;
        perturb(&mut model, 0.01 * length, planar.normal);
        let two = analyze_model(&model, DimRequest::Two).unwrap_or_else(|e| panic!("{f}: {e}"));
        let three = analyze_model(&model, DimRequest::Three).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert_eq!(two.system.dim, Dimension::Two, "{f}");
        assert_eq!(three.system.dim, Dimension::Three, "{f}");
        assert!(
            two.assembly.iterations > 0,
            "{f}: the perturbation did nothing"
        );
        let gap = largest_pose_gap(&poses(&two.system), &poses(&three.system));
        assert!(
            gap <= 1e-9 * length.max(1.0),
            "{f}: 2D and 3D differ by {gap}"
        );
        // The 2D count has only the in-plane freedoms (a spherical joint keeps 1, not 3).
        assert!(two.redundancy.dof() <= three.redundancy.dof(), "{f}");
    }
}

#[test]
fn generic_model_reassembles_onto_its_dataset_in_2d_and_3d() {
    // DOF 0 (spec §5.4): the assembled configuration is unique, so a misplaced copy must
    // come back to the positions the dataset gives.
    let original = read(&find("adamspy/test/files/generic_model/generic_model.adm"));
    let reference = analyze_model(&original, DimRequest::Three).unwrap();
    assert_eq!(reference.assembly.iterations, 0, "the dataset is assembled");
    let mut model = original.clone();
    perturb(&mut model, 0.02 * reference.system.length, 2);
    for dim in [DimRequest::Two, DimRequest::Three] {
        let a = analyze_model(&model, dim).unwrap();
        let from_file: Vec<(Vec3, Mat3)> = original
            .parts
            .iter()
            .map(|p| (p.position, p.orientation))
            .collect();
        let ours: Vec<(Vec3, Mat3)> = original
            .parts
            .iter()
            .map(|p| {
                let h = a
                    .system
                    .parts
                    .iter()
                    .find(|q| q.id == Some(p.el.id))
                    .unwrap();
                (h.bcs_origin(), h.rot.to_rotation_matrix().into_inner())
            })
            .collect();
        let gap = largest_pose_gap(&ours, &from_file);
        assert!(
            gap <= 1e-8 * reference.system.length,
            "{dim:?}: {gap} from the dataset"
        );
    }
}

// ---------------------------------------------------------------------------------
// The whole corpus.

/// Files that do not get through the pipeline, with the reason.
const NOT_ANALYSED: [(&str, &str); 10] = [
    // Synthetic MBDyn translator samples: the reader reports errors (the codes are listed
    // in src/model/model_corpus_tests.rs).
    ("mbdyn/contrib/a2m/samples/bipendolo.adm", "read"),
    ("mbdyn/contrib/a2m/samples/bipendololeo.adm", "read"),
    ("mbdyn/contrib/a2m/samples/mark.adm", "read"),
    ("mbdyn/contrib/a2m/samples/monster.adm", "read"),
    ("mbdyn/contrib/a2m/samples/pm02.adm", "read"),
    ("mbdyn/contrib/a2m/samples/pm03.adm", "read"),
    ("mbdyn/contrib/a2m/samples/prova.adm", "read"),
    ("mbdyn/contrib/a2m/samples/prova_beam00.adm", "read"),
    ("mbdyn/contrib/a2m/samples/prova_beam01.adm", "read"),
    ("mbdyn/contrib/a2m/samples/prova_marker01.adm", "read"),
];

#[test]
fn every_corpus_dataset_is_analysed_or_listed_with_its_reason() {
    let files = adm_files(&corpus());
    assert_eq!(files.len(), 75);
    let mut wrong = Vec::new();
    let mut analysed = 0;
    for path in &files {
        let bytes = std::fs::read(path).unwrap();
        let (text, _) = mbfx::model::decode(&bytes);
        let listed = NOT_ANALYSED.iter().find(|(f, _)| ends_with(path, f));
        let auto = mbfx::mbd::pipeline::analyze_dataset(&text, DimRequest::Auto);
        // The 3D build of a scene built in 2D must assemble as well.
        if let Ok(a) = &auto {
            if a.system.dim == Dimension::Two {
                if let Err(f) = mbfx::mbd::pipeline::analyze_dataset(&text, DimRequest::Three) {
                    wrong.push(format!("{} in 3D: {f}", path.display()));
                }
            }
        }
        match (auto, listed) {
            (Ok(a), None) => {
                analysed += 1;
                if a.assembly.residual > 1e-10 {
                    wrong.push(format!(
                        "{}: residual {}",
                        path.display(),
                        a.assembly.residual
                    ));
                }
            }
            (Ok(_), Some(_)) => wrong.push(format!("{}: analysed now; unlist it", path.display())),
            (Err(Failure::Read(_)), Some((_, "read"))) => {}
            (Err(f), Some((_, why))) if f.to_string().contains(why) => {}
            (Err(f), _) => wrong.push(format!("{}: {f}", path.display())),
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    assert_eq!(analysed, 75 - NOT_ANALYSED.len());
}

// ---------------------------------------------------------------------------------
// `mbfx check` on datasets.

fn check(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .args(["--color", "never", "check"])
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

const FOUR_BAR: &str = "tests/data/models/four_bar.adm";
const CONFLICTING: &str = "tests/data/models/conflicting_four_bar.adm";

#[test]
fn check_reports_the_planar_four_bar_in_2d_and_in_3d() {
    // Reference-problems §5.1: the four-bar has 1 DOF; in 2D Grübler 1 and nothing
    // redundant, in 3D Grübler −2 and 3 redundant equations.
    let (code, out, err) = check(&[FOUR_BAR]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("built in 2D: every part stays in the global XY plane"),
        "{out}"
    );
    assert!(
        out.contains("Gruebler count 1 (3·3 moving parts − 8 equations)"),
        "{out}"
    );
    assert!(
        out.contains("actual 1 (rank 8 of 8 equations; 0 redundant)"),
        "{out}"
    );
    assert!(out.contains("redundant constraints:\n    none"), "{out}");
    // Crank 1 starts 0.02 m off its pin (the dataset's QG).
    assert!(out.contains("largest part move 2.000e-2 (PART/2)"), "{out}");

    let (code, out, err) = check(&["--dim", "3", FOUR_BAR]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("built in 3D: asked for with --dim 3"), "{out}");
    assert!(
        out.contains("Gruebler count -2 (6·3 moving parts − 20 equations)"),
        "{out}"
    );
    assert!(
        out.contains("actual 1 (rank 17 of 20 equations; 3 redundant)"),
        "{out}"
    );
    assert!(
        out.contains("Degree-of-freedom analysis identified redundant constraints in the model:")
    );
    assert_eq!(
        out.matches(" -  deactivating constraint equation  ")
            .count(),
        3
    );
    assert!(
        out.contains("→ JPRIM INLINE would remove these 3 redundant equations"),
        "{out}"
    );
}

#[test]
fn check_fails_on_conflicting_constraints_and_on_a_2d_request_it_cannot_meet() {
    let (code, out, err) = check(&[CONFLICTING]);
    assert_eq!(code, 1);
    assert!(
        err.contains("[E0702]") && err.contains("conflicting, not redundant"),
        "{err}"
    );
    assert!(err.contains("JOINT_"), "{err}");
    assert!(
        out.contains(
            "built in 3D: JOINT/2 (REVOLUTE) 'JOINT_2' (Z Delta) is violated out of the XY plane"
        ),
        "{out}"
    );
    assert!(out.contains("1 errors"), "{out}");

    let (code, _, err) = check(&["--dim", "2", CONFLICTING]);
    assert_eq!(code, 1);
    assert!(err.contains("cannot be built in 2D: JOINT/2"), "{err}");

    let (code, _, err) = check(&["--dim", "4", FOUR_BAR]);
    assert_ne!(code, 0, "{err}");
}

#[test]
fn check_warns_when_the_core_cannot_analyse_a_valid_dataset() {
    let (code, _, err) = check(&["tests/data/models/implicit_variable.adm"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("[W0703]") && err.contains("VARIABLE/1 → VARIABLE/1: an implicit VARIABLE"),
        "{err}"
    );
}

// ---------------------------------------------------------------------------------
// Units of measure (issue 24): the census of every unit warning.

/// Every W0312 warning of a dataset text and of probe expressions checked against it:
/// `name:line: message [`quoted text`]`.
fn unit_warnings(name: &str, text: &str, probes: &[&str]) -> Vec<String> {
    use mbfx::check::units::infer_text;
    use mbfx::check::Scope;
    use mbfx::diag::{Code, SourceFile};
    let read = mbfx::model::read_model(text);
    let file = SourceFile::new(name, text);
    let mut out: Vec<String> = read
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::UnitMismatch)
        .map(|d| {
            let (line, _) = file.line_col(d.span.start);
            let quoted = text.get(d.span.clone()).unwrap_or("?").replace('\n', " ");
            format!("{name}:{line}: {} [`{quoted}`]", d.message)
        })
        .collect();
    let scope = read.scope();
    for p in probes {
        if let Ok((_, warnings)) = infer_text(p, scope, scope.unit_names()) {
            for d in warnings {
                out.push(format!("{name}: probe `{p}`: {}", d.message));
            }
        }
    }
    out
}

/// The units census: the corpus (the chrono datasets among it), the project's examples,
/// its test models and the bench scenes (generated ones too, and their probes). Every
/// warning is in `tests/data/units_census.txt`, each inspected by hand and explained in
/// docs/units.md as a true inconsistency; a new one (a rule that fires falsely, or a new
/// file) fails here until it is inspected too.
#[test]
fn units_census_lists_every_warning() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut found = Vec::new();
    let dirs = [
        (corpus(), "corpus"),
        (root.join("examples"), "examples"),
        (root.join("tests/models"), "tests/models"),
        (root.join("tests/data/models"), "tests/data/models"),
    ];
    let mut files = 0;
    for (dir, label) in &dirs {
        for path in adm_files(dir) {
            let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let (text, _) = mbfx::model::decode(&bytes);
            let rel = path
                .strip_prefix(dir)
                .unwrap_or(&path)
                .to_string_lossy()
                .replace('\\', "/");
            found.extend(unit_warnings(&format!("{label}/{rel}"), &text, &[]));
            files += 1;
        }
    }
    let scenes = mbfx::bench::scene::load_dir(&root.join("examples/scenes")).expect("scenes");
    for s in &scenes {
        let text = s.dataset_text().expect("scene dataset");
        let probes: Vec<&str> = s.probes.iter().map(|p| p.expr.as_str()).collect();
        found.extend(unit_warnings(&format!("scene {}", s.name), &text, &probes));
    }
    assert!(files > 120, "only {files} datasets");
    let listed =
        std::fs::read_to_string(root.join("tests/data/units_census.txt")).unwrap_or_default();
    let listed: Vec<&str> = listed
        .lines()
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .collect();
    assert_eq!(found, listed, "\n{}", found.join("\n"));
}
