//! A closed planar four-bar linkage in its three link angles under the loop constraint
//! ([`linkage`]): two `#[lagrangian]` constraints wrapped in [`varembed::Holonomic`] and paired,
//! solved by [`varembed::Problem::solve_constrained_ivp`] with direct and variational schemes.
//!
//! The lengths satisfy Grashof's condition strictly (shortest + longest = 3.2 < 3.6, the crank
//! the shortest link, next to the ground): a crank-rocker, whose crank turns fully while the
//! rocker and the coupler swing. The rocker's and the coupler's angles are charts of the loop
//! only between their turning points, which the motion passes twice per crank turn; the crank
//! angle covers the branch, but only through the loop closed in closed form on a chosen
//! assembly branch, which is how the reference is written. The constrained form needs neither.
//!
//! The sweep measures errors against that reference over ten seconds; a long run of 10⁵ steps
//! per line measures the loop's opening `max_i |g_i(Q_k)|` and the energy error at every node.

pub mod linkage;

use self::linkage::{
    CLOSURE, Linkage, angle_difference, branch, chart, energy, initial, opening, potential_range,
    reference,
};
use crate::cost;
use crate::reference::ReferenceCurve;
use crate::scene::{
    Context, Figure, SceneReport, SchemeLine, Series, SweepLine, SweepPoint, doubling,
};
use std::f64::consts::TAU;
use varembed::{ConstrainedSolution, Embedding, Grid, Problem, Scheme, Side, Vector};

/// The scene's file-name stem.
pub const NAME: &str = "four-bar";

/// `[a, b]` of the sweep: about eight crank turns.
pub const INTERVAL: (f64, f64) = (0.0, 10.0);

/// The step of the long runs.
pub const LONG_H: f64 = 0.005;

/// The start of a long run whose energy error gives its band (about four crank turns): a
/// bounded error stays in it, a drifting one leaves it.
pub const EARLY: f64 = 5.0;

/// One line: a scheme under an embedding, swept over its sizes on [`INTERVAL`] and run once
/// for the long run.
pub type Line = SchemeLine;

/// The lines: midpoint (both schemes), trapezoidal (variational) and Gauss-FDE− (both).
pub fn lines(cx: &Context) -> Vec<Line> {
    let second = doubling(cx.pick(500, 200), cx.pick(5, 3));
    let first = doubling(cx.pick(1000, 200), cx.pick(4, 3));
    let (midpoint, fde) = (
        Embedding::midpoint(),
        Embedding::finite_difference(Side::Backward),
    );
    let line = SchemeLine::new;
    vec![
        line(
            "variational midpoint",
            midpoint,
            Scheme::Variational,
            second,
        ),
        line("direct midpoint", midpoint, Scheme::Direct, second),
        line(
            "variational trapezoidal",
            Embedding::trapezoidal(),
            Scheme::Variational,
            second,
        ),
        line("variational FDE−", fde, Scheme::Variational, first),
        line("direct FDE−", fde, Scheme::Direct, first),
    ]
}

/// What the scene reads off one run.
pub struct Run {
    /// `(t_k, max_i |g_i(Q_k)|)`.
    pub opening: Vec<(f64, f64)>,
    /// `(t_k, E_k − E)`: the energy of the projected node values
    /// ([`ConstrainedSolution::node_values`]) against that of the initial data.
    pub energy: Vec<(f64, f64)>,
    /// Crank turns, `(Q_N,0 − Q_0,0) / 2π`.
    pub turns: f64,
    /// How often the rocker reverses (a turning point of its angle, where it is no chart).
    pub reversals: usize,
    /// Newton iterations of the run.
    pub newton_iterations: usize,
    /// Wall time of the solve, seconds.
    pub seconds: f64,
}

