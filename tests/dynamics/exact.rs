//! Exact solutions of the chrono cases that reduce to one degree of freedom (or to two that
//! do not couple), derived by hand from each dataset's numbers and integrated by the
//! independent [`dopri5`](crate::reference::dopri5) at rtol 1e-12.
//!
//! Every such case is one ground-fixed axis `a` through the I marker's origin `p`: the part
//! may turn about it (angle φ), slide along it (s), or both (the cylindrical joint), and a
//! spring may act about or along it. With `r₀ = CM(0) − p` perpendicular to `a` and the
//! part's CM inertia `I` (IP in the CM marker's axes, Adams' sign convention; every case
//! here has zero products), the Lagrangian splits:
//! - turning: `I_a·φ̈ = m·a·(r(φ) × g) − k_φ·φ − c_φ·φ̇`, `r(φ) = Rot(a, φ)·r₀`,
//!   `I_a = aᵀ·I·a + m·|r₀|²` (only `m·|r₀|²` when the part keeps its orientation, as under a
//!   distance constraint acting at its CM);
//! - sliding: `m·s̈ = m·g·a − k_s·s − c_s·ṡ`, because `a·(a × r) = 0` and the turning
//!   inertia does not depend on `s`.
//!
//! A part released at rest under a spherical or universal joint stays in the plane normal
//! to `a` when `a` is a principal axis of `I` (checked) and gravity's torque is along `a`:
//! that motion satisfies the joint and Euler's equations, so it is the motion.
//!
//! Kinematics follow by differentiation: `v = φ̇·a × r + ṡ·a`, `acc = φ̈·a × r +
//! φ̇²·a × (a × r) + s̈·a`, `ω = φ̇·a`, `ω̇ = φ̈·a`, orientation `Rot(a, φ)·R_cm(0)`.
//! The reaction files hold the load of the joint (and spring) on the I marker's part, which
//! is ground in every case: Newton–Euler on the moving part gives the total load on it of
//! the elements tying it to ground, `F = m·(acc − g)` and, about the CM,
//! `M_c = I_R·ω̇ + ω × I_R·ω`; moved to the I marker, `M_p = M_c + (CM − p) × F`; the
//! load on ground is `(−F, −M_p)`. (Checked on Revolute_Case01 against spec multibody.md
//! §8's hand value −0.23919 N at t = 0.)

use crate::adams::{Quantity, QUANTITIES};
use crate::reference::dopri5;
use nalgebra::{Matrix3, Unit, UnitQuaternion, Vector3};

pub type V3 = Vector3<f64>;

pub const G: f64 = 9.80665;

/// Adams REULER (ψ, θ, φ) in degrees, body 3-1-3: Rz(ψ)·Rx(θ)·Rz(φ) (spec multibody.md §2.4).
pub fn reuler(deg: [f64; 3]) -> UnitQuaternion<f64> {
    let [a, b, c] = deg.map(f64::to_radians);
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), a)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), b)
        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), c)
}

/// Euler parameters (e0, e1, e2, e3) from body 3-1-3 angles in radians, as Adams'
/// ORIENT(27, …) reports them: the product of the three half-angle quaternions.
pub fn euler_parameters(psi: f64, theta: f64, phi: f64) -> [f64; 4] {
    let (s, d) = ((psi + phi) / 2.0, (psi - phi) / 2.0);
    let (ct, st) = ((theta / 2.0).cos(), (theta / 2.0).sin());
    [ct * s.cos(), st * d.cos(), st * d.sin(), ct * s.sin()]
}

