//! Boundary value problems: `Q_0`, `Q_N` given, Newton on the whole system for `Q_1..Q_{N−1}`.
//!
//! The Jacobian is block-tridiagonal for the classical embeddings (every row couples three
//! consecutive nodes) and is factorised as a band matrix in `O(N d³)`; for Gauss-GLEσ it is
//! dense and factorised by dense LU in `O((N d)³)`, the small-`N` reference path, or solved by
//! the FFT Newton–Krylov fast path of [`fractional`], as chosen by [`FractionalSolver`].

pub(crate) mod checks;
pub(crate) mod guess;

pub(crate) use guess::straight_line;

use crate::discretisation::{Discretisation, Pointwise};
use crate::embedding::{Embedding, Scheme};
use crate::error::{Error, Location, Result};
use crate::lagrangian::{Lagrangian, Matrix, Vector};
use crate::linalg::{BandedMatrix, DenseLu, max_norm};
use crate::options::{FractionalSolver, SolverOptions};
use crate::side::Side;
use crate::solve::conditioning::{
    ILL_POSED_BELOW, NUMERICALLY_SINGULAR, condition_bound, ill_posedness, inverse_iteration,
    neighbour_coupling, smallest_pencil_eigenvalue,
};
use crate::solve::fractional;
use crate::solve::newton::{Converging, GlobalSystem, solve_global, two_norm};
use crate::solve::solution::{Solution, Warning};
use checks::{check_guess_values, check_nodes};
use nalgebra::DMatrix;
use std::ops::ControlFlow;

/// Where the Jacobian blocks of the global system go (banded or dense storage).
trait BlockSink<const D: usize> {
    fn add_block(&mut self, row: usize, col: usize, block: &Matrix<D>);
}

impl<const D: usize> BlockSink<D> for BandedMatrix {
    fn add_block(&mut self, row: usize, col: usize, block: &Matrix<D>) {
        for a in 0..D {
            for b in 0..D {
                self.add(row * D + a, col * D + b, block[(a, b)]);
            }
        }
    }
}

impl<const D: usize> BlockSink<D> for DMatrix<f64> {
    fn add_block(&mut self, row: usize, col: usize, block: &Matrix<D>) {
        for a in 0..D {
            for b in 0..D {
                self[(row * D + a, col * D + b)] += block[(a, b)];
            }
        }
    }
}

/// Solves the boundary value problem of `scheme` from `guess` (see [`solve_unchecked`]), with
/// the input checked first ([`check_input`](checks::check_input); the nodes' part by each path, the fast one with the
/// velocities of its first evaluation), `∂²L/∂v²` checked on the solution's nodes, and the
/// solution's warnings attached (the same for every path: banded, dense and fast). So a
/// problem no path can solve (a forced Lagrangian under a fractional embedding, a dense
/// fractional system too large to factorise) reports that before any node of its guess.
pub(crate) fn solve<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    options: &SolverOptions,
    scheme: Scheme,
    guess: Vec<Vector<D>>,
) -> Result<Solution<D>> {
    check_guess_values(disc, &guess)?;
    if disc.embedding().is_fractional() && disc.lagrangian().is_forced() {
        // The fractional systems' Jacobians and preconditioners are built from L's Hessian
        // alone; a force's blocks have no place there yet.
        return Err(Error::Unsupported {
            operation: "a boundary value problem under a generalised force",
            embedding: disc.embedding().to_string(),
        });
    }
    let mut solution = solve_unchecked(disc, options, scheme, guess)?;
    let fractional = fractional_warnings(disc.embedding(), &solution.q);
    solution.warnings.extend(fractional);
    Ok(solution)
}

