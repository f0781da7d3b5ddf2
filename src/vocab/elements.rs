//! The elements of a dataset the layers name to each other: the Adams joint types and
//! joint primitives (multibody spec §4.2), the force statements (§7), the element kinds
//! the core's equations and messages belong to, and the one table of how each kind is
//! spelled ([`ELEMENT_NAMES`]). The reader reads type flags from that table, and the
//! core's errors and redundancy report print from it, so the three cannot disagree.

/// The Adams joint types (multibody spec §4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JointType {
    /// FIXED: all six relative motions locked.
    Fixed,
    /// REVOLUTE: rotation about z_J only.
    Revolute,
    /// SPHERICAL: coincident origins, free rotation.
    Spherical,
    /// TRANSLATIONAL: translation along z_J only.
    Translational,
    /// CYLINDRICAL: translation along and rotation about z_J.
    Cylindrical,
    /// PLANAR: I's origin in J's xy plane, rotation about z_J.
    Planar,
    /// HOOKE: coincident origins with x_I ⟂ y_J.
    Hooke,
    /// UNIVERSAL: coincident origins with z_I ⟂ z_J.
    Universal,
    /// CONVEL: constant-velocity joint.
    Convel,
    /// RACKPIN: rack travel tied to pinion rotation by PD.
    Rackpin,
    /// SCREW: travel along z_J tied to rotation by PITCH.
    Screw,
}

/// The Adams joint primitives (multibody spec §4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JprimType {
    /// ATPOINT: coincident origins.
    Atpoint,
    /// INLINE: I's origin on J's z axis.
    Inline,
    /// INPLANE: I's origin in J's xy plane.
    Inplane,
    /// ORIENTATION: axes locked together.
    Orientation,
    /// PARALLEL_AXES: z_I parallel to z_J.
    ParallelAxes,
    /// PERPENDICULAR: z_I ⟂ z_J.
    Perpendicular,
}

/// The force statements of multibody spec §7.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ForceKind {
    /// SFORCE: a scalar force along I–J or a torque about z_J.
    Sforce,
    /// VFORCE: a force vector in RM axes.
    Vforce,
    /// VTORQUE: a torque vector in RM axes.
    Vtorque,
    /// GFORCE: a force and a torque vector in RM axes.
    Gforce,
    /// SPRINGDAMPER: linear spring and damper, translational or rotational.
    Springdamper,
    /// BUSHING: linear six-component spring and damper.
    Bushing,
    /// BEAM: Timoshenko's linear beam between two markers.
    Beam,
    /// FIELD: a 6×6 linear stiffness and damping between two markers.
    Field,
    /// FRICTION: the friction of a joint, loaded by the joint's reaction.
    Friction,
}

/// The kind of element a constraint equation, a force or a message belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ElementKind {
    /// A JOINT of the given type.
    Joint(JointType),
    /// A JPRIM of the given type.
    Jprim(JprimType),
    /// A GCON.
    Gcon,
    /// A MOTION.
    Motion,
    /// Exudyn's 2D prismatic joint (multibody spec §6.4), library API only.
    Prismatic2d,
    /// An applied force element (no constraint equations; named in dynamics messages).
    Force(ForceKind),
}

/// One element as the user named it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ElementRef {
    /// What kind of element it is.
    pub kind: ElementKind,
    /// The Adams id.
    pub id: u32,
    /// The `adams_view_name`, when the dataset gives one.
    pub name: Option<String>,
}

/// How the dataset spells one element kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ElementName {
    /// The element kind spelled.
    pub kind: ElementKind,
    /// The statement keyword, full spelling (`JOINT`, `SFORCE`).
    pub keyword: &'static str,
    /// The type flag that follows the id of a JOINT or JPRIM (`REVOLUTE`, `PARALLEL_AXES`).
    pub flag: Option<&'static str>,
}

const fn joint(t: JointType, flag: &'static str) -> ElementName {
    ElementName {
        kind: ElementKind::Joint(t),
        keyword: "JOINT",
        flag: Some(flag),
    }
}

