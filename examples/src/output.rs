//! Where the tour writes, decided when it runs (never when it was compiled), and the one error
//! type of everything it writes: each failure names the file or folder it was about.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

/// A failure to write the report, with the path it concerns.
#[derive(Debug)]
pub enum OutputError {
    /// A file-system operation on `path` failed.
    Io {
        /// What was being done (`create folder`, `write`, `read`).
        action: &'static str,
        /// The file or folder.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
    /// A figure could not be drawn into `path`.
    Plot {
        /// The SVG file.
        path: PathBuf,
        /// The plotting library's message.
        message: String,
    },
    /// A file the documentation update rewrites lacks its markers (left untouched).
    Markers {
        /// The file.
        path: PathBuf,
        /// The start marker that was looked for.
        start: &'static str,
    },
    /// `--update-docs` was asked for outside a checkout of the repository.
    NoCheckout {
        /// The folder the search started from.
        from: PathBuf,
    },
}

impl fmt::Display for OutputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OutputError::Io {
                action,
                path,
                source,
            } => write!(f, "could not {action} {}: {source}", path.display()),
            OutputError::Plot { path, message } => {
                write!(f, "could not draw {}: {message}", path.display())
            }
            OutputError::Markers { path, start } => write!(
                f,
                "{} lacks the markers {start} … (or they are out of order); it was not changed",
                path.display()
            ),
            OutputError::NoCheckout { from } => write!(
                f,
                "no varembed checkout (a Cargo.toml with [workspace] next to README.md) at or \
                 above {}: --update-docs rewrites the repository's README.md and report/",
                from.display()
            ),
        }
    }
}

impl std::error::Error for OutputError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            OutputError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// `Result` of the report's writers.
pub type Result<T> = std::result::Result<T, OutputError>;

/// Attaches `path` and `action` to an I/O result.
pub fn at<T>(action: &'static str, path: &Path, result: io::Result<T>) -> Result<T> {
    result.map_err(|source| OutputError::Io {
        action,
        path: path.to_path_buf(),
        source,
    })
}

/// `std::fs::create_dir_all`, naming the folder on failure.
pub fn create_dir_all(dir: &Path) -> Result<()> {
    at("create folder", dir, std::fs::create_dir_all(dir))
}

/// `std::fs::write`, naming the file on failure.
pub fn write(path: &Path, contents: impl AsRef<[u8]>) -> Result<()> {
    at("write", path, std::fs::write(path, contents))
}

/// `std::fs::read_to_string`, naming the file on failure.
pub fn read_to_string(path: &Path) -> Result<String> {
    at("read", path, std::fs::read_to_string(path))
}

/// The root of the Cargo workspace at or above `from`: the nearest folder whose `Cargo.toml`
/// declares `[workspace]`.
pub fn workspace_root(from: &Path) -> Option<PathBuf> {
    from.ancestors()
        .find(|dir| {
            std::fs::read_to_string(dir.join("Cargo.toml"))
                .is_ok_and(|toml| toml.lines().any(|l| l.trim() == "[workspace]"))
        })
        .map(Path::to_path_buf)
}

/// The default output folder when the tour runs in `cwd`: `target/varembed-report` (or
/// `target/varembed-report-quick`) under the workspace containing `cwd` — ignored by git —, or
/// under `cwd` itself outside any workspace (e.g. a binary installed with `cargo install`).
pub fn default_dir(cwd: &Path, quick: bool) -> PathBuf {
    let base = workspace_root(cwd).unwrap_or_else(|| cwd.to_path_buf());
    let name = if quick {
        "varembed-report-quick"
    } else {
        "varembed-report"
    };
    base.join("target").join(name)
}

/// The checkout whose documents `--update-docs` rewrites: the workspace at or above `cwd`, if
/// it has a `README.md`.
pub fn checkout_root(cwd: &Path) -> Result<PathBuf> {
    workspace_root(cwd)
        .filter(|root| root.join("README.md").is_file())
        .ok_or_else(|| OutputError::NoCheckout {
            from: cwd.to_path_buf(),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_io_error_names_its_path() {
        let missing = std::env::temp_dir().join("varembed-no-such-folder-x9/README.md");
        let error = read_to_string(&missing).unwrap_err();
        let text = error.to_string();
        assert!(text.contains(&missing.display().to_string()), "{text}");
        assert!(text.starts_with("could not read "), "{text}");
    }

    #[test]
    fn the_default_folder_is_under_the_workspace_target() {
        let here = Path::new(env!("CARGO_MANIFEST_DIR"));
        let root = workspace_root(here).expect("the examples crate is in the workspace");
        assert_eq!(Some(root.as_path()), here.parent());
        assert_eq!(
            default_dir(&here.join("src"), false),
            root.join("target/varembed-report")
        );
        let outside = Path::new("/");
        assert_eq!(
            default_dir(outside, true),
            Path::new("/target/varembed-report-quick")
        );
    }
}
