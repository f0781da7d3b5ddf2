//! The request's defaults and refusals, command files, probes, a simulation kept and
//! run again, failures that keep their rows, and interrupts.

use super::*;
use crate::mbd::dynamics::integrator::{Attempt, Integrator, OutputTimes, Settings};
use crate::mbd::dynamics::Dynamics;
use crate::mbd::dynamics::{simulate, DynError};
use crate::session::plan::Plan;
use crate::session::run::{Method, RunSpec, Simulation};
use crate::session::DimRequest;
use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// A 1 kg pendulum of length 1 swinging from the horizontal under gravity −y.
const PENDULUM: &str = "pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
    PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2, QP = 1, 0, 0\n\
    MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 10\nACCGRAV/JGRAV = -9.81\nEND\n";

/// A 1 kg slider on a rail along x, pulled by a SPRINGDAMPER to the origin.
const OSCILLATOR: &str = "oscillator\nPART/1, GROUND\nMARKER/10, PART = 1\n\
    MARKER/11, PART = 1, REULER = 90D, 90D, 0\n\
    PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = 1.2, 0, 0\n\
    MARKER/20, PART = 2\nMARKER/21, PART = 2, REULER = 90D, 90D, 0\n\
    JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
    SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 100, C = 4, LENGTH = 1\nEND\n";

/// A slider whose SFORCE/1 becomes the square root of a negative number at t = 0.5
/// (tests/models/failures/nan_in_force.adm).
const NAN_AT_HALF: &str = "nan\nPART/1, GROUND\nMARKER/101, PART = 1\n\
    MARKER/102, PART = 1, REULER = 90D, 90D, -90D\n\
    PART/2, MASS = 1, CM = 201, IP = 1, 1, 1\nMARKER/201, PART = 2\n\
    MARKER/202, PART = 2, REULER = 90D, 90D, -90D\n\
    JOINT/1, TRANSLATIONAL, I = 102, J = 202\nACCGRAV/KGRAV = -9.80665\n\
    SFORCE/1, TRANSLATIONAL, ACTIONONLY, I = 201, J = 102, \
    FUNCTION = IF(TIME - 0.5: 0, 0, SQRT(-1 - DX(201,101)**2))\nEND\n";

/// Runs `r`, collecting its rows.
fn rows_of(r: &RunRequest) -> (Vec<Vec<f64>>, Result<RunDone, Box<RunFailed>>) {
    let mut rows = Vec::new();
    let result = run(
        r,
        &mut |row: &[f64]| -> io::Result<()> {
            rows.push(row.to_vec());
            Ok(())
        },
        None,
    );
    (rows, result)
}

/// The failure of `r`, which must fail before running.
fn refusal(r: &RunRequest) -> Box<RunFailed> {
    let (rows, result) = rows_of(r);
    assert!(rows.is_empty());
    match result {
        Ok(_) => panic!("the request is refused"),
        Err(f) => f,
    }
}

#[test]
fn the_defaults_are_mbfx_runs() {
    let mut r = RunRequest::dataset("pendulum.adm", PENDULUM);
    r.end = Some(2.0);
    let (rows, result) = rows_of(&r);
    let done = result.expect("the pendulum runs");
    // A row every END/100, the last exactly at END; GSTIFF without an INTEGRATOR.
    assert_eq!(rows.len(), 101);
    for (k, row) in rows.iter().enumerate() {
        assert!(
            (row[0] - k as f64 * 0.02).abs() < 1e-12,
            "row {k}: {}",
            row[0]
        );
    }
    assert_eq!(rows[100][0], 2.0);
    assert_eq!(done.header, ["time"]);
    assert_eq!(done.summary.integrator, "gstiff");
    assert!(done.dim_reason.starts_with("2D"), "{}", done.dim_reason);
    // The dataset's INTEGRATOR when the request names none; the request's over it.
    let hht = PENDULUM.replace("END\n", "INTEGRATOR/HHT\nEND\n");
    r.input = Input::Dataset {
        name: "hht.adm".into(),
        text: hht,
    };
    assert_eq!(rows_of(&r).1.expect("runs").summary.integrator, "hht");
    r.method = Some(Method::Wstiff);
    assert_eq!(rows_of(&r).1.expect("runs").summary.integrator, "wstiff");
}

