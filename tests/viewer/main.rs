//! The HTML viewer in a real browser: pages written by `mbfx::viewer::page` for glTF
//! binaries built by hand (glb.rs) and by `mbfx run --animate` (runs.rs), screenshotted
//! and dumped by headless Chromium.

mod browser;
mod glb;
mod runs;

use browser::{body_data, dom, evaluate, shot, Scratch, Shot};
use mbfx::viewer::{page, Chart};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The page's background, as docs/viewer.md gives it (linear 0.80, 0.84, 0.89 written to
/// an 8-bit canvas).
pub(crate) const BACKGROUND: [u8; 3] = [204, 214, 227];

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

/// The page for the hand-made mechanism in a fresh directory (kept while the guard lives).
fn write_page(name: &str, animated: bool) -> (Scratch, PathBuf) {
    let dir = Scratch::new(name);
    let notes = vec!["1 EXTERNAL graphic drawn as a placeholder box".to_string()];
    let html = page(
        &glb::mechanism(animated),
        &chart(),
        "viewer test mechanism",
        &notes,
    );
    let file = dir.0.join("page.html");
    std::fs::write(&file, html).unwrap();
    (dir, file)
}

/// The 3D pane's rectangle (x, y, w, h) in CSS pixels, as the page reports it: asked
/// once (every test page has one layout: one window size, one header line).
fn pane(file: &Path) -> [u32; 4] {
    static PANE: OnceLock<[u32; 4]> = OnceLock::new();
    *PANE.get_or_init(|| {
        let d = dom(file, "t=0", 1000, &[]);
        let text = body_data(&d, "pane").expect("the page reports its 3D pane");
        let v: Vec<u32> = text.split(',').map(|s| s.parse().unwrap()).collect();
        [v[0], v[1], v[2], v[3]]
    })
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
    let (_dir, file) = write_page("moves", true);
    let r = pane(&file);
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
    let (_dir, file) = write_page("fragment", true);
    for t in [0.5, 1.25] {
        let d = dom(&file, &format!("t={t}&probe=PART/2"), 1000, &[]);
        assert_eq!(
            body_data(&d, "ready").as_deref(),
            Some("1"),
            "the first frame was drawn"
        );
        assert_eq!(
            body_data(&d, "webgl").as_deref(),
            Some("1"),
            "WebGL2 came up"
        );
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
    let (_dir, file) = write_page("static", false);
    let r = pane(&file);
    let s = shot(&file, "", "static");
    let (n, _, _) = census(&s, r, red);
    assert!(n > 200, "the red box shows: {n} pixels");
}

#[test]
fn hovering_picks_the_node_under_the_pointer() {
    let (_dir, file) = write_page("pick", true);
    let r = pane(&file);
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
    // Two pixels off a dark grey line (the circle or the zigzag, one pixel wide) still
    // picks it: picking looks a few pixels around the pointer.
    let grey = |p: [u8; 3]| p[0] < 110 && p[0].abs_diff(p[1]) < 12 && p[0].abs_diff(p[2]) < 12;
    let (gx, gy) = (r[0]..r[0] + r[2])
        .flat_map(|x| (r[1]..r[1] + r[3]).map(move |y| (x, y)))
        .find(|&(x, y)| x > r[0] + 3 && y > r[1] + 3 && grey(s.pixel(x, y)))
        .expect("a grey line is drawn");
    let d = dom(
        &file,
        &format!("t=0&pick={},{}", gx - r[0] - 2, gy - r[1] - 2),
        1000,
        &[],
    );
    let name = body_data(&d, "pick").unwrap();
    assert!(
        name == "GRAPHICS/4" || name == "GRAPHICS/5",
        "picked {name:?} near a line at ({gx}, {gy})"
    );
    // The pointer over the box: the tip names it and its part, with their view names.
    let hover = format!(
        r#"(async () => {{
  const sleep = ms => new Promise(r => setTimeout(r, ms));
  while (document.body.dataset.ready !== '1') await sleep(50);
  const c = document.getElementById('gl'), r = c.getBoundingClientRect(), tip = document.getElementById('tip');
  c.dispatchEvent(new PointerEvent('pointermove', {{ clientX: r.left + {x}, clientY: r.top + {y}, bubbles: true }}));
  for (let k = 0; k < 40 && tip.hidden; k++) await sleep(50);
  return tip.hidden ? 'hidden' : tip.textContent;
}})()"#,
        x = x as u32 - r[0],
        y = y as u32 - r[1]
    );
    assert_eq!(
        evaluate(&file, "t=0", &hover),
        "GRAPHICS/1 “crank_box” — PART/2 “crank”"
    );
}

