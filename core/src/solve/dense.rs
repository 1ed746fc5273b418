//! Dense output: a solution's position, velocity and momentum at any time `t` of `[a, b]`,
//! interpolated from its nodes.
//!
//! The schemes' own curves are poor between the nodes (the piecewise-linear curve of the
//! classical and symmetric embeddings has an `O(h)` velocity; the Gauss–Legendre collocation
//! polynomial is `O(h^{s+1})` in `q` while the nodes are `O(h^{2s})`), so the values between
//! nodes come from a local polynomial through neighbouring nodes whose own error is of a
//! higher order than the nodes' error in both `q` and `v`: the nodes' error, smooth in `t` on a
//! smooth solution, then sets the order between the nodes too. The stencil is centred on the
//! interval that holds `t` and shifted inwards near the ends (one-sided there), so it never
//! reads past `Q_0` or `Q_N`.
//!
//! - From the positions alone (every embedding with node values): the Lagrange polynomial
//!   through `4` nodes (degree 3) for the embeddings of order 1 and 2, through `2s + 2` nodes
//!   (degree `2s + 1`) for Gauss–Legendre with `s` stages. For `s ≥ 3` its error constants
//!   are far above the integrator's, which are tiny: its own error dominates until the nodes'
//!   reaches round-off.
//! - With the Lagrangian, for Gauss–Legendre: the Hermite polynomial through the positions
//!   `q_k`, the node velocities `v_k` (from the momenta the integrator carries) and the node
//!   accelerations (from the Euler–Lagrange equation at `(q_k, v_k, t_k)`), on the step's two
//!   nodes for `s ≤ 2` (degree 5) and on four for `s = 3, 4` (degree 11). Three values per node
//!   keep the stencil narrow, and with it the error constants: on the pendulum with `s = 4`,
//!   positions and velocities alone on six nodes (degree 11 too) left the Hermite polynomial's
//!   error a hundred times above the nodes' at every step where those are above round-off.
//!
//! [`Solution::at`] and [`Solution::state_at`] are here; the run-time-dimension path's forms
//! are in `dynamic/dense.rs` and share [`stencil`].

use crate::embedding::{Embedding, EmbeddingKind, Scheme};
use crate::error::{Error, Result, check_len};
use crate::grid::Grid;
use crate::lagrangian::{Lagrangian, Vector};
use crate::solve::nodes::{NodeState, invert_momentum};
use crate::solve::solution::Solution;
use crate::stack::with_room_for;

/// The most nodes a stencil reads: `2s + 2 = 10` for the positions-only polynomial of
/// Gauss–Legendre with 4 stages.
const MAX_POINTS: usize = 10;

/// Which polynomial interpolates a solution between its nodes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Interpolant {
    /// The number of nodes of the positions-only (Lagrange) polynomial.
    pub(crate) points: usize,
    /// The number of nodes of the Hermite polynomial through positions, node velocities and
    /// node accelerations that the Lagrangian form uses instead, when it does.
    pub(crate) hermite: Option<usize>,
}

/// The interpolant of a solution of `scheme` under `embedding`; [`Error::Unsupported`] (naming
/// `operation`) where [`Solution::node_values`] refuses too: the fractional embeddings, whose
/// velocity at an end is a Riemann–Liouville derivative without a finite limit, and the
/// direct Gauss–Legendre scheme, which does not exist.
pub(crate) fn interpolant(
    embedding: &Embedding,
    scheme: Scheme,
    operation: &'static str,
) -> Result<Interpolant> {
    match (embedding.kind(), scheme) {
        // Order 1 or 2 at the nodes (2 for Störmer–Verlet on ½vᵀMv − U): a cubic's own error
        // is O(h⁴) in q and O(h³) in v.
        (
            EmbeddingKind::FiniteDifference
            | EmbeddingKind::Asymmetric
            | EmbeddingKind::Midpoint
            | EmbeddingKind::Trapezoidal,
            _,
        ) => Ok(Interpolant {
            points: 4,
            hermite: None,
        }),
        // Order 2s at the nodes: degree 2s + 1 leaves O(h^{2s+2}) in q and O(h^{2s+1}) in v;
        // Hermite of degree 3m − 1 on m nodes (5 or 11) at least O(h^{2s+2}) and O(h^{2s+1}).
        (EmbeddingKind::GaussLegendre { stages }, Scheme::Variational) => Ok(Interpolant {
            points: 2 * stages + 2,
            hermite: Some(if stages <= 2 { 2 } else { 4 }),
        }),
        (EmbeddingKind::GaussLegendre { .. }, Scheme::Direct)
        | (
            EmbeddingKind::GrunwaldLetnikov { .. }
            | EmbeddingKind::Caputo { .. }
            | EmbeddingKind::CorrectedGrunwaldLetnikov { .. }
            | EmbeddingKind::CorrectedCaputo { .. },
            _,
        ) => Err(Error::Unsupported {
            operation,
            embedding: embedding.to_string(),
        }),
    }
}

