//! [`Start`]: how an initial value problem gets its second node.

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
