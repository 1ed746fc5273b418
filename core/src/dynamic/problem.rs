//! [`DynProblem`]: a run-time-dimension model on a grid with an embedding, solved as an
//! initial value problem that stores every node, every `s`-th node, or none (an observer).

use crate::embedding::Embedding;
use crate::grid::Grid;
use crate::lagrangian::Vector;
use crate::options::{BvpSolver, NewtonOptions};
use crate::solve::solution::{Solution, Warning};
use crate::solve::start::Start;

use super::DynLagrangian;
use super::ivp::DynRun;

mod initial_value;

/// A [`DynLagrangian`] on a grid with a discrete embedding: what
/// [`Problem`](crate::Problem) is for a const-generic [`Lagrangian`](crate::Lagrangian).
///
/// The Gauss-FDEσ embeddings ([`Embedding::finite_difference`], and the coherent
/// [`Embedding::asymmetric`]) and the symmetric ones ([`Embedding::midpoint`],
/// [`Embedding::trapezoidal`]) are offered, both schemes, as initial value problems with the
/// discrete Legendre start or the second-order start ([`with_start`](Self::with_start)): the
/// steps of the const-generic path, from the same table of terms. The variational
/// Gauss–Legendre integrators ([`Embedding::gauss_legendre`], `s = 1..=4`) are offered as
/// initial value problems (one-step maps of `(q, p)`: no start; the carried momenta are
/// [`DynSolution::momenta`]), their `s·d` stage unknowns ordered component by component so that
/// the stage Jacobian of a model of half-bandwidth `b` is a band of half-width `s (b + 1) − 1`.
/// The Gauss-FDEσ, asymmetric and symmetric embeddings are also offered as boundary value
/// problems, both schemes, and Gauss–Legendre as a collocation boundary value problem, all
/// solved by sparse LU.
/// Every implicit step is solved by Newton's method on a band matrix (`O(d b²)` for
/// half-bandwidth `b`); a step that is affine in the newest node is taken in closed form, and
/// a constant step Jacobian is factorised once per run. The runs are watched by the blow-up
/// guard of the const-generic path. The eigenvalue stability check of that path
/// (a `2d × 2d` eigenproblem) is not run. Where the model's modes decouple
/// (`L = ½ m|v|² − U(x, t)`: `∂²L/∂v² = m I`, `∂²L/∂x∂v = 0`, no force) a run is checked at its
/// initial data by bounds on the eigenvalues of `−∂²L/∂x² / m`, against its kind's limit on
/// the oscillator (`h ω = 2` for Störmer–Verlet, the trapezoidal steps and the direct
/// midpoint step, `√3` for the direct σ = + step): [`Error::Unstable`](crate::Error::Unstable)
/// when they prove it passed. Any other
/// unstable step shows as [`Error::BlowUp`](crate::Error::BlowUp) or
/// [`Error::NotFinite`](crate::Error::NotFinite) once it has grown. The const-generic path's trust checks run on its solutions, which carry their
/// [`warnings`](DynSolution::warnings): an initial value run whose step does not resolve the
/// fastest motion at the initial data ([`with_resolution_check`](Self::with_resolution_check))
/// and a boundary value problem near a resonance
/// ([`with_posedness_check`](Self::with_posedness_check)). Its two schemes are compared
/// as a [`Problem`](crate::Problem)'s are, into the same
/// [`Comparison`](crate::Comparison) ([`compare_ivp`](Self::compare_ivp),
/// [`compare_bvp`](Self::compare_bvp)).
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
///     fn hessian_bandwidth(&self) -> Option<usize> { Some(0) }
/// }
///
/// let model = Oscillators { n: 1000 };
/// let grid = Grid::new(0.0, 1.0, 1000)?;
/// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
/// let (q0, v0) = (vec![1.0; 1000], vec![0.0; 1000]);
/// // Keep every 100th node only.
/// let solution = problem.solve_ivp_every(Scheme::Variational, &q0, &v0, 100)?;
/// assert_eq!(solution.len(), 11);
/// assert!((solution.node(10)[0] - 1f64.cos()).abs() < 1e-3);
/// # Ok::<(), varembed::Error>(())
/// ```
pub struct DynProblem<'l, L: ?Sized> {
    pub(crate) lagrangian: &'l L,
    pub(crate) grid: Grid,
    pub(crate) embedding: Embedding,
    pub(crate) newton: NewtonOptions,
    pub(crate) blow_up_guard: bool,
    pub(crate) start: Start,
    /// Whether an initial value run's step is checked against its fastest motion (see the
    /// resolution module).
    pub(crate) resolution_check: bool,
    /// Whether a converged boundary value problem measures how close it is to singular (see
    /// the conditioning module).
    pub(crate) posedness_check: bool,
    /// How a boundary value problem's Newton systems are solved.
    pub(crate) bvp_solver: BvpSolver,
}

