//! The driven Duffing oscillator in its chaotic regime, `q̈ + δq̇ + αq + βq³ = γ cos ωt` with
//! the classic `δ = 0.3`, `α = −1`, `β = 1`, `γ = 0.5`, `ω = 1.2`: the double-well Lagrangian
//! `L = ½v² − ½αx² − ¼βx⁴` under the friction `−δq̇` ([`varembed::Rayleigh`]) and the drive
//! `γ cos ωt`, a hand-written [`Force`] of `t` alone, summed into one force (a pair of forces is a [`Force`]).
//!
//! A short sweep against DOP853 (the equation written by hand) shows the orders; a long run of
//! 10⁵ midpoint variational steps shows the energy balance `E_k − E_0 − W_k`, with `W_k` the
//! work of both forces ([`Forced::work`]), over a chaotic trajectory.

use crate::cost;
use crate::reference::ReferenceCurve;
use crate::scene::{Context, Doubling, Figure, SceneReport, Series, SweepLine, doubling};
use varembed::{
    CompareOptions, Dependence, Embedding, Force, ForceDependence, ForceJacobian, Forced, Grid,
    Matrix, Problem, Rayleigh, Reference, Scheme, Side, Solution, Start, Vector, lagrangian,
};

/// The damping `δ`.
pub const DELTA: f64 = 0.3;
/// The linear stiffness `α` (negative: two wells).
pub const ALPHA: f64 = -1.0;
/// The cubic stiffness `β`.
pub const BETA: f64 = 1.0;
/// The drive's amplitude `γ`.
pub const GAMMA: f64 = 0.5;
/// The drive's frequency `ω`.
pub const OMEGA: f64 = 1.2;

/// The Duffing Lagrangian `L = ½v² − ½αx² − ¼βx⁴`.
#[lagrangian]
pub fn duffing(x: f64, v: f64, alpha: f64, beta: f64) -> f64 {
    0.5 * v * v - 0.5 * alpha * x * x - 0.25 * beta * x * x * x * x
}

/// Linear friction, `R = ½δv²`.
#[lagrangian]
pub fn friction(_x: f64, v: f64, delta: f64) -> f64 {
    0.5 * delta * v * v
}

/// The drive `f = γ cos ωt`: a force of `t` alone, its Jacobian zero.
#[derive(Clone, Copy, Debug)]
pub struct Drive {
    /// `γ`.
    pub amplitude: f64,
    /// `ω`.
    pub omega: f64,
}

impl Force<1> for Drive {
    fn force(&self, _x: &Vector<1>, _v: &Vector<1>, t: f64) -> Vector<1> {
        Vector::<1>::new(self.amplitude * (self.omega * t).cos())
    }
    fn jacobian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> ForceJacobian<1> {
        ForceJacobian {
            x: Matrix::<1>::zeros(),
            v: Matrix::<1>::zeros(),
        }
    }
    fn jacobian_dependence(&self) -> ForceDependence {
        ForceDependence {
            x: Dependence::NONE,
            v: Dependence::NONE,
        }
    }
    fn constants(&self) -> Vec<(&'static str, f64)> {
        vec![("amplitude", self.amplitude), ("omega", self.omega)]
    }
}

/// The Lagrangian.
pub const MODEL: Duffing = Duffing {
    alpha: ALPHA,
    beta: BETA,
};
/// The friction alone.
pub const FRICTION: Rayleigh<Friction> = Rayleigh(Friction { delta: DELTA });
/// The drive alone.
pub const DRIVE: Drive = Drive {
    amplitude: GAMMA,
    omega: OMEGA,
};
/// The driven, damped Duffing oscillator.
pub const DRIVEN: Forced<Duffing, (Rayleigh<Friction>, Drive)> =
    Forced::new(MODEL, (FRICTION, DRIVE));

/// The scene's file-name stem.
pub const NAME: &str = "duffing";

/// `[a, b]` of the sweep: a few drive periods, before the chaos has amplified every error.
pub const INTERVAL: (f64, f64) = (0.0, 10.0);
/// `q(0)`, `q̇(0)`: at rest at the bottom of the right well.
pub const START: (f64, f64) = (1.0, 0.0);
/// The step of the long run.
pub const LONG_H: f64 = 0.01;

/// DOP853 on `q̈ = −δq̇ − αq − βq³ + γ cos ωt`, written by hand.
pub fn reference() -> ReferenceCurve<1> {
    let acceleration = |q: &[f64], v: &[f64], t: f64, a: &mut [f64]| {
        a[0] = -DELTA * v[0] - ALPHA * q[0] - BETA * q[0].powi(3) + GAMMA * (OMEGA * t).cos();
    };
    ReferenceCurve::dop853(
        &acceleration,
        INTERVAL,
        Vector::<1>::new(START.0),
        Vector::<1>::new(START.1),
        20_000,
    )
}

