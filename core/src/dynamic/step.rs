//! One step of the Gauss-FDEσ schemes for a run-time-dimension model: the momentum `π` from
//! the two previous nodes, then the discrete Legendre map `G(y) = π` for the newest node, by a
//! closed form where the step is affine in `y` and by sparse Newton otherwise.
//!
//! The equations, the Jacobians and the affine cases are the step module's tables (read there
//! with `Q_{n−2} = a`, `Q_{n−1} = b`, `Q_n = y`); this module evaluates them on slices and
//! assembles the Jacobian `h J` entry by entry from the model's sparse blocks into a
//! [`BandSystem`]. Every buffer is allocated once per run.

use crate::error::{Error, Location, Result};
use crate::linalg::BandNorms;
use crate::options::NewtonOptions;
use crate::solve::newton::at_round_off;
use crate::step::{StepKind, is_affine, jacobian_is_constant};

use super::DynLagrangian;
use super::band::BandSystem;
use super::sparse::{SparseBlock, SparseHessian};

/// How the newest node of a step is found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Update {
    /// Newton's method at every step.
    Newton,
    /// Affine in `y`, `h J = I` at every step: `y = b − h (G(b) − π)`, no solve.
    Identity,
    /// Affine, `h J` the same at every step: factorised once.
    Constant,
    /// Affine, `h J` read at `b`: one factorisation per step.
    PerStep,
    /// A variational step with `h J = I` (`L_vv = I`, `L_xv = 0`) of an autonomous model, where
    /// both sides' steps reduce to Störmer–Verlet, `y = 2b − a + h² f(b)`: `p = v + c` with a
    /// constant `c`, which cancels between `π` and `G`, and `f` does not depend on `v`.
    Verlet,
}

/// The step solver of one run: the model, the scheme's kind, the step size, the Newton
/// options, and the buffers.
pub(crate) struct StepSolver<'l, L: ?Sized> {
    lagrangian: &'l L,
    kind: StepKind,
    h: f64,
    inv_h: f64,
    newton: NewtonOptions,
    update: Update,
    /// Whether the factors of a constant `h J` are in `system`.
    factored: bool,
    system: BandSystem,
    hessian: SparseHessian,
    /// Velocity, force, momentum and residual buffers (length `d`), and a zero velocity.
    v: Vec<f64>,
    zero: Vec<f64>,
    f: Vec<f64>,
    p: Vec<f64>,
    r: Vec<f64>,
}

/// Whether the momentum and the step equation are read `@right` (σ = −).
fn at_right(kind: StepKind) -> bool {
    matches!(
        kind,
        StepKind::VariationalBackward | StepKind::DirectBackward
    )
}

/// Where the step evaluates on the interval `[u, w]` (times `t_u`, `t_w`), with the velocity
/// `(w − u)/h`: at `(w, t_w)` `@right` (σ = −), at `(u, t_u)` `@left` (σ = +). The momentum
/// reads it on `[a, b]`, the step equation on `[b, y]`.
fn point<'a>(
    kind: StepKind,
    (u, w): (&'a [f64], &'a [f64]),
    (t_u, t_w): (f64, f64),
) -> (&'a [f64], f64) {
    if at_right(kind) { (w, t_w) } else { (u, t_u) }
}

/// Whether the momentum is `p + h f` (otherwise `p`); the equation is then `p` (otherwise
/// `p − h f`).
fn momentum_has_force(kind: StepKind) -> bool {
    matches!(
        kind,
        StepKind::VariationalBackward | StepKind::DirectForward
    )
}

