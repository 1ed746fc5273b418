//! The paper's example `q̈ + q̇ + q = 0` (§1.2), `q(0) = 1`, `q̇(0) = 0`, exact solution
//! `e^{−t/2}(cos ωt + sin ωt / (2ω))`, `ω = √3/2`, reached three ways:
//!
//! - through the general direct embedding of the operator as written
//!   (`O = d²/dt² + d/dt + 1` under FDE±, [`varembed::DifferentialOperator`]), which needs no
//!   Lagrangian;
//! - as the Euler–Lagrange equation of `L = eᵗ(½v² − ½x²)` (`d/dt(eᵗ q̇) + eᵗ q = eᵗ(q̈ + q̇ + q)`),
//!   with the schemes of every embedding the initial value scenes sweep;
//! - by forcing: the oscillator `½v² − ½x²` under the friction `f = −q̇` of the Rayleigh
//!   function `R = ½γv²`, `γ = 1` ([`varembed::Forced`], [`varembed::Rayleigh`]), under the
//!   midpoint, trapezoidal, Gauss–Legendre (`s = 2`) and Gauss-FDE− embeddings; with the energy
//!   balance `E_k − E_0 = W_k` of its runs ([`varembed::Forced::work`]).
//!
//! The FDE± lines are first order whatever the route (their one-sided differences are, and a
//! force that depends on `q̇` keeps them so); the symmetric embeddings are second order and
//! Gauss–Legendre of order `2s` on both Lagrangian routes.

use crate::ivp_scene::{Advice, HigherOrderSweeps, IvpScene, Trajectory, Units, all_variants};
use crate::reference::ReferenceCurve;
use crate::scene::{Context, Doubling, SceneReport, SchemeLine, SweepLine, SweepPoint, doubling};
use varembed::{
    CompareOptions, DifferentialOperator, Embedding, Forced, Grid, Problem, Rayleigh, Reference,
    Scheme, Side, Start, Vector, lagrangian, max_error,
};

/// `L = eᵗ(½v² − ½x²)`, whose Euler–Lagrange equation is `eᵗ(q̈ + q̇ + q) = 0`.
#[lagrangian]
pub fn damped(x: f64, v: f64, t: f64) -> f64 {
    t.exp() * (0.5 * v * v - 0.5 * x * x)
}

/// The undamped oscillator `L = ½v² − ½x²`, the Lagrangian of the route by forcing.
#[lagrangian]
pub fn oscillator(x: f64, v: f64) -> f64 {
    0.5 * v * v - 0.5 * x * x
}

/// The Rayleigh dissipation function `R = ½γv²` of linear friction, `f = −∂R/∂v = −γv`.
#[lagrangian]
pub fn friction(_x: f64, v: f64, gamma: f64) -> f64 {
    0.5 * gamma * v * v
}

/// `q̈ + q̇ + q = 0` by forcing: the oscillator under the friction `−q̇` (`γ = 1`).
pub const FORCED: Forced<Oscillator, Rayleigh<Friction>> =
    Forced::new(Oscillator, Rayleigh(Friction { gamma: 1.0 }));

/// The scene's file-name stem.
pub const NAME: &str = "damped";

/// `[a, b]`.
pub const INTERVAL: (f64, f64) = (0.0, 10.0);

/// The exact solution and its derivative.
pub fn exact() -> ReferenceCurve<1> {
    let w = 3f64.sqrt() / 2.0;
    ReferenceCurve::exact(
        move |t: f64| {
            Vector::<1>::new((-t / 2.0).exp() * ((w * t).cos() + (w * t).sin() / (2.0 * w)))
        },
        move |t: f64| Vector::<1>::new(-(-t / 2.0).exp() * (w * t).sin() / w),
    )
}

/// The legend entry of the general direct embedding under FDEσ.
fn general_label(side: Side) -> String {
    let sign = match side {
        Side::Backward => "−",
        Side::Forward => "+",
    };
    format!("general direct embedding FDE{sign} of q̈ + q̇ + q")
}

