use super::*;
use crate::embedding::Embedding;
use crate::lagrangian::{Hessian, Matrix};
use crate::problem::Problem;
use crate::side::Side;

/// `L = ½v² − ½x²`: `q = cos t` from `q(0) = 1`, `q̇(0) = 0`.
struct Oscillator;
impl Lagrangian<1> for Oscillator {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        0.5 * v[0] * v[0] - 0.5 * x[0] * x[0]
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        (-x, *v)
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: -Matrix::<1>::identity(),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}

fn cosine(t: f64) -> Vector<1> {
    Vector::<1>::new(t.cos())
}

fn problem(n: usize) -> Problem<'static, Oscillator, 1> {
    let grid = Grid::new(0.0, 5.0, n).unwrap();
    Problem::new(
        &Oscillator,
        grid,
        Embedding::finite_difference(Side::Backward),
    )
}

fn exact_options() -> CompareOptions<'static, 1> {
    CompareOptions {
        reference: Reference::Exact(&cosine),
        start: Start::SecondOrder,
        order: true,
    }
}

#[test]
fn observed_order_is_log2_of_the_error_ratio_per_doubling() {
    for (e_coarse, e_fine) in [(0.3, 0.07), (1e-3, 5e-4), (2.0, 3.0)] {
        assert_eq!(
            observed_order((50, e_coarse), (100, e_fine)),
            (e_coarse / e_fine).log2()
        );
    }
    // Over two doublings the ratio is spread over both.
    let p = observed_order((50, 1.0), (200, 1.0 / 64.0));
    assert!((p - 3.0).abs() < 1e-15, "{p}");
    assert_eq!(
        observed_orders(&[(10, 8.0), (20, 2.0), (40, 1.0)]),
        vec![2.0, 1.0]
    );
}

#[test]
fn convergence_run_solves_each_doubling_once_with_its_error_and_orders() {
    let run = problem(100).convergence_ivp(Scheme::Variational, 1.0, 0.0, &exact_options(), 4);
    assert!(run.failures.is_empty(), "{:?}", run.failures);
    let sizes: Vec<usize> = run.levels.iter().map(Level::n).collect();
    assert_eq!(sizes, [100, 200, 400, 800]);
    for level in &run.levels {
        let fresh = problem(level.n())
            .solve_ivp_with(Scheme::Variational, 1.0, 0.0, Start::SecondOrder)
            .unwrap();
        assert_eq!(level.solution, fresh);
        assert_eq!(level.error, Some(max_error(&fresh.grid, &fresh.q, cosine)));
    }
    let errors: Vec<(usize, f64)> = run
        .levels
        .iter()
        .map(|l| (l.n(), l.error.unwrap()))
        .collect();
    assert_eq!(run.error_estimates(), errors);
    let orders = run.orders();
    assert_eq!(orders, observed_orders(&errors));
    // Störmer–Verlet from the second-order start.
    assert!(orders.iter().all(|p| (p - 2.0).abs() < 0.05), "{orders:?}");
    for (i, n) in [100, 200, 400].into_iter().enumerate() {
        assert_eq!(run.order_at(n), Some(orders[i]));
    }
    assert_eq!(run.order_at(800), None);
}

#[test]
fn self_convergence_estimates_are_distances_on_the_coarse_nodes() {
    let options = CompareOptions::<1>::default();
    let run = problem(64).convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3);
    assert_eq!(run.reference, "none");
    assert!(run.levels.iter().all(|l| l.error.is_none()));
    let q: Vec<&[Vector<1>]> = run.levels.iter().map(|l| &l.solution.q[..]).collect();
    let gap = |coarse: &[Vector<1>], fine: &[Vector<1>]| {
        (0..coarse.len())
            .map(|k| (coarse[k][0] - fine[2 * k][0]).abs())
            .fold(0.0, f64::max)
    };
    let estimates = vec![(64, gap(q[0], q[1])), (128, gap(q[1], q[2]))];
    assert_eq!(run.error_estimates(), estimates);
    let order = run.orders();
    assert_eq!(order, vec![(estimates[0].1 / estimates[1].1).log2()]);
    assert!((order[0] - 1.0).abs() < 0.1, "{order:?}");
}

#[test]
fn a_comparison_is_the_runs_at_its_grid_with_their_orders() {
    let options = exact_options();
    let coarse = problem(100);
    let direct = coarse.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3);
    let variational = coarse.convergence_ivp(Scheme::Variational, 1.0, 0.0, &options, 3);
    let at = problem(200);
    let from_runs = at.compare_runs(&direct, &variational).unwrap();
    let fresh = at.compare_ivp_with(1.0, 0.0, &options).unwrap();
    for (run, from_runs, fresh) in [
        (&direct, &from_runs.direct, &fresh.direct),
        (&variational, &from_runs.variational, &fresh.variational),
    ] {
        let level = run.level(200).unwrap();
        assert_eq!(from_runs.solution, level.solution);
        assert_eq!(from_runs.wall_time, level.wall_time);
        assert_eq!(from_runs.order, run.order_at(200));
        assert_eq!(from_runs.order, Some(run.orders()[1]));
        // A comparison solved from scratch computes the same numbers by the same definitions.
        assert_eq!(fresh.solution, level.solution);
        assert_eq!(fresh.error, level.error);
        assert_eq!(fresh.order, from_runs.order);
        assert_eq!(fresh.residual_of_other, from_runs.residual_of_other);
        assert_eq!(fresh.energy, from_runs.energy);
    }
    assert_eq!(from_runs.max_distance, fresh.max_distance);
    assert_eq!(from_runs.to_string().lines().count(), 5);

    // The finest grid has no next level, so no order; a grid the runs skipped is an error.
    let finest = problem(400).compare_runs(&direct, &variational).unwrap();
    assert_eq!(finest.direct.order, None);
    assert!(problem(300).compare_runs(&direct, &variational).is_err());
    assert!(at.compare_runs(&variational, &direct).is_err());
}

#[test]
fn a_failed_size_is_recorded_and_is_the_comparisons_answer() {
    let options = exact_options();
    let run = problem(10).convergence_ivp(Scheme::Direct, f64::NAN, 0.0, &options, 2);
    assert!(run.levels.is_empty());
    let sizes: Vec<usize> = run.failures.iter().map(|(n, _)| *n).collect();
    assert_eq!(sizes, [10, 20]);
    assert!(run.orders().is_empty());
    let variational = problem(10).convergence_ivp(Scheme::Variational, 1.0, 0.0, &options, 2);
    let error = problem(10).compare_runs(&run, &variational).unwrap_err();
    assert_eq!(error, run.failures[0].1);
    assert_eq!(
        problem(10)
            .compare_ivp_with(f64::NAN, 0.0, &options)
            .unwrap_err(),
        run.failures[0].1
    );
}
