//! Boundary value problems of run-time-dimension models with no solution are flagged
//! (`Warning::IllPosed`), well-posed neighbours are not: chains of oscillators `q̈ = −q` on
//! `[0, π]` with `q(0) = 0`, `q(π) = 1` in every component — uncoupled, coupled in a line
//! (a banded Jacobian) and in a ring (not banded) — whose uniform mode is at resonance,
//! against the same chains on `[0, π/2]`, for every embedding and scheme of the run-time path
//! and `N` = 50, 100, 1000; and the measure equal to the const-generic path's on the same
//! model.

use std::f64::consts::PI;

use super::bvp::kinds;
use varembed::{DynLagrangian, DynProblem, Embedding, Grid, Scheme, Side, lagrangian};
use varembed_tests::warnings::ill_posed;

/// `n` unit oscillators, neighbours joined by springs of stiffness `kappa` (free ends): the
/// uniform mode has frequency 1 whatever `kappa`, the others `√(1 + 4κ sin²(jπ/(2n)))`.
#[lagrangian]
fn line(x: &[f64], v: &[f64], n: usize, kappa: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * (v[i] * v[i] - x[i] * x[i]);
    }
    for i in 0..n - 1 {
        let d = x[i + 1] - x[i];
        l += -0.5 * kappa * d * d;
    }
    l
}

/// The same oscillators joined in a ring (`x[(i + 1) % n]`): the uniform mode has frequency 1,
/// the others `√(1 + 4κ sin²(jπ/n))`; its Hessian is not banded in the model's order.
#[lagrangian]
fn ring(x: &[f64], v: &[f64], n: usize, kappa: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        let d = x[(i + 1) % n] - x[i];
        l += 0.5 * (v[i] * v[i] - x[i] * x[i]) - 0.5 * kappa * d * d;
    }
    l
}

/// The line of oscillators with a named dimension: a `Lagrangian<N>` for the const-generic
/// path and, from the same macro call, a `DynLagrangian`.
mod named {
    use varembed::lagrangian;

    /// The number of oscillators.
    pub const N: usize = 6;

    /// As the run-time `line`.
    #[lagrangian]
    pub fn line(x: [f64; N], v: [f64; N], kappa: f64) -> f64 {
        let mut l = 0.0;
        for i in 0..N {
            l += 0.5 * (v[i] * v[i] - x[i] * x[i]);
        }
        for i in 0..N - 1 {
            let d = x[i + 1] - x[i];
            l += -0.5 * kappa * d * d;
        }
        l
    }
}

/// The resonant problem on `[0, π]` is flagged and its neighbour on `[0, π/2]` (measure ¾) is
/// not, for `model` under every kind and `N`.
fn resonance_flagged<L: DynLagrangian>(name: &str, model: &L) {
    let d = model.dimension();
    let (qa, qb) = (vec![0.0; d], vec![1.0; d]);
    for (embedding, scheme) in kinds() {
        for n in [50, 100, 1000] {
            let resonant = DynProblem::new(model, Grid::new(0.0, PI, n).unwrap(), embedding)
                .solve_bvp(scheme, &qa, &qb)
                .unwrap();
            let measure = ill_posed(&resonant.warnings);
            assert!(
                measure.is_some_and(|m| m < 1e-2),
                "{name} {embedding} {scheme} N = {n}: {:?}",
                resonant.warnings
            );
            assert_eq!(resonant.warnings, resonant.run.warnings);
            let neighbour = DynProblem::new(model, Grid::new(0.0, PI / 2.0, n).unwrap(), embedding)
                .solve_bvp(scheme, &qa, &qb)
                .unwrap();
            assert!(
                neighbour.warnings.is_empty(),
                "{name} {embedding} {scheme} N = {n}: {:?}",
                neighbour.warnings
            );
        }
    }
}

#[test]
fn resonant_chains_are_flagged_and_their_well_posed_neighbours_are_not() {
    resonance_flagged("uncoupled", &Line { n: 4, kappa: 0.0 });
    resonance_flagged("line", &Line { n: 4, kappa: 0.3 });
    let ring = Ring { n: 5, kappa: 0.3 };
    assert_eq!(ring.hessian_bandwidth(), None, "the ring is not banded");
    resonance_flagged("ring", &ring);
}

#[test]
fn the_measure_is_the_const_generic_measure() {
    // The same model, the same Jacobian: the run-time path's sparse LU and the const-generic
    // path's band LU give the same smallest eigenvalue and coupling (measured: within 1.3e-9
    // relative, measures from 2.1e-5 to 2.6e-3).
    let model = named::Line { kappa: 0.3 };
    let (qa, qb) = ([0.0; named::N], [1.0; named::N]);
    for (embedding, scheme) in kinds() {
        for n in [50, 200] {
            let grid = Grid::new(0.0, PI, n).unwrap();
            let reference = varembed_tests::problem(&model, grid, embedding)
                .solve_bvp(scheme, qa, qb)
                .unwrap();
            let solution = DynProblem::new(&model, grid, embedding)
                .solve_bvp(scheme, &qa, &qb)
                .unwrap();
            let (expected, found) = (
                ill_posed(&reference.warnings).unwrap(),
                ill_posed(&solution.warnings).unwrap(),
            );
            let gap = (found - expected).abs() / expected;
            assert!(
                gap < 1e-6,
                "{embedding} {scheme} N = {n}: {found:e} against {expected:e} ({gap:e})"
            );
        }
    }
}

#[test]
fn the_check_can_be_turned_off() {
    let model = Line { n: 4, kappa: 0.3 };
    let grid = Grid::new(0.0, PI, 100).unwrap();
    let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    let quiet = problem
        .with_posedness_check(false)
        .solve_bvp(Scheme::Variational, &[0.0; 4], &[1.0; 4])
        .unwrap();
    assert!(quiet.warnings.is_empty() && quiet.run.warnings.is_empty());
}
