//! Sums as values: a sum bound to a local and squared, divided by, taken the root of or read
//! in a second loop, and accumulators declared inside a loop, each against num-dual's
//! hyper-dual numbers on the same formula written out by hand (the oracle never goes through
//! the macro), on both traits where the model has both.

use num_dual::{DualNum, HyperDual64};
use varembed::{DynLagrangian, Lagrangian, SparseHessian, Vector, lagrangian};
use varembed_tests::models::num_dual::{assert_matches_oracle, close, dual_derivatives};
use varembed_tests::rng::Rng;

const N: usize = 4;

/// `½(Σ v_i)²` bound to a local, squared, plus an on-site potential.
#[lagrangian]
fn square_of_sum(x: [f64; N], v: [f64; N], k: f64) -> f64 {
    let s = (0..N).map(|i| v[i]).sum::<f64>();
    let mut u = 0.0;
    for i in 0..N {
        u += 0.5 * k * x[i] * x[i];
    }
    0.5 * s * s + 0.5 * v[0] * v[0] - u
}

fn square_of_sum_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], k: f64) -> T {
    let (x, v) = z.split_at(N);
    let s = v.iter().fold(T::zero(), |a, &b| a + b);
    let u = x.iter().fold(T::zero(), |a, &b| a + b * b * (0.5 * k));
    s * s * 0.5 + v[0] * v[0] * 0.5 - u
}

/// The same with an accumulator.
#[lagrangian]
fn square_of_accumulator(x: [f64; N], v: [f64; N], k: f64) -> f64 {
    let mut s = 0.0;
    for i in 0..N {
        s += v[i];
    }
    let u: f64 = (0..N).map(|i| 0.5 * k * x[i] * x[i]).sum();
    0.5 * s * s + 0.5 * v[0] * v[0] - u
}

/// A centre of mass `cx` from one loop, read in a second loop.
#[lagrangian]
fn centre_of_mass(x: [f64; N], v: [f64; N], k: f64) -> f64 {
    let mut cx = 0.0;
    for i in 0..N {
        cx += x[i] / N as f64;
    }
    let mut l = 0.0;
    for i in 0..N {
        l += 0.5 * v[i] * v[i] - 0.5 * k * (x[i] - cx) * (x[i] - cx);
    }
    l
}

fn centre_of_mass_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], k: f64) -> T {
    let (x, v) = z.split_at(N);
    let cx = x.iter().fold(T::zero(), |a, &b| a + b / N as f64);
    (0..N).fold(T::zero(), |a, i| {
        a + v[i] * v[i] * 0.5 - (x[i] - cx) * (x[i] - cx) * (0.5 * k)
    })
}

/// Nonlinear functions of sums: a root, a quotient, a logarithm and a condition.
#[lagrangian]
fn functions_of_sums(x: [f64; N], v: [f64; N], k: f64) -> f64 {
    let r2: f64 = (0..N).map(|i| x[i] * x[i]).sum();
    let r = (1.0 + r2).sqrt();
    let kinetic: f64 = (0..N).map(|i| 0.5 * v[i] * v[i]).sum();
    let p = (0..N).map(|i| (i as f64 + 1.0) * v[i]).sum::<f64>();
    let mut w = 0.0;
    for i in 0..N {
        w += x[i] * v[i] / (2.0 + r2);
    }
    let wall = if p > 0.0 { p.powi(3) } else { 0.0 };
    // A sum of a function of another sum, itself inside a function.
    let q: f64 = (0..N).map(|i| (v[i] / (1.0 + r2)).sin()).sum();
    kinetic * (1.0 + 0.1 * r) - k / r + (1.0 + p * p).ln() + w * w.sin() + 0.01 * wall + q.exp()
}

