//! Discrete embeddings and their two schemes: which velocity operator, which quadrature rows,
//! which rows each scheme's equations sit on.

use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::operator::Operator;
use crate::side::Side;
use std::fmt;
use std::ops::RangeInclusive;

/// Which discrete scheme of an embedding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Scheme {
    /// The direct embedding of the Euler–Lagrange equation: the embedding's operators
    /// substituted into `∂_x L − d/dt ∂_v L = 0`.
    Direct,
    /// The variational integrator: the critical points of the discrete action `S_h`.
    Variational,
}

impl Scheme {
    /// The other scheme of the same embedding.
    pub(crate) fn other(self) -> Scheme {
        match self {
            Scheme::Direct => Scheme::Variational,
            Scheme::Variational => Scheme::Direct,
        }
    }
}

impl fmt::Display for Scheme {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Scheme::Direct => "direct",
            Scheme::Variational => "variational",
        })
    }
}

/// The families of discrete embeddings: the three of the paper, and the two symmetric ones
/// (midpoint and trapezoidal) whose discrete Lagrangians are second order.
#[derive(Clone, Copy, Debug, PartialEq)]
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
    /// `tests/tests/hard_fractional.rs`.
    GrunwaldLetnikov {
        /// The order `0 < α ≤ 1`.
        alpha: f64,
    },
    /// The midpoint embedding: the discrete Lagrangian
    /// `L_d(Q_k, Q_{k+1}) = h L((Q_k + Q_{k+1})/2, (Q_{k+1} − Q_k)/h, t_k + h/2)`. Its
    /// variational scheme is the implicit midpoint rule's variational integrator (on a linear
    /// system, the Cayley transform: A-stable); its direct scheme evaluates `∂L/∂x` at the node
    /// with the centred velocity. Not coherent: the two schemes differ by `O(h²)`
    /// (docs/schemes.md).
    Midpoint,
    /// The trapezoidal embedding: the discrete Lagrangian
    /// `L_d(Q_k, Q_{k+1}) = h/2 [L(Q_k, V, t_k) + L(Q_{k+1}, V, t_{k+1})]`,
    /// `V = (Q_{k+1} − Q_k)/h`. Its variational scheme is Störmer–Verlet on `½|v|² − U(x)`
    /// (stable for `ωh < 2`); its direct scheme evaluates `∂L/∂x` at the node with the centred
    /// velocity. Not coherent on Lagrangians with an `x`–`v` coupling (docs/schemes.md).
    Trapezoidal,
}

/// A discrete embedding: a family and a side σ.
///
/// The symmetric embeddings ([`Embedding::midpoint`], [`Embedding::trapezoidal`]) look at
/// both neighbours of a node and have no side of their own: for them [`side`](Self::side) is
/// [`Side::Backward`], which says only how their interval values are stored: the velocity
/// `V_k = (Q_k − Q_{k−1})/h` of the interval `[t_{k−1}, t_k]` sits on row `k`, rows `1..=N`
/// as for `Δ_−` (docs/conventions.md).
///
/// # Example
///
/// ```
/// use varembed::{Embedding, Side};
/// let gle = Embedding::grunwald_letnikov(Side::Backward, 0.5)?;
/// assert_eq!(gle.to_string(), "Gauss-GLE− (α = 0.5)");
/// assert!(Embedding::grunwald_letnikov(Side::Backward, 1.5).is_err());
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Embedding {
    kind: EmbeddingKind,
    side: Side,
}

