//! Boundary value problems with no solution are flagged (`Warning::IllPosed`), well-posed
//! neighbours are not: the resonant oscillator `q̈ = −q` on `[0, π]`, `q(0) = 0`, `q(π) = 1`,
//! against the same equation on `[0, π/2]`, for every classical embedding and scheme and every
//! `N ≥ 50`; and random oscillators whose distance to the nearest resonance is known in closed
//! form.

use std::f64::consts::PI;

use varembed::{Embedding, Grid, Scheme, Side};
use varembed_tests::models::hand::Oscillator;
use varembed_tests::rng::Rng;
use varembed_tests::warnings::ill_posed;

/// Every classical embedding that solves boundary value problems.
fn embeddings() -> Vec<Embedding> {
    vec![
        Embedding::finite_difference(Side::Backward),
        Embedding::finite_difference(Side::Forward),
        Embedding::asymmetric(Side::Backward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ]
}

#[test]
fn the_resonant_oscillator_is_flagged_and_its_well_posed_neighbour_is_not() {
    let oscillator = Oscillator { omega: 1.0 };
    for embedding in embeddings() {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            for n in [50, 100, 400, 1000] {
                let resonant =
                    varembed_tests::problem(&oscillator, Grid::new(0.0, PI, n).unwrap(), embedding)
                        .solve_bvp(scheme, 0.0, 1.0)
                        .unwrap();
                let measure = ill_posed(&resonant.warnings);
                assert!(
                    measure.is_some_and(|m| m < 1e-2),
                    "{embedding} {scheme} N = {n}: {:?}",
                    resonant.warnings
                );
                let neighbour = varembed_tests::problem(
                    &oscillator,
                    Grid::new(0.0, PI / 2.0, n).unwrap(),
                    embedding,
                )
                .solve_bvp(scheme, 0.0, 1.0)
                .unwrap();
                assert_eq!(
                    ill_posed(&neighbour.warnings),
                    None,
                    "{embedding} {scheme} N = {n}"
                );
            }
        }
    }
}

#[test]
fn the_measure_tends_to_the_distance_from_resonance() {
    // L = ½v² − ½ω²x² on [0, T]: the measure tends to min_j |j² − (ωT/π)²|, the lowest
    // eigenvalue of −d²/dt² − ω² over that of −d²/dt². Random ω T/π near an integer (flagged
    // below 1e-2) and between integers (not flagged), on the midpoint scheme at N = 2000.
    let mut rng = Rng(0x0111_9053_d0e5);
    for case in 0..40 {
        let j = 1 + rng.below(4);
        let offset = if case % 2 == 0 {
            rng.uniform(-2e-4, 2e-4)
        } else {
            rng.uniform(0.2, 0.8)
        };
        let ratio = j as f64 + offset; // ω T / π
        let length = rng.uniform(0.5, 3.0);
        let omega = ratio * PI / length;
        let exact = (1..=j + 1)
            .map(|k| ((k * k) as f64 - ratio * ratio).abs())
            .fold(f64::INFINITY, f64::min);
        let grid = Grid::new(0.0, length, 2000).unwrap();
        let run = varembed_tests::problem(&Oscillator { omega }, grid, Embedding::midpoint())
            .with_posedness_check(true)
            .solve_bvp(Scheme::Variational, 0.0, 1.0)
            .unwrap();
        match ill_posed(&run.warnings) {
            Some(measure) => {
                assert!(
                    exact < 1e-2,
                    "case {case}: flagged at {measure:e}, exact {exact:e}"
                );
                // The discrete measure is the exact one up to O(h²) and the inverse
                // iteration's few digits.
                assert!(
                    (measure - exact).abs() < 0.05 * exact + 1e-3,
                    "case {case}: {measure:e} against {exact:e}"
                );
            }
            None => assert!(exact >= 1e-2, "case {case}: not flagged, exact {exact:e}"),
        }
    }
}

#[test]
fn the_check_can_be_turned_off() {
    let oscillator = Oscillator { omega: 1.0 };
    let problem = varembed_tests::problem(
        &oscillator,
        Grid::new(0.0, PI, 100).unwrap(),
        Embedding::midpoint(),
    );
    let quiet = problem
        .with_posedness_check(false)
        .solve_bvp(Scheme::Variational, 0.0, 1.0)
        .unwrap();
    assert!(quiet.warnings.is_empty());
}
