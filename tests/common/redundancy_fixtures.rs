//! Reference mechanisms for the redundancy analysis's tests and bench, built straight from
//! the multibody spec's equations (not from the assembly code): the IFToMM A02 N-four-bar
//! in 3D and 2D and the A04 Bricard loop (reference-problems §4.2, §4.4, §5).
//!
//! Velocity-level rows (spec §4.1, columns [v, ω] of a part in ground axes). For markers I
//! on part a and J on part b with origins p_I, p_J, part centres c_a, c_b, lever arms
//! ρ_I = p_I − c_a, ρ_J = p_J − c_b and separation d = p_I − p_J:
//!
//! * translational Φ = d·e with e ∈ {x_J, y_J, z_J} fixed in b. Since ḋ = v_a + ω_a×ρ_I −
//!   v_b − ω_b×ρ_J and ė = ω_b×e, Φ̇ = e·v_a + (ρ_I×e)·ω_a − e·v_b − ((ρ_J + d)×e)·ω_b,
//!   using (ω×ρ)·e = ω·(ρ×e) and d·(ω×e) = ω·(e×d). The row is divided by the model
//!   length, as the assembly does.
//! * rotational Φ = u·w with u ∈ {x_I, z_I} fixed in a and w ∈ {x_J, y_J, z_J} fixed in b
//!   (Zi.Xj: u = z_I, w = x_J, …). Φ̇ = (ω_a×u)·w + u·(ω_b×w) = (u×w)·(ω_a − ω_b).
//!
//! In 2D the columns are [v_x, v_y, ω_z]: the same rows restricted to those components.
//! Ground (part `None`) has no columns.
//!
//! Test data, not library API: the redundancy unit tests (`src/mbd/redundancy/tests.rs`)
//! and `benches/redundancy.rs` include this file through `#[path]`, and it names the
//! library `mbfx` in both (the library's unit tests see itself under that name).

use mbfx::mbd::equations::{Equation, EquationLabel};
use mbfx::mbd::redundancy::{analyze, AnalysisError, Options, Problem, Report};
use mbfx::mbd::sparse::Triplets;
use mbfx::vocab::elements::{ElementKind, ElementRef, JointType};
use mbfx::vocab::math::{Mat3, Vec3};

/// A marker at the configuration analysed: its part (`None` for ground), origin and axes
/// (columns x, y, z) in ground coordinates.
#[derive(Clone, Debug)]
pub struct Marker {
    pub part: Option<usize>,
    pub origin: Vec3,
    pub axes: Mat3,
}

/// One element: its equations between markers I and J. The fixtures model the
/// translational equations and Zi.Xj, Zi.Yj, Xi.Yj, Zi.Zj; building a row of another
/// equation panics.
#[derive(Clone, Debug)]
pub struct Constraint {
    pub element: ElementRef,
    pub i: Marker,
    pub j: Marker,
    pub equations: Vec<Equation>,
}

/// Moving parts (by their centres) and constraints.
#[derive(Clone, Debug)]
pub struct Mechanism {
    pub dim: usize,
    pub centres: Vec<Vec3>,
    pub constraints: Vec<Constraint>,
    /// The model length translational rows and residuals are divided by.
    pub length: f64,
}

impl Mechanism {
    /// The velocity-level constraint Jacobian, one row per equation in constraint order.
    pub fn jacobian(&self) -> Triplets {
        let per_part = if self.dim == 2 { 3 } else { 6 };
        let rows = self.constraints.iter().map(|c| c.equations.len()).sum();
        let mut t = Triplets::new(rows, per_part * self.centres.len());
        let mut row = 0;
        for c in &self.constraints {
            for &eq in &c.equations {
                for (marker, side) in self.sides(c, eq) {
                    let Some(part) = marker else { continue };
                    let components: &[usize] = if self.dim == 2 {
                        &[0, 1, 5]
                    } else {
                        &[0, 1, 2, 3, 4, 5]
                    };
                    for (k, &comp) in components.iter().enumerate() {
                        t.push(row, per_part * part + k, side[comp]);
                    }
                }
                row += 1;
            }
        }
        t
    }

