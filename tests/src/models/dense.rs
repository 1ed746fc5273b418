//! Wrappers that keep a run on the const-generic path: [`Dense`] hides a model's Hessian
//! bandwidth and its run-time form, so that a run takes the dense step solve (the reference the
//! banded and the run-time ones are compared with, in tests and benches); [`ConstGeneric`]
//! hides only the run-time form, so that a large model written with loops keeps the
//! const-generic banded step solve instead of being handed to the run-time engine.

use varembed::{Dependence, Hessian, HessianDependence, Lagrangian, Vector};

/// Forwards every method of `L` but claims no bandwidth and no run-time form: the dense Newton
/// path.
pub struct Dense<L>(pub L);

/// Forwards every method of `L`, its bandwidth included, but not its run-time form: the
/// const-generic path at every size.
pub struct ConstGeneric<L>(pub L);

/// `Lagrangian<D>` for a wrapper of `L`, forwarding everything but `run_time` (left at its
/// default, `None`) and the bandwidth, which `bandwidth` gives from the wrapped model.
macro_rules! forward {
    ($wrapper:ident, $bandwidth:expr) => {
        impl<const D: usize, L: Lagrangian<D>> Lagrangian<D> for $wrapper<L> {
            fn value(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> f64 {
                self.0.value(x, v, t)
            }
            fn gradient(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> (Vector<D>, Vector<D>) {
                self.0.gradient(x, v, t)
            }
            fn hessian(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> Hessian<D> {
                self.0.hessian(x, v, t)
            }
            fn gradient_and_hessian(
                &self,
                x: &Vector<D>,
                v: &Vector<D>,
                t: f64,
            ) -> (Vector<D>, Vector<D>, Hessian<D>) {
                self.0.gradient_and_hessian(x, v, t)
            }
            fn value_and_gradient(
                &self,
                x: &Vector<D>,
                v: &Vector<D>,
                t: f64,
            ) -> (f64, Vector<D>, Vector<D>) {
                self.0.value_and_gradient(x, v, t)
            }
            fn hessian_dependence(&self) -> HessianDependence {
                self.0.hessian_dependence()
            }
            fn dependence(&self) -> Dependence {
                self.0.dependence()
            }
            fn constants(&self) -> Vec<(&'static str, f64)> {
                self.0.constants()
            }
            fn hessian_bandwidth(&self) -> Option<usize> {
                let bandwidth: fn(&L) -> Option<usize> = $bandwidth;
                bandwidth(&self.0)
            }
        }
    };
}

forward!(Dense, |_| None);
forward!(ConstGeneric, |model| model.hessian_bandwidth());
