//! The variational boundary value problems of run-time dimension by Newton–MINRES: `O(N d)`
//! memory where the sparse LU's fill grows like a two-dimensional mesh's (3.4 GB for the
//! FPUT chain at `d = 1024`, `N = 1000`).
//!
//! The Jacobian of a variational scheme is the Hessian of the discrete action, so it is
//! symmetric (possibly indefinite: an action is a saddle in general), and MINRES solves it with
//! a symmetric positive definite preconditioner. The preconditioner keeps, for each coordinate
//! `c`, the Jacobian's entries between `(Q_k)_c` and `(Q_{k±1})_c`: `d` tridiagonal matrices in
//! time, whose dominant part is `Dᵀ L_vv D` (`1/h²` times a second difference for `L_vv = I`),
//! solved in `O(N d)`. What it leaves out, the couplings between coordinates (`L_xx`, and the
//! off-diagonal entries of `L_vv`, `L_xv`), is `O(h²)` against it for a chain with a diagonal
//! mass: the preconditioned system is a small perturbation of the identity, and MINRES
//! converges in a few iterations.
//!
//! When a tridiagonal has a non-positive pivot (the preconditioner is indefinite: a time step
//! too large for the model's stiffness, or a mass that is not positive), or when MINRES does
//! not reach its tolerance within its budget (the couplings it leaves out are not small), the
//! Newton iteration stops and the problem is solved again by sparse LU; the reason is the run
//! report's [`LinearSolve::SparseLuAfterMinres`].
//!
//! The Newton iteration is the sparse LU path's (stopping rule, line search, errors: a Newton
//! iteration that does not converge is the problem's error, not a reason to try LU). Each
//! Newton system is solved to the relative residual `η = 0.1 · tolerance · scale / ‖r‖₂`
//! (MINRES stops on the 2-norm, which bounds the next residual's max-norm), or, while the
//! residual falls slowly, Eisenstat–Walker's looser `0.9 (‖r‖₂/‖r_prev‖₂)²`; between `10⁻¹³`
//! and `10⁻³`. At the converged iterate the conditioning checks of the LU path run on MINRES
//! solves: two steps of inverse iteration for `Error::IllConditioned` (with the last Newton
//! direction's `‖δ‖/‖r‖` as the LU path uses its own) and the ill-posedness measure. A nearly
//! singular Jacobian mostly shows as MINRES exhausting its budget, and the sparse LU path
//! then decides.
//!
//! A forced model (a generalised force's `∂f/∂v` makes the Jacobian non-symmetric) and the
//! Gauss–Legendre collocation system (not symmetric either) are always solved by sparse LU.

use crate::embedding::Scheme;
use crate::error::{Error, Location, Result};
use crate::options::{BvpSolver, LinearSolve, NewtonOptions};
use crate::solve::conditioning::{NUMERICALLY_SINGULAR, condition_bound, inverse_iteration};
use crate::solve::krylov::{KrylovOptions, KrylovSystem};
use crate::solve::minres::{MinresWork, minres_in};
use crate::solve::newton::{Converging, GlobalSystem, solve_global};
use std::ops::ControlFlow;

use super::DynLagrangian;
use super::bvp::{Converged, assemble_matrix, evaluate_rows, jacobian_norm, measure, newton};
use super::problem::DynProblem;
use super::rows::{CurveValues, DynRows, HessianCache};
use super::slices::max_norm;
use super::sparse_lu::SparseRows;

impl<L: DynLagrangian + ?Sized> DynProblem<'_, L> {
    /// How the Newton systems of a boundary value problem are solved ([`BvpSolver`]; default
    /// [`BvpSolver::Auto`]: preconditioned MINRES for a variational scheme of at least
    /// [`BvpSolver::MINRES_FROM`] unknowns, sparse LU otherwise). What was used is the run
    /// report's [`linear_solve`](crate::DynRun::linear_solve).
    ///
    /// ```
    /// use varembed::{BvpSolver, DynProblem, Embedding, Grid, LinearSolve, Scheme, lagrangian};
    ///
    /// #[lagrangian]
    /// fn chain(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     let mut l = 0.5 * (v[0] * v[0] - x[0] * x[0]);
    ///     for i in 1..n {
    ///         let s = x[i] - x[i - 1];
    ///         l += 0.5 * (v[i] * v[i] - s * s);
    ///     }
    ///     l
    /// }
    ///
    /// let model = Chain { n: 4 };
    /// let problem = DynProblem::new(&model, Grid::new(0.0, 1.0, 50)?, Embedding::midpoint());
    /// let (qa, qb) = ([0.0; 4], [0.1, 0.2, 0.3, 0.4]);
    /// let by_lu = problem.solve_bvp(Scheme::Variational, &qa, &qb)?;
    /// let by_minres = problem
    ///     .with_bvp_solver(BvpSolver::Minres)
    ///     .solve_bvp(Scheme::Variational, &qa, &qb)?;
    /// assert!(matches!(by_minres.run.linear_solve, Some(LinearSolve::Minres { .. })));
    /// assert!(by_lu.q.iter().zip(&by_minres.q).all(|(a, b)| (a - b).abs() < 1e-12));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_bvp_solver(mut self, solver: BvpSolver) -> Self {
        self.bvp_solver = solver;
        self
    }
}

