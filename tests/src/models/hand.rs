//! Hand-written Lagrangians: plain formulas for `value`, `gradient` and `hessian`.

use varembed::{Dependence, Hessian, HessianDependence, Lagrangian, Matrix, Vector};

use crate::curve::v1;

/// A non-separable, time-dependent Lagrangian in d = 2:
/// `L = ½(1 + x₀²)v₀² + ½v₁² + cos(t) x₀ v₁ + 0.3 x₁ v₀ v₁ − ½(1 + 0.1t)(x₀² + x₁⁴)`.
///
/// Every Hessian block depends on the state and `L_xv` on `t`, so no step of it is affine and
/// no term of a scheme vanishes by accident.
pub struct Coupled;

impl Lagrangian<2> for Coupled {
    fn value(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> f64 {
        0.5 * (1.0 + x[0] * x[0]) * v[0] * v[0]
            + 0.5 * v[1] * v[1]
            + t.cos() * x[0] * v[1]
            + 0.3 * x[1] * v[0] * v[1]
            - 0.5 * (1.0 + 0.1 * t) * (x[0] * x[0] + x[1].powi(4))
    }
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> (Vector<2>, Vector<2>) {
        let s = 1.0 + 0.1 * t;
        (
            Vector::<2>::new(
                x[0] * v[0] * v[0] + t.cos() * v[1] - s * x[0],
                0.3 * v[0] * v[1] - 2.0 * s * x[1].powi(3),
            ),
            Vector::<2>::new(
                (1.0 + x[0] * x[0]) * v[0] + 0.3 * x[1] * v[1],
                v[1] + t.cos() * x[0] + 0.3 * x[1] * v[0],
            ),
        )
    }
    fn hessian(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> Hessian<2> {
        let s = 1.0 + 0.1 * t;
        Hessian {
            xx: Matrix::<2>::new(v[0] * v[0] - s, 0.0, 0.0, -6.0 * s * x[1] * x[1]),
            xv: Matrix::<2>::new(2.0 * x[0] * v[0], t.cos(), 0.3 * v[1], 0.3 * v[0]),
            vv: Matrix::<2>::new(1.0 + x[0] * x[0], 0.3 * x[1], 0.3 * x[1], 1.0),
        }
    }
}

/// `L = ½v² − U(x)` in d = 1 with `U = x⁴/4 − cos x`: separable, so its variational scheme is
/// Störmer–Verlet.
pub struct Anharmonic;

impl Anharmonic {
    /// The force `−U′(x) = −(x³ + sin x)`.
    pub fn force(x: f64) -> f64 {
        -(x.powi(3) + x.sin())
    }
}

impl Lagrangian<1> for Anharmonic {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        0.5 * v[0] * v[0] - (0.25 * x[0].powi(4) - x[0].cos())
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        (v1(Self::force(x[0])), *v)
    }
    fn hessian(&self, x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::new(-(3.0 * x[0] * x[0] + x[0].cos())),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}

/// Harmonic oscillator `L = ½v² − ½ω²x²`; its discrete solutions are in
/// [`crate::reference::DiscreteOscillation`].
pub struct Oscillator {
    /// The angular frequency `ω`.
    pub omega: f64,
}

impl Lagrangian<1> for Oscillator {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        0.5 * v[0] * v[0] - 0.5 * self.omega.powi(2) * x[0] * x[0]
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        (v1(-self.omega.powi(2) * x[0]), *v)
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::new(-self.omega.powi(2)),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}

/// The Caldirola–Kanai oscillator `L = e^{γt}(½v² − ½ω²x²)`: a damped oscillator, `L` depends
/// on `t` through a factor that grows along the run.
#[derive(Clone, Copy, Debug)]
pub struct CaldirolaKanai {
    /// The damping rate `γ`.
    pub gamma: f64,
    /// The angular frequency `ω`.
    pub omega: f64,
}

impl Lagrangian<1> for CaldirolaKanai {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
        (self.gamma * t).exp() * (0.5 * v[0] * v[0] - 0.5 * self.omega.powi(2) * x[0] * x[0])
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
        let e = (self.gamma * t).exp();
        (v1(-e * self.omega.powi(2) * x[0]), v1(e * v[0]))
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, t: f64) -> Hessian<1> {
        let e = (self.gamma * t).exp();
        Hessian {
            xx: Matrix::<1>::new(-e * self.omega.powi(2)),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::new(e),
        }
    }
}

/// Pendulum `L = ½ l² v² + g l cos x` (the same model as
/// [`generated::Pendulum`](crate::models::generated::Pendulum)).
pub struct Pendulum {
    /// Gravity `g`.
    pub g: f64,
    /// Length `l`.
    pub l: f64,
}

impl Lagrangian<1> for Pendulum {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        0.5 * self.l * self.l * v[0] * v[0] + self.g * self.l * x[0].cos()
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        (
            v1(-self.g * self.l * x[0].sin()),
            v1(self.l * self.l * v[0]),
        )
    }
    fn hessian(&self, x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::new(-self.g * self.l * x[0].cos()),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::new(self.l * self.l),
        }
    }
}

