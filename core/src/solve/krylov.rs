//! Preconditioned Krylov solvers for `A x = b` given only products: conjugate gradients for
//! symmetric positive definite `A` and restarted GMRES(m) for everything else.
//!
//! Both stop when `‖b − A x‖₂ ≤ tolerance · ‖b‖₂` and start from `x = 0`.
//!
//! - [`conjugate_gradient`]: with an SPD preconditioner `M ≈ A⁻¹`,
//!   `α = (r·z)/(p·Ap)`, `x += α p`, `r −= α Ap`, `z = M r`, `β = (r·z)_new/(r·z)`,
//!   `p = z + β p`. A system whose products need `C p` for some linear `C`, and whose
//!   preconditioner yields `C z` as a by-product, has it carried along the recurrence
//!   (`C p = C z + β C p`, [`KrylovSystem::image_len`]) instead of computed again. It reports
//!   [`KrylovFailure::Breakdown`] as soon as a curvature `p·Ap` or
//!   `r·z` is not positive (an indefinite `A` or `M`), rather than continue on a meaningless
//!   recurrence.
//! - [`gmres`]: right-preconditioned, `A M y = b`, `x = M y`; Arnoldi with modified
//!   Gram–Schmidt and Givens rotations, restarted every `restart` iterations. It needs only a
//!   nonsingular `A`. It too applies `A` to preconditioned vectors only inside a cycle, with
//!   their images and the vector preconditioned
//!   ([`KrylovSystem::apply_preconditioned`]), and takes the first cycle's residual as `b`
//!   (from `x = 0`) without a product.
//!
//! ## Reference
//!
//! Y. Saad, *Iterative Methods for Sparse Linear Systems*, 2nd ed., Algorithms 9.1 (PCG) and
//! 9.5 (right-preconditioned GMRES).

use crate::linalg::zeroed;

/// A linear system known through products: `y = A x` and `z = M r` with `M ≈ A⁻¹`.
pub trait KrylovSystem {
    /// The number of unknowns.
    fn len(&self) -> usize;
    /// Whether there are no unknowns.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// `y = A x`.
    fn apply(&mut self, x: &[f64], y: &mut [f64]);
    /// `z = M r`.
    fn precondition(&mut self, r: &[f64], z: &mut [f64]);

    /// The length of the images `C x` (for a linear map `C` of the system's choosing) that
    /// [`apply_with_image`](Self::apply_with_image) can use instead of computing them; 0 (the
    /// default) when the system has none.
    fn image_len(&self) -> usize {
        0
    }
    /// `z = M r`, and `C z` into `image` when the preconditioner yields it as a by-product.
    fn precondition_with_image(&mut self, r: &[f64], z: &mut [f64], image: &mut [f64]) {
        let _ = image;
        self.precondition(r, z);
    }
    /// `y = A x`, given `image = C x`.
    fn apply_with_image(&mut self, x: &[f64], image: &[f64], y: &mut [f64]) {
        let _ = image;
        self.apply(x, y);
    }
    /// `y ← c · A x + β y` for `x = factor · M r` (the preconditioner's output for `r`,
    /// scaled), given `image = C x` (`y` is only written where `β = 0`). A system whose
    /// preconditioner is the exact inverse of a part `P` of `A` may compute
    /// `A x = factor · r + (A − P) x` and spare the products with `P`. MINRES builds its next
    /// Lanczos vector on `y` this way, with no vector of its own for `A x`; the default applies
    /// `A` into a vector it allocates (systems of many unknowns override it).
    fn apply_preconditioned(
        &mut self,
        x: &[f64],
        image: &[f64],
        (r, factor): (&[f64], f64),
        (c, beta): (f64, f64),
        y: &mut [f64],
    ) {
        let _ = (r, factor);
        let mut ax = vec![0.0; y.len()];
        self.apply_with_image(x, image, &mut ax);
        scale_onto(&ax, (c, beta), y);
    }
}

/// `y ← c a + β y` entry by entry ([`onto`]).
fn scale_onto(a: &[f64], onto_y: (f64, f64), y: &mut [f64]) {
    y.iter_mut()
        .zip(a)
        .for_each(|(y, a)| *y = onto(*y, *a, onto_y));
}

