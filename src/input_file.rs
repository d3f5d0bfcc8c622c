//! Opening an input file (mesh, deck, `*INCLUDE`, matrix, study, super-element) only when it
//! is a regular file. A device or a pipe has no end to read to: `/dev/zero` named as a deck
//! (or a symlink to it) once filled the memory before anything could say why.

use std::fs::File;
use std::io;
use std::path::Path;

/// Refuses anything but a regular file (symlinks are followed), with a sentence.
pub fn check(path: &Path) -> io::Result<()> {
    let kind = std::fs::metadata(path)?.file_type();
    if kind.is_file() {
        Ok(())
    } else {
        let what = if kind.is_dir() {
            "a folder"
        } else {
            "a device, pipe or socket"
        };
        Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("is {what}, not a regular file"),
        ))
    }
}

/// [`File::open`] of a regular file only.
pub fn open(path: &Path) -> io::Result<File> {
    check(path)?;
    File::open(path)
}

/// [`std::fs::read`] of a regular file only.
pub fn read(path: &Path) -> io::Result<Vec<u8>> {
    check(path)?;
    std::fs::read(path)
}

/// [`std::fs::read_to_string`] of a regular file only.
pub fn read_to_string(path: &Path) -> io::Result<String> {
    check(path)?;
    std::fs::read_to_string(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_folders_and_links_to_them_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let link = dir.path().join("deck.inp");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        for (path, words) in [
            (Path::new("/dev/zero"), "device"),
            (link.as_path(), "device"),
            (dir.path(), "folder"),
        ] {
            let e = read(path).unwrap_err();
            assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
            assert!(e.to_string().contains(words), "{e}");
        }
        let file = dir.path().join("ok.txt");
        std::fs::write(&file, "x").unwrap();
        assert_eq!(read_to_string(&file).unwrap(), "x");
    }
}
