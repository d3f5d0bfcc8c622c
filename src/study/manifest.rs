//! What a cached result held when it was made, file by file, so that a rerun uses it only
//! if it still holds exactly that (issue 30, class 2). Before, a study stage counted as
//! cached when its record's key matched and its `sweep.json` was a file: edited
//! eigenvalues, a `sweep.json` swapped with another stage's, two points' files exchanged
//! or a deleted `cea.json` were all reported as results with exit status 0, and a
//! truncated `sweep.json` failed every rerun with a bare JSON error.
//!
//! A manifest lists every file under a folder with its length and FNV-1a hash (the hash
//! the super-element files use: it finds any change that is not made on purpose to fool it,
//! which is what a cache must survive: editors, copies, truncation, mix-ups).

use crate::mesh::hash::bytes_hash;
use std::path::Path;

/// Every file under a folder: (path relative to it with `/` separators, length, hash),
/// sorted by path.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Manifest {
    pub files: Vec<(String, u64, String)>,
}

impl Manifest {
    /// The manifest of `dir` as it is now.
    pub fn of(dir: &Path) -> std::io::Result<Manifest> {
        let mut files = Vec::new();
        collect(dir, "", &mut files)?;
        files.sort();
        Ok(Manifest { files })
    }

    /// Why `dir` no longer holds what this manifest lists (the first difference, in
    /// words), if it does not.
    pub fn check(&self, dir: &Path) -> Option<String> {
        let now = match Manifest::of(dir) {
            Ok(m) => m,
            Err(e) => return Some(format!("{} cannot be read ({e})", dir.display())),
        };
        for (path, length, hash) in &self.files {
            match now.files.iter().find(|f| &f.0 == path) {
                None => return Some(format!("{path} is missing")),
                Some((_, l, _)) if l != length => {
                    return Some(format!("{path} has {l} bytes, {length} when it was made"))
                }
                Some((_, _, h)) if h != hash => {
                    return Some(format!("{path} changed since it was made"))
                }
                Some(_) => {}
            }
        }
        now.files
            .iter()
            .find(|f| !self.files.iter().any(|g| g.0 == f.0))
            .map(|(path, _, _)| format!("{path} was not there when it was made"))
    }
}

fn collect(dir: &Path, prefix: &str, out: &mut Vec<(String, u64, String)>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let relative = format!("{prefix}{name}");
        if entry.file_type()?.is_dir() {
            collect(&entry.path(), &format!("{relative}/"), out)?;
        } else {
            let bytes = std::fs::read(entry.path())?;
            out.push((relative, bytes.len() as u64, bytes_hash(&bytes)));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn any_change_of_a_folder_is_found_and_named() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir_all(d.join("mu_0.300")).unwrap();
        std::fs::create_dir_all(d.join("mu_0.600")).unwrap();
        std::fs::write(d.join("sweep.json"), b"{\"a\": 1}").unwrap();
        std::fs::write(d.join("mu_0.300/cea.json"), b"[0.3]").unwrap();
        std::fs::write(d.join("mu_0.600/cea.json"), b"[0.6]").unwrap();
        let m = Manifest::of(d).unwrap();
        assert_eq!(m.files.len(), 3);
        assert_eq!(m.check(d), None);
        // An edit of the same length.
        std::fs::write(d.join("sweep.json"), b"{\"a\": 2}").unwrap();
        assert!(m.check(d).unwrap().contains("sweep.json changed"));
        std::fs::write(d.join("sweep.json"), b"{\"a\": 1}").unwrap();
        // Truncated.
        std::fs::write(d.join("sweep.json"), b"{\"a\"").unwrap();
        assert!(m.check(d).unwrap().contains("sweep.json has 4 bytes, 8"));
        std::fs::write(d.join("sweep.json"), b"{\"a\": 1}").unwrap();
        // Two points' files exchanged.
        std::fs::write(d.join("mu_0.300/cea.json"), b"[0.6]").unwrap();
        std::fs::write(d.join("mu_0.600/cea.json"), b"[0.3]").unwrap();
        assert!(m.check(d).unwrap().contains("mu_0.300/cea.json changed"));
        std::fs::write(d.join("mu_0.300/cea.json"), b"[0.3]").unwrap();
        std::fs::write(d.join("mu_0.600/cea.json"), b"[0.6]").unwrap();
        // Deleted, added.
        std::fs::remove_file(d.join("mu_0.600/cea.json")).unwrap();
        assert!(m.check(d).unwrap().contains("mu_0.600/cea.json is missing"));
        std::fs::write(d.join("mu_0.600/cea.json"), b"[0.6]").unwrap();
        std::fs::write(d.join("extra.json"), b"").unwrap();
        assert!(m.check(d).unwrap().contains("extra.json was not there"));
        std::fs::remove_file(d.join("extra.json")).unwrap();
        assert_eq!(m.check(d), None);
        assert!(m.check(&d.join("gone")).unwrap().contains("cannot be read"));
    }
}
