//! SVG figures with plotters: linear axes for trajectories and energy errors, log–log for
//! work–precision. Text is left to the SVG viewer (no font is loaded), so the tour needs no
//! system font library.
//!
//! Labels are for reading ([`ticks`](crate::ticks)): powers of ten on log axes, plain numbers
//! on linear ones (a common factor `×10ᵏ` goes into the axis title), and the legend sits in a
//! strip under the plot, where it cannot cover a curve.

use crate::output::{self, OutputError};
use crate::scene::{Figure, SweepLine};
use crate::ticks::{common_exponent, plain, power_of_ten, scaled_title};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::error::Error;
use std::path::Path;

/// Size of every figure, in SVG pixels.
const SIZE: (u32, u32) = (900, 600);

/// Height of one row of the legend strip.
const LEGEND_ROW: u32 = 22;
/// Width the legend's text is given per character (15 px sans-serif averages about 7.5),
/// and the width of an entry besides its text (the line sample and the gaps).
const LEGEND_CHAR: u32 = 8;
const LEGEND_SAMPLE: u32 = 56;
/// Left edge of the legend and the width it may fill.
const LEGEND_LEFT: i32 = 90;
const LEGEND_WIDTH: u32 = SIZE.0 - 100;

/// The line colours, in legend order: distinct up to the twenty lines a scene may sweep (the
/// damped oscillator sweeps eighteen: three routes to one equation).
const PALETTE: [RGBColor; 20] = [
    RGBColor(0, 0, 0),
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
    RGBColor(23, 190, 207),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    // The lighter tones of the same hues, for the lines after the eleventh.
    RGBColor(174, 199, 232),
    RGBColor(255, 152, 150),
    RGBColor(152, 223, 138),
    RGBColor(197, 176, 213),
    RGBColor(255, 187, 120),
    RGBColor(196, 156, 148),
    RGBColor(158, 218, 229),
    RGBColor(247, 182, 210),
    RGBColor(219, 219, 141),
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

/// One legend entry: its label, colour and line width.
struct Entry<'a> {
    label: &'a str,
    colour: RGBColor,
    width: u32,
}

/// The figure's canvas split into the plot (with the caption) and the legend strip under it.
type Areas<'a> = (
    DrawingArea<SVGBackend<'a>, Shift>,
    DrawingArea<SVGBackend<'a>, Shift>,
    DrawingArea<SVGBackend<'a>, Shift>,
);

/// Entries per legend row: as many as fit side by side with the longest label (1 to 4).
/// Combining marks (the dots of `q̈`) take no width.
fn legend_columns(labels: &[&str]) -> usize {
    let width = |label: &str| {
        let combining = '\u{300}'..='\u{36f}';
        label.chars().filter(|c| !combining.contains(c)).count()
    };
    let longest = labels.iter().map(|l| width(l)).max().unwrap_or(0) as u32;
    let entry = LEGEND_SAMPLE + LEGEND_CHAR * longest;
    ((LEGEND_WIDTH / entry.max(1)) as usize).clamp(1, 4)
}

fn canvas<'a>(path: &'a Path, labels: &[&str]) -> Result<Areas<'a>, Box<dyn Error>> {
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let rows = labels.len().div_ceil(legend_columns(labels)) as u32;
    let (plot, legend) = root.split_vertically(SIZE.1 - rows * LEGEND_ROW - 12);
    Ok((root, plot, legend))
}

