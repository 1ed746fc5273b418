//! A wrapper that hides a model's Hessian bandwidth, so that a run takes the dense step
//! solve: the reference the banded one is compared with, in tests and benches.

use varembed::{Dependence, Hessian, HessianDependence, Lagrangian, Vector};

/// Forwards every method of `L` but claims no bandwidth: the dense Newton path.
pub struct Dense<L>(pub L);

impl<const D: usize, L: Lagrangian<D>> Lagrangian<D> for Dense<L> {
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
        None
    }
}
