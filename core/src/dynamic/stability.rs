//! The linear stability of a run-time-dimension model's recurrence, checked before its first
//! step, without the `2d × 2d` eigenproblem of the const-generic check.
//!
//! On a model whose modes decouple, `L = ½ m|v|² − U(x, t)` (`∂²L/∂v² = m I`, `m > 0`, and
//! `∂²L/∂x∂v = 0` at every point, no generalised force; `m` is what makes `c L` decouple as
//! `L` does, with the same `K`), every classical step kind linearised at a state acts mode by
//! mode: with `κ` an eigenvalue of `K = −∂²L/∂x² / m = U″/m` there, the step map on that mode
//! is the kind's step map on the harmonic oscillator of frequency `ω = √κ`. The const-generic
//! verdict flags that map beyond the kind's limit `hω = z*` (2 for Störmer–Verlet, whose step
//! map then has a real eigenvalue `λ < −1`, the sawtooth mode of an under-resolved step; `√3`
//! for the direct σ = + step, whose eigenvalues reach modulus 2 there; none for the A-stable
//! ones). So, for the modes with `κ ≥ 0`, the run linearised at its initial data is flagged
//! exactly when the largest eigenvalue of `K` exceeds `z*²/h²` (the steps read `K` at `Q_1` or
//! at midpoints, the same to `O(h)`, exactly for a quadratic `U`; an inverted mode, `κ < 0`,
//! which the const-generic verdict may flag, is not looked at). Two bounds decide that in
//! `O(nnz)` work per product with `K`:
//!
//! - Gershgorin: every eigenvalue of the symmetric `K` lies below its largest absolute row sum
//!   `G`, so `h² G ≤ z*²` proves the step stable at once (every run well inside the limit);
//! - a Rayleigh quotient `xᵀKx / xᵀx` never exceeds the largest eigenvalue, so once one
//!   exceeds `z*²/h²` the step is unstable. The quotients come from power iteration on
//!   `K + G I` (its spectrum in `[0, 2G]`, the largest eigenvalue of `K` its largest), from
//!   the alternating vector `(−1)^i`, the shape of a chain's highest mode.
//!
//! The check reports only what it proves: between the two bounds, after its iterations, it
//! gives no verdict, and the blow-up guard watches the run as before. A model whose modes do
//! not decouple gets no check here.
//!
//! The same linearisation at the initial data gives the resolution check
//! ([`resolution_warning`]): the const-generic path's power iteration on the sparse blocks,
//! skipped when a norm bound already proves the step resolved.

use std::sync::OnceLock;

use nalgebra::Complex;

use crate::lagrangian::{Dependence, HessianDependence, Matrix};
use crate::solve::resolution::{dominant_rate, proved_resolved, under_resolved};
use crate::solve::solution::Warning;
use crate::solve::stability::{Verdict, oscillator_limit, oscillator_step_map, step_map_verdict};
use crate::step::StepKind;

use super::band::BandSystem;
use super::sparse::{SparseBlock, SparseHessian};

/// Power iterations before the check gives no verdict.
const ITERATIONS: usize = 64;

/// The verdict at the initial data of a run of `kind` with step `h`, for a model whose modes
/// decouple (module docs) with the mass `m` ([`decoupled_mass`]) and `xx = ∂²L/∂x²` there (its
/// entries listed): the flagged eigenvalue of the step map on the mode of the best Rayleigh
/// quotient `κ` of `K = −xx/m` found above `z*²/h²`, and the largest stable step `z*/√κ` that
/// quotient gives; `None` when no instability is proven.
pub(crate) fn mode_unstable(
    kind: StepKind,
    (mass, xx): (f64, &SparseBlock),
    h: f64,
) -> Option<(Complex<f64>, f64)> {
    let limit = oscillator_limit_of(kind)?;
    // The quotients of `−xx` are `m` times those of `K`: a model and its multiples `c L` get
    // the same `κ`, and the same verdict.
    let kappa = rayleigh_quotient_above(xx, mass * (limit / h) * (limit / h))? / mass;
    // The mode's map is the unit oscillator's with the step `z = h√κ`.
    let z = h * kappa.sqrt();
    let (a, b) = oscillator_step_map(kind, z)?;
    match step_map_verdict(&Matrix::<1>::new(a), &Matrix::<1>::new(b), z) {
        Verdict::Unstable(lambda) => Some((lambda, limit / kappa.sqrt())),
        Verdict::Stable | Verdict::Undecided => None,
    }
}