/// A case reduced to turning about and/or sliding along one ground-fixed axis.
pub struct AxisModel {
    pub name: &'static str,
    pub mass: f64,
    /// IP (Ixx, Iyy, Izz) in the CM marker's axes; the products are zero (see `evidence`).
    pub ip: [f64; 3],
    /// REULER of the CM marker (the part's BCS is ground's in every dataset).
    pub cm_reuler: [f64; 3],
    pub cm0: V3,
    /// The I marker's origin: the pivot and the point the reaction is reported about.
    pub pivot: V3,
    pub axis: V3,
    pub swings: bool,
    /// Whether the part turns with φ (false under a distance constraint at the CM).
    pub rotates: bool,
    pub slides: bool,
    pub gravity: V3,
    /// Torque −k·φ − c·φ̇ about the axis on the part.
    pub rot_spring: (f64, f64),
    /// Force −k·s − c·ṡ along the axis on the part, at its CM.
    pub trans_spring: (f64, f64),
    /// (statement, arguments) the numbers above were read from, checked against the file.
    pub evidence: Vec<(&'static str, Vec<String>)>,
}

/// The state of the reduced system at one output time.
#[derive(Clone, Copy, Debug)]
pub struct State {
    pub phi: f64,
    pub dphi: f64,
    pub ddphi: f64,
    pub s: f64,
    pub ds: f64,
    pub dds: f64,
}

/// Every kinematic and load quantity of the chrono files, in ground axes.
pub struct Kin {
    pub pos: V3,
    pub vel: V3,
    pub acc: V3,
    pub quat: [f64; 4],
    pub avel: V3,
    pub aacc: V3,
    pub rforce: V3,
    pub rtorque: V3,
}

impl Kin {
    pub fn get(&self, q: Quantity) -> Vec<f64> {
        match q {
            Quantity::Pos => self.pos.as_slice().to_vec(),
            Quantity::Vel => self.vel.as_slice().to_vec(),
            Quantity::Acc => self.acc.as_slice().to_vec(),
            Quantity::Quat => self.quat.to_vec(),
            Quantity::Avel => self.avel.as_slice().to_vec(),
            Quantity::Aacc => self.aacc.as_slice().to_vec(),
            Quantity::Rforce => self.rforce.as_slice().to_vec(),
            Quantity::Rtorque => self.rtorque.as_slice().to_vec(),
        }
    }
}

impl AxisModel {
    fn r0(&self) -> V3 {
        self.cm0 - self.pivot
    }

    fn inertia0(&self) -> Matrix3<f64> {
        let r = reuler(self.cm_reuler).to_rotation_matrix().into_inner();
        r * Matrix3::from_diagonal(&V3::from(self.ip)) * r.transpose()
    }

    /// `I_a`: the part's inertia about the axis through the pivot.
    pub fn axis_inertia(&self) -> f64 {
        let own = if self.rotates {
            self.axis.dot(&(self.inertia0() * self.axis))
        } else {
            0.0
        };
        own + self.mass * self.r0().norm_squared()
    }

    fn accelerations(&self, y: &[f64; 4]) -> (f64, f64) {
        let [phi, dphi, s, ds] = *y;
        let a = Unit::new_unchecked(self.axis);
        let ddphi = if self.swings {
            let r = UnitQuaternion::from_axis_angle(&a, phi) * self.r0();
            let (k, c) = self.rot_spring;
            (self.mass * self.axis.dot(&r.cross(&self.gravity)) - k * phi - c * dphi)
                / self.axis_inertia()
        } else {
            0.0
        };
        let dds = if self.slides {
            let (k, c) = self.trans_spring;
            self.gravity.dot(&self.axis) - (k * s + c * ds) / self.mass
        } else {
            0.0
        };
        (ddphi, dds)
    }

    /// The reduced system's state at each time (rtol 1e-12).
    pub fn solve(&self, times: &[f64]) -> Vec<State> {
        assert!(
            (self.axis.norm() - 1.0).abs() < 1e-15,
            "{}: axis",
            self.name
        );
        if self.swings {
            assert!(
                self.r0().dot(&self.axis).abs() < 1e-9,
                "{}: r0 ∦ a",
                self.name
            );
            if self.rotates {
                let ia = self.inertia0() * self.axis;
                assert!(
                    ia.cross(&self.axis).norm() < 1e-12,
                    "{}: a not principal",
                    self.name
                );
            }
        }
        let ys = dopri5(
            |_, y| {
                let (ddphi, dds) = self.accelerations(y);
                [y[1], ddphi, y[3], dds]
            },
            [0.0; 4],
            times,
            1e-12,
            1e-14,
        );
        ys.iter()
            .map(|y| {
                let (ddphi, dds) = self.accelerations(y);
                State {
                    phi: y[0],
                    dphi: y[1],
                    ddphi,
                    s: y[2],
                    ds: y[3],
                    dds,
                }
            })
            .collect()
    }

