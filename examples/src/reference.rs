//! Reference solutions computed *independently* of the schemes under test.
//!
//! Where a scene has no closed-form solution, its Euler–Lagrange equation is written out by hand
//! as a first-order system `y = (q, q̇)`, `ẏ = (q̇, q̈(q, q̇, t))` — not derived by the macro —
//! and integrated by Hairer's DOP853 (the `ode_solvers` crate: explicit Runge–Kutta of order 8
//! with adaptive steps and a dense output of order 7) at `rtol = atol = 10⁻¹³` unless a tighter
//! tolerance is asked for. The curve is sampled on a fine uniform grid and evaluated between
//! samples by cubic Hermite interpolation from `q` and `q̇` (error `O(Δt⁴)`, below 10⁻¹³ at the
//! sample spacing used here).
//!
//! Time is carried as an extra state `τ` with `τ̇ = 1`, so DOP853 sees an autonomous system:
//! `ode_solvers` 0.6.2 evaluates the stages of a time-dependent right-hand side at the wrong
//! times (on the Mathieu equation it shrinks the step to 10⁻⁵ and diverges), while the
//! autonomous form is integrated correctly (checked below against `q = t³`).

use ode_solvers::{DVector, Dop853, System};
use varembed::Vector;

/// `q̈ = acceleration(q, q̇, t)`, written into the last argument.
pub type Acceleration = dyn Fn(&[f64], &[f64], f64, &mut [f64]) + Sync;

/// A solution `t ↦ (q(t), q̇(t))`: a closed form, or DOP853 samples every `dt` interpolated.
pub struct ReferenceCurve<const D: usize> {
    eval: Box<dyn Fn(f64) -> (Vector<D>, Vector<D>) + Sync>,
    /// How the curve was computed, for the report.
    pub name: String,
}

struct Samples<const D: usize> {
    a: f64,
    dt: f64,
    q: Vec<Vector<D>>,
    v: Vec<Vector<D>>,
}

struct FirstOrder<'a, const D: usize> {
    acceleration: &'a Acceleration,
}

impl<const D: usize> System<f64, DVector<f64>> for FirstOrder<'_, D> {
    fn system(&self, t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        let _ = t; // the time is the state y[2D] (see the module docs)
        let (q, rest) = y.as_slice().split_at(D);
        let (v, tau) = rest.split_at(D);
        let mut acc = [0.0; D];
        (self.acceleration)(q, v, tau[0], &mut acc);
        let dy = dy.as_mut_slice();
        dy[..D].copy_from_slice(v);
        dy[D..2 * D].copy_from_slice(&acc);
        dy[2 * D] = 1.0;
    }
}

impl<const D: usize> ReferenceCurve<D> {
    /// Integrates `q̈ = acceleration(q, q̇, t)` from `q(a) = q0`, `q̇(a) = v0` to `b` with DOP853,
    /// sampling every `(b − a)/samples`.
    ///
    /// # Panics
    /// If DOP853 reports a failure (too many steps or a stiff problem): the scenes are fixed
    /// and non-stiff, so that is a bug in the scene, not an input error.
    pub fn dop853(
        acceleration: &Acceleration,
        interval: (f64, f64),
        q0: Vector<D>,
        v0: Vector<D>,
        samples: usize,
    ) -> Self {
        Self::dop853_with_tolerance(acceleration, interval, q0, v0, samples, 1e-13)
    }

    /// [`dop853`](Self::dop853) at `rtol = atol = tolerance` instead of `10⁻¹³`: for the
    /// convergence tests whose finest errors come within a few decades of that reference's own.
    /// Hairer's DOP853 refuses `rtol ≤ 10ε`; keep `tolerance` above it.
    ///
    /// # Panics
    /// As [`dop853`](Self::dop853), and if `tolerance ≤ 10ε`.
    pub fn dop853_with_tolerance(
        acceleration: &Acceleration,
        (a, b): (f64, f64),
        q0: Vector<D>,
        v0: Vector<D>,
        samples: usize,
        tolerance: f64,
    ) -> Self {
        assert!(
            tolerance > 10.0 * f64::EPSILON,
            "DOP853 tolerance {tolerance:e} is below 10ε"
        );
        let dt = (b - a) / samples as f64;
        let y0 = DVector::from_iterator(2 * D + 1, q0.iter().chain(v0.iter()).copied().chain([a]));
        let (system, rtol, atol) = (FirstOrder::<D> { acceleration }, tolerance, tolerance);
        let mut solver = Dop853::new(system, a, b, dt, y0, rtol, atol);
        solver
            .integrate()
            .expect("DOP853 integrates the fixed, non-stiff scenes");
        let (x_out, y_out) = (solver.x_out(), solver.y_out());
        // The dense output accumulates `t += dt`; keep exactly one sample per grid time. Its
        // times drift from the grid's by rounding (about 1e-11 after 10⁵ samples on [0, 30]),
        // which would put `q̇ δ` into the curve, above DOP853's own error: each sample is moved
        // by `δ = a + k dt − t` along its Taylor polynomial (`q + q̇ δ + ½ q̈ δ²`, `q̇ + q̈ δ`,
        // error `O(δ³)`).
        let mut q = Vec::with_capacity(samples + 1);
        let mut v = Vec::with_capacity(samples + 1);
        for (&t, y) in x_out.iter().zip(y_out) {
            let k = ((t - a) / dt).round() as usize;
            if k == q.len() && k <= samples {
                let delta = a + k as f64 * dt - t;
                debug_assert!(delta.abs() <= 1e-9 * dt.max(1.0));
                let (qt, vt) = (&y.as_slice()[..D], &y.as_slice()[D..2 * D]);
                let mut acc = [0.0; D];
                acceleration(qt, vt, t, &mut acc);
                q.push(Vector::<D>::from_fn(|i, _| {
                    qt[i] + delta * (vt[i] + 0.5 * delta * acc[i])
                }));
                v.push(Vector::<D>::from_fn(|i, _| vt[i] + delta * acc[i]));
            }
        }
        assert_eq!(q.len(), samples + 1, "DOP853 dense output covers the grid");
        let samples = Samples { a, dt, q, v };
        ReferenceCurve {
            eval: Box::new(move |t| samples.at(t)),
            name: format!("DOP853 (ode_solvers), rtol = atol = {tolerance:e}"),
        }
    }

