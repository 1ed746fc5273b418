//! Boundary value problems of a run-time-dimension model: `Q_0`, `Q_N` given, Newton's method
//! on the whole system for `Q_1..Q_{N−1}`, its Jacobian assembled as a sparse matrix and
//! factorised by sparse LU after a fill-reducing ordering ([solvers, "Boundary value problems
//! of large models"](crate::guide::solvers#boundary-value-problems-of-large-models)).
//!
//! The rows, the stopping rule, the line search and the errors are those of the const-generic
//! [`Problem::solve_bvp`](crate::Problem::solve_bvp): on a model that implements both traits
//! the two give the same nodes, in the same number of Newton iterations.

use crate::embedding::{EmbeddingKind, Scheme};
use crate::error::{Error, Location, Result, check_len};
use crate::memory::reserve;
use crate::options::{LinearSolve, NewtonOptions};
use crate::solve::conditioning::{
    ILL_POSED_BELOW, NUMERICALLY_SINGULAR, condition_bound, ill_posedness, inverse_iteration,
    neighbour_coupling_of,
};
use crate::solve::newton::{Converging, GlobalSystem, solve_global};
use crate::solve::solution::Warning;
use std::ops::ControlFlow;

use super::DynLagrangian;
use super::ivp::DynRun;
use super::problem::{DynProblem, DynSolution};
use super::rows::{CurveValues, DynRows, HessianCache};
use super::slices::max_norm;
use super::sparse_lu::{Singular, SparseLu, SparseRows};

