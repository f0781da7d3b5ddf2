//! The .glb writer on scenes made by hand (a box on a moving part, a spring stretching
//! between two parts, a force arrow), read back by the `gltf` crate and checked by the
//! Khronos validator: the structure the conventions ask for, and poses recomputed here
//! from the frames by the glTF spec's TRS composition.

use crate::validator::validate;
use mbfx::scene::{
    Anchor, ArrowSource, Frames, Item, Mesh, Motion, PartNode, Pose, Role, Scene, Topology,
};

/// A unit cube's 8 corners and 12 triangles (normals along the corners' directions).
fn cube(color: [f32; 4]) -> Mesh {
    let positions: Vec<[f32; 3]> = (0..8)
        .map(|k| [(k & 1) as f32, ((k >> 1) & 1) as f32, ((k >> 2) & 1) as f32])
        .collect();
    let normals = positions
        .iter()
        .map(|p| {
            let v = p.map(|x| x - 0.5);
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            v.map(|x| x / n)
        })
        .collect();
    let indices = vec![
        0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6,
        1, 3, 5, 3, 7, 5,
    ];
    Mesh {
        positions,
        normals,
        indices,
        topology: Topology::Triangles,
        color,
    }
}

fn line(color: [f32; 4]) -> Mesh {
    Mesh {
        positions: vec![[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
        normals: Vec::new(),
        indices: vec![0, 1],
        topology: Topology::Lines,
        color,
    }
}

fn quat_z(angle: f64) -> [f64; 4] {
    [0.0, 0.0, (angle / 2.0).sin(), (angle / 2.0).cos()]
}

/// Ground, and part 2 turning about z at 1 rad/s and sliding along x, with a box on it,
/// a spring from ground's origin to a point on part 2 and an arrow at part 2.
fn scene_and_frames(up: [f64; 3]) -> (Scene, Frames) {
    let parts = vec![
        PartNode {
            id: 1,
            view_name: Some("ground".into()),
            ground: true,
            input: Pose::IDENTITY,
        },
        PartNode {
            id: 2,
            view_name: Some("crank".into()),
            ground: false,
            input: Pose::IDENTITY,
        },
        // Still, but assembled away from its input pose.
        PartNode {
            id: 3,
            view_name: None,
            ground: false,
            input: Pose::IDENTITY,
        },
    ];
    let item = |name: &str, mesh, role, motion| Item {
        name: name.into(),
        view_name: None,
        part: 1,
        local: Pose {
            translation: [0.1, 0.2, 0.3],
            rotation: quat_z(0.5),
        },
        mesh,
        role,
        motion,
    };
    let items = vec![
        item("GRAPHICS/1", 0, Role::Graphic, Motion::Rigid),
        Item {
            local: Pose::IDENTITY,
            ..item(
                "GRAPHICS/2",
                1,
                Role::Graphic,
                Motion::Stretch {
                    from: Anchor {
                        part: 0,
                        point: [0.0, 0.0, 0.0],
                    },
                    to: Anchor {
                        part: 1,
                        point: [1.0, 0.0, 0.0],
                    },
                },
            )
        },
        Item {
            local: Pose::IDENTITY,
            ..item(
                "GRAPHICS/3",
                1,
                Role::Arrow,
                Motion::Arrow {
                    at: Anchor {
                        part: 1,
                        point: [0.0, 0.0, 0.0],
                    },
                    arrow: 0,
                },
            )
        },
        item("glyph PART/2 inertia", 0, Role::Glyph, Motion::Rigid),
        item(
            "placeholder GRAPHICS/5",
            0,
            Role::Placeholder,
            Motion::Rigid,
        ),
        item("GRAPHICS/6", 2, Role::Graphic, Motion::Rigid),
        item("GRAPHICS/7", 3, Role::Graphic, Motion::Rigid),
        // A force with no function to read (every frame NaN): no track.
        Item {
            local: Pose::IDENTITY,
            ..item(
                "GRAPHICS/8",
                1,
                Role::Arrow,
                Motion::Arrow {
                    at: Anchor {
                        part: 1,
                        point: [0.0, 0.0, 0.0],
                    },
                    arrow: 1,
                },
            )
        },
    ];
    let strip = Mesh {
        topology: Topology::LineStrip,
        positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
        indices: vec![0, 1, 2],
        // See-through: blended.
        ..line([0.1, 0.7, 0.1, 0.5])
    };
    let lines_loop = Mesh {
        topology: Topology::LineLoop,
        ..strip.clone()
    };
    let scene = Scene {
        title: "by hand".into(),
        meters_per_length: 0.001,
        up,
        extent: 2.0,
        parts,
        meshes: vec![
            cube([0.8, 0.2, 0.2, 1.0]),
            line([0.2, 0.2, 0.8, 1.0]),
            strip,
            lines_loop,
        ],
        items,
        arrows: vec![ArrowSource {
            etype: "SFORCE",
            eid: 1,
            emarker: 20,
        }],
        notes: Vec::new(),
    };
    let mut frames = Frames::default();
    for k in 0..=40 {
        let t = k as f64 * 0.1;
        frames.times.push(t);
        frames.poses.push(vec![
            Pose::IDENTITY,
            Pose {
                translation: [t, 0.0, 0.0],
                rotation: quat_z(t),
            },
            Pose {
                translation: [0.0, 5.0, 0.0],
                rotation: quat_z(1.0),
            },
        ]);
        // Zero at the start: the arrow has no length then.
        frames
            .arrows
            .push(vec![[t * 10.0, -t * 5.0, 0.0], [f64::NAN; 3]]);
    }
    (scene, frames)
}

type Trs = ([f64; 3], [f64; 4], [f64; 3]);

/// The glTF spec's node matrix T·R·S applied to point `p`.
fn apply(trs: &Trs, p: [f64; 3]) -> [f64; 3] {
    let (t, q, s) = trs;
    let v = nalgebra::Vector3::new(p[0] * s[0], p[1] * s[1], p[2] * s[2]);
    let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        q[3], q[0], q[1], q[2],
    ));
    let r = q * v;
    [r.x + t[0], r.y + t[1], r.z + t[2]]
}

