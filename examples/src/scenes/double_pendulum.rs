//! The double pendulum (unit masses and lengths, `g = 1`) released from rest with both arms
//! horizontal — the chaotic regime. The mass matrix depends on the configuration, so every
//! step of both schemes is implicit (Newton with the macro's Jacobian), and neither the
//! second-order start nor the Störmer–Verlet structure of separable Lagrangians applies.

use crate::ivp_scene::{IvpScene, Trajectory, Units, standard_variants};
use crate::reference::ReferenceCurve;
use crate::scene::{Context, SceneReport, doubling};
use std::f64::consts::FRAC_PI_2;
use varembed::{Embedding, Side, Vector, lagrangian};

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
            "Orders: every line is first order. `L` is not separable (`∂²L/∂v²` depends on \
             `x`), so the variational Gauss-FDE− scheme is a one-sided (symplectic-Euler-like) \
             discretisation, not Störmer–Verlet, and a second-order start cannot lift it to \
             order 2. The chaos amplifies every error by the same factor at a fixed end time, so \
             the ratios (and the orders) survive; the errors themselves are large on coarse grids."
                .to_string(),
        ],
        lagrangian: &MODEL,
        interval: INTERVAL,
        q0,
        v0,
        reference,
        exact: false,
        table_n: cx.pick(8000, 1000),
        table_embeddings: vec![Embedding::finite_difference(Side::Backward)],
        sweep: doubling(cx.pick(2000, 1000), cx.pick(6, 4)),
        variants: standard_variants(),
        trajectory: Trajectory::Time,
        units: Units {
            time: "√(l/g)",
            position: "rad",
            energy: "m g l",
        },
    }
}

/// The scene.
pub fn run(cx: &Context) -> varembed::Result<SceneReport> {
    scene(cx, &reference()).run(cx)
}
