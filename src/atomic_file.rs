//! Results are written whole or not at all: into a temporary file in the same folder, synced,
//! then renamed over the target. A reader never sees half a file, and a failed write (or a
//! panic) leaves the old file (or none) and no temporary behind. Every writer of squeal goes
//! through here.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Writes `path` with what `fill` writes into a buffered temporary file.
pub fn write_with(
    path: &Path,
    fill: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let name = path.file_name().ok_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "expected a file name to write to",
        )
    })?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if !dir.is_dir() {
            // "Does not exist" was said of a file in the folder's place too.
            let why = if dir.exists() {
                format!("{} is a file, not a folder", dir.display())
            } else {
                format!("folder {} does not exist", dir.display())
            };
            return Err(std::io::Error::new(std::io::ErrorKind::NotFound, why));
        }
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    // tempfile gives a unique hidden name created exclusively (two runs writing one folder
    // cannot clobber each other's temporary), and removes it on every early return or
    // panic: only `persist` keeps it, under the final name.
    let temp = tempfile::Builder::new()
        .prefix(&format!(".{}.", name.to_string_lossy()))
        .suffix(".tmp")
        .tempfile_in(dir)?;
    let mut out = BufWriter::new(temp.as_file().try_clone()?);
    fill(&mut out)?;
    out.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    temp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// Writes `contents` to `path` atomically.
pub fn write(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    write_with(path, |out| out.write_all(contents))
}
