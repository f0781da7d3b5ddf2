//! Joint FRICTION (issue 40 §2) against closed forms written here: a flywheel on a
//! revolute under a known radial load slows at μd·Rp·N/J; a block sliding on a
//! translational joint stops after v0²/(2·μd·g); below the stiction force a pushed block
//! holds, deflected by its stiction deformation P·δmax/(μs·N) (a flywheel and a ball
//! under a torque likewise, at δ/R), in a run and in statics; above it the block slides
//! off with acceleration (P − μd·N)/m. The load is the joint's own reaction, solved with
//! the motion.

use mbfx::session::request::{run, RunRequest};
use mbfx::session::DimRequest;

const G: f64 = 9.81;

/// Runs `text` to `end` with output step `dt`, probing `probes`, in `dim`; the rows and
/// the header.
fn run_with(
    text: &str,
    end: f64,
    dt: f64,
    probes: &[(&str, &str)],
    dim: DimRequest,
) -> (Vec<Vec<f64>>, Vec<String>) {
    let mut r = RunRequest::dataset("friction.adm", text);
    (r.end, r.output_step, r.error, r.dim) = (Some(end), Some(dt), Some(1e-6), dim);
    r.probes = probes
        .iter()
        .map(|(n, e)| (n.to_string(), e.to_string()))
        .collect();
    let mut out = Vec::new();
    let mut sink = |row: &[f64]| -> std::io::Result<()> {
        out.push(row.to_vec());
        Ok(())
    };
    let done = run(&r, &mut sink, None).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(
        !done.summary.warnings.iter().any(|w| w.contains("FRICTION")),
        "{:?}",
        done.summary.warnings
    );
    (out, done.header)
}

/// [`run_with`]'s rows.
fn rows(text: &str, end: f64, dt: f64, probes: &[(&str, &str)], dim: DimRequest) -> Vec<Vec<f64>> {
    run_with(text, end, dt, probes, dim).0
}

// The flywheel: m on its axis, gravity across it, so the pin carries N = m·g.
const M: f64 = 10.0;
const JZ: f64 = 0.5;
const RP: f64 = 0.05;
const MU_S: f64 = 0.3;
const MU_D: f64 = 0.2;
const VS: f64 = 0.01;
const W0: f64 = 5.0;

fn flywheel() -> String {
    format!(
        "flywheel\nPART/1, GROUND\nMARKER/10, PART = 1\n\
         PART/2, MASS = {M}, CM = 20, IP = 0.3, 0.3, {JZ}, WZ = {W0}\nMARKER/20, PART = 2\n\
         JOINT/1, REVOLUTE, I = 20, J = 10\n\
         FRICTION/1, JOINT = 1, MU_STATIC = {MU_S}, MU_DYNAMIC = {MU_D}, PIN_RADIUS = {RP}, \
         STICTION_TRANSITION_VELOCITY = {VS}, TRANSITION_VELOCITY_COEFFICIENT = 1.5\n\
         ACCGRAV/JGRAV = -{G}\nEND\n"
    )
}

#[test]
fn a_flywheel_slows_at_mu_r_n_over_j_and_stops() {
    let alpha = MU_D * RP * M * G / JZ;
    let stop = W0 / alpha;
    // Full sliding down to the slip speed 1.5·VS, that is ω = 1.5·VS/RP.
    let sliding_until = (W0 - 1.5 * VS / RP) / alpha;
    let probes = [
        ("w", "WZ(20, 10)"),
        ("t", "FRICTION(1, 0, 8, 10)"),
        ("n", "JOINT(1, 0, 3, 10)"),
    ];
    for dim in [DimRequest::Auto, DimRequest::Three] {
        let (out, header) = run_with(&flywheel(), stop + 5.0, 0.01, &probes, dim);
        // The run's own friction columns follow the probes.
        assert_eq!(
            header[4..],
            ["FRICTION1.F", "FRICTION1.T", "FRICTION1.V"],
            "{header:?}"
        );
        for r in out.iter().filter(|r| r[0] < sliding_until - 0.01) {
            let want = W0 - alpha * r[0];
            assert!(
                (r[1] - want).abs() < 1e-6 * W0,
                "{dim:?} t = {}: ω {} vs {want}",
                r[0],
                r[1]
            );
            // The friction torque on the wheel: −μd·Rp·N, N the pin's reaction m·g.
            assert!(
                (r[2] + MU_D * RP * M * G).abs() < 1e-6 * MU_D * RP * M * G,
                "{dim:?} t = {}: torque {}",
                r[0],
                r[2]
            );
            assert!(
                (r[3] - M * G).abs() < 1e-6 * M * G,
                "{dim:?} reaction {}",
                r[3]
            );
            assert_eq!(r[5], -r[2], "{dim:?}: the torque column is the magnitude");
            assert!((r[6] - RP * r[1]).abs() < 1e-12, "{dim:?}: slip {}", r[6]);
        }
        // Stopped: the stiction deformation gathered while stopping (about vs²/(2·a),
        // 5 % of δmax here) springs back at the rate vs/δmax = 1/s: after 5 s, at
        // about 1e-4 rad/s.
        let last = out.last().expect("rows");
        assert!(
            last[1].abs() < 1e-3,
            "{dim:?} ω at {}: {}",
            last[0],
            last[1]
        );
    }
}