impl<L: DynLagrangian + ?Sized> DynProblem<'_, L> {
    /// Solves the boundary value problem `q(a) = qa`, `q(b) = qb` of `scheme`, from the
    /// straight line between them: the same residual rows, Newton stopping rule, line search
    /// and errors as [`Problem::solve_bvp`](crate::Problem::solve_bvp), for the Gauss-FDEσ
    /// embeddings ([`Embedding::finite_difference`](crate::Embedding::finite_difference)), the
    /// coherent [`Embedding::asymmetric`](crate::Embedding::asymmetric) and the symmetric
    /// [`Embedding::midpoint`](crate::Embedding::midpoint) and
    /// [`Embedding::trapezoidal`](crate::Embedding::trapezoidal), both schemes, and the
    /// variational Gauss–Legendre integrators
    /// ([`Embedding::gauss_legendre`](crate::Embedding::gauss_legendre): their stage equations
    /// on every step as one collocation system, the solution's momenta in
    /// [`DynSolution::momenta`]); [`Error::Unsupported`] for the fractional embeddings.
    ///
    /// Each Newton iteration assembles the Jacobian of the `(N − 1) d` equations as a sparse
    /// matrix (every row couples three consecutive nodes through the model's sparse
    /// second-derivative blocks) and factorises it by sparse LU after a fill-reducing ordering,
    /// computed once per solve; a periodic chain, which is not banded, costs the same. The
    /// solution stores every node (`indices` are `0..=N`); its run report has
    /// `explicit_steps = 0`, `band` the half-bandwidth of the Jacobian in time-major order (not
    /// the order it is factorised in) and `reordered = true`.
    ///
    /// Errors: [`Error::WrongLength`] for end values not of length `d`,
    /// [`Error::NonFiniteInput`] for a non-finite one or model constant,
    /// [`Error::InvalidModel`], [`Error::OutsideDomain`] and [`Error::DegenerateLagrangian`]
    /// (at [`Location::Node`]) on the initial guess and the solution, and [`Error::NotFinite`],
    /// [`Error::SingularJacobian`] and [`Error::NewtonDidNotConverge`] at
    /// [`Location::Newton`].
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynLagrangian, DynProblem, Embedding, Grid, Scheme, Side, SparseHessian};
    ///
    /// /// `n` uncoupled unit oscillators.
    /// struct Oscillators { n: usize }
    ///
    /// impl DynLagrangian for Oscillators {
    ///     fn dimension(&self) -> usize { self.n }
    ///     fn value(&self, x: &[f64], v: &[f64], _t: f64) -> f64 {
    ///         x.iter().zip(v).map(|(x, v)| 0.5 * (v * v - x * x)).sum()
    ///     }
    ///     fn force(&self, x: &[f64], _v: &[f64], _t: f64, f: &mut [f64]) {
    ///         for (f, x) in f.iter_mut().zip(x) { *f = -x; }
    ///     }
    ///     fn momentum(&self, _x: &[f64], v: &[f64], _t: f64, p: &mut [f64]) {
    ///         p.copy_from_slice(v);
    ///     }
    ///     fn hessian(&self, _x: &[f64], _v: &[f64], _t: f64, out: &mut SparseHessian) {
    ///         for i in 0..self.n {
    ///             out.xx.add(i, i, -1.0);
    ///             out.vv.add(i, i, 1.0);
    ///         }
    ///     }
    /// }
    ///
    /// let model = Oscillators { n: 3 };
    /// let grid = Grid::new(0.0, 1.0, 100)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// // q = sin t / sin 1 in each coordinate, from q(0) = 0 to q(1) = 1.
    /// let solution = problem.solve_bvp(Scheme::Variational, &[0.0; 3], &[1.0; 3])?;
    /// let exact = 0.5f64.sin() / 1f64.sin();
    /// assert!(solution.node(50).iter().all(|q| (q - exact).abs() < 1e-4));
    /// assert_eq!(solution.len(), 101);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_bvp(&self, scheme: Scheme, qa: &[f64], qb: &[f64]) -> Result<DynSolution> {
        if !self.embedding.is_one_step() {
            DynRows::new(self.lagrangian, self.grid, self.embedding, scheme)?;
        }
        check_model(self.lagrangian)?;
        let d = self.lagrangian.dimension();
        check_len("qa", d, qa.len())?;
        check_len("qb", d, qb.len())?;
        let n = self.grid.n();
        // The ends exactly, so that a non-finite end is reported as that end.
        let mut guess = reserve(
            (n + 1).saturating_mul(d),
            "the nodes Q_0..=Q_N of the initial guess",
        )?;
        for k in 0..=n {
            match k {
                0 => guess.extend_from_slice(qa),
                k if k == n => guess.extend_from_slice(qb),
                k => {
                    let s = k as f64 / n as f64;
                    guess.extend(qa.iter().zip(qb).map(|(a, b)| a + (b - a) * s));
                }
            }
        }
        self.solve_bvp_from(scheme, &guess)
    }

    /// Solves the boundary value problem of [`solve_bvp`](Self::solve_bvp) from an initial
    /// guess of all `N + 1` nodes, flat (node `k` at `guess[k d..(k + 1) d]`); its first and
    /// last nodes are the boundary values. [`Error::WrongDimension`] when the length is not a
    /// multiple of `d`, [`Error::WrongLength`] when it is not `N + 1` nodes,
    /// [`Error::NonFiniteInput`] for a non-finite entry.
    ///
    /// ```
    /// # use varembed::{DynLagrangian, SparseHessian};
    /// # struct Oscillators { n: usize }
    /// # impl DynLagrangian for Oscillators {
    /// #     fn dimension(&self) -> usize { self.n }
    /// #     fn value(&self, x: &[f64], v: &[f64], _t: f64) -> f64 {
    /// #         x.iter().zip(v).map(|(x, v)| 0.5 * (v * v - x * x)).sum()
    /// #     }
    /// #     fn force(&self, x: &[f64], _v: &[f64], _t: f64, f: &mut [f64]) {
    /// #         for (f, x) in f.iter_mut().zip(x) { *f = -x; }
    /// #     }
    /// #     fn momentum(&self, _x: &[f64], v: &[f64], _t: f64, p: &mut [f64]) {
    /// #         p.copy_from_slice(v);
    /// #     }
    /// #     fn hessian(&self, _x: &[f64], _v: &[f64], _t: f64, out: &mut SparseHessian) {
    /// #         for i in 0..self.n { out.xx.add(i, i, -1.0); out.vv.add(i, i, 1.0); }
    /// #     }
    /// # }
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, Side};
    /// let model = Oscillators { n: 2 };
    /// let problem = DynProblem::new(&model, Grid::new(0.0, 1.0, 10)?, Embedding::asymmetric(Side::Forward));
    /// let solution = problem.solve_bvp_from(Scheme::Direct, &vec![1.0; 11 * 2])?;
    /// assert_eq!((solution.node(0), solution.node(10)), (&[1.0, 1.0][..], &[1.0, 1.0][..]));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_bvp_from(&self, scheme: Scheme, guess: &[f64]) -> Result<DynSolution> {
        self.erased().bvp_from(scheme, guess)
    }
}

