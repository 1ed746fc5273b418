//! Discrete embeddings and their two schemes: which velocity operator, which quadrature rows,
//! which rows each scheme's equations sit on.

use crate::error::{Error, Result};
use crate::side::Side;
use std::fmt;

pub(crate) mod kind;
mod operators;
pub(crate) use kind::EmbeddingKind;

/// Which discrete scheme of an embedding.
///
/// With `f_k = ∂L/∂x` and `p_k = ∂L/∂v` at `(Q_k, V_k, t_k)` on the quadrature rows, the
/// direct scheme's rows are, for Gauss-FDEσ (`k = 2..=N` for σ = −, `0..=N−2` for σ = +) and
/// for the coherent embeddings (`k = 1..=N−1`),
///
/// <!-- tex: f_k + \sigma \, (\Delta_\sigma p)_k = 0 \qquad \text{and} \qquad f_k - \sigma \, (\Delta_{-\sigma} p)_k = 0 \quad (\Delta^\alpha_{-\sigma} \text{ for Gauss-GLE}\sigma), -->
/// <math display="block"><mrow><msub><mi>f</mi><mi>k</mi></msub><mo>&#x0002B;</mo><mi>&#x003C3;</mi><mspace width="0.167em" /><mo stretchy="false">&#x00028;</mo><msub><mi>&#x00394;</mi><mi>&#x003C3;</mi></msub><mi>p</mi><msub><mo stretchy="false">&#x00029;</mo><mi>k</mi></msub><mo>&#x0003D;</mo><mn>0</mn><mspace width="2em" /><mtext>and</mtext><mspace width="2em" /><msub><mi>f</mi><mi>k</mi></msub><mo>&#x02212;</mo><mi>&#x003C3;</mi><mspace width="0.167em" /><mo stretchy="false">&#x00028;</mo><msub><mi>&#x00394;</mi><mrow><mo>&#x02212;</mo><mi>&#x003C3;</mi></mrow></msub><mi>p</mi><msub><mo stretchy="false">&#x00029;</mo><mi>k</mi></msub><mo>&#x0003D;</mo><mn>0</mn><mspace width="1em" /><mo stretchy="false">&#x00028;</mo><msubsup><mi>&#x00394;</mi><mrow><mo>&#x02212;</mo><mi>&#x003C3;</mi></mrow><mi>&#x003B1;</mi></msubsup><mtext>&#x000A0;for&#x000A0;Gauss-GLE</mtext><mi>&#x003C3;</mi><mo stretchy="false">&#x00029;</mo><mo>&#x0002C;</mo></mrow></math>
///
/// and the variational scheme's rows are the gradient of the discrete action, through the
/// transpose of the velocity operator `D = −σΔ_σ`:
///
/// <!-- tex: \frac{1}{h} \frac{\partial S_h}{\partial Q_k} = f_k + (D^{\top} p)_k = 0, \qquad k = 1, \dots, N-1. -->
/// <math display="block"><mrow><mfrac><mrow><mn>1</mn></mrow><mrow><mi>h</mi></mrow></mfrac><mfrac><mrow><mo>&#x02202;</mo><msub><mi>S</mi><mi>h</mi></msub></mrow><mrow><mo>&#x02202;</mo><msub><mi>Q</mi><mi>k</mi></msub></mrow></mfrac><mo>&#x0003D;</mo><msub><mi>f</mi><mi>k</mi></msub><mo>&#x0002B;</mo><mo stretchy="false">&#x00028;</mo><msup><mi>D</mi><mrow><mo>&#x022A4;</mo></mrow></msup><mi>p</mi><msub><mo stretchy="false">&#x00029;</mo><mi>k</mi></msub><mo>&#x0003D;</mo><mn>0</mn><mo>&#x0002C;</mo><mspace width="2em" /><mi>k</mi><mo>&#x0003D;</mo><mn>1</mn><mo>&#x0002C;</mo><mo>&#x02026;</mo><mo>&#x0002C;</mo><mi>N</mi><mo>&#x02212;</mo><mn>1</mn><mo>&#x0002E;</mo></mrow></math>
///
/// # Example
///
/// ```
/// use varembed::{Embedding, Grid, Problem, Scheme, Side, Vector, lagrangian};
///
/// #[lagrangian]
/// fn free(_x: f64, v: f64) -> f64 {
///     0.5 * v * v
/// }
///
/// // Under Gauss-FDE−, the direct rows are k = 2..=N and the variational ones k = 1..=N−1.
/// let problem = Problem::new(&Free, Grid::new(0.0, 1.0, 4)?, Embedding::finite_difference(Side::Backward));
/// assert_eq!(problem.residual_rows(Scheme::Direct), 2..=4);
/// assert_eq!(problem.residual_rows(Scheme::Variational), 1..=3);
/// assert_eq!(Scheme::Direct.to_string(), "direct");
/// # Ok::<(), varembed::Error>(())
/// ```
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