/// A block of 2 kg on a translational joint along x, gravity across it, given `extra`.
fn block(extra: &str) -> String {
    block_with(extra, "")
}

/// [`block`] with `friction` added to its FRICTION.
fn block_with(extra: &str, friction: &str) -> String {
    format!(
        "block\nPART/1, GROUND\nMARKER/10, PART = 1, REULER = 90D, 90D, 0\nMARKER/11, PART = 1\n\
         MARKER/12, PART = 1, FLOATING\n\
         PART/2, MASS = 2, CM = 20, IP = 0.1, 0.1, 0.1{extra}\n\
         MARKER/20, PART = 2, REULER = 90D, 90D, 0\n\
         JOINT/1, TRANSLATIONAL, I = 20, J = 10\n\
         FRICTION/1, JOINT = 1, MU_STATIC = {MU_S}, MU_DYNAMIC = {MU_D}, \
         STICTION_TRANSITION_VELOCITY = {VS}{friction}\n\
         ACCGRAV/JGRAV = -{G}\n"
    )
}

#[test]
fn a_sliding_block_stops_after_v0_squared_over_2_mu_g() {
    let v0 = 2.0;
    let text = block(&format!(", VX = {v0}")) + "END\n";
    let out = rows(
        &text,
        1.5,
        0.01,
        &[("x", "DX(20, 11)"), ("v", "VX(20, 11)")],
        DimRequest::Auto,
    );
    let a = MU_D * G;
    for r in out.iter().filter(|r| v0 - a * r[0] > 1.5 * VS + 0.01) {
        let want = v0 - a * r[0];
        assert!(
            (r[2] - want).abs() < 1e-6 * v0,
            "t = {}: v {} vs {want}",
            r[0],
            r[2]
        );
    }
    let last = out.last().expect("rows");
    let want = v0 * v0 / (2.0 * a);
    // The last 1.5·VS of speed is shed over a creep of at most (1.5·VS)²/(2·a)·(μd/μ).
    assert!(
        (last[1] - want).abs() < 1e-3 * want,
        "stopped at {} vs {want}",
        last[1]
    );
    assert!(last[2].abs() < 1e-3, "v {}", last[2]);
}

/// MAX_STICTION_DEFORMATION of the hold tests.
const DMAX: f64 = 1e-3;

/// The row of `out` at time `t`.
fn row_at(out: &[Vec<f64>], t: f64) -> &[f64] {
    (out.iter().find(|r| (r[0] - t).abs() < 1e-9)).unwrap_or_else(|| panic!("no row at {t}"))
}

/// Asserts a hold: column 1 of `out` at `settled` within 1e-6 of `want` (relative), and
/// unchanged by 1e-9 from there to the end.
fn assert_holds(out: &[Vec<f64>], settled: f64, want: f64, what: &str) {
    let at = row_at(out, settled)[1];
    assert!(
        (at - want).abs() < 1e-6 * want.abs(),
        "{what}: held at {at} vs {want}"
    );
    let last = out.last().expect("rows");
    assert!(
        (last[1] - at).abs() < 1e-9,
        "{what}: crept {} from t = {settled} to {}",
        last[1] - at,
        last[0]
    );
}

#[test]
fn a_block_sticks_below_the_stiction_force_and_slides_above() {
    let n = 2.0 * G;
    // Below: P = 0.8·μs·N holds, the stiction deformation a spring of μs·N/δmax:
    // x = P·δmax/(μs·N), and no creep over the 10 s that follow.
    let p = 0.8 * MU_S * n;
    let want = p * DMAX / (MU_S * n);
    let text = block_with("", &format!(", MAX_STICTION_DEFORMATION = {DMAX}"))
        + &format!("SFORCE/1, TRANSLATION, ACTIONONLY, I = 20, J = 10, FUNCTION = {p}\nEND\n");
    for dim in [DimRequest::Auto, DimRequest::Three] {
        let out = rows(
            &text,
            12.0,
            0.05,
            &[("x", "DX(20, 11)"), ("v", "VX(20, 11)")],
            dim,
        );
        assert_holds(&out, 2.0, want, &format!("{dim:?}"));
    }
    // Above: P = 1.2·μs·N breaks free and accelerates at (P − μd·N)/m once sliding.
    let p = 1.2 * MU_S * n;
    let text = block("")
        + &format!("SFORCE/1, TRANSLATION, ACTIONONLY, I = 20, J = 10, FUNCTION = {p}\nEND\n");
    let out = rows(
        &text,
        1.0,
        0.01,
        &[("x", "DX(20, 11)"), ("v", "VX(20, 11)")],
        DimRequest::Auto,
    );
    let a = (p - MU_D * n) / 2.0;
    let slope = (row_at(&out, 1.0)[2] - row_at(&out, 0.5)[2]) / 0.5;
    assert!((slope - a).abs() < 1e-4 * a, "a {slope} vs {a}");
}

