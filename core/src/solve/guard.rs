//! The blow-up guard of the initial value problems: growth of the discrete energy beyond what
//! the early run shows.
//!
//! The stability check of the IVP loop reads the eigenvalues of the linearised step map; it
//! cannot see a double eigenvalue `−1` (Störmer–Verlet at `ωh = 2` exactly, whose nodes grow
//! linearly) nor a nonlinear blow-up such as a spherical pendulum passing near its pole. Both
//! show as growth of the energy `E = v·∂L/∂v − L`, which the flow of an autonomous Lagrangian
//! conserves. Oscillation is not growth: the discrete energy of a variational scheme
//! oscillates with an amplitude that depends on `h` (by a factor of hundreds near `ωh = 2`),
//! and the direct Gauss-FDE− scheme loses energy by design. So the guard compares each
//! window's *gain* of energy with the gain of the first window (the early run), and ignores
//! losses.
//!
//! # The rule
//!
//! Every `s`-th step (`s` = the largest power of two ≤ `N/1024`, clamped to `1..=64`, so that
//! short runs still get samples and long ones pay for one energy evaluation in 64 steps) the
//! guard evaluates `E_j` and `K_j = |v·∂L/∂v|` at the quadrature node of the step just taken
//! (`(Q_{n−1}, (Q_{n−1} − Q_{n−2})/h)` for σ = −, `(Q_{n−2}, …)` for σ = +; for the symmetric
//! embeddings where their discrete Lagrangian evaluates `L` on the interval
//! `[Q_{n−2}, Q_{n−1}]`: at its midpoint, or the mean of its two ends; the Gauss–Legendre
//! integrators, which have no velocity at the nodes, at the first stage `(Q_1, V_1)` of the
//! step, a point of the step's collocation polynomial). In the three-point recurrences the
//! step's momentum evaluates `∂L/∂v` at that point anyway: it takes `L` from the same
//! evaluation (`value_and_gradient`), so a sample costs little more than the step; a
//! Gauss–Legendre sample evaluates `L` and `∂L/∂v` at its stage. The gain of a
//! sample is `g_j = (E_j − E_0) · sign(v·∂L/∂v)`: the growth of energy in the direction of the
//! kinetic term (positive kinetic energy: an increase; a Lagrangian multiplied by −1 gives the
//! same dynamics and the same gains). Samples are grouped in windows of
//! [`WINDOW`] samples; `G_w` is the largest gain in window `w`. With `G_1` the early gain,
//! window `w ≥ 2` is a blow-up when
//!
//! ```text
//! G_w > max( GROWTH · G_1,  SCALE_FRACTION · max_{j so far} K_j,  round-off )
//! ```
//!
//! with [`GROWTH`]` = 16`, [`SCALE_FRACTION`]` = 0.1`, and the round-off floor
//! `1024 ε · max_j (|E_j| + ‖Q‖∞ ‖∂L/∂v‖∞ / h)` (the cancellation in `(Q_{n−1} − Q_{n−2})/h`;
//! a stage velocity has none, and its floor is `1024 ε · max_j |E_j|`).
//! The second term keeps an early window that is short against the motion's period (small
//! gain early, larger later at the same relative accuracy) from tripping the first; it costs
//! nothing against a real blow-up, whose gain is of the order of the kinetic term itself.
//! The last, partial window is checked too.
//!
//! A direct scheme drifts by design: Gauss-FDE− loses energy (never a gain, so never flagged),
//! Gauss-FDE+ gains it at a steady rate (its oscillations grow by `√(1 + ω²h²)` per step). For
//! the direct schemes `G_1` is therefore extrapolated linearly, `G_1 · (n_w − n_0)/(n_1 − n_0)`
//! at the end `n_w` of window `w` (`n_0` the first sample, `n_1` the end of the first window):
//! a steady drift passes until it has compounded to about `e⁴` (where `eˣ − 1 = 16x`), and
//! growth faster than the early run's by a factor 16 is flagged.
//!
//! Where the energy is sampled matters for the midpoint scheme: it is A-stable, and at `ωh ≫ 1`
//! the energy at a node with the interval's velocity swings by a relative `O(1/(ωh)²)` over a
//! beat of the nodes, which a short early window does not see; its energy at the interval's
//! midpoint is exactly conserved on a linear system (the Cayley transform is an isometry of the
//! energy norm, and the midpoint is the mean of two points of one orbit).
//!
//! Non-autonomous Lagrangians (`dependence().t`) and forced ones (`is_forced()`) are not
//! guarded: their energy is not
//! conserved, and growth of the energy, of `‖Q‖` or of the momenta is what a driven
//! oscillator at resonance or a parametrically excited one (Mathieu) does physically. No
//! growth rule tells that apart from a numerical blow-up, and a guard that flagged physics as
//! an error would be a wrong answer of its own. The stability check and
//! [`Error::NotFinite`] still apply to them.

use crate::error::{Error, Result};
use crate::lagrangian::{Lagrangian, Vector};

/// Samples per window.
pub(crate) const WINDOW: usize = 16;
/// How many times the early gain a later window's gain must exceed.
pub(crate) const GROWTH: f64 = 16.0;
/// The fraction of the largest `|v·∂L/∂v|` seen a gain must exceed.
pub(crate) const SCALE_FRACTION: f64 = 0.1;
/// The largest stride between two samples.
pub(crate) const MAX_STRIDE: usize = 64;

