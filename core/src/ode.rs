//! The general direct embedding (paper §1.2): a differential operator
//! `O = Σ_i f_i(·) (d/dt)^i ∘ g_i(·)` becomes `O^h = Σ_i f_i(·) (−σΔ_σ)^i ∘ g_i(·)`, on the rows
//! where every term is defined (`k = m..=N` for σ = −, `k = 0..=N−m` for σ = +, `m` the highest
//! order).
//!
//! `(−σΔ_σ)^i` is the `i`-th backward difference for σ = − and the `i`-th forward difference for
//! σ = +: `(Δ_−)^i G_k = h^{−i} Σ_{r=0}^{i} (−1)^r C(i, r) G_{k−r}` and
//! `(−Δ_+)^i G_k = h^{−i} Σ_{r=0}^{i} (−1)^{i−r} C(i, r) G_{k+r}`.
//!
//! The discrete operator depends on how `O` is *written*, not only on what it is (the paper's
//! `d/dt ∘ sin` versus `cos(·) d/dt`): each [`Term`] is embedded as given.

use crate::error::{Error, Location, Result, check_len};
use crate::grid::Grid;
use crate::lagrangian::{Matrix, Vector};
use crate::linalg::solve_small;
use crate::options::NewtonOptions;
use crate::side::Side;
use crate::stack::with_room_for;
use std::ops::RangeInclusive;

// `Send + Sync`: an operator and its embeddings are shared by threads (an ensemble of initial
// conditions solves one embedding from many threads at once).
type Coefficient<'a, const D: usize> = Box<dyn Fn(&Vector<D>, f64) -> f64 + Send + Sync + 'a>;
type Inner<'a, const D: usize> = Box<dyn Fn(&Vector<D>, f64) -> Vector<D> + Send + Sync + 'a>;

/// One term `f(q, t) · (d/dt)^order [g(q, t)]`.
struct Term<'a, const D: usize> {
    order: usize,
    f: Coefficient<'a, D>,
    g: Inner<'a, D>,
}

/// A differential operator `O(q) = Σ_i f_i(q, t) (d/dt)^{order_i} [g_i(q, t)]` on curves in `R^D`.
///
/// # Example
///
/// The paper's `q̈ + q̇ + q = 0` under FDE−:
/// `(Q_k − 2Q_{k−1} + Q_{k−2})/h² + (Q_k − Q_{k−1})/h + Q_k = 0`, `k = 2..=N`, from
/// `q(0) = 1`, `q̇(0) = 0`.
///
/// ```
/// use varembed::{DifferentialOperator, Grid, Side, Vector};
///
/// let op = DifferentialOperator::<1>::new().linear(2, 1.0).linear(1, 1.0).linear(0, 1.0);
/// let grid = Grid::new(0.0, 1.0, 10)?;
/// let scheme = op.embed(Side::Backward, grid);
/// assert_eq!(scheme.rows(), 2..=10);
/// let q = scheme.solve_ivp(&[Vector::<1>::new(1.0), Vector::<1>::new(0.0)])?;
/// let h = grid.h();
/// let row = (q[10][0] - 2.0 * q[9][0] + q[8][0]) / (h * h) + (q[10][0] - q[9][0]) / h + q[10][0];
/// assert!(row.abs() < 1e-9);
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Default)]
pub struct DifferentialOperator<'a, const D: usize> {
    terms: Vec<Term<'a, D>>,
}

impl<'a, const D: usize> DifferentialOperator<'a, D> {
    /// The zero operator.
    ///
    /// ```
    /// assert_eq!(varembed::DifferentialOperator::<1>::new().order(), 0);
    /// ```
    pub fn new() -> Self {
        DifferentialOperator { terms: Vec::new() }
    }

