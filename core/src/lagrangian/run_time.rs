//! The [`DynLagrangian`] trait: a Lagrangian whose dimension is a run-time value, with sparse
//! second derivatives. A child of the lagrangian module, which re-exports it.

use super::{Dependence, HessianDependence};
use crate::dynamic::sparse::{SparseBlock, SparseForceJacobian, SparseHessian};

/// A Lagrangian `L(x, v, t)` on `R^d × R^d × R` with `d` known at run time, and sparse second
/// derivatives.
///
/// `#[lagrangian]` implements it for every model written with loops (a named dimension
/// `[f64; N]`, or slices `x: &[f64]` whose length is a `usize` model constant); a hand-written
/// implementation provides [`dimension`](Self::dimension), [`value`](Self::value),
/// [`force`](Self::force), [`momentum`](Self::momentum) and [`hessian`](Self::hessian).
///
/// # Example
///
/// ```
/// use varembed::{DynLagrangian, SparseHessian};
///
/// /// A chain of `n` unit masses, neighbours joined by unit springs, ends free.
/// struct Chain { n: usize }
///
/// impl DynLagrangian for Chain {
///     fn dimension(&self) -> usize { self.n }
///     fn value(&self, x: &[f64], v: &[f64], _t: f64) -> f64 {
///         let kinetic: f64 = v.iter().map(|v| 0.5 * v * v).sum();
///         let springs: f64 = x.windows(2).map(|w| 0.5 * (w[1] - w[0]).powi(2)).sum();
///         kinetic - springs
///     }
///     fn force(&self, x: &[f64], _v: &[f64], _t: f64, f: &mut [f64]) {
///         f.fill(0.0);
///         for i in 0..self.n - 1 {
///             let s = x[i + 1] - x[i];
///             f[i] += s;
///             f[i + 1] -= s;
///         }
///     }
///     fn momentum(&self, _x: &[f64], v: &[f64], _t: f64, p: &mut [f64]) {
///         p.copy_from_slice(v);
///     }
///     fn hessian(&self, _x: &[f64], _v: &[f64], _t: f64, out: &mut SparseHessian) {
///         for i in 0..self.n {
///             out.vv.add(i, i, 1.0);
///         }
///         for i in 0..self.n - 1 {
///             out.xx.add(i, i, -1.0);
///             out.xx.add(i + 1, i + 1, -1.0);
///             out.xx.add(i, i + 1, 1.0);
///             out.xx.add(i + 1, i, 1.0);
///         }
///     }
///     fn hessian_bandwidth(&self) -> Option<usize> { Some(1) }
/// }
///
/// let chain = Chain { n: 3 };
/// let mut f = [0.0; 3];
/// chain.force(&[0.0, 1.0, 3.0], &[0.0; 3], 0.0, &mut f);
/// assert_eq!(f, [1.0, 1.0, -2.0]);
/// ```
pub trait DynLagrangian {
    /// The dimension `d`: the length of `x` and `v`.
    fn dimension(&self) -> usize;

    /// `L(x, v, t)`.
    fn value(&self, x: &[f64], v: &[f64], t: f64) -> f64;

    /// Writes `∂L/∂x` at `(x, v, t)` into `f` (every entry is overwritten).
    fn force(&self, x: &[f64], v: &[f64], t: f64, f: &mut [f64]);

    /// Writes `∂L/∂v` at `(x, v, t)` into `p` (every entry is overwritten).
    fn momentum(&self, x: &[f64], v: &[f64], t: f64, p: &mut [f64]);

