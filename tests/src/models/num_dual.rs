//! The double pendulum with every derivative from num-dual's (hyper-)dual numbers, the crate a
//! Rust user would otherwise pick. The implicit-step bench times it against
//! [`DoublePendulum`] and the num-dual oracle test checks that the two agree, so
//! both measure the same model.

use nalgebra::SVector;
use num_dual::{DualNum, HyperDual64};
use varembed::{Hessian, Lagrangian, Vector};

use crate::models::generated::DoublePendulum;

/// [`generated::double_pendulum`](crate::models::generated::double_pendulum) for num-dual,
/// generic over the (hyper-)dual number type.
pub fn double_pendulum_dual<T: DualNum<Primitive = f64> + Copy>(
    p: &DoublePendulum,
    x: [T; 2],
    v: [T; 2],
) -> T {
    let DoublePendulum { m1, m2, l1, l2, g } = *p;
    let kinetic = v[0] * v[0] * (0.5 * (m1 + m2) * l1 * l1)
        + v[1] * v[1] * (0.5 * m2 * l2 * l2)
        + v[0] * v[1] * (x[0] - x[1]).cos() * (m2 * l1 * l2);
    let potential = -x[0].cos() * ((m1 + m2) * g * l1) - x[1].cos() * (m2 * g * l2);
    kinetic - potential
}

/// The double pendulum with every derivative from num-dual.
pub struct NumDualDoublePendulum(pub DoublePendulum);

/// `z = (x, v)`, the variables num-dual differentiates in.
pub fn stack(x: &Vector<2>, v: &Vector<2>) -> SVector<f64, 4> {
    SVector::<f64, 4>::new(x[0], x[1], v[0], v[1])
}

impl Lagrangian<2> for NumDualDoublePendulum {
    fn value(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> f64 {
        double_pendulum_dual(&self.0, [x[0], x[1]], [v[0], v[1]])
    }
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> (Vector<2>, Vector<2>) {
        let (_, grad) = num_dual::gradient(
            |z| double_pendulum_dual(&self.0, [z[0], z[1]], [z[2], z[3]]),
            &stack(x, v),
        );
        (
            grad.fixed_rows::<2>(0).into_owned(),
            grad.fixed_rows::<2>(2).into_owned(),
        )
    }
    fn hessian(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> Hessian<2> {
        self.gradient_and_hessian(x, v, t).2
    }
    /// One `num_dual::hessian` call: its hyper-dual numbers carry the gradient too.
    fn gradient_and_hessian(
        &self,
        x: &Vector<2>,
        v: &Vector<2>,
        _t: f64,
    ) -> (Vector<2>, Vector<2>, Hessian<2>) {
        let (_, grad, hess) = num_dual::hessian(
            |z| double_pendulum_dual(&self.0, [z[0], z[1]], [z[2], z[3]]),
            &stack(x, v),
        );
        let hessian = Hessian {
            xx: hess.fixed_view::<2, 2>(0, 0).into_owned(),
            xv: hess.fixed_view::<2, 2>(0, 2).into_owned(),
            vv: hess.fixed_view::<2, 2>(2, 2).into_owned(),
        };
        (
            grad.fixed_rows::<2>(0).into_owned(),
            grad.fixed_rows::<2>(2).into_owned(),
            hessian,
        )
    }
}

/// Value, gradient and Hessian of `f` at `z` from hyper-dual numbers, entry by entry: the
/// oracle the macro's derivatives are checked against, one independent evaluation per entry.
pub fn dual_derivatives(
    f: &dyn Fn(&[HyperDual64]) -> HyperDual64,
    z: &[f64],
) -> (f64, Vec<f64>, Vec<Vec<f64>>) {
    let m = z.len();
    let seed = |a: usize, b: usize| -> HyperDual64 {
        let w: Vec<HyperDual64> = (0..m)
            .map(|k| {
                HyperDual64::new(
                    z[k],
                    f64::from(u8::from(k == a)),
                    f64::from(u8::from(k == b)),
                    0.0,
                )
            })
            .collect();
        f(&w)
    };
    let value = seed(m, m).re;
    let gradient = (0..m).map(|a| seed(a, m).eps1).collect();
    let hessian = (0..m)
        .map(|a| (0..m).map(|b| seed(a, b).eps1eps2).collect())
        .collect();
    (value, gradient, hessian)
}

/// Asserts a generated value `a` equals its oracle `b` to 1e-12, relative to `max(|b|, 1)`.
pub fn close(what: &str, a: f64, b: f64) {
    assert!(
        (a - b).abs() <= 1e-12 * b.abs().max(1.0),
        "{what}: generated {a:e}, oracle {b:e}"
    );
}

/// Asserts the value and every derivative method of `lag` at `(x, v, t = 0)` against the
/// hyper-dual `oracle` of the same Lagrangian on `z = (x, v)` (each to 1e-12 by [`close`]), and
/// the fused methods (`gradient_and_hessian`, `value_and_gradient`) against the separate ones,
/// bit for bit. Returns the Hessian, for checks of its structure.
pub fn assert_matches_oracle<const D: usize>(
    name: &str,
    lag: &impl Lagrangian<D>,
    oracle: &dyn Fn(&[HyperDual64]) -> HyperDual64,
    x: &Vector<D>,
    v: &Vector<D>,
) -> Hessian<D> {
    let z: Vec<f64> = x.iter().chain(v.iter()).copied().collect();
    let (value, grad, hess) = dual_derivatives(oracle, &z);
    close(&format!("{name} L"), lag.value(x, v, 0.0), value);
    let (f, q) = lag.gradient(x, v, 0.0);
    let h = lag.hessian(x, v, 0.0);
    let (ff, fq, fh) = lag.gradient_and_hessian(x, v, 0.0);
    let (fl, gf, gq) = lag.value_and_gradient(x, v, 0.0);
    close(&format!("{name} fused L"), fl, value);
    for i in 0..D {
        close(&format!("{name} ∂L/∂x[{i}]"), f[i], grad[i]);
        close(&format!("{name} ∂L/∂v[{i}]"), q[i], grad[D + i]);
        assert_eq!((ff[i], fq[i]), (f[i], q[i]), "{name}: fused gradient");
        assert_eq!((gf[i], gq[i]), (f[i], q[i]), "{name}: value and gradient");
        for j in 0..D {
            close(&format!("{name} xx[({i}, {j})]"), h.xx[(i, j)], hess[i][j]);
            close(
                &format!("{name} xv[({i}, {j})]"),
                h.xv[(i, j)],
                hess[i][D + j],
            );
            close(
                &format!("{name} vv[({i}, {j})]"),
                h.vv[(i, j)],
                hess[D + i][D + j],
            );
        }
    }
    assert_eq!(
        (fh.xx, fh.xv, fh.vv),
        (h.xx, h.xv, h.vv),
        "{name}: fused Hessian"
    );
    h
}
