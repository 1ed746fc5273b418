//! `#[force]`: the generated force and its Jacobian blocks `∂f/∂x`, `∂f/∂v` against num-dual
//! (each column from its own dual evaluation of the same formula written as a plain generic
//! fn) and against central differences of the generated force, at 300 generated points per
//! force; the claimed `jacobian_dependence` against the exact claims and against redrawn
//! points (a block that claims not to read `x`, `v` or `t` is unchanged, bit for bit, when it
//! is redrawn); `constants` and `DERIVATIVES`.

#![allow(
    dead_code,
    reason = "the #[force] fns stay callable, but these tests use the generated structs"
)]
#![allow(
    clippy::needless_range_loop,
    reason = "the loop forms the macro accepts, written as the docs show them"
)]

use num_dual::{Dual64, DualNum};
use varembed::{Dependence, Force, ForceDependence, Vector, force, lagrangian};
use varembed_tests::rng::Rng;

/// The numbers the oracles run on: num-dual's, over `f64`.
pub trait Real: DualNum<Primitive = f64> + Copy {}

impl<T: DualNum<Primitive = f64> + Copy> Real for T {}

/// Points per force.
pub const POINTS: usize = 300;

/// A non-symmetric `∂f/∂x` (a curl `w`), `let` bindings, constants, both blocks reading `x`
/// and `v`.
#[force]
fn twist(x: [f64; 3], v: [f64; 3], k: f64, w: f64) -> [f64; 3] {
    let r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
    let s = (1.0 + r2).sqrt();
    [
        -k * x[0] / s + w * x[1] * v[2],
        -k * x[1] / s - w * x[0].sin() * v[0],
        -k * x[2] * s + w * (x[0] * x[1]).cos() - 0.1 * v[2].powi(3),
    ]
}

fn twist_dual<T: Real>(x: &[T], v: &[T], _t: T, c: &Twist) -> Vec<T> {
    let s = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + 1.0).sqrt();
    vec![
        -x[0] / s * c.k + x[1] * v[2] * c.w,
        -x[1] / s * c.k - x[0].sin() * v[0] * c.w,
        -x[2] * s * c.k + (x[0] * x[1]).cos() * c.w - v[2].powi(3) * 0.1,
    ]
}

/// A drive in `t`.
#[force]
fn drive(x: [f64; 2], v: [f64; 2], t: f64, a: f64, omega: f64) -> [f64; 2] {
    let phase = omega * t;
    [
        a * phase.cos() * x[1].tanh() - v[0] * t,
        a * phase.sin() * (x[0] - v[1]).exp_m1(),
    ]
}

fn drive_dual<T: Real>(x: &[T], v: &[T], t: T, c: &Drive) -> Vec<T> {
    let phase = t * c.omega;
    vec![
        phase.cos() * x[1].tanh() * c.a - v[0] * t,
        phase.sin() * (x[0] - v[1]).exp_m1() * c.a,
    ]
}

/// A spring's pull `k d + k d³` as an array, from a helper.
#[lagrangian(helper)]
fn pull(d: f64, k: f64) -> [f64; 2] {
    [k * d, k * d * d * d]
}

/// Helper calls, `atan`, `hypot`.
#[force]
fn anharmonic(x: [f64; 2], v: [f64; 2], k: f64, c: f64) -> [f64; 2] {
    let p = pull(x[0] - x[1], k);
    [
        -(p[0] + p[1]) - c * v[0].atan(),
        p[0] + p[1] - c * v[1] * v[0].hypot(1.0),
    ]
}

fn anharmonic_dual<T: Real>(x: &[T], v: &[T], _t: T, m: &Anharmonic) -> Vec<T> {
    let d = x[0] - x[1];
    let p = d * m.k + d * d * d * m.k;
    vec![
        -p - v[0].atan() * m.c,
        p - v[1] * (v[0] * v[0] + 1.0).sqrt() * m.c,
    ]
}

/// A local array set element by element in loops over literal ranges (unrolled).
#[force]
fn chain_drag(x: [f64; 4], v: [f64; 4], c: f64) -> [f64; 4] {
    let mut f = [0.0; 4];
    for i in 0..4 {
        f[i] = -c * v[i] * (1.0 + x[i] * x[i]);
    }
    for i in 0..3 {
        let s = (x[i + 1] - x[i]).sin();
        f[i] += s;
        f[i + 1] -= 0.5 * s * v[i];
    }
    f
}

