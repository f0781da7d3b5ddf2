//! The INTEGRATOR statement (multibody spec §6.2) read into typed settings, the same way
//! from a dataset (`.adm`) and from a command file (`.acf`): which integrator (GSTIFF,
//! WSTIFF, CONSTANT_BDF, HASTIFF, HHT, NEWMARK), which formulation (I3, SI2, SI1), and
//! ERROR, HMAX, HINIT, HMIN, KMAX, MAXIT, ALPHA, BETA, GAMMA, CORRECTOR, PATTERN,
//! INTERPOLATE and ADAPTIVITY. Every value is checked where it is written (`E0605` at its
//! span); every argument the run does not honour is a `W0602` warning naming it, kept in
//! [`IntegratorStatement::warnings`] so `mbfx run` can print them beside the file they
//! point into. What the run does with the settings is decided in `session::plan`.

use super::statement::{Argument, Item, ItemKind};
use super::stmt_args::Args;
use crate::diag::{Code, Diagnostic, Span};

/// Which integrator the statement names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// Gear's BDF with a fixed leading coefficient, variable order and step (Adams' default).
    Gstiff,
    /// Variable-coefficient BDF.
    Wstiff,
    /// BDF with constant coefficients.
    ConstantBdf,
    /// Hiller–Anantharaman stiff integrator.
    Hastiff,
    /// Hilber–Hughes–Taylor (ALPHA).
    Hht,
    /// Newmark (BETA, GAMMA).
    Newmark,
}

impl Family {
    /// The name as Adams writes it.
    pub fn name(self) -> &'static str {
        match self {
            Family::Gstiff => "GSTIFF",
            Family::Wstiff => "WSTIFF",
            Family::ConstantBdf => "CONSTANT_BDF",
            Family::Hastiff => "HASTIFF",
            Family::Hht => "HHT",
            Family::Newmark => "NEWMARK",
        }
    }

    /// The backward-difference members (they take KMAX, formulations, ADAPTIVITY).
    pub fn is_bdf(self) -> bool {
        matches!(
            self,
            Family::Gstiff | Family::Wstiff | Family::ConstantBdf | Family::Hastiff
        )
    }
}

/// The DAE formulation (spec §6.2): index 3, stabilized index 2 or stabilized index 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Formulation {
    /// Index 3: the position constraints only.
    #[default]
    I3,
    /// Stabilized index 2: position and velocity constraints.
    Si2,
    /// Stabilized index 1: position, velocity and acceleration constraints.
    Si1,
}

/// CORRECTOR (spec §6.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Corrector {
    /// ORIGINAL: the convergence test covers every variable.
    Original,
    /// MODIFIED: the convergence test leaves the multipliers out.
    Modified,
    /// ORIGINAL even when the model has CONTACT.
    OrigConstant,
}

/// One value as written, with where it was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Given<T> {
    /// The value.
    pub value: T,
    /// Byte range of the argument in the file.
    pub span: Span,
}

/// An INTEGRATOR statement or command, typed. `None`: not written (the run's default
/// applies, or an earlier statement's value).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IntegratorStatement {
    /// The integrator (GSTIFF, WSTIFF, HHT, NEWMARK, ...).
    pub family: Option<Given<Family>>,
    /// I3, SI2 or SI1.
    pub formulation: Option<Given<Formulation>>,
    /// ERROR: the local error tolerance.
    pub error: Option<Given<f64>>,
    /// HMAX: the largest step.
    pub hmax: Option<Given<f64>>,
    /// HINIT: the first step.
    pub hinit: Option<Given<f64>>,
    /// HMIN: the smallest step.
    pub hmin: Option<Given<f64>>,
    /// KMAX: the highest BDF order.
    pub kmax: Option<Given<u32>>,
    /// MAXIT: the most corrector iterations per step.
    pub maxit: Option<Given<u32>>,
    /// ALPHA of HHT.
    pub alpha: Option<Given<f64>>,
    /// BETA of NEWMARK.
    pub beta: Option<Given<f64>>,
    /// GAMMA of NEWMARK.
    pub gamma: Option<Given<f64>>,
    /// CORRECTOR: the convergence test.
    pub corrector: Option<Given<Corrector>>,
    /// PATTERN: per corrector iteration, whether the Jacobian is evaluated.
    pub pattern: Option<Given<Vec<bool>>>,
    /// INTERPOLATE: output rows interpolated rather than stepped to.
    pub interpolate: Option<Given<bool>>,
    /// ADAPTIVITY: the term added to the corrector's convergence tolerance.
    pub adaptivity: Option<Given<f64>>,
    /// The `W0602` warnings about what the run does not honour (also among the reader's
    /// diagnostics).
    pub warnings: Vec<Diagnostic>,
}

