//! Generalised forces on the run-time-dimension path: [`DynForce`], and what makes [`Rayleigh`]
//! one and [`Forced`] a [`DynLagrangian`].

use super::{ForceDependence, Forced, Rayleigh, discrete_force_pairs, joined};
use crate::dynamic::problem::DynSolution;
use crate::dynamic::sparse::{SparseForceJacobian, SparseHessian};
use crate::error::{Error, Result};
use crate::lagrangian::{Dependence, DynLagrangian, HessianDependence};

/// A generalised force `f(x, v, t)` on `R^d` with `d` known at run time and a sparse Jacobian:
/// what [`Forced`] needs to be a [`DynLagrangian`] (solved by [`DynProblem`](crate::DynProblem)).
///
/// # Example
///
/// ```
/// use varembed::{DynForce, SparseForceJacobian};
///
/// /// Linear friction `f = −γ v` on every component.
/// struct Friction { gamma: f64 }
///
/// impl DynForce for Friction {
///     fn add_force(&self, _x: &[f64], v: &[f64], _t: f64, f: &mut [f64]) {
///         for (f, v) in f.iter_mut().zip(v) {
///             *f -= self.gamma * v;
///         }
///     }
///     fn jacobian(&self, x: &[f64], _v: &[f64], _t: f64, out: &mut SparseForceJacobian) {
///         for i in 0..x.len() {
///             out.v.add(i, i, -self.gamma);
///         }
///     }
/// }
/// let mut f = [1.0, 1.0];
/// Friction { gamma: 0.5 }.add_force(&[0.0; 2], &[2.0, -2.0], 0.0, &mut f);
/// assert_eq!(f, [0.0, 2.0]);
/// ```
pub trait DynForce {
    /// Adds `f(x, v, t)` to `f`.
    fn add_force(&self, x: &[f64], v: &[f64], t: f64, f: &mut [f64]);

    /// Adds the entries of `∂f/∂x` and `∂f/∂v` at `(x, v, t)` to `out` (cleared by the caller;
    /// a loop over many entries runs faster through [`SparseForceJacobian::writer`], as the
    /// `force` attribute writes it).
    fn jacobian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseForceJacobian);

    /// What the Jacobian's blocks depend on, as [`Force::jacobian_dependence`](super::Force::jacobian_dependence).
    fn jacobian_dependence(&self) -> ForceDependence {
        ForceDependence::ALL
    }

    /// The force's constants by name.
    fn constants(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }

    /// Why this force cannot act on a model of dimension `d`, if it cannot (checked with the
    /// model's [`DynLagrangian::invalid_dimension`] before any step). The default finds
    /// nothing.
    fn invalid_dimension(&self, _d: usize) -> Option<String> {
        None
    }

    /// A half-bandwidth `b` that both blocks of the Jacobian keep (`|i − j| ≤ b` for every
    /// entry), as [`DynLagrangian::hessian_bandwidth`]: with the model's, the step Jacobian is
    /// factorised in the model's own order on that band. The default, `None`, lets the solver
    /// read the pattern off the entries (and reorder the unknowns to narrow it).
    fn bandwidth(&self) -> Option<usize> {
        None
    }
}

/// `f = −∂R/∂v` is the momentum of `R`, subtracted (one buffer of length `d` per evaluation;
/// a hand-written [`DynForce`] adds in place); its Jacobian, the `xv` and `vv` blocks of `R`'s
/// Hessian. (Keeping both buffers between evaluations in thread-local storage measured 4 %
/// faster on a chain of 1024 under dashpots, not worth the machinery.)
impl<R: DynLagrangian> DynForce for Rayleigh<R> {
    fn add_force(&self, x: &[f64], v: &[f64], t: f64, f: &mut [f64]) {
        let mut momentum = vec![0.0; f.len()];
        self.0.momentum(x, v, t, &mut momentum);
        for (f, p) in f.iter_mut().zip(&momentum) {
            *f -= p;
        }
    }

    fn jacobian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseForceJacobian) {
        let mut hessian = SparseHessian::new(self.0.dimension());
        self.0.hessian(x, v, t, &mut hessian);
        // ∂f/∂x = −(∂²R/∂x∂v)ᵀ, ∂f/∂v = −∂²R/∂v².
        for &(i, j, value) in hessian.xv.entries() {
            out.x.add(j, i, -value);
        }
        for &(i, j, value) in hessian.vv.entries() {
            out.v.add(i, j, -value);
        }
    }

    fn jacobian_dependence(&self) -> ForceDependence {
        ForceDependence::of_dissipation(self.0.hessian_dependence())
    }

    fn constants(&self) -> Vec<(&'static str, f64)> {
        self.0.constants()
    }

    /// The dissipation function's Hessian band, which holds `∂²R/∂x∂v` and `∂²R/∂v²`.
    fn bandwidth(&self) -> Option<usize> {
        self.0.hessian_bandwidth()
    }

    fn invalid_dimension(&self, d: usize) -> Option<String> {
        let own = self.0.dimension();
        if own != d {
            return Some(format!(
                "the dissipation function has dimension {own}, the model it acts on {d}"
            ));
        }
        self.0.invalid_dimension()
    }
}

