//! The rows of the symmetric embeddings (midpoint, trapezoidal) on a whole curve of a
//! run-time-dimension model: the const-generic discretisation's symmetric rows, on flat slices
//! and with the model's sparse second-derivative blocks.
//!
//! Interval `k` is `[Q_{k−1}, Q_k]`, `k = 1..=N`, with velocity `V_k = (Q_k − Q_{k−1})/h`,
//! momentum `P_k` and forces `F_{u,k}`, `F_{w,k}` (the interval module's discrete Lagrangians:
//! the midpoint rule evaluates `L` once, at the midpoint, the trapezoidal rule at both ends).
//! The rows `k = 1..=N−1` are
//!
//! ```text
//! variational:  ½ (F_{w,k} + F_{u,k+1}) − (P_{k+1} − P_k)/h
//! direct:       f_k                     − (P_{k+1} − P_k)/h
//! ```
//!
//! with `f_k` the force at `Q_k` with the centred velocity `(Q_{k+1} − Q_{k−1})/(2h)`.
//!
//! Every Hessian a row reads is at a [`Point`] whose position is `c_u Q_{k−1} + c_w Q_k` for
//! the interval's ends `Q_{k−1}`, `Q_k` (`c = ½, ½` at the midpoint; `1, 0` and `0, 1` at the
//! ends), with velocity `V_k`; a value `g(x, V)` there has `∂g/∂Q_{k−1} = c_u g_x − g_v/h` and
//! `∂g/∂Q_k = c_w g_x + g_v/h`. A row takes the momentum of such a point with weight `m` and
//! its force with weight `φ`, so the point adds to the block of `Q_{k−1}`
//! `m c_u L_vx − (m/h) L_vv + φ c_u L_xx − (φ/h) L_xv`, and to that of `Q_k` the same with
//! `c_w` and `+1/h`.

use super::{CurveValues, DynRows, Part, Point, largest};
use crate::discretisation::relative;
use crate::embedding::Scheme;
use crate::error::{Error, Location, Result};
use crate::interval::Rule;

use crate::dynamic::DynLagrangian;

/// One evaluation point of an interval: where it sits (`c_u`, `c_w`), the weight of its
/// momentum in `P` and whether its force is the interval's `F_u` (left) or `F_w` (right).
struct IntervalPoint {
    point: Point,
    c: (f64, f64),
    momentum: f64,
    left_force: bool,
    right_force: bool,
}

/// The evaluation points of interval `k` under `rule`.
fn interval_points(rule: Rule, k: usize) -> Vec<IntervalPoint> {
    match rule {
        Rule::Midpoint => vec![IntervalPoint {
            point: Point::Mid(k),
            c: (0.5, 0.5),
            momentum: 1.0,
            left_force: true,
            right_force: true,
        }],
        Rule::Trapezoidal => vec![
            IntervalPoint {
                point: Point::Left(k),
                c: (1.0, 0.0),
                momentum: 0.5,
                left_force: true,
                right_force: false,
            },
            IntervalPoint {
                point: Point::Right(k),
                c: (0.0, 1.0),
                momentum: 0.5,
                left_force: false,
                right_force: true,
            },
        ],
    }
}

