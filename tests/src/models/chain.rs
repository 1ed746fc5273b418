//! The FPUT chain written by hand as a [`DynLagrangian`]: plain loops over the bonds, with the
//! force and the tridiagonal (or, periodic, cyclic) Hessian derived on paper. The independent
//! second computation the run-time-dimension solver and the generated models are checked
//! against.

use varembed::{Dependence, DynLagrangian, HessianDependence, SparseHessian};

/// `n` unit masses, neighbours joined by the FPUT spring `V(d) = d²/2 + α d³/3 + β d⁴/4`:
/// between two walls at 0 (`x_{−1} = x_n = 0`, the bonds to the walls included), or periodic
/// (`x_n = x_0`). `L = Σ ½ v_i² − Σ V(d)`.
#[derive(Clone, Copy, Debug)]
pub struct FputChain {
    /// Number of moving masses.
    pub n: usize,
    /// Cubic coefficient α.
    pub alpha: f64,
    /// Quartic coefficient β.
    pub beta: f64,
    /// Periodic (a ring) rather than between walls.
    pub periodic: bool,
}

impl FputChain {
    /// `V'(d)`.
    fn dv(&self, d: f64) -> f64 {
        d + self.alpha * d * d + self.beta * d * d * d
    }
    /// `V''(d)`.
    fn ddv(&self, d: f64) -> f64 {
        1.0 + 2.0 * self.alpha * d + 3.0 * self.beta * d * d
    }
    /// `V(d)`.
    fn v(&self, d: f64) -> f64 {
        0.5 * d * d + self.alpha / 3.0 * d.powi(3) + self.beta / 4.0 * d.powi(4)
    }
    /// The bonds between masses, `(j, k, d)` with `d = x_k − x_j`.
    fn bonds<'a>(&'a self, x: &'a [f64]) -> impl Iterator<Item = (usize, usize, f64)> + 'a {
        let n = self.n;
        let inner = if self.periodic { n } else { n - 1 };
        (0..inner).map(move |i| (i, (i + 1) % n, x[(i + 1) % n] - x[i]))
    }
    /// The bonds to the walls, `(j, s)`: mass `j` with the bond `d = s x_j` (`s = 1` at the
    /// left wall, `−1` at the right); none for a ring.
    fn walls(&self) -> Vec<(usize, f64)> {
        if self.periodic {
            vec![]
        } else {
            vec![(0, 1.0), (self.n - 1, -1.0)]
        }
    }
}

impl DynLagrangian for FputChain {
    fn dimension(&self) -> usize {
        self.n
    }
    fn value(&self, x: &[f64], v: &[f64], _t: f64) -> f64 {
        let kinetic: f64 = v.iter().map(|v| 0.5 * v * v).sum();
        let bonds: f64 = self.bonds(x).map(|(_, _, d)| self.v(d)).sum();
        let walls: f64 = self.walls().iter().map(|&(j, s)| self.v(s * x[j])).sum();
        kinetic - bonds - walls
    }
    fn force(&self, x: &[f64], _v: &[f64], _t: f64, f: &mut [f64]) {
        f.fill(0.0);
        for (j, k, d) in self.bonds(x) {
            let dv = self.dv(d);
            f[k] -= dv;
            f[j] += dv;
        }
        for (j, s) in self.walls() {
            f[j] -= s * self.dv(s * x[j]);
        }
    }
    fn momentum(&self, _x: &[f64], v: &[f64], _t: f64, p: &mut [f64]) {
        p.copy_from_slice(v);
    }
    fn hessian(&self, x: &[f64], _v: &[f64], _t: f64, out: &mut SparseHessian) {
        for i in 0..self.n {
            out.vv.add(i, i, 1.0);
        }
        for (j, k, d) in self.bonds(x) {
            let c = self.ddv(d);
            out.xx.add(j, j, -c);
            out.xx.add(k, k, -c);
            out.xx.add(j, k, c);
            out.xx.add(k, j, c);
        }
        for (j, s) in self.walls() {
            out.xx.add(j, j, -self.ddv(s * x[j]));
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        HessianDependence {
            xx: Dependence {
                x: true,
                v: false,
                t: false,
            },
            xv: Dependence::NONE,
            vv: Dependence::NONE,
        }
    }
    fn hessian_bandwidth(&self) -> Option<usize> {
        (!self.periodic).then_some(1)
    }
    fn dependence(&self) -> Dependence {
        Dependence {
            x: true,
            v: true,
            t: false,
        }
    }
    fn constants(&self) -> Vec<(&'static str, f64)> {
        vec![("alpha", self.alpha), ("beta", self.beta)]
    }
}