#[test]
fn a_command_file_gives_the_segments_and_its_note() {
    let dir = std::env::temp_dir().join(format!("mbfx-request-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch folder");
    std::fs::write(dir.join("pendulum.adm"), PENDULUM).expect("write");
    let acf = dir.join("swing.acf");
    std::fs::write(&acf, "pendulum\nswing_out\nsim/dyn, end=0.5, dtout=0.1\n").expect("write");
    let (rows, result) = rows_of(&RunRequest::file(&acf));
    let done = result.expect("the command file runs");
    let times: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(times.len(), 6, "{times:?}");
    assert!(done
        .summary
        .notes
        .iter()
        .any(|n| n.contains("swing_out.req")));
    // The request's end replaces the SIMULATE commands (the first DTOUT kept).
    let mut r = RunRequest::file(&acf);
    r.end = Some(0.3);
    let (rows, result) = rows_of(&r);
    assert!(result.is_ok());
    assert_eq!(rows.len(), 4);
    // Without SIMULATE, the command file needs an end time.
    std::fs::write(&acf, "pendulum\nswing_out\n").expect("write");
    let f = refusal(&RunRequest::file(&acf));
    assert_eq!(
        (f.code, f.cause.as_str()),
        (Code::MissingArgument, acf::NO_SIMULATION)
    );
    assert_eq!(f.source.name, acf.display().to_string());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn arguments_are_refused_with_the_command_lines_messages() {
    let base = || {
        let mut r = RunRequest::dataset("pendulum.adm", PENDULUM);
        r.end = Some(1.0);
        r
    };
    type Change = fn(&mut RunRequest);
    let cases: [(Change, &str); 11] = [
        (|r| r.end = Some(-1.0), "--end -1 must be a positive time"),
        (|r| r.end = Some(f64::NAN), "--end NaN must be a positive time"),
        (|r| r.hmax = Some(0.0), "--hmax 0 must be a positive number"),
        (|r| r.alpha = Some(0.5), "--alpha 0.5 must lie in [-1/3, 0]"),
        (|r| r.rho_inf = Some(2.0), "--rho-inf 2 must lie in [0, 1]"),
        (|r| r.kmax = Some(7), "--kmax 7 must be an order from 1 to 6"),
        (
            |r| (r.end, r.output_step) = (Some(1e9), Some(1e-9)),
            "--output-step 1e-9 over --end 1e9 makes 1.000e18 rows: times that close cannot be told apart (at most 4.504e15 rows); take a longer step",
        ),
        (
            |r| r.end = None,
            "--end is required to run a dataset (pendulum.adm); a command file (.acf) may give it instead, and --statics alone needs none",
        ),
        (
            |r| r.probes.push(parse_probe("DX(20)")),
            "--probe DX(20): expected NAME=EXPR, e.g. --probe x=DX(2,1)",
        ),
        (
            |r| {
                r.probes.push(parse_probe("x=DX(20)"));
                r.probes.push(parse_probe("x=DY(20)"));
            },
            "--probe x=DY(20): another --probe is named x; give each probe a name of its own",
        ),
        (
            |r| r.probes.push(parse_probe("time=TIME")),
            "--probe time=TIME: the time column is named time; give each probe a name of its own",
        ),
    ];
    for (change, message) in cases {
        let mut r = base();
        change(&mut r);
        let f = refusal(&r);
        assert_eq!((f.code, f.cause.as_str()), (Code::CommandLine, message));
        assert_eq!(f.source.name, COMMAND_LINE);
        assert!(f.header.is_none() && f.summary.is_none());
    }
    // A probe that does not compile points into its own text.
    let mut r = base();
    r.probes.push(("p".into(), "DX(20) + NOPE(1)".into()));
    let f = refusal(&r);
    assert_eq!(f.code, Code::UnknownFunction);
    assert_eq!(
        (f.source.name.as_str(), f.probe.as_deref()),
        ("--probe p", Some("p"))
    );
    assert_eq!(&f.source.text[f.diagnostics[0].span.clone()], "NOPE");
}

#[test]
fn probes_split_at_the_first_equals_sign() {
    assert_eq!(parse_probe(" x = DX(2)=1"), ("x".into(), " DX(2)=1".into()));
    assert_eq!(parse_probe(" =DX(2)"), (String::new(), " =DX(2)".into()));
    assert_eq!(parse_probe("DX(2)"), (String::new(), "DX(2)".into()));
}

/// The oscillator with its stiffness as design variable 1 in an SFORCE.
fn design_oscillator() -> String {
    OSCILLATOR.replace(
        "SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 100, C = 4, LENGTH = 1",
        "VARIABLE/1, FUNCTION = 100\n\
             SFORCE/1, TRANSLATION, I = 20, J = 10, FUNCTION = -VARVAL(1)*(DM(20, 10) - 1)",
    )
}

fn reused(result: &Result<RunDone, Box<RunFailed>>) -> bool {
    result.as_ref().expect("the run").summary.reused
}

#[test]
fn a_run_again_reuses_the_simulation_and_gives_its_bits() {
    prepared::forget();
    let mut r = RunRequest::dataset("osc", design_oscillator());
    r.end = Some(1.0);
    r.probes = vec![("x".into(), "DX(20, 10)".into())];
    let (first, done) = rows_of(&r);
    assert!(!reused(&done));
    let (again, done) = rows_of(&r);
    assert!(reused(&done));
    assert_eq!(first, again);
    // A design variable's number: the kept simulation, with the bits of the edited
    // dataset built afresh.
    r.set = vec!["VARIABLE/1.FUN=400".into()];
    let (stiff, done) = rows_of(&r);
    assert!(reused(&done));
    prepared::forget();
    let mut edited = r.clone();
    edited.set.clear();
    edited.input = Input::Dataset {
        name: "osc".into(),
        text: design_oscillator().replace("FUNCTION = 100", "FUNCTION = 400"),
    };
    let (fresh, done) = rows_of(&edited);
    assert!(!reused(&done));
    assert_eq!(stiff, fresh);
    assert_ne!(stiff, first);
    // Any other setting or dataset builds again, and leaves the kept one alone.
    prepared::forget();
    r.set = vec!["VARIABLE/1.FUNCTION=-2.5E2".into()];
    assert!(!reused(&rows_of(&r).1));
    r.set = vec!["PART/2.MASS=2".into()];
    assert!(!reused(&rows_of(&r).1));
    r.set = vec!["VARIABLE/1.FUNCTION=250".into()];
    let (softer, done) = rows_of(&r);
    assert!(reused(&done));
    assert_ne!(softer, first);
    r.set = vec!["VARIABLE/1.FUNCTION=2*PI".into()];
    assert!(!reused(&rows_of(&r).1));
    r.set.clear();
    r.end = Some(0.5);
    assert!(!reused(&rows_of(&r).1));
}

#[test]
fn a_failure_keeps_its_rows_and_names_time_element_and_code() {
    let mut r = RunRequest::dataset("nan.adm", NAN_AT_HALF);
    (r.end, r.output_step, r.fixed_step) = (Some(1.0), Some(0.01), Some(1e-3));
    r.dim = DimRequest::Three;
    r.probes.push(("x".into(), "DX(201,101)".into()));
    let (rows, result) = rows_of(&r);
    let Err(f) = result else {
        panic!("the force becomes NaN")
    };
    assert_eq!(f.code, Code::NonFiniteForce);
    let t = f.time.unwrap_or_else(|| panic!("a time: {f:?}"));
    assert!((0.5..=0.51).contains(&t), "failed at {t}");
    assert!(
        f.element
            .as_deref()
            .is_some_and(|e| e.starts_with("SFORCE/1")),
        "{:?}",
        f.element
    );
    assert!(f.cause.contains(&format!("at time {t}")), "{}", f.cause);
    let span = f.diagnostics[0].span.clone();
    assert!(f.source.text[span].starts_with("SFORCE/1"));
    assert_eq!(f.source.name, "nan.adm");
    // Every row before the failure was handed out, on the grid, and the summary kept.
    assert_eq!(
        f.header.as_deref(),
        Some(&["time".to_string(), "x".into()][..])
    );
    assert_eq!(rows.len(), 51);
    assert!(rows
        .iter()
        .enumerate()
        .all(|(k, r)| (r[0] - k as f64 * 0.01).abs() < 1e-12));
    let summary = f.summary.as_ref().expect("a summary");
    assert!(summary.stats.steps >= 500);
    assert!(f.to_string().starts_with("[E0803] SFORCE/1: "), "{f}");
}

/// Delegates to `inner`, setting `flag` at its `at`-th accepted step.
struct Tripwire<'a> {
    inner: Box<dyn Integrator>,
    flag: &'a AtomicBool,
    at: usize,
    accepted: usize,
}

impl Integrator for Tripwire<'_> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }
    fn error_order(&self) -> f64 {
        self.inner.error_order()
    }
    fn order(&self) -> Option<u32> {
        self.inner.order()
    }
    fn max_growth(&self) -> f64 {
        self.inner.max_growth()
    }
    fn monitored_error(&self, err: f64) -> f64 {
        self.inner.monitored_error(err)
    }
    fn formulation(&self) -> Option<String> {
        self.inner.formulation()
    }
    fn step_factor(&self) -> Option<f64> {
        self.inner.step_factor()
    }
    fn first_step(&self, d: &Dynamics, hinit: f64, s: &Settings) -> f64 {
        self.inner.first_step(d, hinit, s)
    }
    fn restart(&mut self, d: &mut Dynamics) {
        self.inner.restart(d)
    }
    fn start(&mut self, d: &mut Dynamics) -> Result<(), DynError> {
        self.inner.start(d)
    }
    fn attempt(&mut self, d: &mut Dynamics, h: f64, s: &Settings) -> Result<Attempt, DynError> {
        self.inner.attempt(d, h, s)
    }
    fn accept(&mut self, d: &mut Dynamics) {
        self.inner.accept(d);
        self.accepted += 1;
        if self.accepted == self.at {
            self.flag.store(true, Ordering::Relaxed);
        }
    }
    fn reject(&mut self, d: &mut Dynamics) {
        self.inner.reject(d)
    }
}

