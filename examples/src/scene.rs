//! What a scene hands to the report: its comparison tables, its work–precision sweep and the
//! curves to plot. Nothing here knows about plotting or files.

use indicatif::ProgressBar;
use std::time::Instant;

/// How much of the tour to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Every scene at the sizes the report is written at.
    Full,
    /// Every scene, every table and every plot, on small grids and short sweeps (seconds, even
    /// unoptimised): what the tour's own test runs.
    Quick,
}

/// The run-wide settings and the progress bar the sweeps advance.
pub struct Context {
    /// Full or quick.
    pub mode: Mode,
    /// One tick per solve of a work–precision sweep.
    pub progress: ProgressBar,
}

impl Context {
    /// A context whose progress bar draws nothing (tests).
    pub fn hidden(mode: Mode) -> Self {
        Context {
            mode,
            progress: ProgressBar::hidden(),
        }
    }

    /// `full` in full mode, `quick` in quick mode.
    pub fn pick<T>(&self, full: T, quick: T) -> T {
        match self.mode {
            Mode::Full => full,
            Mode::Quick => quick,
        }
    }

    /// Wall time of `solve` in seconds. In full mode a solve shorter than 20 ms is repeated
    /// until 50 ms have passed and the fastest run is kept (the minimum is the least noisy
    /// estimate on a shared machine); quick mode times one run.
    pub fn time<T, E>(&self, mut solve: impl FnMut() -> Result<T, E>) -> Result<(T, f64), E> {
        let start = Instant::now();
        let value = solve()?;
        let mut best = start.elapsed().as_secs_f64();
        if self.mode == Mode::Full && best < 0.02 {
            let budget = Instant::now();
            while budget.elapsed().as_secs_f64() < 0.05 {
                let start = Instant::now();
                solve()?;
                best = best.min(start.elapsed().as_secs_f64());
            }
        }
        Ok((value, best))
    }
}

/// `n0, 2 n0, 4 n0, …` (`count` sizes): the sweeps double `N` so that `log₂` of successive error
/// ratios is the observed order.
pub fn doubling(n0: usize, count: usize) -> Vec<usize> {
    (0..count).map(|j| n0 << j).collect()
}

/// One point of a work–precision sweep.
#[derive(Clone, Copy, Debug)]
pub struct SweepPoint {
    /// Steps.
    pub n: usize,
    /// Wall time of the solve, seconds.
    pub seconds: f64,
    /// Max over the nodes of `|Q_k − q(t_k)|∞` against the scene's reference.
    pub error: f64,
}

/// One line of a work–precision plot: a scheme (and its start) swept over doubling `N`.
#[derive(Clone, Debug)]
pub struct SweepLine {
    /// The scheme, as the legend shows it.
    pub label: String,
    /// One point per `N` that solved, increasing.
    pub points: Vec<SweepPoint>,
    /// The sizes at which the scheme failed, with the error (e.g. the direct scheme collapsing
    /// at Kepler's perihelion on a coarse grid): reported, not hidden.
    pub failures: Vec<(usize, String)>,
}

impl SweepLine {
    /// The observed order between successive points, `ln(e_N / e_{N'}) / ln(N' / N)`
    /// (`log₂(e_N / e_{2N})` on a doubling sweep).
    pub fn orders(&self) -> Vec<f64> {
        self.points
            .windows(2)
            .map(|w| (w[0].error / w[1].error).ln() / (w[1].n as f64 / w[0].n as f64).ln())
            .collect()
    }
}

/// A curve of a figure.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend entry.
    pub label: String,
    /// `(x, y)` points, in drawing order.
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// A series from its points, thinned to at most 2000 (evenly spaced by index; first and last
    /// kept) so that an SVG of a 10⁵-step run stays small.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        const MAX: usize = 2000;
        let points = if points.len() > MAX {
            let stride = points.len().div_ceil(MAX);
            let last = *points.last().expect("non-empty");
            let mut thinned: Vec<_> = points.into_iter().step_by(stride).collect();
            if thinned.last() != Some(&last) {
                thinned.push(last);
            }
            thinned
        } else {
            points
        };
        Series {
            label: label.into(),
            points,
        }
    }
}

/// A figure with linear axes (trajectories, energy error over time).
#[derive(Clone, Debug)]
pub struct Figure {
    /// File name inside the report folder (`.svg`).
    pub file: String,
    /// Caption.
    pub title: String,
    /// Horizontal axis label.
    pub x_label: String,
    /// Vertical axis label.
    pub y_label: String,
    /// The curves.
    pub series: Vec<Series>,
}

/// Everything one scene contributes to the report.
#[derive(Clone, Debug)]
pub struct SceneReport {
    /// Short name, used for file names (`pendulum`).
    pub name: &'static str,
    /// Section title.
    pub title: String,
    /// What the scene shows and how to read it (markdown).
    pub notes: Vec<String>,
    /// The comparison tables (`Comparison`'s `Display`), printed and copied into the report.
    pub tables: Vec<String>,
    /// What the sweep's errors are measured against.
    pub reference: String,
    /// The work–precision sweep, one line per scheme.
    pub sweep: Vec<SweepLine>,
    /// Trajectories and energy error over time.
    pub figures: Vec<Figure>,
}