/// A discrete embedding: a family and a side σ.
///
/// Its velocity of a curve `Q = (Q_0, …, Q_N)` lives on the quadrature rows `k ∈ I_σ`:
///
/// <!-- tex: V_k = -\sigma \Delta_\sigma Q_k, \qquad \Delta_- Q_k = \frac{Q_k - Q_{k-1}}{h}, \quad \Delta_+ Q_k = \frac{Q_k - Q_{k+1}}{h}, \qquad I_- = \{1, \dots, N\}, \quad I_+ = \{0, \dots, N-1\} -->
/// <math display="block"><mrow><msub><mi>V</mi><mi>k</mi></msub><mo>&#x0003D;</mo><mo>&#x02212;</mo><mi>&#x003C3;</mi><msub><mi>&#x00394;</mi><mi>&#x003C3;</mi></msub><msub><mi>Q</mi><mi>k</mi></msub><mo>&#x0002C;</mo><mspace width="2em" /><msub><mi>&#x00394;</mi><mo>&#x02212;</mo></msub><msub><mi>Q</mi><mi>k</mi></msub><mo>&#x0003D;</mo><mfrac><mrow><msub><mi>Q</mi><mi>k</mi></msub><mo>&#x02212;</mo><msub><mi>Q</mi><mrow><mi>k</mi><mo>&#x02212;</mo><mn>1</mn></mrow></msub></mrow><mrow><mi>h</mi></mrow></mfrac><mo>&#x0002C;</mo><mspace width="1em" /><msub><mi>&#x00394;</mi><mo>&#x0002B;</mo></msub><msub><mi>Q</mi><mi>k</mi></msub><mo>&#x0003D;</mo><mfrac><mrow><msub><mi>Q</mi><mi>k</mi></msub><mo>&#x02212;</mo><msub><mi>Q</mi><mrow><mi>k</mi><mo>&#x0002B;</mo><mn>1</mn></mrow></msub></mrow><mrow><mi>h</mi></mrow></mfrac><mo>&#x0002C;</mo><mspace width="2em" /><msub><mi>I</mi><mo>&#x02212;</mo></msub><mo>&#x0003D;</mo><mo stretchy="false">&#x0007B;</mo><mn>1</mn><mo>&#x0002C;</mo><mo>&#x02026;</mo><mo>&#x0002C;</mo><mi>N</mi><mo stretchy="false">&#x0007D;</mo><mo>&#x0002C;</mo><mspace width="1em" /><msub><mi>I</mi><mo>&#x0002B;</mo></msub><mo>&#x0003D;</mo><mo stretchy="false">&#x0007B;</mo><mn>0</mn><mo>&#x0002C;</mo><mo>&#x02026;</mo><mo>&#x0002C;</mo><mi>N</mi><mo>&#x02212;</mo><mn>1</mn><mo stretchy="false">&#x0007D;</mo></mrow></math>
///
/// and for Gauss-GLEσ the Grünwald–Letnikov operators take the place of `Δ_±`:
///
/// <!-- tex: \Delta^\alpha_- Q_k = h^{-\alpha} \sum_{r=0}^{k} \alpha_r Q_{k-r}, \qquad \Delta^\alpha_+ Q_k = h^{-\alpha} \sum_{r=0}^{N-k} \alpha_r Q_{k+r}, \qquad \alpha_0 = 1, \quad \alpha_r = \alpha_{r-1} \frac{r - 1 - \alpha}{r} -->
/// <math display="block"><mrow><msubsup><mi>&#x00394;</mi><mo>&#x02212;</mo><mi>&#x003B1;</mi></msubsup><msub><mi>Q</mi><mi>k</mi></msub><mo>&#x0003D;</mo><msup><mi>h</mi><mrow><mo>&#x02212;</mo><mi>&#x003B1;</mi></mrow></msup><munderover><mo>&#x02211;</mo><mrow><mi>r</mi><mo>&#x0003D;</mo><mn>0</mn></mrow><mrow><mi>k</mi></mrow></munderover><msub><mi>&#x003B1;</mi><mi>r</mi></msub><msub><mi>Q</mi><mrow><mi>k</mi><mo>&#x02212;</mo><mi>r</mi></mrow></msub><mo>&#x0002C;</mo><mspace width="2em" /><msubsup><mi>&#x00394;</mi><mo>&#x0002B;</mo><mi>&#x003B1;</mi></msubsup><msub><mi>Q</mi><mi>k</mi></msub><mo>&#x0003D;</mo><msup><mi>h</mi><mrow><mo>&#x02212;</mo><mi>&#x003B1;</mi></mrow></msup><munderover><mo>&#x02211;</mo><mrow><mi>r</mi><mo>&#x0003D;</mo><mn>0</mn></mrow><mrow><mi>N</mi><mo>&#x02212;</mo><mi>k</mi></mrow></munderover><msub><mi>&#x003B1;</mi><mi>r</mi></msub><msub><mi>Q</mi><mrow><mi>k</mi><mo>&#x0002B;</mo><mi>r</mi></mrow></msub><mo>&#x0002C;</mo><mspace width="2em" /><msub><mi>&#x003B1;</mi><mn>0</mn></msub><mo>&#x0003D;</mo><mn>1</mn><mo>&#x0002C;</mo><mspace width="1em" /><msub><mi>&#x003B1;</mi><mi>r</mi></msub><mo>&#x0003D;</mo><msub><mi>&#x003B1;</mi><mrow><mi>r</mi><mo>&#x02212;</mo><mn>1</mn></mrow></msub><mfrac><mrow><mi>r</mi><mo>&#x02212;</mo><mn>1</mn><mo>&#x02212;</mo><mi>&#x003B1;</mi></mrow><mrow><mi>r</mi></mrow></mfrac></mrow></math>
///
/// The variational scheme makes the discrete action stationary:
///
/// <!-- tex: S_h(Q) = h \sum_{k \in I_\sigma} L(Q_k, V_k, t_k) -->
/// <math display="block"><mrow><msub><mi>S</mi><mi>h</mi></msub><mo stretchy="false">&#x00028;</mo><mi>Q</mi><mo stretchy="false">&#x00029;</mo><mo>&#x0003D;</mo><mi>h</mi><munder><mo>&#x02211;</mo><mrow><mi>k</mi><mo>&#x02208;</mo><msub><mi>I</mi><mi>&#x003C3;</mi></msub></mrow></munder><mi>L</mi><mo stretchy="false">&#x00028;</mo><msub><mi>Q</mi><mi>k</mi></msub><mo>&#x0002C;</mo><msub><mi>V</mi><mi>k</mi></msub><mo>&#x0002C;</mo><msub><mi>t</mi><mi>k</mi></msub><mo stretchy="false">&#x00029;</mo></mrow></math>
///
/// (index ranges and signs: [conventions](crate::guide::conventions)).
///
/// The symmetric embeddings ([`Embedding::midpoint`], [`Embedding::trapezoidal`]) look at
/// both neighbours of a node and have no side of their own: for them [`side`](Self::side) is
/// [`Side::Backward`], which says only how their interval values are stored: the velocity
/// `V_k = (Q_k − Q_{k−1})/h` of the interval `[t_{k−1}, t_k]` sits on row `k`, rows `1..=N`
/// as for `Δ_−` ([conventions](crate::guide::conventions)).
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