/// Solves the boundary value problem of `scheme` from `q` (all `N + 1` nodes of the guess, the
/// first iterate; the first and last are the boundary values): Newton's method on the residual
/// rows ([`solve_global`]). The fractional embeddings go to the fast path when `options` say
/// so (falling back to dense LU as [`FractionalSolver::Auto`] describes).
fn solve_unchecked<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    options: &SolverOptions,
    scheme: Scheme,
    q: Vec<Vector<D>>,
) -> Result<Solution<D>> {
    let (n, embedding) = (disc.grid().n(), *disc.embedding());
    let unknowns = (n - 1) * D;
    if unknowns == 0 {
        check_nodes(disc, &q, true)?;
        return Ok(solution(disc, scheme, q, 0));
    }
    if embedding.is_fractional() {
        let fast = match options.fractional {
            FractionalSolver::Dense => false,
            FractionalSolver::Fast => true,
            FractionalSolver::Auto => unknowns > FractionalSolver::DENSE_LIMIT,
        };
        if !fast && unknowns > FractionalSolver::DENSE_MAX {
            let m = unknowns as f64;
            let remedy = "use FractionalSolver::Fast or Auto, whose Newton–Krylov iterations cost \
                 O(N log N)";
            return Err(Error::TooLarge {
                what: format!(
                    "the dense fractional solver at {unknowns} unknowns factorises a \
                     {unknowns} × {unknowns} matrix at every Newton iteration ({:.1e} flops, \
                     {:.1e} bytes with the momenta's operator it is assembled from), minutes \
                     to hours; {remedy}",
                    m * m * m / 3.0,
                    8.0 * (m * m + (n * n) as f64)
                ),
            });
        }
        if fast {
            // The guess is the fast path's first iterate; a copy is kept only where a failed
            // Krylov solve falls back to dense LU, at a size where it costs little.
            let fallback = options.fractional == FractionalSolver::Auto
                && unknowns <= FractionalSolver::DENSE_FALLBACK_LIMIT;
            let kept = fallback.then(|| q.clone());
            match (fractional::solve(disc, options, scheme, q), kept) {
                (Err(Error::KrylovDidNotConverge { .. }), Some(q)) => {
                    return solve_by_lu(disc, options, scheme, q);
                }
                (result, _) => return result,
            }
        }
    }
    solve_by_lu(disc, options, scheme, q)
}

/// The solution `q` of `scheme` on the discretisation's grid after `newton_iterations`, its
/// warnings still to come.
fn solution<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    scheme: Scheme,
    q: Vec<Vector<D>>,
    newton_iterations: usize,
) -> Solution<D> {
    Solution {
        scheme,
        embedding: *disc.embedding(),
        grid: *disc.grid(),
        q,
        newton_iterations,
        explicit_steps: 0,
        momenta: Vec::new(),
        warnings: Vec::new(),
    }
}

/// [`solve_unchecked`] by dense or banded LU ([`ByLu`]), from the first iterate `q`, its nodes
/// and the solution's checked ([`check_nodes`]).
fn solve_by_lu<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    options: &SolverOptions,
    scheme: Scheme,
    q: Vec<Vector<D>>,
) -> Result<Solution<D>> {
    check_nodes(disc, &q, true)?;
    let unknowns = (disc.grid().n() - 1) * D;
    let mut system = ByLu {
        disc,
        scheme,
        posedness_check: options.posedness_check,
        jacobian: None,
    };
    let (q, newton_iterations, measure) = solve_global(&mut system, q, unknowns, &options.newton)?;
    check_nodes(disc, &q, false)?;
    let mut solution = solution(disc, scheme, q, newton_iterations);
    let ill_posed = measure.filter(|&m| m < ILL_POSED_BELOW);
    solution
        .warnings
        .extend(ill_posed.map(|measure| Warning::IllPosed { measure }));
    Ok(solution)
}

/// A Jacobian of the global system at one iterate: dense for Gauss-GLEσ (every row reads
/// every node), banded for the classical embeddings (every row couples three consecutive
/// nodes).
enum Jacobian {
    Dense(DMatrix<f64>),
    Banded(BandedMatrix),
}