/// [`Error::TimeOutOfRange`] unless `a ≤ t ≤ b` (which a NaN is not).
pub(crate) fn check_time(grid: &Grid, t: f64) -> Result<()> {
    let (a, b) = (grid.a(), grid.b());
    if a <= t && t <= b {
        Ok(())
    } else {
        Err(Error::TimeOutOfRange { t, a, b })
    }
}

/// The nodes a polynomial reads at `t`, with the Lagrange basis `ℓ_i(t)` and its derivative
/// `ℓ_i'(t)` on them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stencil {
    /// The first stored node read; the stencil is `first..first + len`.
    pub(crate) first: usize,
    /// The number of nodes read.
    pub(crate) len: usize,
    /// `ℓ_i(t)`, `i < len`.
    pub(crate) value: [f64; MAX_POINTS],
    /// `ℓ_i'(t)`, `i < len`.
    pub(crate) slope: [f64; MAX_POINTS],
    /// The stored node whose time is `t` exactly, if any.
    pub(crate) node: Option<usize>,
}

/// The stencil of `points` consecutive stored nodes around `t` among `count ≥ 2` nodes with
/// increasing times `time(0) < … < time(count − 1)`, `time(0) ≤ t ≤ time(count − 1)`.
///
/// It is centred on the interval `[time(j), time(j + 1)]` that holds `t` (for an even number
/// of points) and shifted inwards near the ends. When the last gap is shorter than the others
/// (`short_last`: the last node of a run stored every `s`-th node, `N` not a multiple of `s`),
/// the last node is read only on that gap: elsewhere its basis polynomial would be large, the
/// nodes on either side of the short gap acting as a difference quotient.
pub(crate) fn stencil(
    time: &dyn Fn(usize) -> f64,
    count: usize,
    short_last: bool,
    points: usize,
    t: f64,
) -> Stencil {
    debug_assert!(count >= 2 && (2..=MAX_POINTS).contains(&points));
    // The last j with time(j) ≤ t, at most count − 2: bisection on the increasing times.
    let (mut lo, mut hi) = (0, count - 1);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if time(mid) <= t {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let j = lo;
    let usable = if short_last && j + 2 < count {
        count - 1
    } else {
        count
    };
    let len = points.min(usable);
    let first = j.saturating_sub(len / 2 - 1).min(usable - len);
    let node = [j, j + 1].into_iter().find(|&k| time(k) == t);
    let mut stencil = Stencil {
        first,
        len,
        value: [0.0; MAX_POINTS],
        slope: [0.0; MAX_POINTS],
        node,
    };
    let x: Vec<f64> = (first..first + len).map(time).collect();
    for i in 0..len {
        // ℓ_i = Π_{j≠i} (t − x_j)/(x_i − x_j), its derivative by the product rule factor by
        // factor (valid at the nodes too, where the logarithmic derivative is not).
        let (mut value, mut slope) = (1.0, 0.0);
        for (m, &xm) in x.iter().enumerate() {
            if m != i {
                let gap = x[i] - xm;
                let factor = (t - xm) / gap;
                slope = slope * factor + value / gap;
                value *= factor;
            }
        }
        stencil.value[i] = value;
        stencil.slope[i] = slope;
    }
    stencil
}

impl<const D: usize> Solution<D> {
    /// The position and velocity `(q(t), v(t))` at any time `t` of `[a, b]`, interpolated from
    /// the nodes (dense output, as `sol(t)` of other ODE libraries).
    ///
    /// `q(t)` is the Lagrange polynomial through neighbouring nodes and `v(t)` its derivative:
    /// 4 nodes (degree 3) for the classical and symmetric embeddings, `2s + 2` nodes (degree
    /// `2s + 1`) for Gauss–Legendre with `s` stages; the stencil is centred on the step that
    /// holds `t` and one-sided near the ends (all nodes when there are fewer). At a node,
    /// `t = t_k` exactly (as [`times`](Self::times) gives it), `q` is `Q_k` bit for bit and `v`
    /// the polynomial's slope, not [`NodeValues::v`](crate::NodeValues::v).
    ///
    /// The polynomial's own error is of higher order than the nodes' (`O(h^{r+2})` in `q` and
    /// `O(h^{r+1})` in `v` for nodes of order `r`), so between the nodes `q(t)` and `v(t)`
    /// converge at the order of the nodal positions: 1 for Gauss-FDEσ and its asymmetric form
    /// (2 where their nodes are: Störmer–Verlet on `L = ½vᵀMv − U` from
    /// [`Start::SecondOrder`](crate::Start::SecondOrder) or as a boundary value problem), 2 for
    /// the midpoint and trapezoidal embeddings, `2s` for Gauss–Legendre. The last is an
    /// asymptotic statement only for `s ≥ 3`: the integrator's error constants are so small
    /// that the polynomial's own error dominates at every step where the nodes' error is above
    /// round-off, and the values between the nodes are far less accurate than the nodes (on
    /// the pendulum with `s = 4` and `N = 64` over `[0, 40]`, 6.4e-4 against 1.8e-8 at the
    /// nodes; observed orders between `2s − 1` and `2s + 3`). For Gauss–Legendre use [`state_at`](Self::state_at), which interpolates the
    /// node velocities and accelerations too and keeps the nodes' accuracy. The orders
    /// measured per embedding and scheme are in `docs/solvers.md` (*Values between the
    /// nodes*).
    ///
    /// Errors: [`Error::TimeOutOfRange`] for `t` outside `[a, b]` or NaN;
    /// [`Error::Unsupported`] for the fractional embeddings, which have no node values
    /// ([`node_values`](Self::node_values)); [`Error::WrongLength`] for a solution whose `q`
    /// does not hold `N + 1` nodes.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Error, Grid, Problem, Scheme, lagrangian};
    ///
    /// /// Harmonic oscillator `L = ½v² − ½x²`: `q = cos t` from rest at 1.
    /// #[lagrangian]
    /// fn oscillator(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v - 0.5 * x * x
    /// }
    ///
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 2.0, 40)?, Embedding::midpoint());
    /// let solution = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?;
    /// // Halfway between t_12 = 0.6 and t_13 = 0.65: second order in q and in v.
    /// let (q, v) = solution.at(0.625)?;
    /// assert!((q[0] - 0.625f64.cos()).abs() < 1e-3);
    /// assert!((v[0] + 0.625f64.sin()).abs() < 1e-3);
    /// // At a node, the node itself.
    /// assert_eq!(solution.at(solution.times()[7])?.0, solution.q[7]);
    /// assert!(matches!(solution.at(2.5), Err(Error::TimeOutOfRange { .. })));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn at(&self, t: f64) -> Result<(Vector<D>, Vector<D>)> {
        let interpolant = interpolant(&self.embedding, self.scheme, "Solution::at")?;
        self.lagrange_at(t, interpolant.points)
    }

    /// The state `(t, q, v, p)` at any time `t` of `[a, b]`, with `p = ∂L/∂v(q, v, t)` and,
    /// for an autonomous Lagrangian, the energy `v·p − L`. `lagrangian` must be the one the
    /// solution was computed with.
    ///
    /// `q` and `v` are those of [`at`](Self::at), except for Gauss–Legendre: there they come
    /// from the Hermite polynomial through the positions `q_k`, the node velocities `v_k`
    /// (which solve `∂L/∂v(q_k, v_k, t_k) = p_k` for the momenta the integrator carries, as in
    /// [`node_values`](Self::node_values)) and the node accelerations (from the
    /// Euler–Lagrange equation `L_vv q̈ = ∂L/∂x − L_vx v − ∂²L/∂v∂t` at `(q_k, v_k, t_k)`,
    /// the last term by a central difference in `t` when `L` depends on `t`), on the step's
    /// two nodes for `s = 1, 2` (degree 5) and on four nodes for `s = 3, 4` (degree 11). Its
    /// own error is of order at least `2s + 2` in `q` and `2s + 1` in `v`, with constants
    /// small enough that `q`, `v` and `p` between the nodes have the nodes' accuracy and their
    /// order `2s`. Elsewhere `p` has the order of `q` and `v`.
    ///
    /// Errors: those of [`at`](Self::at); for Gauss–Legendre, those of
    /// [`node_values`](Self::node_values) at the nodes read (a momentum that cannot be
    /// inverted; [`Error::SingularJacobian`] at that node also when `∂²L/∂v²` is singular for
    /// the acceleration) and [`Error::WrongLength`] when the momenta are missing;
    /// [`Error::OutsideDomain`] when `∂L/∂v` or the energy is not finite at the interpolated
    /// state.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, lagrangian};
    ///
    /// /// `L = ½mv² − ½kx²` with `m = k = 2`: `q = cos t`, `p = 2 q̇`.
    /// #[lagrangian]
    /// fn spring(x: f64, v: f64, m: f64, k: f64) -> f64 {
    ///     0.5 * m * v * v - 0.5 * k * x * x
    /// }
    ///
    /// let spring = Spring { m: 2.0, k: 2.0 };
    /// let problem = Problem::new(&spring, Grid::new(0.0, 3.0, 12)?, Embedding::gauss_legendre(3)?);
    /// let solution = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?;
    /// // In the first step, where every stencil is one-sided; the nodes' error is about 1e-8.
    /// let state = solution.state_at(0.1, &spring)?;
    /// let error = (state.q[0] - 0.1f64.cos()).abs();
    /// assert!(error < 1e-8 && (state.p[0] + 2.0 * 0.1f64.sin()).abs() < 1e-8);
    /// assert!((state.energy.unwrap() - 1.0).abs() < 1e-8); // ½mv² + ½kx² = 1
    /// // The positions-only polynomial of `at` is far less accurate for s = 3.
    /// let (q, _) = solution.at(0.1)?;
    /// assert!((q[0] - 0.1f64.cos()).abs() > 100.0 * error);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn state_at<L: Lagrangian<D> + ?Sized>(
        &self,
        t: f64,
        lagrangian: &L,
    ) -> Result<NodeState<D>> {
        let interpolant = interpolant(&self.embedding, self.scheme, "Solution::state_at")?;
        let (q, v) = match interpolant.hermite {
            // The Hermite derivatives solve with `∂²L/∂v²` (see the stack module).
            Some(points) => with_room_for::<D, _>(|| self.hermite_at(t, lagrangian, points))?,
            None => self.lagrange_at(t, interpolant.points)?,
        };
        let (_, p) = lagrangian.gradient(&q, &v, t);
        let energy = (!lagrangian.dependence().t).then(|| v.dot(&p) - lagrangian.value(&q, &v, t));
        if !(p.iter().all(|x| x.is_finite()) && energy.is_none_or(f64::is_finite)) {
            return Err(Error::OutsideDomain {
                what: format!(
                    "the interpolated state q = {:?}, v = {:?} at t = {t}",
                    q.as_slice(),
                    v.as_slice()
                ),
            });
        }
        Ok(NodeState { t, q, v, p, energy })
    }

    /// The stencil of `points` nodes at `t`, after the checks every form makes.
    fn stencil_at(&self, t: f64, points: usize) -> Result<Stencil> {
        check_time(&self.grid, t)?;
        let n = self.grid.n();
        check_len("solution nodes", n + 1, self.q.len())?;
        Ok(stencil(&|k| self.grid.t(k), n + 1, false, points, t))
    }

    /// `(q(t), v(t))` of the Lagrange polynomial through `points` nodes.
    fn lagrange_at(&self, t: f64, points: usize) -> Result<(Vector<D>, Vector<D>)> {
        let stencil = self.stencil_at(t, points)?;
        let (mut q, mut v) = (Vector::<D>::zeros(), Vector::<D>::zeros());
        for i in 0..stencil.len {
            let node = &self.q[stencil.first + i];
            q += node * stencil.value[i];
            v += node * stencil.slope[i];
        }
        if let Some(k) = stencil.node {
            q = self.q[k];
        }
        Ok((q, v))
    }

    /// `(q(t), v(t))` of the Hermite polynomial through the positions, node velocities and
    /// node accelerations of `points` nodes (the integrator's momenta inverted through
    /// `lagrangian`, the accelerations from the Euler–Lagrange equation there).
    fn hermite_at<L: Lagrangian<D> + ?Sized>(
        &self,
        t: f64,
        lagrangian: &L,
        points: usize,
    ) -> Result<(Vector<D>, Vector<D>)> {
        let stencil = self.stencil_at(t, points)?;
        let n = self.grid.n();
        check_len("solution momenta", n + 1, self.momenta.len())?;
        let mut x = Vec::with_capacity(stencil.len);
        let mut data = Vec::with_capacity(stencil.len);
        for k in stencil.first..stencil.first + stencil.len {
            let tk = self.grid.t(k);
            // The difference quotient of the step from or to node k starts Newton's method.
            let guess = (self.q[k.max(1)] - self.q[k.max(1) - 1]) / self.grid.h();
            let velocity = invert_momentum(lagrangian, &self.q[k], tk, &self.momenta[k], guess, k)?;
            let acceleration = acceleration(lagrangian, &self.q[k], &velocity, tk, k)?;
            x.push(tk);
            data.push([self.q[k], velocity, acceleration]);
        }
        let (mut q, v) = hermite(&x, &data, t);
        if let Some(k) = stencil.node {
            q = self.q[k];
        }
        Ok((q, v))
    }
}

