//! Newton's answers do not depend on the scale of `L`: `c L` (`c > 0`) has the Euler–Lagrange
//! equations of `L`, so every solver must return the same nodes for it.
//!
//! The property test draws 240 cases from a seeded generator: a factor `c = 10^u`, `u` uniform
//! in `[−12, 12]` (a quarter of the cases `c = 2^k`, `k` in `−39..=39`), a model (pendulum,
//! harmonic oscillator, the 2-D coupled time-dependent model, the Caldirola–Kanai oscillator
//! `e^{γt}(½v² − ½ω²x²)`) and a solver (the const-generic initial value problems of every
//! classical embedding and Gauss–Legendre, the classical boundary value problems, and the
//! fractional ones, dense and fast, the corrected Gauss-GLEσ's direct scheme among them). `c L` must give the nodes of `L` to 1e-9 relative to
//! `max |Q|`; for `c = 2^k` every product by `c` is exact, so every quantity of the solve is
//! scaled exactly and the nodes must be equal bit for bit, with the same Newton iterations.
//! The run-time-dimension solvers have their cases in the `dynamic` test binary.
//!
//! The models' Hessian dependence is the trait's default (`ALL`), so every implicit step runs
//! Newton's method, whose stopping rule is what is under test.

use std::collections::BTreeMap;

use varembed::{
    Embedding, FractionalSolver, Grid, Lagrangian, Problem, Scheme, Side, Solution, Vector,
};
use varembed_tests::curve::{max_diff, max_norm, v1};
use varembed_tests::models::hand::{CaldirolaKanai, Coupled, Oscillator, Pendulum};
use varembed_tests::models::scaled::Scaled;
use varembed_tests::rng::Rng;

/// What a case solves.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// An initial value problem of the scheme under the embedding.
    Ivp(Embedding, Scheme),
    /// A classical boundary value problem.
    Bvp(Embedding, Scheme),
    /// A fractional (Gauss-GLEσ) boundary value problem with the linear solver (`α` drawn per
    /// case).
    Fractional(Side, FractionalSolver),
    /// The direct scheme of the corrected Gauss-GLEσ, likewise.
    Corrected(Side, FractionalSolver),
    /// The direct scheme of the corrected Caputo form, likewise.
    CorrectedCaputo(Side, FractionalSolver),
}

/// Every solver of the property test, with the name its figures are reported under.
fn solvers() -> Vec<(String, Kind)> {
    let mut out = Vec::new();
    for side in [Side::Backward, Side::Forward] {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let embedding = Embedding::finite_difference(side);
            out.push((
                format!("IVP {embedding} {scheme:?}"),
                Kind::Ivp(embedding, scheme),
            ));
        }
    }
    for embedding in [Embedding::midpoint(), Embedding::trapezoidal()] {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            out.push((
                format!("IVP {embedding} {scheme:?}"),
                Kind::Ivp(embedding, scheme),
            ));
        }
    }
    for stages in 1..=3 {
        let embedding = Embedding::gauss_legendre(stages).unwrap();
        out.push((
            format!("IVP {embedding}"),
            Kind::Ivp(embedding, Scheme::Variational),
        ));
    }
    for embedding in [
        Embedding::finite_difference(Side::Backward),
        Embedding::finite_difference(Side::Forward),
        Embedding::asymmetric(Side::Backward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ] {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            out.push((
                format!("BVP {embedding} {scheme:?}"),
                Kind::Bvp(embedding, scheme),
            ));
        }
    }
    for side in [Side::Backward, Side::Forward] {
        for solver in [FractionalSolver::Dense, FractionalSolver::Fast] {
            out.push((
                format!("fractional BVP Gauss-GLE {side:?} {solver:?}"),
                Kind::Fractional(side, solver),
            ));
        }
    }
    out
}

/// The nodes and Newton iterations of `kind` for `lagrangian`, from `(q0, v0)` (initial value
/// problems) or between `q0` and `qb` (boundary value problems).
fn solve<const D: usize, L: Lagrangian<D>>(
    lagrangian: &L,
    kind: Kind,
    (grid, alpha): (Grid, f64),
    (q0, v0, qb): (Vector<D>, Vector<D>, Vector<D>),
) -> varembed::Result<Solution<D>> {
    match kind {
        Kind::Ivp(embedding, scheme) => {
            Problem::new(lagrangian, grid, embedding).solve_ivp(scheme, q0, v0)
        }
        Kind::Bvp(embedding, scheme) => {
            Problem::new(lagrangian, grid, embedding).solve_bvp(scheme, q0, qb)
        }
        Kind::Fractional(side, solver) => {
            let embedding = Embedding::grunwald_letnikov(side, alpha).unwrap();
            Problem::new(lagrangian, grid, embedding)
                .with_fractional_solver(solver)
                .solve_bvp(Scheme::Variational, q0, qb)
        }
        Kind::Corrected(side, solver) | Kind::CorrectedCaputo(side, solver) => {
            let embedding = match kind {
                Kind::Corrected(..) => Embedding::corrected_grunwald_letnikov(side, alpha),
                _ => Embedding::corrected_caputo(side, alpha),
            }
            .unwrap();
            Problem::new(lagrangian, grid, embedding)
                .with_fractional_solver(solver)
                .solve_bvp(Scheme::Direct, q0, qb)
        }
    }
}

