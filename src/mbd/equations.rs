//! What each scalar constraint equation means, in the user's words: the element it
//! belongs to (an index into the system's [`crate::vocab::elements::ElementRef`]s) and its
//! Adams label (multibody spec §4.1: `X Delta`, `Zi.Xj`, ...). Constraint assembly attaches
//! one [`EquationLabel`] to every row of the constraint vector; the redundancy report and
//! error messages read them.

/// What one scalar equation constrains. The translational ones are resolved in J-marker
/// axes (spec §4.1 recommendation): `XDelta` is d·x_J = 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Equation {
    /// d·x_J = 0.
    XDelta,
    /// d·y_J = 0.
    YDelta,
    /// d·z_J = 0.
    ZDelta,
    /// z_I·x_J = 0.
    ZiXj,
    /// z_I·y_J = 0.
    ZiYj,
    /// x_I·y_J = 0.
    XiYj,
    /// z_I·z_J = 0 (UNIVERSAL, JPRIM PERPENDICULAR).
    ZiZj,
    /// x_I·y_J + y_I·x_J = 0.
    Convel,
    /// RACKPIN: travel along z_J tied to the pinion angle by PD.
    Rackpin,
    /// SCREW: travel along z_J tied to the rotation by PITCH.
    Screw,
    /// A GCON's expression.
    Gcon,
    /// A MOTION's drive: measure − g(t).
    Motion,
}

impl Equation {
    /// The label Adams Solver prints for the equation (spec §4.1, §5.1).
    pub fn label(self) -> &'static str {
        match self {
            Equation::XDelta => "X Delta",
            Equation::YDelta => "Y Delta",
            Equation::ZDelta => "Z Delta",
            Equation::ZiXj => "Zi.Xj",
            Equation::ZiYj => "Zi.Yj",
            Equation::XiYj => "Xi.Yj",
            Equation::ZiZj => "Zi.Zj",
            Equation::Convel => "Xi.Yj+Yi.Xj",
            Equation::Rackpin => "Rackpin",
            Equation::Screw => "Screw",
            Equation::Gcon => "Gcon",
            Equation::Motion => "Motion",
        }
    }
}

/// The meaning of one row of the constraint vector: `element` indexes the system's list
/// of [`crate::vocab::elements::ElementRef`]s.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EquationLabel {
    /// Index into the system's element list.
    pub element: usize,
    /// What the row constrains.
    pub equation: Equation,
}
