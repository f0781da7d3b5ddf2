//! The HTML viewer in a real browser: pages written by `mbfx::viewer::page` for glTF
//! binaries built by hand (glb.rs), screenshotted and dumped by headless Chromium.

mod browser;
mod glb;

use browser::{body_data, dom, scratch, shot, Shot};
use mbfx::viewer::{page, Chart};
use std::path::PathBuf;

/// The page's background, as docs/viewer.md gives it (linear 0.80, 0.84, 0.89 written to
/// an 8-bit canvas).
const BACKGROUND: [u8; 3] = [204, 214, 227];

fn chart() -> Chart {
    let rows = (0..=30)
        .map(|k| {
            let t = k as f64 * 0.1;
            vec![t, (t * 2.0).sin(), if k == 5 { f64::NAN } else { t * t }]
        })
        .collect();
    Chart {
        names: vec!["time".into(), "REQUEST/1 x".into(), "PART/2 angle".into()],
        rows,
    }
}

fn write_page(name: &str, animated: bool) -> PathBuf {
    let dir = scratch(name);
    let notes = vec!["1 EXTERNAL graphic drawn as a placeholder box".to_string()];
    let html = page(
        &glb::mechanism(animated),
        &chart(),
        "viewer test mechanism",
        &notes,
    );
    let file = dir.join("page.html");
    std::fs::write(&file, html).unwrap();
    file
}

/// The 3D pane's rectangle (x, y, w, h) in CSS pixels, as the page reports it.
fn pane(dom: &str) -> [u32; 4] {
    let text = body_data(dom, "pane").expect("the page reports its 3D pane");
    let v: Vec<u32> = text.split(',').map(|s| s.parse().unwrap()).collect();
    [v[0], v[1], v[2], v[3]]
}

fn near(a: [u8; 3], b: [u8; 3], tol: i32) -> bool {
    (0..3).all(|k| (a[k] as i32 - b[k] as i32).abs() <= tol)
}

/// The box's pixels: clearly red (its material is (0.85, 0.1, 0.1); shading scales all
/// channels alike, so red stays well above green and blue).
fn red(p: [u8; 3]) -> bool {
    p[0] as i32 > 2 * p[1] as i32 + 20 && p[0] as i32 > 2 * p[2] as i32 + 20
}

/// Count and mean x, y of the pixels of the pane that `keep` accepts.
fn census(s: &Shot, r: [u32; 4], keep: impl Fn([u8; 3]) -> bool) -> (usize, f64, f64) {
    let (mut n, mut sx, mut sy) = (0usize, 0.0, 0.0);
    for y in r[1]..(r[1] + r[3]).min(s.height) {
        for x in r[0]..(r[0] + r[2]).min(s.width) {
            if keep(s.pixel(x, y)) {
                n += 1;
                sx += x as f64;
                sy += y as f64;
            }
        }
    }
    (n, sx / n.max(1) as f64, sy / n.max(1) as f64)
}

#[test]
fn the_mechanism_is_drawn_and_moves() {
    let file = write_page("moves", true);
    let d = dom(&file, "t=0", 1500, &[]);
    assert_eq!(
        body_data(&d, "ready").as_deref(),
        Some("1"),
        "the first frame was drawn"
    );
    assert_eq!(body_data(&d, "webgl").as_deref(), Some("1"));
    let r = pane(&d);
    let area = (r[2] * r[3]) as usize;
    let a = shot(&file, "t=0", "t0");
    let b = shot(&file, "t=2", "t2");
    // The pane's commonest colour is the documented background.
    let (bg, _, _) = census(&a, r, |p| near(p, BACKGROUND, 2));
    assert!(
        bg > area / 2,
        "background {BACKGROUND:?} covers {bg} of {area} pixels"
    );
    let (drawn, _, _) = census(&a, r, |p| !near(p, BACKGROUND, 2));
    assert!(
        drawn * 100 >= area,
        "only {drawn} of {area} pixels differ from the background"
    );
    // The box moves +1.5 along the model's x (world +x): from the default view (from +x,
    // +z, above), world +x runs to the right of the screen.
    let (n0, x0, _) = census(&a, r, red);
    let (n2, x2, _) = census(&b, r, red);
    assert!(
        n0 > 200 && n2 > 200,
        "the red box shows: {n0} and {n2} pixels"
    );
    assert!(
        x2 > x0 + 20.0,
        "the box moved right: centroid x {x0:.1} → {x2:.1}"
    );
    let changed = (0..a.rgb.len() / 3)
        .filter(|&i| a.rgb[3 * i..3 * i + 3] != b.rgb[3 * i..3 * i + 3])
        .count();
    assert!(
        changed > 400,
        "{changed} pixels changed between t = 0 and t = 2"
    );
}

/// World matrix at t of PART/2: root rotation × translation × rotation, from the keys.
fn expected_part2(t: f64) -> [f64; 16] {
    let k = glb::KEY_TIMES
        .iter()
        .rposition(|&k| (k as f64) <= t)
        .unwrap()
        .min(2);
    let u = (t - glb::KEY_TIMES[k] as f64) / (glb::KEY_TIMES[k + 1] - glb::KEY_TIMES[k]) as f64;
    let x = glb::KEY_X[k] as f64 + u * (glb::KEY_X[k + 1] - glb::KEY_X[k]) as f64;
    // A turn about one axis: slerp is the linear blend of the angles.
    let angle =
        (glb::KEY_DEGREES[k] + u * (glb::KEY_DEGREES[k + 1] - glb::KEY_DEGREES[k])).to_radians();
    let (c, s) = (angle.cos(), angle.sin());
    // Model: columns of R_z(angle), translation (x, 0, PART_Z). Root: model (x, y, z) →
    // world (x, z, −y).
    let to_world = |v: [f64; 3]| [v[0], v[2], -v[1]];
    let (cx, cy, cz) = (
        to_world([c, s, 0.0]),
        to_world([-s, c, 0.0]),
        to_world([0.0, 0.0, 1.0]),
    );
    let tr = to_world([x, 0.0, glb::PART_Z as f64]);
    [
        cx[0], cx[1], cx[2], 0.0, cy[0], cy[1], cy[2], 0.0, cz[0], cz[1], cz[2], 0.0, tr[0], tr[1],
        tr[2], 1.0,
    ]
}