/// Key times and values of each (node, path) channel.
type Channels = std::collections::HashMap<(usize, String), (Vec<f32>, Vec<Vec<f32>>)>;

/// Each channel's (node, path) → keyframe values, read by the `gltf` crate.
fn channels(doc: &gltf::Gltf) -> Channels {
    let blob = doc.blob.as_deref().expect("a BIN chunk");
    let mut out = std::collections::HashMap::new();
    for anim in doc.animations() {
        assert_eq!(anim.name(), Some("run"));
        for ch in anim.channels() {
            assert_eq!(
                ch.sampler().interpolation(),
                gltf::animation::Interpolation::Linear
            );
            let reader = ch.reader(|_| Some(blob));
            let times: Vec<f32> = reader.read_inputs().expect("inputs").collect();
            use gltf::animation::util::ReadOutputs;
            let values: Vec<Vec<f32>> = match reader.read_outputs().expect("outputs") {
                ReadOutputs::Translations(v) => v.map(|x| x.to_vec()).collect(),
                ReadOutputs::Rotations(r) => r.into_f32().map(|x| x.to_vec()).collect(),
                ReadOutputs::Scales(v) => v.map(|x| x.to_vec()).collect(),
                ReadOutputs::MorphTargetWeights(_) => panic!("no morph weights are written"),
            };
            let path = format!("{:?}", ch.target().property());
            out.insert((ch.target().node().index(), path), (times, values));
        }
    }
    out
}

fn node<'a>(doc: &'a gltf::Gltf, name: &str) -> gltf::Node<'a> {
    doc.nodes()
        .find(|n| n.name() == Some(name))
        .unwrap_or_else(|| panic!("no node {name}"))
}

fn write(name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("animate");
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("written");
    path
}

