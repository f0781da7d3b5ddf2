//! Headless Chromium for the viewer's tests: screenshots (decoded with `png`) and the DOM
//! after a page's scripts ran, each run with a fresh profile directory.

use std::path::{Path, PathBuf};
use std::process::Command;

const CHROMIUM: &str = "/usr/bin/chromium-headless-shell";
/// The window the tests look through (CSS pixels; headless's device scale is 1).
pub const WIDTH: u32 = 800;
pub const HEIGHT: u32 = 600;

/// An RGB screenshot.
pub struct Shot {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Shot {
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = ((y * self.width + x) * 3) as usize;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }
}

/// A fresh directory under the system's temp dir, named for the test; removed when the
/// test passes, kept (with its pages and screenshots) when it fails.
pub struct Scratch(pub PathBuf);

impl Scratch {
    pub fn new(name: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("mbfx-viewer-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("pages and screenshots kept in {}", self.0.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

fn run(dir: &Path, extra: &[String], page: &Path, fragment: &str) -> String {
    if !Path::new(CHROMIUM).exists() {
        panic!("{CHROMIUM} is missing: install it with `sudo apt-get install chromium-headless-shell` (the viewer's tests need a real browser)");
    }
    let profile = dir.join(format!(
        "profile-{}",
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap()
            .as_nanos()
    ));
    let mut args: Vec<String> = [
        "--headless",
        "--no-sandbox",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--no-first-run",
        "--hide-scrollbars",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    args.push(format!("--user-data-dir={}", profile.display()));
    args.push(format!("--window-size={WIDTH},{HEIGHT}"));
    args.extend(extra.iter().cloned());
    args.push(format!("file://{}#{fragment}", page.display()));
    let launch = || {
        let _ = std::fs::remove_dir_all(&profile);
        Command::new(CHROMIUM)
            .args(&args)
            .output()
            .expect("chromium-headless-shell runs")
    };
    let mut out = launch();
    // Headless Chromium itself now and then dies of a signal (a segmentation fault seen
    // once in some forty launches under CI's load): one more launch, said on stderr. A
    // second crash, or any exit with a code, fails the test.
    if out.status.code().is_none() {
        eprintln!(
            "chromium died of a signal ({}); launching it once more",
            String::from_utf8_lossy(&out.stderr).trim()
        );
        out = launch();
    }
    let _ = std::fs::remove_dir_all(&profile);
    assert!(
        out.status.success(),
        "chromium failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The page's DOM once its scripts ran for `budget_ms` of virtual time.
pub fn dom(page: &Path, fragment: &str, budget_ms: u32, extra: &[&str]) -> String {
    let dir = page.parent().unwrap();
    let mut flags: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    flags.push(format!("--virtual-time-budget={budget_ms}"));
    flags.push("--dump-dom".into());
    run(dir, &flags, page, fragment)
}

/// A screenshot of the page at `fragment`, saved as `name`.png beside it.
pub fn shot(page: &Path, fragment: &str, name: &str) -> Shot {
    let dir = page.parent().unwrap();
    let file = dir.join(format!("{name}.png"));
    let flags = vec![
        "--virtual-time-budget=1500".to_string(),
        format!("--screenshot={}", file.display()),
    ];
    run(dir, &flags, page, fragment);
    let decoder =
        png::Decoder::new(std::fs::File::open(&file).expect("chromium wrote the screenshot"));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let rgb = buf[..info.buffer_size()]
        .chunks(channels)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    Shot {
        width: info.width,
        height: info.height,
        rgb,
    }
}

/// The value of `data-<name>` on the body of a dumped DOM.
pub fn body_data(dom: &str, name: &str) -> Option<String> {
    let start = dom.find("<body")?;
    let tag = &dom[start..start + dom[start..].find('>')?];
    let key = format!("data-{name}=\"");
    let at = tag.find(&key)? + key.len();
    Some(tag[at..at + tag[at..].find('"')?].to_string())
}

/// The string `expression` (a promise is awaited) gives in the page at `fragment`, in
/// real time: through tests/viewer/cdp.js (Node) and Chromium's DevTools pipe.
pub fn evaluate(page: &Path, fragment: &str, expression: &str) -> String {
    if !Path::new(CHROMIUM).exists() {
        panic!(
            "{CHROMIUM} is missing: install it with `sudo apt-get install chromium-headless-shell`"
        );
    }
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/viewer/cdp.js");
    let out = Command::new("node")
        .args([script, &page.display().to_string(), fragment, expression])
        .output()
        .expect("node runs (Node 20: `sudo apt-get install nodejs`)");
    assert!(
        out.status.success(),
        "cdp.js failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}
