use super::*;
use crate::lagrangian::{Dependence, HessianDependence};
use crate::linalg::solve_small;
use crate::test_models::{FORCED_MIXED, Mixed};

const TIMES: StepTimes = StepTimes::new(0.1, 0.3, 0.4, 0.5);

fn step<const D: usize, L: Lagrangian<D>>(
    lagrangian: &L,
    kind: StepKind,
    a: Vector<D>,
    b: Vector<D>,
) -> Step<D> {
    Step::new(lagrangian, kind, &a, &b, &TIMES)
}

/// The table of the module docs, written out once more: `(π, G(y))` for `kind`.
fn by_the_table<const D: usize, L: Lagrangian<D>>(
    lagrangian: &L,
    kind: StepKind,
    [a, b, y]: [Vector<D>; 3],
) -> (Vector<D>, Vector<D>) {
    let StepTimes {
        h, t_a, t_b, t_y, ..
    } = TIMES;
    let (v_ab, v_by) = ((b - a) / h, (y - b) / h);
    let right_ab = lagrangian.gradient(&b, &v_ab, t_b);
    let left_ab = lagrangian.gradient(&a, &v_ab, t_a);
    let right_by = lagrangian.gradient(&y, &v_by, t_y);
    let left_by = lagrangian.gradient(&b, &v_by, t_b);
    match kind {
        StepKind::VariationalBackward => (right_ab.1 + right_ab.0 * h, right_by.1),
        StepKind::VariationalForward => (left_ab.1, left_by.1 - left_by.0 * h),
        StepKind::DirectBackward => (right_ab.1, right_by.1 - right_by.0 * h),
        StepKind::DirectForward => (left_ab.1 + left_ab.0 * h, left_by.1),
        // Midpoint: everything at the interval's midpoint and mid-time.
        StepKind::MidpointVariational | StepKind::MidpointDirect => {
            let mid_ab = lagrangian.gradient(&((a + b) / 2.0), &v_ab, (t_a + t_b) / 2.0);
            let mid_by = lagrangian.gradient(&((b + y) / 2.0), &v_by, (t_b + t_y) / 2.0);
            if kind == StepKind::MidpointVariational {
                (
                    mid_ab.1 + mid_ab.0 * (h / 2.0),
                    mid_by.1 - mid_by.0 * (h / 2.0),
                )
            } else {
                let node = lagrangian.gradient(&b, &((y - a) / (2.0 * h)), t_b);
                (mid_ab.1, mid_by.1 - node.0 * h)
            }
        }
        // Trapezoidal: the momentum averaged over both ends of the interval.
        StepKind::TrapezoidalVariational => (
            (left_ab.1 + right_ab.1) / 2.0 + right_ab.0 * (h / 2.0),
            (left_by.1 + right_by.1) / 2.0 - left_by.0 * (h / 2.0),
        ),
        StepKind::TrapezoidalDirect => {
            let node = lagrangian.gradient(&b, &((y - a) / (2.0 * h)), t_b);
            (
                (left_ab.1 + right_ab.1) / 2.0,
                (left_by.1 + right_by.1) / 2.0 - node.0 * h,
            )
        }
    }
}

#[test]
fn momentum_and_residual_follow_the_table() {
    let (a, b, y) = (
        Vector::<2>::new(0.3, -0.2),
        Vector::<2>::new(0.35, -0.12),
        Vector::<2>::new(0.41, -0.05),
    );
    for kind in StepKind::ALL {
        let (pi, g) = by_the_table(&Mixed, kind, [a, b, y]);
        let step = step(&Mixed, kind, a, b);
        assert!((step.momentum - pi).amax() <= 1e-13, "{kind:?} momentum");
        let (r, _) = residual(&Mixed, &step, &y);
        assert!((r - (g - pi)).amax() <= 1e-13, "{kind:?} residual");
    }
}

/// The Jacobian of every kind against central differences of its residual, on a Lagrangian
/// whose blocks all depend on `x`, `v` and `t` (`L_xv ≠ L_xvᵀ`, so a transposed block shows),
/// alone and under a force whose blocks are not symmetric either.
#[test]
fn jacobians_match_finite_differences() {
    jacobians_match(&Mixed);
    jacobians_match(&FORCED_MIXED);
}

