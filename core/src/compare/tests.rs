use super::order::{observed_order, observed_orders, order_statuses};
use super::*;
use crate::embedding::Embedding;
use crate::lagrangian::{Dependence, Hessian, Lagrangian, Matrix};
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
    fn dependence(&self) -> Dependence {
        Dependence {
            t: false,
            ..Dependence::ALL
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

fn exact_options() -> CompareOptions<'static, Vector<1>> {
    CompareOptions {
        reference: Reference::Exact(&cosine),
        start: Start::SecondOrder,
        order: true,
        timing: true,
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
    let options = CompareOptions::<Vector<1>>::default();
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
    // The table, the distance, then the legend: one line per column.
    let table = from_runs.to_string();
    let lines: Vec<&str> = table.lines().collect();
    assert_eq!(lines.len(), 5 + 1 + 8, "{table}");
    assert_eq!(lines[5], "  legend:");
    // `{:#}`: the same table without the legend, no trailing newline.
    assert_eq!(format!("{from_runs:#}"), lines[..5].join("\n"));
    // Built from runs: no solve of its own, the order read off 400, where the runs end, so
    // it cannot be checked against the next one.
    assert_eq!(
        (from_runs.extra_solves, &from_runs.order_grids[..]),
        (0, &[400][..])
    );
    assert_eq!(from_runs.direct.order_status, Some(OrderStatus::Unchecked));
    assert!(table.contains("read off the runs"), "{table}");
    // Solved afresh: two more solves per scheme, on 2N and 4N.
    assert_eq!(
        (fresh.extra_solves, &fresh.order_grids[..]),
        (2, &[400, 800][..])
    );
    assert!(fresh.to_string().contains("from 2 more solves per scheme"));
    // Störmer–Verlet from the second-order start on 200, 400, 800: a settled order 2.
    assert_eq!(
        fresh.variational.order_status,
        Some(OrderStatus::Asymptotic)
    );

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

/// `(N, e, scale)` with successive orders `orders` from `e = 1` at `N = 10`.
fn errors_with_orders(orders: &[f64], scale: f64) -> Vec<(usize, f64, f64)> {
    let mut errors = vec![(10, 1.0, scale)];
    for p in orders {
        let &(n, e, _) = errors.last().unwrap();
        errors.push((2 * n, e / 2f64.powf(*p), scale));
    }
    errors
}

#[test]
fn successive_orders_that_disagree_are_pre_asymptotic() {
    use OrderStatus::*;
    let errors = errors_with_orders(&[-0.29, 3.18], 1.0);
    let orders = observed_orders(&errors.iter().map(|&(n, e, _)| (n, e)).collect::<Vec<_>>());
    assert!((orders[0] + 0.29).abs() < 1e-12 && (orders[1] - 3.18).abs() < 1e-12);
    // A growing error is not converging at all; a first order of 0.5 before 3.18 is
    // pre-asymptotic.
    assert_eq!(order_statuses(&errors), [NotConverging, Unchecked]);
    let errors = errors_with_orders(&[0.5, 3.18], 1.0);
    assert_eq!(order_statuses(&errors), [PreAsymptotic, Unchecked]);
    // A power law within the tolerance; the last order has nothing to be checked against.
    let settled = errors_with_orders(&[2.04, 1.98, 2.0], 1.0);
    assert_eq!(
        order_statuses(&settled),
        [Asymptotic, Asymptotic, Unchecked]
    );
    // Just past the tolerance.
    let errors = errors_with_orders(&[2.0, 2.0 + 1.01 * OrderStatus::TOLERANCE], 1.0);
    assert_eq!(order_statuses(&errors)[0], PreAsymptotic);
}

#[test]
fn a_steady_drift_is_marked_and_a_settling_run_is_not() {
    use OrderStatus::*;
    // Each step below the tolerance, but the orders keep rising: no limit to trust.
    let drift = errors_with_orders(&[0.27, 0.33, 0.38, 0.41, 0.44], 1.0);
    assert_eq!(
        order_statuses(&drift),
        [Drifting, Drifting, Drifting, Drifting, Unchecked]
    );
    // Aitken on 0.27, 0.33, 0.38 alone extrapolates to 0.63: the first order is 0.36 away.
    let short = errors_with_orders(&[0.27, 0.33, 0.38], 1.0);
    assert_eq!(order_statuses(&short), [Drifting, Drifting, Unchecked]);
    // Settling towards 2: the limit 1.995 is within the tolerance of every order.
    let healthy = errors_with_orders(&[1.95, 1.98, 1.99], 1.0);
    assert_eq!(
        order_statuses(&healthy),
        [Asymptotic, Asymptotic, Unchecked]
    );
    // Alternating noise around 2 contracts: asymptotic.
    let noisy = errors_with_orders(&[2.03, 1.97, 2.01, 1.99], 1.0);
    assert_eq!(
        order_statuses(&noisy),
        [Asymptotic, Asymptotic, Asymptotic, Unchecked]
    );
    // Settling from far: the early order is further than the tolerance from the limit 1.0.
    let settling = order_statuses(&errors_with_orders(&[0.6, 0.8, 0.88, 0.94, 0.97], 1.0));
    assert_eq!(settling[0], PreAsymptotic);
    assert_eq!(settling[1], Drifting);
    assert_eq!(settling[3], Asymptotic);
}

#[test]
fn errors_that_do_not_fall_are_not_converging() {
    use OrderStatus::*;
    // Error estimates that stay near 0.105 from N = 50 to 800: orders 0.001–0.003.
    let stalled = errors_with_orders(&[0.001, 0.002, 0.003, 0.002], 1.0);
    assert_eq!(order_statuses(&stalled), [NotConverging; 4]);
    // Below the threshold, and a growing error.
    let at = errors_with_orders(&[0.09, -0.5], 1.0);
    assert_eq!(order_statuses(&at), [NotConverging, NotConverging]);
    let above = errors_with_orders(&[0.11, 0.11, 0.11], 1.0);
    assert_eq!(order_statuses(&above), [Asymptotic, Asymptotic, Unchecked]);
}

#[test]
fn orders_of_errors_at_round_off_are_marked() {
    use OrderStatus::*;
    // Errors 1, 1/4, 1/16, 1/64 on a solution of size 1e13: 1/16 and 1/64 are below
    // 100 ε · 1e13 ≈ 0.22, so every order touching them is round-off, and the first order
    // cannot be checked against one.
    let errors = errors_with_orders(&[2.0, 2.0, 2.0], 1e13);
    assert_eq!(order_statuses(&errors), [Unchecked, RoundOff, RoundOff]);
    // An exact solution: error zero, the order is not a number.
    let exact = [(10, 0.0, 1.0), (20, 0.0, 1.0)];
    assert_eq!(order_statuses(&exact), [RoundOff]);
}

/// `L = ½v² − ½(1 + t)x²`: the same oscillator with a stiffness growing in time.
struct Stiffening;
impl Lagrangian<1> for Stiffening {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
        0.5 * v[0] * v[0] - 0.5 * (1.0 + t) * x[0] * x[0]
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
        (-(1.0 + t) * x, *v)
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, t: f64) -> Hessian<1> {
        Hessian {
            xx: -(1.0 + t) * Matrix::<1>::identity(),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
    fn dependence(&self) -> Dependence {
        Dependence::ALL
    }
}

#[test]
fn the_energy_column_is_shown_only_where_the_flow_conserves_energy() {
    let options = CompareOptions::<Vector<1>> {
        order: false,
        ..CompareOptions::default()
    };
    let grid = Grid::new(0.0, 5.0, 200).unwrap();
    let fde = Embedding::finite_difference(Side::Backward);
    // Autonomous and classical: the deviation is the energy's, recomputed here.
    let autonomous = Problem::new(&Oscillator, grid, fde)
        .compare_ivp_with(1.0, 0.0, &options)
        .unwrap();
    assert_eq!(autonomous.energy_not_conserved, None);
    for r in [&autonomous.direct, &autonomous.variational] {
        let e = &r.energy;
        let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max);
        assert_eq!(r.energy_deviation, Some(drift));
        assert!(drift > 0.0);
    }
    let table = autonomous.to_string();
    assert!(table.contains("the flow conserves E"), "{table}");
    // Time-dependent: no deviation, "—" in the column and the reason in the legend.
    let driven = Problem::new(&Stiffening, grid, fde)
        .compare_ivp_with(1.0, 0.0, &options)
        .unwrap();
    assert!(driven.energy_not_conserved.unwrap().contains("depend on t"));
    assert_eq!(driven.direct.energy_deviation, None);
    assert_eq!(driven.variational.energy_deviation, None);
    let table = driven.to_string();
    let variational_row = table.lines().nth(3).unwrap();
    // scheme, error, order, theory, then the energy.
    assert_eq!(
        variational_row.split_whitespace().nth(4),
        Some("—"),
        "{table}"
    );
    assert!(table.contains("E is not conserved, so its drift would measure nothing"));
    // Fractional: the same, with its own reason, also for an autonomous Lagrangian.
    let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
    let fractional = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 32).unwrap(), gle)
        .compare_bvp_with(0.0, 1.0, &options)
        .unwrap();
    assert!(
        fractional
            .energy_not_conserved
            .unwrap()
            .contains("fractional")
    );
    assert_eq!(fractional.variational.energy_deviation, None);
    let md = fractional.to_markdown();
    assert!(md.contains("| max \\|ΔE\\| |"), "{md}");
    assert!(
        md.contains("- **max |ΔE|**: — : the embedding is fractional"),
        "{md}"
    );
    // Without the order: no extra solve, and the legend says so.
    assert_eq!(
        (fractional.extra_solves, fractional.order_grids.len()),
        (0, 0)
    );
    assert!(md.contains("not computed"), "{md}");
}