    /// The CM marker's kinematics and the load on ground at one state (derivation above).
    pub fn kinematics(&self, st: &State) -> Kin {
        let a = self.axis;
        let turn = UnitQuaternion::from_axis_angle(&Unit::new_unchecked(a), st.phi);
        let r = turn * self.r0();
        let pos = self.pivot + st.s * a + r;
        let vel = st.dphi * a.cross(&r) + st.ds * a;
        let acc = st.ddphi * a.cross(&r) + st.dphi.powi(2) * a.cross(&a.cross(&r)) + st.dds * a;
        let (avel, aacc, q) = if self.rotates {
            (st.dphi * a, st.ddphi * a, turn * reuler(self.cm_reuler))
        } else {
            (V3::zeros(), V3::zeros(), reuler(self.cm_reuler))
        };
        let rm = q.to_rotation_matrix().into_inner();
        let inertia = rm * Matrix3::from_diagonal(&V3::from(self.ip)) * rm.transpose();
        let force = self.mass * (acc - self.gravity);
        let m_cm = inertia * aacc + avel.cross(&(inertia * avel));
        let m_pivot = m_cm + (pos - self.pivot).cross(&force);
        let qc = q.quaternion().coords; // nalgebra stores (i, j, k, w)
        Kin {
            pos,
            vel,
            acc,
            quat: [qc[3], qc[0], qc[1], qc[2]],
            avel,
            aacc,
            rforce: -force,
            rtorque: -m_pivot,
        }
    }

    /// All eight quantities at `times`.
    pub fn all_columns(&self, times: &[f64]) -> Vec<(Quantity, Vec<Vec<f64>>)> {
        let kins: Vec<Kin> = self
            .solve(times)
            .iter()
            .map(|s| self.kinematics(s))
            .collect();
        QUANTITIES
            .iter()
            .map(|&q| {
                let rows: Vec<Vec<f64>> = kins.iter().map(|k| k.get(q)).collect();
                let cols = (0..rows[0].len())
                    .map(|c| rows.iter().map(|r| r[c]).collect())
                    .collect();
                (q, cols)
            })
            .collect()
    }
}

fn reuler_z(deg: [f64; 3]) -> V3 {
    reuler(deg) * V3::z()
}

const ROD: [f64; 3] = [0.04, 0.1, 0.1];
const ROD_Z: [f64; 3] = [0.1, 0.1, 0.04];
const NONE: [f64; 3] = [0.0, 0.0, 0.0];
const RX_M90: [f64; 3] = [180.0, 90.0, 180.0];
const RX_M45: [f64; 3] = [180.0, 45.0, 180.0];

fn v(x: f64, y: f64, z: f64) -> V3 {
    V3::new(x, y, z)
}

/// A case without springs. `evidence` lists the statements its numbers come from; for the
/// chrono numbering (`PART/02`, `0201`) name the `joint` ("REVOLUTE", …, or "GCON" for the
/// distance constraint) and the part's mass and IP, the joint's I/J and the gravity are
/// added; with `joint` empty, `evidence` is the whole list.
#[allow(clippy::too_many_arguments)]
fn model(
    name: &'static str,
    ip: [f64; 3],
    cm_reuler: [f64; 3],
    cm0: V3,
    pivot: V3,
    axis: V3,
    (swings, rotates, slides): (bool, bool, bool),
    evidence: &[(&'static str, &[&'static str])],
    joint: &'static str,
) -> AxisModel {
    let mut ev: Vec<(&'static str, Vec<String>)> = Vec::new();
    let mut add = |head: &'static str, args: &[&str]| {
        ev.push((head, args.iter().map(|a| a.to_string()).collect()));
    };
    if !joint.is_empty() {
        let [a, b, c] = ip;
        add(
            "PART/02",
            &["MASS = 1", &format!("CM = 0201, IP = {a}, {b}, {c}")],
        );
    }
    for (head, args) in evidence {
        add(head, args);
    }
    match joint {
        "" => {}
        "GCON" => add("GCON/1", &["I = 0102, FUNCTION = DM(0202, 0102)-2"]),
        kind => add("JOINT/1", &[kind, "I = 0102, J = 0202"]),
    }
    if !joint.is_empty() {
        add("ACCGRAV/", &["KGRAV = -9.80665"]);
    }
    AxisModel {
        name,
        mass: 1.0,
        ip,
        cm_reuler,
        cm0,
        pivot,
        axis,
        swings,
        rotates,
        slides,
        gravity: v(0.0, 0.0, -G),
        rot_spring: (0.0, 0.0),
        trans_spring: (0.0, 0.0),
        evidence: ev,
    }
}