#[test]
fn without_webgl_the_page_says_so() {
    let (_dir, file) = write_page("nogl", true);
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
    let dir = Scratch::new("fps");
    let glb = glb::chain(100, 1000);
    let file = dir.0.join("page.html");
    std::fs::write(&file, page(&glb, &Chart::default(), "chain of 100", &[])).unwrap();
    let wait = "new Promise(done => { const look = () => window.mbfxViewer && window.mbfxViewer.stats.fps !== null \
        ? done(JSON.stringify(window.mbfxViewer.stats)) : setTimeout(look, 100); look(); })";
    let text = evaluate(&file, "fps", wait);
    let stats: serde_json::Value = serde_json::from_str(&text).unwrap();
    let (fps, frames) = (
        stats["fps"].as_f64().unwrap(),
        stats["frames"].as_f64().unwrap(),
    );
    eprintln!(
        "chain of 100, 1000 key times, .glb {} bytes: {fps:.1} frames/s, {:.2} ms JS per frame, first frame at {} ms",
        glb.len(),
        stats["drawMs"],
        stats["readyMs"]
    );
    // Over 2 s a page that draws at all shows several frames; the figure is reported, the
    // machine's load decides the rest.
    assert!(frames >= 4.0 && fps > 1.0, "{stats}");
}

/// The controls, driven as a user would (events dispatched in the page, real time).
const DRIVE: &str = r#"(async () => {
  const v = window.mbfxViewer, sleep = ms => new Promise(r => setTimeout(r, ms)), out = {};
  const key = k => document.dispatchEvent(new KeyboardEvent('keydown', { key: k, bubbles: true }));
  while (document.body.dataset.ready !== '1') await sleep(50);
  out.playingAtStart = v.state.playing;
  await sleep(700);
  out.playedTo = v.state.t;
  key(' ');
  out.pausedBySpace = !v.state.playing;
  const slider = document.getElementById('slider');
  slider.value = 0.5; slider.dispatchEvent(new Event('input'));
  out.slider = v.state.t;
  key('ArrowRight'); out.right1 = v.state.t;
  key('ArrowRight'); out.right2 = v.state.t;
  key('ArrowLeft'); out.left = v.state.t;
  const c = document.getElementById('chart'), r = c.getBoundingClientRect();
  const click = f => { key(' '); c.dispatchEvent(new MouseEvent('click', { clientX: r.left + f * r.width, clientY: r.top + r.height / 2 })); return v.state.t; };
  out.chartA = click(0.4); out.chartPaused = !v.state.playing;
  // The cursor is drawn where the click was: the chart's column there holds red pixels.
  const g = c.getContext('2d'), x = Math.round(0.4 * c.width), col = g.getImageData(x - 1, 0, 3, c.height).data;
  out.cursorRed = 0;
  for (let i = 0; i < col.length; i += 4) if (col[i] > 150 && col[i + 1] < 90 && col[i + 2] < 90) out.cursorRed++;
  out.chartB = click(0.8);
  out.label = document.getElementById('time').textContent;
  const speed = document.getElementById('speed'), loop = document.getElementById('loop');
  speed.value = '4'; speed.dispatchEvent(new Event('change'));
  loop.checked = false; loop.dispatchEvent(new Event('change'));
  slider.value = 2.5; slider.dispatchEvent(new Event('input'));
  key(' '); await sleep(900);
  out.endT = v.state.t; out.endPlaying = v.state.playing;
  loop.checked = true; loop.dispatchEvent(new Event('change'));
  slider.value = 2.5; slider.dispatchEvent(new Event('input'));
  key(' '); await sleep(500);
  out.loopT = v.state.t; out.loopPlaying = v.state.playing;
  return JSON.stringify(out);
})()"#;