impl Run {
    fn read(
        run: &ConstrainedSolution<3, 2>,
        grid: &Grid,
        exact: f64,
        seconds: f64,
    ) -> varembed::Result<Run> {
        let q = &run.solution.q;
        let energies = run.node_values(&Linkage, &CLOSURE)?.energy;
        let energies = energies.expect("the linkage does not depend on t");
        let rocker: Vec<f64> = q.windows(2).map(|w| w[1][2] - w[0][2]).collect();
        let timed = |values: Vec<f64>| values.into_iter().enumerate().map(|(k, y)| (grid.t(k), y));
        Ok(Run {
            opening: timed(q.iter().map(opening).collect()).collect(),
            energy: timed(energies.iter().map(|e| e - exact).collect()).collect(),
            turns: (q[q.len() - 1][0] - q[0][0]) / TAU,
            reversals: rocker.windows(2).filter(|w| w[0] * w[1] < 0.0).count(),
            newton_iterations: run.solution.newton_iterations,
            seconds,
        })
    }

    /// `max_k max_i |g_i(Q_k)|`.
    pub fn max_opening(&self) -> f64 {
        self.opening.iter().map(|(_, g)| *g).fold(0.0, f64::max)
    }

    /// `max max_i |g_i(Q_k)|` over the first tenth of the nodes and over the last: a loop
    /// that opens as the run goes on would show a larger second.
    pub fn opening_tenths(&self) -> (f64, f64) {
        let tenth = (self.opening.len() / 10).max(1);
        let max = |s: &[(f64, f64)]| s.iter().map(|(_, g)| *g).fold(0.0, f64::max);
        (
            max(&self.opening[..tenth]),
            max(&self.opening[self.opening.len() - tenth..]),
        )
    }

    /// `max_k |E_k − E|`.
    pub fn max_energy_error(&self) -> f64 {
        self.energy.iter().map(|(_, e)| e.abs()).fold(0.0, f64::max)
    }

    /// The least and greatest `E_k − E` for `t_k ≤ EARLY`, and the mean of `E_k − E` over the
    /// last tenth of the nodes.
    pub fn energy_trend(&self) -> ((f64, f64), f64) {
        let early = self.energy.iter().take_while(|(t, _)| *t <= EARLY);
        let band = early.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (_, e)| {
            (lo.min(*e), hi.max(*e))
        });
        let last = &self.energy[self.energy.len() - (self.energy.len() / 10).max(1)..];
        let mean = last.iter().map(|(_, e)| e).sum::<f64>() / last.len() as f64;
        (band, mean)
    }
}

fn solve(
    line: &Line,
    grid: Grid,
    (q0, v0): (Vector<3>, Vector<3>),
) -> varembed::Result<ConstrainedSolution<3, 2>> {
    let problem = Problem::new(&Linkage, grid, line.embedding);
    problem.solve_constrained_ivp(line.scheme, &CLOSURE, q0, v0)
}

/// `max_k |Q_k − q(t_k)|∞`, `q` the reference's crank angle closed into the loop by [`chart`].
fn error(q: &[Vector<3>], grid: &Grid, reference: &ReferenceCurve<1>, side: f64) -> f64 {
    let at = |k: usize, q: &Vector<3>| {
        let exact = chart(reference.q(grid.t(k))[0], side);
        (0..3)
            .map(|i| angle_difference(q[i], exact[i]).abs())
            .fold(0.0, f64::max)
    };
    q.iter()
        .enumerate()
        .map(|(k, q)| at(k, q))
        .fold(0.0, f64::max)
}

/// A line's sweep with its run at `n` (every line's sizes hold it) or the error there.
type Swept = (Line, SweepLine, Result<Run, String>);

/// Every line swept against the reference, and the reference's name.
fn sweep(
    cx: &Context,
    initial: (Vector<3>, Vector<3>),
    n: usize,
) -> varembed::Result<(Vec<Swept>, String)> {
    let reference = reference(&initial.0, &initial.1, INTERVAL);
    let (side, exact) = (branch(&initial.0), energy(&initial.0, &initial.1));
    let lines = lines(cx);
    let grids: usize = lines.iter().map(|l| l.sizes.count).sum();
    cx.progress.inc_length((cx.repeats * grids) as u64);
    let mut out = Vec::with_capacity(lines.len());
    for line in lines {
        let mut swept = SweepLine {
            label: line.label.to_string(),
            points: Vec::new(),
            failures: Vec::new(),
            statuses: Vec::new(),
        };
        let mut at_n = Err("not solved".to_string());
        for size in line.sizes.sizes() {
            let grid = Grid::new(INTERVAL.0, INTERVAL.1, size)?;
            cx.record(NAME, &format!("{} {}", line.embedding, line.scheme), size);
            let solved = cx.median_time(|| solve(&line, grid, initial));
            let run = solved.and_then(|(run, seconds)| {
                let error = error(&run.solution.q, &grid, &reference, side);
                swept.points.push(SweepPoint {
                    n: size,
                    seconds,
                    error,
                });
                Run::read(&run, &grid, exact, seconds)
            });
            if let Err(e) = &run {
                swept.failures.push((size, e.to_string()));
            }
            if size == n {
                at_n = run.map_err(|e| e.to_string());
            }
        }
        out.push((line, swept, at_n));
    }
    Ok((out, reference.name))
}

