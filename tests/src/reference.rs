//! Exact discrete solutions: what a scheme's run must equal node for node, not just converge to;
//! and the pendulum's exact continuous solution ([`PendulumFromRest`]), for errors between the
//! nodes.
//!
//! For the harmonic oscillator `L = ½v² − ½ω²x²` under Gauss-FDE± every scheme is a linear
//! two-step recurrence with constant coefficients, so its run from `Q_0, Q_1` is
//! `Q_k = ρ^k (A cos kθ + B sin kθ)` with `ρ e^{±iθ}` the roots of its characteristic
//! polynomial, `A = Q_0` and `B = (Q_1/ρ − A cos θ)/sin θ`:
//!
//! | scheme | recurrence | `ρ` | `θ` |
//! | --- | --- | --- | --- |
//! | variational, both σ | `(Q_{k+1} − 2Q_k + Q_{k−1})/h² = −ω²Q_k` | 1 (for `ωh < 2`) | `cos θ = 1 − (ωh)²/2` |
//! | direct σ = − | `(Q_k − 2Q_{k−1} + Q_{k−2})/h² = −ω²Q_k` | `(1 + ω²h²)^{−1/2}` | `tan θ = ωh` |
//! | direct σ = + | `(Q_{k+2} − 2Q_{k+1} + Q_k)/h² = −ω²Q_k` | `(1 + ω²h²)^{1/2}` | `tan θ = ωh` |

/// `Q_k = ρ^k (A cos kθ + B sin kθ)`: the run of one of the oscillator's schemes (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiscreteOscillation {
    /// `ρ`, the factor of amplitude per step.
    pub ratio: f64,
    /// `θ`, the angle per step.
    pub angle: f64,
    /// `A = Q_0`.
    pub a: f64,
    /// `B`, fitted to `Q_1`.
    pub b: f64,
}

impl DiscreteOscillation {
    /// The run through `Q_0 = q0`, `Q_1 = q1` with the given `ρ` and `θ`.
    pub fn through(ratio: f64, angle: f64, q0: f64, q1: f64) -> Self {
        let a = q0;
        let b = (q1 / ratio - a * angle.cos()) / angle.sin();
        DiscreteOscillation { ratio, angle, a, b }
    }

    /// The variational scheme (Störmer–Verlet), either side, stable for `ωh < 2`: an exact
    /// rotation by `θ`, `cos θ = 1 − (ωh)²/2`.
    pub fn variational(omega_h: f64, q0: f64, q1: f64) -> Self {
        Self::through(1.0, (1.0 - omega_h.powi(2) / 2.0).acos(), q0, q1)
    }

    /// The implicit direct scheme, σ = −: it loses the factor `(1 + ω²h²)^{−1/2}` of amplitude
    /// every step.
    pub fn direct_backward(omega_h: f64, q0: f64, q1: f64) -> Self {
        Self::through((1.0 + omega_h.powi(2)).powf(-0.5), omega_h.atan(), q0, q1)
    }

    /// The explicit direct scheme, σ = +: it gains the factor `(1 + ω²h²)^{1/2}` every step.
    pub fn direct_forward(omega_h: f64, q0: f64, q1: f64) -> Self {
        Self::through((1.0 + omega_h.powi(2)).sqrt(), omega_h.atan(), q0, q1)
    }

    /// `Q_k`.
    pub fn at(&self, k: usize) -> f64 {
        let phase = k as f64 * self.angle;
        self.ratio.powi(k as i32) * (self.a * phase.cos() + self.b * phase.sin())
    }

    /// `√(A² + B²)`: the bound of `|Q_k| / ρ^k`, reached to within a factor `cos(θ/2)`.
    pub fn amplitude(&self) -> f64 {
        (self.a * self.a + self.b * self.b).sqrt()
    }
}

/// The pendulum `q̈ = −sin q` (`L = ½v² + cos x`) released from rest at `q(0) = q0`, in closed
/// form: `q(t) = 2 arcsin(k sn(K − t | k²))`, `q̇(t) = −2k cn(K − t | k²)`, `k = sin(q0/2)`,
/// `K = K(k²)` the quarter period.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PendulumFromRest {
    /// `k = sin(q0/2)`.
    pub k: f64,
    /// `K(k²)`, the complete elliptic integral of the first kind.
    pub quarter_period: f64,
}

