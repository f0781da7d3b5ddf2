//! `mbfx run --animate` end to end: every part node's world pose in the .glb (root ×
//! part TRS, read back by the `gltf` crate at every key) against the run's own probes
//! of a marker on the part (DX/DY/DZ, and PSI/THETA/PHI turned into a matrix by the
//! 3-1-3 Euler formula); the CSV byte for byte with and without --animate and
//! --interpolate; and the failures, which leave no file behind.

use crate::validator::validate;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A 3D spherical pendulum in millimeters, gravity along −z: its body spins about an
/// axis it is not symmetric about, so it tumbles. Marker 22 (QP, REULER in the part's
/// BCS, which is global at input) is the one probed.
const PENDULUM_3D: &str = "spherical pendulum\n\
    UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = MILLIMETER, TIME = SECOND\n\
    PART/1, GROUND\nMARKER/10, PART = 1\n\
    PART/2, MASS = 1, CM = 20, IP = 4E3, 9E3, 1.2E4, WX = 2, WY = -1, WZ = 6\n\
    MARKER/20, PART = 2, QP = 100, 50, -300\nMARKER/21, PART = 2\n\
    MARKER/22, PART = 2, QP = 30, -20, 10, REULER = 40D, 60D, 10D\n\
    JOINT/1, SPHERICAL, I = 21, J = 10\nACCGRAV/KGRAV = -9806.65\nEND\n";

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("animate-run");
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    dir.join(name)
}

fn examples(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name)
}

/// `mbfx run ARGS`: exit code, stdout, stderr.
fn mbfx(args: &[&str]) -> (i32, Vec<u8>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .arg("run")
        .args(args)
        .output()
        .expect("mbfx runs");
    (
        out.status.code().unwrap_or(-1),
        out.stdout,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The CSV's header and rows.
fn csv(bytes: &[u8]) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = String::from_utf8(bytes.to_vec()).expect("utf-8");
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("a header")
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().expect("a number")).collect())
        .collect();
    (header, rows)
}

type Pose = (Vector3<f64>, UnitQuaternion<f64>, Vector3<f64>);

fn quat(r: &[f32]) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        r[3] as f64,
        r[0] as f64,
        r[1] as f64,
        r[2] as f64,
    ))
}

fn vec3(v: &[f32]) -> Vector3<f64> {
    Vector3::new(v[0] as f64, v[1] as f64, v[2] as f64)
}

/// The glTF spec's node transform: x ↦ T + R (S ∘ x).
fn apply(p: &Pose, x: &Vector3<f64>) -> Vector3<f64> {
    p.0 + p.1 * p.2.component_mul(x)
}

/// The .glb's key times and, per key, the named part node's local TRS (its channels,
/// else its static TRS), with the root's TRS.
fn part_keys(glb: &[u8], part: &str) -> (Pose, Vec<f32>, Vec<Pose>) {
    let doc = gltf::Gltf::from_slice(glb).expect("the gltf crate reads it");
    let blob = doc.blob.as_deref().expect("a BIN chunk");
    let decomposed = |n: &gltf::Node| -> Pose {
        let (t, r, s) = n.transform().decomposed();
        (vec3(&t), quat(&r), vec3(&s))
    };
    let root = doc
        .nodes()
        .find(|n| n.name() == Some("mbfx"))
        .expect("root");
    let node = doc
        .nodes()
        .find(|n| n.name() == Some(part))
        .expect("part node");
    assert!(
        root.children().any(|c| c.index() == node.index()),
        "{part} under the root"
    );
    let still = decomposed(&node);
    let mut times = Vec::new();
    let mut t: Vec<Vector3<f64>> = Vec::new();
    let mut r: Vec<UnitQuaternion<f64>> = Vec::new();
    for anim in doc.animations() {
        for ch in anim
            .channels()
            .filter(|c| c.target().node().index() == node.index())
        {
            let reader = ch.reader(|_| Some(blob));
            times = reader.read_inputs().expect("inputs").collect();
            use gltf::animation::util::ReadOutputs;
            match reader.read_outputs().expect("outputs") {
                ReadOutputs::Translations(v) => t = v.map(|x| vec3(&x)).collect(),
                ReadOutputs::Rotations(q) => r = q.into_f32().map(|x| quat(&x)).collect(),
                _ => panic!("a part is never scaled"),
            }
        }
    }
    assert_eq!(t.len(), r.len());
    let keys = (0..times.len())
        .map(|k| (t[k], r[k], Vector3::repeat(1.0)))
        .collect::<Vec<_>>();
    let keys = if keys.is_empty() { vec![still] } else { keys };
    (decomposed(&root), times, keys)
}

/// 3-1-3 Euler angles to the rotation matrix R = Rz(ψ)·Rx(θ)·Rz(φ) (Adams' body-fixed
/// 3-1-3 sequence; the spec's formula written out rather than composed).
fn euler_313(psi: f64, theta: f64, phi: f64) -> Matrix3<f64> {
    let (s1, c1) = psi.sin_cos();
    let (s2, c2) = theta.sin_cos();
    let (s3, c3) = phi.sin_cos();
    Matrix3::new(
        c1 * c3 - s1 * c2 * s3,
        -c1 * s3 - s1 * c2 * c3,
        s1 * s2,
        s1 * c3 + c1 * c2 * s3,
        -s1 * s3 + c1 * c2 * c3,
        -c1 * s2,
        s2 * s3,
        s2 * c3,
        c2,
    )
}

