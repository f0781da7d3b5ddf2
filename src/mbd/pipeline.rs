//! The pipeline every analysis of a dataset starts with: build the system from a read
//! [`Model`] (2D when the scene is planar and its out-of-plane freedoms are held by
//! constraints, unless 3D is asked for), assemble positions and velocities at t = 0, and
//! run the redundancy analysis on the Jacobian at the assembled configuration. `session`
//! sequences it for every shell; tests and benches call it to reach the system.
//!
//! ```
//! use mbfx::mbd::pipeline::{analyze_dataset, DimRequest};
//!
//! let adm = "pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\nPART/2, MASS = 1, CM = 20\n\
//!            MARKER/20, PART = 2, QP = 1, 0, 0\nMARKER/21, PART = 2\n\
//!            JOINT/1, REVOLUTE, I = 21, J = 10\nEND\n";
//! let a = analyze_dataset(adm, DimRequest::Auto).unwrap();
//! assert_eq!(a.system.dim, mbfx::mbd::Dimension::Two);
//! assert_eq!((a.redundancy.dof(), a.redundancy.redundant.len()), (1, 0));
//! ```
//!
//! Order matters: assembly comes first because it needs no redundancy information (its
//! minimum-norm steps treat redundant rows like any other), and the rank of the Jacobian
//! is only meaningful at a configuration that satisfies the constraints. GCON and MOTION
//! functions are compiled with their exact IR derivative ([`CompiledExprs`]).

use super::assembly::{AssemblyError, AssemblyOptions, AssemblyReport};
use super::compiled::CompiledExprs;
use super::error::MbdError;
use super::planar::{self, Dim};
use super::redundancy::{self, Problem, Report};
use super::system::{Dimension, System};
use crate::diag::Diagnostic;
use crate::model::elements::Model;
use crate::vocab::math::DVec;
use mbfx_runtime::Spline;
use std::fmt;
use std::sync::Arc;

/// Which dimension the caller asks for (`mbfx check --dim`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DimRequest {
    /// 2D when the scene is planar, else 3D.
    #[default]
    Auto,
    /// 2D, or an error saying why the scene is not planar.
    Two,
    /// 3D whatever the scene.
    Three,
}

/// A model read, built, assembled and analysed.
pub struct Analysis {
    /// The assembled system; `system.dim` and `system.dim_reason` say which dimension
    /// was used and why.
    pub system: System,
    /// What assembly did.
    pub assembly: AssemblyReport,
    /// The redundancy analysis.
    pub redundancy: Report,
    /// The dataset's SPLINE data, fitted once (`Model::runtime_splines`): what AKISPL and
    /// CUBSPL read, in the GCON/MOTION functions and in expressions typed later.
    pub splines: Arc<[Spline]>,
    /// The compiler that holds the GCON and MOTION functions: a run records its forces
    /// and outputs in it too, for one module ([`CompiledExprs::unify`]).
    pub exprs: CompiledExprs,
}

/// Where the pipeline stopped, with what it had built so far.
pub enum Failure {
    /// The dataset has errors; these are the reader's diagnostics (errors and warnings).
    Read(Vec<Diagnostic>),
    /// The model could not be turned into a system.
    Build(MbdError),
    /// 2D was asked for and the scene is not planar (the reason, in words).
    NotPlanar(String),
    /// The constraints could not be satisfied, or a dropped equation is violated.
    /// `conflict` is the redundancy analysis at the configuration assembly stopped at,
    /// when it finds violated equations that follow from the others: the constraints
    /// contradict each other (conflicting, not redundant).
    Assembly {
        /// The system at the configuration assembly stopped at.
        system: Box<System>,
        /// Why assembly stopped.
        error: AssemblyError,
        /// Conflicting equations found at that configuration, when any.
        conflict: Option<redundancy::AnalysisError>,
    },
    /// The redundancy analysis found conflicting constraints (or a malformed system).
    Redundancy {
        /// The assembled system.
        system: Box<System>,
        /// What assembly did.
        assembly: AssemblyReport,
        /// What the analysis found.
        error: redundancy::AnalysisError,
    },
}