const PENDULUM: (bool, bool, bool) = (true, true, false);
const SLIDE: (bool, bool, bool) = (false, false, true);
const CYLINDER: (bool, bool, bool) = (true, true, true);

/// The RotSpring spring the output was made with (fitted in `springs.rs`): k = 200 N·m/rad,
/// c = 10 N·m·s/rad.
pub const ROTSPRING_FIT: (f64, f64) = (200.0, 10.0);
/// The dataset's: `-1.0*RTOD*AZ - 5.0E-002*RTOD*WZ`, i.e. 1 N·m/deg and 0.05 N·m·s/deg.
pub const ROTSPRING_GIVEN: (f64, f64) = (
    180.0 / std::f64::consts::PI,
    0.05 * 180.0 / std::f64::consts::PI,
);
/// The TransSpring spring the output was made with (fitted in `springs.rs`).
pub const TRANSSPRING_FIT: (f64, f64) = (10.0, 0.5);

/// Revolute_Case01's pendulum with a rotational spring about the joint axis: RotSpring.
pub fn rotspring(spring: (f64, f64)) -> AxisModel {
    AxisModel {
        rot_spring: spring,
        ..model(
            "RotSpring_Case01",
            ROD,
            RX_M90,
            v(2.0, 0.0, 0.0),
            V3::zeros(),
            reuler_z(RX_M90),
            PENDULUM,
            &[
                ("PART/2", &["MASS = 1", "CM = 201", "IP = 0.04, 0.1, 0.1"]),
                ("MARKER/201", &["QP = 2, 0, 0", "REULER = 180D, 90D, 180D"]),
                ("MARKER/102", &["REULER = 180D, 90D, 180D"]),
                ("MARKER/207", &["PART = 1", "REULER = 180D, 90D, 180D"]),
                ("MARKER/208", &["PART = 2", "REULER = 180D, 90D, 180D"]),
                ("JOINT/1", &["REVOLUTE", "I = 102", "J = 202"]),
                ("ACCGRAV/", &["KGRAV = -9.80665"]),
            ],
            "",
        )
    }
}

