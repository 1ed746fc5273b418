//! Chains and lattices of any length as plain generic fns of `z = (x, v)`, for num-dual's
//! hyper-dual numbers: the oracles of the `#[lagrangian]` models with loops (a named dimension
//! in `macro_loops.rs`, a run-time one in `macro_dyn.rs`).

use num_dual::DualNum;

/// `V(d) = d²/2 + α d³/3 + β d⁴/4`, the FPUT spring.
pub fn spring_dual<T: DualNum<Primitive = f64> + Copy>(d: T, alpha: f64, beta: f64) -> T {
    d * d * 0.5 + d.powi(3) * (alpha / 3.0) + d.powi(4) * (beta / 4.0)
}

/// The FPUT chain of `n = z.len() / 2` unit masses with fixed ends `x_{−1} = x_n = 0`;
/// `p = [α, β]`.
pub fn fput_fixed_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], p: [f64; 2]) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let mut l = T::zero();
    for i in 0..n {
        l += v[i] * v[i] * 0.5;
    }
    // Positions with the fixed ends: 0, x_0, …, x_{N−1}, 0.
    let at = |k: usize| {
        if k == 0 || k == n + 1 {
            T::zero()
        } else {
            x[k - 1]
        }
    };
    for k in 0..=n {
        l -= spring_dual(at(k + 1) - at(k), p[0], p[1]);
    }
    l
}

/// The periodic FPUT chain, `x_n = x_0`; `p = [α, β]`.
pub fn fput_periodic_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], p: [f64; 2]) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let mut l = T::zero();
    for i in 0..n {
        l += v[i] * v[i] * 0.5 - spring_dual(x[(i + 1) % n] - x[i], p[0], p[1]);
    }
    l
}

/// The periodic Toda lattice, `V(d) = (a/b) e^{−b d} + a d`; `p = [a, b]`.
pub fn toda_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], p: [f64; 2]) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let (a, b) = (p[0], p[1]);
    let mut l = T::zero();
    for i in 0..n {
        let d = x[(i + 1) % n] - x[i];
        l += v[i] * v[i] * 0.5 - ((d * (-b)).exp() * (a / b) + d * a);
    }
    l
}

/// The n-link pendulum of unit masses, lengths `l`, gravity `g`; `p = [g, l]`.
pub fn n_link_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], p: [f64; 2]) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let (g, l) = (p[0], p[1]);
    let mut out = T::zero();
    for i in 0..n {
        for j in 0..n {
            let m = (n - i.max(j)) as f64;
            out += (x[i] - x[j]).cos() * v[i] * v[j] * (0.5 * l * l * m);
        }
        out += x[i].cos() * (g * l * (n - i) as f64);
    }
    out
}
