//! The project's own rules: the module graph (imports one way, files under 600 lines) and the public API snapshot. One test binary for the group.

mod guide_pages;
mod module_graph;
mod public_api;