impl<'l, L: DynLagrangian + ?Sized> StepSolver<'l, L> {
    /// The solver of `kind` (a Gauss-FDEσ kind) with step `h`, its linear system planned on
    /// the pattern of the Hessian at `(x, v, t)` (a point of the run's initial data).
    pub(crate) fn new(
        lagrangian: &'l L,
        kind: StepKind,
        h: f64,
        newton: NewtonOptions,
        (x, v, t): (&[f64], &[f64], f64),
    ) -> Self {
        let d = lagrangian.dimension();
        let mut hessian = SparseHessian::new(d);
        lagrangian.hessian(x, v, t, &mut hessian);
        let system = BandSystem::plan(
            d,
            lagrangian.hessian_bandwidth(),
            &jacobian_blocks(kind, &hessian),
        );
        let dependence = lagrangian.hessian_dependence();
        let update = if !is_affine(kind, &dependence) {
            Update::Newton
        } else if jacobian_is_constant(kind, &dependence) {
            if scaled_jacobian_is_identity(kind, h, &hessian) {
                let variational = matches!(
                    kind,
                    StepKind::VariationalBackward | StepKind::VariationalForward
                );
                if variational && !lagrangian.dependence().t {
                    Update::Verlet
                } else {
                    Update::Identity
                }
            } else {
                Update::Constant
            }
        } else {
            Update::PerStep
        };
        // In the model's own order, the blocks are summed in place in band storage and the
        // Jacobian is combined row by row; a reordered system reads the listed entries.
        drop(hessian);
        let blocks = if system.is_reordered() || matches!(update, Update::Identity | Update::Verlet)
        {
            // Listed entries, or none at all: these updates never read the blocks.
            SparseHessian::new(d)
        } else {
            SparseHessian::with_band(d, system.band())
        };
        StepSolver {
            lagrangian,
            kind,
            h,
            inv_h: 1.0 / h,
            newton,
            update,
            factored: false,
            system,
            hessian: blocks,
            v: vec![0.0; d],
            zero: vec![0.0; d],
            f: vec![0.0; d],
            p: vec![0.0; d],
            r: vec![0.0; d],
        }
    }

    /// The half-bandwidth the step Jacobians are factorised with, and whether the unknowns
    /// were reordered to reach it.
    pub(crate) fn band(&self) -> (usize, bool) {
        (self.system.band(), self.system.is_reordered())
    }

    /// Whether the steps are Störmer–Verlet steps ([`verlet`](Self::verlet)), which need no
    /// momentum and no guess.
    pub(crate) fn is_verlet(&self) -> bool {
        self.update == Update::Verlet
    }

    /// The Störmer–Verlet step `y = 2b − a + h² f(b)` of step `n` (`b` at `t_b`): one force
    /// evaluation and one pass, as the hand-written loop takes.
    #[inline]
    pub(crate) fn verlet(
        &mut self,
        (a, b): (&[f64], &[f64]),
        t_b: f64,
        y: &mut [f64],
        n: usize,
    ) -> Result<()> {
        self.lagrangian.force(b, &self.zero, t_b, &mut self.f);
        let h2 = self.h * self.h;
        // A double is not finite when its exponent bits are all set: an integer test, whose
        // results are or-ed without a chain of dependent floating-point operations.
        const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
        let mut not_finite = false;
        for (((y, a), b), f) in y.iter_mut().zip(a).zip(b).zip(&self.f) {
            *y = 2.0 * b - a + h2 * f;
            not_finite |= y.to_bits() & EXPONENT == EXPONENT;
        }
        if !not_finite {
            Ok(())
        } else {
            Err(Error::NotFinite {
                at: Location::Step(n),
            })
        }
    }

    /// Writes the momentum `π` of the step from `a`, `b` (times `t_a`, `t_b`) into `pi`, and
    /// when `sample`, returns `v·p` and `‖p‖∞` with `p = ∂L/∂v` at the momentum's point (the
    /// energy `v·p − L` and its round-off scale, for the blow-up guard).
    #[inline]
    pub(crate) fn momentum(
        &mut self,
        (a, b): (&[f64], &[f64]),
        (t_a, t_b): (f64, f64),
        pi: &mut [f64],
        sample: bool,
    ) -> Option<(f64, f64)> {
        let inv_h = self.inv_h;
        for ((v, a), b) in self.v.iter_mut().zip(a).zip(b) {
            *v = (b - a) * inv_h;
        }
        let (x, t) = point(self.kind, (a, b), (t_a, t_b));
        self.lagrangian.momentum(x, &self.v, t, pi);
        let terms = sample.then(|| {
            let vp = dot(&self.v, pi);
            (vp, max_norm(pi))
        });
        if momentum_has_force(self.kind) {
            self.lagrangian.force(x, &self.v, t, &mut self.f);
            let h = self.h;
            for (pi, f) in pi.iter_mut().zip(&self.f) {
                *pi += h * f;
            }
        }
        terms
    }

    /// `L` at the momentum's point of the step from `a`, `b`, right after
    /// [`momentum`](Self::momentum) of the same step (whose velocity it reads): with its `v·p`,
    /// the energy the blow-up guard samples.
    pub(crate) fn lagrangian_at_momentum_point(
        &self,
        nodes: (&[f64], &[f64]),
        times: (f64, f64),
    ) -> f64 {
        let (x, t) = point(self.kind, nodes, times);
        self.lagrangian.value(x, &self.v, t)
    }