impl<'l> DynProblem<'_, dyn DynLagrangian + 'l> {
    /// Newton's method on `rows` from `guess` with this problem's linear solver: the converged
    /// iterate and what solved its systems (sparse LU, MINRES, or sparse LU after MINRES gave
    /// way, with the reason).
    pub(super) fn newton_by_solver(
        &self,
        rows: &DynRows<'_, dyn DynLagrangian + 'l>,
        guess: &[f64],
    ) -> Result<(Converged, LinearSolve)> {
        let unknowns = self.grid.n().saturating_sub(1) * rows.d;
        // A generalised force makes the Jacobian non-symmetric (its `∂f/∂v` enters with the
        // velocity's weights), so a forced model goes to sparse LU.
        let minres = rows.scheme == Scheme::Variational
            && unknowns > 0
            && !rows.lagrangian.is_forced()
            && match self.bvp_solver {
                BvpSolver::Auto => unknowns >= BvpSolver::MINRES_FROM,
                BvpSolver::Minres => true,
                BvpSolver::SparseLu => false,
            };
        let by_lu = || newton(rows, &self.newton, guess, self.posedness_check);
        if !minres {
            return Ok((by_lu()?, LinearSolve::SparseLu));
        }
        Ok(
            match minres_newton(rows, &self.newton, guess, self.posedness_check)? {
                Ok((converged, products)) => (converged, LinearSolve::Minres { products }),
                Err((reason, products)) => (
                    by_lu()?,
                    LinearSolve::SparseLuAfterMinres { reason, products },
                ),
            },
        )
    }
}

/// MINRES iterations per Newton system before it gives way to sparse LU.
const BUDGET: usize = 500;

/// The relative residual the inverse iteration's solves are taken to (an estimate, two steps).
const INVERSE_ITERATION_TOLERANCE: f64 = 1e-8;

/// The `d` tridiagonal matrices in time of the module docs, factorised as `L D Lᵀ`: unknown
/// `u = (k − 1) d + c` has its time neighbours at `u ± d`.
struct TimeTridiagonals {
    d: usize,
    /// `1 / D_u`.
    inverse_pivot: Vec<f64>,
    /// `L_u`, the multiplier of `u` by `u − d` (0 for the first node).
    multiplier: Vec<f64>,
}

impl TimeTridiagonals {
    /// From the Jacobian's entries (the two off-diagonal entries averaged, so that it is
    /// symmetric); the unknown with a non-positive pivot when there is one.
    fn new(matrix: &SparseRows, d: usize) -> std::result::Result<Self, usize> {
        let n = matrix.order();
        let mut diagonal = vec![0.0; n];
        let mut coupling = vec![0.0; n];
        for (i, j, value) in matrix.entries() {
            if i == j {
                diagonal[i] += value;
            } else if j == i + d {
                coupling[i] += 0.5 * value;
            } else if i == j + d {
                coupling[j] += 0.5 * value;
            }
        }
        let (mut inverse_pivot, mut multiplier) = (vec![0.0; n], vec![0.0; n]);
        for u in 0..n {
            let pivot = if u >= d {
                let l = coupling[u - d] * inverse_pivot[u - d];
                multiplier[u] = l;
                diagonal[u] - l * coupling[u - d]
            } else {
                diagonal[u]
            };
            // Positive, and not lost to cancellation against the diagonal (a NaN fails too).
            let positive = pivot > 64.0 * f64::EPSILON * diagonal[u].abs();
            if !positive {
                return Err(u);
            }
            inverse_pivot[u] = 1.0 / pivot;
        }
        Ok(TimeTridiagonals {
            d,
            inverse_pivot,
            multiplier,
        })
    }

    /// `z = T⁻¹ r`.
    fn solve(&self, r: &[f64], z: &mut [f64]) {
        let (n, d) = (r.len(), self.d);
        // L y = r, then Lᵀ z = D⁻¹ y, along each coordinate's line (stride d).
        for u in 0..n {
            z[u] = if u >= d {
                r[u] - self.multiplier[u] * z[u - d]
            } else {
                r[u]
            };
        }
        for u in (0..n).rev() {
            let scaled = z[u] * self.inverse_pivot[u];
            z[u] = if u + d < n {
                scaled - self.multiplier[u + d] * z[u + d]
            } else {
                scaled
            };
        }
    }
}

