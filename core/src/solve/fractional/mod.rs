//! The fast path for the boundary value problems of Gauss-GLEσ: Newton–Krylov with the
//! operators applied by FFT, `O(N log N)` per iteration and `O(N)` memory.
//!
//! Gauss-GLEσ is coherent, so its direct and variational schemes are the same equations; the
//! fast path solves the variational form `r_j = f_j + (Dᵀ p)_j = 0` on the interior nodes
//! `j = 1..N−1`, with `D = −σ Δ^α_σ` and `V = D Q`. (The corrected Gauss-GLEσ adds its
//! starting columns to `D` and to the momenta's operator, which for its direct scheme is not
//! `Dᵀ`, so that its `J` is not symmetric: see `end_columns`.) Its Jacobian, restricted to the
//! interior unknowns (the boundary nodes are fixed), is the symmetric
//!
//! `J = L_xx + L_xv D + Dᵀ L_vx + Dᵀ L_vv D`,
//!
//! never formed: `J δ` costs two FFT products (`a = D δ`, then `Dᵀ(L_vx δ + L_vv a)`), and
//! inside the Krylov solver only one, since the preconditioner hands it the product with `D`'s
//! square block
//! ([`KrylovSystem::image_len`](crate::solve::krylov::KrylovSystem::image_len)), or none when
//! every `L_xv` is zero, no starting columns are in the products and the preconditioner
//! inverts the kinetic part exactly (`preconditioner`).
//!
//! The parts: `system` (the Newton system at one iterate, known through products),
//! `preconditioner` (the inverse of its kinetic part `Dᵀ L_vv D`, by FFT and Woodbury; the
//! reason the iteration counts stay flat as `N` grows), `residual` (the evaluation at an
//! iterate), and here the inexact Newton driver.
//!
//! **Linear solves.** `J` is symmetric (the Hessian of the discrete action; the corrected
//! direct scheme's goes to GMRES with the same preconditioner) and the
//! preconditioner `P'` is symmetric positive definite wherever every `L_vv` is, so the Newton
//! systems go to preconditioned MINRES ([`minres_in`]), which needs no definite `J`. A potential
//! whose `L_xx` outweighs the kinetic term makes `J` indefinite: on `L = ½v² − 12.5x² + x` at
//! α = 0.3, `P'⁻¹J = I − 25 P'⁻¹` has about 70 negative eigenvalues at every `N` (the kinetic
//! eigenvalues grow like `j^{2α}`, so many lie below 25). Conjugate gradients break down there,
//! and restarted GMRES(30), which took over before, stagnated at a relative residual of 0.83:
//! each restart discards the Krylov space that held those directions. MINRES keeps a
//! three-term recurrence instead of a basis, so it never restarts; it converged on the same
//! systems at `N = 200 … 4000` (both sides), at the cost per iteration of CG (one product with
//! `J`, one with `P'⁻¹`, the preconditioner's `D_a z` by-product used as CG used it). Where
//! MINRES breaks down (some `L_vv` not positive definite, so `P'` is not) GMRES(m) with right
//! preconditioning takes over. Each Newton system is solved to the Eisenstat–Walker forcing
//! tolerance `η_k`, never below what the Newton tolerance needs. When the Krylov solver gets
//! neither below `η_k` nor below `0.1` (which still gives a usable inexact Newton step), the
//! solve fails with [`Error::KrylovDidNotConverge`], whose message names the remedies; with
//! [`FractionalSolver::Auto`] a small system then falls back to dense LU.
//!
//! **First iterate.** The guess, or, from [`NESTED_FROM`] steps on, where the guess is the
//! straight line between the ends, the solution on a grid [`COARSENING`] times coarser,
//! interpolated ([`nested_guess`]), whose first Newton step is solved to
//! [`NESTED_FIRST_FORCING`]: on large grids a Newton step fewer. A solve from it that fails is
//! made again from the straight line ([`solve_nested`]).
//!
//! **Globalisation.** The Newton iteration of every global system ([`solve_global`]), whose
//! line search takes full steps first, in the 2-norm of the residual (the norm in which the
//! forcing term makes an inexact step a descent direction), with a watchdog.
//!
//! **Stopping rule.** The same as the dense path: `max|r| ≤ tol · (max|f| + h^{−α} max|p|)`
//! over the values the rows read (`f` on the interior nodes, `p` on the quadrature nodes),
//! or a residual that has stopped falling at round-off ([`NewtonOptions`]). The residual is
//! computed by FFT, with `V = D Q` taken through the differences of the curve
//! (`FftOperator`, "the difference form"), so that its own error stays below the floor of
//! double precision: the residual of the exact discrete solution rounded to doubles, of size
//! `ε h^{−2α}` since `J` has norm about `4h^{−2α}` (1.51e-9 at `N = 10⁵` on the benchmark
//! pendulum, measured with a double-double oracle by the integration test `residual_floor.rs`;
//! random roundings do no better). A tolerance below that floor runs Newton down to it (the
//! oracle puts the solution there at 1.50e-9).
//!
//! [`NewtonOptions`]: crate::options::NewtonOptions
//! [`FractionalSolver::Auto`]: crate::options::FractionalSolver::Auto
//!
//! ## Reference
//!
//! S. C. Eisenstat and H. F. Walker, *Choosing the forcing terms in an inexact Newton method*,
//! SIAM J. Sci. Comput. 17 (1996) (choice 2).

