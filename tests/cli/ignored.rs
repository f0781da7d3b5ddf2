//! `mbfx run` never drops physics silently (issue 40 §0): every statement the model
//! leaves out that could change the motion (a CONTACT, a COUPLER, a USER subroutine) is
//! a W0602 warning once per kind with its count, and a line of the run's summary; with
//! `--strict` the run exits 3. Output and data statements (GRAPHICS, MATERIAL,
//! PREFERENCES) stay quiet. The datasets are written here, so the truth is what Adams
//! would model, not what mbfx does.

use super::{mbfx, scratch_file, Run};

/// A cylinder falling onto a box: Adams stops it there, and so does mbfx since issue 40
/// §1 models the CONTACT.
const CONTACT: &str = "cylinder falls onto a box
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/10, PART = 1
GRAPHICS/10, BOX, CORNER = 10, X = 1, Y = 1, Z = 0.1
PART/2, MASS = 1, CM = 20, IP = 1, 1, 1
MARKER/20, PART = 2, QP = 0.5, 0.5, 0.5
GRAPHICS/20, CYLINDER, CM = 20, RADIUS = 0.1, LENGTH = 0.2
CONTACT/1, IGEOM = 20, JGEOM = 10, IMPACT, STIFFNESS = 1E5, DAMPING = 10, DMAX = 1E-3, EXPONENT = 1.5
ACCGRAV/KGRAV = -9.81
END
";

/// A pendulum coupled to itself (twice: COUPLER is outside the subset) and a USER
/// torque.
const COUPLED: &str = "pendulum with couplers
PART/1, GROUND
MARKER/10, PART = 1
PART/2, MASS = 1, CM = 20, IP = 1, 1, 1
MARKER/20, PART = 2, QP = 1, 0, 0
MARKER/21, PART = 2
JOINT/1, REVOLUTE, I = 21, J = 10
COUPLER/1, JOINTS = 1, 1, SCALES = 1, -1
COUPLER/2, JOINTS = 1, 1, SCALES = 1, -1
SFORCE/3, ROTATIONAL, I = 21, J = 10, FUNCTION = USER(1, 2)
ACCGRAV/JGRAV = -9.81
END
";

/// The pendulum with statements that change nothing physical.
const QUIET: &str = "pendulum with display and material
PREFERENCES/CONTACT_GEOMETRY_LIBRARY = Default_library
PART/1, GROUND
MARKER/10, PART = 1
PART/2, MASS = 1, CM = 20, IP = 1, 1, 1
MARKER/20, PART = 2, QP = 1, 0, 0
MARKER/21, PART = 2
MATERIAL/1, NAME = steel, DENSITY = 7801, YOUNGS_MODULUS = 2.07E11, POISSONS_RATIO = 0.29
GRAPHICS/1, CYLINDER, CM = 20, RADIUS = 0.1, LENGTH = 0.2
JOINT/1, REVOLUTE, I = 21, J = 10
ACCGRAV/JGRAV = -9.81
END
";

/// `mbfx run` of `path` to `end` with `extra` options, the rows thrown away.
fn run(path: &std::path::Path, end: &str, extra: &[&str]) -> Run {
    let path = path.to_str().expect("a UTF-8 path");
    let base = [
        "run",
        "--color",
        "never",
        path,
        "--end",
        end,
        "--csv",
        "/dev/null",
    ];
    mbfx(&[&base[..], extra].concat())
}

/// `run` of a dataset text.
fn run_text(name: &str, text: &str, extra: &[&str]) -> Run {
    run(&scratch_file(name, text.as_bytes()), "0.1", extra)
}

#[test]
fn a_modelled_contact_is_not_named_as_left_out() {
    let plain = run_text("contact.adm", CONTACT, &[]);
    assert_eq!(plain.code, 0, "{}", plain.describe());
    assert!(!plain.stderr.contains("W0602"), "{}", plain.describe());
    assert!(
        !plain.stderr.contains("not modelled"),
        "{}",
        plain.describe()
    );
}

#[test]
fn couplers_and_user_subroutines_are_counted_once_per_kind() {
    let plain = run_text("coupled.adm", COUPLED, &[]);
    assert_eq!(plain.code, 0, "{}", plain.describe());
    let d = plain.describe();
    assert!(
        d.contains("COUPLER is outside the mbfx subset: 2 statements ignored"),
        "{d}"
    );
    assert!(d.contains("COUPLER/1 (line 8), COUPLER/2 (line 9)"), "{d}");
    assert!(d.contains("1 statement with a USER subroutine"), "{d}");
    assert!(d.contains("SFORCE/3 (line 10)"), "{d}");
    let summary =
        "not modelled: 2 COUPLER, 1 USER subroutine — the results leave out their physics";
    assert_eq!(plain.stderr.matches(summary).count(), 1, "{d}");
    let strict = run_text("coupled.adm", COUPLED, &["--strict"]);
    assert_eq!(strict.code, 3, "{}", strict.describe());
}

#[test]
fn output_and_data_statements_stay_quiet() {
    let quiet = run_text("quiet.adm", QUIET, &["--strict"]);
    assert_eq!(quiet.code, 0, "{}", quiet.describe());
    assert!(!quiet.stderr.contains("W0602"), "{}", quiet.describe());
    assert!(
        !quiet.stderr.contains("not modelled"),
        "{}",
        quiet.describe()
    );
    // `check` still lists those outside the subset; GRAPHICS is read, and counted.
    let check = super::check(&scratch_file("quiet.adm", QUIET.as_bytes()));
    assert!(
        check.stdout.contains("graphics: 1 CYLINDER"),
        "{}",
        check.describe()
    );
    assert!(!check.stderr.contains("GRAPHICS"), "{}", check.describe());
    for kind in ["PREFERENCES", "MATERIAL"] {
        let said = format!("{kind} is outside the mbfx subset: 1 statement ignored");
        assert!(
            check.stdout.contains(&said) || check.stderr.contains(&said),
            "{}",
            check.describe()
        );
    }
}

/// A dataset of the shared corpus.
fn corpus(path: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/corpus/adams")
        .join(path)
}

#[test]
fn the_corpus_frictions_run_and_its_contact_is_named() {
    // RD3's 12 joint FRICTIONs are modelled (issue 40 §2): nothing is left out, and it
    // runs the second its RD3.msg shows Adams running (t = 0 to 1).
    let rd3 = run(&corpus("ssernap__T_MSC_ADAMS/RD3.adm"), "1", &[]);
    assert_eq!(rd3.code, 0, "{}", rd3.describe());
    assert!(
        !rd3.stderr.contains("FRICTION is outside"),
        "{}",
        rd3.describe()
    );
    assert!(!rd3.stderr.contains("not modelled"), "{}", rd3.describe());
    let contact = run(
        &corpus("bthornton191__aview_hpc/test/models/test_2.adm"),
        "0.01",
        &[],
    );
    // Its CONTACT is modelled (issue 40 §1): not named as left out.
    assert_eq!(contact.code, 0, "{}", contact.describe());
    assert!(
        !contact
            .stderr
            .contains("CONTACT is outside the mbfx subset"),
        "{}",
        contact.describe()
    );
    assert!(
        !contact.stderr.contains("not modelled"),
        "{}",
        contact.describe()
    );
}