fn functions_of_sums_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], k: f64) -> T {
    let (x, v) = z.split_at(N);
    let r2 = x.iter().fold(T::zero(), |a, &b| a + b * b);
    let r = (r2 + 1.0).sqrt();
    let kinetic = v.iter().fold(T::zero(), |a, &b| a + b * b * 0.5);
    let p = (0..N).fold(T::zero(), |a, i| a + v[i] * (i as f64 + 1.0));
    let w = (0..N).fold(T::zero(), |a, i| a + x[i] * v[i] / (r2 + 2.0));
    let wall = if p.re() > 0.0 { p.powi(3) } else { T::zero() };
    let q = v.iter().fold(T::zero(), |a, &b| a + (b / (r2 + 1.0)).sin());
    kinetic * (r * 0.1 + 1.0) - r.recip() * k
        + (p * p + 1.0).ln()
        + w * w.sin()
        + wall * 0.01
        + q.exp()
}

/// The n-link pendulum as a physicist writes it: absolute angles, the Cartesian velocity of
/// each bob summed link by link in accumulators declared inside the loop over the bobs.
#[lagrangian]
fn n_link_accumulated(x: [f64; N], v: [f64; N], g: f64, l: f64) -> f64 {
    let mut kinetic = 0.0;
    let mut potential = 0.0;
    for k in 0..N {
        let mut vx = 0.0;
        let mut vy = 0.0;
        let mut y = 0.0;
        for i in 0..=k {
            vx += l * x[i].cos() * v[i];
            vy += l * x[i].sin() * v[i];
            y -= l * x[i].cos();
        }
        kinetic += 0.5 * (vx.powi(2) + vy * vy);
        potential += g * y;
    }
    kinetic - potential
}

/// The docs' closed-form n-link pendulum (the mass below each link).
#[lagrangian]
fn n_link_closed(x: [f64; N], v: [f64; N], g: f64, l: f64) -> f64 {
    let mut kinetic = 0.0;
    for i in 0..N {
        for j in 0..N {
            let mass_below = (N - i.max(j)) as f64;
            kinetic += 0.5 * l * l * mass_below * (x[i] - x[j]).cos() * v[i] * v[j];
        }
    }
    let potential: f64 = (0..N).map(|i| -g * l * (N - i) as f64 * x[i].cos()).sum();
    kinetic - potential
}

/// `(Σ v_i)²` of run-time dimension, and a root of a global sum.
#[lagrangian]
fn runtime_sums(x: &[f64], v: &[f64], n: usize, k: f64) -> f64 {
    let s: f64 = (0..n).map(|i| v[i]).sum();
    let mut r2 = 0.0;
    for i in 0..n {
        r2 += x[i] * x[i];
    }
    let mut springs = 0.0;
    for i in 0..n - 1 {
        springs += 0.5 * (x[i + 1] - x[i]).powi(2);
    }
    0.5 * s * s - springs - k * (1.0 + r2).sqrt()
}

fn runtime_sums_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], n: usize, k: f64) -> T {
    let (x, v) = z.split_at(n);
    let s = v.iter().fold(T::zero(), |a, &b| a + b);
    let r2 = x.iter().fold(T::zero(), |a, &b| a + b * b);
    let springs = (0..n - 1).fold(T::zero(), |a, i| a + (x[i + 1] - x[i]).powi(2) * 0.5);
    s * s * 0.5 - springs - (r2 + 1.0).sqrt() * k
}