/// `q̈` from the Euler–Lagrange equation at `(x, v, t)`:
/// `L_vv q̈ = ∂L/∂x − L_vx v − ∂²L/∂v∂t`.
fn acceleration<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    x: &Vector<D>,
    v: &Vector<D>,
    t: f64,
    k: usize,
) -> Result<Vector<D>> {
    let (f, _) = lagrangian.gradient(x, v, t);
    let hs = lagrangian.hessian(x, v, t);
    let p_t = if lagrangian.dependence().t {
        let dt = 1e-5 * (1.0 + t.abs());
        (lagrangian.gradient(x, v, t + dt).1 - lagrangian.gradient(x, v, t - dt).1) / (2.0 * dt)
    } else {
        Vector::<D>::zeros()
    };
    let rhs = f - hs.xv.transpose() * v - p_t;
    crate::linalg::solve_small(&hs.vv, &rhs).ok_or(Error::SingularJacobian {
        at: crate::error::Location::Node(k),
    })
}

/// Value and derivative at `t` of the polynomial of degree `3m − 1` that takes, at each of the
/// `m` times `x_i`, the value, slope and second derivative `data[i]`: Newton's form on the
/// confluent divided differences (each `x_i` three times; a difference over one repeated time
/// is the derivative of that order over its factorial).
fn hermite<const D: usize>(x: &[f64], data: &[[Vector<D>; 3]], t: f64) -> (Vector<D>, Vector<D>) {
    let z: Vec<usize> = (0..3 * x.len()).map(|j| j / 3).collect();
    let n = z.len();
    let mut column: Vec<Vector<D>> = z.iter().map(|&i| data[i][0]).collect();
    let mut coefficients = vec![column[0]];
    for level in 1..n {
        for j in 0..n - level {
            column[j] = if z[j + level] == z[j] {
                // level is 1 or 2 here: f' or f''/2.
                data[z[j]][level] / level as f64
            } else {
                (column[j + 1] - column[j]) / (x[z[j + level]] - x[z[j]])
            };
        }
        coefficients.push(column[0]);
    }
    let (mut p, mut dp) = (coefficients[n - 1], Vector::<D>::zeros());
    for j in (0..n - 1).rev() {
        let d = t - x[z[j]];
        dp = dp * d + p;
        p = p * d + coefficients[j];
    }
    (p, dp)
}
