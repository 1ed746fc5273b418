//! What a scene hands to the report: its comparison tables, its work–precision sweep and the
//! curves to plot. Nothing here knows about plotting or files.

use indicatif::ProgressBar;
use std::sync::{Mutex, PoisonError};
use std::time::Duration;
use varembed::{
    ComparedSolution, Convergence, Embedding, OrderStatus, Scheme, Solution, observed_orders,
};

/// How many times the full tour solves each grid it times; the time it reports is the median.
/// One measurement on a shared machine can be several times too slow (a scheduler pause, a
/// cache flushed by another process), which puts kinks into a work–precision line; the median
/// of five ignores two such outliers, and keeps the full tour at a few times its single-solve
/// cost (a minute or less in release).
pub const TIMING_REPEATS: usize = 5;

/// How much of the tour to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Every scene at the sizes the report is written at.
    Full,
    /// Every scene, every table and every plot, on small grids and short sweeps (seconds, even
    /// unoptimised): what the tour's own test runs.
    Quick,
}

/// One solve of the tour: which scene, which scheme (with its embedding and start) and `N`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Solve {
    /// The scene's file-name stem.
    pub scene: &'static str,
    /// The scheme, its embedding and start, as text.
    pub what: String,
    /// Steps.
    pub n: usize,
}

/// The run-wide settings, the progress bar, and the ledger of every solve (so that the tour's
/// test can check that each grid is solved once: tables are read off the sweeps; the repeated
/// solves of a timing are not in the ledger).
pub struct Context {
    /// Full or quick.
    pub mode: Mode,
    /// One tick per solve, repeats included.
    pub progress: ProgressBar,
    /// How many times each timed grid is solved ([`timed`](Self::timed)):
    /// [`TIMING_REPEATS`] in full mode, 1 in quick mode (its times are not what it is for).
    pub repeats: usize,
    solves: Mutex<Vec<Solve>>,
}

impl Context {
    /// A context drawing on `progress`.
    pub fn new(mode: Mode, progress: ProgressBar) -> Self {
        let repeats = match mode {
            Mode::Full => TIMING_REPEATS,
            Mode::Quick => 1,
        };
        Context {
            mode,
            progress,
            repeats,
            solves: Mutex::new(Vec::new()),
        }
    }

    /// The same context timing each grid `repeats` times (at least once).
    pub fn with_repeats(mut self, repeats: usize) -> Self {
        self.repeats = repeats.max(1);
        self
    }

    /// A context whose progress bar draws nothing (tests).
    pub fn hidden(mode: Mode) -> Self {
        Context::new(mode, ProgressBar::hidden())
    }

    /// `full` in full mode, `quick` in quick mode.
    pub fn pick<T>(&self, full: T, quick: T) -> T {
        match self.mode {
            Mode::Full => full,
            Mode::Quick => quick,
        }
    }

    /// Records one solve of `scene` and advances the progress bar.
    pub fn record(&self, scene: &'static str, what: &str, n: usize) {
        let solve = Solve {
            scene,
            what: what.to_string(),
            n,
        };
        self.solves
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(solve);
        self.progress.inc(1);
    }

    /// Records every size a convergence run attempted (solved or failed).
    pub fn record_run<const D: usize>(
        &self,
        scene: &'static str,
        what: &str,
        run: &Convergence<Solution<D>>,
    ) {
        let sizes = run.levels.iter().map(|l| l.n());
        for n in sizes.chain(run.failures.iter().map(|(n, _)| *n)) {
            self.record(scene, what, n);
        }
    }

