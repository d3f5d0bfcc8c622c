//! The one error type of the matrix readers and writer. Every variant names the file; parse
//! errors name the 1-based line and what was expected there.

use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum MatrixFileError {
    /// The file could not be opened, read or written.
    #[error("{file}: {source}")]
    Io {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A line did not hold what the format requires there.
    #[error("{file}:{line}: {message}")]
    Parse {
        file: PathBuf,
        /// 1-based line number.
        line: usize,
        message: String,
    },
    /// The file (or a set of files) parsed but cannot be used as asked: unknown format,
    /// matrices of different sizes, a non-symmetric matrix to be written as symmetric...
    #[error("{file}: {message}")]
    Invalid { file: PathBuf, message: String },
}

impl MatrixFileError {
    pub(super) fn parse(file: &Path, line: usize, message: impl Into<String>) -> Self {
        MatrixFileError::Parse {
            file: file.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    pub(super) fn invalid(file: &Path, message: impl Into<String>) -> Self {
        MatrixFileError::Invalid {
            file: file.to_path_buf(),
            message: message.into(),
        }
    }

    pub(super) fn io(file: &Path, source: std::io::Error) -> Self {
        MatrixFileError::Io {
            file: file.to_path_buf(),
            source,
        }
    }
}