/// The stored nodes of a run of a [`DynProblem`]: `Q_k` for `k` in [`indices`](Self::indices),
/// flat (node `j` at `q[j d..(j + 1) d]`), with the run's report. With every node stored, its
/// velocities, momenta and energies at the nodes are
/// [`node_values`](Self::node_values) (a [`DynNodeValues`](crate::DynNodeValues), with CSV
/// output).
#[derive(Clone, Debug, PartialEq)]
pub struct DynSolution {
    /// The run's report (scheme, grid, last node, Newton iterations, band).
    pub run: DynRun,
    /// The dimension `d`.
    pub dimension: usize,
    /// The indices `k` of the stored nodes: every `s`-th node and the last.
    pub indices: Vec<usize>,
    /// The stored nodes, flat.
    pub q: Vec<f64>,
    /// The momenta `p_k` a Gauss–Legendre integrator carries, at the stored nodes, flat as
    /// [`q`](Self::q); empty for every other scheme (whose momenta
    /// [`node_values`](Self::node_values) computes from the nodes).
    pub momenta: Vec<f64>,
    /// What the caller should know about this solution (empty when nothing):
    /// [`Warning::UnderResolved`] for an initial value run whose step does not resolve the
    /// fastest motion at the initial data, [`Warning::IllPosed`] for a boundary value problem
    /// near a resonance. The same as the run report's [`DynRun::warnings`].
    pub warnings: Vec<Warning>,
}

impl DynSolution {
    /// The nodes as a const-generic [`Solution`] of dimension `D = d` (every node stored):
    /// what [`Problem`](crate::Problem) returns for a run it handed to this engine.
    pub(crate) fn into_nodes<const D: usize>(self) -> Solution<D> {
        let q = self
            .q
            .chunks_exact(D)
            .map(Vector::<D>::from_column_slice)
            .collect();
        Solution {
            scheme: self.run.scheme,
            embedding: self.run.embedding,
            grid: self.run.grid,
            q,
            momenta: self
                .momenta
                .chunks_exact(D)
                .map(Vector::<D>::from_column_slice)
                .collect(),
            newton_iterations: self.run.newton_iterations,
            explicit_steps: self.run.explicit_steps,
            warnings: self.warnings,
        }
    }

    /// The number of stored nodes.
    pub fn len(&self) -> usize {
        self.indices.len()
    }

    /// Whether no node is stored (never, for a solved problem).
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }

    /// Stored node `j` (node `Q_k` with `k = indices[j]`).
    ///
    /// # Panics
    ///
    /// When `j ≥ len()`.
    pub fn node(&self, j: usize) -> &[f64] {
        &self.q[j * self.dimension..(j + 1) * self.dimension]
    }

    /// The times `t_k` of the stored nodes.
    pub fn times(&self) -> Vec<f64> {
        self.indices.iter().map(|&k| self.run.grid.t(k)).collect()
    }
}

impl<'l, L: DynLagrangian + ?Sized> DynProblem<'l, L> {
    /// The problem of `lagrangian` on `grid` with `embedding`, Newton's default options and
    /// the blow-up guard on.
    pub fn new(lagrangian: &'l L, grid: Grid, embedding: Embedding) -> Self {
        DynProblem {
            lagrangian,
            grid,
            embedding,
            newton: NewtonOptions::default(),
            blow_up_guard: true,
            start: Start::Legendre,
            resolution_check: true,
            posedness_check: true,
            bvp_solver: BvpSolver::Auto,
        }
    }