mod end_columns;
mod posedness;
mod preconditioner;
mod residual;
mod row_blocks;
mod system;
#[cfg(test)]
mod tests;

use crate::discretisation::Discretisation;
use crate::embedding::Scheme;
use crate::error::{Error, Location, Result};
use crate::fft_operator::FftOperator;
use crate::grid::Grid;
use crate::lagrangian::{Lagrangian, Vector};
use crate::linalg::block;
use crate::options::{KrylovBudget, SolverOptions};
use crate::solve::bvp::checks::check_nodes_with;
use crate::solve::bvp::guess::{is_straight_line, straight_line};
use crate::solve::krylov::{KrylovFailure, KrylovOptions, gmres_in};
use crate::solve::minres::{MinresWork, minres_in};
use crate::solve::newton::{Converging, GlobalSystem, solve_global};
use crate::solve::solution::{Solution, Warning};
use end_columns::EndColumns;
use posedness::{CHECK_STEPS, interpolate};
use residual::{Evaluation, residual, velocities};
use std::ops::ControlFlow;
use system::FastSystem;

/// The largest forcing term: a step whose linear residual is below this fraction of the
/// nonlinear one is still a descent step of an inexact Newton method.
const ETA_MAX: f64 = 0.1;

/// How far above the forcing term the tolerance needs (`½ tol · scale / ‖r‖₂`) the
/// Eisenstat–Walker choice may be and still be replaced by it, making its Newton step the
/// last. Their choice predicts the next residual from the last two (`η_k ≈ ‖r_{k+1}‖/‖r_k‖`
/// at quadratic convergence); a prediction within a thousand times of the tolerance leaves a
/// Newton step to go whose residual and Krylov start cost more than the few Krylov iterations
/// (MINRES gains about a factor ten per iteration on these systems, so up to three) that reach
/// the tolerance at once. At the first step, where there is no prediction, the cap
/// [`ETA_MAX`] stands for the choice ([`NESTED_FIRST_FORCING`] from a coarser grid's solution). On the benchmark pendulum from the straight line at
/// `N = 10⁶` and `10⁷` the choice is 112 and 58 times the needed term, and one more MINRES
/// iteration makes the third Newton step the last (BENCHMARKS.md).
const LAST_STEP_REACH: f64 = 1e3;

