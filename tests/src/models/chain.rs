//! The FPUT chain written by hand as a [`DynLagrangian`]: plain loops over the bonds, with the
//! force and the tridiagonal (or, periodic, cyclic) Hessian derived on paper. The independent
//! second computation the run-time-dimension solver and the generated models are checked
//! against.

use varembed::{Dependence, DynLagrangian, HessianDependence, SparseHessian};

/// `n` unit masses, neighbours joined by the FPUT spring `V(d) = d²/2 + α d³/3 + β d⁴/4`:
/// between two walls at 0 (`x_{−1} = x_n = 0`, the bonds to the walls included), or periodic
/// (`x_n = x_0`). `L = Σ ½ v_i² − Σ V(d)`.
#[derive(Clone, Copy, Debug)]
pub struct FputChain {
    /// Number of moving masses.
    pub n: usize,
    /// Cubic coefficient α.
    pub alpha: f64,
    /// Quartic coefficient β.
    pub beta: f64,
    /// Periodic (a ring) rather than between walls.
    pub periodic: bool,
}

/// A smooth initial displacement of `n` masses, of amplitude `amplitude` and phase `phase`:
/// not a normal mode, so every mode and the nonlinearity take part.
pub fn displacement(n: usize, amplitude: f64, phase: f64) -> Vec<f64> {
    (0..n)
        .map(|i| {
            amplitude
                * ((i as f64 + 1.0) * 0.7 + phase).sin()
                * (1.0 + 0.3 * (i as f64 * 1.3).cos())
        })
        .collect()
}

impl FputChain {
    /// `V'(d)`.
    fn dv(&self, d: f64) -> f64 {
        d + self.alpha * d * d + self.beta * d * d * d
    }
    /// `V''(d)`.
    fn ddv(&self, d: f64) -> f64 {
        1.0 + 2.0 * self.alpha * d + 3.0 * self.beta * d * d
    }
    /// `V(d)`.
    fn v(&self, d: f64) -> f64 {
        0.5 * d * d + self.alpha / 3.0 * d.powi(3) + self.beta / 4.0 * d.powi(4)
    }
    /// The bonds between masses, `(j, k)`, `d = x_k − x_j`: `(i, i + 1)`, and `(n − 1, 0)` for a
    /// ring.
    fn bonds(&self) -> impl Iterator<Item = (usize, usize)> + use<> {
        let n = self.n;
        let wrap = self.periodic.then_some((n - 1, 0));
        (0..n - 1).map(|i| (i, i + 1)).chain(wrap)
    }
    /// The bonds to the walls, `(j, s)`: mass `j` with the bond `d = s x_j` (`s = 1` at the
    /// left wall, `−1` at the right); none for a ring.
    fn walls(&self) -> impl Iterator<Item = (usize, f64)> + use<> {
        let walls = [(0, 1.0), (self.n - 1, -1.0)];
        let count = if self.periodic { 0 } else { 2 };
        walls.into_iter().take(count)
    }
}

