//! One point of a chart: a scene run once with one method at one tolerance (or fixed
//! step), timed and scored against the scene's truth. Building and compiling the model
//! is not timed; the run is (the summary's CPU time: integration and output rows), and
//! a short run is repeated and its best time kept, so a point's CPU is not one
//! scheduler hiccup.

use super::scene::{Errors, Group, Scene};
use crate::diag::Severity;
use crate::mbd::dynamics::Stats;
use crate::model::integrator_settings::Formulation;
use crate::session::run::{Engine, Estimate, Method, RunFailure, RunSpec, Simulation};
use crate::session::DimRequest;

/// A named method: an integrator with its formulation and parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Variant {
    /// The name on the command line and in the CSV.
    pub name: &'static str,
    /// The integrator.
    pub method: Method,
    /// The BDF formulation (None: not a BDF).
    pub formulation: Option<Formulation>,
    /// Runs with fixed steps (no error control).
    pub fixed: bool,
    /// Generalized-α's ρ∞ when not the default.
    pub rho_inf: Option<f64>,
    /// The order its theory gives on smooth problems.
    pub order: u32,
    /// ERROR bounds the whole run's error, not each step's.
    pub per_run: bool,
    /// dopri853 keeps to the Cartesian form where joint coordinates would do.
    pub cartesian: bool,
}

const fn variant(name: &'static str, method: Method, fixed: bool, order: u32) -> Variant {
    Variant {
        name,
        method,
        formulation: None,
        fixed,
        rho_inf: None,
        order,
        per_run: false,
        cartesian: false,
    }
}

/// Every method the benches know, error-controlled first.
pub const VARIANTS: &[Variant] = &[
    Variant {
        formulation: Some(Formulation::I3),
        ..variant("gstiff", Method::Gstiff, false, 6)
    },
    Variant {
        formulation: Some(Formulation::Si2),
        ..variant("gstiff-si2", Method::Gstiff, false, 6)
    },
    Variant {
        formulation: Some(Formulation::I3),
        ..variant("wstiff", Method::Wstiff, false, 6)
    },
    variant("hht", Method::Hht, false, 2),
    variant("galpha", Method::Galpha, false, 2),
    Variant {
        rho_inf: Some(1.0),
        ..variant("galpha-rho1", Method::Galpha, false, 2)
    },
    variant("newmark", Method::Newmark, false, 1),
    variant("dopri853", Method::Dopri853, false, 8),
    Variant {
        cartesian: true,
        ..variant("dopri853-cartesian", Method::Dopri853, false, 8)
    },
    Variant {
        formulation: Some(Formulation::I3),
        per_run: true,
        ..variant("gstiff-run", Method::Gstiff, false, 6)
    },
    Variant {
        formulation: Some(Formulation::Si2),
        per_run: true,
        ..variant("gstiff-si2-run", Method::Gstiff, false, 6)
    },
    Variant {
        per_run: true,
        ..variant("hht-run", Method::Hht, false, 2)
    },
    Variant {
        per_run: true,
        ..variant("galpha-run", Method::Galpha, false, 2)
    },
    Variant {
        per_run: true,
        ..variant("dopri853-run", Method::Dopri853, false, 8)
    },
    variant("hht-fixed", Method::Hht, true, 2),
    variant("newmark-fixed", Method::Newmark, true, 1),
    variant("dopri853-fixed", Method::Dopri853, true, 8),
    variant("galpha-fixed", Method::Galpha, true, 2),
    Variant {
        rho_inf: Some(1.0),
        ..variant("galpha-rho1-fixed", Method::Galpha, true, 2)
    },
];

/// The methods `bench wp` charts unless told otherwise.
pub const DEFAULT_WP: &[&str] = &[
    "gstiff",
    "gstiff-si2",
    "wstiff",
    "hht",
    "galpha",
    "dopri853",
    "dopri853-cartesian",
    "hht-fixed",
];

/// The method of a name.
pub fn variant_named(name: &str) -> Option<Variant> {
    VARIANTS.iter().copied().find(|v| v.name == name)
}

impl Variant {
    /// The formulation column of the CSV.
    pub fn formulation_name(&self) -> &'static str {
        match self.formulation {
            Some(Formulation::I3) => "i3",
            Some(Formulation::Si2) => "si2",
            Some(Formulation::Si1) => "si1",
            None => "-",
        }
    }
}

