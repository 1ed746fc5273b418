//! Boundary value problems: `Q_0`, `Q_N` given, Newton on the whole system for `Q_1..Q_{N−1}`.
//!
//! The Jacobian is block-tridiagonal for the classical embeddings (every row couples three
//! consecutive nodes) and is factorised as a band matrix in `O(N d³)`; for Gauss-GLEσ it is
//! dense and factorised by dense LU in `O((N d)³)`, the small-`N` reference path, or solved by
//! the FFT Newton–Krylov fast path of [`fractional`], as chosen by [`FractionalSolver`].

use crate::discretisation::{Discretisation, Pointwise};
use crate::embedding::{Embedding, Scheme};
use crate::error::{Error, Location, Result, check_len};
use crate::lagrangian::{Lagrangian, Matrix, Vector};
use crate::linalg::{BandedMatrix, DenseLu, max_norm};
use crate::memory::reserve;
use crate::options::{FractionalSolver, SolverOptions};
use crate::regularity::{
    check_constants, check_vv, hessian_in_domain, kinetic_in_domain, pivot_range,
};
use crate::side::Side;
use crate::solve::conditioning::{
    ILL_POSED_BELOW, NUMERICALLY_SINGULAR, condition_bound, ill_posedness, inverse_iteration,
    neighbour_coupling, smallest_pencil_eigenvalue,
};
use crate::solve::fractional;
use crate::solve::newton::{LineSearch, at_round_off, two_norm};
use crate::solve::solution::{Solution, Warning};
use nalgebra::DMatrix;

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

/// The straight line from `qa` to `qb` on `n` steps: the default initial guess.
pub(crate) fn straight_line<const D: usize>(
    qa: Vector<D>,
    qb: Vector<D>,
    n: usize,
) -> Result<Vec<Vector<D>>> {
    let mut line = reserve(n + 1, "the nodes Q_0..=Q_N of the initial guess")?;
    // The ends exactly (`qa + (qb − qa)·1` need not round to `qb`), so that a non-finite end
    // stays where it was given and is reported as that end.
    line.extend((0..=n).map(|k| match k {
        0 => qa,
        k if k == n => qb,
        k => qa + (qb - qa) * (k as f64 / n as f64),
    }));
    Ok(line)
}

/// The checks before a boundary value problem is solved: finite constants, finite ends (each
/// named as the end it belongs to), a finite guess, every guess node inside the Lagrangian's
/// domain and `∂²L/∂v²` not degenerate there.
pub(crate) fn check_input<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    guess: &[Vector<D>],
) -> Result<()> {
    let grid = disc.grid();
    check_len("discrete curve Q", grid.n() + 1, guess.len())?;
    check_constants(disc.lagrangian())?;
    let last = grid.n();
    for (k, end, at) in [(0, "a", grid.a()), (last, "b", grid.b())] {
        if !guess[k].iter().all(|c| c.is_finite()) {
            return Err(Error::NonFiniteInput {
                what: format!(
                    "the end value Q_{k} at {end} = {at}: {:?}",
                    guess[k].as_slice()
                ),
            });
        }
    }
    disc.check_curve(guess)?;
    check_nodes(disc, guess, true)
}

/// `∂²L/∂v²` not degenerate at the quadrature nodes of `q` (with its discrete velocity),
/// measured against its largest pivot over those nodes; for an initial `guess`, each node also
/// inside the Lagrangian's domain ([`Error::OutsideDomain`]).
pub(crate) fn check_nodes<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    q: &[Vector<D>],
    guess: bool,
) -> Result<()> {
    let (grid, lagrangian) = (disc.grid(), disc.lagrangian());
    let v = disc.velocity(q)?;
    let rows = disc.embedding().quadrature_rows(grid.n());
    let unread = disc.embedding().unread_force_end(grid.n());
    let mut blocks = Vec::with_capacity(v.len());
    for (k, vk) in rows.zip(&v) {
        let t = grid.t(k);
        let hs = if guess {
            let in_domain = if unread == Some(k) {
                kinetic_in_domain(lagrangian, &q[k], vk, t)
            } else {
                hessian_in_domain(lagrangian, &q[k], vk, t)
            };
            in_domain.ok_or_else(|| {
                let node = match k {
                    0 => format!("the end value Q_0 = {:?} at a", q[k].as_slice()),
                    k if k == grid.n() => {
                        format!("the end value Q_{k} = {:?} at b", q[k].as_slice())
                    }
                    k => format!("node Q_{k} = {:?} of the initial guess", q[k].as_slice()),
                };
                Error::OutsideDomain {
                    what: format!("{node} (velocity {:?})", vk.as_slice()),
                }
            })?
        } else {
            lagrangian.hessian(&q[k], vk, t)
        };
        blocks.push((k, hs.vv));
    }
    let reference = blocks
        .iter()
        .filter_map(|(_, vv)| pivot_range(vv))
        .fold(0.0, |m, (_, hi)| f64::max(m, hi));
    for (k, vv) in &blocks {
        check_vv(vv, reference, Location::Node(*k))?;
    }
    Ok(())
}

