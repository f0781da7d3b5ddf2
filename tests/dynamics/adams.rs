//! Adams' own output for the chrono joint models (`../shared/corpus/adams/projectchrono__
//! chrono/data/testing/joints/`): a reader for its tab-separated result files and the case
//! table that ties each output folder to the dataset that (nominally) made it, the id of
//! the CM marker, and the expressions Adams' REQUEST/05 used for the reaction.

use std::path::{Path, PathBuf};

/// The chrono joint-test folder in the shared corpus.
pub fn joints_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/corpus/adams/projectchrono__chrono/data/testing/joints")
}

/// `tests/models/` of this repository.
pub fn models_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/models")
}

/// One Adams result file: `Time` plus value columns, rows at 0.01 s from 0 to 5 s.
pub struct Table {
    pub names: Vec<String>,
    pub time: Vec<f64>,
    pub cols: Vec<Vec<f64>>,
}

impl Table {
    /// Reads a file: `#` lines, one header row (`Time X Y Z`), then numbers, tab-separated.
    pub fn read(path: &Path) -> Table {
        let text =
            std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut lines = text
            .lines()
            .filter(|l| !l.starts_with('#') && !l.trim().is_empty());
        let header: Vec<String> = lines
            .next()
            .unwrap_or_else(|| panic!("{}: no header", path.display()))
            .split_whitespace()
            .map(str::to_owned)
            .collect();
        assert_eq!(header[0], "Time", "{}", path.display());
        let mut time = Vec::new();
        let mut cols = vec![Vec::new(); header.len() - 1];
        for line in lines {
            let v: Vec<f64> = line
                .split_whitespace()
                .map(|s| {
                    s.parse()
                        .unwrap_or_else(|e| panic!("{}: {s}: {e}", path.display()))
                })
                .collect();
            assert_eq!(v.len(), header.len(), "{}: {line}", path.display());
            time.push(v[0]);
            for (c, x) in cols.iter_mut().zip(&v[1..]) {
                c.push(*x);
            }
        }
        Table {
            names: header[1..].to_vec(),
            time,
            cols,
        }
    }
}

/// The eight quantities chrono saved per case, with the file suffix and how Adams' own
/// accuracy bounds them (issue 8, section 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    Pos,
    Vel,
    Acc,
    Quat,
    Avel,
    Aacc,
    Rforce,
    Rtorque,
}

pub const QUANTITIES: [Quantity; 8] = [
    Quantity::Pos,
    Quantity::Vel,
    Quantity::Acc,
    Quantity::Quat,
    Quantity::Avel,
    Quantity::Aacc,
    Quantity::Rforce,
    Quantity::Rtorque,
];

impl Quantity {
    pub fn suffix(self) -> &'static str {
        match self {
            Quantity::Pos => "Pos",
            Quantity::Vel => "Vel",
            Quantity::Acc => "Acc",
            Quantity::Quat => "Quat",
            Quantity::Avel => "Avel",
            Quantity::Aacc => "Aacc",
            Quantity::Rforce => "Rforce",
            Quantity::Rtorque => "Rtorque",
        }
    }

    /// The scale of a column with largest magnitude `col_max` in a quantity whose largest
    /// magnitude over all its columns is `q_max`: the column's own, unless it is below 1e-3
    /// of its quantity's; then the column is zero in truth (the out-of-plane components of
    /// a planar swing) and holds only the noise of the other components' computation, so
    /// it is measured against its vector, `q_max`. Adams prints 3e-5 m/s² of out-of-plane
    /// acceleration beside 20 m/s² in Spherical_Case02 (and 5.8e-4 rad/s² of angular
    /// acceleration beside 4.8): "2e-3 of the column" would bound noise by noise.
    pub fn scale(col_max: f64, q_max: f64) -> f64 {
        if col_max < 1e-3 * q_max {
            q_max
        } else {
            col_max
        }
    }

    /// The bound on |value − Adams| (issue 8's figures for Adams' own accuracy). Positions,
    /// Euler parameters and (angular) velocities: absolute, plus 1e-6 of the column (the
    /// files print 7 significant digits). The rest: 2e-3 of the column's [`scale`], plus
    /// [`ROUND_OFF`] for quantities that are zero in truth (a revolute's torque).
    ///
    /// [`scale`]: Quantity::scale
    pub fn adams_bound(self, col_max: f64, q_max: f64) -> f64 {
        match self {
            Quantity::Pos | Quantity::Quat => 2e-3 + 1e-6 * col_max,
            Quantity::Vel | Quantity::Avel => 5e-3 + 1e-6 * col_max,
            _ => 2e-3 * Quantity::scale(col_max, q_max) + ROUND_OFF,
        }
    }
}

