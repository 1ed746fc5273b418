//! The node values of run-time-dimension solutions (`DynSolution::node_values`) and of the
//! nodes a run hands its observer: the const-generic twin's `t, q, v, p` and energy under every
//! embedding and scheme the run-time path solves, the observer's values bit for bit those of the
//! stored run, an energy at the nodes of the order of the scheme (exact conservation on a
//! linear chain, a drift falling by 4 on a sine-Gordon ring), the typed error of a thinned
//! solution, and the CSV and JSON exports read back.

use varembed::{
    DynLagrangian, DynNodeValues, DynProblem, Embedding, Error, Grid, NodeValues, Scheme, Vector,
    lagrangian,
};

// Every embedding the run-time path solves as an initial value problem.
use super::through_problem::embeddings;

const N: usize = 8;

/// An α-FPUT chain whose masses depend on the positions: `∂²L/∂v²` varies, so each discrete
/// Legendre velocity takes Newton's method on it.
#[lagrangian]
fn heavy_chain(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 0.0;
    for i in 0..N {
        l += 0.5 * (1.0 + 0.2 * x[i] * x[i]) * v[i] * v[i] - 0.5 * x[i] * x[i];
    }
    for i in 0..N - 1 {
        let s = x[i + 1] - x[i];
        l -= 0.5 * s * s + 0.25 * s * s * s;
    }
    l
}

/// A driven chain with a gyroscopic coupling: not autonomous (no energy), `L_xv` not symmetric.
#[lagrangian]
fn driven(x: [f64; N], v: [f64; N], t: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..N {
        l += 0.5 * (1.0 + 0.1 * x[i] * x[i]) * v[i] * v[i] - 0.5 * x[i] * x[i]
            + 0.1 * t.sin() * x[i];
    }
    for i in 0..N - 1 {
        l += 0.2 * x[i] * v[i + 1] - 0.5 * (x[i + 1] - x[i]).powi(2);
    }
    l
}

/// A sine-Gordon ring of `n` sites.
#[lagrangian]
fn sine_gordon(x: &[f64], v: &[f64], n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        let s = x[(i + 1) % n] - x[i];
        l += 0.5 * v[i] * v[i] - 0.5 * s * s + x[i].cos();
    }
    l
}

/// A linear chain of `n` unit masses with fixed ends: quadratic, so the midpoint rule conserves
/// its energy exactly.
#[lagrangian]
fn linear_chain(x: &[f64], v: &[f64], n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * v[i] * v[i] - 0.5 * x[i] * x[i];
    }
    for i in 0..n - 1 {
        l -= 0.5 * (x[i + 1] - x[i]).powi(2);
    }
    l
}

const SCHEMES: [Scheme; 2] = [Scheme::Direct, Scheme::Variational];

fn initial() -> ([f64; N], [f64; N]) {
    let mut q = [0.0; N];
    let mut v = [0.0; N];
    for i in 0..N {
        q[i] = 0.5 * (std::f64::consts::PI * (i + 1) as f64 / (N + 1) as f64).sin();
        v[i] = 0.3 * ((i as f64) * 0.7).cos();
    }
    (q, v)
}

/// The largest gap between `ours` (flat) and `theirs` (one vector a node), relative to the
/// largest entry of `theirs`.
fn gap(ours: &[f64], theirs: &[Vector<N>]) -> f64 {
    assert_eq!(ours.len(), theirs.len() * N);
    let size = theirs.iter().map(|x| x.amax()).fold(0.0, f64::max);
    let flat = theirs.iter().flat_map(|x| x.iter());
    ours.iter()
        .zip(flat)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / size
}

