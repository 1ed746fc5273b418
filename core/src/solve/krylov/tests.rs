use super::*;

/// A dense symmetric matrix with a Jacobi preconditioner.
struct Dense {
    a: Vec<Vec<f64>>,
    jacobi: bool,
}
impl KrylovSystem for Dense {
    fn len(&self) -> usize {
        self.a.len()
    }
    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        for (yi, row) in y.iter_mut().zip(&self.a) {
            *yi = dot(row, x);
        }
    }
    fn precondition(&mut self, r: &[f64], z: &mut [f64]) {
        for i in 0..r.len() {
            z[i] = if self.jacobi {
                r[i] / self.a[i][i].abs()
            } else {
                r[i]
            };
        }
    }
}

/// `tridiag(−1, 2 + shift, −1)`: SPD for `shift > −2(1 − cos(π/(n+1)))`, indefinite below.
fn shifted_laplacian(n: usize, shift: f64) -> Dense {
    let mut a = vec![vec![0.0; n]; n];
    for i in 0..n {
        a[i][i] = 2.0 + shift;
        if i > 0 {
            a[i][i - 1] = -1.0;
            a[i - 1][i] = -1.0;
        }
    }
    Dense { a, jacobi: true }
}

fn residual(system: &mut Dense, b: &[f64], x: &[f64]) -> f64 {
    let mut y = vec![0.0; b.len()];
    system.apply(x, &mut y);
    norm(&b.iter().zip(&y).map(|(b, y)| b - y).collect::<Vec<_>>()) / norm(b)
}

/// The 1-D Laplacian `tridiag(−1, 2, −1)` preconditioned by its diagonal, written as a
/// user of the trait would: CG and GMRES reach the tolerance and agree.
#[test]
fn cg_and_gmres_solve_the_laplacian() {
    struct Laplacian(usize);
    impl KrylovSystem for Laplacian {
        fn len(&self) -> usize {
            self.0
        }
        fn apply(&mut self, x: &[f64], y: &mut [f64]) {
            for i in 0..self.0 {
                let left = if i > 0 { x[i - 1] } else { 0.0 };
                let right = if i + 1 < self.0 { x[i + 1] } else { 0.0 };
                y[i] = 2.0 * x[i] - left - right;
            }
        }
        fn precondition(&mut self, r: &[f64], z: &mut [f64]) {
            for (z, r) in z.iter_mut().zip(r) {
                *z = 0.5 * r;
            }
        }
    }
    let b = vec![1.0; 20];
    let options = KrylovOptions {
        tolerance: 1e-10,
        max_iterations: 100,
        restart: 30,
    };
    let mut x = vec![0.0; 20];
    let cg = conjugate_gradient(&mut Laplacian(20), &b, &mut x, &options).unwrap();
    assert!(cg.iterations <= 20 && cg.relative_residual <= 1e-10);
    let mut y = vec![0.0; 20];
    gmres(&mut Laplacian(20), &b, &mut y, &options).unwrap();
    assert!(x.iter().zip(&y).all(|(a, b)| (a - b).abs() < 1e-8));
}

const OPTIONS: KrylovOptions = KrylovOptions {
    tolerance: 1e-10,
    max_iterations: 400,
    restart: 20,
};

#[test]
fn cg_solves_spd_and_reports_indefinite_breakdown() {
    let n = 60;
    let b: Vec<f64> = (0..n).map(|i| ((i * 3) as f64).sin() + 0.1).collect();
    let mut x = vec![0.0; n];
    let mut spd = shifted_laplacian(n, 0.01);
    let stats = conjugate_gradient(&mut spd, &b, &mut x, &OPTIONS).unwrap();
    assert!(residual(&mut spd, &b, &x) <= 1e-10, "{stats:?}");
    // Shifted well below the smallest eigenvalue: indefinite, CG must stop and say so.
    let mut indefinite = shifted_laplacian(n, -1.0);
    let failure = conjugate_gradient(&mut indefinite, &b, &mut x, &OPTIONS).unwrap_err();
    assert!(
        matches!(failure, KrylovFailure::Breakdown { .. }),
        "{failure:?}"
    );
}

#[test]
fn gmres_solves_the_indefinite_system_cg_cannot() {
    let n = 60;
    let b: Vec<f64> = (0..n).map(|i| ((i * 3) as f64).cos()).collect();
    let mut system = shifted_laplacian(n, -1.0);
    system.jacobi = false;
    let mut x = vec![0.0; n];
    let options = KrylovOptions {
        max_iterations: 2000,
        restart: 60,
        ..OPTIONS
    };
    let stats = gmres(&mut system, &b, &mut x, &options).unwrap();
    let r = residual(&mut system, &b, &x);
    assert!(r <= 1e-10, "{stats:?}, true residual {r:e}");
}

/// GMRES in a pool of vectors (left with other lengths and contents) gives the iterates of
/// GMRES on fresh ones, bit for bit, through restarts, and gives back every vector it
/// was lent: each solve after the first is served from the pool. It never holds more than its
/// basis of `restart + 1` vectors, the product and the preconditioned vector (a restart gives
/// the last basis back before it lends the next).
#[test]
fn gmres_in_a_pool_gives_the_same_iterates_and_every_vector_back() {
    #[derive(Default)]
    struct Counting {
        held: Vec<Vec<f64>>,
        lent: usize,
        given: usize,
        fresh: usize,
        most_out: usize,
    }
    impl VectorPool for Counting {
        fn lend(&mut self) -> Vec<f64> {
            self.lent += 1;
            self.most_out = self.most_out.max(self.lent - self.given);
            self.held.pop().unwrap_or_else(|| {
                self.fresh += 1;
                Vec::new()
            })
        }
        fn give(&mut self, vector: Vec<f64>) {
            self.given += 1;
            self.held.push(vector);
        }
    }
    let n = 40;
    let b: Vec<f64> = (0..n).map(|i| ((i * 3) as f64).cos()).collect();
    let options = KrylovOptions {
        max_iterations: 400,
        restart: 4,
        tolerance: 1e-10,
    };
    let mut alone = vec![0.0; n];
    gmres(&mut shifted_laplacian(n, 0.05), &b, &mut alone, &options).unwrap();
    let mut pool = Counting {
        held: vec![vec![f64::NAN; 7], vec![3.0; 2 * n]],
        ..Counting::default()
    };
    for solve in 0..2 {
        let mut x = vec![1.0; n];
        gmres_in(
            &mut shifted_laplacian(n, 0.05),
            &b,
            &mut x,
            &options,
            &mut pool,
        )
        .unwrap();
        assert_eq!(x, alone, "solve {solve}");
        assert_eq!(pool.lent, pool.given, "solve {solve}");
    }
    assert_eq!(pool.most_out, options.restart + 3);
    let per_solve = pool.lent / 2;
    assert!(
        pool.fresh < per_solve,
        "{} fresh of {}",
        pool.fresh,
        pool.lent
    );
}

#[test]
fn gmres_reports_an_exhausted_budget_with_the_true_residual() {
    let n = 200;
    let b = vec![1.0; n];
    let mut system = shifted_laplacian(n, -1.0);
    system.jacobi = false;
    let mut x = vec![0.0; n];
    let options = KrylovOptions {
        max_iterations: 5,
        restart: 3,
        ..OPTIONS
    };
    let failure = gmres(&mut system, &b, &mut x, &options).unwrap_err();
    let r = residual(&mut system, &b, &x);
    assert!(failure.relative_residual() > 1e-10);
    assert!((failure.relative_residual() - r).abs() <= 1e-12 * r.max(1.0));
}