fn chain_drag_dual<T: Real>(x: &[T], v: &[T], _t: T, m: &ChainDrag) -> Vec<T> {
    let mut f: Vec<T> = (0..4).map(|i| -v[i] * (x[i] * x[i] + 1.0) * m.c).collect();
    for i in 0..3 {
        let s = (x[i + 1] - x[i]).sin();
        f[i] += s;
        f[i + 1] -= s * v[i] * 0.5;
    }
    f
}

/// A ring: periodic indices `x[(i + 1) % 4]` in an unrolled loop, resolved to components.
#[force]
fn ring(x: [f64; 4], v: [f64; 4], k: f64) -> [f64; 4] {
    let mut f = [0.0; 4];
    for i in 0..4 {
        f[i] = k * (x[(i + 1) % 4] - x[i]).sin() - 0.1 * v[(i + 3) % 4];
    }
    f
}

fn ring_dual<T: Real>(x: &[T], v: &[T], _t: T, m: &Ring) -> Vec<T> {
    (0..4)
        .map(|i| (x[(i + 1) % 4] - x[i]).sin() * m.k - v[(i + 3) % 4] * 0.1)
        .collect()
}

/// Linear damping with a position coupling: constant blocks.
#[force]
fn damping(x: [f64; 2], v: [f64; 2], c: f64) -> [f64; 2] {
    [-c * v[0], -c * v[1] - 0.5 * x[0]]
}

fn damping_dual<T: Real>(x: &[T], v: &[T], _t: T, m: &Damping) -> Vec<T> {
    vec![-v[0] * m.c, -v[1] * m.c - x[0] * 0.5]
}

/// One degree of freedom: `x`, `v` and the force `f64`.
#[force]
fn van_der_pol(x: f64, v: f64, mu: f64) -> f64 {
    mu * (1.0 - x * x) * v
}

fn van_der_pol_dual<T: Real>(x: &[T], v: &[T], _t: T, m: &VanDerPol) -> Vec<T> {
    vec![(-x[0] * x[0] + 1.0) * v[0] * m.mu]
}

/// The largest errors of a force over the points: against num-dual (relative to
/// `max(|oracle|, 1)`) and against central differences (step `1e-6`).
#[derive(Debug, Default)]
pub struct Errors {
    pub dual: f64,
    pub central: f64,
}

impl Errors {
    /// The line the tests print for `name` (run with `--nocapture`).
    pub fn print(&self, name: &str) {
        println!(
            "{name}: {POINTS} points, max relative error vs num-dual {:e}, vs central differences {:e}",
            self.dual, self.central
        );
    }
}

/// The oracle of a force `F`: `f(x, v, t)` on dual numbers, with the force's constants.
type Oracle<F> = fn(&[Dual64], &[Dual64], Dual64, &F) -> Vec<Dual64>;

/// Checks `f` against `oracle` at [`POINTS`] points drawn from `seed`, and its claimed
/// dependence by redrawing what a block claims not to read; prints the largest errors.
fn check<const D: usize, F: Force<D>>(name: &str, f: &F, oracle: Oracle<F>, seed: u64) {
    let mut rng = Rng(seed);
    let mut errors = Errors::default();
    let claimed = f.jacobian_dependence();
    for _ in 0..POINTS {
        let (x, v): (Vector<D>, Vector<D>) = (rng.vector(1.0), rng.vector(1.0));
        let t = rng.uniform(0.0, 2.0);
        let value = f.force(&x, &v, t);
        let j = f.jacobian(&x, &v, t);
        // Column `c` of `[∂f/∂x | ∂f/∂v]` from one dual evaluation seeded in `z_c`.
        for c in 0..=2 * D {
            let seed = |k: usize, a: f64| Dual64::new(a, f64::from(u8::from(k == c)));
            let xd: Vec<Dual64> = (0..D).map(|k| seed(k, x[k])).collect();
            let vd: Vec<Dual64> = (0..D).map(|k| seed(D + k, v[k])).collect();
            let out = oracle(&xd, &vd, Dual64::from(t), f);
            for i in 0..D {
                let (got, want) = match c {
                    c if c == 2 * D => (value[i], out[i].re),
                    c if c < D => (j.x[(i, c)], out[i].eps),
                    c => (j.v[(i, c - D)], out[i].eps),
                };
                let err = (got - want).abs() / want.abs().max(1.0);
                assert!(
                    err <= 1e-12,
                    "{name} column {c} row {i}: {got:e} vs {want:e}"
                );
                errors.dual = errors.dual.max(err);
            }
        }
        // Central differences of the generated force itself.
        let h = 1e-6;
        for c in 0..2 * D {
            let (mut xp, mut vp, mut xm, mut vm) = (x, v, x, v);
            if c < D {
                xp[c] += h;
                xm[c] -= h;
            } else {
                vp[c - D] += h;
                vm[c - D] -= h;
            }
            let diff = (f.force(&xp, &vp, t) - f.force(&xm, &vm, t)) / (2.0 * h);
            for i in 0..D {
                let got = if c < D { j.x[(i, c)] } else { j.v[(i, c - D)] };
                let err = (got - diff[i]).abs() / diff[i].abs().max(1.0);
                assert!(
                    err <= 1e-7,
                    "{name} central {c} row {i}: {got:e} vs {:e}",
                    diff[i]
                );
                errors.central = errors.central.max(err);
            }
        }
        // What a block claims not to read, redrawn alone, leaves it unchanged.
        let (x2, v2, t2) = (rng.vector(1.0), rng.vector(1.0), rng.uniform(0.0, 2.0));
        let redrawn = [
            ("x", f.jacobian(&x2, &v, t)),
            ("v", f.jacobian(&x, &v2, t)),
            ("t", f.jacobian(&x, &v, t2)),
        ];
        for (what, again) in redrawn {
            for (block, dep, before, after) in [
                ("∂f/∂x", claimed.x, j.x, again.x),
                ("∂f/∂v", claimed.v, j.v, again.v),
            ] {
                let reads = match what {
                    "x" => dep.x,
                    "v" => dep.v,
                    _ => dep.t,
                };
                if !reads {
                    assert_eq!(after, before, "{name}: {block} claims not to read {what}");
                }
            }
        }
    }
    errors.print(name);
}

