//! The blocks of a run-time step's Jacobian `h J`: which of the model's (and a force's) sparse
//! blocks enter it, and how they are added into the band system.

use crate::dynamic::band::{BandSystem, OutsideBand};
use crate::dynamic::sparse::{SparseBlock, SparseForceJacobian, SparseHessian};
use crate::step::terms::{BlockWeights, Terms};

/// `xx L_xx + xv L_xv + vx L_xvᵀ + vv L_vv` from `hessian`'s blocks into (`fresh`) or onto the
/// system.
pub(super) fn add_blocks(
    system: &mut BandSystem,
    hessian: &SparseHessian,
    w: BlockWeights,
    fresh: bool,
) -> std::result::Result<(), OutsideBand> {
    let SparseHessian { xx, xv, vv } = hessian;
    if vv.band().is_some() || xx.band().is_some() || xv.band().is_some() {
        return system.add_bands([(w.vv, vv), (w.xx, xx), (w.xv, xv)], (w.vx, xv), fresh);
    }
    if fresh {
        system.clear();
    }
    for (weight, block) in [(w.vv, vv), (w.xx, xx), (w.xv, xv)] {
        if weight != 0.0 {
            for &(i, j, value) in block.entries() {
                system.add(i, j, weight * value)?;
            }
        }
    }
    if w.vx != 0.0 {
        for &(i, j, value) in xv.entries() {
            system.add(j, i, w.vx * value)?;
        }
    }
    Ok(())
}

/// The blocks that enter the step Jacobian of the equation `terms` with step `h`: those with a
/// nonzero weight in some term. The system is planned on their pattern alone: a long-range
/// `L_xx` does not widen the band of a step whose Jacobian does not read it.
pub(super) fn jacobian_blocks<'a>(
    terms: &Terms,
    h: f64,
    hessian: &'a SparseHessian,
) -> Vec<&'a SparseBlock> {
    let reads = |weight: fn(&BlockWeights) -> f64| terms.reads(h, weight);
    let mut blocks = Vec::new();
    if reads(|w| w.vv) {
        blocks.push(&hessian.vv);
    }
    if reads(|w| w.xv.abs() + w.vx.abs()) {
        blocks.push(&hessian.xv);
    }
    if reads(|w| w.xx) {
        blocks.push(&hessian.xx);
    }
    blocks
}

/// The blocks of a force that enter the step Jacobian of the equation `terms`: `∂f/∂x` where
/// `L_xx` has a weight, `∂f/∂v` where `L_xv` has one.
pub(super) fn force_blocks<'a>(
    terms: &Terms,
    h: f64,
    force: &'a SparseForceJacobian,
) -> Vec<&'a SparseBlock> {
    let mut blocks = Vec::new();
    if terms.reads(h, |w| w.xv) {
        blocks.push(&force.v);
    }
    if terms.reads(h, |w| w.xx) {
        blocks.push(&force.x);
    }
    blocks
}

/// Whether `h J` is exactly the identity for the constant blocks in `hessian`: one term with
/// `L_vv = I` and no other block of `J` with a nonzero entry. The closed form is then
/// `y = b − h (G(b) − π)`, with no rounding beyond the hand-written Störmer–Verlet loop's.
pub(super) fn scaled_jacobian_is_identity(terms: &Terms, h: f64, hessian: &SparseHessian) -> bool {
    let [term] = terms.as_slice() else {
        return false;
    };
    let w = term.block_weights(h);
    h.is_finite()
        && w.vv == 1.0
        && hessian.vv.is_identity()
        && (w.xv == 0.0 && w.vx == 0.0 || hessian.xv.is_zero())
        && (w.xx == 0.0 || hessian.xx.is_zero())
}
