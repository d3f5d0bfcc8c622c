//! Paths beside an output, and what stands in the way of one: the names every writer of the
//! study layer shares (staging, the output lock, the atomic writes), below all of them.

use std::path::{Path, PathBuf};

/// `<output><suffix>`, beside the output.
pub fn beside(output: &Path, suffix: &str) -> PathBuf {
    let mut name = output
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_else(|| "squeal-out".into());
    name.push(suffix);
    output.with_file_name(name)
}

/// Why no folder can be made at `path`'s parent: the nearest of its ancestors that exists is
/// a file (`-o afile/x.msh` used to say "creating afile: File exists (os error 17)").
pub fn file_among_ancestors(path: &Path) -> Option<String> {
    path.parent().and_then(not_a_folder)
}

/// Why no folder can be made at `dir`: it, or the nearest of its ancestors that exists, is
/// a file.
pub fn not_a_folder(dir: &Path) -> Option<String> {
    let existing = dir
        .ancestors()
        .filter(|a| !a.as_os_str().is_empty())
        .find(|a| std::fs::symlink_metadata(a).is_ok())?;
    (!existing.is_dir()).then(|| format!("{} is a file, not a folder", existing.display()))
}