    /// Adds the entries of the three second-derivative blocks at `(x, v, t)` to `out`, which
    /// the caller has cleared: `out.xx.add(i, j, ∂²L/∂x_i∂x_j)`, `out.xv.add(i, j, ∂²L/∂x_i∂v_j)`,
    /// `out.vv.add(i, j, ∂²L/∂v_i∂v_j)`. An entry may be added to more than once
    /// (the contributions sum); an entry never added is zero. A loop over many entries runs
    /// faster through [`SparseHessian::writer`] (`let mut out = out.writer();`, then the same
    /// `out.xx.add(i, j, e)`), as `#[lagrangian]` writes it: the blocks' fields stay in local
    /// variables instead of being read back after every entry.
    fn hessian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseHessian);

    /// What each second-derivative block depends on (see
    /// [`Lagrangian::hessian_dependence`](crate::Lagrangian::hessian_dependence)). The default
    /// claims nothing; a step whose Jacobian is constant is factorised once per run.
    fn hessian_dependence(&self) -> HessianDependence {
        HessianDependence::ALL
    }

    /// The structural half-bandwidth of the second derivatives, as in
    /// [`Lagrangian::hessian_bandwidth`](crate::Lagrangian::hessian_bandwidth). `None` (the
    /// default) makes the solver order the unknowns by the pattern it reads off
    /// [`hessian`](Self::hessian) (reverse Cuthill–McKee): a periodic chain becomes a band of
    /// half-width 2.
    fn hessian_bandwidth(&self) -> Option<usize> {
        None
    }

    /// On which of `x`, `v`, `t` the Lagrangian depends (see
    /// [`Lagrangian::dependence`](crate::Lagrangian::dependence)).
    fn dependence(&self) -> Dependence {
        Dependence::ALL
    }

    /// Why this model cannot be evaluated at its dimension, if it cannot: a component read
    /// beyond it, or a loop whose range needs more components than there are. The solvers ask
    /// before the first step and report it as [`Error::InvalidModel`](crate::Error). The
    /// default finds nothing; `#[lagrangian]` checks, at run time, what it checks at compile
    /// time for a named dimension.
    fn invalid_dimension(&self) -> Option<String> {
        None
    }

    /// The model's constants by name, so that a non-finite one is reported by its name.
    fn constants(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }

    /// Whether [`force`](Self::force) writes `∂L/∂x + f` with `f` a generalised force (a
    /// [`Forced`](crate::Forced) model), as [`Lagrangian::is_forced`](crate::Lagrangian). The
    /// default: `false`.
    fn is_forced(&self) -> bool {
        false
    }

    /// What `∂f/∂x` and `∂f/∂v` of that force depend on, as
    /// [`Lagrangian::force_dependence`](crate::Lagrangian). The default, `None`, claims nothing.
    fn force_dependence(&self) -> Option<[Dependence; 2]> {
        None
    }

    /// Adds the entries of `∂f/∂x` and `∂f/∂v` of that force at `(x, v, t)` to `out`, which the
    /// caller has cleared (in a loop, through [`SparseForceJacobian::writer`], as
    /// [`hessian`](Self::hessian) through its writer). The default adds nothing.
    fn force_jacobian(&self, _x: &[f64], _v: &[f64], _t: f64, _out: &mut SparseForceJacobian) {}

    /// The energy `E = v·∂L/∂v − L` (allocates one buffer of length `d`).
    fn energy(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        let mut p = vec![0.0; x.len()];
        self.momentum(x, v, t, &mut p);
        v.iter().zip(&p).map(|(v, p)| v * p).sum::<f64>() - self.value(x, v, t)
    }
}

impl<L: DynLagrangian + ?Sized> DynLagrangian for &L {
    fn dimension(&self) -> usize {
        (**self).dimension()
    }
    fn value(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        (**self).value(x, v, t)
    }
    fn force(&self, x: &[f64], v: &[f64], t: f64, f: &mut [f64]) {
        (**self).force(x, v, t, f)
    }
    fn momentum(&self, x: &[f64], v: &[f64], t: f64, p: &mut [f64]) {
        (**self).momentum(x, v, t, p)
    }
    fn hessian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseHessian) {
        (**self).hessian(x, v, t, out)
    }
    fn hessian_dependence(&self) -> HessianDependence {
        (**self).hessian_dependence()
    }
    fn hessian_bandwidth(&self) -> Option<usize> {
        (**self).hessian_bandwidth()
    }
    fn dependence(&self) -> Dependence {
        (**self).dependence()
    }
    fn invalid_dimension(&self) -> Option<String> {
        (**self).invalid_dimension()
    }
    fn constants(&self) -> Vec<(&'static str, f64)> {
        (**self).constants()
    }
    fn is_forced(&self) -> bool {
        (**self).is_forced()
    }
    fn force_dependence(&self) -> Option<[Dependence; 2]> {
        (**self).force_dependence()
    }
    fn force_jacobian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseForceJacobian) {
        (**self).force_jacobian(x, v, t, out)
    }
    fn energy(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        (**self).energy(x, v, t)
    }
}

/// A const-generic [`Lagrangian<D>`](crate::Lagrangian) seen as a [`DynLagrangian`] of
/// dimension `D`: the run-time engine's solvers on a small model that has no run-time form of
/// its own (its non-zero second-derivative entries listed from the dense blocks).
pub(crate) struct FixedDimension<'l, L: ?Sized, const D: usize>(pub(crate) &'l L);

impl<L: crate::Lagrangian<D> + ?Sized, const D: usize> FixedDimension<'_, L, D> {
    fn vectors(x: &[f64], v: &[f64]) -> (crate::Vector<D>, crate::Vector<D>) {
        (
            crate::Vector::<D>::from_column_slice(x),
            crate::Vector::<D>::from_column_slice(v),
        )
    }
}

/// Adds the non-zero entries of a dense block to a sparse one.
fn add_dense<const D: usize>(block: &crate::Matrix<D>, out: &mut SparseBlock) {
    for i in 0..D {
        for j in 0..D {
            if block[(i, j)] != 0.0 {
                out.add(i, j, block[(i, j)]);
            }
        }
    }
}

