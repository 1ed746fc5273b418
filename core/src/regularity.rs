//! What the solvers check of a Lagrangian before a solve and along it: finite model constants,
//! input inside the Lagrangian's domain, and a `∂²L/∂v²` that is not degenerate.
//!
//! These checks turn a run that would otherwise return a meaningless curve (a degenerate
//! Lagrangian whose step Jacobians happen to be regular) or fail later under a misleading name
//! (a NaN model constant reported as a non-finite node at step 1) into a typed error that names
//! the input or the node. They run once before a solve and, along an initial value problem,
//! only where its stability check already runs, so the stepping loop does no extra work.

use crate::degenerate::degenerate_directions;
use crate::error::{Error, Location, Result};
use crate::lagrangian::{Hessian, Lagrangian, Matrix, Vector};

/// A `∂²L/∂v²` whose pivot ratio (see [`Error::DegenerateLagrangian`]) is below this is
/// degenerate. A singular matrix computed in floating point has pivots at the round-off of its
/// scale, `≈ 10⁻¹⁶`: the threshold leaves four orders of magnitude for rounding, and above it
/// the acceleration `L_vv⁻¹ (…)` keeps at least four significant digits. The step solves treat
/// a pivot as zero only below `10⁻¹⁴` of the largest entry, so a step never fails as singular
/// on a Lagrangian this check passed for a reason of `L_vv` alone.
pub(crate) const DEGENERACY_THRESHOLD: f64 = 1e-12;

/// `(min |u_ii|, max |u_ii|)` over the pivots of the LU factorisation with partial pivoting of
/// `m`; `None` when `m` is not finite. A column that is zero below the diagonal has the pivot
/// zero and is skipped.
pub(crate) fn pivot_range<const D: usize>(m: &Matrix<D>) -> Option<(f64, f64)> {
    if !m.iter().all(|c| c.is_finite()) {
        return None;
    }
    let mut m = *m;
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for col in 0..D {
        let (piv, max) = (col..D)
            .map(|r| (r, m[(r, col)].abs()))
            .fold((col, -1.0), |best, c| if c.1 > best.1 { c } else { best });
        lo = lo.min(max);
        hi = hi.max(max);
        if max == 0.0 {
            continue;
        }
        m.swap_rows(piv, col);
        for r in col + 1..D {
            let l = m[(r, col)] / m[(col, col)];
            for c in col..D {
                m[(r, c)] -= l * m[(col, c)];
            }
        }
    }
    Some((lo, hi))
}

/// The pivot ratio of `vv` against the reference scale `reference` (the largest pivot at the
/// start of the run; `0` to measure `vv` against itself), and its own largest pivot. `None`
/// when `vv` is not finite.
pub(crate) fn pivot_ratio<const D: usize>(vv: &Matrix<D>, reference: f64) -> Option<(f64, f64)> {
    let (lo, hi) = pivot_range(vv)?;
    let scale = hi.max(reference);
    let ratio = if scale > 0.0 { lo / scale } else { 0.0 };
    Some((ratio, hi))
}

/// [`Error::DegenerateLagrangian`] at `at` unless `vv` passes; otherwise its largest pivot (the
/// reference scale for the rest of a run). A non-finite `vv` is [`Error::NotFinite`] at `at`.
pub(crate) fn check_vv<const D: usize>(
    vv: &Matrix<D>,
    reference: f64,
    at: Location,
) -> Result<f64> {
    match pivot_ratio(vv, reference) {
        None => Err(Error::NotFinite { at }),
        Some((measure, _)) if measure < DEGENERACY_THRESHOLD => Err(Error::DegenerateLagrangian {
            at,
            measure,
            directions: degenerate_directions(D, |i, j| vv[(i, j)]),
        }),
        Some((_, hi)) => Ok(hi),
    }
}

/// [`Error::NonFiniteInput`] naming the first model constant (by its field name) that is NaN
/// or infinite.
pub(crate) fn check_constants<L: Lagrangian<D> + ?Sized, const D: usize>(
    lagrangian: &L,
) -> Result<()> {
    constants_finite(lagrangian.constants())
}

