//! Generalised forces on the run-time-dimension path: [`DynForce`], and what makes [`Rayleigh`]
//! one and [`Forced`] a [`DynLagrangian`].

use super::{ForceDependence, Forced, Rayleigh, joined};
use crate::dynamic::sparse::{SparseForceJacobian, SparseHessian};
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

    /// Adds the entries of `∂f/∂x` and `∂f/∂v` at `(x, v, t)` to `out` (cleared by the caller).
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
