//! The comparison's "other scheme's residual" is measured row by row against the size of the
//! terms each row sums: checked against the rows written out by hand, and shown not to grow
//! with a Lagrangian that grows along the run, nor to change with the scale of `L`.

use varembed::{CompareOptions, Comparison, Embedding, Grid, Side, Solution, Vector, lagrangian};
use varembed_tests::models::hand::CaldirolaKanai;
use varembed_tests::models::scaled::Scaled;

#[lagrangian]
fn oscillator(x: f64, v: f64) -> f64 {
    0.5 * v * v - 0.5 * x * x
}

/// `max_j |r_j| / s_j` over rows given as `(r_j, s_j)`.
fn max_relative(rows: impl Iterator<Item = (f64, f64)>) -> f64 {
    rows.map(|(r, s)| r.abs() / s).fold(0.0, f64::max)
}

/// Each report's residual equals the one computed by hand (`[direct, variational]`), which is
/// far from round-off (above `floor`: the embedding is not coherent on this model).
fn assert_reports(cmp: &Comparison<Solution<1>>, expected: [f64; 2], floor: f64) {
    let got = [
        cmp.direct.residual_of_other,
        cmp.variational.residual_of_other,
    ];
    for (got, expected) in got.into_iter().zip(expected) {
        assert!(
            (got - expected).abs() <= 1e-12 * expected && expected > floor,
            "{got:e} vs {expected:e}"
        );
    }
}