/// The dynamic trait of a model against the oracle on `z = (x, v)`, every entry of the three
/// blocks (listed entries summed), and the claimed bandwidth against the entries.
fn assert_dyn_matches(
    name: &str,
    lag: &impl DynLagrangian,
    oracle: &dyn Fn(&[HyperDual64]) -> HyperDual64,
    x: &[f64],
    v: &[f64],
) {
    let n = x.len();
    let z: Vec<f64> = x.iter().chain(v).copied().collect();
    let (value, grad, hess) = dual_derivatives(oracle, &z);
    close(&format!("{name} L"), lag.value(x, v, 0.0), value);
    let (mut f, mut p) = (vec![0.0; n], vec![0.0; n]);
    lag.force(x, v, 0.0, &mut f);
    lag.momentum(x, v, 0.0, &mut p);
    let mut h = SparseHessian::new(n);
    lag.hessian(x, v, 0.0, &mut h);
    for i in 0..n {
        close(&format!("{name} ∂L/∂x[{i}]"), f[i], grad[i]);
        close(&format!("{name} ∂L/∂v[{i}]"), p[i], grad[n + i]);
        for j in 0..n {
            let (xx, xv, vv) = (h.xx.get(i, j), h.xv.get(i, j), h.vv.get(i, j));
            close(&format!("{name} xx[({i}, {j})]"), xx, hess[i][j]);
            close(&format!("{name} xv[({i}, {j})]"), xv, hess[i][n + j]);
            close(&format!("{name} vv[({i}, {j})]"), vv, hess[n + i][n + j]);
        }
    }
}

fn points(rng: &mut Rng) -> (Vector<N>, Vector<N>) {
    (rng.vector::<N>(0.8), rng.vector::<N>(1.5))
}

#[test]
fn a_sum_bound_to_a_local_and_squared() {
    let mut rng = Rng(11);
    let a = SquareOfSum { k: 0.7 };
    let b = SquareOfAccumulator { k: 0.7 };
    for _ in 0..5 {
        let (x, v) = points(&mut rng);
        let oracle = |w: &[HyperDual64]| square_of_sum_dual(w, 0.7);
        let h = assert_matches_oracle("square of sum", &a, &oracle, &x, &v);
        assert_matches_oracle("square of accumulator", &b, &oracle, &x, &v);
        // The mass matrix is the all-ones matrix plus one diagonal entry.
        for i in 0..N {
            for j in 0..N {
                let expected = 1.0 + f64::from(u8::from(i == 0 && j == 0));
                assert_eq!(h.vv[(i, j)], expected);
            }
        }
        let xs: Vec<f64> = x.iter().copied().collect();
        let vs: Vec<f64> = v.iter().copied().collect();
        close(
            "the fn's own value",
            Lagrangian::value(&a, &x, &v, 0.0),
            square_of_sum(x.into(), v.into(), 0.7),
        );
        assert_dyn_matches("square of sum (dyn)", &a, &oracle, &xs, &vs);
    }
    assert_eq!(Lagrangian::hessian_bandwidth(&a), None);
}

#[test]
fn a_centre_of_mass_read_in_a_second_loop() {
    let mut rng = Rng(12);
    let lag = CentreOfMass { k: 1.3 };
    for _ in 0..5 {
        let (x, v) = points(&mut rng);
        let oracle = |w: &[HyperDual64]| centre_of_mass_dual(w, 1.3);
        assert_matches_oracle("centre of mass", &lag, &oracle, &x, &v);
        let xs: Vec<f64> = x.iter().copied().collect();
        let vs: Vec<f64> = v.iter().copied().collect();
        assert_dyn_matches("centre of mass (dyn)", &lag, &oracle, &xs, &vs);
    }
}

#[test]
fn functions_of_sums_are_differentiated_through_the_sum() {
    let mut rng = Rng(13);
    let lag = FunctionsOfSums { k: 0.9 };
    for _ in 0..8 {
        let (x, v) = points(&mut rng);
        let oracle = |w: &[HyperDual64]| functions_of_sums_dual(w, 0.9);
        assert_matches_oracle("functions of sums", &lag, &oracle, &x, &v);
        let xs: Vec<f64> = x.iter().copied().collect();
        let vs: Vec<f64> = v.iter().copied().collect();
        assert_dyn_matches("functions of sums (dyn)", &lag, &oracle, &xs, &vs);
        close(
            "the fn's own value",
            Lagrangian::value(&lag, &x, &v, 0.0),
            functions_of_sums(x.into(), v.into(), 0.9),
        );
    }
    assert_eq!(Lagrangian::hessian_bandwidth(&lag), None);
}

