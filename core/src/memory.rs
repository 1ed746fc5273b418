//! Allocations whose size the user's grid decides, reserved before any work: a grid too large
//! for the machine is [`Error::TooLarge`], not an abort of the process when the allocator gives
//! up (`N = 10¹⁰` nodes of a pendulum would need 80 GB).

use crate::error::{Error, Result};

/// An empty vector with room for `len` values of `T` (`what` names them in the error), or
/// [`Error::TooLarge`] when the allocator refuses. On Linux an allocation larger than the
/// memory the kernel can promise is refused at once; one that is promised but cannot be backed
/// later is the kernel's to handle.
pub(crate) fn reserve<T>(len: usize, what: &str) -> Result<Vec<T>> {
    let mut v = Vec::new();
    let bytes = (len as f64) * std::mem::size_of::<T>() as f64;
    v.try_reserve_exact(len).map_err(|_| Error::TooLarge {
        what: format!(
            "{what}: {len} values, {bytes:.1e} bytes, do not fit in memory; take a smaller N, or \
             (for a run-time-dimension model) observe the run or store every k-th node"
        ),
    })?;
    Ok(v)
}
