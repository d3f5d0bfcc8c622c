//! Writing results: whole or not at all (a temporary file renamed into place), by rank 0.

use super::error::StudyError;
use std::path::Path;

/// Writes `contents` to `path` whole or not at all, creating its folder. A helper of the
/// study layer: its public functions report a failure with the path
/// ([`write_file`], [`StudyError::Write`]).
pub(super) fn write_atomically(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        create_dir_all(dir)?;
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
    create_dir_all(dir).map_err(|source| StudyError::create_dir(dir, source))
}

/// [`std::fs::create_dir_all`], saying which file is in the way instead of the OS's "File
/// exists (os error 17)" or "Not a directory (os error 20)".
pub(super) fn create_dir_all(dir: &Path) -> std::io::Result<()> {
    match super::paths::not_a_folder(dir) {
        Some(why) => Err(std::io::Error::new(std::io::ErrorKind::InvalidInput, why)),
        None => std::fs::create_dir_all(dir),
    }
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

/// Runs `write` on rank 0 alone and shares how it went: a failed write (a file in the way,
/// a full disc) is then every rank's error, said once by rank 0, and no rank has to abort
/// the others (`compare`, `bench` and `--write-study` ended in an MPI_ABORT banner).
/// Collective.
pub fn on_root(
    comm: crate::petsc::Comm,
    write: impl FnOnce() -> Result<(), StudyError>,
) -> Result<(), StudyError> {
    let local = if comm.rank() == 0 { write() } else { Ok(()) };
    collective(comm, local)
}

/// Why no file can be written at `path`: it is a folder, or the nearest of its ancestors
/// that exists is a file. Checked before the work whose result it is to hold.
pub fn output_file_problem(path: &Path) -> Option<String> {
    if path.is_dir() {
        Some(format!("{} is a folder", path.display()))
    } else {
        super::paths::file_among_ancestors(path)
    }
}

/// Refuses, on every rank alike, an output file that cannot be written (see
/// [`output_file_problem`]), before the work whose result it is to hold. Collective.
pub fn check_output_file(comm: crate::petsc::Comm, path: &Path) -> Result<(), StudyError> {
    on_root(comm, || match output_file_problem(path) {
        Some(why) => Err(StudyError::OutputInTheWay {
            path: path.to_path_buf(),
            why,
        }),
        None => Ok(()),
    })
}

/// A kind of file in words and how to recognise one.
pub type FileKind<'a> = (&'a str, fn(&Path) -> bool);

/// Refuses, on every rank alike, an output file that is an input of the run (or a folder
/// holding one), or that exists and is not what `is_kind` recognises (`kind` in words): an
/// output replaces only a file of its own kind, never what the run reads. Collective.
pub fn check_output_file_owner(
    comm: crate::petsc::Comm,
    path: &Path,
    inputs: &[std::path::PathBuf],
    kind: Option<FileKind>,
) -> Result<(), StudyError> {
    on_root(comm, || {
        let in_the_way = |why: String| StudyError::OutputInTheWay {
            path: path.to_path_buf(),
            why,
        };
        if let Some(why) = super::ownership::input_problem(path, inputs) {
            return Err(in_the_way(why));
        }
        match kind {
            Some((kind, is_kind)) if path.is_file() && !is_kind(path) => Err(in_the_way(format!(
                "it exists and is not {kind}, which is all this command replaces"
            ))),
            _ => Ok(()),
        }
    })
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
