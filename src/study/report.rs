//! Writing results: whole or not at all (a temporary file renamed into place), by rank 0.

use std::path::Path;

/// Writes `contents` to `path` whole or not at all, creating its folder.
pub fn write_atomically(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    crate::atomic_file::write(path, contents)
}

/// An error every rank has (same input, same check): rank 0 reports it once and every rank
/// exits with failure, no abort needed.
#[derive(Debug, thiserror::Error)]
#[error("{0:#}")]
pub struct Collective(pub anyhow::Error);

/// Makes a per-rank result collective: if any rank failed, every rank returns an error
/// (its own, or "failed on another rank"), marked [`Collective`]. Collective call.
pub fn collective<T, E>(comm: crate::petsc::Comm, local: Result<T, E>) -> anyhow::Result<T>
where
    E: Into<anyhow::Error>,
{
    let ok = comm.all(local.is_ok());
    match local {
        Ok(v) if ok => Ok(v),
        Ok(_) => Err(Collective(anyhow::anyhow!("failed on another rank")).into()),
        Err(e) => Err(Collective(e.into()).into()),
    }
}
