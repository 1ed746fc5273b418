//! The large-chain scene against oracles at small `d`: its model's energy against the FPUT
//! Hamiltonian written bond by bond, its variational run against a hand-written Störmer–Verlet
//! loop, its direct run's energy non-increasing (implicit Euler on a convex potential) and the
//! variational one's bounded, the Runge–Kutta reference of its sweep against the
//! variational run at a fine step, and its comparison table's numbers against the
//! hand-written Störmer–Verlet loop and the energy read off the nodes by hand.

use varembed::{DynLagrangian, DynProblem, Embedding, Grid, OrderStatus, Scheme, Side, Start};
use varembed_examples::scene::{Context, Mode};
use varembed_examples::scenes::large_chain::{self, EnergyRun};
use varembed_tests::rng::Rng;

/// `H(x, v) = ½|v|² + Σ_{i=0}^{d} V(x_{i+1} − x_i)`, `V(r) = r²/2 + α r³/3`, with the walls
/// `x_0 = x_{d+1} = 0` (1-based).
fn hamiltonian(x: &[f64], v: &[f64]) -> f64 {
    let d = x.len();
    let at = |i: usize| if i == 0 || i == d + 1 { 0.0 } else { x[i - 1] };
    let kinetic: f64 = v.iter().map(|v| 0.5 * v * v).sum();
    let bonds: f64 = (0..=d)
        .map(|i| {
            let r = at(i + 1) - at(i);
            0.5 * r * r + large_chain::ALPHA / 3.0 * r * r * r
        })
        .sum();
    kinetic + bonds
}

/// `f = −∇U`, written per particle from its two bonds (not bond by bond as the scene's).
fn force(x: &[f64]) -> Vec<f64> {
    let d = x.len();
    let at = |i: usize| if i == 0 || i == d + 1 { 0.0 } else { x[i - 1] };
    let spring = |r: f64| r + large_chain::ALPHA * r * r;
    (1..=d)
        .map(|i| spring(at(i + 1) - at(i)) - spring(at(i) - at(i - 1)))
        .collect()
}

fn random(rng: &mut Rng, d: usize, scale: f64) -> Vec<f64> {
    (0..d).map(|_| rng.uniform(-scale, scale)).collect()
}

