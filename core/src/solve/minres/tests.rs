use super::*;

/// `tridiag(−1, 2, −1) − shift` of order `n`, with the SPD preconditioner
/// `tridiag(−1, 2, −1)⁻¹` applied by the Thomas algorithm (or none).
struct Shifted {
    n: usize,
    shift: f64,
    precondition: bool,
}

impl KrylovSystem for Shifted {
    fn len(&self) -> usize {
        self.n
    }
    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        for i in 0..self.n {
            let left = if i > 0 { x[i - 1] } else { 0.0 };
            let right = if i + 1 < self.n { x[i + 1] } else { 0.0 };
            y[i] = (2.0 - self.shift) * x[i] - left - right;
        }
    }
    fn precondition(&mut self, r: &[f64], z: &mut [f64]) {
        if !self.precondition {
            z.copy_from_slice(r);
            return;
        }
        // Thomas algorithm for tridiag(−1, 2, −1).
        let n = self.n;
        let mut c = vec![0.0; n];
        let mut d = vec![0.0; n];
        for i in 0..n {
            let pivot = 2.0 + if i > 0 { c[i - 1] } else { 0.0 };
            c[i] = -1.0 / pivot;
            d[i] = (r[i] + if i > 0 { d[i - 1] } else { 0.0 }) / pivot;
        }
        z[n - 1] = d[n - 1];
        for i in (0..n - 1).rev() {
            z[i] = d[i] - c[i] * z[i + 1];
        }
    }
}

fn true_residual(system: &mut Shifted, b: &[f64], x: &[f64]) -> f64 {
    let mut y = vec![0.0; b.len()];
    system.apply(x, &mut y);
    let r: f64 = b.iter().zip(&y).map(|(b, y)| (b - y) * (b - y)).sum();
    (r / dot(b, b)).sqrt()
}

const OPTIONS: KrylovOptions = KrylovOptions {
    tolerance: 1e-10,
    max_iterations: 500,
    restart: 0,
};

/// The Laplacian shifted past its ten lowest eigenvalues: indefinite, ten negative
/// eigenvalues. MINRES reaches the tolerance on the true residual, with and without the
/// (SPD) preconditioner.
/// Between solves, the work lends and takes back the vectors a solve uses; after a solve
/// without images, a vector given back never lands in the unused image's place (where it
/// would be held to the end, unused): of eight given, five are kept.
#[test]
fn work_keeps_no_vector_in_an_unused_place() {
    let mut system = Shifted {
        n: 40,
        shift: 0.5,
        precondition: true,
    };
    let b: Vec<f64> = (0..40).map(|i| (i as f64).sin()).collect();
    let mut x = vec![0.0; 40];
    let mut work = MinresWork::default();
    minres_in(
        &mut system,
        &mut b.clone(),
        &mut x,
        &OPTIONS,
        None,
        &mut work,
    )
    .unwrap();
    let kept = |work: &mut MinresWork| work.vectors().filter(|v| v.capacity() > 0).count();
    assert_eq!(kept(&mut work), 5);
    let lent: Vec<Vec<f64>> = (0..3).map(|_| work.lend()).collect();
    assert!(lent.iter().all(|v| v.capacity() >= 40));
    assert_eq!(kept(&mut work), 2);
    for vector in lent.into_iter().chain((0..5).map(|_| vec![0.0; 40])) {
        work.give(vector);
    }
    assert_eq!(kept(&mut work), 5);
    assert_eq!(work.z_image.capacity(), 0);
    // Keeping at most three frees the smallest.
    let small = std::mem::take(&mut work.w);
    work.give(Vec::with_capacity(1));
    drop(small);
    work.keep_at_most(3);
    assert_eq!(kept(&mut work), 3);
    assert!(
        work.vectors()
            .all(|v| v.capacity() == 0 || v.capacity() >= 40)
    );
}