const fn jprim(t: JprimType, flag: &'static str) -> ElementName {
    ElementName {
        kind: ElementKind::Jprim(t),
        keyword: "JPRIM",
        flag: Some(flag),
    }
}

const fn plain(kind: ElementKind, keyword: &'static str) -> ElementName {
    ElementName {
        kind,
        keyword,
        flag: None,
    }
}

const fn force(k: ForceKind, keyword: &'static str) -> ElementName {
    plain(ElementKind::Force(k), keyword)
}

/// Every element kind once, spelled as Adams Solver datasets spell it (multibody spec §2.5,
/// §4.2, §7): the statement keywords and type flags the reader accepts in full.
pub static ELEMENT_NAMES: &[ElementName] = &[
    joint(JointType::Fixed, "FIXED"),
    joint(JointType::Revolute, "REVOLUTE"),
    joint(JointType::Spherical, "SPHERICAL"),
    joint(JointType::Translational, "TRANSLATIONAL"),
    joint(JointType::Cylindrical, "CYLINDRICAL"),
    joint(JointType::Planar, "PLANAR"),
    joint(JointType::Hooke, "HOOKE"),
    joint(JointType::Universal, "UNIVERSAL"),
    joint(JointType::Convel, "CONVEL"),
    joint(JointType::Rackpin, "RACKPIN"),
    joint(JointType::Screw, "SCREW"),
    jprim(JprimType::Atpoint, "ATPOINT"),
    jprim(JprimType::Inline, "INLINE"),
    jprim(JprimType::Inplane, "INPLANE"),
    jprim(JprimType::Orientation, "ORIENTATION"),
    jprim(JprimType::ParallelAxes, "PARALLEL_AXES"),
    jprim(JprimType::Perpendicular, "PERPENDICULAR"),
    plain(ElementKind::Gcon, "GCON"),
    plain(ElementKind::Motion, "MOTION"),
    force(ForceKind::Sforce, "SFORCE"),
    force(ForceKind::Vforce, "VFORCE"),
    force(ForceKind::Vtorque, "VTORQUE"),
    force(ForceKind::Gforce, "GFORCE"),
    force(ForceKind::Springdamper, "SPRINGDAMPER"),
    force(ForceKind::Bushing, "BUSHING"),
    force(ForceKind::Beam, "BEAM"),
    force(ForceKind::Field, "FIELD"),
    force(ForceKind::Friction, "FRICTION"),
    // No dataset statement makes one (see `ElementKind::in_dataset`): the name is
    // Exudyn's (`ObjectJointPrismatic2D`) in the dataset's upper case.
    plain(ElementKind::Prismatic2d, "PRISMATIC2D"),
];

impl ElementKind {
    /// This kind's row of [`ELEMENT_NAMES`].
    pub fn names(self) -> &'static ElementName {
        ELEMENT_NAMES
            .iter()
            .find(|n| n.kind == self)
            .expect("ELEMENT_NAMES has a row for every element kind (tested)")
    }

    /// The statement keyword: `JOINT`, `GCON`, `SFORCE`.
    pub fn keyword(self) -> &'static str {
        self.names().keyword
    }

    /// The type flag of a JOINT or JPRIM (`REVOLUTE`, `INLINE`); `None` for other kinds.
    pub fn flag(self) -> Option<&'static str> {
        self.names().flag
    }

    /// `JPRIM INLINE`, `GCON`: the kind as a user writes it.
    pub fn phrase(self) -> String {
        match self.flag() {
            Some(flag) => format!("{} {flag}", self.keyword()),
            None => self.keyword().to_string(),
        }
    }

    /// The kind a full statement keyword and type flag name (upper case, as in
    /// [`ELEMENT_NAMES`]); the flag must be given exactly for a JOINT or JPRIM.
    pub fn from_words(keyword: &str, flag: Option<&str>) -> Option<ElementKind> {
        ELEMENT_NAMES
            .iter()
            .find(|n| n.keyword == keyword && n.flag == flag)
            .map(|n| n.kind)
    }

    /// False for the 2D prismatic joint, which only the library API builds: no dataset
    /// statement makes one.
    pub fn in_dataset(self) -> bool {
        self != ElementKind::Prismatic2d
    }
}