/// The state of the guard over one run (see the module docs).
pub(crate) struct BlowUpGuard {
    enabled: bool,
    /// Whether the scheme drifts by design (the direct schemes): the early gain is then
    /// extrapolated linearly in the number of steps.
    drifts: bool,
    /// The step of the first sample.
    first: usize,
    stride: usize,
    /// `E_0`, the first sample's energy.
    e0: f64,
    /// The early gain `G_1` and the last step of the first window, once it is complete.
    early: Option<(f64, usize)>,
    /// The largest `|v·p|` so far.
    kinetic: f64,
    /// The round-off scale so far.
    round_off: f64,
    /// The current window: its first step, its last step, its largest gain, its samples.
    window: (usize, usize, f64, usize),
    samples: usize,
}

impl BlowUpGuard {
    /// The guard of a run of `n_steps` steps of `lagrangian`;
    /// `enabled` off (or a Lagrangian that depends on `t`, or one under a generalised force:
    /// the energy is not conserved) makes every sample a no-op.
    pub(crate) fn new<L: Lagrangian<D> + ?Sized, const D: usize>(
        lagrangian: &L,
        drifts: bool,
        n_steps: usize,
        enabled: bool,
    ) -> Self {
        let conserved = !lagrangian.dependence().t && !lagrangian.is_forced();
        Self::watching(drifts, n_steps, enabled && conserved)
    }

    /// The guard of a run of `n_steps` steps, watching when `enabled` (which the caller has
    /// already turned off for a Lagrangian that depends on `t`).
    pub(crate) fn watching(drifts: bool, n_steps: usize, enabled: bool) -> Self {
        let stride = (n_steps / 1024).clamp(1, MAX_STRIDE);
        BlowUpGuard {
            enabled,
            drifts,
            first: 0,
            stride: 1 << stride.ilog2(),
            e0: 0.0,
            early: None,
            kinetic: 0.0,
            round_off: 0.0,
            window: (0, 0, 0.0, 0),
            samples: 0,
        }
    }

    /// Whether the run is watched: off by the option, or for a Lagrangian that depends on `t`.
    pub(crate) fn is_enabled(&self) -> bool {
        self.enabled
    }

    /// Steps between two samples: a power of two no larger than [`MAX_STRIDE`], so it divides
    /// the stability check's interval.
    pub(crate) fn stride(&self) -> usize {
        self.stride
    }

    /// Samples the energy of the step from `a = Q_{n−2}`, `b = Q_{n−1}` at step `n`, from
    /// `L` and `p = ∂L/∂v` at the step's energy point (means over the trapezoid's two ends),
    /// which the step's momentum evaluated; a window that ends here is checked.
    pub(crate) fn sample<const D: usize>(
        &mut self,
        (value, p): (f64, Vector<D>),
        a: &Vector<D>,
        b: &Vector<D>,
        inv_h: f64,
        n: usize,
    ) -> Result<()> {
        if !self.enabled {
            return Ok(());
        }
        let vp = ((b - a) * inv_h).dot(&p);
        let e = vp - value;
        let x_scale = a.amax().max(b.amax());
        self.record(e, vp, e.abs() + x_scale * p.amax() * inv_h, n)
    }

    /// Samples the energy at the state `(x, v, t)` at step `n`: what a one-step integrator
    /// (Gauss–Legendre, whose stages carry their own velocities) calls directly. A stage
    /// velocity is no difference quotient, so the round-off floor is that of `E` alone.
    #[cold]
    #[inline(never)]
    pub(crate) fn sample_state<L: Lagrangian<D> + ?Sized, const D: usize>(
        &mut self,
        lagrangian: &L,
        x: &Vector<D>,
        v: &Vector<D>,
        t: f64,
        n: usize,
    ) -> Result<()> {
        if !self.enabled {
            return Ok(());
        }
        let (value, _, p) = lagrangian.value_and_gradient(x, v, t);
        let vp = v.dot(&p);
        let e = vp - value;
        self.record(e, vp, e.abs(), n)
    }

    /// Records a sample: the energy `e`, `v·∂L/∂v = vp` and the round-off scale of `e`, at
    /// step `n`; a window that ends here is checked.
    pub(crate) fn record(&mut self, e: f64, vp: f64, scale: f64, n: usize) -> Result<()> {
        // A sample outside the Lagrangian's domain gives no verdict; the step itself reports it.
        if !e.is_finite() {
            return Ok(());
        }
        if self.samples == 0 {
            self.e0 = e;
            self.first = n;
            self.window = (n, n, 0.0, 0);
        }
        self.samples += 1;
        self.kinetic = self.kinetic.max(vp.abs());
        self.round_off = self.round_off.max(1024.0 * f64::EPSILON * scale);
        let gain = (e - self.e0) * vp.signum();
        let (from, _, largest, count) = self.window;
        self.window = (from, n, largest.max(gain), count + 1);
        if count + 1 == WINDOW {
            self.close_window()?;
        }
        Ok(())
    }

    /// Checks the last, partial window of the run.
    pub(crate) fn finish(&mut self) -> Result<()> {
        if self.enabled && self.window.3 > 0 {
            self.close_window()?;
        }
        Ok(())
    }

    /// Checks the current window against the rule and starts the next one.
    fn close_window(&mut self) -> Result<()> {
        let (from, to, gain, _) = self.window;
        self.window = (to + self.stride, to + self.stride, 0.0, 0);
        let Some((early, early_to)) = self.early else {
            self.early = Some((gain.max(0.0), to));
            return Ok(());
        };
        let extrapolated = if self.drifts {
            early * (to - self.first) as f64 / (early_to - self.first).max(1) as f64
        } else {
            early
        };
        let threshold = (GROWTH * extrapolated)
            .max(SCALE_FRACTION * self.kinetic)
            .max(self.round_off);
        if gain > threshold {
            return Err(Error::BlowUp {
                from,
                to,
                growth: gain / early.max(self.round_off),
            });
        }
        Ok(())
    }
}