/// [`check_constants`] of a model's list of constants, whichever trait gave it.
fn constants_finite(constants: Vec<(&'static str, f64)>) -> Result<()> {
    match constants.into_iter().find(|(_, value)| !value.is_finite()) {
        Some((name, value)) => Err(Error::NonFiniteInput {
            what: format!("model constant `{name}` = {value}"),
        }),
        None => Ok(()),
    }
}

/// The Hessian at `(x, v, t)` when `L`, its gradient and its Hessian are all finite there:
/// whether the point lies in the Lagrangian's domain.
pub(crate) fn hessian_in_domain<L: Lagrangian<D> + ?Sized, const D: usize>(
    lagrangian: &L,
    x: &Vector<D>,
    v: &Vector<D>,
    t: f64,
) -> Option<Hessian<D>> {
    derivatives_in_domain(lagrangian, x, v, t).map(|(_, _, hs)| hs)
}

/// The Hessian at `(x, v, t)` when the momentum `∂L/∂v` and `∂²L/∂v²` are finite there and
/// neither `L` nor `∂L/∂x` is NaN: the domain check of a node whose force no equation reads
/// (see `Embedding::unread_force_end`), where `L` and `∂L/∂x` may be infinite (a forcing
/// singular at that end) but a NaN still says the point is outside the Lagrangian's domain.
pub(crate) fn kinetic_in_domain<L: Lagrangian<D> + ?Sized, const D: usize>(
    lagrangian: &L,
    x: &Vector<D>,
    v: &Vector<D>,
    t: f64,
) -> Option<Hessian<D>> {
    let (f, p, hs) = lagrangian.gradient_and_hessian(x, v, t);
    let finite = p.iter().chain(hs.vv.iter()).all(|c| c.is_finite());
    let defined = !lagrangian.value(x, v, t).is_nan() && !f.iter().any(|c| c.is_nan());
    (finite && defined).then_some(hs)
}

/// [`hessian_in_domain`] with the gradient: `(∂L/∂x, ∂L/∂v, Hessian)` from one evaluation.
fn derivatives_in_domain<L: Lagrangian<D> + ?Sized, const D: usize>(
    lagrangian: &L,
    x: &Vector<D>,
    v: &Vector<D>,
    t: f64,
) -> Option<(Vector<D>, Vector<D>, Hessian<D>)> {
    let (f, p, hs) = lagrangian.gradient_and_hessian(x, v, t);
    let finite = lagrangian.value(x, v, t).is_finite()
        && f.iter().chain(p.iter()).all(|c| c.is_finite())
        && [hs.xx, hs.xv, hs.vv]
            .iter()
            .all(|m| m.iter().all(|c| c.is_finite()));
    finite.then_some((f, p, hs))
}

/// What the checks of the initial data read of a model, on either storage: the const-generic
/// path's dense blocks ([`ConstPoint`]) or the run-time path's sparse ones and band.
pub(crate) trait InitialDataModel {
    /// The model's named constants.
    fn constants(&self) -> Vec<(&'static str, f64)>;
    /// Evaluates `L`, its gradient and its Hessian at `(x, v, t)`, keeps them, and says
    /// whether all are finite there: whether the point lies in the Lagrangian's domain.
    fn in_domain(&mut self, x: &[f64], v: &[f64], t: f64) -> bool;
    /// The pivot ratio (see [`Error::DegenerateLagrangian`]) of the `∂²L/∂v²` kept by the last
    /// [`in_domain`](Self::in_domain).
    fn vv_measure(&mut self) -> f64;
    /// The directions without inertia of that `∂²L/∂v²`, read when it is degenerate.
    fn degenerate_directions(&self) -> Vec<Vec<(usize, f64)>>;
}

/// What an initial value problem starts from, as its checks read and name it.
#[derive(Clone, Copy, Debug)]
pub(crate) enum InitialData<'a> {
    /// `q(a) = q0`, `q̇(a) = v0` at `t0`: checked there, at [`Location::Step`]`(0)`.
    Velocity {
        q0: &'a [f64],
        v0: &'a [f64],
        t0: f64,
    },
    /// The first nodes `Q_0 = q0`, `Q_1 = q1` of a grid of step `h`: checked at `Q_1` with the
    /// velocity `(Q_1 − Q_0)/h` at `t1`, where the recurrence first reads them, at
    /// [`Location::Step`]`(1)`.
    Nodes {
        q0: &'a [f64],
        q1: &'a [f64],
        t1: f64,
        h: f64,
    },
}

impl InitialData<'_> {
    /// Where the checks place these data: step 0 for `q(a)`, `q̇(a)`; step 1 for given first
    /// nodes, checked at `Q_1`.
    pub(crate) fn location(&self) -> Location {
        match self {
            InitialData::Velocity { .. } => Location::Step(0),
            InitialData::Nodes { .. } => Location::Step(1),
        }
    }
}

