//! The assembled system: parts (ground and moving), markers, constraint elements and
//! measures, each set addressed by a small `Copy` handle, plus the coordinate layout.
//!
//! **Coordinates.** A moving part's pose is its BCS origin `r` and a unit quaternion
//! (`q` holds x, y, z, e0, e1, e2, e3 per part). Changes of pose are *velocity-level*
//! increments (δr, δθ) in global axes: r ← r + δr, R ← exp(\[δθ\]×)·R. This is the
//! rotation-vector increment on a reference rotation: it has no Euler-angle singularity,
//! needs no normalisation constraint (which would add rows that are not the user's
//! equations to the redundancy analysis), and its Jacobian columns are exactly the
//! velocity-level columns of multibody spec §5.3 (6 per moving part). The velocity `v`
//! holds ṙ and ω in global axes, 6 per moving part.
//!
//! **2D.** A planar scene ([`super::planar`]) keeps the same poses but moves each part only
//! in a global coordinate plane (XY, YZ or ZX) and by θ about its normal n:
//! R = R_n(θ)·R₀ with R₀ the input orientation. Its columns are the two in-plane
//! translations and δθ_n (3 per part); all kinematics are computed in 3D either way, so measures
//! and equations are one code path and the 2D system gives the 3D results.

use super::measure_set::MeasureSet;
use super::rows::Element;
// The handles are vocabulary (rows and measures hold them too); their old path stays.
pub use super::handles::{ElementHandle, MarkerHandle, PartHandle};
use crate::model::elements::Id;
use crate::vocab::math::{DVec, Mat3, Quat, Vec3};
use std::collections::HashMap;

/// Whether the system runs in 2D or 3D.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// Planar: 3 columns per moving part.
    Two,
    /// Spatial: 6 columns per moving part.
    Three,
}

impl Dimension {
    /// Translational axes: 2 or 3.
    pub fn axes(self) -> usize {
        match self {
            Dimension::Two => 2,
            Dimension::Three => 3,
        }
    }

    /// Columns per moving part.
    pub fn cols(self) -> usize {
        match self {
            Dimension::Two => 3,
            Dimension::Three => 6,
        }
    }
}

/// A rigid part. Ground never moves and has no columns.
#[derive(Clone, Debug)]
pub struct Part {
    /// The Adams PART id (None for a part the model does not name).
    pub id: Option<Id>,
    /// The `adams_view_name`, when the dataset gives one.
    pub name: Option<String>,
    /// The part's reference point, global: its centre of mass when the dataset names a
    /// CM marker (Newton–Euler equations then need no coupling terms), else the BCS
    /// origin. [`Part::bcs_origin`] gives the BCS origin either way.
    pub r: Vec3,
    /// Orientation: columns of its matrix are the BCS axes, global.
    pub rot: Quat,
    /// Linear velocity of the BCS origin and angular velocity, global axes.
    pub v: Vec3,
    /// Angular velocity, global axes.
    pub w: Vec3,
    /// Input pose and velocity (assembly reports moves from these; the velocity solve
    /// stays closest to these velocities).
    pub input_r: Vec3,
    /// Input orientation.
    pub input_rot: Quat,
    /// Input velocity of the BCS origin, global axes.
    pub input_v: Vec3,
    /// Input angular velocity, global axes.
    pub input_w: Vec3,
    /// 2D: rotation about global Z from the input orientation.
    pub theta: f64,
    /// Index among the moving parts (its column block); None for ground.
    pub index: Option<usize>,
    /// Mass (model units; 0 for a massless part and for ground).
    pub mass: f64,
    /// Inertia tensor about the reference point (the CM), in BCS axes.
    pub inertia: Mat3,
    /// The reference point in BCS coordinates (the CM marker's QP; zero without one).
    pub cm_offset: Vec3,
    /// Acceleration of the reference point and angular acceleration, global axes (set
    /// by the dynamics; zero before).
    pub acc: Vec3,
    /// Angular acceleration, global axes.
    pub alpha: Vec3,
    /// `rot` as a matrix, kept by [`Part::set_rot`] (every marker frame reads it).
    rotm: Mat3,
    /// The bits of θ and the input orientation a 2D move last turned `rot` from: a move
    /// that keeps both (along a translational joint) skips the sine, cosine and matrix.
    planar_key: Option<(u64, Quat)>,
}

