//! The self-contained HTML page of an animation: the project's WebGL2 viewer, with the
//! `.glb` and the run's columns inlined; nothing is fetched at view time.

/// The run's columns for the chart pane: names (time first) and rows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Chart {
    /// Column names, `time` first.
    pub names: Vec<String>,
    /// Rows, each as long as `names`.
    pub rows: Vec<Vec<f64>>,
}

/// The page showing `glb` (a glTF binary) with `chart` beside it, titled `title`, with
/// `notes` (what the scene could not draw as the dataset asks) shown once.
pub fn page(glb: &[u8], chart: &Chart, title: &str, notes: &[String]) -> String {
    // The viewer is to come; the page says what it holds.
    let _ = chart;
    format!(
        "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>{}</title></head><body><p>{} bytes of glTF; {} notes</p></body></html>",
        title.replace('<', "&lt;"),
        glb.len(),
        notes.len()
    )
}