/// A fractional embedding of order `alpha` on `side`, of the kind `kind(alpha)`; the typed
/// error unless `0 < α ≤ 1` (NaN included).
fn fractional(side: Side, alpha: f64, kind: fn(f64) -> EmbeddingKind) -> Result<Embedding> {
    if !(alpha > 0.0 && alpha <= 1.0) {
        return Err(Error::AlphaOutOfRange { alpha });
    }
    Ok(Embedding {
        kind: kind(alpha),
        side,
    })
}

impl Embedding {
    /// Gauss-FDEσ.
    ///
    /// ```
    /// use varembed::{Embedding, EmbeddingKind, Side};
    /// let fde = Embedding::finite_difference(Side::Forward);
    /// assert_eq!((fde.kind(), fde.side()), (EmbeddingKind::FiniteDifference, Side::Forward));
    /// assert!(!fde.is_coherent());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn finite_difference(side: Side) -> Self {
        Embedding {
            kind: EmbeddingKind::FiniteDifference,
            side,
        }
    }
    /// The asymmetric Gauss-FDEσ.
    ///
    /// ```
    /// use varembed::{Embedding, EmbeddingKind, Side};
    /// let asym = Embedding::asymmetric(Side::Backward);
    /// assert_eq!(asym.kind(), EmbeddingKind::Asymmetric);
    /// assert!(asym.is_coherent());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn asymmetric(side: Side) -> Self {
        Embedding {
            kind: EmbeddingKind::Asymmetric,
            side,
        }
    }
    /// Gauss-GLEσ of order α; errors unless `0 < α ≤ 1`.
    ///
    /// ```
    /// use varembed::{Embedding, EmbeddingKind, Side};
    /// let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7)?;
    /// assert_eq!(gle.kind(), EmbeddingKind::GrunwaldLetnikov { alpha: 0.7 });
    /// assert!(Embedding::grunwald_letnikov(Side::Backward, 0.0).is_err());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn grunwald_letnikov(side: Side, alpha: f64) -> Result<Self> {
        fractional(side, alpha, |alpha| EmbeddingKind::GrunwaldLetnikov {
            alpha,
        })
    }

    /// Gauss-GLEσ in the Caputo form ([`EmbeddingKind::Caputo`]) of order α: the velocity
    /// `V = −σ Δ^α_σ (Q − Q_e)`, `Q_e` the end node where the derivative starts (`Q_0` for
    /// σ = −, `Q_N` for σ = +); errors unless `0 < α ≤ 1`. For boundary data that do not
    /// vanish at that end, where Gauss-GLEσ has infinite action for `α ≥ 1/2`
    /// ([solvers](crate::guide::solvers)).
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, EmbeddingKind, Error, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn free(_x: f64, v: f64) -> f64 {
    ///     0.5 * v * v
    /// }
    ///
    /// let caputo = Embedding::caputo(Side::Backward, 0.8)?;
    /// assert_eq!(caputo.kind(), EmbeddingKind::Caputo { alpha: 0.8 });
    /// assert_eq!(caputo.to_string(), "Caputo Gauss-GLE− (α = 0.8)");
    /// assert!(caputo.is_fractional() && caputo.is_coherent());
    /// assert_eq!(Embedding::caputo(Side::Forward, 1.5), Err(Error::AlphaOutOfRange { alpha: 1.5 }));
    ///
    /// // A constant curve has zero Caputo velocity, so it is a critical point of the action:
    /// // the data q(0) = q(1) = 0.3 give back the constant, with no warning.
    /// let problem = Problem::new(&Free, Grid::new(0.0, 1.0, 16)?, caputo);
    /// let solution = problem.solve_bvp(Scheme::Variational, 0.3, 0.3)?;
    /// assert!(solution.q.iter().all(|q| (q[0] - 0.3).abs() < 1e-12));
    /// assert!(solution.warnings.is_empty());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn caputo(side: Side, alpha: f64) -> Result<Self> {
        fractional(side, alpha, |alpha| EmbeddingKind::Caputo { alpha })
    }

    /// Gauss-GLEσ corrected at the ends ([`EmbeddingKind::CorrectedGrunwaldLetnikov`]) of
    /// order α: starting columns make the velocity operator exact on `t^α` and `t^{1+α}` next
    /// to the end where it starts, and the operator the direct scheme applies to the momenta
    /// exact on a momentum that does not vanish at the other end. Errors unless `0 < α ≤ 1`.
    /// Its **direct** scheme is the one to use: second order on data where Gauss-GLEσ's order
    /// is 0.5 to 0.8 at α = 0.6, 0.8 (a momentum not vanishing at either end), still second
    /// order where Gauss-GLEσ's is. Boundary value problems, on both fractional solvers (the
    /// fast one by GMRES: the direct scheme's Jacobian is not symmetric).
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// // q = t^{0.6}/Γ(1.6) has the momentum p = D^{0.6}_− q = 1, which vanishes at neither
    /// // end; it solves L = ½v² − F(t) x with F = D^{0.6}_+ p = (1 − t)^{−0.6}/Γ(0.4), a forcing
    /// // infinite at t = 1, where no row of the scheme reads it.
    /// #[lagrangian]
    /// fn forced(x: f64, v: f64, t: f64) -> f64 {
    ///     0.5 * v * v - x * (1.0 - t).powf(-0.6) / 2.218_159_543_757_688
    /// }
    ///
    /// let corrected = Embedding::corrected_grunwald_letnikov(Side::Backward, 0.6)?;
    /// assert_eq!(corrected.to_string(), "corrected Gauss-GLE− (α = 0.6)");
    /// assert!(corrected.is_fractional() && !corrected.is_coherent());
    ///
    /// let q = |t: f64| t.powf(0.6) / 0.893_515_349_287_690_3; // Γ(1.6)
    /// let grid = Grid::new(0.0, 1.0, 64)?;
    /// let max_error = |embedding| -> Result<f64, varembed::Error> {
    ///     let run = Problem::new(&Forced, grid, embedding).solve_bvp(Scheme::Direct, 0.0, q(1.0))?;
    ///     let nodes = grid.nodes().into_iter().zip(&run.q);
    ///     Ok(nodes.fold(0.0f64, |m, (t, x)| m.max((x[0] - q(t)).abs())))
    /// };
    /// // Exact on this solution, where the paper's scheme is off by more than 1e-3.
    /// assert!(max_error(corrected)? < 1e-10);
    /// assert!(max_error(Embedding::grunwald_letnikov(Side::Backward, 0.6)?)? > 1e-3);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn corrected_grunwald_letnikov(side: Side, alpha: f64) -> Result<Self> {
        fractional(side, alpha, |alpha| {
            EmbeddingKind::CorrectedGrunwaldLetnikov { alpha }
        })
    }

    /// The Caputo form corrected at the ends ([`EmbeddingKind::CorrectedCaputo`]) of order α:
    /// [`corrected_grunwald_letnikov`](Self::corrected_grunwald_letnikov)'s operators on the
    /// curve minus its value `Q_e` at the end where the derivative starts, as in
    /// [`caputo`](Self::caputo). Errors unless `0 < α ≤ 1`. Its **direct** scheme is second
    /// order on data with `q(a) ≠ 0` (σ = −) and a momentum vanishing at neither end, where the
    /// Caputo form's order is below 1.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// // q = 0.5 + t^{0.6}/Γ(1.6) has the Caputo momentum p = D^{0.6}_− (q − q(0)) = 1, so it
    /// // solves L = ½v² − F(t) x with F = D^{0.6}_+ p = (1 − t)^{−0.6}/Γ(0.4).
    /// #[lagrangian]
    /// fn forced(x: f64, v: f64, t: f64) -> f64 {
    ///     0.5 * v * v - x * (1.0 - t).powf(-0.6) / 2.218_159_543_757_688
    /// }
    ///
    /// let corrected = Embedding::corrected_caputo(Side::Backward, 0.6)?;
    /// assert_eq!(corrected.to_string(), "corrected Caputo Gauss-GLE− (α = 0.6)");
    /// let q = |t: f64| 0.5 + t.powf(0.6) / 0.893_515_349_287_690_3; // Γ(1.6)
    /// let grid = Grid::new(0.0, 1.0, 64)?;
    /// let max_error = |embedding| -> Result<f64, varembed::Error> {
    ///     let run = Problem::new(&Forced, grid, embedding).solve_bvp(Scheme::Direct, q(0.0), q(1.0))?;
    ///     let nodes = grid.nodes().into_iter().zip(&run.q);
    ///     Ok(nodes.fold(0.0f64, |m, (t, x)| m.max((x[0] - q(t)).abs())))
    /// };
    /// assert!(max_error(corrected)? < 1e-10);
    /// assert!(max_error(Embedding::caputo(Side::Backward, 0.6)?)? > 1e-3);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn corrected_caputo(side: Side, alpha: f64) -> Result<Self> {
        fractional(side, alpha, |alpha| EmbeddingKind::CorrectedCaputo {
            alpha,
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

    /// The recommended embedding when nothing else is known about the problem: the
    /// [`midpoint`](Self::midpoint) embedding, to be solved with [`Scheme::Variational`]. Its
    /// variational scheme is second order on every smooth Lagrangian (separable or not),
    /// symplectic (energy error bounded, no drift), keeps the momentum maps of the
    /// Lagrangian's symmetries exactly (discrete Noether), has no stability limit on linear
    /// oscillations (A-stable: any `ωh`), and solves both initial and boundary value problems,
    /// at the price of one Newton solve of `d` unknowns per step. [Choosing a
    /// scheme](crate::guide::choosing) says when another scheme is better (Störmer–Verlet for
    /// `½vᵀMv − U` with a constant `M`, Gauss–Legendre for high accuracy, the direct schemes for
    /// stiff damping).
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Scheme};
    /// let recommended = Embedding::recommended();
    /// assert_eq!(recommended, Embedding::midpoint());
    /// assert_eq!(recommended.order(Scheme::Variational), Some(2));
    /// ```
    pub fn recommended() -> Self {
        Embedding::midpoint()
    }

    /// The family.
    ///
    /// ```
    /// use varembed::{Embedding, EmbeddingKind, Side};
    /// assert_eq!(Embedding::asymmetric(Side::Forward).kind(), EmbeddingKind::Asymmetric);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn kind(&self) -> EmbeddingKind {
        self.kind
    }
    /// The side σ.
    ///
    /// ```
    /// use varembed::{Embedding, EmbeddingKind, Side};
    /// assert_eq!(Embedding::asymmetric(Side::Forward).side(), Side::Forward);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn side(&self) -> Side {
        self.side
    }
    /// The order α (1 for the classical embeddings).
    ///
    /// ```
    /// use varembed::{Embedding, EmbeddingKind, Side};
    /// assert_eq!(Embedding::finite_difference(Side::Forward).alpha(), 1.0);
    /// assert_eq!(Embedding::grunwald_letnikov(Side::Forward, 0.6)?.alpha(), 0.6);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn alpha(&self) -> f64 {
        match self.kind {
            EmbeddingKind::GrunwaldLetnikov { alpha }
            | EmbeddingKind::Caputo { alpha }
            | EmbeddingKind::CorrectedGrunwaldLetnikov { alpha }
            | EmbeddingKind::CorrectedCaputo { alpha } => alpha,
            _ => 1.0,
        }
    }
    /// Whether the embedding is Grünwald–Letnikov, in any form (even at α = 1, where its
    /// operators equal the classical ones but are stored densely).
    ///
    /// ```
    /// use varembed::{Embedding, EmbeddingKind, Side};
    /// assert!(Embedding::grunwald_letnikov(Side::Forward, 1.0)?.is_fractional());
    /// assert!(Embedding::caputo(Side::Forward, 0.6)?.is_fractional());
    /// assert!(!Embedding::asymmetric(Side::Forward).is_fractional());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn is_fractional(&self) -> bool {
        matches!(
            self.kind,
            EmbeddingKind::GrunwaldLetnikov { .. }
                | EmbeddingKind::Caputo { .. }
                | EmbeddingKind::CorrectedGrunwaldLetnikov { .. }
                | EmbeddingKind::CorrectedCaputo { .. }
        )
    }

    /// Whether the velocity differentiates the curve minus its value at the end where the
    /// derivative starts: the Caputo form, corrected or not.
    pub(crate) fn is_caputo(&self) -> bool {
        matches!(
            self.kind,
            EmbeddingKind::Caputo { .. } | EmbeddingKind::CorrectedCaputo { .. }
        )
    }

    /// The node whose value the velocity subtracts from the curve: `Some(0)` (σ = −) or
    /// `Some(N)` (σ = +) for the Caputo forms, `None` for every other embedding.
    pub(crate) fn caputo_end(&self, n: usize) -> Option<usize> {
        self.is_caputo().then_some(match self.side {
            Side::Backward => 0,
            Side::Forward => n,
        })
    }
    /// The quadrature node whose force `∂L/∂x` no row of either scheme reads, for the
    /// fractional embeddings: the end where the right derivative of their Euler–Lagrange
    /// equation starts (`Some(N)` for σ = −, `Some(0)` for σ = +). Its momentum is read. A
    /// forcing singular there, such as `D^α_+ p ~ (b − t)^{−α}` when the momentum does not
    /// vanish at `b`, is not evaluated into anything, and may be infinite.
    pub(crate) fn unread_force_end(&self, n: usize) -> Option<usize> {
        match self.side {
            _ if !self.is_fractional() => None,
            Side::Backward => Some(n),
            Side::Forward => Some(0),
        }
    }

    /// Whether the embedding is coherent (direct = variational): proved by the paper for the
    /// asymmetric Gauss-FDEσ and Gauss-GLEσ, and so for the Caputo form, whose two schemes are
    /// Gauss-GLEσ's rows at its own velocity. Gauss-FDEσ is not; neither are the midpoint and
    /// trapezoidal embeddings, whose direct scheme evaluates `∂L/∂x` once at the node where
    /// the variational one averages it over the two neighbouring intervals
    /// ([schemes](crate::guide::schemes)); nor are the corrected Gauss-GLEσ and its Caputo form,
    /// whose corrected momentum operator is not the transpose of the corrected velocity
    /// operator; the Gauss–Legendre integrators have no direct scheme to be coherent with.
    ///
    /// ```
    /// use varembed::{Embedding, EmbeddingKind, Side};
    /// assert!(Embedding::grunwald_letnikov(Side::Backward, 0.5)?.is_coherent());
    /// assert!(!Embedding::finite_difference(Side::Backward).is_coherent());
    /// assert!(!Embedding::midpoint().is_coherent());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn is_coherent(&self) -> bool {
        matches!(
            self.kind,
            EmbeddingKind::Asymmetric
                | EmbeddingKind::GrunwaldLetnikov { .. }
                | EmbeddingKind::Caputo { .. }
        )
    }

    /// Whether the embedding is a one-step integrator of `(q, p)` with internal stages rather
    /// than an operator on the nodes: the Gauss–Legendre integrators. Their boundary value
    /// problems are a collocation system of their own; the evaluations on a whole curve
    /// (quadrature velocities, residuals, action, quadrature energies) are
    /// [`Error::Unsupported`].
    pub(crate) fn is_one_step(&self) -> bool {
        matches!(self.kind, EmbeddingKind::GaussLegendre { .. })
    }

    /// Whether the embedding is symmetric (midpoint or trapezoidal): its discrete Lagrangian
    /// `L_d(Q_k, Q_{k+1})` reads the whole interval, with no side.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Side};
    /// assert!(Embedding::trapezoidal().is_symmetric());
    /// assert!(!Embedding::finite_difference(Side::Forward).is_symmetric());
    /// ```
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
    /// - Gauss–Legendre with `s` stages: `2s`, variational only (`None` for the direct
    ///   scheme, which it does not have).
    /// - Gauss-GLEσ, in either form: 1 at α = 1 (the Gauss-FDEσ operators, which ignore the
    ///   Caputo shift); `None` for `α < 1`, where the order depends on the data: the solution
    ///   of a fractional problem is in general singular at the ends
    ///   ([schemes](crate::guide::schemes)).
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Scheme, Side};
    /// let fde = Embedding::finite_difference(Side::Backward);
    /// assert_eq!(fde.order(Scheme::Direct), Some(1));
    /// let gauss = Embedding::gauss_legendre(3)?;
    /// assert_eq!(gauss.order(Scheme::Variational), Some(6));
    /// assert_eq!(gauss.order(Scheme::Direct), None); // no direct scheme
    /// let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7)?;
    /// assert_eq!(gle.order(Scheme::Variational), None); // depends on the data
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn order(&self, scheme: Scheme) -> Option<u32> {
        // Every family but Gauss–Legendre has one order for both schemes.
        match self.kind {
            EmbeddingKind::Midpoint | EmbeddingKind::Trapezoidal => Some(2),
            EmbeddingKind::FiniteDifference | EmbeddingKind::Asymmetric => Some(1),
            EmbeddingKind::GrunwaldLetnikov { alpha }
            | EmbeddingKind::Caputo { alpha }
            | EmbeddingKind::CorrectedGrunwaldLetnikov { alpha }
            | EmbeddingKind::CorrectedCaputo { alpha } => (alpha == 1.0).then_some(1),
            // Variational only: no order for a direct scheme that does not exist.
            EmbeddingKind::GaussLegendre { stages } => {
                (scheme == Scheme::Variational).then_some(2 * stages as u32)
            }
        }
    }
}

impl fmt::Display for Embedding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = self.side.symbol();
        match self.kind {
            EmbeddingKind::FiniteDifference => write!(f, "Gauss-FDE{s}"),
            EmbeddingKind::Asymmetric => write!(f, "asymmetric Gauss-FDE{s}"),
            EmbeddingKind::GrunwaldLetnikov { alpha } => write!(f, "Gauss-GLE{s} (α = {alpha})"),
            EmbeddingKind::Caputo { alpha } => write!(f, "Caputo Gauss-GLE{s} (α = {alpha})"),
            EmbeddingKind::CorrectedGrunwaldLetnikov { alpha } => {
                write!(f, "corrected Gauss-GLE{s} (α = {alpha})")
            }
            EmbeddingKind::CorrectedCaputo { alpha } => {
                write!(f, "corrected Caputo Gauss-GLE{s} (α = {alpha})")
            }
            EmbeddingKind::GaussLegendre { stages } => write!(f, "Gauss–Legendre s = {stages}"),
            EmbeddingKind::Midpoint => f.write_str("midpoint"),
            EmbeddingKind::Trapezoidal => f.write_str("trapezoidal"),
        }
    }
}