/// The mass `m > 0` of a model whose modes decouple (module docs): `∂²L/∂v²` and `∂²L/∂x∂v`
/// depend on nothing (`dependence`), no generalised force (`forced`), and at the initial data
/// (`hessian`, entries listed) they are `m I` and zero; `None` for any other model.
pub(crate) fn decoupled_mass(
    hessian: &SparseHessian,
    dependence: &HessianDependence,
    forced: bool,
) -> Option<f64> {
    let decouple = !forced
        && dependence.vv == Dependence::NONE
        && dependence.xv == Dependence::NONE
        && hessian.xv.is_zero();
    let mass = hessian.vv.as_multiple_of_identity().filter(|_| decouple)?;
    (mass > 0.0 && mass.is_finite()).then_some(mass)
}

/// [`oscillator_limit`] of `kind`, computed once per process (a scan and a bisection of the
/// one-dimensional step map); `None` for the kinds without a limit.
fn oscillator_limit_of(kind: StepKind) -> Option<f64> {
    static LIMITS: OnceLock<Vec<(StepKind, Option<f64>)>> = OnceLock::new();
    let limits = LIMITS.get_or_init(|| {
        StepKind::ALL
            .iter()
            .map(|&kind| (kind, oscillator_limit(kind)))
            .collect()
    });
    let limit = limits.iter().find(|(k, _)| *k == kind)?.1?;
    (limit > 0.0).then_some(limit)
}

/// A Rayleigh quotient of `K = −xx` (entries listed) proven above `limit` (by a margin for
/// its rounding), from the power iteration of the module docs; `None` when Gershgorin's bound
/// is within `limit` or no quotient clearly exceeds it.
fn rayleigh_quotient_above(xx: &SparseBlock, limit: f64) -> Option<f64> {
    let d = xx.dimension();
    // K = −L_xx; a repeated entry is summed by the products below.
    let entries = xx.entries();
    let mut row_sums = vec![0.0; d];
    for &(i, _, c) in entries {
        row_sums[i] += c.abs();
    }
    let bound = row_sums.iter().fold(0.0f64, |m, &s| m.max(s));
    drop(row_sums);
    if !bound.is_finite() || bound <= limit {
        return None;
    }
    let product = |x: &[f64], y: &mut [f64]| {
        y.fill(0.0);
        for &(i, j, c) in entries {
            y[i] -= c * x[j];
        }
    };
    let mut v: Vec<f64> = (0..d)
        .map(|i| {
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            sign * (1.0 + 0.1 * (i as f64 + 1.0).sin())
        })
        .collect();
    let mut kv = vec![0.0; d];
    let mut best = f64::NEG_INFINITY;
    for _ in 0..ITERATIONS {
        product(&v, &mut kv);
        let norm2: f64 = v.iter().map(|c| c * c).sum();
        let quotient = v.iter().zip(&kv).map(|(a, b)| a * b).sum::<f64>() / norm2;
        if !quotient.is_finite() {
            break;
        }
        best = best.max(quotient);
        // v ← (K + G I) v, normalised.
        let mut norm = 0.0f64;
        for (v, k) in v.iter_mut().zip(&kv) {
            *v = k + bound * *v;
            norm = norm.max(v.abs());
        }
        if norm == 0.0 || !norm.is_finite() {
            break;
        }
        v.iter_mut().for_each(|c| *c /= norm);
    }
    // A margin for the rounding of the quotient: only a clear excess is reported.
    (best > limit * (1.0 + 1e-9)).then_some(best)
}

/// [`Warning::UnderResolved`] when the step `h` does not resolve the fastest rate of the
/// equation linearised at the initial data, from its blocks `hessian` there (entries listed)
/// and `vv`, `∂²L/∂v²` there factorised. When `∂²L/∂v²` is diagonal (every `½ vᵀMv` with
/// diagonal `M`), a norm bound on `K = (∂²L/∂v²)⁻¹(−∂²L/∂x²)` from one pass over the entries
/// proves most runs resolved without the power iteration ([`proved_resolved`]).
pub(crate) fn resolution_warning(
    hessian: &SparseHessian,
    vv: &mut BandSystem,
    h: f64,
    stages: usize,
) -> Option<Warning> {
    if diagonal_mass_bound(hessian).is_some_and(|bound| proved_resolved(bound, h, stages)) {
        return None;
    }
    under_resolved(fastest_rate(&hessian.xx, vv)?, h, stages)
}