/// `(Q_1 − Q_0)/h` of given first nodes: divided by `h`, as the const-generic path forms it, so
/// that the checks and the run-time path's run read the same velocity.
pub(crate) fn velocity_from_nodes(q0: &[f64], q1: &[f64], h: f64) -> Vec<f64> {
    q0.iter().zip(q1).map(|(a, b)| (b - a) / h).collect()
}

/// The checks of the data an initial value problem starts from, before any step, written once
/// for both paths: finite constants and data (a bad coordinate named by its index), a point
/// inside the Lagrangian's domain (for `q(a)`, `q̇(a)`, a velocity outside it is blamed on the
/// velocity when the position with velocity zero is inside), and a non-degenerate `∂²L/∂v²`.
/// The model keeps its evaluations at the checked point, which the starts and the stability
/// checks read.
pub(crate) fn check_initial_point(
    model: &mut impl InitialDataModel,
    data: InitialData<'_>,
) -> Result<()> {
    constants_finite(model.constants())?;
    let named = match data {
        InitialData::Velocity { q0, v0, .. } => [
            ("q0", "the initial position q(a)", q0),
            ("v0", "the initial velocity q̇(a)", v0),
        ],
        InitialData::Nodes { q0, q1, .. } => [
            ("q0", "the first node Q_0", q0),
            ("q1", "the second node Q_1", q1),
        ],
    };
    for (name, what, x) in named {
        if let Some(i) = x.iter().position(|c| !c.is_finite()) {
            return Err(Error::NonFiniteInput {
                what: format!("{name}[{i}] = {} ({what})", x[i]),
            });
        }
    }
    match data {
        InitialData::Velocity { q0, v0, t0 } => {
            if !model.in_domain(q0, v0, t0) {
                let what = if model.in_domain(q0, &vec![0.0; v0.len()], t0) {
                    format!(
                        "the initial velocity q̇(a) = {} (at q(a) = {}, t = {t0})",
                        shown(v0),
                        shown(q0)
                    )
                } else {
                    format!("the initial position q(a) = {} (t = {t0})", shown(q0))
                };
                return Err(Error::OutsideDomain { what });
            }
        }
        InitialData::Nodes { q0, q1, t1, h } => {
            let v = velocity_from_nodes(q0, q1, h);
            if !model.in_domain(q1, &v, t1) {
                let what = format!(
                    "the first nodes Q_0 = {}, Q_1 = {} (velocity {})",
                    shown(q0),
                    shown(q1),
                    shown(&v)
                );
                return Err(Error::OutsideDomain { what });
            }
        }
    }
    let measure = model.vv_measure();
    if measure.is_nan() || measure < DEGENERACY_THRESHOLD {
        return Err(Error::DegenerateLagrangian {
            at: data.location(),
            measure,
            directions: model.degenerate_directions(),
        });
    }
    Ok(())
}

/// `x` for a message: every coordinate up to eight; else the first three, the last, the
/// dimension and the coordinate largest in modulus (where a value outside the domain is most
/// likely to be).
fn shown(x: &[f64]) -> String {
    match x {
        [first, second, third, .., last] if x.len() > 8 => {
            let (i, largest) = x
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
                .expect("more than eight coordinates");
            format!(
                "[{first:?}, {second:?}, {third:?}, …, {last:?}] (d = {}; largest [{i}] = {largest:?})",
                x.len()
            )
        }
        _ => format!("{x:?}"),
    }
}

/// A [`Lagrangian<D>`] under the checks of its initial data, with the derivatives of the last
/// point evaluated.
struct ConstPoint<'l, L: ?Sized, const D: usize> {
    lagrangian: &'l L,
    derivatives: Option<(Vector<D>, Vector<D>, Hessian<D>)>,
}

