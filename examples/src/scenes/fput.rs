//! The Fermi–Pasta–Ulam–Tsingou recurrence: the α-FPUT chain of `N = 32` unit masses between
//! fixed walls (`x_0 = x_33 = 0`), unit springs with the cubic term `α = 0.25`,
//! `L = Σ_i ½v_i² − Σ_{i=0}^{32} [½(x_{i+1} − x_i)² + (α/3)(x_{i+1} − x_i)³]`, started with all
//! its energy in the first normal mode, `x_i = A sin(πi/33)`, `v = 0`, `A = 1` (`E ≈ 0.075`):
//! the set-up of Fermi, Pasta, Ulam and Tsingou (Los Alamos report LA-1940, 1955; α = 1/4,
//! N = 32, amplitude 1 is their first run), whose energy does not spread over the modes but
//! returns almost entirely to mode 1 after about 150 of its periods.
//!
//! Normal modes of the linear chain: `a_k = √(2/(N+1)) Σ_i x_i sin(πik/(N+1))` (an orthogonal,
//! symmetric transform), `ω_k = 2 sin(πk/(2(N+1)))`. A mode energy `½(ȧ_k² + ω_k² a_k²)` is
//! measured on the half step between two nodes of a run, from its positions alone,
//! `E_k = ½((a_k' − a_k)/h)² + ½ω_k² a_k a_k'` (`a_k`, `a_k'` at `t_n`, `t_{n+1}`): an `O(h²)`
//! approximation of the mode energy which Störmer–Verlet keeps exactly on the linear chain,
//! so what moves in the figures is the chain's physics, not the measurement.
//!
//! The sweep and tables compare the schemes on `t ∈ [0, 10]` against DOP853 on the
//! hand-written equations of motion; the long runs at `h = 0.1` show the recurrence (the
//! variational Gauss-FDE− scheme from the second-order start, which here is Störmer–Verlet,
//! explicit) and the direct Gauss-FDE− scheme losing the energy (implicit, so run over a
//! shorter time).

use crate::ivp_scene::{Advice, HigherOrderSweeps, IvpScene, Trajectory, Units, all_variants};
use crate::reference::ReferenceCurve;
use crate::scene::{Context, Figure, SceneReport, Series, doubling};
use std::f64::consts::PI;
use varembed::{Embedding, Grid, Lagrangian, Problem, Scheme, Side, Start, Vector, lagrangian};

/// The number of moving particles.
pub const N: usize = 32;

/// The scene's file-name stem.
pub const NAME: &str = "fput";

/// The cubic coefficient of the springs.
pub const ALPHA: f64 = 0.25;

/// The amplitude `A` of the first mode at `t = 0`.
pub const AMPLITUDE: f64 = 1.0;

/// The FPUT spring, `V(d) = d²/2 + α d³/3`.
#[lagrangian(helper)]
pub fn spring(d: f64, alpha: f64) -> f64 {
    0.5 * d * d + alpha / 3.0 * d * d * d
}

/// The α-FPUT chain with fixed ends: the bonds between moving particles in a sum, the two
/// bonds to the walls written out (`x_0 = 0` on the left, `x_{N+1} = 0` on the right).
#[lagrangian]
pub fn fput(x: [f64; N], v: [f64; N], alpha: f64) -> f64 {
    let kinetic = (0..N).map(|i| 0.5 * v[i] * v[i]).sum::<f64>();
    let mut bonds = 0.0;
    for i in 0..N - 1 {
        bonds += spring(x[i + 1] - x[i], alpha);
    }
    kinetic - bonds - spring(x[0], alpha) - spring(-x[N - 1], alpha)
}

/// The model, `α = 0.25`.
pub const MODEL: Fput = Fput { alpha: ALPHA };

/// `[a, b]` of the sweep and tables.
pub const SWEEP_INTERVAL: (f64, f64) = (0.0, 10.0);

/// The step of the long runs.
pub const LONG_H: f64 = 0.1;

/// The mode energies drawn in the figure, `E_1..E_5`.
pub const SHOWN_MODES: usize = 5;

/// `ω_k = 2 sin(πk/(2(N+1)))`, `k = 1..=N`.
pub fn frequency(k: usize) -> f64 {
    2.0 * (PI * k as f64 / (2.0 * (N + 1) as f64)).sin()
}

/// The period `2π/ω_1` of the first mode.
pub fn first_period() -> f64 {
    2.0 * PI / frequency(1)
}

/// The normal-mode transform `a = S x`, `S_{ki} = √(2/(N+1)) sin(πik/(N+1))`, `i, k = 1..=N`
/// (orthogonal and symmetric, so `S` is its own inverse).
pub struct NormalModes {
    s: Vec<f64>,
}