/// How a run's step is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Control {
    /// Error control at this ERROR.
    Tolerance(f64),
    /// Fixed steps of this size.
    FixedStep(f64),
}

impl Control {
    /// `tolerance` or `fixed-step`.
    pub fn kind(&self) -> &'static str {
        match self {
            Control::Tolerance(_) => "tolerance",
            Control::FixedStep(_) => "fixed-step",
        }
    }

    /// The tolerance or the step.
    pub fn value(&self) -> f64 {
        match *self {
            Control::Tolerance(v) | Control::FixedStep(v) => v,
        }
    }
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    /// It reached the end time.
    Ok,
    /// It stopped with this diagnostic (time, cause, element).
    Failed(String),
}

/// One measured run.
#[derive(Clone, Debug)]
pub struct Point {
    /// The scene's name.
    pub scene: String,
    /// The method.
    pub variant: Variant,
    /// Its tolerance or step.
    pub control: Control,
    /// The engine that evaluated the expressions.
    pub engine: Engine,
    /// The dimension the scene was built in.
    pub dim: u8,
    /// Equations the redundancy analysis found redundant (dropped unless kept).
    pub redundant: usize,
    /// Errors against the truth, per group.
    pub errors: Errors,
    /// Best CPU time of the run, s.
    pub cpu: f64,
    /// Best CPU time of the same run reading the position probes only, s, when the
    /// scene reads reactions too: what a user who asks for positions pays (reactions
    /// need consistent accelerations and multipliers at every output, positions do not).
    pub cpu_position: Option<f64>,
    /// The run's counters.
    pub stats: Stats,
    /// The largest scaled constraint residual at the output times.
    pub max_residual: f64,
    /// How it ended.
    pub status: Status,
    /// What the run itself said was wrong although it reached the end (the summary's
    /// warnings): a run that says so did not fail silently.
    pub warnings: Vec<String>,
    /// The run's global error estimate, when [`Options::estimate`] asked for one and it
    /// could be made.
    pub estimate: Option<Estimate>,
}

/// What else a run may change from the scene's own settings.
#[derive(Clone, Copy, Debug, Default)]
pub struct Options {
    /// The engine (default: the JIT).
    pub engine: Engine,
    /// Force 2D or 3D (default: the scene's `dim`, else 2D when planar).
    pub dim: Option<u8>,
    /// Seconds of runs after which a point stops repeating for a better time.
    pub repeat_budget: f64,
    /// ERROR of a fixed-step run (its local error monitor compares with it).
    pub error: Option<f64>,
    /// A BDF's highest order (None: 6).
    pub kmax: Option<u32>,
    /// Keep the redundant rows in the equations of motion.
    pub keep_redundant: bool,
    /// Estimate each error-controlled run's error from a second run at ERROR/10
    /// (`mbfx run --estimate-error`); its CPU is not the point's.
    pub estimate: bool,
}

/// Runs `scene` (dataset `text`) with `variant` under `control` and scores it.
pub fn measure(scene: &Scene, text: &str, variant: Variant, control: Control, o: Options) -> Point {
    let mut point = Point {
        scene: scene.name.clone(),
        variant,
        control,
        engine: o.engine,
        dim: 0,
        redundant: 0,
        errors: Errors::default(),
        cpu: f64::NAN,
        cpu_position: None,
        stats: Stats::default(),
        max_residual: f64::NAN,
        status: Status::Ok,
        warnings: Vec::new(),
        estimate: None,
    };
    // Repeat a short run (each from a freshly built model) and keep its best time.
    let best = least_cpu(o.repeat_budget, || {
        let mut sim = match build(scene, text, variant, control, &o, None) {
            Ok(s) => s,
            Err(why) => {
                point.status = Status::Failed(why);
                return None;
            }
        };
        point.redundant = sim.redundant;
        point.dim = sim.dynamics.sys.dim.axes() as u8;
        let mut rows: Vec<Vec<f64>> = Vec::new();
        let np = scene.probes.len();
        let (summary, failure) = sim.run(&mut |row: &[f64]| {
            rows.push(row[1..=np].to_vec());
            Ok(())
        });
        point.errors = scene.score(&rows, scene.stride());
        point.stats = summary.stats;
        point.max_residual = summary.max_residual;
        point.warnings = summary.warnings.clone();
        // The estimate's CPU, like the run's, is the best of the repeats.
        point.estimate = match (point.estimate, summary.estimate) {
            (Some(a), Some(b)) => Some(Estimate {
                cpu_seconds: a.cpu_seconds.min(b.cpu_seconds),
                ..b
            }),
            (_, b) => b,
        };
        point.status = match failure {
            None => Status::Ok,
            Some(e) => Status::Failed(e.to_string()),
        };
        Some((summary.cpu_seconds, point.status == Status::Ok))
    });
    let Some(best) = best else {
        return point;
    };
    point.cpu = best;
    if point.status == Status::Ok && scene.groups().len() > 1 {
        point.cpu_position = positions_only(scene, text, variant, control, &o);
    }
    point
}

