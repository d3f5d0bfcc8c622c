//! What the fuzz targets share: splitting one input into several files, and a scratch folder
//! to write them in for the readers that take paths (the deck reader follows `*INCLUDE` on
//! disk; the matrix readers check a declared count against the file's size on disk).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Separates the files packed in one fuzz input. A NUL byte never appears in a text deck or
/// matrix file, so the seeds split where meant, and one mutation can add or drop a file.
pub const FILE_SEPARATOR: u8 = 0;

/// The files of one input, at most `max` (the rest stays in the last one).
pub fn split_files(data: &[u8], max: usize) -> Vec<&[u8]> {
    data.splitn(max, |&b| b == FILE_SEPARATOR).collect()
}

/// One folder per fuzzing process, under `$TMPDIR`, reused by every run (a new folder per
/// run would cost more than the reading). It is left behind when the process ends: ci/fuzz
/// points `TMPDIR` at a folder it removes.
pub fn scratch() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("squeal-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("create the scratch folder");
        dir
    })
}

/// Writes the named files in the scratch folder (and removes the other `names`, so a file
/// absent from this input is absent on disk); returns the paths of the written ones.
pub fn write_files(names: &[&str], contents: &[&[u8]]) -> Vec<PathBuf> {
    let dir = scratch();
    let mut written = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let path = dir.join(name);
        match contents.get(k) {
            Some(bytes) => {
                std::fs::write(&path, bytes).expect("write a scratch file");
                written.push(path);
            }
            None => {
                let _ = std::fs::remove_file(&path);
            }
        }
    }
    written
}
