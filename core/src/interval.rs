//! The discrete Lagrangians of the symmetric embeddings on one interval `[u, w] = [Q_k, Q_{k+1}]`
//! (times `t_u`, `t_w`, step `h`, velocity `V = (w − u)/h`), written once for the step kernels
//! and for the global residuals:
//!
//! | rule | `L_d(u, w)` |
//! | --- | --- |
//! | midpoint | `h L((u + w)/2, V, (t_u + t_w)/2)` |
//! | trapezoidal | `h/2 [L(u, V, t_u) + L(w, V, t_w)]` |
//!
//! Both derivatives of `L_d` are written with an interval *momentum* `P` and two interval
//! *forces* `F_u`, `F_w`:
//!
//! ```text
//! D₁L_d(u, w) = h/2 F_u − P,        D₂L_d(u, w) = h/2 F_w + P
//! midpoint:     P = p(m),  F_u = F_w = f(m),      m = ((u + w)/2, V, (t_u + t_w)/2)
//! trapezoidal:  P = ½ [p(u) + p(w)],  F_u = f(u),  F_w = f(w),   at (u, V, t_u), (w, V, t_w)
//! ```
//!
//! with `f = ∂L/∂x`, `p = ∂L/∂v`. The direct schemes also need the force at a node `Q_k` with
//! the centred velocity `(Q_{k+1} − Q_{k−1})/(2h)`: [`node_force`].

use crate::lagrangian::{ForceJacobian, Hessian, Lagrangian, Matrix, Vector};

/// Which symmetric discrete Lagrangian.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rule {
    /// `h L((u + w)/2, V, (t_u + t_w)/2)`.
    Midpoint,
    /// `h/2 [L(u, V, t_u) + L(w, V, t_w)]`.
    Trapezoidal,
}

/// An interval `[u, w]` with its times and step (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval<const D: usize> {
    /// The left node `Q_k`.
    pub u: Vector<D>,
    /// The right node `Q_{k+1}`.
    pub w: Vector<D>,
    /// `t_k`.
    pub t_u: f64,
    /// `t_{k+1}`.
    pub t_w: f64,
    /// The step `h`.
    pub h: f64,
}

/// `P`, `F_u`, `F_w` of one interval (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntervalGradient<const D: usize> {
    /// The interval momentum `P`.
    pub momentum: Vector<D>,
    /// `F_u`, the force of `D₁L_d`.
    pub force_left: Vector<D>,
    /// `F_w`, the force of `D₂L_d`.
    pub force_right: Vector<D>,
}

/// The derivatives of `P`, `F_u`, `F_w` with respect to `u` (entry 0) and `w` (entry 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntervalJacobian<const D: usize> {
    /// `∂P/∂u`, `∂P/∂w`.
    pub momentum: [Matrix<D>; 2],
    /// `∂F_u/∂u`, `∂F_u/∂w`.
    pub force_left: [Matrix<D>; 2],
    /// `∂F_w/∂u`, `∂F_w/∂w`.
    pub force_right: [Matrix<D>; 2],
}

impl<const D: usize> Interval<D> {
    /// The velocity `V = (w − u)/h`.
    #[inline]
    pub fn velocity(&self) -> Vector<D> {
        (self.w - self.u) / self.h
    }

    /// The midpoint `((u + w)/2, (t_u + t_w)/2)`.
    #[inline]
    fn midpoint(&self) -> (Vector<D>, f64) {
        ((self.u + self.w) * 0.5, 0.5 * (self.t_u + self.t_w))
    }

    /// `L_d(u, w)`.
    pub fn discrete_lagrangian<L: Lagrangian<D> + ?Sized>(
        &self,
        lagrangian: &L,
        rule: Rule,
    ) -> f64 {
        let v = self.velocity();
        match rule {
            Rule::Midpoint => {
                let (m, t) = self.midpoint();
                self.h * lagrangian.value(&m, &v, t)
            }
            Rule::Trapezoidal => {
                0.5 * self.h
                    * (lagrangian.value(&self.u, &v, self.t_u)
                        + lagrangian.value(&self.w, &v, self.t_w))
            }
        }
    }

    /// The energy `E = V·∂L/∂v − L` of the interval, where the rule evaluates `L`: at the
    /// midpoint, or the mean of the two ends.
    pub fn energy<L: Lagrangian<D> + ?Sized>(&self, lagrangian: &L, rule: Rule) -> f64 {
        let v = self.velocity();
        match rule {
            Rule::Midpoint => {
                let (m, t) = self.midpoint();
                lagrangian.energy(&m, &v, t)
            }
            Rule::Trapezoidal => {
                0.5 * (lagrangian.energy(&self.u, &v, self.t_u)
                    + lagrangian.energy(&self.w, &v, self.t_w))
            }
        }
    }

    /// `P`, `F_u`, `F_w`.
    #[inline]
    pub fn gradient<L: Lagrangian<D> + ?Sized>(
        &self,
        lagrangian: &L,
        rule: Rule,
    ) -> IntervalGradient<D> {
        let gradient = |x: &Vector<D>, v: &Vector<D>, t: f64| {
            let (f, p) = lagrangian.gradient(x, v, t);
            (0.0, f, p)
        };
        self.evaluate(rule, gradient).1
    }