impl Default for NormalModes {
    fn default() -> Self {
        Self::new()
    }
}

impl NormalModes {
    /// The transform's matrix, computed once.
    pub fn new() -> Self {
        let c = (2.0 / (N + 1) as f64).sqrt();
        let s = (0..N * N)
            .map(|m| {
                let (k, i) = (m / N + 1, m % N + 1);
                c * (PI * (i * k) as f64 / (N + 1) as f64).sin()
            })
            .collect();
        NormalModes { s }
    }

    /// The amplitudes `a_k`, `k = 1..=N`, at index `k − 1`.
    pub fn amplitudes(&self, x: &Vector<N>) -> Vector<N> {
        Vector::<N>::from_fn(|k, _| {
            let row = &self.s[k * N..(k + 1) * N];
            row.iter().zip(x.iter()).map(|(s, x)| s * x).sum()
        })
    }

    /// The positions `x = S a` of the amplitudes `a`.
    pub fn positions(&self, a: &Vector<N>) -> Vector<N> {
        // S is symmetric: the same rows.
        self.amplitudes(a)
    }

    /// The mode energies `E_k`, `k = 1..=N` at index `k − 1`, on the half step between nodes
    /// `x` and `x'` a step `h` apart: `½((a_k' − a_k)/h)² + ½ω_k² a_k a_k'`.
    pub fn half_step_energies(&self, x: &Vector<N>, next: &Vector<N>, h: f64) -> Vector<N> {
        half_step_energies(&self.amplitudes(x), &self.amplitudes(next), h)
    }
}

/// The mode energies on the half step between the amplitudes `a` and `b` of two nodes a step
/// `h` apart (see [`NormalModes::half_step_energies`]).
pub fn half_step_energies(a: &Vector<N>, b: &Vector<N>, h: f64) -> Vector<N> {
    Vector::<N>::from_fn(|k, _| {
        let w = frequency(k + 1);
        0.5 * ((b[k] - a[k]) / h).powi(2) + 0.5 * w * w * a[k] * b[k]
    })
}

/// All the energy in mode 1: `x_i = A sin(πi/(N+1))`, `v = 0`.
pub fn initial_data() -> (Vector<N>, Vector<N>) {
    let q = Vector::<N>::from_fn(|i, _| AMPLITUDE * (PI * (i + 1) as f64 / (N + 1) as f64).sin());
    (q, Vector::<N>::zeros())
}

/// `ẍ_i = V'(x_{i+1} − x_i) − V'(x_i − x_{i−1})`, `V'(d) = d + α d²`, walls at 0: written by
/// hand, independent of the macro.
pub fn acceleration(x: &[f64], _: &[f64], _: f64, a: &mut [f64]) {
    let at = |i: usize| if i == 0 || i == N + 1 { 0.0 } else { x[i - 1] };
    let force = |d: f64| d + ALPHA * d * d;
    for i in 1..=N {
        a[i - 1] = force(at(i + 1) - at(i)) - force(at(i) - at(i - 1));
    }
}

/// DOP853 on [`acceleration`] over [`SWEEP_INTERVAL`].
pub fn reference() -> ReferenceCurve<N> {
    let (q0, v0) = initial_data();
    ReferenceCurve::dop853(&acceleration, SWEEP_INTERVAL, q0, v0, 20_000)
}

/// A long run's mode energies and total energy.
pub struct LongRun {
    /// The half-step times `t_n + h/2`.
    pub times: Vec<f64>,
    /// `E_1..E_N` at each half step.
    pub modes: Vec<Vector<N>>,
    /// The total energy at the interior nodes `(t_n, E(Q_n, (Q_{n+1} − Q_{n−1})/(2h)))`: the
    /// model's own energy with the centred velocity (second order for Störmer–Verlet).
    pub energy: Vec<(f64, f64)>,
}