fn dep(x: bool, v: bool, t: bool) -> Dependence {
    Dependence { x, v, t }
}

#[test]
fn forces_match_num_dual_and_central_differences() {
    check("twist", &Twist { k: 1.3, w: 0.7 }, twist_dual, 1);
    check("drive", &Drive { a: 0.8, omega: 2.1 }, drive_dual, 2);
    check(
        "anharmonic",
        &Anharmonic { k: 0.9, c: 0.4 },
        anharmonic_dual,
        3,
    );
    check("chain_drag", &ChainDrag { c: 0.6 }, chain_drag_dual, 4);
    check("damping", &Damping { c: 0.25 }, damping_dual, 5);
    check("van_der_pol", &VanDerPol { mu: 1.5 }, van_der_pol_dual, 6);
    check("ring", &Ring { k: 0.7 }, ring_dual, 7);
}

/// What each force's blocks read, exactly: the macro finds no dependence that is not there and
/// misses none.
#[test]
fn forces_claim_what_their_blocks_read() {
    let claims = [
        (
            Twist { k: 1.0, w: 1.0 }.jacobian_dependence(),
            [dep(true, true, false), dep(true, true, false)],
        ),
        (
            Drive { a: 1.0, omega: 1.0 }.jacobian_dependence(),
            [dep(true, true, true), dep(true, true, true)],
        ),
        (
            ChainDrag { c: 1.0 }.jacobian_dependence(),
            [dep(true, true, false), dep(true, false, false)],
        ),
        (
            Damping { c: 1.0 }.jacobian_dependence(),
            [Dependence::NONE, Dependence::NONE],
        ),
        (
            VanDerPol { mu: 1.0 }.jacobian_dependence(),
            [dep(true, true, false), dep(true, false, false)],
        ),
    ];
    for (k, (got, [x, v])) in claims.into_iter().enumerate() {
        assert_eq!(got, ForceDependence { x, v }, "force {k}");
    }
}

#[test]
fn forces_list_their_constants_and_derivatives() {
    let drive = Drive { a: 0.8, omega: 2.1 };
    assert_eq!(drive.constants(), vec![("a", 0.8), ("omega", 2.1)]);
    assert!(
        Damping::DERIVATIVES.contains("∂f[1]/∂x[0] = -0.5"),
        "{}",
        Damping::DERIVATIVES
    );
    assert!(
        VanDerPol::DERIVATIVES.starts_with("f = "),
        "{}",
        VanDerPol::DERIVATIVES
    );
    assert!(
        !Twist::DERIVATIVES.contains("∂f[2]/∂v[0]"),
        "{}",
        Twist::DERIVATIVES
    );
    // The fn stays callable and agrees with the struct.
    let (x, v) = ([0.3, -0.2], [0.5, 0.1]);
    let f = drive.force(&Vector::<2>::from(x), &Vector::<2>::from(v), 0.7);
    assert_eq!(
        f,
        Vector::<2>::from(super::forces::drive(x, v, 0.7, 0.8, 2.1))
    );
}