/// KMAX: Adams' BDF orders run from 1 to 6.
const KMAX_RANGE: std::ops::RangeInclusive<u32> = 1..=6;

/// The flags that name the integrator, with their shortest accepted abbreviations.
const FAMILIES: [(&str, usize, Family); 6] = [
    ("GSTIFF", 2, Family::Gstiff),
    ("WSTIFF", 2, Family::Wstiff),
    ("CONSTANT_BDF", 3, Family::ConstantBdf),
    ("HASTIFF", 3, Family::Hastiff),
    ("HHT", 3, Family::Hht),
    ("NEWMARK", 3, Family::Newmark),
];

const FORMULATIONS: [(&str, usize, Formulation); 3] = [
    ("I3", 2, Formulation::I3),
    ("SI2", 3, Formulation::Si2),
    ("SI1", 3, Formulation::Si1),
];

/// Reads the arguments of an INTEGRATOR statement or command; errors and warnings go to
/// `a.diags` (unknown arguments are left for `Args::finish` to report).
pub fn read_integrator(a: &mut Args) -> IntegratorStatement {
    let mut s = IntegratorStatement {
        family: flag_choice(a, &FAMILIES),
        formulation: flag_choice(a, &FORMULATIONS),
        ..IntegratorStatement::default()
    };
    let positive = |x: f64| x > 0.0;
    s.error = real(a, "ERROR", 3, positive, "a positive tolerance");
    s.hmax = real(a, "HMAX", 3, positive, "a positive step");
    s.hinit = real(a, "HINIT", 3, positive, "a positive step");
    s.hmin = real(a, "HMIN", 3, positive, "a positive step");
    s.kmax = integer(a, "KMAX", 2, KMAX_RANGE);
    s.maxit = integer(a, "MAXIT", 3, 1..=u32::MAX);
    s.alpha = real(
        a,
        "ALPHA",
        2,
        |x| (-1.0 / 3.0..=0.0).contains(&x),
        "within [-1/3, 0]",
    );
    s.beta = real(a, "BETA", 2, positive, "positive");
    s.gamma = real(a, "GAMMA", 2, |x| x >= 0.5, "at least 0.5");
    s.adaptivity = real(a, "ADAPTIVITY", 3, |x| x >= 0.0, "zero or positive");
    s.corrector = word(
        a,
        "CORRECTOR",
        3,
        &[
            ("ORIGINAL", 4, Corrector::Original),
            ("MODIFIED", 3, Corrector::Modified),
            ("ORIG_CONSTANT", 6, Corrector::OrigConstant),
        ],
    );
    s.interpolate = word(a, "INTERPOLATE", 3, &[("ON", 2, true), ("OFF", 2, false)]);
    s.pattern = pattern(a);
    check_order(a, &s);
    s.warnings = unhonoured(&s);
    a.diags.extend(s.warnings.iter().cloned());
    s
}

impl IntegratorStatement {
    /// This statement with the values `later` writes put over it: an INTEGRATOR command
    /// changes what it names and keeps the rest (naming an integrator resets nothing else).
    pub fn merged(&self, later: &IntegratorStatement) -> IntegratorStatement {
        fn pick<T: Clone>(a: &Option<Given<T>>, b: &Option<Given<T>>) -> Option<Given<T>> {
            b.clone().or_else(|| a.clone())
        }
        IntegratorStatement {
            family: pick(&self.family, &later.family),
            formulation: pick(&self.formulation, &later.formulation),
            error: pick(&self.error, &later.error),
            hmax: pick(&self.hmax, &later.hmax),
            hinit: pick(&self.hinit, &later.hinit),
            hmin: pick(&self.hmin, &later.hmin),
            kmax: pick(&self.kmax, &later.kmax),
            maxit: pick(&self.maxit, &later.maxit),
            alpha: pick(&self.alpha, &later.alpha),
            beta: pick(&self.beta, &later.beta),
            gamma: pick(&self.gamma, &later.gamma),
            corrector: pick(&self.corrector, &later.corrector),
            pattern: pick(&self.pattern, &later.pattern),
            interpolate: pick(&self.interpolate, &later.interpolate),
            adaptivity: pick(&self.adaptivity, &later.adaptivity),
            warnings: Vec::new(),
        }
    }
}

