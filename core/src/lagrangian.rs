//! The [`Lagrangian`] trait: `L(x, v, t)` with its first and second derivatives, and the
//! per-step kernels of the classical schemes.
//!
//! # The step kernels
//!
//! Every classical scheme of DESIGN.md (direct and variational, σ = ±) is a three-point
//! recurrence, and all four have the same shape: from the two previous nodes
//! `a = Q_{n−2}`, `b = Q_{n−1}` compute a *momentum* `π`, then solve a discrete Legendre map for
//! the newest node `y = Q_n`. Write `@left(a, b)` for evaluation at `(a, (b − a)/h, t_a)` and
//! `@right(a, b)` for evaluation at `(b, (b − a)/h, t_b)`, with `p = ∂L/∂v`, `f = ∂L/∂x`:
//!
//! | [`StepKind`] | momentum `π` from `(a, b)` | equation for `y` from `(b, y)` |
//! | --- | --- | --- |
//! | `VariationalBackward` (σ=−) | `(p + h f)@right(a, b)` | `p@right(b, y) = π` |
//! | `VariationalForward` (σ=+) | `p@left(a, b)` | `(p − h f)@left(b, y) = π` |
//! | `DirectBackward` (σ=−) | `p@right(a, b)` | `(p − h f)@right(b, y) = π` |
//! | `DirectForward` (σ=+) | `(p + h f)@left(a, b)` | `p@left(b, y) = π` |
//!
//! Each row is the scheme's residual row multiplied by `−h` (variational σ=−, row `n−1`:
//! `f + (p_{n−1} − p_n)/h = 0`; direct σ=+, row `n−2`: `f + (p_{n−2} − p_{n−1})/h = 0`, …), so
//! the step residual is in units of momentum. The discrete Legendre start of DESIGN.md is the
//! variational equation with `π = π_0 = ∂L/∂v(q(a), q̇(a), a)`.
//!
//! The Jacobians `∂(equation)/∂y`, with `L_vx = L_xvᵀ`:
//!
//! | equation | Jacobian |
//! | --- | --- |
//! | `p@right(b, y)` | `L_vx + L_vv/h` |
//! | `(p − h f)@left(b, y)` | `L_vv/h − L_xv` |
//! | `(p − h f)@right(b, y)` | `L_vx + L_vv/h − h L_xx − L_xv` |
//! | `p@left(b, y)` | `L_vv/h` |

use nalgebra::{SMatrix, SVector};

/// A point of `R^D`.
pub type Vector<const D: usize> = SVector<f64, D>;
/// A `D × D` block.
pub type Matrix<const D: usize> = SMatrix<f64, D, D>;

/// A point of `R^D` given as `f64` (when `D = 1`), `[f64; D]` or [`Vector<D>`].
pub trait IntoVector<const D: usize> {
    /// The point as a [`Vector<D>`].
    fn into_vector(self) -> Vector<D>;
}

impl IntoVector<1> for f64 {
    fn into_vector(self) -> Vector<1> {
        Vector::<1>::new(self)
    }
}

impl<const D: usize> IntoVector<D> for [f64; D] {
    fn into_vector(self) -> Vector<D> {
        Vector::<D>::from(self)
    }
}

impl<const D: usize> IntoVector<D> for Vector<D> {
    fn into_vector(self) -> Vector<D> {
        self
    }
}

/// The three second-derivative blocks of a Lagrangian at one point.
///
/// `xx[(i, j)] = ∂²L/∂x_i∂x_j`, `xv[(i, j)] = ∂²L/∂x_i∂v_j`, `vv[(i, j)] = ∂²L/∂v_i∂v_j`.
/// The fourth block is `L_vx = xvᵀ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hessian<const D: usize> {
    /// `∂²L/∂x∂x`.
    pub xx: Matrix<D>,
    /// `∂²L/∂x∂v` (row: x index, column: v index).
    pub xv: Matrix<D>,
    /// `∂²L/∂v∂v`.
    pub vv: Matrix<D>,
}

/// Which classical scheme a step kernel advances (see the step tables of `Lagrangian`'s
/// module).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StepKind {
    /// Variational integrator of Gauss-FDE− (σ = −).
    VariationalBackward,
    /// Variational integrator of Gauss-FDE+ (σ = +).
    VariationalForward,
    /// Direct embedding of Gauss-FDE− (σ = −): implicit in the newest node.
    DirectBackward,
    /// Direct embedding of Gauss-FDE+ (σ = +).
    DirectForward,
}