/// Every line for `steps` steps of [`LONG_H`] from `initial`, each solved once and timed once.
pub fn long_runs(
    cx: &Context,
    initial: (Vector<3>, Vector<3>),
    steps: usize,
) -> varembed::Result<Vec<(Line, Result<Run, String>)>> {
    let grid = Grid::new(0.0, LONG_H * steps as f64, steps)?;
    let exact = energy(&initial.0, &initial.1);
    let lines = lines(cx);
    cx.progress.inc_length(lines.len() as u64);
    let mut out = Vec::with_capacity(lines.len());
    for line in lines {
        let what = format!("long run, {} {}", line.embedding, line.scheme);
        cx.record(NAME, &what, steps);
        let started = std::time::Instant::now();
        let run = solve(&line, grid, initial)
            .and_then(|run| Run::read(&run, &grid, exact, started.elapsed().as_secs_f64()));
        out.push((line, run.map_err(|e| e.to_string())));
    }
    Ok(out)
}

/// A table row: the line's label, then its columns, or its error across them.
fn row(label: &str, run: &Result<Run, String>, columns: impl Fn(&Run) -> String) -> String {
    let columns = match run {
        Ok(run) => columns(run),
        Err(e) => format!("failed: {e}"),
    };
    format!("  {label:<24} {columns}\n")
}

/// The sweep's table at `n` and the long runs' table.
fn tables(
    n: usize,
    swept: &[Swept],
    long: &[(Line, Result<Run, String>)],
    steps: usize,
) -> Vec<String> {
    let mut at_n = format!(
        "four-bar linkage on [{}, {}], N = {n}\n  {:<24} {:>10} {:>12} {:>10} {:>7} {:>9}\n",
        INTERVAL.0,
        INTERVAL.1,
        "line",
        "max error",
        "max |g(Q_k)|",
        "max |ΔE|",
        "Newton",
        "time (s)"
    );
    for (line, sweep, run) in swept {
        let point = sweep.points.iter().find(|p| p.n == n);
        let error = point.map_or(f64::NAN, |p| p.error);
        at_n += &row(line.label, run, |run| {
            format!(
                "{error:>10.2e} {:>12.1e} {:>10.1e} {:>7} {:>9.2e}",
                run.max_opening(),
                run.max_energy_error(),
                run.newton_iterations,
                run.seconds
            )
        });
    }
    // The loop's opening over the first and the last tenth of the nodes; the energy error's
    // range up to `EARLY` and its mean over the last tenth.
    let mut long_table = format!(
        "four-bar linkage, {steps} steps of h = {LONG_H}\n  {:<24} {:>12} {:>12} {:>9} {:>21} \
         {:>10} {:>6} {:>8} {:>9}\n",
        "line",
        "|g|, first ⅒",
        "|g|, last ⅒",
        "max |ΔE|",
        format!("ΔE range, t ≤ {EARLY}"),
        "ΔE, last ⅒",
        "turns",
        "Newton",
        "time (s)"
    );
    for (line, run) in long {
        long_table += &row(line.label, run, |run| {
            let ((lo, hi), late) = run.energy_trend();
            let (first, last) = run.opening_tenths();
            format!(
                "{first:>12.1e} {last:>12.1e} {:>9.1e} {lo:>9.1e} to {hi:>8.1e} {late:>10.1e} \
                 {:>6.1} {:>8} {:>9.2e}",
                run.max_energy_error(),
                run.turns,
                run.newton_iterations,
                run.seconds
            )
        });
    }
    vec![at_n, long_table]
        .into_iter()
        .map(|t| t.trim_end().to_string())
        .collect()
}

