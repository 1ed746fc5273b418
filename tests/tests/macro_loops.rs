//! Lagrangians with loops through `#[lagrangian]`: quick check.

use varembed::{Lagrangian, Vector, lagrangian};

const N: usize = 4;

#[lagrangian]
fn chain(x: [f64; N], v: [f64; N], alpha: f64) -> f64 {
    let mut kinetic = 0.0;
    for i in 0..N {
        kinetic += 0.5 * v[i] * v[i];
    }
    let potential = (0..N - 1)
        .map(|i| {
            let d = x[i + 1] - x[i];
            0.5 * d * d + alpha / 3.0 * d.powi(3)
        })
        .sum::<f64>();
    kinetic - potential
}

#[test]
fn chain_runs() {
    let lag = Chain { alpha: 0.25 };
    let x = Vector::<N>::from_fn(|i, _| (i as f64 * 0.7).sin());
    let v = Vector::<N>::from_fn(|i, _| (i as f64 * 0.3).cos());
    let (f, p) = lag.gradient(&x, &v, 0.0);
    let h = lag.hessian(&x, &v, 0.0);
    println!("{}", Chain::DERIVATIVES);
    println!("{f} {p} {}", h.xx);
    assert_eq!(lag.value(&x, &v, 0.0), chain([x[0], x[1], x[2], x[3]], [v[0], v[1], v[2], v[3]], 0.25));
}