impl DynProblem<'_, dyn DynLagrangian + '_> {
    /// [`solve_bvp_from`](DynProblem::solve_bvp_from), compiled once for every model.
    fn bvp_from(&self, scheme: Scheme, guess: &[f64]) -> Result<DynSolution> {
        if let EmbeddingKind::GaussLegendre { stages } = self.embedding.kind() {
            return self.solve_gauss_bvp(stages, scheme, guess);
        }
        let rows = DynRows::new(self.lagrangian, self.grid, self.embedding, scheme)?;
        check_input(&rows, guess)?;
        let (converged, linear_solve) = self.newton_by_solver(&rows, guess)?;
        let Converged {
            q,
            iterations: newton_iterations,
            band,
            measure,
        } = converged;
        check_nodes(&rows, &q, false)?;
        let solve = (newton_iterations, band, linear_solve);
        Ok(self.bvp_solution(scheme, (q, Vec::new()), solve, measure))
    }

    /// A boundary value problem's solution: every node of `q` (flat) and the scheme's
    /// `momenta` (empty where `node_values` computes them), the Newton iterations, the
    /// Jacobian's band and the linear solver, and `Warning::IllPosed` when the ill-posedness
    /// `measure` is below the threshold.
    pub(super) fn bvp_solution(
        &self,
        scheme: Scheme,
        (q, momenta): (Vec<f64>, Vec<f64>),
        (newton_iterations, band, linear_solve): (usize, usize, LinearSolve),
        measure: Option<f64>,
    ) -> DynSolution {
        let (n, d) = (self.grid.n(), self.lagrangian.dimension());
        let warnings: Vec<Warning> = measure
            .filter(|&m| m < ILL_POSED_BELOW)
            .map(|measure| Warning::IllPosed { measure })
            .into_iter()
            .collect();
        DynSolution {
            run: DynRun {
                scheme,
                embedding: self.embedding,
                grid: self.grid,
                last: q[n * d..].to_vec(),
                newton_iterations,
                explicit_steps: 0,
                band,
                reordered: true,
                warnings: warnings.clone(),
                linear_solve: Some(linear_solve),
            },
            dimension: d,
            indices: (0..=n).collect(),
            q,
            momenta,
            warnings,
        }
    }
}

/// `V`, `f`, `p` and the residual rows at an iterate, and the residual's max-norm; any failure
/// is [`Error::NotFinite`] at that Newton iteration.
pub(super) fn evaluate<L: DynLagrangian + ?Sized>(
    rows: &DynRows<'_, L>,
    q: &[f64],
    values: &mut CurveValues,
    iteration: usize,
) -> Result<f64> {
    let not_finite = Error::NotFinite {
        at: Location::Newton(iteration),
    };
    if !q.iter().all(|c| c.is_finite()) {
        return Err(not_finite);
    }
    rows.evaluate(q, values).map_err(|_| not_finite)?;
    Ok(max_norm(&values.r))
}

/// The Jacobian at `q` assembled into the planned pattern, planning it first when there is
/// none or when an entry falls outside it; whether it was planned anew.
pub(super) fn assemble_matrix<'s, L: DynLagrangian + ?Sized>(
    rows: &DynRows<'_, L>,
    (q, values): (&[f64], &CurveValues),
    hessians: &mut HessianCache,
    matrix: &'s mut Option<SparseRows>,
) -> (&'s mut SparseRows, bool) {
    let (d, blocks) = (rows.d, rows.rows().count());
    let fill = |matrix: &mut SparseRows, hessians: &mut HessianCache| {
        matrix.clear();
        let mut fits = true;
        for i in 0..blocks {
            rows.jacobian_row(i, hessians, q, values, |r, c, v| {
                fits &= matrix.add(r, c, v).is_ok();
            });
        }
        fits
    };
    let fits = matrix.as_mut().is_some_and(|m| fill(m, hessians));
    if !fits {
        let mut planned = SparseRows::with_order(blocks * d);
        let mut entries = Vec::new();
        for i in 0..blocks {
            entries.clear();
            rows.jacobian_row(i, hessians, q, values, |r, c, _| entries.push((r, c)));
            planned.push_rows(i * d, d, &mut entries);
        }
        debug_assert!(planned.is_complete());
        let fitted = fill(&mut planned, hessians);
        debug_assert!(fitted, "the pattern was read off the same rows");
        *matrix = Some(planned);
    }
    (matrix.as_mut().expect("planned above"), !fits)
}

