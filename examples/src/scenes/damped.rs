//! The paper's example `q̈ + q̇ + q = 0` (§1.2), `q(0) = 1`, `q̇(0) = 0`, exact solution
//! `e^{−t/2}(cos ωt + sin ωt / (2ω))`, `ω = √3/2`, reached two ways:
//!
//! - through the general direct embedding of the operator as written
//!   (`O = d²/dt² + d/dt + 1` under FDE±, [`varembed::DifferentialOperator`]), which needs no
//!   Lagrangian;
//! - as the Euler–Lagrange equation of `L = eᵗ(½v² − ½x²)` (`d/dt(eᵗ q̇) + eᵗ q = eᵗ(q̈ + q̇ + q)`),
//!   with the direct and variational schemes of Gauss-FDE−.
//!
//! All are first order; they differ in where the damping term is evaluated, and the
//! variational scheme of the time-dependent `L` keeps the exact decay of its discrete momentum
//! map rather than the energy (there is no conserved energy).

use crate::ivp_scene::{Advice, HigherOrderSweeps, IvpScene, Trajectory, Units, all_variants};
use crate::reference::ReferenceCurve;
use crate::scene::{Context, Doubling, SceneReport, SweepLine, SweepPoint, doubling};
use varembed::{DifferentialOperator, Embedding, Grid, Side, Vector, lagrangian, max_error};

/// `L = eᵗ(½v² − ½x²)`, whose Euler–Lagrange equation is `eᵗ(q̈ + q̇ + q) = 0`.
#[lagrangian]
pub fn damped(x: f64, v: f64, t: f64) -> f64 {
    t.exp() * (0.5 * v * v - 0.5 * x * x)
}

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
    let label = match side {
        Side::Backward => "general direct embedding FDE− of q̈ + q̇ + q",
        Side::Forward => "general direct embedding FDE+ of q̈ + q̇ + q",
    };
    cx.progress.inc_length((cx.repeats * sizes.count) as u64);
    let mut points = Vec::new();
    for n in sizes.sizes() {
        let grid = Grid::new(INTERVAL.0, INTERVAL.1, n)?;
        let embedding = operator.embed(side, grid);
        let (q, seconds) = cx
            .median_time(|| embedding.solve_ivp(&[Vector::<1>::new(1.0), Vector::<1>::new(0.0)]))?;
        cx.record(NAME, label, n);
        let error = max_error(&grid, &q, |t| reference.q(t));
        points.push(SweepPoint { n, seconds, error });
    }
    Ok(SweepLine {
        label: label.to_string(),
        points,
        failures: Vec::new(),
        statuses: Vec::new(),
    })
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
    Ok(report)
}
