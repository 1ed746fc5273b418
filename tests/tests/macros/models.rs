//! Models through `#[lagrangian]` against hand-written derivatives (`1e-13`), and core's step
//! kernels on the generated derivatives against the same kernels on the hand-written ones.
//!
//! Each hand-written impl below implements `value`, `gradient`, `hessian` and
//! `hessian_dependence` (decided by hand from the second-derivative blocks); the generated
//! impls also fuse gradient and Hessian into one `gradient_and_hessian` and decide the
//! dependence symbolically, which must give the same answer.

use varembed::__private::step::{Step, StepKind, StepTimes, Update, is_affine, residual};
use varembed::{Dependence, Hessian, HessianDependence, Lagrangian, Matrix, Vector, lagrangian};
use varembed_tests::models::generated::{DoublePendulum, Pendulum};
use varembed_tests::models::hand::{DeclaredDoublePendulum, DeclaredPendulum, SEPARABLE};
use varembed_tests::rng::Rng;

const KINDS: [StepKind; 8] = StepKind::ALL;

/// A block that depends on `t` only.
const ON_T: Dependence = Dependence {
    x: false,
    v: false,
    t: true,
};

/// `|a − b| ≤ tol · max(1, |b|)`: relative for large entries, absolute near zero (entries that
/// are exactly zero by hand may come out as round-off from the generated code's factoring).
fn close(what: &str, a: f64, b: f64, tol: f64) {
    assert!(
        (a - b).abs() <= tol * b.abs().max(1.0),
        "{what}: generated {a:e}, hand-written {b:e}"
    );
}

fn close_vec<const D: usize>(what: &str, a: &Vector<D>, b: &Vector<D>, tol: f64) {
    for i in 0..D {
        close(&format!("{what}[{i}]"), a[i], b[i], tol);
    }
}

fn close_mat<const D: usize>(what: &str, a: &Matrix<D>, b: &Matrix<D>, tol: f64) {
    for i in 0..D {
        for j in 0..D {
            close(&format!("{what}[({i}, {j})]"), a[(i, j)], b[(i, j)], tol);
        }
    }
}

/// Derivatives at 1e-13 on random points.
fn check_derivatives<const D: usize>(
    gen_: &impl Lagrangian<D>,
    hand: &impl Lagrangian<D>,
    center: Vector<D>,
    rng: &mut Rng,
) {
    const TOL: f64 = 1e-13;
    for _ in 0..200 {
        let x = center + rng.vector::<D>(1.5);
        let v = rng.vector::<D>(2.0);
        let t = rng.uniform(-1.0, 3.0);
        close("L", gen_.value(&x, &v, t), hand.value(&x, &v, t), TOL);
        let (gf, gp) = gen_.gradient(&x, &v, t);
        let (hf, hp) = hand.gradient(&x, &v, t);
        close_vec("∂L/∂x", &gf, &hf, TOL);
        close_vec("∂L/∂v", &gp, &hp, TOL);
        let (gh, hh) = (gen_.hessian(&x, &v, t), hand.hessian(&x, &v, t));
        close_mat("xx", &gh.xx, &hh.xx, TOL);
        close_mat("xv", &gh.xv, &hh.xv, TOL);
        close_mat("vv", &gh.vv, &hh.vv, TOL);
        let (ff, fp, fh) = gen_.gradient_and_hessian(&x, &v, t);
        close_vec("fused ∂L/∂x", &ff, &hf, TOL);
        close_vec("fused ∂L/∂v", &fp, &hp, TOL);
        close_mat("fused xx", &fh.xx, &hh.xx, TOL);
        close_mat("fused xv", &fh.xv, &hh.xv, TOL);
        close_mat("fused vv", &fh.vv, &hh.vv, TOL);
        let (vl, vf, vp) = gen_.value_and_gradient(&x, &v, t);
        close("fused L", vl, hand.value(&x, &v, t), TOL);
        close_vec("fused L, ∂L/∂x", &vf, &hf, TOL);
        close_vec("fused L, ∂L/∂v", &vp, &hp, TOL);
    }
    assert_eq!(
        gen_.hessian_dependence(),
        hand.hessian_dependence(),
        "dependence of the Hessian blocks"
    );
}

