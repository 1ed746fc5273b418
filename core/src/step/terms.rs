//! What each step kind evaluates, and with which weights: the table both storages' steps read.
//!
//! Every classical step sums *terms* `w_p p + w_f h f` (`p = ∂L/∂v`, `f = ∂L/∂x`) at points of
//! one interval `[u, w]` (times `t_u`, `t_w`, step `h`). The momentum `π` sums them on
//! `[a, b] = [Q_{n−2}, Q_{n−1}]`, the step equation `G(y)` on `[b, y] = [Q_{n−1}, Q_n]`:
//!
//! | [`Point`] | `x` | `v` | `t` |
//! | --- | --- | --- | --- |
//! | `Left` | `u` | `(w − u)/h` | `t_u` |
//! | `Middle` | `(u + w)/2` | `(w − u)/h` | `(t_u + t_w)/2` |
//! | `Right` | `w` | `(w − u)/h` | `t_w` |
//! | `Centred` | `u` | `(w − a)/(2h)`, `a` the node before `u` | `t_u` |
//!
//! | [`StepKind`] | momentum `π` on `[a, b]` | equation `G(y)` on `[b, y]` |
//! | --- | --- | --- |
//! | `VariationalBackward` | `p + h f` at `Right` | `p` at `Right` |
//! | `VariationalForward` | `p` at `Left` | `p − h f` at `Left` |
//! | `DirectBackward` | `p` at `Right` | `p − h f` at `Right` |
//! | `DirectForward` | `p + h f` at `Left` | `p` at `Left` |
//! | `MidpointVariational` | `p + ½ h f` at `Middle` | `p − ½ h f` at `Middle` |
//! | `MidpointDirect` | `p` at `Middle` | `p` at `Middle`, `− h f` at `Centred` |
//! | `TrapezoidalVariational` | `½ p` at `Left`, `½ p + ½ h f` at `Right` | `½ p − ½ h f` at `Left`, `½ p` at `Right` |
//! | `TrapezoidalDirect` | `½ p` at `Left` and at `Right` | `½ p` at `Left` and at `Right`, `− h f` at `Centred` |
//!
//! These are the tables of the step module written out term by term: the Gauss-FDEσ rows,
//! and for the symmetric embeddings `π = D₂L_d(a, b)`, `G(y) = −D₁L_d(b, y)` (variational) or
//! the interval momentum `P` and the node force with the centred velocity (direct), with
//! `D₁L_d = h/2 F_u − P`, `D₂L_d = h/2 F_w + P` of the interval module.
//!
//! The Jacobian of a term with respect to the newest node follows from how its point moves
//! with the interval's right end ([`Point::slopes`]): with `∂x/∂w = c_x` and `h ∂v/∂w = c_v`,
//! `h ∂(w_p p + w_f h f)/∂w = w_p (c_x h L_vx + c_v L_vv) + w_f (c_x h² L_xx + c_v h L_xv)`
//! ([`BlockWeights`]), with `L_vx = L_xvᵀ`. The step Jacobian `h J = h ∂G/∂y` sums it over the
//! equation's terms.

use super::StepKind;

/// Where a term is evaluated on the interval `[u, w]` (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Point {
    /// `(u, (w − u)/h, t_u)`.
    Left,
    /// `((u + w)/2, (w − u)/h, (t_u + t_w)/2)`.
    Middle,
    /// `(w, (w − u)/h, t_w)`.
    Right,
    /// `(u, (w − a)/(2h), t_u)` with `a` the node before `u`.
    Centred,
}

impl Point {
    /// `(∂x/∂w, h ∂v/∂w)`: how the point's position and velocity move with the interval's
    /// right end `w`, the newest node of a step.
    #[inline(always)]
    pub const fn slopes(self) -> (f64, f64) {
        match self {
            Point::Left => (0.0, 1.0),
            Point::Middle => (0.5, 1.0),
            Point::Right => (1.0, 1.0),
            Point::Centred => (0.0, 0.5),
        }
    }

    /// The point's time on an interval with end times `t_u`, `t_w`.
    #[inline(always)]
    pub fn time(self, t_u: f64, t_w: f64) -> f64 {
        match self {
            Point::Left | Point::Centred => t_u,
            Point::Middle => 0.5 * (t_u + t_w),
            Point::Right => t_w,
        }
    }
}

/// One term `w_p p + w_f h f` at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Term {
    /// Where `p` and `f` are evaluated.
    pub point: Point,
    /// The weight `w_p` of `p = ∂L/∂v`.
    pub p: f64,
    /// The weight `w_f` of `h f`, `f = ∂L/∂x`.
    pub f: f64,
}