/// The energy balance of a run of [`DRIVEN`]: per node `(t_k, E_k − E_0 − W_k)`, with `E_k`
/// the Duffing energy at the nodes and `W_k` the work of both forces; and the work of the
/// friction and of the drive over the run, and `E_N − E_0`.
pub struct Balance {
    /// `(t_k, E_k − E_0 − W_k)`.
    pub miss: Vec<(f64, f64)>,
    /// `W_N` of the friction alone.
    pub friction_work: f64,
    /// `W_N` of the drive alone.
    pub drive_work: f64,
    /// `E_N − E_0`.
    pub energy_change: f64,
}

impl Balance {
    /// The balance of `solution`, a run of [`DRIVEN`].
    pub fn new(solution: &Solution<1>) -> varembed::Result<Self> {
        let energy = solution
            .node_values(&DRIVEN)?
            .energy
            .expect("L is autonomous");
        let work = DRIVEN.work(solution)?;
        let part = |w: varembed::Result<Vec<f64>>| w.map(|w| w[w.len() - 1]);
        let times = solution.times();
        Ok(Balance {
            miss: times
                .iter()
                .zip(energy.iter().zip(&work))
                .map(|(&t, (e, w))| (t, e - energy[0] - w))
                .collect(),
            friction_work: part(Forced::new(MODEL, FRICTION).work(solution))?,
            drive_work: part(Forced::new(MODEL, DRIVE).work(solution))?,
            energy_change: energy[energy.len() - 1] - energy[0],
        })
    }

    /// `max_k |E_k − E_0 − W_k|` over the first half of the nodes and over the second half.
    pub fn halves(&self) -> (f64, f64) {
        let half = self.miss.len() / 2;
        let max = |s: &[(f64, f64)]| s.iter().map(|(_, m)| m.abs()).fold(0.0, f64::max);
        (max(&self.miss[..half]), max(&self.miss[half..]))
    }
}

/// The lines of the sweep: the midpoint and trapezoidal variational schemes (order 2),
/// Gauss–Legendre `s = 2` (order 4) and Gauss-FDE− variational (order 1: the friction reads
/// the one-sided velocity).
fn lines(cx: &Context) -> Vec<(&'static str, Embedding, Doubling)> {
    let second = doubling(cx.pick(250, 100), cx.pick(6, 3));
    vec![
        ("variational midpoint", Embedding::midpoint(), second),
        ("variational trapezoidal", Embedding::trapezoidal(), second),
        (
            "Gauss–Legendre s = 2",
            Embedding::gauss_legendre(2).expect("2 stages exist"),
            doubling(25, cx.pick(7, 3)),
        ),
        (
            "variational FDE−",
            Embedding::finite_difference(Side::Backward),
            doubling(cx.pick(500, 100), cx.pick(6, 4)),
        ),
    ]
}