impl LongRun {
    /// Solves `scheme` of Gauss-FDE− from the second-order start on `[0, end]` with step `h`,
    /// and measures it.
    pub fn new(scheme: Scheme, end: f64, h: f64, modes: &NormalModes) -> varembed::Result<Self> {
        let steps = (end / h).round() as usize;
        let grid = Grid::new(0.0, steps as f64 * h, steps)?;
        let problem = Problem::new(&MODEL, grid, Embedding::finite_difference(Side::Backward));
        let (q0, v0) = initial_data();
        let q = problem
            .solve_ivp_with(scheme, q0, v0, Start::SecondOrder)?
            .q;
        let times = (0..steps).map(|n| grid.t(n) + 0.5 * h).collect();
        let amplitudes: Vec<Vector<N>> = q.iter().map(|x| modes.amplitudes(x)).collect();
        let energies = amplitudes
            .windows(2)
            .map(|w| half_step_energies(&w[0], &w[1], h))
            .collect();
        let energy = q
            .windows(3)
            .enumerate()
            .map(|(n, w)| {
                let v = (w[2] - w[0]) / (2.0 * h);
                (grid.t(n + 1), MODEL.energy(&w[1], &v, 0.0))
            })
            .collect();
        Ok(LongRun {
            times,
            modes: energies,
            energy,
        })
    }

    /// `(t, E_k)` of mode `k` (1-based).
    pub fn mode(&self, k: usize) -> Vec<(f64, f64)> {
        self.times
            .iter()
            .zip(&self.modes)
            .map(|(t, e)| (*t, e[k - 1]))
            .collect()
    }

    /// `max_n |E_n − E_0| / E_0` of the total energy.
    pub fn energy_spread(&self) -> f64 {
        let e0 = self.energy[0].1;
        self.energy
            .iter()
            .fold(0.0f64, |m, (_, e)| m.max((e - e0).abs()))
            / e0
    }
}

/// The recurrence as measured on a run: the first minimum of `E_1` and the largest return of
/// `E_1` after it.
#[derive(Clone, Copy, Debug)]
pub struct Recurrence {
    /// `E_1` at the first half step.
    pub initial: f64,
    /// The time and value of the smallest `E_1` before the return.
    pub low: (f64, f64),
    /// The time and value of the largest `E_1` after `low`.
    pub back: (f64, f64),
}

impl Recurrence {
    /// Read off `E_1` of `run`: `low` is the minimum over the first half of the run, `back`
    /// the maximum after it. `None` on a run of fewer than two half steps.
    pub fn of(run: &LongRun) -> Option<Self> {
        let e1 = run.mode(1);
        let initial = e1.first()?.1;
        let half = e1.len() / 2;
        let arg = |s: &[(f64, f64)], better: fn(f64, f64) -> bool| {
            s.iter()
                .copied()
                .reduce(|b, p| if better(p.1, b.1) { p } else { b })
        };
        let low = arg(&e1[..half.max(1)], |a, b| a < b)?;
        let at = e1.iter().position(|p| p.0 >= low.0)?;
        let back = arg(&e1[at..], |a, b| a > b)?;
        Some(Recurrence { initial, low, back })
    }
}

/// The scene's tables and sweep, on [`SWEEP_INTERVAL`].
pub fn scene<'a>(cx: &Context, reference: &'a ReferenceCurve<N>) -> IvpScene<'a, Fput, N> {
    let (q0, v0) = initial_data();
    IvpScene {
        name: NAME,
        title: "FPUT recurrence (α-FPUT, N = 32)",
        notes: vec![
            "α-FPUT chain of 32 unit masses and springs between fixed walls, `α = 0.25`, all the \
             energy in mode 1 at amplitude 1 (`E ≈ 0.075`), the first run of Fermi, Pasta, Ulam \
             and Tsingou (1955). Sweep and tables on `t ∈ [0, 10]`, errors against DOP853 on \
             the hand-written equations of motion; the long runs below use `h = 0.1`."
                .to_string(),
        ],
        lagrangian: &MODEL,
        interval: SWEEP_INTERVAL,
        q0,
        v0,
        reference,
        exact: false,
        table_n: cx.pick(200, 100),
        table_embeddings: vec![
            Embedding::finite_difference(Side::Backward),
            Embedding::midpoint(),
            Embedding::trapezoidal(),
        ],
        sweep: doubling(50, cx.pick(6, 4)),
        variants: all_variants(HigherOrderSweeps {
            // Holds the tables' N and 2N: their midpoint and trapezoidal rows are read off it.
            second_order: doubling(50, cx.pick(5, 3)),
            gauss2: doubling(10, cx.pick(5, 3)),
            // Order 8 on this slow motion reaches DOP853's floor (about 1e-12) by N = 8: its
            // line starts at one step over [0, 10].
            gauss4: doubling(1, cx.pick(3, 3)),
        }),
        trajectory: Trajectory::Components(&[0, 15]),
        units: Units {
            time: "√(m/κ)",
            position: "ℓ, the length in which α = 0.25",
            energy: "κℓ²",
        },
        advice: Advice {
            target: 1e-8,
            why: "On this slow motion (ω_1 ≈ 0.095, the excited modes below 0.5) the order decides at this accuracy, and a Gauss–Legendre step, a Newton solve of s × 32 unknowns, covers a long h. The chain is separable, `½|v|² − U(x)`, so the variational Gauss-FDE− scheme from the second-order start is Störmer–Verlet: explicit, second order, its energy bounded, the cheap choice at the accuracy of the long runs below (10⁵ steps in a few hundredths of a second).",
        },
    }
}