    /// The two parts an equation's row touches and their 6-component velocity rows.
    fn sides(&self, c: &Constraint, eq: Equation) -> [(Option<usize>, [f64; 6]); 2] {
        let lever = |m: &Marker| m.part.map_or(m.origin, |p| m.origin - self.centres[p]);
        let (i, j) = (&c.i, &c.j);
        let row = |lin: Vec3, ang: Vec3| [lin.x, lin.y, lin.z, ang.x, ang.y, ang.z];
        match translation_axis(eq) {
            Some(k) => {
                let e = j.axes.column(k).into_owned();
                let d = i.origin - j.origin;
                let s = 1.0 / self.length;
                [
                    (i.part, row(e * s, lever(i).cross(&e) * s)),
                    (j.part, row(-e * s, -(lever(j) + d).cross(&e) * s)),
                ]
            }
            None => {
                let (u, w) = rotation_axes(c, eq);
                let g = u.cross(&w);
                [
                    (i.part, row(Vec3::zeros(), g)),
                    (j.part, row(Vec3::zeros(), -g)),
                ]
            }
        }
    }

    /// Φ at this configuration, translational equations in model lengths.
    pub fn residuals(&self) -> Vec<f64> {
        let mut out = Vec::new();
        for c in &self.constraints {
            for &eq in &c.equations {
                out.push(match translation_axis(eq) {
                    Some(k) => (c.i.origin - c.j.origin).dot(&c.j.axes.column(k)) / self.length,
                    None => {
                        let (u, w) = rotation_axes(c, eq);
                        u.dot(&w)
                    }
                });
            }
        }
        out
    }

    pub fn labels(&self) -> Vec<EquationLabel> {
        let mut out = Vec::new();
        for (element, c) in self.constraints.iter().enumerate() {
            out.extend(
                c.equations
                    .iter()
                    .map(|&equation| EquationLabel { element, equation }),
            );
        }
        out
    }

    pub fn elements(&self) -> Vec<ElementRef> {
        self.constraints.iter().map(|c| c.element.clone()).collect()
    }

    /// Runs the analysis on this mechanism, with its residuals.
    pub fn analyze(&self, options: &Options) -> Result<Report, AnalysisError> {
        let (jacobian, labels, elements, residuals) = (
            self.jacobian(),
            self.labels(),
            self.elements(),
            self.residuals(),
        );
        analyze(
            &Problem {
                residuals: Some(&residuals),
                ..Problem::new(&jacobian, &labels, &elements, self.centres.len(), self.dim)
            },
            options,
        )
    }
}

/// The J-axis (0, 1, 2) of a translational equation.
fn translation_axis(eq: Equation) -> Option<usize> {
    match eq {
        Equation::XDelta => Some(0),
        Equation::YDelta => Some(1),
        Equation::ZDelta => Some(2),
        _ => None,
    }
}

/// The I-axis u and J-axis w of a rotational equation u·w = 0.
fn rotation_axes(c: &Constraint, eq: Equation) -> (Vec3, Vec3) {
    let (ui, wj) = match eq {
        Equation::ZiXj => (2, 0),
        Equation::ZiYj => (2, 1),
        Equation::XiYj => (0, 1),
        Equation::ZiZj => (2, 2),
        other => panic!("fixtures build no {other:?} equation"),
    };
    (
        c.i.axes.column(ui).into_owned(),
        c.j.axes.column(wj).into_owned(),
    )
}

/// A right-handed frame whose z axis is `axis`, turned by `spin` about it.
pub fn frame_with_z(axis: Vec3, spin: f64) -> Mat3 {
    let z = axis.normalize();
    let t = if z.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let x0 = (t - z * t.dot(&z)).normalize();
    let y0 = z.cross(&x0);
    let (s, c) = spin.sin_cos();
    let x = x0 * c + y0 * s;
    Mat3::from_columns(&[x, z.cross(&x), z])
}