/// `ours` equals `theirs` in every field to `1e-12` relative.
fn assert_twins(ours: &DynNodeValues, theirs: &NodeValues<N>, what: &str) {
    assert_eq!(ours.rule, theirs.rule, "{what}");
    assert_eq!(ours.t, theirs.t, "{what}");
    for (name, field, twin) in [
        ("q", &ours.q, &theirs.q),
        ("v", &ours.v, &theirs.v),
        ("p", &ours.p, &theirs.p),
    ] {
        let gap = gap(field, twin);
        assert!(gap <= 1e-12, "{what} {name}: {gap:e}");
    }
    match (&ours.energy, &theirs.energy) {
        (Some(ours), Some(theirs)) => {
            let size = theirs.iter().fold(0.0f64, |m, e| m.max(e.abs()));
            let gap = ours
                .iter()
                .zip(theirs)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(gap <= 1e-12 * size, "{what} energy: {:e}", gap / size);
        }
        (None, None) => {}
        _ => panic!("{what}: the energy on one path only"),
    }
    assert_eq!(ours.csv_header(), theirs.csv_header(), "{what}");
}

/// Both paths' node values of the same model, as initial value problems.
fn ivp_twins<L>(
    model: &L,
    grid: Grid,
    embedding: Embedding,
    scheme: Scheme,
) -> (DynNodeValues, NodeValues<N>)
where
    L: DynLagrangian + varembed::Lagrangian<N> + Sync,
{
    let (q0, v0) = initial();
    let run = DynProblem::new(model, grid, embedding)
        .solve_ivp(scheme, &q0, &v0)
        .unwrap();
    let reference = varembed_tests::problem(model, grid, embedding)
        .solve_ivp(scheme, Vector::<N>::from(q0), Vector::<N>::from(v0))
        .unwrap();
    (
        run.node_values(model).unwrap(),
        reference.node_values(model).unwrap(),
    )
}

#[test]
fn node_values_of_every_run_time_solve_are_the_const_generic_ones() {
    let grid = Grid::new(0.0, 3.0, 150).unwrap();
    for embedding in embeddings() {
        for scheme in SCHEMES {
            let what = format!("{embedding} {scheme:?}");
            let (ours, theirs) = ivp_twins(&HeavyChain, grid, embedding, scheme);
            assert!(ours.energy.is_some(), "{what}");
            assert_twins(&ours, &theirs, &format!("heavy chain {what}"));
            let (ours, theirs) = ivp_twins(&Driven, grid, embedding, scheme);
            assert!(ours.energy.is_none(), "{what}");
            assert_twins(&ours, &theirs, &format!("driven {what}"));
        }
    }
    // The boundary value problems the run-time path solves: the Gauss-FDEσ embeddings.
    let (qa, qb) = ([0.1; N], [-0.2; N]);
    for embedding in &embeddings()[..4] {
        for scheme in SCHEMES {
            let run = DynProblem::new(&HeavyChain, grid, *embedding)
                .solve_bvp(scheme, &qa, &qb)
                .unwrap();
            let reference = varembed_tests::problem(&HeavyChain, grid, *embedding)
                .solve_bvp(scheme, Vector::<N>::from(qa), Vector::<N>::from(qb))
                .unwrap();
            let (ours, theirs) = (
                run.node_values(&HeavyChain).unwrap(),
                reference.node_values(&HeavyChain).unwrap(),
            );
            assert_twins(
                &ours,
                &theirs,
                &format!("boundary value problem {embedding} {scheme:?}"),
            );
        }
    }
}

#[test]
fn the_observer_hands_the_node_values_of_the_stored_run_bit_for_bit() {
    let (q0, v0) = initial();
    // N = 1 and 2 hand their nodes at the start and after the first step; N = 40 along the run.
    for steps in [1, 2, 3, 40] {
        let grid = Grid::new(0.0, 0.05 * steps as f64, steps).unwrap();
        for embedding in embeddings() {
            for scheme in SCHEMES {
                let what = format!("N = {steps}, {embedding} {scheme:?}");
                let problem = DynProblem::new(&HeavyChain, grid, embedding);
                let stored = problem.solve_ivp(scheme, &q0, &v0).unwrap();
                let nodes = stored.node_values(&HeavyChain).unwrap();
                let mut handed = 0;
                problem
                    .run_ivp_with_values(scheme, &q0, &v0, |node| {
                        let k = node.index;
                        assert_eq!(k, handed, "{what}: in order");
                        handed += 1;
                        let state = nodes.get(k).unwrap();
                        assert_eq!(node.t.to_bits(), state.t.to_bits(), "{what} t_{k}");
                        assert_eq!(node.q, state.q, "{what} q_{k}");
                        assert_eq!(node.previous, nodes.get(k.max(1) - 1).unwrap().q, "{what}");
                        let bits = |x: &[f64]| x.iter().map(|c| c.to_bits()).collect::<Vec<_>>();
                        assert_eq!(bits(node.v), bits(state.v), "{what} v_{k}");
                        assert_eq!(bits(node.p), bits(state.p), "{what} p_{k}");
                        assert_eq!(
                            node.energy.map(f64::to_bits),
                            state.energy.map(f64::to_bits),
                            "{what} E_{k}"
                        );
                    })
                    .unwrap();
                assert_eq!(handed, steps + 1, "{what}: every node");
            }
        }
    }
}

