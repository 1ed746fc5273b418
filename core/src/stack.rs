//! Room on the stack for the const-generic path's `D × D` blocks.
//!
//! A solve of a [`Lagrangian<D>`](crate::Lagrangian) keeps its blocks in local variables: the
//! [`Hessian<D>`](crate::Hessian) the trait returns by value (three `D × D` matrices), the step
//! Jacobian and its LU factors, the Jacobian blocks of a boundary value problem. That is what
//! lets a small model's blocks live in registers and its steps allocate nothing; but at
//! `D = 256` one `Hessian<D>` is 1.5 MB, most of the 2 MiB stack of a test thread or a rayon
//! worker, and the thread overflows its stack (an abort, not an error). So each solve of the
//! const-generic path runs through [`with_room_for`]: where the thread has less room left than
//! a solve of this `D` needs, on a stack segment of its own (`stacker::maybe_grow`, allocated
//! once per solve and freed after it); otherwise on the thread's stack, at the cost of a
//! thread-local read and a comparison.

/// `D × D` blocks of room a solve gets. Measured at the test profile (opt-level 1): a solve of
/// each three-point embedding and scheme of a 256-site ring, initial and boundary value
/// problems, overflowed a segment of 64 blocks and passed with 128 (its inlined steps keep
/// many block temporaries in one frame). Twice that, as a margin: unoptimised builds, whose
/// frames are larger, were not measured. A segment is mapped read-write for its whole size
/// (128 MiB at `D = 256`, one per solve and per thread that solves at once), though only the
/// pages a solve touches are backed: under strict overcommit or a low `ulimit -v` the mapping
/// can fail, and `stacker` then panics.
const BLOCKS: usize = 256;

/// Room for everything else a solve keeps on the stack (its frames, vectors of length `D`).
const BASE: usize = 256 << 10;

/// The stack a solve of a `D`-dimensional model needs.
pub(crate) const fn room_for(d: usize) -> usize {
    let blocks = BLOCKS.saturating_mul(d).saturating_mul(d);
    BASE.saturating_add(blocks.saturating_mul(std::mem::size_of::<f64>()))
}

/// `f` with at least [`room_for`]`(D)` bytes of stack: on the thread's stack when it has them
/// left, on a new segment of that size otherwise.
#[inline]
pub(crate) fn with_room_for<const D: usize, R>(f: impl FnOnce() -> R) -> R {
    let room = room_for(D);
    stacker::maybe_grow(room, room, f)
}