/// Solves `J δ = rhs` to the relative tolerance `eta`: MINRES, then GMRES when MINRES breaks
/// down (a preconditioner that is not positive definite: some `L_vv` is not); GMRES alone
/// when `J` is not symmetric (the corrected form's direct scheme). Accepts an iterate below
/// [`ETA_MAX`] as an inexact step. `rhs`'s storage is taken for MINRES's residual (MINRES
/// gives the right-hand side back when it breaks down).
fn solve_newton_system<const D: usize>(
    system: &mut FastSystem<'_, D>,
    rhs: &mut [f64],
    delta: &mut [f64],
    eta: f64,
    budget: &KrylovBudget,
    at: Location,
    work: &mut MinresWork,
) -> Result<usize> {
    let mut options = KrylovOptions {
        tolerance: eta,
        max_iterations: budget.minres_iterations,
        restart: budget.restart,
    };
    // MINRES needs a symmetric J: the corrected form's direct scheme goes to GMRES at once.
    let mut before_gmres = 0;
    if system.symmetric() {
        match minres_in(system, rhs, delta, &options, None, work) {
            Ok(stats) => return Ok(stats.iterations),
            Err(failure @ KrylovFailure::MaxIterations { .. }) => {
                return accept_or_fail(failure, at);
            }
            Err(breakdown) => before_gmres = breakdown.iterations(),
        }
    }
    options.max_iterations = budget.gmres_iterations;
    match gmres_in(system, rhs, delta, &options, work) {
        Ok(stats) => Ok(before_gmres + stats.iterations),
        Err(failure) => accept_or_fail(failure, at),
    }
}

/// The iterations of a Krylov solve that stopped short of its tolerance, if its relative
/// residual is below [`ETA_MAX`] (an inexact Newton step still), or the error.
fn accept_or_fail(failure: KrylovFailure, at: Location) -> Result<usize> {
    if failure.relative_residual() <= ETA_MAX {
        return Ok(failure.iterations());
    }
    Err(Error::KrylovDidNotConverge {
        at,
        iterations: failure.iterations(),
        residual: failure.relative_residual(),
    })
}

/// The fewest steps from which a solve whose guess is the straight line starts Newton from
/// the solution on a grid [`COARSENING`] times coarser instead ([`nested_guess`]).
const NESTED_FROM: usize = 1 << 19;

/// How many times coarser the grid of [`nested_guess`]'s solve is than the solve's own.
const COARSENING: usize = 32;

/// The forcing term of the first Newton step from a coarser grid's solution, where the first
/// step from the straight line has [`ETA_MAX`]. What that step leaves of the first iterate's
/// error comes back squared in the last step, where the residual hardly sees it (a smooth
/// error): with [`ETA_MAX`] the two steps from a 32 times coarser grid left the benchmark
/// pendulum's nodes 9.4e-9 from the round-off floor's solution at `N = 10⁶`, where the three
/// from the straight line leave 1.9e-11; with this term 6.4e-12, for one or two more Krylov
/// iterations (BENCHMARKS.md).
const NESTED_FIRST_FORCING: f64 = 1e-4;

/// Newton–Krylov on the interior nodes of a Gauss-GLEσ boundary value problem, from `guess`
/// (already checked: `N + 1` finite nodes, `N ≥ 2`), or from a coarser grid's solution where
/// `guess` is the straight line ([`nested_guess`]).
pub(crate) fn solve<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    options: &SolverOptions,
    scheme: Scheme,
    guess: Vec<Vector<D>>,
) -> Result<Solution<D>> {
    solve_nested(disc, options, scheme, guess, NESTED_FROM)
}

/// [`solve`] with nested iteration from `nested_from` steps on ([`NESTED_FROM`] but in tests).
fn solve_nested<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    options: &SolverOptions,
    scheme: Scheme,
    guess: Vec<Vector<D>>,
    nested_from: usize,
) -> Result<Solution<D>> {
    let (guess, nested) = nested_guess(disc, options, scheme, guess, nested_from)?;
    let ends = (guess[0], guess[disc.grid().n()]);
    let from = |guess, first_forcing| {
        disc.with_velocity_fft(|fft| {
            let guess = (guess, first_forcing);
            solve_with(disc, fft, options, scheme, guess, CHECK_STEPS)
        })
        .map(|(solution, _)| solution)
    };
    if !nested {
        return from(guess, ETA_MAX);
    }
    // A solve from the coarser grid's solution that fails is made again from the straight
    // line, whose checks and errors are those the caller would have had.
    from(guess, NESTED_FIRST_FORCING)
        .or_else(|_| from(straight_line(ends.0, ends.1, disc.grid().n())?, ETA_MAX))
}