/// The largest `|E_k − E_0|` of a run of `model` on `[0, 4]` in `steps` steps, from its node
/// values, and from the first-order backward difference an observer would form itself.
fn energy_drifts(
    model: &SineGordon,
    embedding: Embedding,
    scheme: Scheme,
    steps: usize,
) -> (f64, f64) {
    let grid = Grid::new(0.0, 4.0, steps).unwrap();
    let h = grid.h();
    let q0: Vec<f64> = (0..model.n).map(|i| 0.8 * (i as f64 * 0.4).sin()).collect();
    let v0: Vec<f64> = (0..model.n).map(|i| 0.3 * (i as f64 * 0.9).cos()).collect();
    let (mut first, mut drift, mut backward, mut e_back) = (None, 0.0f64, 0.0f64, None);
    DynProblem::new(model, grid, embedding)
        .run_ivp_with_values(scheme, &q0, &v0, |node| {
            let e = node.energy.unwrap();
            let e0 = *first.get_or_insert(e);
            drift = drift.max((e - e0).abs());
            if node.index > 0 {
                let v: Vec<f64> = node
                    .q
                    .iter()
                    .zip(node.previous)
                    .map(|(q, p)| (q - p) / h)
                    .collect();
                let e = model.energy(node.q, &v, node.t);
                let e1 = *e_back.get_or_insert(e);
                backward = backward.max((e - e1).abs());
            }
        })
        .unwrap();
    (drift, backward)
}

#[test]
fn the_energy_at_the_nodes_of_a_midpoint_run_is_second_order() {
    let ring = SineGordon { n: 32 };
    for scheme in SCHEMES {
        let drifts: Vec<(f64, f64)> = [200, 400, 800]
            .iter()
            .map(|&steps| energy_drifts(&ring, Embedding::midpoint(), scheme, steps))
            .collect();
        for pair in drifts.windows(2) {
            let ratio = pair[0].0 / pair[1].0;
            assert!(
                (3.6..=4.4).contains(&ratio),
                "{scheme:?}: drift ratio {ratio} ({drifts:?})"
            );
            // The observer's own backward difference is first order: its drift is far larger.
            assert!(pair[1].1 > 10.0 * pair[1].0, "{scheme:?}: {drifts:?}");
        }
    }
}

#[test]
fn the_midpoint_rule_conserves_a_quadratic_energy_at_every_node() {
    // The variational midpoint rule is the implicit midpoint rule on (q, p), which conserves
    // quadratic invariants: E = ½|p|² + ½ qᵀ K q at its discrete Legendre momenta, exactly.
    let chain = LinearChain { n: 16 };
    let q0: Vec<f64> = (0..16).map(|i| (i as f64 * 0.5).sin()).collect();
    let v0: Vec<f64> = (0..16).map(|i| 0.5 * (i as f64 * 0.3).cos()).collect();
    let grid = Grid::new(0.0, 20.0, 200).unwrap();
    let solution = DynProblem::new(&chain, grid, Embedding::midpoint())
        .solve_ivp(Scheme::Variational, &q0, &v0)
        .unwrap();
    let nodes = solution.node_values(&chain).unwrap();
    let energy = nodes.energy.unwrap();
    let drift = energy
        .iter()
        .map(|e| (e - energy[0]).abs())
        .fold(0.0, f64::max);
    assert!(drift <= 1e-13 * energy[0], "{:e}", drift / energy[0]);
    // Not a constant by accident: the step is large (h = 0.1 against ω up to 2.2), and the
    // trapezoidal rule's energy, which is not quadratic-conserving, moves.
    let trapezoidal = DynProblem::new(&chain, grid, Embedding::trapezoidal())
        .solve_ivp(Scheme::Variational, &q0, &v0)
        .unwrap()
        .node_values(&chain)
        .unwrap()
        .energy
        .unwrap();
    let moved = trapezoidal
        .iter()
        .map(|e| (e - trapezoidal[0]).abs())
        .fold(0.0, f64::max);
    assert!(moved > 1e-6 * trapezoidal[0], "{moved:e}");
}

