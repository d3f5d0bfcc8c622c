//! Writing results: whole or not at all (a temporary file renamed into place), by rank 0.

use std::io::Write;
use std::path::Path;

/// Writes `contents` to `path` through a temporary file in the same folder, so a reader
/// never sees half a file and a failure leaves the old one (or none).
pub fn write_atomically(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    if let Some(dir) = dir {
        std::fs::create_dir_all(dir)?;
    }
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp{}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(contents)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
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
