//! Lagrangians shared by the unit tests of several modules.

use crate::lagrangian::{Hessian, Lagrangian, Matrix, Vector};

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
