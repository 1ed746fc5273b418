//! A `#[force]` in a solve: the pair under its drag (`forces.rs`, `Drag`, written by hand as
//! `impl Force` with its Jacobian by hand) and the same force written as a `#[force]` fn give
//! the same nodes, to 1e-12, under every classical embedding and scheme; and a
//! `#[constraint]` in a constrained solve gives the nodes of the same constraint written as a
//! `Holonomic` Lagrangian.

use varembed::{
    Constraint, Dependence, Force, ForceDependence, Forced, Grid, Holonomic, Scheme, Vector,
    constraint, force, lagrangian,
};

use super::forces::{Drag, Pair, classical, tight};

/// `Drag` of `forces.rs` as a `#[force]` fn.
#[force]
fn generated_drag(x: [f64; 2], v: [f64; 2], t: f64) -> [f64; 2] {
    [
        -0.3 * v[0] * v[0].abs() + 0.2 * t.sin(),
        -0.1 * v[1] + 0.05 * x[0],
    ]
}

#[test]
fn a_generated_force_gives_the_nodes_of_the_hand_written_one() {
    // The hand-written force claims nothing of its blocks; the generated one claims exactly
    // what they read, which the planning may use.
    assert_eq!(
        Force::<2>::jacobian_dependence(&GeneratedDrag),
        ForceDependence {
            x: Dependence::NONE,
            v: Dependence {
                x: false,
                v: true,
                t: false
            },
        }
    );
    let hand = Forced::new(Pair, Drag);
    let generated = Forced::new(Pair, GeneratedDrag);
    let mut worst: f64 = 0.0;
    for (embedding, scheme) in classical() {
        let grid = Grid::new(0.0, 8.0, 200).unwrap();
        let a = varembed_tests::problem(&hand, grid, embedding)
            .with_newton(tight())
            .solve_ivp(scheme, [0.4, -0.2], [1.0, -0.5])
            .unwrap();
        let b = varembed_tests::problem(&generated, grid, embedding)
            .with_newton(tight())
            .solve_ivp(scheme, [0.4, -0.2], [1.0, -0.5])
            .unwrap();
        let gap =
            a.q.iter()
                .zip(&b.q)
                .map(|(p, q)| (p - q).amax())
                .fold(0.0, f64::max);
        assert!(
            gap <= 1e-12,
            "{embedding} {scheme}: nodes differ by {gap:e}"
        );
        let moved = (a.q[a.q.len() - 1] - a.q[0]).amax();
        assert!(
            moved > 0.1,
            "{embedding} {scheme}: the pair moved by {moved}"
        );
        worst = worst.max(gap);
    }
    println!("generated vs hand-written force: largest node difference {worst:e}");
}

/// The unit sphere as a `#[constraint]`.
#[constraint]
fn sphere(x: [f64; 3]) -> [f64; 1] {
    [0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - 1.0)]
}

/// The same as a `Holonomic` Lagrangian.
#[lagrangian]
fn sphere_lagrangian(x: [f64; 3], _v: [f64; 3]) -> f64 {
    0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - 1.0)
}

/// A spherical pendulum under gravity.
#[lagrangian]
fn free_fall(x: [f64; 3], v: [f64; 3]) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - x[2]
}

fn constrained_nodes<C: Constraint<3, 1>>(c: &C) -> Vec<Vector<3>> {
    let grid = Grid::new(0.0, 3.0, 150).unwrap();
    let x0 = [0.6, 0.0, -0.8];
    let v0 = [0.0, 0.9, 0.0];
    varembed_tests::problem(&FreeFall, grid, varembed::Embedding::midpoint())
        .with_newton(tight())
        .solve_constrained_ivp(Scheme::Variational, c, x0, v0)
        .unwrap()
        .solution
        .q
}

#[test]
fn a_generated_constraint_gives_the_nodes_of_a_holonomic_lagrangian() {
    let a = constrained_nodes(&Sphere);
    let b = constrained_nodes(&Holonomic(SphereLagrangian));
    let gap = a
        .iter()
        .zip(&b)
        .map(|(p, q)| (p - q).amax())
        .fold(0.0, f64::max);
    println!("generated vs Holonomic constraint: largest node difference {gap:e}");
    assert!((a[a.len() - 1] - a[0]).amax() > 0.1, "the pendulum moved");
    assert!(gap <= 1e-12, "nodes differ by {gap:e}");
}
