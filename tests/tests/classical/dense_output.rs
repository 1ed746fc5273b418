//! Dense output against exact solutions between the nodes: `q`, `v` (and `p` with the
//! Lagrangian) at the midpoint of every step converge at the orders core/docs/solvers.md documents,
//! for every embedding and scheme with node values, on the harmonic oscillator and on the
//! pendulum (closed form by Jacobi elliptic functions); at a node the value is the node; the
//! const-generic and the run-time-dimension paths agree on a model that implements both
//! traits, stored every node or every `s`-th; bad times and the fractional embeddings are
//! typed errors.

use varembed::{
    DynProblem, DynSolution, Embedding, EmbeddingKind, Error, Grid, Hessian, Lagrangian, Matrix,
    Problem, Scheme, Side, Solution, Start, Vector, lagrangian, observed_orders,
};
use varembed_tests::reference::PendulumFromRest;

/// `L = ½mv² − ½kx²` with `m = 2`, `k = 8`: `ω = 2`, `p = 2v`.
#[lagrangian]
fn spring(x: f64, v: f64, m: f64, k: f64) -> f64 {
    0.5 * m * v * v - 0.5 * k * x * x
}

/// `L = ½v² + cos x`: `p = v`.
#[lagrangian]
fn pendulum(x: f64, v: f64) -> f64 {
    0.5 * v * v + x.cos()
}

const SPRING: Spring = Spring { m: 2.0, k: 8.0 };

/// The oscillator from `q(0) = 1`, `q̇(0) = 0.5`: `(q, q̇)` at `t`.
fn oscillation(t: f64) -> (f64, f64) {
    let (s, c) = (2.0 * t).sin_cos();
    (c + 0.25 * s, -2.0 * s + 0.5 * c)
}

/// How a case is solved.
#[derive(Clone, Copy, Debug)]
enum Run {
    /// An initial value problem from the exact `q(0)`, `q̇(0)`, with this start.
    Ivp(Start),
    /// A boundary value problem between the exact `q(a)`, `q(b)`.
    Bvp,
}

/// One embedding and scheme, how it is solved, on which grids, and the orders of `q` and `v`
/// between the nodes that core/docs/solvers.md documents for it.
#[derive(Clone, Copy, Debug)]
struct Case {
    embedding: Embedding,
    scheme: Scheme,
    run: Run,
    /// `[0, b]` with `N, 2N, 4N` steps.
    b: f64,
    n: usize,
    /// The order of `Solution::state_at` (and of `Solution::at`, unless `at_at_least`).
    order: f64,
    /// `Solution::at` is documented as `order` only asymptotically (Gauss–Legendre with 3 or
    /// 4 stages, whose positions-only polynomial's own error dominates wherever the nodes'
    /// error is above round-off): its observed orders, on their way, are at least `order − 1`.
    at_at_least: bool,
}

/// The paper's and the symmetric embeddings, both schemes, from both starts and as boundary
/// value problems, on `[0, b]` with `n` steps (`n/2` for the second-order embeddings).
fn classical_cases(b: f64, n: usize) -> Vec<Case> {
    let mut cases = Vec::new();
    for side in [Side::Backward, Side::Forward] {
        for embedding in [
            Embedding::finite_difference(side),
            Embedding::asymmetric(side),
        ] {
            for scheme in [Scheme::Direct, Scheme::Variational] {
                // Störmer–Verlet (the variational recurrence, which the asymmetric direct
                // scheme is too) is second order from the second-order start and as a
                // boundary value problem on L = ½v² − U; the rest first order.
                let verlet =
                    scheme == Scheme::Variational || embedding == Embedding::asymmetric(side);
                for (run, order) in [
                    (Run::Ivp(Start::Legendre), 1.0),
                    (Run::Ivp(Start::SecondOrder), if verlet { 2.0 } else { 1.0 }),
                    (Run::Bvp, if verlet { 2.0 } else { 1.0 }),
                ] {
                    cases.push(Case {
                        embedding,
                        scheme,
                        run,
                        b,
                        n,
                        order,
                        at_at_least: false,
                    });
                }
            }
        }
    }
    for embedding in [Embedding::midpoint(), Embedding::trapezoidal()] {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            for run in [Run::Ivp(Start::Legendre), Run::Bvp] {
                cases.push(Case {
                    embedding,
                    scheme,
                    run,
                    b,
                    n: n / 2,
                    order: 2.0,
                    at_at_least: false,
                });
            }
        }
    }
    cases
}