/// Draws the legend entries in rows of [`legend_columns`] into the strip under the plot.
fn legend(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    entries: &[Entry],
) -> Result<(), Box<dyn Error>> {
    let labels: Vec<&str> = entries.iter().map(|e| e.label).collect();
    let columns = legend_columns(&labels);
    let column = LEGEND_WIDTH as i32 / columns as i32;
    for (i, entry) in entries.iter().enumerate() {
        let x = LEGEND_LEFT + column * (i % columns) as i32;
        let y = 8 + LEGEND_ROW as i32 * (i / columns) as i32;
        let style = entry.colour.stroke_width(entry.width);
        area.draw(&PathElement::new(vec![(x, y + 7), (x + 28, y + 7)], style))?;
        area.draw(&Text::new(
            entry.label.to_string(),
            (x + 36, y),
            ("sans-serif", 15).into_font(),
        ))?;
    }
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
    let labels: Vec<&str> = figure.series.iter().map(|s| s.label.as_str()).collect();
    let (root, plot, strip) = canvas(path, &labels)?;
    let points = || figure.series.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = span(points().map(|p| p.0));
    let (y0, y1) = span(points().map(|p| p.1));
    // Plain numbers on both axes: a very small or very large axis shows its values over 10ᵏ
    // and says so in its title.
    let (kx, ky) = (common_exponent(x0, x1), common_exponent(y0, y1));
    let (sx, sy) = (10f64.powi(-kx), 10f64.powi(-ky));
    let (x0, x1, y0, y1) = (x0 * sx, x1 * sx, y0 * sy, y1 * sy);
    let (step_x, step_y) = ((x1 - x0) / 10.0, (y1 - y0) / 10.0);
    let mut chart = ChartBuilder::on(&plot)
        .caption(&figure.title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc(scaled_title(&figure.x_label, kx))
        .y_desc(scaled_title(&figure.y_label, ky))
        .x_label_formatter(&|x| plain(*x, step_x))
        .y_label_formatter(&|y| plain(*y, step_y))
        .draw()?;
    let mut entries = Vec::new();
    for (i, series) in figure.series.iter().enumerate() {
        let width = if i == 0 { 1 } else { 2 };
        let style = colour(i).stroke_width(width);
        let scaled = series.points.iter().map(|&(x, y)| (x * sx, y * sy));
        chart.draw_series(LineSeries::new(scaled, style))?;
        entries.push(Entry {
            label: &series.label,
            colour: colour(i),
            width,
        });
    }
    legend(&strip, &entries)?;
    root.present()?;
    Ok(())
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
    let labels: Vec<&str> = lines.iter().map(|l| l.label.as_str()).collect();
    let (root, plot, strip) = canvas(path, &labels)?;
    let points = || lines.iter().flat_map(|l| l.points.iter());
    let (x0, x1) = log_span(points().map(|p| p.seconds));
    let (y0, y1) = log_span(points().map(|p| p.error));
    let mut chart = ChartBuilder::on(&plot)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("wall time of the solve (s)")
        .y_desc("max error max_k |Q_k − q(t_k)| (units of q)")
        .x_label_formatter(&|x| power_of_ten(*x))
        .y_label_formatter(&|y| power_of_ten(*y))
        .draw()?;
    let mut entries = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let style = colour(i).stroke_width(2);
        let xy: Vec<(f64, f64)> = line
            .points
            .iter()
            .filter(|p| p.seconds > 0.0 && p.error > 0.0)
            .map(|p| (p.seconds, p.error))
            .collect();
        chart.draw_series(LineSeries::new(xy.iter().copied(), style))?;
        chart.draw_series(xy.iter().map(|&p| Circle::new(p, 3, colour(i).filled())))?;
        entries.push(Entry {
            label: &line.label,
            colour: colour(i),
            width: 2,
        });
    }
    legend(&strip, &entries)?;
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::legend_columns;

    /// The longest label of a sweep legend fits two columns; short ones fit four; combining
    /// marks take no room.
    #[test]
    fn legend_columns_fit_the_longest_label() {
        assert_eq!(legend_columns(&["variational FDE−, second-order start"]), 2);
        assert_eq!(
            legend_columns(&["general direct embedding FDE− of q̈ + q̇ + q"]),
            2
        );
        assert_eq!(legend_columns(&["reference q0", "direct q1"]), 4);
        assert_eq!(legend_columns(&[&"x".repeat(80)]), 1);
    }
}
