//! How the steps of one run find the newest node: the closed-form update of the steps that are
//! affine in it (the step module's third table), decided once per run, with `J⁻¹` inverted
//! once when the step Jacobian is constant.

use crate::lagrangian::{Dependence, HessianDependence, Lagrangian, Matrix, Vector};
use crate::linalg::solve_small;

use super::terms::equation_terms;
use super::{Step, StepKind, StepTimes, equation, scaled_jacobian, single_term};

/// Whether the step equation of `kind` is affine in the newest node (third table of the
/// module docs), read off the table of terms: every block its Jacobian reads depends neither on
/// the velocity, which moves with the newest node at every point, nor, at a point that moves
/// with it (`@right`, the midpoint), on the position. The symmetric kinds are never planned in
/// closed form: `false`.
pub fn is_affine(kind: StepKind, dependence: &HessianDependence) -> bool {
    single_term(kind).is_some()
        && !jacobian_blocks(kind, dependence).any(|(block, moves)| block.v || (moves && block.x))
}

/// Whether every block in the Jacobian of `kind` is a constant, so that with a uniform step
/// the Jacobian is the same at every step (asked of the affine kinds only: `false` for the
/// symmetric kinds).
pub(crate) fn jacobian_is_constant(kind: StepKind, dependence: &HessianDependence) -> bool {
    single_term(kind).is_some()
        && jacobian_blocks(kind, dependence).all(|(block, _)| block == Dependence::NONE)
}

/// What each block in the Jacobian of `kind`'s step equation depends on (a block is in it where
/// its weight in some term is not zero; `L_vx` depends on what `L_xv` does), with whether its
/// term's point moves with the newest node.
fn jacobian_blocks(
    kind: StepKind,
    dependence: &HessianDependence,
) -> impl Iterator<Item = (Dependence, bool)> {
    let HessianDependence { xx, xv, vv } = *dependence;
    let terms = equation_terms(kind);
    (0..terms.as_slice().len()).flat_map(move |k| {
        let term = terms.as_slice()[k];
        let w = term.block_weights(1.0);
        let moves = term.point.slopes().0 != 0.0;
        [(w.xx, xx), (w.xv, xv), (w.vx, xv), (w.vv, vv)]
            .into_iter()
            .filter(|(weight, _)| *weight != 0.0)
            .map(move |(_, block)| (block, moves))
    })
}

/// How the steps of one run find the newest node, decided once per run by [`Update::plan`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Update<const D: usize> {
    /// Newton's method: the step is not affine, or its constant Jacobian is singular (Newton
    /// then reports the singular Jacobian with the step index).
    Newton,
    /// Affine with a constant diagonal `J⁻¹`, stored as its diagonal: one multiplication per
    /// coordinate, with no zero entries on the critical path of an explicit run.
    ConstantDiagonalInverse(Vector<D>),
    /// Affine with a constant `J⁻¹`.
    ConstantInverse(Matrix<D>),
    /// Affine with a Jacobian that changes from step to step: one linear solve per step.
    SolvePerStep,
}

impl<const D: usize> Update<D> {
    /// The update of every step of `kind` for `lagrangian` with step size `times.h`.
    ///
    /// A constant Jacobian is inverted here, from the blocks at the first step's previous node
    /// `b` (any point gives the same blocks; a real node keeps clear of points where the
    /// Lagrangian is undefined).
    pub fn plan<L: Lagrangian<D> + ?Sized>(
        lagrangian: &L,
        kind: StepKind,
        b: &Vector<D>,
        times: &StepTimes,
    ) -> Self {
        let dependence = step_dependence(lagrangian, kind);
        if !is_affine(kind, &dependence) {
            return Update::Newton;
        }
        if !jacobian_is_constant(kind, &dependence) {
            return Update::SolvePerStep;
        }
        let (rest, t) = (Vector::<D>::zeros(), kind.equation_time(times));
        let hs = lagrangian.hessian(b, &rest, t);
        let force = lagrangian.force_jacobian(b, &rest, t);
        let Some(m_inv) = inverse(&scaled_jacobian(kind, &hs, force, times.h)) else {
            return Update::Newton;
        };
        let j_inv = m_inv * times.h;
        if (0..D).all(|i| (0..D).all(|j| i == j || j_inv[(i, j)] == 0.0)) {
            Update::ConstantDiagonalInverse(j_inv.diagonal())
        } else {
            Update::ConstantInverse(j_inv)
        }
    }