/// The one flag of `options` present, with its span; two of them are an error.
fn flag_choice<T: Copy>(a: &mut Args, options: &[(&str, usize, T)]) -> Option<Given<T>> {
    let names: Vec<(&str, usize)> = options.iter().map(|(n, m, _)| (*n, *m)).collect();
    let k = a.choice(&names)?;
    let (full, min, value) = options[k];
    let arg = a
        .stmt
        .args
        .iter()
        .find(|x| super::keywords::abbreviates(&x.name, full, min))?;
    Some(Given {
        value,
        span: arg.name_span.clone(),
    })
}

/// The one item of an argument, or an error at the argument.
pub(super) fn single<'s>(a: &mut Args, arg: &'s Argument, what: &str) -> Option<&'s Item> {
    match arg.items() {
        [one] => Some(one),
        _ => {
            let msg = format!("{} takes {what}", arg.name);
            a.error(Code::BadArgument, arg.span.clone(), msg);
            None
        }
    }
}

/// A number that must satisfy `ok` (described by `range` in the message).
pub(super) fn real(
    a: &mut Args,
    full: &str,
    min: usize,
    ok: impl Fn(f64) -> bool,
    range: &str,
) -> Option<Given<f64>> {
    let arg = a.find(full, min)?;
    let item = single(a, arg, "one number")?;
    let value = match item.kind {
        ItemKind::Number { value, degrees } if !degrees => value,
        _ => {
            let msg = format!("{full}: expected a number, found `{}`", item.text);
            a.error(Code::BadArgument, item.span.clone(), msg);
            return None;
        }
    };
    if !value.is_finite() {
        // Already E0607 where the statement was read.
        return None;
    }
    if !ok(value) {
        let msg = format!("{full} = {} must be {range}", item.text);
        a.error(Code::BadArgument, item.span.clone(), msg);
        return None;
    }
    Some(Given {
        value,
        span: item.span.clone(),
    })
}

/// An integer within `range`.
pub(super) fn integer(
    a: &mut Args,
    full: &str,
    min: usize,
    range: std::ops::RangeInclusive<u32>,
) -> Option<Given<u32>> {
    let arg = a.find(full, min)?;
    let item = single(a, arg, "one integer")?;
    let value = item.as_integer().and_then(|v| u32::try_from(v).ok());
    match value.filter(|v| range.contains(v)) {
        Some(value) => Some(Given {
            value,
            span: item.span.clone(),
        }),
        None => {
            let want = if *range.end() == u32::MAX {
                format!("an integer of at least {}", range.start())
            } else {
                format!("an integer from {} to {}", range.start(), range.end())
            };
            let msg = format!("{full} = {} must be {want}", item.text);
            a.error(Code::BadArgument, item.span.clone(), msg);
            None
        }
    }
}

/// A word value out of `options` (abbreviations accepted).
fn word<T: Copy>(
    a: &mut Args,
    full: &str,
    min: usize,
    options: &[(&str, usize, T)],
) -> Option<Given<T>> {
    let arg = a.find(full, min)?;
    let item = single(a, arg, "one word")?;
    let hit = options
        .iter()
        .find(|(name, m, _)| super::keywords::abbreviates(&item.text, name, *m));
    match hit {
        Some(&(_, _, value)) if item.kind == ItemKind::Word => Some(Given {
            value,
            span: item.span.clone(),
        }),
        _ => {
            let names: Vec<&str> = options.iter().map(|(n, _, _)| *n).collect();
            let msg = format!("{full} = {}: expected {}", item.text, names.join(" or "));
            a.error(Code::BadArgument, item.span.clone(), msg);
            None
        }
    }
}