/// A marker: a frame fixed on a part.
#[derive(Clone, Debug)]
pub struct Marker {
    /// The Adams MARKER id.
    pub id: Option<Id>,
    /// The part the marker is fixed on.
    pub part: PartHandle,
    /// Origin in the part's BCS.
    pub s: Vec3,
    /// Columns are the marker axes in BCS coordinates.
    pub rot: Mat3,
    /// FLOATING: a marker whose pose the element using it sets.
    pub floating: bool,
}

/// A marker's frame in global coordinates at the current state.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// Origin, global.
    pub r: Vec3,
    /// Axes (columns), global.
    pub rot: Mat3,
    /// r − (part's BCS origin).
    pub a: Vec3,
    /// The part the marker is fixed on.
    pub part: PartHandle,
}

/// Buffers the system's expressions share: the model's measure slot values (one array
/// for every GCON and force expression, each writing the slots it reads before it runs)
/// and a GCON row's partials and measure duals. Reused: no allocation per evaluation.
#[derive(Default)]
pub struct ExprScratch {
    /// Measure slot values, indexed by slot.
    pub slots: Vec<f64>,
    /// A GCON row's partials ∂f/∂slot.
    pub grad: Vec<f64>,
    /// A GCON row's measure duals, one per slot.
    pub evs: Vec<super::measure_set::Evaluated>,
}

impl ExprScratch {
    /// The slot array, grown to hold slot `last` (the first time only).
    pub fn slots_to(&mut self, last: Option<u32>) -> &mut [f64] {
        let len = last.map_or(0, |s| s as usize + 1);
        if self.slots.len() < len {
            self.slots.resize(len, 0.0);
        }
        &mut self.slots
    }
}

/// The multibody system.
pub struct System {
    /// Ground first, then the moving parts.
    pub parts: Vec<Part>,
    /// Every marker, addressed by [`MarkerHandle`].
    pub markers: Vec<Marker>,
    /// The constraint elements, addressed by [`ElementHandle`].
    pub elements: Vec<Element>,
    /// The measures that constraint rows and expressions read.
    pub measures: MeasureSet,
    /// 2D or 3D.
    pub dim: Dimension,
    /// Why the system is 2D or 3D, in words.
    pub dim_reason: String,
    /// ACCGRAV, model units.
    pub gravity: Vec3,
    /// Units-consistency factor: Force·UCF = Mass·Acceleration.
    pub ucf: f64,
    /// The model length that scales translational rows (spec §5.3).
    pub length: f64,
    /// In 2D, the axis (0 = X, 1 = Y, 2 = Z) normal to the plane of motion.
    pub normal: usize,
    /// Time at which MOTIONs and GCONs are evaluated.
    pub time: f64,
    moving: usize,
    marker_ids: HashMap<Id, MarkerHandle>,
    /// What the expressions share ([`ExprScratch`]).
    pub(crate) scratch: std::cell::RefCell<ExprScratch>,
    /// The GCONs' and displacement MOTIONs' expressions fused into one call
    /// ([`super::fused_rows`]).
    pub(crate) fused_rows: Option<super::rows::FusedRows>,
}

impl Default for System {
    fn default() -> Self {
        System::new()
    }
}

impl System {
    /// The ground part's handle.
    pub const GROUND: PartHandle = PartHandle(0);

    /// An empty 3D system holding only ground.
    pub fn new() -> Self {
        let ground = Part::new(None, Vec3::zeros(), Quat::identity());
        System {
            parts: vec![ground],
            markers: Vec::new(),
            elements: Vec::new(),
            measures: MeasureSet::default(),
            dim: Dimension::Three,
            dim_reason: "3D: built through the library API".into(),
            gravity: Vec3::zeros(),
            ucf: 1.0,
            length: 1.0,
            normal: 2,
            time: 0.0,
            moving: 0,
            marker_ids: HashMap::new(),
            scratch: Default::default(),
            fused_rows: None,
        }
    }