/// What a quantity that is zero in truth may show: 1e-7 of the largest reaction of these
/// cases (29 N at Universal_Case02's lowest point), 100 times tighter than the 1e-5 the
/// exact comparisons allow a column with content. Adams prints up to 4e-12 N·m of torque in
/// Universal_Case02's free axes; in mbfx rounding seeds the out-of-plane mode of that
/// symmetric pendulum and generalized-α (ρ∞ = 0.9, little damping) lets it reach
/// 1.7e-6 N·m (HHT: 1.3e-8) by t = 4.24 s.
pub const ROUND_OFF: f64 = 3e-6;

/// What the Rforce/Rtorque files of a case hold, as expressions a probe can evaluate.
/// Three each, ground axes, the load on the part of the element's I marker.
pub struct Reaction {
    pub force: [&'static str; 3],
    pub torque: [&'static str; 3],
}

const JOINT1: Reaction = Reaction {
    force: ["JOINT(1,0,2,0)", "JOINT(1,0,3,0)", "JOINT(1,0,4,0)"],
    torque: ["JOINT(1,0,6,0)", "JOINT(1,0,7,0)", "JOINT(1,0,8,0)"],
};
/// Distance cases: `REQUEST/05, F, I=0102, J=0202, RM=0101` (the GCON's force on ground).
const GCON_102_202: Reaction = Reaction {
    force: ["FX(102,202)", "FY(102,202)", "FZ(102,202)"],
    torque: ["TX(102,202)", "TY(102,202)", "TZ(102,202)"],
};
/// RotSpring: the file's force is the revolute joint's (the dataset's REQUEST/05 asks
/// for SFORCE(1,0,2..4,101), which is zero for a rotational spring, yet the file holds
/// −0.239 N at t = 0, the joint's value of Revolute_Case01) and its torque the spring's
/// (the revolute carries no torque about its axis, the file's Y torque is k·φ + c·φ̇).
/// The sum joint + spring on ground is both.
const ROTSPRING: Reaction = Reaction {
    force: [
        "JOINT(1,0,2,0)+SFORCE(1,0,2,0)",
        "JOINT(1,0,3,0)+SFORCE(1,0,3,0)",
        "JOINT(1,0,4,0)+SFORCE(1,0,4,0)",
    ],
    torque: [
        "JOINT(1,0,6,0)+SFORCE(1,0,6,0)",
        "JOINT(1,0,7,0)+SFORCE(1,0,7,0)",
        "JOINT(1,0,8,0)+SFORCE(1,0,8,0)",
    ],
};
/// TransSpring: `FX(204,205)` … as its REQUEST/05 (the spring's load on ground).
const TRANSSPRING: Reaction = Reaction {
    force: ["FX(204,205)", "FY(204,205)", "FZ(204,205)"],
    torque: ["TX(204,205)", "TY(204,205)", "TZ(204,205)"],
};

/// One chrono case with Adams output.
pub struct Case {
    /// The result-file prefix (`Revolute_Case01`; chrono spells `TranSpring`).
    pub name: &'static str,
    /// The folder under [`joints_dir`] holding the result files.
    pub folder: &'static str,
    /// The dataset under `joints_dir()/adams_models/`.
    pub adm: &'static str,
    /// A copy of the dataset under `tests/models/chrono/` carrying the values the output
    /// was made with, when the dataset does not describe that run.
    pub corrected: Option<&'static str>,
    /// CM marker of the moving part (the results are of it relative to ground marker 101).
    pub cm: u32,
    pub reaction: &'static Reaction,
}

impl Case {
    pub fn file(&self, q: Quantity) -> PathBuf {
        joints_dir()
            .join(self.folder)
            .join(format!("{}_ADAMS_{}.txt", self.name, q.suffix()))
    }

    pub fn table(&self, q: Quantity) -> Table {
        Table::read(&self.file(q))
    }

    pub fn dataset(&self) -> PathBuf {
        joints_dir().join("adams_models").join(self.adm)
    }

    /// The dataset that reproduces the output: the corrected copy when there is one.
    pub fn model(&self) -> PathBuf {
        match self.corrected {
            Some(c) => models_dir().join("chrono").join(c),
            None => self.dataset(),
        }
    }
}

macro_rules! case {
    ($name:literal, $folder:literal, $reaction:expr) => {
        case!($name, $folder, $reaction, None)
    };
    ($name:literal, $folder:literal, $reaction:expr, $corrected:expr) => {
        Case {
            name: $name,
            folder: $folder,
            adm: concat!("test_", $name, ".adm"),
            corrected: $corrected,
            cm: 201,
            reaction: $reaction,
        }
    };
}

/// Every chrono case with Adams output (18: the RackPinion model has none).
pub const CASES: [Case; 18] = [
    case!("Revolute_Case01", "revolute_joint", &JOINT1),
    case!("Revolute_Case02", "revolute_joint", &JOINT1),
    case!("Spherical_Case01", "spherical_joint", &JOINT1),
    case!("Spherical_Case02", "spherical_joint", &JOINT1),
    case!("Universal_Case01", "universal_joint", &JOINT1),
    case!("Universal_Case02", "universal_joint", &JOINT1),
    case!("Universal_Case03", "universal_joint", &JOINT1),
    case!("Prismatic_Case01", "prismatic_joint", &JOINT1),
    case!("Prismatic_Case02", "prismatic_joint", &JOINT1),
    case!("Prismatic_Case03", "prismatic_joint", &JOINT1),
    case!("Cylindrical_Case01", "cylindrical_joint", &JOINT1),
    case!("Cylindrical_Case02", "cylindrical_joint", &JOINT1),
    case!("Cylindrical_Case03", "cylindrical_joint", &JOINT1),
    case!("Distance_Case01", "distance_constraint", &GCON_102_202),
    case!("Distance_Case02", "distance_constraint", &GCON_102_202),
    case!("Distance_Case03", "distance_constraint", &GCON_102_202),
    case!(
        "RotSpring_Case01",
        "rotspring_force",
        &ROTSPRING,
        Some("test_RotSpring_Case01.adm")
    ),
    Case {
        name: "TranSpring_Case01",
        folder: "transpring_force",
        adm: "test_TransSpring_Case01.adm",
        corrected: Some("test_TransSpring_Case01.adm"),
        cm: 201,
        reaction: &TRANSSPRING,
    },
];

pub fn case(name: &str) -> &'static Case {
    CASES
        .iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no case {name}"))
}

#[test]
fn every_case_has_all_eight_files_on_the_output_grid() {
    for c in &CASES {
        assert!(c.dataset().is_file(), "{}", c.dataset().display());
        assert!(c.model().is_file(), "{}", c.model().display());
        for q in QUANTITIES {
            let t = c.table(q);
            let width = if q == Quantity::Quat { 4 } else { 3 };
            assert_eq!(t.cols.len(), width, "{} {q:?}", c.name);
            assert_eq!(t.time.len(), 501, "{} {q:?}", c.name);
            for (k, &tk) in t.time.iter().enumerate() {
                assert!(
                    (tk - k as f64 * 0.01).abs() < 1e-9,
                    "{} {q:?} row {k}",
                    c.name
                );
            }
        }
    }
}

#[test]
fn the_reader_keeps_seven_digits() {
    // Revolute_Case01 Pos, second row: +1.000000E-02 +2.000000E+00 +0.000000E+00 -4.783730E-04.
    let t = case("Revolute_Case01").table(Quantity::Pos);
    assert_eq!(t.names, ["X_Pos", "Y_Pos", "Z_Pos"]);
    assert_eq!(
        (t.time[1], t.cols[0][1], t.cols[2][1]),
        (0.01, 2.0, -4.783730e-4)
    );
}