/// Core's kernels on the generated derivatives against the same kernels on the hand impl, for
/// every kind. The kernels combine derivatives (`p − h f − π`, `L_vx + L_vv/h − h L_xx −
/// L_xv`), so the tolerance is relative to the size of the terms, at 1e-12.
fn check_kernels<const D: usize>(
    gen_: &impl Lagrangian<D>,
    hand: &impl Lagrangian<D>,
    center: Vector<D>,
    rng: &mut Rng,
) {
    const TOL: f64 = 1e-12;
    let mut explicit_seen = 0;
    for _ in 0..200 {
        let h = rng.uniform(0.01, 0.2);
        let t_a = rng.uniform(-1.0, 2.0);
        let times = StepTimes::new(h, t_a, t_a + h, t_a + 2.0 * h);
        let a = center + rng.vector::<D>(1.0);
        let b = a + rng.vector::<D>(2.0 * h);
        let y = b + rng.vector::<D>(2.0 * h);
        for kind in KINDS {
            let gm = Step::new(gen_, kind, &a, &b, &times).momentum;
            let step = Step::new(hand, kind, &a, &b, &times);
            let hm = step.momentum;
            let scale = 1.0 + hm.amax();
            close_vec(
                &format!("{kind:?} momentum"),
                &(gm / scale),
                &(hm / scale),
                TOL,
            );

            let (gr, gj) = residual(gen_, &step, &y);
            let (hr, hj) = residual(hand, &step, &y);
            let scale = 1.0 + hm.amax() + hand.gradient(&y, &((y - b) / h), t_a).1.amax();
            close_vec(
                &format!("{kind:?} residual"),
                &(gr / scale),
                &(hr / scale),
                TOL,
            );
            let scale = 1.0 + hj.amax();
            close_mat(
                &format!("{kind:?} jacobian"),
                &(gj / scale),
                &(hj / scale),
                TOL,
            );

            assert_eq!(
                is_affine(kind, &gen_.hessian_dependence()),
                is_affine(kind, &hand.hessian_dependence()),
                "{kind:?}: affinity"
            );
            let ge = Update::plan(gen_, kind, &b, &times).explicit(gen_, &step);
            let he = Update::plan(hand, kind, &b, &times).explicit(hand, &step);
            match (ge, he) {
                (Some(g), Some(e)) => {
                    explicit_seen += 1;
                    close_vec(&format!("{kind:?} explicit"), &g, &e, 1e-10);
                    // The explicit update solves the step equation.
                    let (r, _) = residual(gen_, &step, &g);
                    assert!(
                        r.amax() <= 1e-9 * (1.0 + hm.amax()),
                        "{kind:?}: residual {r}"
                    );
                }
                (None, None) => {}
                other => panic!("{kind:?}: explicit update differs: {other:?}"),
            }
        }
    }
    let affine = KINDS
        .iter()
        .filter(|&&k| is_affine(k, &hand.hessian_dependence()))
        .count();
    assert_eq!(explicit_seen, 200 * affine);
}

// ---------------------------------------------------------------- pendulum (d = 1)

#[test]
fn pendulum_matches_hand_written() {
    let mut rng = Rng(1);
    let (gen_, hand) = (
        Pendulum { g: 9.81, l: 1.3 },
        DeclaredPendulum { g: 9.81, l: 1.3 },
    );
    check_derivatives(&gen_, &hand, Vector::<1>::zeros(), &mut rng);
    check_kernels(&gen_, &hand, Vector::<1>::zeros(), &mut rng);
}

// ---------------------------------------------------------------- Kepler (d = 2)

#[lagrangian]
fn kepler(x: [f64; 2], v: [f64; 2], mu: f64) -> f64 {
    let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
    0.5 * (v[0] * v[0] + v[1] * v[1]) + mu / r
}

struct KeplerHand {
    mu: f64,
}

