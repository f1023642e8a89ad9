//! The one error type of the core crate.
//!
//! Every variant carries what a user needs to act on it: the file, and where the
//! file is at fault the byte offset. The binding crate maps each variant to its own
//! Python exception class, so nothing here knows about Python.

use std::io;
use std::path::{Path, PathBuf};

/// Result alias used throughout the core crate.
pub type CoreResult<T> = Result<T, CoreError>;

/// What can go wrong in the core crate.
#[derive(Debug, thiserror::Error)]
pub enum CoreError {
    /// The file does not exist.
    #[error("{path}: no such file")]
    NotFound { path: PathBuf },

    /// The operating system refused or failed an operation on the file.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: io::Error,
    },

    /// The file exists but its content is not what it should be.
    #[error("{path}: {message} (at byte {offset})")]
    Format {
        path: PathBuf,
        offset: u64,
        message: String,
    },

    /// A caller passed a value the operation cannot work with.
    #[error("{0}")]
    InvalidArgument(String),
}

impl CoreError {
    /// Wraps an I/O error about `path`, telling a missing file apart from other failures.
    pub fn io(path: &Path, source: io::Error) -> Self {
        if source.kind() == io::ErrorKind::NotFound {
            CoreError::NotFound {
                path: path.to_path_buf(),
            }
        } else {
            CoreError::Io {
                path: path.to_path_buf(),
                source,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn io_error_not_found_becomes_not_found_variant() {
        let err = CoreError::io(Path::new("/x"), io::Error::from(io::ErrorKind::NotFound));
        assert!(matches!(err, CoreError::NotFound { .. }));
        assert_eq!(err.to_string(), "/x: no such file");
    }

    #[test]
    fn format_error_names_file_and_offset() {
        let err = CoreError::Format {
            path: PathBuf::from("bag.mcap"),
            offset: 42,
            message: "bad magic".into(),
        };
        assert_eq!(err.to_string(), "bag.mcap: bad magic (at byte 42)");
    }
}