    /// Runs `run` [`repeats`](Self::repeats) times and returns the first run with the wall
    /// time of each level replaced by the median of that level's times over the runs, matched
    /// by `N` (the solutions, errors and failures are the first run's: the runs are
    /// deterministic, only their times differ). The runs after the first only tick the
    /// progress bar: the caller records the returned run in the ledger, once.
    pub fn timed<S: ComparedSolution>(
        &self,
        mut run: impl FnMut() -> Convergence<S>,
    ) -> Convergence<S> {
        let mut first = run();
        let mut times: Vec<Vec<Duration>> = first
            .levels
            .iter()
            .map(|l| l.wall_time.into_iter().collect())
            .collect();
        for _ in 1..self.repeats {
            // Only the times are kept: the solutions of a repeat are dropped at once.
            let again = run();
            self.progress
                .inc((again.levels.len() + again.failures.len()) as u64);
            for (level, times) in first.levels.iter().zip(&mut times) {
                if let Some(repeated) = again.level(level.n()) {
                    times.extend(repeated.wall_time);
                }
            }
        }
        for (level, times) in first.levels.iter_mut().zip(times) {
            // An untimed study (`CompareOptions::timing` off) has no times to take a median of.
            level.wall_time = (!times.is_empty()).then(|| median(times));
        }
        first
    }

    /// Calls `solve` [`repeats`](Self::repeats) times, timing each call, and returns the first
    /// call's result with the median time in seconds; the repeats only tick the progress bar.
    /// Stops at the first error.
    pub fn median_time<T, E>(
        &self,
        mut solve: impl FnMut() -> Result<T, E>,
    ) -> Result<(T, f64), E> {
        let mut times = Vec::with_capacity(self.repeats);
        let started = std::time::Instant::now();
        let first = solve()?;
        times.push(started.elapsed());
        for _ in 1..self.repeats {
            let started = std::time::Instant::now();
            solve()?;
            times.push(started.elapsed());
            self.progress.inc(1);
        }
        Ok((first, median(times).as_secs_f64()))
    }

    /// Every solve recorded so far, in order.
    pub fn solves(&self) -> Vec<Solve> {
        self.solves
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone()
    }
}

/// The median of `times` (the mean of the two middle ones for an even count; zero for none).
pub fn median(mut times: Vec<Duration>) -> Duration {
    times.sort();
    let k = times.len();
    match k {
        0 => Duration::ZERO,
        _ if k % 2 == 1 => times[k / 2],
        _ => (times[k / 2 - 1] + times[k / 2]) / 2,
    }
}

/// `N = n0, 2 n0, 4 n0, …` (`count` sizes): the sweeps double `N` so that `log₂` of successive
/// error ratios is the observed order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Doubling {
    /// The coarsest `N`.
    pub n0: usize,
    /// How many sizes.
    pub count: usize,
}

impl Doubling {
    /// The sizes, increasing.
    pub fn sizes(&self) -> Vec<usize> {
        (0..self.count).map(|j| self.n0 << j).collect()
    }

    /// The finest `N`.
    pub fn finest(&self) -> usize {
        self.n0 << self.count.saturating_sub(1)
    }

    /// Whether `n` is one of the sizes.
    pub fn contains(&self, n: usize) -> bool {
        self.sizes().contains(&n)
    }
}

/// `n0, 2 n0, 4 n0, …` (`count` sizes).
pub fn doubling(n0: usize, count: usize) -> Doubling {
    Doubling { n0, count }
}

/// A line that a scene sweeps itself: a scheme of an embedding, over its own `N`.
#[derive(Clone, Copy, Debug)]
pub struct SchemeLine {
    /// Legend entry.
    pub label: &'static str,
    /// The embedding.
    pub embedding: Embedding,
    /// Direct or variational.
    pub scheme: Scheme,
    /// The `N` of the line.
    pub sizes: Doubling,
}

impl SchemeLine {
    /// `scheme` of `embedding` over `sizes`, shown as `label`.
    pub fn new(label: &'static str, embedding: Embedding, scheme: Scheme, sizes: Doubling) -> Self {
        SchemeLine {
            label,
            embedding,
            scheme,
            sizes,
        }
    }
}

