//! One step of the classical schemes for a run-time-dimension model: the momentum `π` from
//! the two previous nodes, then the step equation `G(y) = π` for the newest node, by a closed
//! form where the step is affine in `y` and by sparse Newton otherwise.
//!
//! What each step kind evaluates, and with which weights, is the step module's table of terms
//! (the const-generic steps read the same table, so the two paths take the same steps); this
//! module evaluates the terms on slices and assembles the Jacobian `h J` from the model's
//! sparse blocks, term by term, into a [`BandSystem`]. Every buffer is allocated once per run.

use crate::error::{Error, Location, Result};
use crate::options::NewtonOptions;
use crate::solve::newton::{StepIteration, newton};
use crate::step::terms::{Point, Terms, equation_terms, momentum_terms};
use crate::step::{StepKind, is_affine, jacobian_is_constant, reads_force, with_force};

use super::DynLagrangian;
use super::band::{BandSystem, OutsideBand};
use super::slices::{accumulate, axpy, dot, max_norm};
use super::sparse::{SparseBlock, SparseForceJacobian, SparseHessian};

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

/// The energy terms a step's momentum evaluation samples for the blow-up guard: the energy
/// `Σ w_p (v·p − L)` over the momentum's terms, its `Σ w_p v·p`, and the largest `‖p‖∞`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct EnergySample {
    pub(crate) energy: f64,
    pub(crate) vp: f64,
    pub(crate) p_max: f64,
}

/// The positions and velocities at which the terms of one interval `[u, w]` evaluate.
struct Points {
    /// The midpoint `(u + w)/2` (empty when no term reads it).
    middle: Vec<f64>,
    /// `(w − u)/h`.
    velocity: Vec<f64>,
    /// `(w − a)/(2h)`, `a` the node before `u` (empty when no term reads it).
    centred: Vec<f64>,
}

impl Points {
    /// Buffers of length `d` for what the terms of `tables` read.
    fn new(d: usize, tables: &[Terms]) -> Self {
        let reads = |point| {
            tables
                .iter()
                .any(|terms| terms.as_slice().iter().any(|t| t.point == point))
        };
        let buffer = |point| vec![0.0; if reads(point) { d } else { 0 }];
        Points {
            middle: buffer(Point::Middle),
            velocity: vec![0.0; d],
            centred: buffer(Point::Centred),
        }
    }

    /// The velocity of `[u, w]` (and, when `centred`, that of `w` against `before`) and the
    /// midpoint, where a term reads it.
    #[inline]
    fn on_interval(&mut self, (before, u, w): (&[f64], &[f64], &[f64]), inv_h: f64, centred: bool) {
        for ((v, u), w) in self.velocity.iter_mut().zip(u).zip(w) {
            *v = (w - u) * inv_h;
        }
        for ((m, u), w) in self.middle.iter_mut().zip(u).zip(w) {
            *m = 0.5 * (u + w);
        }
        if centred {
            let half = 0.5 * inv_h;
            for ((c, a), w) in self.centred.iter_mut().zip(before).zip(w) {
                *c = (w - a) * half;
            }
        }
    }

    /// `(x, v, t)` of `point` on `[u, w]` (times `t_u`, `t_w`), after
    /// [`on_interval`](Self::on_interval).
    #[inline]
    fn at<'a>(
        &'a self,
        point: Point,
        (u, w): (&'a [f64], &'a [f64]),
        (t_u, t_w): (f64, f64),
    ) -> (&'a [f64], &'a [f64], f64) {
        let t = point.time(t_u, t_w);
        match point {
            Point::Left => (u, &self.velocity, t),
            Point::Middle => (&self.middle, &self.velocity, t),
            Point::Right => (w, &self.velocity, t),
            Point::Centred => (u, &self.centred, t),
        }
    }
}

