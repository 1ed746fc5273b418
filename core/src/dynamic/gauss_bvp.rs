//! Boundary value problems of the variational Gauss–Legendre integrators: the stage equations
//! of every interval and the two ends' data as one global system (a collocation boundary value
//! problem), solved by Newton's method with the sparse LU of the other boundary value problems.
//!
//! # The system
//!
//! The one-step map of `solve::gauss` (whose module docs derive it) from `(q_k, p_k)` with stage
//! velocities `V^k_1..V^k_s`, `Q_i = q_k + h Σ_j a_ij V_j`, `Ṗ_i = ∂L/∂x`, `P_i = ∂L/∂v` at
//! `(Q_i, V_i, t_k + c_i h)`, is imposed on every interval `k = 0..N−1` at once, with
//! `q_0 = q(a)` and `q_N = q(b)` given:
//!
//! ```text
//! stages    P_i − p_k − h Σ_j a_ij Ṗ_j = 0                 i = 1..s   (s d rows)
//! position  w (q_k + h Σ_i b_i V_i − q_{k+1}) = 0                     (d rows)
//! momentum  p_{k+1} − p_k − h Σ_i b_i Ṗ_i = 0            k < N − 1    (d rows)
//! ```
//!
//! for the unknowns `p_k`, `V^k` (every interval) and `q_{k+1}` (interior nodes): `N (s + 2) d − d`
//! equations in as many unknowns, stored interval by interval (`p_k`, `V^k`, `q_{k+1}`; rows:
//! stages, position, momentum), each interval coupled to its neighbours through `q_k` and
//! `p_{k+1}` only. Its solution is the integrator's run from `(q(a), p_0)` that reaches `q(b)`:
//! the discrete Euler–Lagrange equations of `S_h = Σ_k L_d(q_k, q_{k+1})` with `L_d` the
//! Gauss–Legendre discrete Lagrangian, order `2s` at the nodes. The position rows are weighted
//! by `w = max |∂²L/∂v²| / h` at the guess's first node (the momentum a unit change of
//! position over one step makes), so that every row is in momentum units: the stopping rule (the residual within the tolerance
//! of `‖p‖∞ + ‖P‖∞ + h ‖Ṗ‖∞`) and the line search's merit then measure all rows alike. The
//! momentum unknowns are stored as `p_k / w`, in position units like the nodes (the stage
//! velocities are velocities, the same for `c L` as for `L`): `c L` then has `c` times the rows
//! and Jacobian of `L` at the same unknowns, and (`c` a power of two) the same pivots in the
//! sparse LU, which pivots across the unknowns, so it is solved as `L` is, bit for bit.
//!
//! A converged solution with the posedness check on carries `Warning::IllPosed` when the
//! variational midpoint rows linearised at its nodes measure a resonance: the same continuous
//! linearisation discretised to second order (this system's Jacobian mixes positions,
//! velocities and momenta and has no neighbour coupling of its own to measure against); it
//! costs one sparse LU of the node system.

use crate::embedding::{Embedding, Scheme};
use crate::error::{Error, Location, Result};
use crate::gauss_legendre::GaussTableau;
use crate::grid::Grid;
use crate::options::{LinearSolve, NewtonOptions};
use crate::side::Side;
use crate::solve::newton::{Converging, GlobalSystem, Iterate, solve_global};
use std::ops::ControlFlow;

use super::DynLagrangian;
use super::bvp::{check_input, check_nodes, isolated, jacobian_norm, lu_direction, posedness_at};
use super::problem::{DynProblem, DynSolution};
use super::rows::DynRows;
use super::slices::max_norm;
use super::sparse::{SparseForceJacobian, SparseHessian};
use super::sparse_lu::{Singular, SparseLu, SparseRows};

/// The unknowns of the global system, flat: what the line search moves.
#[derive(Clone)]
struct Unknowns(Vec<f64>);

impl Iterate for Unknowns {
    fn along(&self, delta: &[f64], lambda: f64) -> Self {
        Unknowns(
            self.0
                .iter()
                .zip(delta)
                .map(|(z, delta)| z - delta * lambda)
                .collect(),
        )
    }

    fn size(&self) -> f64 {
        max_norm(&self.0)
    }
}