#[test]
fn a_pushed_block_holds_in_statics() {
    // Statics holds the joint where it starts: the equilibrium deflects it by
    // P·δmax/(μs·N), and the run from there stays.
    let n = 2.0 * G;
    let p = 0.5 * MU_S * n;
    let want = p * DMAX / (MU_S * n);
    let text = block_with("", &format!(", MAX_STICTION_DEFORMATION = {DMAX}"))
        + &format!("SFORCE/1, TRANSLATION, ACTIONONLY, I = 20, J = 10, FUNCTION = {p}\nEND\n");
    for dim in [DimRequest::Auto, DimRequest::Three] {
        let mut r = RunRequest::dataset("friction.adm", &text);
        (r.end, r.output_step, r.error, r.dim) = (Some(2.0), Some(0.5), Some(1e-6), dim);
        r.statics = true;
        r.probes = vec![("x".into(), "DX(20, 11)".into())];
        let mut out = Vec::new();
        let mut sink = |row: &[f64]| -> std::io::Result<()> {
            out.push(row.to_vec());
            Ok(())
        };
        run(&r, &mut sink, None).unwrap_or_else(|e| panic!("{dim:?}: {e:?}"));
        assert_holds(&out, 0.0, want, &format!("{dim:?} statics"));
    }
}

/// A wheel of `joint` (REVOLUTE or SPHERICAL, its radius argument `radius`) at rest,
/// loaded as the flywheel, under a torque `t` about z.
fn wheel_under(joint: &str, radius: &str, t: f64) -> String {
    format!(
        "wheel\nPART/1, GROUND\nMARKER/10, PART = 1\n\
         PART/2, MASS = {M}, CM = 20, IP = 0.3, 0.3, {JZ}\nMARKER/20, PART = 2\n\
         JOINT/1, {joint}, I = 20, J = 10\n\
         FRICTION/1, JOINT = 1, MU_STATIC = {MU_S}, MU_DYNAMIC = {MU_D}, {radius} = {RP}, \
         STICTION_TRANSITION_VELOCITY = {VS}, MAX_STICTION_DEFORMATION = {DMAX}\n\
         SFORCE/1, ROTATION, ACTIONONLY, I = 20, J = 10, FUNCTION = {t}\n\
         ACCGRAV/JGRAV = -{G}\nEND\n"
    )
}

#[test]
fn a_flywheel_and_a_ball_under_a_torque_below_stiction_hold_at_delta_over_r() {
    // N = R·m·g (the pin's or ball's reaction at its radius): the stiction spring is
    // μs·R·m·g/δmax on the slip δ = R·θ, so T holds at θ = δ/R with
    // δ = T·δmax/(μs·R·m·g).
    let t = 0.5 * MU_S * RP * M * G;
    let delta = t * DMAX / (MU_S * RP * M * G);
    let cases = [
        ("REVOLUTE", "PIN_RADIUS", DimRequest::Auto),
        ("REVOLUTE", "PIN_RADIUS", DimRequest::Three),
        ("SPHERICAL", "BALL_RADIUS", DimRequest::Three),
    ];
    for (joint, radius, dim) in cases {
        let out = rows(
            &wheel_under(joint, radius, t),
            8.0,
            0.05,
            &[("a", "AZ(20, 10)")],
            dim,
        );
        assert_holds(&out, 3.0, delta / RP, &format!("{joint} {dim:?}"));
    }
}