#[test]
fn a_hand_made_scene_reads_back_as_the_conventions_say() {
    let (scene, frames) = scene_and_frames([0.0, 0.0, 1.0]);
    let bytes = mbfx::gltf::glb(&scene, &frames);
    let doc = gltf::Gltf::from_slice(&bytes).expect("the gltf crate reads it");
    assert!(doc
        .document
        .as_json()
        .asset
        .generator
        .as_deref()
        .is_some_and(|g| g.starts_with("mbfx ")));
    // The root: +z up turned to +Y is a quarter turn about −X; scale mm → m.
    let root = node(&doc, "mbfx");
    let (_, r, s) = root.transform().decomposed();
    let turned = apply(&([0.0; 3], r.map(|x| x as f64), [1.0; 3]), [0.0, 0.0, 1.0]);
    assert!((turned[1] - 1.0).abs() < 1e-6, "{turned:?}");
    assert_eq!(s, [0.001; 3]);
    assert_eq!(
        doc.scenes().next().unwrap().nodes().next().unwrap().index(),
        root.index()
    );
    // Parts under the root, view names in extras; rigid items under their part.
    let crank = node(&doc, "PART/2");
    let extras: serde_json::Value =
        serde_json::from_str(crank.extras().as_ref().unwrap().get()).unwrap();
    assert_eq!(extras["adams_view_name"], "crank");
    let under_crank: Vec<_> = crank
        .children()
        .filter_map(|c| c.name().map(String::from))
        .collect();
    assert_eq!(
        under_crank,
        [
            "GRAPHICS/1",
            "glyph PART/2 inertia",
            "placeholder GRAPHICS/5",
            "GRAPHICS/6",
            "GRAPHICS/7"
        ]
    );
    let under_root: Vec<_> = root
        .children()
        .filter_map(|c| c.name().map(String::from))
        .collect();
    assert_eq!(
        under_root,
        [
            "PART/1",
            "PART/2",
            "PART/3",
            "GRAPHICS/2",
            "GRAPHICS/3",
            "GRAPHICS/8"
        ]
    );
    for (name, role) in [
        ("GRAPHICS/1", "graphic"),
        ("GRAPHICS/2", "graphic"),
        ("GRAPHICS/3", "arrow"),
        ("glyph PART/2 inertia", "glyph"),
        ("placeholder GRAPHICS/5", "placeholder"),
        ("GRAPHICS/8", "arrow"),
    ] {
        let e: serde_json::Value =
            serde_json::from_str(node(&doc, name).extras().as_ref().unwrap().get()).unwrap();
        assert_eq!(e["mbfx"]["role"], role, "{name}");
    }
    // One material per colour; triangles with normals, lines without.
    assert_eq!(doc.materials().count(), 3);
    let modes: Vec<_> = doc
        .meshes()
        .map(|m| {
            let p = m.primitives().next().unwrap();
            (p.mode(), p.get(&gltf::Semantic::Normals).is_some())
        })
        .collect();
    assert_eq!(
        modes,
        [
            (gltf::mesh::Mode::Triangles, true),
            (gltf::mesh::Mode::Lines, false),
            (gltf::mesh::Mode::LineStrip, false),
            (gltf::mesh::Mode::LineLoop, false),
        ]
    );
    // Tracks: ground has none; the crank's translation and rotation at every key are
    // the frames' (float32).
    let ch = channels(&doc);
    let ground = node(&doc, "PART/1").index();
    assert!(!ch.keys().any(|(n, _)| *n == ground));
    let (times, t) = &ch[&(crank.index(), "Translation".to_string())];
    let (_, r) = &ch[&(crank.index(), "Rotation".to_string())];
    assert_eq!(times.len(), 41);
    for k in 0..41 {
        let tk = k as f64 * 0.1;
        assert!((times[k] as f64 - tk).abs() < 1e-6);
        assert!((t[k][0] as f64 - tk).abs() < 1e-6);
        let q = quat_z(tk);
        // The same rotation, either sign; the sign continuous from key to key.
        let dot: f64 = (0..4).map(|i| r[k][i] as f64 * q[i]).sum();
        assert!(
            (dot.abs() - 1.0).abs() < 1e-6,
            "key {k}: {:?} vs {q:?}",
            r[k]
        );
        if k > 0 {
            let step: f32 = (0..4).map(|i| r[k][i] * r[k - 1][i]).sum();
            assert!(step > 0.0);
        }
    }
    // The spring: from ground's origin to part 2's (1, 0, 0), recomputed here.
    let spring = node(&doc, "GRAPHICS/2").index();
    let st = &ch[&(spring, "Translation".to_string())].1;
    let sr = &ch[&(spring, "Rotation".to_string())].1;
    let ss = &ch[&(spring, "Scale".to_string())].1;
    for k in 0..41 {
        let tk = k as f64 * 0.1;
        let trs: Trs = (
            [st[k][0], st[k][1], st[k][2]].map(|x| x as f64),
            [sr[k][0], sr[k][1], sr[k][2], sr[k][3]].map(|x| x as f64),
            [ss[k][0], ss[k][1], ss[k][2]].map(|x| x as f64),
        );
        let end = apply(&trs, [0.0, 0.0, 1.0]);
        let want = [tk + tk.cos(), tk.sin(), 0.0];
        for i in 0..3 {
            assert!(
                (end[i] - want[i]).abs() < 1e-5,
                "key {k}: {end:?} vs {want:?}"
            );
        }
        assert_eq!(apply(&trs, [0.0; 3]), [0.0; 3]);
    }
    // A part that never moves: no track, its node where the frames hold it.
    let still = node(&doc, "PART/3");
    assert!(!ch.keys().any(|(n, _)| *n == still.index()));
    let (t, r, _) = still.transform().decomposed();
    assert_eq!(t, [0.0, 5.0, 0.0]);
    assert!((r[2] as f64 - 0.5f64.sin()).abs() < 1e-7, "{r:?}");
    // The force never known has no track.
    let unknown = node(&doc, "GRAPHICS/8").index();
    assert!(!ch.keys().any(|(n, _)| *n == unknown));
    // The arrow: along the force, its largest a quarter of the extent (0.5).
    let arrow = node(&doc, "GRAPHICS/3").index();
    let az = &ch[&(arrow, "Scale".to_string())].1;
    let ar = &ch[&(arrow, "Rotation".to_string())].1;
    let largest = (40.0f64 * 40.0 * 0.01 * 125.0).sqrt();
    for k in 0..41 {
        let tk = k as f64 * 0.1;
        let f = (125.0f64).sqrt() * tk;
        let len = (az[k][2] as f64).max(0.0);
        assert!(az[k][2] > 0.0, "never a zero scale");
        if k > 0 {
            assert!((len - 0.5 * f / largest).abs() < 1e-6, "key {k}: {len}");
            let q = ([ar[k][0], ar[k][1], ar[k][2], ar[k][3]]).map(|x| x as f64);
            let dir = apply(&([0.0; 3], q, [1.0; 3]), [0.0, 0.0, 1.0]);
            let want = [2.0 / 5f64.sqrt(), -1.0 / 5f64.sqrt(), 0.0];
            for i in 0..3 {
                assert!((dir[i] - want[i]).abs() < 1e-6, "key {k}: {dir:?}");
            }
        }
    }
}

