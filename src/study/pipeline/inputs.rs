//! What a study's mesh file brings into the stage keys: its own bytes and, for an Abaqus or
//! CalculiX deck, the bytes of every file it reads through an `INPUT=` parameter (`*INCLUDE`,
//! `*NODE, INPUT=...`, ...), recursively, relative to the file that names it as the reader
//! resolves them. An edited included file then changes every key, as an edited deck does.

use crate::mesh::hash::bytes_hash;
use std::path::{Path, PathBuf};

/// Includes nested deeper than this are the reader's to refuse; the key stops following.
const MAX_DEPTH: usize = 32;

/// A hash of `path` and of every file it includes (in the order met), or why one cannot be
/// read.
pub fn mesh_files_hash(path: &Path) -> Result<String, (PathBuf, std::io::Error)> {
    let mut seen = Vec::new();
    let mut text = String::new();
    collect(path, 0, &mut seen, &mut text)?;
    Ok(bytes_hash(text.as_bytes()))
}

fn collect(
    path: &Path,
    depth: usize,
    seen: &mut Vec<PathBuf>,
    hashes: &mut String,
) -> Result<(), (PathBuf, std::io::Error)> {
    let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
    if seen.contains(&canonical) || depth > MAX_DEPTH {
        return Ok(());
    }
    seen.push(canonical);
    let bytes = crate::input_file::read(path).map_err(|e| (path.to_path_buf(), e))?;
    hashes.push_str(&bytes_hash(&bytes));
    hashes.push('\n');
    let is_deck = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("inp"));
    if !is_deck {
        return Ok(());
    }
    let dir = path.parent().unwrap_or(Path::new(""));
    for name in input_parameters(&String::from_utf8_lossy(&bytes)) {
        collect(&dir.join(name), depth + 1, seen, hashes)?;
    }
    Ok(())
}

/// The `INPUT=` values of a deck's keyword lines (`*...`, not `**` comments).
fn input_parameters(deck: &str) -> Vec<String> {
    deck.lines()
        .map(str::trim_start)
        .filter(|l| l.starts_with('*') && !l.starts_with("**"))
        .flat_map(|l| l.split(',').skip(1))
        .filter_map(|p| {
            let (key, value) = p.split_once('=')?;
            key.trim()
                .eq_ignore_ascii_case("INPUT")
                .then(|| value.trim().trim_matches('"').to_string())
        })
        .filter(|v| !v.is_empty())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_changed_included_file_changes_the_hash() {
        let dir = tempfile::tempdir().unwrap();
        let sub = dir.path().join("sub");
        std::fs::create_dir_all(&sub).unwrap();
        std::fs::write(
            dir.path().join("main.inp"),
            "** *INCLUDE, INPUT=ignored.inp\n*include, input=\"sub/mesh.inp\"\n",
        )
        .unwrap();
        std::fs::write(
            sub.join("mesh.inp"),
            "*NODE, INPUT=nodes.inp\n*INCLUDE, INPUT=mesh.inp\n",
        )
        .unwrap();
        std::fs::write(sub.join("nodes.inp"), "1, 0, 0, 0\n").unwrap();
        let main = dir.path().join("main.inp");
        let before = mesh_files_hash(&main).unwrap();
        assert_eq!(before, mesh_files_hash(&main).unwrap());
        // A file two includes down (and a self-include, which must not loop).
        std::fs::write(sub.join("nodes.inp"), "1, 0, 0, 1\n").unwrap();
        assert_ne!(before, mesh_files_hash(&main).unwrap());
        // A missing include names itself.
        std::fs::remove_file(sub.join("nodes.inp")).unwrap();
        let (missing, _) = mesh_files_hash(&main).unwrap_err();
        assert!(missing.ends_with("sub/nodes.inp"), "{}", missing.display());
    }

    #[test]
    fn a_gmsh_file_is_its_own_bytes() {
        let dir = tempfile::tempdir().unwrap();
        let msh = dir.path().join("m.msh");
        std::fs::write(
            &msh,
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n*INCLUDE, INPUT=x\n",
        )
        .unwrap();
        assert!(mesh_files_hash(&msh).is_ok());
    }
}
