//! `mbfx bench wp|stability|scaling|generate`: the speed-against-accuracy benches of
//! [`crate::bench`] on the scenes of `examples/scenes/` (or `--scenes DIR`), writing
//! CSV, SVG charts and a markdown summary into `--out DIR`, with progress on stderr.

use super::output::{Output, Stop};
use crate::bench::point::{variant_named, Options, Point, Status, Variant, DEFAULT_WP};
use crate::bench::scene::{load_dir, Scene};
use crate::bench::wp::{parse_errors, run_scene, Grid, Row};
use crate::bench::{generate, output};
use crate::diag::{Code, Diagnostic, SourceFile};
use indicatif::ProgressBar;
use std::path::{Path, PathBuf};

#[derive(clap::Subcommand)]
pub enum BenchCommand {
    /// Work-precision charts: every scene × method × tolerance, scored against the truth.
    Wp(WpArgs),
    /// The stability suite: scenes where methods fail, each cell accurate, failed
    /// (named) or wrong (silently); markdown and an SVG heat map.
    Stability(StabilityArgs),
    /// CPU per step and per simulated second against N (chain, N-four-bar; 2D and 3D).
    Scaling(ScalingArgs),
    /// Everything, in one directory: wp (with the 3D and interpreter variations),
    /// stability, scaling and orders.
    All(AllArgs),
    /// Orders of convergence of every method on the A01 scene.
    Orders(OrdersArgs),
    /// Print a generated dataset (`chain`, `tree` or `four_bar`, size N) on stdout.
    Generate {
        /// `chain`, `tree` or `four_bar`.
        kind: String,
        /// The size.
        n: usize,
    },
}

#[derive(clap::Args)]
pub struct WpArgs {
    /// Scenes to run (names of truth files in --scenes) [default: all].
    scenes: Vec<String>,
    /// Where the scenes' truth files are.
    #[arg(long = "scenes", value_name = "DIR", default_value = DEFAULT_SCENES)]
    dir: PathBuf,
    /// Methods, comma-separated [default: gstiff,gstiff-si2,wstiff,hht,galpha,dopri853,
    /// dopri853-cartesian,hht-fixed].
    #[arg(long, value_delimiter = ',')]
    integrators: Vec<String>,
    /// Tolerances: A..B (the Test Set ladder 10^-(2+m/2) between them) or a list.
    #[arg(long, default_value = "1e-2..1e-10")]
    errors: String,
    /// Where the CSV, SVG and summary go.
    #[arg(long, default_value = "target/bench-wp")]
    out: PathBuf,
    /// A directory of peers' points (benches/peers/run.sh), drawn on the same charts.
    #[arg(long, value_name = "DIR")]
    peers: Option<PathBuf>,
    /// Seconds one run may take before a method's tighter settings are skipped.
    #[arg(long, default_value = "2")]
    budget: f64,
    /// Halvings of the output step a fixed-step method tries.
    #[arg(long, default_value = "10")]
    halvings: u32,
    /// Also run the first method in 3D on planar scenes, with the redundant rows kept
    /// where there are some, and with the interpreter (curves `NAME@3d`,
    /// `NAME@keep-redundant`, `NAME@interp`).
    #[arg(long)]
    variations: bool,
    /// Estimate each error-controlled run's error from a second run at ERROR/10 (`mbfx
    /// run --estimate-error`): warnings.md then tells the warnings apart with and
    /// without it, and what it costs.
    #[arg(long = "estimate-error")]
    estimate_error: bool,
}

#[derive(clap::Args)]
pub struct AllArgs {
    /// Where the scenes' truth files are.
    #[arg(long = "scenes", value_name = "DIR", default_value = DEFAULT_SCENES)]
    dir: PathBuf,
    /// Where everything goes.
    #[arg(long, default_value = "target/bench-wp")]
    out: PathBuf,
    /// A directory of peers' points (benches/peers/run.sh), drawn on the same charts.
    #[arg(long, value_name = "DIR")]
    peers: Option<PathBuf>,
}