/// Gauss-FDE−, `L = ½v² − ½x²`, `V_k = (Q_k − Q_{k−1})/h`, `f_k = −Q_k`, `p_k = V_k`. The
/// variational row `j ∈ 1..=N−1` is `−Q_j − (V_{j+1} − V_j)/h`, its terms
/// `|Q_j| + (|V_j| + |V_{j+1}|)/h`; the direct row `k ∈ 2..=N` is `−Q_k − (V_k − V_{k−1})/h`,
/// its terms `|Q_k| + (|V_k| + |V_{k−1}|)/h`. Each report's residual is the other scheme's rows
/// on its solution, written out here.
#[test]
fn finite_difference_rows_by_hand() {
    let n = 40;
    let grid = Grid::new(0.0, 3.0, n).unwrap();
    let h = grid.h();
    let problem = varembed_tests::problem(
        &Oscillator,
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    let options = CompareOptions {
        order: false,
        ..Default::default()
    };
    let cmp = problem.compare_ivp_with(1.0, 0.3, &options).unwrap();
    let variational_rows = |q: &[Vector<1>]| {
        let v = |k: usize| (q[k][0] - q[k - 1][0]) / h;
        max_relative((1..n).map(|j| {
            let (r, s) = (-q[j][0] - (v(j + 1) - v(j)) / h, q[j][0].abs());
            (r, s + (v(j).abs() + v(j + 1).abs()) / h)
        }))
    };
    let direct_rows = |q: &[Vector<1>]| {
        let v = |k: usize| (q[k][0] - q[k - 1][0]) / h;
        max_relative((2..=n).map(|k| {
            let (r, s) = (-q[k][0] - (v(k) - v(k - 1)) / h, q[k][0].abs());
            (r, s + (v(k).abs() + v(k - 1).abs()) / h)
        }))
    };
    let expected = [
        variational_rows(&cmp.direct.solution.q),
        direct_rows(&cmp.variational.solution.q),
    ];
    assert_reports(&cmp, expected, 1e-4);
}

/// The midpoint embedding, `L = ½v² − ½x²`, interval `k`'s `V_k = (Q_k − Q_{k−1})/h` and
/// `X_k = (Q_k + Q_{k−1})/2`. The variational row `j` is `−(X_j + X_{j+1})/2 − (V_{j+1} − V_j)/h`,
/// the direct one `−Q_j − (V_{j+1} − V_j)/h`; the terms in modulus as above.
#[test]
fn midpoint_rows_by_hand() {
    let n = 30;
    let grid = Grid::new(0.0, 4.0, n).unwrap();
    let h = grid.h();
    let problem = varembed_tests::problem(&Oscillator, grid, Embedding::midpoint());
    let options = CompareOptions {
        order: false,
        ..Default::default()
    };
    let cmp = problem.compare_bvp_with(0.2, 1.0, &options).unwrap();
    let rows = |q: &[Vector<1>], variational: bool| {
        let v = |k: usize| (q[k][0] - q[k - 1][0]) / h;
        let x = |k: usize| 0.5 * (q[k][0] + q[k - 1][0]);
        max_relative((1..n).map(|j| {
            let momenta = (v(j + 1) - v(j)) / h;
            let sizes = (v(j).abs() + v(j + 1).abs()) / h;
            if variational {
                let (a, b) = (-0.5 * x(j), -0.5 * x(j + 1));
                (a + b - momenta, a.abs() + b.abs() + sizes)
            } else {
                (-q[j][0] - momenta, q[j][0].abs() + sizes)
            }
        }))
    };
    let expected = [
        rows(&cmp.direct.solution.q, true),
        rows(&cmp.variational.solution.q, false),
    ];
    assert_reports(&cmp, expected, 1e-6);
}

/// The Caldirola–Kanai oscillator `e^{γt}(½v² − ½ω²x²)` carries `e^{γt}` into every row at
/// `t`. With `γ = 0.1`, `ω = 2`, `h = 0.02`, the plain max-norm of the variational rows on the
/// direct solution grows from 0.195 over `[0, 20]` to 1.18 over `[0, 200]` (Gauss-FDE−), and
/// from 4.1e-3 to 34.4 (midpoint). Row by row against its own terms, the residual reads alike on
/// both spans: measured 9.94e-4 and 9.99e-4 (Gauss-FDE−), 2.00e-4 on both (midpoint).
#[test]
fn residual_does_not_grow_with_a_lagrangian_that_grows_along_the_run() {
    let model = CaldirolaKanai {
        gamma: 0.1,
        omega: 2.0,
    };
    let options = CompareOptions {
        order: false,
        ..Default::default()
    };
    for embedding in [
        Embedding::finite_difference(Side::Backward),
        Embedding::midpoint(),
    ] {
        let residual = |t_end: f64| {
            let grid = Grid::new(0.0, t_end, (t_end * 50.0) as usize).unwrap();
            let cmp = varembed_tests::problem(&model, grid, embedding)
                .compare_ivp_with(1.0, 0.0, &options)
                .unwrap();
            [
                cmp.direct.residual_of_other,
                cmp.variational.residual_of_other,
            ]
        };
        let (short, long) = (residual(20.0), residual(200.0));
        for (a, b) in short.iter().zip(&long) {
            assert!(
                *a > 0.0 && (b - a).abs() < 0.1 * a,
                "{embedding}: {a:e} over [0, 20], {b:e} over [0, 200]"
            );
        }
    }
}

/// `c L` has the equations of `L`, the same solutions, and the same relative residual, for
/// scales from 1e-12 to 1e12.
#[test]
fn residual_does_not_change_with_the_scale_of_l() {
    let grid = Grid::new(0.0, 5.0, 100).unwrap();
    let options = CompareOptions {
        order: false,
        ..Default::default()
    };
    for embedding in [
        Embedding::finite_difference(Side::Forward),
        Embedding::asymmetric(Side::Backward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ] {
        let of = |c: f64| {
            let cmp = varembed_tests::problem(&Scaled::new(c, Oscillator), grid, embedding)
                .compare_bvp_with(1.0, -0.5, &options)
                .unwrap();
            [
                cmp.direct.residual_of_other,
                cmp.variational.residual_of_other,
            ]
        };
        let reference = of(1.0);
        for c in [1e-12, 3.7e-5, 1e9, 1e12] {
            for (a, b) in of(c).iter().zip(&reference) {
                // A coherent embedding's residual is round-off, which changes with c.
                let tolerance = 1e-9 * b + 1e-13;
                assert!(
                    (a - b).abs() <= tolerance,
                    "{embedding}, c = {c}: {a:e} vs {b:e}"
                );
            }
        }
    }
}
