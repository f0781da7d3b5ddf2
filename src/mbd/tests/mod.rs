//! Tests of the core with truth from outside the code: the worked examples of
//! expr-language §6, closed-form mechanism geometry (pendulum, slider-crank, four-bar),
//! the DOF table of multibody spec §4.2 and the redundancy counts of reference-problems
//! §5, and central finite differences as the oracle for every Jacobian. Shared scene
//! helpers live here; each submodule tests one part of the core.

mod from_model;
mod jacobians;
mod measures;
mod mechanisms;

use super::expr::{Closure, ExprFn};
use super::system::{MarkerHandle, System};
use crate::vocab::elements::{ElementKind, ElementRef, JointType};
use crate::vocab::math::{DMat, Mat3, Vec3};

pub(super) fn rz(a: f64) -> Mat3 {
    *nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), a).matrix()
}

pub(super) fn rot(x: f64, y: f64, z: f64) -> Mat3 {
    *nalgebra::Rotation3::from_scaled_axis(Vec3::new(x, y, z)).matrix()
}

pub(super) fn er(id: u32) -> ElementRef {
    ElementRef {
        kind: ElementKind::Gcon,
        id,
        name: None,
    }
}

/// g(t) = g0 + rate·t with its derivative.
pub(super) fn time_fn(g0: f64, rate: f64) -> Box<dyn ExprFn> {
    Box::new(Closure {
        slots: vec![],
        f: move |t: f64, _: &[f64]| g0 + rate * t,
        g: move |_: f64, _: &[f64], _: &mut [f64]| rate,
    })
}

pub(super) fn dense(t: &super::sparse::Triplets) -> DMat {
    let mut m = DMat::zeros(t.nrows, t.ncols);
    for &(r, c, v) in &t.entries {
        m[(r as usize, c as usize)] += v;
    }
    m
}

pub(super) fn rank(m: &DMat) -> usize {
    if m.nrows() == 0 {
        return 0;
    }
    let s = m.clone().svd(false, false).singular_values;
    let tol = 1e-9 * s.max().max(1.0);
    s.iter().filter(|&&x| x > tol).count()
}

pub(super) fn ground_marker(sys: &mut System, at: Vec3, r: Mat3) -> MarkerHandle {
    sys.add_marker(None, System::GROUND, at, r)
}

pub(super) fn rev(sys: &mut System, id: u32, i: MarkerHandle, j: MarkerHandle) {
    let e = ElementRef {
        kind: ElementKind::Joint(JointType::Revolute),
        id,
        name: None,
    };
    sys.joint(e, JointType::Revolute, i, j, 0.0).unwrap();
}
