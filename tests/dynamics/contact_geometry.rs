//! Contact geometry's issue 40 gaps against closed forms written here: a mesh cube on a
//! mesh slab given with `--geometry` alone (no `--animate`) and a sphere on a GRAPHICS
//! PLANE, each at rest at (m g / k)^(1/e); stand-in boxes that overlap at the start,
//! held out with a warning until they separate, then a contact at the same rest depth;
//! and the corpus datasets whose stand-ins overlap at the start.

use crate::run::{last, named, run_probed, run_raw, test_data as data, Csv};
use std::path::{Path, PathBuf};

const G: f64 = 9.80665;

/// The rest depth of 1 kg on an IMPACT contact of k = 1E5, e = 1.5.
fn rest_depth() -> f64 {
    (G / 1e5).powf(1.0 / 1.5)
}

/// Writes the OBJ of the box between `lo` and `hi` to `path` (12 triangles, wound
/// outward).
fn write_box(path: &Path, lo: [f64; 3], hi: [f64; 3]) {
    let mut text = String::new();
    for k in 0..8 {
        let c = |i: usize| if k >> i & 1 == 1 { hi[i] } else { lo[i] };
        text += &format!("v {} {} {}\n", c(0), c(1), c(2));
    }
    let faces = [
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
    ];
    for f in faces {
        text += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn a_mesh_cube_rests_on_a_mesh_slab_given_with_geometry_alone() {
    let dir = std::env::temp_dir().join(format!("mbfx-mesh-rest-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (slab, cube) = (dir.join("slab.obj"), dir.join("cube.obj"));
    write_box(&slab, [-1.0, -0.2, -1.0], [1.0, 0.0, 1.0]);
    write_box(&cube, [-0.1; 3], [0.1; 3]);
    let slab_arg = format!("GRAPHICS/11={}", slab.display());
    let cube_arg = format!("GRAPHICS/21={}", cube.display());
    let args = [
        "--end",
        "1",
        "--output-step",
        "0.01",
        "--error",
        "1e-5",
        "--geometry",
        &slab_arg,
        "--geometry",
        &cube_arg,
    ];
    let out = run_raw(&data("contact_mesh_rest.adm"), &args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("without a mesh"), "{stderr}");
    let csv = Csv::parse(&String::from_utf8_lossy(&out.stdout));
    let want = rest_depth();
    let pen = last(&csv.col("CONTACT1.PEN"));
    assert!((pen - want).abs() < 1e-2 * want, "{pen} {want}");
    assert!((last(&csv.col("CONTACT1.FN")) - G).abs() < 1e-3 * G);
    // A mesh file that cannot be read is an error naming it, --animate or not.
    let missing = format!("GRAPHICS/21={}", dir.join("no-such.obj").display());
    let out = run_raw(
        &data("contact_mesh_rest.adm"),
        &[
            "--end",
            "0.1",
            "--geometry",
            &slab_arg,
            "--geometry",
            &missing,
        ],
    );
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no-such.obj"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_sphere_rests_on_a_plane_at_the_static_depth() {
    let args = ["--end", "1", "--output-step", "0.01", "--error", "1e-5"];
    let csv = run_probed(
        &data("contact_plane_rest.adm"),
        &args,
        &named(&[("y", "DY(20)")]),
    );
    let want = rest_depth();
    // The plane is y = 0; the sphere's radius 0.1.
    let depth = 0.1 - last(&csv.col("y"));
    assert!((depth - want).abs() < 1e-2 * want, "{depth} {want}");
    assert!((last(&csv.col("CONTACT1.FN")) - G).abs() < 1e-3 * G);
}

#[test]
fn stand_ins_overlapping_at_the_start_are_held_out_until_they_separate() {
    let args = [
        "--end",
        "2",
        "--output-step",
        "0.01",
        "--error",
        "1e-5",
        "--probe",
        "y=DY(20)",
    ];
    let out = run_raw(&data("contact_stand_in_overlap.adm"), &args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let held = "CONTACT/1: GRAPHICS/21 and GRAPHICS/31 overlap by 0.01 at the start";
    assert_eq!(stderr.matches(held).count(), 1, "{stderr}");
    let csv = Csv::parse(&String::from_utf8_lossy(&out.stdout));
    let (t, y, f) = (csv.col("time"), csv.col("y"), csv.col("CONTACT1.FN"));
    // Leaving at 1 m/s, no force while the boxes overlap: free flight, y = 0.19 + t −
    // g t²/2, until the cube's bottom (y − 0.1) clears the base's top (0.1).
    for k in 0..t.len() {
        let free = 0.19 + t[k] - G * t[k] * t[k] / 2.0;
        if free - 0.2 > 0.0 || t[k] > 0.05 {
            break;
        }
        assert_eq!(f[k], 0.0, "t = {}", t[k]);
        assert!((y[k] - free).abs() < 1e-6, "t = {}: {} {free}", t[k], y[k]);
    }
    // Released once apart, it falls back and rests on the base.
    let want = rest_depth();
    let depth = 0.2 - last(&y);
    assert!((depth - want).abs() < 1e-2 * want, "{depth} {want}");
    assert!((last(&f) - G).abs() < 1e-3 * G);
}

/// The corpus dataset `rel`.
fn corpus(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/corpus/adams")
        .join(rel)
}

#[test]
fn the_exoskeleton_plants_run_with_their_overlapping_stand_ins_held_out() {
    // Their EXTERNAL geometry (a Parasolid file) is not in the corpus; the stand-in
    // boxes of CONTACT/4 (and /6 in the co-simulation plant) overlap at the start.
    for rel in [
        "aniket0112__exoskeleton/load-analysis/pd-control/Controls_Plant_1.adm",
        "aniket0112__exoskeleton/load-analysis/LQR-control/lqr_control_plant.adm",
        "aniket0112__exoskeleton/ADAMS-MATLAB_Cosimulation/Controls_Plant_1.adm",
    ] {
        let out = run_raw(&corpus(rel), &["--end", "0.1", "--output-step", "0.01"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{rel}: {stderr}");
        assert!(
            stderr.contains("CONTACT/4: GRAPHICS/7 and GRAPHICS/4 overlap"),
            "{rel}: {stderr}"
        );
    }
}
