//! Readers of the data and output statements: VARIABLE, SPLINE, ARRAY, REQUEST, and the
//! settings statements (OUTPUT, RESULTS, INTEGRATOR, EQUILIBRIUM, KINEMATICS, IC) kept as
//! written (spec §2.5, §7, §8).

use super::elements::{
    Array, Id, PlantVariables, Request, RequestKind, Setting, SplineData, Variable,
};
use super::reader::Reader;
use super::resolve::{ExprArg, MarkerUse};
use super::statement::ArgValue;
use super::stmt_args::Args;
use crate::check::Expect;
use crate::diag::{Code, Diagnostic};

pub fn variable(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let ic = a.number("IC", 2);
    if let Some(function) = r.required_expr(a, "FUNCTION", 2) {
        r.model.variables.push(Variable { el, function, ic });
    }
}

/// `PINPUT/id, VARIABLES = id, …` (`output` false) or `POUTPUT/id, VARIABLES = …`.
pub fn plant(r: &mut Reader, a: &mut Args, output: bool) {
    let el = r.named(a);
    if a.stmt.arg("VARIABLES", 3).is_none() {
        return a.missing("VARIABLES = id, …");
    }
    let Some(values) = a.numbers("VARIABLES", 3, 1..=usize::MAX) else {
        return;
    };
    let mut variables = Vec::with_capacity(values.len());
    for v in values {
        match Id::try_from(v as i64)
            .ok()
            .filter(|_| v.fract() == 0.0 && v >= 1.0)
        {
            Some(id) => variables.push(id),
            None => {
                let span = a.stmt.keyword_span.clone();
                let msg = format!("{}: VARIABLES lists ids, and {v} is not one", a.label);
                return a.error(Code::BadArgument, span, msg);
            }
        }
    }
    r.model.plants.push(PlantVariables {
        el,
        output,
        variables,
    });
}

/// `SPLINE/id, X = …, Y = …[, Z = …]`: a curve, or one row of Y per Z value; X (and Z)
/// strictly increasing.
pub fn spline(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let linear_extrapolate = a.flag("LINEAR_EXTRAPOLATE", 3);
    if let Some(arg) = a.find("FILE", 3) {
        let msg = format!(
            "{} reads its data from a file, which mbfx does not",
            a.label
        );
        a.diags.push(Diagnostic::warning(
            Code::UnsupportedStatement,
            arg.span.clone(),
            msg,
        ));
        return;
    }
    // Both fits need at least 4 knots (spec AKISPL: ≥ 4 x values).
    let x = a.numbers("X", 1, 4..=usize::MAX);
    let y = a.numbers("Y", 1, 1..=usize::MAX);
    let z = a.numbers("Z", 1, 1..=usize::MAX).unwrap_or_default();
    let present = |a: &Args, k: &str| a.stmt.arg(k, 1).is_some();
    for k in ["X", "Y"] {
        if !present(a, k) {
            a.missing(&format!("{k} = values"));
        }
    }
    let (Some(x), Some(y)) = (x, y) else { return };
    let rows = z.len().max(1);
    if y.len() != x.len() * rows {
        let span = a.stmt.keyword_span.clone();
        let msg = format!(
            "{} has {} Y values for {} X values{}",
            a.label,
            y.len(),
            x.len(),
            if z.is_empty() {
                String::new()
            } else {
                format!(" and {} Z values", z.len())
            }
        );
        a.error(Code::BadArgument, span, msg);
        return;
    }
    for (key, v) in [("X", &x), ("Z", &z)] {
        if v.windows(2)
            .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
        {
            let span = a.stmt.keyword_span.clone();
            let msg = format!("{key} of {} must increase strictly", a.label);
            a.error(Code::BadArgument, span, msg);
            return;
        }
    }
    let y = y.chunks(x.len()).map(<[f64]>::to_vec).collect();
    r.model.splines.push(SplineData {
        el,
        x,
        y,
        z,
        linear_extrapolate,
    });
}

/// `ARRAY/id, [X | U | Y | IC], NUMBERS = …[, SIZE = n]`, or a U array's
/// `VARIABLES = id, …` (kept in `numbers`).
pub fn array(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    const KINDS: [&str; 4] = ["IC", "U", "X", "Y"];
    let kind = a
        .choice(&KINDS.map(|k| (k, k.len())))
        .map_or(String::new(), |k| KINDS[k].to_string());
    let numbers = if a.stmt.arg("NUMBERS", 3).is_some() {
        a.numbers("NUMBERS", 3, 1..=usize::MAX).unwrap_or_default()
    } else if a.stmt.arg("VARIABLES", 3).is_some() {
        // A U array lists the VARIABLEs that are an LSE's or TFSISO's inputs (issue 40).
        a.numbers("VARIABLES", 3, 1..=usize::MAX)
            .unwrap_or_default()
    } else {
        Vec::new()
    };
    if let Some(size) = a.number("SIZE", 2) {
        if !numbers.is_empty() && size != numbers.len() as f64 {
            let span = a.stmt.keyword_span.clone();
            let msg = format!(
                "SIZE of {} is {size}, but it lists {} numbers",
                a.label,
                numbers.len()
            );
            a.error(Code::BadArgument, span, msg);
        }
    }
    r.model.arrays.push(Array { el, kind, numbers });
}