impl DynLagrangian for FputChain {
    fn dimension(&self) -> usize {
        self.n
    }
    fn value(&self, x: &[f64], v: &[f64], _t: f64) -> f64 {
        let kinetic: f64 = v.iter().map(|v| 0.5 * v * v).sum();
        let bonds: f64 = self.bonds().map(|(j, k)| self.v(x[k] - x[j])).sum();
        let walls: f64 = self.walls().map(|(j, s)| self.v(s * x[j])).sum();
        kinetic - bonds - walls
    }
    fn force(&self, x: &[f64], _v: &[f64], _t: f64, f: &mut [f64]) {
        if !self.periodic {
            let n = self.n;
            let mut previous = self.dv(x[0]);
            for j in 1..n {
                let dv = self.dv(x[j] - x[j - 1]);
                f[j - 1] = dv - previous;
                previous = dv;
            }
            f[n - 1] = self.dv(-x[n - 1]) - previous;
            return;
        }
        f.fill(0.0);
        for (j, k) in self.bonds() {
            let dv = self.dv(x[k] - x[j]);
            f[k] -= dv;
            f[j] += dv;
        }
        for (j, s) in self.walls() {
            f[j] -= s * self.dv(s * x[j]);
        }
    }
    fn momentum(&self, _x: &[f64], v: &[f64], _t: f64, p: &mut [f64]) {
        p.copy_from_slice(v);
    }
    fn hessian(&self, x: &[f64], _v: &[f64], _t: f64, out: &mut SparseHessian) {
        for i in 0..self.n {
            out.vv.add(i, i, 1.0);
        }
        for (j, k) in self.bonds() {
            let c = self.ddv(x[k] - x[j]);
            out.xx.add(j, j, -c);
            out.xx.add(k, k, -c);
            out.xx.add(j, k, c);
            out.xx.add(k, j, c);
        }
        for (j, s) in self.walls() {
            out.xx.add(j, j, -self.ddv(s * x[j]));
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        HessianDependence {
            xx: Dependence {
                x: true,
                v: false,
                t: false,
            },
            xv: Dependence::NONE,
            vv: Dependence::NONE,
        }
    }
    fn hessian_bandwidth(&self) -> Option<usize> {
        (!self.periodic).then_some(1)
    }
    fn dependence(&self) -> Dependence {
        Dependence {
            x: true,
            v: true,
            t: false,
        }
    }
    fn constants(&self) -> Vec<(&'static str, f64)> {
        vec![("alpha", self.alpha), ("beta", self.beta)]
    }
}

/// A hand-written run of the chain ([`direct_backward_by_hand`], [`stormer_verlet_by_hand`])
/// as a plain fn: `(q0, v0, (h, steps), (α, β), observe)`.
pub type HandWrittenRun = fn(&[f64], &[f64], (f64, usize), (f64, f64), &mut dyn FnMut(&[f64]));

/// `V'(d)` and `V''(d)` of the spring `V(d) = d²/2 + α d³/3 + β d⁴/4`.
#[inline(always)]
fn spring(d: f64, alpha: f64, beta: f64) -> (f64, f64) {
    (
        d + alpha * d * d + beta * d * d * d,
        1.0 + 2.0 * alpha * d + 3.0 * beta * d * d,
    )
}

/// The direct Gauss-FDE− run of the FPUT chain between walls, written by hand as a user would
/// for this chain alone: `Q_1 = q0 + h v0` (the discrete Legendre start of σ = −), then each
/// step solves `G(y) = (y − b)/h + h ∇U(y) = (b − a)/h` (the library's residual, in momentum
/// units) by Newton on the tridiagonal `∂G/∂y = I/h + h ∇²U(y)` (Thomas algorithm), from the
/// guess `2b − a`, stopping when `|G − π|∞ ≤ 1e-12 (1 + |π|∞)`. Every node `Q_0, …, Q_N` is
/// handed to `observe`; the buffers are allocated once.
pub fn direct_backward_by_hand(
    q0: &[f64],
    v0: &[f64],
    (h, steps): (f64, usize),
    (alpha, beta): (f64, f64),
    mut observe: impl FnMut(&[f64]),
) {
    let n = q0.len();
    let mut a = q0.to_vec();
    let mut b: Vec<f64> = q0.iter().zip(v0).map(|(q, v)| q + h * v).collect();
    observe(&a);
    observe(&b);
    let (mut grad, mut diag, mut off) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut r, mut c, mut y, mut pi) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for _ in 2..=steps {
        let mut scale = 0.0f64;
        for i in 0..n {
            pi[i] = (b[i] - a[i]) / h;
            scale = scale.max(pi[i].abs());
            y[i] = 2.0 * b[i] - a[i];
        }
        let scale = 1.0 + scale;
        for _ in 0..50 {
            potential_derivatives(&y, (alpha, beta), (&mut grad, &mut diag, &mut off));
            let mut residual = 0.0f64;
            for i in 0..n {
                r[i] = (y[i] - b[i]) / h + h * grad[i] - pi[i];
                residual = residual.max(r[i].abs());
            }
            if residual <= 1e-12 * scale {
                break;
            }
            thomas((1.0 / h, h), (&diag, &off), &mut r, &mut c);
            y.iter_mut().zip(&r).for_each(|(y, d)| *y -= d);
        }
        observe(&y);
        std::mem::swap(&mut a, &mut b);
        std::mem::swap(&mut b, &mut y);
    }
}