/// Solves the boundary value problem of `scheme` from `guess` (see [`solve_unchecked`]), with
/// the input checked first, `∂²L/∂v²` checked on the solution's nodes, and the solution's
/// warnings attached (the same for every path: banded, dense and fast).
pub(crate) fn solve<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    options: &SolverOptions,
    scheme: Scheme,
    guess: &[Vector<D>],
) -> Result<Solution<D>> {
    check_input(disc, guess)?;
    if disc.embedding().is_fractional() && disc.lagrangian().is_forced() {
        // The fractional systems' Jacobians and preconditioners are built from L's Hessian
        // alone; a force's blocks have no place there yet.
        return Err(Error::Unsupported {
            operation: "a boundary value problem under a generalised force",
            embedding: disc.embedding().to_string(),
        });
    }
    let mut solution = solve_unchecked(disc, options, scheme, guess)?;
    check_nodes(disc, &solution.q, false)?;
    let fractional = fractional_warnings(disc.embedding(), &solution.q);
    solution.warnings.extend(fractional);
    Ok(solution)
}

/// Solves the boundary value problem of `scheme` from `guess` (all `N + 1` nodes; the first and
/// last are the boundary values): Newton's method on the residual rows, globalised by
/// [`LineSearch`]. The fractional embeddings go to the fast path when `options` say
/// so (falling back to dense LU as [`FractionalSolver::Auto`] describes).
fn solve_unchecked<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    options: &SolverOptions,
    scheme: Scheme,
    guess: &[Vector<D>],
) -> Result<Solution<D>> {
    let (grid, embedding) = (*disc.grid(), *disc.embedding());
    let n = grid.n();
    let mut q = guess.to_vec();
    let unknowns = (n - 1) * D;
    let finish = |q: Vec<Vector<D>>, newton_iterations| Solution {
        scheme,
        embedding,
        grid,
        q,
        newton_iterations,
        explicit_steps: 0,
        momenta: Vec::new(),
        warnings: Vec::new(),
    };
    if unknowns == 0 {
        return Ok(finish(q, 0));
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
            match fractional::solve(disc, options, scheme, guess) {
                Err(Error::KrylovDidNotConverge { .. })
                    if options.fractional == FractionalSolver::Auto
                        && unknowns <= FractionalSolver::DENSE_FALLBACK_LIMIT => {}
                result => return result,
            }
        }
    }
    let newton = options.newton;
    let (mut r, mut pw) = residual_and_pointwise(disc, scheme, &q, 0)?;
    let mut res = max_norm(&r);
    let mut merit = two_norm(&r);
    let mut line_search = LineSearch::new(&q, merit);
    let mut previous = f64::INFINITY;
    for iteration in 0..=newton.max_iterations {
        let at = Location::Newton(iteration);
        let scale = disc.row_scale(scheme, &pw);
        // Factorise before testing convergence: a solution where the Jacobian is singular
        // is not isolated, and is reported rather than returned.
        let mut rhs: Vec<f64> = r.iter().flat_map(|x| x.iter().copied()).collect();
        let converged = |j_norm: f64| {
            res <= newton.tolerance * scale || at_round_off(res, previous, j_norm, max_norm(&q))
        };
        // On convergence, the smallest eigenvalue by inverse iteration on the factorisation at
        // hand, for the condition bound and (banded) the ill-posedness measure (see the
        // conditioning module); the coupling the banded measure needs is read from the Jacobian
        // before the factorisation overwrites it, and only when the check is on.
        let check = |done: bool| done && options.posedness_check;
        let measure = |sigma: Option<f64>, coupling: Option<f64>| {
            let length = grid.b() - grid.a();
            let (sigma, coupling) = (sigma?, coupling?);
            Some(ill_posedness(
                sigma,
                coupling,
                grid.h(),
                length,
                embedding.alpha(),
            ))
        };
        let (done, j_norm, inverse, ill_posedness_measure) = if embedding.is_fractional() {
            let mut jac = DMatrix::<f64>::zeros(unknowns, unknowns);
            disc.assemble_jacobian(scheme, &q, &pw, |i, j, b| jac.add_block(i, j, b));
            if !jac.iter().all(|c| c.is_finite()) {
                return Err(Error::NotFinite { at });
            }
            let j_norm = jac
                .row_iter()
                .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
                .fold(0.0, f64::max);
            let lu = DenseLu::new(jac).ok_or(Error::SingularJacobian { at })?;
            if !lu.solve(&mut rhs) {
                return Err(Error::SingularJacobian { at });
            }
            let done = converged(j_norm);
            let solve = |v: &mut [f64]| {
                if !lu.solve(v) {
                    v.fill(f64::NAN);
                }
            };
            let inverse = done.then(|| inverse_iteration(unknowns, solve)).flatten();
            // The ill-posedness measure against the kinetic part itself (see the conditioning
            // module).
            let measure = check(done).then(|| {
                let vv = kinetic_blocks(disc, &q, &pw.v);
                smallest_pencil_eigenvalue(unknowns, |x, y| kinetic_product(disc, &vv, x, y), solve)
            });
            (done, j_norm, inverse, measure.flatten())
        } else {
            let mut jac = BandedMatrix::zeros(unknowns, 2 * D - 1, 2 * D - 1);
            disc.assemble_jacobian(scheme, &q, &pw, |i, j, b| jac.add_block(i, j, b));
            if !jac.is_finite() {
                return Err(Error::NotFinite { at });
            }
            let j_norm = jac.norm_inf();
            let done = converged(j_norm);
            let coupling =
                check(done).then(|| neighbour_coupling(unknowns, D, |i, j| jac.get(i, j)));
            jac.factorize()
                .map_err(|_| Error::SingularJacobian { at })?;
            jac.solve_inplace(&mut rhs);
            let inverse = done
                .then(|| inverse_iteration(unknowns, |v| jac.solve_inplace(v)))
                .flatten();
            let sigma = inverse.map(|run| run.sigma);
            (done, j_norm, inverse, measure(sigma, coupling))
        };
        if done {
            // A solution whose Newton system is singular to working precision is round-off,
            // however small its residual: an error, not an answer. The last correction
            // `δ = J⁻¹ r` (not applied) bounds `‖J⁻¹‖` from below as well: on a recurrence
            // amplifying a parasitic mode, far from normal, it exceeds the inverse iteration's
            // `1/σ` by many orders.
            let step = rhs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let correction = if res > 0.0 { step / res } else { 0.0 };
            let condition = condition_bound(j_norm, inverse, unknowns, correction);
            if condition >= NUMERICALLY_SINGULAR {
                return Err(Error::IllConditioned { at, condition });
            }
            let mut solution = finish(q, iteration);
            let ill_posed = ill_posedness_measure.filter(|&m| m < ILL_POSED_BELOW);
            solution
                .warnings
                .extend(ill_posed.map(|measure| Warning::IllPosed { measure }));
            return Ok(solution);
        }
        if iteration == newton.max_iterations {
            break;
        }
        let (trial, (rt, pt), rest, mt) = line_search.step(&q, merit, &rhs, |trial| {
            let (rt, pt) = residual_and_pointwise(disc, scheme, trial, iteration + 1)?;
            let (res, merit) = (max_norm(&rt), two_norm(&rt));
            Ok(((rt, pt), res, merit))
        })?;
        (q, r, pw, previous, res, merit) = (trial, rt, pt, res, rest, mt);
    }
    Err(Error::NewtonDidNotConverge {
        at: Location::Newton(newton.max_iterations),
        iterations: newton.max_iterations,
        residual: res,
    })
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