/// The global system of `scheme` with its Newton systems solved by dense or banded LU.
struct ByLu<'d, 'l, L: ?Sized, const D: usize> {
    disc: &'d Discretisation<'l, L, D>,
    scheme: Scheme,
    posedness_check: bool,
    /// The last linearisation and its `‖J‖∞`.
    jacobian: Option<(Jacobian, f64)>,
}

/// A factorised Jacobian.
enum Factors {
    Dense(DenseLu),
    Banded(BandedMatrix),
}

impl Factors {
    /// `x ← J⁻¹ x`; NaN where the dense LU finds the system singular.
    fn solve(&self, x: &mut [f64]) {
        match self {
            Factors::Dense(lu) => {
                if !lu.solve(x) {
                    x.fill(f64::NAN);
                }
            }
            Factors::Banded(jac) => jac.solve_inplace(x),
        }
    }
}

impl<L: Lagrangian<D> + ?Sized, const D: usize> ByLu<'_, '_, L, D> {
    /// The last linearisation factorised, and `δ = J⁻¹ r` into `delta`;
    /// [`Error::SingularJacobian`] at `at` when it is singular.
    fn solve(&mut self, r: &[Vector<D>], delta: &mut [f64], at: Location) -> Result<Factors> {
        let (jacobian, _) = self.jacobian.take().expect("linearised before");
        for (x, r) in delta.chunks_exact_mut(D).zip(r) {
            x.copy_from_slice(r.as_slice());
        }
        match jacobian {
            Jacobian::Dense(jac) => {
                let lu = DenseLu::new(jac).ok_or(Error::SingularJacobian { at })?;
                if !lu.solve(delta) {
                    return Err(Error::SingularJacobian { at });
                }
                Ok(Factors::Dense(lu))
            }
            Jacobian::Banded(mut jac) => {
                jac.factorize()
                    .map_err(|_| Error::SingularJacobian { at })?;
                jac.solve_inplace(delta);
                Ok(Factors::Banded(jac))
            }
        }
    }
}

impl<L: Lagrangian<D> + ?Sized, const D: usize> GlobalSystem for ByLu<'_, '_, L, D> {
    type Iterate = Vec<Vector<D>>;
    type Evaluation = (Vec<Vector<D>>, Pointwise<D>);
    /// The nodes, the Newton iterations and the ill-posedness measure.
    type Output = (Vec<Vector<D>>, usize, Option<f64>);

    fn evaluate(
        &mut self,
        q: &Vec<Vector<D>>,
        iteration: usize,
    ) -> Result<(Self::Evaluation, f64, f64)> {
        let (r, pw) = residual_and_pointwise(self.disc, self.scheme, q, iteration)?;
        let (res, merit) = (max_norm(&r), two_norm(&r));
        Ok(((r, pw), res, merit))
    }

    fn within(&self, (_, pw): &Self::Evaluation, residual: f64, tolerance: f64) -> bool {
        residual <= tolerance * self.disc.row_scale(self.scheme, pw)
    }

    fn linearise(
        &mut self,
        q: &Vec<Vector<D>>,
        (_, pw): &Self::Evaluation,
        iteration: usize,
    ) -> Result<ControlFlow<Self::Output, f64>> {
        let (disc, scheme) = (self.disc, self.scheme);
        let unknowns = (disc.grid().n() - 1) * D;
        let not_finite = Error::NotFinite {
            at: Location::Newton(iteration),
        };
        let (jacobian, j_norm) = if disc.embedding().is_fractional() {
            let mut jac = DMatrix::<f64>::zeros(unknowns, unknowns);
            disc.assemble_jacobian(scheme, q, pw, |i, j, b| jac.add_block(i, j, b));
            if !jac.iter().all(|c| c.is_finite()) {
                return Err(not_finite);
            }
            let j_norm = jac
                .row_iter()
                .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
                .fold(0.0, f64::max);
            (Jacobian::Dense(jac), j_norm)
        } else {
            let mut jac = BandedMatrix::zeros(unknowns, 2 * D - 1, 2 * D - 1);
            disc.assemble_jacobian(scheme, q, pw, |i, j, b| jac.add_block(i, j, b));
            if !jac.is_finite() {
                return Err(not_finite);
            }
            let j_norm = jac.norm_inf();
            (Jacobian::Banded(jac), j_norm)
        };
        self.jacobian = Some((jacobian, j_norm));
        Ok(ControlFlow::Continue(j_norm))
    }

