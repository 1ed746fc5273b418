//! Gauss-GLEσ boundary data whose value at the end where the derivative starts is not zero:
//! for `α ≥ 1/2` every curve has infinite action, the discrete solutions do not converge, and
//! every solution says so with `Warning::InfiniteFractionalAction`; compatible data, orders
//! below 1/2, α = 1 and the Caputo form are not flagged.

use varembed::{
    CompareOptions, Embedding, FractionalSolver, Grid, Scheme, Side, Solution, Warning, lagrangian,
};

/// `L = ½v² − ½x² + x`.
#[lagrangian]
fn shifted_spring(x: f64, v: f64) -> f64 {
    0.5 * v * v - 0.5 * x * x + x
}

fn solve(embedding: Embedding, scheme: Scheme, (qa, qb): (f64, f64)) -> Vec<Solution<1>> {
    let grid = Grid::new(0.0, 1.0, 64).unwrap();
    [FractionalSolver::Dense, FractionalSolver::Fast]
        .map(|solver| {
            varembed_tests::problem(&ShiftedSpring, grid, embedding)
                .with_fractional_solver(solver)
                .solve_bvp(scheme, qa, qb)
                .unwrap()
        })
        .into()
}

fn gle(side: Side, alpha: f64) -> Embedding {
    Embedding::grunwald_letnikov(side, alpha).unwrap()
}

/// The warning names the end, its value and the reason, on both solvers and both schemes.
#[test]
fn a_nonzero_value_where_the_derivative_starts_is_flagged() {
    for (side, data, value) in [
        (Side::Backward, (0.3, 1.0), 0.3),
        (Side::Forward, (0.3, 1.0), 1.0),
        (Side::Forward, (0.0, -2.0), 2.0),
    ] {
        for alpha in [0.5, 0.7, 0.9] {
            for scheme in [Scheme::Direct, Scheme::Variational] {
                for solution in solve(gle(side, alpha), scheme, data) {
                    let flagged = Warning::InfiniteFractionalAction { alpha, side, value };
                    let expected = if alpha == 0.5 {
                        vec![Warning::IllPosedFractional { alpha }, flagged]
                    } else {
                        vec![flagged]
                    };
                    assert_eq!(solution.warnings, expected, "{side:?} α = {alpha} {scheme}");
                }
            }
        }
    }
    let message =
        solve(gle(Side::Forward, 0.9), Scheme::Variational, (0.3, 1.0))[0].warnings[0].to_string();
    for part in [
        "value at b",
        "α = 0.9",
        "(b − t)^{−α}",
        "infinite action",
        "Embedding::caputo",
    ] {
        assert!(message.contains(part), "{part:?} not in {message}");
    }
}

/// Data vanishing at that end (or negligibly small there against the curve), orders where the
/// action stays finite (`α < 1/2`: only `IllPosedFractional`, for its own reason; `α = 1`: the
/// classical difference), and the Caputo form carry no such warning.
#[test]
fn compatible_data_other_orders_and_the_caputo_form_are_not_flagged() {
    let none = |embedding: Embedding, data: (f64, f64), expected: &[Warning]| {
        for solution in solve(embedding, Scheme::Variational, data) {
            assert_eq!(solution.warnings, expected, "{embedding} {data:?}");
        }
    };
    for alpha in [0.5, 0.7, 0.9] {
        let below = if alpha == 0.5 {
            vec![Warning::IllPosedFractional { alpha }]
        } else {
            vec![]
        };
        none(gle(Side::Backward, alpha), (0.0, 1.0), &below);
        none(gle(Side::Backward, alpha), (1e-12, 1.0), &below);
        none(gle(Side::Forward, alpha), (0.3, 0.0), &below);
        for side in [Side::Backward, Side::Forward] {
            none(Embedding::caputo(side, alpha).unwrap(), (0.3, 1.0), &below);
        }
    }
    none(
        gle(Side::Backward, 0.4),
        (0.3, 1.0),
        &[Warning::IllPosedFractional { alpha: 0.4 }],
    );
    none(gle(Side::Backward, 1.0), (0.3, 1.0), &[]);
}

/// The comparison table shows the warning under the table, once for the two schemes.
#[test]
fn the_comparison_table_shows_the_warning() {
    let grid = Grid::new(0.0, 1.0, 40).unwrap();
    let problem = varembed_tests::problem(&ShiftedSpring, grid, gle(Side::Backward, 0.9));
    let comparison = problem.compare_bvp(0.3, 1.0).unwrap();
    let warning = Warning::InfiniteFractionalAction {
        alpha: 0.9,
        side: Side::Backward,
        value: 0.3,
    };
    assert_eq!(comparison.warnings(), [warning]);
    let (text, markdown) = (comparison.to_string(), comparison.to_markdown());
    for table in [text, markdown] {
        assert_eq!(
            table.matches("value at a is not zero").count(),
            1,
            "{table}"
        );
        assert!(table.contains(&warning.to_string()), "{table}");
    }
}

/// What the warning is about: on the data flagged, the convergence study's error estimates
/// stay put as `N` grows (measured: 0.01446, 0.01471, 0.01484, 0.01491 for `N = 50 … 400`);
/// the Caputo form of the same data converges (0.00082, 0.00049, 0.00029, 0.00017).
#[test]
fn flagged_data_do_not_converge_and_the_caputo_form_does() {
    let grid = Grid::new(0.0, 1.0, 50).unwrap();
    let estimates = |embedding: Embedding| {
        varembed_tests::problem(&ShiftedSpring, grid, embedding)
            .convergence_bvp(Scheme::Variational, 0.3, 1.0, &CompareOptions::default(), 5)
            .error_estimates()
    };
    let flagged = estimates(gle(Side::Backward, 0.9));
    assert_eq!(flagged.len(), 4);
    for (n, e) in &flagged {
        assert!((e - 0.0148).abs() < 0.0005, "N = {n}: {e}");
    }
    let caputo = estimates(Embedding::caputo(Side::Backward, 0.9).unwrap());
    for pair in caputo.windows(2) {
        let ratio = pair[1].1 / pair[0].1;
        // A halving each doubling or better than 0.62 (order ≥ 0.7; measured 0.60, 0.59, 0.58).
        assert!(ratio < 0.62, "{caputo:?}");
    }
    assert!(caputo[3].1 < 2e-4, "{caputo:?}");
}
