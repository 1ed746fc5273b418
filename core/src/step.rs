//! The step math of the classical schemes, written once for every [`Lagrangian`].
//!
//! Every classical scheme (direct and variational, σ = ±) is a three-point recurrence, and all
//! four have the same shape: from the two previous nodes `a = Q_{n−2}`, `b = Q_{n−1}` compute a
//! *momentum* `π`, then solve a discrete Legendre map `G(y) = π` for the newest node
//! `y = Q_n`. Write `@left(a, b)` for evaluation at `(a, (b − a)/h, t_a)` and `@right(a, b)`
//! for evaluation at `(b, (b − a)/h, t_b)`, with `p = ∂L/∂v`, `f = ∂L/∂x`:
//!
//! | [`StepKind`] | momentum `π` from `(a, b)` | equation `G(y) = π` from `(b, y)` |
//! | --- | --- | --- |
//! | `VariationalBackward` (σ=−) | `(p + h f)@right(a, b)` | `p@right(b, y) = π` |
//! | `VariationalForward` (σ=+) | `p@left(a, b)` | `(p − h f)@left(b, y) = π` |
//! | `DirectBackward` (σ=−) | `p@right(a, b)` | `(p − h f)@right(b, y) = π` |
//! | `DirectForward` (σ=+) | `(p + h f)@left(a, b)` | `p@left(b, y) = π` |
//!
//! Each row is the scheme's residual row multiplied by `−h` (variational σ=−, row `n−1`:
//! `f + (p_{n−1} − p_n)/h = 0`; direct σ=+, row `n−2`: `f + (p_{n−2} − p_{n−1})/h = 0`, …), so
//! the step residual is in units of momentum. The discrete Legendre start is the variational
//! equation with `π = π_0 = ∂L/∂v(q(a), q̇(a), a)`.
//!
//! The Jacobians `J = ∂G/∂y`, with `L_vx = L_xvᵀ`:
//!
//! | equation | Jacobian `J` |
//! | --- | --- |
//! | `p@right(b, y)` | `L_vx + L_vv/h` |
//! | `(p − h f)@left(b, y)` | `L_vv/h − L_xv` |
//! | `(p − h f)@right(b, y)` | `L_vx + L_vv/h − h L_xx − L_xv` |
//! | `p@left(b, y)` | `L_vv/h` |
//!
//! # Closed-form steps
//!
//! A step is *affine* in `y` when the blocks in its Jacobian depend neither on `y` itself nor
//! on the velocity `(y − b)/h`. Then `G(y) = G(b) + J (y − b)` exactly, and one Newton step
//! from `y = b` (velocity 0) is the answer: `y = b − J⁻¹ (G(b) − π)`. From
//! [`Lagrangian::hessian_dependence`] (`@right` reads the blocks at `y`, `@left` at `b`):
//!
//! | [`StepKind`] | affine when |
//! | --- | --- |
//! | `VariationalBackward` | `L_xv`, `L_vv` depend on neither `x` nor `v` |
//! | `VariationalForward` | `L_xv`, `L_vv` do not depend on `v` |
//! | `DirectBackward` | `L_xx`, `L_xv`, `L_vv` depend on neither `x` nor `v` |
//! | `DirectForward` | `L_vv` does not depend on `v` |
//!
//! So for `L = ½ vᵀM(x)v − U(x)` the direct forward step is closed-form (`L_vv = M(x)` is read
//! at `b`), the variational forward step is not (`L_xv = M′(x)v` depends on `v`); with a
//! constant `M` the variational backward step is closed-form too, and the direct backward step
//! only when `U` is quadratic (`L_xx = −U″` must be constant). [`Update::plan`] decides this
//! once per run, and when the blocks in `J` are constants it inverts `J` once for the whole
//! run.
//!
//! # The symmetric embeddings
//!
//! The midpoint and trapezoidal schemes are three-point recurrences of the same shape, written
//! with the interval momentum `P` and forces `F_u`, `F_w` of the interval module
//! (`D₁L_d = h/2 F_u − P`, `D₂L_d = h/2 F_w + P`), `[a, b]` and `[b, y]` the two intervals:
//!
//! | [`StepKind`] | momentum `π` from `(a, b)` | equation `G(y) = π` |
//! | --- | --- | --- |
//! | `MidpointVariational`, `TrapezoidalVariational` | `D₂L_d(a, b) = (P + h/2 F_w)[a, b]` | `−D₁L_d(b, y) = (P − h/2 F_u)[b, y]` |
//! | `MidpointDirect`, `TrapezoidalDirect` | `P[a, b]` | `P[b, y] − h f(b, (y − a)/(2h), t_b)` |
//!
//! (the discrete Euler–Lagrange equation, and the direct row of
//! [schemes](crate::guide::schemes), times `−h`). The direct equation reads the oldest node
//! `a` as well, through the centred velocity: a [`Step`] carries it. Their Jacobians are
//! `∂P/∂y − h/2 ∂F_u/∂y` and `∂P/∂y − L_xv/2` (the last block at the node with the centred
//! velocity). These steps always run Newton's method (from the linear extrapolation `2b − a`);
//! on `L = ½|v|² − U(x)` the trapezoidal ones are affine, and Newton stops after one iteration.
//!
//! # One table for both storages
//!
//! Both tables are written out term by term in the `terms` submodule: each kind's momentum and
//! equation as sums of `w_p p + w_f h f` at named points of an interval, and the weights of the
//! second-derivative blocks in its Jacobian. The kernels here (fixed-size vectors, dense
//! blocks) and the run-time-dimension steps (slices, band blocks) both evaluate that table, so
//! a kind is defined once and the two paths take the same steps.