    /// A closed-form solution `q(t)` with its derivative `q̇(t)`.
    pub fn exact(
        q: impl Fn(f64) -> Vector<D> + Sync + 'static,
        v: impl Fn(f64) -> Vector<D> + Sync + 'static,
    ) -> Self {
        ReferenceCurve {
            eval: Box::new(move |t| (q(t), v(t))),
            name: "exact solution".to_string(),
        }
    }

    /// `(q(t), q̇(t))`.
    pub fn at(&self, t: f64) -> (Vector<D>, Vector<D>) {
        (self.eval)(t)
    }

    /// `q(t)`.
    pub fn q(&self, t: f64) -> Vector<D> {
        self.at(t).0
    }
}

impl<const D: usize> Samples<D> {
    /// `(q(t), q̇(t))` by cubic Hermite interpolation between samples (exact at the samples).
    fn at(&self, t: f64) -> (Vector<D>, Vector<D>) {
        let s = ((t - self.a) / self.dt).clamp(0.0, (self.q.len() - 1) as f64);
        let k = (s.floor() as usize).min(self.q.len() - 2);
        let u = s - k as f64;
        if u == 0.0 {
            return (self.q[k], self.v[k]);
        }
        let (q0, q1, v0, v1) = (self.q[k], self.q[k + 1], self.v[k], self.v[k + 1]);
        let h = self.dt;
        let (u2, u3) = (u * u, u * u * u);
        let q = q0 * (2.0 * u3 - 3.0 * u2 + 1.0)
            + v0 * (h * (u3 - 2.0 * u2 + u))
            + q1 * (-2.0 * u3 + 3.0 * u2)
            + v1 * (h * (u3 - u2));
        let v = (q0 - q1) * ((6.0 * u2 - 6.0 * u) / h)
            + v0 * (3.0 * u2 - 4.0 * u + 1.0)
            + v1 * (3.0 * u2 - 2.0 * u);
        (q, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The oracle is checked against closed forms before it is trusted: DOP853 on the harmonic
    /// oscillator and on `q̈ + q̇ + q = 0` reproduces the exact solutions, at and between samples.
    #[test]
    fn dop853_reproduces_closed_forms() {
        let oscillator = |q: &[f64], _: &[f64], _: f64, a: &mut [f64]| a[0] = -q[0];
        let r = ReferenceCurve::<1>::dop853(
            &oscillator,
            (0.0, 20.0),
            Vector::<1>::new(1.0),
            Vector::<1>::new(0.0),
            20_000,
        );
        let damped = |q: &[f64], v: &[f64], _: f64, a: &mut [f64]| a[0] = -q[0] - v[0];
        let d = ReferenceCurve::<1>::dop853(
            &damped,
            (0.0, 10.0),
            Vector::<1>::new(1.0),
            Vector::<1>::new(0.0),
            10_000,
        );
        // Time-dependent: q̈ = 6t from rest, q = t³.
        let cubic = |_: &[f64], _: &[f64], t: f64, a: &mut [f64]| a[0] = 6.0 * t;
        let c = ReferenceCurve::<1>::dop853(
            &cubic,
            (1.0, 3.0),
            Vector::<1>::new(1.0),
            Vector::<1>::new(3.0),
            1000,
        );
        for k in 0..=100 {
            let t = 1.0 + 0.02 * k as f64;
            assert!((c.q(t)[0] - t.powi(3)).abs() < 1e-11, "t = {t}");
        }
        let w = 3f64.sqrt() / 2.0;
        let exact_damped = |t: f64| (-t / 2.0).exp() * ((w * t).cos() + (w * t).sin() / (2.0 * w));
        for k in 0..2000 {
            let t = k as f64 * 0.01 + 0.000_37 * (k % 3) as f64; // on and off the samples
            let (q, v) = r.at(t);
            assert!(
                (q[0] - t.cos()).abs() < 1e-11,
                "t = {t}: {}",
                q[0] - t.cos()
            );
            assert!(
                (v[0] + t.sin()).abs() < 1e-10,
                "t = {t}: {}",
                v[0] + t.sin()
            );
            let t = t / 2.0;
            assert!((d.q(t)[0] - exact_damped(t)).abs() < 1e-12);
        }
    }
}
