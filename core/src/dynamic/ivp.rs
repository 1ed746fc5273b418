//! The initial value problems of a run-time-dimension model: the checks of the initial data,
//! the discrete Legendre start, and the three-point recurrence with its blow-up guard, each
//! node handed to an observer as it is computed.
//!
//! Only two nodes are kept (three while a step is solved), so a run of `N` steps at dimension
//! `d` needs `O(d · b)` memory beyond what the observer keeps, `b` the band of the step
//! Jacobian ([solvers, "Large
//! models"](crate::guide::solvers#large-models-run-time-dimension-and-sparse-newton)).

use crate::embedding::{Embedding, EmbeddingKind, Scheme};
use crate::error::{Error, Location, Result};
use crate::grid::Grid;
use crate::options::{LinearSolve, NewtonOptions};
use crate::regularity::{InitialData, InitialDataModel, check_initial_point, velocity_from_nodes};
use crate::solve::guard::BlowUpGuard;
use crate::solve::ivp::step_kind;
use crate::solve::solution::Warning;
use crate::solve::start::{Start, second_order_start};
use crate::step::StepKind;

use super::DynLagrangian;
use super::band::BandSystem;
use super::observer::{DynNode, DynNodeModel, NodeObserver};
use super::slices::max_norm;
use super::sparse::SparseHessian;
use super::stability::{decoupled_mass, mode_unstable, resolution_warning};
use super::step::{EnergySample, StepSolver};

/// What a run reports beyond its nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct DynRun {
    /// The scheme that was run.
    pub scheme: Scheme,
    /// Its embedding.
    pub embedding: Embedding,
    /// Its grid.
    pub grid: Grid,
    /// The last node `Q_N`.
    pub last: Vec<f64>,
    /// Newton iterations, summed over the steps `Q_2, …, Q_N` (as
    /// [`Solution::newton_iterations`](crate::Solution::newton_iterations); the start's are not
    /// counted).
    pub newton_iterations: usize,
    /// Steps taken in closed form, without a Newton iteration.
    pub explicit_steps: usize,
    /// The half-bandwidth the step Jacobians were factorised with.
    pub band: usize,
    /// Whether the unknowns were reordered (reverse Cuthill–McKee) to reach that band.
    pub reordered: bool,
    /// What the caller should know about the run (empty when nothing): see
    /// [`DynSolution::warnings`](super::problem::DynSolution::warnings).
    pub warnings: Vec<Warning>,
    /// How a boundary value problem's Newton systems were solved; `None` for an initial value
    /// run.
    pub linear_solve: Option<LinearSolve>,
}

/// How a run gets its second node `Q_1`.
#[derive(Clone, Copy, Debug)]
pub(crate) enum SecondNode<'a> {
    /// From the initial velocity, by a start.
    Start(Start),
    /// Given: the run from its first two nodes, checked at `Q_1` with the velocity
    /// `(Q_1 − Q_0)/h` and warned at `Q_0` with it, as on the const-generic path.
    Given(&'a [f64]),
}

/// The parts of a run-time-dimension problem an initial value problem reads.
pub(crate) struct DynIvp<'a, L: ?Sized> {
    pub(crate) lagrangian: &'a L,
    pub(crate) grid: Grid,
    pub(crate) embedding: Embedding,
    pub(crate) newton: NewtonOptions,
    pub(crate) blow_up_guard: bool,
    /// Whether the run's step is checked against its fastest motion at the initial data.
    pub(crate) resolution_check: bool,
}