#[derive(clap::Args)]
pub struct StabilityArgs {
    /// Where the scenes' truth files are.
    #[arg(long = "scenes", value_name = "DIR", default_value = DEFAULT_SCENES)]
    dir: PathBuf,
    /// Where stability.md and stability.svg go.
    #[arg(long, default_value = "target/bench-wp")]
    out: PathBuf,
    /// A directory with the peers' cells (`stability.csv`, benches/peers/run_stability.sh),
    /// shown beside mbfx's.
    #[arg(long, value_name = "DIR")]
    peers: Option<PathBuf>,
    /// Print the cases as CSV (case, scene, tolerance, fixed step, whether the motion
    /// must stop) on stdout and run nothing: the peers' script reads the suite from it.
    #[arg(long)]
    list: bool,
    /// Give each error-controlled run the global error estimate (`mbfx run
    /// --estimate-error`): its warning then names a wrong answer too.
    #[arg(long = "estimate-error")]
    estimate_error: bool,
}

#[derive(clap::Args)]
pub struct OrdersArgs {
    /// Where the scenes' truth files are.
    #[arg(long = "scenes", value_name = "DIR", default_value = DEFAULT_SCENES)]
    dir: PathBuf,
    /// Where orders.md goes.
    #[arg(long, default_value = "target/bench-wp")]
    out: PathBuf,
}

#[derive(clap::Args)]
pub struct ScalingArgs {
    /// Where scaling.csv, scaling.svg and scaling.md go.
    #[arg(long, default_value = "target/bench-wp")]
    out: PathBuf,
    /// The methods, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "gstiff,dopri853")]
    integrator: Vec<String>,
    /// Their tolerance.
    #[arg(long, default_value = "1e-6")]
    error: f64,
    /// Simulated time of each run, s.
    #[arg(long, default_value = "1")]
    end: f64,
}

fn fail(msg: String, o: &mut Output) -> Result<i32, Stop> {
    let d = Diagnostic::error(Code::CommandLine, 0..0, msg);
    o.diagnostics(&[d], &SourceFile::textless("command line"))?;
    Err(Stop::Failed)
}

pub fn run(c: &BenchCommand, o: &mut Output) -> Result<i32, Stop> {
    match c {
        BenchCommand::Wp(a) => wp(a, o),
        BenchCommand::Stability(a) => stability(a, o),
        BenchCommand::Scaling(a) => scaling(a, o),
        BenchCommand::Orders(a) => orders(a, o),
        BenchCommand::All(a) => all(a, o),
        BenchCommand::Generate { kind, n } => match generate::generate(kind, *n) {
            Some(text) => {
                o.out().write_all(text.as_bytes()).map_err(Stop::Io)?;
                Ok(0)
            }
            None => fail(
                format!("cannot generate `{kind}` of size {n} (chain, tree or four_bar, N ≥ 1)"),
                o,
            ),
        },
    }
}

/// Where `--scenes` points: `dir` itself, except that the default `examples/scenes`,
/// absent from the working folder, is the repository's (the one this binary was built
/// in), so `mbfx bench` runs from any folder.
fn scenes_dir(dir: &Path) -> std::borrow::Cow<'_, Path> {
    let built_in = Path::new(env!("CARGO_MANIFEST_DIR")).join(DEFAULT_SCENES);
    match dir == Path::new(DEFAULT_SCENES) && !dir.is_dir() && built_in.is_dir() {
        true => built_in.into(),
        false => dir.into(),
    }
}

/// `--scenes`' default, relative to the working folder.
const DEFAULT_SCENES: &str = "examples/scenes";

/// Every scene of `--scenes` (see [`scenes_dir`]).
fn load_scenes(dir: &Path) -> Result<Vec<Scene>, String> {
    load_dir(&scenes_dir(dir))
}

