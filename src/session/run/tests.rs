//! Runs against closed forms: one module for every expression, a damped spring, plain
//! Newmark's amplification matrix.

use super::*;

/// A 1 kg slider on a rail along global x, pulled by a SPRINGDAMPER (K = 100,
/// C = 4, free length 1) to the ground origin, released at rest at x = 1.2.
pub(super) const OSCILLATOR: &str = "oscillator\nPART/1, GROUND\nMARKER/10, PART = 1\n\
    MARKER/11, PART = 1, REULER = 90D, 90D, 0\n\
    PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = 1.2, 0, 0\n\
    MARKER/20, PART = 2\nMARKER/21, PART = 2, REULER = 90D, 90D, 0\n\
    JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
    SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 100, C = 4, LENGTH = 1\nEND\n";

#[test]
fn every_expression_of_a_model_lands_in_one_module() {
    // A GCON (compiled for assembly first), a MOTION, an SFORCE, a GFORCE's six
    // components, a VARIABLE read by a force, a REQUEST's F1..F2 and a probe.
    let model = "one module\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
        MARKER/22, PART = 2, FLOATING\n\
        PART/3, MASS = 1, CM = 30, IP = 1, 1, 1, QG = 0, 0, 1\nMARKER/30, PART = 3\n\
        MARKER/31, PART = 3\nMARKER/11, PART = 1, QP = 0, 0, 1\n\
        JOINT/1, SPHERICAL, I = 20, J = 10\nJOINT/2, TRANSLATIONAL, I = 31, J = 11\n\
        GCON/1, I = 20, FUNCTION = AX(20, 10)\n\
        GCON/2, I = 20, FUNCTION = AY(20, 10) - 0.1*SIN(TIME)\n\
        MOTION/1, JOINT = 2, FUNCTION = 0.1*TIME\n\
        VARIABLE/1, FUNCTION = -2*WZ(20, 10)\n\
        SFORCE/1, ROTATION, I = 20, J = 10, FUNCTION = VARVAL(1)\n\
        GFORCE/1, I = 20, JFLOAT = 22, RM = 10, FX = 0\\ FY = 0\\ FZ = 1\\ TX = 0\\ TY = 0\\ TZ = 0.1\n\
        REQUEST/1, F1 = DZ(31, 11)\\ F2 = WZ(20, 10)\nEND\n";
    let probes = [("z".to_string(), "DZ(30)".to_string())];
    let build = |engine| {
        let mut spec = RunSpec::new(0.1, 0.05);
        spec.engine = engine;
        match Simulation::new(model, spec, &probes) {
            Ok(sim) => sim,
            Err(_) => panic!("the model builds"),
        }
    };
    if crate::jit::Jit::new().is_ok() {
        assert_eq!(build(Engine::Jit).jit_modules(), 1);
    }
    assert_eq!(build(Engine::Interp).jit_modules(), 0);
}

#[test]
fn a_damped_spring_follows_its_closed_form() {
    // m ẍ = −k (x − 1) − c ẋ: ω = 10, ζ = c/(2√(k m)) = 0.2, ω_d = ω√(1 − ζ²);
    // x − 1 = 0.2·e^{−ζωt}(cos ω_d t + ζω/ω_d sin ω_d t).
    let probes = [
        ("x".to_string(), "DX(20,10)".to_string()),
        ("f".to_string(), "SPDP(1,0,2,0)".to_string()),
    ];
    for method in [Method::Hht, Method::Galpha] {
        let mut spec = RunSpec::new(2.0, 0.05);
        spec.method = Some(method);
        spec.error = Some(1e-11);
        let Ok(mut sim) = Simulation::new(OSCILLATOR, spec, &probes) else {
            panic!("the oscillator builds");
        };
        let mut rows = Vec::new();
        let (_, failed) = sim.run(&mut |r| {
            rows.push(r.to_vec());
            Ok(())
        });
        assert!(failed.is_none(), "{failed:?}");
        assert_eq!(rows.len(), 41);
        let (w, z) = (10.0f64, 0.2f64);
        let wd = w * (1.0 - z * z).sqrt();
        for r in &rows {
            let t = r[0];
            let e = (-z * w * t).exp();
            let x = 1.0 + 0.2 * e * ((wd * t).cos() + z * w / wd * (wd * t).sin());
            let v = -0.2 * e * (w * w / wd) * (wd * t).sin();
            assert!(
                (r[1] - x).abs() < 1e-6,
                "{method:?} t = {t}: x {} vs {x}",
                r[1]
            );
            // The spring's force on I along x: −k(x − 1) − c·ẋ.
            let f = -100.0 * (x - 1.0) - 4.0 * v;
            assert!(
                (r[2] - f).abs() < 1e-4,
                "{method:?} t = {t}: force {} vs {f}",
                r[2]
            );
        }
    }
}