impl<L: DynLagrangian + ?Sized> DynIvp<'_, L> {
    /// The step kind of `scheme`: that of the const-generic path
    /// ([`step_kind`]).
    fn step_kind(&self, scheme: Scheme) -> Result<StepKind> {
        step_kind(&self.embedding, scheme)
    }

    /// The run of `scheme` from `q(a) = q0`, `q̇(a) = v0` with `second` for `Q_1` (`v0` is
    /// not read when `Q_1` is given), each node `Q_0, …, Q_N` handed to `observe` in order (as
    /// [`DynNode`] says), with its velocity, momentum and energy when `values` (empty slices
    /// and `None` otherwise, for a caller that reads only the positions).
    pub(crate) fn run(
        &self,
        scheme: Scheme,
        (q0, v0): (&[f64], &[f64]),
        (second, values): (SecondNode<'_>, bool),
        mut observe: impl FnMut(DynNode<'_>),
    ) -> Result<DynRun> {
        if let EmbeddingKind::GaussLegendre { stages } = self.embedding.kind() {
            return match second {
                // A one-step map: no start, and the momenta carried from node to node.
                SecondNode::Start(_) => self.run_gauss((scheme, stages), (q0, v0), values, observe),
                SecondNode::Given(_) => Err(Error::Unsupported {
                    operation: "a three-point recurrence from two nodes",
                    embedding: self.embedding.to_string(),
                }),
            };
        }
        let kind = self.step_kind(scheme)?;
        let (grid, h) = (self.grid, self.grid.h());
        let data = match second {
            SecondNode::Given(q1) => InitialData::Nodes {
                q0,
                q1,
                t1: grid.t(1),
                h,
            },
            SecondNode::Start(_) => InitialData::Velocity {
                q0,
                v0,
                t0: grid.t(0),
            },
        };
        let checked = self.check_initial_data(data)?;
        let from_nodes = match second {
            SecondNode::Given(q1) => Some(velocity_from_nodes(q0, q1, h)),
            SecondNode::Start(_) => None,
        };
        let v0 = from_nodes.as_deref().unwrap_or(v0);
        // The stability verdict and the resolution are read at `q0`, `v0`, `t_0`, as on the
        // const-generic path: for given first nodes, that is `Q_0` with `(Q_1 − Q_0)/h`, which
        // the checks (at `Q_1`) did not evaluate; neither is read where the model cannot be
        // evaluated or factorised there.
        let at_data = match second {
            SecondNode::Start(_) => Some(checked),
            SecondNode::Given(_) => {
                drop(checked);
                self.evaluated_at(q0, v0, grid.t(0))
            }
        };
        let mut warning = None;
        if let Some((mut vv, hessian)) = at_data {
            // The recurrence's linear stability at the initial data, where the model's modes
            // decouple (the blow-up guard watches every run).
            let l = self.lagrangian;
            if let Some(mass) = decoupled_mass(&hessian, &l.hessian_dependence(), l.is_forced())
                && let Some((lambda, largest_stable_step)) =
                    mode_unstable(kind, (mass, &hessian.xx), h)
            {
                return Err(Error::Unstable {
                    at: Location::Step(0),
                    re: lambda.re,
                    im: lambda.im,
                    largest_stable_step: Some(largest_stable_step),
                });
            }
            // The resolution at the initial data, while `∂²L/∂v²` there is factorised; the
            // warning is attached to a run that returns. Both are freed before the run, whose
            // memory is O(d b).
            warning = self
                .resolution_check
                .then(|| resolution_warning(&hessian, &mut vv, h, 1))
                .flatten();
        }
        let d = q0.len();
        let t0 = grid.t(0);
        // The node values' buffers, and a constant `∂²L/∂v²` factorised now, before the steps'
        // buffers exist.
        let setting = (&self.embedding, scheme, self.grid);
        let mut values = match values {
            true => Some(NodeObserver::new(self.lagrangian, setting, d)?.primed(q0, v0, t0)),
            false => None,
        };
        let mut hand = |k: usize, window: (usize, &[&[f64]]), observe: &mut _| match &mut values {
            Some(values) => values.hand(k, window, None, observe),
            None => {
                node_without_values((k, grid.t(k), &[]), window, observe);
                Ok(())
            }
        };
        let mut pi = vec![0.0; d];
        let mut b = match second {
            SecondNode::Start(Start::SecondOrder) => {
                let model = &mut DynNodeModel::new(self.lagrangian, d);
                second_order_start(model, (q0, v0), (t0, h))?
            }
            SecondNode::Start(Start::Legendre) => self.legendre_start(kind, q0, v0, &mut pi)?,
            SecondNode::Given(q1) => q1.to_vec(),
        };
        let mut a = q0.to_vec();
        if grid.n() == 1 {
            hand(0, (0, &[&a, &b]), &mut observe)?;
            hand(1, (0, &[&a, &b]), &mut observe)?;
        }

        let mut solver = StepSolver::new(self.lagrangian, kind, h, self.newton, (q0, v0, t0));
        let drifts = matches!(kind, StepKind::DirectBackward | StepKind::DirectForward);
        let enabled =
            self.blow_up_guard && !self.lagrangian.dependence().t && !self.lagrangian.is_forced();
        let mut guard = BlowUpGuard::watching(drifts, grid.n(), enabled);
        let stride = guard.stride();
        let inv_h = 1.0 / h;
        let mut y = vec![0.0; d];
        let (mut iterations, mut explicit_steps) = (0, 0);
        let verlet = solver.is_verlet();
        for n in 2..=grid.n() {
            let times = (grid.t(n - 2), grid.t(n - 1));
            let sample = guard.is_enabled() && (n - 2) % stride == 0;
            if sample || !verlet {
                let sampled = solver.momentum((&a, &b), times, &mut pi, sample);
                if let Some(EnergySample { energy, vp, p_max }) = sampled {
                    let x_scale = max_norm(&a).max(max_norm(&b));
                    guard.record(energy, vp, energy.abs() + x_scale * p_max * inv_h, n)?;
                }
            }
            let its = if verlet {
                solver.verlet((&a, &b), times.1, &mut y, n)?;
                0
            } else {
                solver.solve((&a, &b), &pi, (grid.t(n - 1), grid.t(n)), &mut y, n)?
            };
            iterations += its;
            explicit_steps += usize::from(its == 0);
            // Rotate the nodes: a ← b ← y, reusing a's buffer for the next y.
            std::mem::swap(&mut a, &mut b);
            std::mem::swap(&mut b, &mut y);
            // y holds Q_{n−2} until the next step overwrites it: node n − 1 (and node 0 with
            // node 1) has every node its formulas read.
            let window: &[&[f64]] = &[&y, &a, &b];
            if n == 2 {
                hand(0, (0, window), &mut observe)?;
            }
            hand(n - 1, (n - 2, window), &mut observe)?;
            if n == grid.n() {
                hand(n, (n - 2, window), &mut observe)?;
            }
        }
        guard.finish()?;
        // Read after the run: an entry outside the planned band re-plans the system mid-run.
        let (band, reordered) = solver.band();
        let last = b;
        Ok(DynRun {
            scheme,
            embedding: self.embedding,
            grid,
            last,
            newton_iterations: iterations,
            explicit_steps,
            band,
            reordered,
            warnings: warning.into_iter().collect(),
            linear_solve: None,
        })
    }

    /// The discrete Legendre start: the variational step equation with `π = ∂L/∂v` at the
    /// initial data, from the guess `q0 + h v0`; `pi` is a buffer of length `d`.
    fn legendre_start(
        &self,
        kind: StepKind,
        q0: &[f64],
        v0: &[f64],
        pi: &mut [f64],
    ) -> Result<Vec<f64>> {
        let (grid, h, t0) = (self.grid, self.grid.h(), self.grid.t(0));
        let start_kind = kind.legendre_start();
        self.lagrangian.momentum(q0, v0, t0, pi);
        let mut start = StepSolver::new(self.lagrangian, start_kind, h, self.newton, (q0, v0, t0));
        // The node before q0 on the tangent, so that Newton's guess 2b − a is q0 + h v0.
        let before: Vec<f64> = q0.iter().zip(v0).map(|(q, v)| q - h * v).collect();
        let mut b = vec![0.0; q0.len()];
        start.solve((&before, q0), pi, (t0, grid.t(1)), &mut b, 1)?;
        Ok(b)
    }

    /// The checks before any step: the model at its dimension, the data of the right lengths,
    /// then [`check_initial_point`] (as on the const-generic path). Returns `∂²L/∂v²` at the
    /// checked point, factorised, and the second derivatives there.
    pub(super) fn check_initial_data(
        &self,
        data: InitialData<'_>,
    ) -> Result<(BandSystem, SparseHessian)> {
        let l = self.lagrangian;
        if let Some(reason) = l.invalid_dimension() {
            return Err(Error::InvalidModel { reason });
        }
        let d = l.dimension();
        let lengths = match data {
            InitialData::Velocity { q0, v0, .. } => [("q0", q0), ("v0", v0)],
            InitialData::Nodes { q0, q1, .. } => [("q0", q0), ("q1", q1)],
        };
        for (name, x) in lengths {
            crate::error::check_len(name, d, x.len())?;
        }
        let mut point = DynPoint::new(l, d);
        check_initial_point(&mut point, data)?;
        match point.vv {
            Some(vv) => Ok((vv, point.hessian)),
            None => Err(Error::NotFinite {
                at: data.location(),
            }),
        }
    }

    /// `∂²L/∂v²` factorised and the second derivatives at `(x, v, t)`: the checks of initial
    /// data there, with their errors dropped (`None` where the model is not finite or
    /// `∂²L/∂v²` is degenerate there).
    fn evaluated_at(&self, x: &[f64], v: &[f64], t: f64) -> Option<(BandSystem, SparseHessian)> {
        let mut point = DynPoint::new(self.lagrangian, x.len());
        let data = InitialData::Velocity {
            q0: x,
            v0: v,
            t0: t,
        };
        check_initial_point(&mut point, data).ok()?;
        point.vv.map(|vv| (vv, point.hessian))
    }
}

/// A [`DynLagrangian`] under the checks of its initial data: the Hessian of the last point
/// evaluated, and its `∂²L/∂v²` factorised as a band once measured.
struct DynPoint<'l, L: ?Sized> {
    lagrangian: &'l L,
    hessian: SparseHessian,
    vv: Option<BandSystem>,
}

