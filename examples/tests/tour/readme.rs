//! The README's quick start and `examples/examples/quick_start.rs` are one program: the block
//! is compiled as a doctest of the core crate, the file is run by CI as an example, and this
//! test keeps them equal, so neither can drift from the other.

#[test]
fn the_readme_quick_start_is_the_quick_start_example() {
    let readme = include_str!("../../../README.md");
    let example = include_str!("../../examples/quick_start.rs");
    let section = readme
        .find("## Quick start")
        .expect("the README has a quick start");
    let start = section
        + readme[section..]
            .find("```rust\n")
            .expect("a rust block in the quick start")
        + "```rust\n".len();
    let end = start + readme[start..].find("```").expect("the block ends");
    let block = &readme[start..end];
    let program = &example[example
        .find("use varembed")
        .expect("the example starts with its imports")..];
    assert_eq!(
        block, program,
        "README.md's quick start and examples/examples/quick_start.rs differ"
    );
}

/// Every example is listed in the README, so a reader finds it.
#[test]
fn every_example_is_named_in_the_readme() {
    let readme = include_str!("../../../README.md");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).expect("examples/examples") {
        let path = entry.expect("entry").path();
        let name = path.file_stem().expect("a file name").to_string_lossy();
        assert!(
            readme.contains(&format!("`{name}`")),
            "README.md does not name the example {name}"
        );
        count += 1;
    }
    assert!(count >= 5);
}