/// `guess`, or, where it is the straight line between the ends ([`Problem::solve_bvp`]'s) on
/// `N ≥ from` steps, the solution on a grid [`COARSENING`] times coarser (found the same way,
/// without its ill-posedness check) interpolated linearly to this grid: nested iteration;
/// with whether it is the latter. That first iterate is within the coarse grid's
/// discretisation error of the solution, where Newton from the straight line spends its
/// first step getting there: on the benchmark pendulum two Newton steps instead of three
/// (BENCHMARKS.md). Where the coarse solve fails, the straight line; the solve from it
/// reports what there is to report (as does [`solve_nested`] where the solve from the
/// coarser grid's solution fails).
///
/// [`Problem::solve_bvp`]: crate::Problem::solve_bvp
fn nested_guess<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    options: &SolverOptions,
    scheme: Scheme,
    guess: Vec<Vector<D>>,
    from: usize,
) -> Result<(Vec<Vector<D>>, bool)> {
    let (grid, n) = (disc.grid(), disc.grid().n());
    // A coarse grid of at least two steps (a corrected operator's starting columns need them).
    if n < from.max(2 * COARSENING) || !is_straight_line(&guess) {
        return Ok((guess, false));
    }
    // The fine line is not held while the coarse grid is solved: its ends make it again.
    let (qa, qb) = (guess[0], guess[n]);
    drop(guess);
    let steps = n / COARSENING;
    let coarse = Grid::new(grid.a(), grid.b(), steps)
        .map(|grid| Discretisation::new(disc.lagrangian(), grid, *disc.embedding()));
    let options = SolverOptions {
        posedness_check: false,
        ..*options
    };
    let solved = coarse.and_then(|coarse| {
        let line = straight_line(qa, qb, steps)?;
        solve_nested(&coarse, &options, scheme, line, from)
    });
    match solved {
        Ok(solution) => Ok((interpolate(&solution.q, n), true)),
        Err(_) => Ok((straight_line(qa, qb, n)?, false)),
    }
}

/// [`solve`] with `fft`, the FFT form of the discretisation's `Δ^α_σ`, from `guess` with the
/// forcing term `first_forcing` for the first Newton step ([`ETA_MAX`] but from a coarser
/// grid's solution), the ill-posedness check on at most `check_steps` steps (`posedness`);
/// with the solution, the Krylov iterations of each Newton step.
fn solve_with<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    fft: &mut FftOperator,
    options: &SolverOptions,
    scheme: Scheme,
    (guess, first_forcing): (Vec<Vector<D>>, f64),
    check_steps: usize,
) -> Result<(Solution<D>, Vec<usize>)> {
    let columns = EndColumns::new(scheme, disc.velocity_operator(), disc.adjoint_operator());
    let mut newton = FastNewton {
        disc,
        options,
        scheme,
        system: FastSystem::<D>::new(disc.velocity_operator(), columns, fft),
        work: MinresWork::default(),
        eta: first_forcing,
        previous_norm: None,
        krylov_iterations: Vec::new(),
        check_steps,
        guess_unchecked: true,
    };
    let unknowns = (disc.grid().n() - 1) * D;
    solve_global(&mut newton, guess, unknowns, &options.newton)
}

