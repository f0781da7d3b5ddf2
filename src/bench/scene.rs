//! A scene with truth: a dataset (a file beside the truth file, or one generated for
//! any N) and its reference values, read from the truth file whose format
//! `examples/scenes/README.md` gives. Loading checks everything a bench run relies on
//! (every reference names a probe, every reference time is an output time), so a bench
//! never discovers a malformed scene halfway through.

use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What a probe's error is scored with: positions and reactions are scored apart, as
/// the references advise (multipliers are orders larger and less accurate).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Group {
    /// Positions, angles, velocities: what every method controls.
    Position,
    /// Reaction forces and torques, multipliers.
    Reaction,
}

impl Group {
    /// The group's name in the CSV header.
    pub fn name(self) -> &'static str {
        match self {
            Group::Position => "position",
            Group::Reaction => "reaction",
        }
    }
}

/// Where the reference values come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Truth {
    /// A closed form, or a quadrature of one, evaluated outside mbfx.
    Exact,
    /// A published reference vector.
    TestSet,
    /// Two different integrators agreeing to the stated digits.
    Converged,
}

/// One output column of a scene.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Probe {
    /// Column name, unique in the scene.
    pub name: String,
    /// The expression, in the model's scope.
    pub expr: String,
    /// Which error it counts towards.
    pub group: Group,
    /// Scored as |y − r| / |r| instead of |y − r| / scale.
    #[serde(default)]
    pub relative: bool,
}

/// A dataset written for any size N.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Generated {
    /// `chain` or `four_bar`.
    pub kind: String,
    /// The size.
    pub n: usize,
    /// The dimension the scene is built in (the truth file's `dim` wins).
    #[serde(default)]
    pub dim: Option<u8>,
}

/// The truth file as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    title: String,
    #[serde(default)]
    model: Option<String>,
    #[serde(default)]
    generate: Option<Generated>,
    end: f64,
    output_step: f64,
    section: String,
    truth: Truth,
    source: String,
    #[serde(default)]
    dim: Option<u8>,
    #[serde(default)]
    scale: Option<f64>,
    #[serde(default)]
    hmax: Option<f64>,
    #[serde(default)]
    hmin: Option<f64>,
    probe: Vec<Probe>,
    at: Vec<BTreeMap<String, toml::Value>>,
}

/// One reference value: probe `probe` (an index into [`Scene::probes`]) at output row
/// `row` (an index into the run's rows, t = row · output_step).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reference {
    /// The output row.
    pub row: usize,
    /// The time it stands for.
    pub time: f64,
    /// The probe.
    pub probe: usize,
    /// The reference value.
    pub value: f64,
}

/// The dataset a scene runs.
#[derive(Clone, Debug)]
pub enum Dataset {
    /// A file beside the truth file.
    File(PathBuf),
    /// Written by [`super::generate`].
    Generated(Generated),
}

/// A scene ready to run and score.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The truth file's stem: the scene's name on the command line and in file names.
    pub name: String,
    /// One line saying what it is.
    pub title: String,
    /// The dataset.
    pub dataset: Dataset,
    /// Simulated time.
    pub end: f64,
    /// Rows of the run.
    pub output_step: f64,
    /// The largest step, when the scene sets one (else the bench's output step).
    pub hmax: Option<f64>,
    /// The smallest step, when the scene sets one (else 1e-6·HMAX, as `mbfx run`).
    pub hmin: Option<f64>,
    /// Where the problem is described.
    pub section: String,
    /// Where the values come from.
    pub truth: Truth,
    /// How they were obtained, in words.
    pub source: String,
    /// 2 or 3 when the scene asks for it.
    pub dim: Option<u8>,
    /// The error unit of absolute probes.
    pub scale: f64,
    /// The columns.
    pub probes: Vec<Probe>,
    /// Every reference value, by row.
    pub references: Vec<Reference>,
}