/// `c a + β y`, where `y` is not read for `β = 0` (a NaN there stays out): the rule of every
/// [`KrylovSystem::apply_preconditioned`].
#[inline(always)]
pub(crate) fn onto(y: f64, a: f64, (c, beta): (f64, f64)) -> f64 {
    if beta == 0.0 { c * a } else { c * a + beta * y }
}

/// Stopping rule and sizes of the Krylov solvers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KrylovOptions {
    /// Relative residual `‖b − A x‖₂ / ‖b‖₂` to reach.
    pub tolerance: f64,
    /// Products with `A` before giving up.
    pub max_iterations: usize,
    /// GMRES restart length `m` (memory: `m + 1` vectors).
    pub restart: usize,
}

/// A converged solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KrylovStats {
    /// Products with `A`.
    pub iterations: usize,
    /// `‖b − A x‖₂ / ‖b‖₂` reached.
    pub relative_residual: f64,
}

/// Why a Krylov solve stopped short; `x` then holds the last iterate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum KrylovFailure {
    /// CG met a non-positive curvature `p·Ap ≤ 0` or `r·z ≤ 0` (or a non-finite value).
    Breakdown {
        /// Products with `A` so far.
        iterations: usize,
        /// Relative residual of the last iterate.
        relative_residual: f64,
    },
    /// The iteration budget ran out (or GMRES stagnated).
    MaxIterations {
        /// Products with `A`.
        iterations: usize,
        /// Relative residual of the last iterate.
        relative_residual: f64,
    },
}