/// The variational Gauss-FDE+ run of the FPUT chain between walls, written by hand: the
/// two-step Störmer–Verlet loop `Q_n = 2 Q_{n−1} − Q_{n−2} + h² f(Q_{n−1})`, from the discrete
/// Legendre start of σ = +, `Q_1 = q0 + h v0 + h² f(q0)`, with the force written out over the
/// bonds. Every node is handed to `observe`.
pub fn stormer_verlet_by_hand(
    q0: &[f64],
    v0: &[f64],
    (h, steps): (f64, usize),
    (alpha, beta): (f64, f64),
    mut observe: impl FnMut(&[f64]),
) {
    let n = q0.len();
    let h2 = h * h;
    let mut f = vec![0.0; n];
    let force = |x: &[f64], f: &mut [f64]| {
        // Bond j joins x_{j−1} and x_j (walls x_{−1} = x_n = 0); f_j gains V'(d_{j+1}) − V'(d_j).
        let mut previous = spring(x[0], alpha, beta).0;
        for j in 1..n {
            let dv = spring(x[j] - x[j - 1], alpha, beta).0;
            f[j - 1] = dv - previous;
            previous = dv;
        }
        f[n - 1] = spring(-x[n - 1], alpha, beta).0 - previous;
    };
    let mut a = q0.to_vec();
    force(&a, &mut f);
    let mut b: Vec<f64> = (0..n).map(|i| q0[i] + h * v0[i] + h2 * f[i]).collect();
    observe(&a);
    observe(&b);
    let mut y = vec![0.0; n];
    for _ in 2..=steps {
        force(&b, &mut f);
        for i in 0..n {
            y[i] = 2.0 * b[i] - a[i] + h2 * f[i];
        }
        observe(&y);
        std::mem::swap(&mut a, &mut b);
        std::mem::swap(&mut b, &mut y);
    }
}

/// `∇U` and the tridiagonal `∇²U` (diagonal `diag`, off-diagonal `off[i] = ∂²U/∂x_i∂x_{i+1}`)
/// of the chain between walls at `x`, over the bonds `d_j = x_j − x_{j−1}`, `j = 0..=n`.
fn potential_derivatives(
    x: &[f64],
    (alpha, beta): (f64, f64),
    (grad, diag, off): (&mut [f64], &mut [f64], &mut [f64]),
) {
    let n = x.len();
    grad.fill(0.0);
    diag.fill(0.0);
    for j in 0..=n {
        let left = if j == 0 { 0.0 } else { x[j - 1] };
        let right = if j == n { 0.0 } else { x[j] };
        let (dv, ddv) = spring(right - left, alpha, beta);
        if j < n {
            grad[j] += dv;
            diag[j] += ddv;
        }
        if j > 0 {
            grad[j - 1] -= dv;
            diag[j - 1] += ddv;
            if j < n {
                off[j - 1] = -ddv;
            }
        }
    }
}

/// Solves `(s I + w T) z = r` in place (the Thomas algorithm), `T` the tridiagonal matrix of
/// diagonal `diag` and off-diagonal `off`, `c` a buffer of the same length.
fn thomas((s, w): (f64, f64), (diag, off): (&[f64], &[f64]), r: &mut [f64], c: &mut [f64]) {
    let n = r.len();
    let mut pivot = s + w * diag[0];
    c[0] = w * off[0] / pivot;
    r[0] /= pivot;
    for i in 1..n {
        pivot = s + w * diag[i] - w * off[i - 1] * c[i - 1];
        c[i] = if i + 1 < n { w * off[i] / pivot } else { 0.0 };
        r[i] = (r[i] - w * off[i - 1] * r[i - 1]) / pivot;
    }
    for i in (0..n - 1).rev() {
        r[i] -= c[i] * r[i + 1];
    }
}