/// `√(‖K‖₁ ‖K‖∞) ≥ ‖K‖₂` for `K = (∂²L/∂v²)⁻¹(−∂²L/∂x²)` when `∂²L/∂v²` is diagonal (its
/// listed entries off the diagonal all zero); `None` otherwise, or when a diagonal entry is
/// zero. Repeated entries add their moduli, which only raises the bound.
fn diagonal_mass_bound(hessian: &SparseHessian) -> Option<f64> {
    let d = hessian.vv.dimension();
    let mut mass = vec![0.0; d];
    for &(i, j, value) in hessian.vv.entries() {
        if i == j {
            mass[i] += value;
        } else if value != 0.0 {
            return None;
        }
    }
    if mass.contains(&0.0) {
        return None;
    }
    let (mut rows, mut columns) = (vec![0.0; d], vec![0.0; d]);
    for &(i, j, value) in hessian.xx.entries() {
        let entry = (value / mass[i]).abs();
        rows[i] += entry;
        columns[j] += entry;
    }
    let largest = |x: &[f64]| x.iter().fold(0.0f64, |m, &c| m.max(c));
    Some((largest(&rows) * largest(&columns)).sqrt())
}

/// The fastest rate `ω = √|μ|` of the equation linearised at a state, `μ` the eigenvalue of
/// largest modulus of `(∂²L/∂v²)⁻¹(−∂²L/∂x²)`, from `xx = ∂²L/∂x²` there (its entries listed)
/// and `vv`, `∂²L/∂v²` there factorised: the const-generic path's power iteration, each product
/// a pass over the entries of `xx` and a band solve (`O(d b)`). `None` when a product is not
/// finite.
fn fastest_rate(xx: &SparseBlock, vv: &mut BandSystem) -> Option<f64> {
    let entries = xx.entries();
    dominant_rate(xx.dimension(), |y, out| {
        out.fill(0.0);
        for &(i, j, c) in entries {
            out[i] -= c * y[j];
        }
        vv.solve_in_place(out);
        Some(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamic::DynLagrangian;
    use crate::dynamic::sparse::SparseHessian;

    /// `n` unit masses on linear springs between two walls: `K = tridiag(−1, 2, −1)`, whose
    /// eigenvalues are `2 − 2 cos(kπ/(n + 1))`, the largest below the Gershgorin bound 4.
    struct Springs {
        n: usize,
    }

    impl DynLagrangian for Springs {
        fn dimension(&self) -> usize {
            self.n
        }
        fn value(&self, x: &[f64], v: &[f64], _t: f64) -> f64 {
            let n = self.n;
            let stretch: f64 = (0..=n)
                .map(|i| {
                    let right = if i < n { x[i] } else { 0.0 };
                    let left = if i > 0 { x[i - 1] } else { 0.0 };
                    (right - left).powi(2)
                })
                .sum();
            0.5 * v.iter().map(|v| v * v).sum::<f64>() - 0.5 * stretch
        }
        fn force(&self, x: &[f64], _v: &[f64], _t: f64, f: &mut [f64]) {
            let n = self.n;
            for i in 0..n {
                let left = if i > 0 { x[i - 1] } else { 0.0 };
                let right = if i + 1 < n { x[i + 1] } else { 0.0 };
                f[i] = left - 2.0 * x[i] + right;
            }
        }
        fn momentum(&self, _x: &[f64], v: &[f64], _t: f64, p: &mut [f64]) {
            p.copy_from_slice(v);
        }
        fn hessian(&self, _x: &[f64], _v: &[f64], _t: f64, out: &mut SparseHessian) {
            for i in 0..self.n {
                out.vv.add(i, i, 1.0);
                out.xx.add(i, i, -2.0);
                if i + 1 < self.n {
                    out.xx.add(i, i + 1, 1.0);
                    out.xx.add(i + 1, i, 1.0);
                }
            }
        }
    }

    #[test]
    fn only_a_proven_instability_is_reported_with_its_eigenvalue() {
        let n = 20;
        let springs = Springs { n };
        let x = vec![0.0; n];
        let mut hessian = SparseHessian::new(n);
        springs.hessian(&x, &x, 0.0, &mut hessian);
        let dependence = HessianDependence {
            xx: Dependence::ALL,
            xv: Dependence::NONE,
            vv: Dependence::NONE,
        };
        assert_eq!(decoupled_mass(&hessian, &dependence, false), Some(1.0));
        assert_eq!(
            decoupled_mass(&hessian, &HessianDependence::ALL, false),
            None
        );
        assert_eq!(decoupled_mass(&hessian, &dependence, true), None);
        let xx = &hessian.xx;
        let verlet = StepKind::VariationalBackward;
        let largest = 2.0 - 2.0 * (n as f64 * std::f64::consts::PI / (n as f64 + 1.0)).cos();
        // Inside Gershgorin's bound: proven stable without an iteration.
        assert_eq!(mode_unstable(verlet, (1.0, xx), 0.99), None);
        // Between the largest eigenvalue and the bound: stable, and never reported.
        let h = (4.0 / (0.5 * (largest + 4.0))).sqrt();
        assert_eq!(mode_unstable(verlet, (1.0, xx), h), None);
        // Beyond the largest eigenvalue: the sawtooth mode's eigenvalue, from within, and a
        // largest stable step at most 1 % above the exact `2/√κ_max`.
        let h = (4.0 / (largest - 0.05)).sqrt();
        let mu = h * h * largest;
        let exact = ((2.0 - mu) - ((2.0 - mu).powi(2) - 4.0).sqrt()) / 2.0;
        let (reported, step) = mode_unstable(verlet, (1.0, xx), h).expect("unstable");
        assert!(
            exact <= reported.re
                && reported.re < -1.0
                && reported.re - exact < 0.01 * exact.abs()
                && reported.im == 0.0,
            "{reported} against {exact}"
        );
        // `c L` (mass `c`, blocks `c xx`) gets the same verdict.
        for c in [1e-9, 1e9] {
            let mut scaled = SparseBlock::new(n);
            xx.entries()
                .iter()
                .for_each(|&(i, j, v)| scaled.add(i, j, c * v));
            let (lambda, step_c) = mode_unstable(verlet, (c, &scaled), h).expect("unstable");
            assert!(
                (lambda - reported).norm() <= 1e-12 * reported.norm(),
                "c = {c:e}"
            );
            assert!((step_c - step).abs() <= 1e-12 * step, "c = {c:e}");
        }
        let limit = 2.0 / largest.sqrt();
        assert!(
            limit <= step && step < 1.01 * limit,
            "{step} against {limit}"
        );
    }

    /// The kinds' limits on the chain: the direct σ = + step from `h√κ = √3` with an
    /// eigenvalue of modulus 2 or more (`λ = 1 ± i h√κ`), the direct midpoint one from 2, the
    /// A-stable kinds never; each reported only past its own limit.
    #[test]
    fn each_kind_is_checked_against_its_own_limit() {
        let n = 20;
        let x = vec![0.0; n];
        let mut hessian = SparseHessian::new(n);
        Springs { n }.hessian(&x, &x, 0.0, &mut hessian);
        let largest = 2.0 - 2.0 * (n as f64 * std::f64::consts::PI / (n as f64 + 1.0)).cos();
        let at = |z: f64| z / largest.sqrt();
        let cases = [
            (StepKind::DirectForward, Some(3f64.sqrt())),
            (StepKind::MidpointDirect, Some(2.0)),
            (StepKind::TrapezoidalVariational, Some(2.0)),
            (StepKind::DirectBackward, None),
            (StepKind::MidpointVariational, None),
        ];
        for (kind, limit) in cases {
            match limit {
                Some(z) => {
                    assert_eq!(
                        mode_unstable(kind, (1.0, &hessian.xx), at(0.97 * z)),
                        None,
                        "{kind:?}"
                    );
                    let (lambda, _) = mode_unstable(kind, (1.0, &hessian.xx), at(1.03 * z))
                        .unwrap_or_else(|| panic!("{kind:?} past its limit"));
                    assert!(
                        lambda.norm() >= 2.0 || lambda.re < -1.0,
                        "{kind:?}: {lambda}"
                    );
                }
                None => assert_eq!(
                    mode_unstable(kind, (1.0, &hessian.xx), at(50.0)),
                    None,
                    "{kind:?}"
                ),
            }
        }
        let h = at(1.03 * 3f64.sqrt());
        let (lambda, _) = mode_unstable(StepKind::DirectForward, (1.0, &hessian.xx), h).unwrap();
        let z = h * largest.sqrt();
        assert!((lambda.re - 1.0).abs() < 0.02 && (lambda.im.abs() - z).abs() < 0.02 * z);
    }
}