/// The ill-posedness measure of the conditioning module for the linearisation of the rows at
/// the curve `q` (all `N + 1` nodes): the sparse LU path's, from its Jacobian there; `None`
/// when the curve cannot be evaluated or the Jacobian factorised (nothing to measure), or
/// there are no unknowns.
pub(super) fn posedness_at<L: DynLagrangian + ?Sized>(
    rows: &DynRows<'_, L>,
    q: &[f64],
) -> Option<f64> {
    let unknowns = rows.grid.n().saturating_sub(1) * rows.d;
    if unknowns == 0 {
        return None;
    }
    let mut values = rows.zero_values();
    rows.evaluate(q, &mut values).ok()?;
    let mut hessians = HessianCache::new(rows.d);
    let (mut matrix, mut lu) = (None, None);
    let (matrix, lu) = assemble(rows, q, &values, &mut hessians, (&mut matrix, &mut lu)).ok()?;
    lu.factorize(matrix).ok()?;
    let sigma = inverse_iteration(unknowns, |v| lu.solve_in_place(v))?.sigma;
    measure(rows, matrix, sigma)
}

/// The Jacobian at `q` (see [`assemble_matrix`]) and its symbolic LU factorisation, planned
/// again with the pattern.
fn assemble<'s, L: DynLagrangian + ?Sized>(
    rows: &DynRows<'_, L>,
    q: &[f64],
    values: &CurveValues,
    hessians: &mut HessianCache,
    (matrix, lu): (&'s mut Option<SparseRows>, &'s mut Option<SparseLu>),
) -> std::result::Result<(&'s mut SparseRows, &'s mut SparseLu), Singular> {
    let (matrix, planned) = assemble_matrix(rows, (q, values), hessians, matrix);
    if planned || lu.is_none() {
        *lu = Some(SparseLu::plan(matrix)?);
    }
    Ok((matrix, lu.as_mut().expect("planned above")))
}

/// What Newton's method returns: the nodes, the iterations, the Jacobian's time-major band and,
/// when asked for, the ill-posedness measure at the converged iterate.
pub(super) struct Converged {
    pub(super) q: Vec<f64>,
    pub(super) iterations: usize,
    pub(super) band: usize,
    pub(super) measure: Option<f64>,
}

/// Newton's method ([`solve_global`]) on the rows from `guess` with sparse LU solves: the
/// const-generic boundary value solve's stopping rule, line search and errors. With
/// `posedness_check`, the converged iterate's Jacobian and its factorisation give the
/// ill-posedness measure (see [`measure`]).
pub(super) fn newton<L: DynLagrangian + ?Sized>(
    rows: &DynRows<'_, L>,
    options: &NewtonOptions,
    guess: &[f64],
    posedness_check: bool,
) -> Result<Converged> {
    let unknowns = rows.grid.n().saturating_sub(1) * rows.d;
    if unknowns == 0 {
        let (q, iterations, band, measure) = (guess.to_vec(), 0, 0, None);
        return Ok(Converged {
            q,
            iterations,
            band,
            measure,
        });
    }
    let mut system = ByLu {
        rows,
        posedness_check,
        hessians: HessianCache::new(rows.d),
        matrix: None,
        lu: None,
        j_norm: 0.0,
    };
    solve_global(&mut system, guess.to_vec(), unknowns, options)
}

/// The rows' global system, its Newton systems solved by sparse LU after a fill-reducing
/// ordering planned once (and again when the Jacobian's pattern changes).
struct ByLu<'r, 'l, L: ?Sized> {
    rows: &'r DynRows<'l, L>,
    posedness_check: bool,
    hessians: HessianCache,
    matrix: Option<SparseRows>,
    lu: Option<SparseLu>,
    /// `‖J‖∞` of the last linearisation.
    j_norm: f64,
}

impl<L: DynLagrangian + ?Sized> ByLu<'_, '_, L> {
    /// The last linearisation and its (symbolic) factorisation.
    fn factors(&mut self) -> (&SparseRows, &mut SparseLu) {
        let matrix = self.matrix.as_ref().expect("linearised before");
        (matrix, self.lu.as_mut().expect("planned with the matrix"))
    }
}

