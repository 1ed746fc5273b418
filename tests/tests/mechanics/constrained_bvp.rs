//! Boundary value problems under holonomic constraints (`Problem::solve_constrained_bvp`), and
//! the scale of `L` in every constrained solve, against oracles independent of the constrained
//! boundary value solver:
//!
//! - the constrained initial value problem, a separate step-by-step solver: a boundary value
//!   problem with a constrained run's end values returns its nodes and multipliers, for every
//!   classical embedding and scheme, one constraint (the spherical pendulum) and two (the
//!   four-bar linkage), with and without a force;
//! - the scale of `L`: `c L` has the constrained equations of `L` with multipliers `c λ`, so
//!   every constrained solve must return the nodes of `L` (for `c = 2^k`, bit for bit, with the
//!   same Newton iterations) at generated scales;
//! - the typed errors: an end value off the constraints (naming the end and the constraint),
//!   Gauss–Legendre and the fractional embeddings refused.

use varembed::{
    ConstrainedSolution, Constraint, Embedding, EmbeddingKind, Error, Forced, Grid, Holonomic,
    Lagrangian, Location, Problem, Rayleigh, Scheme, Side, Vector, lagrangian,
    project_initial_data,
};
use varembed_tests::models::scaled::Scaled;
use varembed_tests::rng::Rng;

use super::constraints::{Falling, Linkage, LoopX, LoopY, Sphere, initial, runs};

/// The largest difference of two runs' nodes, and of their multipliers relative to the largest
/// multiplier.
fn differences<const M: usize>(
    a: &ConstrainedSolution<3, M>,
    b: &ConstrainedSolution<3, M>,
) -> (f64, f64) {
    let nodes = a
        .solution
        .q
        .iter()
        .zip(&b.solution.q)
        .map(|(x, y)| (x - y).amax())
        .fold(0.0, f64::max);
    let largest = a.multipliers.iter().map(|m| m.amax()).fold(0.0, f64::max);
    assert_eq!(a.multipliers.len(), b.multipliers.len());
    let multipliers = a
        .multipliers
        .iter()
        .zip(&b.multipliers)
        .map(|(x, y)| (x - y).amax())
        .fold(0.0, f64::max);
    (nodes, multipliers / largest)
}

/// The constrained run from `(q0, v0)`, then the boundary value problem between its end values
/// from the projected straight line: the same nodes to 1e-10 and multipliers to 1e-8 relative.
fn bvp_returns_ivp<L: Lagrangian<3>, C: Constraint<3, M>, const M: usize>(
    model: &L,
    constraint: &C,
    (q0, v0): (Vector<3>, Vector<3>),
    grid: Grid,
    embedding: Embedding,
    scheme: Scheme,
) {
    let problem = Problem::new(model, grid, embedding);
    let run = problem
        .solve_constrained_ivp(scheme, constraint, q0, v0)
        .unwrap();
    let bvp = problem
        .solve_constrained_bvp(scheme, constraint, q0, run.solution.last())
        .unwrap_or_else(|e| panic!("{embedding} {scheme}: {e}"));
    let (nodes, multipliers) = differences(&run, &bvp);
    assert!(
        nodes <= 1e-10 && multipliers <= 1e-8,
        "{embedding} {scheme}: nodes differ by {nodes:e}, multipliers by {multipliers:e} relative"
    );
    let off = bvp
        .solution
        .q
        .iter()
        .map(|q| constraint.value(q).amax())
        .fold(0.0, f64::max);
    assert!(off <= 1e-12, "{embedding} {scheme}: |g| = {off:e}");
}

/// The spherical pendulum over two time units (about a third of a swing), every classical
/// embedding and scheme.
#[test]
fn spherical_pendulum_bvp_returns_the_constrained_run() {
    let grid = Grid::new(0.0, 2.0, 100).unwrap();
    for (embedding, scheme) in runs() {
        bvp_returns_ivp(
            &Falling,
            &Holonomic(Sphere),
            initial(),
            grid,
            embedding,
            scheme,
        );
    }
}

/// Two constraints: the four-bar linkage's loop, over half a time unit (the crank turns by
/// about one radian).
#[test]
fn four_bar_bvp_returns_the_constrained_run() {
    let closure = (Holonomic(LoopX), Holonomic(LoopY));
    let guess = Vector::<3>::new(std::f64::consts::FRAC_PI_2, -0.3, 1.2);
    let data = project_initial_data(&closure, guess, Vector::<3>::new(2.0, 0.0, 0.0)).unwrap();
    let grid = Grid::new(0.0, 0.5, 100).unwrap();
    for (embedding, scheme) in [
        (Embedding::midpoint(), Scheme::Variational),
        (Embedding::trapezoidal(), Scheme::Direct),
        (Embedding::finite_difference(Side::Backward), Scheme::Direct),
        (
            Embedding::finite_difference(Side::Forward),
            Scheme::Variational,
        ),
    ] {
        bvp_returns_ivp(&Linkage, &closure, data, grid, embedding, scheme);
    }
}

