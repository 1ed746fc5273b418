//! A forcing term that is huge at an end of the interval, where no row of the fractional
//! boundary value problem reads it, does not change the solution.
//!
//! `L = ½v² − ½x² − F(t) x` under Gauss-GLEσ: the force `∂L/∂x = −x − F(t)` is evaluated at
//! every quadrature node, the end node `t = b` (σ = −) or `t = a` (σ = +) included, but the rows
//! are the interior nodes. With the end's force in the scale of Newton's stopping rule, a
//! forcing singular there (`F = 1/|t_end − t|`, or `10³⁰⁰` at the end only) made the tolerance
//! astronomical, and the solve stopped at its straight-line guess (an error of 0.18, reported
//! as a success). Now the scale is the rows', and the nodes are those of the same forcing set to
//! 0 at the end, bit for bit, for the dense and the fast solver.

use varembed::{
    Embedding, FractionalSolver, Grid, Hessian, Lagrangian, Matrix, Scheme, Side, Vector,
};
use varembed_tests::curve::{max_diff, v1};

/// `L = ½v² − ½x² − F(t) x`, `F` given at every time but `end`, where it is `at_end`.
struct Forced {
    /// The end node's time, `a` or `b`.
    end: f64,
    /// `F` away from the end.
    forcing: fn(f64, f64) -> f64,
    /// `F(end)`.
    at_end: f64,
}

impl Forced {
    fn forcing(&self, t: f64) -> f64 {
        if t == self.end {
            self.at_end
        } else {
            (self.forcing)(t, self.end)
        }
    }
}

impl Lagrangian<1> for Forced {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
        0.5 * v[0] * v[0] - 0.5 * x[0] * x[0] - self.forcing(t) * x[0]
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
        (v1(-x[0] - self.forcing(t)), *v)
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::new(-1.0),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}

/// `1/(|t_end − t| + 10⁻³⁰⁰)`: singular at the end (`10³⁰⁰` there), `1/h` at its neighbour.
fn singular(t: f64, end: f64) -> f64 {
    1.0 / ((end - t).abs() + 1e-300)
}

/// A smooth forcing, `2 + sin 3t`.
fn smooth(t: f64, _end: f64) -> f64 {
    2.0 + (3.0 * t).sin()
}

#[test]
fn a_forcing_huge_at_the_end_node_leaves_the_nodes_unchanged() {
    let grid = Grid::new(0.0, 1.0, 40).unwrap();
    for (side, end) in [(Side::Backward, grid.b()), (Side::Forward, grid.a())] {
        assert_eq!(grid.t(if end == grid.a() { 0 } else { grid.n() }), end);
        let embedding = Embedding::grunwald_letnikov(side, 0.8).unwrap();
        for (name, forcing, at_end) in [
            (
                "1/|t_end − t|",
                singular as fn(f64, f64) -> f64,
                singular(end, end),
            ),
            ("1e300 at the end", smooth, 1e300),
        ] {
            for solver in [FractionalSolver::Dense, FractionalSolver::Fast] {
                let solve = |at_end| {
                    let model = Forced {
                        end,
                        forcing,
                        at_end,
                    };
                    varembed_tests::problem(&model, grid, embedding)
                        .with_fractional_solver(solver)
                        .solve_bvp(Scheme::Variational, 0.0, 1.0)
                        .unwrap()
                };
                let (huge, zero) = (solve(at_end), solve(0.0));
                let line: Vec<Vector<1>> = (0..=grid.n())
                    .map(|k| v1(k as f64 / grid.n() as f64))
                    .collect();
                assert!(
                    huge.q == zero.q && zero.newton_iterations > 0,
                    "{side:?}, F = {name}, {solver:?}: {:e} from the nodes with F(end) = 0 \
                     ({} and {} iterations), {:e} from the straight line",
                    max_diff(&huge.q, &zero.q),
                    huge.newton_iterations,
                    zero.newton_iterations,
                    max_diff(&huge.q, &line),
                );
            }
        }
    }
}
