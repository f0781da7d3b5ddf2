//! What each scalar constraint equation means, in the user's words: the element it
//! belongs to (an index into the system's [`crate::vocab::elements::ElementRef`]s) and its
//! Adams label (multibody spec §4.1: `X Delta`, `Zi.Xj`, ...). Constraint assembly attaches
//! one [`EquationLabel`] to every row of the constraint vector; the redundancy report and
//! error messages read them.

/// What one scalar equation constrains. The translational ones are resolved in J-marker
/// axes (spec §4.1 recommendation): `XDelta` is d·x_J = 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Equation {
    XDelta,
    YDelta,
    ZDelta,
    ZiXj,
    ZiYj,
    XiYj,
    ZiZj,
    /// x_I·y_J + y_I·x_J = 0.
    Convel,
    Rackpin,
    Screw,
    Gcon,
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
    pub element: usize,
    pub equation: Equation,
}
