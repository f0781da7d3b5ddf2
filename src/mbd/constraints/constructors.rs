//! The constructors of constraint elements: each JOINT, JPRIM and Exudyn's 2D prismatic
//! joint lists primitive equations between its two markers; RACKPIN, SCREW and MOTION
//! are measures minus a drive, GCON an expression of measures. They add [`Element`]s to
//! the system.

use crate::mbd::equations::Equation;
use crate::mbd::error::MbdError;
use crate::mbd::expr::ExprFn;
use crate::mbd::handles::{ElementHandle, MarkerHandle};
use crate::mbd::measure_set::Measure;
use crate::mbd::rows::{Element, Equ, Row};
use crate::mbd::system::System;
use crate::vocab::elements::{ElementKind, ElementRef, JointType, JprimType};
use crate::vocab::math::Vec3;
use std::f64::consts::PI;

/// The primitive equations of a JOINT or JPRIM type (spec §4.2), in Adams label order.
pub fn primitive_set(kind: ElementKind) -> &'static [Equation] {
    use Equation::*;
    const XYZ: &[Equation] = &[XDelta, YDelta, ZDelta];
    match kind {
        ElementKind::Joint(t) => match t {
            JointType::Fixed => &[XDelta, YDelta, ZDelta, ZiXj, ZiYj, XiYj],
            JointType::Revolute => &[XDelta, YDelta, ZDelta, ZiXj, ZiYj],
            JointType::Spherical => XYZ,
            JointType::Translational => &[XDelta, YDelta, ZiXj, ZiYj, XiYj],
            JointType::Cylindrical => &[XDelta, YDelta, ZiXj, ZiYj],
            JointType::Planar => &[ZDelta, ZiXj, ZiYj],
            JointType::Hooke => &[XDelta, YDelta, ZDelta, XiYj],
            JointType::Universal => &[XDelta, YDelta, ZDelta, ZiZj],
            JointType::Convel => &[XDelta, YDelta, ZDelta, Convel],
            JointType::Rackpin => &[Rackpin],
            JointType::Screw => &[Screw],
        },
        ElementKind::Jprim(t) => match t {
            JprimType::Atpoint => XYZ,
            JprimType::Inline => &[XDelta, YDelta],
            JprimType::Inplane => &[ZDelta],
            JprimType::Orientation => &[ZiXj, ZiYj, XiYj],
            JprimType::ParallelAxes => &[ZiXj, ZiYj],
            JprimType::Perpendicular => &[ZiZj],
        },
        ElementKind::Prismatic2d => &[YDelta, XiYj],
        ElementKind::Gcon => &[Gcon],
        ElementKind::Motion => &[Motion],
        ElementKind::Force(_) => &[],
    }
}

fn axis(c: usize) -> Vec3 {
    let mut v = Vec3::zeros();
    v[c] = 1.0;
    v
}

impl System {
    fn check_pair(&self, e: &ElementRef, i: MarkerHandle, j: MarkerHandle) -> Result<(), MbdError> {
        for m in [i, j] {
            if self.marker(m).floating {
                return Err(MbdError::Floating(
                    e.clone(),
                    self.marker(m).id.unwrap_or(0) as i64,
                ));
            }
        }
        if self.marker(i).part == self.marker(j).part {
            return Err(MbdError::SamePart(e.clone()));
        }
        Ok(())
    }

    /// Adds an element with its equations.
    pub fn add_element(&mut self, elref: ElementRef, eqs: Vec<Equ>) -> ElementHandle {
        self.elements.push(Element { elref, eqs });
        ElementHandle(self.elements.len() as u32 - 1)
    }

    fn primitives(
        &mut self,
        elref: ElementRef,
        i: MarkerHandle,
        j: MarkerHandle,
    ) -> Result<ElementHandle, MbdError> {
        self.check_pair(&elref, i, j)?;
        let eqs = primitive_set(elref.kind)
            .iter()
            .map(|&eq| self.primitive(eq, i, j))
            .collect::<Result<_, _>>()?;
        Ok(self.add_element(elref, eqs))
    }

    /// One primitive equation of spec §4.1 (plus Zi.Zj and CONVEL's x_I·y_J + y_I·x_J,
    /// whose two terms are UVX(I, J)-type measures).
    fn primitive(
        &mut self,
        eq: Equation,
        i: MarkerHandle,
        j: MarkerHandle,
    ) -> Result<Equ, MbdError> {
        use Equation::*;
        let along = |c| Row::Along {
            i,
            j,
            dir: axis(c),
            sign: 1.0,
        };
        let dot = |a, b| Row::Dot {
            i,
            j,
            a: axis(a),
            b: axis(b),
        };
        let row = match eq {
            XDelta => along(0),
            YDelta => along(1),
            ZDelta => along(2),
            ZiXj => dot(2, 0),
            ZiYj => dot(2, 1),
            XiYj => dot(0, 1),
            ZiZj => dot(2, 2),
            Convel => {
                let (i, k) = (Some(i), Some(j));
                let xy = self.measures.add(Measure::UnitVec {
                    i,
                    k,
                    axis: 0,
                    comp: 1,
                });
                let yx = self.measures.add(Measure::UnitVec {
                    i,
                    k,
                    axis: 1,
                    comp: 0,
                });
                Row::Measured {
                    terms: vec![(1.0, xy), (1.0, yx)],
                    drive: None,
                }
            }
            Rackpin | Screw | Gcon | Motion => return Err(MbdError::NotPrimitive(eq.label())),
        };
        Ok(Equ::new(row, eq, matches!(eq, XDelta | YDelta | ZDelta)))
    }