/// The scenes named (all when none), or why not.
pub fn select(dir: &Path, names: &[String]) -> Result<Vec<Scene>, String> {
    let all = load_scenes(dir)?;
    if names.is_empty() {
        return Ok(all);
    }
    names
        .iter()
        .map(|n| {
            all.iter().find(|s| &s.name == n).cloned().ok_or_else(|| {
                let known: Vec<&str> = all.iter().map(|s| s.name.as_str()).collect();
                format!(
                    "no scene `{n}` in {} (there are: {})",
                    dir.display(),
                    known.join(", ")
                )
            })
        })
        .collect()
}

/// The methods named (the default set when none), or why not.
pub fn variants(names: &[String], default: &[&str]) -> Result<Vec<Variant>, String> {
    let names: Vec<&str> = if names.is_empty() {
        default.to_vec()
    } else {
        names.iter().map(|s| s.as_str()).collect()
    };
    names
        .iter()
        .map(|n| {
            variant_named(n).ok_or_else(|| {
                let known: Vec<&str> = crate::bench::point::VARIANTS
                    .iter()
                    .map(|v| v.name)
                    .collect();
                format!("no method `{n}` (there are: {})", known.join(", "))
            })
        })
        .collect()
}

/// A bar over points on stderr when it is a terminal, else one line per scene.
pub struct Ticker {
    bar: Option<ProgressBar>,
}

impl Ticker {
    pub fn new(total: u64) -> Ticker {
        let template = "{bar:30} {pos}/{len} {msg} [{elapsed_precise}]";
        Ticker {
            bar: super::progress::terminal_bar(total, template),
        }
    }

    /// One more run done, described by `message` (built only when there is a bar).
    pub fn tick(&self, message: impl FnOnce() -> String) {
        if let Some(b) = &self.bar {
            b.inc(1);
            b.set_message(message());
        }
    }

    pub fn point(&self, p: &Point) {
        self.tick(|| {
            let e = p.errors.worst().map_or("—".into(), |e| format!("{e:.1e}"));
            format!(
                "{} {} {:.0e}: error {e}, {:.2e} s",
                p.scene,
                p.variant.name,
                p.control.value(),
                p.cpu
            )
        });
    }