impl Embedding {
    /// Gauss-FDEσ.
    pub fn finite_difference(side: Side) -> Self {
        Embedding {
            kind: EmbeddingKind::FiniteDifference,
            side,
        }
    }
    /// The asymmetric Gauss-FDEσ.
    pub fn asymmetric(side: Side) -> Self {
        Embedding {
            kind: EmbeddingKind::Asymmetric,
            side,
        }
    }
    /// Gauss-GLEσ of order α; errors unless `0 < α ≤ 1`.
    pub fn grunwald_letnikov(side: Side, alpha: f64) -> Result<Self> {
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(Error::AlphaOutOfRange { alpha });
        }
        Ok(Embedding {
            kind: EmbeddingKind::GrunwaldLetnikov { alpha },
            side,
        })
    }

    /// The midpoint embedding ([`EmbeddingKind::Midpoint`]): classical, second order.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Scheme, Side};
    /// let midpoint = Embedding::midpoint();
    /// assert_eq!(midpoint.to_string(), "midpoint");
    /// assert_eq!(midpoint.side(), Side::Backward); // rows 1..=N, one per interval
    /// assert!(!midpoint.is_coherent());
    /// assert_eq!(midpoint.order(Scheme::Variational), Some(2));
    /// ```
    pub fn midpoint() -> Self {
        Embedding {
            kind: EmbeddingKind::Midpoint,
            side: Side::Backward,
        }
    }
    /// The trapezoidal embedding ([`EmbeddingKind::Trapezoidal`]): classical, second order.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Scheme};
    /// let trapezoidal = Embedding::trapezoidal();
    /// assert_eq!(trapezoidal.to_string(), "trapezoidal");
    /// assert_eq!(trapezoidal.order(Scheme::Direct), Some(2));
    /// ```
    pub fn trapezoidal() -> Self {
        Embedding {
            kind: EmbeddingKind::Trapezoidal,
            side: Side::Backward,
        }
    }

    /// The family.
    pub fn kind(&self) -> EmbeddingKind {
        self.kind
    }
    /// The side σ.
    pub fn side(&self) -> Side {
        self.side
    }
    /// The order α (1 for the classical embeddings).
    pub fn alpha(&self) -> f64 {
        match self.kind {
            EmbeddingKind::GrunwaldLetnikov { alpha } => alpha,
            _ => 1.0,
        }
    }
    /// Whether the embedding is Grünwald–Letnikov (even at α = 1, where its operators equal
    /// the classical ones but are stored densely).
    pub fn is_fractional(&self) -> bool {
        matches!(self.kind, EmbeddingKind::GrunwaldLetnikov { .. })
    }
    /// Whether the embedding is coherent (direct = variational): proved by the paper for the
    /// asymmetric Gauss-FDEσ and Gauss-GLEσ. Gauss-FDEσ is not; neither are the midpoint and
    /// trapezoidal embeddings, whose direct scheme evaluates `∂L/∂x` once at the node where
    /// the variational one averages it over the two neighbouring intervals (docs/schemes.md).
    pub fn is_coherent(&self) -> bool {
        matches!(
            self.kind,
            EmbeddingKind::Asymmetric | EmbeddingKind::GrunwaldLetnikov { .. }
        )
    }
    /// Whether the embedding is symmetric (midpoint or trapezoidal): its discrete Lagrangian
    /// `L_d(Q_k, Q_{k+1})` reads the whole interval, with no side.
    pub fn is_symmetric(&self) -> bool {
        matches!(
            self.kind,
            EmbeddingKind::Midpoint | EmbeddingKind::Trapezoidal
        )
    }

    /// The order of `scheme` in `h` on a smooth solution of a general Lagrangian: the exponent
    /// `p` of the maximum nodal error `O(h^p)`, for an initial value problem started by
    /// [`Start::Legendre`](crate::Start::Legendre) and for a boundary value problem; `None`
    /// where no one order holds.
    ///
    /// - Gauss-FDEσ and the asymmetric Gauss-FDEσ: 1, both schemes. On `L = ½ vᵀMv − U(x)`
    ///   with a constant `M` their variational recurrence is Störmer–Verlet, second order as a
    ///   boundary value problem and from [`Start::SecondOrder`](crate::Start::SecondOrder) —
    ///   there, and only there (the discrete Legendre start, a mass matrix `M(x)` or an
    ///   `x`–`v` coupling leave it at 1).
    /// - Midpoint and trapezoidal: 2, both schemes, on every smooth Lagrangian, separable or
    ///   not (each scheme is symmetric, and the discrete Legendre start
    ///   `p_0 = −D₁L_d(Q_0, Q_1)` is second order).
    /// - Gauss-GLEσ: 1 at α = 1 (the Gauss-FDEσ operators); `None` for `α < 1`, where the
    ///   order depends on the data: the solution of a fractional problem is in general
    ///   singular at the ends (docs/schemes.md).
    pub fn order(&self, scheme: Scheme) -> Option<u32> {
        let _ = scheme; // every family has one order for both schemes
        match self.kind {
            EmbeddingKind::Midpoint | EmbeddingKind::Trapezoidal => Some(2),
            EmbeddingKind::FiniteDifference | EmbeddingKind::Asymmetric => Some(1),
            EmbeddingKind::GrunwaldLetnikov { alpha } => (alpha == 1.0).then_some(1),
        }
    }

    /// The operator `Δ_σ` (or `Δ^α_σ`): the velocity is `V = −σ Δ_σ Q` on the quadrature rows.
    pub(crate) fn velocity_operator(&self, grid: &Grid) -> Operator {
        self.operator(self.side, grid)
    }

    /// The operator `Δ_{−σ}` (or `Δ^α_{−σ}`) that the direct scheme of the coherent
    /// embeddings applies to `p`.
    pub(crate) fn adjoint_operator(&self, grid: &Grid) -> Operator {
        self.operator(self.side.opposite(), grid)
    }

    fn operator(&self, side: Side, grid: &Grid) -> Operator {
        match self.kind {
            EmbeddingKind::GrunwaldLetnikov { alpha } => {
                Operator::grunwald_letnikov(side, alpha, grid)
                    .expect("α was checked when the embedding was built")
            }
            _ => Operator::finite_difference(side, grid),
        }
    }

    /// The Gauss σ-quadrature rows `I_σ`: `1..=N` for σ = −, `0..=N−1` for σ = +.
    pub fn quadrature_rows(&self, n: usize) -> RangeInclusive<usize> {
        match self.side {
            Side::Backward => 1..=n,
            Side::Forward => 0..=n - 1,
        }
    }

    /// The rows of the direct scheme (the table in `docs/schemes.md`): Gauss-FDE− `2..=N`,
    /// Gauss-FDE+ `0..=N−2`, the coherent embeddings `1..=N−1`. Always `N − 1` rows (empty when
    /// `N = 1`).
    #[allow(clippy::reversed_empty_ranges)] // an empty range is the right answer for N = 1
    pub fn direct_rows(&self, n: usize) -> RangeInclusive<usize> {
        match (self.kind, self.side) {
            (EmbeddingKind::FiniteDifference, Side::Backward) => 2..=n,
            (EmbeddingKind::FiniteDifference, Side::Forward) if n >= 2 => 0..=n - 2,
            (EmbeddingKind::FiniteDifference, Side::Forward) => 1..=0,
            _ => variational_rows(n),
        }
    }

    /// The nodes `k` of the equations of `scheme` on a grid of `n` steps: the direct rows
    /// above, or the interior nodes `1..=N−1` for the variational scheme.
    pub(crate) fn scheme_rows(&self, scheme: Scheme, n: usize) -> RangeInclusive<usize> {
        match scheme {
            Scheme::Direct => self.direct_rows(n),
            Scheme::Variational => variational_rows(n),
        }
    }
}

/// The rows of the variational scheme, `1..=N−1` (the interior nodes).
#[allow(clippy::reversed_empty_ranges)]
pub(crate) fn variational_rows(n: usize) -> RangeInclusive<usize> {
    if n >= 2 { 1..=n - 1 } else { 1..=0 }
}

impl fmt::Display for Embedding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = self.side.symbol();
        match self.kind {
            EmbeddingKind::FiniteDifference => write!(f, "Gauss-FDE{s}"),
            EmbeddingKind::Asymmetric => write!(f, "asymmetric Gauss-FDE{s}"),
            EmbeddingKind::GrunwaldLetnikov { alpha } => write!(f, "Gauss-GLE{s} (α = {alpha})"),
            EmbeddingKind::Midpoint => f.write_str("midpoint"),
            EmbeddingKind::Trapezoidal => f.write_str("trapezoidal"),
        }
    }
}
