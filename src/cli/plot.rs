//! `mbfx run --plot FILE.svg|FILE.png`: the output columns against time, drawn with
//! plotters: up to six in stacked panels over one time axis (their scales differ), more
//! in one chart with a legend. The probes are drawn when there are any, else the request
//! columns.
//! Text uses the DejaVu Sans font of the system ([`crate::font`]).

use crate::font::font;
use plotters::prelude::*;
use std::path::Path;

/// Draws columns 1.. of `rows` (column 0 is time) to `path`: the first `probes` columns
/// when there are probes, else all.
pub fn draw(
    path: &Path,
    header: &[String],
    rows: &[Vec<f64>],
    probes: usize,
) -> Result<(), String> {
    font()?;
    let cols: Vec<usize> = if probes > 0 {
        (1..=probes).collect()
    } else {
        (1..header.len()).collect()
    };
    let svg = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    // Up to PANELS columns get a panel each, stacked over one time axis: their scales
    // differ (a position in metres, a force in newtons); more share one chart.
    let panels = if cols.len() <= PANELS { cols.len() } else { 1 };
    let size = (960, 600.max(220 * panels as u32));
    if svg {
        let root = SVGBackend::new(path, size).into_drawing_area();
        stacked(root, header, rows, &cols, panels)
    } else {
        let mut rgb = vec![0u8; 3 * size.0 as usize * size.1 as usize];
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        stacked(root, header, rows, &cols, panels)?;
        write_png(path, size, &rgb)
    }
}

/// Encodes an RGB buffer as PNG with the `png` crate directly: plotters' own encoder goes
/// through `image`, whose codecs were a tenth of the first build's CPU (README: the first
/// hour) for the one format used.
fn write_png(path: &Path, (width, height): (u32, u32), rgb: &[u8]) -> Result<(), String> {
    let err = |e: png::EncodingError| format!("{}: {e}", path.display());
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(err)?;
    writer.write_image_data(rgb).map_err(err)?;
    writer.finish().map_err(err)
}

/// Columns that get a panel of their own.
const PANELS: usize = 6;

/// One panel per column (`panels` of them), or all columns in one.
fn stacked<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    header: &[String],
    rows: &[Vec<f64>],
    cols: &[usize],
    panels: usize,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    if panels <= 1 {
        chart(&root, header, rows, cols, 0)?;
    } else {
        for (k, area) in root.split_evenly((panels, 1)).iter().enumerate() {
            chart(area, header, rows, &cols[k..=k], k)?;
        }
    }
    root.present().map_err(err)
}

/// Draws `cols` against time in `root`, colours from the palette's `first` on; a single
/// column is named on its axis, several in a legend.
fn chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    header: &[String],
    rows: &[Vec<f64>],
    cols: &[usize],
    first: usize,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let t0 = rows.first().map_or(0.0, |r| r[0]);
    let t1 = rows.last().map_or(1.0, |r| r[0]).max(t0 + f64::EPSILON);
    let finite = |x: &f64| x.is_finite();
    let values = || {
        rows.iter()
            .flat_map(|r| cols.iter().map(move |&c| r[c]))
            .filter(finite)
    };
    let lo = values().fold(f64::INFINITY, f64::min);
    let hi = values().fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if lo.is_finite() {
        (lo, hi)
    } else {
        (-1.0, 1.0)
    };
    let pad = ((hi - lo) * 0.05).max(1e-12 * hi.abs().max(1.0));
    let mut chart = ChartBuilder::on(root)
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(90)
        .build_cartesian_2d(t0..t1, (lo - pad)..(hi + pad))
        .map_err(err)?;
    let mut mesh = chart.configure_mesh();
    mesh.x_desc("time");
    if let [c] = cols {
        mesh.y_desc(header[*c].as_str());
    }
    mesh.draw().map_err(err)?;
    for (k, &c) in cols.iter().enumerate() {
        let color = Palette99::pick(first + k).to_rgba();
        chart
            .draw_series(LineSeries::new(
                rows.iter()
                    .filter(|r| r[c].is_finite())
                    .map(|r| (r[0], r[c])),
                color.stroke_width(2),
            ))
            .map_err(err)?
            .label(header[c].clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
    }
    if cols.len() > 1 {
        let corner = quiet_corner(rows, cols, (t0, t1), (lo - pad, hi + pad));
        chart
            .configure_series_labels()
            .position(corner)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

/// The corner of the plot where the legend hides the fewest points: each corner's box
/// (a third of the width, a tenth of the height per line plus a margin) counts the
/// points of the drawn columns inside it; ties go in the order upper right, upper left,
/// lower right, lower left.
fn quiet_corner(
    rows: &[Vec<f64>],
    cols: &[usize],
    (t0, t1): (f64, f64),
    (lo, hi): (f64, f64),
) -> SeriesLabelPosition {
    let height = (0.1 * cols.len() as f64 + 0.05).min(0.9);
    let width = 1.0 / 3.0;
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let mut counts = [0usize; 4];
    for r in rows {
        let x = (r[0] - t0) / (t1 - t0);
        for &c in cols {
            let y = (r[c] - lo) / (hi - lo);
            if !y.is_finite() {
                continue;
            }
            for (n, &(_, right, upper)) in corners.iter().enumerate() {
                let in_x = if right { x >= 1.0 - width } else { x <= width };
                let in_y = if upper {
                    y >= 1.0 - height
                } else {
                    y <= height
                };
                counts[n] += (in_x && in_y) as usize;
            }
        }
    }
    let best = (0..4).min_by_key(|&n| counts[n]).unwrap_or(0);
    corners[best].0.clone()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corner_of(ys: impl Fn(f64) -> f64) -> SeriesLabelPosition {
        let rows: Vec<Vec<f64>> = (0..=100)
            .map(|k| {
                let t = k as f64 / 100.0;
                vec![t, ys(t)]
            })
            .collect();
        quiet_corner(&rows, &[1], (0.0, 1.0), (0.0, 1.0))
    }

    #[test]
    fn the_legend_goes_where_the_curve_is_not() {
        let name = |p: SeriesLabelPosition| format!("{p:?}");
        // A rising line leaves the upper left and the lower right empty.
        assert_eq!(name(corner_of(|t| t)), name(SeriesLabelPosition::UpperLeft));
        // A curve high on the left and falling leaves the upper right empty.
        assert_eq!(
            name(corner_of(|t| 1.0 - t)),
            name(SeriesLabelPosition::UpperRight)
        );
        // A curve along the top leaves the lower corners: lower right first.
        assert_eq!(
            name(corner_of(|_| 0.98)),
            name(SeriesLabelPosition::LowerRight)
        );
    }
}
