//! Room on the stack for the const-generic path's `D × D` blocks.
//!
//! A solve of a [`Lagrangian<D>`](crate::Lagrangian) keeps its blocks in local variables: the
//! [`Hessian<D>`](crate::Hessian) the trait returns by value (three `D × D` matrices), the step
//! Jacobian and its LU factors, the Jacobian blocks of a boundary value problem. That is what
//! lets a small model's blocks live in registers and its steps allocate nothing; but at
//! `D = 256` one `Hessian<D>` is 1.5 MB, most of the 2 MiB stack of a test thread or a rayon
//! worker, and the thread overflows its stack (an abort, not an error). So each solve of the
//! const-generic path runs through [`with_room_for`]: where the thread has less room left than
//! a solve of this `D` needs, on a stack segment of its own (`stacker::grow`, mapped once per
//! solve and unmapped after it; [`Error::TooLarge`] when the system will not map it); otherwise
//! on the thread's stack, at the cost of a thread-local read and a comparison.

use crate::error::{Error, Result};

/// `D × D` blocks of room a solve gets. Measured at the test profile (opt-level 1): a solve of
/// each three-point embedding and scheme of a 256-site ring, initial and boundary value
/// problems, overflowed a segment of 64 blocks and passed with 128 (its inlined steps keep
/// many block temporaries in one frame). Twice that, as a margin: unoptimised builds, whose
/// frames are larger, were not measured. A segment is mapped read-write for its whole size
/// (128 MiB at `D = 256`, one per solve and per thread that solves at once), though only the
/// pages a solve touches are backed: under strict overcommit or a low `ulimit -v` the mapping
/// can fail: [`with_room_for`] asks first, and returns [`Error::TooLarge`] then.
const BLOCKS: usize = 256;

/// Room for everything else a solve keeps on the stack (its frames, vectors of length `D`).
const BASE: usize = 256 << 10;

/// The stack a solve of a `D`-dimensional model needs.
pub(crate) const fn room_for(d: usize) -> usize {
    let blocks = BLOCKS.saturating_mul(d).saturating_mul(d);
    BASE.saturating_add(blocks.saturating_mul(std::mem::size_of::<f64>()))
}

/// `f` with at least [`room_for`]`(D)` bytes of stack: on the thread's stack when it has them
/// left, on a new segment of that size otherwise. [`Error::TooLarge`] when the system will not
/// map a segment of that size (at `D = 4096` it is 34 GB of address space, more than a machine
/// without overcommit can promise): `stacker` would panic there.
#[inline]
pub(crate) fn with_room_for<const D: usize, R>(f: impl FnOnce() -> Result<R>) -> Result<R> {
    let room = room_for(D);
    if stacker::remaining_stack().is_some_and(|left| left >= room) {
        return f();
    }
    segment_can_be_mapped(room, D)?;
    stacker::grow(room, f)
}

/// [`Error::TooLarge`] unless a read-write mapping of `room` bytes is granted: asked the way
/// `stacker` will ask for its segment (an anonymous private mapping, read-write, charged to the
/// commit limit and to the address-space limit alike), directly from the system rather than
/// through the allocator (which may map with `MAP_NORESERVE`, keep address space after a free,
/// or touch the pages), and unmapped at once, no page touched. Two solves that probe at once
/// on two threads may both be granted and then not both be mapped: the probe narrows the
/// panic to that race, it cannot close it.
fn segment_can_be_mapped(room: usize, d: usize) -> Result<()> {
    match memmap2::MmapMut::map_anon(room) {
        Ok(_) => Ok(()),
        Err(_) => Err(Error::TooLarge {
            what: format!(
                "a solve of a `Lagrangian<{d}>` on the const-generic path: its dense {d} × {d} \
                 blocks need a stack segment of {:.1e} bytes, which the system will not map; \
                 implement `DynLagrangian` for the model (`#[lagrangian]` does, for a model \
                 written with loops) and solve it through `DynProblem`, whose blocks are sparse",
                room as f64
            ),
        }),
    }
}
