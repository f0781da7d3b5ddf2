//! Compile once, run many (issue 23): a simulation rewound and run again gives the bits of
//! a simulation built afresh, on every bundled scene and the integrated MOTIONs; a design
//! variable (a constant VARIABLE) changed on a built simulation gives the bits of the
//! dataset written with the new value; and a value a constraint reads is refused.

use mbfx::session::run::{Method, RewindError, RunSpec, Simulation};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every output row of a run of `sim`, with the failure that stopped it, if any.
fn rows(sim: &mut Simulation) -> (Vec<Vec<f64>>, Option<String>) {
    let mut rows = Vec::new();
    let (_, failed) = sim.run(&mut |r: &[f64]| {
        rows.push(r.to_vec());
        Ok(())
    });
    (rows, failed.map(|e| e.to_string()))
}

/// Bits of every value, NaN included.
fn bits(rows: &[Vec<f64>]) -> Vec<Vec<u64>> {
    rows.iter()
        .map(|r| r.iter().map(|x| x.to_bits()).collect())
        .collect()
}

fn simulation(text: &str, spec: RunSpec, probes: &[(String, String)]) -> Simulation {
    match Simulation::new(text, spec, probes) {
        Ok(sim) => sim,
        Err(_) => panic!("the dataset does not build:\n{text}"),
    }
}

/// Output columns: (name, expression).
type Probes = Vec<(String, String)>;

/// A scene's dataset, end (capped: the test is about bits, not about long runs) and probes.
fn scene(toml_path: &Path) -> Option<(String, f64, Probes)> {
    let t: toml::Table = std::fs::read_to_string(toml_path).ok()?.parse().ok()?;
    let model = t.get("model")?.as_str()?;
    let text = std::fs::read_to_string(toml_path.with_file_name(model)).ok()?;
    let end = t.get("end")?.as_float()?.min(1.0);
    let probes = t
        .get("probe")
        .and_then(|p| p.as_array())
        .into_iter()
        .flatten()
        .filter_map(|p| {
            Some((
                p.get("name")?.as_str()?.to_string(),
                p.get("expr")?.as_str()?.to_string(),
            ))
        })
        .collect();
    Some((text, end, probes))
}

/// Runs `text` twice on one simulation (rewound between) and once on a new one: the
/// three give the same bits.
fn assert_rerun_is_fresh(name: &str, text: &str, spec: RunSpec, probes: &[(String, String)]) {
    let mut sim = simulation(text, spec.clone(), probes);
    let first = rows(&mut sim);
    sim.rewind(&[]).unwrap_or_else(|e| panic!("{name}: {e:?}"));
    let second = rows(&mut sim);
    let fresh = rows(&mut simulation(text, spec, probes));
    assert!(first.0.len() > 2, "{name}: {} rows", first.0.len());
    assert_eq!(
        bits(&first.0),
        bits(&fresh.0),
        "{name}: first run and a fresh one"
    );
    assert_eq!(
        bits(&second.0),
        bits(&fresh.0),
        "{name}: rewound run and a fresh one"
    );
    assert_eq!(second.1, fresh.1, "{name}");
}

#[test]
fn a_rewound_simulation_reruns_every_scene_bit_for_bit() {
    let mut seen = 0;
    let dir = root().join("examples/scenes");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("examples/scenes")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    for toml_path in files {
        // Generated scenes (no `model`) are the chains and four-bars: covered by others.
        let Some((text, end, probes)) = scene(&toml_path) else {
            continue;
        };
        let name = toml_path.display().to_string();
        for method in [Method::Gstiff, Method::Dopri853] {
            let mut spec = RunSpec::new(end, end / 20.0);
            spec.method = Some(method);
            spec.hmin = Some(1e-12);
            assert_rerun_is_fresh(&name, &text, spec, &probes);
        }
        seen += 1;
    }
    assert!(seen >= 10, "only {seen} scenes");
}

