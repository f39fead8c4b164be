//! The error shared by every command: a file that could not be read or written, naming the path and
//! what was being done. Each command's own error enum wraps it beside its real variants.

use std::io;
use std::path::{Path, PathBuf};

/// A file operation that failed: `PATH: ACTION: CAUSE`.
#[derive(Debug, thiserror::Error)]
#[error("{}: {action}: {source}", path.display())]
pub struct FileError {
    /// The file or folder.
    pub path: PathBuf,
    /// What failed, e.g. "cannot read".
    pub action: &'static str,
    /// The operating system's reason.
    pub source: io::Error,
}

impl FileError {
    /// A closure for `map_err`: the failure of `action` on `path`.
    pub fn on<'a, E: Into<io::Error>>(
        path: &'a Path,
        action: &'static str,
    ) -> impl FnOnce(E) -> FileError + 'a {
        move |source| FileError {
            path: path.to_path_buf(),
            action,
            source: source.into(),
        }
    }
}

/// A chart that could not be drawn or written. The chart modules report their failures as text that
/// already names the file; this carries it unchanged.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct ChartError(pub String);

impl From<String> for ChartError {
    fn from(message: String) -> Self {
        ChartError(message)
    }
}

/// JSON output that could not be serialised.
#[derive(Debug, thiserror::Error)]
#[error("JSON output: {0}")]
pub struct JsonError(#[from] pub serde_json::Error);