/// One case: `model` and `c · model` solved by `kind` from data drawn by `rng`; returns the
/// largest node difference relative to `max |Q|`. For `c = 2^k` (`exact`) the nodes and the
/// iterations must be equal. Where `L`'s solve fails, `c L`'s must fail alike (the same error
/// variant, `None`), and only where `failures` allows it.
fn case<const D: usize, L: Lagrangian<D>>(
    rng: &mut Rng,
    model: &L,
    kind: Kind,
    (c, exact): (f64, bool),
    failures: bool,
) -> Option<f64> {
    let (bvp, n) = match kind {
        Kind::Ivp(..) => (false, 20 + rng.below(61)),
        _ => (true, 8 + rng.below(53)),
    };
    let grid = Grid::new(0.0, if bvp { 1.0 } else { 2.0 }, n).unwrap();
    let alpha = rng.uniform(0.6, 0.95);
    let data = (
        rng.vector::<D>(0.8),
        rng.vector::<D>(0.8),
        rng.vector::<D>(0.8),
    );
    let what = || {
        let model = std::any::type_name::<L>();
        format!("{kind:?} of {model}, c = {c:e} on {grid:?} (α = {alpha}), from {data:?}")
    };
    let (plain, scaled) = match (
        solve(model, kind, (grid, alpha), data),
        solve(&Scaled::new(c, model), kind, (grid, alpha), data),
    ) {
        (Ok(plain), Ok(scaled)) => (plain, scaled),
        (Err(a), Err(b)) if failures => {
            let same = std::mem::discriminant(&a) == std::mem::discriminant(&b);
            assert!(same, "{}: L fails with {a}, c L with {b}", what());
            return None;
        }
        (a, b) => panic!("{}: L gives {:?}, c L {:?}", what(), a.err(), b.err()),
    };
    let gap = max_diff(&plain.q, &scaled.q) / max_norm(&plain.q);
    if exact {
        assert!(
            plain.q == scaled.q && plain.newton_iterations == scaled.newton_iterations,
            "c = {c:e} = 2^k: {kind:?}, N = {n}: nodes {gap:e} apart, iterations {} and {}",
            plain.newton_iterations,
            scaled.newton_iterations
        );
    }
    Some(gap)
}

/// 240 random cases: `c L` gives the nodes of `L` to 1e-9 relative for every solver and model,
/// bit for bit when `c` is a power of two.
#[test]
fn every_solver_gives_c_l_the_nodes_of_l() {
    property(&solvers(), 0x5CA1E, 240, 20, false);
}

/// The same property for the direct scheme of the corrected Gauss-GLEσ, both sides, both
/// fractional solvers: 80 cases of their own. Some data have no solution Newton reaches from
/// the straight line (the coupled model at α ≈ 0.6; the paper's scheme fails on them too):
/// there `c L` must fail as `L` does.
#[test]
fn the_corrected_form_gives_c_l_the_nodes_of_l() {
    let solvers = on_both_sides_and_solvers("corrected Gauss-GLE", Kind::Corrected);
    property(&solvers, 0xC0DE, 80, 4, true);
}

/// The same property for the direct scheme of the corrected Caputo form (whose data need not
/// vanish where the derivative starts), both sides, both fractional solvers: 40 cases of
/// their own.
#[test]
fn the_corrected_caputo_form_gives_c_l_the_nodes_of_l() {
    let solvers = on_both_sides_and_solvers("corrected Caputo Gauss-GLE", Kind::CorrectedCaputo);
    property(&solvers, 0xCA9, 40, 4, true);
}

/// The fractional boundary value problems of `kind` on both sides with both fractional solvers,
/// named after `name`, in the order the property tests draw them from.
fn on_both_sides_and_solvers(
    name: &str,
    kind: fn(Side, FractionalSolver) -> Kind,
) -> Vec<(String, Kind)> {
    let mut solvers = Vec::new();
    for side in [Side::Backward, Side::Forward] {
        for solver in [FractionalSolver::Dense, FractionalSolver::Fast] {
            solvers.push((
                format!("fractional BVP {name} {side:?} {solver:?}"),
                kind(side, solver),
            ));
        }
    }
    solvers
}

