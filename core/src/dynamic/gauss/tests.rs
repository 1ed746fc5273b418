//! The stage system of the run-time Gauss–Legendre integrators against finite differences,
//! and the band of its interleaved order.

use super::*;
use crate::dynamic::sparse::SparseBlock;
use crate::test_models::{DYN_MIXED_DIMENSION, DynMixed};

const D: usize = DYN_MIXED_DIMENSION;

/// The stage Jacobian, solved against unit vectors, equals central differences of the
/// stage residual for every s (the band's storage and the interleaved order included).
#[test]
fn stage_jacobian_matches_finite_differences() {
    let qk: Vec<f64> = (0..D).map(|i| 0.3 - 0.2 * i as f64).collect();
    let pk: Vec<f64> = (0..D).map(|i| 0.1 * i as f64 - 0.4).collect();
    let (tk, h) = (0.2, 0.15);
    for s in 1..=4 {
        let fresh = || {
            let v0 = vec![0.0; D];
            let mut system = StageSystem::new(
                &DynMixed { forced: true },
                GaussTableau::new(s),
                h,
                &v0,
                NewtonOptions::default(),
            );
            for (k, v) in system.v.iter_mut().enumerate() {
                *v = 0.5 + 0.1 * k as f64 - 0.07 * (k * k % 5) as f64;
            }
            system
        };
        let mut system = fresh();
        assert!(system.evaluate(&qk, tk));
        let (_, regular) = system.factorize_jacobian();
        assert!(regular);
        let width = s * D;
        let eps = 1e-6;
        for col in 0..width {
            let residual = |delta: f64| {
                let mut other = fresh();
                other.v[col] += delta;
                assert!(other.evaluate(&qk, tk));
                other.residual(&pk);
                other.rhs
            };
            let (plus, minus) = (residual(eps), residual(-eps));
            // J e_col by differences, then J⁻¹ (J e_col) through the factors: e_col.
            let mut column: Vec<f64> = plus
                .iter()
                .zip(&minus)
                .map(|(p, m)| (p - m) / (2.0 * eps))
                .collect();
            let (band_system, _) = system.system.as_mut().unwrap();
            band_system.solve_in_place(&mut column);
            for (row, x) in column.iter().enumerate() {
                let expected = if row == col { 1.0 } else { 0.0 };
                assert!((x - expected).abs() < 1e-6, "s = {s} ({row}, {col}): {x}");
            }
        }
    }
}

/// The interleaved order gives a chain's stage Jacobian the half-width `s (b + 1) − 1`.
#[test]
fn a_chain_stage_system_has_half_width_s_b_plus_s_minus_one() {
    let d = 40;
    let mut chain = SparseBlock::new(d);
    for i in 0..d - 1 {
        chain.add(i, i + 1, 1.0);
        chain.add(i + 1, i, 1.0);
        chain.add(i, i, 2.0);
    }
    for s in 1..=4 {
        let (system, reordered) = BandSystem::interleaved(d, s, Some(1), &[&chain]);
        assert_eq!((system.band(), reordered), (2 * s - 1, false), "s = {s}");
    }
}
