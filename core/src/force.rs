//! Generalised forces: `d/dt ∂L/∂v − ∂L/∂x = f(x, v, t)`, solved by both schemes.
//!
//! A [`Force`] is a vector field `f(x, v, t)` with its Jacobian; [`Rayleigh`] makes one from a
//! dissipation function `R(x, v, t)` (`f = −∂R/∂v`), written as a `#[lagrangian]` fn so that the
//! macro differentiates it. [`Forced`] attaches a force to a Lagrangian and is itself a
//! [`Lagrangian`]: its gradient's first output is `∂L/∂x + f`, the generalised force of the
//! Euler–Lagrange equation, so every scheme takes it where it takes `∂L/∂x`.
//!
//! That one substitution is both schemes with forces. The direct scheme embeds the forced
//! equation. The variational scheme is the discrete Lagrange–d'Alembert principle (Marsden and
//! West 2001, §3.2) with the discrete forces of the embedding's own quadrature: for
//! `L_d(Q_k, Q_{k+1}) = h Σ_i w_i L(x_i, V, t_i)`, `x_i = (1 − θ_i) Q_k + θ_i Q_{k+1}`,
//! `f_d^−(Q_k, Q_{k+1}) = h Σ_i w_i (1 − θ_i) f(x_i, V, t_i)` and
//! `f_d^+(Q_k, Q_{k+1}) = h Σ_i w_i θ_i f(x_i, V, t_i)`, which enter the discrete
//! Euler–Lagrange equation exactly where `h Σ_i w_i (1 − θ_i) ∂L/∂x` and
//! `h Σ_i w_i θ_i ∂L/∂x` do. The node momenta of [`Solution::node_values`] are then the forced
//! discrete Legendre transforms `p_k^− = −D₁L_d − f_d^−`, `p_{k+1}^+ = D₂L_d + f_d^+`, and the
//! forced discrete Noether theorem holds exactly: for a symmetry `ξ` of `L_d`,
//! `p_N·ξ − p_0·ξ` is the sum of the discrete impulses `(f_d^− + f_d^+)·ξ` ([`Forced::impulses`]).
//! The Gauss–Legendre integrators take the force at their stages the same way.

pub(crate) mod run_time;

pub use run_time::DynForce;

use crate::embedding::Scheme;
use crate::error::{Error, Result};
use crate::lagrangian::{
    Dependence, DynLagrangian, ForceJacobian, Hessian, HessianDependence, Lagrangian, Vector,
};
use crate::solve::nodes::{NodeFormula, rule};
use crate::solve::solution::Solution;

/// What the blocks of a force's Jacobian depend on: `x` of `∂f/∂x`, `v` of `∂f/∂v`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ForceDependence {
    /// What `∂f/∂x` depends on.
    pub x: Dependence,
    /// What `∂f/∂v` depends on.
    pub v: Dependence,
}

impl ForceDependence {
    /// Both blocks may depend on everything (nothing is known).
    ///
    /// ```
    /// assert_eq!(varembed::ForceDependence::ALL.v, varembed::Dependence::ALL);
    /// ```
    pub const ALL: ForceDependence = ForceDependence {
        x: Dependence::ALL,
        v: Dependence::ALL,
    };

    /// The blocks of `f = −∂R/∂v` from what `R`'s Hessian blocks depend on: `∂f/∂x = −R_xvᵀ`,
    /// `∂f/∂v = −R_vv` (for [`Rayleigh`] on both paths).
    pub(crate) fn of_dissipation(blocks: HessianDependence) -> Self {
        ForceDependence {
            x: blocks.xv,
            v: blocks.vv,
        }
    }
}