    /// Adds the term `f(q, t) · (d/dt)^order [g(q, t)]`.
    ///
    /// Both closures are `Send + Sync`, so that an operator and its embeddings can be shared
    /// between threads (solved from many initial conditions by an
    /// [`Ensemble`](crate::Ensemble), say). This bound is a breaking change from earlier
    /// versions, which took any closure: one that captures a `Cell`, a `RefCell` or an `Rc`
    /// is now refused; capture an atomic, a `Mutex` or an `Arc` instead, or copy the value in.
    ///
    /// ```
    /// use varembed::{DifferentialOperator, Grid, Side, Vector};
    /// // d/dt [sin q], embedded as (sin Q_k − sin Q_{k−1})/h.
    /// let op = DifferentialOperator::<1>::new().term(1, |_, _| 1.0, |q, _| q.map(f64::sin));
    /// let scheme = op.embed(Side::Backward, Grid::new(0.0, 1.0, 2)?);
    /// let r = scheme.residual(&[0.0, 0.5, 1.0].map(Vector::<1>::new))?;
    /// assert!((r[0][0] - 0.5f64.sin() / 0.5).abs() < 1e-15);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn term(
        mut self,
        order: usize,
        f: impl Fn(&Vector<D>, f64) -> f64 + Send + Sync + 'a,
        g: impl Fn(&Vector<D>, f64) -> Vector<D> + Send + Sync + 'a,
    ) -> Self {
        self.terms.push(Term {
            order,
            f: Box::new(f),
            g: Box::new(g),
        });
        self
    }

    /// Adds the linear term `coefficient · q^{(order)}`.
    ///
    /// ```
    /// let op = varembed::DifferentialOperator::<1>::new().linear(3, 2.0);
    /// assert_eq!(op.order(), 3);
    /// ```
    pub fn linear(self, order: usize, coefficient: f64) -> Self {
        self.term(order, move |_, _| coefficient, |q, _| *q)
    }

    /// The highest order `m` of the terms.
    ///
    /// ```
    /// let op = varembed::DifferentialOperator::<2>::new().linear(1, 1.0).linear(2, 1.0);
    /// assert_eq!(op.order(), 2);
    /// ```
    pub fn order(&self) -> usize {
        self.terms.iter().map(|t| t.order).max().unwrap_or(0)
    }

    /// The direct embedding of `O` under FDEσ on `grid`.
    ///
    /// ```
    /// use varembed::{DifferentialOperator, Grid, Side, Vector};
    /// let op = DifferentialOperator::<1>::new().linear(2, 1.0).linear(0, 1.0); // q̈ + q
    /// assert_eq!(op.embed(Side::Forward, Grid::new(0.0, 1.0, 10)?).rows(), 0..=8);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn embed(&self, side: Side, grid: Grid) -> DirectEmbedding<'_, 'a, D> {
        DirectEmbedding {
            operator: self,
            side,
            grid,
            newton: NewtonOptions::default(),
        }
    }
}

/// `O^h`: a [`DifferentialOperator`] embedded under FDEσ on a grid.
///
/// ```
/// use varembed::{DifferentialOperator, Grid, Side, Vector};
/// let op = DifferentialOperator::<1>::new().linear(2, 1.0).linear(0, 1.0); // q̈ + q
/// let scheme = op.embed(Side::Backward, Grid::new(0.0, 1.0, 100)?);
/// let q = scheme.solve_ivp(&[Vector::<1>::new(1.0), Vector::<1>::new(0.0)])?; // q(0), q̇(0)
/// assert!((q[100][0] - 1f64.cos()).abs() < 0.05); // q = cos t, first order
/// # Ok::<(), varembed::Error>(())
/// ```
pub struct DirectEmbedding<'o, 'a, const D: usize> {
    operator: &'o DifferentialOperator<'a, D>,
    side: Side,
    grid: Grid,
    newton: NewtonOptions,
}

