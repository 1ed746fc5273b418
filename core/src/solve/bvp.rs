//! Boundary value problems: `Q_0`, `Q_N` given, Newton on the whole system for `Q_1..Q_{N−1}`.
//!
//! The Jacobian is block-tridiagonal for the classical embeddings (every row couples three
//! consecutive nodes) and is factorised as a band matrix in `O(N d³)`; for Gauss-GLEσ it is
//! dense and factorised by dense LU in `O((N d)³)`, the small-`N` reference path, or solved by
//! the FFT Newton–Krylov fast path of [`fractional`], as chosen by
//! [`FractionalSolver`].

use crate::error::{Error, Location, Result};
use crate::lagrangian::{IntoVector, Lagrangian, Matrix, Vector};
use crate::problem::{BlockSink, Problem, Scheme};
use crate::solve::Solution;
use crate::solve::fractional::{
    self, DENSE_FALLBACK_LIMIT, DENSE_LIMIT, FractionalSolver, KrylovBudget,
};
use crate::solve::linear::{BandedMatrix, solve_dense};
use crate::solve::max_norm;
use crate::solve::newton::{at_round_off, backtrack};
use nalgebra::{DMatrix, DVector};

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

impl<L: Lagrangian<D> + ?Sized, const D: usize> Problem<'_, L, D> {
    /// Solves the boundary value problem `Q_0 = qa`, `Q_N = qb` for `scheme`, from the straight
    /// line between them. Works for every embedding.
    ///
    /// Newton's method on the rows of [`residual`](Self::residual), with a backtracking line
    /// search on the max-norm of the residual. Errors: [`Error::SingularJacobian`],
    /// [`Error::NewtonDidNotConverge`] (iterations, last residual) and [`Error::NotFinite`],
    /// located at the global Newton iteration; on the fractional fast path (see
    /// [`FractionalSolver`]) also [`Error::KrylovDidNotConverge`].
    pub fn solve_bvp(
        &self,
        scheme: Scheme,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
    ) -> Result<Solution<D>> {
        let (qa, qb) = (qa.into_vector(), qb.into_vector());
        let n = self.grid.n();
        let guess: Vec<Vector<D>> = (0..=n)
            .map(|k| qa + (qb - qa) * (k as f64 / n as f64))
            .collect();
        self.solve_bvp_from(scheme, &guess)
    }

    /// Solves the boundary value problem from an initial guess of all `N + 1` nodes; its first
    /// and last nodes are the boundary values.
    pub fn solve_bvp_from(&self, scheme: Scheme, guess: &[Vector<D>]) -> Result<Solution<D>> {
        self.check_curve(guess)?;
        let n = self.grid.n();
        let mut q = guess.to_vec();
        let unknowns = (n - 1) * D;
        let finish = |q: Vec<Vector<D>>, newton_iterations| Solution {
            scheme,
            embedding: self.embedding,
            grid: self.grid,
            q,
            newton_iterations,
            explicit_steps: 0,
        };
        if unknowns == 0 {
            return Ok(finish(q, 0));
        }
        if self.embedding.is_fractional() {
            let fast = match self.fractional_solver {
                FractionalSolver::Dense => false,
                FractionalSolver::Fast => true,
                FractionalSolver::Auto => unknowns > DENSE_LIMIT,
            };
            if fast {
                match fractional::solve(self, scheme, guess, &KrylovBudget::default()) {
                    Err(Error::KrylovDidNotConverge { .. })
                        if self.fractional_solver == FractionalSolver::Auto
                            && unknowns <= DENSE_FALLBACK_LIMIT => {}
                    result => return result,
                }
            }
        }
        let opts = self.newton;
        let h_alpha = self.grid.h().powf(-self.embedding.alpha());
        let (mut r, mut pw) = self.residual_and_pointwise(scheme, &q, 0)?;
        let mut res = max_norm(&r);
        let mut previous = f64::INFINITY;
        for iteration in 0..=opts.max_iterations {
            let at = Location::Newton(iteration);
            let scale = 1.0 + max_norm(&pw.f) + h_alpha * max_norm(&pw.p);
            // Factorise before testing convergence: a solution where the Jacobian is singular
            // is not isolated, and is reported rather than returned.
            let mut rhs: Vec<f64> = r.iter().flat_map(|x| x.iter().copied()).collect();
            let j_norm;
            if self.embedding.is_fractional() {
                let mut jac = DMatrix::<f64>::zeros(unknowns, unknowns);
                self.assemble_jacobian(scheme, &q, &pw, &mut jac);
                if !jac.iter().all(|c| c.is_finite()) {
                    return Err(Error::NotFinite { at });
                }
                j_norm = jac
                    .row_iter()
                    .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
                    .fold(0.0, f64::max);
                let x = solve_dense(jac, &DVector::from_vec(rhs))
                    .ok_or(Error::SingularJacobian { at })?;
                rhs = x.as_slice().to_vec();
            } else {
                let mut jac = BandedMatrix::zeros(unknowns, 2 * D - 1, 2 * D - 1);
                self.assemble_jacobian(scheme, &q, &pw, &mut jac);
                if !jac.is_finite() {
                    return Err(Error::NotFinite { at });
                }
                j_norm = jac.norm_inf();
                jac.factorize()
                    .map_err(|_| Error::SingularJacobian { at })?;
                jac.solve_inplace(&mut rhs);
            }
            if res <= opts.tolerance * scale || at_round_off(res, previous, j_norm, max_norm(&q)) {
                return Ok(finish(q, iteration));
            }
            if iteration == opts.max_iterations {
                break;
            }
            let (trial, (rt, pt), rest) = backtrack(&q, &rhs, res, |trial| {
                let (rt, pt) = self.residual_and_pointwise(scheme, trial, iteration + 1)?;
                let res = max_norm(&rt);
                Ok(((rt, pt), res))
            })?;
            (q, r, pw, previous, res) = (trial, rt, pt, res, rest);
        }
        Err(Error::NewtonDidNotConverge {
            at: Location::Newton(opts.max_iterations),
            iterations: opts.max_iterations,
            residual: res,
        })
    }

    fn residual_and_pointwise(
        &self,
        scheme: Scheme,
        q: &[Vector<D>],
        iteration: usize,
    ) -> Result<(Vec<Vector<D>>, crate::problem::Pointwise<D>)> {
        let not_finite = Error::NotFinite {
            at: Location::Newton(iteration),
        };
        if !q.iter().all(|x| x.iter().all(|c| c.is_finite())) {
            return Err(not_finite);
        }
        let pw = self.pointwise(q).map_err(|_| not_finite)?;
        let r = self.residual_from(scheme, &pw);
        debug_assert_eq!(r.len(), self.grid.n() - 1, "every scheme has N − 1 rows");
        Ok((r, pw))
    }
}
