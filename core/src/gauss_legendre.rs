//! The Gauss–Legendre collocation tableau with `s` stages: nodes `c_i`, weights `b_i` and
//! coefficients `a_ij`, computed to round-off.
//!
//! The nodes are the roots of the Legendre polynomial `P_s(2c − 1)`, found by Newton's method on
//! the three-term recurrence; the weights are `b_i = 1 / ((1 − x_i²) P_s′(x_i)²)` with
//! `x_i = 2c_i − 1`; and `a_ij = ∫_0^{c_i} ℓ_j(τ) dτ`, `ℓ_j` the Lagrange basis polynomial of
//! the nodes, integrated by the same Gauss rule scaled to `[0, c_i]` (exact: `ℓ_j` has degree
//! `s − 1 ≤ 2s − 1`). Every step is a well-conditioned evaluation, unlike solving the
//! collocation conditions `Σ_j a_ij c_j^{k−1} = c_i^k / k` with their Vandermonde matrix.

/// The Gauss–Legendre tableau of `s` stages (the Runge–Kutta method of order `2s`).
#[derive(Clone, Debug, PartialEq)]
pub struct GaussTableau {
    /// The nodes `c_1 < … < c_s` in `(0, 1)`.
    pub c: Vec<f64>,
    /// The weights `b_i`, summing to 1.
    pub b: Vec<f64>,
    /// `a_ij` row by row: `a[i * s + j]`.
    pub a: Vec<f64>,
}

impl GaussTableau {
    /// The tableau of `stages ≥ 1` stages.
    pub fn new(stages: usize) -> Self {
        let s = stages.max(1);
        let (x, w) = legendre_nodes_and_weights(s);
        let c: Vec<f64> = x.iter().map(|x| 0.5 * (1.0 + x)).collect();
        let b: Vec<f64> = w.iter().map(|w| 0.5 * w).collect();
        // ℓ_j(τ) = Π_{m≠j} (τ − c_m)/(c_j − c_m).
        let basis = |j: usize, tau: f64| {
            (0..s)
                .filter(|&m| m != j)
                .map(|m| (tau - c[m]) / (c[j] - c[m]))
                .product::<f64>()
        };
        let mut a = vec![0.0; s * s];
        for i in 0..s {
            for j in 0..s {
                // ∫_0^{c_i} ℓ_j = c_i Σ_m b_m ℓ_j(c_i c_m).
                a[i * s + j] = c[i] * (0..s).map(|m| b[m] * basis(j, c[i] * c[m])).sum::<f64>();
            }
        }
        GaussTableau { c, b, a }
    }

    /// The number of stages `s`.
    pub fn stages(&self) -> usize {
        self.c.len()
    }

    /// `a_ij`.
    pub fn a(&self, i: usize, j: usize) -> f64 {
        self.a[i * self.stages() + j]
    }

    /// `ℓ_j(1 + c_i)` row by row (`i` the row): the Lagrange basis of the nodes `c` evaluated
    /// at the next step's nodes, which carries the stage velocities of one step to the Newton
    /// guess of the next (the collocation polynomial's velocity extrapolated, an `O(hˢ)` guess).
    pub(crate) fn extrapolation(&self) -> Vec<f64> {
        let (s, c) = (self.stages(), &self.c);
        let mut weights = vec![1.0; s * s];
        for i in 0..s {
            for j in 0..s {
                for m in (0..s).filter(|&m| m != j) {
                    weights[i * s + j] *= (1.0 + c[i] - c[m]) / (c[j] - c[m]);
                }
            }
        }
        weights
    }
}

/// `(P_s(x), P_s′(x))` by the recurrence `(k + 1) P_{k+1} = (2k + 1) x P_k − k P_{k−1}`.
fn legendre(s: usize, x: f64) -> (f64, f64) {
    let (mut previous, mut current) = (1.0, x);
    for k in 1..s {
        let k = k as f64;
        let next = ((2.0 * k + 1.0) * x * current - k * previous) / (k + 1.0);
        (previous, current) = (current, next);
    }
    // P_s′ = s (x P_s − P_{s−1}) / (x² − 1), finite inside (−1, 1) where the roots lie.
    let derivative = s as f64 * (x * current - previous) / (x * x - 1.0);
    (current, derivative)
}