#[test]
fn the_n_link_pendulum_with_per_link_accumulators_is_the_closed_form() {
    let mut rng = Rng(14);
    let (g, l) = (9.81, 0.7);
    let acc = NLinkAccumulated { g, l };
    let closed = NLinkClosed { g, l };
    for _ in 0..10 {
        let (x, v) = points(&mut rng);
        let tol = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + b.abs());
        assert!(tol(
            Lagrangian::value(&acc, &x, &v, 0.0),
            Lagrangian::value(&closed, &x, &v, 0.0)
        ));
        let (a, b) = (
            Lagrangian::gradient_and_hessian(&acc, &x, &v, 0.0),
            Lagrangian::gradient_and_hessian(&closed, &x, &v, 0.0),
        );
        for i in 0..N {
            assert!(tol(a.0[i], b.0[i]) && tol(a.1[i], b.1[i]), "gradient {i}");
            for j in 0..N {
                assert!(tol(a.2.xx[(i, j)], b.2.xx[(i, j)]), "xx ({i}, {j})");
                assert!(tol(a.2.xv[(i, j)], b.2.xv[(i, j)]), "xv ({i}, {j})");
                assert!(tol(a.2.vv[(i, j)], b.2.vv[(i, j)]), "vv ({i}, {j})");
            }
        }
    }
}

#[test]
fn sums_of_run_time_dimension() {
    let mut rng = Rng(15);
    // The point: `v = (1, 2, 3)`, `x = (0.1, 0.2, 0.3)`.
    let lag = RuntimeSums { n: 3, k: 0.5 };
    let (x, v) = (vec![0.1, 0.2, 0.3], vec![1.0, 2.0, 3.0]);
    close(
        "value at the point",
        lag.value(&x, &v, 0.0),
        runtime_sums(&x, &v, 3, 0.5),
    );
    for n in [1, 2, 5, 9] {
        let lag = RuntimeSums { n, k: 0.5 };
        let x: Vec<f64> = (0..n).map(|_| rng.uniform(-0.8, 0.8)).collect();
        let v: Vec<f64> = (0..n).map(|_| rng.uniform(-1.5, 1.5)).collect();
        let oracle = |w: &[HyperDual64]| runtime_sums_dual(w, n, 0.5);
        assert_dyn_matches(&format!("run-time sums at n = {n}"), &lag, &oracle, &x, &v);
        assert_eq!(lag.hessian_bandwidth(), None);
    }
}

/// A chain between walls pulled towards the origin by `k·√(1 + |x|²)`: a function of a global
/// sum, which couples every pair of particles.
#[lagrangian]
fn radial_chain(x: &[f64], v: &[f64], n: usize, k: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * v[i] * v[i];
    }
    for i in 0..n - 1 {
        l -= 0.5 * (x[i + 1] - x[i]).powi(2);
    }
    let r2: f64 = (0..n).map(|i| x[i] * x[i]).sum();
    l - 0.5 * x[0] * x[0] - 0.5 * x[n - 1] * x[n - 1] - k * (1.0 + r2).sqrt()
}