/// `cases` random cases drawn from `seed` over `solvers`: each solver drawn must give `c L`
/// the nodes of `L` (at least `least` of them drawn); where `failures`, a case whose `L` fails
/// passes if `c L` fails alike (counted in the report, and at most a quarter of the cases).
fn property(solvers: &[(String, Kind)], seed: u64, cases: usize, least: usize, failures: bool) {
    let mut rng = Rng(seed);
    let mut failed = 0;
    let mut worst: BTreeMap<&str, (f64, usize)> = BTreeMap::new();
    let mut exact_cases = 0;
    for _ in 0..cases {
        let exact = rng.below(4) == 0;
        let c = if exact {
            2f64.powi(rng.below(79) as i32 - 39)
        } else {
            10f64.powf(rng.uniform(-12.0, 12.0))
        };
        exact_cases += usize::from(exact);
        let (name, kind) = &solvers[rng.below(solvers.len())];
        let scale = (c, exact);
        let gap = match rng.below(4) {
            0 => case(
                &mut rng,
                &Pendulum { g: 2.0, l: 1.0 },
                *kind,
                scale,
                failures,
            ),
            1 => case(&mut rng, &Oscillator { omega: 2.0 }, *kind, scale, failures),
            2 => case(&mut rng, &Coupled, *kind, scale, failures),
            _ => {
                let model = CaldirolaKanai {
                    gamma: 0.5,
                    omega: 3.0,
                };
                case(&mut rng, &model, *kind, scale, failures)
            }
        };
        let Some(gap) = gap else {
            failed += 1;
            continue;
        };
        let entry = worst.entry(name).or_insert((0.0, 0));
        *entry = (entry.0.max(gap), entry.1 + 1);
    }
    let mut report = String::new();
    for (name, (gap, count)) in &worst {
        report += &format!("{name}: {gap:.2e} over {count} cases\n");
    }
    eprintln!(
        "largest relative node difference, c L against L ({exact_cases} cases c = 2^k, \
         {failed} failing alike for L and c L):\n{report}"
    );
    assert!(worst.len() >= least, "too few solvers drawn:\n{report}");
    assert!(
        4 * failed <= cases,
        "{failed} of {cases} cases failed:\n{report}"
    );
    assert!(worst.values().all(|&(gap, _)| gap <= 1e-9), "{report}");
}

/// The bug this file guards: at `c = 10⁻⁸` the implicit direct Gauss-FDE− pendulum stopped at
/// the absolute floor of the old rule (`1 + ‖π‖∞`) and moved by 1.7e-5. It must match `c = 1`.
#[test]
fn implicit_direct_pendulum_at_a_tiny_scale_matches_the_unit_scale() {
    let pendulum = Pendulum { g: 9.81, l: 1.0 };
    let grid = Grid::new(0.0, 5.0, 500).unwrap();
    let embedding = Embedding::finite_difference(Side::Backward);
    let run = |c: f64| {
        varembed_tests::problem(&Scaled::new(c, &pendulum), grid, embedding)
            .solve_ivp(Scheme::Direct, 1.0, 0.5)
            .unwrap()
    };
    let (unit, tiny) = (run(1.0), run(1e-8));
    let gap = max_diff(&unit.q, &tiny.q) / max_norm(&unit.q);
    assert!(gap <= 1e-9, "c = 1e-8 against c = 1: {gap:e}");
    assert!(tiny.newton_iterations > 0, "the steps ran Newton");
}

/// A body at rest where every term is exactly zero (the oscillator at rest at 0) stops at once
/// on every solver, at every scale: the residual is exactly zero. And a body at rest at an
/// equilibrium the floating-point numbers miss (the pendulum at `x = π`, where `sin π ≈ 1e-16`)
/// stops at round-off, well before the iteration limit.
#[test]
fn a_body_at_rest_stops() {
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    let zero = Vector::<1>::zeros();
    for (name, kind) in solvers() {
        for c in [1.0, 1e-12, 1e12] {
            let model = Scaled::new(c, Oscillator { omega: 2.0 });
            let run = solve(&model, kind, (grid, 0.8), (zero, zero, zero)).unwrap();
            assert!(
                run.q.iter().all(|q| q[0] == 0.0) && run.newton_iterations == 0,
                "{name}, c = {c:e}: {} iterations",
                run.newton_iterations
            );
        }
    }
    let pendulum = Scaled::new(1e-9, Pendulum { g: 9.81, l: 1.0 });
    let top = v1(std::f64::consts::PI);
    for (name, kind) in solvers() {
        let run = solve(&pendulum, kind, (grid, 0.8), (top, zero, top)).unwrap();
        let per_step = run.newton_iterations as f64 / grid.n() as f64;
        assert!(
            (run.q.last().unwrap()[0] - top[0]).abs() < 1e-6 && per_step <= 10.0,
            "{name}: {} iterations",
            run.newton_iterations
        );
    }
}