/// What the energy error of a long run does, in words and numbers: bounded when its mean over
/// the last tenth is within the range it took up to [`EARLY`]. `above` is the energy above the
/// potential's minimum on the loop: the most a run can lose and still be on it.
fn energy_verdict(run: &Run, above: f64) -> String {
    let ((lo, hi), late) = run.energy_trend();
    let range = format!("`[{lo:.1e}, {hi:.1e}]` for `t ≤ {EARLY}`");
    if (lo..=hi).contains(&late) {
        format!(
            "stays bounded (mean over the last tenth {late:.1e}, within its range {range}; max \
             `|E_k − E|` {:.1e})",
            run.max_energy_error()
        )
    } else {
        let way = if late > hi { "up" } else { "down" };
        format!(
            "drifts {way}: its mean over the last tenth is {late:.2e}, {:.0}% of the energy \
             above the potential's minimum, outside its range {range} (the crank turns {:.1} \
             times)",
            100.0 * late.abs() / above,
            run.turns
        )
    }
}

/// The orders of the sweep, and what a line that does not converge on it does instead.
fn orders_note(swept: &[Swept]) -> String {
    let mut orders = Vec::new();
    let mut stalled = Vec::new();
    for (line, sweep, run) in swept {
        let Some(order) = sweep.orders().last().copied() else {
            continue;
        };
        orders.push(format!("{} {order:.2}", line.label));
        if order < 0.5 {
            let errors: Vec<String> = sweep
                .points
                .iter()
                .map(|p| format!("{:.2}", p.error))
                .collect();
            let falls = run
                .as_ref()
                .is_ok_and(|run| run.energy_trend().1 < run.energy_trend().0.0);
            stalled.push(format!(
                " The {} line does not converge on these `N`: its max error is {} (π is the most \
                 an angle can be off){}.",
                line.label,
                errors.join(", "),
                if falls {
                    ": its energy falls (tables), and the crank falls behind the reference"
                } else {
                    ""
                }
            ));
        }
    }
    format!(
        "Observed orders between the two finest `N`: {}.{}",
        orders.join(", "),
        stalled.concat()
    )
}

