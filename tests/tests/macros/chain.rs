//! A generated chain integrated by the library against a hand-written `Lagrangian` impl of the
//! same chain, and a chain of 10⁴ particles through the macro (its expansion is the size of a
//! chain of 4: the loops stay loops).

use varembed::{
    Embedding, Grid, Hessian, HessianDependence, Lagrangian, Matrix, Problem, Scheme, Side, Vector,
    lagrangian,
};
use varembed_tests::models::hand::SEPARABLE;

/// α-FPUT chain of 16 particles with fixed ends, through the macro.
mod fput16 {
    use super::lagrangian;

    pub const N: usize = 16;

    #[lagrangian]
    pub fn fput(x: [f64; N], v: [f64; N], alpha: f64) -> f64 {
        let kinetic = (0..N).map(|i| 0.5 * v[i] * v[i]).sum::<f64>();
        let mut potential = 0.0;
        for i in 0..N + 1 {
            // Bond `i` joins particle `i − 1` and particle `i`; both ends are fixed at 0.
            let left = if i == 0 { 0.0 } else { x[(i + N - 1) % N] };
            let right = if i == N { 0.0 } else { x[i % N] };
            let d = right - left;
            potential += 0.5 * d * d + alpha / 3.0 * d * d * d;
        }
        kinetic - potential
    }
}

/// The same chain written by hand with loops: `V'(d) = d + α d²`, `V''(d) = 1 + 2α d`.
struct HandFput {
    alpha: f64,
}

impl HandFput {
    /// The bond lengths `d_k = x_k − x_{k−1}`, `k = 0..=N`, with `x_{−1} = x_N = 0`.
    fn bonds(x: &Vector<16>) -> [f64; 17] {
        let at = |k: usize| if k == 0 || k == 17 { 0.0 } else { x[k - 1] };
        std::array::from_fn(|k| at(k + 1) - at(k))
    }
}

impl Lagrangian<16> for HandFput {
    fn value(&self, x: &Vector<16>, v: &Vector<16>, _t: f64) -> f64 {
        let potential: f64 = Self::bonds(x)
            .iter()
            .map(|d| 0.5 * d * d + self.alpha / 3.0 * d * d * d)
            .sum();
        0.5 * v.norm_squared() - potential
    }
    fn gradient(&self, x: &Vector<16>, v: &Vector<16>, _t: f64) -> (Vector<16>, Vector<16>) {
        let d = Self::bonds(x);
        let force = Vector::<16>::from_fn(|i, _| {
            let dv = |k: usize| d[k] + self.alpha * d[k] * d[k];
            dv(i + 1) - dv(i)
        });
        (force, *v)
    }
    fn hessian(&self, x: &Vector<16>, _v: &Vector<16>, _t: f64) -> Hessian<16> {
        let d = Self::bonds(x);
        let stiffness = |k: usize| 1.0 + 2.0 * self.alpha * d[k];
        let mut xx = Matrix::<16>::zeros();
        for i in 0..16 {
            xx[(i, i)] = -stiffness(i) - stiffness(i + 1);
            if i + 1 < 16 {
                xx[(i, i + 1)] = stiffness(i + 1);
                xx[(i + 1, i)] = stiffness(i + 1);
            }
        }
        Hessian {
            xx,
            xv: Matrix::<16>::zeros(),
            vv: Matrix::<16>::identity(),
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        SEPARABLE
    }
}

/// Both schemes, both sides: the generated chain's trajectory is the hand-written one's.
#[test]
fn generated_fput_chain_integrates_as_the_hand_written_one() -> varembed::Result<()> {
    let generated = fput16::Fput { alpha: 0.25 };
    let hand = HandFput { alpha: 0.25 };
    assert_eq!(generated.hessian_dependence(), hand.hessian_dependence());
    // The lowest normal mode, `x_i = A sin(π (i + 1)/17)`, at rest.
    let q0 =
        Vector::<16>::from_fn(|i, _| 0.8 * (std::f64::consts::PI * (i + 1) as f64 / 17.0).sin());
    let v0 = Vector::<16>::zeros();
    let grid = Grid::new(0.0, 20.0, 2000)?;
    for side in [Side::Backward, Side::Forward] {
        let embedding = Embedding::finite_difference(side);
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let a = Problem::new(&generated, grid, embedding).solve_ivp(scheme, q0, v0)?;
            let b = Problem::new(&hand, grid, embedding).solve_ivp(scheme, q0, v0)?;
            let distance = a.max_distance(&b.q).expect("same grid");
            let size = b.q.iter().map(|q| q.amax()).fold(0.0, f64::max);
            assert!(
                distance <= 1e-10 * size,
                "{side:?} {scheme}: distance {distance:e}"
            );
            // The run moved: the chain is not at rest at the end.
            assert!((b.q[2000] - q0).amax() > 0.1, "{side:?} {scheme}");
        }
    }
    Ok(())
}

