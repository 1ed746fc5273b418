//! The double pendulum (unit masses and lengths, `g = 1`) released from rest with both arms
//! horizontal — the chaotic regime. The mass matrix depends on the configuration, so every
//! step of both schemes is implicit (Newton with the macro's Jacobian), and neither the
//! second-order start nor the Störmer–Verlet structure of separable Lagrangians applies.

use crate::cost::cheapest;
use crate::ivp_scene::{
    Advice, HigherOrderSweeps, IvpScene, Trajectory, Units, all_variants, standard_variants,
};
use crate::reference::ReferenceCurve;
use crate::scene::{Context, SceneReport, SweepLine, doubling};
use std::f64::consts::FRAC_PI_2;
use varembed::{Embedding, Ensemble, Grid, Problem, Scheme, Side, Vector, lagrangian};

/// The double pendulum: `T = v₀² + ½v₁² + v₀v₁ cos(x₀ − x₁)`, `U = −2g cos x₀ − g cos x₁`.
#[lagrangian]
pub fn double_pendulum(x: [f64; 2], v: [f64; 2], g: f64) -> f64 {
    v[0] * v[0]
        + 0.5 * v[1] * v[1]
        + v[0] * v[1] * (x[0] - x[1]).cos()
        + 2.0 * g * x[0].cos()
        + g * x[1].cos()
}

/// `[a, b]`.
pub const INTERVAL: (f64, f64) = (0.0, 10.0);

/// The Euler–Lagrange equation solved for the accelerations, derived by hand (independent of
/// the macro): `M(x) a = r` with `M = [[2, c], [c, 1]]`, `c = cos(x₀ − x₁)`, `s = sin(x₀ − x₁)`,
/// `r = (−v₁² s − 2g sin x₀, v₀² s − g sin x₁)`.
pub fn acceleration(g: f64) -> impl Fn(&[f64], &[f64], f64, &mut [f64]) + Sync {
    move |x: &[f64], v: &[f64], _: f64, a: &mut [f64]| {
        let (s, c) = (x[0] - x[1]).sin_cos();
        let r0 = -v[1] * v[1] * s - 2.0 * g * x[0].sin();
        let r1 = v[0] * v[0] * s - g * x[1].sin();
        let det = 2.0 - c * c;
        a[0] = (r0 - c * r1) / det;
        a[1] = (2.0 * r1 - c * r0) / det;
    }
}

/// The model, `g = 1`.
pub const MODEL: DoublePendulum = DoublePendulum { g: 1.0 };

/// Both arms horizontal, at rest.
pub fn initial_data() -> (Vector<2>, Vector<2>) {
    (Vector::<2>::new(FRAC_PI_2, FRAC_PI_2), Vector::<2>::zeros())
}

/// DOP853 on the hand-derived equations of motion.
pub fn reference() -> ReferenceCurve<2> {
    let (q0, v0) = initial_data();
    ReferenceCurve::dop853(&acceleration(MODEL.g), INTERVAL, q0, v0, 100_000)
}

/// The scene's tables and sweep.
pub fn scene<'a>(
    cx: &Context,
    reference: &'a ReferenceCurve<2>,
) -> IvpScene<'a, DoublePendulum, 2> {
    let (q0, v0) = initial_data();
    IvpScene {
        name: "double-pendulum",
        title: "Double pendulum (chaotic)",
        notes: vec![
            "Unit masses and lengths, `g = 1`, both arms horizontal at rest, `t ∈ [0, 10]`; \
             errors against DOP853 on the hand-derived equations of motion."
                .to_string(),
            "Orders: the three Gauss-FDE− lines are first order. `L` is not separable \
             (`∂²L/∂v²` depends on `x`), so the variational Gauss-FDE− scheme is a one-sided \
             (symplectic-Euler-like) discretisation, not Störmer–Verlet, and a second-order start \
             cannot lift it to order 2. The symmetric midpoint and trapezoidal embeddings are \
             second order in both schemes, separable `L` or not, and Gauss–Legendre with s \
             stages is of order 2s. The errors are measured down to about 1e-11, where the \
             DOP853 reference (tolerance 1e-13) stops being trustworthy on this chaotic motion; \
             the sweeps of the high-order lines stop above it."
                .to_string(),
        ],
        lagrangian: &MODEL,
        interval: INTERVAL,
        q0,
        v0,
        reference,
        exact: false,
        table_n: cx.pick(8000, 1000),
        table_embeddings: vec![
            Embedding::finite_difference(Side::Backward),
            Embedding::midpoint(),
            Embedding::trapezoidal(),
        ],
        sweep: doubling(cx.pick(2000, 1000), cx.pick(6, 4)),
        variants: all_variants(HigherOrderSweeps {
            // Holds the tables' N and 2N: their midpoint and trapezoidal rows are read off it.
            second_order: doubling(1000, cx.pick(7, 3)),
            gauss2: doubling(125, cx.pick(5, 3)),
            gauss4: doubling(15, cx.pick(4, 3)),
        }),
        trajectory: Trajectory::Time,
        units: Units {
            time: "√(l/g)",
            position: "rad",
            energy: "m g l",
        },
        advice: Advice {
            target: 1e-8,
            why: "Every step of every line is implicit here (the mass matrix depends on `x`), so a step of the s-stage system costs a few times a one-step scheme's, while order 2s cuts the number of steps by orders of magnitude.",
        },
    }
}

