//! The self-contained HTML page of an animation: the project's WebGL2 viewer (plain
//! JavaScript, no framework), with the `.glb` (base64) and the run's columns (JSON)
//! inlined; nothing is fetched at view time. The assets sit in `assets/` and are embedded
//! with `include_str!`; docs/viewer.md describes the page, its controls and test hooks.

use base64::Engine as _;

/// The run's columns for the chart pane: names (time first) and rows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Chart {
    /// Column names, `time` first.
    pub names: Vec<String>,
    /// Rows, each as long as `names`.
    pub rows: Vec<Vec<f64>>,
}

const TEMPLATE: &str = include_str!("assets/page.html");
const CSS: &str = include_str!("assets/viewer.css");
/// The viewer's scripts in the order they depend on each other (the controller last).
const SCRIPTS: [&str; 5] = [
    include_str!("assets/math.js"),
    include_str!("assets/glb.js"),
    include_str!("assets/render.js"),
    include_str!("assets/chart.js"),
    include_str!("assets/viewer.js"),
];

/// The page showing `glb` (a glTF binary) with `chart` beside it, titled `title`, with
/// `notes` (what the scene could not draw as the dataset asks) shown once.
pub fn page(glb: &[u8], chart: &Chart, title: &str, notes: &[String]) -> String {
    let title = if title.trim().is_empty() {
        "mbfx animation"
    } else {
        title
    };
    let js = format!("(function () {{\n'use strict';\n{}}})();", SCRIPTS.concat());
    fill(TEMPLATE, |key| match key {
        "title" => escape_html(title),
        "notes" => escape_html(&notes.join(" · ")),
        "css" => CSS.to_string(),
        "js" => js.clone(),
        "glb" => base64::engine::general_purpose::STANDARD.encode(glb),
        "chart" => chart_json(chart),
        _ => String::new(),
    })
}

/// The size in bytes of the viewer itself (scripts and style, without the data).
pub fn viewer_size() -> usize {
    CSS.len() + SCRIPTS.iter().map(|s| s.len()).sum::<usize>()
}

/// `template` with each `{{key}}` replaced by `value(key)`, in one pass (so nothing a
/// value holds is taken for a placeholder).
fn fill(template: &str, value: impl Fn(&str) -> String) -> String {
    let mut out = String::with_capacity(template.len());
    let mut rest = template;
    while let Some(open) = rest.find("{{") {
        let Some(close) = rest[open..].find("}}") else {
            break;
        };
        out.push_str(&rest[..open]);
        out.push_str(&value(&rest[open + 2..open + close]));
        rest = &rest[open + close + 2..];
    }
    out.push_str(rest);
    out
}

fn escape_html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

/// The chart's columns as JSON, `{"names": [...], "columns": [[...], ...]}`: column-major
/// (what a curve reads), NaN, infinities and missing cells as null, and `<` escaped so no
/// name can close the script element holding it.
fn chart_json(chart: &Chart) -> String {
    let columns: Vec<Vec<Option<f64>>> = (0..chart.names.len())
        .map(|c| {
            let cell = |row: &Vec<f64>| row.get(c).copied().filter(|v| v.is_finite());
            chart.rows.iter().map(cell).collect()
        })
        .collect();
    let json = serde_json::json!({ "names": chart.names, "columns": columns });
    json.to_string().replace('<', "\\u003c")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placeholders_are_filled_once() {
        let out = fill("a{{x}}b{{y}}c{{", |k| format!("<{k}{{{{y}}}}>"));
        assert_eq!(out, "a<x{{y}}>b<y{{y}}>c{{");
    }

    #[test]
    fn chart_json_nulls_what_json_cannot_hold() {
        let chart = Chart {
            names: vec!["time".into(), "</script>".into()],
            rows: vec![vec![0.0, f64::NAN], vec![1.0, f64::INFINITY], vec![2.0]],
        };
        let text = chart_json(&chart);
        assert!(!text.contains('<'), "{text}");
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back["names"][1], "</script>");
        assert_eq!(back["columns"][0], serde_json::json!([0.0, 1.0, 2.0]));
        assert_eq!(back["columns"][1], serde_json::json!([null, null, null]));
    }

    #[test]
    fn title_and_notes_are_text() {
        let html = page(b"glTF", &Chart::default(), "a<b & \"c\"", &["n<1>".into()]);
        assert!(html.contains("<title>a&lt;b &amp; &quot;c&quot;</title>"));
        assert!(html.contains("n&lt;1&gt;"));
        assert!(html.contains(">Z2xURg==</script>"), "the .glb in base64");
    }
}