    /// Adds a moving part with its BCS pose (columns of `rot` = BCS axes, global).
    pub fn add_part(&mut self, id: Option<Id>, position: Vec3, rot: Mat3) -> PartHandle {
        // Shepperd's direct formula (nalgebra's `from_matrix` iterates and never ends on
        // a non-finite matrix), then renormalised.
        let rq = Quat::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(rot));
        let q = Quat::new_normalize(*rq.quaternion());
        let mut p = Part::new(id, position, q);
        p.index = Some(self.moving);
        self.moving += 1;
        self.parts.push(p);
        PartHandle(self.parts.len() as u32 - 1)
    }

    /// Adds a marker at `s` (BCS) with axes `rot` (BCS) on `part`.
    pub fn add_marker(
        &mut self,
        id: Option<Id>,
        part: PartHandle,
        s: Vec3,
        rot: Mat3,
    ) -> MarkerHandle {
        self.markers.push(Marker {
            id,
            part,
            s,
            rot,
            floating: false,
        });
        let h = MarkerHandle(self.markers.len() as u32 - 1);
        if let Some(id) = id {
            self.marker_ids.insert(id, h);
        }
        h
    }

    /// The marker with Adams id `id`.
    pub fn marker_by_id(&self, id: Id) -> Option<MarkerHandle> {
        self.marker_ids.get(&id).copied()
    }

    /// A measure argument's marker: id 0 is the ground frame at the origin (None); an id
    /// that names no marker is an error.
    pub fn marker_or_ground(
        &self,
        id: i64,
    ) -> Result<Option<MarkerHandle>, super::error::MbdError> {
        if id == 0 {
            return Ok(None);
        }
        u32::try_from(id)
            .ok()
            .and_then(|id| self.marker_by_id(id))
            .map(Some)
            .ok_or(super::error::MbdError::UnknownMarker(id))
    }

    /// The part `h` addresses.
    pub fn part(&self, h: PartHandle) -> &Part {
        &self.parts[h.0 as usize]
    }

    /// The part `h` addresses, mutable.
    pub fn part_mut(&mut self, h: PartHandle) -> &mut Part {
        &mut self.parts[h.0 as usize]
    }

    /// The marker `h` addresses.
    pub fn marker(&self, h: MarkerHandle) -> &Marker {
        &self.markers[h.0 as usize]
    }

    /// Number of moving parts.
    pub fn moving_parts(&self) -> usize {
        self.moving
    }

    /// Columns of the Jacobians (= length of `v`).
    pub fn ncols(&self) -> usize {
        self.moving * self.dim.cols()
    }

    /// Global origin of marker `m` and its offset from its part's reference point
    /// (None: the ground frame's origin): a frame without its axes, what displacements
    /// and velocities read.
    #[inline]
    pub fn origin(&self, m: Option<MarkerHandle>) -> (Vec3, Vec3, PartHandle) {
        match m {
            None => (Vec3::zeros(), Vec3::zeros(), Self::GROUND),
            Some(m) => {
                let mk = self.marker(m);
                let p = self.part(mk.part);
                let a = p.rotation() * mk.s;
                (p.r + a, a, mk.part)
            }
        }
    }

    /// Global frame of marker `m` (None = the ground frame at the origin).
    pub fn frame(&self, m: Option<MarkerHandle>) -> Frame {
        match m {
            None => Frame {
                r: Vec3::zeros(),
                rot: Mat3::identity(),
                a: Vec3::zeros(),
                part: Self::GROUND,
            },
            Some(m) => {
                let (r, a, part) = self.origin(Some(m));
                Frame {
                    r,
                    rot: self.part(part).rotation() * self.marker(m).rot,
                    a,
                    part,
                }
            }
        }
    }

    /// Sets the state velocity of a part (global axes) and makes it the input velocity.
    pub fn set_part_velocity(&mut self, h: PartHandle, v: Vec3, w: Vec3) {
        let p = self.part_mut(h);
        (p.v, p.w, p.input_v, p.input_w) = (v, w, v, w);
    }

    /// The coordinate vector: x, y, z, e0, e1, e2, e3 per moving part in 3D; x, y, θ in 2D.
    pub fn q(&self) -> DVec {
        let mut out = Vec::new();
        for p in self.parts.iter().filter(|p| p.index.is_some()) {
            match self.dim {
                Dimension::Three => {
                    let c = p.rot.coords; // (i, j, k, w)
                    out.extend_from_slice(&[p.r.x, p.r.y, p.r.z, c.w, c.x, c.y, c.z]);
                }
                Dimension::Two => {
                    let (a, b, _) = self.plane_axes();
                    out.extend_from_slice(&[p.r[a], p.r[b], p.theta])
                }
            }
        }
        DVec::from_vec(out)
    }

    /// The velocity vector: ṙ, ω (global) per moving part in 3D; ẋ, ẏ, ω_z in 2D.
    pub fn v(&self) -> DVec {
        let n = self.dim.cols();
        let mut out = DVec::zeros(self.ncols());
        for p in self.parts.iter() {
            if let Some(i) = p.index {
                for c in 0..6 {
                    if let Some(k) = self.local_col(c) {
                        out[i * n + k] = if c < 3 { p.v[c] } else { p.w[c - 3] };
                    }
                }
            }
        }
        out
    }

    /// Sets every part's velocity from a vector laid out like [`System::v`]; in 2D the
    /// out-of-plane components are zero.
    pub fn set_v(&mut self, v: &DVec) {
        let n = self.dim.cols();
        let map: [Option<usize>; 6] = std::array::from_fn(|c| self.local_col(c));
        for p in self.parts.iter_mut() {
            if let Some(i) = p.index {
                for (c, k) in map.iter().enumerate() {
                    let x = k.map_or(0.0, |k| v[i * n + k]);
                    if c < 3 {
                        p.v[c] = x;
                    } else {
                        p.w[c - 3] = x;
                    }
                }
            }
        }
    }

    /// Moves every part by a column-space increment: δr and δθ (global) in 3D, δx, δy,
    /// δθz in 2D.
    pub fn apply_increment(&mut self, dx: &[f64]) {
        let (dim, axes) = (self.dim, self.plane_axes());
        for p in self.parts.iter_mut() {
            p.move_by(dx, dim, axes, p.r, p.rot, p.theta);
        }
    }

    /// The poses `base` (as `System::snapshot` took them) moved by the column-space
    /// increment `dx`: a restore and [`System::apply_increment`] in one pass, with one
    /// rotation update per part.
    pub fn set_moved(&mut self, base: &[(Vec3, Quat, f64)], dx: &[f64]) {
        let (dim, axes) = (self.dim, self.plane_axes());
        for (p, &(r, rot, theta)) in self.parts.iter_mut().zip(base) {
            if p.index.is_some() {
                p.move_by(dx, dim, axes, r, rot, theta);
            } else {
                (p.r, p.theta) = (r, theta);
                // Ground keeps its pose: no matrix to rebuild.
                if p.rot != rot {
                    p.set_rot(rot);
                }
            }
        }
    }

    /// Global column of direction `c` (0..6) of part `h`, if it has one.
    pub fn col(&self, h: PartHandle, c: usize) -> Option<usize> {
        let i = self.part(h).index?;
        Some(i * self.dim.cols() + self.local_col(c)?)
    }

    /// The in-plane axes and the normal (a, b, n), a right-handed cycle of 0, 1, 2.
    pub fn plane_axes(&self) -> (usize, usize, usize) {
        let n = self.normal;
        ((n + 1) % 3, (n + 2) % 3, n)
    }

    /// Column (within a part) of the 3D direction `c` (δr x y z, δθ x y z), if the
    /// layout has it: all six in 3D; the two in-plane translations and the rotation
    /// about the normal in 2D.
    fn local_col(&self, c: usize) -> Option<usize> {
        match self.dim {
            Dimension::Three => Some(c),
            Dimension::Two => {
                let (a, b, n) = self.plane_axes();
                [a, b, 3 + n].iter().position(|&k| k == c)
            }
        }
    }

    /// Resets poses and velocities to the input ones.
    pub fn reset_to_input(&mut self) {
        for p in &mut self.parts {
            (p.r, p.v, p.w, p.theta) = (p.input_r, p.input_v, p.input_w, 0.0);
            p.set_rot(p.input_rot);
        }
    }

    /// A model length for scaling: the largest distance of a marker or part origin from
    /// the origin or from each other's centroid, at least 1e-6 (the unit length when the
    /// scene is a point).
    pub(crate) fn characteristic_length(&self) -> f64 {
        let pts: Vec<Vec3> = self
            .markers
            .iter()
            .enumerate()
            .map(|(i, _)| self.frame(Some(MarkerHandle(i as u32))).r)
            .chain(self.parts.iter().skip(1).map(|p| p.r))
            .collect();
        if pts.is_empty() {
            return 1.0;
        }
        let c = pts.iter().sum::<Vec3>() / pts.len() as f64;
        let l = pts.iter().map(|p| (p - c).norm()).fold(0.0, f64::max);
        if l > 1e-6 {
            l
        } else {
            1.0
        }
    }
}