/// Grid data a step kernel needs: the step `h`, its inverse, and the times of the three nodes
/// `t_{n−2}, t_{n−1}, t_n` (taken from the grid, so they match [`crate::Grid::t`] exactly).
///
/// The kernels form velocities as `(b − a) · inv_h`: a multiplication, where a division by `h`
/// would sit on the critical path of every step of an explicit run. Build it with
/// [`StepTimes::new`], which sets `inv_h = 1/h`.
///
/// # Example
///
/// ```
/// let times = varembed::__private::step::StepTimes::new(0.25, 1.0, 1.25, 1.5);
/// assert_eq!(times.inv_h, 4.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepTimes {
    /// Step size `h`.
    pub h: f64,
    /// `1/h`, as computed by [`StepTimes::new`] (the kernels rely on the two agreeing).
    pub inv_h: f64,
    /// `t_{n−2}`, the time of the oldest node `a`.
    pub t_a: f64,
    /// `t_{n−1}`, the time of the middle node `b`.
    pub t_b: f64,
    /// `t_n`, the time of the newest node `y`.
    pub t_y: f64,
}

impl StepTimes {
    /// The step data for step size `h` and node times `t_a`, `t_b`, `t_y`, with
    /// `inv_h = 1/h`.
    pub const fn new(h: f64, t_a: f64, t_b: f64, t_y: f64) -> Self {
        StepTimes {
            h,
            inv_h: 1.0 / h,
            t_a,
            t_b,
            t_y,
        }
    }
}