impl Scene {
    /// Reads and checks a truth file. The message of an error names the file and what is wrong.
    pub fn load(path: &Path) -> Result<Scene, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .ok_or_else(|| format!("{}: not a scene file name", path.display()))?
            .to_string();
        let dir = path.parent().unwrap_or(Path::new("."));
        Scene::parse(&name, &text, dir).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parses truth-file text; `dir` is where a `model` file is looked for.
    pub fn parse(name: &str, text: &str, dir: &Path) -> Result<Scene, String> {
        let f: File = toml::from_str(text).map_err(|e| e.to_string())?;
        let dataset = match (f.model, f.generate) {
            (Some(m), None) => Dataset::File(dir.join(m)),
            (None, Some(g)) => {
                if super::generate::generate(&g.kind, g.n).is_none() {
                    return Err(format!("cannot generate a `{}` of size {}", g.kind, g.n));
                }
                Dataset::Generated(g)
            }
            _ => return Err("give either `model` or `[generate]`, not both".into()),
        };
        let positive = |what: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(format!("`{what}` must be a positive number, not {v}"))
            }
        };
        let end = positive("end", f.end)?;
        let output_step = positive("output_step", f.output_step)?;
        let scale = positive("scale", f.scale.unwrap_or(1.0))?;
        for (what, h) in [("hmax", f.hmax), ("hmin", f.hmin)] {
            if let Some(h) = h {
                positive(what, h)?;
            }
        }
        let dim = match f.dim {
            None => match &dataset {
                Dataset::Generated(g) => g.dim,
                Dataset::File(_) => None,
            },
            Some(d @ (2 | 3)) => Some(d),
            Some(d) => return Err(format!("`dim` must be 2 or 3, not {d}")),
        };
        if f.probe.is_empty() {
            return Err("no [[probe]]".into());
        }
        for (i, p) in f.probe.iter().enumerate() {
            if p.name == "time" || f.probe[..i].iter().any(|q| q.name == p.name) {
                return Err(format!("probe name `{}` is reserved or repeated", p.name));
            }
        }
        let rows = (end / output_step).round() as usize;
        let mut references = Vec::new();
        for at in &f.at {
            let time = match at.get("time") {
                Some(t) => number(t).ok_or("an [[at]] `time` is not a number")?,
                None => return Err("an [[at]] row has no `time`".into()),
            };
            let row = (time / output_step).round();
            if !(0.0..=rows as f64).contains(&row)
                || (row * output_step - time).abs() > 1e-9 * end.max(1.0)
            {
                return Err(format!(
                    "reference time {time} is not an output time (a multiple of {output_step} up to {end})"
                ));
            }
            for (key, v) in at.iter().filter(|(k, _)| k.as_str() != "time") {
                let probe = f
                    .probe
                    .iter()
                    .position(|p| &p.name == key)
                    .ok_or_else(|| format!("[[at]] time {time}: `{key}` is not a probe"))?;
                let value = number(v)
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| format!("[[at]] time {time}: `{key}` is not a finite number"))?;
                if f.probe[probe].relative && value == 0.0 {
                    return Err(format!(
                        "[[at]] time {time}: relative probe `{key}` has a zero reference"
                    ));
                }
                references.push(Reference {
                    row: row as usize,
                    time,
                    probe,
                    value,
                });
            }
        }
        if references.is_empty() {
            return Err("no reference values ([[at]] rows)".into());
        }
        Ok(Scene {
            name: name.to_string(),
            title: f.title,
            dataset,
            end,
            output_step,
            hmax: f.hmax,
            hmin: f.hmin,
            section: f.section,
            truth: f.truth,
            source: f.source,
            dim,
            scale,
            probes: f.probe,
            references,
        })
    }

    /// The dataset's text.
    pub fn dataset_text(&self) -> Result<String, String> {
        match &self.dataset {
            Dataset::File(p) => {
                std::fs::read_to_string(p).map_err(|e| format!("{}: cannot read: {e}", p.display()))
            }
            Dataset::Generated(g) => super::generate::generate(&g.kind, g.n)
                .ok_or_else(|| format!("cannot generate a `{}` of size {}", g.kind, g.n)),
        }
    }

    /// The rows a bench run needs: every `stride`-th output row of the scene, the
    /// largest stride that still lands on every reference time (and on the end). Rows
    /// cost little, but every output time cuts a step, so a run with the scene's dense
    /// rows would measure the row spacing, not the method.
    pub fn stride(&self) -> usize {
        fn gcd(a: usize, b: usize) -> usize {
            if b == 0 {
                a
            } else {
                gcd(b, a % b)
            }
        }
        let last = (self.end / self.output_step).round() as usize;
        self.references.iter().map(|r| r.row).fold(last, gcd).max(1)
    }

    /// The groups the scene scores, in order.
    pub fn groups(&self) -> Vec<Group> {
        let mut g: Vec<Group> = self.probes.iter().map(|p| p.group).collect();
        g.sort();
        g.dedup();
        g
    }

    /// The errors of one run's rows (`rows[k]` = the probe values at output row
    /// k·`stride`; a run that stopped early has fewer), per group: None where a
    /// reference row was not reached or a value is not finite.
    pub fn score(&self, rows: &[Vec<f64>], stride: usize) -> Errors {
        let mut e = Errors::default();
        for g in self.groups() {
            let mut worst: Option<f64> = Some(0.0);
            for r in self
                .references
                .iter()
                .filter(|r| self.probes[r.probe].group == g)
            {
                let y = rows.get(r.row / stride).map(|row| row[r.probe]);
                worst = match (worst, y) {
                    (Some(w), Some(y)) if y.is_finite() => {
                        let d = (y - r.value).abs();
                        let d = if self.probes[r.probe].relative {
                            d / r.value.abs()
                        } else {
                            d / self.scale
                        };
                        Some(w.max(d))
                    }
                    _ => None,
                };
            }
            match g {
                Group::Position => e.position = worst,
                Group::Reaction => e.reaction = worst,
            }
        }
        e
    }
}