    /// The rule's mean of what `eval` gives for `L` (`L_d/h`) and `P`, and the forces, with
    /// `eval` returning `(L, ∂L/∂x, ∂L/∂v)` at a point: [`gradient`](Self::gradient) with a
    /// `L` it never reads, or the step's energy terms (`E = V·P − L_d/h`) with it.
    #[inline(always)]
    pub(crate) fn evaluate(
        &self,
        rule: Rule,
        eval: impl Fn(&Vector<D>, &Vector<D>, f64) -> (f64, Vector<D>, Vector<D>),
    ) -> (f64, IntervalGradient<D>) {
        let v = self.velocity();
        match rule {
            Rule::Midpoint => {
                let (m, t) = self.midpoint();
                let (l, f, p) = eval(&m, &v, t);
                let g = IntervalGradient {
                    momentum: p,
                    force_left: f,
                    force_right: f,
                };
                (l, g)
            }
            Rule::Trapezoidal => {
                let (l_u, f_u, p_u) = eval(&self.u, &v, self.t_u);
                let (l_w, f_w, p_w) = eval(&self.w, &v, self.t_w);
                let g = IntervalGradient {
                    momentum: (p_u + p_w) * 0.5,
                    force_left: f_u,
                    force_right: f_w,
                };
                (0.5 * (l_u + l_w), g)
            }
        }
    }

    /// `P`, `F_u`, `F_w` and their derivatives with respect to `u` and `w`.
    ///
    /// With `V = (w − u)/h`, `∂V/∂u = −I/h`, `∂V/∂w = I/h`, and the blocks `L_xx`, `L_xv`,
    /// `L_vx = L_xvᵀ`, `L_vv` at the evaluation point, the chain rule gives for a value
    /// `g(x, V)` evaluated at `x = c_u u + c_w w`: `∂g/∂u = c_u g_x − g_v/h`,
    /// `∂g/∂w = c_w g_x + g_v/h` (`c = ½, ½` at the midpoint; `1, 0` at `u`; `0, 1` at `w`).
    ///
    /// Forced inline, as is [`node_force`]: the symmetric steps call it inside Newton's loop,
    /// and out of line the derivatives the step does not read are computed anyway (the
    /// trapezoidal steps, which evaluate `L` at both ends, ran about 1.6× slower,
    /// BENCHMARKS.md).
    pub fn gradient_and_jacobian<L: Lagrangian<D> + ?Sized>(
        &self,
        lagrangian: &L,
        rule: Rule,
    ) -> (IntervalGradient<D>, IntervalJacobian<D>) {
        let v = self.velocity();
        let inv_h = 1.0 / self.h;
        // (∂p/∂u, ∂p/∂w) and (∂f/∂u, ∂f/∂w) at a point x = c_u u + c_w w.
        // A generalised force joins `L_xx` and `L_xv` in `f`'s derivatives, not in `p`'s.
        let blocks = |hs: &Hessian<D>, force: Option<ForceJacobian<D>>, c_u: f64, c_w: f64| {
            let (p_x, p_v) = (hs.xv.transpose(), hs.vv * inv_h);
            let (f_x, f_v) = match force {
                Some(force) => (hs.xx + force.x, (hs.xv + force.v) * inv_h),
                None => (hs.xx, hs.xv * inv_h),
            };
            (
                [p_x * c_u - p_v, p_x * c_w + p_v],
                [f_x * c_u - f_v, f_x * c_w + f_v],
            )
        };
        match rule {
            Rule::Midpoint => {
                let (m, t) = self.midpoint();
                let (f, p, hs) = lagrangian.gradient_and_hessian(&m, &v, t);
                let (dp, df) = blocks(&hs, lagrangian.force_jacobian(&m, &v, t), 0.5, 0.5);
                (
                    IntervalGradient {
                        momentum: p,
                        force_left: f,
                        force_right: f,
                    },
                    IntervalJacobian {
                        momentum: dp,
                        force_left: df,
                        force_right: df,
                    },
                )
            }
            Rule::Trapezoidal => {
                let (f_u, p_u, hs_u) = lagrangian.gradient_and_hessian(&self.u, &v, self.t_u);
                let (f_w, p_w, hs_w) = lagrangian.gradient_and_hessian(&self.w, &v, self.t_w);
                let force_u = lagrangian.force_jacobian(&self.u, &v, self.t_u);
                let force_w = lagrangian.force_jacobian(&self.w, &v, self.t_w);
                let (dp_u, df_u) = blocks(&hs_u, force_u, 1.0, 0.0);
                let (dp_w, df_w) = blocks(&hs_w, force_w, 0.0, 1.0);
                (
                    IntervalGradient {
                        momentum: (p_u + p_w) * 0.5,
                        force_left: f_u,
                        force_right: f_w,
                    },
                    IntervalJacobian {
                        momentum: [(dp_u[0] + dp_w[0]) * 0.5, (dp_u[1] + dp_w[1]) * 0.5],
                        force_left: df_u,
                        force_right: df_w,
                    },
                )
            }
        }
    }
}