impl<L: Lagrangian<D> + ?Sized, const D: usize> InitialDataModel for ConstPoint<'_, L, D> {
    fn constants(&self) -> Vec<(&'static str, f64)> {
        self.lagrangian.constants()
    }
    fn in_domain(&mut self, x: &[f64], v: &[f64], t: f64) -> bool {
        let (x, v) = (
            Vector::<D>::from_column_slice(x),
            Vector::<D>::from_column_slice(v),
        );
        self.derivatives = derivatives_in_domain(self.lagrangian, &x, &v, t);
        self.derivatives.is_some()
    }
    fn vv_measure(&mut self) -> f64 {
        // Finite where kept: `in_domain` checked every block.
        let measure = self
            .derivatives
            .as_ref()
            .and_then(|(_, _, hs)| pivot_ratio(&hs.vv, 0.0));
        measure.map_or(0.0, |(ratio, _)| ratio)
    }
    fn degenerate_directions(&self) -> Vec<Vec<(usize, f64)>> {
        match &self.derivatives {
            Some((_, _, hs)) => degenerate_directions(D, |i, j| hs.vv[(i, j)]),
            None => Vec::new(),
        }
    }
}

/// [`check_initial_point`] of a [`Lagrangian<D>`] at `q(a) = q0`, `q̇(a) = v0`, `t0`. Returns
/// `(∂L/∂x, ∂L/∂v, Hessian)` there, which the starts read.
pub(crate) fn check_initial_data<L: Lagrangian<D> + ?Sized, const D: usize>(
    lagrangian: &L,
    q0: &Vector<D>,
    v0: &Vector<D>,
    t0: f64,
) -> Result<(Vector<D>, Vector<D>, Hessian<D>)> {
    let (q0, v0) = (q0.as_slice(), v0.as_slice());
    check_point(lagrangian, InitialData::Velocity { q0, v0, t0 })
}

/// [`check_initial_point`] of a [`Lagrangian<D>`]: `(∂L/∂x, ∂L/∂v, Hessian)` at the checked
/// point.
pub(crate) fn check_point<L: Lagrangian<D> + ?Sized, const D: usize>(
    lagrangian: &L,
    data: InitialData<'_>,
) -> Result<(Vector<D>, Vector<D>, Hessian<D>)> {
    let mut point = ConstPoint {
        lagrangian,
        derivatives: None,
    };
    check_initial_point(&mut point, data)?;
    point.derivatives.ok_or(Error::NotFinite {
        at: data.location(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pivot_ratio_is_scale_free_and_flags_singular_blocks() {
        let ratio = |m: Matrix<2>| pivot_ratio(&m, 0.0).unwrap().0;
        // 10⁻⁸ I is as regular as I; diag(1, 10⁻⁶) has the ratio 10⁻⁶.
        assert_eq!(ratio(Matrix::<2>::identity() * 1e-8), 1.0);
        assert!((ratio(Matrix::<2>::new(1.0, 0.0, 0.0, 1e-6)) - 1e-6).abs() < 1e-20);
        // Zero, rank one, and a permutation (regular: partial pivoting swaps the rows).
        assert_eq!(ratio(Matrix::<2>::zeros()), 0.0);
        assert_eq!(ratio(Matrix::<2>::new(1.0, 2.0, 2.0, 4.0)), 0.0);
        assert_eq!(ratio(Matrix::<2>::new(0.0, 3.0, 3.0, 0.0)), 1.0);
        // Against a reference scale: a scalar that has fallen to 10⁻¹³ of its start.
        let (r, hi) = pivot_ratio(&Matrix::<1>::new(1e-13), 1.0).unwrap();
        assert_eq!((r, hi), (1e-13, 1e-13));
        assert!(pivot_ratio(&Matrix::<1>::new(f64::NAN), 0.0).is_none());
    }

    /// The pivots of a `3 × 3` block whose LU needs a row exchange, against the factors
    /// computed by hand: `P A = L U` with `U = [[4, 2, 0], [0, 2, 1], [0, 0, −0.25]]`.
    #[test]
    fn pivots_are_those_of_lu_with_partial_pivoting() {
        let a = Matrix::<3>::new(2.0, 3.0, 1.0, 4.0, 2.0, 0.0, 1.0, 0.5, 0.0);
        // Column 0: pivot 4 (row 1). Rows become [2, 3, 1] − ½[4, 2, 0] = [0, 2, 1] and
        // [1, 0.5, 0] − ¼[4, 2, 0] = [0, 0, 0]: column 1 pivot 2, column 2 pivot 0.
        assert_eq!(pivot_range(&a), Some((0.0, 4.0)));
        let b = Matrix::<3>::new(2.0, 3.0, 1.0, 4.0, 2.0, 0.0, 1.0, 0.5, -0.25);
        assert_eq!(pivot_range(&b), Some((0.25, 4.0)));
    }
}