    /// Solves `G(y) = π` for the newest node of step `n` from `a = Q_{n−2}`, `b = Q_{n−1}`
    /// (times `t_b`, `t_y` of `b` and `y`) into `y`. Returns the Newton iterations (0 for a
    /// closed-form step).
    ///
    /// As in the const-generic path, a closed form that fails (its Jacobian singular or not
    /// finite, or its node not finite) hands the step to Newton's method, from the linear
    /// extrapolation `2b − a` like every implicit step, which reports the failure if it is one.
    pub(crate) fn solve(
        &mut self,
        (a, b): (&[f64], &[f64]),
        pi: &[f64],
        times: (f64, f64),
        y: &mut [f64],
        n: usize,
    ) -> Result<usize> {
        if !pi.iter().all(|c| c.is_finite()) {
            return Err(Error::NotFinite {
                at: Location::Step(n),
            });
        }
        if self.update != Update::Newton && self.closed_form(b, pi, times, y, n) {
            return Ok(0);
        }
        for ((y, a), b) in y.iter_mut().zip(a).zip(b) {
            *y = 2.0 * b - a;
        }
        self.newton(b, pi, times, y, n)
    }

    /// The closed-form node `y = b − h (h J)⁻¹ (G(b) − π)` of an affine step; `false` when its
    /// Jacobian is singular or not finite or the node is not finite.
    fn closed_form(
        &mut self,
        b: &[f64],
        pi: &[f64],
        times: (f64, f64),
        y: &mut [f64],
        n: usize,
    ) -> bool {
        y.copy_from_slice(b);
        self.residual(b, pi, times, y);
        match self.update {
            // A Verlet solver's start (the one step it takes through `solve`) is `h J = I`.
            Update::Identity | Update::Verlet => {}
            Update::Constant if self.factored => self.system.solve_in_place(&mut self.r),
            _ => {
                self.read_blocks(b, times, y);
                if self.assemble(Location::Step(n)).is_err() || !self.system.factorize() {
                    return false;
                }
                self.factored = true;
                self.system.solve_in_place(&mut self.r);
            }
        }
        for (y, z) in y.iter_mut().zip(&self.r) {
            *y -= self.h * z;
        }
        y.iter().all(|c| c.is_finite())
    }

    /// Newton's method on step `n` (the stopping rule and the errors of the const-generic
    /// path's `newton_step`).
    fn newton(
        &mut self,
        b: &[f64],
        pi: &[f64],
        times: (f64, f64),
        y: &mut [f64],
        n: usize,
    ) -> Result<usize> {
        let at = Location::Step(n);
        let momentum_size = max_norm(pi);
        let mut residual = f64::INFINITY;
        let options = self.newton;
        let diverged = |iterations, residual| Error::NewtonDidNotConverge {
            at,
            iterations,
            residual,
        };
        for iteration in 0..=options.max_iterations {
            self.residual(b, pi, times, y);
            let previous = residual;
            // NaN when an entry is: one pass both measures and checks.
            residual = max_norm(&self.r);
            // The scale of the equation: the terms it balances, `π` and those of `G(y)` (as
            // the const-generic path; no absolute part, so `c L` stops where `L` does).
            let scale = momentum_size.max(self.terms());
            if residual.is_finite() && iteration > 0 && residual <= options.tolerance * scale {
                // Converged after a step from an iterate whose Jacobian was factorised (and
                // regular): the converged iterate is `O(|δ|)` from it, so its Jacobian is not
                // formed again. This skips a third of the Hessian evaluations, assemblies and
                // factorisations of a step that converges in two iterations.
                return Ok(iteration);
            }
            if residual.is_finite() {
                self.read_blocks(b, times, y);
            }
            let assembled = residual.is_finite() && self.assemble(at).is_ok();
            // The solve for the next iterate comes with the factorisation; it is wasted only
            // on an iteration that turns out to be at round-off.
            let (norms, regular) = if assembled {
                self.system.factorize_solving(&mut self.r)
            } else {
                (BandNorms::NOT_FINITE, false)
            };
            if !norms.is_finite() {
                return Err(if iteration == 0 {
                    Error::NotFinite { at }
                } else {
                    diverged(iteration, previous)
                });
            }
            let j_norm = norms.inf * self.inv_h;
            let converged = residual <= options.tolerance * scale
                || at_round_off(residual, previous, j_norm, max_norm(y));
            if !regular {
                return Err(if iteration == 0 || converged {
                    Error::SingularJacobian { at }
                } else {
                    diverged(iteration, residual)
                });
            }
            if converged {
                return Ok(iteration);
            }
            if iteration == options.max_iterations {
                break;
            }
            for (y, z) in y.iter_mut().zip(&self.r) {
                *y -= self.h * z;
            }
            if !y.iter().all(|c| c.is_finite()) {
                return Err(diverged(iteration + 1, residual));
            }
        }
        Err(diverged(options.max_iterations, residual))
    }