impl Part {
    fn new(id: Option<Id>, r: Vec3, rot: Quat) -> Part {
        Part {
            id,
            name: None,
            r,
            rot,
            v: Vec3::zeros(),
            w: Vec3::zeros(),
            input_r: r,
            input_rot: rot,
            input_v: Vec3::zeros(),
            input_w: Vec3::zeros(),
            theta: 0.0,
            index: None,
            mass: 0.0,
            inertia: Mat3::zeros(),
            cm_offset: Vec3::zeros(),
            acc: Vec3::zeros(),
            alpha: Vec3::zeros(),
            rotm: rot.to_rotation_matrix().into_inner(),
            planar_key: None,
        }
    }

    /// Sets the pose to (`r`, `rot`, `theta`) moved by this part's columns of `dx` (a
    /// part without columns just takes the pose).
    fn move_by(
        &mut self,
        dx: &[f64],
        dim: Dimension,
        (a, b, n): (usize, usize, usize),
        r: Vec3,
        rot: Quat,
        theta: f64,
    ) {
        (self.r, self.theta) = (r, theta);
        let Some(i) = self.index else {
            return;
        };
        let cols = dim.cols();
        let d = &dx[i * cols..(i + 1) * cols];
        match dim {
            Dimension::Three => {
                self.r += Vec3::new(d[0], d[1], d[2]);
                let dq = Quat::from_scaled_axis(Vec3::new(d[3], d[4], d[5]));
                self.set_rot(Quat::new_normalize((dq * rot).into_inner()));
            }
            Dimension::Two => {
                self.r[a] += d[0];
                self.r[b] += d[1];
                self.theta += d[2];
                let key = Some((self.theta.to_bits(), self.input_rot));
                if self.planar_key != key {
                    let axis = nalgebra::Unit::new_unchecked(Vec3::ith(n, 1.0));
                    self.set_rot(Quat::from_axis_angle(&axis, self.theta) * self.input_rot);
                    self.planar_key = key;
                }
            }
        }
    }