/// A Lagrangian `L(x, v, t)` on `R^D × R^D × R`.
///
/// Implement [`value`](Self::value), [`gradient`](Self::gradient) and
/// [`hessian`](Self::hessian) by hand, or let `#[lagrangian]` generate them (it also overrides
/// the step kernels with fused code). The step kernels have generic defaults written only in
/// terms of `gradient` and `hessian`.
///
/// # Example
///
/// ```
/// use varembed::{Hessian, Lagrangian, Matrix, Vector};
///
/// /// Harmonic oscillator `L = ½v² − ½ω²x²`.
/// struct Oscillator { omega: f64 }
///
/// impl Lagrangian<1> for Oscillator {
///     fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
///         0.5 * v[0] * v[0] - 0.5 * self.omega.powi(2) * x[0] * x[0]
///     }
///     fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
///         (Vector::<1>::new(-self.omega.powi(2) * x[0]), *v)
///     }
///     fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
///         Hessian {
///             xx: Matrix::<1>::new(-self.omega.powi(2)),
///             xv: Matrix::<1>::zeros(),
///             vv: Matrix::<1>::identity(),
///         }
///     }
/// }
/// let (f, p) = Oscillator { omega: 2.0 }.gradient(&Vector::<1>::new(1.0), &Vector::<1>::new(3.0), 0.0);
/// assert_eq!((f[0], p[0]), (-4.0, 3.0));
/// ```
pub trait Lagrangian<const D: usize> {
    /// `L(x, v, t)`.
    fn value(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> f64;

    /// `(∂L/∂x, ∂L/∂v)` at `(x, v, t)`.
    fn gradient(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> (Vector<D>, Vector<D>);

    /// The second-derivative blocks at `(x, v, t)`.
    fn hessian(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> Hessian<D>;

    /// The energy `E = v·∂L/∂v − L`.
    fn energy(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> f64 {
        let (_, p) = self.gradient(x, v, t);
        v.dot(&p) - self.value(x, v, t)
    }

    /// The momentum `π` that the step for `Q_n` must reproduce, from `a = Q_{n−2}`,
    /// `b = Q_{n−1}` (see the step tables of this trait's module).
    fn step_momentum(
        &self,
        kind: StepKind,
        a: &Vector<D>,
        b: &Vector<D>,
        times: &StepTimes,
    ) -> Vector<D> {
        let h = times.h;
        let v = (b - a) * times.inv_h;
        match kind {
            StepKind::VariationalBackward => {
                let (f, p) = self.gradient(b, &v, times.t_b);
                p + f * h
            }
            StepKind::VariationalForward => self.gradient(a, &v, times.t_a).1,
            StepKind::DirectBackward => self.gradient(b, &v, times.t_b).1,
            StepKind::DirectForward => {
                let (f, p) = self.gradient(a, &v, times.t_a);
                p + f * h
            }
        }
    }

    /// Residual `G(y) − π` of the step equation for the newest node `y = Q_n`, given
    /// `b = Q_{n−1}`, and its Jacobian `∂G/∂y`.
    fn step_residual(
        &self,
        kind: StepKind,
        b: &Vector<D>,
        y: &Vector<D>,
        momentum: &Vector<D>,
        times: &StepTimes,
    ) -> (Vector<D>, Matrix<D>) {
        let h = times.h;
        let v = (y - b) * times.inv_h;
        match kind {
            StepKind::VariationalBackward => {
                let (_, p) = self.gradient(y, &v, times.t_y);
                let hs = self.hessian(y, &v, times.t_y);
                (p - momentum, hs.xv.transpose() + hs.vv / h)
            }
            StepKind::VariationalForward => {
                let (f, p) = self.gradient(b, &v, times.t_b);
                let hs = self.hessian(b, &v, times.t_b);
                (p - f * h - momentum, hs.vv / h - hs.xv)
            }
            StepKind::DirectBackward => {
                let (f, p) = self.gradient(y, &v, times.t_y);
                let hs = self.hessian(y, &v, times.t_y);
                (
                    p - f * h - momentum,
                    hs.xv.transpose() + hs.vv / h - hs.xx * h - hs.xv,
                )
            }
            StepKind::DirectForward => {
                let (_, p) = self.gradient(b, &v, times.t_b);
                let hs = self.hessian(b, &v, times.t_b);
                (p - momentum, hs.vv / h)
            }
        }
    }

    /// Whether the step equation of `kind` is affine in `y` with a Jacobian that does not
    /// depend on `y` (e.g. `L = ½ vᵀMv − U(x)` for the variational and the forward direct
    /// schemes). The default says `false`; `#[lagrangian]` decides it symbolically.
    fn step_is_affine(&self, kind: StepKind) -> bool {
        let _ = kind;
        false
    }

    /// The newest node in closed form, when the step is affine: one linear solve, no Newton
    /// loop. `None` when the step is not affine or its matrix is singular (the solver then
    /// runs Newton, which reports the singular Jacobian with the step index).
    fn step_explicit(
        &self,
        kind: StepKind,
        b: &Vector<D>,
        momentum: &Vector<D>,
        times: &StepTimes,
    ) -> Option<Vector<D>> {
        if !self.step_is_affine(kind) {
            return None;
        }
        // Affine: G(y) = G(b) + J (y − b) exactly, so one Newton step from b is the solution.
        let (r, j) = self.step_residual(kind, b, b, momentum, times);
        crate::linalg::solve_small(&j, &r).map(|dy| b - dy)
    }
}

impl<const D: usize, L: Lagrangian<D> + ?Sized> Lagrangian<D> for &L {
    fn value(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> f64 {
        (**self).value(x, v, t)
    }
    fn gradient(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> (Vector<D>, Vector<D>) {
        (**self).gradient(x, v, t)
    }
    fn hessian(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> Hessian<D> {
        (**self).hessian(x, v, t)
    }
    fn energy(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> f64 {
        (**self).energy(x, v, t)
    }
    fn step_momentum(&self, k: StepKind, a: &Vector<D>, b: &Vector<D>, s: &StepTimes) -> Vector<D> {
        (**self).step_momentum(k, a, b, s)
    }
    fn step_residual(
        &self,
        k: StepKind,
        b: &Vector<D>,
        y: &Vector<D>,
        m: &Vector<D>,
        s: &StepTimes,
    ) -> (Vector<D>, Matrix<D>) {
        (**self).step_residual(k, b, y, m, s)
    }
    fn step_is_affine(&self, k: StepKind) -> bool {
        (**self).step_is_affine(k)
    }
    fn step_explicit(
        &self,
        k: StepKind,
        b: &Vector<D>,
        m: &Vector<D>,
        s: &StepTimes,
    ) -> Option<Vector<D>> {
        (**self).step_explicit(k, b, m, s)
    }
}
