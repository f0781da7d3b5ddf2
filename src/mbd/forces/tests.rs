//! Every force law's Q against its own definition at a known state, and its exact
//! Jacobians against central differences of Q (the test oracle DESIGN.md allows).
use crate::mbd::compiled::CompiledExprs;
use crate::mbd::dynamics::Dynamics;
use crate::mbd::planar::Dim;
use crate::mbd::system::System;
use crate::model::read_model;
use crate::vocab::math::DVec;

/// Two free parts in 3D, every force kind between them.
const FORCES: &str = "forces\nPART/1, GROUND\nMARKER/10, PART = 1\n\
    PART/2, MASS = 2, CM = 20, IP = 1, 2, 3, QG = 0.1, 0.2, 0.3, REULER = 10D, 20D, 30D, VX = 0.3, WZ = 0.7\n\
    MARKER/20, PART = 2\nMARKER/21, PART = 2, QP = 0.5, -0.2, 0.1, REULER = 5D, 10D, 15D\n\
    PART/3, MASS = 1, CM = 30, IP = 1, 1, 1, QG = 1.1, 0.4, -0.2, WX = -0.4, VY = 0.2\n\
    MARKER/30, PART = 3\nMARKER/31, PART = 3, QP = -0.3, 0.2, 0.0, REULER = 0, 12D, 0\n\
    MARKER/32, PART = 3, FLOATING\n\
    SFORCE/1, TRANSLATION, I = 21, J = 31, FUNCTION = -50*(DM(21,31) - 1) - 3*VR(21,31) + 0.1*TIME\n\
    SFORCE/2, ROTATION, I = 21, J = 31, FUNCTION = -4*AZ(21,31) - 0.5*WZ(21,31,31)\n\
    SFORCE/3, TRANSLATION, ACTIONONLY, I = 31, J = 21, FUNCTION = DX(31,21)*DY(21,31)\n\
    SPRINGDAMPER/1, TRANSLATION, I = 21, J = 31, K = 30, C = 2, LENGTH = 0.8, FORCE = 1\n\
    SPRINGDAMPER/2, ROTATION, I = 21, J = 31, KT = 5, CT = 0.3, ANGLE = 0.1, TORQUE = 0.2\n\
    BUSHING/1, I = 21, J = 31, K = 10, 20, 30, C = 1, 2, 3, KT = 4, 5, 6, CT = 0.1, 0.2, 0.3, FORCE = 0.1, 0.2, 0.3, TORQUE = 0.01, 0.02, 0.03\n\
    GFORCE/1, I = 21, JFLOAT = 32, RM = 31, FX = VX(21,31)\\ FY = 2*DZ(21,31)\\ FZ = 1\\ TX = WX(21,31)\\ TY = 0.5\\ TZ = DM(21,31)\\\n\
    BEAM/1, I = 21, J = 31, LENGTH = 0.9, AREA = 0.01, IXX = 2E-5, IYY = 1E-5, IZZ = 1.5E-5, ASY = 1.2, ASZ = 1.1, EMODULUS = 2E5, GMODULUS = 8E4, CRATIO = 0.01\n\
    FIELD/1, I = 21, J = 31, KMATRIX = -3, 4, 0, 7, 3, -1, 6, 2, -2, 5, 1, -3, 4, 0, 7, 3, -1, 6, 2, -2, 5, 1, -3, 4, 0, 7, 3, -1, 6, 2, -2, 5, 1, -3, 4, 0, CRATIO = 0.05, LENGTH = 0.7, 0.1, -0.1, 0.05, 0, 0.02, FORCE = 1, 2, 3, 0.1, 0.2, 0.3\n\
    JOINT/1, CYLINDRICAL, I = 21, J = 31\n\
    FRICTION/1, JOINT = 1, MU_STATIC = 0.3, MU_DYNAMIC = 0.2, STICTION_TRANSITION_VELOCITY = 2, FRICTION_FORCE_PRELOAD = 5, INITIAL_OVERLAP = 0.5, OVERLAP_DELTA = INCREASE, PIN_RADIUS = 0.3\n\
    FRICTION/2, JOINT = 1, MU_STATIC = 0.3, MU_DYNAMIC = 0.2, STICTION_TRANSITION_VELOCITY = 0.2, TRANSITION_VELOCITY_COEFFICIENT = 10, FRICTION_FORCE_PRELOAD = 5, PIN_RADIUS = 0.3\n\
    END\n";

