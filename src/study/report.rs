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
/// (its own, or [`StudyError::OnAnotherRank`]), marked [`StudyError::Collective`].
/// Collective call.
pub fn collective<T, E>(comm: crate::petsc::Comm, local: Result<T, E>) -> Result<T, StudyError>
where
    E: Into<StudyError>,
{
    let ok = comm.all(local.is_ok());
    match local {
        Ok(v) if ok => Ok(v),
        Ok(_) => Err(StudyError::OnAnotherRank.collective()),
        Err(e) => Err(e.into().collective()),
    }
}