    /// The residual `G(y) − π` into `self.r` (and the velocity `(y − b)/h` into `self.v`).
    #[inline]
    fn residual(&mut self, b: &[f64], pi: &[f64], (t_b, t_y): (f64, f64), y: &[f64]) {
        let inv_h = self.inv_h;
        for ((v, y), b) in self.v.iter_mut().zip(y).zip(b) {
            *v = (y - b) * inv_h;
        }
        let (x, t) = point(self.kind, (b, y), (t_b, t_y));
        let l = self.lagrangian;
        l.momentum(x, &self.v, t, &mut self.p);
        if momentum_has_force(self.kind) {
            for ((r, p), pi) in self.r.iter_mut().zip(&self.p).zip(pi) {
                *r = p - pi;
            }
        } else {
            l.force(x, &self.v, t, &mut self.f);
            let h = self.h;
            for (((r, p), f), pi) in self.r.iter_mut().zip(&self.p).zip(&self.f).zip(pi) {
                *r = p - h * f - pi;
            }
        }
    }

    /// The size of the terms of `G(y)` after [`residual`](Self::residual): `‖p‖∞`, and
    /// `h ‖f‖∞` when `G` has the force.
    fn terms(&self) -> f64 {
        let p = max_norm(&self.p);
        if momentum_has_force(self.kind) {
            p
        } else {
            p.max(self.h * max_norm(&self.f))
        }
    }

    /// The blocks at the equation's point into `self.hessian`, after
    /// [`residual`](Self::residual) at the same `y` (whose velocity they read).
    fn read_blocks(&mut self, b: &[f64], (t_b, t_y): (f64, f64), y: &[f64]) {
        let (x, t) = point(self.kind, (b, y), (t_b, t_y));
        self.hessian.clear();
        self.lagrangian.hessian(x, &self.v, t, &mut self.hessian);
    }

    /// `h J` from the blocks in `self.hessian` into the band system (second table of the step
    /// module, times `h`); an entry outside the band re-plans the system on this pattern.
    fn assemble(&mut self, at: Location) -> Result<()> {
        if self.try_assemble().is_err() {
            // An entry outside the planned band: plan again on the full pattern, and list the
            // entries from now on.
            let d = self.lagrangian.dimension();
            self.hessian = self.hessian.to_listed();
            self.system = BandSystem::plan(d, None, &jacobian_blocks(self.kind, &self.hessian));
            self.try_assemble()
                .map_err(|_| Error::SingularJacobian { at })?;
        }
        Ok(())
    }

    fn try_assemble(&mut self) -> std::result::Result<(), super::band::OutsideBand> {
        let h = self.h;
        let (xv_t, xv_plain, xx_scale) = match self.kind {
            StepKind::VariationalBackward => (h, 0.0, 0.0),
            StepKind::VariationalForward => (0.0, -h, 0.0),
            StepKind::DirectBackward => (h, -h, -h * h),
            _ => (0.0, 0.0, 0.0),
        };
        let SparseHessian { xx, xv, vv } = &self.hessian;
        let system = &mut self.system;
        if vv.band().is_some() || xx.band().is_some() || xv.band().is_some() {
            return system.set_from_bands([(1.0, vv), (xx_scale, xx), (xv_plain, xv)], (xv_t, xv));
        }
        system.clear();
        for &(i, j, value) in vv.entries() {
            system.add(i, j, value)?;
        }
        for &(i, j, value) in xv.entries() {
            if xv_t != 0.0 {
                system.add(j, i, xv_t * value)?;
            }
            if xv_plain != 0.0 {
                system.add(i, j, xv_plain * value)?;
            }
        }
        if xx_scale != 0.0 {
            for &(i, j, value) in xx.entries() {
                system.add(i, j, xx_scale * value)?;
            }
        }
        Ok(())
    }
}

