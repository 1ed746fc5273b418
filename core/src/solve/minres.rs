//! Preconditioned MINRES for symmetric, possibly indefinite `A` with a symmetric positive
//! definite preconditioner `M ≈ A⁻¹`, and the Lanczos tridiagonal matrix it builds on the way.
//!
//! MINRES runs the Lanczos process on `M A` in the `M⁻¹` inner product (`z_j = M v_j / γ_j`,
//! `δ_j = z_j·A z_j`, `v_{j+1} = A z_j − (δ_j/γ_j) v_j − (γ_j/γ_{j−1}) v_{j−1}`,
//! `γ_{j+1} = √(v_{j+1}·M v_{j+1})`), solves the small least-squares problem of its
//! tridiagonal matrix with Givens rotations, and updates `x` along directions `w_j` with a
//! three-term recurrence. Unlike conjugate gradients it needs no definite `A`: the Krylov
//! iterate minimises the residual in the `M` norm over the Krylov space, so an eigenvalue of
//! `M A` on either side of zero costs iterations, never a breakdown. Unlike GMRES it keeps
//! three vectors, not a basis, so it never restarts: GMRES(m) with a restart shorter than the
//! number of negative eigenvalues of `M A` forgets the directions it had found and stagnates.
//!
//! Each iteration costs one product with `A` and one with `M`, as a CG iteration does, and
//! the same [`KrylovSystem::image_len`] by-product applies: `A` is only ever applied to the
//! preconditioned vectors `z_j`, and since `z_j = M v_j / γ_j`, a system whose preconditioner
//! inverts a part of `A` exactly is handed `v_j` with it
//! ([`KrylovSystem::apply_preconditioned`]). The residual `b − A x` is carried along in the 2-norm, so the
//! stopping rule is that of the other solvers, `‖b − A x‖₂ ≤ tolerance · ‖b‖₂`, by a
//! recurrence on the Lanczos vectors that needs no vector of its own: with
//! `ṽ_j = v_j/γ_j`, the Lanczos relation `A Z_k = Ṽ_{k+1} T̄_k` (`T̄_k` the `(k+1) × k`
//! tridiagonal matrix) and `x_k = Z_k y_k` give `r_k = Ṽ_{k+1}(γ_1 e_1 − T̄_k y_k)
//! = φ̄_{k+1} Ṽ_{k+1} Q_kᵀ e_{k+1}`, where `Q_k` is the product of the Givens rotations and
//! `φ̄_{k+1} = −s_k φ̄_k`; the last column of `Q_kᵀ` is `(−s_k Q_{k−1}ᵀ e_k, c_k)`, so
//! `r_k = s_k² r_{k−1} + φ̄_{k+1} c_k ṽ_{k+1}` (Choi, Paige and Saunders). It is the
//! residual of the iterate `x_k` to rounding, whether or not the Lanczos vectors stay
//! orthogonal, since it rests only on the three-term recurrence that defines them; it
//! replaced the recurrence of the products `A w_j`, whose two vectors were 16 bytes a node of
//! the fractional fast path.
//!
//! MINRES holds five vectors beside `x` and `b`: `v_{j−1}`, `v_j`, `z_j`, `w_{j−1}`, `w_j`
//! (and the image of `z_j` where the system keeps one, [`KrylovSystem::image_len`]).
//! The residual's recurrence runs in the storage of the right-hand side, which the caller
//! hands over ([`minres_in`]), and the product `A z_j` is added onto `v_{j−1}`'s storage
//! ([`KrylovSystem::apply_preconditioned`] takes `y ← c A x + β y`), where `v_{j+1}` is
//! built: `δ_j = z_j·A z_j` is then `z_j·(A z_j − β v_{j−1}) + β z_j·v_{j−1}`, the last dot
//! product (zero but for rounding) taken in the sweep that scales `z_j`.
//!
//! The tridiagonal matrix `T_k` (diagonal `δ_j`, off-diagonal `γ_{j+1}`) is that of
//! `M^{1/2} A M^{1/2}`, so its eigenvalues (the Ritz values) approximate those of `M A`, and
//! each comes with a bound: some eigenvalue of `M A` lies within `|γ_{k+1} s_k|` of a Ritz
//! value whose unit eigenvector of `T_k` ends in `s_k` ([`ritz_values`]).
//!
//! ## Reference
//!
//! C. C. Paige and M. A. Saunders, *Solution of sparse indefinite systems of linear
//! equations*, SIAM J. Numer. Anal. 12 (1975); the preconditioned form as in H. C. Elman,
//! D. J. Silvester and A. J. Wathen, *Finite Elements and Fast Iterative Solvers*, 2nd ed.,
//! Algorithm 4.1. The Ritz bound: B. N. Parlett, *The Symmetric Eigenvalue Problem*, §13.1.
//! The residual recurrence: S.-C. T. Choi, C. C. Paige and M. A. Saunders, *MINRES-QLP: a
//! Krylov subspace method for indefinite or singular symmetric systems*, SIAM J. Sci. Comput.
//! 33 (2011), §2.