/// A run's errors per group (None: the scene has no such probe, or the run did not
/// produce the values).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Errors {
    /// Positions.
    pub position: Option<f64>,
    /// Reactions.
    pub reaction: Option<f64>,
}

impl Errors {
    /// The error of a group.
    pub fn of(&self, g: Group) -> Option<f64> {
        match g {
            Group::Position => self.position,
            Group::Reaction => self.reaction,
        }
    }

    /// The larger of the groups' errors (None when none was scored).
    pub fn worst(&self) -> Option<f64> {
        match (self.position, self.reaction) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        }
    }
}

fn number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Float(f) => Some(*f),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// Every scene (`*.toml`) in a directory, sorted by name.
pub fn load_dir(dir: &Path) -> Result<Vec<Scene>, String> {
    let entries = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: cannot list the scenes: {e}", dir.display()))?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    paths.iter().map(|p| Scene::load(p)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const A01: &str = r#"
title = "A01"
model = "a01.adm"
end = 10.0
output_step = 0.5
section = "§4.1"
truth = "exact"
source = "elliptic functions"
[[probe]]
name = "x"
expr = "DX(201)"
group = "position"
[[probe]]
name = "t"
expr = "FZ(1)"
group = "reaction"
relative = true
[[at]]
time = 1.0
x = 0.5
t = 2.0
[[at]]
time = 10
x = -1.0
"#;

    #[test]
    fn scores_each_group_apart_at_its_rows() {
        let s = Scene::parse("a01", A01, Path::new("/x")).unwrap();
        assert_eq!(s.references.len(), 3);
        assert_eq!((s.references[0].row, s.references[2].row), (2, 20));
        assert_eq!(s.stride(), 2);
        let sparse: Vec<Vec<f64>> = (0..=10).map(|k| vec![k as f64, 2.0]).collect();
        assert_eq!(s.score(&sparse, 2).position, Some(11.0));
        let mut rows = vec![vec![0.0, 0.0]; 21];
        rows[2] = vec![0.5 + 1e-3, 2.0 * (1.0 + 1e-5)];
        rows[20] = vec![-1.0 - 1e-4, 0.0];
        let e = s.score(&rows, 1);
        assert!((e.position.unwrap() - 1e-3).abs() < 1e-15);
        assert!((e.reaction.unwrap() - 1e-5).abs() < 1e-15);
        // A run that stopped before t = 10 has no position error.
        assert_eq!(s.score(&rows[..5], 1).position, None);
    }

    #[test]
    fn rejects_references_off_the_output_times_and_unknown_probes() {
        let off = A01.replace("time = 10", "time = 9.7");
        assert!(Scene::parse("a", &off, Path::new("."))
            .unwrap_err()
            .contains("not an output time"));
        let unknown = A01.replace("x = -1.0", "z = -1.0");
        assert!(Scene::parse("a", &unknown, Path::new("."))
            .unwrap_err()
            .contains("`z` is not a probe"));
    }
}
