//! The harmonic oscillator `L = ½v² − ½ω²x²`, `q(0) = 1`, `q̇(0) = 0` on `[0, 20]`: the one
//! scene with a closed-form solution of the continuous problem *and* of every discrete scheme
//! (see `tests/tests/classical/harmonic_exact.rs`), so the orders here are the textbook ones.

use crate::ivp_scene::{Advice, HigherOrderSweeps, IvpScene, Trajectory, Units, all_variants};
use crate::reference::ReferenceCurve;
use crate::scene::{Context, SceneReport, doubling};
use varembed::{Embedding, Side, Vector, lagrangian};

/// The harmonic oscillator.
#[lagrangian]
pub fn oscillator(x: f64, v: f64, omega: f64) -> f64 {
    0.5 * v * v - 0.5 * omega * omega * x * x
}

/// `[a, b]`.
pub const INTERVAL: (f64, f64) = (0.0, 20.0);

/// The model, `ω = 1`.
pub const MODEL: Oscillator = Oscillator { omega: 1.0 };

/// The exact solution `cos t`.
pub fn reference() -> ReferenceCurve<1> {
    ReferenceCurve::exact(
        |t: f64| Vector::<1>::new(t.cos()),
        |t: f64| Vector::<1>::new(-t.sin()),
    )
}

/// The scene's tables and sweep.
pub fn scene<'a>(
    cx: &Context,
    model: &'a Oscillator,
    reference: &'a ReferenceCurve<1>,
) -> IvpScene<'a, Oscillator, 1> {
    IvpScene {
        name: "harmonic",
        title: "Harmonic oscillator",
        notes: vec![
            "`L = ½v² − ½x²`, `q(0) = 1`, `q̇(0) = 0` on `[0, 20]`; errors against the exact \
             solution `cos t`."
                .to_string(),
            "Gauss-FDE− is not coherent: the direct scheme damps (its discrete solution is \
             `r^k(…)` with `r < 1`, energy decays), the variational one is Störmer–Verlet \
             (energy bounded). The asymmetric Gauss-FDE− is coherent: both schemes are the same \
             recurrence and each solves the other's equations to round-off. Orders: direct 1; \
             variational 1 from the discrete Legendre start (the start's `O(h)` offset of the \
             positions persists) and 2 from the second-order start."
                .to_string(),
        ],
        lagrangian: model,
        interval: INTERVAL,
        q0: Vector::<1>::new(1.0),
        v0: Vector::<1>::new(0.0),
        reference,
        exact: true,
        table_n: cx.pick(2000, 200),
        table_embeddings: vec![
            Embedding::finite_difference(Side::Backward),
            Embedding::finite_difference(Side::Forward),
            Embedding::asymmetric(Side::Backward),
            Embedding::midpoint(),
            Embedding::trapezoidal(),
        ],
        sweep: doubling(cx.pick(500, 100), cx.pick(7, 4)),
        variants: all_variants(HigherOrderSweeps {
            // Holds the tables' N and 2N: their midpoint and trapezoidal rows are read off it.
            second_order: doubling(cx.pick(250, 100), cx.pick(7, 3)),
            gauss2: doubling(25, cx.pick(8, 3)),
            gauss4: doubling(10, cx.pick(5, 3)),
        }),
        trajectory: Trajectory::Time,
        units: Units {
            time: "1/ω",
            position: "q(0)",
            energy: "ω² q(0)²",
        },
        advice: Advice {
            target: 1e-10,
            why: "The order decides: every halving of `h` divides the error by 2ᵖ, so the order-8 line needs tens of steps per period where the order-2 lines need orders of magnitude more, and one step of its four-stage system is cheap at this size. All variational lines keep the energy bounded over long runs.",
        },
    }
}

/// The scene.
pub fn run(cx: &Context) -> varembed::Result<SceneReport> {
    scene(cx, &MODEL, &reference()).run(cx)
}