    /// Sets the orientation and the rotation matrix every frame reads.
    pub fn set_rot(&mut self, rot: Quat) {
        self.rot = rot;
        self.rotm = rot.to_rotation_matrix().into_inner();
        self.planar_key = None;
    }

    /// The orientation as a rotation matrix (columns: BCS axes, global).
    pub fn rotation(&self) -> Mat3 {
        debug_assert!(
            (self.rotm - self.rot.to_rotation_matrix().into_inner()).amax() < 1e-12,
            "Part::rot changed without Part::set_rot"
        );
        self.rotm
    }

    /// The BCS origin, global.
    pub fn bcs_origin(&self) -> Vec3 {
        self.r - self.rot * self.cm_offset
    }

    /// The inertia tensor about the CM in global axes: R·J·Rᵀ (J itself when it is
    /// isotropic, as for a sphere or a cube: no rotation changes it).
    #[inline(always)]
    pub fn inertia_global(&self) -> Mat3 {
        if self.isotropic() {
            return self.inertia;
        }
        let r = self.rotation();
        r * self.inertia * r.transpose()
    }

    /// Whether the inertia tensor is a multiple of the identity (then it has no
    /// gyroscopic moment and the same components in every frame).
    pub fn isotropic(&self) -> bool {
        self.inertia == Mat3::from_diagonal_element(self.inertia[(0, 0)])
    }
}