/// PATTERN = T:F:…: up to ten T or F values.
fn pattern(a: &mut Args) -> Option<Given<Vec<bool>>> {
    let arg = a.find("PATTERN", 3)?;
    let mut out = Vec::new();
    for item in arg.items() {
        match item.text.to_ascii_uppercase().as_str() {
            "T" | "TRUE" => out.push(true),
            "F" | "FALSE" => out.push(false),
            _ => {
                let msg = format!("PATTERN: expected T or F, found `{}`", item.text);
                a.error(Code::BadArgument, item.span.clone(), msg);
                return None;
            }
        }
    }
    if out.is_empty() || out.len() > 10 {
        let msg = format!("PATTERN takes 1 to 10 values T or F, found {}", out.len());
        a.error(Code::BadArgument, arg.span.clone(), msg);
        return None;
    }
    Some(Given {
        value: out,
        span: arg.span.clone(),
    })
}

/// Checks that span two values: HMIN ≤ HINIT ≤ HMAX where written together, and
/// Newmark's BETA ≥ GAMMA/2 (the unconditionally stable members: error control takes
/// steps that a conditionally stable member could not).
fn check_order(a: &mut Args, s: &IntegratorStatement) {
    let pairs = [
        (&s.hmin, "HMIN", &s.hmax, "HMAX"),
        (&s.hinit, "HINIT", &s.hmax, "HMAX"),
        (&s.hmin, "HMIN", &s.hinit, "HINIT"),
    ];
    for (lo, lo_name, hi, hi_name) in pairs {
        if let (Some(lo), Some(hi)) = (lo, hi) {
            if lo.value > hi.value {
                let d = Diagnostic::error(
                    Code::BadArgument,
                    lo.span.clone(),
                    format!("{lo_name} must not exceed {hi_name}"),
                )
                .with_label(hi.span.clone(), format!("{hi_name} is {}", hi.value));
                a.diags.push(d);
            }
        }
    }
    let beta = s.beta.as_ref();
    let gamma = s.gamma.as_ref();
    let (b, g) = (
        beta.map_or(NEWMARK_BETA, |x| x.value),
        gamma.map_or(NEWMARK_GAMMA, |x| x.value),
    );
    if let Some(at) = beta.or(gamma).filter(|_| 2.0 * b < g) {
        a.diags.push(
            Diagnostic::error(
                Code::BadArgument,
                at.span.clone(),
                format!("NEWMARK with BETA = {b} and GAMMA = {g} is not unconditionally stable"),
            )
            .with_help("take BETA ≥ GAMMA/2, e.g. BETA = 0.36 with GAMMA = 0.7"),
        );
    }
}

/// Adams' NEWMARK defaults (spec §6.2).
pub const NEWMARK_BETA: f64 = 0.36;
/// Adams' NEWMARK default for GAMMA (spec §6.2).
pub const NEWMARK_GAMMA: f64 = 0.7;

/// A `W0602` warning about an argument the run does not honour.
fn warn(span: &Span, message: String) -> Diagnostic {
    Diagnostic::warning(Code::UnsupportedStatement, span.clone(), message)
}

