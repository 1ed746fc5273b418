//! Compile-fail cases of `#[lagrangian]`, one per file, grouped by kind, with `.stderr`
//! snapshots (regenerate with `TRYBUILD=overwrite`, then review).

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("ui/signature/*.rs");
    t.compile_fail("ui/body/*.rs");
    t.compile_fail("ui/function/*.rs");
    t.compile_fail("ui/loops/*.rs");
}