use crate::lagrangian::{ForceJacobian, Hessian, Lagrangian, Matrix, Vector};

use terms::{BlockWeights, Point, Term, Terms, equation_terms, momentum_terms};

/// Which classical scheme a step advances (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StepKind {
    /// Variational integrator of Gauss-FDE− (σ = −).
    VariationalBackward,
    /// Variational integrator of Gauss-FDE+ (σ = +).
    VariationalForward,
    /// Direct embedding of Gauss-FDE− (σ = −): implicit in the newest node.
    DirectBackward,
    /// Direct embedding of Gauss-FDE+ (σ = +).
    DirectForward,
    /// Variational integrator of the midpoint embedding.
    MidpointVariational,
    /// Direct scheme of the midpoint embedding.
    MidpointDirect,
    /// Variational integrator of the trapezoidal embedding.
    TrapezoidalVariational,
    /// Direct scheme of the trapezoidal embedding.
    TrapezoidalDirect,
}

impl StepKind {
    /// The four kinds of the Gauss-FDEσ schemes, in declaration order.
    pub const FINITE_DIFFERENCE: [StepKind; 4] = [
        StepKind::VariationalBackward,
        StepKind::VariationalForward,
        StepKind::DirectBackward,
        StepKind::DirectForward,
    ];
    /// The four kinds of the symmetric embeddings, in declaration order.
    pub const SYMMETRIC: [StepKind; 4] = [
        StepKind::MidpointVariational,
        StepKind::MidpointDirect,
        StepKind::TrapezoidalVariational,
        StepKind::TrapezoidalDirect,
    ];
    /// Every kind, in declaration order.
    pub const ALL: [StepKind; 8] = [
        StepKind::VariationalBackward,
        StepKind::VariationalForward,
        StepKind::DirectBackward,
        StepKind::DirectForward,
        StepKind::MidpointVariational,
        StepKind::MidpointDirect,
        StepKind::TrapezoidalVariational,
        StepKind::TrapezoidalDirect,
    ];

    /// The variational kind whose step equation, with `π` the momentum of the initial data, is
    /// the discrete Legendre start of this kind's runs.
    pub fn legendre_start(self) -> StepKind {
        match self {
            StepKind::VariationalBackward | StepKind::DirectBackward => {
                StepKind::VariationalBackward
            }
            StepKind::VariationalForward | StepKind::DirectForward => StepKind::VariationalForward,
            StepKind::MidpointVariational | StepKind::MidpointDirect => {
                StepKind::MidpointVariational
            }
            StepKind::TrapezoidalVariational | StepKind::TrapezoidalDirect => {
                StepKind::TrapezoidalVariational
            }
        }
    }