/// Runs `dataset` with probes of `marker` and --animate, then checks the part node's
/// world pose × the marker's place on it (`qp`, `reuler` in degrees, from the dataset)
/// against the probes at every key.
fn poses_match_probes(
    dataset: &Path,
    end: &str,
    part: &str,
    marker: u32,
    qp: [f64; 3],
    reuler: [f64; 3],
) {
    let glb = scratch(&format!("{part}-{marker}.glb").replace('/', "_"));
    let probe = |name: &str| format!("{name}={name}({marker})");
    let probes: Vec<String> = ["DX", "DY", "DZ", "PSI", "THETA", "PHI"]
        .iter()
        .map(|n| probe(n))
        .collect();
    let mut args = vec![
        dataset.to_str().unwrap(),
        "--end",
        end,
        "--animate",
        glb.to_str().unwrap(),
    ];
    for p in &probes {
        args.extend(["--probe", p.as_str()]);
    }
    let (code, out, err) = mbfx(&args);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = csv(&out);
    assert_eq!(&header[1..7], ["DX", "DY", "DZ", "PSI", "THETA", "PHI"]);
    let bytes = std::fs::read(&glb).expect("the .glb is written");
    let (root, times, keys) = part_keys(&bytes, part);
    assert_eq!(times.len(), rows.len(), "a key at every row");
    let d = reuler.map(f64::to_radians);
    let on_part = euler_313(d[0], d[1], d[2]);
    let qp = Vector3::from(qp);
    let scale = root.2.x;
    let mut moved = 0.0f64;
    for (k, row) in rows.iter().enumerate() {
        assert!(
            (times[k] as f64 - row[0]).abs() <= 1e-6 * row[0].max(1.0),
            "key {k}"
        );
        let key = &keys[k];
        // The marker in the glTF world: root ∘ part ∘ marker.
        let at = apply(&root, &apply(key, &qp));
        let want = apply(&root, &Vector3::new(row[1], row[2], row[3]));
        // Float32 keys: some ulps of the coordinates and of the marker's arm (model
        // units; the root's scale turns both into meters).
        let err = (at - want).norm() / scale;
        let tol =
            16.0 * f32::EPSILON as f64 * (Vector3::new(row[1], row[2], row[3]).norm() + qp.norm());
        assert!(
            err <= tol,
            "key {k}: marker at {at:?}, probes {want:?} ({err:e} > {tol:e})"
        );
        let turn = root.1.to_rotation_matrix().into_inner()
            * key.1.to_rotation_matrix().into_inner()
            * on_part;
        let probed = root.1.to_rotation_matrix().into_inner() * euler_313(row[4], row[5], row[6]);
        let rerr = (turn - probed).abs().max();
        assert!(rerr < 1e-6, "key {k}: rotation off by {rerr:e}");
        moved = moved.max(
            (Vector3::new(row[1], row[2], row[3])
                - Vector3::new(rows[0][1], rows[0][2], rows[0][3]))
            .norm(),
        );
    }
    assert!(moved > 0.0, "the part moves");
}

#[test]
fn slider_part_poses_are_the_probes() {
    // examples/slider.adm: marker 21 at QP 0.3 on PART/2, REULER 90D, 90D, 0D. (Marker
    // 22 beside it has the BCS's axes, where THETA = 0 leaves PSI and PHI undefined
    // apart: the probes give PSI = π, PHI = 0 for the identity.)
    poses_match_probes(
        &examples("slider.adm"),
        "1",
        "PART/2",
        21,
        [0.3, 0.0, 0.0],
        [90.0, 90.0, 0.0],
    );
}

#[test]
fn pendulum_3d_part_poses_are_the_probes() {
    let path = scratch("pendulum3d.adm");
    std::fs::write(&path, PENDULUM_3D).expect("written");
    poses_match_probes(
        &path,
        "2",
        "PART/2",
        22,
        [30.0, -20.0, 10.0],
        [40.0, 60.0, 10.0],
    );
    // Millimeters: the root scales by 1/1000 and turns +z (against gravity) to +Y.
    let glb = scratch("PART_2-22.glb");
    let (root, _, _) = part_keys(&std::fs::read(glb).unwrap(), "PART/2");
    assert!((root.2.x - 1e-3).abs() < 1e-9);
    assert!((root.1 * Vector3::z() - Vector3::y()).norm() < 1e-6);
}