/// `∇U` alone at `x` (as [`potential_derivatives`]).
fn potential_gradient(x: &[f64], (alpha, beta): (f64, f64), grad: &mut [f64]) {
    let n = x.len();
    let mut previous = spring(x[0], alpha, beta).0;
    for j in 1..n {
        let dv = spring(x[j] - x[j - 1], alpha, beta).0;
        grad[j - 1] = previous - dv;
        previous = dv;
    }
    grad[n - 1] = previous - spring(-x[n - 1], alpha, beta).0;
}

/// The variational midpoint run of the FPUT chain between walls, written by hand as a user
/// would for this chain alone. With `L_d(a, b) = h L((a + b)/2, (b − a)/h)` each step solves
/// `G(y) = (y − b)/h + (h/2) ∇U((b + y)/2) = π`, the momentum
/// `π = (b − a)/h − (h/2) ∇U((a + b)/2)`, by Newton on the tridiagonal
/// `∂G/∂y = I/h + (h/4) ∇²U((b + y)/2)` (Thomas algorithm) from the guess `2b − a`, stopping
/// when `|G − π|∞ ≤ 1e-12 (1 + |π|∞)`. The start solves the same equation with `b = q0`,
/// `π = v0` (the discrete Legendre transform `p_0 = −D₁L_d(Q_0, Q_1)`) from `q0 + h v0`. Every
/// node is handed to `observe`; the buffers are allocated once.
pub fn midpoint_variational_by_hand(
    q0: &[f64],
    v0: &[f64],
    (h, steps): (f64, usize),
    params: (f64, f64),
    mut observe: impl FnMut(&[f64]),
) {
    let n = q0.len();
    let (mut grad, mut diag, mut off) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut r, mut c, mut m, mut pi) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    // Solves `G(y) = π` with `b` the node before `y`, from the guess in `y`.
    let mut solve = |b: &[f64], pi: &[f64], y: &mut [f64]| {
        let scale = 1.0 + pi.iter().fold(0.0f64, |s, p| s.max(p.abs()));
        for _ in 0..50 {
            for i in 0..n {
                m[i] = 0.5 * (b[i] + y[i]);
            }
            potential_derivatives(&m, params, (&mut grad, &mut diag, &mut off));
            let mut residual = 0.0f64;
            for i in 0..n {
                r[i] = (y[i] - b[i]) / h + 0.5 * h * grad[i] - pi[i];
                residual = residual.max(r[i].abs());
            }
            if residual <= 1e-12 * scale {
                return;
            }
            thomas((1.0 / h, 0.25 * h), (&diag, &off), &mut r, &mut c);
            y.iter_mut().zip(&r).for_each(|(y, d)| *y -= d);
        }
    };
    let mut a = q0.to_vec();
    let mut b: Vec<f64> = q0.iter().zip(v0).map(|(q, v)| q + h * v).collect();
    solve(q0, v0, &mut b);
    observe(&a);
    observe(&b);
    let mut y = vec![0.0; n];
    let mut ga = vec![0.0; n];
    for _ in 2..=steps {
        for i in 0..n {
            y[i] = 0.5 * (a[i] + b[i]);
        }
        potential_gradient(&y, params, &mut ga);
        for i in 0..n {
            pi[i] = (b[i] - a[i]) / h - 0.5 * h * ga[i];
            y[i] = 2.0 * b[i] - a[i];
        }
        solve(&b, &pi, &mut y);
        observe(&y);
        std::mem::swap(&mut a, &mut b);
        std::mem::swap(&mut b, &mut y);
    }
}