/// Everything written that `mbfx run` does not honour, each named at its span. What is
/// honoured: GSTIFF and WSTIFF (the default GSTIFF when none is named) with I3 or SI2 and
/// KMAX, HHT and its ALPHA, NEWMARK and its BETA and GAMMA, ERROR, HMAX, HINIT, HMIN,
/// MAXIT, INTERPOLATE.
fn unhonoured(s: &IntegratorStatement) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let family = s.family.as_ref().map(|f| f.value);
    let bdf = family.is_none_or(Family::is_bdf);
    if let Some(f) = s
        .family
        .as_ref()
        .filter(|f| matches!(f.value, Family::ConstantBdf | Family::Hastiff))
    {
        out.push(
            warn(
                &f.span,
                format!(
                    "INTEGRATOR/{}: mbfx has no {0}; GSTIFF runs instead",
                    f.value.name()
                ),
            )
            .with_note("ERROR, HMAX, HINIT, HMIN, KMAX and MAXIT still apply"),
        );
    }
    if let Some(f) = s
        .formulation
        .as_ref()
        .filter(|f| f.value != Formulation::I3)
    {
        let message = match (f.value, bdf) {
            (Formulation::Si1, true) => {
                "INTEGRATOR SI1 is not honoured: mbfx has no SI1 formulation; SI2 runs instead"
            }
            (Formulation::Si2, true) => "",
            _ => "INTEGRATOR SI2/SI1 is not honoured: it belongs to the BDF integrators, and HHT and NEWMARK integrate the index-3 DAE (I3)",
        };
        if !message.is_empty() {
            out.push(warn(&f.span, message.into()));
        }
    }
    if let Some(k) = s.kmax.as_ref().filter(|_| !bdf) {
        out.push(warn(
            &k.span,
            format!(
                "INTEGRATOR KMAX = {} is not honoured: it bounds a BDF's order, and HHT and NEWMARK are second order",
                k.value
            ),
        ));
    }
    if let Some(x) = &s.alpha {
        if family.is_some_and(|f| f != Family::Hht) {
            out.push(warn(
                &x.span,
                "INTEGRATOR ALPHA is not honoured: it belongs to HHT".into(),
            ));
        }
    }
    for (x, name) in [(&s.beta, "BETA"), (&s.gamma, "GAMMA")] {
        if let Some(x) = x.as_ref().filter(|_| family != Some(Family::Newmark)) {
            out.push(warn(
                &x.span,
                format!("INTEGRATOR {name} is not honoured: it belongs to NEWMARK"),
            ));
        }
    }
    if let Some(c) = &s.corrector {
        out.push(warn(
            &c.span,
            "INTEGRATOR CORRECTOR is not honoured: the mbfx corrector tests what its corrections do to the integrated variables and leaves the multipliers out (as CORRECTOR = MODIFIED does)".into(),
        ));
    }
    if let Some(p) = &s.pattern {
        out.push(warn(
            &p.span,
            "INTEGRATOR PATTERN is not honoured: mbfx re-evaluates the Jacobian when Newton contracts poorly or the step changes".into(),
        ));
    }
    if let Some(x) = &s.adaptivity {
        out.push(warn(
            &x.span,
            "INTEGRATOR ADAPTIVITY is not honoured: the mbfx BDF corrector keeps its own tolerance (a thousandth of ERROR)"
                .into(),
        ));
    }
    out
}