#[test]
fn integrated_motions_and_reactions_rerun_bit_for_bit() {
    for (file, probes) in [
        ("tests/models/motions/slider_velocity.adm", vec![]),
        ("tests/models/motions/slider_acceleration.adm", vec![]),
        ("tests/models/motions/pendulum_acceleration.adm", vec![]),
        // Forces reading accelerations, reactions and forces: the last run's solution
        // values must not leak into the next.
        ("tests/models/solution/added_mass_oscillator.adm", vec![]),
        ("tests/models/solution/friction_loop.adm", vec![]),
        ("tests/models/solution/force_reads_force.adm", vec![]),
        // A planar run whose probe reads a reaction: the 3D shadow is rewound too.
        (
            "tests/models/pendulum_out_of_plane_loads.adm",
            vec![("fz".to_string(), "JOINT(1, 0, 4, 0)".to_string())],
        ),
    ] {
        let text = std::fs::read_to_string(root().join(file)).expect(file);
        assert_rerun_is_fresh(file, &text, RunSpec::new(1.0, 0.05), &probes);
    }
    // A chain of 10 rods: its Newton matrix is factored sparse, not dense.
    let chain = mbfx::bench::generate::chain(10);
    let probes = [("tip".to_string(), "DY(1103)".to_string())];
    assert_rerun_is_fresh("chain of 10", &chain, RunSpec::new(0.2, 0.02), &probes);
}

/// The IMPACT block of examples/scenes with its stiffness and damping as design variables.
fn impact_block(k: &str, c: &str) -> String {
    let text = std::fs::read_to_string(root().join("examples/scenes/impact_block_k1e5.adm"))
        .expect("impact block");
    text.replace(
        "IMPACT(DY(201, 101), VY(201, 101), 0.05, 1E5, 1.5, 50, 0.1)",
        "IMPACT(DY(201, 101), VY(201, 101), 0.05, VARVAL(1), 1.5, VARVAL(2), 0.1)",
    )
    .replace(
        "ACCGRAV/JGRAV = -9.81",
        &format!("VARIABLE/1, FUNCTION = {k}\nVARIABLE/2, FUNCTION = {c}\nACCGRAV/JGRAV = -9.81"),
    )
}

fn impact_spec() -> RunSpec {
    let mut spec = RunSpec::new(1.0, 0.01);
    spec.method = Some(Method::Dopri853);
    spec.error = Some(3e-6);
    spec
}

#[test]
fn a_design_variable_changed_on_a_built_simulation_gives_the_datasets_bits() {
    let probes = [("y".to_string(), "DY(201, 101)".to_string())];
    let mut sim = simulation(&impact_block("1E5", "50"), impact_spec(), &probes);
    assert_eq!(sim.designs(), &[(1, 1e5), (2, 50.0)]);
    let base = rows(&mut sim).0;
    // The literal and the design variable are the same numbers in the same law.
    let literal = std::fs::read_to_string(root().join("examples/scenes/impact_block_k1e5.adm"))
        .expect("impact block");
    let written = rows(&mut simulation(&literal, impact_spec(), &probes)).0;
    assert_eq!(
        bits(&base),
        bits(&written),
        "VARVAL(1) = 1E5 against 1E5 written"
    );
    for (k, c) in [(3e5, 50.0), (2e4, 80.0), (1e5, 50.0)] {
        sim.rewind(&[(1, k), (2, c)]).expect("rewind");
        let changed = rows(&mut sim).0;
        let fresh = rows(&mut simulation(
            &impact_block(&format!("{k:?}"), &format!("{c:?}")),
            impact_spec(),
            &probes,
        ))
        .0;
        assert_eq!(bits(&changed), bits(&fresh), "k = {k}, c = {c}");
        assert_eq!(
            (k == 1e5),
            bits(&changed) == bits(&base),
            "k = {k}, c = {c}"
        );
    }
}

#[test]
fn a_design_variable_a_constraint_reads_needs_a_new_build() {
    // A slider held at x = VARVAL(1) by a GCON: the value moves the assembly.
    let text = "slider\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        MARKER/11, PART = 1, REULER = 90D, 90D, 0\n\
        PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
        MARKER/21, PART = 2, REULER = 90D, 90D, 0\n\
        JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
        VARIABLE/1, FUNCTION = 0.25\nVARIABLE/2, FUNCTION = 3\n\
        GCON/1, FUNCTION = DX(20, 10) - VARVAL(1)\n\
        SFORCE/1, TRANSLATION, I = 20, J = 10, FUNCTION = VARVAL(2)\nEND\n";
    let mut sim = simulation(text, RunSpec::new(0.1, 0.05), &[]);
    let (r, failed) = rows(&mut sim);
    assert_eq!(failed, None);
    assert_eq!(r[0][0], 0.0);
    assert!(matches!(
        sim.rewind(&[(1, 0.5)]),
        Err(RewindError::ConstraintReads(1))
    ));
    // The force's variable only moves the multiplier: allowed.
    sim.rewind(&[(2, 4.0)]).expect("a force's design variable");
}