/// The Laplacian with a diagonal preconditioner whose last entry is negative: MINRES
/// breaks down, at the start for `M = −I` and after a few iterations for the other, and
/// hands the right-hand side back in its residual's storage (exactly at the start, after it
/// to the recurrence's gap to the true residual, here within 1e-13) for the solver that takes
/// over.
#[test]
fn a_breakdown_gives_the_right_hand_side_back() {
    /// `M = diag(1, …, 1, last)`, or `−I` for `None`.
    struct Indefinite {
        laplacian: Shifted,
        last: Option<f64>,
    }
    impl KrylovSystem for Indefinite {
        fn len(&self) -> usize {
            self.laplacian.n
        }
        fn apply(&mut self, x: &[f64], y: &mut [f64]) {
            self.laplacian.apply(x, y);
        }
        fn precondition(&mut self, r: &[f64], z: &mut [f64]) {
            z.copy_from_slice(r);
            match self.last {
                Some(last) => z[r.len() - 1] *= last,
                None => z.iter_mut().for_each(|z| *z = -*z),
            }
        }
    }
    let n = 12;
    let b: Vec<f64> = (0..n).map(|i| 1.0 / (1.0 + i as f64).powi(3)).collect();
    for (last, at_start) in [(None, true), (Some(-50.0), false)] {
        let laplacian = Shifted {
            n,
            shift: 0.0,
            precondition: false,
        };
        let mut system = Indefinite { laplacian, last };
        let (mut r, mut x) = (b.clone(), vec![0.0; n]);
        let mut work = MinresWork::default();
        let result = minres_in(&mut system, &mut r, &mut x, &OPTIONS, None, &mut work);
        let Err(KrylovFailure::Breakdown { iterations, .. }) = result else {
            panic!("{last:?}: {result:?}");
        };
        assert_eq!(iterations == 0, at_start, "{last:?}: {iterations}");
        let error = r
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (r, b)| m.max((r - b).abs()));
        if at_start {
            assert_eq!(r, b);
        } else {
            assert!(x.iter().any(|x| *x != 0.0) && error < 1e-13, "{error:e}");
        }
    }
}

#[test]
fn minres_solves_an_indefinite_system() {
    let n = 200;
    let shift = 2.0 - 2.0 * (10.5 * std::f64::consts::PI / (n + 1) as f64).cos();
    let b: Vec<f64> = (0..n).map(|i| ((i * 7) as f64).sin() + 0.2).collect();
    for precondition in [true, false] {
        let mut system = Shifted {
            n,
            shift,
            precondition,
        };
        let mut x = vec![0.0; n];
        let stats = minres(&mut system, &b, &mut x, &OPTIONS, None).unwrap();
        let r = true_residual(&mut system, &b, &x);
        assert!(r <= 2e-10, "{precondition}: {stats:?}, true residual {r:e}");
    }
}

/// With the unshifted Laplacian as preconditioner, `M A = I − shift·L⁻¹`, whose eigenvalues
/// are `1 − shift/λ_j` with `λ_j = 2 − 2cos(jπ/(n+1))`: the Ritz values of the recorded
/// tridiagonal matrix approach them, and each Ritz bound holds.
#[test]
fn ritz_values_bound_the_eigenvalues_of_the_preconditioned_operator() {
    let n = 100;
    let lambda = |j: usize| 2.0 - 2.0 * (j as f64 * std::f64::consts::PI / (n + 1) as f64).cos();
    let shift = 0.5 * (lambda(1) + lambda(2));
    let exact: Vec<f64> = (1..=n).map(|j| 1.0 - shift / lambda(j)).collect();
    let mut system = Shifted {
        n,
        shift,
        precondition: true,
    };
    let b: Vec<f64> = (0..n).map(|i| 1.0 + i as f64 / n as f64).collect();
    let mut x = vec![0.0; n];
    let mut t = Tridiagonal::default();
    let options = KrylovOptions {
        max_iterations: 8,
        tolerance: 0.0,
        ..OPTIONS
    };
    let _ = minres(&mut system, &b, &mut x, &options, Some(&mut t));
    assert_eq!(t.diagonal.len(), 8);
    let ritz = ritz_values(&t);
    for &(theta, bound) in &ritz {
        let nearest = exact
            .iter()
            .map(|e| (e - theta).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest <= bound * (1.0 + 1e-8) + 1e-12,
            "{theta}: {nearest:e} > {bound:e}"
        );
    }
    // The lowest eigenvalue, 1 − shift/λ₁ < 0, is found to many digits.
    let (lowest, bound) = ritz[0];
    assert!(
        (lowest - exact[0]).abs() <= 1e-8 && bound <= 1e-6,
        "{lowest} {bound:e}"
    );
}