/// Gauss–Legendre with `s = 1..=4` stages on `[0, b]` with `n[s − 1]` steps.
fn gauss_cases(b: f64, n: [usize; 4]) -> Vec<Case> {
    (1..=4)
        .map(|s| Case {
            embedding: Embedding::gauss_legendre(s).unwrap(),
            scheme: Scheme::Variational,
            run: Run::Ivp(Start::Legendre),
            b,
            n: n[s - 1],
            order: 2.0 * s as f64,
            at_at_least: s >= 3,
        })
        .collect()
}

/// The largest errors over the midpoints of the steps: `[q, v]` of `at`, `[q, v, p]` of
/// `state_at`, and the largest error of the nodes themselves.
#[derive(Clone, Copy, Debug)]
struct Errors {
    at: [f64; 2],
    state: [f64; 3],
    nodes: f64,
}

fn solve<L: Lagrangian<1>>(
    model: &L,
    case: &Case,
    n: usize,
    exact: &dyn Fn(f64) -> (f64, f64),
) -> Solution<1> {
    let problem = Problem::new(model, Grid::new(0.0, case.b, n).unwrap(), case.embedding);
    let (q0, v0) = exact(0.0);
    match case.run {
        Run::Ivp(start) => problem.solve_ivp_with(case.scheme, q0, v0, start),
        Run::Bvp => problem.solve_bvp(case.scheme, q0, exact(case.b).0),
    }
    .unwrap()
}

/// [`Errors`] of `solution` against `exact`, `p = mass · q̇`.
fn midpoint_errors<L: Lagrangian<1>>(
    model: &L,
    solution: &Solution<1>,
    exact: &dyn Fn(f64) -> (f64, f64),
    mass: f64,
) -> Errors {
    let t = solution.times();
    let mut errors = Errors {
        at: [0.0; 2],
        state: [0.0; 3],
        nodes: 0.0,
    };
    for k in 0..t.len() - 1 {
        let middle = 0.5 * (t[k] + t[k + 1]);
        let (q, v) = exact(middle);
        let (at_q, at_v) = solution.at(middle).unwrap();
        let state = solution.state_at(middle, model).unwrap();
        assert_eq!(state.t, middle);
        if !matches!(
            solution.embedding.kind(),
            EmbeddingKind::GaussLegendre { .. }
        ) {
            // Only Gauss–Legendre's Lagrangian form has a polynomial of its own.
            assert_eq!((state.q, state.v), (at_q, at_v));
        }
        assert!((state.p[0] - mass * state.v[0]).abs() <= 1e-12 * (1.0 + state.p[0].abs()));
        for (e, x) in errors.at.iter_mut().zip([at_q[0] - q, at_v[0] - v]) {
            *e = e.max(x.abs());
        }
        let gaps = [state.q[0] - q, state.v[0] - v, state.p[0] - mass * v];
        for (e, x) in errors.state.iter_mut().zip(gaps) {
            *e = e.max(x.abs());
        }
    }
    for (k, node) in solution.q.iter().enumerate() {
        errors.nodes = errors.nodes.max((node[0] - exact(t[k]).0).abs());
    }
    errors
}