#[test]
fn the_validator_finds_no_error_in_any_kind_of_item() {
    let mut paths = Vec::new();
    for (name, up) in [
        ("z-up.glb", [0.0, 0.0, 1.0]),
        ("minus-y-up.glb", [0.0, -1.0, 0.0]),
        ("y-up.glb", [0.0, 1.0, 0.0]),
    ] {
        let (scene, frames) = scene_and_frames(up);
        paths.push(write(name, &mbfx::gltf::glb(&scene, &frames)));
    }
    // No frames at all: a still scene; one frame: still too.
    let (scene, frames) = scene_and_frames([0.0, 0.0, 1.0]);
    paths.push(write(
        "still.glb",
        &mbfx::gltf::glb(&scene, &Frames::default()),
    ));
    let one = Frames {
        times: vec![0.0],
        poses: vec![frames.poses[3].clone()],
        arrows: vec![frames.arrows[3].clone()],
    };
    paths.push(write("one-frame.glb", &mbfx::gltf::glb(&scene, &one)));
    let refs: Vec<&std::path::Path> = paths.iter().map(|p| p.as_path()).collect();
    for r in validate(&refs) {
        assert_eq!(r.errors, 0, "{}: {:?}", r.file, r.messages);
    }
}

#[test]
fn up_along_minus_y_is_a_half_turn_about_x() {
    let (scene, frames) = scene_and_frames([0.0, -1.0, 0.0]);
    let bytes = mbfx::gltf::glb(&scene, &frames);
    let doc = gltf::Gltf::from_slice(&bytes).expect("read");
    let (_, r, _) = node(&doc, "mbfx").transform().decomposed();
    assert!(
        (r[0].abs() - 1.0).abs() < 1e-7 && r[3].abs() < 1e-7,
        "{r:?}"
    );
}

#[test]
fn the_validator_does_report_errors() {
    // A file whose header's length lies: the validator must say so, or its 0 errors
    // elsewhere mean nothing.
    let (scene, frames) = scene_and_frames([0.0, 0.0, 1.0]);
    let mut bytes = mbfx::gltf::glb(&scene, &frames);
    bytes[8] ^= 0x10;
    let path = write("broken.glb", &bytes);
    let reports = validate(&[path.as_path()]);
    assert!(reports[0].errors > 0, "{reports:?}");
}