/// The step solver of one run: the model, the scheme's kind and its terms, the step size, the
/// Newton options, and the buffers.
pub(crate) struct StepSolver<'l, L: ?Sized> {
    lagrangian: &'l L,
    momentum_terms: Terms,
    equation_terms: Terms,
    /// Whether the equation has a term with the centred velocity (it then reads `a`).
    centred: bool,
    h: f64,
    inv_h: f64,
    newton: NewtonOptions,
    update: Update,
    /// Whether the factors of a constant `h J` are in `system`.
    factored: bool,
    system: BandSystem,
    hessian: SparseHessian,
    /// The Jacobian of a generalised force at a term's point, where the step equation reads
    /// the force (entries listed; unused without a force).
    force: SparseForceJacobian,
    /// Whether the step equation's Jacobian has a force's blocks.
    forced: bool,
    points: Points,
    /// A zero velocity, and force, momentum and residual buffers (length `d`).
    zero: Vec<f64>,
    f: Vec<f64>,
    p: Vec<f64>,
    r: Vec<f64>,
    /// The size of the terms `G(y)` summed at the last residual's `y`: the largest of
    /// `|w_p| ‖p‖∞` and `|w_f| h ‖f‖∞`.
    size: f64,
}

impl<'l, L: DynLagrangian + ?Sized> StepSolver<'l, L> {
    /// The solver of `kind` with step `h`, its linear system planned on the pattern of the
    /// Hessian at `(x, v, t)` (a point of the run's initial data).
    pub(crate) fn new(
        lagrangian: &'l L,
        kind: StepKind,
        h: f64,
        newton: NewtonOptions,
        (x, v, t): (&[f64], &[f64], f64),
    ) -> Self {
        let d = lagrangian.dimension();
        let (momentum, equation) = (momentum_terms(kind), equation_terms(kind));
        let mut hessian = SparseHessian::new(d);
        lagrangian.hessian(x, v, t, &mut hessian);
        let forced = lagrangian.is_forced() && reads_force(kind);
        let mut force = SparseForceJacobian::new(d);
        let mut blocks = jacobian_blocks(&equation, h, &hessian);
        if forced {
            lagrangian.force_jacobian(x, v, t, &mut force);
            blocks.extend(force_blocks(&equation, h, &force));
        }
        let system = BandSystem::plan(d, lagrangian.hessian_bandwidth(), &blocks);
        let dependence = with_force(
            lagrangian.hessian_dependence(),
            kind,
            lagrangian.is_forced(),
            lagrangian.force_dependence(),
        );
        let update = if !is_affine(kind, &dependence) {
            Update::Newton
        } else if jacobian_is_constant(kind, &dependence) {
            if !forced && scaled_jacobian_is_identity(&equation, h, &hessian) {
                let variational = matches!(
                    kind,
                    StepKind::VariationalBackward | StepKind::VariationalForward
                );
                // The Störmer–Verlet step fuses the momentum, reading `∂L/∂x` at rest: not
                // under a force, which may depend on the velocity.
                if variational && !lagrangian.dependence().t && !lagrangian.is_forced() {
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
        drop(blocks);
        drop(hessian);
        let blocks = if system.is_reordered() || matches!(update, Update::Identity | Update::Verlet)
        {
            // Listed entries, or none at all: these updates never read the blocks.
            SparseHessian::new(d)
        } else {
            SparseHessian::with_band(d, system.band())
        };
        let centred = equation
            .as_slice()
            .iter()
            .any(|term| term.point == Point::Centred);
        StepSolver {
            lagrangian,
            momentum_terms: momentum,
            equation_terms: equation,
            centred,
            h,
            inv_h: 1.0 / h,
            newton,
            update,
            factored: false,
            system,
            hessian: blocks,
            force,
            forced,
            points: Points::new(d, &[momentum, equation]),
            zero: vec![0.0; d],
            f: vec![0.0; d],
            p: vec![0.0; d],
            r: vec![0.0; d],
            size: 0.0,
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
    /// when `sample`, returns the energy terms at the momentum's points (for the blow-up
    /// guard).
    #[inline]
    pub(crate) fn momentum(
        &mut self,
        (a, b): (&[f64], &[f64]),
        times: (f64, f64),
        pi: &mut [f64],
        sample: bool,
    ) -> Option<EnergySample> {
        let l = self.lagrangian;
        self.points.on_interval((a, a, b), self.inv_h, false);
        let mut sampled = sample.then(EnergySample::default);
        for (k, term) in self.momentum_terms.as_slice().iter().enumerate() {
            let (x, v, t) = self.points.at(term.point, (a, b), times);
            // Every momentum term reads `p`; the first with weight 1 writes it in place.
            let in_place = k == 0 && term.p == 1.0;
            if in_place {
                l.momentum(x, v, t, pi);
            } else {
                l.momentum(x, v, t, &mut self.p);
                axpy(pi, term.p, &self.p, k == 0);
            }
            if let Some(s) = &mut sampled {
                let p: &[f64] = if in_place { pi } else { &self.p };
                let vp = dot(v, p);
                s.vp += term.p * vp;
                s.energy += term.p * (vp - l.value(x, v, t));
                s.p_max = s.p_max.max(max_norm(p));
            }
            if term.f != 0.0 {
                l.force(x, v, t, &mut self.f);
                axpy(pi, term.f * self.h, &self.f, false);
            }
        }
        sampled
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
        if self.update != Update::Newton && self.closed_form((a, b), pi, times, y, n) {
            return Ok(0);
        }
        for ((y, a), b) in y.iter_mut().zip(a).zip(b) {
            *y = 2.0 * b - a;
        }
        self.newton((a, b), pi, times, y, n)
    }

    /// The closed-form node `y = b − h (h J)⁻¹ (G(b) − π)` of an affine step; `false` when its
    /// Jacobian is singular or not finite or the node is not finite.
    fn closed_form(
        &mut self,
        (a, b): (&[f64], &[f64]),
        pi: &[f64],
        times: (f64, f64),
        y: &mut [f64],
        n: usize,
    ) -> bool {
        y.copy_from_slice(b);
        self.residual((a, b, y), pi, times);
        match self.update {
            // A Verlet solver's start (the one step it takes through `solve`) is `h J = I`.
            Update::Identity | Update::Verlet => {}
            Update::Constant if self.factored => self.system.solve_in_place(&mut self.r),
            _ => {
                if self.assemble((b, y), times, Location::Step(n)).is_err()
                    || !self.system.factorize()
                {
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

    /// Newton's method ([`newton`]) on step `n` from the iterate in `y`.
    fn newton(
        &mut self,
        nodes: (&[f64], &[f64]),
        pi: &[f64],
        times: (f64, f64),
        y: &mut [f64],
        n: usize,
    ) -> Result<usize> {
        let options = self.newton;
        let at = Location::Step(n);
        let mut iteration = SliceStep {
            momentum_size: max_norm(pi),
            solver: self,
            nodes,
            pi,
            times,
            y,
            at,
        };
        newton(&mut iteration, &options, at)
    }

    /// The residual `G(y) − π` into `self.r`, the size of its terms into `self.size`, and the
    /// points of `[b, y]` into `self.points` (read by [`assemble`](Self::assemble) at the
    /// same `y`); returns `‖G(y) − π‖∞` (NaN when an entry is), measured by the last term's
    /// pass.
    #[inline]
    fn residual(
        &mut self,
        (a, b, y): (&[f64], &[f64], &[f64]),
        pi: &[f64],
        times: (f64, f64),
    ) -> f64 {
        let l = self.lagrangian;
        self.points.on_interval((a, b, y), self.inv_h, self.centred);
        let mut first = Some(pi);
        let (mut size, mut residual) = (0.0f64, f64::NAN);
        for term in self.equation_terms.as_slice() {
            let (x, v, t) = self.points.at(term.point, (b, y), times);
            if term.p != 0.0 {
                l.momentum(x, v, t, &mut self.p);
                let (term_size, r_norm) = accumulate(&mut self.r, term.p, &self.p, first.take());
                (size, residual) = (size.max(term_size), r_norm);
            }
            if term.f != 0.0 {
                l.force(x, v, t, &mut self.f);
                let w = term.f * self.h;
                let (term_size, r_norm) = accumulate(&mut self.r, w, &self.f, first.take());
                (size, residual) = (size.max(term_size), r_norm);
            }
        }
        self.size = size;
        residual
    }

    /// `h J` at the points of the last [`residual`](Self::residual) into the band system, one
    /// term's blocks at a time (module docs); an entry outside the band re-plans the system
    /// on the pattern of every term's blocks, listed from then on.
    fn assemble(&mut self, nodes: (&[f64], &[f64]), times: (f64, f64), at: Location) -> Result<()> {
        if self.try_assemble(nodes, times).is_err() {
            let d = self.lagrangian.dimension();
            let listed: Vec<(SparseHessian, SparseForceJacobian)> = self
                .equation_terms
                .as_slice()
                .iter()
                .map(|term| {
                    let (x, v, t) = self.points.at(term.point, nodes, times);
                    let mut hessian = SparseHessian::new(d);
                    self.lagrangian.hessian(x, v, t, &mut hessian);
                    let mut force = SparseForceJacobian::new(d);
                    if self.forced {
                        self.lagrangian.force_jacobian(x, v, t, &mut force);
                    }
                    (hessian, force)
                })
                .collect();
            let (terms, h) = (&self.equation_terms, self.h);
            let blocks: Vec<&SparseBlock> = listed
                .iter()
                .flat_map(|(hessian, force)| {
                    let mut blocks = jacobian_blocks(terms, h, hessian);
                    blocks.extend(force_blocks(terms, h, force));
                    blocks
                })
                .collect();
            self.system = BandSystem::plan(d, None, &blocks);
            self.hessian = SparseHessian::new(d);
            self.try_assemble(nodes, times)
                .map_err(|_| Error::SingularJacobian { at })?;
        }
        Ok(())
    }

    fn try_assemble(
        &mut self,
        nodes: (&[f64], &[f64]),
        times: (f64, f64),
    ) -> std::result::Result<(), OutsideBand> {
        let terms = self.equation_terms;
        for (k, term) in terms.as_slice().iter().enumerate() {
            let (x, v, t) = self.points.at(term.point, nodes, times);
            self.hessian.clear();
            self.lagrangian.hessian(x, v, t, &mut self.hessian);
            let weights = term.block_weights(self.h);
            add_blocks(&mut self.system, &self.hessian, weights, k == 0)?;
            if self.forced && term.f != 0.0 {
                // The force joins `∂L/∂x`: its `∂f/∂x` where `L_xx` stands, its `∂f/∂v` where
                // `L_xv` does (never `L_vx`, which differentiates `p`).
                self.force.clear();
                self.lagrangian.force_jacobian(x, v, t, &mut self.force);
                for (weight, block) in [(weights.xx, &self.force.x), (weights.xv, &self.force.v)] {
                    if weight != 0.0 {
                        for &(i, j, value) in block.entries() {
                            self.system.add(i, j, weight * value)?;
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// A step of the run-time path at its current iterate `y`, as Newton's method sees it.
struct SliceStep<'s, 'l, 'n, L: ?Sized> {
    solver: &'s mut StepSolver<'l, L>,
    nodes: (&'n [f64], &'n [f64]),
    pi: &'n [f64],
    momentum_size: f64,
    times: (f64, f64),
    y: &'n mut [f64],
    at: Location,
}

impl<L: DynLagrangian + ?Sized> StepIteration for SliceStep<'_, '_, '_, L> {
    fn residual(&mut self) -> (f64, f64) {
        let (a, b) = self.nodes;
        // NaN when an entry is: the residual's own passes both measure and check.
        let residual = self.solver.residual((a, b, self.y), self.pi, self.times);
        (residual, self.momentum_size.max(self.solver.size))
    }

    fn solve(&mut self) -> (f64, bool) {
        let solver = &mut *self.solver;
        if solver
            .assemble((self.nodes.1, self.y), self.times, self.at)
            .is_err()
        {
            return (f64::NAN, false);
        }
        // The solve for the correction comes with the factorisation.
        let (norms, regular) = solver.system.factorize_solving(&mut solver.r);
        let j_norm = if norms.is_finite() {
            norms.inf * solver.inv_h
        } else {
            f64::NAN
        };
        (j_norm, regular)
    }

    fn size(&self) -> f64 {
        max_norm(self.y)
    }

    fn update(&mut self) -> bool {
        let h = self.solver.h;
        for (y, z) in self.y.iter_mut().zip(&self.solver.r) {
            *y -= h * z;
        }
        self.y.iter().all(|c| c.is_finite())
    }
}

mod blocks;

use blocks::{add_blocks, force_blocks, jacobian_blocks, scaled_jacobian_is_identity};