/// A generalised force `f(x, v, t)` on `R^D`, with its Jacobian (Newton's method on an implicit
/// step needs it: a force that depends on `v` makes implicit the steps whose equation reads it).
///
/// Implement it by hand, generate it from a vector-valued fn with
/// [`#[force]`](macro@crate::force), or make one from a dissipation function with [`Rayleigh`].
///
/// # Example
///
/// ```
/// use varembed::{Force, ForceDependence, ForceJacobian, Matrix, Vector, Dependence};
///
/// /// A periodic drive `f = A cos(ω t)`.
/// struct Drive { amplitude: f64, omega: f64 }
///
/// impl Force<1> for Drive {
///     fn force(&self, _x: &Vector<1>, _v: &Vector<1>, t: f64) -> Vector<1> {
///         Vector::<1>::new(self.amplitude * (self.omega * t).cos())
///     }
///     fn jacobian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> ForceJacobian<1> {
///         ForceJacobian { x: Matrix::<1>::zeros(), v: Matrix::<1>::zeros() }
///     }
///     // The Jacobian is a constant (zero): the steps that are affine without the force stay so.
///     fn jacobian_dependence(&self) -> ForceDependence {
///         ForceDependence { x: Dependence::NONE, v: Dependence::NONE }
///     }
/// }
/// let f = Drive { amplitude: 0.3, omega: 1.2 }.force(&Vector::<1>::zeros(), &Vector::<1>::zeros(), 0.0);
/// assert_eq!(f[0], 0.3);
/// ```
pub trait Force<const D: usize> {
    /// `f(x, v, t)`.
    fn force(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> Vector<D>;

    /// `∂f/∂x` and `∂f/∂v` at `(x, v, t)`.
    fn jacobian(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> ForceJacobian<D>;

    /// What the Jacobian's blocks depend on. The default claims nothing; a constant Jacobian
    /// (linear damping, a drive in `t` alone) keeps the closed-form steps of the model.
    fn jacobian_dependence(&self) -> ForceDependence {
        ForceDependence::ALL
    }

    /// The force's constants by name, checked for finiteness before a run with the model's.
    fn constants(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }
}

/// The force `f = −∂R/∂v` of a Rayleigh dissipation function `R(x, v, t)`, given as a
/// [`Lagrangian`] (write `R` as a `#[lagrangian]` fn: the macro differentiates it, and
/// `∂f/∂x = −(∂²R/∂x∂v)ᵀ`, `∂f/∂v = −∂²R/∂v²` are its Hessian blocks).
///
/// # Example
///
/// ```
/// use varembed::{Force, Rayleigh, Vector, lagrangian};
///
/// /// Linear friction: `R = ½ γ v²`, `f = −γ v`.
/// #[lagrangian]
/// fn friction(x: f64, v: f64, gamma: f64) -> f64 {
///     0.5 * gamma * v * v
/// }
/// let f = Rayleigh(Friction { gamma: 0.5 });
/// assert_eq!(f.force(&Vector::<1>::new(1.0), &Vector::<1>::new(2.0), 0.0)[0], -1.0);
/// assert_eq!(f.jacobian(&Vector::<1>::new(1.0), &Vector::<1>::new(2.0), 0.0).v[(0, 0)], -0.5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rayleigh<R>(pub R);

impl<const D: usize, R: Lagrangian<D>> Force<D> for Rayleigh<R> {
    #[inline]
    fn force(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> Vector<D> {
        -self.0.gradient(x, v, t).1
    }

    #[inline]
    fn jacobian(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> ForceJacobian<D> {
        let Hessian { xv, vv, .. } = self.0.hessian(x, v, t);
        ForceJacobian {
            x: -xv.transpose(),
            v: -vv,
        }
    }

    fn jacobian_dependence(&self) -> ForceDependence {
        ForceDependence::of_dissipation(self.0.hessian_dependence())
    }

    fn constants(&self) -> Vec<(&'static str, f64)> {
        self.0.constants()
    }
}

/// A Lagrangian `L` under a generalised force `f`: the system
/// `d/dt ∂L/∂v − ∂L/∂x = f(x, v, t)` (module docs).
///
/// It is a [`Lagrangian`] whose [`value`](Lagrangian::value), momentum, Hessian and energy are
/// `L`'s, and whose gradient's first output is `∂L/∂x + f`; solve it as any model, on the
/// const-generic path ([`Lagrangian::run_time`] is `None`). The force has constants of its own,
/// set where it is built; the blow-up guard stands down (the energy of `L` is not conserved),
/// and the energy balance is [`Forced::work`]. Initial value problems under every classical
/// embedding and both schemes; boundary value problems under the Gauss-FDEσ, asymmetric,
/// midpoint and trapezoidal embeddings; the fractional embeddings return
/// [`Error::Unsupported`].
///
/// # Example
///
/// ```
/// use varembed::{Forced, Grid, Problem, Rayleigh, Scheme, lagrangian};
///
/// #[lagrangian]
/// fn oscillator(x: f64, v: f64) -> f64 {
///     0.5 * v * v - 0.5 * x * x
/// }
/// #[lagrangian]
/// fn friction(x: f64, v: f64, gamma: f64) -> f64 {
///     0.5 * gamma * v * v
/// }
///
/// // q̈ + 0.2 q̇ + q = 0 from q(0) = 1, q̇(0) = 0.
/// let damped = Forced::new(Oscillator, Rayleigh(Friction { gamma: 0.2 }));
/// let solution = Problem::recommended(&damped, Grid::new(0.0, 10.0, 1000)?)
///     .solve_ivp(Scheme::Variational, 1.0, 0.0)?;
/// let omega = (1.0f64 - 0.01).sqrt();
/// let exact = (-0.1f64 * 10.0).exp() * ((omega * 10.0).cos() + 0.1 / omega * (omega * 10.0).sin());
/// assert!((solution.last()[0] - exact).abs() < 1e-4);
///
/// // The energy balance: E_N − E_0 against the work of the friction.
/// let nodes = solution.node_values(&damped)?;
/// let energy = nodes.energy.expect("L is autonomous");
/// let work = damped.work(&solution)?;
/// assert!((energy[1000] - energy[0] - work[1000]).abs() < 1e-4);
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Forced<L, F> {
    /// The Lagrangian.
    pub lagrangian: L,
    /// The generalised force.
    pub force: F,
}

impl<L, F> Forced<L, F> {
    /// `lagrangian` under `force`.
    pub const fn new(lagrangian: L, force: F) -> Self {
        Forced { lagrangian, force }
    }

    /// The discrete forces of each interval `[t_k, t_{k+1}]`, `(f_d^−, f_d^+)` with
    /// `f_d^− = h Σ_i w_i (1 − θ_i) f(x_i, V_k, t_i)` and `f_d^+ = h Σ_i w_i θ_i f(x_i, V_k, t_i)`
    /// over the quadrature points `x_i = (1 − θ_i) Q_k + θ_i Q_{k+1}` of the solution's
    /// embedding (`N` pairs): the virtual work `f_d^−·δQ_k + f_d^+·δQ_{k+1}` of the discrete
    /// Lagrange–d'Alembert principle, which the variational scheme solves. For a symmetry of `L`
    /// acting linearly, with generator `ξ(q) = A q` (a rotation too, not only a translation),
    /// that the discrete Lagrangian inherits (see the guide to forces and constraints), the
    /// node momenta of [`Solution::node_values`] called with this `Forced` model (the forced
    /// discrete Legendre transforms; `L`'s own would not do) satisfy the forced discrete
    /// Noether theorem `p_{k+1}·ξ(Q_{k+1}) − p_k·ξ(Q_k) = f_d^−·ξ(Q_k) + f_d^+·ξ(Q_{k+1})` to
    /// round-off.
    ///
    /// Only this `Forced`'s force counts: for several forces on one model, attach their sum
    /// (a pair `(f1, f2)` is a [`Force`]) rather than nesting `Forced` (whose schemes are
    /// right, but whose inner force these sums leave out).
    ///
    /// [`Error::Unsupported`] for the Gauss–Legendre integrators (their discrete forces are sums
    /// over the stages, which the solution does not keep) and the fractional embeddings.
    pub fn discrete_forces<const D: usize>(
        &self,
        solution: &Solution<D>,
    ) -> Result<Vec<(Vector<D>, Vector<D>)>>
    where
        F: Force<D>,
    {
        let flat: Vec<f64> = solution.q.iter().flat_map(|q| q.iter().copied()).collect();
        let pairs = discrete_force_pairs(
            &solution.embedding,
            &solution.grid,
            (D, &flat),
            |x, v, t, f| {
                let (x, v) = (
                    Vector::<D>::from_column_slice(x),
                    Vector::<D>::from_column_slice(v),
                );
                f.copy_from_slice(self.force.force(&x, &v, t).as_slice());
            },
        )?;
        Ok(pairs
            .into_iter()
            .map(|(left, right)| {
                (
                    Vector::<D>::from_column_slice(&left),
                    Vector::<D>::from_column_slice(&right),
                )
            })
            .collect())
    }

    /// The discrete impulse of the force over each interval `[t_k, t_{k+1}]`,
    /// `f_d^− + f_d^+ = h Σ_i w_i f(x_i, V_k, t_i)` ([`discrete_forces`](Self::discrete_forces);
    /// `N` vectors). For a direction `ξ` along which `L` is invariant (a translation), the
    /// variational scheme's node momenta satisfy `p_{k+1}·ξ − p_k·ξ = impulse_k·ξ` to
    /// round-off (the forced discrete Noether theorem). Errors as `discrete_forces`.
    pub fn impulses<const D: usize>(&self, solution: &Solution<D>) -> Result<Vec<Vector<D>>>
    where
        F: Force<D>,
    {
        let forces = self.discrete_forces(solution)?;
        Ok(forces
            .into_iter()
            .map(|(left, right)| left + right)
            .collect())
    }

    /// The work of the force from `t_0` to each node, `W_0 = 0`,
    /// `W_{k+1} = W_k + impulse_k·(Q_{k+1} − Q_k)/h` ([`impulses`](Self::impulses)): the
    /// quadrature of `∫ f·q̇ dt` by the embedding's rule. The energy of `L` at the nodes
    /// ([`Solution::node_values`]) satisfies `E_k − E_0 = W_k` to the scheme's order.
    pub fn work<const D: usize>(&self, solution: &Solution<D>) -> Result<Vec<f64>>
    where
        F: Force<D>,
    {
        let impulses = self.impulses(solution)?;
        let (h, q) = (solution.grid.h(), &solution.q);
        let mut work = Vec::with_capacity(q.len());
        work.push(0.0);
        for (k, impulse) in impulses.iter().enumerate() {
            work.push(work[k] + impulse.dot(&(q[k + 1] - q[k])) / h);
        }
        Ok(work)
    }
}

/// The discrete forces `(f_d^−, f_d^+)` of every interval of a run of `embedding` on `grid`
/// with the nodes `q` (flat, `d` values each), `force(x, v, t, f)` writing `f(x, v, t)` into
/// `f`: the quadrature of [`Forced::discrete_forces`], for both paths.
pub(crate) fn discrete_force_pairs(
    embedding: &crate::embedding::Embedding,
    grid: &crate::grid::Grid,
    (d, q): (usize, &[f64]),
    mut force: impl FnMut(&[f64], &[f64], f64, &mut [f64]),
) -> Result<Vec<(Vec<f64>, Vec<f64>)>> {
    let points = match rule(embedding, Scheme::Variational)?.formula {
        NodeFormula::DiscreteLegendre { points } => points,
        _ => {
            return Err(Error::Unsupported {
                operation: "the discrete forces of a force",
                embedding: embedding.to_string(),
            });
        }
    };
    let h = grid.h();
    let node = |k: usize| &q[k * d..(k + 1) * d];
    let (mut x, mut v, mut f) = (vec![0.0; d], vec![0.0; d], vec![0.0; d]);
    Ok((0..grid.n())
        .map(|k| {
            let (a, b) = (node(k), node(k + 1));
            for i in 0..d {
                v[i] = (b[i] - a[i]) / h;
            }
            let (mut left, mut right) = (vec![0.0; d], vec![0.0; d]);
            for &(theta, w) in points {
                for i in 0..d {
                    x[i] = a[i] * (1.0 - theta) + b[i] * theta;
                }
                let t = match theta {
                    0.0 => grid.t(k),
                    1.0 => grid.t(k + 1),
                    _ => grid.t(k) + theta * h,
                };
                force(&x, &v, t, &mut f);
                for i in 0..d {
                    let fi = f[i] * (h * w);
                    left[i] += fi * (1.0 - theta);
                    right[i] += fi * theta;
                }
            }
            (left, right)
        })
        .collect())
}

impl<const D: usize, L: Lagrangian<D>, F: Force<D>> Lagrangian<D> for Forced<L, F> {
    #[inline]
    fn value(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> f64 {
        self.lagrangian.value(x, v, t)
    }

    #[inline]
    fn gradient(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> (Vector<D>, Vector<D>) {
        let (f, p) = self.lagrangian.gradient(x, v, t);
        (f + self.force.force(x, v, t), p)
    }

    #[inline]
    fn hessian(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> Hessian<D> {
        self.lagrangian.hessian(x, v, t)
    }

    #[inline]
    fn gradient_and_hessian(
        &self,
        x: &Vector<D>,
        v: &Vector<D>,
        t: f64,
    ) -> (Vector<D>, Vector<D>, Hessian<D>) {
        let (f, p, hs) = self.lagrangian.gradient_and_hessian(x, v, t);
        (f + self.force.force(x, v, t), p, hs)
    }

    #[inline]
    fn value_and_gradient(
        &self,
        x: &Vector<D>,
        v: &Vector<D>,
        t: f64,
    ) -> (f64, Vector<D>, Vector<D>) {
        let (l, f, p) = self.lagrangian.value_and_gradient(x, v, t);
        (l, f + self.force.force(x, v, t), p)
    }

    /// `L`'s: the force's blocks are [`force_dependence`](Lagrangian::force_dependence).
    fn hessian_dependence(&self) -> HessianDependence {
        self.lagrangian.hessian_dependence()
    }

    /// The force's, joined to those of a force `L` itself carries (a nested `Forced`).
    fn force_dependence(&self) -> Option<[Dependence; 2]> {
        let own = self.force.jacobian_dependence();
        Some(joined([own.x, own.v], self.lagrangian.force_dependence()))
    }

    /// `None`: the force's Jacobian may couple any two components.
    fn hessian_bandwidth(&self) -> Option<usize> {
        None
    }

    fn dependence(&self) -> Dependence {
        self.lagrangian.dependence()
    }

    fn constants(&self) -> Vec<(&'static str, f64)> {
        let mut constants = self.lagrangian.constants();
        constants.extend(self.force.constants());
        constants
    }

    fn run_time(&self) -> Option<&dyn DynLagrangian> {
        None
    }

    fn energy(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> f64 {
        self.lagrangian.energy(x, v, t)
    }

    fn is_forced(&self) -> bool {
        true
    }

    /// The force's, plus that of a force `L` itself carries (a nested `Forced`).
    #[inline]
    fn force_jacobian(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> Option<ForceJacobian<D>> {
        let mut jacobian = self.force.jacobian(x, v, t);
        if let Some(inner) = self.lagrangian.force_jacobian(x, v, t) {
            jacobian.x += inner.x;
            jacobian.v += inner.v;
        }
        Some(jacobian)
    }
}

/// `own` joined to `inner`, block by block.
fn joined(own: [Dependence; 2], inner: Option<[Dependence; 2]>) -> [Dependence; 2] {
    match inner {
        Some([x, v]) => [own[0].joined(x), own[1].joined(v)],
        None => own,
    }
}

/// The sum of two forces: how to put friction and a drive on one model (its
/// [`Forced::work`] and [`Forced::impulses`] count both).
///
/// ```
/// use varembed::{Force, Rayleigh, Vector, lagrangian};
///
/// #[lagrangian]
/// fn friction(_x: f64, v: f64, gamma: f64) -> f64 {
///     0.5 * gamma * v * v
/// }
/// #[lagrangian]
/// fn well(x: f64, _v: f64) -> f64 {
///     0.5 * x * x
/// }
/// // −0.5 v, and −∂(½x²)/∂v = 0.
/// let both = (Rayleigh(Friction { gamma: 0.5 }), Rayleigh(Well));
/// assert_eq!(both.force(&Vector::<1>::new(3.0), &Vector::<1>::new(2.0), 0.0)[0], -1.0);
/// ```
impl<const D: usize, A: Force<D>, B: Force<D>> Force<D> for (A, B) {
    fn force(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> Vector<D> {
        self.0.force(x, v, t) + self.1.force(x, v, t)
    }
    fn jacobian(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> ForceJacobian<D> {
        let (a, b) = (self.0.jacobian(x, v, t), self.1.jacobian(x, v, t));
        ForceJacobian {
            x: a.x + b.x,
            v: a.v + b.v,
        }
    }
    fn jacobian_dependence(&self) -> ForceDependence {
        let (a, b) = (self.0.jacobian_dependence(), self.1.jacobian_dependence());
        let [x, v] = joined([a.x, a.v], Some([b.x, b.v]));
        ForceDependence { x, v }
    }
    fn constants(&self) -> Vec<(&'static str, f64)> {
        let mut constants = self.0.constants();
        constants.extend(self.1.constants());
        constants
    }
}

impl<const D: usize, F: Force<D> + ?Sized> Force<D> for &F {
    fn force(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> Vector<D> {
        (**self).force(x, v, t)
    }
    fn jacobian(&self, x: &Vector<D>, v: &Vector<D>, t: f64) -> ForceJacobian<D> {
        (**self).jacobian(x, v, t)
    }
    fn jacobian_dependence(&self) -> ForceDependence {
        (**self).jacobian_dependence()
    }
    fn constants(&self) -> Vec<(&'static str, f64)> {
        (**self).constants()
    }
}
