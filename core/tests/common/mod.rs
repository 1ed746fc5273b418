//! Hand-written Lagrangians shared by the integration tests (the macro is tested elsewhere).
#![allow(dead_code)] // each test file uses a subset

use varembed::{Hessian, Lagrangian, Matrix, Vector};

/// A deterministic PRNG (SplitMix64), so that failures reproduce.
pub struct Rng(pub u64);
impl Rng {
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
    pub fn curve<const D: usize>(&mut self, n: usize, amplitude: f64) -> Vec<Vector<D>> {
        (0..=n)
            .map(|_| Vector::<D>::from_fn(|_, _| self.uniform(-amplitude, amplitude)))
            .collect()
    }
}

pub fn v1(x: f64) -> Vector<1> {
    Vector::<1>::new(x)
}

/// A non-separable, time-dependent Lagrangian in d = 2:
/// `L = ½(1 + x₀²)v₀² + ½v₁² + cos(t) x₀ v₁ + 0.3 x₁ v₀ v₁ − ½(1 + 0.1t)(x₀² + x₁⁴)`.
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

/// `L = ½v² − U(x)` in d = 1 with `U = x⁴/4 − cos x`.
pub struct Anharmonic;

impl Anharmonic {
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

/// Harmonic oscillator `L = ½v² − ½ω²x²`.
pub struct Oscillator {
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

/// Pendulum `L = ½ l² v² + g l cos x`.
pub struct Pendulum {
    pub g: f64,
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

/// Max-norm of a list of vectors.
pub fn max_norm<const D: usize>(x: &[Vector<D>]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.amax()))
}

/// Max-norm of the difference of two lists.
pub fn max_diff<const D: usize>(a: &[Vector<D>], b: &[Vector<D>]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).amax()))
}