/// The general direct embedding of `q̈ + q̇ + q` under FDEσ, swept over `sizes`, from the
/// initial data `q(0) = 1`, `q̇(0) = 0` of the Lagrangian schemes: its start nodes are their
/// Taylor polynomial (`Q_0 = 1`, `Q_1 = 1 + h·0`), as the operator's `solve_ivp` builds them;
/// from rest this `Q_1` is also the discrete Legendre start of `L` (`eᵗ¹ (Q_1 − Q_0)/h = 0`), so
/// the line compares with the Lagrangian schemes from the same two nodes.
/// The error and the orders are the library's definitions ([`max_error`],
/// [`SweepLine::orders`]).
pub fn general_embedding_sweep(
    cx: &Context,
    side: Side,
    sizes: Doubling,
    reference: &ReferenceCurve<1>,
) -> varembed::Result<SweepLine> {
    let operator = DifferentialOperator::<1>::new()
        .linear(2, 1.0)
        .linear(1, 1.0)
        .linear(0, 1.0);
    let label = general_label(side);
    cx.progress.inc_length((cx.repeats * sizes.count) as u64);
    let mut points = Vec::new();
    for n in sizes.sizes() {
        let grid = Grid::new(INTERVAL.0, INTERVAL.1, n)?;
        let embedding = operator.embed(side, grid);
        let (q, seconds) = cx
            .median_time(|| embedding.solve_ivp(&[Vector::<1>::new(1.0), Vector::<1>::new(0.0)]))?;
        cx.record(NAME, &label, n);
        let error = max_error(&grid, &q, |t| reference.q(t));
        points.push(SweepPoint { n, seconds, error });
    }
    Ok(SweepLine {
        label,
        points,
        failures: Vec::new(),
        statuses: Vec::new(),
    })
}

/// The lines of the route by forcing: both schemes of the midpoint and trapezoidal embeddings
/// (second order), Gauss–Legendre `s = 2` (order 4), both schemes of Gauss-FDE− (first
/// order), each over the sizes of the same embedding's line of `L = eᵗ(½v² − ½x²)`.
pub fn forced_lines(cx: &Context) -> Vec<SchemeLine> {
    let second_order = doubling(cx.pick(250, 100), cx.pick(7, 3));
    let first_order = doubling(cx.pick(500, 100), cx.pick(7, 4));
    let gauss2 = doubling(25, cx.pick(8, 3));
    let (midpoint, trapezoidal) = (Embedding::midpoint(), Embedding::trapezoidal());
    let fde = Embedding::finite_difference(Side::Backward);
    let line = SchemeLine::new;
    vec![
        line(
            "forced: direct midpoint",
            midpoint,
            Scheme::Direct,
            second_order,
        ),
        line(
            "forced: variational midpoint",
            midpoint,
            Scheme::Variational,
            second_order,
        ),
        line(
            "forced: direct trapezoidal",
            trapezoidal,
            Scheme::Direct,
            second_order,
        ),
        line(
            "forced: variational trapezoidal",
            trapezoidal,
            Scheme::Variational,
            second_order,
        ),
        line(
            "forced: Gauss–Legendre s = 2",
            Embedding::gauss_legendre(2).expect("2 stages exist"),
            Scheme::Variational,
            gauss2,
        ),
        line("forced: direct FDE−", fde, Scheme::Direct, first_order),
        line(
            "forced: variational FDE−",
            fde,
            Scheme::Variational,
            first_order,
        ),
    ]
}

/// The energy balance of one forced run ([`energy_balance`]).
#[derive(Clone, Copy, Debug)]
pub struct Balance {
    /// The line the run was read off.
    pub label: &'static str,
    /// `max_k |E_k − E_0 − W_k|`.
    pub max_miss: f64,
    /// `W_N`, the work of the friction over the run.
    pub work: f64,
}

/// The energy balance of a forced run: `max_k |E_k − E_0 − W_k|`, with `E_k` the oscillator's
/// energy at the nodes ([`varembed::Solution::node_values`] of the forced model) and `W_k` the
/// work of the friction ([`Forced::work`]); and the work `W_N` at the end.
pub fn energy_balance(solution: &varembed::Solution<1>) -> varembed::Result<(f64, f64)> {
    let energy = solution
        .node_values(&FORCED)?
        .energy
        .expect("the oscillator is autonomous");
    let work = FORCED.work(solution)?;
    let balance = energy
        .iter()
        .zip(&work)
        .map(|(e, w)| (e - energy[0] - w).abs())
        .fold(0.0, f64::max);
    Ok((balance, work[work.len() - 1]))
}