/// A block that depends on `x` only.
pub const ON_X: Dependence = Dependence {
    x: true,
    v: false,
    t: false,
};

/// `L_xx` depends on `x`, `L_xv` and `L_vv` are constants: `L = ½ vᵀMv + vᵀCx − U(x)`.
pub const SEPARABLE: HessianDependence = HessianDependence {
    xx: ON_X,
    xv: Dependence::NONE,
    vv: Dependence::NONE,
};

/// [`Pendulum`] as a user writing the impl for speed would: `#[inline]` methods and its
/// [`HessianDependence`] declared ([`SEPARABLE`]), so it takes the same closed-form steps as
/// the generated model.
pub struct DeclaredPendulum {
    /// Gravity `g`.
    pub g: f64,
    /// Length `l`.
    pub l: f64,
}

impl Lagrangian<1> for DeclaredPendulum {
    #[inline]
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        0.5 * self.l * self.l * v[0] * v[0] + self.g * self.l * x[0].cos()
    }
    #[inline]
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        let (g, l) = (self.g, self.l);
        (
            Vector::<1>::new(-g * l * x[0].sin()),
            Vector::<1>::new(l * l * v[0]),
        )
    }
    #[inline]
    fn hessian(&self, x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        let (g, l) = (self.g, self.l);
        Hessian {
            xx: Matrix::<1>::new(-g * l * x[0].cos()),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::new(l * l),
        }
    }
    #[inline]
    fn hessian_dependence(&self) -> HessianDependence {
        // L_vv constant and L_xv = 0; only the direct backward step sees L_xx(y).
        SEPARABLE
    }
}

/// The double pendulum of [`generated::DoublePendulum`](crate::models::generated::DoublePendulum)
/// by hand, `#[inline]`, with its [`HessianDependence`] declared.
pub struct DeclaredDoublePendulum {
    /// Mass of the first bob.
    pub m1: f64,
    /// Mass of the second bob.
    pub m2: f64,
    /// Length of the first rod.
    pub l1: f64,
    /// Length of the second rod.
    pub l2: f64,
    /// Gravity.
    pub g: f64,
}

impl Lagrangian<2> for DeclaredDoublePendulum {
    #[inline]
    fn value(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> f64 {
        let Self { m1, m2, l1, l2, g } = *self;
        crate::models::generated::double_pendulum([x[0], x[1]], [v[0], v[1]], m1, m2, l1, l2, g)
    }
    #[inline]
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> (Vector<2>, Vector<2>) {
        let Self { m1, m2, l1, l2, g } = *self;
        let (c, s) = ((x[0] - x[1]).cos(), (x[0] - x[1]).sin());
        let k = m2 * l1 * l2;
        let f = Vector::<2>::new(
            -k * v[0] * v[1] * s - (m1 + m2) * g * l1 * x[0].sin(),
            k * v[0] * v[1] * s - m2 * g * l2 * x[1].sin(),
        );
        let p = Vector::<2>::new(
            (m1 + m2) * l1 * l1 * v[0] + k * v[1] * c,
            m2 * l2 * l2 * v[1] + k * v[0] * c,
        );
        (f, p)
    }
    #[inline]
    fn hessian(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> Hessian<2> {
        let Self { m1, m2, l1, l2, g } = *self;
        let (c, s) = ((x[0] - x[1]).cos(), (x[0] - x[1]).sin());
        let k = m2 * l1 * l2;
        let kvvc = k * v[0] * v[1] * c;
        Hessian {
            xx: Matrix::<2>::new(
                -kvvc - (m1 + m2) * g * l1 * x[0].cos(),
                kvvc,
                kvvc,
                -kvvc - m2 * g * l2 * x[1].cos(),
            ),
            xv: Matrix::<2>::new(-k * v[1] * s, -k * v[0] * s, k * v[1] * s, k * v[0] * s),
            vv: Matrix::<2>::new((m1 + m2) * l1 * l1, k * c, k * c, m2 * l2 * l2),
        }
    }
    #[inline]
    fn hessian_dependence(&self) -> HessianDependence {
        // L_vv depends on x only: affine exactly when the Jacobian reads L_vv at the fixed
        // node b and nothing else (direct σ = +). L_xv depends on v, which rules out
        // VariationalForward.
        let on_x_and_v = Dependence {
            x: true,
            v: true,
            t: false,
        };
        HessianDependence {
            xx: on_x_and_v,
            xv: on_x_and_v,
            vv: ON_X,
        }
    }
}