/// Under friction too: the forced and constrained boundary value problem returns the forced
/// and constrained run.
#[test]
fn forced_constrained_bvp_returns_the_forced_run() {
    #[lagrangian]
    fn friction(_x: [f64; 3], v: [f64; 3], gamma: f64) -> f64 {
        0.5 * gamma * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    }
    let damped = Forced::new(Falling, Rayleigh(Friction { gamma: 0.3 }));
    let grid = Grid::new(0.0, 2.0, 100).unwrap();
    for (embedding, scheme) in [
        (Embedding::midpoint(), Scheme::Variational),
        (
            Embedding::finite_difference(Side::Backward),
            Scheme::Variational,
        ),
        (Embedding::asymmetric(Side::Forward), Scheme::Direct),
    ] {
        bvp_returns_ivp(
            &damped,
            &Holonomic(Sphere),
            initial(),
            grid,
            embedding,
            scheme,
        );
    }
}

/// 60 generated cases: a factor `c` (`10^u`, `u` uniform in `[−12, 12]`, or `2^k`, `k` in
/// `−39..=39`, half each), a classical embedding and scheme (Gauss–Legendre `s = 1..3`
/// included), and an initial or a boundary value problem of the spherical pendulum. `c L`
/// gives the nodes of `L` to 1e-9 and multipliers `c λ` to 1e-9 relative; for `c = 2^k` the
/// nodes are equal bit for bit, with the same Newton iterations.
#[test]
fn constrained_solves_do_not_depend_on_the_scale_of_l() {
    let mut rng = Rng(0x5ca1e_c0257);
    let mut runs = runs();
    runs.extend((1..=3).map(|s| (Embedding::gauss_legendre(s).unwrap(), Scheme::Variational)));
    let grid = Grid::new(0.0, 2.0, 60).unwrap();
    let (q0, v0) = initial();
    for case in 0..60 {
        let exact = case % 2 == 0;
        let c = if exact {
            2f64.powi(rng.below(79) as i32 - 39)
        } else {
            10f64.powf(rng.uniform(-12.0, 12.0))
        };
        let (embedding, scheme) = runs[rng.below(runs.len())];
        // Gauss–Legendre has initial value problems only.
        let one_step = matches!(embedding.kind(), EmbeddingKind::GaussLegendre { .. });
        let boundary = rng.below(2) == 1 && !one_step;
        let scaled = Scaled::new(c, Falling);
        // A boundary value problem between the ends of the unscaled run.
        let end = boundary.then(|| {
            varembed_tests::problem(&Falling, grid, embedding)
                .solve_constrained_ivp(scheme, &Holonomic(Sphere), q0, v0)
                .unwrap()
                .solution
                .last()
        });
        let run = |problem: &dyn Solve| problem.solve(scheme, (q0, v0), end);
        let (plain, times_c) = (
            run(&Problem::new(&Falling, grid, embedding)),
            run(&Problem::new(&scaled, grid, embedding)),
        );
        let what = format!("case {case}: c = {c:e}, {embedding} {scheme}, boundary {boundary}");
        let unscaled = ConstrainedSolution {
            solution: times_c.solution.clone(),
            multipliers: times_c.multipliers.iter().map(|m| m / c).collect(),
        };
        let (nodes, multipliers) = differences(&plain, &unscaled);
        assert!(
            nodes <= 1e-9 && multipliers <= 1e-9,
            "{what}: nodes differ by {nodes:e}, multipliers by {multipliers:e} relative"
        );
        if exact {
            let equal = plain.solution.q == times_c.solution.q;
            assert!(equal, "{what}: not bit for bit, nodes differ by {nodes:e}");
            assert_eq!(
                plain.solution.newton_iterations, times_c.solution.newton_iterations,
                "{what}"
            );
        }
    }
}

/// A constrained initial value problem from `(q0, v0)`, or the boundary value problem from
/// `q0` to `end` when one is given.
trait Solve {
    fn solve(
        &self,
        scheme: Scheme,
        data: (Vector<3>, Vector<3>),
        end: Option<Vector<3>>,
    ) -> ConstrainedSolution<3, 1>;
}

impl<L: Lagrangian<3>> Solve for Problem<'_, L, 3> {
    fn solve(
        &self,
        scheme: Scheme,
        (q0, v0): (Vector<3>, Vector<3>),
        end: Option<Vector<3>>,
    ) -> ConstrainedSolution<3, 1> {
        let sphere = Holonomic(Sphere);
        match end {
            None => self.solve_constrained_ivp(scheme, &sphere, q0, v0),
            Some(end) => self.solve_constrained_bvp(scheme, &sphere, q0, end),
        }
        .unwrap()
    }
}