#[test]
fn a_fragment_time_opens_paused_there_with_poses_interpolated() {
    let file = write_page("fragment", true);
    for t in [0.5, 1.25] {
        let d = dom(&file, &format!("t={t}&probe=PART/2"), 1000, &[]);
        assert_eq!(body_data(&d, "ready").as_deref(), Some("1"));
        let label = d
            .split("id=\"time\"")
            .nth(1)
            .and_then(|s| s.split('>').nth(1))
            .and_then(|s| s.split(' ').next())
            .unwrap();
        assert_eq!(label.parse::<f64>().unwrap(), t, "time label {label:?}");
        let probe: Vec<f64> = body_data(&d, "probe")
            .unwrap()
            .split(',')
            .map(|v| v.parse().unwrap())
            .collect();
        let want = expected_part2(t);
        for (k, (got, want)) in probe.iter().zip(want).enumerate() {
            assert!(
                (got - want).abs() < 1e-5,
                "t = {t}: world matrix [{k}] = {got}, want {want}"
            );
        }
    }
}

#[test]
fn a_page_without_animation_is_drawn() {
    let file = write_page("static", false);
    let d = dom(&file, "", 1000, &[]);
    assert_eq!(body_data(&d, "ready").as_deref(), Some("1"));
    let r = pane(&d);
    let s = shot(&file, "", "static");
    let (n, _, _) = census(&s, r, red);
    assert!(n > 200, "the red box shows: {n} pixels");
}

#[test]
fn hovering_picks_the_node_under_the_pointer() {
    let file = write_page("pick", true);
    let d = dom(&file, "t=0", 1000, &[]);
    let r = pane(&d);
    let s = shot(&file, "t=0", "pick");
    let (n, x, y) = census(&s, r, red);
    assert!(n > 200);
    // The centroid of a convex box's image lies on the box.
    let d = dom(
        &file,
        &format!("t=0&pick={},{}", x as u32 - r[0], y as u32 - r[1]),
        1000,
        &[],
    );
    assert_eq!(body_data(&d, "pick").as_deref(), Some("GRAPHICS/1"));
    let d = dom(&file, &format!("t=0&pick={},{}", 2, 2), 1000, &[]);
    assert_eq!(
        body_data(&d, "pick").as_deref(),
        Some("none"),
        "nothing at the pane's corner"
    );
}

#[test]
fn without_webgl_the_page_says_so() {
    let file = write_page("nogl", true);
    for flag in ["--disable-webgl", "--disable-3d-apis"] {
        let d = dom(&file, "t=0.5", 1000, &[flag]);
        assert_eq!(body_data(&d, "webgl").as_deref(), Some("0"), "{flag}");
        let message = "This viewer needs WebGL2, which this browser does not offer.";
        let at = d
            .find(message)
            .unwrap_or_else(|| panic!("{flag}: the message is missing"));
        let tag_start = d[..at].rfind('<').unwrap();
        assert!(
            !d[tag_start..at].contains("hidden"),
            "{flag}: the message is hidden"
        );
        assert_eq!(
            body_data(&d, "ready").as_deref(),
            Some("1"),
            "{flag}: the chart is still shown"
        );
    }
}

#[test]
fn the_page_loads_nothing_from_the_network() {
    let html = page(&glb::mechanism(true), &chart(), "t", &[]);
    let lower = html.to_ascii_lowercase();
    for bad in [
        "http://",
        "https://",
        "//cdn",
        "fetch(",
        "import(",
        "xmlhttprequest",
        "src=",
        "href=",
        "@import",
        "url(",
    ] {
        assert!(!lower.contains(bad), "the page holds {bad:?}");
    }
    let size = mbfx::viewer::viewer_size();
    assert!(size < 60_000, "the viewer is {size} bytes of JS and CSS");
}

#[test]
fn the_frame_rate_hook_measures_a_chain_of_100() {
    let dir = scratch("fps");
    let glb = glb::chain(100, 1000);
    let file = dir.join("page.html");
    std::fs::write(&file, page(&glb, &Chart::default(), "chain of 100", &[])).unwrap();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/viewer/fps.js");
    let out = std::process::Command::new("node")
        .arg(script)
        .arg(&file)
        .output()
        .expect("node runs (Node 20 is needed for the frame-rate test)");
    assert!(
        out.status.success(),
        "fps.js failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stats: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let (fps, frames) = (
        stats["fps"].as_f64().unwrap(),
        stats["frames"].as_f64().unwrap(),
    );
    eprintln!(
        "chain of 100, 1000 key times, .glb {} bytes: {fps:.1} frames/s, {:.2} ms JS per frame",
        glb.len(),
        stats["drawMs"]
    );
    // Over 2 s a page that draws at all shows several frames; the figure is reported, the
    // machine's load decides the rest.
    assert!(frames >= 4.0 && fps > 1.0, "{stats}");
}