impl<L: crate::Lagrangian<D> + ?Sized, const D: usize> DynLagrangian for FixedDimension<'_, L, D> {
    fn dimension(&self) -> usize {
        D
    }
    fn value(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        let (x, v) = Self::vectors(x, v);
        self.0.value(&x, &v, t)
    }
    fn force(&self, x: &[f64], v: &[f64], t: f64, f: &mut [f64]) {
        let (x, v) = Self::vectors(x, v);
        f.copy_from_slice(self.0.gradient(&x, &v, t).0.as_slice());
    }
    fn momentum(&self, x: &[f64], v: &[f64], t: f64, p: &mut [f64]) {
        let (x, v) = Self::vectors(x, v);
        p.copy_from_slice(self.0.gradient(&x, &v, t).1.as_slice());
    }
    fn hessian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseHessian) {
        let (x, v) = Self::vectors(x, v);
        let h = self.0.hessian(&x, &v, t);
        add_dense(&h.xx, &mut out.xx);
        add_dense(&h.xv, &mut out.xv);
        add_dense(&h.vv, &mut out.vv);
    }
    fn hessian_dependence(&self) -> HessianDependence {
        self.0.hessian_dependence()
    }
    fn hessian_bandwidth(&self) -> Option<usize> {
        self.0.hessian_bandwidth()
    }
    fn dependence(&self) -> Dependence {
        self.0.dependence()
    }
    fn constants(&self) -> Vec<(&'static str, f64)> {
        self.0.constants()
    }
    fn is_forced(&self) -> bool {
        self.0.is_forced()
    }
    fn force_dependence(&self) -> Option<[Dependence; 2]> {
        self.0.force_dependence()
    }
    fn force_jacobian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseForceJacobian) {
        let (x, v) = Self::vectors(x, v);
        if let Some(force) = self.0.force_jacobian(&x, &v, t) {
            add_dense(&force.x, &mut out.x);
            add_dense(&force.v, &mut out.v);
        }
    }
    fn energy(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        let (x, v) = Self::vectors(x, v);
        self.0.energy(&x, &v, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A model whose every method answers something of its own, so that a forwarding impl
    /// that falls back to a default shows.
    struct Distinct;

    impl DynLagrangian for Distinct {
        fn dimension(&self) -> usize {
            2
        }
        fn value(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
            x[0] + 2.0 * v[1] + t
        }
        fn force(&self, _x: &[f64], _v: &[f64], t: f64, f: &mut [f64]) {
            f.copy_from_slice(&[1.0, t]);
        }
        fn momentum(&self, _x: &[f64], _v: &[f64], t: f64, p: &mut [f64]) {
            p.copy_from_slice(&[t, 2.0]);
        }
        fn hessian(&self, _x: &[f64], _v: &[f64], _t: f64, out: &mut SparseHessian) {
            out.xv.add(0, 1, 3.0);
        }
        fn hessian_bandwidth(&self) -> Option<usize> {
            Some(1)
        }
        fn invalid_dimension(&self) -> Option<String> {
            Some("distinct".into())
        }
        fn constants(&self) -> Vec<(&'static str, f64)> {
            vec![("c", 4.0)]
        }
        fn is_forced(&self) -> bool {
            true
        }
        fn force_jacobian(&self, _x: &[f64], _v: &[f64], _t: f64, out: &mut SparseForceJacobian) {
            out.v.add(1, 0, 5.0);
        }
        fn energy(&self, _x: &[f64], _v: &[f64], _t: f64) -> f64 {
            -7.0
        }
    }

    /// What the solvers see of a model through `&L` (and so behind `dyn DynLagrangian`, as
    /// `DynProblem` hands it to the run-time engine) is what the model itself answers.
    #[test]
    fn a_reference_answers_as_the_model() {
        let model = Distinct;
        let by_reference: &dyn DynLagrangian = &&model;
        let (x, v, t) = ([0.5, 1.5], [2.5, 3.5], 0.25);
        assert_eq!(by_reference.dimension(), model.dimension());
        assert_eq!(by_reference.value(&x, &v, t), model.value(&x, &v, t));
        assert_eq!(by_reference.energy(&x, &v, t), -7.0);
        let (mut f, mut p) = ([0.0; 2], [0.0; 2]);
        by_reference.force(&x, &v, t, &mut f);
        by_reference.momentum(&x, &v, t, &mut p);
        assert_eq!((f, p), ([1.0, t], [t, 2.0]));
        let mut hessian = SparseHessian::new(2);
        by_reference.hessian(&x, &v, t, &mut hessian);
        assert_eq!(hessian.xv.entries(), &[(0, 1, 3.0)]);
        let mut jacobian = SparseForceJacobian::new(2);
        by_reference.force_jacobian(&x, &v, t, &mut jacobian);
        assert_eq!(jacobian.v.entries(), &[(1, 0, 5.0)]);
        assert_eq!(by_reference.hessian_bandwidth(), Some(1));
        assert_eq!(
            by_reference.invalid_dimension().as_deref(),
            Some("distinct")
        );
        assert_eq!(by_reference.constants(), vec![("c", 4.0)]);
        assert!(by_reference.is_forced());
    }
}
