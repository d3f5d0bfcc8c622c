//! The deck's lines, from the top file and the files it includes (`*INCLUDE`, `INPUT=`), each
//! with its place (file and line) for the messages.

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

use super::SourceLine;
use crate::mesh::MeshError;

/// Deeper nesting than this is surely a mistake (and a cycle is caught before it anyway).
const MAX_INCLUDE_DEPTH: usize = 32;

/// A place in the deck: index into `Lines::files` and 1-based line.
#[derive(Clone, Copy, Debug)]
pub(super) struct Loc {
    pub(super) file: u32,
    pub(super) line: u32,
}

struct OpenFile {
    reader: BufReader<File>,
    file: u32,
    line: u32,
    canonical: PathBuf,
}

pub(super) struct Lines {
    files: Vec<PathBuf>,
    stack: Vec<OpenFile>,
    bytes: Vec<u8>,
}

impl Lines {
    pub(super) fn new(path: &Path) -> Result<Self, MeshError> {
        let file = crate::input_file::open(path).map_err(|source| MeshError::Io {
            file: path.to_path_buf(),
            source,
        })?;
        Ok(Lines {
            files: vec![path.to_path_buf()],
            stack: vec![OpenFile {
                reader: BufReader::new(file),
                file: 0,
                line: 0,
                canonical: path.canonicalize().unwrap_or_else(|_| path.to_path_buf()),
            }],
            bytes: Vec::new(),
        })
    }

    pub(super) fn error(&self, loc: Loc, message: impl Into<String>) -> MeshError {
        MeshError::parse(
            self.files[loc.file as usize].clone(),
            loc.line as usize,
            message,
        )
    }

    pub(super) fn source(&self, loc: Loc) -> SourceLine {
        SourceLine {
            file: self.files[loc.file as usize].clone(),
            line: loc.line as usize,
        }
    }

    pub(super) fn at(&self, loc: Loc) -> String {
        self.source(loc).to_string()
    }

    /// Continue reading from `name` (relative to the file of `from`), then return to the
    /// line after `from`.
    pub(super) fn include(
        &mut self,
        name: &str,
        from: Loc,
        keyword: &str,
    ) -> Result<(), MeshError> {
        let including = &self.files[from.file as usize];
        let path = match including.parent() {
            Some(dir) => dir.join(name),
            None => PathBuf::from(name),
        };
        let file = crate::input_file::open(&path).map_err(|e| {
            self.error(
                from,
                format!(
                    "{keyword}: cannot open the file \"{name}\" ({}): {e}",
                    path.display()
                ),
            )
        })?;
        let canonical = path.canonicalize().unwrap_or_else(|_| path.clone());
        if self.stack.iter().any(|open| open.canonical == canonical) {
            return Err(self.error(
                from,
                format!("{keyword}: \"{name}\" is already being read (the includes form a cycle)"),
            ));
        }
        if self.stack.len() >= MAX_INCLUDE_DEPTH {
            return Err(self.error(
                from,
                format!("{keyword}: includes nested more than {MAX_INCLUDE_DEPTH} deep"),
            ));
        }
        let index = u32::try_from(self.files.len())
            .map_err(|_| self.error(from, "too many included files"))?;
        self.files.push(path);
        self.stack.push(OpenFile {
            reader: BufReader::new(file),
            file: index,
            line: 0,
            canonical,
        });
        Ok(())
    }

    /// The next line (untrimmed) into `buf`, or `None` at the end of the top-level file.
    pub(super) fn next(&mut self, buf: &mut String) -> Result<Option<Loc>, MeshError> {
        loop {
            let Some(top) = self.stack.last_mut() else {
                return Ok(None);
            };
            self.bytes.clear();
            let n = top
                .reader
                .read_until(b'\n', &mut self.bytes)
                .map_err(|source| MeshError::Io {
                    file: self.files[top.file as usize].clone(),
                    source,
                })?;
            if n == 0 {
                self.stack.pop();
                continue;
            }
            top.line = top.line.saturating_add(1);
            buf.clear();
            // Headings and comments written on Windows are often Latin-1: keep going.
            let text = String::from_utf8_lossy(&self.bytes);
            // A byte-order mark would hide the '*' of a first keyword line.
            buf.push_str(match top.line {
                1 => text.strip_prefix('\u{feff}').unwrap_or(&text),
                _ => &text,
            });
            return Ok(Some(Loc {
                file: top.file,
                line: top.line,
            }));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::super::*;

    #[test]
    fn include_is_relative_to_the_including_file_and_nests() {
        let dir = TempDir::new("include");
        dir.write("sub/nodes.inp", &unit_tet_nodes(11));
        dir.write(
            "sub/mesh.inp",
            "*NODE, NSET=NALL\n*INCLUDE, INPUT=nodes.inp\n*ELEMENT, TYPE=C3D10, \
             ELSET=EALL, INPUT=elements.inp\n",
        );
        dir.write("sub/elements.inp", &unit_tet_element(7, 11));
        let main = dir.write(
            "main.inp",
            &format!(
                "*INCLUDE, INPUT=sub/mesh.inp\n{STEEL}*SOLID SECTION, ELSET=EALL, \
                 MATERIAL=STEEL\n"
            ),
        );
        let deck = read(&main).unwrap();
        assert_eq!(deck.mesh.nodes.len(), 10);
        assert_eq!(deck.mesh.node_sets["NALL"].len(), 10);
        assert_eq!(deck.mesh.elements.len(), 1);
        assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
    }

    #[test]
    fn an_error_in_an_included_file_names_that_file_and_its_line() {
        let dir = TempDir::new("include-error");
        let bad = dir.write("sub/nodes.inp", "** nodes\n11, 0, 0, 0\n12, 1, zero, 0\n");
        let main = dir.write("main.inp", "*NODE\n*INCLUDE, INPUT=sub/nodes.inp\n");
        let (file, line, message) = parse_error(read(&main));
        assert_eq!((file, line), (bad, 3));
        assert!(
            message.contains("\"zero\"") && message.contains("node 12"),
            "{message}"
        );
    }

    #[test]
    fn a_missing_include_names_the_file_and_the_including_line() {
        let dir = TempDir::new("include-missing");
        let main = dir.write("main.inp", "*HEADING\nx\n*INCLUDE, INPUT=\"absent.inp\"\n");
        let (file, line, message) = parse_error(read(&main));
        assert_eq!((file, line), (main, 3));
        assert!(message.contains("absent.inp"), "{message}");
    }

    #[test]
    fn an_include_cycle_is_an_error() {
        let dir = TempDir::new("include-cycle");
        dir.write("a.inp", "*INCLUDE, INPUT=b.inp\n");
        let b = dir.write("b.inp", "** b\n*INCLUDE, INPUT=a.inp\n");
        let (file, line, message) = parse_error(read(&dir.0.join("a.inp")));
        assert_eq!((file, line), (b, 2));
        assert!(message.contains("cycle"), "{message}");
    }

    #[test]
    fn a_byte_order_mark_crlf_and_latin1_are_accepted() {
        let mut bytes = b"\xef\xbb\xbf*HEADING\r\nCaf\xe9 brake\r\n".to_vec();
        bytes.extend(one_tet().replace('\n', "\r\n").into_bytes());
        let dir = TempDir::new("bom");
        let path = dir.0.join("deck.inp");
        std::fs::write(&path, bytes).unwrap();
        let deck = read(&path).unwrap();
        assert!(deck.heading.starts_with("Caf") && deck.heading.ends_with(" brake"));
        assert_eq!(deck.mesh.elements.len(), 1);
    }
}