#[test]
fn a_thinned_solution_names_the_solve_that_stores_every_node() {
    let ring = SineGordon { n: 8 };
    let grid = Grid::new(0.0, 1.0, 100).unwrap();
    let problem = DynProblem::new(&ring, grid, Embedding::midpoint());
    let (q0, v0) = (vec![0.3; 8], vec![0.0; 8]);
    let thinned = problem
        .solve_ivp_every(Scheme::Variational, &q0, &v0, 7)
        .unwrap();
    let error = thinned.node_values(&ring).unwrap_err();
    assert_eq!(
        error,
        Error::NodesNotStored {
            operation: "DynSolution::node_values",
            stored: 16,
            nodes: 101,
        }
    );
    let message = error.to_string();
    assert!(
        message.contains("DynProblem::solve_ivp (not solve_ivp_every)"),
        "{message}"
    );
    // A stride of 1 stores every node: the values of solve_ivp.
    let every = problem
        .solve_ivp_every(Scheme::Variational, &q0, &v0, 1)
        .unwrap();
    let full = problem.solve_ivp(Scheme::Variational, &q0, &v0).unwrap();
    assert_eq!(
        every.node_values(&ring).unwrap(),
        full.node_values(&ring).unwrap()
    );
    // Nodes of the wrong length are refused, not read out of bounds.
    let mut short = full.clone();
    short.q.pop();
    assert!(matches!(
        short.node_values(&ring),
        Err(Error::WrongLength { .. })
    ));
}

#[test]
fn the_node_values_read_back_from_csv_and_json() {
    let grid = Grid::new(0.0, 1.0, 30).unwrap();
    for (model, energy) in [
        (&HeavyChain as &dyn Both, true),
        (&Driven as &dyn Both, false),
    ] {
        let (q0, v0) = initial();
        let nodes = DynProblem::new(model, grid, Embedding::midpoint())
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap()
            .node_values(model)
            .unwrap();
        let csv = nodes.to_csv();
        let mut lines = csv.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(header.len(), 1 + 3 * N + usize::from(energy));
        assert_eq!(
            (header[1], header[N + 1], header[2 * N + 1]),
            ("q0", "v0", "p0")
        );
        assert_eq!(header.last() == Some(&"E"), energy);
        let mut read = 0;
        for (line, node) in lines.zip(nodes.iter()) {
            let numbers: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            let mut expected = vec![node.t];
            expected.extend(node.q.iter().chain(node.v).chain(node.p));
            expected.extend(node.energy);
            let bits = |x: &[f64]| x.iter().map(|c| c.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&numbers), bits(&expected));
            read += 1;
        }
        assert_eq!(read, 31);
        let json = serde_json::to_value(&nodes).unwrap();
        let records = json.as_array().unwrap();
        assert_eq!(records.len(), 31);
        for (record, node) in records.iter().zip(nodes.iter()) {
            assert_eq!(record["t"].as_f64().unwrap().to_bits(), node.t.to_bits());
            assert_eq!(
                record["v"][N - 1].as_f64().unwrap().to_bits(),
                node.v[N - 1].to_bits()
            );
            assert_eq!(
                record["energy"].as_f64().map(f64::to_bits),
                node.energy.map(f64::to_bits)
            );
        }
    }
}

/// A model of both kinds, as a trait object.
trait Both: DynLagrangian {}
impl Both for HeavyChain {}
impl Both for Driven {}