#[test]
fn a_function_of_a_global_sum_at_a_thousand_particles() {
    use varembed::{DynProblem, Embedding, Grid, Scheme, Side};
    let (n, k) = (1000, 0.3);
    let chain = RadialChain { n, k };
    let q0: Vec<f64> = (0..n)
        .map(|i| (std::f64::consts::PI * (i + 1) as f64 / (n + 1) as f64).sin())
        .collect();
    let v0 = vec![0.0; n];
    // The force and the dense `xx` block against their closed forms at the initial data:
    // `f_i = x_{i−1} − 2x_i + x_{i+1} − k x_i / r` and `xx = T − k (I/r − x xᵀ/r³)`.
    let r = (1.0 + q0.iter().map(|q| q * q).sum::<f64>()).sqrt();
    let at = |i: usize| if i < n { q0[i] } else { 0.0 };
    let force = |x: &[f64], f: &mut [f64]| {
        let r = (1.0 + x.iter().map(|q| q * q).sum::<f64>()).sqrt();
        for i in 0..n {
            let left = if i > 0 { x[i - 1] } else { 0.0 };
            let right = if i + 1 < n { x[i + 1] } else { 0.0 };
            f[i] = left - 2.0 * x[i] + right - k * x[i] / r;
        }
    };
    let mut f = vec![0.0; n];
    let mut generated = vec![0.0; n];
    force(&q0, &mut f);
    chain.force(&q0, &v0, 0.0, &mut generated);
    for i in 0..n {
        close(&format!("force {i}"), generated[i], f[i]);
    }
    let mut h = SparseHessian::new(n);
    chain.hessian(&q0, &v0, 0.0, &mut h);
    for (i, j) in [
        (0usize, 0usize),
        (0, 1),
        (3, 900),
        (500, 500),
        (999, 998),
        (17, 400),
    ] {
        let tridiagonal = match i.abs_diff(j) {
            0 => -2.0,
            1 => 1.0,
            _ => 0.0,
        };
        let identity = f64::from(u8::from(i == j));
        let expected = tridiagonal - k * (identity / r - at(i) * at(j) / r.powi(3));
        close(&format!("xx[({i}, {j})]"), h.xx.get(i, j), expected);
    }
    // Every entry of the dense part is listed, beside the bonds' and the sum's own terms.
    assert!(h.xx.entries().len() >= n * n);
    // The explicit variational run (Störmer–Verlet) reads the force only: the same nodes as
    // the loop written by hand.
    let (steps, h_step) = (200, 0.05);
    let grid = Grid::new(0.0, steps as f64 * h_step, steps).unwrap();
    let run = DynProblem::new(&chain, grid, Embedding::finite_difference(Side::Forward))
        .solve_ivp(Scheme::Variational, &q0, &v0)
        .unwrap();
    let h2 = h_step * h_step;
    force(&q0, &mut f);
    let mut a = q0.clone();
    let mut b: Vec<f64> = (0..n).map(|i| q0[i] + h2 * f[i]).collect();
    let mut worst = 0.0f64;
    for step in 2..=steps {
        force(&b, &mut f);
        let y: Vec<f64> = (0..n).map(|i| 2.0 * b[i] - a[i] + h2 * f[i]).collect();
        let gap = y
            .iter()
            .zip(run.node(step))
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        worst = worst.max(gap);
        (a, b) = (b, y);
    }
    assert!(worst < 1e-11, "largest node gap {worst:.2e}");
}

#[test]
fn the_two_n_link_pendulums_give_the_same_nodes() {
    use varembed::{Embedding, Grid, Problem, Scheme};
    let (g, l) = (9.81, 0.7);
    let grid = Grid::new(0.0, 1.0, 200).unwrap();
    let q0 = Vector::<N>::from_fn(|i, _| 0.3 + 0.2 * i as f64);
    let v0 = Vector::<N>::from_fn(|i, _| 0.5 - 0.25 * i as f64);
    for embedding in [Embedding::midpoint(), Embedding::gauss_legendre(2).unwrap()] {
        let a = Problem::new(&NLinkAccumulated { g, l }, grid, embedding)
            .solve_ivp(Scheme::Variational, q0, v0)
            .unwrap();
        let b = Problem::new(&NLinkClosed { g, l }, grid, embedding)
            .solve_ivp(Scheme::Variational, q0, v0)
            .unwrap();
        let gap = (0..=200)
            .map(|k| (a.q[k] - b.q[k]).amax())
            .fold(0.0, f64::max);
        assert!(gap < 1e-10, "node gap {gap:.2e}");
    }
}