/// Every case with an exact reduced solution, each from the dataset its output was made
/// with (the corrected copy for RotSpring and TransSpring).
pub fn models() -> Vec<AxisModel> {
    vec![
        // Pendulum about the revolute axis z_I = Rx(−90°)·z = +y; I_a = 0.1 + 1·2².
        model(
            "Revolute_Case01",
            ROD,
            RX_M90,
            v(2.0, 0.0, 0.0),
            V3::zeros(),
            reuler_z(RX_M90),
            PENDULUM,
            &[
                ("MARKER/0201", &["QP = 2, 0, 0", "REULER = 180D, 90D, 180D"]),
                ("MARKER/0102", &["QP = 0, 0, 0", "REULER = 180D, 90D, 180D"]),
            ],
            "REVOLUTE",
        ),
        // Axis Rx(−45°)·z = (0, √½, √½): only g's part normal to the axis drives φ; the
        // axial part goes into the reaction.
        model(
            "Revolute_Case02",
            ROD,
            RX_M45,
            v(3.0, 2.0, 3.0),
            v(1.0, 2.0, 3.0),
            reuler_z(RX_M45),
            PENDULUM,
            &[
                ("MARKER/0201", &["QP = 3, 2, 3", "REULER = 180D, 45D, 180D"]),
                ("MARKER/0102", &["QP = 1, 2, 3", "REULER = 180D, 45D, 180D"]),
            ],
            "REVOLUTE",
        ),
        // Spherical, CM on +x, g on −z: gravity's torque r₀ × g is along +y, a principal
        // axis (Iyy = 0.1), so the part swings in the XZ plane about y.
        model(
            "Spherical_Case01",
            ROD,
            NONE,
            v(2.0, 0.0, 0.0),
            V3::zeros(),
            V3::y(),
            PENDULUM,
            &[
                ("MARKER/0201", &["QP = 2, 0, 0"]),
                ("MARKER/0102", &["QP = 0, 0, 0"]),
            ],
            "SPHERICAL",
        ),
        // As Case01 from (1, 2, 3); the CM marker is Rx(−45°) but Iyy = Izz, so in ground
        // axes the tensor is still diag(0.04, 0.1, 0.1) and y is principal.
        model(
            "Spherical_Case02",
            ROD,
            RX_M45,
            v(3.0, 2.0, 3.0),
            v(1.0, 2.0, 3.0),
            V3::y(),
            PENDULUM,
            &[
                ("MARKER/0201", &["QP = 3, 2, 3", "REULER = 180D, 45D, 180D"]),
                ("MARKER/0102", &["QP = 1, 2, 3", "REULER = 180D, 45D, 180D"]),
            ],
            "SPHERICAL",
        ),
        // HOOKE: the ground cross pin is x_I = Rx(90°)·x = +x; CM on +y, g on −z: the part
        // swings about that pin (a principal axis, Ixx = 0.1 in the Rx(90°) CM marker).
        model(
            "Universal_Case01",
            ROD_Z,
            [0.0, 90.0, 0.0],
            v(0.0, 2.0, 0.0),
            V3::zeros(),
            V3::x(),
            PENDULUM,
            &[
                ("MARKER/0201", &["QP = 0, 2, 0", "REULER = 0D, 90D, 0D"]),
                ("MARKER/0102", &["QP = 0, 0, 0", "REULER = 0D, 90D, 0D"]),
                ("MARKER/0202", &["QP = 0, 0, 0", "REULER = 0D, 90D, 0D"]),
            ],
            "HOOKE",
        ),
        // HOOKE with markers Ry(90°): the part's pin y_J = +y stays along y while the part
        // turns about it; CM on −x.
        model(
            "Universal_Case02",
            ROD_Z,
            [90.0, 90.0, -90.0],
            v(-2.0, 0.0, 0.0),
            V3::zeros(),
            reuler([90.0, 90.0, -90.0]) * V3::y(),
            PENDULUM,
            &[
                ("MARKER/0201", &["QP = -2, 0, 0", "REULER = 90D, 90D, -90D"]),
                ("MARKER/0202", &["QP = 0, 0, 0", "REULER = 90D, 90D, -90D"]),
            ],
            "HOOKE",
        ),
        // Translational along z: free fall, s = −g·t²/2.
        model(
            "Prismatic_Case01",
            ROD,
            NONE,
            v(2.0, 0.0, 0.0),
            V3::zeros(),
            V3::z(),
            SLIDE,
            &[
                ("MARKER/0201", &["QP = 2, 0, 0"]),
                ("MARKER/0102", &["QP = 0, 0, 0"]),
            ],
            "TRANSLATIONAL",
        ),
        // Along (0, √½, √½): s̈ = g·a = −g/√2.
        model(
            "Prismatic_Case02",
            ROD,
            RX_M45,
            v(3.0, 2.0, 3.0),
            v(1.0, 2.0, 3.0),
            reuler_z(RX_M45),
            SLIDE,
            &[
                ("MARKER/0201", &["QP = 3, 2, 3", "REULER = 180D, 45D, 180D"]),
                ("MARKER/0102", &["QP = 1, 2, 3", "REULER = 180D, 45D, 180D"]),
            ],
            "TRANSLATIONAL",
        ),
        // Along +y, horizontal: the part stays, the joint holds its weight.
        model(
            "Prismatic_Case03",
            ROD,
            RX_M90,
            v(3.0, 2.0, 3.0),
            v(1.0, 2.0, 3.0),
            reuler_z(RX_M90),
            SLIDE,
            &[
                ("MARKER/0201", &["QP = 3, 2, 3", "REULER = 180D, 90D, 180D"]),
                ("MARKER/0102", &["QP = 1, 2, 3", "REULER = 180D, 90D, 180D"]),
            ],
            "TRANSLATIONAL",
        ),
        // Cylindrical along z: g ∥ a gives no torque about it, so a free fall with φ = 0.
        model(
            "Cylindrical_Case01",
            ROD,
            NONE,
            v(2.0, 0.0, 0.0),
            V3::zeros(),
            V3::z(),
            CYLINDER,
            &[
                ("MARKER/0201", &["QP = 2, 0, 0"]),
                ("MARKER/0102", &["QP = 0, 0, 0"]),
            ],
            "CYLINDRICAL",
        ),
        // Cylindrical along +y (horizontal): Revolute_Case01's pendulum, s stays 0.
        model(
            "Cylindrical_Case02",
            ROD,
            RX_M90,
            v(2.0, 0.0, 0.0),
            V3::zeros(),
            reuler_z(RX_M90),
            CYLINDER,
            &[
                ("MARKER/0201", &["QP = 2, 0, 0", "REULER = 180D, 90D, 180D"]),
                ("MARKER/0102", &["QP = 0, 0, 0", "REULER = 180D, 90D, 180D"]),
            ],
            "CYLINDRICAL",
        ),
        // Cylindrical along (0, √½, √½): a pendulum under g's normal part and a slide under
        // its axial part, uncoupled.
        model(
            "Cylindrical_Case03",
            ROD,
            RX_M45,
            v(3.0, 2.0, 3.0),
            v(1.0, 2.0, 3.0),
            reuler_z(RX_M45),
            CYLINDER,
            &[
                ("MARKER/0201", &["QP = 3, 2, 3", "REULER = 180D, 45D, 180D"]),
                ("MARKER/0102", &["QP = 1, 2, 3", "REULER = 180D, 45D, 180D"]),
            ],
            "CYLINDRICAL",
        ),
        // GCON DM(0202, 0102) = 2 with 0202 at the CM: the force passes through the CM, so
        // the part keeps its orientation and the CM is a point mass on a sphere, released
        // on +y: it swings about x with I_a = m·2².
        model(
            "Distance_Case01",
            ROD,
            NONE,
            v(0.0, 2.0, 0.0),
            V3::zeros(),
            V3::x(),
            (true, false, false),
            &[
                ("MARKER/0201", &["QP = 0, 2, 0"]),
                ("MARKER/0202", &["QP = 0, 2, 0"]),
                ("MARKER/0102", &["QP = 0, 0, 0"]),
            ],
            "GCON",
        ),
        rotspring(ROTSPRING_FIT),
        // The corrected TransSpring: CM at the origin, spring from ground 204 at (0, 0, 2)
        // to 205 at the CM, free length 2: a vertical mass–spring–damper,
        // s̈ = −g − (k·s + c·ṡ)/m.
        AxisModel {
            trans_spring: TRANSSPRING_FIT,
            ..model(
                "TranSpring_Case01",
                ROD,
                NONE,
                V3::zeros(),
                v(0.0, 0.0, 2.0),
                V3::z(),
                SLIDE,
                &[
                    ("PART/2", &["MASS = 1", "CM = 201", "IP = 0.04, 0.1, 0.1"]),
                    ("MARKER/201", &["PART = 2", "QP = 0, 0, 0"]),
                    ("MARKER/204", &["PART = 1", "QP = 0, 0, 2"]),
                    ("MARKER/205", &["PART = 2", "QP = 0, 0, 0"]),
                    (
                        "SFORCE/1",
                        &[
                            "TRANSLATIONAL",
                            "I = 204",
                            "J = 205",
                            "FUNCTION = - 10.0*(dm(204,205)-2.0)",
                            "- 0.5*vr(204,205)",
                        ],
                    ),
                    ("ACCGRAV/", &["KGRAV = -9.80665"]),
                ],
                "",
            )
        },
    ]
}