/// `REQUEST/id`: a standard set (DISPLACEMENT, VELOCITY, ACCELERATION, FORCE of I
/// relative to J in RM) or expressions F1..F8.
pub fn request(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    const KINDS: [(&str, usize, RequestKind); 4] = [
        ("DISPLACEMENT", 1, RequestKind::Displacement),
        ("VELOCITY", 1, RequestKind::Velocity),
        ("ACCELERATION", 1, RequestKind::Acceleration),
        ("FORCE", 1, RequestKind::Force),
    ];
    let kind = a.choice(&KINDS.map(|(n, m, _)| (n, m))).map(|k| KINDS[k].2);
    let mut standard = None;
    if let Some(kind) = kind {
        let i = r.marker_ref(a, "I", 1, MarkerUse::Any, true);
        let j = r.marker_ref(a, "J", 1, MarkerUse::Any, false);
        let rm = r.marker_ref(a, "RM", 2, MarkerUse::Any, false);
        if let Some(i) = i {
            standard = Some((kind, i.0, j.map(|m| m.0), rm.map(|m| m.0)));
        }
    }
    let mut functions = Vec::new();
    for k in 0..8 {
        let key = format!("F{}", k + 1);
        if let ExprArg::Ok(e) = r.expr(a, &key, 2, Expect::Scalar) {
            functions.push((k, e));
        }
    }
    // A `FUNCTION = USER(…)` request is warned about by `expr`.
    let _ = r.expr(a, "FUNCTION", 2, Expect::Scalar);
    let comment = a
        .find("COMMENT", 1)
        .and_then(|c| c.items().first())
        .map(|i| i.text.clone());
    // Labels of the output columns: they name results, they change no value.
    for (key, min) in [
        ("TITLE", 2),
        ("CNAMES", 2),
        ("CLABELS", 2),
        ("RESULTS_NAME", 2),
    ] {
        a.find(key, min);
    }
    r.model.requests.push(Request {
        el,
        standard,
        functions,
        comment,
    });
}

/// A settings statement, its arguments kept as written.
pub fn setting(r: &mut Reader, a: &mut Args) {
    for arg in &a.stmt.args {
        a.find(&arg.name, arg.name.len());
    }
    keep_setting(r, a);
}

/// INTEGRATOR: typed ([`super::integrator_settings`]), and kept as written for the
/// report. A second statement overrides what it writes, as a command would.
pub fn integrator(r: &mut Reader, a: &mut Args) {
    let typed = super::integrator_settings::read_integrator(a);
    let first = r.model.integrator.take();
    r.model.integrator = Some(match first {
        Some(first) => {
            let mut m = first.merged(&typed);
            m.warnings = [first.warnings, typed.warnings].concat();
            m
        }
        None => typed,
    });
    keep_setting(r, a);
}

/// EQUILIBRIUM: typed ([`super::equilibrium_settings`]), and kept as written for the
/// report. A second statement overrides what it writes.
pub fn equilibrium(r: &mut Reader, a: &mut Args) {
    let typed = super::equilibrium_settings::read_equilibrium(a);
    r.model.equilibrium = Some(match r.model.equilibrium.take() {
        Some(first) => first.then(typed),
        None => typed,
    });
    keep_setting(r, a);
}

/// KINEMATICS: typed ([`super::kinematics_settings`]), and kept as written for the
/// report. A second statement overrides what it writes.
pub fn kinematics(r: &mut Reader, a: &mut Args) {
    let typed = super::kinematics_settings::read_kinematics(a);
    r.model.kinematics = Some(match r.model.kinematics.take() {
        Some(first) => first.then(typed),
        None => typed,
    });
    keep_setting(r, a);
}

/// Records a settings statement's arguments as written.
fn keep_setting(r: &mut Reader, a: &Args) {
    let stmt = a.stmt;
    let mut args = Vec::with_capacity(stmt.args.len());
    for arg in &stmt.args {
        let value = match &arg.value {
            ArgValue::Flag => String::new(),
            _ => {
                let after = r.text[arg.name_span.end..arg.span.end].trim_start();
                after.strip_prefix('=').unwrap_or(after).trim().to_string()
            }
        };
        args.push((arg.name.clone(), value));
    }
    r.model.settings.push(Setting {
        statement: stmt.canonical.unwrap_or(&stmt.keyword).to_string(),
        span: stmt.span.clone(),
        args,
    });
}