/// A `W0602` warning at each argument of `table` (full name, shortest abbreviation, why)
/// that the statement `keyword` writes and mbfx reads but does not honour; the warnings
/// also go to `a.diags`.
pub fn unhonoured_arguments(
    a: &mut Args,
    keyword: &str,
    table: &[(&str, usize, &str)],
) -> Vec<Diagnostic> {
    let mut warnings = Vec::new();
    for &(full, min, why) in table {
        if let Some(arg) = a.find(full, min) {
            warnings.push(Diagnostic::warning(
                Code::UnsupportedStatement,
                arg.span.clone(),
                format!("{keyword}/{full} is not honoured: {why}"),
            ));
        }
    }
    a.diags.extend(warnings.iter().cloned());
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::read_model;

    fn read(stmt: &str) -> (Option<IntegratorStatement>, Vec<Diagnostic>) {
        let text = format!("t\nPART/1, GROUND\n{stmt}\nEND\n");
        let r = read_model(&text);
        (r.model.integrator, r.diagnostics)
    }

    #[test]
    fn corpus_spellings_read_into_typed_values() {
        // adamspy drillsim and ssernap T_MSC_ADAMS (spec §6.2 "Real INTEGRATOR statements").
        let (s, d) =
            read("INTEGRATOR/\n, HHT\n, HMAX = 0.005\n, ALPHA = -0.25\n, CORRECTOR = MODIFIED");
        let s = s.expect("typed");
        assert_eq!(s.family.map(|f| f.value), Some(Family::Hht));
        assert_eq!(s.hmax.map(|x| x.value), Some(0.005));
        assert_eq!(s.alpha.map(|x| x.value), Some(-0.25));
        assert_eq!(s.corrector.map(|x| x.value), Some(Corrector::Modified));
        assert!(d.iter().all(|d| !d.is_error()), "{d:?}");
        assert!(d
            .iter()
            .any(|d| d.message.contains("CORRECTOR is not honoured")));

        let (s, d) = read(
            "INTEGRATOR/\n, GSTIFF\n, SI2\n, ERROR = 1.0E-004\n, PATTERN = T:T:T:T:T:T:T:T:T:T\n, MAXIT = 25\n, HINIT = 1.0E-004\n, KMAX = 4",
        );
        let s = s.expect("typed");
        assert_eq!(s.family.map(|f| f.value), Some(Family::Gstiff));
        assert_eq!(s.formulation.map(|f| f.value), Some(Formulation::Si2));
        assert_eq!(s.error.map(|x| x.value), Some(1e-4));
        assert_eq!(s.maxit.map(|x| x.value), Some(25));
        assert_eq!(s.kmax.map(|x| x.value), Some(4));
        assert_eq!(s.pattern.map(|x| x.value), Some(vec![true; 10]));
        assert!(d.iter().all(|d| !d.is_error()), "{d:?}");
        // GSTIFF, SI2 and KMAX are honoured; PATTERN is not.
        let warned: Vec<&str> = s.warnings.iter().map(|w| w.message.as_str()).collect();
        assert!(warned.iter().any(|w| w.contains("PATTERN")), "{warned:?}");
        for honoured in ["GSTIFF", "SI2", "KMAX"] {
            assert!(!warned.iter().any(|w| w.contains(honoured)), "{warned:?}");
        }
        for (stmt, named) in [
            (
                "INTEGRATOR/HASTIFF, SI1",
                ["no HASTIFF; GSTIFF runs", "SI2 runs instead"],
            ),
            ("INTEGRATOR/HHT, KMAX = 3, SI2", ["KMAX = 3", "SI2/SI1"]),
        ] {
            let s = read(stmt).0.expect("typed");
            let warned: Vec<&str> = s.warnings.iter().map(|w| w.message.as_str()).collect();
            for n in named {
                assert!(warned.iter().any(|w| w.contains(n)), "{n}: {warned:?}");
            }
        }
    }

    #[test]
    fn bad_values_are_errors_at_their_span() {
        for (stmt, bad) in [
            ("INTEGRATOR/HHT, ALPHA = -0.5", "-0.5"),
            ("INTEGRATOR/HHT, ERROR = 0", "0"),
            ("INTEGRATOR/GSTIFF, KMAX = 7", "7"),
            ("INTEGRATOR/GSTIFF, MAXIT = 2.5", "2.5"),
            ("INTEGRATOR/HHT, HMAX = -1", "-1"),
            ("INTEGRATOR/HHT, HMAX = fast", "fast"),
            ("INTEGRATOR/NEWMARK, GAMMA = 0.4", "0.4"),
            ("INTEGRATOR/NEWMARK, BETA = 0.25, GAMMA = 0.7", "0.25"),
            ("INTEGRATOR/HHT, INTERPOLATE = MAYBE", "MAYBE"),
            ("INTEGRATOR/HHT, PATTERN = T:X", "X"),
            ("INTEGRATOR/HHT, HMIN = 0.1, HMAX = 0.01", "0.1"),
        ] {
            let text = format!("t\nPART/1, GROUND\n{stmt}\nEND\n");
            let r = read_model(&text);
            let e = r
                .diagnostics
                .iter()
                .find(|d| d.is_error())
                .unwrap_or_else(|| panic!("{stmt}: no error"));
            assert_eq!(e.code, Code::BadArgument, "{stmt}");
            assert_eq!(&text[e.span.clone()], bad, "{stmt}: {}", e.message);
        }
    }

    #[test]
    fn two_integrators_in_one_statement_are_an_error() {
        let (_, d) = read("INTEGRATOR/HHT, GSTIFF");
        assert!(d
            .iter()
            .any(|d| d.is_error() && d.message.contains("exclude")));
    }

    #[test]
    fn a_later_statement_overrides_only_what_it_writes() {
        let (a, _) = read("INTEGRATOR/GSTIFF, ERROR = 1e-4, HMAX = 1e-5");
        let (b, _) = read("INTEGRATOR/HHT, ERROR = 1e-7");
        let m = a.expect("a").merged(&b.expect("b"));
        assert_eq!(m.family.map(|f| f.value), Some(Family::Hht));
        assert_eq!(m.error.map(|x| x.value), Some(1e-7));
        assert_eq!(m.hmax.map(|x| x.value), Some(1e-5));
    }
}
