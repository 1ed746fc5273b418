//! A time-dependent Lagrangian: the parametric oscillator (Mathieu equation)
//! `L = ½v² − ½ω²(1 + ε cos Ωt) x²` at the principal resonance `Ω = 2ω`, where the amplitude
//! grows exponentially. Energy is not conserved (`∂L/∂t ≠ 0`); the energy figure shows
//! `E_k − E(q(t_k), q̇(t_k), t_k)` against the reference's energy at the same time.

use crate::ivp_scene::{Advice, HigherOrderSweeps, IvpScene, Trajectory, Units, all_variants};
use crate::reference::ReferenceCurve;
use crate::scene::{Context, SceneReport, doubling};
use varembed::{Embedding, Side, Vector, lagrangian};

/// The parametric oscillator.
#[lagrangian]
pub fn parametric(x: f64, v: f64, t: f64, omega: f64, epsilon: f64, drive: f64) -> f64 {
    0.5 * v * v - 0.5 * omega * omega * (1.0 + epsilon * (drive * t).cos()) * x * x
}

/// `[a, b]`.
pub const INTERVAL: (f64, f64) = (0.0, 20.0);

/// The model: `ω = 1`, `ε = 0.5`, `Ω = 2`.
pub const MODEL: Parametric = Parametric {
    omega: 1.0,
    epsilon: 0.5,
    drive: 2.0,
};

/// DOP853 on the Mathieu equation `q̈ = −ω²(1 + ε cos Ωt) q`, `q(0) = 1`, `q̇(0) = 0`.
pub fn reference() -> ReferenceCurve<1> {
    let Parametric {
        omega,
        epsilon,
        drive,
    } = MODEL;
    let acceleration = move |x: &[f64], _: &[f64], t: f64, a: &mut [f64]| {
        a[0] = -omega * omega * (1.0 + epsilon * (drive * t).cos()) * x[0];
    };
    ReferenceCurve::dop853(
        &acceleration,
        INTERVAL,
        Vector::<1>::new(1.0),
        Vector::<1>::new(0.0),
        20_000,
    )
}

/// The scene's tables and sweep.
pub fn scene<'a>(cx: &Context, reference: &'a ReferenceCurve<1>) -> IvpScene<'a, Parametric, 1> {
    IvpScene {
        name: "parametric",
        title: "Parametric oscillator",
        notes: vec![
            "`L = ½v² − ½(1 + 0.5 cos 2t) x²`, `q(0) = 1`, `q̇(0) = 0` on `[0, 20]`, inside the \
             first resonance tongue; errors against DOP853 on the Mathieu equation."
                .to_string(),
            "`L` depends on `t` but stays separable, so the variational Gauss-FDE− scheme is \
             Störmer–Verlet with the potential at `t_k`: order 2 from the second-order start \
             (whose `q̈(0)` includes the time dependence), order 1 from the Legendre start; the \
             direct scheme is order 1."
                .to_string(),
        ],
        lagrangian: &MODEL,
        interval: INTERVAL,
        q0: Vector::<1>::new(1.0),
        v0: Vector::<1>::new(0.0),
        reference,
        exact: false,
        table_n: cx.pick(4000, 400),
        table_embeddings: vec![
            Embedding::finite_difference(Side::Backward),
            Embedding::midpoint(),
            Embedding::trapezoidal(),
        ],
        sweep: doubling(cx.pick(500, 200), cx.pick(7, 4)),
        variants: all_variants(HigherOrderSweeps {
            // Holds the tables' N and 2N: their midpoint and trapezoidal rows are read off it.
            second_order: doubling(cx.pick(250, 100), cx.pick(7, 4)),
            gauss2: doubling(25, cx.pick(8, 3)),
            gauss4: doubling(15, cx.pick(4, 3)),
        }),
        trajectory: Trajectory::Time,
        units: Units {
            time: "1/ω",
            position: "q(0)",
            energy: "ω² q(0)²",
        },
        advice: Advice {
            target: 1e-10,
            why: "The time dependence costs the Gauss–Legendre integrators nothing (their stages sit at the Gauss nodes in time), so they keep their orders 4 and 8 and the highest order wins.",
        },
    }
}

/// The scene.
pub fn run(cx: &Context) -> varembed::Result<SceneReport> {
    scene(cx, &reference()).run(cx)
}