/// An end value off the sphere is an error naming the end and the constraint; Gauss–Legendre
/// and the fractional embeddings are refused.
#[test]
fn constrained_bvp_errors_are_typed() {
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    let problem = varembed_tests::problem(&Falling, grid, Embedding::midpoint());
    let on = Vector::<3>::new(0.0, 0.0, -1.0);
    let off = Vector::<3>::new(0.0, 0.6, -0.9);
    for (qa, qb, end) in [(off, on, "a"), (on, off, "b")] {
        let error = problem
            .solve_constrained_bvp(Scheme::Variational, &Holonomic(Sphere), qa, qb)
            .unwrap_err();
        assert!(
            matches!(error, Error::InconsistentBoundaryData { end: e, constraint: 0, .. } if e == end),
            "{error:?}"
        );
        assert!(
            error.to_string().contains("project_initial_data"),
            "{error}"
        );
    }
    let side = Vector::<3>::new(1.0, 0.0, 0.0);
    for embedding in [
        Embedding::gauss_legendre(2).unwrap(),
        Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap(),
    ] {
        let error = varembed_tests::problem(&Falling, grid, embedding)
            .solve_constrained_bvp(Scheme::Variational, &Holonomic(Sphere), on, side)
            .unwrap_err();
        assert!(
            matches!(error, Error::Unsupported { .. }),
            "{embedding}: {error:?}"
        );
    }
}

/// The smallest grids (`N = 1`: no unknowns; `N = 2`: one row, whose constraint force sits on
/// an end under the direct Gauss-FDE∓ schemes) solve, with one multiplier per row; a guess of
/// the path (`solve_constrained_bvp_from`) gives the straight line's solution; ends whose
/// straight line crosses the sphere's centre are `RankDeficientConstraints` at that node, and
/// solve from a guess of the path.
#[test]
fn constrained_bvp_edge_cases() {
    let sphere = Holonomic(Sphere);
    let (bottom, side) = (
        Vector::<3>::new(0.0, 0.0, -1.0),
        Vector::<3>::new(1.0, 0.0, 0.0),
    );
    for n in [1, 2] {
        for (embedding, scheme) in runs() {
            let problem = varembed_tests::problem(
                &Falling,
                Grid::new(0.0, 0.1 * n as f64, n).unwrap(),
                embedding,
            );
            let run = problem
                .solve_constrained_bvp(scheme, &sphere, bottom, side)
                .unwrap_or_else(|e| panic!("N = {n}, {embedding} {scheme}: {e}"));
            assert_eq!(run.solution.q.len(), n + 1);
            assert_eq!(
                run.multipliers.len(),
                n - 1,
                "N = {n}, {embedding} {scheme}"
            );
            let off = run
                .solution
                .q
                .iter()
                .map(|q| sphere.value(q).amax())
                .fold(0.0, f64::max);
            assert!(off <= 1e-12, "N = {n}, {embedding} {scheme}: |g| = {off:e}");
        }
    }
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    let problem = varembed_tests::problem(&Falling, grid, Embedding::midpoint());
    let straight = problem
        .solve_constrained_bvp(Scheme::Variational, &sphere, bottom, side)
        .unwrap();
    // A guess along the great circle through the ends, slightly off it.
    let arc: Vec<Vector<3>> = (0..=20)
        .map(|k| {
            let angle = std::f64::consts::FRAC_PI_2 * k as f64 / 20.0;
            let wobble = if k == 0 || k == 20 { 0.0 } else { 0.05 };
            Vector::<3>::new(angle.sin(), wobble, -angle.cos())
        })
        .collect();
    let from_arc = problem
        .solve_constrained_bvp_from(Scheme::Variational, &sphere, &arc)
        .unwrap();
    let (nodes, multipliers) = differences(&straight, &from_arc);
    assert!(
        nodes <= 1e-12 && multipliers <= 1e-10,
        "{nodes:e}, {multipliers:e}"
    );
    let antipodal = problem.solve_constrained_bvp(Scheme::Variational, &sphere, bottom, -bottom);
    assert!(
        matches!(
            antipodal,
            Err(Error::RankDeficientConstraints {
                at: Location::Node(10),
                ..
            })
        ),
        "{antipodal:?}"
    );
    let over_the_side: Vec<Vector<3>> = (0..=20)
        .map(|k| {
            let angle = std::f64::consts::PI * k as f64 / 20.0;
            Vector::<3>::new(angle.sin(), 0.0, -angle.cos())
        })
        .collect();
    let run = problem
        .solve_constrained_bvp_from(Scheme::Variational, &sphere, &over_the_side)
        .unwrap();
    // The guess's end values are the problem's (the top of the sphere, to round-off).
    assert_eq!(run.solution.last(), over_the_side[20]);
    assert!((run.solution.last() + bottom).amax() < 1e-15);
}
