//! Log-log charts as SVG: work-precision (error against CPU time, one curve per method,
//! each tolerance-controlled point joined by a faint stem to a hollow mark at the
//! tolerance it was asked for, so the distance between asked and got is visible), and
//! scaling (a cost against N, with the fitted slope in the legend). Peers' curves are
//! drawn with triangles, mbfx's with dots.

use super::scene::Group;
use super::wp::{label, Row};
use crate::font::font;
use plotters::prelude::*;
use std::path::Path;

/// One curve of a chart.
pub struct Curve {
    /// Its name in the legend.
    pub name: String,
    /// (x, y) points, x ascending.
    pub points: Vec<(f64, f64)>,
    /// The tolerance each point asked for (same length as `points`; None for none).
    pub asked: Vec<Option<f64>>,
    /// A peer's curve.
    pub peer: bool,
}

/// The work-precision curves of one group: one per method (label), points sorted by
/// CPU; failed runs and runs without an error of the group left out.
pub fn wp_curves(rows: &[Row], group: Group) -> Vec<Curve> {
    let mut names: Vec<String> = Vec::new();
    for r in rows {
        let l = label(r);
        if !names.contains(&l) {
            names.push(l);
        }
    }
    let mut curves = Vec::new();
    for name in names {
        let mut pts: Vec<(f64, f64, Option<f64>)> = rows
            .iter()
            .filter(|r| label(r) == name && r.ok() && r.cpu_of(group) > 0.0)
            .filter_map(|r| {
                let e = r.error(group)?;
                let asked = (r.control == "tolerance").then_some(r.setting);
                Some((r.cpu_of(group), e.max(1e-17), asked))
            })
            .collect();
        if pts.is_empty() {
            continue;
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let peer = name.starts_with("exudyn") || name.starts_with("mujoco");
        curves.push(Curve {
            name,
            points: pts.iter().map(|p| (p.0, p.1)).collect(),
            asked: pts.iter().map(|p| p.2).collect(),
            peer,
        });
    }
    curves
}

/// Axis labels and the title of a chart.
pub struct Axes<'a> {
    /// The chart's title.
    pub title: &'a str,
    /// The x axis.
    pub x: &'a str,
    /// The y axis.
    pub y: &'a str,
}

/// Draws panels side by side (one per (axes, curves)) to an SVG file.
pub fn draw(path: &Path, panels: &[(Axes, Vec<Curve>)]) -> Result<(), String> {
    font()?;
    // The legend gets a column of its own beside the panels: with a dozen curves it
    // would hide the points.
    let names: Vec<(String, bool)> = panels
        .iter()
        .flat_map(|(_, cs)| cs.iter().map(|c| (c.name.clone(), c.peer)))
        .fold(Vec::new(), |mut v, n| {
            if !v.contains(&n) {
                v.push(n);
            }
            v
        });
    let widest = names.iter().map(|n| n.0.chars().count()).max().unwrap_or(0) as u32;
    let legend_w = 60 + 7 * widest;
    let width = 640 * panels.len().max(1) as u32 + legend_w;
    let height = 540.max(40 + 18 * names.len() as u32);
    let root = SVGBackend::new(path, (width, height)).into_drawing_area();
    let err = |e: DrawingAreaErrorKind<_>| format!("{}: {e}", path.display());
    root.fill(&WHITE).map_err(err)?;
    let (plots, legend) = root.split_horizontally(width - legend_w);
    let areas = plots.split_evenly((1, panels.len().max(1)));
    for ((axes, curves), area) in panels.iter().zip(areas.iter()) {
        panel(area, axes, curves, &names).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    for (k, (name, peer)) in names.iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let y = 40 + 18 * k as i32;
        legend
            .draw(&PathElement::new(
                vec![(8, y), (34, y)],
                color.stroke_width(2),
            ))
            .map_err(err)?;
        if *peer {
            legend
                .draw(&TriangleMarker::new((21, y), 5, color.filled()))
                .map_err(err)?;
        } else {
            legend
                .draw(&Circle::new((21, y), 3, color.filled()))
                .map_err(err)?;
        }
        legend
            .draw(&Text::new(
                name.clone(),
                (42, y - 7),
                ("sans-serif", 13).into_font(),
            ))
            .map_err(err)?;
    }
    root.present().map_err(err)
}

/// A decade range covering `vals`.
fn decades(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in vals.filter(|v| v.is_finite() && *v > 0.0) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (1e-3, 1.0);
    }
    let lo = 10f64.powf(lo.log10().floor());
    let hi = 10f64.powf(hi.log10().ceil()).max(lo * 10.0);
    (lo, hi)
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    axes: &Axes,
    curves: &[Curve],
    names: &[(String, bool)],
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (x0, x1) = decades(curves.iter().flat_map(|c| c.points.iter().map(|p| p.0)));
    let (y0, y1) = decades(curves.iter().flat_map(|c| {
        c.points
            .iter()
            .map(|p| p.1)
            .chain(c.asked.iter().flatten().copied())
    }));
    let mut chart = ChartBuilder::on(area)
        .caption(axes.title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(axes.x)
        .y_desc(axes.y)
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(err)?;
    for c in curves {
        // The same colour for a curve in every panel: its place in the shared legend.
        let k = names.iter().position(|n| n.0 == c.name).unwrap_or(0);
        let color = Palette99::pick(k).to_rgba();
        for (p, a) in c.points.iter().zip(&c.asked) {
            if let Some(a) = a {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![*p, (p.0, *a)],
                        color.mix(0.25),
                    )))
                    .map_err(err)?;
                chart
                    .draw_series(std::iter::once(Circle::new((p.0, *a), 3, color.mix(0.6))))
                    .map_err(err)?;
            }
        }
        chart
            .draw_series(LineSeries::new(
                c.points.iter().copied(),
                color.stroke_width(2),
            ))
            .map_err(err)?;
        if c.peer {
            chart
                .draw_series(
                    c.points
                        .iter()
                        .map(|&p| TriangleMarker::new(p, 5, color.filled())),
                )
                .map_err(err)?;
        } else {
            chart
                .draw_series(c.points.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(err)?;
        }
    }
    Ok(())
}

/// The least-squares slope of log y against log x.
pub fn slope(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
        .map(|p| (p.0.ln(), p.1.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law() {
        let pts: Vec<(f64, f64)> = (1..6)
            .map(|k| (k as f64, 3.0 * (k as f64).powf(1.5)))
            .collect();
        assert!((slope(&pts).unwrap() - 1.5).abs() < 1e-12);
        assert_eq!(slope(&pts[..1]), None);
    }
}
