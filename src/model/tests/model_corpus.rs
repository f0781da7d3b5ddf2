//! The model reader on every `.adm` file of `shared/corpus/adams`: each loads with no
//! errors, or is listed in [`INVALID`] with the exact set of error codes it must give and
//! why. Element counts of a set of files are compared with an independent scan of the
//! raw text (statement heads at the start of a line, up to `END`).

use super::corpus_files::adm_files;
use crate::model::{decode, read_model};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Files that must give errors: path under `corpus/adams`, every error code, and why.
/// All are samples of MBDyn's a2m translator that exercise its error handling.
const INVALID: &[(&str, &[&str], &str)] = &[
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/bipendolo.adm",
        &["E0601"],
        "an edited export that lost its title line, so line 2 continues no statement",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/bipendololeo.adm",
        &["E0604", "E0606"],
        "a GFORCE without FY and FZ, and JFLOAT markers that are not FLOATING",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/mark.adm",
        &["E0311", "E0606"],
        "four MARKER lines only: no GROUND, and the PARTs they name do not exist",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/monster.adm",
        &["E0301", "E0302", "E0601", "E0603", "E0604", "E0606"],
        "four datasets pasted together: unknown function COSIN, undefined names, VARIABLE \
         ids defined twice, a GFORCE without torques and a fixed JFLOAT marker",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/pm02.adm",
        &["E0101", "E0311", "E0601", "E0604", "E0606", "E0608"],
        "statements continued without a comma, `^` as a power, no GROUND, missing markers, \
         IP = 10, 20, 30, 45, 60, 70 (principal moments -96.7, 58.1, 98.6: not a body's)",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/pm03.adm",
        &["E0201", "E0301", "E0302", "E0311", "E0604", "E0606"],
        "no GROUND, expressions measuring markers the dataset does not define, fixed \
         JFLOAT markers, force elements without components",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/prova.adm",
        &[
            "E0302", "E0311", "E0601", "E0603", "E0604", "E0606", "E0608",
        ],
        "garbage arguments, ids defined twice (PART/1, MARKER/1, JOINT/1, ...), \
         references to markers that are not defined, IP = 10, 20, 30, 40, 50, 60 (principal \
         moment -80)",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/prova_beam00.adm",
        &["E0311", "E0604", "E0606"],
        "markers without PART and no GROUND; the BEAM (read since issue 40) names those \
         markers, which are therefore not defined",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/prova_beam01.adm",
        &["E0311", "E0604", "E0605", "E0606"],
        "a BEAM alone: no GROUND part, no markers for its I and J, IZ = 30,5,1,4 (four \
         numbers) and no EMODULUS or GMODULUS",
    ),
    (
        "alex-marinov__mbdyn/contrib/a2m/samples/prova_marker01.adm",
        &["E0311", "E0601", "E0606", "E0608"],
        "statements continued without a comma, no GROUND, CM markers not defined, IP \
         tensors with a negative principal moment",
    ),
];

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/adams")
}

fn load(path: &Path) -> String {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    decode(&bytes).0.into_owned()
}

fn rel(path: &Path) -> String {
    path.strip_prefix(corpus())
        .expect("under the corpus")
        .to_string_lossy()
        .replace('\\', "/")
}