/// The arguments of statement `head` (its line and the `,` continuation lines after it,
/// comments skipped), whitespace collapsed.
pub fn statement(adm: &str, head: &str) -> Option<String> {
    let mut lines = adm.lines().map(str::trim);
    let first =
        lines.find(|l| l.split(',').next().map(str::trim) == Some(head) || l.trim_end() == head)?;
    let mut text = first.to_owned();
    for l in lines {
        if l.starts_with('!') || l.is_empty() {
            continue;
        }
        if !l.starts_with(',') {
            break;
        }
        text.push_str(l);
    }
    Some(text.split_whitespace().collect::<Vec<_>>().join(" "))
}

#[test]
fn hand_copied_numbers_are_the_datasets() {
    let cases = crate::adams::CASES;
    for m in models() {
        let case = cases.iter().find(|c| c.name == m.name).expect("case");
        let text = std::fs::read_to_string(case.model()).expect("dataset");
        for (head, args) in &m.evidence {
            let st = statement(&text, head)
                .unwrap_or_else(|| panic!("{}: no {head} in {}", m.name, case.model().display()));
            for arg in args {
                let arg = arg.split_whitespace().collect::<Vec<_>>().join(" ");
                assert!(st.contains(&arg), "{}: {head} lacks `{arg}`: {st}", m.name);
            }
        }
    }
}

