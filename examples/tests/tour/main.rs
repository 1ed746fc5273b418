//! The tour and its scenes: the tour end to end, what it prints, the report it writes and the
//! pages that cite it, and each scene's physics and orders against its oracle. One test binary
//! for the crate: each file is a module, so the examples link once.

mod choosing;
mod conservation;
mod console;
mod end_to_end;
mod fput;
mod gauss_order;
mod large_chain;
mod macro_num_dual;
mod orders;
mod readme;