/// The route by forcing: every [`forced_lines`] swept against the exact solution, and the
/// energy balance ([`energy_balance`]) of the variational midpoint and trapezoidal runs at `n`
/// (read off their sweeps, which hold `n`), with their labels.
pub fn forced_sweep(
    cx: &Context,
    reference: &ReferenceCurve<1>,
    n: usize,
) -> varembed::Result<(Vec<SweepLine>, Vec<Balance>)> {
    let lines = forced_lines(cx);
    let grids: usize = lines.iter().map(|l| l.sizes.count).sum();
    cx.progress.inc_length((cx.repeats * grids) as u64);
    let curve = |t: f64| reference.q(t);
    let mut sweep = Vec::with_capacity(lines.len());
    let mut balances = Vec::new();
    for line in lines {
        let grid = Grid::new(INTERVAL.0, INTERVAL.1, line.sizes.n0)?;
        let problem = Problem::new(&FORCED, grid, line.embedding);
        let options = CompareOptions {
            reference: Reference::Exact(&curve),
            start: Start::Legendre,
            order: true,
            timing: true,
        };
        let run =
            cx.timed(|| problem.convergence_ivp(line.scheme, 1.0, 0.0, &options, line.sizes.count));
        let what = format!("forced oscillator: {} {}", line.embedding, line.scheme);
        cx.record_run(NAME, &what, &run);
        let balanced = line.scheme == Scheme::Variational
            && [Embedding::midpoint(), Embedding::trapezoidal()].contains(&line.embedding);
        if let Some(level) = run.level(n).filter(|_| balanced) {
            let (max_miss, work) = energy_balance(&level.solution)?;
            balances.push(Balance {
                label: line.label,
                max_miss,
                work,
            });
        }
        sweep.push(SweepLine::from_run(line.label, &run));
    }
    Ok((sweep, balances))
}

/// The observed order between the two finest `N` of the line labelled `label` (with the mark
/// of its status), `—` when there is no such line.
fn finest_order(lines: &[SweepLine], label: &str) -> String {
    let line = lines.iter().find(|l| l.label == label);
    line.and_then(|l| l.marked_orders().last().cloned())
        .unwrap_or_else(|| "—".to_string())
}

/// The orders of the three routes, embedding by embedding, as a markdown table.
fn orders_table(lines: &[SweepLine]) -> String {
    let mut table = String::from(
        "| embedding | forced, direct | forced, variational | `eᵗ(½v² − ½x²)`, direct | \
         `eᵗ(½v² − ½x²)`, variational |\n| --- | ---: | ---: | ---: | ---: |\n",
    );
    let rows = [
        ("Gauss-FDE−", "FDE−", "FDE−, Legendre start"),
        ("midpoint", "midpoint", "midpoint"),
        ("trapezoidal", "trapezoidal", "trapezoidal"),
    ];
    for (embedding, direct, variational) in rows {
        table += &format!(
            "| {embedding} | {} | {} | {} | {} |\n",
            finest_order(lines, &format!("forced: direct {direct}")),
            finest_order(lines, &format!("forced: variational {direct}")),
            finest_order(lines, &format!("direct {direct}")),
            finest_order(lines, &format!("variational {variational}")),
        );
    }
    let gauss = "Gauss–Legendre s = 2";
    table += &format!(
        "| {gauss} | — | {} | — | {} |\n",
        finest_order(lines, &format!("forced: {gauss}")),
        finest_order(lines, gauss),
    );
    table
}