/// `L` under `f` on the run-time path: [`DynLagrangian::force`] writes `∂L/∂x + f`.
impl<L: DynLagrangian, F: DynForce> DynLagrangian for Forced<L, F> {
    fn dimension(&self) -> usize {
        self.lagrangian.dimension()
    }
    fn value(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        self.lagrangian.value(x, v, t)
    }
    fn force(&self, x: &[f64], v: &[f64], t: f64, f: &mut [f64]) {
        self.lagrangian.force(x, v, t, f);
        self.force.add_force(x, v, t, f);
    }
    fn momentum(&self, x: &[f64], v: &[f64], t: f64, p: &mut [f64]) {
        self.lagrangian.momentum(x, v, t, p)
    }
    fn hessian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseHessian) {
        self.lagrangian.hessian(x, v, t, out)
    }
    fn hessian_dependence(&self) -> HessianDependence {
        self.lagrangian.hessian_dependence()
    }
    /// The wider of the model's band and the force's, when both declare one; otherwise
    /// `None` (the solver reads the pattern of both off their entries).
    fn hessian_bandwidth(&self) -> Option<usize> {
        let model = self.lagrangian.hessian_bandwidth()?;
        Some(model.max(self.force.bandwidth()?))
    }
    fn dependence(&self) -> Dependence {
        self.lagrangian.dependence()
    }
    fn invalid_dimension(&self) -> Option<String> {
        let d = self.lagrangian.dimension();
        (self.lagrangian.invalid_dimension()).or_else(|| self.force.invalid_dimension(d))
    }
    fn constants(&self) -> Vec<(&'static str, f64)> {
        let mut constants = self.lagrangian.constants();
        constants.extend(self.force.constants());
        constants
    }
    fn energy(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        self.lagrangian.energy(x, v, t)
    }
    fn is_forced(&self) -> bool {
        true
    }
    fn force_dependence(&self) -> Option<[Dependence; 2]> {
        let own = self.force.jacobian_dependence();
        Some(joined([own.x, own.v], self.lagrangian.force_dependence()))
    }
    /// The force's entries, and those of a force `L` itself carries (a nested `Forced`).
    fn force_jacobian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseForceJacobian) {
        self.lagrangian.force_jacobian(x, v, t, out);
        self.force.jacobian(x, v, t, out)
    }
}

/// The discrete forces, impulses and work of a run-time-dimension solution: those of
/// [`Forced::discrete_forces`], [`Forced::impulses`] and [`Forced::work`], by the same
/// quadrature, on a [`DynSolution`] that stores every node.
impl<L, F: DynForce> Forced<L, F> {
    /// [`Forced::discrete_forces`] of a [`DynSolution`]: `(f_d^−, f_d^+)` of each interval,
    /// `d` values each. [`Error::WrongLength`] for a solution that does not store every node
    /// (from [`DynProblem::solve_ivp_every`](crate::DynProblem::solve_ivp_every) with a stride
    /// above 1); [`Error::Unsupported`] for the Gauss–Legendre and fractional embeddings.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Forced, Grid, Scheme, force, lagrangian};
    ///
    /// #[lagrangian]
    /// fn springs(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     (0..n).map(|i| 0.5 * v[i] * v[i] - 0.5 * x[i] * x[i]).sum()
    /// }
    /// #[force]
    /// fn friction(_x: &[f64], v: &[f64], n: usize, gamma: f64) -> Vec<f64> {
    ///     let mut f = vec![0.0; n];
    ///     for i in 0..n {
    ///         f[i] -= gamma * v[i];
    ///     }
    ///     f
    /// }
    ///
    /// let model = Forced::new(Springs { n: 3 }, Friction { n: 3, gamma: 0.1 });
    /// let grid = Grid::new(0.0, 1.0, 100)?;
    /// let run = DynProblem::new(&model, grid, Embedding::midpoint())
    ///     .solve_ivp(Scheme::Variational, &[1.0, 0.0, -1.0], &[0.0; 3])?;
    /// let forces = model.dyn_discrete_forces(&run)?;
    /// assert_eq!((forces.len(), forces[0].0.len()), (100, 3));
    /// // Friction takes energy out: its work is negative.
    /// assert!(model.dyn_work(&run)?[100] < 0.0);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn dyn_discrete_forces(&self, solution: &DynSolution) -> Result<Vec<(Vec<f64>, Vec<f64>)>> {
        let grid = solution.run.grid;
        if solution.indices.len() != grid.n() + 1 {
            return Err(Error::WrongLength {
                what: "the stored nodes of the solution (the discrete forces read every node: solve_ivp, not solve_ivp_every)",
                expected: grid.n() + 1,
                found: solution.indices.len(),
            });
        }
        discrete_force_pairs(
            &solution.run.embedding,
            &grid,
            (solution.dimension, &solution.q),
            |x, v, t, f| {
                f.fill(0.0);
                self.force.add_force(x, v, t, f);
            },
        )
    }

    /// [`Forced::impulses`] of a [`DynSolution`]: `f_d^− + f_d^+` of each interval. Errors as
    /// [`dyn_discrete_forces`](Self::dyn_discrete_forces).
    pub fn dyn_impulses(&self, solution: &DynSolution) -> Result<Vec<Vec<f64>>> {
        Ok(self
            .dyn_discrete_forces(solution)?
            .into_iter()
            .map(|(left, right)| left.iter().zip(&right).map(|(l, r)| l + r).collect())
            .collect())
    }

    /// [`Forced::work`] of a [`DynSolution`]: `W_0 = 0`,
    /// `W_{k+1} = W_k + impulse_k·(Q_{k+1} − Q_k)/h`. Errors as
    /// [`dyn_discrete_forces`](Self::dyn_discrete_forces).
    pub fn dyn_work(&self, solution: &DynSolution) -> Result<Vec<f64>> {
        let impulses = self.dyn_impulses(solution)?;
        let (h, d, q) = (solution.run.grid.h(), solution.dimension, &solution.q);
        let mut work = Vec::with_capacity(impulses.len() + 1);
        work.push(0.0);
        for (k, impulse) in impulses.iter().enumerate() {
            let step: f64 = (0..d)
                .map(|i| impulse[i] * (q[(k + 1) * d + i] - q[k * d + i]))
                .sum();
            work.push(work[k] + step / h);
        }
        Ok(work)
    }
}