    /// The smallest eigenvalue by inverse iteration on the factorisation, for the condition
    /// bound and (banded) the ill-posedness measure; the dense fractional path measures the
    /// smallest eigenvalue of the pencil with the kinetic part instead (see the conditioning
    /// module).
    fn converged(&mut self, c: Converging<'_, Self>) -> Result<Self::Output> {
        let (at, disc) = (c.at(), self.disc);
        let (grid, unknowns) = (*disc.grid(), c.scratch.len());
        let j_norm = self.jacobian.as_ref().map_or(0.0, |(_, norm)| *norm);
        // The banded measure's coupling is read off the Jacobian before the factorisation
        // overwrites it, and only when the check is on.
        let coupling = match &self.jacobian {
            Some((Jacobian::Banded(jac), _)) if self.posedness_check => {
                Some(neighbour_coupling(unknowns, D, |i, j| jac.get(i, j)))
            }
            _ => None,
        };
        let (r, pw) = &c.evaluation;
        let factors = self.solve(r, c.scratch, at)?;
        let inverse = inverse_iteration(unknowns, |v| factors.solve(v));
        let measure = if !self.posedness_check {
            None
        } else if disc.embedding().is_fractional() {
            // The ill-posedness measure against the kinetic part itself (see the conditioning
            // module).
            let vv = kinetic_blocks(disc, &c.q, &pw.v);
            let product = |x: &[f64], y: &mut [f64]| kinetic_product(disc, &vv, x, y);
            smallest_pencil_eigenvalue(unknowns, product, |v| factors.solve(v))
        } else {
            let (sigma, length) = (inverse.map(|run| run.sigma), grid.b() - grid.a());
            let alpha = disc.embedding().alpha();
            sigma
                .zip(coupling)
                .map(|(sigma, coupling)| ill_posedness(sigma, coupling, grid.h(), length, alpha))
        };
        // A solution whose Newton system is singular to working precision is round-off,
        // however small its residual: an error, not an answer. The last correction
        // `δ = J⁻¹ r` (not applied) bounds `‖J⁻¹‖` from below as well: on a recurrence
        // amplifying a parasitic mode, far from normal, it exceeds the inverse iteration's
        // `1/σ` by many orders.
        let step = c.scratch.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let correction = if c.residual > 0.0 {
            step / c.residual
        } else {
            0.0
        };
        let condition = condition_bound(j_norm, inverse, unknowns, correction);
        if condition >= NUMERICALLY_SINGULAR {
            return Err(Error::IllConditioned { at, condition });
        }
        Ok((c.q, c.iteration, measure))
    }

    fn direction(
        &mut self,
        (_, (r, _)): (&Vec<Vector<D>>, &mut Self::Evaluation),
        _: (f64, f64),
        delta: &mut [f64],
        iteration: usize,
    ) -> Result<ControlFlow<Self::Output>> {
        self.solve(r, delta, Location::Newton(iteration))?;
        Ok(ControlFlow::Continue(()))
    }
}

/// Below this fraction of the solution's largest node an end value counts as zero in
/// [`fractional_warnings`]: the part of the error it causes that does not converge is
/// proportional to it (about 0.05 times the end value on the oscillator of
/// [`Warning::InfiniteFractionalAction`]), so below `10⁻⁸` of the curve it stays under about
/// `10⁻⁹` of it, below the discretisation error of fractional solves at practical `N`; and
/// data meant to be zero but computed (`sin π`) are not flagged.
const END_VALUE_NEGLIGIBLE: f64 = 1e-8;