/// One point of a work–precision sweep.
#[derive(Clone, Copy, Debug)]
pub struct SweepPoint {
    /// Steps.
    pub n: usize,
    /// Wall time of the solve, seconds: the median of [`Context::repeats`] solves of the grid.
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
    /// The library's [`OrderStatus`] of each of [`orders`](Self::orders), when the line was
    /// read from a convergence run (empty otherwise: the orders are then printed unmarked).
    pub statuses: Vec<OrderStatus>,
}

impl SweepLine {
    /// The line of a convergence run against a reference: per solved `N`, its wall time and
    /// error as the library measured them (a level without an error, i.e. a run without a
    /// reference, gives no point).
    pub fn from_run<const D: usize>(
        label: impl Into<String>,
        run: &Convergence<Solution<D>>,
    ) -> Self {
        let points: Vec<SweepPoint> = run
            .levels
            .iter()
            .filter_map(|level| {
                Some(SweepPoint {
                    n: level.n(),
                    // A work–precision point needs the time: an untimed level has none.
                    seconds: level.wall_time?.as_secs_f64(),
                    error: level.error?,
                })
            })
            .collect();
        // The statuses follow the run's error estimates; they line up with the points only
        // when every level has an error and none failed.
        let statuses = if run.failures.is_empty() && points.len() == run.levels.len() {
            run.order_statuses()
        } else {
            Vec::new()
        };
        SweepLine {
            label: label.into(),
            points,
            failures: run
                .failures
                .iter()
                .map(|(n, e)| (*n, e.to_string()))
                .collect(),
            statuses,
        }
    }

    /// The library's observed order between successive points
    /// ([`varembed::observed_order`]: `log₂(e_N / e_{2N})` on a doubling sweep), the
    /// same numbers as the orders of the run the line was read from.
    pub fn orders(&self) -> Vec<f64> {
        let errors: Vec<(usize, f64)> = self.points.iter().map(|p| (p.n, p.error)).collect();
        observed_orders(&errors)
    }

    /// [`orders`](Self::orders) as printed, each followed by the mark of its status
    /// ([`OrderStatus::mark`]).
    pub fn marked_orders(&self) -> Vec<String> {
        self.orders()
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let mark = self.statuses.get(i).map_or("", |s| s.mark());
                format!("{p:.2}{mark}")
            })
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
    /// The comparison tables (`Comparison`'s `{:#}`: without the legend, which the tour
    /// prints once, [`console::table_legend`](crate::console::table_legend)), printed with
    /// `--verbose` and copied into the report.
    pub tables: Vec<String>,
    /// What the sweep's errors are measured against.
    pub reference: String,
    /// The work–precision sweep, one line per scheme.
    pub sweep: Vec<SweepLine>,
    /// The max error at which the scene's advice compares the lines (the cheapest line to
    /// reach it is the scene's best), if it gives advice.
    pub advice_target: Option<f64>,
    /// Trajectories and energy error over time.
    pub figures: Vec<Figure>,
}

/// A comparison table that could not be built, as text: what it would have compared, then one
/// row per scheme with the error its run gave at `n` (or that it solved), and the comparison's
/// own error when neither run failed there. A run that fails is a row of the report, not a
/// crash of the tour.
pub fn failed_table<const D: usize>(
    embedding: Embedding,
    n: usize,
    runs: [(&str, &Convergence<Solution<D>>); 2],
    error: &varembed::Error,
) -> String {
    let kind = runs[0].1.kind;
    let mut table = format!("{kind} under {embedding}, N = {n}: no comparison\n");
    table += &format!("  {:<12} result\n", "scheme");
    let mut any = false;
    for (name, run) in runs {
        let row = match run.failures.iter().find(|(m, _)| *m == n) {
            Some((_, e)) => {
                any = true;
                format!("failed: {e}")
            }
            None if run.level(n).is_some() => "solved".to_string(),
            None => "not run on this N".to_string(),
        };
        table += &format!("  {name:<12} {row}\n");
    }
    if !any {
        table += &format!("  the comparison failed: {error}\n");
    }
    table.trim_end().to_string()
}