#[test]
fn a_block_whose_friction_loads_its_own_joint_slows_at_the_loops_closed_form() {
    // The block's CM stands H above its joint marker I, where the friction f acts: the
    // joint holds the block upright with a bending moment H·|f| (about I, m·a = f at
    // the CM), which loads the friction through Xs (INITIAL_OVERLAP) as N = m·g +
    // H·|f|/Xs. With |f| = μd·N: N = m·g/(1 − μd·H/Xs). The loop's gain μd·H/Xs is
    // 0.9 here: repeating the solve would shed a tenth of its error per sweep. (EFFECT =
    // SLIDING keeps μ ≤ μd as the block stops: with μs the gain would pass 1 there, and
    // the block would jam, N growing without bound, as a drawer pushed from too high.)
    const H: f64 = 0.45;
    const XS: f64 = 0.1;
    let gain = MU_D * H / XS;
    let a = MU_D * G / (1.0 - gain);
    let v0 = 4.0;
    let text = format!(
        "loop\nPART/1, GROUND\nMARKER/10, PART = 1, REULER = 90D, 90D, 0\nMARKER/11, PART = 1\n\
         PART/2, MASS = 2, CM = 21, IP = 0.1, 0.1, 0.1, VX = {v0}\n\
         MARKER/20, PART = 2, REULER = 90D, 90D, 0\nMARKER/21, PART = 2, QP = 0, {H}, 0\n\
         JOINT/1, TRANSLATIONAL, I = 20, J = 10\n\
         FRICTION/1, JOINT = 1, MU_STATIC = {MU_S}, MU_DYNAMIC = {MU_D}, \
         STICTION_TRANSITION_VELOCITY = {VS}, INITIAL_OVERLAP = {XS}, EFFECT = SLIDING\n\
         ACCGRAV/JGRAV = -{G}\nEND\n"
    );
    let stop = v0 / a;
    for dim in [DimRequest::Auto, DimRequest::Three] {
        let out = rows(
            &text,
            stop + 0.1,
            0.005,
            &[("x", "DX(20, 11)"), ("v", "VX(20, 11)")],
            dim,
        );
        let sliding: Vec<_> = (out.iter())
            .filter(|r| v0 - a * r[0] > 1.5 * VS + 0.01)
            .collect();
        assert!(
            sliding.len() > 30,
            "{dim:?}: {} rows sliding",
            sliding.len()
        );
        for r in sliding {
            let want = v0 - a * r[0];
            assert!(
                (r[2] - want).abs() < 1e-6 * v0,
                "{dim:?} t = {}: v {} vs {want}",
                r[0],
                r[2]
            );
        }
        let last = out.last().expect("rows");
        let want = v0 * v0 / (2.0 * a);
        assert!(
            (last[1] - want).abs() < 1e-3 * want,
            "{dim:?}: stopped at {} vs {want}",
            last[1]
        );
    }
}

#[test]
fn a_held_block_linearizes_with_its_stiction_deformation() {
    // Held at P = 0.5·μs·N (statics), on (x, ẋ, δ): ẍ = −(c·ẋ + k·δ)/m and δ̇ = ẋ with
    // k = μs·N/δmax, c = μs·N/vs (δ elastic there), so A = [[0, 1, 0], [0, −c/m, −k/m],
    // [0, 1, 0]] (up to the coordinate's sign, which flips A[1][2] and A[2][1] together).
    let (m, n) = (2.0, 2.0 * G);
    let (k, c) = (MU_S * n / DMAX, MU_S * n / VS);
    let p = 0.5 * MU_S * n;
    let text = block_with("", &format!(", MAX_STICTION_DEFORMATION = {DMAX}"))
        + &format!("SFORCE/1, TRANSLATION, ACTIONONLY, I = 20, J = 10, FUNCTION = {p}\nEND\n");
    for dim in [DimRequest::Auto, DimRequest::Three] {
        let mut r = RunRequest::dataset("friction.adm", &text);
        (r.statics, r.dim) = (true, dim);
        r.linear = Some(mbfx::session::request::LinearRequest::eigensol(None));
        let mut sink = |_: &[f64]| -> std::io::Result<()> { Ok(()) };
        let done = run(&r, &mut sink, None).unwrap_or_else(|f| panic!("{}", f.cause));
        let lin = &done.summary.linear[0].linearized;
        assert_eq!(lin.state_names()[2], "FRICTION/1 δ1", "{dim:?}");
        let a = lin.state_matrix().expect("state matrix");
        let close = |got: f64, want: f64, what: &str| {
            assert!(
                (got - want).abs() < 1e-6 * (1.0 + want.abs()),
                "{dim:?} {what}: {got} vs {want}\n{a}"
            )
        };
        for (r, col) in [(0, 0), (0, 2), (1, 0), (2, 0), (2, 2)] {
            close(a[(r, col)], 0.0, &format!("A[{r}][{col}]"));
        }
        close(a[(0, 1)], 1.0, "A[0][1]");
        close(a[(1, 1)], -c / m, "A[1][1]");
        close(a[(2, 1)].abs(), 1.0, "|A[2][1]|");
        close(a[(1, 2)] * a[(2, 1)], -k / m, "A[1][2]·A[2][1]");
    }
}