impl Failure {
    /// The system, when the pipeline got as far as building it.
    pub fn system(&self) -> Option<&System> {
        match self {
            Failure::Assembly { system, .. } | Failure::Redundancy { system, .. } => Some(system),
            _ => None,
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Read(d) => write!(
                f,
                "the dataset has {} errors",
                d.iter()
                    .filter(|d| d.severity == crate::diag::Severity::Error)
                    .count()
            ),
            Failure::Build(e) => write!(f, "the model cannot be built: {e}"),
            Failure::NotPlanar(why) => write!(f, "the model cannot be built in 2D: {why}"),
            Failure::Assembly {
                error,
                conflict: Some(redundancy::AnalysisError::Conflicting { report, conflicts }),
                ..
            } => {
                for c in conflicts {
                    writeln!(
                        f,
                        "conflicting, not redundant: {} of {} follows from the other constraints but is off by {:.3e} where assembly stopped",
                        c.label.equation.label(),
                        redundancy::element_title(&report.elements[c.label.element]),
                        c.residual.abs()
                    )?;
                }
                write!(f, "{error}")
            }
            Failure::Assembly { error, .. } => write!(f, "{error}"),
            Failure::Redundancy { error, .. } => write!(f, "{error}"),
        }
    }
}

impl fmt::Debug for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

/// Reads `text` as a dataset and analyses its model.
pub fn analyze_dataset(text: &str, dim: DimRequest) -> Result<Analysis, Failure> {
    let read = crate::model::read_model(text);
    if read.has_errors() {
        return Err(Failure::Read(read.diagnostics));
    }
    analyze_model(&read.model, dim)
}

/// Builds, assembles and analyses a model read without errors.
pub fn analyze_model(model: &Model, dim: DimRequest) -> Result<Analysis, Failure> {
    analyze_model_with(model, dim, false)
}

/// [`analyze_model`] with the model's expressions run by the interpreter when
/// `interpret` (else by the JIT where the CPU has one).
pub fn analyze_model_with(
    model: &Model,
    dim: DimRequest,
    interpret: bool,
) -> Result<Analysis, Failure> {
    let build_dim = match dim {
        DimRequest::Three => Dim::Three,
        DimRequest::Auto | DimRequest::Two => Dim::Auto,
    };
    let splines: Arc<[Spline]> = model
        .runtime_splines()
        .map_err(|why| Failure::Build(MbdError::Spline(why)))?
        .into();
    let exprs = if interpret {
        CompiledExprs::interpreted()
    } else {
        CompiledExprs::new()
    }
    .with_splines(splines.clone());
    let mut system = planar::build(model, build_dim, &exprs).map_err(Failure::Build)?;
    if dim == DimRequest::Two && system.dim != Dimension::Two {
        let why = system.dim_reason.trim_start_matches("3D: ").to_string();
        return Err(Failure::NotPlanar(why));
    }
    let assembly = match system.assemble(&AssemblyOptions::default()) {
        Ok(a) => a,
        Err(error) => {
            let conflict = match &error {
                // Velocities were not assembled: only positions can say which conflicts.
                AssemblyError::NotAssembled { .. } => redundancy_at(&system, false).err(),
                _ => None,
            };
            return Err(Failure::Assembly {
                system: Box::new(system),
                error,
                conflict,
            });
        }
    };
    match redundancy_of(&system) {
        Ok(redundancy) => Ok(Analysis {
            system,
            assembly,
            redundancy,
            splines,
            exprs,
        }),
        Err(error) => Err(Failure::Redundancy {
            system: Box::new(system),
            assembly,
            error,
        }),
    }
}

/// The redundancy analysis of `system` at its current configuration: the scaled
/// Jacobian, and the residuals scaled the same way so that violated redundant rows are
/// reported as conflicts.
pub fn redundancy_of(system: &System) -> Result<Report, redundancy::AnalysisError> {
    redundancy_at(system, true)
}

/// [`redundancy_of`], checking conflicts at velocities too when `velocities` (the system's
/// velocities are assembled).
fn redundancy_at(system: &System, velocities: bool) -> Result<Report, redundancy::AnalysisError> {
    let shape = |e: MbdError| redundancy::AnalysisError::Shape(e.to_string());
    let jacobian = system.jacobian(true).map_err(shape)?;
    let scale = |r: DVec| -> Vec<f64> {
        system
            .rows()
            .zip(r.iter())
            .map(
                |((e, q), &x)| match system.elements[e].eqs[q].translational {
                    true => x / system.length,
                    false => x,
                },
            )
            .collect()
    };
    let scaled = scale(system.residual().map_err(shape)?);
    let at_velocities = match velocities {
        true => Some(scale(system.velocity_residual().map_err(shape)?)),
        false => None,
    };
    let labels = system.labels();
    let elements = system.element_refs();
    let dim = system.dim.axes();
    let mut problem = Problem::new(&jacobian, &labels, &elements, system.moving_parts(), dim);
    problem.residuals = Some(&scaled);
    problem.velocity_residuals = at_velocities.as_deref();
    redundancy::analyze(&problem, &redundancy::Options::default())
}