    /// The time at which a closed-form step evaluates its equation: that of the single
    /// term of a Gauss-FDEσ kind, `t_y` (`@right`) or `t_b` (`@left`).
    fn equation_time(self, times: &StepTimes) -> f64 {
        match equation_terms(self).first().point {
            Point::Right => times.t_y,
            _ => times.t_b,
        }
    }
}

/// Grid data a step needs: the step `h`, its inverse, and the times of the three nodes
/// `t_{n−2}, t_{n−1}, t_n` (taken from the grid, so they match [`crate::Grid::t`] exactly).
///
/// The kernels form velocities as `(b − a) · inv_h`: a multiplication, where a division by `h`
/// would sit on the critical path of every step of an explicit run. Build it with
/// [`StepTimes::new`], which sets `inv_h = 1/h`.
///
/// # Example
///
/// ```
/// let times = varembed::__private::step::StepTimes::new(0.25, 1.0, 1.25, 1.5);
/// assert_eq!(times.inv_h, 4.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepTimes {
    /// Step size `h`.
    pub h: f64,
    /// `1/h`, as computed by [`StepTimes::new`] (the kernels rely on the two agreeing).
    pub inv_h: f64,
    /// `t_{n−2}`, the time of the oldest node `a`.
    pub t_a: f64,
    /// `t_{n−1}`, the time of the middle node `b`.
    pub t_b: f64,
    /// `t_n`, the time of the newest node `y`.
    pub t_y: f64,
}

impl StepTimes {
    /// The step data for step size `h` and node times `t_a`, `t_b`, `t_y`, with
    /// `inv_h = 1/h`.
    pub const fn new(h: f64, t_a: f64, t_b: f64, t_y: f64) -> Self {
        StepTimes {
            h,
            inv_h: 1.0 / h,
            t_a,
            t_b,
            t_y,
        }
    }
}

/// One step's equation `G(y) = π` for the newest node: its kind, the two previous nodes, the
/// momentum `π` and the grid data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step<const D: usize> {
    /// Which scheme.
    pub kind: StepKind,
    /// The oldest node `Q_{n−2}`: read only by the direct steps of the symmetric embeddings
    /// (their force takes the centred velocity `(y − a)/(2h)`).
    pub a: Vector<D>,
    /// The previous node `Q_{n−1}`.
    pub b: Vector<D>,
    /// The momentum `π` the step must reproduce.
    pub momentum: Vector<D>,
    /// The step size and node times.
    pub times: StepTimes,
}

impl<const D: usize> Step<D> {
    /// The step from `a = Q_{n−2}`, `b = Q_{n−1}`: its momentum by [`momentum`].
    #[inline]
    pub fn new<L: Lagrangian<D> + ?Sized>(
        lagrangian: &L,
        kind: StepKind,
        a: &Vector<D>,
        b: &Vector<D>,
        times: &StepTimes,
    ) -> Self {
        Step {
            kind,
            a: *a,
            b: *b,
            momentum: momentum(lagrangian, kind, a, b, times),
            times: *times,
        }
    }
}

/// The momentum `π` that the step for `Q_n` must reproduce, from `a = Q_{n−2}`,
/// `b = Q_{n−1}` (first table of the module docs).
#[inline]
pub fn momentum<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    kind: StepKind,
    a: &Vector<D>,
    b: &Vector<D>,
    times: &StepTimes,
) -> Vector<D> {
    let gradient = |x: &Vector<D>, v: &Vector<D>, t: f64| {
        let (f, p) = lagrangian.gradient(x, v, t);
        (0.0, f, p)
    };
    momentum_from(kind, a, b, times, gradient).0
}