impl PendulumFromRest {
    /// Released from rest at `q0` (`|q0| < π`).
    pub fn new(q0: f64) -> Self {
        let k = (0.5 * q0).sin();
        let (_, _, quarter_period) = jacobi(0.0, k * k);
        PendulumFromRest { k, quarter_period }
    }

    /// `(q(t), q̇(t))`.
    pub fn at(&self, t: f64) -> (f64, f64) {
        let (sn, cn, _) = jacobi(self.quarter_period - t, self.k * self.k);
        (2.0 * (self.k * sn).asin(), -2.0 * self.k * cn)
    }
}

/// `(sn(u | m), cn(u | m), K(m))` by the arithmetic–geometric mean (Abramowitz–Stegun 16.4.3
/// and 17.6).
fn jacobi(u: f64, m: f64) -> (f64, f64, f64) {
    let (mut a, mut b) = (1.0f64, (1.0 - m).sqrt());
    let (mut a_n, mut c_n) = (vec![1.0], vec![m.sqrt()]);
    while c_n.last().is_some_and(|c| c.abs() > 1e-17) && c_n.len() < 40 {
        let c = 0.5 * (a - b);
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
        a_n.push(a);
        c_n.push(c);
    }
    let n = c_n.len() - 1;
    let mut phi = 2f64.powi(n as i32) * a * u;
    for j in (1..=n).rev() {
        phi = 0.5 * (phi + (c_n[j] / a_n[j] * phi.sin()).asin());
    }
    (phi.sin(), phi.cos(), std::f64::consts::FRAC_PI_2 / a)
}

#[cfg(test)]
mod tests {
    use super::{DiscreteOscillation, PendulumFromRest};

    /// The pendulum's closed form starts at rest at `q0`, conserves `½q̇² − cos q` and its
    /// velocity is the derivative of its position (central difference).
    #[test]
    fn pendulum_closed_form_solves_the_pendulum() {
        let q0 = 2.0;
        let exact = PendulumFromRest::new(q0);
        let (q, v) = exact.at(0.0);
        assert!((q - q0).abs() < 1e-14 && v.abs() < 1e-14);
        for i in 1..100 {
            let t = 0.1 * i as f64;
            let (q, v) = exact.at(t);
            assert!((0.5 * v * v - q.cos() + q0.cos()).abs() < 1e-13);
            let e = 1e-5;
            let slope = (exact.at(t + e).0 - exact.at(t - e).0) / (2.0 * e);
            assert!((slope - v).abs() < 1e-8, "{t}: {slope} vs {v}");
        }
    }

    /// Each closed form solves its recurrence, so the table in the module docs is right
    /// independently of the library.
    #[test]
    fn closed_forms_solve_their_recurrences() {
        let (omega, h) = (2.0, 0.03);
        let c = (omega * h) * (omega * h);
        let close = |lhs: f64, rhs: f64| (lhs - rhs).abs() <= 1e-12 * (1.0 + rhs.abs());
        let v = DiscreteOscillation::variational(omega * h, 1.0, 0.9);
        let b = DiscreteOscillation::direct_backward(omega * h, 1.0, 0.9);
        let f = DiscreteOscillation::direct_forward(omega * h, 1.0, 0.9);
        for s in [v, b, f] {
            assert!(close(s.at(0), 1.0) && close(s.at(1), 0.9), "{s:?}");
        }
        for k in 2..200 {
            assert!(close(
                v.at(k) - 2.0 * v.at(k - 1) + v.at(k - 2),
                -c * v.at(k - 1)
            ));
            assert!(close(
                b.at(k) - 2.0 * b.at(k - 1) + b.at(k - 2),
                -c * b.at(k)
            ));
            assert!(close(
                f.at(k) - 2.0 * f.at(k - 1) + f.at(k - 2),
                -c * f.at(k - 2)
            ));
        }
        assert!(b.ratio < 1.0 && f.ratio > 1.0 && v.ratio == 1.0);
        assert!((b.ratio * f.ratio - 1.0).abs() < 1e-15);
    }
}