/// An FPUT chain of 10⁴ particles with fixed ends.
mod fput10k {
    use super::lagrangian;

    pub const N: usize = 10_000;

    #[lagrangian]
    pub fn fput(x: [f64; N], v: [f64; N], alpha: f64, beta: f64) -> f64 {
        let mut l = 0.0;
        for i in 0..N {
            l += 0.5 * v[i] * v[i];
        }
        for i in 0..N - 1 {
            let d = x[i + 1] - x[i];
            l -= 0.5 * d * d + alpha / 3.0 * d.powi(3) + beta / 4.0 * d.powi(4);
        }
        l - 0.5 * x[0] * x[0] - 0.5 * x[N - 1] * x[N - 1]
    }
}

/// The 10⁴-particle chain compiles (through the same loops as a small one) and its value and
/// gradient are those of the chain's formula evaluated by hand. (Its Hessian is a dense
/// 10⁴ × 10⁴ matrix in today's `Hessian`, too large to build here.)
#[test]
fn chain_of_ten_thousand_particles() {
    const N: usize = fput10k::N;
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(|| {
            let lag = fput10k::Fput {
                alpha: 0.25,
                beta: 0.5,
            };
            let x = Box::new(Vector::<N>::from_fn(|i, _| 0.3 * (0.01 * i as f64).sin()));
            let v = Box::new(Vector::<N>::from_fn(|i, _| (0.02 * i as f64).cos()));
            let vd = |d: f64| d + 0.25 * d * d + 0.5 * d * d * d;
            let mut bonds = vec![x[0]];
            bonds.extend((0..N - 1).map(|i| x[i + 1] - x[i]));
            bonds.push(-x[N - 1]);
            let value: f64 = 0.5 * v.norm_squared()
                - bonds
                    .iter()
                    .map(|d| 0.5 * d * d + 0.25 / 3.0 * d.powi(3) + 0.5 / 4.0 * d.powi(4))
                    .sum::<f64>();
            // With fixed ends the first and last bonds are plain springs in the macro's form.
            let end = |d: f64| 0.25 / 3.0 * d.powi(3) + 0.5 / 4.0 * d.powi(4);
            let value = value + end(bonds[0]) + end(bonds[N]);
            let got = lag.value(&x, &v, 0.0);
            assert!((got - value).abs() <= 1e-12 * value.abs(), "{got} {value}");
            let (f, p) = lag.gradient(&x, &v, 0.0);
            for i in 0..N {
                let left = if i == 0 { bonds[0] } else { vd(bonds[i]) };
                let right = if i == N - 1 {
                    bonds[N]
                } else {
                    vd(bonds[i + 1])
                };
                let expected = right - left;
                assert!(
                    (f[i] - expected).abs() <= 1e-12 * expected.abs().max(1.0),
                    "f[{i}]"
                );
                assert_eq!(p[i], v[i]);
            }
        })
        .expect("a thread")
        .join()
        .expect("the check passes");
}
