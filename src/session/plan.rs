//! What integrates one stretch of a run: the command line's choices, else the INTEGRATOR
//! statement in force (the dataset's, with a command file's INTEGRATOR commands put over
//! it), else Adams' defaults (spec §6.2), turned into a [`Scheme`] and the driver's
//! [`Settings`]. [`Plan::integrator`] is the one place a scheme becomes an integrator:
//! GSTIFF (the default, as in Adams) and WSTIFF run the BDF of
//! [`crate::mbd::dynamics::bdf`] with their KMAX and formulation; CONSTANT_BDF and HASTIFF,
//! which mbfx does not have, run GSTIFF with a note saying so, and so does SI1 (as SI2).
//! [`segments`] turns a command file's INTEGRATOR and SIMULATE commands into the run's
//! segments.

use super::run::{Method, RunSpec, Segment};
use crate::mbd::dynamics::bdf::{self, Bdf, Coefficients};
use crate::mbd::dynamics::dopri853::Dopri853;
use crate::mbd::dynamics::integrator::{Integrator, Settings};
use crate::mbd::dynamics::newmark::{self, Newmark};
use crate::model::commands::Step;
use crate::model::equilibrium_settings::EquilibriumStatement;
use crate::model::integrator_settings::{
    Family, Formulation, IntegratorStatement, NEWMARK_BETA, NEWMARK_GAMMA,
};

/// Adams' HHT default ALPHA (spec §6.2).
pub const HHT_ALPHA: f64 = -0.3;

/// Exudyn's default spectral radius for generalized-α (spec §6.3).
pub const GALPHA_RHO_INF: f64 = 0.9;

/// Adams' default KMAX, the highest BDF order.
pub const BDF_KMAX: u32 = 6;

/// The method a plan asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scheme {
    /// A member of the Newmark family (HHT, generalized-α, plain Newmark).
    Newmark(newmark::Method),
    /// A backward-difference method with its settings.
    Bdf {
        /// GSTIFF, WSTIFF, ...
        family: Family,
        /// The highest order.
        kmax: u32,
        /// I3, SI2 or SI1.
        formulation: Formulation,
    },
    /// The explicit Dormand–Prince 8(5,3) on the index-1 equations, or on a planar
    /// tree's joint coordinates (command line only).
    Dopri853 {
        /// Keep to the Cartesian form where joint coordinates would do.
        cartesian: bool,
    },
}

/// The integrator and settings of one stretch of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// The method.
    pub scheme: Scheme,
    /// Step sizes, tolerance and iteration limits.
    pub settings: Settings,
}

impl Plan {
    /// The plan for output step `dt` under `statement` (the INTEGRATOR in force, if any)
    /// and the command line's `spec`, which wins over the statement.
    pub fn new(statement: Option<&IntegratorStatement>, spec: &RunSpec, dt: f64) -> Plan {
        let stmt = statement.cloned().unwrap_or_default();
        let value =
            |g: &Option<crate::model::integrator_settings::Given<f64>>| g.as_ref().map(|g| g.value);
        let mut s = Settings::for_output_step(dt);
        s.error = spec.error.or(value(&stmt.error)).unwrap_or(s.error);
        s.interpolate = spec.interpolate || stmt.interpolate.as_ref().is_some_and(|i| i.value);
        // Stepped output holds HMAX to the output step; interpolated output leaves the
        // steps to error control (Adams: no limit unless HMAX is given).
        let hmax = spec.hmax.or(value(&stmt.hmax));
        s.hmax = match s.interpolate {
            true => hmax.unwrap_or(f64::INFINITY),
            false => hmax.unwrap_or(s.hmax).min(dt),
        };
        s.hinit = spec
            .hinit
            .or(value(&stmt.hinit))
            .unwrap_or(s.hinit)
            .min(s.hmax);
        s.hmin = spec.hmin.or(value(&stmt.hmin)).unwrap_or(s.hmin);
        if let Some(m) = &stmt.maxit {
            s.maxit = m.value as usize;
        }
        s.fixed_step = spec.fixed_step;
        s.error_per_run = spec.error_per_run;
        let alpha = spec.alpha.or(value(&stmt.alpha)).unwrap_or(HHT_ALPHA);
        let newmark = newmark::Method::Newmark {
            beta: value(&stmt.beta).unwrap_or(NEWMARK_BETA),
            gamma: value(&stmt.gamma).unwrap_or(NEWMARK_GAMMA),
        };
        let bdf_scheme = |family| Scheme::Bdf {
            family,
            kmax: spec.kmax.or(stmt.kmax.map(|k| k.value)).unwrap_or(BDF_KMAX),
            formulation: spec
                .formulation
                .or(stmt.formulation.map(|f| f.value))
                .unwrap_or_default(),
        };
        let scheme = match spec.method {
            Some(Method::Hht) => Scheme::Newmark(newmark::Method::Hht { alpha }),
            Some(Method::Galpha) => Scheme::Newmark(newmark::Method::GeneralizedAlpha {
                rho_inf: spec.rho_inf.unwrap_or(GALPHA_RHO_INF),
            }),
            Some(Method::Newmark) => Scheme::Newmark(newmark),
            Some(Method::Gstiff) => bdf_scheme(Family::Gstiff),
            Some(Method::Wstiff) => bdf_scheme(Family::Wstiff),
            Some(Method::Dopri853) => Scheme::Dopri853 {
                cartesian: spec.cartesian,
            },
            None => match stmt.family.map(|f| f.value) {
                Some(Family::Hht) => Scheme::Newmark(newmark::Method::Hht { alpha }),
                Some(Family::Newmark) => Scheme::Newmark(newmark),
                Some(family) => bdf_scheme(family),
                None => bdf_scheme(Family::Gstiff),
            },
        };
        Plan {
            scheme,
            settings: s,
        }
    }

