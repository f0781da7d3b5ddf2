//! Readers of UNITS, ACCGRAV, PART and MARKER (multibody spec §2.1–§2.4).

use super::elements::{Marker, Part};
use super::frames::{axes_from_points, reuler, PointsError};
use super::reader::Reader;
use super::resolve::MarkerUse;
use super::stmt_args::Args;
use super::units::{si_value, system, ucf, Quantity};
use crate::check::units::UnitNames;
use crate::diag::{Code, Diagnostic};
use crate::vocab::math::{Mat3, Vec3};

/// `UNITS/`: unit names (or a SYSTEM preset) and the UCF they imply; `UCF =` overrides.
/// A unit left out is the SI one.
pub fn units(r: &mut Reader, a: &mut Args) {
    let mut names: [Option<String>; 4] = Default::default();
    if let Some((sys, span)) = a.word("SYSTEM", 2) {
        match system(sys) {
            Some(preset) => {
                for (slot, n) in names.iter_mut().zip(preset) {
                    *slot = Some(n.to_string());
                }
            }
            None if sys.eq_ignore_ascii_case("NONE") => {}
            None => a.error(
                Code::BadArgument,
                span,
                format!("unknown unit system `{sys}` (MKS, MMKS, CGS, FPS, IPS, NONE)"),
            ),
        }
    }
    let quantities = [
        ("FORCE", Quantity::Force, "NEWTON"),
        ("MASS", Quantity::Mass, "KILOGRAM"),
        ("LENGTH", Quantity::Length, "METER"),
        ("TIME", Quantity::Time, "SECOND"),
    ];
    let mut si = [1.0; 4];
    for (k, (key, q, default)) in quantities.into_iter().enumerate() {
        if let Some((name, span)) = a.word(key, 1) {
            names[k] = Some(name.to_ascii_uppercase());
            if si_value(q, name).is_none() {
                a.error(
                    Code::BadArgument,
                    span,
                    format!("unknown {} unit `{name}`", key.to_ascii_lowercase()),
                );
            }
        }
        si[k] = names[k]
            .as_deref()
            .and_then(|n| si_value(q, n))
            .or_else(|| si_value(q, default))
            .unwrap_or(1.0);
    }
    let [force, mass, length, time] = names;
    let mut factor = ucf(si[0], si[1], si[2], si[3]);
    if let Some(u) = a.number("UCF", 2) {
        factor = u;
    }
    r.scope.unit_names = UnitNames::from_dataset(
        force.as_deref(),
        mass.as_deref(),
        length.as_deref(),
        time.as_deref(),
    );
    r.model.units = super::elements::Units {
        force,
        mass,
        length,
        time,
        ucf: factor,
    };
}

/// `ACCGRAV/ IGRAV, JGRAV, KGRAV` in model units along global axes.
pub fn accgrav(r: &mut Reader, a: &mut Args) {
    let g = ["IGRAV", "JGRAV", "KGRAV"].map(|k| a.number(k, 1).unwrap_or(0.0));
    r.model.gravity = Vec3::new(g[0], g[1], g[2]);
}

/// An orientation from `REULER` or a pair of points (`ZP`/`XP`, `ZG`/`XG`) about
/// `origin`; identity when none is given.
fn orientation(a: &mut Args, origin: Vec3, zkey: &str, xkey: &str, usexp: bool) -> Mat3 {
    let angles = a.numbers("REULER", 2, 3..=3);
    let zp = a.vec3(zkey, 2);
    let xp = a.vec3(xkey, 2);
    if let Some(v) = angles {
        if zp.is_some() || xp.is_some() {
            let span = a.stmt.keyword_span.clone();
            let msg = format!("{} gives both REULER and {zkey}/{xkey}", a.label);
            a.error(Code::BadArgument, span, msg);
        }
        return reuler(v[0], v[1], v[2]);
    }
    let (z, x) = match (zp, xp) {
        (None, None) => return Mat3::identity(),
        // One point alone: the other axis follows from the global one it stands for.
        (Some(z), None) => (z, origin + Vec3::x()),
        (None, Some(x)) => (origin + Vec3::z(), x),
        (Some(z), Some(x)) => (z, x),
    };
    match axes_from_points(origin, z, x, usexp) {
        Ok(m) => m,
        Err(e) => {
            let why = match e {
                PointsError::AtOrigin => "a point lies on the origin",
                PointsError::OnAxis => "the two points lie on one line through the origin",
            };
            let span = a.stmt.keyword_span.clone();
            let msg = format!("{zkey}/{xkey} of {} define no axes: {why}", a.label);
            a.error(Code::BadArgument, span, msg);
            Mat3::identity()
        }
    }
}