/// The max error at which the cost of the best higher-order line is set against the best
/// Gauss-FDE− line's.
pub const TARGET: f64 = 1e-8;

/// The note comparing the cost of reaching [`TARGET`]: the cheapest of the `fde` lines (the
/// Gauss-FDE− schemes) against the cheapest of the `higher_order` lines, each measured where its
/// sweep reached the target and extrapolated along its observed order where it did not.
pub fn speed_up(fde: &[SweepLine], higher_order: &[SweepLine]) -> String {
    match (cheapest(fde, TARGET), cheapest(higher_order, TARGET)) {
        (Some(old), Some(new)) => format!(
            "Cost to reach max error {TARGET:.0e}: the best Gauss-FDE− line, {}; the \
             best higher-order line, {}. The higher-order line is {:.0}× faster ({:.0}× fewer \
             steps).",
            old.describe(),
            new.describe(),
            old.seconds / new.seconds,
            old.n / new.n
        ),
        (old, new) => format!(
            "Cost to reach max error {TARGET:.0e}: not computable from this sweep (best \
             Gauss-FDE− line: {}; best higher-order line: {}).",
            old.map_or("none".to_string(), |c| c.describe()),
            new.map_or("none".to_string(), |c| c.describe())
        ),
    }
}

/// Members of the sensitivity ensemble.
pub const ENSEMBLE: usize = 16;

/// The initial spread of the sensitivity ensemble: member `k` starts with its upper angle
/// raised by `k · SPACING` rad.
pub const SPACING: f64 = 1e-9;

/// The sensitivity ensemble's interval: four times the scene's, long enough for the
/// separation of nearby runs to dominate.
pub const ENSEMBLE_INTERVAL: (f64, f64) = (0.0, 40.0);

/// The chaos, measured: Gauss–Legendre with two stages (order 4) from [`ENSEMBLE`] initial
/// conditions [`SPACING`] apart, solved as one [`Ensemble`] (in parallel, each finished member
/// recorded and ticked on the tour's progress bar by the ensemble's callback). Returns the
/// final upper angles, in member order.
pub fn sensitivity(cx: &Context) -> varembed::Result<(usize, Vec<f64>)> {
    let n = cx.pick(16000, 4000);
    let grid = Grid::new(ENSEMBLE_INTERVAL.0, ENSEMBLE_INTERVAL.1, n)?;
    let problem = Problem::new(&MODEL, grid, Embedding::gauss_legendre(2)?);
    let (q0, v0) = initial_data();
    let members: Vec<(Vector<2>, Vector<2>)> = (0..ENSEMBLE)
        .map(|k| (q0 + Vector::<2>::new(k as f64 * SPACING, 0.0), v0))
        .collect();
    cx.progress.inc_length(ENSEMBLE as u64);
    let ensemble = Ensemble::new().with_progress(|done, _| {
        cx.record(
            "double-pendulum",
            &format!("sensitivity ensemble, member {done} to finish"),
            n,
        )
    });
    let finals = problem
        .solve_ivp_ensemble(Scheme::Variational, &members, &ensemble)
        .into_iter()
        .map(|run| run.map(|solution| solution.last()[0]))
        .collect::<varembed::Result<Vec<f64>>>()?;
    Ok((n, finals))
}

/// The note of [`sensitivity`]: how far the final angles of runs that start `SPACING` apart
/// spread.
pub fn sensitivity_note(n: usize, finals: &[f64]) -> String {
    let (lo, hi) = finals
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    let start = (ENSEMBLE - 1) as f64 * SPACING;
    format!(
        "Sensitivity: {ENSEMBLE} runs of Gauss–Legendre s = 2 (N = {n}) whose upper angles start \
         {SPACING:.0e} rad apart ({start:.1e} rad in all), solved as one `Ensemble` in parallel: \
         at t = {} their upper angles spread over {:.2e} rad, {:.1e} times the initial spread: \
         a perturbation of the data, or a rounding error, grows by about as much over the run.",
        ENSEMBLE_INTERVAL.1,
        hi - lo,
        (hi - lo) / start
    )
}

/// The scene, with the cost comparison at [`TARGET`] and the sensitivity ensemble in its notes.
pub fn run(cx: &Context) -> varembed::Result<SceneReport> {
    let mut report = scene(cx, &reference()).run(cx)?;
    let (fde, higher_order) = report.sweep.split_at(standard_variants().len());
    let note = speed_up(fde, higher_order);
    let (n, finals) = sensitivity(cx)?;
    // Before the advice, which closes the notes.
    let at = report.notes.len().saturating_sub(1);
    report.notes.insert(at, note);
    report.notes.insert(at + 1, sensitivity_note(n, &finals));
    Ok(report)
}
