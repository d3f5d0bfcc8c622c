//! Errors of the mesh stage. Every variant names the file; parse errors name the line (or
//! the byte offset in a binary section) and what was expected there.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file could not be opened or read.
    #[error("{file}: {source}")]
    Io {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A text line did not hold what the format requires there.
    #[error("{file}:{line}: {message}")]
    Parse {
        file: PathBuf,
        /// 1-based line number.
        line: usize,
        message: String,
    },
    /// A binary section did not hold what the format requires there.
    #[error("{file}: at byte {offset}: {message}")]
    Binary {
        file: PathBuf,
        offset: u64,
        message: String,
    },
    /// The file parsed, but the model it describes is not usable (inverted element, missing
    /// node reference, part without material, unknown set...).
    #[error("{file}: {message}")]
    Invalid { file: PathBuf, message: String },
}

impl MeshError {
    pub fn io(file: impl Into<PathBuf>, source: std::io::Error) -> Self {
        MeshError::Io {
            file: file.into(),
            source,
        }
    }

    pub fn parse(file: impl Into<PathBuf>, line: usize, message: impl Into<String>) -> Self {
        MeshError::Parse {
            file: file.into(),
            line,
            message: message.into(),
        }
    }

    pub fn invalid(file: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        MeshError::Invalid {
            file: file.into(),
            message: message.into(),
        }
    }
}
