//! `compare_ivp` / `compare_bvp`: every number of the table checked against an oracle.

use varembed::{
    CompareOptions, Embedding, FractionalSolver, Grid, OrderStatus, Reference, Scheme, Side, Start,
    Vector, Warning, lagrangian,
};
use varembed_tests::curve::v1;
use varembed_tests::models::hand::Pendulum;

/// Harmonic oscillator `L = ½v² − ½ω²x²`, autonomous as `#[lagrangian]` declares.
#[lagrangian]
fn oscillator(x: f64, v: f64, omega: f64) -> f64 {
    0.5 * v * v - 0.5 * omega * omega * x * x
}

fn exact_oscillator(t: f64) -> Vector<1> {
    // ω = 1, q(0) = 1, q̇(0) = 0.
    v1(t.cos())
}

#[test]
fn ivp_comparison_reports_errors_orders_energy_and_coherence() {
    let oscillator = Oscillator { omega: 1.0 };
    let grid = Grid::new(0.0, 10.0, 2000).unwrap();
    let problem = varembed_tests::problem(
        &oscillator,
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    for (start, variational_order) in [(Start::Legendre, 1.0), (Start::SecondOrder, 2.0)] {
        let options = CompareOptions {
            reference: Reference::Exact(&exact_oscillator),
            start,
            order: true,
            timing: true,
        };
        let cmp = problem.compare_ivp_with(1.0, 0.0, &options).unwrap();
        // Errors: recomputed independently from the returned solutions.
        for report in [&cmp.direct, &cmp.variational] {
            let e = (0..=2000)
                .map(|k| (report.solution.q[k][0] - grid.t(k).cos()).abs())
                .fold(0.0, f64::max);
            assert_eq!(report.error, Some(e));
        }
        let direct_order = cmp.direct.order.unwrap();
        let var_order = cmp.variational.order.unwrap();
        assert!(
            (direct_order - 1.0).abs() < 0.1,
            "direct order {direct_order}"
        );
        assert!(
            (var_order - variational_order).abs() < 0.1,
            "{start:?}: variational order {var_order}"
        );
        // Gauss-FDE− is not coherent: each solution leaves the other scheme a residual of order
        // h·q⃛, against rows whose momentum terms are of size |p|/h: relative, of order h²
        // (h² = 2.5e-5 here).
        for report in [&cmp.direct, &cmp.variational] {
            let r = report.residual_of_other;
            assert!(r > 2e-6 && r < 2.5e-4, "{r:e}");
        }
        // The direct σ = − scheme dissipates: energy falls by about 1 − r^{2N} ≈ 1 − e^{−hT}.
        let drift = |r: &varembed::SchemeReport<varembed::Solution<1>>| r.energy_deviation.unwrap();
        assert!(drift(&cmp.direct) > 10.0 * drift(&cmp.variational));
        assert!(cmp.max_distance > 1e-3);
        let table = cmp.to_string();
        assert!(
            table.contains("Gauss-FDE−")
                && table.contains("variational")
                && table.contains("exact solution")
        );
    }
}

#[test]
fn coherent_embedding_has_round_off_cross_residuals() {
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let grid = Grid::new(0.0, 5.0, 500).unwrap();
    let problem = varembed_tests::problem(&pendulum, grid, Embedding::asymmetric(Side::Forward));
    let cmp = problem.compare_ivp(1.0, 0.0).unwrap();
    assert_eq!(
        cmp.max_distance, 0.0,
        "both schemes run the same recurrence"
    );
    assert!(
        cmp.direct.residual_of_other < 1e-9,
        "{}",
        cmp.direct.residual_of_other
    );
    // Self-convergence order of the variational scheme from the Legendre start ≈ 1.
    let order = cmp.variational.order.unwrap();
    assert!((order - 1.0).abs() < 0.15, "order {order}");
    assert_eq!(cmp.reference, "none");
    assert!(cmp.direct.error.is_none());
}

#[test]
fn fractional_bvp_comparison_is_coherent() {
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let grid = Grid::new(0.0, 1.0, 64).unwrap();
    let problem = varembed_tests::problem(
        &pendulum,
        grid,
        Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap(),
    );
    let options = CompareOptions {
        order: false,
        ..CompareOptions::default()
    };
    let cmp = problem.compare_bvp_with(0.0, 1.0, &options).unwrap();
    assert!(cmp.max_distance < 1e-12, "{}", cmp.max_distance);
    assert!(cmp.direct.residual_of_other < 1e-9 && cmp.variational.residual_of_other < 1e-9);
    assert!(cmp.direct.order.is_none());
    assert_eq!(cmp.variational.energy.len(), 64);
}

#[test]
fn convergence_runs_keep_the_fractional_solver() {
    // Pendulum under Gauss-GLE− at α = 0.7, 31 to 127 unknowns: each solver is used as chosen,
    // even below the size where `Auto` would switch to the fast path.
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
    let problem = |n: usize, solver| {
        varembed_tests::problem(&pendulum, Grid::new(0.0, 1.0, n).unwrap(), gle)
            .with_fractional_solver(solver)
    };
    let options = CompareOptions::default();
    let mut finest = Vec::new();
    for solver in [FractionalSolver::Dense, FractionalSolver::Fast] {
        let run = problem(32, solver).convergence_bvp(Scheme::Variational, 0.0, 1.0, &options, 3);
        assert!(run.failures.is_empty(), "{:?}", run.failures);
        for level in &run.levels {
            let direct = problem(level.n(), solver)
                .solve_bvp(Scheme::Variational, 0.0, 1.0)
                .unwrap();
            assert_eq!(level.solution, direct, "{solver:?}, N = {}", level.n());
        }
        // The comparison's own finer solves too.
        let cmp = problem(32, solver).compare_bvp(0.0, 1.0).unwrap();
        assert_eq!(cmp.order_grids, [64, 128, 256]);
        assert_eq!(cmp.extra_solves, 3);
        let direct_128 = run.level(128).unwrap();
        assert_eq!(direct_128.solution.q.len(), 129);
        finest.push(direct_128.solution.q.clone());
    }
    // The two solvers do not give the same bits: the runs above did use different ones.
    assert_ne!(finest[0], finest[1]);
    let gap = finest[0]
        .iter()
        .zip(&finest[1])
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    assert!(gap > 0.0 && gap < 1e-10, "{gap:e}");
}

#[test]
fn an_ill_posed_fractional_table_shows_its_warning() {
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let gle = Embedding::grunwald_letnikov(Side::Backward, 0.5).unwrap();
    let problem = varembed_tests::problem(&pendulum, Grid::new(0.0, 1.0, 32).unwrap(), gle);
    let options = CompareOptions {
        order: false,
        ..CompareOptions::default()
    };
    let cmp = problem.compare_bvp_with(0.0, 1.0, &options).unwrap();
    let warning = Warning::IllPosedFractional { alpha: 0.5 };
    assert_eq!(cmp.warnings(), [warning]);
    let line = format!("  warning: {warning}");
    assert!(cmp.to_string().lines().any(|l| l == line), "{cmp}");
    assert!(
        cmp.to_markdown()
            .contains(&format!("**Warning:** {warning}"))
    );
}

#[test]
fn a_coarse_self_convergence_order_is_not_reported_as_settled() {
    // ωh = 1.25 at N = 40 on [0, 50], then 0.63, 0.31, 0.16: the coarse grids are far from
    // the asymptotic regime, and the table must say so rather than print a plain order.
    let problem = varembed_tests::problem(
        &Oscillator { omega: 1.0 },
        Grid::new(0.0, 50.0, 40).unwrap(),
        Embedding::finite_difference(Side::Backward),
    );
    let cmp = problem.compare_ivp(1.0, 0.0).unwrap();
    let (order, status) = (cmp.variational.order.unwrap(), cmp.variational.order_status);
    assert_eq!(
        status,
        Some(OrderStatus::PreAsymptotic),
        "order {order}\n{cmp}"
    );
    let row = cmp.to_string().lines().nth(3).unwrap().to_string();
    assert!(row.contains(&format!("{order:.2}*")), "{row}");
}