/// The Newton system as MINRES sees it.
struct Preconditioned<'a> {
    matrix: &'a SparseRows,
    preconditioner: &'a TimeTridiagonals,
}

impl KrylovSystem for Preconditioned<'_> {
    fn len(&self) -> usize {
        self.matrix.order()
    }
    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        self.matrix.apply(x, y);
    }
    fn precondition(&mut self, r: &[f64], z: &mut [f64]) {
        self.preconditioner.solve(r, z);
    }
    fn apply_preconditioned(
        &mut self,
        x: &[f64],
        _: &[f64],
        _: (&[f64], f64),
        onto: (f64, f64),
        y: &mut [f64],
    ) {
        self.matrix.apply_onto(x, onto, y);
    }
}

/// Why MINRES gave way, and the products with the Jacobian it had made by then.
type GaveWay = (String, usize);

/// `J x = b` by MINRES to the relative residual `tolerance`: the products made, or why it
/// stopped short and the products it made. `b`'s storage is taken for MINRES's residual.
fn solve(
    system: &mut Preconditioned<'_>,
    (b, x): (&mut [f64], &mut [f64]),
    tolerance: f64,
    work: &mut MinresWork,
) -> std::result::Result<usize, GaveWay> {
    let options = KrylovOptions {
        tolerance,
        max_iterations: BUDGET,
        restart: 0,
    };
    minres_in(system, b, x, &options, None, work)
        .map(|stats| stats.iterations)
        .map_err(|failure| {
            let reason = format!(
                "MINRES stopped at relative residual {:.1e} after {} products (asked {tolerance:.0e})",
                failure.relative_residual(),
                failure.iterations()
            );
            (reason, failure.iterations())
        })
}

/// Newton's method ([`solve_global`]) on the rows from `guess` with MINRES solves (module
/// docs): the converged iterate and the products with the Jacobian, or the reason MINRES gave
/// way and the products it had made. The errors of the problem itself (a non-finite
/// evaluation, a Newton iteration that does not converge, a singular linearisation at the
/// solution) are the sparse LU path's.
fn minres_newton<L: DynLagrangian + ?Sized>(
    rows: &DynRows<'_, L>,
    options: &NewtonOptions,
    guess: &[f64],
    posedness_check: bool,
) -> Result<std::result::Result<(Converged, usize), GaveWay>> {
    let unknowns = rows.grid.n().saturating_sub(1) * rows.d;
    if unknowns == 0 {
        let converged = Converged {
            q: guess.to_vec(),
            iterations: 0,
            band: 0,
            measure: None,
        };
        return Ok(Ok((converged, 0)));
    }
    let mut system = ByMinres {
        rows,
        tolerance: options.tolerance,
        posedness_check,
        hessians: HessianCache::new(rows.d),
        matrix: None,
        preconditioner: None,
        j_norm: 0.0,
        work: MinresWork::default(),
        products: 0,
        previous_merit: None,
        correction: 0.0,
    };
    solve_global(&mut system, guess.to_vec(), unknowns, options)
}

/// The rows' global system, its Newton systems solved by MINRES with the time-tridiagonal
/// preconditioner.
struct ByMinres<'r, 'l, L: ?Sized> {
    rows: &'r DynRows<'l, L>,
    /// The Newton tolerance, which the forcing terms are chosen for.
    tolerance: f64,
    posedness_check: bool,
    hessians: HessianCache,
    matrix: Option<SparseRows>,
    preconditioner: Option<TimeTridiagonals>,
    /// `‖J‖∞` of the last linearisation.
    j_norm: f64,
    work: MinresWork,
    /// The products with the Jacobian so far.
    products: usize,
    /// The residual's 2-norm at the last Newton direction.
    previous_merit: Option<f64>,
    /// `‖δ‖∞ / ‖r‖∞` of the last Newton direction (see the conditioning check).
    correction: f64,
}

impl<L: DynLagrangian + ?Sized> ByMinres<'_, '_, L> {
    /// The last linearisation as MINRES sees it, and MINRES's vectors.
    fn system(&mut self) -> (Preconditioned<'_>, &mut MinresWork) {
        let matrix = self.matrix.as_ref().expect("linearised before");
        let preconditioner = self.preconditioner.as_ref().expect("built with the matrix");
        let system = Preconditioned {
            matrix,
            preconditioner,
        };
        (system, &mut self.work)
    }
}

impl<L: DynLagrangian + ?Sized> GlobalSystem for ByMinres<'_, '_, L> {
    type Iterate = Vec<f64>;
    type Evaluation = CurveValues;
    type Output = std::result::Result<(Converged, usize), GaveWay>;

