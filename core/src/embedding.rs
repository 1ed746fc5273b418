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

/// The three families of discrete embeddings of the paper.
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
    /// The variational Gauss–Legendre integrator of `s` stages, order `2s` (Marsden–West
    /// §2.6; Hairer–Lubich–Wanner VI.6): the discrete Lagrangian
    /// `L_d(q_k, q_{k+1}) = h Σ_i b_i L(Q_i, V_i, t_k + c_i h)` over the degree-`s` polynomial
    /// through `q_k` and `q_{k+1}` collocated at the Gauss nodes, as a one-step map of
    /// `(q_k, p_k)` (a symplectic partitioned Runge–Kutta method). Variational only: it is
    /// built from the action, with a polynomial on each step and a quadrature rule at its
    /// stages, not from an operator on the nodes that could be substituted into the
    /// Euler–Lagrange equation, so it has no direct scheme in the paper's sense and asking for
    /// one is [`Error::Unsupported`] (`docs/schemes.md` says why, and how Gauss collocation of
    /// the equation relates to it). Only initial value problems (`docs/solvers.md`).
    GaussLegendre {
        /// The number of stages `1 ≤ s ≤ 4`.
        stages: usize,
    },
}

/// A discrete embedding: a family and a side σ.
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

    /// The variational Gauss–Legendre integrator of `stages` stages (order `2·stages`);
    /// errors unless `1 ≤ stages ≤ 4`. It has no side: [`side`](Self::side) reports
    /// [`Side::Backward`], which nothing reads.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Error, Grid, Problem, Scheme, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillator(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v - 0.5 * x * x
    /// }
    ///
    /// let gauss = Embedding::gauss_legendre(2)?;
    /// assert_eq!(gauss.to_string(), "Gauss–Legendre s = 2");
    /// assert_eq!(Embedding::gauss_legendre(5), Err(Error::StagesOutOfRange { stages: 5 }));
    ///
    /// // One period of q = cos t in 40 steps.
    /// let grid = Grid::new(0.0, 2.0 * std::f64::consts::PI, 40)?;
    /// let problem = Problem::new(&Oscillator, grid, gauss);
    /// let run = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?;
    /// assert!((run.last()[0] - 1.0).abs() < 1e-6);
    /// assert!(matches!(
    ///     problem.solve_ivp(Scheme::Direct, 1.0, 0.0),
    ///     Err(Error::Unsupported { .. })
    /// ));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn gauss_legendre(stages: usize) -> Result<Self> {
        if !(1..=4).contains(&stages) {
            return Err(Error::StagesOutOfRange { stages });
        }
        Ok(Embedding {
            kind: EmbeddingKind::GaussLegendre { stages },
            side: Side::Backward,
        })
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
    /// Whether the paper proves the embedding coherent (direct = variational).
    pub fn is_coherent(&self) -> bool {
        match self.kind {
            EmbeddingKind::FiniteDifference => false,
            // No direct scheme to be coherent with.
            EmbeddingKind::GaussLegendre { .. } => false,
            _ => true,
        }
    }

    /// Whether the embedding is a one-step integrator of `(q, p)` with internal stages rather
    /// than an operator on the nodes: the Gauss–Legendre integrators. They solve initial value
    /// problems only; the evaluations on a whole curve (velocity, residuals, action, energy)
    /// and boundary value problems are [`Error::Unsupported`].
    pub(crate) fn is_one_step(&self) -> bool {
        matches!(self.kind, EmbeddingKind::GaussLegendre { .. })
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
            EmbeddingKind::GaussLegendre { stages } => write!(f, "Gauss–Legendre s = {stages}"),
        }
    }
}