/// `PART/id`: ground flag, mass properties, pose and initial velocities.
pub fn part(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let ground = a.flag("GROUND", 2);
    let mass = mass(a);
    let cm = r.marker_ref(a, "CM", 2, MarkerUse::Fixed, false);
    let im = r.marker_ref(a, "IM", 2, MarkerUse::Fixed, false);
    let mut ip = [0.0; 6];
    if let Some(v) = a.numbers("IP", 2, 3..=6) {
        if v.len() == 3 || v.len() == 6 {
            ip[..v.len()].copy_from_slice(&v);
            check_inertia(a, &ip, mass);
        } else {
            let span = arg_span(a, "IP");
            let msg = format!("IP of {} takes 3 or 6 numbers", a.label);
            a.error(Code::BadArgument, span, msg);
        }
    }
    let position = a.vec3("QG", 2).unwrap_or_default();
    let orientation = orientation(a, position, "ZG", "XG", false);
    let velocity = ["VX", "VY", "VZ"].map(|k| a.number(k, 2));
    let angular_velocity = ["WX", "WY", "WZ"].map(|k| a.number(k, 2));
    let vm = r.marker_ref(a, "VM", 2, MarkerUse::Fixed, false);
    let wm = r.marker_ref(a, "WM", 2, MarkerUse::Fixed, false);
    let mut exact = [false; 6];
    if let Some(arg) = a.find("EXACT", 2) {
        const COORDS: [&str; 6] = ["X", "Y", "Z", "PSI", "THETA", "PHI"];
        for item in arg.items() {
            match COORDS
                .iter()
                .position(|c| c.eq_ignore_ascii_case(&item.text))
            {
                Some(k) => exact[k] = true,
                None => a.error(
                    Code::BadArgument,
                    item.span.clone(),
                    format!("EXACT takes X, Y, Z, PSI, THETA, PHI, not `{}`", item.text),
                ),
            }
        }
    }
    // MATERIAL names a material for graphics and mass computation in Adams View; the
    // solver reads MASS and IP, so the name changes nothing here.
    a.find("MATERIAL", 3);
    if !ground && mass.is_some() && cm.is_none() && a.stmt.arg("CM", 2).is_none() {
        a.missing("CM = marker (the centre of mass) with MASS");
    }
    for (key, m) in [("CM", &cm), ("IM", &im)] {
        let Some((id, span)) = m else { continue };
        if let Some(marker) = r.marker(*id).filter(|mk| mk.part != el.id) {
            a.diags.push(
                Diagnostic::error(
                    Code::Topology,
                    span.clone(),
                    format!(
                        "{key} of {} is MARKER/{id}, which is on PART/{}",
                        a.label, marker.part
                    ),
                )
                .with_help("the CM and IM markers belong to their own part"),
            );
        }
    }
    r.model.parts.push(Part {
        el,
        ground,
        mass,
        cm: cm.map(|m| m.0),
        im: im.map(|m| m.0),
        ip,
        position,
        orientation,
        velocity,
        angular_velocity,
        vm: vm.map(|m| m.0),
        wm: wm.map(|m| m.0),
        exact,
    });
}

/// The span of argument `key` (name and value), or the statement keyword's.
fn arg_span(a: &Args, key: &str) -> std::ops::Range<usize> {
    a.stmt
        .arg(key, 2)
        .map_or(a.stmt.keyword_span.clone(), |arg| arg.span.clone())
}

/// `MASS`: `None` for a massless part (MASS absent or 0, as Adams reads it); a negative
/// mass is an error (E0608).
fn mass(a: &mut Args) -> Option<f64> {
    let m = a.number("MASS", 2)?;
    if m < 0.0 {
        let msg = format!("MASS of {} is {m}: a mass cannot be negative", a.label);
        let d = Diagnostic::error(Code::MassProperties, arg_span(a, "MASS"), msg)
            .with_help("MASS = 0 (or no MASS) makes a massless part");
        a.diags.push(d);
        return None;
    }
    (m > 0.0).then_some(m)
}

/// Reports an IP the dynamics cannot use (E0608), or one no real body has (W0609): see
/// [`super::inertia`]. Zero inertia with a mass is a point mass (IFToMM A01's bob): a
/// warning, since only constraints can then hold its rotations (`mbfx run` checks that).
fn check_inertia(a: &mut Args, ip: &[f64; 6], mass: Option<f64>) {
    use super::inertia::{check, tensor, Impossible};
    let span = arg_span(a, "IP");
    let d = match check(&tensor(ip)) {
        Err(e @ Impossible::Negative { .. }) => {
            let msg = format!("IP of {} is no body's inertia: {}", a.label, e.describe());
            Diagnostic::error(Code::MassProperties, span, msg)
        }
        Err(e @ Impossible::Triangle { .. }) => {
            let msg = format!(
                "IP of {} is no real body's inertia: {}",
                a.label,
                e.describe()
            );
            Diagnostic::warning(Code::ImplausibleInertia, span, msg)
                .with_help("the tensor is positive semi-definite, so mbfx uses it as written")
        }
        Ok(moments) if moments[2] == 0.0 && mass.is_some() => {
            let msg = format!(
                "IP of {} is zero while the part has a mass: a point mass, whose rotations only constraints can hold",
                a.label
            );
            Diagnostic::warning(Code::ImplausibleInertia, span, msg)
                .with_help("give the moments of inertia, or MASS = 0 for a massless part")
        }
        Ok(_) => return,
    };
    let d = d.with_note(
        "IP = Ixx, Iyy, Izz[, Ixy, Ixz, Iyz] with products +∫xy dm: the tensor \
         [[Ixx, -Ixy, -Ixz], [-Ixy, Iyy, -Iyz], [-Ixz, -Iyz, Izz]] must be positive \
         semi-definite and each principal moment at most the sum of the other two",
    );
    a.diags.push(d);
}

/// `MARKER/id, PART=…`: origin and axes in the part's BCS; FLOATING markers move.
pub fn marker(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let part = match a.required_id("PART", 2) {
        Some((id, span)) => {
            if !r.scope.has("PART", i64::from(id)) {
                a.diags.push(
                    Diagnostic::error(
                        Code::UndefinedElement,
                        span,
                        format!("PART/{id} is not defined in this dataset"),
                    )
                    .with_note(format!("{} is on it", a.label)),
                );
            }
            id
        }
        None => 0,
    };
    let floating = a.flag("FLOATING", 2);
    let position = a.vec3("QP", 2).unwrap_or_default();
    let usexp = a.flag("USEXP", 2);
    let orientation = orientation(a, position, "ZP", "XP", usexp);
    r.add_marker(Marker {
        el,
        part,
        position,
        orientation,
        floating,
    });
}
