//! Contact (reference-problems §6): a 1 kg block on a translational joint meeting a stop
//! through IMPACT or BISTOP (`tests/models/contact/`), run by `mbfx run` at a tight ERROR
//! with both integrators, against truths computed here:
//! - IMPACT with cmax = 0 is Hertz's elastic contact (§6.2): the maximum penetration, the
//!   contact time (from the Γ function) and the rebound speed in closed form, for
//!   k = 1e5 and 1e7;
//! - IMPACT with damping (§6.4 scene 1, the block dropped 0.1 m, §6.5's bouncing
//!   ball) against the 1-DOF equation `m·ÿ = F(y, ẏ) − m·g` integrated by the independent
//!   Dormand–Prince, with the contact law written here from spec expr-language §5.4–5.5
//!   (clamped: it never pulls), its convergence checked by two tolerances;
//! - BISTOP (§6.6): elastic, every impact a §6.2 Hertz contact, so the free flights between
//!   the stops are known exactly; damped, against the Dormand–Prince.
//!
//! Between contacts the block is in free flight (the force is exactly 0 off the stop), so
//! a row there gives the exact time it left the stop (`t − (y − x1)/ẏ` without gravity)
//! and the apex of the next flight (`t + ẏ/g`, `y + ẏ²/(2g)`) without interpolation.

use crate::adams::models_dir;
use crate::reference::dopri5;
use crate::run::{named, run_probed, Csv, INTEGRATORS};
use std::f64::consts::PI;
use std::time::Instant;

/// Adams' cubic STEP(x, x0, h0, x1, h1) (spec multibody §7). Written again here, as the
/// contact laws below, on purpose: the truth must not call the runtime it checks.
fn step(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    if x <= x0 {
        h0
    } else if x >= x1 {
        h1
    } else {
        let d = (x - x0) / (x1 - x0);
        h0 + (h1 - h0) * d * d * (3.0 - 2.0 * d)
    }
}

/// The contact laws of spec expr-language §5.4 and §5.5, with the clamp.
#[derive(Clone, Copy, Debug)]
enum Law {
    /// IMPACT(x, ẋ, x1, k, e, cmax, d): `max(0, k·(x1 − x)^e − STEP(x, x1−d, cmax, x1, 0)·ẋ)`
    /// below x1, else 0.
    Impact {
        x1: f64,
        k: f64,
        e: f64,
        cmax: f64,
        d: f64,
    },
    /// BISTOP(x, ẋ, x1, x2, k, e, cmax, d): IMPACT's force below x1, 0 in the gap,
    /// `min(0, −k·(x − x2)^e − STEP(x, x2, 0, x2+d, cmax)·ẋ)` above x2.
    Bistop {
        x1: f64,
        x2: f64,
        k: f64,
        e: f64,
        cmax: f64,
        d: f64,
    },
}

impl Law {
    fn force(self, x: f64, xd: f64) -> f64 {
        match self {
            Law::Impact { x1, k, e, cmax, d } => {
                if x < x1 {
                    (k * (x1 - x).powf(e) - step(x, x1 - d, cmax, x1, 0.0) * xd).max(0.0)
                } else {
                    0.0
                }
            }
            Law::Bistop {
                x1,
                x2,
                k,
                e,
                cmax,
                d,
            } => {
                if x < x1 {
                    Law::Impact { x1, k, e, cmax, d }.force(x, xd)
                } else if x > x2 {
                    (-k * (x - x2).powf(e) - step(x, x2, 0.0, x2 + d, cmax) * xd).min(0.0)
                } else {
                    0.0
                }
            }
        }
    }

    /// The potential energy of the spring term (`k·p^(e+1)/(e+1)` at penetration p).
    fn potential(self, x: f64) -> f64 {
        let (p, k, e) = match self {
            Law::Impact { x1, k, e, .. } => ((x1 - x).max(0.0), k, e),
            Law::Bistop { x1, x2, k, e, .. } => ((x1 - x).max(0.0) + (x - x2).max(0.0), k, e),
        };
        k * p.powf(e + 1.0) / (e + 1.0)
    }
}