/// The residual at an iterate, the scale of its momentum rows, and `p_N`.
struct Evaluation {
    r: Vec<f64>,
    /// `max ‖r‖∞`.
    max: f64,
    /// `‖p‖∞ + ‖P‖∞ + h ‖Ṗ‖∞` over every interval.
    scale: f64,
    /// The momentum at `b`, `p_{N−1} + h Σ_i b_i Ṗ_i` of the last interval.
    last_momentum: Vec<f64>,
}

/// The global system of one boundary value problem.
struct GaussSystem<'a, L: ?Sized> {
    lagrangian: &'a L,
    grid: Grid,
    tableau: GaussTableau,
    d: usize,
    qa: &'a [f64],
    qb: &'a [f64],
    /// The weight of the position rows (module docs).
    w: f64,
}

impl<L: DynLagrangian + ?Sized> GaussSystem<'_, L> {
    fn s(&self) -> usize {
        self.tableau.stages()
    }

    /// The first unknown (and row) of interval `k`.
    fn start(&self, k: usize) -> usize {
        k * (self.s() + 2) * self.d
    }

    /// The number of unknowns (and equations).
    fn order(&self) -> usize {
        self.start(self.grid.n()) - self.d
    }

    /// `q_k`: an end, or the unknown of interval `k − 1`.
    fn node<'z>(&'z self, z: &'z [f64], k: usize) -> &'z [f64] {
        let (n, d, s) = (self.grid.n(), self.d, self.s());
        match k {
            0 => self.qa,
            k if k == n => self.qb,
            k => &z[self.start(k - 1) + (s + 1) * d..][..d],
        }
    }

    /// `p_k / w` and the stage velocities `V^k` of interval `k` (module docs: the momenta are
    /// stored in position units).
    fn interval<'z>(&self, z: &'z [f64], k: usize) -> (&'z [f64], &'z [f64]) {
        let (d, s) = (self.d, self.s());
        let at = self.start(k);
        (&z[at..at + d], &z[at + d..at + (s + 1) * d])
    }

    /// The stage positions `Q_i = q_k + h Σ_j a_ij V_j` of interval `k` into `q` (`s d`).
    fn stage_positions(&self, z: &[f64], k: usize, q: &mut [f64]) {
        let (d, s, h) = (self.d, self.s(), self.grid.h());
        let qk = self.node(z, k);
        let (_, v) = self.interval(z, k);
        for i in 0..s {
            let qi = &mut q[i * d..(i + 1) * d];
            qi.copy_from_slice(qk);
            for j in 0..s {
                let a = h * self.tableau.a(i, j);
                for (x, v) in qi.iter_mut().zip(&v[j * d..(j + 1) * d]) {
                    *x += v * a;
                }
            }
        }
    }

    /// `Q_i`, `Ṗ_i`, `P_i` of interval `k` into `stages` (`(Q, Ṗ, P)`, `s d` each); whether
    /// they are finite.
    fn stages(&self, z: &[f64], k: usize, (q, f, p): (&mut [f64], &mut [f64], &mut [f64])) -> bool {
        let (d, h) = (self.d, self.grid.h());
        self.stage_positions(z, k, q);
        let (_, v) = self.interval(z, k);
        for i in 0..self.s() {
            let (qi, vi) = (&q[i * d..(i + 1) * d], &v[i * d..(i + 1) * d]);
            let t = self.grid.t(k) + self.tableau.c[i] * h;
            self.lagrangian.force(qi, vi, t, &mut f[i * d..(i + 1) * d]);
            self.lagrangian
                .momentum(qi, vi, t, &mut p[i * d..(i + 1) * d]);
        }
        f.iter().chain(p.iter()).all(|c| c.is_finite())
    }

    /// The rows at `z` (module docs); [`Error::NotFinite`] at `iteration` when any value is
    /// not finite.
    fn evaluate(&self, z: &[f64], iteration: usize) -> Result<Evaluation> {
        let (n, d, s, h) = (self.grid.n(), self.d, self.s(), self.grid.h());
        let not_finite = Error::NotFinite {
            at: Location::Newton(iteration),
        };
        if !z.iter().all(|c| c.is_finite()) {
            return Err(not_finite);
        }
        let mut r = vec![0.0; self.order()];
        let (mut q, mut f, mut p) = (vec![0.0; s * d], vec![0.0; s * d], vec![0.0; s * d]);
        let mut scale = 0.0f64;
        let mut last_momentum = vec![0.0; d];
        for k in 0..n {
            if !self.stages(z, k, (&mut q, &mut f, &mut p)) {
                return Err(not_finite);
            }
            let (pk, v) = self.interval(z, k);
            let pk: Vec<f64> = pk.iter().map(|p| p * self.w).collect();
            let (qk, next) = (self.node(z, k), self.node(z, k + 1));
            scale = scale.max(max_norm(&pk) + max_norm(&p) + h * max_norm(&f));
            let rows = &mut r[self.start(k)..];
            for i in 0..s {
                for c in 0..d {
                    let sum: f64 = (0..s).map(|j| self.tableau.a(i, j) * f[j * d + c]).sum();
                    rows[i * d + c] = p[i * d + c] - pk[c] - h * sum;
                }
            }
            for c in 0..d {
                let moved: f64 = (0..s).map(|i| self.tableau.b[i] * v[i * d + c]).sum();
                rows[s * d + c] = self.w * (qk[c] + h * moved - next[c]);
                let impulse: f64 = (0..s).map(|i| self.tableau.b[i] * f[i * d + c]).sum();
                if k + 1 < n {
                    let (next_p, _) = self.interval(z, k + 1);
                    rows[(s + 1) * d + c] = next_p[c] * self.w - pk[c] - h * impulse;
                } else {
                    last_momentum[c] = pk[c] + h * impulse;
                }
            }
        }
        if !r.iter().all(|c| c.is_finite()) {
            return Err(not_finite);
        }
        let max = max_norm(&r);
        Ok(Evaluation {
            r,
            max,
            scale,
            last_momentum,
        })
    }

    /// Every Jacobian entry at `z`, `add(row, col, value)` (an entry may come in parts), the
    /// Hessians of one interval's stages at a time.
    fn jacobian(&self, z: &[f64], mut add: impl FnMut(usize, usize, f64)) {
        let (n, d, s, h) = (self.grid.n(), self.d, self.s(), self.grid.h());
        let (a, b) = (|i, j| self.tableau.a(i, j), &self.tableau.b);
        let mut q = vec![0.0; s * d];
        let mut hessians: Vec<SparseHessian> = (0..s).map(|_| SparseHessian::new(d)).collect();
        let forced = self.lagrangian.is_forced();
        let mut forces: Vec<SparseForceJacobian> =
            (0..s).map(|_| SparseForceJacobian::new(d)).collect();
        for k in 0..n {
            // The Jacobian reads the Hessians at the stages, not the forces and momenta.
            self.stage_positions(z, k, &mut q);
            let (_, v) = self.interval(z, k);
            for i in 0..s {
                let (qi, vi) = (&q[i * d..(i + 1) * d], &v[i * d..(i + 1) * d]);
                let t = self.grid.t(k) + self.tableau.c[i] * h;
                hessians[i].clear();
                self.lagrangian.hessian(qi, vi, t, &mut hessians[i]);
                forces[i].clear();
                if forced {
                    self.lagrangian.force_jacobian(qi, vi, t, &mut forces[i]);
                }
            }
            // ∂Ṗ/∂x and ∂Ṗ/∂v at stage j: L_xx, L_xv and a force's blocks.
            let dx = |j: usize| hessians[j].xx.entries().iter().chain(forces[j].x.entries());
            let dv = |j: usize| hessians[j].xv.entries().iter().chain(forces[j].v.entries());
            let at = self.start(k);
            let (row_stage, row_position, row_momentum) = (at, at + s * d, at + (s + 1) * d);
            let (col_p, col_v, col_next) = (at, at + d, at + (s + 1) * d);
            // q_k's columns: the previous interval's last unknowns (none at k = 0).
            let col_q = (k > 0).then(|| self.start(k - 1) + (s + 1) * d);
            for i in 0..s {
                let row = row_stage + i * d;
                for &(r, c, value) in hessians[i].vv.entries() {
                    add(row + r, col_v + i * d + c, value);
                }
                // L_vx(i)(r, c) = L_xv(i)(c, r): into V_m with h a_im, into q_k with 1.
                for &(c, r, value) in hessians[i].xv.entries() {
                    for m in 0..s {
                        add(row + r, col_v + m * d + c, h * a(i, m) * value);
                    }
                    if let Some(col_q) = col_q {
                        add(row + r, col_q + c, value);
                    }
                }
                for j in 0..s {
                    for &(r, c, value) in dv(j) {
                        add(row + r, col_v + j * d + c, -h * a(i, j) * value);
                    }
                    for &(r, c, value) in dx(j) {
                        for m in 0..s {
                            let weight = h * h * a(i, j) * a(j, m);
                            add(row + r, col_v + m * d + c, -weight * value);
                        }
                        if let Some(col_q) = col_q {
                            add(row + r, col_q + c, -h * a(i, j) * value);
                        }
                    }
                }
                for c in 0..d {
                    add(row + c, col_p + c, -self.w);
                }
            }
            for c in 0..d {
                if let Some(col_q) = col_q {
                    add(row_position + c, col_q + c, self.w);
                }
                for (i, b) in b.iter().enumerate() {
                    add(row_position + c, col_v + i * d + c, self.w * h * b);
                }
                if k + 1 < n {
                    add(row_position + c, col_next + c, -self.w);
                    add(row_momentum + c, col_p + c, -self.w);
                    add(row_momentum + c, self.start(k + 1) + c, self.w);
                }
            }
            if k + 1 < n {
                for (j, b) in b.iter().enumerate() {
                    for &(r, c, value) in dv(j) {
                        add(row_momentum + r, col_v + j * d + c, -h * b * value);
                    }
                    for &(r, c, value) in dx(j) {
                        for m in 0..s {
                            let weight = h * h * b * a(j, m);
                            add(row_momentum + r, col_v + m * d + c, -weight * value);
                        }
                        if let Some(col_q) = col_q {
                            add(row_momentum + r, col_q + c, -h * b * value);
                        }
                    }
                }
            }
        }
    }

    /// The Jacobian at `z` in the planned pattern, planned (with its symbolic factorisation)
    /// when there is none or an entry falls outside it.
    fn assemble<'s>(
        &self,
        z: &[f64],
        system: &'s mut Option<(SparseRows, SparseLu)>,
    ) -> std::result::Result<&'s mut (SparseRows, SparseLu), Singular> {
        let fill = |matrix: &mut SparseRows| {
            matrix.clear();
            let mut fits = true;
            self.jacobian(z, |r, c, v| fits &= matrix.add(r, c, v).is_ok());
            fits
        };
        if let Some((matrix, _)) = system.as_mut()
            && !fill(matrix)
        {
            *system = None;
        }
        if system.is_none() {
            let order = self.order();
            let mut rows: Vec<Vec<(usize, usize)>> = vec![Vec::new(); order];
            self.jacobian(z, |r, c, _| rows[r].push((r, c)));
            let mut matrix = SparseRows::with_order(order);
            for (r, entries) in rows.iter_mut().enumerate() {
                matrix.push_rows(r, 1, entries);
            }
            let lu = SparseLu::plan(&matrix)?;
            let fitted = fill(&mut matrix);
            debug_assert!(fitted, "the pattern was read off the same entries");
            *system = Some((matrix, lu));
        }
        Ok(system.as_mut().expect("planned above"))
    }
}

