//! SVG figures with plotters: linear axes for trajectories and energy errors, log–log for
//! work–precision. Text is left to the SVG viewer (no font is loaded), so the tour needs no
//! system font library.

use crate::output::{self, OutputError};
use crate::scene::{Figure, SweepLine};
use plotters::coord::{CoordTranslate, Shift};
use plotters::prelude::*;
use std::error::Error;
use std::path::Path;

/// Size of every figure, in SVG pixels.
const SIZE: (u32, u32) = (900, 560);

/// The line colours, in legend order.
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 0, 0),
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
    RGBColor(23, 190, 207),
];

fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// `[lo, hi]` of the finite values, widened by 5 % (or around a constant).
fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return (-1.0, 1.0);
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1e-300)
    };
    (lo - pad, hi + pad)
}

/// `[lo, hi]` of the positive finite values, widened by a factor 1.5 at both ends.
fn log_span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return (1e-16, 1.0);
    }
    (lo / 1.5, hi * 1.5)
}

fn canvas(path: &Path) -> Result<DrawingArea<SVGBackend<'_>, Shift>, Box<dyn Error>> {
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    Ok(root)
}

/// Draws the legend and writes the file.
fn finish<'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, CT>,
    root: &DrawingArea<SVGBackend<'a>, Shift>,
) -> Result<(), Box<dyn Error>> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

/// Runs `draw` on the file `path`, naming the file if it fails.
fn drawn(
    path: &Path,
    draw: impl FnOnce(&Path) -> Result<(), Box<dyn Error>>,
) -> output::Result<()> {
    draw(path).map_err(|e| OutputError::Plot {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Draws a figure with linear axes into `dir/figure.file`.
pub fn linear(dir: &Path, figure: &Figure) -> output::Result<()> {
    drawn(&dir.join(&figure.file), |path| draw_linear(path, figure))
}

fn draw_linear(path: &Path, figure: &Figure) -> Result<(), Box<dyn Error>> {
    let root = canvas(path)?;
    let points = || figure.series.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = span(points().map(|p| p.0));
    let (y0, y1) = span(points().map(|p| p.1));
    let mut chart = ChartBuilder::on(&root)
        .caption(&figure.title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(85)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc(figure.x_label.as_str())
        .y_desc(figure.y_label.as_str())
        .y_label_formatter(&|y| format!("{y:.2e}"))
        .draw()?;
    for (i, series) in figure.series.iter().enumerate() {
        let style = colour(i).stroke_width(if i == 0 { 1 } else { 2 });
        chart
            .draw_series(LineSeries::new(series.points.iter().copied(), style))?
            .label(series.label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
    }
    finish(&mut chart, &root)
}

/// Draws the work–precision figure of a sweep (error against wall time, log–log, one line per
/// scheme, a marker per `N`) into `dir/file`.
pub fn work_precision(
    dir: &Path,
    file: &str,
    title: &str,
    lines: &[SweepLine],
) -> output::Result<()> {
    drawn(&dir.join(file), |path| {
        draw_work_precision(path, title, lines)
    })
}

fn draw_work_precision(
    path: &Path,
    title: &str,
    lines: &[SweepLine],
) -> Result<(), Box<dyn Error>> {
    let root = canvas(path)?;
    let points = || lines.iter().flat_map(|l| l.points.iter());
    let (x0, x1) = log_span(points().map(|p| p.seconds));
    let (y0, y1) = log_span(points().map(|p| p.error));
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(85)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("wall time of the solve (s)")
        .y_desc("max error")
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()?;
    for (i, line) in lines.iter().enumerate() {
        let style = colour(i).stroke_width(2);
        let xy: Vec<(f64, f64)> = line
            .points
            .iter()
            .filter(|p| p.seconds > 0.0 && p.error > 0.0)
            .map(|p| (p.seconds, p.error))
            .collect();
        chart
            .draw_series(LineSeries::new(xy.iter().copied(), style))?
            .label(line.label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        chart.draw_series(xy.iter().map(|&p| Circle::new(p, 3, colour(i).filled())))?;
    }
    finish(&mut chart, &root)
}