/// The scene: the sweep, then the long runs of both Gauss-FDE− schemes.
pub fn run(cx: &Context) -> varembed::Result<SceneReport> {
    let reference = reference();
    let mut report = scene(cx, &reference).run(cx)?;
    let modes = NormalModes::new();
    // The recurrence needs about 153 periods of mode 1; the direct scheme, implicit, is run
    // only as long as it takes to lose most of its energy.
    let (end, direct_end) = (cx.pick(11_000.0, 11_000.0), cx.pick(1000.0, 300.0));
    cx.progress.inc_length(2);
    let variational = LongRun::new(Scheme::Variational, end, LONG_H, &modes)?;
    cx.record(NAME, "long run, variational", variational.times.len());
    let direct = LongRun::new(Scheme::Direct, direct_end, LONG_H, &modes)?;
    cx.record(NAME, "long run, direct", direct.times.len());
    let period = first_period();
    let recurrence = Recurrence::of(&variational);
    if let Some(r) = &recurrence {
        report.notes.push(format!(
            "Recurrence (figure `fput-modes.svg`, variational, `h = {LONG_H}`): `E_1` falls to \
             {:.1} % of its start at t = {:.0} ({:.0} periods of mode 1, `2π/ω_1 = {period:.1}`), \
             the energy spread over modes 2–5 and back, and returns to {:.1} % at t = {:.0} \
             ({:.1} periods); the total energy stays within {:.1e} of its start (relative). \
             The recurrence time settles as `h` shrinks (measured when the scene was written: \
             t = 10131, 10149, 10195, 10346 at h = 0.025, 0.05, 0.1, 0.2).",
            100.0 * r.low.1 / r.initial,
            r.low.0,
            r.low.0 / period,
            100.0 * r.back.1 / r.initial,
            r.back.0,
            r.back.0 / period,
            variational.energy_spread()
        ));
    }
    let relative = |run: &LongRun| -> Vec<(f64, f64)> {
        let e0 = run.energy[0].1;
        run.energy.iter().map(|(t, e)| (*t, e / e0)).collect()
    };
    let direct_left = direct.energy.last().map_or(f64::NAN, |(_, e)| *e) / direct.energy[0].1;
    report.notes.push(format!(
        "Direct against variational: the direct Gauss-FDE− scheme is dissipative (on the \
         oscillator its amplitude shrinks by `(1 + ω²h²)^(−1/2)` per step), so the chain loses \
         its energy instead of passing it between modes: after t = {direct_end:.0} it keeps \
         {:.0} % of it (figure `fput-energy-long.svg`; its `E_1` is `E1, direct` in \
         `fput-modes.svg`). The variational scheme conserves the energy to {:.1e} \
         over the whole run.",
        100.0 * direct_left,
        variational.energy_spread()
    ));
    let mut series: Vec<Series> = (1..=SHOWN_MODES)
        .map(|k| Series::new(format!("E{k}, variational"), variational.mode(k)))
        .collect();
    series.push(Series::new("E1, direct", direct.mode(1)));
    let figures = [
        Figure {
            file: "fput-modes.svg".to_string(),
            title: format!(
                "FPUT: energies E_1..E_{SHOWN_MODES} of the normal modes, Gauss-FDE−, h = \
                 {LONG_H}, variational to t = {end:.0}, direct to t = {direct_end:.0}"
            ),
            x_label: "time t (√(m/κ))".to_string(),
            y_label: "mode energy E_k (κℓ²)".to_string(),
            series,
        },
        Figure {
            file: "fput-energy-long.svg".to_string(),
            title: format!("FPUT: total energy E(t) / E(0), Gauss-FDE−, h = {LONG_H}"),
            x_label: "time t (√(m/κ))".to_string(),
            y_label: "E(t) / E(0) (dimensionless)".to_string(),
            series: vec![
                Series::new("direct", relative(&direct)),
                Series::new("variational", relative(&variational)),
            ],
        },
    ];
    // The advice closes the notes: after the two (or, without a recurrence, one) just added.
    let added = if recurrence.is_some() { 2 } else { 1 };
    let advice = report.notes.remove(report.notes.len() - 1 - added);
    report.notes.push(advice);
    report.figures.extend(figures);
    Ok(report)
}
