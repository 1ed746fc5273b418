//! `compare_ivp` / `compare_bvp`: every number of the table checked against an oracle.

use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Side, Start, Vector};
use varembed_tests::curve::v1;
use varembed_tests::models::hand::{Oscillator, Pendulum};

fn exact_oscillator(t: f64) -> Vector<1> {
    // ω = 1, q(0) = 1, q̇(0) = 0.
    v1(t.cos())
}

#[test]
fn ivp_comparison_reports_errors_orders_energy_and_coherence() {
    let oscillator = Oscillator { omega: 1.0 };
    let grid = Grid::new(0.0, 10.0, 2000).unwrap();
    let problem = Problem::new(
        &oscillator,
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    for (start, variational_order) in [(Start::Legendre, 1.0), (Start::SecondOrder, 2.0)] {
        let options = CompareOptions {
            reference: Reference::Exact(&exact_oscillator),
            start,
            order: true,
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
        // Gauss-FDE− is not coherent: each solution leaves the other scheme a residual of order h·q⃛.
        assert!(cmp.direct.residual_of_other > 1e-4 && cmp.variational.residual_of_other > 1e-4);
        // The direct σ = − scheme dissipates: energy falls by about 1 − r^{2N} ≈ 1 − e^{−hT}.
        assert!(cmp.direct.energy_deviation > 10.0 * cmp.variational.energy_deviation);
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
    let problem = Problem::new(&pendulum, grid, Embedding::asymmetric(Side::Forward));
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
    let problem = Problem::new(
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