impl DynProblem<'_, dyn DynLagrangian + '_> {
    /// The boundary value problem of the Gauss–Legendre integrator with `stages` stages from
    /// the nodes `guess` (flat, `N + 1` nodes; the first and last are the ends): the global
    /// system of the module docs.
    pub(crate) fn solve_gauss_bvp(
        &self,
        stages: usize,
        scheme: Scheme,
        guess: &[f64],
    ) -> Result<DynSolution> {
        if scheme == Scheme::Direct {
            return Err(Error::Unsupported {
                operation: "the direct scheme (a Gauss–Legendre integrator is variational only)",
                embedding: self.embedding.to_string(),
            });
        }
        let (l, grid) = (self.lagrangian, self.grid);
        // The guess is checked as a curve of Gauss-FDE−'s rows: every node in the domain and
        // `∂²L/∂v²` not degenerate there, with the backward difference as the velocity.
        let nodes = DynRows::new(
            l,
            grid,
            Embedding::finite_difference(Side::Backward),
            scheme,
        )?;
        check_input(&nodes, guess)?;
        let (n, d, h) = (grid.n(), l.dimension(), grid.h());
        let (qa, qb) = (&guess[..d], &guess[n * d..]);
        let mut system = GaussSystem {
            lagrangian: l,
            grid,
            tableau: GaussTableau::new(stages),
            d,
            qa,
            qb,
            w: 1.0,
        };
        // The initial unknowns: each interval's difference quotient as every stage velocity,
        // and the momentum there.
        let mut z = vec![0.0; system.order()];
        let mut velocity = vec![0.0; d];
        for k in 0..n {
            let (qk, next) = (&guess[k * d..(k + 1) * d], &guess[(k + 1) * d..(k + 2) * d]);
            for ((v, a), b) in velocity.iter_mut().zip(qk).zip(next) {
                *v = (b - a) / h;
            }
            if k == 0 {
                system.w = position_weight(l, (qk, &velocity, grid.t(0)), h);
            }
            let at = system.start(k);
            l.momentum(qk, &velocity, grid.t(k), &mut z[at..at + d]);
            z[at..at + d].iter_mut().for_each(|p| *p /= system.w);
            for i in 0..stages {
                z[at + (i + 1) * d..at + (i + 2) * d].copy_from_slice(&velocity);
            }
            if k + 1 < n {
                z[at + (stages + 1) * d..at + (stages + 2) * d].copy_from_slice(next);
            }
        }
        let (z, iterations, last_momentum) = newton(&system, &self.newton, z)?;
        let mut q = Vec::with_capacity((n + 1) * d);
        let mut p = Vec::with_capacity((n + 1) * d);
        for k in 0..n {
            q.extend_from_slice(system.node(&z, k));
            p.extend(system.interval(&z, k).0.iter().map(|p| p * system.w));
        }
        q.extend_from_slice(qb);
        p.extend_from_slice(&last_momentum);
        check_nodes(&nodes, &q, false)?;
        // The resonance measure of the node-based problems, from the variational midpoint
        // rows linearised at these nodes: the same continuous linearisation, discretised to
        // second order (the collocation system's own Jacobian mixes positions, velocities and
        // momenta, and has no neighbour coupling to measure against).
        let measure = self
            .posedness_check
            .then(|| {
                let midpoint = DynRows::new(l, grid, Embedding::midpoint(), scheme).ok()?;
                posedness_at(&midpoint, &q)
            })
            .flatten();
        let solve = (iterations, 0, LinearSolve::SparseLu);
        Ok(self.bvp_solution(scheme, (q, p), solve, measure))
    }
}