/// What a fractional boundary value problem's solution `q` should carry, from its data alone:
/// every problem of order `α ≤ 1/2` ([`Warning::IllPosedFractional`], since telling compatible
/// end values from generic ones would take another solve), and a Gauss-GLEσ problem of order
/// `1/2 ≤ α < 1` whose value at the end where the derivative starts is not zero
/// ([`Warning::InfiniteFractionalAction`]; the Caputo forms subtract that value and are never
/// flagged).
fn fractional_warnings<const D: usize>(embedding: &Embedding, q: &[Vector<D>]) -> Vec<Warning> {
    let mut warnings = Vec::new();
    if !embedding.is_fractional() {
        return warnings;
    }
    let (alpha, side) = (embedding.alpha(), embedding.side());
    if alpha <= 0.5 {
        warnings.push(Warning::IllPosedFractional { alpha });
    }
    // The Caputo forms subtract the end value: only the Riemann–Liouville ones are flagged.
    let riemann_liouville = !embedding.is_caputo();
    if riemann_liouville && (0.5..1.0).contains(&alpha) {
        let end = match side {
            Side::Backward => 0,
            Side::Forward => q.len() - 1,
        };
        let value = q[end].amax();
        let scale = q.iter().fold(0.0f64, |m, x| m.max(x.amax()));
        if value > END_VALUE_NEGLIGIBLE * scale {
            warnings.push(Warning::InfiniteFractionalAction { alpha, side, value });
        }
    }
    warnings
}

/// `∂²L/∂v²` on the quadrature rows of `q`, `v` the velocities stored by node index (as
/// [`Pointwise`] stores them).
fn kinetic_blocks<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    q: &[Vector<D>],
    v: &[Vector<D>],
) -> Vec<Matrix<D>> {
    let grid = disc.grid();
    disc.embedding()
        .quadrature_rows(grid.n())
        .map(|k| disc.lagrangian().hessian(&q[k], &v[k], grid.t(k)).vv)
        .collect()
}

/// `y = P' x` for the kinetic part `P' = Dᵀ L_vv D` of a fractional Jacobian on the interior
/// unknowns, with the dense operator (`vv` from [`kinetic_blocks`]); NaN if it cannot be
/// applied.
fn kinetic_product<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    vv: &[Matrix<D>],
    x: &[f64],
    y: &mut [f64],
) {
    let op = disc.velocity_operator();
    let n = disc.grid().n();
    let nodes: Vec<Vector<D>> = (0..=n)
        .map(|k| match k {
            0 => Vector::<D>::zeros(),
            k if k == n => Vector::<D>::zeros(),
            k => Vector::<D>::from_column_slice(&x[(k - 1) * D..k * D]),
        })
        .collect();
    // D = −σ Δ^α_σ; the two signs cancel in Dᵀ L_vv D.
    let product = op.apply(&nodes).and_then(|a| {
        let b: Vec<Vector<D>> = a.iter().zip(vv).map(|(a, m)| m * a).collect();
        op.apply_transpose(&b)
    });
    match product {
        Ok(p) => (1..n).for_each(|k| y[(k - 1) * D..k * D].copy_from_slice(p[k].as_slice())),
        Err(_) => y.fill(f64::NAN),
    }
}

/// The residual of `scheme` at an iterate and the values it came from; any failure is
/// [`Error::NotFinite`] at that Newton iteration.
fn residual_and_pointwise<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    scheme: Scheme,
    q: &[Vector<D>],
    iteration: usize,
) -> Result<(Vec<Vector<D>>, Pointwise<D>)> {
    let not_finite = Error::NotFinite {
        at: Location::Newton(iteration),
    };
    if !q.iter().all(|x| x.iter().all(|c| c.is_finite())) {
        return Err(not_finite);
    }
    let pw = disc.pointwise(q).map_err(|_| not_finite)?;
    let r = disc.residual_from(scheme, &pw);
    debug_assert_eq!(r.len(), disc.grid().n() - 1, "every scheme has N − 1 rows");
    Ok((r, pw))
}
