//! What `squeal compare` can fail with: a sweep folder that cannot be read or is not a
//! sweep, two sweeps without a shared friction value, a result that cannot be written.

use crate::results::DocumentError;
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    #[error("{}: {source}", file.display())]
    Read {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: not a squeal sweep.json: {message}", file.display())]
    Format { file: PathBuf, message: String },
    #[error("{}: shares no friction value with the reference {}", other.display(), reference.display())]
    NoCommonFriction { reference: PathBuf, other: PathBuf },
    #[error("writing {}: {source}", file.display())]
    Write {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl From<DocumentError> for CompareError {
    fn from(e: DocumentError) -> Self {
        match e {
            DocumentError::Read { file, source } => CompareError::Read { file, source },
            DocumentError::Format { file, message } => CompareError::Format { file, message },
        }
    }
}