impl<'l, L: ?Sized> DynPoint<'l, L> {
    /// `lagrangian` at dimension `d`, nothing evaluated yet.
    fn new(lagrangian: &'l L, d: usize) -> Self {
        DynPoint {
            lagrangian,
            hessian: SparseHessian::new(d),
            vv: None,
        }
    }
}

impl<L: DynLagrangian + ?Sized> InitialDataModel for DynPoint<'_, L> {
    fn constants(&self) -> Vec<(&'static str, f64)> {
        self.lagrangian.constants()
    }
    fn in_domain(&mut self, x: &[f64], v: &[f64], t: f64) -> bool {
        let (l, d) = (self.lagrangian, x.len());
        let (mut f, mut p) = (vec![0.0; d], vec![0.0; d]);
        l.force(x, v, t, &mut f);
        l.momentum(x, v, t, &mut p);
        self.hessian.clear();
        l.hessian(x, v, t, &mut self.hessian);
        l.value(x, v, t).is_finite()
            && f.iter().chain(&p).all(|c| c.is_finite())
            && self.hessian.is_finite()
    }
    fn vv_measure(&mut self) -> f64 {
        let d = self.hessian.vv.dimension();
        let bandwidth = self.lagrangian.hessian_bandwidth();
        let (system, measure) = vv_factorised(d, bandwidth, &self.hessian);
        self.vv = system;
        measure
    }
    fn degenerate_directions(&self) -> Vec<Vec<(usize, f64)>> {
        self.hessian.vv.degenerate_directions()
    }
}

