//! `#[constraint]`: the generated `g`, `G` and `Σ_k λ_k ∂²g_k/∂x²` against num-dual (dual
//! numbers for `G`, hyper-dual numbers for each second derivative, on the same formula
//! written as a plain generic fn) and against central differences of the generated `λᵀG`, at
//! 300 generated points and multipliers per constraint.

#![allow(
    dead_code,
    reason = "the #[constraint] fns stay callable, but these tests use the generated structs"
)]
#![allow(
    clippy::needless_range_loop,
    reason = "the loop forms the macro accepts, written as the docs show them"
)]

use nalgebra::SVector;
use num_dual::{Dual64, HyperDual64};
use varembed::{Constraint, Vector, constraint};
use varembed_tests::rng::Rng;

use super::forces::{Errors, POINTS, Real};

/// A planar two-link mechanism: two rod lengths and an angle relation; `let` bindings, a
/// local array, constants, `atan2`.
#[constraint]
fn linkage(x: [f64; 4], a: f64, b: f64) -> [f64; 3] {
    let d = [x[2] - x[0], x[3] - x[1]];
    [
        x[0] * x[0] + x[1] * x[1] - a * a,
        d[0] * d[0] + d[1] * d[1] - b * b,
        x[1].atan2(x[0]) - 0.3 * (x[3] * x[2]).sin(),
    ]
}

fn linkage_dual<T: Real>(x: &[T], c: &Linkage) -> Vec<T> {
    let (d0, d1) = (x[2] - x[0], x[3] - x[1]);
    vec![
        x[0] * x[0] + x[1] * x[1] - c.a * c.a,
        d0 * d0 + d1 * d1 - c.b * c.b,
        x[1].atan2(x[0]) - (x[3] * x[2]).sin() * 0.3,
    ]
}

/// A sphere cut by a plane, the array set in an unrolled loop.
#[constraint]
fn sphere_plane(x: [f64; 3], r: f64) -> [f64; 2] {
    let mut g = [0.0; 2];
    for i in 0..3 {
        g[0] += x[i] * x[i];
        g[1] += (i as f64 + 1.0) * x[i];
    }
    g[0] -= r * r;
    g
}

fn sphere_plane_dual<T: Real>(x: &[T], c: &SpherePlane) -> Vec<T> {
    let sphere = x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - c.r * c.r;
    let plane = x[0] + x[1] * 2.0 + x[2] * 3.0;
    vec![sphere, plane]
}

/// The oracle of a constraint `C` on numbers `T`: `g(x)` with the constraint's constants.
type Oracle<T, C> = fn(&[T], &C) -> Vec<T>;

fn check<const D: usize, const M: usize, C: Constraint<D, M>>(
    name: &str,
    g: &C,
    (first, second): (Oracle<Dual64, C>, Oracle<HyperDual64, C>),
    seed: u64,
) {
    let mut rng = Rng(seed);
    let mut errors = Errors::default();
    let mut record = |what: &str, got: f64, want: f64, tol: f64, central: bool| {
        let err = (got - want).abs() / want.abs().max(1.0);
        assert!(err <= tol, "{name} {what}: {got:e} vs {want:e}");
        let slot = if central {
            &mut errors.central
        } else {
            &mut errors.dual
        };
        *slot = slot.max(err);
    };
    for _ in 0..POINTS {
        let x: Vector<D> = rng.vector(1.0);
        let lambda = SVector::<f64, M>::from_fn(|_, _| rng.uniform(-2.0, 2.0));
        let (value, jac, h) = (g.value(&x), g.jacobian(&x), g.weighted_hessian(&x, &lambda));
        for j in 0..D {
            let z: Vec<Dual64> = (0..D)
                .map(|k| Dual64::new(x[k], f64::from(u8::from(k == j))))
                .collect();
            let out = first(&z, g);
            for k in 0..M {
                record("g", value[k], out[k].re, 1e-12, false);
                record("G", jac[(k, j)], out[k].eps, 1e-12, false);
            }
        }
        for a in 0..D {
            for b in 0..D {
                let z: Vec<HyperDual64> = (0..D)
                    .map(|k| {
                        let (e1, e2) = (u8::from(k == a), u8::from(k == b));
                        HyperDual64::new(x[k], f64::from(e1), f64::from(e2), 0.0)
                    })
                    .collect();
                let out = second(&z, g);
                let want: f64 = (0..M).map(|k| lambda[k] * out[k].eps1eps2).sum();
                record("Σλ∇²g", h[(a, b)], want, 1e-12, false);
            }
        }
        // Central differences of `λᵀG`, the constraint force, in `x`.
        let step = 1e-6;
        for b in 0..D {
            let (mut xp, mut xm) = (x, x);
            xp[b] += step;
            xm[b] -= step;
            let force = |x: &Vector<D>| g.jacobian(x).transpose() * lambda;
            let diff = (force(&xp) - force(&xm)) / (2.0 * step);
            for a in 0..D {
                record("central Σλ∇²g", h[(a, b)], diff[a], 1e-7, true);
            }
        }
        assert_eq!(h, h.transpose(), "{name}: symmetric");
    }
    errors.print(name);
}

#[test]
fn constraints_match_num_dual_and_central_differences() {
    let (linkage, sphere) = (Linkage { a: 1.0, b: 1.5 }, SpherePlane { r: 0.8 });
    check(
        "linkage (M = 3)",
        &linkage,
        (linkage_dual, linkage_dual),
        11,
    );
    let plane = "sphere_plane (M = 2)";
    check(plane, &sphere, (sphere_plane_dual, sphere_plane_dual), 12);
}

#[test]
fn constraints_are_holonomic_and_list_their_derivatives() {
    let linkage = Linkage { a: 1.0, b: 1.5 };
    assert_eq!(linkage.not_holonomic(), None);
    // The plane's second derivatives are zero: only the sphere's enter.
    assert!(
        !SpherePlane::DERIVATIVES.contains("∂²g[1]"),
        "{}",
        SpherePlane::DERIVATIVES
    );
    assert!(SpherePlane::DERIVATIVES.contains("∂g[1]/∂x[2] = 3"));
    let x = [0.3, -0.4, 0.9, 0.2];
    assert_eq!(
        linkage.value(&Vector::<4>::from(x)),
        SVector::<f64, 3>::from(super::constraints::linkage(x, 1.0, 1.5))
    );
}