/// [`momentum`] and, from the same evaluations, the weighted sums `Σ w_p L` and `Σ w_p ∂L/∂v`
/// over the momentum's terms, all at the velocity `(b − a)/h`: `L` and `p` at the quadrature
/// node of side σ, at the interval's midpoint, or their means over its two ends (the
/// trapezoid). The step's energy is `v·p − L`: the blow-up guard samples it at no cost beyond
/// the step's own.
#[inline]
pub(crate) fn momentum_and_energy_terms<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    kind: StepKind,
    a: &Vector<D>,
    b: &Vector<D>,
    times: &StepTimes,
) -> (Vector<D>, (f64, Vector<D>)) {
    momentum_from(kind, a, b, times, |x, v, t| {
        lagrangian.value_and_gradient(x, v, t)
    })
}

/// `(x, v, t)` of a term's point on `[u, w]` (times `t_u`, `t_w`), `before` the node before
/// `u` (the table of the terms module).
#[inline(always)]
fn locate<const D: usize>(
    point: Point,
    (before, u, w): (&Vector<D>, &Vector<D>, &Vector<D>),
    (t_u, t_w): (f64, f64),
    inv_h: f64,
) -> (Vector<D>, Vector<D>, f64) {
    let t = point.time(t_u, t_w);
    match point {
        Point::Left => (*u, (w - u) * inv_h, t),
        Point::Middle => ((u + w) * 0.5, (w - u) * inv_h, t),
        Point::Right => (*w, (w - u) * inv_h, t),
        Point::Centred => (*u, (w - before) * (0.5 * inv_h), t),
    }
}

/// `w_p p + w_f h f` of `term`, with no operation for a zero weight (`0 · f` would not fold
/// away: it is NaN for an infinite `f`).
#[inline(always)]
fn weighted<const D: usize>(term: &Term, p: Vector<D>, f: Vector<D>, h: f64) -> Vector<D> {
    match (term.p != 0.0, term.f != 0.0) {
        (true, true) => p * term.p + f * (term.f * h),
        (true, false) => p * term.p,
        (false, true) => f * (term.f * h),
        (false, false) => Vector::<D>::zeros(),
    }
}

/// `xx L_xx + xv L_xv + vx L_vx + vv L_vv`, with no operation for a zero weight.
#[inline(always)]
fn block_sum<const D: usize>(hs: &Hessian<D>, w: BlockWeights) -> Matrix<D> {
    let mut m = if w.vv != 0.0 {
        hs.vv * w.vv
    } else {
        Matrix::<D>::zeros()
    };
    if w.vx != 0.0 {
        m += hs.xv.transpose() * w.vx;
    }
    if w.xv != 0.0 {
        m += hs.xv * w.xv;
    }
    if w.xx != 0.0 {
        m += hs.xx * w.xx;
    }
    m
}

/// The blocks of a generalised force in `h J`: `∂f/∂x` where `L_xx` stands and `∂f/∂v` where
/// `L_xv` does (the force enters with `∂L/∂x`, never with `p`), with no operation for a zero
/// weight.
#[inline(always)]
fn force_block_sum<const D: usize>(
    m: &mut Matrix<D>,
    force: Option<ForceJacobian<D>>,
    w: BlockWeights,
) {
    if let Some(force) = force {
        if w.xv != 0.0 {
            *m += force.v * w.xv;
        }
        if w.xx != 0.0 {
            *m += force.x * w.xx;
        }
    }
}

/// Sums `each` over the (up to three) terms, written out rather than looped so that, for a
/// kind known at compile time, each term's weights are constants and what a zero weight
/// multiplies is never computed.
#[inline(always)]
fn sum_terms<T>(terms: &Terms, mut each: impl FnMut(&Term) -> T, add: impl Fn(T, T) -> T) -> T {
    let mut sum = each(&terms.first());
    let terms = terms.as_slice();
    if let Some(term) = terms.get(1) {
        sum = add(sum, each(term));
    }
    if let Some(term) = terms.get(2) {
        sum = add(sum, each(term));
    }
    sum
}

