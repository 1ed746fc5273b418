//! Lagrangians shared by the unit tests of several modules.

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