/// The weights of the second-derivative blocks in `h ∂(w_p p + w_f h f)/∂w` (module docs):
/// `xx L_xx + xv L_xv + vx L_vx + vv L_vv`, with `L_vx = L_xvᵀ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlockWeights {
    /// Of `L_xx`.
    pub xx: f64,
    /// Of `L_xv`.
    pub xv: f64,
    /// Of `L_vx = L_xvᵀ`.
    pub vx: f64,
    /// Of `L_vv`.
    pub vv: f64,
}

impl Term {
    /// The weights of the blocks at this term's point in `h ∂term/∂w`, for step `h`.
    #[inline(always)]
    pub fn block_weights(&self, h: f64) -> BlockWeights {
        let (c_x, c_v) = self.point.slopes();
        // A zero weight is an exact 0, decided on the constants alone (`0 · h` would not fold
        // away), so that a step of a kind known at compile time never computes a block it
        // does not read.
        let scaled = |c: f64, s: f64| if c == 0.0 { 0.0 } else { c * s };
        BlockWeights {
            xx: scaled(self.f * c_x, h * h),
            xv: scaled(self.f * c_v, h),
            vx: scaled(self.p * c_x, h),
            vv: self.p * c_v,
        }
    }
}

/// Up to three terms, held by value so that a step of a kind known at compile time reads its
/// weights as constants: each table's arms are `const` blocks, evaluated by the compiler.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Terms {
    items: [Term; 3],
    len: usize,
}

impl Terms {
    #[inline(always)]
    const fn of<const N: usize>(terms: [Term; N]) -> Self {
        let unused = Term {
            point: Point::Left,
            p: 0.0,
            f: 0.0,
        };
        let mut items = [unused; 3];
        let mut k = 0;
        while k < N {
            items[k] = terms[k];
            k += 1;
        }
        Terms { items, len: N }
    }

    /// The first term (every kind has one): read without a bounds check, so that a step of a
    /// kind not known at compile time has no panic path in its loop.
    #[inline(always)]
    pub fn first(&self) -> Term {
        self.items[0]
    }

    /// The terms, in the order the table lists them.
    #[inline(always)]
    pub fn as_slice(&self) -> &[Term] {
        &self.items[..self.len]
    }

    /// Whether some term reads the block of `weight` for step `h` (the block then enters the
    /// step Jacobian).
    pub fn reads(&self, h: f64, weight: impl Fn(&BlockWeights) -> f64) -> bool {
        self.as_slice()
            .iter()
            .any(|term| weight(&term.block_weights(h)) != 0.0)
    }
}

const fn term(point: Point, p: f64, f: f64) -> Term {
    Term { point, p, f }
}

/// The terms of the momentum `π` of `kind`, on `[a, b]` (module docs).
#[inline(always)]
pub const fn momentum_terms(kind: StepKind) -> Terms {
    use Point::*;
    match kind {
        StepKind::VariationalBackward => const { Terms::of([term(Right, 1.0, 1.0)]) },
        StepKind::VariationalForward => const { Terms::of([term(Left, 1.0, 0.0)]) },
        StepKind::DirectBackward => const { Terms::of([term(Right, 1.0, 0.0)]) },
        StepKind::DirectForward => const { Terms::of([term(Left, 1.0, 1.0)]) },
        StepKind::MidpointVariational => const { Terms::of([term(Middle, 1.0, 0.5)]) },
        StepKind::MidpointDirect => const { Terms::of([term(Middle, 1.0, 0.0)]) },
        StepKind::TrapezoidalVariational => {
            const { Terms::of([term(Left, 0.5, 0.0), term(Right, 0.5, 0.5)]) }
        }
        StepKind::TrapezoidalDirect => {
            const { Terms::of([term(Left, 0.5, 0.0), term(Right, 0.5, 0.0)]) }
        }
    }
}

/// The terms of the step equation `G(y)` of `kind`, on `[b, y]` (module docs).
#[inline(always)]
pub const fn equation_terms(kind: StepKind) -> Terms {
    use Point::*;
    match kind {
        StepKind::VariationalBackward => const { Terms::of([term(Right, 1.0, 0.0)]) },
        StepKind::VariationalForward => const { Terms::of([term(Left, 1.0, -1.0)]) },
        StepKind::DirectBackward => const { Terms::of([term(Right, 1.0, -1.0)]) },
        StepKind::DirectForward => const { Terms::of([term(Left, 1.0, 0.0)]) },
        StepKind::MidpointVariational => const { Terms::of([term(Middle, 1.0, -0.5)]) },
        StepKind::MidpointDirect => {
            const { Terms::of([term(Middle, 1.0, 0.0), term(Centred, 0.0, -1.0)]) }
        }
        StepKind::TrapezoidalVariational => {
            const { Terms::of([term(Left, 0.5, -0.5), term(Right, 0.5, 0.0)]) }
        }
        StepKind::TrapezoidalDirect => {
            const {
                Terms::of([
                    term(Left, 0.5, 0.0),
                    term(Right, 0.5, 0.0),
                    term(Centred, 0.0, -1.0),
                ])
            }
        }
    }
}
