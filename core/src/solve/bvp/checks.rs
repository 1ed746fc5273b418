//! The checks of a boundary value problem's input and solution that every solver of the
//! const-generic path makes: finite constants and ends, a finite guess inside the Lagrangian's
//! domain, and `∂²L/∂v²` not degenerate at the quadrature nodes of the guess and of the
//! solution. Their own module so that the fractional fast path, which `bvp` calls, can make
//! the nodes' part with the velocities of its own evaluations ([`check_nodes_with`]).

use crate::discretisation::Discretisation;
use crate::error::{Error, Location, Result, check_len};
use crate::lagrangian::{Hessian, Lagrangian, Vector};
use crate::regularity::{
    check_constants, check_vv, hessian_in_domain, kinetic_in_domain, pivot_range,
};

/// The checks before a boundary value problem is solved: finite constants, finite ends (each
/// named as the end it belongs to), a finite guess, every guess node inside the Lagrangian's
/// domain and `∂²L/∂v²` not degenerate there.
pub(crate) fn check_input<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    guess: &[Vector<D>],
) -> Result<()> {
    check_guess_values(disc, guess)?;
    check_nodes(disc, guess, true)
}

/// [`check_input`] but the nodes' check ([`check_nodes`]), which the fractional fast path
/// makes at its first evaluation, with the velocities it computes there.
pub(crate) fn check_guess_values<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    guess: &[Vector<D>],
) -> Result<()> {
    let grid = disc.grid();
    check_len("discrete curve Q", grid.n() + 1, guess.len())?;
    check_constants(disc.lagrangian())?;
    let last = grid.n();
    for (k, end, at) in [(0, "a", grid.a()), (last, "b", grid.b())] {
        if !guess[k].iter().all(|c| c.is_finite()) {
            return Err(Error::NonFiniteInput {
                what: format!(
                    "the end value Q_{k} at {end} = {at}: {:?}",
                    guess[k].as_slice()
                ),
            });
        }
    }
    disc.check_curve(guess)
}

/// `∂²L/∂v²` not degenerate at the quadrature nodes of `q` (with its discrete velocity),
/// measured against its largest pivot over those nodes; for an initial `guess`, each node also
/// inside the Lagrangian's domain ([`Error::OutsideDomain`]).
pub(crate) fn check_nodes<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    q: &[Vector<D>],
    guess: bool,
) -> Result<()> {
    let v = disc.velocity(q)?;
    check_nodes_with(disc, q, |i| v[i], guess, |_, _| {})
}

/// [`check_nodes`] with the velocities `v(i)` of the quadrature rows (entry `i` is the `i`-th
/// row of `I_σ`) already at hand; `keep(i, hessian)` is handed each row's second derivatives
/// as they are evaluated (for a solver whose first linearisation reads them at the same
/// point).
pub(crate) fn check_nodes_with<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    q: &[Vector<D>],
    v: impl Fn(usize) -> Vector<D>,
    guess: bool,
    mut keep: impl FnMut(usize, &Hessian<D>),
) -> Result<()> {
    let (grid, lagrangian) = (disc.grid(), disc.lagrangian());
    let rows = disc.embedding().quadrature_rows(grid.n());
    let unread = disc.embedding().unread_force_end(grid.n());
    let first = *rows.start();
    let mut blocks = Vec::with_capacity(rows.clone().count());
    for (i, k) in rows.enumerate() {
        let (vk, t) = (&v(i), grid.t(k));
        let hs = if guess {
            let in_domain = if unread == Some(k) {
                kinetic_in_domain(lagrangian, &q[k], vk, t)
            } else {
                hessian_in_domain(lagrangian, &q[k], vk, t)
            };
            in_domain.ok_or_else(|| {
                let node = match k {
                    0 => format!("the end value Q_0 = {:?} at a", q[k].as_slice()),
                    k if k == grid.n() => {
                        format!("the end value Q_{k} = {:?} at b", q[k].as_slice())
                    }
                    k => format!("node Q_{k} = {:?} of the initial guess", q[k].as_slice()),
                };
                Error::OutsideDomain {
                    what: format!("{node} (velocity {:?})", vk.as_slice()),
                }
            })?
        } else {
            lagrangian.hessian(&q[k], vk, t)
        };
        keep(i, &hs);
        blocks.push(hs.vv);
    }
    let reference = blocks
        .iter()
        .filter_map(pivot_range)
        .fold(0.0, |m, (_, hi)| f64::max(m, hi));
    for (i, vv) in blocks.iter().enumerate() {
        check_vv(vv, reference, Location::Node(first + i))?;
    }
    Ok(())
}