fn dynamics() -> Dynamics {
    let read = read_model(FORCES);
    assert!(!read.has_errors(), "{:?}", read.diagnostics);
    let exprs = CompiledExprs::new();
    let mut sys = System::from_model(&read.model, Dim::Three, &exprs).unwrap();
    sys.time = 0.3;
    let forces = sys.forces_from_model(&read.model, &exprs).unwrap();
    assert_eq!(forces.elements.len(), 11);
    Dynamics::new(sys, forces, &[]).unwrap()
}

fn q_of(d: &mut Dynamics) -> DVec {
    d.eval_forces(false).unwrap();
    d.gen.q.clone()
}

/// Column `c` of the Jacobian `k` against the central difference of Q from the
/// states `up` and `down`, ±h apart in coordinate `what` c.
fn column_matches(k: &[Vec<f64>], c: usize, up: &DVec, down: &DVec, h: f64, what: &str) {
    for (r, row) in k.iter().enumerate() {
        let fd = (up[r] - down[r]) / (2.0 * h);
        assert!(
            (row[c] - fd).abs() < 1e-5 * (1.0 + fd.abs()),
            "dQ{r}/d{what}{c}: {} vs {fd}",
            row[c]
        );
    }
}

#[test]
fn force_jacobians_match_central_differences() {
    let mut d = dynamics();
    d.eval_forces(true).unwrap();
    // The frictions act here (their preload loads them; their slip is in the stiction
    // branch for FRICTION/1 and in the transition for FRICTION/2).
    for l in &d.forces.loads[9..] {
        assert!(l.on_i.0.norm() > 1e-3 && l.on_i.1.norm() > 1e-3, "{l:?}");
    }
    let n = d.n;
    let (mut kq, mut kv) = (vec![vec![0.0; n]; n], vec![vec![0.0; n]; n]);
    for &(r, c, x) in &d.gen.dq {
        kq[r][c] += x;
    }
    for &(r, c, x) in &d.gen.dv {
        kv[r][c] += x;
    }
    let base = d.snapshot();
    let v0 = d.sys.v();
    let h = 1e-6;
    for c in 0..n {
        let mut dx = vec![0.0; n];
        let mut at = |s: f64, d: &mut Dynamics| {
            dx[c] = s * h;
            d.set_state(&base, &dx, &v0, 0.3);
            q_of(d)
        };
        let (up, down) = (at(1.0, &mut d), at(-1.0, &mut d));
        column_matches(&kq, c, &up, &down, h, "q");
        let mut v = v0.clone();
        v[c] += h;
        d.set_state(&base, &vec![0.0; n], &v, 0.3);
        let up = q_of(&mut d);
        v[c] -= 2.0 * h;
        d.set_state(&base, &vec![0.0; n], &v, 0.3);
        let down = q_of(&mut d);
        column_matches(&kv, c, &up, &down, h, "v");
    }
}

#[test]
fn action_reaction_forces_balance() {
    // Without gravity and with only action-reaction elements between parts 2 and 3
    // (SFORCE/3 acts on I alone, so leave it out), the total force and the total
    // moment about the origin vanish.
    let text = FORCES.replace(
        "SFORCE/3, TRANSLATION, ACTIONONLY, I = 31, J = 21, FUNCTION = DX(31,21)*DY(21,31)\n",
        "",
    );
    let read = read_model(&text);
    let exprs = CompiledExprs::new();
    let mut sys = System::from_model(&read.model, Dim::Three, &exprs).unwrap();
    let forces = sys.forces_from_model(&read.model, &exprs).unwrap();
    let mut d = Dynamics::new(sys, forces, &[]).unwrap();
    d.eval_forces(false).unwrap();
    let (mut f, mut m) = (
        crate::vocab::math::Vec3::zeros(),
        crate::vocab::math::Vec3::zeros(),
    );
    for p in d.sys.parts.iter().filter(|p| p.index.is_some()) {
        let b = 6 * p.index.unwrap();
        let fp = crate::vocab::math::Vec3::new(d.gen.q[b], d.gen.q[b + 1], d.gen.q[b + 2]);
        let tp = crate::vocab::math::Vec3::new(d.gen.q[b + 3], d.gen.q[b + 4], d.gen.q[b + 5]);
        // Remove the gyroscopic moment −ω × (J ω), which is no applied force.
        let j = p.inertia_global();
        let gyro = -p.w.cross(&(j * p.w));
        f += fp;
        m += tp - gyro + p.r.cross(&fp);
    }
    assert!(f.norm() < 1e-12 && m.norm() < 1e-12, "{f} {m}");
}