    /// The integrator the plan runs, and a note when it is not the one asked for.
    pub fn integrator(&self) -> (Box<dyn Integrator>, Option<String>) {
        match self.scheme {
            Scheme::Newmark(m) => (Box::new(Newmark::new(m)), None),
            Scheme::Dopri853 { cartesian: false } => (Box::new(Dopri853::new()), None),
            Scheme::Dopri853 { cartesian: true } => (Box::new(Dopri853::cartesian()), None),
            Scheme::Bdf {
                family,
                kmax,
                formulation,
            } => {
                let mut notes = Vec::new();
                let coefficients = match family {
                    Family::Wstiff => Coefficients::Variable,
                    Family::Gstiff => Coefficients::FixedLeading,
                    _ => {
                        notes.push(format!("mbfx has no {}; GSTIFF ran instead", family.name()));
                        Coefficients::FixedLeading
                    }
                };
                let formulation = match formulation {
                    Formulation::I3 => bdf::Formulation::I3,
                    Formulation::Si2 => bdf::Formulation::Si2,
                    Formulation::Si1 => {
                        notes.push("mbfx has no SI1 formulation; SI2 ran instead".into());
                        bdf::Formulation::Si2
                    }
                };
                let note = (!notes.is_empty())
                    .then(|| format!("INTEGRATOR/{}: {}", family.name(), notes.join("; ")));
                let b = Bdf::new(coefficients, formulation, kmax as usize);
                (Box::new(b), note)
            }
        }
    }
}