/// The force of the direct schemes at node `x = Q_k` (time `t`), with the centred velocity
/// `c = (next − previous)/(2h)`, and its derivatives `(∂f/∂x, ∂f/∂v)`: `L_xx`, `L_xv` and a
/// generalised force's blocks. Its derivatives with respect to `Q_{k−1}`, `Q_k`, `Q_{k+1}`,
/// `−f_v/(2h)`, `f_x`, `f_v/(2h)`, are [`node_force_jacobian`]'s.
#[inline(always)]
pub fn node_force<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    previous: &Vector<D>,
    x: &Vector<D>,
    next: &Vector<D>,
    t: f64,
    h: f64,
) -> (Vector<D>, [Matrix<D>; 2]) {
    let c = (next - previous) / (2.0 * h);
    let (f, _, hs) = lagrangian.gradient_and_hessian(x, &c, t);
    match lagrangian.force_jacobian(x, &c, t) {
        Some(force) => (f, [hs.xx + force.x, hs.xv + force.v]),
        None => (f, [hs.xx, hs.xv]),
    }
}

/// `∂f/∂Q_{k−1}`, `∂f/∂Q_k`, `∂f/∂Q_{k+1}` of [`node_force`] from its derivatives
/// `[f_x, f_v]`.
#[inline]
pub fn node_force_jacobian<const D: usize>([f_x, f_v]: &[Matrix<D>; 2], h: f64) -> [Matrix<D>; 3] {
    let side = f_v / (2.0 * h);
    [-side, *f_x, side]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_models::Mixed;

    /// The derivative blocks against central differences of `P`, `F_u`, `F_w`, both rules, on
    /// a Lagrangian whose blocks all depend on `x`, `v` and `t`.
    #[test]
    fn jacobian_matches_finite_differences() {
        jacobian_matches(&Mixed);
        jacobian_matches(&crate::test_models::FORCED_MIXED);
    }

    fn jacobian_matches<L: Lagrangian<2>>(lagrangian: &L) {
        let interval = Interval {
            u: Vector::<2>::new(0.3, -0.2),
            w: Vector::<2>::new(0.36, -0.13),
            t_u: 0.4,
            t_w: 0.5,
            h: 0.1,
        };
        for rule in [Rule::Midpoint, Rule::Trapezoidal] {
            let (g, jac) = interval.gradient_and_jacobian(lagrangian, rule);
            assert_eq!(g, interval.gradient(lagrangian, rule));
            for (end, c) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let eps = 1e-6;
                let moved = |s: f64| {
                    let mut i = interval;
                    if end == 0 {
                        i.u[c] += s;
                    } else {
                        i.w[c] += s;
                    }
                    i.gradient(lagrangian, rule)
                };
                let (plus, minus) = (moved(eps), moved(-eps));
                let fd = |a: Vector<2>, b: Vector<2>| (a - b) / (2.0 * eps);
                for (exact, numeric) in [
                    (jac.momentum[end], fd(plus.momentum, minus.momentum)),
                    (jac.force_left[end], fd(plus.force_left, minus.force_left)),
                    (
                        jac.force_right[end],
                        fd(plus.force_right, minus.force_right),
                    ),
                ] {
                    let gap = (exact.column(c) - numeric).amax();
                    assert!(
                        gap < 1e-7 * (1.0 + exact.amax()),
                        "{rule:?} {end} {c}: {gap:e}"
                    );
                }
            }
        }
    }

    /// `D₁L_d = h/2 F_u − P` and `D₂L_d = h/2 F_w + P` against central differences of `L_d`.
    #[test]
    fn momentum_and_forces_are_the_derivatives_of_the_discrete_lagrangian() {
        let interval = Interval {
            u: Vector::<2>::new(-0.1, 0.25),
            w: Vector::<2>::new(-0.02, 0.2),
            t_u: 1.0,
            t_w: 1.1,
            h: 0.1,
        };
        for rule in [Rule::Midpoint, Rule::Trapezoidal] {
            let g = interval.gradient(&Mixed, rule);
            let d1 = g.force_left * (0.5 * interval.h) - g.momentum;
            let d2 = g.force_right * (0.5 * interval.h) + g.momentum;
            for c in 0..2 {
                let eps = 1e-6;
                let ld = |du: f64, dw: f64| {
                    let mut i = interval;
                    i.u[c] += du;
                    i.w[c] += dw;
                    i.discrete_lagrangian(&Mixed, rule)
                };
                let fd1 = (ld(eps, 0.0) - ld(-eps, 0.0)) / (2.0 * eps);
                let fd2 = (ld(0.0, eps) - ld(0.0, -eps)) / (2.0 * eps);
                assert!(
                    (d1[c] - fd1).abs() < 1e-8,
                    "{rule:?} D1[{c}] {} vs {fd1}",
                    d1[c]
                );
                assert!(
                    (d2[c] - fd2).abs() < 1e-8,
                    "{rule:?} D2[{c}] {} vs {fd2}",
                    d2[c]
                );
            }
        }
    }
}
