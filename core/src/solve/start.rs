//! [`Start`]: how an initial value problem gets its second node, and the second-order start
//! written once for both paths.

use crate::error::{Error, Location, Result};
use crate::solve::nodes::engine::NodeModel;

/// How an initial value problem gets its second node `Q_1` from `q(a)` and `q̇(a)`.
///
/// # Example
///
/// ```
/// use varembed::{Embedding, Grid, Problem, Scheme, Side, Start, lagrangian};
///
/// #[lagrangian]
/// fn oscillator(x: f64, v: f64) -> f64 {
///     0.5 * v * v - 0.5 * x * x
/// }
///
/// // q = cos t: the second-order start gives second-order positions, the default first order.
/// let error = |n: usize, start: Start| -> varembed::Result<f64> {
///     let grid = Grid::new(0.0, 1.0, n)?;
///     let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
///     let q = problem.solve_ivp_with(Scheme::Variational, 1.0, 0.0, start)?.last()[0];
///     Ok((q - 1f64.cos()).abs())
/// };
/// let ratio = |start| -> varembed::Result<f64> { Ok(error(100, start)? / error(200, start)?) };
/// assert!((ratio(Start::SecondOrder)? - 4.0).abs() < 0.2);
/// assert!((ratio(Start::Legendre)? - 2.0).abs() < 0.1);
/// assert_eq!(Start::default(), Start::Legendre);
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Start {
    /// The discrete Legendre transform of the variational scheme
    /// ([`Problem::legendre_start`](crate::Problem::legendre_start)): keeps the discrete
    /// momentum maps exact. Positions first order under Gauss-FDEσ, second order under the
    /// midpoint and trapezoidal embeddings (`p_0 = −D₁L_d(Q_0, Q_1)` of a symmetric `L_d`).
    #[default]
    Legendre,
    /// `Q_1 = Q_0 + h q̇(a) + ½h² q̈(a)` ([`Problem::second_order_start`](crate::Problem::second_order_start)): positions second
    /// order on `L = ½|v|² − U` for the variational schemes.
    SecondOrder,
}

/// `Q_1 = q0 + h v0 + ½h² q̈(a)`, the second-order start of both paths: the acceleration
/// solves the Euler–Lagrange equation at the initial data `(q0, v0, t)`,
/// `L_vv q̈ = ∂L/∂x − L_vx v0 − ∂p/∂t`, with `∂p/∂t` by a central difference in `t` of step
/// `10⁻⁵ (1 + |t|)` (see [`Problem::second_order_start`](crate::Problem::second_order_start)).
/// Errors at step 1: [`Error::SingularJacobian`] when `L_vv` is singular there,
/// [`Error::NotFinite`] when `Q_1` is not finite.
pub(crate) fn second_order_start(
    model: &mut impl NodeModel,
    (q0, v0): (&[f64], &[f64]),
    (t, h): (f64, f64),
) -> Result<Vec<f64>> {
    let d = q0.len();
    let dt = 1e-5 * (1.0 + t.abs());
    let (mut rhs, mut later, mut earlier) = (vec![0.0; d], vec![0.0; d], vec![0.0; d]);
    // `later` is a scratch for the momentum at t until it holds the one at t + dt.
    model.gradient(q0, v0, t, &mut rhs, &mut later);
    model.momentum(q0, v0, t + dt, &mut later);
    model.momentum(q0, v0, t - dt, &mut earlier);
    for ((r, p1), p0) in rhs.iter_mut().zip(&later).zip(&earlier) {
        *r -= (p1 - p0) / (2.0 * dt);
    }
    model.subtract_vx_product(q0, v0, t, v0, &mut rhs);
    let at = Location::Step(1);
    if !model.solve_vv(q0, v0, t, &mut rhs).1 {
        return Err(Error::SingularJacobian { at });
    }
    let q1: Vec<f64> = q0
        .iter()
        .zip(v0)
        .zip(&rhs)
        .map(|((q, v), acceleration)| q + v * h + acceleration * (0.5 * h * h))
        .collect();
    if q1.iter().all(|c| c.is_finite()) {
        Ok(q1)
    } else {
        Err(Error::NotFinite { at })
    }
}