/// The blocks that enter the Jacobian of `kind` (second table of the step module): `vv`
/// always, `xv` (and its transpose) except for the direct σ = + step, `xx` for the direct σ = −
/// step only. The system is planned on their pattern alone: a long-range `L_xx` does not widen
/// the band of a step whose Jacobian does not read it.
fn jacobian_blocks(kind: StepKind, hessian: &SparseHessian) -> Vec<&SparseBlock> {
    let mut blocks = vec![&hessian.vv];
    if kind != StepKind::DirectForward {
        blocks.push(&hessian.xv);
    }
    if kind == StepKind::DirectBackward {
        blocks.push(&hessian.xx);
    }
    blocks
}

/// Whether `h J` is exactly the identity for the constant blocks in `hessian`: `L_vv = I` and
/// no block of `J` other than `vv` has a nonzero entry. The closed form is then `y = b −
/// h (G(b) − π)`, with no rounding beyond the hand-written Störmer–Verlet loop's.
fn scaled_jacobian_is_identity(kind: StepKind, h: f64, hessian: &SparseHessian) -> bool {
    let d = hessian.vv.dimension();
    let mut diagonal = vec![0.0; d];
    let mut off_diagonal = false;
    for &(i, j, value) in hessian.vv.entries() {
        if i == j {
            diagonal[i] += value;
        } else {
            off_diagonal |= value != 0.0;
        }
    }
    let others_zero =
        |block: &super::sparse::SparseBlock| block.entries().iter().all(|e| e.2 == 0.0);
    let xv_enters = !matches!(kind, StepKind::DirectForward);
    let xx_enters = matches!(kind, StepKind::DirectBackward);
    h.is_finite()
        && !off_diagonal
        && diagonal.iter().all(|&c| c == 1.0)
        && (!xv_enters || others_zero(&hessian.xv))
        && (!xx_enters || others_zero(&hessian.xx))
}

/// Max-norm of a slice; NaN when an entry is NaN.
///
/// Four running maxima over interleaved entries, so that each comparison waits on the one
/// four entries back rather than on the last (a single running maximum is a chain of
/// dependent comparisons, the slowest pass of a Newton iteration on a chain).
pub(crate) fn max_norm(x: &[f64]) -> f64 {
    let mut lanes = [0.0f64; 4];
    let mut nan = false;
    let mut chunks = x.chunks_exact(4);
    for chunk in &mut chunks {
        for (m, c) in lanes.iter_mut().zip(chunk) {
            let a = c.abs();
            *m = if a > *m { a } else { *m };
            nan |= a.is_nan();
        }
    }
    for (m, c) in lanes.iter_mut().zip(chunks.remainder()) {
        let a = c.abs();
        *m = if a > *m { a } else { *m };
        nan |= a.is_nan();
    }
    if nan {
        f64::NAN
    } else {
        lanes.into_iter().fold(0.0, f64::max)
    }
}

/// `Σ a_i b_i` over four running sums of interleaved terms (a single running sum is a chain
/// of dependent additions, as slow as a whole explicit step at large `d`); the guard's `v·p`,
/// where the order of the additions only moves the last bits.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut lanes = [0.0f64; 4];
    let (mut x, mut y) = (a.chunks_exact(4), b.chunks_exact(4));
    for (x, y) in (&mut x).zip(&mut y) {
        for ((s, x), y) in lanes.iter_mut().zip(x).zip(y) {
            *s += x * y;
        }
    }
    let tail: f64 = x
        .remainder()
        .iter()
        .zip(y.remainder())
        .map(|(x, y)| x * y)
        .sum();
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail
}

#[cfg(test)]
mod tests {
    use super::{dot, max_norm};

    #[test]
    fn dot_is_the_sum_of_products() {
        for n in 0..11 {
            let a: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 1.3).cos()).collect();
            let expected: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            assert!(
                (dot(&a, &b) - expected).abs() <= 1e-15 * n as f64,
                "n = {n}"
            );
        }
    }

    #[test]
    fn max_norm_is_the_largest_magnitude_and_nan_anywhere_shows() {
        for n in 0..11 {
            let x: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64 - 5.3) * 1.7).collect();
            let expected = x.iter().fold(0.0f64, |m, c| m.max(c.abs()));
            assert_eq!(max_norm(&x), expected, "n = {n}");
            for k in 0..n {
                let mut with_nan = x.clone();
                with_nan[k] = f64::NAN;
                assert!(max_norm(&with_nan).is_nan(), "NaN at {k} of {n}");
            }
        }
        assert_eq!(max_norm(&[1.0, f64::NEG_INFINITY]), f64::INFINITY);
    }
}