/// The least CPU of up to five runs of `once`, fewer once they spent `budget` seconds
/// or one says to stop (`once` gives its CPU and whether to go on); None when one could
/// not run.
fn least_cpu(budget: f64, mut once: impl FnMut() -> Option<(f64, bool)>) -> Option<f64> {
    let (mut spent, mut best) = (0.0, f64::INFINITY);
    for _ in 0..5 {
        let (cpu, go_on) = once()?;
        spent += cpu;
        best = best.min(cpu);
        if !go_on || spent > budget {
            break;
        }
    }
    Some(best)
}

/// The best CPU time of runs reading the scene's position probes only (None when one
/// fails), repeated as [`measure`] repeats; no error estimate (its CPU is not the run's).
fn positions_only(
    scene: &Scene,
    text: &str,
    variant: Variant,
    control: Control,
    o: &Options,
) -> Option<f64> {
    let o = Options {
        estimate: false,
        ..*o
    };
    least_cpu(o.repeat_budget, || {
        let mut sim = build(scene, text, variant, control, &o, Some(Group::Position)).ok()?;
        let (summary, failure) = sim.run(&mut |_: &[f64]| Ok(()));
        failure.is_none().then_some((summary.cpu_seconds, true))
    })
}

fn build(
    scene: &Scene,
    text: &str,
    variant: Variant,
    control: Control,
    o: &Options,
    group: Option<Group>,
) -> Result<Simulation, String> {
    let step = scene.output_step * scene.stride() as f64;
    let mut spec = RunSpec::new(scene.end, step);
    spec.method = Some(variant.method);
    spec.formulation = variant.formulation;
    spec.rho_inf = variant.rho_inf;
    spec.hmax = scene.hmax;
    spec.hmin = scene.hmin;
    spec.kmax = o.kmax;
    spec.error_per_run = variant.per_run;
    spec.cartesian = variant.cartesian;
    spec.keep_redundant = o.keep_redundant;
    spec.estimate_error = o.estimate;
    spec.carry_error = o.estimate;
    spec.engine = o.engine;
    spec.dim = match o.dim.or(scene.dim) {
        Some(2) => DimRequest::Two,
        Some(_) => DimRequest::Three,
        None => DimRequest::Auto,
    };
    match control {
        Control::Tolerance(e) => spec.error = Some(e),
        Control::FixedStep(h) => {
            spec.fixed_step = Some(h);
            spec.error = o.error;
        }
    }
    let probes: Vec<(String, String)> = scene
        .probes
        .iter()
        .filter(|p| group.is_none_or(|g| p.group == g))
        .map(|p| (p.name.clone(), p.expr.clone()))
        .collect();
    Simulation::new(text, spec, &probes).map_err(|f| describe(&f))
}

/// A failure before the run, in one line.
pub fn describe(f: &RunFailure) -> String {
    match f {
        RunFailure::Diagnostics { probe, diagnostics } => {
            let first = diagnostics
                .iter()
                .find(|d| d.severity == Severity::Error)
                .or(diagnostics.first())
                .map_or("errors".to_string(), |d| d.message.clone());
            match probe {
                Some(p) => format!("probe {p}: {first}"),
                None => format!("dataset: {first}"),
            }
        }
        RunFailure::Analysis(a) => a.to_string(),
        RunFailure::Dynamics(d) => d.to_string(),
    }
}
