//! The example of the `#[lagrangian]` docs, compiled and run (the proc-macro crate cannot run
//! doctests that use `varembed`).

use varembed::{Lagrangian, Vector, lagrangian};

/// Planar pendulum of length `l` under gravity `g`.
#[lagrangian]
fn pendulum(x: f64, v: f64, g: f64, l: f64) -> f64 {
    0.5 * l * l * v * v + g * l * x.cos()
}

#[test]
fn doc_example() {
    let lag = Pendulum { g: 9.81, l: 2.0 };
    let (x, v) = (Vector::<1>::new(0.3), Vector::<1>::new(-1.0));
    let (f, p) = lag.gradient(&x, &v, 0.0);
    assert_eq!(f[0], -9.81 * 2.0 * 0.3f64.sin());
    assert_eq!(p[0], -4.0);
    assert_eq!(pendulum(0.3, -1.0, 9.81, 2.0), lag.value(&x, &v, 0.0));
    println!("{}", Pendulum::DERIVATIVES);
}