#[test]
fn every_corpus_dataset_loads_or_fails_as_listed() {
    let files = adm_files(&corpus());
    assert!(files.len() >= 70, "only {} files", files.len());
    let mut problems = Vec::new();
    for path in &files {
        let name = rel(path);
        let text = load(path);
        let r = read_model(&text);
        let got: BTreeSet<&str> = r
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| d.code.as_str())
            .collect();
        let want: BTreeSet<&str> = INVALID
            .iter()
            .find(|(f, _, _)| *f == name)
            .map(|(_, codes, _)| codes.iter().copied().collect())
            .unwrap_or_default();
        if got != want {
            let first = r.diagnostics.iter().find(|d| d.is_error());
            problems.push(format!(
                "{name}: errors {got:?}, want {want:?}; first {first:?}"
            ));
        }
        if let Some(d) = r.diagnostics.iter().find(|d| d.span.end > text.len()) {
            problems.push(format!("{name}: span outside the file: {d:?}"));
        }
        if want.is_empty() && r.model.ground().is_none() {
            problems.push(format!("{name}: no ground part"));
        }
    }
    for (f, _, _) in INVALID {
        if !files.iter().any(|p| rel(p) == *f) {
            problems.push(format!("{f}: listed but not in the corpus"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// Statement heads `KIND/` at the start of a line (after blanks), from line 2 to `END`.
fn count_heads(text: &str, kind: &str) -> usize {
    let mut n = 0;
    for line in text.lines().skip(1) {
        let t = line.trim_start();
        if t.trim_end().eq_ignore_ascii_case("END") {
            break;
        }
        let head = t.split('/').next().unwrap_or("");
        if t.contains('/') && head.trim().eq_ignore_ascii_case(kind) {
            n += 1;
        }
    }
    n
}

#[test]
fn element_counts_match_a_scan_of_the_file() {
    let mut files = adm_files(&corpus().join("projectchrono__chrono"));
    for f in [
        "bthornton191__adamspy/test/files/generic_model/generic_model.adm",
        "ssernap__T_MSC_ADAMS/RD3.adm",
        "old-NWTC__FAST/CertTest/Old_Adams_files/Test02_ADAMS.adm",
        "MarcinPiotrowski__MultiBodySystemDynamics/test/LWR_6DOF_GRABER.adm",
        "kiterunner347__3-RPR-parallel--robot/RPRAdams/RPR3.adm",
    ] {
        files.push(corpus().join(f));
    }
    assert!(files.len() >= 24, "{} files", files.len());
    let mut problems = Vec::new();
    for path in &files {
        let text = load(path);
        let m = read_model(&text).model;
        let counts = [
            ("PART", m.parts.len()),
            ("MARKER", m.markers.len()),
            ("JOINT", m.joints.len()),
            ("JPRIM", m.jprims.len()),
            ("MOTION", m.motions.len()),
            ("REQUEST", m.requests.len()),
        ];
        for (kind, got) in counts {
            let want = count_heads(&text, kind);
            if got != want {
                problems.push(format!("{}: {kind} {got}, the file has {want}", rel(path)));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn chrono_joint_models_load_without_errors() {
    let dir = corpus().join("projectchrono__chrono/data/testing/joints/adams_models");
    let files = adm_files(&dir);
    assert!(files.len() >= 19, "{} files", files.len());
    for path in &files {
        let r = read_model(&load(path));
        let errors: Vec<_> = r.diagnostics.iter().filter(|d| d.is_error()).collect();
        assert!(errors.is_empty(), "{}: {errors:#?}", rel(path));
        assert_eq!(r.model.units.ucf, 1.0, "{}", rel(path));
        assert!(r.model.ground().is_some());
    }
}

/// Truncated datasets and datasets missing one line never panic, and every span stays
/// inside the text.
#[test]
fn damaged_datasets_never_panic() {
    let text = load(&corpus().join(
        "projectchrono__chrono/data/testing/joints/adams_models/test_TransSpring_Case01.adm",
    ));
    let lines: Vec<&str> = text.split_inclusive('\n').collect();
    let mut variants: Vec<String> = (0..text.len())
        .step_by(3)
        .filter(|&cut| text.is_char_boundary(cut))
        .map(|cut| text[..cut].to_string())
        .collect();
    variants.extend((0..lines.len()).map(|skip| {
        lines
            .iter()
            .enumerate()
            .filter(|(k, _)| *k != skip)
            .map(|(_, l)| *l)
            .collect()
    }));
    assert!(variants.len() > 100);
    for v in &variants {
        let r = read_model(v);
        for d in &r.diagnostics {
            assert!(d.span.end <= v.len(), "{d:?} in {v:?}");
        }
    }
}

/// Every orientation the corpus gives (REULER, ZP/XP, ZG/XG) becomes a rotation matrix.
#[test]
fn every_corpus_orientation_is_a_rotation() {
    let files = adm_files(&corpus());
    let mut checked = 0;
    for path in &files {
        let m = read_model(&load(path)).model;
        let frames = m
            .parts
            .iter()
            .map(|p| (p.el.id, p.orientation))
            .chain(m.markers.iter().map(|mk| (mk.el.id, mk.orientation)));
        for (id, r) in frames {
            let err = (r.transpose() * r - crate::vocab::math::Mat3::identity())
                .abs()
                .max();
            assert!(
                err < 1e-9 && (r.determinant() - 1.0).abs() < 1e-9,
                "{}: element {id}: {r}",
                rel(path)
            );
            checked += 1;
        }
    }
    // 8,803 MARKER and 1,148 PART statements start a line in the corpus files.
    assert!(checked > 9_000, "{checked} frames");
}

/// generic_model.adm (spec §1.5, §2.1, §9.3): IPS units, `MOTION/1, JOINT = 1` drives the
/// JOINT although a JPRIM/1 exists, and its function is `30.0d * time`.
#[test]
fn generic_model_matches_the_spec() {
    let path = corpus().join("bthornton191__adamspy/test/files/generic_model/generic_model.adm");
    let r = read_model(&load(&path));
    assert!(!r.has_errors(), "{:#?}", r.diagnostics);
    let m = r.model;
    assert!((m.units.ucf - 386.0886).abs() < 1e-3, "{}", m.units.ucf);
    assert!(m.jprims.iter().any(|j| j.el.id == 1));
    let motion = m.motions.iter().find(|mo| mo.el.id == 1).expect("MOTION/1");
    assert!(matches!(
        motion.target,
        crate::model::elements::MotionTarget::Joint {
            joint: 1,
            rotation: true
        }
    ));
    assert!(m.joint(1).is_some());
}