    /// This problem with its model behind `dyn DynLagrangian` (through the `&L` impl of the
    /// trait, which any `L` has): the engine's steps, rows, Newton iterations and checks are
    /// compiled once for every model instead of once per model type, for an indirect call per
    /// evaluation of `L` (two where the model is itself a trait object, as on
    /// [`Problem`](crate::Problem)'s route to this engine), each of which does `O(d)` work;
    /// the large-chain bench runs measure the cost.
    pub(crate) fn erased(&self) -> DynProblem<'_, dyn DynLagrangian + '_> {
        DynProblem {
            lagrangian: &self.lagrangian,
            grid: self.grid,
            embedding: self.embedding,
            newton: self.newton,
            blow_up_guard: self.blow_up_guard,
            start: self.start,
            resolution_check: self.resolution_check,
            posedness_check: self.posedness_check,
            bvp_solver: self.bvp_solver,
        }
    }

    /// The problem of `lagrangian` on `grid` with [`Embedding::recommended`] (midpoint), as
    /// [`Problem::recommended`](crate::Problem::recommended): its variational scheme is
    /// second order, symplectic and A-stable, each step a banded Newton solve.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, lagrangian};
    ///
    /// /// A ring of `n` pendula, each coupled to its neighbours.
    /// #[lagrangian]
    /// fn ring(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     (0..n)
    ///         .map(|i| 0.5 * v[i] * v[i] + x[i].cos() - 0.5 * (x[(i + 1) % n] - x[i]).powi(2))
    ///         .sum()
    /// }
    ///
    /// let (ring, grid) = (Ring { n: 64 }, Grid::new(0.0, 1.0, 100)?);
    /// let q0: Vec<f64> = (0..64).map(|i| (i as f64 * 0.1).sin()).collect();
    /// let run = DynProblem::recommended(&ring, grid).solve_ivp(Scheme::Variational, &q0, &vec![0.0; 64])?;
    /// let midpoint = DynProblem::new(&ring, grid, Embedding::midpoint())
    ///     .solve_ivp(Scheme::Variational, &q0, &vec![0.0; 64])?;
    /// assert_eq!((run.len(), run.node(100)), (101, midpoint.node(100)));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn recommended(lagrangian: &'l L, grid: Grid) -> Self {
        DynProblem::new(lagrangian, grid, Embedding::recommended())
    }

    /// With these Newton options for the implicit steps.
    pub fn with_newton(mut self, newton: NewtonOptions) -> Self {
        self.newton = newton;
        self
    }

    /// With the blow-up guard on or off (see
    /// [`Problem::with_blow_up_guard`](crate::Problem::with_blow_up_guard)).
    pub fn with_blow_up_guard(mut self, on: bool) -> Self {
        self.blow_up_guard = on;
        self
    }

    /// With `start` for the second node `Q_1` of its initial value problems: the discrete
    /// Legendre start (the default), or `Q_1 = q0 + h v0 + ½h² q̈(a)`
    /// ([`Start::SecondOrder`], the acceleration from the Euler–Lagrange equation at the
    /// initial data, `∂²L/∂v²` solved as a band), which makes the Störmer–Verlet recurrence
    /// of `L = ½|v|² − U` second order in its positions. The comparisons
    /// ([`compare_ivp_with`](Self::compare_ivp_with), [`convergence_ivp`](Self::convergence_ivp))
    /// take their start from [`CompareOptions::start`](crate::CompareOptions::start) instead,
    /// as [`Problem`](crate::Problem)'s do.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, Side, Start, lagrangian};
    ///
    /// /// `n` uncoupled unit oscillators.
    /// #[lagrangian]
    /// fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     let mut l = 0.0;
    ///     for i in 0..n {
    ///         l += 0.5 * (v[i] * v[i] - x[i] * x[i]);
    ///     }
    ///     l
    /// }
    ///
    /// // q = cos t: halving h divides the error by 4 from the second-order start, by 2 from
    /// // the Legendre start.
    /// let model = Oscillators { n: 3 };
    /// let error = |n: usize, start: Start| -> varembed::Result<f64> {
    ///     let grid = Grid::new(0.0, 1.0, n)?;
    ///     let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward))
    ///         .with_start(start);
    ///     let last = problem.run_ivp(Scheme::Variational, &[1.0; 3], &[0.0; 3], |_| {})?.last;
    ///     Ok((last[0] - 1f64.cos()).abs())
    /// };
    /// let ratio = |start| -> varembed::Result<f64> { Ok(error(100, start)? / error(200, start)?) };
    /// assert!((ratio(Start::SecondOrder)? - 4.0).abs() < 0.2);
    /// assert!((ratio(Start::Legendre)? - 2.0).abs() < 0.1);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_start(mut self, start: Start) -> Self {
        self.start = start;
        self
    }

    /// Turns the resolution check of initial value runs on or off (on by default), as
    /// [`Problem::with_resolution_check`](crate::Problem::with_resolution_check).
    ///
    /// A run whose `h ω` at the initial data exceeds 2 carries [`Warning::UnderResolved`]:
    /// an implicit step (the direct Gauss-FDE− step, and every step of a model that is not
    /// explicit) is stable there, but does not follow the fastest motion's phase. `ω` is the
    /// fastest rate of `(∂²L/∂v²)⁻¹(−∂²L/∂x²)` at the initial data, by 30 power iterations on
    /// the model's sparse blocks (a product with `∂²L/∂x²` and a band solve with `∂²L/∂v²`
    /// each, `O(d b)`); with a diagonal `∂²L/∂v²`, a norm bound from one pass over the entries
    /// proves most resolved runs so without them. A stiff run made on purpose turns it off.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, Side, Warning, lagrangian};
    ///
    /// /// `n` uncoupled oscillators of frequency 10.
    /// #[lagrangian]
    /// fn stiff(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     let mut l = 0.0;
    ///     for i in 0..n {
    ///         l += 0.5 * (v[i] * v[i] - 100.0 * x[i] * x[i]);
    ///     }
    ///     l
    /// }
    ///
    /// // ω = 10, h = 1: the direct Gauss-FDE− step is stable, and meaningless.
    /// let model = Stiff { n: 4 };
    /// let grid = Grid::new(0.0, 10.0, 10)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let run = problem.solve_ivp(Scheme::Direct, &[1.0; 4], &[0.0; 4])?;
    /// assert!(matches!(run.warnings[..], [Warning::UnderResolved { h_omega, .. }] if (h_omega - 10.0).abs() < 1e-6));
    /// let quiet = problem.with_resolution_check(false).solve_ivp(Scheme::Direct, &[1.0; 4], &[0.0; 4])?;
    /// assert!(quiet.warnings.is_empty());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_resolution_check(mut self, on: bool) -> Self {
        self.resolution_check = on;
        self
    }

    /// Turns the ill-posedness check of boundary value problems on or off (on by default), as
    /// [`Problem::with_posedness_check`](crate::Problem::with_posedness_check).
    ///
    /// A solve that converges measures, from its last sparse LU factorisation, how close the
    /// linearised problem is to singular (a resonance), and flags it with
    /// [`Warning::IllPosed`]; the check costs two back-substitutions and one pass over the
    /// Jacobian's entries, on the converged iterate only. Turn it off to time a solve without
    /// it, or for a problem known to sit at a resonance.
    ///
    /// # Example
    ///
    /// ```
    /// use std::f64::consts::PI;
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, Side, Warning, lagrangian};
    ///
    /// /// `n` uncoupled unit oscillators.
    /// #[lagrangian]
    /// fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     let mut l = 0.0;
    ///     for i in 0..n {
    ///         l += 0.5 * (v[i] * v[i] - x[i] * x[i]);
    ///     }
    ///     l
    /// }
    ///
    /// // q̈ = −q, q(0) = 0, q(π) = 1 in each component: no solution. The discrete one exists,
    /// // and is flagged.
    /// let model = Oscillators { n: 3 };
    /// let grid = Grid::new(0.0, PI, 100)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let run = problem.solve_bvp(Scheme::Variational, &[0.0; 3], &[1.0; 3])?;
    /// assert!(matches!(run.warnings[..], [Warning::IllPosed { .. }]));
    /// let quiet = problem.with_posedness_check(false).solve_bvp(Scheme::Variational, &[0.0; 3], &[1.0; 3])?;
    /// assert!(quiet.warnings.is_empty());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_posedness_check(mut self, on: bool) -> Self {
        self.posedness_check = on;
        self
    }

    /// The model.
    pub fn lagrangian(&self) -> &'l L {
        self.lagrangian
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }
}