/// The Newton iteration of the fast path: the residual by FFT, the Newton systems by
/// preconditioned MINRES (or GMRES) to the Eisenstat–Walker forcing term.
struct FastNewton<'d, 'l, 'f, L: ?Sized, const D: usize> {
    disc: &'d Discretisation<'l, L, D>,
    options: &'d SolverOptions,
    scheme: Scheme,
    system: FastSystem<'f, D>,
    /// The vectors of the linear solves, kept from one Newton step to the next, and lent to
    /// the evaluations.
    work: MinresWork,
    /// The forcing term of the last Newton step.
    eta: f64,
    /// The residual's 2-norm at the last Newton step.
    previous_norm: Option<f64>,
    /// The Krylov iterations of each Newton step.
    krylov_iterations: Vec<usize>,
    /// The largest grid of the ill-posedness check ([`CHECK_STEPS`] but in tests).
    check_steps: usize,
    /// Whether the guess's nodes are still to be checked ([`check_nodes_with`]), at its
    /// evaluation.
    guess_unchecked: bool,
}

impl<L: Lagrangian<D> + ?Sized, const D: usize> GlobalSystem for FastNewton<'_, '_, '_, L, D> {
    type Iterate = Vec<Vector<D>>;
    type Evaluation = Evaluation<D>;
    type Output = (Solution<D>, Vec<usize>);

    /// A trial's evaluation borrows three of the idle Krylov vectors. Its `V` and `p` go back
    /// once the Hessians have been read at them ([`direction`](Self::direction)), and its
    /// residual, which the Krylov solver takes for its own, before the next line search
    /// ([`recycle`](Self::recycle)): the Krylov solver allocates what it misses, two vectors
    /// a Newton step on the benchmark pendulum.
    fn evaluate(
        &mut self,
        q: &Vec<Vector<D>>,
        iteration: usize,
    ) -> Result<(Evaluation<D>, f64, f64)> {
        let n = self.disc.grid().n();
        let buffers = [self.work.lend(), self.work.lend(), self.work.lend()];
        let mut e = Evaluation::from_buffers(n, buffers);
        velocities(self.disc, &mut self.system, q, iteration, &mut e)?;
        if std::mem::take(&mut self.guess_unchecked) {
            // The input checks' part on the nodes, with the velocities just computed; their
            // second derivatives are those of the first linearisation, at the same iterate.
            let system = &mut self.system;
            let keep = |i, h: &_| {
                system.keep_hessian(i, h);
            };
            check_nodes_with(self.disc, q, |i| block(&e.v, i), true, keep)?;
        }
        residual(self.disc, &mut self.system, q, iteration, &mut e)?;
        let (res, merit) = e.norms();
        Ok((e, res, merit))
    }

    fn within(&self, e: &Evaluation<D>, residual: f64, tolerance: f64) -> bool {
        residual <= tolerance * e.scale
    }

    /// The same rule as the dense path, with the Jacobian's norm bounded, since it is never
    /// assembled here.
    fn linearise(
        &mut self,
        _: &Vec<Vector<D>>,
        _: &Evaluation<D>,
        _: usize,
    ) -> Result<ControlFlow<Self::Output, f64>> {
        Ok(ControlFlow::Continue(self.system.jacobian_bound()))
    }

    fn converged(&mut self, c: Converging<'_, Self>) -> Result<Self::Output> {
        // The Krylov vectors are not needed again (the check on this grid, below, allocates
        // what it uses): freed before the checks allocate, so that they add nothing to the
        // peak.
        self.work = MinresWork::default();
        let v = |i| block(&c.evaluation.v, i);
        check_nodes_with(self.disc, &c.q, v, false, |_, _| {})?;
        let mut warnings = Vec::new();
        if self.options.posedness_check {
            // Past its grid the check runs on a coarser one first (`posedness`), and decides
            // there only when no Ritz value there lies near the threshold; otherwise, or should
            // the Lagrangian not be finite there, on this grid.
            let steps = self.check_steps;
            let coarse = (self.disc.grid().n() > steps)
                .then(|| posedness::ritz_on_grid(self.disc, self.scheme, &c.q, steps))
                .and_then(Result::ok)
                .filter(|ritz| !posedness::in_doubt(ritz));
            let ritz = match coarse {
                Some(ritz) => ritz,
                None => {
                    // The Jacobian at the solution: the last Newton step released its blocks
                    // (or there was none, the guess having converged).
                    let (disc, v) = (self.disc, &c.evaluation.v);
                    self.system.linearize(disc, &c.q, v, c.at())?;
                    posedness::ritz(&mut self.system, c.scratch, &mut self.work)
                }
            };
            let measure = posedness::flagged(&ritz);
            warnings.extend(measure.map(|measure| Warning::IllPosed { measure }));
        }
        let solution = Solution {
            scheme: self.scheme,
            embedding: *self.disc.embedding(),
            grid: *self.disc.grid(),
            q: c.q,
            newton_iterations: c.iteration,
            explicit_steps: 0,
            momenta: Vec::new(),
            warnings,
        };
        Ok((solution, std::mem::take(&mut self.krylov_iterations)))
    }

    fn direction(
        &mut self,
        (q, e): (&Vec<Vector<D>>, &mut Evaluation<D>),
        (_, norm): (f64, f64),
        delta: &mut [f64],
        iteration: usize,
    ) -> Result<ControlFlow<Self::Output>> {
        let (at, tolerance) = (Location::Newton(iteration), self.options.newton.tolerance);
        // Eisenstat–Walker choice 2 with its safeguard, capped at ETA_MAX; never asking for
        // more than the Newton tolerance needs (the linear residual then is at most half of it).
        if let Some(previous) = self.previous_norm {
            let ratio = norm / previous;
            let mut next = 0.9 * ratio * ratio;
            if 0.9 * self.eta * self.eta > 0.1 {
                next = next.max(0.9 * self.eta * self.eta);
            }
            self.eta = next.min(ETA_MAX);
        }
        // A forcing term within LAST_STEP_REACH of the one the tolerance needs makes this the
        // last Newton step: solve to the tolerance now, since the step after it would cost a
        // residual and a Krylov start more than the few iterations that close the gap.
        let target = 0.5 * tolerance * e.scale / norm;
        if self.eta < LAST_STEP_REACH * target {
            self.eta = target;
        }
        self.eta = self.eta.max(target).max(1e-13);
        self.previous_norm = Some(norm);
        self.system.linearize(self.disc, q, &e.v, at)?;
        // `V` has served (the Hessians are read at it), as has `p`: their vectors go to the
        // Krylov solver, which would otherwise allocate two more beside them, `p`'s as the
        // rows of `a = D x` where its products form them.
        self.work.give(std::mem::take(&mut e.v));
        let p = std::mem::take(&mut e.p);
        if self.system.forms_rows() {
            self.system.lend_rows(p);
        } else {
            self.work.give(p);
            // The Krylov solve makes no product with D: the spectrum of its FFT form (16 bytes
            // a node) is freed meanwhile, and the next evaluation computes it again (one
            // transform: the peak of a large solve is this phase's).
            self.system.velocity.release_spectrum();
        }
        let budget = &self.options.krylov;
        let iterations = solve_newton_system(
            &mut self.system,
            &mut e.r,
            delta,
            self.eta,
            budget,
            at,
            &mut self.work,
        )?;
        self.krylov_iterations.push(iterations);
        // Not read before the next linearisation, which sets them again: freed, or given to
        // the Krylov vectors ([`recycle`](Self::recycle)).
        self.system.release_hessians();
        self.work.give(self.system.take_rows());
        Ok(ControlFlow::Continue(()))
    }

    /// Of the Krylov vectors, a trial's evaluation borrows three and one more stays idle
    /// beside the line search: the others are freed, and the next Krylov solve allocates what
    /// it misses (the line search's phase holds as many vectors as the Krylov solve's).
    fn recycle(&mut self, e: Evaluation<D>) {
        for vector in e.into_buffers() {
            self.work.give(vector);
        }
        self.work.keep_at_most(4);
    }
}