impl<L: DynLagrangian + ?Sized> GlobalSystem for ByLu<'_, '_, L> {
    type Iterate = Vec<f64>;
    type Evaluation = CurveValues;
    type Output = Converged;

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
    ) -> Result<ControlFlow<Converged, f64>> {
        let at = Location::Newton(iteration);
        self.hessians.invalidate();
        let planned = (&mut self.matrix, &mut self.lu);
        let (matrix, _) = assemble(self.rows, q, e, &mut self.hessians, planned)
            .map_err(|_| Error::SingularJacobian { at })?;
        self.j_norm = jacobian_norm(matrix, at)?;
        Ok(ControlFlow::Continue(self.j_norm))
    }

    fn converged(&mut self, c: Converging<'_, Self>) -> Result<Converged> {
        let (at, j_norm, rows, check) = (c.at(), self.j_norm, self.rows, self.posedness_check);
        let (matrix, lu) = self.factors();
        lu_direction((matrix, lu), &c.evaluation.r, c.scratch, at)?;
        let sigma = isolated((matrix, lu), j_norm, (c.residual, c.scratch), at)?;
        let measure = check.then(|| measure(rows, matrix, sigma?)).flatten();
        Ok(Converged {
            q: c.q,
            iterations: c.iteration,
            band: matrix.bandwidth(),
            measure,
        })
    }

    fn direction(
        &mut self,
        (_, e): (&Vec<f64>, &mut CurveValues),
        _: (f64, f64),
        delta: &mut [f64],
        iteration: usize,
    ) -> Result<ControlFlow<Converged>> {
        lu_direction(self.factors(), &e.r, delta, Location::Newton(iteration))?;
        Ok(ControlFlow::Continue(()))
    }
}

/// The rows at `q` for Newton iteration `iteration` (see [`evaluate`]): the values, the
/// residual's max-norm and its 2-norm.
pub(super) fn evaluate_rows<L: DynLagrangian + ?Sized>(
    rows: &DynRows<'_, L>,
    q: &[f64],
    iteration: usize,
) -> Result<(CurveValues, f64, f64)> {
    let mut values = rows.zero_values();
    let res = evaluate(rows, q, &mut values, iteration)?;
    let merit = two_norm(&values.r);
    Ok((values, res, merit))
}

/// `‖J‖∞` of an assembled Jacobian; [`Error::NotFinite`] at `at` when an entry is not.
pub(super) fn jacobian_norm(matrix: &SparseRows, at: Location) -> Result<f64> {
    if !matrix.is_finite() {
        return Err(Error::NotFinite { at });
    }
    Ok(matrix.norm_inf())
}

/// The Newton direction `δ = J⁻¹ r` into `delta` from the planned `matrix` and its `lu`
/// (factorised here): [`Error::SingularJacobian`] when the LU finds no pivot or the direction
/// is not finite.
pub(super) fn lu_direction(
    (matrix, lu): (&SparseRows, &mut SparseLu),
    r: &[f64],
    delta: &mut [f64],
    at: Location,
) -> Result<()> {
    lu.factorize(matrix)
        .map_err(|_| Error::SingularJacobian { at })?;
    delta.copy_from_slice(r);
    lu.solve_in_place(delta);
    if !delta.iter().all(|c| c.is_finite()) {
        return Err(Error::SingularJacobian { at });
    }
    Ok(())
}

/// At a converged iterate (residual max-norm `res`, last direction `delta`), as the
/// const-generic solve: a system singular to working precision is not an isolated solution,
/// [`Error::IllConditioned`]; otherwise the smallest eigenvalue inverse iteration found, if
/// it did.
pub(super) fn isolated(
    (matrix, lu): (&SparseRows, &mut SparseLu),
    j_norm: f64,
    (res, delta): (f64, &[f64]),
    at: Location,
) -> Result<Option<f64>> {
    let inverse = inverse_iteration(matrix.order(), |v| lu.solve_in_place(v));
    let correction = if res > 0.0 {
        max_norm(delta) / res
    } else {
        0.0
    };
    let condition = condition_bound(j_norm, inverse, matrix.order(), correction);
    if condition >= NUMERICALLY_SINGULAR {
        return Err(Error::IllConditioned { at, condition });
    }
    Ok(inverse.map(|run| run.sigma))
}

/// The 2-norm of flat residual rows, the line search's merit.
pub(super) fn two_norm(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// The ill-posedness measure of the conditioning module at the converged iterate: the largest
/// coupling between neighbouring nodes read off `matrix` (one pass over its entries) against
/// `sigma`, the smallest eigenvalue by inverse iteration on its factorisation.
pub(super) fn measure<L: DynLagrangian + ?Sized>(
    rows: &DynRows<'_, L>,
    matrix: &SparseRows,
    sigma: f64,
) -> Option<f64> {
    let (grid, d) = (rows.grid, rows.d);
    let coupling = neighbour_coupling_of(d, matrix.entries());
    let (h, length) = (grid.h(), grid.b() - grid.a());
    Some(ill_posedness(
        sigma,
        coupling,
        h,
        length,
        rows.embedding.alpha(),
    ))
}

mod checks;
pub(super) use checks::{check_input, check_model, check_nodes};