#[test]
fn the_controls_play_pause_step_and_follow_the_chart() {
    let (_dir, file) = write_page("controls", true);
    let out: serde_json::Value =
        serde_json::from_str(&evaluate(&file, "t=0.5&play", DRIVE)).unwrap();
    let num = |k: &str| out[k].as_f64().unwrap_or_else(|| panic!("{k}: {out}"));
    let yes = |k: &str| out[k].as_bool().unwrap_or_else(|| panic!("{k}: {out}"));
    assert!(yes("playingAtStart"), "#t=0.5&play plays: {out}");
    assert!(num("playedTo") > 0.6, "time ran on from 0.5: {out}");
    assert!(yes("pausedBySpace"), "{out}");
    assert_eq!(num("slider"), 0.5);
    // The key times: PART/2's 0, 1, 2, 3 and the arrow's 0, 1.5, 3 (glb.rs).
    assert_eq!(
        (num("right1"), num("right2"), num("left")),
        (1.0, 1.5, 1.0),
        "{out}"
    );
    // The chart spans the columns' time, 0 to 3 s: a click further right is later.
    let (a, b) = (num("chartA"), num("chartB"));
    assert!(
        a > 0.3 && a < 1.5 && b > a + 0.6 && b < 3.0,
        "chart clicks at 40 % and 80 %: {a}, {b}"
    );
    assert!(yes("chartPaused"));
    assert!(
        num("cursorRed") > 20.0,
        "the cursor is drawn where the click was: {out}"
    );
    let label: f64 = out["label"]
        .as_str()
        .unwrap()
        .trim_end_matches(" s")
        .parse()
        .unwrap();
    assert!((label - b).abs() < 0.0006, "label {label} for t = {b}");
    // 4× from 2.5 s without loop: the end (3 s) within 0.125 s of real time, then stop.
    assert_eq!((num("endT"), yes("endPlaying")), (3.0, false), "{out}");
    // With loop: past the end it starts again and plays on.
    assert!(yes("loopPlaying") && num("loopT") < 2.5, "{out}");
}

#[test]
fn glyphs_and_arrows_hide_by_role() {
    let (_dir, file) = write_page("roles", true);
    let r = pane(&file);
    // The glyph is green (0.1, 0.7, 0.2), the arrow orange (0.9, 0.5, 0.0) (glb.rs).
    let green = |p: [u8; 3]| p[1] as i32 > p[0] as i32 + 50 && p[1] as i32 > p[2] as i32 + 50;
    let orange = |p: [u8; 3]| {
        p[0] > 120
            && p[1] as i32 * 3 > p[0] as i32
            && (p[1] as i32) < p[0] as i32 - 40
            && (p[2] as i32) < p[1] as i32 - 30
    };
    let all = shot(&file, "t=0", "all");
    let some = shot(&file, "t=0&hide=glyph,arrow", "hidden");
    let (g, _, _) = census(&all, r, green);
    let (o, _, _) = census(&all, r, orange);
    assert!(
        g > 10 && o > 10,
        "glyph and arrow drawn: {g} green, {o} orange pixels"
    );
    let (g, _, _) = census(&some, r, green);
    let (o, _, _) = census(&some, r, orange);
    assert_eq!((g, o), (0, 0), "hidden: green and orange pixels left");
    let (n, _, _) = census(&some, r, red);
    assert!(n > 200, "the box (a graphic) stays");
}

#[test]
fn the_hand_made_files_are_gltf() {
    // Read back by an independent reader (the `gltf` crate); the Khronos validator gave
    // them 0 errors and 0 warnings too (docs/viewer.md).
    for (bytes, animations) in [
        (glb::mechanism(true), 1),
        (glb::mechanism(false), 0),
        (glb::chain(3, 10), 1),
    ] {
        let g = gltf::Gltf::from_slice(&bytes).expect("a valid glTF binary");
        assert_eq!(
            g.nodes()
                .next()
                .and_then(|n| n.name().map(String::from))
                .as_deref(),
            Some("mbfx")
        );
        assert_eq!(g.animations().count(), animations);
        assert!(g.blob.as_ref().is_some_and(|b| !b.is_empty()));
    }
}