#[test]
fn the_interrupt_is_read_before_every_step() {
    // One output time at the end: a check at output times only would run to it.
    let spec = RunSpec::new(10.0, 10.0);
    let Ok(mut sim) = Simulation::new(OSCILLATOR, spec.clone(), &[]) else {
        panic!("the oscillator builds")
    };
    sim.dynamics
        .solve_accelerations()
        .expect("consistent at t = 0");
    let plan = Plan::new(None, &spec, 10.0);
    let flag = AtomicBool::new(false);
    let mut tripwire = Tripwire {
        inner: plan.integrator().0,
        flag: &flag,
        at: 7,
        accepted: 0,
    };
    let d = &mut sim.dynamics;
    let stopped = simulate(
        d,
        &mut tripwire,
        &plan.settings,
        &OutputTimes::new(0.0, 10.0, 10.0),
        &mut |_, _| Ok(()),
        Some(&|| flag.load(Ordering::Relaxed)),
    );
    assert_eq!(stopped, Err(DynError::Interrupted { time: d.sys.time }));
    assert_eq!(d.stats.steps, 7);
    assert!(d.sys.time > 0.0 && d.sys.time < 10.0);
}

#[test]
fn an_interrupt_from_another_thread_stops_a_run_promptly() {
    // Ten million fixed steps and no output between the first row and the last.
    let mut r = RunRequest::dataset("oscillator.adm", OSCILLATOR);
    (r.end, r.output_step, r.fixed_step) = (Some(100.0), Some(100.0), Some(1e-5));
    r.method = Some(Method::Hht);
    let (flag, started) = (AtomicBool::new(false), AtomicBool::new(false));
    let set_at: Mutex<Option<Instant>> = Mutex::new(None);
    let mut rows = Vec::new();
    let (result, returned) = std::thread::scope(|s| {
        s.spawn(|| {
            while !started.load(Ordering::Acquire) {
                std::thread::sleep(Duration::from_millis(1));
            }
            std::thread::sleep(Duration::from_millis(50));
            flag.store(true, Ordering::Relaxed);
            *set_at.lock().expect("lock") = Some(Instant::now());
        });
        let mut sink = |row: &[f64]| -> io::Result<()> {
            rows.push(row.to_vec());
            started.store(true, Ordering::Release);
            Ok(())
        };
        let result = run(&r, &mut sink, Some(&|| flag.load(Ordering::Relaxed)));
        (result, Instant::now())
    });
    let Err(f) = result else {
        panic!("the run is interrupted")
    };
    let set_at = set_at.lock().expect("lock").expect("the flag was set");
    let took = returned.saturating_duration_since(set_at);
    assert!(
        took < Duration::from_millis(100),
        "stopped {took:?} after the flag"
    );
    assert_eq!(f.code, Code::Interrupted);
    let stopped = f.error.as_ref().and_then(Stopped::dynamics);
    assert!(matches!(stopped, Some(DynError::Interrupted { .. })));
    let t = f.time.expect("a time");
    assert!(t > 0.0 && t < 100.0, "stopped at {t}");
    // The row at t = 0 was delivered, the summary counts the steps taken.
    assert_eq!(rows.len(), 1);
    let steps = f.summary.as_ref().expect("a summary").stats.steps;
    assert!(
        (t / 1e-5 - steps as f64).abs() < 2.0,
        "{steps} steps to {t}"
    );
}