impl<const D: usize> DirectEmbedding<'_, '_, D> {
    /// The same embedding with other Newton options for [`solve_ivp`](Self::solve_ivp) and
    /// [`solve_ivp_from_nodes`](Self::solve_ivp_from_nodes).
    ///
    /// ```
    /// use varembed::{DifferentialOperator, Grid, Side, Vector};
    /// let op = DifferentialOperator::<1>::new().linear(2, 1.0).linear(0, 1.0); // q̈ + q
    /// let strict = varembed::NewtonOptions { tolerance: 1e-14, max_iterations: 10 };
    /// let scheme = op.embed(Side::Backward, Grid::new(0.0, 1.0, 10)?).with_newton(strict);
    /// assert_eq!(scheme.solve_ivp(&[Vector::<1>::new(1.0), Vector::<1>::new(0.0)])?.len(), 11);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_newton(mut self, newton: NewtonOptions) -> Self {
        self.newton = newton;
        self
    }

    /// The rows `k` of `O^h(Q)_k = 0`: `m..=N` (σ = −) or `0..=N−m` (σ = +); empty if `m > N`.
    ///
    /// ```
    /// use varembed::{DifferentialOperator, Grid, Side, Vector};
    /// let op = DifferentialOperator::<1>::new().linear(2, 1.0).linear(0, 1.0); // q̈ + q
    /// assert_eq!(op.embed(Side::Backward, Grid::new(0.0, 1.0, 10)?).rows(), 2..=10);
    /// assert!(op.embed(Side::Backward, Grid::new(0.0, 1.0, 1)?).rows().is_empty());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    #[allow(clippy::reversed_empty_ranges)] // empty when the grid is shorter than the order
    pub fn rows(&self) -> RangeInclusive<usize> {
        let (n, m) = (self.grid.n(), self.operator.order());
        match self.side {
            _ if m > n => 1..=0,
            Side::Backward => m..=n,
            Side::Forward => 0..=n - m,
        }
    }

    /// `O^h(Q)_k` and the sum of the absolute values of everything it adds up (the scale its
    /// round-off is measured against).
    fn row(&self, q: &[Vector<D>], k: usize) -> (Vector<D>, f64) {
        let h = self.grid.h();
        let mut value = Vector::<D>::zeros();
        let mut scale = 0.0;
        for term in &self.operator.terms {
            let i = term.order;
            let mut diff = Vector::<D>::zeros();
            let mut magnitude = 0.0;
            let mut binomial = 1.0;
            for r in 0..=i {
                let node = match self.side {
                    Side::Backward => k - r,
                    Side::Forward => k + r,
                };
                let sign = match self.side {
                    Side::Backward if r % 2 == 1 => -1.0,
                    Side::Forward if (i - r) % 2 == 1 => -1.0,
                    _ => 1.0,
                };
                let g = (term.g)(&q[node], self.grid.t(node));
                magnitude += binomial * g.amax();
                diff += g * (sign * binomial);
                binomial = binomial * (i - r) as f64 / (r + 1) as f64;
            }
            let factor = (term.f)(&q[k], self.grid.t(k)) * h.powi(-(i as i32));
            // Round-off is relative to the terms before the difference cancels them.
            scale += magnitude * factor.abs();
            value += diff * factor;
        }
        (value, scale)
    }

    /// `O^h(Q)` on [`rows`](Self::rows); `Q` has `N + 1` nodes.
    ///
    /// ```
    /// use varembed::{DifferentialOperator, Grid, Side, Vector};
    /// let op = DifferentialOperator::<1>::new().linear(2, 1.0).linear(0, 1.0); // q̈ + q
    /// let scheme = op.embed(Side::Backward, Grid::new(0.0, 2.0, 2)?); // h = 1
    /// // (Q_2 − 2Q_1 + Q_0)/h² + Q_2 with Q = (0, 1, 3): 1 + 3.
    /// assert_eq!(scheme.residual(&[0.0, 1.0, 3.0].map(Vector::<1>::new))?, [Vector::<1>::new(4.0)]);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn residual(&self, q: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        check_len("discrete curve Q", self.grid.n() + 1, q.len())?;
        if let Some(k) = q.iter().position(|x| !x.iter().all(|c| c.is_finite())) {
            return Err(Error::NonFiniteInput {
                what: format!("Q_{k}"),
            });
        }
        self.rows()
            .map(|k| {
                let (r, _) = self.row(q, k);
                if r.iter().all(|c| c.is_finite()) {
                    Ok(r)
                } else {
                    Err(Error::NotFinite {
                        at: Location::Node(k),
                    })
                }
            })
            .collect()
    }

    /// Solves the initial value problem `O(q) = 0` with `q(a), q'(a), …, q^{(m−1)}(a)` given
    /// (`derivatives`, `m` the operator's [`order`](DifferentialOperator::order)), like every
    /// other initial value problem of the crate: the start nodes `Q_0, …, Q_{m−1}` are the
    /// Taylor polynomial of the derivatives, `Q_j = Σ_{i<m} (jh)^i / i! · q^{(i)}(a)`, then
    /// [`solve_ivp_from_nodes`](Self::solve_ivp_from_nodes) runs the recurrence from them.
    ///
    /// The Taylor polynomial misses `q(t_j)` by `O(h^m)` at each start node (`Q_0 = q(a)`
    /// exactly). The recurrence divides its rows by `h^m`, so a start error `δ` perturbs the
    /// run by about `δ / h^{m−1}`: `O(h)`, the scheme's own order. The solution is first order
    /// from this start, as from exact start nodes.
    ///
    /// Errors: [`Error::WrongLength`] naming the expected count `m` when `derivatives` does
    /// not hold `m` vectors (an operator of order 0 takes none);
    /// [`Error::NonFiniteInput`] for a derivative that is NaN or infinite; then those of
    /// [`solve_ivp_from_nodes`](Self::solve_ivp_from_nodes).
    ///
    /// ```
    /// use varembed::{DifferentialOperator, Error, Grid, Side, Vector};
    /// // q⃛ + q̈ + q̇ + q = 0 from q(0) = 2, q̇(0) = −1, q̈(0) = 0: q = cos t + e^{−t}.
    /// let op = DifferentialOperator::<1>::new().linear(3, 1.0).linear(2, 1.0).linear(1, 1.0).linear(0, 1.0);
    /// let scheme = op.embed(Side::Backward, Grid::new(0.0, 1.0, 1000)?);
    /// let q = scheme.solve_ivp(&[2.0, -1.0, 0.0].map(Vector::<1>::new))?;
    /// assert!((q[1000][0] - (1f64.cos() + (-1f64).exp())).abs() < 2e-3);
    ///
    /// let err = scheme.solve_ivp(&[2.0, -1.0].map(Vector::<1>::new)).unwrap_err();
    /// assert!(matches!(err, Error::WrongLength { expected: 3, found: 2, .. }), "{err}");
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_ivp(&self, derivatives: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        let (n, m) = (self.grid.n(), self.operator.order());
        check_len(
            "initial derivatives q(a), q'(a), …, q^(m−1)(a), m the operator's order",
            m,
            derivatives.len(),
        )?;
        if let Some(i) = derivatives
            .iter()
            .position(|x| !x.iter().all(|c| c.is_finite()))
        {
            return Err(Error::NonFiniteInput {
                what: format!("initial derivative q^({i})(a)"),
            });
        }
        let h = self.grid.h();
        let start: Vec<Vector<D>> = (0..m.min(n + 1))
            .map(|j| {
                // Σ_i (jh)^i / i! q^(i)(a), its powers accumulated term by term.
                let (mut node, mut power) = (Vector::<D>::zeros(), 1.0);
                for (i, derivative) in derivatives.iter().enumerate() {
                    node += derivative * power;
                    power *= j as f64 * h / (i + 1) as f64;
                }
                node
            })
            .collect();
        self.solve_ivp_from_nodes(&start)
    }

    /// Solves `O^h(Q) = 0` forward in time from given first nodes `Q_0..Q_{m−1}` (all `N + 1`
    /// nodes when `m > N`), one `d`-dimensional Newton solve per row for its newest node
    /// (σ = −: `Q_k` in row `k`; σ = +: `Q_{k+m}` in row `k`). This is the paper's setting, for
    /// a caller who has the start nodes (from an exact solution, or another scheme's run);
    /// [`solve_ivp`](Self::solve_ivp) builds them from the initial derivatives.
    ///
    /// The Jacobian of a row with respect to its newest node is taken by central differences
    /// (step `10⁻⁶ (1 + |y_j|)`), since the terms are arbitrary closures; Newton then converges
    /// linearly with a ratio of about `10⁻⁸`, and exactly in one step for linear operators up to
    /// that ratio. Errors carry the index of the node being computed.
    ///
    /// ```
    /// use varembed::{DifferentialOperator, Grid, Side, Vector};
    /// let op = DifferentialOperator::<1>::new().linear(2, 1.0).linear(0, 1.0); // q̈ + q
    /// let scheme = op.embed(Side::Forward, Grid::new(0.0, 1.0, 10)?);
    /// let q = scheme.solve_ivp_from_nodes(&[Vector::<1>::new(1.0); 2])?;
    /// assert!(scheme.residual(&q)?.iter().all(|r| r[0].abs() < 1e-6));
    /// assert!(scheme.solve_ivp_from_nodes(&[Vector::<1>::new(1.0)]).is_err()); // needs m = 2 nodes
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_ivp_from_nodes(&self, initial: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        // The Newton steps hold a `D × D` Jacobian and its LU (see the stack module).
        with_room_for::<D, _>(|| self.steps_from(initial))
    }

    /// The steps of [`solve_ivp_from_nodes`](Self::solve_ivp_from_nodes), which runs them
    /// where the stack has room for their blocks.
    fn steps_from(&self, initial: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        let (n, m) = (self.grid.n(), self.operator.order());
        check_len("initial nodes Q_0..Q_{m−1}", m.min(n + 1), initial.len())?;
        if let Some(k) = initial
            .iter()
            .position(|x| !x.iter().all(|c| c.is_finite()))
        {
            return Err(Error::NonFiniteInput {
                what: format!("initial node Q_{k}"),
            });
        }
        let mut q = initial.to_vec();
        q.resize(n + 1, Vector::<D>::zeros());
        for newest in m..=n {
            let k = match self.side {
                Side::Backward => newest,
                Side::Forward => newest - m,
            };
            let at = Location::Step(newest);
            if newest > 0 {
                q[newest] = q[newest - 1];
            }
            let mut converged = false;
            let mut residual = f64::INFINITY;
            for _ in 0..=self.newton.max_iterations {
                let (r, scale) = self.row(&q, k);
                if !r.iter().all(|c| c.is_finite()) {
                    return Err(Error::NotFinite { at });
                }
                residual = r.amax();
                // Against the terms the row sums (no absolute part): the round-off of the
                // residual is a few ε of them, far below the tolerance.
                if residual <= self.newton.tolerance * scale {
                    converged = true;
                    break;
                }
                let mut jac = Matrix::<D>::zeros();
                for j in 0..D {
                    let y = q[newest][j];
                    let step = 1e-6 * (1.0 + y.abs());
                    q[newest][j] = y + step;
                    let (plus, _) = self.row(&q, k);
                    q[newest][j] = y - step;
                    let (minus, _) = self.row(&q, k);
                    q[newest][j] = y;
                    jac.set_column(j, &((plus - minus) / (2.0 * step)));
                }
                let delta = solve_small(&jac, &r).ok_or(Error::SingularJacobian { at })?;
                q[newest] -= delta;
            }
            if !converged {
                return Err(Error::NewtonDidNotConverge {
                    at,
                    iterations: self.newton.max_iterations,
                    residual,
                });
            }
        }
        Ok(q)
    }
}