use crate::halves;
use crate::linalg::zeroed;
use crate::solve::krylov::{KrylovFailure, KrylovOptions, KrylovStats, KrylovSystem, VectorPool};
use nalgebra::{DMatrix, SymmetricEigen};

/// The Lanczos tridiagonal matrix of `M A` built by [`minres`]: `diagonal[j] = δ_{j+1}` and
/// `off_diagonal[j] = γ_{j+2}` (the last entry couples `T_k` to the next, unbuilt, vector).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tridiagonal {
    /// `δ_1, …, δ_k`.
    pub diagonal: Vec<f64>,
    /// `γ_2, …, γ_{k+1}`.
    pub off_diagonal: Vec<f64>,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The vectors of [`minres`], kept by a caller that solves many systems of one size (the
/// Newton steps of one solve): at `N = 10⁷` unknowns six fresh vectors cost most of a
/// gigabyte of page faults and zeroing per solve. The residual lives in the caller's
/// right-hand side, and `A z` in the storage of `v_{j−1}` ([`minres_in`]).
#[derive(Debug, Default)]
pub(crate) struct MinresWork {
    v: Vec<f64>,
    v_old: Vec<f64>,
    z: Vec<f64>,
    z_image: Vec<f64>,
    w: Vec<f64>,
    w_old: Vec<f64>,
    /// Whether the last solve kept no images: `z_image` then holds no memory, and
    /// [`give`](Self::give) puts nothing there (a vector given into it would be held, unused,
    /// until the work is dropped).
    without_images: bool,
}

impl MinresWork {
    /// The vectors a solve uses, in a fixed order (`z_image` left out after a solve without
    /// images).
    fn vectors(&mut self) -> impl Iterator<Item = &mut Vec<f64>> {
        let image = (!self.without_images).then_some(&mut self.z_image);
        [
            &mut self.v,
            &mut self.v_old,
            &mut self.z,
            &mut self.w,
            &mut self.w_old,
        ]
        .into_iter()
        .chain(image)
    }

    /// One of the vectors (the largest allocation), for other use between two solves: the
    /// caller's buffers need no memory of their own while the solver's are idle. A solve after
    /// it allocates what is missing.
    pub(crate) fn lend(&mut self) -> Vec<f64> {
        self.vectors()
            .max_by_key(|v| v.capacity())
            .map(std::mem::take)
            .unwrap_or_default()
    }

    /// Frees vectors, the smallest first, until at most `count` are held.
    pub(crate) fn keep_at_most(&mut self, count: usize) {
        let mut held: Vec<&mut Vec<f64>> = self.vectors().filter(|v| v.capacity() > 0).collect();
        held.sort_by_key(|v| std::cmp::Reverse(v.capacity()));
        for vector in held.into_iter().skip(count) {
            *vector = Vec::new();
        }
    }

    /// Gives back a vector (from [`lend`](Self::lend) or any other), into an empty place;
    /// dropped when there is none.
    pub(crate) fn give(&mut self, vector: Vec<f64>) {
        if let Some(place) = self.vectors().find(|v| v.capacity() == 0) {
            *place = vector;
        }
    }
}

/// The Krylov vectors lent to GMRES, where it takes over from MINRES or runs instead.
impl VectorPool for MinresWork {
    fn lend(&mut self) -> Vec<f64> {
        MinresWork::lend(self)
    }
    fn give(&mut self, vector: Vec<f64>) {
        MinresWork::give(self, vector);
    }
}

/// Preconditioned MINRES for symmetric `A` and symmetric positive definite `M`, from `x = 0`;
/// `x` is overwritten. With `record`, the Lanczos coefficients of every iteration are appended
/// to it. A non-positive `v·M v` (an indefinite `M`) is [`KrylovFailure::Breakdown`].
pub fn minres(
    system: &mut impl KrylovSystem,
    b: &[f64],
    x: &mut [f64],
    options: &KrylovOptions,
    record: Option<&mut Tridiagonal>,
) -> Result<KrylovStats, KrylovFailure> {
    let mut r = b.to_vec();
    minres_in(
        system,
        &mut r,
        x,
        options,
        record,
        &mut MinresWork::default(),
    )
}

/// [`minres`] in the vectors of `work`, for the right-hand side in `r`, whose storage the
/// solve takes for its residual (a vector fewer at every Newton step of a large solve). On
/// return `r` holds the residual of the scaled system, `(b − A x)/s` (`s` below), except
/// after a [`KrylovFailure::Breakdown`], when it holds `b` again for the solver that takes
/// over: `s r + A x`, one product (none, and exactly `b`, while `x` is still zero). Past the
/// start that `b` carries the gap between the recurrence's residual and the true one, which
/// grows with the iterations' rounding (1.4e-11 of `‖b‖` after 1620 iterations on a diagonal
/// system of condition 10⁶): the solver that takes over solves for it, its result a Newton
/// step still. A breakdown on a residual that is not finite gives back a `b` that is not
/// either.
pub(crate) fn minres_in(
    system: &mut impl KrylovSystem,
    r: &mut [f64],
    x: &mut [f64],
    options: &KrylovOptions,
    record: Option<&mut Tridiagonal>,
    work: &mut MinresWork,
) -> Result<KrylovStats, KrylovFailure> {
    x.fill(0.0);
    let b_norm = dot(r, r).sqrt();
    if b_norm == 0.0 {
        return Ok(KrylovStats {
            iterations: 0,
            relative_residual: 0.0,
        });
    }
    // The system is solved as (A/s) x = b/s with the preconditioner s M, for the power of two
    // s of ‖b‖: exact, and it makes every recurrence coefficient (γ = √(v·Mv) among them)
    // independent of a power-of-two scale of A, b and M⁻¹, so that `c L` (c = 2^k) gives the
    // iterates of `L` bit for bit.
    let scale = power_of_two(b_norm);
    r.iter_mut().for_each(|x| *x /= scale);
    let result = iterate(
        system,
        (r, x),
        (b_norm / scale, scale),
        options,
        record,
        work,
    );
    if let Err(KrylovFailure::Breakdown { .. }) = result {
        if x.iter().all(|x| *x == 0.0) {
            r.iter_mut().for_each(|x| *x *= scale);
        } else {
            let mut ax = vec![0.0; r.len()];
            system.apply(x, &mut ax);
            for (r, ax) in r.iter_mut().zip(&ax) {
                *r = scale * *r + ax;
            }
        }
    }
    result
}

/// The iterations of [`minres_in`] on the scaled system, from `r = b/s`, `x = 0`, with
/// `‖b/s‖₂ = b_norm`.
fn iterate(
    system: &mut impl KrylovSystem,
    (r, x): (&mut [f64], &mut [f64]),
    (b_norm, scale): (f64, f64),
    options: &KrylovOptions,
    mut record: Option<&mut Tridiagonal>,
    work: &mut MinresWork,
) -> Result<KrylovStats, KrylovFailure> {
    let n = system.len();
    let images = system.image_len();
    let MinresWork {
        v,
        v_old,
        z,
        z_image,
        w,
        w_old,
        without_images,
    } = work;
    v.clear();
    v.extend_from_slice(r);
    let (mut v, mut v_old) = (v, zeroed(v_old, n));
    *without_images = images == 0;
    if images == 0 {
        *z_image = Vec::new();
    }
    let (z, z_image) = (zeroed(z, n), zeroed(z_image, images));
    let (mut w, mut w_old) = (zeroed(w, n), zeroed(w_old, n));
    system.precondition_with_image(v, z, z_image);
    z.iter_mut()
        .chain(z_image.iter_mut())
        .for_each(|x| *x *= scale);
    let gamma_sq = dot(z, v);
    if !(gamma_sq > 0.0 && gamma_sq.is_finite()) {
        return Err(KrylovFailure::Breakdown {
            iterations: 0,
            relative_residual: 1.0,
        });
    }
    let (mut gamma, mut gamma_old) = (gamma_sq.sqrt(), 1.0);
    let mut eta = gamma;
    let (mut s_old, mut s, mut c_old, mut c) = (0.0, 0.0, 1.0, 1.0);
    let mut relative = 1.0;
    for iteration in 1..=options.max_iterations {
        let breakdown = |relative_residual| KrylovFailure::Breakdown {
            iterations: iteration,
            relative_residual,
        };
        let inverse = 1.0 / gamma;
        // z_j = z/γ_j, and z_j·v_{j−1} (zero but for rounding: the Lanczos vectors are
        // M-orthogonal) for δ_j below, in one sweep.
        let z_v_old = halves::sum((n, 1), (&mut z[..], &v_old[..]), |_, (z, v_old)| {
            z.iter_mut().zip(v_old).fold(0.0, |sum, (x, v)| {
                *x *= inverse;
                sum + *x * v
            })
        });
        z_image.iter_mut().for_each(|zi| *zi *= inverse);
        // v_{j+1} = A z_j − δ_j/γ_j v_j − γ_j/γ_{j−1} v_{j−1} (A of the scaled system), built
        // in v_old's storage, where the product adds A z_j (no vector of its own), and the
        // two then swap places; z = (scale/γ) M v: a system that inverts part of A exactly
        // uses v.
        let b_coef = gamma / gamma_old;
        let onto = (1.0 / scale, -b_coef);
        system.apply_preconditioned(z, z_image, (v, scale * inverse), onto, v_old);
        let delta =
            halves::sum((n, 1), (&v_old[..], &z[..]), |_, (u, z)| dot(u, z)) + b_coef * z_v_old;
        // The new column of T_k rotated by the previous two Givens rotations, then its own;
        // α₂ and α₃ are known before γ_{j+1}, so w_{j+1}'s numerator
        // z_j − α₃ w_{j−1} − α₂ w_j goes into w_old's storage now, in the sweep that
        // completes v_{j+1}, and z_{j+1} into z's.
        let a = delta / gamma;
        let alpha2 = s * delta + c_old * c * gamma;
        let alpha3 = s_old * gamma;
        let parts = ((&mut v_old[..], &v[..]), (&mut w_old[..], &z[..], &w[..]));
        halves::each((n, 1), parts, |_, ((v_old, v), (w_old, z, w))| {
            for (v_old, v) in v_old.iter_mut().zip(v) {
                *v_old -= a * v;
            }
            for ((w_old, z), w) in w_old.iter_mut().zip(z).zip(w) {
                *w_old = z - alpha3 * *w_old - alpha2 * w;
            }
        });
        std::mem::swap(&mut v, &mut v_old);
        system.precondition_with_image(v, z, z_image);
        z_image.iter_mut().for_each(|x| *x *= scale);
        let gamma_next_sq = halves::sum((n, 1), (&mut z[..], &v[..]), |_, (z, v)| {
            z.iter_mut().zip(v).fold(0.0, |sum, (x, vi)| {
                *x *= scale;
                sum + *x * vi
            })
        });
        if !(gamma_next_sq >= 0.0 && gamma_next_sq.is_finite() && delta.is_finite()) {
            return Err(breakdown(relative));
        }
        let gamma_next = gamma_next_sq.sqrt();
        if let Some(t) = record.as_deref_mut() {
            t.diagonal.push(delta);
            t.off_diagonal.push(gamma_next);
        }
        let alpha0 = c * delta - c_old * s * gamma;
        let alpha1 = alpha0.hypot(gamma_next);
        if alpha1 == 0.0 {
            return Err(breakdown(relative));
        }
        let (c_new, s_new) = (alpha0 / alpha1, gamma_next / alpha1);
        // w_{j+1} = (z_j − α₃ w_{j−1} − α₂ w_j)/α₁; the residual by its recurrence (module
        // docs), with v_{j+1} (now in `v`) = γ_{j+1} ṽ_{j+1} and
        // φ̄_{j+1} c_{j+1} / γ_{j+1} = −η c_new / α₁.
        let step = c_new * eta;
        let (s2, v_coef) = (s_new * s_new, eta * c_new / alpha1);
        let parts = (&mut w_old[..], &mut x[..], &mut r[..], &v[..]);
        let r_sq = halves::sum((n, 1), parts, |_, (w_old, x, r, v)| {
            let mut r_sq = 0.0;
            for (((w_old, x), r), v) in w_old.iter_mut().zip(x).zip(r).zip(v) {
                *w_old /= alpha1;
                *x += step * *w_old;
                *r = s2 * *r - v_coef * v;
                r_sq += *r * *r;
            }
            r_sq
        });
        std::mem::swap(&mut w, &mut w_old);
        eta *= -s_new;
        (c_old, c, s_old, s) = (c, c_new, s, s_new);
        (gamma_old, gamma) = (gamma, gamma_next);
        relative = r_sq.sqrt() / b_norm;
        if !relative.is_finite() {
            return Err(breakdown(relative));
        }
        if relative <= options.tolerance {
            return Ok(KrylovStats {
                iterations: iteration,
                relative_residual: relative,
            });
        }
        // An invariant subspace: the Krylov space holds the solution, and more iterations
        // add nothing.
        if gamma_next == 0.0 {
            return Err(KrylovFailure::MaxIterations {
                iterations: iteration,
                relative_residual: relative,
            });
        }
    }
    Err(KrylovFailure::MaxIterations {
        iterations: options.max_iterations,
        relative_residual: relative,
    })
}

/// The power of two `2^e` with `2^e ≤ x < 2^{e+1}` (1 for zero, subnormal or non-finite `x`).
fn power_of_two(x: f64) -> f64 {
    let exponent = ((x.to_bits() >> 52) & 0x7ff) as i32;
    if exponent == 0 || exponent == 0x7ff {
        1.0
    } else {
        f64::from_bits((exponent as u64) << 52)
    }
}

/// The Ritz values of a Lanczos tridiagonal matrix `T_k` (its eigenvalues), each with the
/// bound `|γ_{k+1} s_k|` on its distance to the nearest eigenvalue of the operator (module
/// docs), in increasing order. Empty for an empty `T`.
pub fn ritz_values(t: &Tridiagonal) -> Vec<(f64, f64)> {
    let k = t.diagonal.len();
    if k == 0 {
        return Vec::new();
    }
    let tk = DMatrix::from_fn(k, k, |i, j| match i.abs_diff(j) {
        0 => t.diagonal[i],
        1 => t.off_diagonal[i.min(j)],
        _ => 0.0,
    });
    let eigen = SymmetricEigen::new(tk);
    let beta = t.off_diagonal[k - 1];
    let mut pairs: Vec<(f64, f64)> = (0..k)
        .map(|i| {
            (
                eigen.eigenvalues[i],
                (beta * eigen.eigenvectors[(k - 1, i)]).abs(),
            )
        })
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    pairs
}

#[cfg(test)]
mod tests;