/// [`momentum_and_energy_terms`] with `eval` giving `(L, ∂L/∂x, ∂L/∂v)` at a point.
#[inline(always)]
fn momentum_from<const D: usize>(
    kind: StepKind,
    a: &Vector<D>,
    b: &Vector<D>,
    times: &StepTimes,
    eval: impl Fn(&Vector<D>, &Vector<D>, f64) -> (f64, Vector<D>, Vector<D>),
) -> (Vector<D>, (f64, Vector<D>)) {
    let h = times.h;
    if let Some(term) = single_term(kind) {
        // The Gauss-FDEσ kinds, the explicit runs' path: their one term written out, so that
        // the stepping loop of an explicit run keeps its shape (measured: through the general
        // sum below the explicit Kepler run took 1.2× its time, BENCHMARKS.md).
        let v = (b - a) * times.inv_h;
        let (x, t) = match term.point {
            Point::Right => (b, times.t_b),
            _ => (a, times.t_a),
        };
        let (l, f, p) = eval(x, &v, t);
        let pi = if term.f != 0.0 { p + f * h } else { p };
        return (pi, (l, p));
    }
    sum_terms(
        &momentum_terms(kind),
        |term| {
            let (x, v, t) = locate(term.point, (a, a, b), (times.t_a, times.t_b), times.inv_h);
            let (l, f, p) = eval(&x, &v, t);
            let pi = weighted(term, p, f, h);
            if term.p == 1.0 {
                (pi, (l, p))
            } else {
                (pi, (term.p * l, p * term.p))
            }
        },
        |(pi, (l, p)), (pi2, (l2, p2))| (pi + pi2, (l + l2, p + p2)),
    )
}

/// The one term of a Gauss-FDEσ kind's momentum (`p` or `p + h f` at a node), `None` for the
/// symmetric kinds.
#[inline(always)]
fn single_term(kind: StepKind) -> Option<Term> {
    match kind {
        StepKind::VariationalBackward
        | StepKind::VariationalForward
        | StepKind::DirectBackward
        | StepKind::DirectForward => Some(momentum_terms(kind).first()),
        _ => None,
    }
}

/// `G(y)` of a closed-form step at `y = b`, from the gradient at `b`: its single term's
/// `w_p p + w_f h f`. Only the Gauss-FDEσ kinds reach it (the symmetric steps are never
/// planned in closed form).
#[inline(always)]
fn equation<const D: usize>(kind: StepKind, f: Vector<D>, p: Vector<D>, h: f64) -> Vector<D> {
    // `p` or `p − h f`: the table's weights are 1 and 0 or −1, written out as the explicit
    // runs take it.
    if equation_terms(kind).first().f != 0.0 {
        p - f * h
    } else {
        p
    }
}

/// `h J` from the blocks at the evaluation point of a single-term kind.
///
/// The closed-form update uses `J⁻¹ = h (h J)⁻¹`: for `L_vv = I` (and `L_xv = 0`) that is
/// exactly `h`, so the update is `b + h π` with no rounding beyond the hand-written
/// Störmer–Verlet loop's.
#[inline(always)]
fn scaled_jacobian<const D: usize>(
    kind: StepKind,
    hs: &Hessian<D>,
    force: Option<ForceJacobian<D>>,
    h: f64,
) -> Matrix<D> {
    let weights = equation_terms(kind).first().block_weights(h);
    let mut m = block_sum(hs, weights);
    force_block_sum(&mut m, force, weights);
    m
}

/// Residual `G(y) − π` of the step equation at the candidate newest node `y`, and its
/// Jacobian `J = ∂G/∂y`: what one Newton iteration needs, from one
/// [`Lagrangian::gradient_and_hessian`] per term of the equation.
///
/// One arm per kind, each handing on the step with its kind a constant: where the caller's kind
/// is not known at compile time (inside Newton's iteration, a function of its own), what that
/// kind does not read (the unused outputs of `gradient_and_hessian`, the other kinds' tables)
/// is still dead code in each arm.
#[inline]
pub fn residual<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    step: &Step<D>,
    y: &Vector<D>,
) -> (Vector<D>, Matrix<D>) {
    let (r, j, _) = residual_and_terms(lagrangian, step, y);
    (r, j)
}