/// Γ(x) by Lanczos (g = 7, nine terms; about 1e-15 relative), reflected below ½.
fn gamma(x: f64) -> f64 {
    #[allow(clippy::excessive_precision)]
    const P: [f64; 9] = [
        0.99999999999980993,
        676.5203681218851,
        -1259.1392167224028,
        771.32342877765313,
        -176.61502916214059,
        12.507343278686905,
        -0.13857109526572012,
        9.9843695780195716e-6,
        1.5056327351493116e-7,
    ];
    if x < 0.5 {
        return PI / ((PI * x).sin() * gamma(1.0 - x));
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let a = P[0]
        + P[1..]
            .iter()
            .enumerate()
            .map(|(i, p)| p / (x + i as f64 + 1.0))
            .sum::<f64>();
    (2.0 * PI).sqrt() * t.powf(x + 0.5) * (-t).exp() * a
}

/// Hertz's elastic impact (§6.2), F = k·δⁿ, mass m at speed v: (δ_max, contact time).
/// δ_max = (p·m·v²/(2k))^(1/p) and t_c = (2·δ_max/v)·√π·Γ(1 + 1/p)/Γ(½ + 1/p), p = n + 1.
fn hertz(k: f64, n: f64, m: f64, v: f64) -> (f64, f64) {
    let p = n + 1.0;
    let dmax = (p * m * v * v / (2.0 * k)).powf(1.0 / p);
    let tc = 2.0 * dmax / v * PI.sqrt() * gamma(1.0 + 1.0 / p) / gamma(0.5 + 1.0 / p);
    (dmax, tc)
}

#[test]
// §6.2's digits as printed, beyond f64's: they round to the nearest double.
#[allow(clippy::excessive_precision)]
fn the_hertz_closed_form_gives_the_published_values() {
    // §6.2: t_c·v/δ_max = 2.9432751843247046574 for n = 1.5, and its two cases.
    let (d6, t6) = hertz(1e6, 1.5, 1.0, 1.0);
    assert!(
        (t6 / d6 - 2.943_275_184_324_704_7).abs() < 1e-13,
        "{}",
        t6 / d6
    );
    assert!((d6 - 0.004_352_752_816_480_620_7).abs() < 1e-16, "{d6}");
    assert!((t6 - 0.012_811_349_348_246_876).abs() < 1e-15, "{t6}");
    let (d5, t5) = hertz(1e5, 1.5, 1.0, 1.0);
    assert!((d5 - 0.010_933_620_739_432_781).abs() < 1e-16, "{d5}");
    assert!((t5 - 0.032_180_654_597_190_431).abs() < 1e-15, "{t5}");
    // Γ at known points.
    assert!((gamma(0.5) - PI.sqrt()).abs() < 1e-14);
    assert!((gamma(5.0) - 24.0).abs() < 1e-12);
}

#[test]
fn the_contact_laws_give_the_spec_examples() {
    // spec expr-language §5.4 and §5.5.
    let imp = Law::Impact {
        x1: 1.0,
        k: 1e5,
        e: 1.5,
        cmax: 100.0,
        d: 0.1,
    };
    assert!((imp.force(0.95, -2.0) - 1218.0339887498967).abs() < 1e-9);
    assert!((imp.force(0.85, -2.0) - 6009.475019311127).abs() < 1e-9);
    assert_eq!(imp.force(1.0, -5.0), 0.0);
    assert_eq!(imp.force(0.95, 30.0), 0.0);
    let bi = Law::Bistop {
        x1: -2.0,
        x2: 2.0,
        k: 1000.0,
        e: 2.0,
        cmax: 10.0,
        d: 0.1,
    };
    assert!((bi.force(2.05, 1.0) + 7.5).abs() < 1e-12);
    assert!((bi.force(-2.05, -1.0) - 7.5).abs() < 1e-12);
    assert_eq!(bi.force(0.0, 5.0), 0.0);
    assert_eq!(bi.force(2.05, -10.0), 0.0);
}

/// One dataset of `tests/models/contact/`: the block's start, gravity, and its force.
struct Scene {
    file: &'static str,
    /// The FUNCTION the dataset must hold (checked), the same law as `law`.
    function: &'static str,
    law: Law,
    /// The joint axis: "Y" (vertical drop) or "X" (BISTOP slider).
    axis: &'static str,
    y0: f64,
    v0: f64,
    /// g along −axis (0 without ACCGRAV).
    g: f64,
    end: f64,
    output_step: f64,
}

const MASS: f64 = 1.0;

impl Scene {
    fn path(&self) -> std::path::PathBuf {
        models_dir().join("contact").join(self.file)
    }

    fn check_dataset(&self) {
        let text = std::fs::read_to_string(self.path()).unwrap();
        let squeeze = |s: &str| s.split_whitespace().collect::<String>();
        let flat = squeeze(&text);
        let a = self.axis;
        let want = [
            squeeze(self.function),
            format!("PART/2,MASS={MASS}"),
            "JOINT/1,TRANSLATIONAL,I=201,J=101".to_owned(),
            "SFORCE/1,TRANSLATION,ACTIONONLY,I=201,J=101".to_owned(),
        ];
        for w in &want {
            assert!(flat.contains(w.as_str()), "{}: no `{w}`", self.file);
        }
        assert!(
            self.function
                .contains(&format!("D{a}(201, 101), V{a}(201, 101)")),
            "{}",
            self.file
        );
        assert_eq!(flat.contains("ACCGRAV/JGRAV=-9.81"), self.g != 0.0);
        let v = format!("V{a}={}", self.v0);
        assert_eq!(flat.contains(&v), self.v0 != 0.0, "{}: {v}", self.file);
    }

    /// `mbfx run` with `integrator` at `error`: time, position, velocity; and the wall time.
    fn run(&self, integrator: &str, error: &str) -> (Csv, f64) {
        let a = self.axis;
        let probes = named(&[
            ("y", &format!("D{a}(201,101)")),
            ("v", &format!("V{a}(201,101)")),
        ]);
        let (end, dt) = (format!("{:?}", self.end), format!("{:?}", self.output_step));
        let args = [
            "--end",
            &end,
            "--output-step",
            &dt,
            "--integrator",
            integrator,
            "--error",
            error,
        ];
        let start = Instant::now();
        let csv = run_probed(&self.path(), &args, &probes);
        let secs = start.elapsed().as_secs_f64();
        csv.assert_grid(self.output_step, Some(self.end));
        assert!(
            (csv.col("y")[0] - self.y0).abs() < 1e-12,
            "{}: y(0)",
            self.file
        );
        assert!(
            (csv.col("v")[0] - self.v0).abs() < 1e-12,
            "{}: v(0)",
            self.file
        );
        (csv, secs)
    }

    /// The 1-DOF equation by Dormand–Prince at `rtol`, at `times`.
    fn reference(&self, times: &[f64], rtol: f64) -> Vec<[f64; 2]> {
        let (law, g) = (self.law, self.g);
        dopri5(
            |_, s| [s[1], law.force(s[0], s[1]) / MASS - g],
            [self.y0, self.v0],
            times,
            rtol,
            rtol * 1e-3,
        )
    }
}

const TIGHT: &str = "1e-12";

/// The Dormand–Prince's relative tolerance for the references (absolute: 1e-3 of it).
const REF_RTOL: f64 = 1e-14;

fn hertz_scene(file: &'static str, function: &'static str, k: f64, dt: f64, end: f64) -> Scene {
    vertical(
        file,
        function,
        impact(0.0, k, 0.0, 0.01),
        (0.01, -1.0, 0.0),
        (end, dt),
    )
}

/// The vertex of the parabola through three equally spaced samples (an interpolated
/// minimum: exact to O(h⁴) at a smooth minimum).
fn vertex(y0: f64, y1: f64, y2: f64) -> f64 {
    y1 - (y2 - y0).powi(2) / (8.0 * (y0 - 2.0 * y1 + y2))
}

/// The lowest point of a trace between rows `from` and `to`, by [`vertex`].
fn lowest(y: &[f64], from: usize, to: usize) -> f64 {
    let r = (from..to).min_by(|&a, &b| y[a].total_cmp(&y[b])).unwrap();
    vertex(y[r - 1], y[r], y[r + 1])
}

/// Hertz (§6.2) with IMPACT's cmax = 0: a block at 1 m/s, 0.01 m from the stop, no gravity.
fn hertz_case(scene: &Scene, k: f64) -> Vec<String> {
    scene.check_dataset();
    let v_in = -scene.v0;
    let (dmax, tc) = hertz(k, 1.5, MASS, v_in);
    let t_in = scene.y0 / v_in;
    let mut bad = Vec::new();
    for integrator in INTEGRATORS {
        let (csv, secs) = scene.run(integrator, TIGHT);
        let (t, y, v) = (csv.time(), csv.col("y"), csv.col("v"));
        let last = t.len() - 1;
        assert!(y[last] > 0.0, "{}: still in contact at the end", scene.file);
        // Free flight before and after: y = y0 − v_in·t, then x1 + v_out·(t − t_out).
        let before = (0..last).filter(|&r| t[r] < t_in).map(|r| {
            (y[r] - (scene.y0 - v_in * t[r]))
                .abs()
                .max((v[r] + v_in).abs())
        });
        let before = before.fold(0.0, f64::max);
        let v_out = v[last];
        let t_out = t[last] - y[last] / v_out;
        let got_tc = t_out - t_in;
        let first = t.iter().position(|&x| x > t_in).unwrap();
        let got_dmax = -lowest(&y, first, last);
        // Energy ½m·v² + k·p^2.5/2.5 stays ½m·v_in² through the contact.
        let energy = (0..=last)
            .map(|r| (0.5 * MASS * v[r] * v[r] + scene.law.potential(y[r])) / (0.5 * v_in * v_in))
            .map(|e| (e - 1.0).abs())
            .fold(0.0, f64::max);
        let rel = |got: f64, want: f64| (got - want).abs() / want.abs();
        let figures = format!(
            "{} {integrator} ({secs:.2} s): t_c {got_tc:.15} vs {tc:.15} ({:.1e}), \
             δ_max {got_dmax:.15} vs {dmax:.15} ({:.1e}), v_out {v_out:.15} vs {v_in} \
             ({:.1e}), energy {energy:.1e}, free flight before {before:.1e}",
            scene.file,
            rel(got_tc, tc),
            rel(got_dmax, dmax),
            rel(v_out, v_in),
        );
        eprintln!("{figures}");
        // 1e-6 relative on each figure (positions within 1e-6 of their range).
        if !(rel(got_tc, tc) <= 1e-6
            && rel(got_dmax, dmax) <= 1e-6
            && rel(v_out, v_in) <= 1e-6
            && energy <= 1e-6
            && before <= 1e-12)
        {
            bad.push(figures);
        }
    }
    bad
}

#[test]
fn impact_elastic_k1e5_gives_the_hertz_values() {
    let scene = hertz_scene(
        "hertz_k1e5.adm",
        "IMPACT(DY(201, 101), VY(201, 101), 0, 1E5, 1.5, 0, 0.01)",
        1e5,
        1e-4,
        0.06,
    );
    let bad = hertz_case(&scene, 1e5);
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn impact_elastic_k1e7_gives_the_hertz_values() {
    let scene = hertz_scene(
        "hertz_k1e7.adm",
        "IMPACT(DY(201, 101), VY(201, 101), 0, 1E7, 1.5, 0, 0.01)",
        1e7,
        1e-5,
        0.02,
    );
    let bad = hertz_case(&scene, 1e7);
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// IMPACT's law with exponent 1.5.
fn impact(x1: f64, k: f64, cmax: f64, d: f64) -> Law {
    Law::Impact {
        x1,
        k,
        e: 1.5,
        cmax,
        d,
    }
}

/// A block on the vertical joint: start (y0, v0), gravity g, run (end, output step).
fn vertical(
    file: &'static str,
    function: &'static str,
    law: Law,
    (y0, v0, g): (f64, f64, f64),
    (end, output_step): (f64, f64),
) -> Scene {
    Scene {
        file,
        function,
        law,
        axis: "Y",
        y0,
        v0,
        g,
        end,
        output_step,
    }
}

/// The BISTOP slider's stops.
const SLIDER_STOPS: (f64, f64) = (-0.1, 0.1);

/// The slider on the horizontal joint between the stops, from the middle at 1 m/s, no
/// gravity, 1 s: BISTOP with k = 1e5, e = 1.5, d = 0.01 and `cmax`.
fn slider(file: &'static str, function: &'static str, cmax: f64) -> Scene {
    Scene {
        file,
        function,
        law: Law::Bistop {
            x1: SLIDER_STOPS.0,
            x2: SLIDER_STOPS.1,
            k: 1e5,
            e: 1.5,
            cmax,
            d: 0.01,
        },
        axis: "X",
        y0: 0.0,
        v0: 1.0,
        g: 0.0,
        end: 1.0,
        output_step: 1e-3,
    }
}

/// The scenes compared with the Dormand–Prince over their whole trace.
fn damped_scenes() -> [Scene; 4] {
    let function = "IMPACT(DY(201, 101), VY(201, 101), 0, 1E5, 1.5, 50, 0.01)";
    [
        vertical(
            "impact_damped.adm",
            function,
            impact(0.0, 1e5, 50.0, 0.01),
            (0.01, -1.0, 0.0),
            (0.06, 1e-4),
        ),
        vertical(
            "drop.adm",
            "IMPACT(DY(201, 101), VY(201, 101), 0.05, 1E5, 1.5, 50, 0.1)",
            impact(0.05, 1e5, 50.0, 0.1),
            (0.15, 0.0, 9.81),
            (2.0, 1e-3),
        ),
        vertical(
            "bounce.adm",
            function,
            impact(0.0, 1e5, 50.0, 0.01),
            (1.0, 0.0, 9.81),
            (2.0, 1e-3),
        ),
        slider(
            "bistop_damped.adm",
            "BISTOP(DX(201, 101), VX(201, 101), -0.1, 0.1, 1E5, 1.5, 50, 0.01)",
            50.0,
        ),
    ]
}

fn scene(file: &str) -> Scene {
    damped_scenes()
        .into_iter()
        .find(|s| s.file == file)
        .unwrap()
}

/// The first row in free flight moving away from the stop after the first contact (the
/// block has left it: y ≥ x1 for IMPACT, inside the gap for BISTOP).
fn first_rebound_row(law: Law, y: &[f64], v: &[f64]) -> Option<usize> {
    let off = |r: usize| law.force(y[r], v[r]) == 0.0 && law.potential(y[r]) == 0.0;
    let hit = (0..y.len()).find(|&r| !off(r))?;
    (hit..y.len()).find(|&r| off(r) && v[r] * v[hit] < 0.0)
}

/// Figures of one trace: the largest |y − y_ref| over the rows, and from the first free
/// flight after the first contact: with gravity the apex (time, height), without it the
/// speed and the time the block left the stop.
struct Figures {
    rebound: Option<(f64, f64)>,
    lowest: f64,
}

fn figures(scene: &Scene, t: &[f64], y: &[f64], v: &[f64]) -> Figures {
    let rebound = first_rebound_row(scene.law, y, v).map(|r| {
        if scene.g > 0.0 {
            (t[r] + v[r] / scene.g, y[r] + v[r] * v[r] / (2.0 * scene.g))
        } else {
            let wall = match scene.law {
                Law::Impact { x1, .. } => x1,
                Law::Bistop { x1, x2, .. } => {
                    if v[r] < 0.0 {
                        x2
                    } else {
                        x1
                    }
                }
            };
            (t[r] - (y[r] - wall) / v[r], v[r])
        }
    });
    let hit = (0..y.len()).find(|&r| scene.law.potential(y[r]) > 0.0);
    let lowest = hit.map_or(f64::NAN, |h| {
        let end = (h..y.len())
            .find(|&r| scene.law.potential(y[r]) == 0.0)
            .unwrap_or(y.len() - 1);
        match scene.law {
            Law::Bistop { .. } if y[h] > 0.0 => {
                -lowest(&y.iter().map(|x| -x).collect::<Vec<_>>(), h, end)
            }
            _ => lowest(y, h, end),
        }
    });
    Figures { rebound, lowest }
}

#[test]
fn the_contact_references_converge() {
    // Ten digits: the Dormand–Prince at REF_RTOL and 10·REF_RTOL agree within 1e-9 of the
    // range.
    for s in damped_scenes() {
        let n = (s.end / s.output_step).round() as usize;
        let times: Vec<f64> = (0..=n).map(|k| k as f64 * s.output_step).collect();
        let fine = s.reference(&times, REF_RTOL);
        let coarse = s.reference(&times, 10.0 * REF_RTOL);
        let range = range(fine.iter().map(|r| r[0]));
        let diff = fine
            .iter()
            .zip(&coarse)
            .map(|(a, b)| (a[0] - b[0]).abs())
            .fold(0.0, f64::max);
        eprintln!("{}: rtol {REF_RTOL:e} vs 10× {diff:e} of {range}", s.file);
        assert!(diff < 1e-9 * range, "{}: {diff:e} of {range}", s.file);
        let y: Vec<f64> = fine.iter().map(|r| r[0]).collect();
        let v: Vec<f64> = fine.iter().map(|r| r[1]).collect();
        let f = figures(&s, &times, &y, &v);
        eprintln!(
            "{}: reference rebound {:?}, lowest {}, range {range}",
            s.file, f.rebound, f.lowest
        );
    }
}

fn range(y: impl Iterator<Item = f64> + Clone) -> f64 {
    let max = y.clone().fold(f64::MIN, f64::max);
    let min = y.fold(f64::MAX, f64::min);
    max - min
}

/// mbfx against the converged reference: every row's position within 1e-6 of the
/// position's range, and the first rebound's figures (apex time and height under gravity,
/// exit time and speed without) and the first contact's lowest point within 1e-6 relative
/// (times relative to themselves).
fn damped_case(file: &str) {
    let s = scene(file);
    s.check_dataset();
    let mut bad = Vec::new();
    for integrator in INTEGRATORS {
        let (csv, secs) = s.run(integrator, TIGHT);
        let (t, y, v) = (csv.time(), csv.col("y"), csv.col("v"));
        let truth = s.reference(&t, REF_RTOL);
        let (yr, vr): (Vec<f64>, Vec<f64>) = truth.iter().map(|r| (r[0], r[1])).unzip();
        let range = range(yr.iter().copied());
        let (dev, at) =
            (0..t.len())
                .map(|r| ((y[r] - yr[r]).abs(), t[r]))
                .fold(
                    (0.0, 0.0),
                    |m, d| if d.0 > m.0 || d.0.is_nan() { d } else { m },
                );
        let (got, want) = (figures(&s, &t, &y, &v), figures(&s, &t, &yr, &vr));
        let (g, w) = (
            got.rebound.unwrap_or((f64::NAN, f64::NAN)),
            want.rebound.expect("the reference rebounds"),
        );
        let rebound_ok =
            (g.0 - w.0).abs() <= 1e-6 * w.0 && (g.1 - w.1).abs() <= 1e-6 * w.1.abs().max(range);
        let pen = |lo: f64| match s.law {
            Law::Impact { x1, .. } => x1 - lo,
            Law::Bistop { x2, .. } => lo - x2,
        };
        let (pg, pw) = (pen(got.lowest), pen(want.lowest));
        let text = format!(
            "{file} {integrator} ({secs:.2} s): max |y − ref| {dev:.2e} at t = {at} \
             (range {range:.4}); first rebound {g:?} vs {w:?}; first penetration {pg:.12} vs \
             {pw:.12}",
        );
        eprintln!("{text}");
        if !(dev <= 1e-6 * range && rebound_ok && (pg - pw).abs() <= 1e-6 * pw) {
            bad.push(text);
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn impact_damped_single_impact_matches_the_reference() {
    damped_case("impact_damped.adm");
}

#[test]
fn impact_block_dropped_0_1_m_matches_the_reference() {
    damped_case("drop.adm");
}

/// §6.5's warning case: after the clamp switches the force off during the rebound, the
/// spring term takes over again near zero penetration for about 0.3 ms (up to 0.17 N).
#[test]
fn impact_bouncing_ball_matches_the_reference() {
    damped_case("bounce.adm");
}

#[test]
fn bistop_damped_slider_matches_the_reference() {
    damped_case("bistop_damped.adm");
}

/// BISTOP with cmax = 0: every impact is §6.2's Hertz contact at 1 m/s, so the slider's
/// free flights are known exactly: it meets the upper stop at t = 0.1, leaves it t_c later
/// at −1 m/s, meets the lower stop 0.2 s after that, and so on.
#[test]
fn bistop_elastic_slider_bounces_as_hertz_between_the_stops() {
    let (x1, x2, k) = (SLIDER_STOPS.0, SLIDER_STOPS.1, 1e5);
    let s = slider(
        "bistop_elastic.adm",
        "BISTOP(DX(201, 101), VX(201, 101), -0.1, 0.1, 1E5, 1.5, 0, 0.01)",
        0.0,
    );
    s.check_dataset();
    let (_, tc) = hertz(k, 1.5, MASS, 1.0);
    let flight = x2 - x1;
    // Exact (x, v) in free flight at t, None in contact.
    let exact = |t: f64| -> Option<(f64, f64)> {
        if t <= x2 {
            return Some((t, 1.0));
        }
        let n = ((t - x2) / (flight + tc)).floor();
        let since = t - x2 - n * (flight + tc);
        if since < tc {
            return None;
        }
        let (wall, v) = if n as i64 % 2 == 0 {
            (x2, -1.0)
        } else {
            (x1, 1.0)
        };
        Some((wall + v * (since - tc), v))
    };
    let mut bad = Vec::new();
    for integrator in INTEGRATORS {
        let (csv, secs) = s.run(integrator, TIGHT);
        let (t, y, v) = (csv.time(), csv.col("y"), csv.col("v"));
        let (mut dev, mut at, mut dv, mut rows) = (0.0_f64, 0.0, 0.0_f64, 0);
        for r in 0..t.len() {
            if let Some((xe, ve)) = exact(t[r]) {
                // Rows within an output step of a contact's ends may straddle it.
                if exact(t[r] - s.output_step).is_none() || exact(t[r] + s.output_step).is_none() {
                    continue;
                }
                rows += 1;
                if (y[r] - xe).abs() > dev || y[r].is_nan() {
                    (dev, at) = ((y[r] - xe).abs(), t[r]);
                }
                dv = dv.max((v[r] - ve).abs());
            }
        }
        let energy = (0..t.len())
            .map(|r| (0.5 * MASS * v[r] * v[r] + s.law.potential(y[r])) / 0.5)
            .map(|e| (e - 1.0).abs())
            .fold(0.0, f64::max);
        let text = format!(
            "bistop_elastic.adm {integrator} ({secs:.2} s): {rows} free-flight rows, max |x − \
             exact| {dev:.2e} at t = {at}, |v − exact| {dv:.2e}, energy {energy:.1e}"
        );
        eprintln!("{text}");
        // Positions within 1e-6 of the range (the gap plus twice δ_max), speed and energy
        // within 1e-6.
        if !(dev <= 1e-6 * 0.22 && dv <= 1e-6 && energy <= 1e-6 && rows > 700) {
            bad.push(text);
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