fn jacobians_match<L: Lagrangian<2>>(lagrangian: &L) {
    let (a, b, y) = (
        Vector::<2>::new(0.3, -0.2),
        Vector::<2>::new(0.35, -0.12),
        Vector::<2>::new(0.41, -0.05),
    );
    for kind in StepKind::ALL {
        let step = step(lagrangian, kind, a, b);
        let (_, j) = residual(lagrangian, &step, &y);
        let delta = 1e-6;
        for c in 0..2 {
            let mut plus = y;
            let mut minus = y;
            plus[c] += delta;
            minus[c] -= delta;
            let column = (residual(lagrangian, &step, &plus).0
                - residual(lagrangian, &step, &minus).0)
                / (2.0 * delta);
            let gap = (j.column(c) - column).amax();
            assert!(
                gap <= 1e-7 * (1.0 + j.amax()),
                "{kind:?} column {c}: {gap:e}"
            );
        }
    }
}

/// `L = ½ vᵀ M v + vᵀ C x − U(x)` with constant `M`, `C`: every step is affine, with a
/// constant Jacobian. `M` is `diag(2, 1)` or coupled, `C` zero or not, `U` quartic.
struct Quadratic {
    m: Matrix<2>,
    c: Matrix<2>,
}

impl Lagrangian<2> for Quadratic {
    fn value(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> f64 {
        0.5 * v.dot(&(self.m * v)) + v.dot(&(self.c * x)) - 0.25 * x.map(|c| c.powi(4)).sum()
    }
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> (Vector<2>, Vector<2>) {
        (
            self.c.transpose() * v - x.map(|c| c.powi(3)),
            self.m * v + self.c * x,
        )
    }
    fn hessian(&self, x: &Vector<2>, _v: &Vector<2>, _t: f64) -> Hessian<2> {
        Hessian {
            xx: Matrix::<2>::from_diagonal(&x.map(|c| -3.0 * c * c)),
            xv: self.c.transpose(),
            vv: self.m,
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        HessianDependence {
            xx: Dependence {
                x: true,
                ..Dependence::NONE
            },
            xv: Dependence::NONE,
            vv: Dependence::NONE,
        }
    }
}

/// `L = ½ m(x) v² + g(x) v − U(x)` in `d = 1`, `m = 2 + sin x`, `g = x²`: `L_vv = m(x)` and
/// `L_xv = g'(x)` depend on `x` only, `L_xx` on `x` and `v`. Affine exactly where the
/// Jacobian reads them at the fixed node `b`: the forward kinds, with a Jacobian that changes
/// from step to step.
struct MassOfX;

impl Lagrangian<1> for MassOfX {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        let (x, v) = (x[0], v[0]);
        0.5 * (2.0 + x.sin()) * v * v + x * x * v - x.cosh()
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        let (x, v) = (x[0], v[0]);
        (
            Vector::<1>::new(0.5 * x.cos() * v * v + 2.0 * x * v - x.sinh()),
            Vector::<1>::new((2.0 + x.sin()) * v + x * x),
        )
    }
    fn hessian(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> Hessian<1> {
        let (x, v) = (x[0], v[0]);
        Hessian {
            xx: Matrix::<1>::new(-0.5 * x.sin() * v * v + 2.0 * v - x.cosh()),
            xv: Matrix::<1>::new(x.cos() * v + 2.0 * x),
            vv: Matrix::<1>::new(2.0 + x.sin()),
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        let on_x = Dependence {
            x: true,
            ..Dependence::NONE
        };
        HessianDependence {
            xx: Dependence {
                x: true,
                v: true,
                t: false,
            },
            xv: Dependence {
                x: true,
                v: true,
                t: false,
            },
            vv: on_x,
        }
    }
}

/// `L = ½ m(x) v² − U(x)`, `m = 1 + sin x`: `L_xv = m'(x) v` depends on `v`, so its variational
/// forward step is *not* affine (`G = m(b) v − ½ h m'(b) v²`); only the direct forward one is.
/// `m` vanishes at `x = −π/2`.
struct HalfMassOfXVSquared;

impl Lagrangian<1> for HalfMassOfXVSquared {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        0.5 * (1.0 + x[0].sin()) * v[0] * v[0] - x[0].cosh()
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        let (x, v) = (x[0], v[0]);
        (
            Vector::<1>::new(0.5 * x.cos() * v * v - x.sinh()),
            Vector::<1>::new((1.0 + x.sin()) * v),
        )
    }
    fn hessian(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> Hessian<1> {
        let (x, v) = (x[0], v[0]);
        Hessian {
            xx: Matrix::<1>::new(-0.5 * x.sin() * v * v - x.cosh()),
            xv: Matrix::<1>::new(x.cos() * v),
            vv: Matrix::<1>::new(1.0 + x.sin()),
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        let on_x_and_v = Dependence {
            x: true,
            v: true,
            t: false,
        };
        HessianDependence {
            xx: on_x_and_v,
            xv: on_x_and_v,
            vv: Dependence {
                x: true,
                ..Dependence::NONE
            },
        }
    }
}

fn affine_kinds(dependence: &HessianDependence) -> Vec<StepKind> {
    StepKind::ALL
        .into_iter()
        .filter(|&k| is_affine(k, dependence))
        .collect()
}

#[test]
fn affinity_follows_the_dependence_of_the_blocks() {
    use StepKind::*;
    let none = Dependence::NONE;
    let on = |x, v, t| Dependence { x, v, t };
    // Nothing known: every step runs Newton.
    assert!(affine_kinds(&HessianDependence::ALL).is_empty());
    // The symmetric kinds always run Newton.
    let constant = HessianDependence {
        xx: none,
        xv: none,
        vv: none,
    };
    assert_eq!(affine_kinds(&constant), StepKind::FINITE_DIFFERENCE);
    // ½ vᵀMv − U(x): L_xx(x) is read at y only by the direct backward step.
    let separable = HessianDependence {
        xx: on(true, false, false),
        xv: none,
        vv: none,
    };
    assert_eq!(
        affine_kinds(&separable),
        [VariationalBackward, VariationalForward, DirectForward]
    );
    // Blocks that depend on t only (e^{γt}(½ m v² − ½ k x²)): every step.
    let on_t = on(false, false, true);
    let damped = HessianDependence {
        xx: on_t,
        xv: none,
        vv: on_t,
    };
    assert_eq!(affine_kinds(&damped), StepKind::FINITE_DIFFERENCE);
    // ½ m(x) v² − U(x): L_xv = m'(x) v depends on v, which rules out the variational forward
    // step; L_vv read at b makes the direct forward one affine.
    let mass_of_x = HalfMassOfXVSquared.hessian_dependence();
    assert_eq!(affine_kinds(&mass_of_x), [DirectForward]);
    // ½ m(x) v² + g(x) v − U(x) with m constant: L_xv = g'(x), L_vv constant. The forward
    // variational step reads them at b (affine), the backward one at y (not).
    let magnetic = HessianDependence {
        xx: on(true, true, false),
        xv: on(true, false, false),
        vv: none,
    };
    assert_eq!(affine_kinds(&magnetic), [VariationalForward, DirectForward]);
    // L_vv depending on v (relativistic): nothing is affine.
    let relativistic = HessianDependence {
        xx: none,
        xv: none,
        vv: on(false, true, false),
    };
    assert!(affine_kinds(&relativistic).is_empty());
    assert_eq!(affine_kinds(&MassOfX.hessian_dependence()), [DirectForward]);
}

#[test]
fn the_plan_inverts_a_constant_jacobian_once() {
    let a = Vector::<2>::new(0.3, -0.2);
    let diagonal = Quadratic {
        m: Matrix::<2>::new(2.0, 0.0, 0.0, 1.0),
        c: Matrix::<2>::zeros(),
    };
    let coupled = Quadratic {
        m: Matrix::<2>::new(2.0, 1.0, 1.0, 3.0),
        c: Matrix::<2>::new(0.0, 0.5, -0.5, 0.0),
    };
    let h = TIMES.h;
    for kind in [StepKind::VariationalBackward, StepKind::VariationalForward] {
        // J⁻¹ = h M⁻¹ = diag(h/2, h) for the diagonal mass.
        assert_eq!(
            Update::plan(&diagonal, kind, &a, &TIMES),
            Update::ConstantDiagonalInverse(Vector::<2>::new(0.5 * h, h)),
            "{kind:?}"
        );
        assert!(
            matches!(
                Update::plan(&coupled, kind, &a, &TIMES),
                Update::ConstantInverse(_)
            ),
            "{kind:?}"
        );
    }
    // L_xx(y) enters the direct backward step: Newton.
    assert_eq!(
        Update::plan(&coupled, StepKind::DirectBackward, &a, &TIMES),
        Update::Newton
    );
    assert_eq!(
        Update::plan(
            &MassOfX,
            StepKind::DirectForward,
            &Vector::<1>::new(0.3),
            &TIMES
        ),
        Update::SolvePerStep
    );
    // A constant singular Jacobian gets no closed form: Newton reports it with its step.
    let singular = Quadratic {
        m: Matrix::<2>::new(1.0, 0.0, 0.0, 0.0),
        c: Matrix::<2>::zeros(),
    };
    assert_eq!(
        Update::plan(&singular, StepKind::DirectForward, &a, &TIMES),
        Update::Newton
    );
    // The default dependence claims nothing.
    assert_eq!(
        Update::plan(&Mixed, StepKind::DirectForward, &a, &TIMES),
        Update::Newton
    );
}

/// For an affine step, one Newton iteration from `y = b` is exact: the closed form must give
/// that node, and it must solve the step equation.
fn closed_form_is_one_newton_step<const D: usize, L: Lagrangian<D>>(
    lagrangian: &L,
    kind: StepKind,
    a: Vector<D>,
    b: Vector<D>,
) {
    let step = step(lagrangian, kind, a, b);
    let update = Update::plan(lagrangian, kind, &b, &TIMES);
    assert_ne!(update, Update::Newton, "{kind:?}");
    let y = update.explicit(lagrangian, &step).expect("a closed form");
    let (r, j) = residual(lagrangian, &step, &b);
    let newton = b - solve_small(&j, &r).expect("an invertible Jacobian");
    let scale = 1.0 + b.amax();
    assert!(
        (y - newton).amax() <= 1e-13 * scale,
        "{kind:?} ({update:?}): closed form {y}, Newton {newton}"
    );
    let (r, j) = residual(lagrangian, &step, &y);
    assert!(
        r.amax() <= 1e-13 * (1.0 + step.momentum.amax() + j.amax() * scale),
        "{kind:?}: residual {r}"
    );
    // Not a trivial step: the node moved.
    assert!((y - b).amax() > 1e-3, "{kind:?}");
}

#[test]
fn closed_forms_equal_one_newton_step() {
    let (a, b) = (Vector::<2>::new(0.3, -0.2), Vector::<2>::new(0.35, -0.12));
    let diagonal = Quadratic {
        m: Matrix::<2>::new(2.0, 0.0, 0.0, 1.0),
        c: Matrix::<2>::zeros(),
    };
    let coupled = Quadratic {
        m: Matrix::<2>::new(2.0, 1.0, 1.0, 3.0),
        c: Matrix::<2>::new(0.0, 0.5, -0.5, 0.0),
    };
    for kind in [
        StepKind::VariationalBackward,
        StepKind::VariationalForward,
        StepKind::DirectForward,
    ] {
        closed_form_is_one_newton_step(&diagonal, kind, a, b);
        closed_form_is_one_newton_step(&coupled, kind, a, b);
    }
    let (a, b) = (Vector::<1>::new(0.3), Vector::<1>::new(0.36));
    closed_form_is_one_newton_step(&MassOfX, StepKind::DirectForward, a, b);
    closed_form_is_one_newton_step(&HalfMassOfXVSquared, StepKind::DirectForward, a, b);
}

#[test]
fn a_singular_jacobian_per_step_declines_the_closed_form() {
    // m(x) = 1 + sin x vanishes at x = −π/2: the direct forward Jacobian L_vv(b)/h is singular
    // there, and the caller's Newton reports it.
    let b = Vector::<1>::new(-std::f64::consts::FRAC_PI_2);
    let step = step(
        &HalfMassOfXVSquared,
        StepKind::DirectForward,
        b.add_scalar(-0.01),
        b,
    );
    let update = Update::plan(&HalfMassOfXVSquared, StepKind::DirectForward, &b, &TIMES);
    assert_eq!(update, Update::SolvePerStep);
    // 1 + sin(−π/2) rounds to exactly 0, so the solve declines.
    assert_eq!(1.0 + b[0].sin(), 0.0);
    assert_eq!(update.explicit(&HalfMassOfXVSquared, &step), None);
}

/// The affinity and constancy read off the table of terms are the step module's third table
/// as written out by hand, for every kind and every dependence of the three blocks (each on
/// any of `x`, `v`, `t`): 512 dependences.
#[test]
fn affinity_read_off_the_terms_is_the_written_table() {
    let written = |kind: StepKind, dependence: &HessianDependence| -> (bool, bool) {
        let HessianDependence { xx, xv, vv } = *dependence;
        let on_x_or_v = |d: Dependence| d.x || d.v;
        let none = Dependence::NONE;
        match kind {
            StepKind::VariationalBackward => {
                (!on_x_or_v(xv) && !on_x_or_v(vv), xv == none && vv == none)
            }
            StepKind::VariationalForward => (!xv.v && !vv.v, xv == none && vv == none),
            StepKind::DirectBackward => (
                !on_x_or_v(xx) && !on_x_or_v(xv) && !on_x_or_v(vv),
                xx == none && xv == none && vv == none,
            ),
            StepKind::DirectForward => (!vv.v, vv == none),
            _ => (false, false),
        }
    };
    let dependence = |bits: usize| Dependence {
        x: bits & 1 != 0,
        v: bits & 2 != 0,
        t: bits & 4 != 0,
    };
    for bits in 0..512 {
        let d = HessianDependence {
            xx: dependence(bits),
            xv: dependence(bits >> 3),
            vv: dependence(bits >> 6),
        };
        for kind in StepKind::ALL {
            let read = (is_affine(kind, &d), jacobian_is_constant(kind, &d));
            assert_eq!(read, written(kind, &d), "{kind:?} {d:?}");
        }
    }
}
