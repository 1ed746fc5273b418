//! Scenes and reports of varembed; see `examples/`.