/// The weight `w` of the position rows: `max |∂²L/∂v²| / h` at the first node of the guess
/// (with its difference quotient), the momentum a position change of one unit over a step
/// makes; 1 where that is zero (a degenerate `∂²L/∂v²`, which the input checks report).
fn position_weight<L: DynLagrangian + ?Sized>(
    l: &L,
    (x, v, t): (&[f64], &[f64], f64),
    h: f64,
) -> f64 {
    let mut hessian = SparseHessian::new(x.len());
    l.hessian(x, v, t, &mut hessian);
    let largest = hessian
        .vv
        .entries()
        .iter()
        .fold(0.0f64, |m, e| m.max(e.2.abs()));
    if largest > 0.0 && (largest / h).is_finite() {
        largest / h
    } else {
        1.0
    }
}

/// Newton's method ([`solve_global`]) on the global system from `z`, as the other boundary
/// value problems run it: the solution, the iterations and `p_N`.
fn newton<L: DynLagrangian + ?Sized>(
    system: &GaussSystem<'_, L>,
    options: &NewtonOptions,
    z: Vec<f64>,
) -> Result<(Vec<f64>, usize, Vec<f64>)> {
    let unknowns = system.order();
    let mut by_lu = ByLu {
        system,
        factors: None,
        j_norm: 0.0,
    };
    solve_global(&mut by_lu, Unknowns(z), unknowns, options)
}

