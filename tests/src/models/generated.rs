//! Models through `#[lagrangian]`, each written as a user of the macro writes it.
//!
//! The benches time these exact bodies (BENCHMARKS.md), so a change to one changes the figures.

use varembed::lagrangian;

/// Planar pendulum of length `l` under gravity `g` (the same model as
/// [`hand::Pendulum`](crate::models::hand::Pendulum)).
#[lagrangian]
pub fn pendulum(x: f64, v: f64, g: f64, l: f64) -> f64 {
    0.5 * l * l * v * v + g * l * x.cos()
}

/// Pendulum with `g = l = 1`, `L = ½v² + cos x`.
#[lagrangian]
pub fn unit_pendulum(x: f64, v: f64) -> f64 {
    0.5 * v * v + x.cos()
}

/// A forced, inverted spring, `L = ½v² − ½k x² + c x`: for `k` above the lowest kinetic
/// eigenvalue of a boundary value problem its Jacobian `DᵀD − k` is indefinite.
#[lagrangian]
pub fn forced_spring(x: f64, v: f64, k: f64, c: f64) -> f64 {
    0.5 * v * v - 0.5 * k * x * x + c * x
}

/// `L = ½v² + c cos x`: a pendulum of strength `c` (the nonlinear fractional cases).
#[lagrangian]
pub fn strong_pendulum(x: f64, v: f64, c: f64) -> f64 {
    0.5 * v * v + c * x.cos()
}

/// `L = ½v² − ¼x⁴ − ½b x² + c x`: a quartic potential well with a quadratic part and a force.
#[lagrangian]
pub fn quartic(x: f64, v: f64, b: f64, c: f64) -> f64 {
    0.5 * v * v - 0.25 * x * x * x * x - 0.5 * b * x * x + c * x
}

/// Kepler, `μ = 1`: `L = ½|v|² + 1/|x|`, singular at the origin.
#[lagrangian]
pub fn kepler(x: [f64; 2], v: [f64; 2]) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1]) + 1.0 / (x[0] * x[0] + x[1] * x[1]).sqrt()
}

/// Double pendulum: a configuration-dependent mass matrix, so its implicit steps run Newton.
#[lagrangian]
pub fn double_pendulum(
    x: [f64; 2],
    v: [f64; 2],
    m1: f64,
    m2: f64,
    l1: f64,
    l2: f64,
    g: f64,
) -> f64 {
    let kinetic = 0.5 * (m1 + m2) * l1 * l1 * v[0] * v[0]
        + 0.5 * m2 * l2 * l2 * v[1] * v[1]
        + m2 * l1 * l2 * v[0] * v[1] * (x[0] - x[1]).cos();
    let potential = -(m1 + m2) * g * l1 * x[0].cos() - m2 * g * l2 * x[1].cos();
    kinetic - potential
}

/// A charged particle in the plane under a uniform magnetic field `b`, symmetric gauge:
/// `L = ½|v|² + (b/2)(x₀v₁ − x₁v₀)`. Not separable (`∂²L/∂x∂v ≠ 0`); the motion is a circle of
/// radius `|v|/|b|` about a fixed guiding centre `(x₀ + v₁/b, x₁ − v₀/b)`, run clockwise at the
/// angular speed `b`.
#[lagrangian]
pub fn magnetic(x: [f64; 2], v: [f64; 2], b: f64) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1]) + 0.5 * b * (x[0] * v[1] - x[1] * v[0])
}

/// A module `$module` holding `N = $n` and the FPUT chain of `N` unit masses between two walls
/// at 0, written with loops: `L = Σ ½v_i² − Σ V(d)` over the bonds `d = x_{i+1} − x_i`, the
/// two to the walls included, `V(d) = d²/2 + α d³/3 + β d⁴/4`. Its Hessian is tridiagonal.
macro_rules! fput_chain {
    ($module:ident, $n:expr) => {
        #[doc = concat!("The FPUT chain of ", stringify!($n), " particles.")]
        pub mod $module {
            use varembed::lagrangian;

            /// The number of moving particles.
            pub const N: usize = $n;

            /// FPUT chain with fixed ends `x_{−1} = x_N = 0`.
            #[lagrangian]
            pub fn fput(x: [f64; N], v: [f64; N], alpha: f64, beta: f64) -> f64 {
                let mut kinetic = 0.0;
                for i in 0..N {
                    kinetic += 0.5 * v[i] * v[i];
                }
                let mut potential = 0.0;
                for i in 0..N - 1 {
                    let d = x[i + 1] - x[i];
                    potential += 0.5 * d * d + alpha / 3.0 * d.powi(3) + beta / 4.0 * d.powi(4);
                }
                let (first, last) = (x[0], -x[N - 1]);
                potential +=
                    0.5 * first * first + alpha / 3.0 * first.powi(3) + beta / 4.0 * first.powi(4);
                potential +=
                    0.5 * last * last + alpha / 3.0 * last.powi(3) + beta / 4.0 * last.powi(4);
                kinetic - potential
            }
        }
    };
}

fput_chain!(fput16, 16);
fput_chain!(fput32, 32);
fput_chain!(fput64, 64);

/// The periodic FPUT chain of `N = 12` particles (a ring: the bond `x_0 − x_{N−1}` closes it),
/// written with loops and `x[(i + 1) % N]`: the const-generic oracle of the run-time ring, whose
/// Hessian is not banded in the model's order.
pub mod ring12 {
    use varembed::lagrangian;

    /// The number of particles.
    pub const N: usize = 12;

    /// The FPUT ring, `V(d) = d²/2 + α d³/3 + β d⁴/4` on every bond.
    #[lagrangian]
    pub fn ring(x: [f64; N], v: [f64; N], alpha: f64, beta: f64) -> f64 {
        let mut l = 0.0;
        for i in 0..N {
            let d = x[(i + 1) % N] - x[i];
            l += 0.5 * v[i] * v[i]
                - (0.5 * d * d + alpha / 3.0 * d.powi(3) + beta / 4.0 * d.powi(4));
        }
        l
    }
}

/// The FPUT chain of the `fput_chain!` models with its length `n` a run-time value:
/// `n` unit masses between two walls at 0, `V(d) = d²/2 + α d³/3 + β d⁴/4`. Through
/// `#[lagrangian]` it implements only `DynLagrangian` (tridiagonal Hessian,
/// `hessian_bandwidth() = Some(1)`).
#[lagrangian]
pub fn fput_chain(x: &[f64], v: &[f64], n: usize, alpha: f64, beta: f64) -> f64 {
    let mut kinetic = 0.0;
    for i in 0..n {
        kinetic += 0.5 * v[i] * v[i];
    }
    let mut potential = 0.0;
    for i in 0..n - 1 {
        let d = x[i + 1] - x[i];
        potential += 0.5 * d * d + alpha / 3.0 * d.powi(3) + beta / 4.0 * d.powi(4);
    }
    let (first, last) = (x[0], -x[n - 1]);
    potential += 0.5 * first * first + alpha / 3.0 * first.powi(3) + beta / 4.0 * first.powi(4);
    potential += 0.5 * last * last + alpha / 3.0 * last.powi(3) + beta / 4.0 * last.powi(4);
    kinetic - potential
}