#[test]
fn csv_is_the_same_bytes_with_and_without_the_animation() {
    let pendulum = scratch("pendulum3d-csv.adm");
    std::fs::write(&pendulum, PENDULUM_3D).expect("written");
    let slider = examples("slider.adm");
    let crank = examples("scenes/slider_crank_driven.adm");
    let glb = scratch("csv.glb");
    let html = scratch("csv.html");
    let datasets = [
        (&slider, "1", "f=DX(22)"),
        (&pendulum, "1", "f=DX(22)"),
        (&crank, "0.5", "f=DX(303)"),
    ];
    for (dataset, end, probe) in datasets {
        for integrator in ["gstiff", "hht", "dopri853"] {
            let base = [
                dataset.to_str().unwrap(),
                "--end",
                end,
                "--integrator",
                integrator,
                "--probe",
                probe,
            ];
            let (code, plain, err) = mbfx(&base);
            assert_eq!(code, 0, "{err}");
            for extra in [
                vec!["--animate", glb.to_str().unwrap()],
                vec!["--animate", glb.to_str().unwrap(), "--interpolate"],
                vec![
                    "--animate",
                    html.to_str().unwrap(),
                    "--interpolate=250",
                    "--glyphs",
                ],
            ] {
                let mut args = base.to_vec();
                args.extend(&extra);
                let (code, out, err) = mbfx(&args);
                assert_eq!(code, 0, "{err}");
                assert!(
                    out == plain,
                    "{} {integrator} {extra:?}: the CSV differs",
                    dataset.display()
                );
            }
        }
    }
}

#[test]
fn interpolated_frames_come_at_the_rate_asked() {
    let glb = scratch("rate.glb");
    let slider = examples("slider.adm");
    let key_times = |flag: &str| {
        let args = [slider.to_str().unwrap(), "--end", "1", "--animate"];
        let (code, _, err) = mbfx(&[&args[..], &[glb.to_str().unwrap(), flag]].concat());
        assert_eq!(code, 0, "{err}");
        part_keys(&std::fs::read(&glb).unwrap(), "PART/2").1
    };
    let times = key_times("--interpolate=50");
    assert_eq!(times.len(), 51);
    for (k, t) in times.iter().enumerate() {
        assert!((*t as f64 - k as f64 / 50.0).abs() < 1e-6);
    }
    assert_eq!(
        key_times("--interpolate").len(),
        61,
        "60 a second by default"
    );
}

#[test]
fn runs_write_files_the_validator_accepts() {
    let pendulum = scratch("pendulum3d-valid.adm");
    std::fs::write(&pendulum, PENDULUM_3D).expect("written");
    let mut files = Vec::new();
    for (dataset, name) in [
        (examples("slider.adm"), "slider"),
        (pendulum, "pendulum"),
        (examples("scenes/slider_crank_driven.adm"), "crank"),
    ] {
        let glb = scratch(&format!("valid-{name}.glb"));
        let (code, _, err) = mbfx(&[
            dataset.to_str().unwrap(),
            "--end",
            "1",
            "--animate",
            glb.to_str().unwrap(),
            "--glyphs",
            "--interpolate",
        ]);
        assert_eq!(code, 0, "{err}");
        files.push(glb);
    }
    let refs: Vec<&Path> = files.iter().map(|p| p.as_path()).collect();
    for r in validate(&refs) {
        assert_eq!(r.errors, 0, "{}: {:?}", r.file, r.messages);
    }
}

#[test]
fn failures_say_why_and_leave_no_file() {
    let slider = examples("slider.adm");
    let dir = scratch("failures");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let listing = || std::fs::read_dir(&dir).unwrap().count();
    // `mbfx run slider.adm --end 1 --animate TARGET EXTRA...`: must fail; its stderr.
    let refused = |target: &Path, extra: &[&str]| {
        let args = [slider.to_str().unwrap(), "--end", "1", "--animate"];
        let (code, out, err) = mbfx(&[&args[..], &[target.to_str().unwrap()], extra].concat());
        assert_ne!(code, 0, "{err}");
        (out, err)
    };
    // An unknown extension: refused before the run, naming the kinds known.
    let (out, err) = refused(&dir.join("run.gltf"), &[]);
    assert!(err.contains(".glb") && err.contains(".html"), "{err}");
    assert!(out.is_empty(), "no row before the refusal");
    assert_eq!(listing(), 0);
    // A mesh file that cannot be read: named, before the run.
    let target = dir.join("run.glb");
    let spec = format!("GRAPHICS/1={}", dir.join("no-such-mesh.stl").display());
    let (_, err) = refused(&target, &["--geometry", &spec]);
    assert!(err.contains("no-such-mesh.stl"), "{err}");
    assert_eq!(listing(), 0, "nothing left behind");
    // A geometry map that cannot be read.
    let map = dir.join("map.toml");
    let (_, err) = refused(&target, &["--geometry", map.to_str().unwrap()]);
    assert!(err.contains("map.toml"), "{err}");
    // A target in a directory that does not exist: refused, no temporary left.
    let (_, err) = refused(&dir.join("missing-dir").join("run.glb"), &[]);
    assert!(err.contains("run.glb"), "{err}");
    assert_eq!(listing(), 0);
    // A rate without --animate.
    let (code, _, err) = mbfx(&[slider.to_str().unwrap(), "--end", "1", "--interpolate=30"]);
    assert_ne!(code, 0);
    assert!(err.contains("--animate"), "{err}");
}
