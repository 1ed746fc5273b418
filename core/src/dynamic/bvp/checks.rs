//! The checks around a boundary value solve of a run-time-dimension model, in the
//! const-generic order: the model and the guess before it (lengths, finite values, the domain,
//! a regular `∂²L/∂v²`), and `∂²L/∂v²` again on the solution.

use crate::error::{Error, Location, Result, check_len};
use crate::regularity::DEGENERACY_THRESHOLD;

use crate::dynamic::DynLagrangian;
use crate::dynamic::band::BandSystem;
use crate::dynamic::rows::DynRows;
use crate::dynamic::sparse::SparseHessian;

/// The model at its dimension, with finite constants.
pub(crate) fn check_model<L: DynLagrangian + ?Sized>(l: &L) -> Result<()> {
    if let Some(reason) = l.invalid_dimension() {
        return Err(Error::InvalidModel { reason });
    }
    if let Some((name, value)) = l.constants().into_iter().find(|c| !c.1.is_finite()) {
        return Err(Error::NonFiniteInput {
            what: format!("model constant `{name}` = {value}"),
        });
    }
    Ok(())
}

/// The checks before the solve, in the const-generic order: the guess's length, finite
/// constants, finite ends (named as the ends), a finite guess, every guess node in the
/// Lagrangian's domain and `∂²L/∂v²` not degenerate there.
pub(crate) fn check_input<L: DynLagrangian + ?Sized>(
    rows: &DynRows<'_, L>,
    guess: &[f64],
) -> Result<()> {
    let (grid, d) = (rows.grid, rows.d);
    let n = grid.n();
    if d > 0 && !guess.len().is_multiple_of(d) {
        return Err(Error::WrongDimension {
            what: "initial guess",
            dimension: d,
            found: guess.len(),
        });
    }
    check_len(
        "discrete curve Q",
        n + 1,
        guess.len().checked_div(d).unwrap_or(n + 1),
    )?;
    check_model(rows.lagrangian)?;
    let non_finite = |k: usize| {
        guess[k * d..(k + 1) * d]
            .iter()
            .position(|c| !c.is_finite())
    };
    for (k, end, at) in [(0, "a", grid.a()), (n, "b", grid.b())] {
        if let Some(i) = non_finite(k) {
            return Err(Error::NonFiniteInput {
                what: format!(
                    "the end value Q_{k} at {end} = {at}: component {i} is {}",
                    guess[k * d + i]
                ),
            });
        }
    }
    if let Some((k, i)) = (0..=n).find_map(|k| non_finite(k).map(|i| (k, i))) {
        return Err(Error::NonFiniteInput {
            what: format!("Q_{k}[{i}] = {}", guess[k * d + i]),
        });
    }
    check_nodes(rows, guess, true)
}

/// `∂²L/∂v²` not degenerate at the quadrature nodes of `q` (with its discrete velocity),
/// measured against its largest pivot over those nodes; for an initial `guess`, each node also
/// inside the Lagrangian's domain ([`Error::OutsideDomain`]).
pub(crate) fn check_nodes<L: DynLagrangian + ?Sized>(
    rows: &DynRows<'_, L>,
    q: &[f64],
    guess: bool,
) -> Result<()> {
    let (l, grid, d) = (rows.lagrangian, rows.grid, rows.d);
    let n = grid.n();
    let (mut v, mut f, mut p) = (vec![0.0; d], vec![0.0; d], vec![0.0; d]);
    let mut hessian = SparseHessian::new(d);
    let mut system: Option<BandSystem> = None;
    let mut pivots = Vec::with_capacity(n);
    for k in rows.quadrature_rows() {
        let (x, t) = (&q[k * d..(k + 1) * d], grid.t(k));
        rows.velocity_at(q, k, &mut v);
        hessian.clear();
        l.hessian(x, &v, t, &mut hessian);
        if guess {
            l.force(x, &v, t, &mut f);
            l.momentum(x, &v, t, &mut p);
            let finite = l.value(x, &v, t).is_finite()
                && f.iter().chain(&p).all(|c| c.is_finite())
                && hessian.is_finite();
            if !finite {
                let node = match k {
                    0 => "the end value Q_0 at a".to_string(),
                    k if k == n => format!("the end value Q_{k} at b"),
                    k => format!("node Q_{k} of the initial guess"),
                };
                return Err(Error::OutsideDomain { what: node });
            }
        } else if !hessian.vv.entries().iter().all(|e| e.2.is_finite()) {
            return Err(Error::NotFinite {
                at: Location::Node(k),
            });
        }
        pivots.push((k, vv_pivots(l, &hessian, &mut system)));
    }
    let reference = pivots.iter().fold(0.0f64, |m, (_, (_, hi))| m.max(*hi));
    for &(k, (lo, hi)) in &pivots {
        let scale = hi.max(reference);
        let measure = if scale > 0.0 { lo / scale } else { 0.0 };
        if measure < DEGENERACY_THRESHOLD {
            // The error's path only: the block again, at the degenerate node, for its
            // directions.
            rows.velocity_at(q, k, &mut v);
            hessian.clear();
            l.hessian(&q[k * d..(k + 1) * d], &v, grid.t(k), &mut hessian);
            return Err(Error::DegenerateLagrangian {
                at: Location::Node(k),
                measure,
                directions: hessian.vv.degenerate_directions(),
            });
        }
    }
    Ok(())
}

/// The smallest and largest pivot of `∂²L/∂v²` (the block `vv` of `hessian`), factorised as a
/// band in the order `system` plans (planned again when an entry falls outside it); `(0, 0)`
/// when singular.
fn vv_pivots<L: DynLagrangian + ?Sized>(
    l: &L,
    hessian: &SparseHessian,
    system: &mut Option<BandSystem>,
) -> (f64, f64) {
    let d = l.dimension();
    for _ in 0..2 {
        let band = system
            .get_or_insert_with(|| BandSystem::plan(d, l.hessian_bandwidth(), &[&hessian.vv]));
        band.clear();
        let fits = hessian
            .vv
            .entries()
            .iter()
            .all(|&(i, j, value)| band.add(i, j, value).is_ok());
        if !fits {
            *system = Some(BandSystem::plan(d, None, &[&hessian.vv]));
            continue;
        }
        return if band.factorize() {
            band.pivot_range()
        } else {
            (0.0, 0.0)
        };
    }
    (0.0, 0.0)
}
