//! Newton's method on a banded step Jacobian: an implicit run of a 64-particle chain written
//! with loops takes the banded factorisation (its Hessian is tridiagonal), and its nodes equal
//! those of the same run on the dense path to 1e-12 relative. The dense path is forced by a
//! wrapper that forwards everything but claims no bandwidth.

use varembed::{Embedding, Grid, Lagrangian, Problem, Scheme, Side, lagrangian};
use varembed_tests::models::dense::{ConstGeneric, Dense};
use varembed_tests::models::generated::fput64::{Fput, N};
use varembed_tests::rng::Rng;

/// A chain with next-nearest-neighbour springs and a position-dependent mass: bandwidth 2,
/// with `vv` depending on `x` and `xv` nonzero.
#[lagrangian]
fn second_neighbours(x: [f64; N], v: [f64; N], k: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..N {
        l += 0.5 * (1.0 + 0.1 * x[i] * x[i]) * v[i] * v[i] - 0.5 * x[i] * x[i];
    }
    for i in 0..N - 2 {
        let d = x[i + 2] - x[i];
        l -= 0.5 * k * d * d * (1.0 + 0.2 * d * d);
    }
    l
}

/// The first normal mode of the linear chain with amplitude `a`, plus a little of the third.
fn start(a: f64) -> [f64; N] {
    let mode =
        |m: f64, i: usize| (std::f64::consts::PI * m * (i + 1) as f64 / (N + 1) as f64).sin();
    std::array::from_fn(|i| a * mode(1.0, i) + 0.1 * a * mode(3.0, i))
}

/// The banded run's nodes against the dense run's, max-norm relative to the largest node, and
/// the same Newton iteration counts (within two over the run). On a thread of its own: the
/// step math of a 64-dimensional model keeps several 64 × 64 blocks on the stack, more than a
/// test thread's default stack holds in a debug build.
fn banded_equals_dense<L: Lagrangian<N> + Send + 'static>(
    lag: L,
    embedding: Embedding,
    scheme: Scheme,
) {
    std::thread::Builder::new()
        .stack_size(64 << 20)
        .spawn(move || run_both(lag, embedding, scheme))
        .unwrap()
        .join()
        .unwrap();
}

fn run_both<L: Lagrangian<N>>(lag: L, embedding: Embedding, scheme: Scheme) {
    let grid = Grid::new(0.0, 10.0, 400).unwrap();
    let dense = Dense(&lag);
    // A model with loops of 64 degrees of freedom would go to the run-time engine: kept on
    // the const-generic banded path.
    let const_generic = ConstGeneric(&lag);
    let banded = Problem::new(&const_generic, grid, embedding)
        .solve_ivp(scheme, start(0.8), [0.0; N])
        .unwrap();
    let reference = Problem::new(&dense, grid, embedding)
        .solve_ivp(scheme, start(0.8), [0.0; N])
        .unwrap();
    assert_eq!(banded.explicit_steps, 0, "every step runs Newton");
    assert!(banded.newton_iterations > 0, "Newton iterates");
    let scale = reference.q.iter().fold(0.0f64, |m, q| m.max(q.amax()));
    let gap = banded
        .q
        .iter()
        .zip(&reference.q)
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    assert!(
        gap <= 1e-12 * scale,
        "banded and dense runs differ by {gap:e}"
    );
    let d = (banded.newton_iterations as i64 - reference.newton_iterations as i64).abs();
    assert!(
        d <= 2,
        "{} vs {}",
        banded.newton_iterations,
        reference.newton_iterations
    );
}

#[test]
fn direct_backward_fput_banded_equals_dense() {
    let lag = Fput {
        alpha: 0.25,
        beta: 0.7,
    };
    assert_eq!(lag.hessian_bandwidth(), Some(1));
    banded_equals_dense(
        lag,
        Embedding::finite_difference(Side::Backward),
        Scheme::Direct,
    );
}

#[test]
fn midpoint_variational_fput_banded_equals_dense() {
    let lag = Fput {
        alpha: 0.25,
        beta: 0.7,
    };
    banded_equals_dense(lag, Embedding::midpoint(), Scheme::Variational);
}

#[test]
fn second_neighbours_banded_equals_dense() {
    let lag = SecondNeighbours { k: 0.5 };
    assert_eq!(lag.hessian_bandwidth(), Some(2));
    banded_equals_dense(
        SecondNeighbours { k: 0.5 },
        Embedding::finite_difference(Side::Backward),
        Scheme::Direct,
    );
    banded_equals_dense(lag, Embedding::midpoint(), Scheme::Variational);
}

/// The claimed bandwidths hold: at random points every entry of the three blocks beyond the
/// band is exactly 0, and some entry on the band's edge is not (the claim is tight).
#[test]
fn claimed_bandwidths_hold_on_the_hessian() {
    let mut rng = Rng(0xBA7D);
    let fput = Fput {
        alpha: 0.25,
        beta: 0.7,
    };
    let second = SecondNeighbours { k: 0.5 };
    let models: [&dyn Lagrangian<N>; 2] = [&fput, &second];
    for lag in models {
        let band = lag.hessian_bandwidth().expect("a banded model");
        let mut edge = false;
        for _ in 0..10 {
            let (x, v) = (rng.vector::<N>(1.0), rng.vector::<N>(1.0));
            let h = lag.hessian(&x, &v, 0.0);
            for m in [h.xx, h.xv, h.vv] {
                for i in 0..N {
                    for j in 0..N {
                        let off = i.abs_diff(j);
                        assert!(off <= band || m[(i, j)] == 0.0, "({i}, {j}) beyond {band}");
                        edge |= off == band && m[(i, j)] != 0.0;
                    }
                }
            }
        }
        assert!(edge, "the band {band} is wider than the Hessian's");
    }
}