impl KrylovFailure {
    /// Products with `A` made.
    pub fn iterations(&self) -> usize {
        match *self {
            KrylovFailure::Breakdown { iterations, .. }
            | KrylovFailure::MaxIterations { iterations, .. } => iterations,
        }
    }
    /// Relative residual of the last iterate.
    pub fn relative_residual(&self) -> f64 {
        match *self {
            KrylovFailure::Breakdown {
                relative_residual, ..
            }
            | KrylovFailure::MaxIterations {
                relative_residual, ..
            } => relative_residual,
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// Preconditioned conjugate gradients for SPD `A` (and SPD `M`); `x` is overwritten.
pub fn conjugate_gradient(
    system: &mut impl KrylovSystem,
    b: &[f64],
    x: &mut [f64],
    options: &KrylovOptions,
) -> Result<KrylovStats, KrylovFailure> {
    let n = system.len();
    x.fill(0.0);
    let b_norm = norm(b);
    if b_norm == 0.0 {
        return Ok(KrylovStats {
            iterations: 0,
            relative_residual: 0.0,
        });
    }
    let mut r = b.to_vec();
    let mut z = vec![0.0; n];
    let mut ap = vec![0.0; n];
    let mut z_image = vec![0.0; system.image_len()];
    system.precondition_with_image(&r, &mut z, &mut z_image);
    let mut p = z.clone();
    let mut p_image = z_image.clone();
    let mut rz = dot(&r, &z);
    let mut relative = 1.0;
    for iteration in 1..=options.max_iterations {
        let breakdown = |relative_residual| KrylovFailure::Breakdown {
            iterations: iteration - 1,
            relative_residual,
        };
        if !(rz > 0.0 && rz.is_finite()) {
            return Err(breakdown(relative));
        }
        system.apply_with_image(&p, &p_image, &mut ap);
        let curvature = dot(&p, &ap);
        if !(curvature > 0.0 && curvature.is_finite()) {
            return Err(breakdown(relative));
        }
        let step = rz / curvature;
        for i in 0..n {
            x[i] += step * p[i];
            r[i] -= step * ap[i];
        }
        relative = norm(&r) / b_norm;
        if relative <= options.tolerance {
            return Ok(KrylovStats {
                iterations: iteration,
                relative_residual: relative,
            });
        }
        system.precondition_with_image(&r, &mut z, &mut z_image);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        for i in 0..n {
            p[i] = z[i] + beta * p[i];
        }
        for (pi, zi) in p_image.iter_mut().zip(&z_image) {
            *pi = zi + beta * *pi;
        }
    }
    Err(KrylovFailure::MaxIterations {
        iterations: options.max_iterations,
        relative_residual: relative,
    })
}

/// Vectors lent to a solver and given back, kept by a caller that solves many systems of one
/// size (at millions of unknowns a fresh vector costs tens of milliseconds of page faults).
pub(crate) trait VectorPool {
    /// A vector of any length and content (empty when the pool holds none).
    fn lend(&mut self) -> Vec<f64>;
    /// A vector back, kept or dropped.
    fn give(&mut self, vector: Vec<f64>);
}

/// A pool that holds nothing: every vector lent is allocated, every one given back dropped.
struct NoPool;

impl VectorPool for NoPool {
    fn lend(&mut self) -> Vec<f64> {
        Vec::new()
    }
    fn give(&mut self, _: Vec<f64>) {}
}

/// A vector of `len` zeros from `pool` (none taken for `len = 0`).
fn lent(pool: &mut impl VectorPool, len: usize) -> Vec<f64> {
    if len == 0 {
        return Vec::new();
    }
    let mut v = pool.lend();
    zeroed(&mut v, len);
    v
}

/// A vector from `pool` holding `values` (of length `len`), written once, not zeroed first.
fn lent_with(
    pool: &mut impl VectorPool,
    len: usize,
    values: impl Iterator<Item = f64>,
) -> Vec<f64> {
    let mut v = pool.lend();
    v.clear();
    v.reserve_exact(len);
    v.extend(values);
    v
}

/// Right-preconditioned restarted GMRES(m); `x` is overwritten.
pub fn gmres(
    system: &mut impl KrylovSystem,
    b: &[f64],
    x: &mut [f64],
    options: &KrylovOptions,
) -> Result<KrylovStats, KrylovFailure> {
    gmres_in(system, b, x, options, &mut NoPool)
}

/// [`gmres`] with its vectors (the Arnoldi basis, the product, the preconditioned vector and
/// its image) lent by `pool` and given back at the end; a restart's residual is formed in the
/// product's vector, so no vector is held beside them.
pub(crate) fn gmres_in(
    system: &mut impl KrylovSystem,
    b: &[f64],
    x: &mut [f64],
    options: &KrylovOptions,
    pool: &mut impl VectorPool,
) -> Result<KrylovStats, KrylovFailure> {
    let n = system.len();
    x.fill(0.0);
    let b_norm = norm(b);
    if b_norm == 0.0 {
        return Ok(KrylovStats {
            iterations: 0,
            relative_residual: 0.0,
        });
    }
    let mut vectors = GmresVectors {
        w: lent(pool, n),
        z: lent(pool, n),
        z_image: lent(pool, system.image_len()),
        basis: Vec::new(),
    };
    let result = gmres_cycles(system, (b, b_norm), x, options, &mut vectors, pool);
    let GmresVectors {
        w,
        z,
        z_image,
        basis,
    } = vectors;
    let vectors = basis.into_iter().chain([w, z, z_image]);
    for vector in vectors.filter(|v| v.capacity() > 0) {
        pool.give(vector);
    }
    result
}

/// `r = b − A x` into `r`, from a fresh product.
fn residual_into(system: &mut impl KrylovSystem, b: &[f64], x: &[f64], r: &mut [f64]) {
    system.apply(x, r);
    for (r, b) in r.iter_mut().zip(b) {
        *r = b - *r;
    }
}

/// The vectors of [`gmres_in`]: the product `w`, the preconditioned vector `z` and its image,
/// and the Arnoldi basis.
struct GmresVectors {
    w: Vec<f64>,
    z: Vec<f64>,
    z_image: Vec<f64>,
    basis: Vec<Vec<f64>>,
}

/// The cycles of [`gmres_in`], in its vectors.
fn gmres_cycles(
    system: &mut impl KrylovSystem,
    (b, b_norm): (&[f64], f64),
    x: &mut [f64],
    options: &KrylovOptions,
    vectors: &mut GmresVectors,
    pool: &mut impl VectorPool,
) -> Result<KrylovStats, KrylovFailure> {
    let n = system.len();
    let m = options.restart.clamp(1, n.max(1));
    let GmresVectors {
        w,
        z,
        z_image,
        basis,
    } = vectors;
    let mut iterations = 0;
    let mut relative = 1.0;
    let mut x_is_zero = true;
    while iterations < options.max_iterations {
        // r = b − A x (b itself in the first cycle, from x = 0: no product), in w.
        let r: &[f64] = if x_is_zero {
            b
        } else {
            residual_into(system, b, x, w);
            w
        };
        let beta = norm(r);
        relative = beta / b_norm;
        if relative <= options.tolerance {
            return Ok(KrylovStats {
                iterations,
                relative_residual: relative,
            });
        }
        if !beta.is_finite() {
            break;
        }
        // The last cycle's basis back first, so that the new one reuses its vectors.
        for vector in basis.drain(..) {
            pool.give(vector);
        }
        basis.push(lent_with(pool, n, r.iter().map(|r| r / beta)));
        // Hessenberg columns, rotated as they come; g = β e₁ rotated.
        let mut hess: Vec<Vec<f64>> = Vec::with_capacity(m);
        let mut rotations: Vec<(f64, f64)> = Vec::with_capacity(m);
        let mut g = vec![0.0; m + 1];
        g[0] = beta;
        let mut inner = 0;
        while inner < m && iterations < options.max_iterations {
            system.precondition_with_image(&basis[inner], z, z_image);
            let preconditioned = (&basis[inner][..], 1.0);
            system.apply_preconditioned(z, z_image, preconditioned, (1.0, 0.0), w);
            iterations += 1;
            let mut h = vec![0.0; inner + 2];
            for (j, v) in basis.iter().enumerate() {
                h[j] = dot(w, v);
                for i in 0..n {
                    w[i] -= h[j] * v[i];
                }
            }
            h[inner + 1] = norm(w);
            for (j, &(c, s)) in rotations.iter().enumerate() {
                let (a, b) = (h[j], h[j + 1]);
                h[j] = c * a + s * b;
                h[j + 1] = -s * a + c * b;
            }
            let (a, b) = (h[inner], h[inner + 1]);
            let rho = a.hypot(b);
            let (c, s) = if rho == 0.0 {
                (1.0, 0.0)
            } else {
                (a / rho, b / rho)
            };
            h[inner] = rho;
            h[inner + 1] = 0.0;
            g[inner + 1] = -s * g[inner];
            g[inner] *= c;
            rotations.push((c, s));
            let next_norm = norm(w);
            hess.push(h);
            inner += 1;
            relative = g[inner].abs() / b_norm;
            if relative <= options.tolerance || next_norm == 0.0 || !relative.is_finite() {
                break;
            }
            basis.push(lent_with(pool, n, w.iter().map(|w| w / next_norm)));
        }
        // Solve the triangular system R y = g and update x += M (V y).
        let mut y = vec![0.0; inner];
        for i in (0..inner).rev() {
            let mut acc = g[i];
            for j in i + 1..inner {
                acc -= hess[j][i] * y[j];
            }
            y[i] = if hess[i][i] != 0.0 {
                acc / hess[i][i]
            } else {
                0.0
            };
        }
        w.fill(0.0);
        for (j, yj) in y.iter().enumerate() {
            for i in 0..n {
                w[i] += yj * basis[j][i];
            }
        }
        system.precondition(w, z);
        let before = relative;
        for i in 0..n {
            x[i] += z[i];
        }
        x_is_zero = false;
        if !x.iter().all(|v| v.is_finite()) {
            break;
        }
        // A restart that reduced nothing will not reduce anything next time either.
        if inner == m && before >= 0.999 * (beta / b_norm) {
            break;
        }
    }
    residual_into(system, b, x, w);
    let true_residual = norm(w) / b_norm;
    if true_residual <= options.tolerance {
        return Ok(KrylovStats {
            iterations,
            relative_residual: true_residual,
        });
    }
    Err(KrylovFailure::MaxIterations {
        iterations,
        relative_residual: if true_residual.is_finite() {
            true_residual
        } else {
            relative
        },
    })
}

#[cfg(test)]
mod tests;