#[test]
fn an_unreadable_file_is_said_in_words() {
    let dir = Scratch::new("broken");
    let file = dir.0.join("page.html");
    std::fs::write(&file, page(b"not a glTF file", &chart(), "broken", &[])).unwrap();
    let d = dom(&file, "t=1", 1000, &[]);
    assert!(
        d.contains("The animation cannot be shown: not a glTF binary"),
        "{d}"
    );
    assert_eq!(
        body_data(&d, "ready").as_deref(),
        Some("1"),
        "the chart is still shown"
    );
    assert!(
        d.contains("1.000 s"),
        "the clock runs over the chart's times"
    );
}

/// The camera, driven by pointer and wheel events in the page (real time).
const CAMERA: &str = r#"
(async () => {
  const v = window.mbfxViewer, sleep = ms => new Promise(r => setTimeout(r, ms)), out = {};
  while (document.body.dataset.ready !== '1') await sleep(50);
  const c = document.getElementById('gl'), r = c.getBoundingClientRect(), cam = v.camera;
  const at = (dx, dy) => ({ clientX: r.left + r.width / 2 + dx, clientY: r.top + r.height / 2 + dy, bubbles: true, pointerId: 1 });
  const snap = () => JSON.parse(JSON.stringify({ dist: cam.dist, yaw: cam.yaw, pitch: cam.pitch, target: cam.target }));
  out.start = snap();
  c.dispatchEvent(new WheelEvent('wheel', { deltaY: -300, bubbles: true, cancelable: true }));
  out.zoomIn = cam.dist;
  c.dispatchEvent(new WheelEvent('wheel', { deltaY: 600, bubbles: true, cancelable: true }));
  out.zoomOut = cam.dist;
  const drag = (button, shift) => {
    c.dispatchEvent(new PointerEvent('pointerdown', { ...at(0, 0), button, shiftKey: shift }));
    c.dispatchEvent(new PointerEvent('pointermove', { ...at(40, 20), button, shiftKey: shift }));
    c.dispatchEvent(new PointerEvent('pointerup', { ...at(40, 20), button, shiftKey: shift }));
  };
  drag(0, false); out.orbit = snap();
  drag(2, false); out.panRight = snap();
  drag(0, true); out.panShift = snap();
  document.getElementById('fit').click(); out.fit = snap();
  return JSON.stringify(out);
})()
"#;

#[test]
fn orbit_pan_zoom_and_fit_move_the_camera() {
    let (_dir, file) = write_page("camera", true);
    let out: serde_json::Value = serde_json::from_str(&evaluate(&file, "t=0", CAMERA)).unwrap();
    let f = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{out}"));
    let (start, orbit, fit) = (&out["start"], &out["orbit"], &out["fit"]);
    assert!(
        f(&out["zoomIn"]) < f(&start["dist"]) && f(&start["dist"]) < f(&out["zoomOut"]),
        "wheel zooms: {out}"
    );
    assert!(
        f(&orbit["yaw"]) != f(&start["yaw"]) && f(&orbit["pitch"]) != f(&start["pitch"]),
        "drag orbits: {out}"
    );
    assert_eq!(
        orbit["target"], start["target"],
        "orbiting keeps the target"
    );
    for pan in ["panRight", "panShift"] {
        assert_ne!(
            out[pan]["target"], orbit["target"],
            "{pan} moves the target: {out}"
        );
        assert_eq!(out[pan]["yaw"], orbit["yaw"], "{pan} does not turn");
    }
    assert_ne!(out["panRight"]["target"], out["panShift"]["target"]);
    // Fit: back to the scene's bounds, whatever the view turned to.
    assert!(
        (f(&fit["dist"]) - f(&start["dist"])).abs() < 1e-9 && fit["target"] == start["target"],
        "{out}"
    );
}