/// Every case's observed orders between the nodes on `N, 2N, 4N`, held to its documented ones
/// (±0.15); each case printed (`--nocapture`) with its coarsest errors.
fn check_orders<L: Lagrangian<1>>(
    name: &str,
    model: &L,
    cases: &[Case],
    exact: &dyn Fn(f64) -> (f64, f64),
    mass: f64,
) {
    for case in cases {
        let levels: Vec<(usize, Errors)> = [case.n, 2 * case.n, 4 * case.n]
            .into_iter()
            .map(|n| {
                (
                    n,
                    midpoint_errors(model, &solve(model, case, n, exact), exact, mass),
                )
            })
            .collect();
        let orders = |pick: &dyn Fn(&Errors) -> f64| {
            let errors: Vec<(usize, f64)> = levels.iter().map(|(n, e)| (*n, pick(e))).collect();
            observed_orders(&errors)
        };
        let label = format!(
            "{name}: {} {} {:?}, N = {}",
            case.scheme, case.embedding, case.run, case.n
        );
        let columns: [(&str, Vec<f64>, f64); 6] = [
            ("nodes", orders(&|e| e.nodes), levels[0].1.nodes),
            ("at q", orders(&|e| e.at[0]), levels[0].1.at[0]),
            ("at v", orders(&|e| e.at[1]), levels[0].1.at[1]),
            ("state q", orders(&|e| e.state[0]), levels[0].1.state[0]),
            ("state v", orders(&|e| e.state[1]), levels[0].1.state[1]),
            ("state p", orders(&|e| e.state[2]), levels[0].1.state[2]),
        ];
        let line: Vec<String> = columns
            .iter()
            .map(|(what, o, e)| format!("{what} {e:.1e} ({:.2}, {:.2})", o[0], o[1]))
            .collect();
        println!("{label}: {}", line.join(", "));
        for (what, observed, _) in &columns[1..] {
            for &p in observed {
                if what.starts_with("at") && case.at_at_least {
                    assert!(
                        p >= case.order - 1.0,
                        "{label}: {what} order {p}, at least {}",
                        case.order - 1.0
                    );
                } else {
                    assert!(
                        (p - case.order).abs() <= 0.15,
                        "{label}: {what} order {p}, documented {}",
                        case.order
                    );
                }
            }
        }
    }
}

#[test]
fn the_oscillator_between_the_nodes_converges_at_the_documented_orders() {
    let mut cases = classical_cases(3.0, 200);
    cases.extend(gauss_cases(10.0, [80, 40, 20, 20]));
    check_orders("oscillator", &SPRING, &cases, &oscillation, SPRING.m);
}

#[test]
fn the_pendulum_between_the_nodes_converges_at_the_documented_orders() {
    // Released from rest at 1 rad: strongly nonlinear over [0, 3].
    let swing = PendulumFromRest::new(1.0);
    check_orders(
        "pendulum",
        &Pendulum,
        &classical_cases(3.0, 200),
        &|t| swing.at(t),
        1.0,
    );
    // Gauss–Legendre's errors are tiny: from 0.5 rad over [0, 40] (six periods) the nodes' error
    // stays above round-off on N, 2N, 4N while the Hermite polynomial's own error is below it.
    let swing = PendulumFromRest::new(0.5);
    check_orders(
        "pendulum",
        &Pendulum,
        &gauss_cases(40.0, [200, 200, 64, 64]),
        &|t| swing.at(t),
        1.0,
    );
}

