//! Integration tests of varembed live in `tests/`; this crate has no library code.
