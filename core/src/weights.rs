//! Grünwald–Letnikov weights.

/// The Grünwald–Letnikov weights `α_0 = 1`, `α_r = α_{r−1} (r − 1 − α)/r`, `r = 0..len`.
///
/// This is the stable recurrence for `α_r = (−1)^r C(α, r)`; no Gamma function is evaluated.
/// At `α = 1` the weights are exactly `1, −1, 0, 0, …`, so `Δ^1_± = Δ_±`.
pub fn grunwald_letnikov(alpha: f64, len: usize) -> Vec<f64> {
    let mut w = Vec::with_capacity(len);
    let mut current = 1.0;
    for r in 0..len {
        if r > 0 {
            current *= (r as f64 - 1.0 - alpha) / r as f64;
        }
        w.push(current);
    }
    w
}

/// The weights of the inverse of the lower-triangular Toeplitz Grünwald–Letnikov matrix:
/// `g_0 = 1`, `g_r = g_{r−1} (r − 1 + α)/r`, i.e. `g_r = Γ(r + α)/(Γ(α) r!) = (−1)^r C(−α, r)`.
///
/// The generating function of the Grünwald–Letnikov weights is `(1 − z)^α`, that of these is
/// `(1 − z)^{−α}`, so the two lower-triangular Toeplitz matrices of any order are inverse to each
/// other. At `α = 1` every `g_r` is 1 (the inverse of the difference is the cumulative sum).
pub fn grunwald_letnikov_inverse(alpha: f64, len: usize) -> Vec<f64> {
    let mut g = Vec::with_capacity(len);
    let mut current = 1.0;
    for r in 0..len {
        if r > 0 {
            current *= (r as f64 - 1.0 + alpha) / r as f64;
        }
        g.push(current);
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_follow_the_recurrence() {
        let w = grunwald_letnikov(0.5, 3);
        assert_eq!(w, vec![1.0, -0.5, -0.125]);
    }

    #[test]
    fn inverse_weights_invert_the_convolution() {
        let (w, g) = (grunwald_letnikov(0.5, 3), grunwald_letnikov_inverse(0.5, 3));
        assert_eq!(g, vec![1.0, 0.5, 0.375]);
        // (w * g)_r = δ_r0 for the truncated convolution.
        assert_eq!(w[0] * g[1] + w[1] * g[0], 0.0);
        assert_eq!(w[0] * g[2] + w[1] * g[1] + w[2] * g[0], 0.0);
    }
}