/// [`residual`] and the size of the terms `G(y)` sums at `y`: the largest of `|w_p| ‖p‖∞` and
/// `|w_f| h ‖f‖∞` over its terms. With `‖π‖∞` it is the scale of the step's equation, against
/// which Newton's tolerance is measured (it scales with `L`, so the stopping rule does not
/// depend on `L`'s scale).
#[inline]
pub(crate) fn residual_and_terms<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    step: &Step<D>,
    y: &Vector<D>,
) -> (Vector<D>, Matrix<D>, f64) {
    use StepKind::*;
    let with = |kind| Step { kind, ..*step };
    match step.kind {
        VariationalBackward => residual_of(lagrangian, &with(VariationalBackward), y),
        VariationalForward => residual_of(lagrangian, &with(VariationalForward), y),
        DirectBackward => residual_of(lagrangian, &with(DirectBackward), y),
        DirectForward => residual_of(lagrangian, &with(DirectForward), y),
        MidpointVariational => residual_of(lagrangian, &with(MidpointVariational), y),
        MidpointDirect => residual_of(lagrangian, &with(MidpointDirect), y),
        TrapezoidalVariational => residual_of(lagrangian, &with(TrapezoidalVariational), y),
        TrapezoidalDirect => residual_of(lagrangian, &with(TrapezoidalDirect), y),
    }
}

/// [`residual`] for one kind: the equation's terms on `[b, y]`.
///
/// Forced inline, as is each term's evaluation ([`equation_term`], a function rather than a
/// closure: a closure is one function for every kind, which the optimiser does not inline
/// into each of its call sites): called out of line, Newton's loop evaluated every derivative
/// the generated code computes, where inlined it drops those the step does not read (the
/// direct midpoint step of the double pendulum ran 1.8× slower out of line, and 1.3× slower
/// through a closure, BENCHMARKS.md).
#[inline(always)]
fn residual_of<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    step: &Step<D>,
    y: &Vector<D>,
) -> (Vector<D>, Matrix<D>, f64) {
    let terms = equation_terms(step.kind);
    let (mut g, mut hj, mut size) = equation_term(lagrangian, step, y, &terms.first());
    for k in [1, 2] {
        if let Some(term) = terms.as_slice().get(k) {
            let (g_k, hj_k, size_k) = equation_term(lagrangian, step, y, term);
            g += g_k;
            hj += hj_k;
            size = size.max(size_k);
        }
    }
    (g - step.momentum, hj * step.times.inv_h, size)
}

/// One term of a step equation at `y`: `w_p p + w_f h f`, its block sum in `h J`, and its size
/// (`|w_p| ‖p‖∞`, `|w_f| h ‖f‖∞`, the larger).
#[inline(always)]
fn equation_term<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    step: &Step<D>,
    y: &Vector<D>,
    term: &Term,
) -> (Vector<D>, Matrix<D>, f64) {
    let StepTimes {
        h, inv_h, t_b, t_y, ..
    } = step.times;
    let (x, v, t) = locate(term.point, (&step.a, &step.b, y), (t_b, t_y), inv_h);
    let (f, p, hs) = lagrangian.gradient_and_hessian(&x, &v, t);
    let size = match (term.p != 0.0, term.f != 0.0) {
        (true, true) => (term.p.abs() * p.amax()).max((term.f * h).abs() * f.amax()),
        (true, false) => term.p.abs() * p.amax(),
        (false, _) => (term.f * h).abs() * f.amax(),
    };
    let weights = term.block_weights(h);
    let mut hj = block_sum(&hs, weights);
    if term.f != 0.0 {
        force_block_sum(&mut hj, lagrangian.force_jacobian(&x, &v, t), weights);
    }
    (weighted(term, p, f, h), hj, size)
}

pub(crate) mod terms;
mod update;

pub use update::{Update, is_affine};
pub(crate) use update::{jacobian_is_constant, reads_force, with_force};

#[cfg(test)]
mod tests;