#[test]
fn revolute_case01_reaction_at_rest_is_the_spec_hand_value() {
    // spec multibody.md §8: −m·(g − α·r) = −(9.80665 − 9.80665·2·2/4.1) on ground, along z.
    let m = &models()[0];
    let st = m.solve(&[0.0])[0];
    let k = m.kinematics(&st);
    let hand = -(G - G * 2.0 * 2.0 / 4.1);
    assert!((k.rforce.z - hand).abs() < 1e-14, "{}", k.rforce.z);
    assert!((hand - -0.23919).abs() < 1e-5);
}

#[test]
fn euler_parameters_of_reuler_match_the_quaternion_product() {
    let (a, b, c) = (30f64, 40f64, 50f64);
    let q = reuler([a, b, c]).quaternion().coords;
    let e = euler_parameters(a.to_radians(), b.to_radians(), c.to_radians());
    for (x, y) in [q[3], q[0], q[1], q[2]].iter().zip(e) {
        assert!((x - y).abs() < 1e-15);
    }
    // spec multibody.md §2.4's numeric check of R = Rz·Rx·Rz for (30°, 40°, 50°).
    let r = reuler([a, b, c]).to_rotation_matrix().into_inner();
    assert!((r[(0, 0)] - 0.263258).abs() < 1e-6 && (r[(0, 1)] + 0.909616).abs() < 1e-6);
    assert!((r[(2, 2)] - 0.766044).abs() < 1e-6 && (r[(1, 2)] + 0.556670).abs() < 1e-6);
}