#[test]
fn each_column_carries_its_unit_in_the_dataset_units() {
    // The oscillator with UNITS in millimetres and kilonewtons, a REQUEST of its
    // displacement and force, and probes of a position, a force, a velocity, a number
    // alone (free: no unit the checker can tell) and a ratio of lengths (dimensionless).
    let text = OSCILLATOR.replace(
        "PART/1, GROUND",
        "UNITS/FORCE = KNEWTON, MASS = KILOGRAM, LENGTH = MILLIMETER, TIME = SECOND\n\
         PART/1, GROUND",
    );
    let text = text.replace(
        "END\n",
        "REQUEST/1, DISPLACEMENT, I = 20, J = 10\nREQUEST/2, F2 = SPDP(1, 0, 2, 0)\nEND\n",
    );
    let mut r = RunRequest::dataset("oscillator.adm", &text);
    r.end = Some(0.01);
    for p in [
        "x=DX(20, 10)",
        "f=SPDP(1, 0, 2, 0)",
        "v=VX(20, 10)",
        "c=2.5",
    ] {
        r.probes.push(parse_probe(p));
    }
    r.probes.push(parse_probe("r=DX(20, 10)/DM(20, 10)"));
    let done = rows_of(&r).1.expect("the oscillator runs");
    assert_eq!(done.units.len(), done.header.len());
    let unit = |name: &str| {
        let k = done.header.iter().position(|h| h == name).expect(name);
        done.units[k].as_str()
    };
    assert_eq!(unit("time"), "second");
    assert_eq!(unit("x"), "millimeter");
    assert_eq!(unit("f"), "knewton");
    assert_eq!(unit("v"), "millimeter/second");
    assert_eq!(unit("c"), "");
    assert_eq!(unit("r"), "1");
    // A DISPLACEMENT request: magnitude and translations in length, then the angles.
    assert_eq!(unit("REQ1.F2"), "millimeter");
    assert_eq!(unit("REQ1.F6"), "radian");
    assert_eq!(unit("REQ2.F2"), "knewton");
}