    pub fn line(&self, o: &mut Output, text: &str) -> Result<(), Stop> {
        match &self.bar {
            Some(b) => b.println(text),
            None => writeln!(o.err(), "{text}").map_err(Stop::Io)?,
        }
        Ok(())
    }

    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

fn wp(a: &WpArgs, o: &mut Output) -> Result<i32, Stop> {
    let setup = (|| -> Result<_, String> {
        let scenes = select(&a.dir, &a.scenes)?;
        let variants = variants(&a.integrators, DEFAULT_WP)?;
        let errors = parse_errors(&a.errors)?;
        if !(a.budget.is_finite() && a.budget > 0.0) {
            return Err(format!(
                "--budget {} must be a positive number of seconds",
                a.budget
            ));
        }
        std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
        Ok((scenes, variants, errors))
    })();
    let (scenes, variants, errors) = match setup {
        Ok(s) => s,
        Err(e) => return fail(e, o),
    };
    let grid = Grid {
        variants: variants.clone(),
        errors: errors.clone(),
        halvings: a.halvings,
        budget: a.budget,
        options: Options {
            repeat_budget: 0.05,
            estimate: a.estimate_error,
            ..Options::default()
        },
    };
    let per_scene = variants
        .iter()
        .map(|v| {
            if v.fixed {
                a.halvings as usize + 1
            } else {
                errors.len()
            }
        })
        .sum::<usize>();
    let ticker = Ticker::new((per_scene * scenes.len()) as u64);
    let clock = std::time::Instant::now();
    let mut summary = String::from("# Work-precision summary\n\nEach table: the cheapest run whose error is at most the level (CPU of the run, best of up to 5 repeats).\n");
    let mut failed = false;
    // mbfx's runs of every scene, for the accuracy warnings' report.
    let mut all_rows: Vec<Row> = Vec::new();
    for scene in &scenes {
        let mut rows: Vec<Row> = Vec::new();
        let mut each = |p: &Point| ticker.point(p);
        let points = match run_scene(scene, &grid, &mut each) {
            Ok(p) => p,
            Err(e) => {
                ticker.line(o, &format!("{}: {e}", scene.name))?;
                failed = true;
                continue;
            }
        };
        rows.extend(points.iter().map(|p| Row::of(p, None)));
        if a.variations {
            let mut one = grid.clone();
            one.variants.truncate(1);
            let first = points.first();
            let mut variations: Vec<(Grid, &str)> = Vec::new();
            if first.is_some_and(|p| p.dim == 2) {
                let mut g = one.clone();
                g.options.dim = Some(3);
                variations.push((g, "3d"));
            }
            if first.is_some_and(|p| p.redundant > 0) {
                let mut g = one.clone();
                g.options.keep_redundant = true;
                variations.push((g, "keep-redundant"));
            }
            one.options.engine = crate::session::run::Engine::Interp;
            variations.push((one, "interp"));
            // Each variation is one more curve of the grid, climbing its ladder by the
            // same rules.
            for (g, tag) in &variations {
                match run_scene(scene, g, &mut |p| ticker.point(p)) {
                    Ok(varied) => rows.extend(varied.iter().map(|p| Row::of(p, Some(tag)))),
                    Err(e) => return fail(e, o),
                }
            }
        }
        let peers = match output::peer_rows(a.peers.as_deref(), scene) {
            Ok(p) => p,
            Err(e) => return fail(e, o),
        };
        match output::write_scene(&a.out, scene, &rows, &peers) {
            Ok(s) => summary += &s,
            Err(e) => return fail(e, o),
        }
        all_rows.extend(rows.iter().cloned());
        let bad = points.iter().filter(|p| p.status != Status::Ok).count();
        ticker.line(
            o,
            &format!(
                "{}: {} runs ({} stopped with a diagnostic), {:.0} s so far",
                scene.name,
                rows.len(),
                bad,
                clock.elapsed().as_secs_f64()
            ),
        )?;
    }
    ticker.finish();
    summary += &format!(
        "\nWhole run: {:.1} s wall clock.\n",
        clock.elapsed().as_secs_f64()
    );
    let alarms = crate::bench::alarms::report(&all_rows);
    for (name, text) in [("summary.md", summary), ("warnings.md", alarms)] {
        let path = a.out.join(name);
        if let Err(e) = std::fs::write(&path, text) {
            return fail(format!("{}: {e}", path.display()), o);
        }
    }
    writeln!(o.err(), "wrote {}", a.out.display()).map_err(Stop::Io)?;
    Ok(if failed { 1 } else { 0 })
}

fn stability(a: &StabilityArgs, o: &mut Output) -> Result<i32, Stop> {
    use crate::bench::peer_cells;
    use crate::bench::stability::{details, heat_map, markdown, run_case, Cell, Verdict, CASES};
    let scenes = match load_scenes(&a.dir) {
        Ok(s) => s,
        Err(e) => return fail(e, o),
    };
    let stops: Vec<bool> = CASES
        .iter()
        .map(|c| {
            scenes
                .iter()
                .any(|s| s.name == c.scene && crate::bench::stability::must_stop(s))
        })
        .collect();
    if a.list {
        let mut text = String::from("case,scene,tolerance,step,must_stop\n");
        for (c, stop) in CASES.iter().zip(&stops) {
            let step = c.step.map_or(String::new(), |h| format!("{h:e}"));
            text += &format!("{},{},{:e},{step},{stop}\n", c.id, c.scene, c.tolerance);
        }
        o.out().write_all(text.as_bytes()).map_err(Stop::Io)?;
        return Ok(0);
    }
    let peers = match &a.peers {
        Some(d) => match peer_cells::read(&d.join("stability.csv"), CASES, &stops) {
            Ok(p) => p,
            Err(e) => return fail(e, o),
        },
        None => Vec::new(),
    };
    if let Err(e) = std::fs::create_dir_all(&a.out) {
        return fail(format!("{}: {e}", a.out.display()), o);
    }
    let total: usize = CASES.iter().map(|c| c.methods.len()).sum();
    let ticker = Ticker::new(total as u64);
    let clock = std::time::Instant::now();
    let mut cells: Vec<Cell> = Vec::new();
    let mut missing = Vec::new();
    for (i, case) in CASES.iter().enumerate() {
        let Some(scene) = scenes.iter().find(|s| s.name == case.scene) else {
            missing.push(case.scene);
            continue;
        };
        let mut each = |c: &Cell| ticker.point(&c.point);
        match run_case(i, case, scene, a.estimate_error, &mut each) {
            Ok(c) => cells.extend(c),
            Err(e) => return fail(format!("{}: {e}", case.scene), o),
        }
    }
    ticker.finish();
    let mut md = String::from("# Stability suite\n\nEach cell: **accurate** (error within 10× the tolerance), **failed, named** (stopped with a diagnostic naming time, cause and element, or finished with a warning from its own monitors) or **wrong, silently** (reported success with a larger error). The error is in brackets.\n\n");
    md += &markdown(CASES, &cells);
    md += "\nWhat the named failures said:\n\n";
    md += &details(CASES, &cells);
    let silent: Vec<&Cell> = cells
        .iter()
        .filter(|c| c.verdict == Verdict::WrongSilently)
        .collect();
    md += &format!(
        "\n{} cells, {} wrong silently ({} of them error-controlled); {:.1} s.\n",
        cells.len(),
        silent.len(),
        silent.iter().filter(|c| !c.point.variant.fixed).count(),
        clock.elapsed().as_secs_f64()
    );
    if !peers.is_empty() {
        md += "\n## The peers on the same cases\n\nExudyn and MuJoCo (benches/peers/), judged by the same rule; **crashed**: the process died; **unsupported**: the peer cannot model the scene. A cell: verdict (error), setting.\n\n";
        md += &peer_cells::markdown(CASES, &peers);
        md += "\nWhat the peers' failed, crashed, unsupported or warned cells said:\n\n";
        md += &peer_cells::details(CASES, &peers);
        let count = |v: Verdict| peers.iter().filter(|c| c.verdict == v).count();
        md += &format!(
            "\n{} peer cells: {} accurate, {} failed named, {} wrong silently, {} crashed, {} unsupported.\n",
            peers.len(),
            count(Verdict::Accurate),
            count(Verdict::FailedNamed),
            count(Verdict::WrongSilently),
            count(Verdict::Crashed),
            count(Verdict::Unsupported)
        );
    }
    if !missing.is_empty() {
        md += &format!(
            "\nScenes not found in {}: {}\n",
            a.dir.display(),
            missing.join(", ")
        );
    }
    let path = a.out.join("stability.md");
    if let Err(e) = std::fs::write(&path, &md) {
        return fail(format!("{}: {e}", path.display()), o);
    }
    if let Err(e) = heat_map(&a.out.join("stability.svg"), CASES, &cells, &peers) {
        return fail(e, o);
    }
    writeln!(
        o.err(),
        "wrote {} and stability.svg: {} cells, {} wrong silently",
        path.display(),
        cells.len(),
        silent.len()
    )
    .map_err(Stop::Io)?;
    Ok(0)
}

fn scaling(a: &ScalingArgs, o: &mut Output) -> Result<i32, Stop> {
    use crate::bench::point::Control;
    use crate::bench::scaling::{sample, sizes_in, write, SIZES};
    let methods = match variants(&a.integrator, &[]) {
        Ok(v) if !v.is_empty() => v,
        Ok(_) => return fail("no method given".into(), o),
        Err(e) => return fail(e, o),
    };
    // One control for all: a fixed step when the first method is a fixed-step one.
    let v = methods[0];
    if let Err(e) = std::fs::create_dir_all(&a.out) {
        return fail(format!("{}: {e}", a.out.display()), o);
    }
    let control = if v.fixed {
        Control::FixedStep(a.error)
    } else {
        Control::Tolerance(a.error)
    };
    let total: usize = SIZES
        .iter()
        .map(|(_, n)| sizes_in(n, 2).count() + sizes_in(n, 3).count())
        .sum();
    let ticker = Ticker::new((total * methods.len()) as u64);
    let mut samples = Vec::new();
    for v in &methods {
        for (kind, sizes) in SIZES {
            for dim in [2u8, 3] {
                for n in sizes_in(sizes, dim) {
                    let s = sample(kind, n, dim, a.end, *v, control);
                    let name = v.name;
                    ticker.tick(|| format!("{name} {kind} {dim}D N = {n}: {:.2e} s", s.cpu));
                    samples.push(s);
                }
            }
        }
    }
    ticker.finish();
    match write(&a.out, &samples, control) {
        Ok(md) => {
            let path = a.out.join("scaling.md");
            if let Err(e) = std::fs::write(&path, md) {
                return fail(format!("{}: {e}", path.display()), o);
            }
            writeln!(o.err(), "wrote {}", path.display()).map_err(Stop::Io)?;
            Ok(0)
        }
        Err(e) => fail(e, o),
    }
}

fn orders(a: &OrdersArgs, o: &mut Output) -> Result<i32, Stop> {
    use crate::bench::orders::{markdown, measure_orders, run_count};
    let scene = match select(&a.dir, &["a01_pendulum".to_string()]) {
        Ok(mut s) => s.remove(0),
        Err(e) => return fail(e, o),
    };
    if let Err(e) = std::fs::create_dir_all(&a.out) {
        return fail(format!("{}: {e}", a.out.display()), o);
    }
    let ticker = Ticker::new(run_count() as u64);
    let result = measure_orders(&scene, &mut |p| ticker.point(p));
    ticker.finish();
    let md = match result {
        Ok(orders) => markdown(&scene, &orders),
        Err(e) => return fail(e, o),
    };
    let path = a.out.join("orders.md");
    if let Err(e) = std::fs::write(&path, &md) {
        return fail(format!("{}: {e}", path.display()), o);
    }
    write!(o.err(), "{md}").map_err(Stop::Io)?;
    Ok(0)
}

fn all(a: &AllArgs, o: &mut Output) -> Result<i32, Stop> {
    let clock = std::time::Instant::now();
    let wp_args = WpArgs {
        scenes: Vec::new(),
        dir: a.dir.clone(),
        integrators: Vec::new(),
        errors: "1e-2..1e-10".into(),
        out: a.out.clone(),
        peers: a.peers.clone(),
        budget: 2.0,
        halvings: 10,
        variations: true,
        estimate_error: true,
    };
    let mut code = wp(&wp_args, o)?;
    // the peers' stability cells are in the same directory as their points, when run
    let st = StabilityArgs {
        dir: a.dir.clone(),
        out: a.out.clone(),
        peers: a.peers.clone().filter(|d| d.join("stability.csv").exists()),
        list: false,
        estimate_error: true,
    };
    code = code.max(stability(&st, o)?);
    let sc = ScalingArgs {
        out: a.out.clone(),
        integrator: vec!["gstiff".into(), "dopri853".into()],
        error: 1e-6,
        end: 1.0,
    };
    code = code.max(scaling(&sc, o)?);
    let or = OrdersArgs {
        dir: a.dir.clone(),
        out: a.out.clone(),
    };
    code = code.max(orders(&or, o)?);
    writeln!(o.err(), "bench all: {:.0} s", clock.elapsed().as_secs_f64()).map_err(Stop::Io)?;
    Ok(code)
}
