//! [`EmbeddingKind`]: the families of discrete embeddings, with what each is.

/// The families of discrete embeddings: the three of the paper, the Caputo form of its
/// fractional one, the forms of both corrected at the ends, and the two symmetric ones (midpoint and trapezoidal) whose discrete
/// Lagrangians are second order.
///
/// ```
/// use varembed::{Embedding, EmbeddingKind, Side};
/// let kind = Embedding::grunwald_letnikov(Side::Forward, 0.5)?.kind();
/// assert_eq!(kind, EmbeddingKind::GrunwaldLetnikov { alpha: 0.5 });
/// # Ok::<(), varembed::Error>(())
/// ```
///
/// Non-exhaustive: further embeddings may be added without a breaking change, so a `match` on it
/// outside this crate ends with a wildcard arm.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum EmbeddingKind {
    /// Gauss-FDEσ (paper §2.1): the direct scheme substitutes `d/dt ↦ −σΔ_σ`. Not coherent.
    FiniteDifference,
    /// The asymmetric Gauss-FDEσ (paper §2.3): `d_− ↦ Δ_−`, `d_+ ↦ Δ_+`. Coherent.
    Asymmetric,
    /// Gauss-GLEσ (paper §3): `D^α_± ↦ Δ^α_±`. Coherent. Only boundary value problems
    /// (every node couples to every other).
    ///
    /// # Which α give a two-point problem
    ///
    /// The discrete system is solvable for every `0 < α ≤ 1`, but for `α ≤ 1/2` it does not
    /// discretise a continuous two-point problem: the action's natural space is `H^α`, whose
    /// curves have point values only when `α > 1/2`, so `q(b)` cannot be imposed and in general
    /// there is no continuous solution. The discrete solutions show it as a boundary layer:
    /// under Gauss-GLE− (pendulum `L = ½v² + cos x`, `[0, 1]`, `Q_0 = 0`, `Q_N = 1`) the jump
    /// `Q_N − Q_{N−1}` at `t = b` is, for N = 100, 200, 400,
    ///
    /// | α | jump | as `h → 0` |
    /// | --- | --- | --- |
    /// | 0.05 | 0.80, 0.84, 0.86 | grows: the interior ignores `q(b)` |
    /// | 0.3 | 0.44, 0.47, 0.49 | grows |
    /// | 0.5 | 0.156, 0.150, 0.144 | borderline, barely decays |
    /// | 0.7 | 0.036, 0.028, 0.021 | vanishes, ≈ `h^{2(α−1/2)}` |
    /// | 1 | 0.0118, 0.0059, 0.0029 | vanishes, `O(h)` |
    ///
    /// For `α > 1/2` the solutions converge (slowly near 1/2), change continuously with α and
    /// tend to the classical ones as α → 1, at distance `O(1 − α)`. Tested in
    /// `tests/tests/fractional/hard_fractional.rs`.
    GrunwaldLetnikov {
        /// The order `0 < α ≤ 1`.
        alpha: f64,
    },
    /// Gauss-GLEσ in the Caputo form: the Grünwald–Letnikov operator applied to the curve
    /// minus its value at the end where the derivative starts, the discretisation of the
    /// Caputo derivative
    ///
    /// `D^α_{C,−} q = D^α_− (q − q(a))` (σ = −), `D^α_{C,+} q = D^α_+ (q − q(b))` (σ = +).
    ///
    /// The velocity is `V = −σ Δ^α_σ (Q − Q_e)` with `Q_e = Q_0` (σ = −) or `Q_N` (σ = +). The
    /// Riemann–Liouville derivative of a curve that does not vanish at that end is singular
    /// like `(t − a)^{−α}` (σ = −), not square integrable for `α ≥ 1/2`: every curve with
    /// such an end value has infinite action under Gauss-GLEσ
    /// ([`Warning::InfiniteFractionalAction`](crate::Warning::InfiniteFractionalAction)). The
    /// Caputo form subtracts that value first: constants have zero velocity, and any end
    /// value gives a finite action. Coherent: with the end value fixed by the boundary
    /// condition, the Euler–Lagrange equation is the Riemann–Liouville one on the other side,
    /// `∂_x L − σ D^α_{−σ}(∂_v L) = 0`, and both schemes are its rows
    /// ([schemes](crate::guide::schemes)). Only boundary value problems.
    Caputo {
        /// The order `0 < α ≤ 1`.
        alpha: f64,
    },
    /// Gauss-GLEσ with starting columns at both ends (Lubich's starting weights): the velocity
    /// operator is exact on the two leading singular terms of a solution next to the end
    /// where it starts (`t^α`, `t^{1+α}` for σ = −), and the operator the direct scheme
    /// applies to the momenta on the two leading terms of a momentum that does not vanish at
    /// the other end (`(b − t)^{−α}`, `(b − t)^{1−α}` in its derivative). Its direct scheme is
    /// second order on such data, where Gauss-GLEσ's order is 0.5 to 0.8 (α = 0.6, 0.8)
    /// ([schemes](crate::guide::schemes)). Not coherent: the corrected momentum operator is
    /// not the transpose of the corrected velocity operator, so the direct scheme is not the
    /// Euler–Lagrange equation of a discrete action, and the variational scheme (the gradient
    /// of `h Σ L(Q_k, Ṽ_k)` with the corrected velocity `Ṽ`) keeps the low order. Only
    /// boundary value problems, on both fractional solvers.
    CorrectedGrunwaldLetnikov {
        /// The order `0 < α ≤ 1`.
        alpha: f64,
    },
    /// The Caputo form with the corrected operators: the velocity
    /// `Ṽ = −σ (Δ^α_σ + C)(Q − Q_e)` of [`CorrectedGrunwaldLetnikov`](Self::CorrectedGrunwaldLetnikov)'s
    /// operator on the curve shifted as in [`Caputo`](Self::Caputo), and that form's corrected
    /// momentum operator in the direct scheme. A Caputo solution with `q(a) ≠ 0` has
    /// `q − q(a) ~ t^α, t^{1+α}` next to `a` (σ = −), exactly the terms the starting columns
    /// are made exact on, so the direct scheme is second order on data with `q(a) ≠ 0` and a
    /// momentum vanishing at neither end, where the Caputo form's order is below 1. Not coherent,
    /// for the corrected form's reason; its variational scheme keeps the low order. Only
    /// boundary value problems, on both fractional solvers.
    CorrectedCaputo {
        /// The order `0 < α ≤ 1`.
        alpha: f64,
    },
    /// The variational Gauss–Legendre integrator of `s` stages, order `2s` (Marsden–West
    /// §2.6; Hairer–Lubich–Wanner VI.6): the discrete Lagrangian
    /// `L_d(q_k, q_{k+1}) = h Σ_i b_i L(Q_i, V_i, t_k + c_i h)` over the degree-`s` polynomial
    /// through `q_k` and `q_{k+1}` collocated at the Gauss nodes, as a one-step map of
    /// `(q_k, p_k)` (a symplectic partitioned Runge–Kutta method). Variational only: it is
    /// built from the action, with a polynomial on each step and a quadrature rule at its
    /// stages, not from an operator on the nodes that could be substituted into the
    /// Euler–Lagrange equation, so it has no direct scheme in the paper's sense and asking for
    /// one is [`Error::Unsupported`](crate::Error::Unsupported) ([schemes](crate::guide::schemes) says why, and how Gauss
    /// collocation of the equation relates to it). Only initial value problems
    /// ([solvers](crate::guide::solvers)).
    GaussLegendre {
        /// The number of stages `1 ≤ s ≤ 4`.
        stages: usize,
    },
    /// The midpoint embedding: the discrete Lagrangian
    /// `L_d(Q_k, Q_{k+1}) = h L((Q_k + Q_{k+1})/2, (Q_{k+1} − Q_k)/h, t_k + h/2)`. Its
    /// variational scheme is the implicit midpoint rule's variational integrator (on a linear
    /// system, the Cayley transform: A-stable); its direct scheme evaluates `∂L/∂x` at the node
    /// with the centred velocity. Not coherent: the two schemes differ by `O(h²)`
    /// ([schemes](crate::guide::schemes)).
    Midpoint,
    /// The trapezoidal embedding: the discrete Lagrangian
    /// `L_d(Q_k, Q_{k+1}) = h/2 [L(Q_k, V, t_k) + L(Q_{k+1}, V, t_{k+1})]`,
    /// `V = (Q_{k+1} − Q_k)/h`. Its variational scheme is Störmer–Verlet on `½|v|² − U(x)`
    /// (stable for `ωh < 2`); its direct scheme evaluates `∂L/∂x` at the node with the centred
    /// velocity. Not coherent where `∂L/∂x` is not affine in `v`
    /// ([schemes](crate::guide::schemes)).
    Trapezoidal,
}