/// The collocation system with its Newton systems solved by sparse LU.
struct ByLu<'s, 'a, L: ?Sized> {
    system: &'s GaussSystem<'a, L>,
    /// The last linearisation and its factorisation.
    factors: Option<(SparseRows, SparseLu)>,
    /// `‖J‖∞` of the last linearisation.
    j_norm: f64,
}

impl<L: DynLagrangian + ?Sized> ByLu<'_, '_, L> {
    fn factors(&mut self) -> (&SparseRows, &mut SparseLu) {
        let (matrix, lu) = self.factors.as_mut().expect("linearised before");
        (matrix, lu)
    }
}

impl<L: DynLagrangian + ?Sized> GlobalSystem for ByLu<'_, '_, L> {
    type Iterate = Unknowns;
    type Evaluation = Evaluation;
    type Output = (Vec<f64>, usize, Vec<f64>);

    fn evaluate(&mut self, z: &Unknowns, iteration: usize) -> Result<(Evaluation, f64, f64)> {
        let values = self.system.evaluate(&z.0, iteration)?;
        let merit = values.r.iter().map(|x| x * x).sum::<f64>().sqrt();
        let max = values.max;
        Ok((values, max, merit))
    }

    fn within(&self, e: &Evaluation, residual: f64, tolerance: f64) -> bool {
        residual <= tolerance * e.scale
    }

