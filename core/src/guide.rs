// The pages of the guide, one module each. The markdown files under `core/docs/` are the
// source: GitHub renders them as they are, rustdoc shows them here and runs their `rust`
// blocks as doctests.
//
// The pages link to each other by reference (`[schemes.md][schemes]`, with
// `[schemes]: schemes.md` at the bottom of the page), which GitHub resolves to the file next
// door. Each module's docs start with `guide_links!()` (lib.rs), the same labels defined as
// intra-doc links: markdown uses the first definition of a label, so rustdoc links the modules,
// and `-D warnings` fails on a broken one. `tests/tests/project/guide_pages.rs` checks that every label
// a page uses is defined there.

#[doc = guide_links!()]
#[doc = include_str!("../docs/conventions.md")]
pub mod conventions {}

#[doc = guide_links!()]
#[doc = include_str!("../docs/schemes.md")]
pub mod schemes {}

#[doc = guide_links!()]
#[doc = include_str!("../docs/solvers.md")]
pub mod solvers {}

#[doc = guide_links!()]
#[doc = include_str!("../docs/forces.md")]
pub mod forces {}

#[doc = guide_links!()]
#[doc = include_str!("../docs/choosing.md")]
pub mod choosing {}

#[doc = guide_links!()]
#[doc = include_str!("../docs/macro.md")]
pub mod lagrangian_macro {}

#[doc = guide_links!()]
#[doc = include_str!("../docs/architecture.md")]
pub mod architecture {}