/// The scene.
pub fn run(cx: &Context) -> varembed::Result<SceneReport> {
    let reference = reference();
    let curve = |t: f64| reference.q(t);
    let lines = lines(cx);
    let grids: usize = lines.iter().map(|(_, _, sizes)| sizes.count).sum();
    let steps = cx.pick(100_000, 10_000);
    cx.progress
        .inc_length((cx.repeats * grids + 2 * cx.repeats) as u64);
    let mut sweep = Vec::with_capacity(lines.len());
    for (label, embedding, sizes) in lines {
        let grid = Grid::new(INTERVAL.0, INTERVAL.1, sizes.n0)?;
        let options = CompareOptions {
            reference: Reference::Computed {
                name: &reference.name,
                q: &curve,
            },
            start: Start::Legendre,
            order: true,
            timing: true,
        };
        let problem = Problem::new(&DRIVEN, grid, embedding);
        let run = cx.timed(|| {
            problem.convergence_ivp(Scheme::Variational, START.0, START.1, &options, sizes.count)
        });
        cx.record_run(NAME, &format!("{embedding} variational"), &run);
        sweep.push(SweepLine::from_run(label, &run));
    }

    // The long runs: 10⁵ steps of h = 0.01 and half as many of 2h over the same interval.
    let mut long = Vec::new();
    for (n, h) in [(steps, LONG_H), (steps / 2, 2.0 * LONG_H)] {
        let grid = Grid::new(0.0, h * n as f64, n)?;
        let problem = Problem::new(&DRIVEN, grid, Embedding::midpoint());
        let (solution, seconds) =
            cx.median_time(|| problem.solve_ivp(Scheme::Variational, START.0, START.1))?;
        cx.record(
            NAME,
            &format!("long run at h = {h}, midpoint variational"),
            n,
        );
        let balance = Balance::new(&solution)?;
        let crossings = solution
            .q
            .windows(2)
            .filter(|w| w[0][0] * w[1][0] < 0.0)
            .count();
        long.push((n, h, seconds, balance, crossings));
    }
    let t_end = LONG_H * steps as f64;
    let mut table = format!(
        "Duffing, midpoint variational on [0, {t_end}]: energy balance E_k − E_0 − W_k\n  \
         {:>7} {:>6} {:>13} {:>13} {:>11} {:>11} {:>11} {:>9} {:>9}\n",
        "N",
        "h",
        "max 1st half",
        "max 2nd half",
        "W friction",
        "W drive",
        "E_N − E_0",
        "q = 0 ×",
        "time (s)"
    );
    for (n, h, seconds, balance, crossings) in &long {
        let (first, second) = balance.halves();
        table += &format!(
            "  {n:>7} {h:>6} {first:>13.2e} {second:>13.2e} {:>11.3} {:>11.3} {:>11.2e} \
             {crossings:>9} {seconds:>9.2e}\n",
            balance.friction_work, balance.drive_work, balance.energy_change,
        );
    }
    let (fine, coarse) = (&long[0].3, &long[1].3);
    let (fine_max, coarse_max) = (
        fine.halves().0.max(fine.halves().1),
        coarse.halves().0.max(coarse.halves().1),
    );
    let order = |label: &str| {
        let line = sweep.iter().find(|l| l.label == label);
        line.and_then(|l| l.marked_orders().last().cloned())
            .unwrap_or_else(|| "—".to_string())
    };
    let (first, second) = fine.halves();
    let growth = if second <= 2.0 * first {
        "it does not grow with the run"
    } else {
        "it grows with the run"
    };
    let target = 1e-8;
    let notes = vec![
        format!(
            "`q̈ + δq̇ + αq + βq³ = γ cos ωt`, `δ = {DELTA}`, `α = {ALPHA}`, `β = {BETA}`, \
             `γ = {GAMMA}`, `ω = {OMEGA}` (chaotic), from rest at `q = 1`: the double-well \
             `L = ½v² − ½αx² − ¼βx⁴` under one force, the sum of the friction `−δq̇` (`Rayleigh`) \
             and the drive `γ cos ωt` (a hand-written `Force` of `t` alone). The sweep, on \
             `[0, 10]` against DOP853 on the equation written by hand, shows the forced schemes' \
             orders between the two finest `N`: midpoint {}, trapezoidal {}, Gauss–Legendre \
             `s = 2` {}, Gauss-FDE− {}.",
            order("variational midpoint"),
            order("variational trapezoidal"),
            order("Gauss–Legendre s = 2"),
            order("variational FDE−"),
        ),
        format!(
            "The energy balance over a long chaotic run, {steps} midpoint variational steps of \
             `h = {LONG_H}` to `t = {t_end}` (figure `{NAME}-balance.svg`; the trajectory \
             crosses `q = 0`, from well to well, {} times): `E_k` is the Duffing energy at the \
             nodes (`Solution::node_values` of the forced model), `W_k` the work of both forces \
             (`Forced::work`; by parts, the friction took {:.1} and the drive gave {:.1}). \
             `max_k |E_k − E_0 − W_k|` is {first:.2e} over the first half and {second:.2e} over \
             the second ({growth}); at `h = {}` it is {coarse_max:.2e}, {:.1} times the \
             `h = {LONG_H}` figure {fine_max:.2e} (4 for the scheme's `O(h²)`; the two runs \
             follow different chaotic trajectories after a few drive periods, so the ratio \
             compares sizes, not values). On this quartic `L` the midpoint balance holds to the \
             scheme's order, not to round-off as on a quadratic one.",
            long[0].4,
            -fine.friction_work,
            fine.drive_work,
            2.0 * LONG_H,
            coarse_max / fine_max,
        ),
        cost::advice(
            &sweep,
            target,
            "Under a smooth drive the order decides: Gauss–Legendre's order 4 against the \
             second-order symmetric embeddings, and Gauss-FDE−'s order 1 under a friction that \
             reads its one-sided velocity.",
        ),
    ];
    let figures = vec![Figure {
        file: format!("{NAME}-balance.svg"),
        title: format!(
            "Duffing: energy balance E_k − E_0 − W_k, midpoint variational, {steps} steps"
        ),
        x_label: "time t".to_string(),
        y_label: "E_k − E_0 − W_k".to_string(),
        series: vec![
            Series::new(format!("h = {LONG_H}"), fine.miss.clone()),
            Series::new(format!("h = {}", 2.0 * LONG_H), coarse.miss.clone()),
        ],
    }];
    Ok(SceneReport {
        name: NAME,
        title: "Driven Duffing oscillator (chaotic)".to_string(),
        notes,
        tables: vec![table.trim_end().to_string()],
        reference: reference.name.clone(),
        sweep,
        advice_target: Some(target),
        figures,
    })
}