/// Every entry of the three blocks beyond the claimed half-bandwidth is exactly zero, at random
/// points: the claim checked against the Hessian itself, never against the macro's reasoning.
fn band_claim_holds<const D: usize>(name: &str, lag: &impl Lagrangian<D>, rng: &mut Rng) {
    let Some(band) = lag.hessian_bandwidth() else {
        return;
    };
    for _ in 0..4 {
        let (x, v) = (rng.vector::<D>(0.8), rng.vector::<D>(1.5));
        let h = lag.hessian(&x, &v, rng.uniform(0.0, 1.0));
        for (block, m) in [("xx", &h.xx), ("xv", &h.xv), ("vv", &h.vv)] {
            for i in 0..D {
                for j in 0..D {
                    if i.abs_diff(j) > band {
                        assert_eq!(m[(i, j)], 0.0, "{name}: {block}[({i}, {j})] beyond {band}");
                    }
                }
            }
        }
    }
}

/// [`band_claim_holds`] for a run-time model, on every listed entry.
fn dyn_band_claim_holds(name: &str, lag: &impl DynLagrangian, rng: &mut Rng) {
    let Some(band) = lag.hessian_bandwidth() else {
        return;
    };
    let n = lag.dimension();
    for _ in 0..4 {
        let x: Vec<f64> = (0..n).map(|_| rng.uniform(-0.8, 0.8)).collect();
        let v: Vec<f64> = (0..n).map(|_| rng.uniform(-1.5, 1.5)).collect();
        let mut h = SparseHessian::new(n);
        lag.hessian(&x, &v, 0.0, &mut h);
        for (block, b) in [("xx", &h.xx), ("xv", &h.xv), ("vv", &h.vv)] {
            for &(i, j, e) in b.entries() {
                if i.abs_diff(j) > band {
                    assert_eq!(e, 0.0, "{name}: {block}[({i}, {j})] beyond {band}");
                }
            }
        }
    }
}

#[test]
fn the_claimed_bands_of_the_suite_models_hold() {
    use varembed_tests::models::generated::{
        DoublePendulum, FputChain, Kepler, Magnetic, fput16, ring12,
    };
    let mut rng = Rng(16);
    band_claim_holds("kepler", &Kepler, &mut rng);
    let double = DoublePendulum {
        m1: 1.0,
        m2: 2.0,
        l1: 1.0,
        l2: 0.5,
        g: 9.81,
    };
    band_claim_holds("double pendulum", &double, &mut rng);
    band_claim_holds("magnetic", &Magnetic { b: 0.7 }, &mut rng);
    let fput = fput16::Fput {
        alpha: 0.25,
        beta: 0.5,
    };
    band_claim_holds("fput16", &fput, &mut rng);
    dyn_band_claim_holds("fput16 (dyn)", &fput, &mut rng);
    let ring = ring12::Ring {
        alpha: 0.25,
        beta: 0.5,
    };
    band_claim_holds("ring12", &ring, &mut rng);
    dyn_band_claim_holds("ring12 (dyn)", &ring, &mut rng);
    let chain = FputChain {
        n: 40,
        alpha: 0.25,
        beta: 0.5,
    };
    dyn_band_claim_holds("fput chain", &chain, &mut rng);
    let n_link = NLinkAccumulated { g: 9.81, l: 0.7 };
    band_claim_holds("n-link (accumulators)", &n_link, &mut rng);
    band_claim_holds("square of sum", &SquareOfSum { k: 0.7 }, &mut rng);
    band_claim_holds("centre of mass", &CentreOfMass { k: 0.7 }, &mut rng);
    dyn_band_claim_holds("run-time sums", &RuntimeSums { n: 7, k: 0.5 }, &mut rng);
    // A claimed band: the bonds of a chain, no sum used as a value.
    assert_eq!(DynLagrangian::hessian_bandwidth(&chain), Some(1));
}
