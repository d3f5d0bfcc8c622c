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
    // Mode 0666 less the umask, as a plain File::create gives: a temporary file is made
    // 0600 (private), and results are for others to read too (a report forwarded, a
    // colleague's ParaView).
    let temp = tempfile::Builder::new()
        .prefix(&format!(".{}.", name.to_string_lossy()))
        .suffix(".tmp")
        .permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666))
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    /// A result file gets the mode a plain `File::create` gives (0666 less the umask), not
    /// the temporary file's private 0600.
    #[test]
    fn a_result_is_readable_as_a_created_file_is() {
        let dir = tempfile::tempdir().unwrap();
        let plain = dir.path().join("plain");
        File::create(&plain).unwrap();
        let written = dir.path().join("written");
        write(&written, b"x").unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&written), mode(&plain));
        assert_eq!(std::fs::read(&written).unwrap(), b"x");
    }
}