    /// A JOINT (spec §4.2). `param` is PD for RACKPIN, PITCH for SCREW, unused otherwise.
    pub fn joint(
        &mut self,
        elref: ElementRef,
        kind: JointType,
        i: MarkerHandle,
        j: MarkerHandle,
        param: f64,
    ) -> Result<ElementHandle, MbdError> {
        let elref = ElementRef {
            kind: ElementKind::Joint(kind),
            ..elref
        };
        let (mi, mj) = (Some(i), Some(j));
        match kind {
            JointType::Rackpin | JointType::Screw => {
                self.check_pair(&elref, i, j)?;
                // One equation on the travel of I along z_J and an unwrapped angle. RACKPIN:
                // −(r_I − r_J)·z_J − (PD/2)·θ, θ = rotation of x_I about z_I from z_J;
                // SCREW: (r_I − r_J)·z_J − PITCH·θ/2π, θ = AZ(I, J). The signs are
                // decisions (the spec marks them [RECALL]).
                let travel = self.measures.add(Measure::Disp {
                    i: mi,
                    j: mj,
                    k: mj,
                    comp: 2,
                });
                let (sign, angle, coef, label) = if kind == JointType::Rackpin {
                    (
                        -1.0,
                        Measure::PinionAngle { i: mi, j: mj },
                        -param / 2.0,
                        Equation::Rackpin,
                    )
                } else {
                    (
                        1.0,
                        Measure::Angle {
                            i: mi,
                            j: mj,
                            axis: 2,
                        },
                        -param / (2.0 * PI),
                        Equation::Screw,
                    )
                };
                let angle = self.measures.add(angle);
                let row = Row::Measured {
                    terms: vec![(sign, travel), (coef, angle)],
                    drive: None,
                };
                Ok(self.add_element(elref, vec![Equ::new(row, label, true)]))
            }
            _ => self.primitives(elref, i, j),
        }
    }

    /// A JPRIM (spec §4.2).
    pub fn jprim(
        &mut self,
        elref: ElementRef,
        kind: JprimType,
        i: MarkerHandle,
        j: MarkerHandle,
    ) -> Result<ElementHandle, MbdError> {
        self.primitives(
            ElementRef {
                kind: ElementKind::Jprim(kind),
                ..elref
            },
            i,
            j,
        )
    }

    /// Exudyn's 2D prismatic joint (spec §6.4) with marker 0 = I, marker 1 = J:
    /// (r_J − r_I)·(R_J n) = 0 (`Y Delta` with the default n = y) and
    /// (R_I t)·(R_J n) = 0 (`Xi.Yj` with the default t = x). `t` is the sliding axis in
    /// I's frame, `n` the normal in J's frame.
    pub fn prismatic_2d(
        &mut self,
        elref: ElementRef,
        i: MarkerHandle,
        j: MarkerHandle,
        t: Vec3,
        n: Vec3,
    ) -> Result<ElementHandle, MbdError> {
        let elref = ElementRef {
            kind: ElementKind::Prismatic2d,
            ..elref
        };
        self.check_pair(&elref, i, j)?;
        let eqs = vec![
            Equ::new(
                Row::Along {
                    i,
                    j,
                    dir: n,
                    sign: -1.0,
                },
                Equation::YDelta,
                true,
            ),
            Equ::new(Row::Dot { i, j, a: t, b: n }, Equation::XiYj, false),
        ];
        Ok(self.add_element(elref, eqs))
    }

    /// A GCON: f(t, measures) = 0, where `map[k]` is the measure index of the k-th slot
    /// `f` reads.
    pub fn gcon(
        &mut self,
        elref: ElementRef,
        f: Box<dyn ExprFn>,
        map: Vec<usize>,
    ) -> Result<ElementHandle, MbdError> {
        let elref = ElementRef {
            kind: ElementKind::Gcon,
            ..elref
        };
        if map.len() != f.slots().len() || map.iter().any(|&m| m >= self.measures.list.len()) {
            return Err(MbdError::GconSlots {
                id: elref.id,
                slots: f.slots().len(),
                measures: map.len(),
            });
        }
        let row = Row::Gcon { f, map };
        Ok(self.add_element(elref, vec![Equ::new(row, Equation::Gcon, false)]))
    }

    /// A displacement MOTION: measure − g(t) = 0.
    pub fn motion(
        &mut self,
        elref: ElementRef,
        measure: Measure,
        g: Box<dyn ExprFn>,
    ) -> Result<ElementHandle, MbdError> {
        let elref = ElementRef {
            kind: ElementKind::Motion,
            ..elref
        };
        let markers = match measure {
            Measure::Angle { i, j, .. }
            | Measure::Disp { i, j, .. }
            | Measure::Body123 { i, j, .. } => (i, j),
            _ => return Err(MbdError::MotionMeasure),
        };
        if let (Some(i), Some(j)) = markers {
            self.check_pair(&elref, i, j)?;
        }
        let translational = matches!(measure, Measure::Disp { .. });
        let m = self.measures.add(measure);
        let row = Row::Measured {
            terms: vec![(1.0, m)],
            drive: Some(g),
        };
        Ok(self.add_element(elref, vec![Equ::new(row, Equation::Motion, translational)]))
    }
}
