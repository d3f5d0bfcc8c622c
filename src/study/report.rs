//! Writing results: whole or not at all (a temporary file renamed into place), by rank 0.

use super::error::StudyError;
use std::path::Path;

/// Writes `contents` to `path` whole or not at all, creating its folder. A helper of the
/// study layer: its public functions report a failure with the path
/// ([`write_file`], [`StudyError::Write`]).
pub(super) fn write_atomically(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    crate::atomic_file::write(path, contents)
}

/// [`write_atomically`], with the file named in the error.
pub fn write_file(path: &Path, contents: &[u8]) -> Result<(), StudyError> {
    write_atomically(path, contents).map_err(|source| StudyError::write(path, source))
}

/// `value` as pretty JSON, to be written to `path` (named in the error).
pub fn json_for(path: &Path, value: &impl serde::Serialize) -> Result<Vec<u8>, StudyError> {
    serde_json::to_vec_pretty(value).map_err(|source| StudyError::JsonFile {
        path: path.to_path_buf(),
        source,
    })
}

/// Creates a folder and its parents, with the folder named in the error.
pub fn create_dir(dir: &Path) -> Result<(), StudyError> {
    std::fs::create_dir_all(dir).map_err(|source| StudyError::create_dir(dir, source))
}

/// Makes a per-rank result collective: if any rank failed, every rank returns an error
/// (its own, or the first failing rank's as [`StudyError::OnAnotherRank`]), marked
/// [`StudyError::Collective`].
/// Collective call.
pub fn collective<T, E>(comm: crate::petsc::Comm, local: Result<T, E>) -> Result<T, StudyError>
where
    E: Into<StudyError>,
{
    let local = local.map_err(Into::into);
    let first = comm.first_message(local.as_ref().err().map(chain));
    match (local, first) {
        (Ok(v), None) => Ok(v),
        (Ok(_), Some((rank, message))) => {
            Err(StudyError::OnAnotherRank { rank, message }.collective())
        }
        // Rank 0 alone prints a collective error: the first failing rank's words, so a
        // failure seen by rank 1 only is not lost.
        (Err(e), Some((rank, message))) if rank != comm.rank() => {
            drop(e);
            Err(StudyError::OnAnotherRank { rank, message }.collective())
        }
        (Err(e), _) => Err(e.collective()),
    }
}

/// An error and its causes, "what: why: why that", each cause once.
fn chain(e: &StudyError) -> String {
    let mut text = e.to_string();
    let mut source = std::error::Error::source(e);
    while let Some(cause) = source {
        let words = cause.to_string();
        if !text.ends_with(&words) {
            text = format!("{text}: {words}");
        }
        source = cause.source();
    }
    text
}