/// The Lagrangian schemes' tables and sweep.
pub fn scene<'a>(cx: &Context, reference: &'a ReferenceCurve<1>) -> IvpScene<'a, Damped, 1> {
    IvpScene {
        name: NAME,
        title: "q̈ + q̇ + q = 0",
        notes: vec![
            "The paper's example, `q(0) = 1`, `q̇(0) = 0` on `[0, 10]`, errors against the exact \
             solution. The general direct embedding of the operator as written (FDE−: \
             `(Q_k − 2Q_{k−1} + Q_{k−2})/h² + (Q_k − Q_{k−1})/h + Q_k = 0`) is compared with the \
             schemes of `L = eᵗ(½v² − ½x²)`, whose Euler–Lagrange equation is the same ODE \
             multiplied by `eᵗ`."
                .to_string(),
            "Every FDE± line is first order: the one-sided differences of FDE± are, and the \
             time-dependent weight `eᵗ` makes the variational scheme one-sided too (the \
             second-order start cannot help, the recurrence itself is first order). The \
             symmetric midpoint and trapezoidal embeddings are second order in both schemes, and \
             Gauss–Legendre with s stages of order 2s, time-dependent `L` or not."
                .to_string(),
        ],
        lagrangian: &Damped,
        interval: INTERVAL,
        q0: Vector::<1>::new(1.0),
        v0: Vector::<1>::new(0.0),
        reference,
        exact: true,
        table_n: cx.pick(2000, 200),
        table_embeddings: vec![
            Embedding::finite_difference(Side::Backward),
            Embedding::midpoint(),
            Embedding::trapezoidal(),
        ],
        sweep: doubling(cx.pick(500, 100), cx.pick(7, 4)),
        variants: all_variants(HigherOrderSweeps {
            // Holds the tables' N and 2N: their midpoint and trapezoidal rows are read off it.
            second_order: doubling(cx.pick(250, 100), cx.pick(7, 3)),
            gauss2: doubling(25, cx.pick(8, 3)),
            gauss4: doubling(10, cx.pick(4, 3)),
        }),
        trajectory: Trajectory::Time,
        units: Units {
            time: "1/ω₀",
            position: "q(0)",
            energy: "ω₀² q(0)²",
        },
        advice: Advice {
            target: 1e-10,
            why: "The weight `eᵗ` makes FDE− one-sided, but the symmetric midpoint and trapezoidal embeddings stay second order and Gauss–Legendre keeps order 2s: the highest order wins.",
        },
    }
}

/// The scene.
pub fn run(cx: &Context) -> varembed::Result<SceneReport> {
    let reference = exact();
    let scene = scene(cx, &reference);
    let sizes = scene.sweep;
    let mut report = scene.run(cx)?;
    for side in [Side::Backward, Side::Forward] {
        report
            .sweep
            .push(general_embedding_sweep(cx, side, sizes, &reference)?);
    }
    let n = cx.pick(2000, 200);
    let (forced, balances) = forced_sweep(cx, &reference, n)?;
    let general = |side| finest_order(&report.sweep, &general_label(side));
    let (fde_minus, fde_plus) = (general(Side::Backward), general(Side::Forward));
    report.sweep.extend(forced);
    report.notes.push(format!(
        "The route by forcing, `Forced::new(Oscillator, Rayleigh(Friction {{ gamma: 1.0 }}))`: \
         the oscillator `½v² − ½x²` under the friction `f = −∂R/∂v = −q̇` of `R = ½γv²`, the \
         lines `forced: …`. Both Lagrangian routes keep the order of the embedding, 1 under \
         Gauss-FDE− (the friction reads the one-sided velocity), 2 under the midpoint and \
         trapezoidal embeddings, 4 under Gauss–Legendre `s = 2`; the general direct embedding \
         is first order (FDE− {fde_minus}, FDE+ {fde_plus}). Observed orders between the two \
         finest `N` of each line:\n\n{}",
        orders_table(&report.sweep).trim_end(),
    ));
    let balance = balances
        .iter()
        .map(|b| {
            let label = b.label.trim_start_matches("forced: ");
            format!("{:.1e} ({label})", b.max_miss)
        })
        .collect::<Vec<_>>()
        .join(", ");
    report.notes.push(format!(
        "Energy balance of the forced runs at N = {n}: `max_k |E_k − E_0 − W_k|` = {balance}, \
         with `E_k` the oscillator's energy at the nodes (`Solution::node_values` of the forced \
         model) and `W_k` the friction's work (`Forced::work`, the embedding's quadrature of \
         `∫ f·q̇ dt`; the friction takes {:.5} of `E_0 = 0.5` by `t = 10`). The variational \
         midpoint scheme keeps the balance to round-off on this quadratic `L`; the trapezoidal \
         one to its order 2.",
        -balances.first().map_or(f64::NAN, |b| b.work),
    ));
    Ok(report)
}
