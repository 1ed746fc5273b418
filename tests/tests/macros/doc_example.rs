//! The examples of the `#[lagrangian]`, `#[force]` and `#[constraint]` docs, compiled and run
//! (the proc-macro crate cannot run doctests that use `varembed`).

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

/// The example of the `#[force]` docs.
mod force_example {
    use varembed::{Force, Vector, force};

    /// A drag `f = −c |v| v` and a spring toward the origin that turns (not a gradient).
    #[force]
    fn drag(x: [f64; 2], v: [f64; 2], c: f64, w: f64) -> [f64; 2] {
        let speed = v[0].hypot(v[1]);
        [-c * speed * v[0] - w * x[1], -c * speed * v[1] + w * x[0]]
    }

    #[test]
    fn doc_example() {
        let f = Drag { c: 0.5, w: 2.0 };
        let (x, v) = (Vector::<2>::new(1.0, 0.0), Vector::<2>::new(0.0, 2.0));
        assert_eq!(f.force(&x, &v, 0.0)[1], -0.5 * 2.0 * 2.0 + 2.0);
        let j = f.jacobian(&x, &v, 0.0);
        assert_eq!((j.x[(0, 1)], j.x[(1, 0)]), (-2.0, 2.0));
        assert_eq!(drag([1.0, 0.0], [0.0, 2.0], 0.5, 2.0)[1], 0.0);
    }
}

/// The example of the `#[constraint]` docs.
mod constraint_example {
    use nalgebra::SVector;
    use varembed::{Constraint, Vector, constraint};

    /// Two rods: the first point at distance `a` from the origin, the second at `b` from it.
    #[constraint]
    fn rods(x: [f64; 4], a: f64, b: f64) -> [f64; 2] {
        let d = [x[2] - x[0], x[3] - x[1]];
        [
            x[0] * x[0] + x[1] * x[1] - a * a,
            d[0] * d[0] + d[1] * d[1] - b * b,
        ]
    }

    #[test]
    fn doc_example() {
        let g = Rods { a: 1.0, b: 2.0 };
        let x = Vector::<4>::new(1.0, 0.0, 1.0, 2.0);
        assert_eq!(g.value(&x), SVector::<f64, 2>::zeros());
        assert_eq!(g.jacobian(&x)[(1, 3)], 4.0);
        let h = g.weighted_hessian(&x, &SVector::<f64, 2>::new(1.0, 0.5));
        assert_eq!((h[(0, 0)], h[(0, 2)], h[(2, 2)]), (3.0, -1.0, 1.0));
        assert_eq!(rods([1.0, 0.0, 1.0, 2.0], 1.0, 2.0), [0.0, 0.0]);
    }
}

/// The loop example of the `#[force]` docs: dashpots between neighbours on slices.
mod looped_force_example {
    use varembed::{DynForce, SparseForceJacobian, force};

    #[force]
    fn dashpots(_x: &[f64], v: &[f64], n: usize, c: f64) -> Vec<f64> {
        let mut f = vec![0.0; n];
        for i in 0..n - 1 {
            let pull = c * (v[i + 1] - v[i]);
            f[i] += pull;
            f[i + 1] -= pull;
        }
        f
    }

    #[test]
    fn doc_example() {
        let force = Dashpots { n: 3, c: 2.0 };
        let mut f = vec![0.0; 3];
        force.add_force(&[0.0; 3], &[1.0, 0.0, 0.5], 0.0, &mut f);
        // The links pull (−2, +1): the ends take one each, the middle both.
        assert_eq!(f, [-2.0, 2.0 + 1.0, -1.0]);
        assert_eq!(dashpots(&[0.0; 3], &[1.0, 0.0, 0.5], 3, 2.0), f);
        let mut j = SparseForceJacobian::new(3);
        force.jacobian(&[0.0; 3], &[0.0; 3], 0.0, &mut j);
        assert_eq!(
            (j.v.get(1, 1), j.v.get(1, 0), j.v.get(0, 2)),
            (-4.0, 2.0, 0.0)
        );
        assert_eq!(force.bandwidth(), Some(1));
        assert_eq!(force.invalid_dimension(3), None);
        assert!(force.invalid_dimension(4).is_some());
    }
}