impl Lagrangian<2> for KeplerHand {
    fn value(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> f64 {
        kepler([x[0], x[1]], [v[0], v[1]], self.mu)
    }
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> (Vector<2>, Vector<2>) {
        let r = x.norm();
        (-x * (self.mu / (r * r * r)), *v)
    }
    fn hessian(&self, x: &Vector<2>, _v: &Vector<2>, _t: f64) -> Hessian<2> {
        let r = x.norm();
        let xx = Matrix::<2>::from_fn(|i, j| {
            let delta = if i == j { 1.0 } else { 0.0 };
            self.mu * (3.0 * x[i] * x[j] / r.powi(5) - delta / r.powi(3))
        });
        Hessian {
            xx,
            xv: Matrix::<2>::zeros(),
            vv: Matrix::<2>::identity(),
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        SEPARABLE
    }
}

#[test]
fn kepler_matches_hand_written() {
    let mut rng = Rng(2);
    let (gen_, hand) = (Kepler { mu: 1.7 }, KeplerHand { mu: 1.7 });
    // Positions around (2.5, −2): away from the singularity at the origin.
    let center = Vector::<2>::new(2.5, -2.0);
    check_derivatives(&gen_, &hand, center, &mut rng);
    check_kernels(&gen_, &hand, center, &mut rng);
}

// ---------------------------------------------------------------- coupled masses (d = 2)

/// Two masses coupled through the kinetic term: a constant, non-diagonal `L_vv = [[2, 1], [1, 2]]`,
/// so the generated explicit update carries `h M⁻¹` folded to numbers.
#[lagrangian]
fn coupled(x: [f64; 2], v: [f64; 2], k: f64) -> f64 {
    v[0] * v[0] + v[0] * v[1] + v[1] * v[1] - 0.5 * k * (x[0] * x[0] + x[1] * x[1])
        + 0.1 * (x[0] * x[1]).sin()
}

struct CoupledHand {
    k: f64,
}

impl Lagrangian<2> for CoupledHand {
    fn value(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> f64 {
        coupled([x[0], x[1]], [v[0], v[1]], self.k)
    }
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> (Vector<2>, Vector<2>) {
        let c = 0.1 * (x[0] * x[1]).cos();
        (
            Vector::<2>::new(-self.k * x[0] + c * x[1], -self.k * x[1] + c * x[0]),
            Vector::<2>::new(2.0 * v[0] + v[1], v[0] + 2.0 * v[1]),
        )
    }
    fn hessian(&self, x: &Vector<2>, _v: &Vector<2>, _t: f64) -> Hessian<2> {
        let (c, s) = ((x[0] * x[1]).cos(), (x[0] * x[1]).sin());
        let off = 0.1 * (c - x[0] * x[1] * s);
        Hessian {
            xx: Matrix::<2>::new(
                -self.k - 0.1 * s * x[1] * x[1],
                off,
                off,
                -self.k - 0.1 * s * x[0] * x[0],
            ),
            xv: Matrix::<2>::zeros(),
            vv: Matrix::<2>::new(2.0, 1.0, 1.0, 2.0),
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        SEPARABLE
    }
}

#[test]
fn constant_mass_matrix_matches_hand_written() {
    let mut rng = Rng(6);
    let (gen_, hand) = (Coupled { k: 1.5 }, CoupledHand { k: 1.5 });
    let center = Vector::<2>::new(0.4, -0.7);
    check_derivatives(&gen_, &hand, center, &mut rng);
    check_kernels(&gen_, &hand, center, &mut rng);
}

// ---------------------------------------------------------------- double pendulum (d = 2)

#[test]
fn double_pendulum_matches_hand_written() {
    let mut rng = Rng(3);
    let gen_ = DoublePendulum {
        m1: 1.2,
        m2: 0.7,
        l1: 1.1,
        l2: 0.8,
        g: 9.81,
    };
    let hand = DeclaredDoublePendulum {
        m1: 1.2,
        m2: 0.7,
        l1: 1.1,
        l2: 0.8,
        g: 9.81,
    };
    check_derivatives(&gen_, &hand, Vector::<2>::zeros(), &mut rng);
    check_kernels(&gen_, &hand, Vector::<2>::zeros(), &mut rng);
}

// ---------------------------------------------------------------- time-dependent (d = 1)

/// Caldirola–Kanai damped oscillator `L = e^{γt} (½ m v² − ½ k x²)`.
#[lagrangian]
fn caldirola_kanai(x: f64, v: f64, t: f64, m: f64, k: f64, gamma: f64) -> f64 {
    (gamma * t).exp() * (0.5 * m * v * v - 0.5 * k * x * x)
}

struct CaldirolaKanaiHand {
    m: f64,
    k: f64,
    gamma: f64,
}

impl Lagrangian<1> for CaldirolaKanaiHand {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
        caldirola_kanai(x[0], v[0], t, self.m, self.k, self.gamma)
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
        let e = (self.gamma * t).exp();
        (
            Vector::<1>::new(-e * self.k * x[0]),
            Vector::<1>::new(e * self.m * v[0]),
        )
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, t: f64) -> Hessian<1> {
        let e = (self.gamma * t).exp();
        Hessian {
            xx: Matrix::<1>::new(-e * self.k),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::new(e * self.m),
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        // L_xx and L_vv depend on t only, L_xv = 0 on nothing: every step is affine.
        HessianDependence {
            xx: ON_T,
            xv: Dependence::NONE,
            vv: ON_T,
        }
    }
}

#[test]
fn time_dependent_matches_hand_written() {
    let mut rng = Rng(4);
    let gen_ = CaldirolaKanai {
        m: 1.5,
        k: 4.0,
        gamma: 0.3,
    };
    let hand = CaldirolaKanaiHand {
        m: 1.5,
        k: 4.0,
        gamma: 0.3,
    };
    check_derivatives(&gen_, &hand, Vector::<1>::zeros(), &mut rng);
    check_kernels(&gen_, &hand, Vector::<1>::zeros(), &mut rng);
}

// ---------------------------------------------------------------- parameterised (d = 1)

/// Anharmonic oscillator with a velocity-dependent coupling:
/// `L = ½ m v² − ½ k x² − ¼ λ x⁴ + c x v`.
#[lagrangian]
fn anharmonic(x: f64, v: f64, m: f64, k: f64, lambda: f64, c: f64) -> f64 {
    0.5 * m * v.powi(2) - 0.5 * k * x.powi(2) - 0.25 * lambda * x.powi(4) + c * x * v
}

struct AnharmonicHand {
    m: f64,
    k: f64,
    lambda: f64,
    c: f64,
}

impl Lagrangian<1> for AnharmonicHand {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        anharmonic(x[0], v[0], self.m, self.k, self.lambda, self.c)
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        let (x, v) = (x[0], v[0]);
        (
            Vector::<1>::new(-self.k * x - self.lambda * x.powi(3) + self.c * v),
            Vector::<1>::new(self.m * v + self.c * x),
        )
    }
    fn hessian(&self, x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::new(-self.k - 3.0 * self.lambda * x[0] * x[0]),
            xv: Matrix::<1>::new(self.c),
            vv: Matrix::<1>::new(self.m),
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        SEPARABLE
    }
}

#[test]
fn parameterised_matches_hand_written() {
    let mut rng = Rng(5);
    for (m, k, lambda, c) in [(1.0, 2.0, 0.5, 0.3), (0.2, -1.0, 3.0, -2.0)] {
        let gen_ = Anharmonic { m, k, lambda, c };
        let hand = AnharmonicHand { m, k, lambda, c };
        check_derivatives(&gen_, &hand, Vector::<1>::zeros(), &mut rng);
        check_kernels(&gen_, &hand, Vector::<1>::zeros(), &mut rng);
    }
}

#[test]
fn derivatives_text_lists_the_formulas() {
    let text = Pendulum::DERIVATIVES;
    // Printed in a normal form for reading: coefficients and powers collected.
    assert!(text.contains("∂L/∂x = -g * l * x.sin()"), "{text}");
    assert!(text.contains("∂L/∂v = l.powi(2) * v"), "{text}");
    assert!(text.lines().any(|l| l.starts_with("∂²L/∂x∂x = ")), "{text}");
    // L_xv = 0 is omitted.
    assert!(!text.contains("∂²L/∂x∂v"), "{text}");
    let text = DoublePendulum::DERIVATIVES;
    assert!(text.contains("∂²L/∂x[0]∂v[1] = "), "{text}");
    assert!(
        !text.contains("∂²L/∂x[1]∂x[0]"),
        "symmetric blocks are listed once: {text}"
    );
}