/// The revolute's equations in `dim` (3D: spec §4.2; 2D: the pinned point).
pub fn revolute_equations(dim: usize) -> Vec<Equation> {
    use Equation::*;
    if dim == 2 {
        vec![XDelta, YDelta]
    } else {
        vec![XDelta, YDelta, ZDelta, ZiXj, ZiYj]
    }
}

/// A revolute joint `JOINT/id` about `axis` through `at` between parts `i` and `j`, both
/// markers with the same axes (turned by `spin` about the hinge).
pub fn revolute(
    id: u32,
    dim: usize,
    at: Vec3,
    axis: Vec3,
    spin: f64,
    i: Option<usize>,
    j: Option<usize>,
) -> Constraint {
    let axes = frame_with_z(axis, spin);
    Constraint {
        element: ElementRef {
            kind: ElementKind::Joint(JointType::Revolute),
            id,
            name: None,
        },
        i: Marker {
            part: i,
            origin: at,
            axes,
        },
        j: Marker {
            part: j,
            origin: at,
            axes,
        },
        equations: revolute_equations(dim),
    }
}

/// The A02 N-four-bar with `n` windows: N + 1 cranks of length 1 pinned to ground at
/// x = 0 … N, tilted by `theta` from upright, and N couplers joining their tops; all hinges
/// about z. Coordinates are multiplied by `unit` (1000 builds the model in mm) and the
/// translational rows divided by `length`.
///
/// Parts: crank k is part k (0 ≤ k ≤ N), coupler k is part N + 1 + k. Joints, window by
/// window: ground–crank k, crank k–coupler k, coupler k–crank k+1; then ground–crank N.
pub fn n_four_bar(n: usize, dim: usize, theta: f64, unit: f64, length: f64) -> Mechanism {
    let base = |k: usize| Vec3::new(k as f64, 0.0, 0.0) * unit;
    let top = |k: usize| base(k) + Vec3::new(theta.sin(), theta.cos(), 0.0) * unit;
    let mut centres: Vec<Vec3> = (0..=n).map(|k| (base(k) + top(k)) / 2.0).collect();
    centres.extend((0..n).map(|k| (top(k) + top(k + 1)) / 2.0));
    let coupler = |k: usize| Some(n + 1 + k);
    let mut constraints = Vec::new();
    let mut hinge = |at: Vec3, i: Option<usize>, j: Option<usize>| {
        let id = constraints.len() as u32 + 1;
        // A different marker spin per joint, so no equation lines up with ground axes.
        let spin = 0.37 * id as f64;
        constraints.push(revolute(id, dim, at, Vec3::z(), spin, i, j));
    };
    for k in 0..n {
        hinge(base(k), Some(k), None);
        hinge(top(k), Some(k), coupler(k));
        hinge(top(k + 1), coupler(k), Some(k + 1));
    }
    hinge(base(n), Some(n), None);
    Mechanism {
        dim,
        centres,
        constraints,
        length,
    }
}

/// The A04 Bricard mechanism at t = 0: five unit rods and six revolutes (reference-problems
/// §4.4 table), rod k is part k − 1.
pub fn bricard() -> Mechanism {
    let v = Vec3::new;
    let corners = [
        v(0.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(1.0, -1.0, 0.0),
        v(1.0, -1.0, 1.0),
        v(0.0, -1.0, 1.0),
        v(0.0, 0.0, 1.0),
    ];
    let axes = [
        Vec3::y(),
        Vec3::z(),
        Vec3::x(),
        Vec3::y(),
        Vec3::z(),
        Vec3::x(),
    ];
    let centres = (0..5)
        .map(|k| (corners[k] + corners[k + 1]) / 2.0)
        .collect();
    let constraints = (0..6usize)
        .map(|k| {
            // Joint k + 1 joins rod k (or ground before rod 1) and rod k + 1 (ground after rod 5).
            let before = k.checked_sub(1);
            let after = (k < 5).then_some(k);
            revolute(k as u32 + 1, 3, corners[k], axes[k], 0.0, after, before)
        })
        .collect();
    Mechanism {
        dim: 3,
        centres,
        constraints,
        length: 1.0,
    }
}
