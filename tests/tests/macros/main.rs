//! The `#[lagrangian]` macro's derivatives, forms and impls, against independent oracles (num-dual, closed forms, hand-written models). One test binary for the group: each file is a module, so the group links once.

mod chain;
mod constraints;
mod doc_example;
mod forces;
mod forms;
mod functions;
mod guards;
mod looped_forces;
mod loops;
mod models;
mod run_time;
mod sums;
mod values;
