//! Grünwald–Letnikov weights.

/// The Grünwald–Letnikov weights `α_0 = 1`, `α_r = α_{r−1} (r − 1 − α)/r`, `r = 0..len`.
///
/// This is the stable recurrence for `α_r = (−1)^r C(α, r)`; no Gamma function is evaluated.
/// At `α = 1` the weights are exactly `1, −1, 0, 0, …`, so `Δ^1_± = Δ_±`.
pub fn grunwald_letnikov(alpha: f64, len: usize) -> Vec<f64> {
    let mut w = Vec::with_capacity(len);
    let mut current = 1.0;
    for r in 0..len {
        current = next_grunwald_letnikov(current, r, alpha);
        w.push(current);
    }
    w
}

/// `w_r` from `w_{r−1}` (`w_0 = 1` from anything): the recurrence of [`grunwald_letnikov`].
#[inline]
fn next_grunwald_letnikov(previous: f64, r: usize, alpha: f64) -> f64 {
    if r == 0 {
        1.0
    } else {
        previous * ((r as f64 - 1.0 - alpha) / r as f64)
    }
}

/// Whether `weights` are the first Grünwald–Letnikov weights of `alpha`, bit for bit as
/// [`grunwald_letnikov`] computes them.
pub(crate) fn are_grunwald_letnikov(weights: &[f64], alpha: f64) -> bool {
    let mut w = 1.0;
    weights.iter().enumerate().all(|(r, &weight)| {
        w = next_grunwald_letnikov(w, r, alpha);
        weight == w
    })
}

/// The weights of the inverse of the lower-triangular Toeplitz Grünwald–Letnikov matrix:
/// `g_0 = 1`, `g_r = g_{r−1} (r − 1 + α)/r`, i.e. `g_r = Γ(r + α)/(Γ(α) r!) = (−1)^r C(−α, r)`.
///
/// The generating function of the Grünwald–Letnikov weights is `(1 − z)^α`, that of these is
/// `(1 − z)^{−α}`, so the two lower-triangular Toeplitz matrices of any order are inverse to each
/// other. At `α = 1` every `g_r` is 1 (the inverse of the difference is the cumulative sum).
pub fn grunwald_letnikov_inverse(alpha: f64, len: usize) -> Vec<f64> {
    let mut walk = InverseWeights::new(alpha);
    (0..len).map(|r| walk.at(r)).collect()
}

/// The weights of [`grunwald_letnikov_inverse`] one at a time, for a reader that asks for
/// them with `r` never decreasing: bit for bit the same numbers, without keeping them (at
/// `N = 10⁷` a vector of them is 80 MB).
#[derive(Clone, Copy, Debug)]
pub(crate) struct InverseWeights {
    alpha: f64,
    r: usize,
    g: f64,
}

impl InverseWeights {
    /// The walk from `g_0 = 1`.
    pub(crate) fn new(alpha: f64) -> Self {
        InverseWeights {
            alpha,
            r: 0,
            g: 1.0,
        }
    }

    /// `g_r`, by the recurrence from the last weight asked for.
    ///
    /// # Panics
    ///
    /// In debug builds, if `r` is below the last weight asked for (an internal misuse).
    #[inline]
    pub(crate) fn at(&mut self, r: usize) -> f64 {
        debug_assert!(r >= self.r, "the weights are walked upwards");
        while self.r < r {
            self.r += 1;
            self.g *= (self.r as f64 - 1.0 + self.alpha) / self.r as f64;
        }
        self.g
    }
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