/// The roots `x_1 < … < x_s` of `P_s` in `(−1, 1)` and the Gauss weights on `[−1, 1]`.
fn legendre_nodes_and_weights(s: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = Vec::with_capacity(s);
    let mut weights = Vec::with_capacity(s);
    for i in (1..=s).rev() {
        // Tricomi's first approximation of the i-th largest root: Newton converges from it.
        let mut x = (std::f64::consts::PI * (i as f64 - 0.25) / (s as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (p, dp) = legendre(s, x);
            let dx = p / dp;
            x -= dx;
            if dx.abs() <= 1e-2 * f64::EPSILON {
                break;
            }
        }
        let (_, dp) = legendre(s, x);
        nodes.push(x);
        weights.push(2.0 / ((1.0 - x * x) * dp * dp));
    }
    (nodes, weights)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) {
        assert!((a - b).abs() <= 4e-16, "{a} vs {b} ({:e})", a - b);
    }

    /// s = 1: the implicit midpoint rule.
    #[test]
    fn one_stage_is_the_midpoint_rule() {
        let t = GaussTableau::new(1);
        assert_eq!(
            (t.c.clone(), t.b.clone(), t.a.clone()),
            (vec![0.5], vec![1.0], vec![0.5])
        );
    }

    /// s = 2 and s = 3 against the closed forms of Hairer–Nørsett–Wanner, Table II.7.3/7.4.
    #[test]
    fn two_and_three_stages_match_the_published_tables() {
        let r3 = 3f64.sqrt();
        let t = GaussTableau::new(2);
        let c = [0.5 - r3 / 6.0, 0.5 + r3 / 6.0];
        let a = [0.25, 0.25 - r3 / 6.0, 0.25 + r3 / 6.0, 0.25];
        (0..2).for_each(|i| close(t.c[i], c[i]));
        (0..2).for_each(|i| close(t.b[i], 0.5));
        (0..4).for_each(|k| close(t.a[k], a[k]));

        let r15 = 15f64.sqrt();
        let t = GaussTableau::new(3);
        let c = [0.5 - r15 / 10.0, 0.5, 0.5 + r15 / 10.0];
        let b = [5.0 / 18.0, 4.0 / 9.0, 5.0 / 18.0];
        #[rustfmt::skip]
        let a = [
            5.0 / 36.0, 2.0 / 9.0 - r15 / 15.0, 5.0 / 36.0 - r15 / 30.0,
            5.0 / 36.0 + r15 / 24.0, 2.0 / 9.0, 5.0 / 36.0 - r15 / 24.0,
            5.0 / 36.0 + r15 / 30.0, 2.0 / 9.0 + r15 / 15.0, 5.0 / 36.0,
        ];
        (0..3).for_each(|i| close(t.c[i], c[i]));
        (0..3).for_each(|i| close(t.b[i], b[i]));
        (0..9).for_each(|k| close(t.a[k], a[k]));
    }

    /// s = 4: nodes and weights against the published 16-digit values of the 4-point Gauss
    /// rule on `[−1, 1]` (Abramowitz–Stegun, Table 25.4).
    #[test]
    fn four_stages_match_the_published_rule() {
        let t = GaussTableau::new(4);
        let x = [
            -0.8611363115940526,
            -0.3399810435848563,
            0.3399810435848563,
            0.8611363115940526,
        ];
        let w = [
            0.3478548451374538,
            0.6521451548625461,
            0.6521451548625461,
            0.3478548451374538,
        ];
        for i in 0..4 {
            assert!((2.0 * t.c[i] - 1.0 - x[i]).abs() < 1e-15, "node {i}");
            assert!((2.0 * t.b[i] - w[i]).abs() < 1e-15, "weight {i}");
        }
    }

    /// For every s = 1..=4: the simplifying conditions of order `2s` — `B(2s)`:
    /// `Σ b_i c_i^{k−1} = 1/k` for `k ≤ 2s`; `C(s)`: `Σ_j a_ij c_j^{k−1} = c_i^k / k`; `D(s)`:
    /// `Σ_i b_i c_i^{k−1} a_ij = b_j (1 − c_j^k)/k` — and the symplecticity condition
    /// `b_i a_ij + b_j a_ji = b_i b_j` that makes the variational partner tableau equal to `a`.
    #[test]
    fn every_tableau_satisfies_the_order_and_symplecticity_conditions() {
        for s in 1..=4 {
            let t = GaussTableau::new(s);
            let tol = 2e-15;
            for k in 1..=2 * s {
                let sum: f64 = (0..s).map(|i| t.b[i] * t.c[i].powi(k as i32 - 1)).sum();
                assert!((sum - 1.0 / k as f64).abs() < tol, "B({k}), s = {s}");
            }
            for k in 1..=s {
                let kf = k as f64;
                for i in 0..s {
                    let sum: f64 = (0..s).map(|j| t.a(i, j) * t.c[j].powi(k as i32 - 1)).sum();
                    assert!(
                        (sum - t.c[i].powi(k as i32) / kf).abs() < tol,
                        "C({k}), s = {s}"
                    );
                }
                for j in 0..s {
                    let sum: f64 = (0..s)
                        .map(|i| t.b[i] * t.c[i].powi(k as i32 - 1) * t.a(i, j))
                        .sum();
                    let expected = t.b[j] * (1.0 - t.c[j].powi(k as i32)) / kf;
                    assert!((sum - expected).abs() < tol, "D({k}), s = {s}");
                }
            }
            for i in 0..s {
                for j in 0..s {
                    let m = t.b[i] * t.a(i, j) + t.b[j] * t.a(j, i) - t.b[i] * t.b[j];
                    assert!(m.abs() < tol, "symplecticity ({i}, {j}), s = {s}");
                }
            }
        }
    }
}
