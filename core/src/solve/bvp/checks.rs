//! The checks of a boundary value problem's input and solution that every solver of the
//! const-generic path makes: finite constants and ends, a finite guess inside the Lagrangian's
//! domain, and `∂²L/∂v²` not degenerate at the quadrature nodes of the guess and of the
//! solution. Their own module so that the fractional fast path, which `bvp` calls, can make
//! the nodes' part with the velocities of its own evaluations ([`check_nodes_with`]).

use crate::discretisation::Discretisation;
use crate::error::{Error, Location, Result, check_len};
use crate::lagrangian::{Hessian, Lagrangian, Vector};
use crate::regularity::{
    DEGENERACY_THRESHOLD, check_constants, check_vv, hessian_in_domain, kinetic_in_domain,
    pivot_range,
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
    // The blocks are checked against the largest pivot over all of them, known only at the
    // end: the first pass keeps that and the smallest pivot, and only where some block fails
    // (not finite, or its pivot ratio below the threshold) the second evaluates them again to
    // name the first that does; at N = 10⁷ a vector of the blocks is 80 MB a coordinate.
    let hessian = |i: usize, k: usize| -> Result<Hessian<D>> {
        let (vk, t) = (&v(i), grid.t(k));
        if !guess {
            return Ok(lagrangian.hessian(&q[k], vk, t));
        }
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
        })
    };
    let (mut reference, mut smallest, mut finite) = (0.0f64, f64::INFINITY, true);
    for (i, k) in rows.clone().enumerate() {
        let hs = hessian(i, k)?;
        keep(i, &hs);
        match pivot_range(&hs.vv) {
            Some((lo, hi)) => (reference, smallest) = (reference.max(hi), smallest.min(lo)),
            None => finite = false,
        }
    }
    // `check_vv`'s ratio of each block is its smallest pivot over the reference.
    if finite && reference > 0.0 && smallest / reference >= DEGENERACY_THRESHOLD {
        return Ok(());
    }
    for (i, k) in rows.enumerate() {
        check_vv(&hessian(i, k)?.vv, reference, Location::Node(first + i))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::embedding::Embedding;
    use crate::grid::Grid;
    use crate::lagrangian::Matrix;
    use crate::side::Side;

    /// `L = ½ (x − c)² v² − ½ x²`: `∂²L/∂v² = (x − c)²` vanishes where the curve passes `c`.
    struct Vanishing {
        c: f64,
    }

    impl Lagrangian<1> for Vanishing {
        fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
            let m = (x[0] - self.c).powi(2);
            0.5 * m * v[0] * v[0] - 0.5 * x[0] * x[0]
        }
        fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
            let d = x[0] - self.c;
            let f = d * v[0] * v[0] - x[0];
            (Vector::<1>::new(f), Vector::<1>::new(d * d * v[0]))
        }
        fn hessian(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> Hessian<1> {
            let d = x[0] - self.c;
            Hessian {
                xx: Matrix::<1>::new(v[0] * v[0] - 1.0),
                xv: Matrix::<1>::new(2.0 * d * v[0]),
                vv: Matrix::<1>::new(d * d),
            }
        }
    }

    /// A curve on which `∂²L/∂v²` vanishes at some nodes is reported at the first of them, in
    /// the guess's check and in the solution's (which differ in how the Hessians are
    /// evaluated), for both sides; one on which it stays away from zero passes. The blocks are
    /// not kept between the two passes of the check, so the second finds the node again.
    #[test]
    fn a_degenerate_kinetic_term_is_reported_at_its_first_node() {
        let n = 20;
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        // Nodes Q_k = k/10 − 0.5: L_vv vanishes at k = 8 (to rounding, for c = 0.3) and nowhere
        // for c = 0.33.
        let q: Vec<Vector<1>> = (0..=n)
            .map(|k| Vector::<1>::new(k as f64 / 10.0 - 0.5))
            .collect();
        // And at k = 5 as well (less so than at k = 8), on a curve with a kink there: the first
        // node is reported, not the one of the smallest pivot.
        let kinked: Vec<Vector<1>> = q
            .iter()
            .enumerate()
            .map(|(k, x)| {
                if k == 5 {
                    Vector::<1>::new(0.3 + 1e-9)
                } else {
                    *x
                }
            })
            .collect();
        for side in [Side::Backward, Side::Forward] {
            let embedding = Embedding::finite_difference(side);
            for guess in [true, false] {
                let check = |c: f64, q: &[Vector<1>]| {
                    let lagrangian = Vanishing { c };
                    let disc = Discretisation::new(&lagrangian, grid, embedding);
                    let v = disc.velocity(q).unwrap();
                    check_nodes_with(&disc, q, |i| v[i], guess, |_, _| {})
                };
                assert_eq!(check(0.33, &q), Ok(()), "{side:?}");
                for (curve, node) in [(&q, 8), (&kinked, 5)] {
                    match check(0.3, curve) {
                        Err(Error::DegenerateLagrangian { at, measure, .. }) => {
                            assert_eq!(at, Location::Node(node), "{side:?} {guess}");
                            assert!(measure < DEGENERACY_THRESHOLD, "{measure}");
                        }
                        other => panic!("{side:?} {guess}: {other:?}"),
                    }
                }
            }
        }
    }
}
