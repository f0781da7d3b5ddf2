//! The whole path a user takes: `mbfx run M.adm --animate page.html`, then the page in
//! headless Chromium. The slider-crank (2D, glyphs only: it has no GRAPHICS) and a 3D
//! spherical pendulum (millimeters, gravity along −z, so turned at the root) must be
//! drawn and must move between two fragment times.

use super::browser::{body_data, dom, shot, Scratch, Shot};
use super::BACKGROUND;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A 3D spherical pendulum in millimeters with gravity along −z, started with a spin, so
/// it swings and tumbles; its body carries a CYLINDER and a BOX.
const PENDULUM_3D: &str = "spherical pendulum\n\
    UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = MILLIMETER, TIME = SECOND\n\
    PART/1, GROUND\nMARKER/10, PART = 1\n\
    PART/2, MASS = 1, CM = 20, IP = 4E3, 9E3, 1.2E4, WX = 2, WY = -1, WZ = 6\n\
    MARKER/20, PART = 2, QP = 100, 50, -300\nMARKER/21, PART = 2\n\
    MARKER/23, PART = 2, QP = 100, 50, -300, REULER = 0D, 0D, 0D\n\
    GRAPHICS/1, CYLINDER, CM = 21, LENGTH = -300, RADIUS = 15\n\
    GRAPHICS/2, BOX, CORNER = 23, X = 80, Y = 80, Z = 80\n\
    JOINT/1, SPHERICAL, I = 21, J = 10\nACCGRAV/KGRAV = -9806.65\nEND\n";

/// `mbfx run` writing `page` for `dataset`, over `end` seconds.
fn animate(dataset: &Path, end: &str, page: &Path) {
    let out = Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .arg("run")
        .arg(dataset)
        .args(["--end", end, "--output-step", "0.01", "--animate"])
        .arg(page)
        .output()
        .expect("mbfx runs");
    assert!(
        out.status.success(),
        "mbfx run {}: {}",
        dataset.display(),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The pane's pixels that differ from the background, and the pixels that differ
/// between two shots.
fn drawn_and_changed(a: &Shot, b: &Shot, pane: [u32; 4]) -> (usize, usize, usize) {
    let (mut drawn, mut changed) = (0, 0);
    for y in pane[1]..(pane[1] + pane[3]).min(a.height) {
        for x in pane[0]..(pane[0] + pane[2]).min(a.width) {
            let (p, q) = (a.pixel(x, y), b.pixel(x, y));
            if (0..3).any(|k| (p[k] as i32 - BACKGROUND[k] as i32).abs() > 2) {
                drawn += 1;
            }
            if p != q {
                changed += 1;
            }
        }
    }
    (drawn, changed, (pane[2] * pane[3]) as usize)
}

fn check_drawn_and_moving(page: &Path, later: &str) {
    let d = dom(page, "t=0", 1500, &[]);
    assert_eq!(
        body_data(&d, "ready").as_deref(),
        Some("1"),
        "the page draws"
    );
    assert_eq!(body_data(&d, "webgl").as_deref(), Some("1"), "with WebGL2");
    let pane: Vec<u32> = body_data(&d, "pane")
        .expect("the page reports its 3D pane")
        .split(',')
        .map(|s| s.parse().unwrap())
        .collect();
    let pane = [pane[0], pane[1], pane[2], pane[3]];
    let a = shot(page, "t=0", "t0");
    let b = shot(page, later, "later");
    let (drawn, changed, area) = drawn_and_changed(&a, &b, pane);
    assert!(
        drawn * 100 >= area,
        "{}: only {drawn} of {area} pane pixels differ from the background",
        page.display()
    );
    assert!(
        changed * 1000 >= area,
        "{}: only {changed} of {area} pane pixels change between t = 0 and {later}",
        page.display()
    );
}

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes")
        .join(name)
}

#[test]
fn the_slider_crank_from_mbfx_run_is_drawn_and_moves() {
    let dir = Scratch::new("run-crank");
    let page = dir.0.join("crank.html");
    animate(&example("slider_crank_driven.adm"), "1", &page);
    // A quarter turn of the crank (one revolution a second).
    check_drawn_and_moving(&page, "t=0.25");
}

#[test]
fn a_3d_pendulum_from_mbfx_run_is_drawn_and_moves() {
    let dir = Scratch::new("run-pendulum");
    let dataset = dir.0.join("pendulum.adm");
    std::fs::write(&dataset, PENDULUM_3D).unwrap();
    let page = dir.0.join("pendulum.html");
    animate(&dataset, "1", &page);
    check_drawn_and_moving(&page, "t=0.5");
}