#[test]
fn plain_newmark_follows_its_amplification_matrix() {
    // Undamped x'' = −ω²x (ω = 10) in fixed steps h: Newmark's two-step recurrence
    // x_{n+1} − 2A₁x_n + A₂x_{n−1} = 0, Ω = ωh, D = 1 + βΩ²,
    // A₁ = 1 − Ω²(γ + ½)/(2D), A₂ = 1 − Ω²(γ − ½)/D (Hughes, The Finite Element
    // Method, §9.1), so x_n = ρⁿ(x₀ cos nθ + c sin nθ) with ρ = √A₂,
    // cos θ = A₁/ρ, and x₁ = x₀(1 − (½ − β)Ω²)/D from rest. β = ¼, γ = ½ keeps the
    // amplitude (ρ = 1) and only lengthens the period; Adams' defaults damp.
    let undamped = OSCILLATOR.replace("C = 4", "C = 0");
    let probes = [("x".to_string(), "DX(20,10)".to_string())];
    let h = 0.02;
    for (beta, gamma) in [(0.25, 0.5), (0.36, 0.7)] {
        let text = undamped.replace(
            "END\n",
            &format!("INTEGRATOR/NEWMARK, BETA = {beta}, GAMMA = {gamma}\nEND\n"),
        );
        let mut spec = RunSpec::new(2.0, h);
        (spec.fixed_step, spec.error) = (Some(h), Some(1e-10));
        let Ok(mut sim) = Simulation::new(&text, spec, &probes) else {
            panic!("the oscillator builds");
        };
        let mut rows = Vec::new();
        let (summary, failed) = sim.run(&mut |r| {
            rows.push(r.to_vec());
            Ok(())
        });
        assert!(failed.is_none(), "{failed:?}");
        assert_eq!(summary.integrator, "newmark");
        assert_eq!(summary.stats.order, Some(if gamma == 0.5 { 2 } else { 1 }));
        let big_omega = 10.0 * h;
        let d = 1.0 + beta * big_omega * big_omega;
        let a1 = 1.0 - big_omega * big_omega * (gamma + 0.5) / (2.0 * d);
        let a2 = 1.0 - big_omega * big_omega * (gamma - 0.5) / d;
        let rho = a2.sqrt();
        let theta = (a2 - a1 * a1).sqrt().atan2(a1);
        let x0 = 0.2;
        let x1 = x0 * (1.0 - (0.5 - beta) * big_omega * big_omega) / d;
        let c = (x1 / rho - x0 * theta.cos()) / theta.sin();
        assert_eq!(rows.len(), 101);
        for (n, r) in rows.iter().enumerate() {
            let nf = n as f64;
            let x = rho.powf(nf) * (x0 * (nf * theta).cos() + c * (nf * theta).sin());
            assert!(
                (r[1] - 1.0 - x).abs() < 1e-9,
                "β {beta} γ {gamma} step {n}: {} vs {x}",
                r[1] - 1.0
            );
        }
    }
}