/// The scene.
pub fn run(cx: &Context) -> varembed::Result<SceneReport> {
    let initial = initial()?;
    let (q0, v0) = initial;
    let n = cx.pick(4000, 400);
    let (swept, reference) = sweep(cx, initial, n)?;
    let steps = cx.pick(100_000, 5_000);
    let long = long_runs(cx, initial, steps)?;
    let (low, high) = potential_range(branch(&q0));
    let e0 = energy(&q0, &v0);
    let sweep: Vec<SweepLine> = swept.iter().map(|(_, line, _)| line.clone()).collect();
    let solved = || {
        long.iter()
            .filter_map(|(line, run)| Some((line, run.as_ref().ok()?)))
    };
    let over = |scheme: Scheme, read: fn(&Run) -> f64| {
        solved()
            .filter(|(line, _)| line.scheme == scheme)
            .map(|(_, run)| read(run))
            .fold(0.0, f64::max)
    };
    let verdicts: Vec<String> = solved()
        .map(|(line, run)| format!("{} {}", line.label, energy_verdict(run, e0 - low)))
        .collect();
    let failed: String = long
        .iter()
        .filter_map(|(line, run)| Some(format!(" {} failed: {}.", line.label, run.as_ref().err()?)))
        .collect();
    let (witness, (turns, reversals)) = solved()
        .next()
        .map_or(("no line", (f64::NAN, 0)), |(line, run)| {
            (line.label, (run.turns, run.reversals))
        });
    let target = 1e-3;
    let notes = vec![
        format!(
            "A crank (length 1, ground pivot `(0, 0)`), coupler (2.2) and rocker (1.6, ground \
             pivot `(2, 0)`): uniform rods under gravity 9.81, unknowns the three link angles, \
             the loop closed by two `#[lagrangian]` constraints wrapped in `Holonomic` and \
             paired. Initial data: `project_initial_data` of the crank horizontal turning at \
             {} with the coupler and rocker guessed, `q(0) = ({:.4}, {:.4}, {:.4})`, crank rate \
             {:.4}; energy `E = {:.4}`, above the potential's maximum {high:.2} on the loop \
             (minimum {low:.2}). Grashof's condition holds (1 + 2.2 < 2 + 1.6): the crank turns \
             fully while the rocker and coupler swing, so the rocker's (and the coupler's) angle \
             is a chart of the loop only between its turning points. The crank angle covers the \
             branch of the motion, but only through the loop closed in closed form on a chosen \
             assembly branch: the reference is written in it by hand and integrated by DOP853, \
             and errors are `max_k |Q_k − q(t_k)|∞` over the three angles on `[0, 10]`.",
            linkage::CRANK_RATE,
            q0[0],
            q0[1],
            q0[2],
            v0[0],
            e0,
        ),
        orders_note(&swept),
        format!(
            "Long runs, {steps} steps of `h = {LONG_H}` from the same data (under {witness} the \
             crank turns {turns:.1} times and the rocker reverses {reversals} times). The loop stays closed \
             at every node of every run (figure `{NAME}-constraint.svg`): `max_k max_i \
             |g_i(Q_k)|` is {:.1e} over the variational runs and {:.1e} over the direct ones, \
             each step solving the constraint at its newest node by Newton's method whatever \
             the scheme. It does not grow along the run: at most {:.1e} over the first tenth of \
             the nodes and {:.1e} over the last, over all runs.",
            over(Scheme::Variational, Run::max_opening),
            over(Scheme::Direct, Run::max_opening),
            over(Scheme::Variational, |r| r.opening_tenths().0)
                .max(over(Scheme::Direct, |r| r.opening_tenths().0)),
            over(Scheme::Variational, |r| r.opening_tenths().1)
                .max(over(Scheme::Direct, |r| r.opening_tenths().1)),
        ),
        format!(
            "The energy error of the projected node values over the long runs (figure \
             `{NAME}-energy.svg`; the midpoint pair alone in `{NAME}-energy-midpoint.svg`, the \
             variational lines alone in `{NAME}-energy-variational.svg`): {}.{failed}",
            verdicts.join("; "),
        ),
        cost::advice(
            &sweep,
            target,
            "Every line solves the same saddle-point system of five unknowns (three angles, two \
             multipliers) per Newton iteration: the order decides.",
        ),
    ];
    // The direct Gauss-FDE− run's fall dwarfs the others' errors: two more figures leave it out.
    let series = |keep: fn(&Line) -> bool, read: fn(&Run) -> &Vec<(f64, f64)>| {
        solved()
            .filter(|(line, _)| keep(line))
            .map(|(line, run)| Series::new(line.label, read(run).clone()))
            .collect()
    };
    let figure = |file: &str, what: &str, y_label: &str, series| Figure {
        file: format!("{NAME}-{file}.svg"),
        title: format!("Four-bar linkage: {what}, {steps} steps of h = {LONG_H}"),
        x_label: "time t (s)".to_string(),
        y_label: y_label.to_string(),
        series,
    };
    let figures = vec![
        figure(
            "constraint",
            "loop opening",
            "max_i |g_i(Q_k)| (crank lengths)",
            series(|_| true, |run| &run.opening),
        ),
        figure(
            "energy",
            "energy error",
            "energy error E_k − E",
            series(|_| true, |run| &run.energy),
        ),
        figure(
            "energy-midpoint",
            "energy error of the midpoint schemes",
            "energy error E_k − E",
            series(
                |line| line.embedding == Embedding::midpoint(),
                |run| &run.energy,
            ),
        ),
        figure(
            "energy-variational",
            "energy error of the variational schemes",
            "energy error E_k − E",
            series(|line| line.scheme == Scheme::Variational, |run| &run.energy),
        ),
    ];
    Ok(SceneReport {
        name: NAME,
        title: "Four-bar linkage under its loop constraint".to_string(),
        notes,
        tables: tables(n, &swept, &long, steps),
        reference: format!("crank-angle form by {reference}"),
        sweep,
        advice_target: Some(target),
        figures,
    })
}
