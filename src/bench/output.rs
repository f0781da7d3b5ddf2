//! What `bench wp` writes for a scene: `SCENE.csv` (mbfx's points, then any peer's read
//! from the peers' directory) and `SCENE.svg` (one work-precision panel per scored
//! group), and the markdown summary section of the scene.

use super::chart::{self, Axes};
use super::scene::{Group, Scene};
use super::wp::{read_csv, summary_table, write_csv, Row};
use std::path::Path;

/// The peers' points for `scene` in `peers` (`SCENE.csv` written by benches/peers), if
/// that file exists.
pub fn peer_rows(peers: Option<&Path>, scene: &Scene) -> Result<Vec<Row>, String> {
    let Some(dir) = peers else {
        return Ok(Vec::new());
    };
    let path = dir.join(format!("{}.csv", scene.name));
    if !path.exists() {
        return Ok(Vec::new());
    }
    Ok(read_csv(&path)?
        .into_iter()
        .filter(|r| r.scene == scene.name)
        .collect())
}

/// Writes `DIR/SCENE.csv` (the mbfx rows only: the peers keep their own files) and
/// `DIR/SCENE.svg` (mbfx and peers), and returns the scene's summary section.
pub fn write_scene(
    dir: &Path,
    scene: &Scene,
    ours: &[Row],
    peers: &[Row],
) -> Result<String, String> {
    write_csv(&dir.join(format!("{}.csv", scene.name)), ours)?;
    let all: Vec<Row> = ours.iter().chain(peers).cloned().collect();
    let titles: Vec<String> = scene
        .groups()
        .iter()
        .map(|g| format!("{}: {} error", scene.name, g.name()))
        .collect();
    let panels: Vec<(Axes, Vec<chart::Curve>)> = scene
        .groups()
        .iter()
        .zip(&titles)
        .map(|(&g, title)| {
            (
                Axes {
                    title,
                    x: "CPU time (s)",
                    y: if g == Group::Position {
                        "error (positions; hollow: ERROR asked)"
                    } else {
                        "error (reactions; hollow: ERROR asked)"
                    },
                },
                chart::wp_curves(&all, g),
            )
        })
        .collect();
    chart::draw(&dir.join(format!("{}.svg", scene.name)), &panels)?;
    let mut s = format!(
        "\n## {} — {}\n\n{} ({}; truth: {:?}). End time {} s.\n",
        scene.name, scene.title, scene.section, scene.name, scene.truth, scene.end
    );
    let failed: Vec<&Row> = ours.iter().filter(|r| !r.ok()).collect();
    s += &summary_table(scene, &all);
    if !failed.is_empty() {
        s += "\nRuns that stopped with a diagnostic:\n\n";
        for r in failed {
            s += &format!("- {} at {:e}: {}\n", r.method, r.setting, r.status);
        }
    }
    Ok(s)
}