impl<L: DynLagrangian + ?Sized> DynRows<'_, L> {
    /// The position and velocity of `point` into `(x, v)`, and its time: the const-generic
    /// interval's expressions, operation for operation.
    pub(super) fn point(
        &self,
        q: &[f64],
        values: &CurveValues,
        point: Point,
        (x, v): (&mut [f64], &mut [f64]),
    ) -> f64 {
        let (d, grid) = (self.d, self.grid);
        let node = |k: usize| &q[k * d..(k + 1) * d];
        let velocity = |k: usize| &values.v[k * d..(k + 1) * d];
        match point {
            Point::Node(k) | Point::Right(k) => {
                x.copy_from_slice(node(k));
                v.copy_from_slice(velocity(k));
                grid.t(k)
            }
            Point::Left(k) => {
                x.copy_from_slice(node(k - 1));
                v.copy_from_slice(velocity(k));
                grid.t(k - 1)
            }
            Point::Mid(k) => {
                for ((x, u), w) in x.iter_mut().zip(node(k - 1)).zip(node(k)) {
                    *x = (u + w) * 0.5;
                }
                v.copy_from_slice(velocity(k));
                0.5 * (grid.t(k - 1) + grid.t(k))
            }
            Point::Centred(k) => {
                x.copy_from_slice(node(k));
                let two_h = 2.0 * grid.h();
                for ((v, before), after) in v.iter_mut().zip(node(k - 1)).zip(node(k + 1)) {
                    *v = (after - before) / two_h;
                }
                grid.t(k)
            }
        }
    }

    /// The interval values and (for the direct scheme) the node forces of `q`, and the rows,
    /// into `values`; [`Error::NotFinite`] at the first interval or node whose values are not.
    pub(super) fn evaluate_symmetric(
        &self,
        rule: Rule,
        q: &[f64],
        values: &mut CurveValues,
    ) -> Result<()> {
        let (n, d, h) = (self.grid.n(), self.d, self.grid.h());
        let (mut x, mut v) = (vec![0.0; d], vec![0.0; d]);
        let (mut f, mut p) = (vec![0.0; d], vec![0.0; d]);
        let not_finite = |k: usize| Error::NotFinite {
            at: Location::Node(k),
        };
        let finite = |x: &[f64]| x.iter().all(|c| c.is_finite());
        for k in 1..=n {
            let at = k * d..(k + 1) * d;
            for ((v, u), w) in values.v[at.clone()]
                .iter_mut()
                .zip(&q[(k - 1) * d..k * d])
                .zip(&q[at.clone()])
            {
                *v = (w - u) / h;
            }
            values.p[at.clone()].fill(0.0);
            for ip in interval_points(rule, k) {
                let t = self.point(q, values, ip.point, (&mut x, &mut v));
                self.lagrangian.force(&x, &v, t, &mut f);
                self.lagrangian.momentum(&x, &v, t, &mut p);
                if !finite(&f) || !finite(&p) {
                    return Err(not_finite(k));
                }
                if ip.left_force {
                    values.f_left[at.clone()].copy_from_slice(&f);
                }
                if ip.right_force {
                    values.f[at.clone()].copy_from_slice(&f);
                }
                // The midpoint's momentum as it is; the trapezoidal (p_u + p_w)·½.
                for (sum, p) in values.p[at.clone()].iter_mut().zip(&p) {
                    *sum += p;
                }
            }
            if rule == Rule::Trapezoidal {
                values.p[at].iter_mut().for_each(|p| *p *= 0.5);
            }
        }
        if self.scheme == Scheme::Direct {
            for k in 1..n {
                let t = self.point(q, values, Point::Centred(k), (&mut x, &mut v));
                let at = k * d..(k + 1) * d;
                self.lagrangian
                    .force(&x, &v, t, &mut values.f_node[at.clone()]);
                if !finite(&values.f_node[at]) {
                    return Err(not_finite(k));
                }
            }
        }
        self.symmetric_residual(values);
        Ok(())
    }

    /// The force row `k` reads: `½ (F_{w,k} + F_{u,k+1})` (variational) or the node force.
    fn row_force(&self, values: &CurveValues, k: usize, a: usize) -> f64 {
        let d = self.d;
        match self.scheme {
            Scheme::Variational => (values.f[k * d + a] + values.f_left[(k + 1) * d + a]) * 0.5,
            Scheme::Direct => values.f_node[k * d + a],
        }
    }

    /// The rows `1..=N−1` (module docs), as the const-generic discretisation sums them.
    fn symmetric_residual(&self, values: &mut CurveValues) {
        let (d, inv_h) = (self.d, 1.0 / self.grid.h());
        for (i, k) in self.rows().enumerate() {
            for a in 0..d {
                let force = self.row_force(values, k, a);
                let momenta = values.p[(k + 1) * d + a] - values.p[k * d + a];
                values.r[i * d + a] = force - momenta * inv_h;
            }
        }
    }

    /// The largest force a row reads, as the const-generic `row_scale` measures it (half of
    /// each interval force of the variational rows, the node force of the direct ones).
    pub(super) fn symmetric_forces(&self, values: &CurveValues) -> f64 {
        let d = self.d;
        let at = |x: &[f64], k: usize| largest(&x[k * d..(k + 1) * d]);
        self.rows().fold(0.0f64, |m, k| match self.scheme {
            Scheme::Variational => m
                .max(0.5 * at(&values.f, k))
                .max(0.5 * at(&values.f_left, k + 1)),
            Scheme::Direct => m.max(at(&values.f_node, k)),
        })
    }

    /// `max_k |r_k|∞ / s_k` with the const-generic term sizes of the symmetric rows,
    /// `s_k = |force|∞ + (|P_k|∞ + |P_{k+1}|∞)/h`.
    pub(super) fn symmetric_relative_residual(&self, values: &CurveValues) -> f64 {
        let (d, inv_h) = (self.d, 1.0 / self.grid.h());
        let at = |x: &[f64], k: usize| largest(&x[k * d..(k + 1) * d]);
        self.rows()
            .enumerate()
            .map(|(i, k)| {
                let force = match self.scheme {
                    Scheme::Variational => 0.5 * (at(&values.f, k) + at(&values.f_left, k + 1)),
                    Scheme::Direct => at(&values.f_node, k),
                };
                let size = force + (at(&values.p, k) + at(&values.p, k + 1)) * inv_h;
                relative(at(&values.r, i), size)
            })
            .fold(0.0, f64::max)
    }

    /// The energy of each interval `k = 1..=N`, where the rule evaluates `L` (the midpoint, or
    /// the mean of the two ends).
    pub(super) fn symmetric_energies(
        &self,
        rule: Rule,
        q: &[f64],
        values: &CurveValues,
    ) -> Vec<f64> {
        let d = self.d;
        let (mut x, mut v) = (vec![0.0; d], vec![0.0; d]);
        (1..=self.grid.n())
            .map(|k| {
                let points = interval_points(rule, k);
                let sum: f64 = points
                    .iter()
                    .map(|ip| {
                        let t = self.point(q, values, ip.point, (&mut x, &mut v));
                        self.lagrangian.energy(&x, &v, t)
                    })
                    .sum();
                sum / points.len() as f64
            })
            .collect()
    }

    /// The block contributions to row `k` (module docs): the points of intervals `k` (momentum
    /// weight `+1/h`, its `F_w`) and `k + 1` (`−1/h`, its `F_u`), the force weights `½` in the
    /// variational rows; the direct rows' force at [`Point::Centred`] instead.
    pub(super) fn symmetric_contributions(
        &self,
        rule: Rule,
        k: usize,
    ) -> Vec<(Point, Part, usize, f64)> {
        let (n, inv_h) = (self.grid.n(), 1.0 / self.grid.h());
        let variational = self.scheme == Scheme::Variational;
        let unknown = |j: usize| (1..n).contains(&j);
        let mut out = Vec::new();
        let mut push = |point: Point, part: Part, j: usize, coefficient: f64| {
            if unknown(j) && coefficient != 0.0 {
                out.push((point, part, j, coefficient));
            }
        };
        for (interval, sign) in [(k, 1.0), (k + 1, -1.0)] {
            for ip in interval_points(rule, interval) {
                let m = sign * ip.momentum * inv_h;
                let reads_force = if sign > 0.0 {
                    ip.right_force
                } else {
                    ip.left_force
                };
                let phi = if variational && reads_force { 0.5 } else { 0.0 };
                for (j, c, s) in [(interval - 1, ip.c.0, -1.0), (interval, ip.c.1, 1.0)] {
                    push(ip.point, Part::Vx, j, m * c);
                    push(ip.point, Part::Vv, j, s * m * inv_h);
                    push(ip.point, Part::Xx, j, phi * c);
                    push(ip.point, Part::Xv, j, s * phi * inv_h);
                }
            }
        }
        if !variational {
            let centred = Point::Centred(k);
            push(centred, Part::Xv, k - 1, -0.5 * inv_h);
            push(centred, Part::Xx, k, 1.0);
            push(centred, Part::Xv, k + 1, 0.5 * inv_h);
        }
        out
    }
}