/// Every embedding and scheme that has node values, hence dense output.
fn with_node_values() -> Vec<(Embedding, Scheme)> {
    let mut all = Vec::new();
    for embedding in [
        Embedding::finite_difference(Side::Backward),
        Embedding::finite_difference(Side::Forward),
        Embedding::asymmetric(Side::Backward),
        Embedding::asymmetric(Side::Forward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ] {
        all.push((embedding, Scheme::Direct));
        all.push((embedding, Scheme::Variational));
    }
    for s in 1..=4 {
        all.push((Embedding::gauss_legendre(s).unwrap(), Scheme::Variational));
    }
    all
}

/// `n` nodes `Q_k = c(t_k)` on `[−1, 2]` as a solution of `(embedding, scheme)`, with the
/// momenta `c'(t_k)` (the velocities of `L = ½v²`).
fn sampled(
    embedding: Embedding,
    scheme: Scheme,
    n: usize,
    c: &dyn Fn(f64) -> (f64, f64),
) -> Solution<1> {
    let grid = Grid::new(-1.0, 2.0, n).unwrap();
    Solution {
        scheme,
        embedding,
        grid,
        q: grid
            .nodes()
            .iter()
            .map(|&t| Vector::<1>::new(c(t).0))
            .collect(),
        momenta: grid
            .nodes()
            .iter()
            .map(|&t| Vector::<1>::new(c(t).1))
            .collect(),
        newton_iterations: 0,
        explicit_steps: 0,
        warnings: Vec::new(),
    }
}

/// `L = ½v² + x f(t)` with `f(t) = d(d − 1) t^{d−2}`: `p = v`, `q̈ = f`, so `t^d` is a
/// solution, and its node accelerations are exact.
struct Forced {
    degree: i32,
}

impl Forced {
    fn force(&self, t: f64) -> f64 {
        let d = self.degree;
        if d < 2 {
            0.0
        } else {
            (d * (d - 1)) as f64 * t.powi(d - 2)
        }
    }
}

impl Lagrangian<1> for Forced {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
        0.5 * v[0] * v[0] + x[0] * self.force(t)
    }
    fn gradient(&self, _x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
        (Vector::<1>::new(self.force(t)), *v)
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::zeros(),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}

#[test]
fn the_polynomials_have_the_documented_degrees_and_are_one_sided_near_the_ends() {
    // At every t, in the interior and at the ends, each polynomial reproduces a polynomial of
    // its degree, `t^d − t/2`, and its slope: the positions-only one of degree 3 (2s + 1 for
    // Gauss–Legendre), the Hermite one of Gauss–Legendre of degree 5 (11 for s = 3, 4). With
    // fewer nodes than their stencils (N = 1, 2) they read all of them: a straight line.
    for (embedding, scheme) in with_node_values() {
        let (lagrange, hermite) = match embedding.kind() {
            EmbeddingKind::GaussLegendre { stages } => (
                2 * stages as i32 + 1,
                Some(if stages <= 2 { 5 } else { 11 }),
            ),
            _ => (3, None),
        };
        for degree in [Some(lagrange), hermite].into_iter().flatten() {
            let power = move |t: f64| {
                (
                    t.powi(degree) - 0.5 * t,
                    degree as f64 * t.powi(degree - 1) - 0.5,
                )
            };
            let line = |t: f64| (0.3 - 0.7 * t, -0.7);
            let forced = Forced { degree };
            let free = Forced { degree: 1 };
            for (n, curve, model) in [
                (1, &line as &dyn Fn(f64) -> (f64, f64), &free),
                (2, &line, &free),
                (12, &power, &forced),
                (40, &power, &forced),
            ] {
                let solution = sampled(embedding, scheme, n, curve);
                for j in 0..=300 {
                    let t = -1.0 + 3.0 * j as f64 / 300.0;
                    let (exact_q, exact_v) = curve(t);
                    let label = format!("{scheme} {embedding}, degree {degree}, N = {n}, t = {t}");
                    let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol * (1.0 + b.abs());
                    if degree == lagrange || n <= 2 {
                        let (q, v) = solution.at(t).unwrap();
                        assert!(
                            close(q[0], exact_q, 1e-11) && close(v[0], exact_v, 1e-9),
                            "{label}: at"
                        );
                    }
                    if hermite == Some(degree) || n <= 2 {
                        let state = solution.state_at(t, model).unwrap();
                        assert!(
                            close(state.q[0], exact_q, 1e-11) && close(state.v[0], exact_v, 1e-9),
                            "{label}: state_at"
                        );
                        assert_eq!((state.p, state.energy), (state.v, None)); // L depends on t
                    }
                }
            }
        }
    }
}

#[test]
fn at_a_node_the_position_is_the_node() {
    for (embedding, scheme) in with_node_values() {
        for n in [1, 2, 5, 16] {
            let grid = Grid::new(0.0, 1.6, n).unwrap();
            let solution = varembed_tests::problem(&SPRING, grid, embedding)
                .solve_ivp(scheme, 1.0, 0.5)
                .unwrap();
            let nodes = solution.node_values(&SPRING).unwrap();
            for (k, &t) in solution.times().iter().enumerate() {
                let label = format!("{scheme} {embedding}, N = {n}, node {k}");
                assert_eq!(solution.at(t).unwrap().0, solution.q[k], "{label}");
                let state = solution.state_at(t, &SPRING).unwrap();
                assert_eq!((state.t, state.q), (t, solution.q[k]), "{label}");
                if matches!(embedding.kind(), EmbeddingKind::GaussLegendre { .. }) {
                    // The Hermite polynomial takes the node velocity as its slope there.
                    let gap = (state.v[0] - nodes.v[k][0]).abs();
                    assert!(gap < 1e-12 * (1.0 + nodes.v[k][0].abs()), "{label}: {gap}");
                }
            }
        }
    }
}

/// Three pendulums joined by springs, written with loops: both traits.
const CHAIN: usize = 3;

#[lagrangian]
fn pendulums(x: [f64; CHAIN], v: [f64; CHAIN], kappa: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..CHAIN {
        l += 0.5 * v[i] * v[i] + x[i].cos();
    }
    for i in 0..CHAIN - 1 {
        let d = x[i + 1] - x[i];
        l -= 0.5 * kappa * d * d;
    }
    l
}

const PENDULUMS: Pendulums = Pendulums { kappa: 0.7 };
const Q0: [f64; CHAIN] = [0.3, -0.2, 0.5];
const V0: [f64; CHAIN] = [0.0, 0.1, -0.2];

/// The run of `(embedding, scheme, run)` on `grid` on both paths (the run-time one storing
/// every `stride`-th node).
fn both_paths(
    (embedding, scheme, run): (Embedding, Scheme, Run),
    grid: Grid,
    stride: usize,
) -> (Solution<CHAIN>, DynSolution) {
    let end = [0.1, 0.4, -0.3];
    let problem = varembed_tests::problem(&PENDULUMS, grid, embedding);
    let dynamic = DynProblem::new(&PENDULUMS, grid, embedding);
    match run {
        Run::Ivp(start) => (
            problem.solve_ivp_with(scheme, Q0, V0, start).unwrap(),
            dynamic
                .with_start(start)
                .solve_ivp_every(scheme, &Q0, &V0, stride)
                .unwrap(),
        ),
        Run::Bvp => (
            problem.solve_bvp(scheme, Q0, end).unwrap(),
            dynamic.solve_bvp(scheme, &Q0, &end).unwrap(),
        ),
    }
}

#[test]
fn both_paths_give_the_same_values_between_the_nodes() {
    let grid = Grid::new(0.0, 2.0, 50).unwrap();
    for side in [Side::Backward, Side::Forward] {
        for embedding in [
            Embedding::finite_difference(side),
            Embedding::asymmetric(side),
        ] {
            for scheme in [Scheme::Direct, Scheme::Variational] {
                for run in [
                    Run::Ivp(Start::Legendre),
                    Run::Ivp(Start::SecondOrder),
                    Run::Bvp,
                ] {
                    let (fixed, dynamic) = both_paths((embedding, scheme, run), grid, 1);
                    let label = format!("{scheme} {embedding} {run:?}");
                    let (mut q, mut v) = (vec![0.0; CHAIN], vec![0.0; CHAIN]);
                    for j in 0..=173 {
                        let t = 2.0 * j as f64 / 173.0;
                        let (fq, fv) = fixed.at(t).unwrap();
                        dynamic.at_into(t, &mut q, &mut v).unwrap();
                        assert_eq!(dynamic.at(t).unwrap(), (q.clone(), v.clone()));
                        let state = fixed.state_at(t, &PENDULUMS).unwrap();
                        let dyn_state = dynamic.state_at(t, &PENDULUMS).unwrap();
                        assert_eq!((dyn_state.t, &dyn_state.q, &dyn_state.v), (t, &q, &v));
                        for i in 0..CHAIN {
                            // The nodes agree to round-off; v and p are their differences over h.
                            assert!((fq[i] - q[i]).abs() < 1e-13, "{label}, t = {t}: q");
                            assert!((fv[i] - v[i]).abs() < 1e-11, "{label}, t = {t}: v");
                            assert!(
                                (state.p[i] - dyn_state.p[i]).abs() < 1e-11,
                                "{label}, t = {t}: p"
                            );
                        }
                        let energies = (state.energy.unwrap(), dyn_state.energy.unwrap());
                        assert!(
                            (energies.0 - energies.1).abs() < 1e-11,
                            "{label}, t = {t}: E"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn a_run_stored_every_s_th_node_is_interpolated_through_those() {
    // Stride 3 on N = 100, 200, 400 (never a multiple of 3: a short last gap every time). The
    // stored nodes' cubic differs from the full run's by its own error in the stored spacing
    // H = 3h: fourth order in q, third in v. At a stored node, q is that node.
    let case = (
        Embedding::finite_difference(Side::Backward),
        Scheme::Variational,
        Run::Ivp(Start::SecondOrder),
    );
    let mut gaps = Vec::new();
    for n in [100, 200, 400] {
        let grid = Grid::new(0.0, 4.0, n).unwrap();
        let (_, full) = both_paths(case, grid, 1);
        let (_, strided) = both_paths(case, grid, 3);
        assert_eq!(*strided.indices.last().unwrap(), n);
        assert_ne!(n % 3, 0);
        for (j, &k) in strided.indices.iter().enumerate() {
            assert_eq!(strided.at(grid.t(k)).unwrap().0, strided.node(j));
            assert_eq!(full.node(k), strided.node(j));
        }
        let (mut q_gap, mut v_gap) = (0.0f64, 0.0f64);
        for k in 0..n {
            let t = grid.t(k) + 0.37 * grid.h();
            let ((fq, fv), (sq, sv)) = (full.at(t).unwrap(), strided.at(t).unwrap());
            for i in 0..CHAIN {
                q_gap = q_gap.max((fq[i] - sq[i]).abs());
                v_gap = v_gap.max((fv[i] - sv[i]).abs());
            }
        }
        println!("stride 3, N = {n}: |q − q_full| {q_gap:.2e}, |v − v_full| {v_gap:.2e}");
        gaps.push((n, [q_gap, v_gap]));
    }
    for (i, expected) in [4.0, 3.0].into_iter().enumerate() {
        let errors: Vec<(usize, f64)> = gaps.iter().map(|(n, g)| (*n, g[i])).collect();
        for order in observed_orders(&errors) {
            assert!(
                (order - expected).abs() < 0.3,
                "stride: order {order}, expected {expected}"
            );
        }
    }
}

/// `L = ½v²·√(x − 10)`: its momentum is NaN wherever `x < 10`.
#[lagrangian]
fn beyond(x: f64, v: f64) -> f64 {
    0.5 * v * v * (x - 10.0).sqrt()
}

/// [`Beyond`] for three components, both traits.
#[lagrangian]
fn beyond_chain(x: [f64; CHAIN], v: [f64; CHAIN]) -> f64 {
    let mut l = 0.0;
    for i in 0..CHAIN {
        l += 0.5 * v[i] * v[i] * (x[i] - 10.0).sqrt();
    }
    l
}

/// `L = ½(v² − x²)` on four components, to be asked of a three-component solution.
#[lagrangian]
fn four(x: [f64; 4], v: [f64; 4]) -> f64 {
    let mut l = 0.0;
    for i in 0..4 {
        l += 0.5 * (v[i] * v[i] - x[i] * x[i]);
    }
    l
}

#[test]
fn bad_times_and_embeddings_without_node_values_are_typed_errors() {
    let grid = Grid::new(0.0, 2.0, 20).unwrap();
    let case = (
        Embedding::finite_difference(Side::Forward),
        Scheme::Direct,
        Run::Ivp(Start::Legendre),
    );
    let (fixed, dynamic) = both_paths(case, grid, 1);
    for t in [
        -1e-9,
        2.0 + 1e-9,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        -5.0,
    ] {
        let expected = |e: Error| matches!(e, Error::TimeOutOfRange { t: bad, a, b } if (bad == t || t.is_nan() && bad.is_nan()) && (a, b) == (0.0, 2.0));
        assert!(expected(fixed.at(t).unwrap_err()), "{t}");
        assert!(expected(fixed.state_at(t, &PENDULUMS).unwrap_err()), "{t}");
        assert!(expected(dynamic.at(t).unwrap_err()), "{t}");
        assert!(
            expected(dynamic.state_at(t, &PENDULUMS).unwrap_err()),
            "{t}"
        );
    }
    let message = fixed.at(f64::NAN).unwrap_err().to_string();
    assert_eq!(
        message,
        "the time t = NaN is outside the solution's interval [0, 2]"
    );
    // The ends themselves are inside.
    assert_eq!(fixed.at(0.0).unwrap().0, fixed.q[0]);
    assert_eq!(dynamic.at(2.0).unwrap().0, dynamic.node(20));

    // The fractional embeddings have no node values (α = 1 included, as for node_values).
    for alpha in [0.7, 1.0] {
        let gle = Embedding::grunwald_letnikov(Side::Backward, alpha).unwrap();
        let solution = varembed_tests::problem(&Pendulum, grid, gle)
            .solve_bvp(Scheme::Variational, 0.0, 1.0)
            .unwrap();
        let error = solution.at(1.0).unwrap_err();
        assert_eq!(
            error,
            Error::Unsupported {
                operation: "Solution::at",
                embedding: gle.to_string()
            }
        );
        assert_eq!(
            error.to_string(),
            format!("Solution::at is not available for {gle}")
        );
        assert!(matches!(
            solution.state_at(1.0, &Pendulum),
            Err(Error::Unsupported {
                operation: "Solution::state_at",
                ..
            })
        ));
        // Checked before the time: the embedding is the first thing wrong.
        assert!(matches!(
            solution.at(f64::NAN),
            Err(Error::Unsupported { .. })
        ));
        let mut run = dynamic.clone();
        run.run.embedding = gle;
        assert!(matches!(
            run.at(1.0),
            Err(Error::Unsupported {
                operation: "DynSolution::at",
                ..
            })
        ));
    }

    // Buffers, models and stored nodes of the wrong size.
    let (mut q, mut v) = (vec![0.0; CHAIN], vec![0.0; CHAIN + 1]);
    let wrong = |what| {
        Err(Error::WrongLength {
            what,
            expected: CHAIN,
            found: CHAIN + 1,
        })
    };
    assert_eq!(
        dynamic.at_into(1.0, &mut q, &mut v),
        wrong("the velocity buffer")
    );
    assert_eq!(
        dynamic.at_into(1.0, &mut v, &mut q),
        wrong("the position buffer")
    );
    assert_eq!(
        dynamic.state_at(1.0, &Four).map(|_| ()),
        Err(Error::WrongLength {
            what: "the model's dimension",
            expected: CHAIN,
            found: 4
        })
    );
    let mut cut = dynamic.clone();
    cut.q.pop();
    assert!(matches!(cut.at(1.0), Err(Error::WrongLength { .. })));
    let mut cut = fixed.clone();
    cut.q.pop();
    assert!(matches!(cut.at(1.0), Err(Error::WrongLength { .. })));
    // Gauss–Legendre's Lagrangian form reads the momenta the integrator carries.
    let gauss = varembed_tests::problem(&SPRING, grid, Embedding::gauss_legendre(2).unwrap());
    let mut solution = gauss.solve_ivp(Scheme::Variational, 1.0, 0.0).unwrap();
    solution.momenta.clear();
    assert!(solution.at(1.0).is_ok());
    assert!(matches!(
        solution.state_at(1.0, &SPRING),
        Err(Error::WrongLength {
            what: "solution momenta",
            ..
        })
    ));

    // A momentum that is not finite at the interpolated state (a model other than the
    // solution's, outside its domain).
    let one = varembed_tests::problem(&SPRING, grid, Embedding::midpoint())
        .solve_ivp(Scheme::Direct, 1.0, 0.0)
        .unwrap();
    assert!(
        matches!(one.state_at(0.55, &Beyond), Err(Error::OutsideDomain { what }) if what.starts_with("the interpolated state q = [") && what.ends_with("at t = 0.55"))
    );
    assert!(matches!(
        dynamic.state_at(0.55, &BeyondChain),
        Err(Error::OutsideDomain { .. })
    ));
}