impl JointType {
    /// Every joint type with its type flag, in table order.
    pub fn flags() -> impl Iterator<Item = (&'static str, JointType)> {
        ELEMENT_NAMES.iter().filter_map(|n| match (n.kind, n.flag) {
            (ElementKind::Joint(t), Some(flag)) => Some((flag, t)),
            _ => None,
        })
    }
}

impl JprimType {
    /// Every joint primitive with its type flag, in table order.
    pub fn flags() -> impl Iterator<Item = (&'static str, JprimType)> {
        ELEMENT_NAMES.iter().filter_map(|n| match (n.kind, n.flag) {
            (ElementKind::Jprim(t), Some(flag)) => Some((flag, t)),
            _ => None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every element kind, listed by hand. The match below does not compile when a variant
    /// is added, which is the reminder to list it here too.
    fn every_kind() -> Vec<ElementKind> {
        use ElementKind::*;
        use ForceKind::*;
        use JointType::*;
        use JprimType::*;
        let joints = [
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
        ];
        let jprims = [
            Atpoint,
            Inline,
            Inplane,
            Orientation,
            ParallelAxes,
            Perpendicular,
        ];
        let forces = [
            Sforce,
            Vforce,
            Vtorque,
            Gforce,
            Springdamper,
            Bushing,
            Beam,
            Field,
            Friction,
        ];
        let all: Vec<ElementKind> = (joints.into_iter().map(Joint))
            .chain(jprims.into_iter().map(Jprim))
            .chain([Gcon, Motion, Prismatic2d])
            .chain(forces.into_iter().map(Force))
            .collect();
        for k in &all {
            match k {
                Joint(
                    Fixed | Revolute | Spherical | Translational | Cylindrical | Planar | Hooke
                    | Universal | Convel | Rackpin | Screw,
                )
                | Jprim(Atpoint | Inline | Inplane | Orientation | ParallelAxes | Perpendicular)
                | Gcon
                | Motion
                | Prismatic2d
                | Force(
                    Sforce | Vforce | Vtorque | Gforce | Springdamper | Bushing | Beam | Field
                    | Friction,
                ) => {}
            }
        }
        all
    }

    #[test]
    fn every_kind_round_trips_through_the_one_table() {
        let all = every_kind();
        assert_eq!(ELEMENT_NAMES.len(), all.len(), "one row per kind");
        for kind in all {
            let n = kind.names();
            assert_eq!(n.kind, kind);
            assert_eq!(
                ElementKind::from_words(n.keyword, n.flag),
                Some(kind),
                "{kind:?}"
            );
            assert_eq!(
                n.flag.is_some(),
                matches!(kind, ElementKind::Joint(_) | ElementKind::Jprim(_)),
                "{kind:?}: only a JOINT or JPRIM has a type flag"
            );
        }
    }

    #[test]
    fn type_flags_name_every_joint_and_primitive_once() {
        let joints: Vec<_> = JointType::flags().collect();
        let jprims: Vec<_> = JprimType::flags().collect();
        assert_eq!((joints.len(), jprims.len()), (11, 6));
        for (flag, t) in joints {
            assert_eq!(
                ElementKind::from_words("JOINT", Some(flag)),
                Some(ElementKind::Joint(t))
            );
        }
        for (flag, t) in jprims {
            assert_eq!(
                ElementKind::from_words("JPRIM", Some(flag)),
                Some(ElementKind::Jprim(t))
            );
        }
    }

    #[test]
    fn phrases_read_as_written() {
        let axes = ElementKind::Jprim(JprimType::ParallelAxes);
        assert_eq!(axes.phrase(), "JPRIM PARALLEL_AXES");
        assert_eq!(ElementKind::Force(ForceKind::Vtorque).phrase(), "VTORQUE");
        assert_eq!(ElementKind::Prismatic2d.phrase(), "PRISMATIC2D");
    }
}