    /// The newest node in closed form, `y = b + J⁻¹ (π − G(b))` with `G` evaluated at `y = b`
    /// (velocity 0). `None` for [`Update::Newton`] and for a singular per-step Jacobian; the
    /// caller then runs Newton, which reports the failure with its step index.
    #[inline(always)]
    pub fn explicit<L: Lagrangian<D> + ?Sized>(
        &self,
        lagrangian: &L,
        step: &Step<D>,
    ) -> Option<Vector<D>> {
        // At y = b the equation is evaluated at b, whichever side.
        let (b, h) = (&step.b, step.times.h);
        let t = step.kind.equation_time(&step.times);
        // The velocity is an exact zero, not (b − b)/h: the optimiser then drops every term
        // of the derivatives it multiplies. One per arm, so that the per-step solve passing
        // its address on cannot keep the other arms' zero in memory.
        let rest = Vector::<D>::zeros;
        // π − G rather than −(G − π): π − 0 folds to π, −(0 − π) does not.
        match self {
            Update::Newton => None,
            Update::ConstantDiagonalInverse(diagonal) => {
                let (f, p) = lagrangian.gradient(b, &rest(), t);
                Some(b + diagonal.component_mul(&(step.momentum - equation(step.kind, f, p, h))))
            }
            Update::ConstantInverse(j_inv) => {
                let (f, p) = lagrangian.gradient(b, &rest(), t);
                Some(b + j_inv * (step.momentum - equation(step.kind, f, p, h)))
            }
            Update::SolvePerStep => {
                let (f, p, hs) = lagrangian.gradient_and_hessian(b, &rest(), t);
                let force = lagrangian.force_jacobian(b, &rest(), t);
                let rhs = step.momentum - equation(step.kind, f, p, h);
                solve_small(&scaled_jacobian(step.kind, &hs, force, h), &rhs).map(|dy| b + dy * h)
            }
        }
    }
}

/// What the blocks of `kind`'s step Jacobian depend on: `L`'s blocks, and where the step's
/// equation reads `∂L/∂x` a force's `∂f/∂x` and `∂f/∂v` joined to `L_xx` and `L_xv` (a step
/// that reads the force only in its momentum keeps `L`'s affinity: the variational
/// Gauss-FDE− step under quadratic drag is still Störmer–Verlet's closed form).
fn step_dependence<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    kind: StepKind,
) -> HessianDependence {
    with_force(
        lagrangian.hessian_dependence(),
        kind,
        lagrangian.is_forced(),
        lagrangian.force_dependence(),
    )
}

/// Whether the step equation of `kind` reads `∂L/∂x` (and so a force folded into it).
pub(crate) fn reads_force(kind: StepKind) -> bool {
    equation_terms(kind)
        .as_slice()
        .iter()
        .any(|term| term.f != 0.0)
}

/// `dependence` with a force's blocks (`[∂f/∂x, ∂f/∂v]`) joined to `L_xx` and `L_xv` where the
/// step equation of `kind` reads the force (both storages' plans). A forced model that
/// declares nothing about its force's blocks (`None`) claims nothing: they may depend on
/// everything.
pub(crate) fn with_force(
    mut dependence: HessianDependence,
    kind: StepKind,
    forced: bool,
    force: Option<[Dependence; 2]>,
) -> HessianDependence {
    if forced && reads_force(kind) {
        let [x, v] = force.unwrap_or([Dependence::ALL; 2]);
        dependence.xx = dependence.xx.joined(x);
        dependence.xv = dependence.xv.joined(v);
    }
    dependence
}

/// `m⁻¹`, column by column with [`solve_small`] so that "singular" means what it means for
/// every other step solve; `None` when singular or not finite.
fn inverse<const D: usize>(m: &Matrix<D>) -> Option<Matrix<D>> {
    let identity = Matrix::<D>::identity();
    let mut inv = Matrix::<D>::zeros();
    for j in 0..D {
        inv.set_column(j, &solve_small(m, &identity.column(j).into_owned())?);
    }
    inv.iter().all(|c| c.is_finite()).then_some(inv)
}
