//! `c L`: a model's Lagrangian times a constant `c > 0`. Its Euler–Lagrange equations are those
//! of `L`, so every solver must give it the nodes of `L` (the scale-invariance tests).

use varembed::{
    Dependence, DynLagrangian, Hessian, HessianDependence, Lagrangian, SparseHessian, Vector,
};

/// `c · inner`: the value, gradient and Hessian blocks multiplied by `c`; what the blocks
/// depend on, the bandwidth and the dependence forwarded unchanged.
#[derive(Clone, Copy, Debug)]
pub struct Scaled<L> {
    /// The factor `c`.
    pub c: f64,
    /// The model `L`.
    pub inner: L,
}

impl<L> Scaled<L> {
    /// `c · inner`.
    pub fn new(c: f64, inner: L) -> Self {
        Scaled { c, inner }
    }

    fn hessian_times_c<const D: usize>(&self, hs: Hessian<D>) -> Hessian<D> {
        Hessian {
            xx: hs.xx * self.c,
            xv: hs.xv * self.c,
            vv: hs.vv * self.c,
        }
    }
}

impl<const D: usize, L: Lagrangian<D>> Lagrangian<D> for Scaled<L> {
    fn value(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> f64 {
        self.c * self.inner.value(x, v, t)
    }
    fn gradient(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> (Vector<D>, Vector<D>) {
        let (f, p) = self.inner.gradient(x, v, t);
        (f * self.c, p * self.c)
    }
    fn hessian(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> Hessian<D> {
        self.hessian_times_c(self.inner.hessian(x, v, t))
    }
    fn gradient_and_hessian(
        &self,
        x: &Vector<D>,
        v: &Vector<D>,
        t: f64,
    ) -> (Vector<D>, Vector<D>, Hessian<D>) {
        let (f, p, hs) = self.inner.gradient_and_hessian(x, v, t);
        (f * self.c, p * self.c, self.hessian_times_c(hs))
    }
    fn value_and_gradient(
        &self,
        x: &Vector<D>,
        v: &Vector<D>,
        t: f64,
    ) -> (f64, Vector<D>, Vector<D>) {
        let (l, f, p) = self.inner.value_and_gradient(x, v, t);
        (self.c * l, f * self.c, p * self.c)
    }
    fn hessian_dependence(&self) -> HessianDependence {
        self.inner.hessian_dependence()
    }
    fn hessian_bandwidth(&self) -> Option<usize> {
        self.inner.hessian_bandwidth()
    }
    fn dependence(&self) -> Dependence {
        self.inner.dependence()
    }
    fn constants(&self) -> Vec<(&'static str, f64)> {
        let mut constants = self.inner.constants();
        constants.push(("c", self.c));
        constants
    }
    fn energy(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> f64 {
        self.c * self.inner.energy(x, v, t)
    }
}

impl<L: DynLagrangian> DynLagrangian for Scaled<L> {
    fn dimension(&self) -> usize {
        self.inner.dimension()
    }
    fn value(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        self.c * self.inner.value(x, v, t)
    }
    fn force(&self, x: &[f64], v: &[f64], t: f64, f: &mut [f64]) {
        self.inner.force(x, v, t, f);
        f.iter_mut().for_each(|f| *f *= self.c);
    }
    fn momentum(&self, x: &[f64], v: &[f64], t: f64, p: &mut [f64]) {
        self.inner.momentum(x, v, t, p);
        p.iter_mut().for_each(|p| *p *= self.c);
    }
    /// The inner model's blocks into blocks of its own (a model may only add to the blocks it
    /// is given, never read them back), then each entry times `c` into `out`.
    fn hessian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseHessian) {
        let mut inner = SparseHessian::new(self.dimension());
        self.inner.hessian(x, v, t, &mut inner);
        for (from, to) in [
            (&inner.xx, &mut out.xx),
            (&inner.xv, &mut out.xv),
            (&inner.vv, &mut out.vv),
        ] {
            for &(i, j, value) in from.entries() {
                to.add(i, j, self.c * value);
            }
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        self.inner.hessian_dependence()
    }
    fn hessian_bandwidth(&self) -> Option<usize> {
        self.inner.hessian_bandwidth()
    }
    fn dependence(&self) -> Dependence {
        self.inner.dependence()
    }
    fn invalid_dimension(&self) -> Option<String> {
        self.inner.invalid_dimension()
    }
    fn constants(&self) -> Vec<(&'static str, f64)> {
        let mut constants = self.inner.constants();
        constants.push(("c", self.c));
        constants
    }
    fn energy(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        self.c * self.inner.energy(x, v, t)
    }
}