    fn evaluate(&mut self, q: &Vec<f64>, iteration: usize) -> Result<(CurveValues, f64, f64)> {
        evaluate_rows(self.rows, q, iteration)
    }

    fn within(&self, e: &CurveValues, residual: f64, tolerance: f64) -> bool {
        residual <= tolerance * self.rows.scale(e)
    }

    fn linearise(
        &mut self,
        q: &Vec<f64>,
        e: &CurveValues,
        iteration: usize,
    ) -> Result<ControlFlow<Self::Output, f64>> {
        let at = Location::Newton(iteration);
        self.hessians.invalidate();
        let (matrix, _) = assemble_matrix(self.rows, (q, e), &mut self.hessians, &mut self.matrix);
        self.j_norm = jacobian_norm(matrix, at)?;
        match TimeTridiagonals::new(matrix, self.rows.d) {
            Ok(t) => self.preconditioner = Some(t),
            Err(u) => {
                let (k, c) = (u / self.rows.d + 1, u % self.rows.d);
                let reason = format!(
                    "the time-tridiagonal preconditioner is not positive definite at Q_{k}[{c}] \
                     (Newton iteration {iteration})"
                );
                return Ok(ControlFlow::Break(Err((reason, self.products))));
            }
        }
        Ok(ControlFlow::Continue(self.j_norm))
    }

    fn converged(&mut self, c: Converging<'_, Self>) -> Result<Self::Output> {
        // As the LU path: a lower bound of ‖J⁻¹‖∞ from the last Newton direction (taken at the
        // iterate one step before this one), and from the inverse iteration, on MINRES solves.
        // A nearly singular Jacobian mostly shows as MINRES exhausting its budget, and the
        // sparse LU path then decides.
        let (at, unknowns) = (c.at(), c.scratch.len());
        let (j_norm, correction) = (self.j_norm, self.correction);
        let (rows, check) = (self.rows, self.posedness_check);
        let mut products = self.products;
        let (mut system, work) = self.system();
        let mut failed = None;
        let rhs = c.scratch;
        let inverse = inverse_iteration(unknowns, |x| {
            rhs.copy_from_slice(x);
            let used = solve(&mut system, (rhs, x), INVERSE_ITERATION_TOLERANCE, work);
            match used {
                Ok(used) => products += used,
                Err((reason, used)) => {
                    products += used;
                    failed.get_or_insert(reason);
                    x.fill(f64::NAN);
                }
            }
        });
        if let Some(reason) = failed {
            let reason = format!("in the conditioning check at the solution: {reason}");
            return Ok(Err((reason, products)));
        }
        let condition = condition_bound(j_norm, inverse, unknowns, correction);
        if condition >= NUMERICALLY_SINGULAR {
            return Err(Error::IllConditioned { at, condition });
        }
        let sigma = inverse.map(|run| run.sigma);
        let matrix = system.matrix;
        let measure = check.then(|| measure(rows, matrix, sigma?)).flatten();
        let converged = Converged {
            q: c.q,
            iterations: c.iteration,
            band: matrix.bandwidth(),
            measure,
        };
        Ok(Ok((converged, products)))
    }

    fn direction(
        &mut self,
        (_, e): (&Vec<f64>, &mut CurveValues),
        (res, merit): (f64, f64),
        delta: &mut [f64],
        iteration: usize,
    ) -> Result<ControlFlow<Self::Output>> {
        // What the next iterate needs to meet the stopping rule: its ∞-norm residual is at most
        // the linear residual's 2-norm, η ‖r‖₂, plus the quadratic term. Far from the solution
        // (the residual falling slowly) Eisenstat–Walker's looser 0.9 (‖r‖/‖r_prev‖)² instead,
        // at most 10⁻³.
        let needed = 0.1 * self.tolerance * self.rows.scale(e) / merit;
        let loose = match self.previous_merit {
            Some(previous) => (0.9 * (merit / previous).powi(2)).min(1e-3),
            None => 0.0,
        };
        let forcing = needed.max(loose).clamp(1e-13, 1e-3);
        self.previous_merit = Some(merit);
        let (mut system, work) = self.system();
        let used = solve(&mut system, (&mut e.r, delta), forcing, work);
        match used {
            Ok(used) => self.products += used,
            Err((reason, used)) => {
                let reason = format!("{reason} at Newton iteration {iteration}");
                return Ok(ControlFlow::Break(Err((reason, self.products + used))));
            }
        }
        if !delta.iter().all(|c| c.is_finite()) {
            let reason = format!("a non-finite MINRES direction at Newton iteration {iteration}");
            return Ok(ControlFlow::Break(Err((reason, self.products))));
        }
        self.correction = if res > 0.0 {
            max_norm(delta) / res
        } else {
            0.0
        };
        Ok(ControlFlow::Continue(()))
    }
}
