//! What each scalar constraint equation means, in the user's words: the element it
//! belongs to (Adams type, id, `adams_view_name`) and its Adams label (multibody spec
//! §4.1: `X Delta`, `Zi.Xj`, ...). Constraint assembly attaches one [`EquationLabel`] to
//! every row of the constraint vector; the redundancy report and error messages read them.

/// The Adams joint types (multibody spec §4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JointType {
    Fixed,
    Revolute,
    Spherical,
    Translational,
    Cylindrical,
    Planar,
    Hooke,
    Universal,
    Convel,
    Rackpin,
    Screw,
}

/// The Adams joint primitives (multibody spec §4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JprimType {
    Atpoint,
    Inline,
    Inplane,
    Orientation,
    ParallelAxes,
    Perpendicular,
}

/// The kind of element a constraint equation comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ElementKind {
    Joint(JointType),
    Jprim(JprimType),
    Gcon,
    Motion,
    /// Exudyn's 2D prismatic joint (multibody spec §6.4), library API only.
    Prismatic2d,
    /// An applied force element (no constraint equations; named in dynamics messages).
    Force(ForceKind),
}

/// The force statements of multibody spec §7.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ForceKind {
    Sforce,
    Vforce,
    Vtorque,
    Gforce,
    Springdamper,
    Bushing,
}

impl ForceKind {
    /// The statement keyword.
    pub fn keyword(self) -> &'static str {
        match self {
            ForceKind::Sforce => "SFORCE",
            ForceKind::Vforce => "VFORCE",
            ForceKind::Vtorque => "VTORQUE",
            ForceKind::Gforce => "GFORCE",
            ForceKind::Springdamper => "SPRINGDAMPER",
            ForceKind::Bushing => "BUSHING",
        }
    }
}

/// One element as the user named it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ElementRef {
    pub kind: ElementKind,
    /// The Adams id.
    pub id: u32,
    /// The `adams_view_name`, when the dataset gives one.
    pub name: Option<String>,
}

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
/// of [`ElementRef`]s.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EquationLabel {
    pub element: usize,
    pub equation: Equation,
}