fn max_gap(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

#[test]
fn the_models_energy_is_the_hand_written_hamiltonian() {
    let mut rng = Rng(0x1a2c);
    for d in [2, 3, 17, 64] {
        let model = large_chain::model(d);
        assert_eq!(model.dimension(), d);
        for _ in 0..20 {
            let (x, v) = (random(&mut rng, d, 0.8), random(&mut rng, d, 1.5));
            let (e, h) = (model.energy(&x, &v, 0.0), hamiltonian(&x, &v));
            assert!(
                (e - h).abs() <= 1e-12 * (1.0 + h.abs()),
                "d = {d}: {e} against {h}"
            );
            // The scene's hand-written force (the Runge–Kutta reference's) is this one.
            let mut f = vec![0.0; d];
            large_chain::force(&x, &mut f);
            assert!(max_gap(&f, &force(&x)) <= 1e-13, "d = {d}");
        }
    }
}

/// The variational Gauss-FDE− run is `Q_n = 2Q_{n−1} − Q_{n−2} + h² f(Q_{n−1})` from the
/// discrete Legendre start of σ = −, node for node. That start solves
/// `∂L/∂v(Q_1, (Q_1 − q0)/h) = ∂L/∂v(q0, v0)`: `Q_1 = q0 + h v0`, no force term (σ = +'s start,
/// `p_0 = −∂L_d(Q_0, Q_1)/∂Q_0` with `L_d = h L(Q_0, V)`, is `q0 + h v0 + h² f(q0)`).
#[test]
fn the_variational_run_is_a_hand_written_stormer_verlet_loop() {
    let (d, h, steps) = (64, large_chain::H, 400);
    let mut rng = Rng(7);
    let q0 = random(&mut rng, d, 0.1);
    let v0 = random(&mut rng, d, 0.1);
    let model = large_chain::model(d);
    let grid = Grid::new(0.0, h * steps as f64, steps).expect("grid");
    let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    let mut nodes = Vec::new();
    let run = problem
        .run_ivp(Scheme::Variational, &q0, &v0, |node| {
            assert_eq!(node.index, nodes.len());
            nodes.push(node.q.to_vec());
        })
        .expect("Störmer–Verlet runs");
    assert_eq!(nodes.len(), steps + 1);
    assert_eq!(run.newton_iterations, 0, "explicit");

    let by_hand = stormer_verlet(&q0, &v0, h, steps);
    for (n, (lib, hand)) in nodes.iter().zip(&by_hand).enumerate() {
        let gap = max_gap(lib, hand);
        assert!(gap <= 1e-12, "node {n}: {gap:e}");
    }
    assert_eq!(run.last, by_hand[steps]);
}

/// The direct scheme is implicit Euler on `(Q, V)`: on the convex potential of a small
/// amplitude its energy with the backward velocity decreases at every step. Störmer–Verlet's
/// oscillates within about `hω/2` of its start (measured: within 0.4 % at d = 64 over 2000
/// steps; the bound leaves a factor of two) and does not drift.
#[test]
fn the_direct_energy_decreases_and_the_variational_one_is_bounded() {
    let (d, steps) = (64, 2000);
    let direct = EnergyRun::new(d, Scheme::Direct, (large_chain::H, steps), 1).expect("direct");
    assert_eq!(direct.energy.len(), steps + 1);
    assert_eq!(direct.run.band, 1);
    let e0 = direct.energy[0].1;
    let (_, q0) = ((), large_chain::initial_data(d).0);
    assert!((e0 - hamiltonian(&q0, &vec![0.0; d])).abs() <= 1e-15);
    for w in direct.energy.windows(2) {
        assert!(w[1].1 <= w[0].1, "energy rose at t = {}: {:?}", w[1].0, w);
    }
    let left = direct.energy[steps].1 / e0;
    assert!(left < 0.99, "{left}");

    let variational =
        EnergyRun::new(d, Scheme::Variational, (large_chain::H, steps), 1).expect("variational");
    let (lo, hi) = variational.range();
    let omega = large_chain::frequency(d, large_chain::mode(d));
    let bound = large_chain::H * omega;
    assert!(
        1.0 - lo <= bound && hi - 1.0 <= bound,
        "[{lo}, {hi}], {bound}"
    );
    // No drift: the last period's mean is the first period's.
    let period = (2.0 * std::f64::consts::PI / omega / large_chain::H) as usize;
    let relative = variational.relative();
    let mean = |s: &[(f64, f64)]| s.iter().map(|p| p.1).sum::<f64>() / s.len() as f64;
    let (first, last) = (mean(&relative[..period]), mean(&relative[steps - period..]));
    assert!((first - last).abs() < 1e-4, "{first} against {last}");
}

/// The sweep's reference (Runge–Kutta 4) agrees with Störmer–Verlet at a fine step to within
/// the latter's error, and the sweep's errors fall as N grows.
#[test]
fn the_reference_and_the_sweep_are_consistent() {
    let d = 32;
    let reference = large_chain::reference(d, large_chain::SWEEP_END, 10, 512);
    let (q0, v0) = large_chain::initial_data(d);
    let model = large_chain::model(d);
    let steps = 6400;
    let grid = Grid::new(0.0, large_chain::SWEEP_END, steps).expect("grid");
    let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    let solved = problem
        .solve_ivp_every(Scheme::Variational, &q0, &v0, steps / 10)
        .expect("runs");
    assert_eq!(solved.len(), 11);
    let gap = (0..11).fold(0.0f64, |m, j| m.max(max_gap(solved.node(j), &reference[j])));
    // First order with h = 1/320 on an amplitude 0.05: well below 1e-3 of the amplitude.
    assert!(gap < 5e-5, "{gap:e}");

    let cx = Context::hidden(Mode::Quick);
    let sizes = [40, 80, 160, 320];
    let fde = Embedding::finite_difference(Side::Backward);
    let line = large_chain::sweep_line(
        &cx,
        "direct",
        (d, fde, Scheme::Direct, Start::Legendre),
        &sizes,
        &reference,
    );
    assert!(line.failures.is_empty(), "{:?}", line.failures);
    let errors: Vec<f64> = line.points.iter().map(|p| p.error).collect();
    assert!(errors.windows(2).all(|w| w[1] < w[0]), "{errors:?}");
    let orders = line.orders();
    assert!(orders.iter().all(|p| (0.7..1.5).contains(p)), "{orders:?}");
    // From the second-order start, Störmer–Verlet is second order against the same reference.
    let line = large_chain::sweep_line(
        &cx,
        "second-order start",
        (d, fde, Scheme::Variational, Start::SecondOrder),
        &sizes,
        &reference,
    );
    assert!(line.failures.is_empty(), "{:?}", line.failures);
    let orders = line.orders();
    assert!(orders.iter().all(|p| (1.8..2.2).contains(p)), "{orders:?}");
    // The implicit lines of the run-time path: midpoint second order, Gauss–Legendre with two
    // stages fourth order, against the same reference.
    for (embedding, range) in [
        (Embedding::midpoint(), 1.8..2.2),
        (Embedding::gauss_legendre(2).expect("s = 2"), 3.7..4.3),
    ] {
        let line = large_chain::sweep_line(
            &cx,
            "implicit",
            (d, embedding, Scheme::Variational, Start::Legendre),
            &sizes,
            &reference,
        );
        assert!(line.failures.is_empty(), "{:?}", line.failures);
        let orders = line.orders();
        assert!(
            orders.iter().all(|p| range.contains(p)),
            "{embedding}: {orders:?}"
        );
    }
}

/// Störmer–Verlet by hand from the discrete Legendre start of σ = − (`Q_1 = q0 + h v0`), every
/// node.
fn stormer_verlet(q0: &[f64], v0: &[f64], h: f64, steps: usize) -> Vec<Vec<f64>> {
    let d = q0.len();
    let mut nodes = vec![q0.to_vec(), (0..d).map(|i| q0[i] + h * v0[i]).collect()];
    for n in 2..=steps {
        let (a, b) = (&nodes[n - 2], &nodes[n - 1]);
        let f = force(b);
        let next = (0..d).map(|i| 2.0 * b[i] - a[i] + h * h * f[i]).collect();
        nodes.push(next);
    }
    nodes
}

/// The scene's comparison at small `d`: the variational line's error and energy drift are
/// those of the hand-written Störmer–Verlet loop against the same Runge–Kutta nodes (the
/// energy with the backward velocity, `E_k = H(Q_k, (Q_k − Q_{k−1})/h)` for `k ≥ 1`, the
/// quadrature nodes of σ = −); its order is that loop's `log₂(e_N / e_2N)`; the direct
/// scheme loses energy and needs Newton; Gauss-FDE− is not coherent, so the other scheme's
/// residual is far from round-off; the table names its reference and the grids of the order.
#[test]
fn the_comparison_table_is_the_hand_written_loop_against_the_same_reference() {
    let (d, n) = (16, 100);
    let compared = large_chain::comparison(d, n).expect("both schemes solve");
    let h = large_chain::SWEEP_END / n as f64;
    let (q0, v0) = large_chain::initial_data(d);
    let reference = large_chain::reference(d, large_chain::SWEEP_END, 4 * n, 4);
    let error_by_hand = |m: usize| {
        let nodes = stormer_verlet(&q0, &v0, large_chain::SWEEP_END / m as f64, m);
        let stride = 4 * n / m;
        (0..=m).fold(0.0f64, |e, k| {
            e.max(max_gap(&nodes[k], &reference[k * stride]))
        })
    };
    let errors: Vec<f64> = [n, 2 * n, 4 * n].map(error_by_hand).to_vec();
    let variational = &compared.variational;
    let error = variational.error.expect("a reference");
    assert!(
        (error - errors[0]).abs() <= 1e-9 * errors[0],
        "{error:e} {:e}",
        errors[0]
    );
    let order = (errors[0] / errors[1]).log2();
    let observed = variational.order.expect("solved on 2N");
    assert!((observed - order).abs() < 1e-6, "{observed} {order}");
    assert!((0.8..1.2).contains(&observed), "first order: {observed}");
    assert_ne!(variational.order_status, Some(OrderStatus::RoundOff));

    let nodes = stormer_verlet(&q0, &v0, h, n);
    let energies: Vec<f64> = (1..=n)
        .map(|k| {
            let v: Vec<f64> = (0..d)
                .map(|i| (nodes[k][i] - nodes[k - 1][i]) / h)
                .collect();
            hamiltonian(&nodes[k], &v)
        })
        .collect();
    assert_eq!(variational.energy.len(), energies.len());
    for (lib, hand) in variational.energy.iter().zip(&energies) {
        assert!((lib - hand).abs() <= 1e-12, "{lib} {hand}");
    }
    let drift = energies
        .iter()
        .fold(0.0f64, |m, e| m.max((e - energies[0]).abs()));
    let deviation = variational.energy_deviation.expect("conserved flow");
    assert!(
        (deviation - drift).abs() <= 1e-12,
        "{deviation:e} {drift:e}"
    );
    assert_eq!(variational.solution.run.newton_iterations, 0, "explicit");

    let direct = &compared.direct;
    assert!(direct.solution.run.newton_iterations >= n - 1);
    let (first, last) = (direct.energy[0], direct.energy[direct.energy.len() - 1]);
    assert!(last < first, "implicit Euler dissipates: {first} {last}");
    // Not coherent: each solution leaves the other scheme's equation far from round-off.
    assert!(direct.residual_of_other > 1e-6 && variational.residual_of_other > 1e-6);
    assert_eq!(compared.order_grids, [2 * n, 4 * n]);
    let table = compared.to_string();
    assert!(table.contains("Runge–Kutta 4 at h/16"), "{table}");
}
