//! The summary a run ends with ([`Summary`]): its counters, residual, energy,
//! equilibria, linear analyses, error estimate, notes and warnings, and its text.

use super::Estimate;
use crate::mbd::dynamics::Stats;

/// The summary `mbfx run` prints.
#[derive(Clone, Debug)]
pub struct Summary {
    /// The integrator's name.
    pub integrator: &'static str,
    /// Counters of the whole run.
    pub stats: Stats,
    /// Seconds spent integrating (wall clock).
    pub cpu_seconds: f64,
    /// Largest scaled residual of the kept constraint rows at the output times.
    pub max_residual: f64,
    /// Kinetic plus gravitational energy at the start and the end, when the model has
    /// no other forces and no drives (None otherwise).
    pub energy: Option<(f64, f64)>,
    /// Notes for the user (settings not honoured, substitutions).
    pub notes: Vec<String>,
    /// Why the run was 2D or 3D, in words.
    pub dim: String,
    /// What the run's own monitors say went wrong although it reached its end (fixed
    /// steps whose local error estimate left ERROR far behind, constraint drift), after
    /// the physics the model leaves out ([`crate::model::report::not_modelled`], added by
    /// [`crate::session::request::run`]): a run that reports success on a wrong answer must at
    /// least say so.
    pub warnings: Vec<String>,
    /// The run reused the simulation of an earlier run on this thread (nothing was read,
    /// built or compiled: [`crate::session::prepared`]).
    pub reused: bool,
    /// The static equilibria it found, in order.
    pub equilibria: Vec<crate::mbd::statics::Report>,
    /// The linear analyses it ran, in order.
    pub linear: Vec<crate::session::linear::LinearReport>,
    /// The second run's global error estimate, when one was asked for and made
    /// (`--estimate-error=rerun`).
    pub estimate: Option<Estimate>,
    /// The run's ERROR (the largest of its segments'), what `stats.global_error` counts
    /// in.
    pub error: f64,
}

impl Summary {
    /// The end-of-run summary `mbfx run` prints (and Python's `Run.summary` holds).
    pub fn text(&self) -> String {
        let s = self;
        let st = &s.stats;
        let mut out = format!(
            "{}: {} steps ({} rejected), {} Newton iterations, {} Jacobian evaluations, {} factorizations, {} expression evaluations, {:.6} s CPU{}\nlargest constraint residual {:.3e}\n",
            s.integrator,
            st.steps,
            st.rejected,
            st.newton_iterations,
            st.jacobian_evaluations,
            st.factorizations,
            st.expression_evaluations,
            s.cpu_seconds,
            // Runs with contact switches say how many were located; others print as before.
            match st.events {
                0 => String::new(),
                n => format!(", {n} force switches located"),
            },
            s.max_residual
        );
        if st.interpolated > 0 {
            out += &format!(
                "{} rows interpolated inside steps (largest position-constraint residual there {:.3e}, {} projected)\n",
                st.interpolated, st.interpolation_residual, st.projected
            );
        }
        if let Some((e0, e1)) = s.energy {
            out += &format!(
                "energy (kinetic + gravity): {e0:.9e} at the start, {e1:.9e} at the end (change {:.3e})\n",
                e1 - e0
            );
        }
        out += &equilibria_text(&s.equilibria);
        for l in &s.linear {
            out += &l.text();
        }
        if let Some(k) = st.global_error {
            out += &format!(
                "estimated error {:.1e} ({}×ERROR, the largest along the run, at t = {})\n",
                k * s.error,
                three_digits(k),
                st.global_error_time
            );
        }
        if let Some(e) = &s.estimate {
            let g = three_digits;
            out += &format!(
                "error estimate: {}×ERROR (a second run at {}×ERROR, {:.6} s CPU, differs by {}×ERROR)\n",
                g(e.error),
                e.ratio,
                e.cpu_seconds,
                g(e.difference)
            );
        }
        for n in &s.notes {
            out += &format!("note: {n}\n");
        }
        for w in &s.warnings {
            out += &format!("warning: {w}\n");
        }
        out
    }
}

/// A multiple of ERROR with three digits whatever its size: an accurate run's estimate is
/// often far below one ERROR.
fn three_digits(x: f64) -> String {
    match x {
        x if x == 0.0 || (1e-2..1e5).contains(&x) => format!("{x:.3}"),
        x => format!("{x:.2e}"),
    }
}

/// The summary's lines about the equilibria: each in full when there are at most
/// three; else their count, iterations and largest imbalance, and the last in full.
pub(super) fn equilibria_text(reports: &[crate::mbd::statics::Report]) -> String {
    match reports {
        [] => String::new(),
        few if few.len() <= 3 => few.iter().map(|r| r.text()).collect(),
        [.., last] => {
            let iterations: usize = reports.iter().map(|r| r.iterations).sum();
            let worst = reports.iter().map(|r| r.imbalance).fold(0.0, f64::max);
            format!(
                "{} static equilibria (quasi-static): {iterations} Newton iterations, largest imbalance {worst:.3e}; the last:\n{}",
                reports.len(),
                last.text()
            )
        }
    }
}