    fn linearise(
        &mut self,
        z: &Unknowns,
        _: &Evaluation,
        iteration: usize,
    ) -> Result<ControlFlow<Self::Output, f64>> {
        let at = Location::Newton(iteration);
        let (matrix, _) = self
            .system
            .assemble(&z.0, &mut self.factors)
            .map_err(|_| Error::SingularJacobian { at })?;
        self.j_norm = jacobian_norm(matrix, at)?;
        Ok(ControlFlow::Continue(self.j_norm))
    }

    fn converged(&mut self, c: Converging<'_, Self>) -> Result<Self::Output> {
        // A solution where the Jacobian is singular to working precision is not isolated.
        let (at, j_norm) = (c.at(), self.j_norm);
        let (matrix, lu) = self.factors();
        lu_direction((matrix, lu), &c.evaluation.r, c.scratch, at)?;
        isolated((matrix, lu), j_norm, (c.residual, c.scratch), at)?;
        Ok((c.q.0, c.iteration, c.evaluation.last_momentum))
    }

    fn direction(
        &mut self,
        (_, e): (&Unknowns, &mut Evaluation),
        _: (f64, f64),
        delta: &mut [f64],
        iteration: usize,
    ) -> Result<ControlFlow<Self::Output>> {
        lu_direction(self.factors(), &e.r, delta, Location::Newton(iteration))?;
        Ok(ControlFlow::Continue(()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_models::{DYN_MIXED_DIMENSION as D, DynMixed};

    /// The global Jacobian equals central differences of the rows, entry by entry, for every
    /// `s`, on a model whose every block varies under a force with its own Jacobian (a
    /// transposed `L_xv`, a missing force block or a wrong tableau weight each fail it).
    #[test]
    fn the_jacobian_matches_central_differences_of_the_rows() {
        let model = DynMixed { forced: true };
        let grid = Grid::new(0.2, 0.8, 3).unwrap();
        let qa: Vec<f64> = (0..D).map(|i| 0.3 - 0.2 * i as f64).collect();
        let qb: Vec<f64> = (0..D).map(|i| 0.1 * i as f64 - 0.4).collect();
        for s in 1..=4 {
            let system = GaussSystem {
                lagrangian: &model,
                grid,
                tableau: GaussTableau::new(s),
                d: D,
                qa: &qa,
                qb: &qb,
                w: 1.7,
            };
            let order = system.order();
            let z: Vec<f64> = (0..order)
                .map(|i| 0.4 * (0.37 * i as f64).sin() + 0.05 * (i % 3) as f64)
                .collect();
            let mut jacobian = vec![0.0; order * order];
            system.jacobian(&z, |r, c, v| jacobian[r * order + c] += v);
            let eps = 1e-6;
            for col in 0..order {
                let rows = |delta: f64| {
                    let mut z = z.clone();
                    z[col] += delta;
                    system.evaluate(&z, 0).unwrap().r
                };
                let (plus, minus) = (rows(eps), rows(-eps));
                for row in 0..order {
                    let fd = (plus[row] - minus[row]) / (2.0 * eps);
                    let exact = jacobian[row * order + col];
                    assert!(
                        (exact - fd).abs() <= 1e-6 * (1.0 + fd.abs()),
                        "s = {s} ({row}, {col}): {exact} vs {fd}"
                    );
                }
            }
        }
    }
}