/// The segments of a command file's `steps`: each SIMULATE runs under the dataset's
/// INTEGRATOR and EQUILIBRIUM statements with every such command before it put over
/// them, after the changes to the model written since the SIMULATE before it (changes
/// after the last SIMULATE change nothing that runs).
pub fn segments(
    dataset: Option<&IntegratorStatement>,
    equilibrium: Option<&EquilibriumStatement>,
    steps: &[Step],
) -> Vec<Segment> {
    let mut current = dataset.cloned();
    let mut statics = equilibrium.cloned();
    let mut changes = Vec::new();
    let mut out: Vec<Segment> = Vec::new();
    for step in steps {
        match step {
            Step::Integrator(s) => {
                current = Some(match current {
                    Some(c) => c.merged(s),
                    None => (**s).clone(),
                });
            }
            Step::Equilibrium(s) => {
                statics = Some(match statics {
                    Some(c) => c.merged(s),
                    None => (**s).clone(),
                });
            }
            Step::Change(c) => changes.push((**c).clone()),
            Step::Simulate(sim) => out.push(Segment {
                end: sim.end,
                output_step: sim.output_step,
                integrator: current.clone(),
                kind: sim.kind,
                equilibrium: statics.clone(),
                linear: None,
                changes: std::mem::take(&mut changes),
            }),
            Step::Linear(l) => {
                let at = out.last().map_or(0.0, |s| s.end);
                out.push(Segment {
                    changes: std::mem::take(&mut changes),
                    ..Segment::linear(at, (**l).clone())
                });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::read_model;

    fn statement(args: &str) -> IntegratorStatement {
        let r = read_model(&format!("t\nPART/1, GROUND\nINTEGRATOR/{args}\nEND\n"));
        r.model.integrator.expect("an INTEGRATOR statement")
    }

    #[test]
    fn defaults_are_adams_for_the_output_step() {
        // Spec §6.2: ERROR 1e-3, HMAX = output step, HINIT = output step / 20, MAXIT 10.
        let p = Plan::new(None, &RunSpec::new(1.0, 0.1), 0.1);
        assert_eq!(
            p.scheme,
            Scheme::Bdf {
                family: Family::Gstiff,
                kmax: 6,
                formulation: Formulation::I3
            }
        );
        assert_eq!(p.settings, Settings::for_output_step(0.1));
    }

    #[test]
    fn the_statement_sets_and_the_command_line_overrides() {
        let st = statement(
            "HHT, ERROR = 1e-5, HMAX = 0.002, HINIT = 1e-4, HMIN = 1e-9, MAXIT = 25, ALPHA = -0.2",
        );
        let spec = RunSpec::new(1.0, 0.01);
        let p = Plan::new(Some(&st), &spec, 0.01);
        assert_eq!(
            p.scheme,
            Scheme::Newmark(newmark::Method::Hht { alpha: -0.2 })
        );
        let s = &p.settings;
        assert_eq!(
            (s.error, s.hmax, s.hinit, s.hmin, s.maxit),
            (1e-5, 0.002, 1e-4, 1e-9, 25)
        );
        let mut spec = spec;
        (spec.error, spec.alpha, spec.method) = (Some(1e-3), Some(-0.1), None);
        let p = Plan::new(Some(&st), &spec, 0.01);
        assert_eq!(p.settings.error, 1e-3);
        assert_eq!(
            p.scheme,
            Scheme::Newmark(newmark::Method::Hht { alpha: -0.1 })
        );
        spec.method = Some(Method::Galpha);
        let p = Plan::new(Some(&st), &spec, 0.01);
        assert!(matches!(
            p.scheme,
            Scheme::Newmark(newmark::Method::GeneralizedAlpha { .. })
        ));
    }

    #[test]
    fn hmax_never_exceeds_the_output_step() {
        let st = statement("HHT, HMAX = 1");
        let p = Plan::new(Some(&st), &RunSpec::new(1.0, 0.01), 0.01);
        assert_eq!(p.settings.hmax, 0.01);
    }

    #[test]
    fn interpolate_comes_from_the_statement_or_the_command_line_and_frees_hmax() {
        let p = Plan::new(
            Some(&statement("HHT, INTERPOLATE = ON")),
            &RunSpec::new(1.0, 0.01),
            0.01,
        );
        assert!(p.settings.interpolate);
        assert_eq!(p.settings.hmax, f64::INFINITY);
        // HINIT and HMIN keep Adams' defaults for the output step.
        assert_eq!((p.settings.hinit, p.settings.hmin), (0.01 / 20.0, 1e-8));
        let st = statement("HHT, INTERPOLATE = OFF, HMAX = 1");
        let mut spec = RunSpec::new(1.0, 0.01);
        assert!(!Plan::new(Some(&st), &spec, 0.01).settings.interpolate);
        spec.interpolate = true;
        let p = Plan::new(Some(&st), &spec, 0.01);
        assert!(p.settings.interpolate);
        assert_eq!(p.settings.hmax, 1.0);
    }

    #[test]
    fn newmark_takes_beta_and_gamma_or_adams_defaults() {
        let p = Plan::new(
            Some(&statement("NEWMARK, BETA = 0.3, GAMMA = 0.6")),
            &RunSpec::new(1.0, 0.1),
            0.1,
        );
        assert_eq!(
            p.scheme,
            Scheme::Newmark(newmark::Method::Newmark {
                beta: 0.3,
                gamma: 0.6
            })
        );
        let p = Plan::new(Some(&statement("NEWMARK")), &RunSpec::new(1.0, 0.1), 0.1);
        assert_eq!(
            p.scheme,
            Scheme::Newmark(newmark::Method::Newmark {
                beta: 0.36,
                gamma: 0.7
            })
        );
    }

    #[test]
    fn bdf_statements_keep_their_settings_and_run_a_bdf() {
        let st = statement("GSTIFF, SI2, KMAX = 4, ERROR = 1e-4");
        let p = Plan::new(Some(&st), &RunSpec::new(1.0, 0.1), 0.1);
        assert_eq!(
            p.scheme,
            Scheme::Bdf {
                family: Family::Gstiff,
                kmax: 4,
                formulation: Formulation::Si2,
            }
        );
        assert_eq!(p.settings.error, 1e-4);
        let (i, note) = p.integrator();
        assert_eq!((i.name(), note), ("gstiff", None));
        let st = statement("WSTIFF");
        let (i, note) = Plan::new(Some(&st), &RunSpec::new(1.0, 0.1), 0.1).integrator();
        assert_eq!((i.name(), note), ("wstiff", None));
        let st = statement("HASTIFF, SI1");
        let (i, note) = Plan::new(Some(&st), &RunSpec::new(1.0, 0.1), 0.1).integrator();
        let note = note.expect("a note");
        assert_eq!(i.name(), "gstiff");
        assert!(note.contains("HASTIFF") && note.contains("SI1"), "{note}");
    }

    #[test]
    fn integrator_commands_apply_to_the_simulations_after_them() {
        let f = crate::model::commands::read_commands(
            "m.adm\nout\nsim/dyn, end=1, dtout=0.1\nint/hht, err=1e-6\nsim/dyn, end=2, steps=5\n",
        );
        let dataset = statement("GSTIFF, HMAX = 1e-3");
        let segs = segments(Some(&dataset), None, &f.steps);
        assert_eq!(segs.len(), 2);
        assert_eq!((segs[1].end, segs[1].output_step), (2.0, 0.2));
        let first = segs[0].integrator.as_ref().expect("the dataset's");
        assert_eq!(first.family.as_ref().map(|f| f.value), Some(Family::Gstiff));
        let second = segs[1].integrator.as_ref().expect("merged");
        assert_eq!(second.family.as_ref().map(|f| f.value), Some(Family::Hht));
        assert_eq!(second.error.as_ref().map(|e| e.value), Some(1e-6));
        assert_eq!(second.hmax.as_ref().map(|e| e.value), Some(1e-3));
    }
}