/// Hands node `k` at `t` of `window` (consecutive nodes, the first of them node `window.0`) to
/// `observe` without its velocity or energy, with the momentum `p` a scheme carries there
/// (empty for the three-point recurrences, which carry none).
pub(super) fn node_without_values(
    (k, t, p): (usize, f64, &[f64]),
    (first, window): (usize, &[&[f64]]),
    observe: &mut impl FnMut(DynNode<'_>),
) {
    observe(DynNode {
        index: k,
        t,
        q: window[k - first],
        previous: window[k.max(1) - 1 - first],
        v: &[],
        p,
        energy: None,
    });
}

/// `∂²L/∂v²` (the block `vv` of `hessian`) factorised as a band, with its pivot ratio; `None`
/// and 0 when singular.
pub(super) fn vv_factorised(
    d: usize,
    claimed: Option<usize>,
    hessian: &SparseHessian,
) -> (Option<BandSystem>, f64) {
    let mut system = BandSystem::plan(d, claimed, &[&hessian.vv]);
    for &(i, j, value) in hessian.vv.entries() {
        if system.add(i, j, value).is_err() {
            return (None, 0.0);
        }
    }
    if system.factorize() {
        let ratio = system.pivot_ratio();
        (Some(system), ratio)
    } else {
        (None, 0.0)
    }
}
