//! Lagrangians shared by the unit tests of several modules.

use crate::dynamic::DynLagrangian;
use crate::dynamic::sparse::{SparseForceJacobian, SparseHessian};
use crate::force::{Force, Forced};
use crate::lagrangian::{ForceJacobian, Hessian, Lagrangian, Matrix, Vector};

/// `L = ½(1 + x₀²)v₀² + ½v₁² + sin(t) x₁ v₀ + x₀ v₀ v₁ − cos x₀ − x₁⁴/4`.
pub(crate) struct Mixed;
impl Lagrangian<2> for Mixed {
    fn value(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> f64 {
        0.5 * (1.0 + x[0] * x[0]) * v[0] * v[0]
            + 0.5 * v[1] * v[1]
            + t.sin() * x[1] * v[0]
            + x[0] * v[0] * v[1]
            - x[0].cos()
            - 0.25 * x[1].powi(4)
    }
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> (Vector<2>, Vector<2>) {
        (
            Vector::<2>::new(
                x[0] * v[0] * v[0] + v[0] * v[1] + x[0].sin(),
                t.sin() * v[0] - x[1].powi(3),
            ),
            Vector::<2>::new(
                (1.0 + x[0] * x[0]) * v[0] + t.sin() * x[1] + x[0] * v[1],
                v[1] + x[0] * v[0],
            ),
        )
    }
    fn hessian(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> Hessian<2> {
        Hessian {
            xx: Matrix::<2>::new(v[0] * v[0] + x[0].cos(), 0.0, 0.0, -3.0 * x[1] * x[1]),
            xv: Matrix::<2>::new(2.0 * x[0] * v[0] + v[1], v[0], t.sin(), 0.0),
            vv: Matrix::<2>::new(1.0 + x[0] * x[0], x[0], x[0], 1.0),
        }
    }
}

/// A force on [`Mixed`]'s space whose Jacobian blocks are neither symmetric nor constant:
/// `f = (−v₀|v₀| x₁ + cos t, −0.5 v₁ x₀² + sin x₀ v₀)`.
pub(crate) struct MixedDrag;
impl Force<2> for MixedDrag {
    fn force(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> Vector<2> {
        Vector::<2>::new(
            -v[0] * v[0].abs() * x[1] + t.cos(),
            -0.5 * v[1] * x[0] * x[0] + x[0].sin() * v[0],
        )
    }
    fn jacobian(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> ForceJacobian<2> {
        ForceJacobian {
            x: Matrix::<2>::new(
                0.0,
                -v[0] * v[0].abs(),
                -v[1] * x[0] + x[0].cos() * v[0],
                0.0,
            ),
            v: Matrix::<2>::new(
                -2.0 * v[0].abs() * x[1],
                0.0,
                x[0].sin(),
                -0.5 * x[0] * x[0],
            ),
        }
    }
}

/// [`Mixed`] under [`MixedDrag`].
pub(crate) const FORCED_MIXED: Forced<Mixed, MixedDrag> = Forced::new(Mixed, MixedDrag);

/// The dimension of [`DynMixed`].
pub(crate) const DYN_MIXED_DIMENSION: usize = 5;

/// A run-time-dimension model whose every block is non-zero, not symmetric where it may not be
/// (`L_xv`), depends on `x`, `v` and `t`, and couples neighbours on a ring of
/// [`DYN_MIXED_DIMENSION`] sites (so a band order must wrap or reorder):
/// `L = Σ_i [½ (1 + x_i²) v_i² + x_i v_{i+1} − cos(x_i − x_{i+1}) + t x_i v_i]`; with `forced`,
/// under the force `f_i = −0.3 v_i x_{i+1}` with its own Jacobian.
pub(crate) struct DynMixed {
    pub(crate) forced: bool,
}

impl DynMixed {
    /// `L`, `∂L/∂x` plus the force, and `∂L/∂v`.
    fn parts(&self, x: &[f64], v: &[f64], t: f64) -> (f64, [f64; 5], [f64; 5]) {
        const D: usize = DYN_MIXED_DIMENSION;
        let (mut value, mut f, mut p) = (0.0, [0.0; D], [0.0; D]);
        for i in 0..D {
            let j = (i + 1) % D;
            value += 0.5 * (1.0 + x[i] * x[i]) * v[i] * v[i] + x[i] * v[j] - (x[i] - x[j]).cos()
                + t * x[i] * v[i];
            f[i] += x[i] * v[i] * v[i] + v[j] + (x[i] - x[j]).sin() + t * v[i];
            f[j] -= (x[i] - x[j]).sin();
            if self.forced {
                f[i] -= 0.3 * v[i] * x[j];
            }
            p[i] += (1.0 + x[i] * x[i]) * v[i] + t * x[i];
            p[j] += x[i];
        }
        (value, f, p)
    }
}

impl DynLagrangian for DynMixed {
    fn dimension(&self) -> usize {
        DYN_MIXED_DIMENSION
    }
    fn value(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        self.parts(x, v, t).0
    }
    fn force(&self, x: &[f64], v: &[f64], t: f64, f: &mut [f64]) {
        f.copy_from_slice(&self.parts(x, v, t).1);
    }
    fn momentum(&self, x: &[f64], v: &[f64], t: f64, p: &mut [f64]) {
        p.copy_from_slice(&self.parts(x, v, t).2);
    }
    fn hessian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseHessian) {
        const D: usize = DYN_MIXED_DIMENSION;
        for i in 0..D {
            let j = (i + 1) % D;
            let c = (x[i] - x[j]).cos();
            out.xx.add(i, i, v[i] * v[i] + c);
            out.xx.add(j, j, c);
            out.xx.add(i, j, -c);
            out.xx.add(j, i, -c);
            out.xv.add(i, i, 2.0 * x[i] * v[i] + t);
            out.xv.add(i, j, 1.0);
            out.vv.add(i, i, 1.0 + x[i] * x[i]);
        }
    }
    fn is_forced(&self) -> bool {
        self.forced
    }
    fn force_jacobian(&self, x: &[f64], v: &[f64], _t: f64, out: &mut SparseForceJacobian) {
        const D: usize = DYN_MIXED_DIMENSION;
        if self.forced {
            for i in 0..D {
                let j = (i + 1) % D;
                out.x.add(i, j, -0.3 * v[i]);
                out.v.add(i, i, -0.3 * x[j]);
            }
        }
    }
}
