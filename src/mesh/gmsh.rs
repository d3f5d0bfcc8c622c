//! Gmsh MSH files: a reader for MSH 4.1 (ASCII and binary, either byte order) and MSH 2.2
//! (ASCII), and a writer for MSH 4.1 ASCII.
//!
//! Format reference: the Gmsh manual, section "MSH file format"
//! (<https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format>) and, for 2.2, "Legacy formats".
//!
//! What becomes what:
//! - 10-node tetrahedra (type 11) are the elements; their node order is converted from
//!   Gmsh's to the internal one (see [`GMSH_TET10`]).
//! - Physical volumes become [`Part`]s (named by `$PhysicalNames`, else `volume_<tag>`,
//!   no material). Tetrahedra in no physical volume go into a part `unassigned`, or into a
//!   part `all` when the file has no physical groups at all.
//! - 6-node (type 9) or 3-node (type 2) triangles in a physical surface become a [`Surface`]
//!   of the tetrahedron faces they cover (outward, as [`Mesh::face`] gives them), and the
//!   surface's nodes become a node set of the same name.
//! - Points (type 15) and lines (types 1 and 8) in physical points and curves become node
//!   sets (`point_<tag>` / `curve_<tag>` when unnamed).
//! - Every other element type is refused by name.
//!
//! Errors name the file and the line (in a binary file: the byte offset) and what was
//! expected there. A file that stops before a section's end marker is an error, never a
//! shorter mesh.

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use crate::mesh::{Face, Mesh, MeshError, Part, Surface};

/// Node order conversion for the 10-node tetrahedron, in both directions (the permutation is
/// its own inverse): `internal[k] = gmsh[GMSH_TET10[k]]` and `gmsh[k] = internal[GMSH_TET10[k]]`.
///
/// Gmsh orders the mid-edge nodes 0-1, 1-2, 2-0, 3-0, 3-2, 3-1 (manual, "Node ordering");
/// the internal (Abaqus C3D10) order is 0-1, 1-2, 2-0, 0-3, 1-3, 2-3. Edge direction does not
/// matter for a mid-edge node, so only the last two nodes trade places.
pub const GMSH_TET10: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];

/// Read a Gmsh mesh file (MSH 4.1 ASCII or binary, or MSH 2.2 ASCII).
pub fn read(path: &Path) -> Result<Mesh, MeshError> {
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    parse(path, &bytes)
}

/// Parse the contents of a Gmsh mesh file; `file` is only used in error messages.
pub fn parse(file: &Path, bytes: &[u8]) -> Result<Mesh, MeshError> {
    let raw = Parser::new(file, bytes).run()?;
    build(file, raw)
}

// ---------------------------------------------------------------------------------------
// Element types
// ---------------------------------------------------------------------------------------

/// The element types squeal reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Point,
    Line2,
    Line3,
    Tri3,
    Tri6,
    Tet10,
}

impl Kind {
    fn from_gmsh(element_type: i32) -> Option<Kind> {
        Some(match element_type {
            15 => Kind::Point,
            1 => Kind::Line2,
            8 => Kind::Line3,
            2 => Kind::Tri3,
            9 => Kind::Tri6,
            11 => Kind::Tet10,
            _ => return None,
        })
    }

    fn nodes(self) -> usize {
        match self {
            Kind::Point => 1,
            Kind::Line2 => 2,
            Kind::Line3 | Kind::Tri3 => 3,
            Kind::Tri6 => 6,
            Kind::Tet10 => 10,
        }
    }

    fn dim(self) -> i32 {
        match self {
            Kind::Point => 0,
            Kind::Line2 | Kind::Line3 => 1,
            Kind::Tri3 | Kind::Tri6 => 2,
            Kind::Tet10 => 3,
        }
    }
}

/// Gmsh's name for an element type (manual, "MSH file format", elm-type list).
fn type_name(element_type: i32) -> Option<&'static str> {
    Some(match element_type {
        1 => "2-node line",
        2 => "3-node triangle",
        3 => "4-node quadrangle",
        4 => "4-node tetrahedron",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        8 => "3-node line",
        9 => "6-node triangle",
        10 => "9-node quadrangle",
        11 => "10-node tetrahedron",
        12 => "27-node hexahedron",
        13 => "18-node prism",
        14 => "14-node pyramid",
        15 => "1-node point",
        16 => "8-node quadrangle",
        17 => "20-node hexahedron",
        18 => "15-node prism",
        19 => "13-node pyramid",
        20 => "9-node incomplete triangle",
        21 => "10-node triangle",
        22 => "12-node incomplete triangle",
        23 => "15-node triangle",
        24 => "15-node incomplete triangle",
        25 => "21-node triangle",
        26 => "4-node line",
        27 => "5-node line",
        28 => "6-node line",
        29 => "20-node tetrahedron",
        30 => "35-node tetrahedron",
        31 => "56-node tetrahedron",
        92 => "64-node hexahedron",
        93 => "125-node hexahedron",
        _ => return None,
    })
}

/// The message refusing an element type squeal does not read.
fn refusal(element_type: i32) -> String {
    let Some(name) = type_name(element_type) else {
        return format!(
            "element type {element_type} is not a Gmsh element type squeal knows: squeal needs \
             10-node tetrahedra (type 11)"
        );
    };
    let why = match element_type {
        4 | 29 | 30 | 31 => "squeal needs 10-node tetrahedra (type 11); mesh with -order 2",
        5 | 6 | 7 | 12 | 13 | 14 | 17 | 18 | 19 | 92 | 93 => {
            "squeal needs 10-node tetrahedra (type 11); mesh every volume with tetrahedra, \
             with -order 2"
        }
        3 | 10 | 16 | 20..=25 => {
            "physical surfaces must be made of 6-node (type 9) or 3-node (type 2) triangles"
        }
        _ => "physical curves must be made of 3-node (type 8) or 2-node (type 1) lines",
    };
    format!("element type {element_type} ({name}) is not supported: {why}")
}

// ---------------------------------------------------------------------------------------
// Positions and the byte cursor
// ---------------------------------------------------------------------------------------

/// Where something was read: a line of a text part, or a byte offset in a binary file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Loc {
    Line(usize),
    Byte(usize),
}

impl Loc {
    fn error(self, file: &Path, message: impl Into<String>) -> MeshError {
        match self {
            Loc::Line(line) => MeshError::parse(file, line, message),
            Loc::Byte(offset) => MeshError::Binary {
                file: file.to_path_buf(),
                offset: offset as u64,
                message: message.into(),
            },
        }
    }
}

/// A token for a message: lossy UTF-8, shortened.
fn show(token: &[u8]) -> String {
    let text = String::from_utf8_lossy(token);
    if text.chars().count() > 40 {
        let short: String = text.chars().take(40).collect();
        format!("{short}...")
    } else {
        text.into_owned()
    }
}

/// Reads whitespace-separated tokens, text lines and raw binary numbers from the bytes of
/// one file, keeping track of the line (text) or the offset (binary file) for messages.
struct Cursor<'a> {
    file: &'a Path,
    bytes: &'a [u8],
    pos: usize,
    /// 1-based line of `pos`; meaningful until the first binary byte was read.
    line: usize,
    /// Binary file: report positions as byte offsets (line numbers mean nothing there).
    offsets: bool,
    /// Numbers of the current section are binary.
    binary_numbers: bool,
    big_endian: bool,
    /// The section being read (for "the file ends inside ..." messages), e.g. "$Nodes".
    section: &'static str,
}

impl<'a> Cursor<'a> {
    fn loc(&self) -> Loc {
        if self.offsets {
            Loc::Byte(self.pos)
        } else {
            Loc::Line(self.line)
        }
    }

    fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    fn skip_whitespace(&mut self) {
        while let Some(&b) = self.bytes.get(self.pos) {
            if !b.is_ascii_whitespace() {
                break;
            }
            if b == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
    }

    /// The error for a file that ends where `what` was expected.
    fn eof_error(&self, what: &str) -> MeshError {
        let loc = match self.loc() {
            // Point at the last line that exists, not the empty one after the final newline.
            Loc::Line(line) if self.bytes.last() == Some(&b'\n') && line > 1 => Loc::Line(line - 1),
            loc => loc,
        };
        let message = if self.section.is_empty() {
            format!("the file ends where {what} was expected; it is truncated")
        } else {
            format!(
                "the file ends inside {} (expected {what}) before ${}; it is truncated",
                self.section,
                end_marker(self.section)
            )
        };
        loc.error(self.file, message)
    }

    fn token(&mut self) -> Option<(&'a [u8], Loc)> {
        self.skip_whitespace();
        if self.pos >= self.bytes.len() {
            return None;
        }
        let loc = self.loc();
        let start = self.pos;
        while self
            .bytes
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        Some((&self.bytes[start..self.pos], loc))
    }

    fn expect_token(&mut self, what: &str) -> Result<(&'a [u8], Loc), MeshError> {
        self.token().ok_or_else(|| self.eof_error(what))
    }

    /// The rest of the current line (without the line break); moves to the next line.
    fn rest_of_line(&mut self) -> (&'a [u8], Loc) {
        let loc = self.loc();
        let start = self.pos;
        while self.bytes.get(self.pos).is_some_and(|&b| b != b'\n') {
            self.pos += 1;
        }
        let mut end = self.pos;
        if self.pos < self.bytes.len() {
            self.pos += 1;
            self.line += 1;
        }
        if end > start && self.bytes[end - 1] == b'\r' {
            end -= 1;
        }
        (&self.bytes[start..end], loc)
    }

    /// The next non-blank line as text.
    fn record_line(&mut self, what: &str) -> Result<(&'a str, Loc), MeshError> {
        self.skip_whitespace();
        if self.pos >= self.bytes.len() {
            return Err(self.eof_error(what));
        }
        let (line, loc) = self.rest_of_line();
        let text = std::str::from_utf8(line).map_err(|_| {
            loc.error(
                self.file,
                format!("expected {what}, found bytes that are not text"),
            )
        })?;
        Ok((text, loc))
    }

    /// Only blanks may follow on this line (used before binary data starts).
    fn end_of_line(&mut self, after: &str) -> Result<(), MeshError> {
        let (rest, loc) = self.rest_of_line();
        if rest.iter().all(|b| b.is_ascii_whitespace()) {
            Ok(())
        } else {
            Err(loc.error(
                self.file,
                format!(
                    "expected a line break after {after}, found '{}'",
                    show(rest)
                ),
            ))
        }
    }

    fn ascii_number<T: std::str::FromStr>(&mut self, what: &str) -> Result<(T, Loc), MeshError> {
        let (token, loc) = self.expect_token(what)?;
        parse_number(token, what)
            .map(|v| (v, loc))
            .map_err(|m| loc.error(self.file, m))
    }

    fn binary_bytes<const N: usize>(&mut self, what: &str) -> Result<([u8; N], Loc), MeshError> {
        let loc = self.loc();
        if self.remaining() < N {
            return Err(loc.error(
                self.file,
                format!(
                    "the file ends inside {} (expected {what}, {N} bytes; {} left) before ${}; \
                     it is truncated",
                    self.section,
                    self.remaining(),
                    end_marker(self.section)
                ),
            ));
        }
        let mut out = [0u8; N];
        out.copy_from_slice(&self.bytes[self.pos..self.pos + N]);
        self.pos += N;
        Ok((out, loc))
    }

    /// A `size_t` (8 bytes in binary, the only data size read).
    fn size(&mut self, what: &str) -> Result<(u64, Loc), MeshError> {
        if !self.binary_numbers {
            return self.ascii_number(what);
        }
        let (b, loc) = self.binary_bytes::<8>(what)?;
        let v = if self.big_endian {
            u64::from_be_bytes(b)
        } else {
            u64::from_le_bytes(b)
        };
        Ok((v, loc))
    }

    fn int(&mut self, what: &str) -> Result<(i32, Loc), MeshError> {
        if !self.binary_numbers {
            return self.ascii_number(what);
        }
        let (b, loc) = self.binary_bytes::<4>(what)?;
        let v = if self.big_endian {
            i32::from_be_bytes(b)
        } else {
            i32::from_le_bytes(b)
        };
        Ok((v, loc))
    }

    fn double(&mut self, what: &str) -> Result<(f64, Loc), MeshError> {
        let (v, loc) = if self.binary_numbers {
            let (b, loc) = self.binary_bytes::<8>(what)?;
            let v = if self.big_endian {
                f64::from_be_bytes(b)
            } else {
                f64::from_le_bytes(b)
            };
            (v, loc)
        } else {
            self.ascii_number::<f64>(what)?
        };
        if v.is_finite() {
            Ok((v, loc))
        } else {
            Err(loc.error(
                self.file,
                format!("expected {what} (a finite number), found {v}"),
            ))
        }
    }

    /// The closing marker of the current section must come next.
    fn expect_end(&mut self) -> Result<(), MeshError> {
        let end = format!("${}", end_marker(self.section));
        let (token, loc) = self.expect_token(&end)?;
        if token == end.as_bytes() {
            self.section = "";
            Ok(())
        } else {
            Err(loc.error(
                self.file,
                format!(
                    "expected {end}, found '{}' ({} holds more than its counts declare)",
                    show(token),
                    self.section
                ),
            ))
        }
    }
}

/// "$Nodes" -> "EndNodes".
fn end_marker(section: &str) -> String {
    format!("End{}", section.trim_start_matches('$'))
}

fn parse_number<T: std::str::FromStr>(token: &[u8], what: &str) -> Result<T, String> {
    match std::str::from_utf8(token).ok().and_then(|s| s.parse().ok()) {
        Some(v) => Ok(v),
        None if token.starts_with(b"$") => Err(format!(
            "expected {what}, found '{}': the section ends before all the items its counts \
             declare",
            show(token)
        )),
        None => Err(format!("expected {what}, found '{}'", show(token))),
    }
}

/// Capacity for a count read from the file: never more than the bytes left could hold, so a
/// corrupt count cannot make us allocate absurd amounts before the data runs out.
fn capacity(count: u64, remaining: usize) -> usize {
    usize::try_from(count).unwrap_or(usize::MAX).min(remaining)
}

// ---------------------------------------------------------------------------------------
// Parsing into raw records
// ---------------------------------------------------------------------------------------

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Version {
    V41,
    V22,
}

/// An element as read, before node tags are resolved.
struct RawElement {
    tag: u64,
    kind: Kind,
    /// (dimension, tag) of the entity that carries its physical groups. In MSH 2.2 the
    /// "entity" is (dimension, physical tag) so that both versions resolve the same way.
    entity: (i32, i32),
    /// Index of its first node tag in [`Raw::element_nodes`].
    first: usize,
    loc: Loc,
}

/// Everything the sections said, resolved afterwards by [`build`].
#[derive(Default)]
struct Raw {
    names: HashMap<(i32, i32), String>,
    /// Physical tags of each entity; `None` when the file has no `$Entities` section.
    entities: Option<HashMap<(i32, i32), Vec<i32>>>,
    node_tags: Vec<u64>,
    coords: Vec<[f64; 3]>,
    node_index: HashMap<u64, usize>,
    elements: Vec<RawElement>,
    element_nodes: Vec<u64>,
}

struct Parser<'a> {
    c: Cursor<'a>,
    version: Version,
    raw: Raw,
    seen_nodes: bool,
    seen_elements: bool,
}

impl<'a> Parser<'a> {
    fn new(file: &'a Path, bytes: &'a [u8]) -> Self {
        Parser {
            c: Cursor {
                file,
                bytes,
                pos: 0,
                line: 1,
                offsets: false,
                binary_numbers: false,
                big_endian: false,
                section: "",
            },
            version: Version::V41,
            raw: Raw::default(),
            seen_nodes: false,
            seen_elements: false,
        }
    }

    fn file(&self) -> &'a Path {
        self.c.file
    }

    fn run(mut self) -> Result<Raw, MeshError> {
        let file = self.file();
        let Some((first, loc)) = self.c.token() else {
            return Err(MeshError::invalid(
                file,
                "the file is empty: expected a Gmsh mesh starting with $MeshFormat",
            ));
        };
        if first != b"$MeshFormat" {
            return Err(loc.error(
                file,
                format!(
                    "expected $MeshFormat at the start of a Gmsh mesh file, found '{}'",
                    show(first)
                ),
            ));
        }
        self.mesh_format()?;
        while let Some((token, loc)) = self.c.token() {
            match token {
                b"$PhysicalNames" => self.physical_names()?,
                b"$Entities" if self.version == Version::V41 => self.entities(loc)?,
                b"$Nodes" => {
                    if self.seen_nodes {
                        return Err(loc.error(file, "a second $Nodes section"));
                    }
                    self.seen_nodes = true;
                    match self.version {
                        Version::V41 => self.nodes41()?,
                        Version::V22 => self.nodes22()?,
                    }
                }
                b"$Elements" => {
                    if self.seen_elements {
                        return Err(loc.error(file, "a second $Elements section"));
                    }
                    self.seen_elements = true;
                    match self.version {
                        Version::V41 => self.elements41()?,
                        Version::V22 => self.elements22()?,
                    }
                }
                b"$PartitionedEntities" => {
                    return Err(loc.error(
                        file,
                        "partitioned meshes are not supported: save the mesh without partitions",
                    ))
                }
                b"$MeshFormat" => return Err(loc.error(file, "a second $MeshFormat section")),
                t if t.len() > 1 && t.starts_with(b"$") && !t.starts_with(b"$End") => {
                    // Gmsh: "Any section with an unrecognized header is simply ignored".
                    self.skip_section(&t[1..], loc)?;
                }
                t => {
                    return Err(loc.error(
                        file,
                        format!(
                            "expected a section header such as $Nodes or $Elements, found '{}'",
                            show(t)
                        ),
                    ))
                }
            }
        }
        if !self.seen_nodes {
            return Err(MeshError::invalid(file, "the file has no $Nodes section"));
        }
        if !self.seen_elements {
            return Err(MeshError::invalid(
                file,
                "the file has no $Elements section",
            ));
        }
        Ok(self.raw)
    }

    fn mesh_format(&mut self) -> Result<(), MeshError> {
        let file = self.file();
        self.c.section = "$MeshFormat";
        let (version, loc) = self.c.expect_token("the MSH version number")?;
        self.version = match version {
            b"4.1" => Version::V41,
            b"2.2" => Version::V22,
            v => {
                return Err(loc.error(
                    file,
                    format!(
                        "MSH version {} is not supported: squeal reads MSH 4.1 (ASCII or binary) \
                         and MSH 2.2 (ASCII); export with gmsh -format msh41 \
                         (or Mesh.MshFileVersion = 4.1)",
                        show(v)
                    ),
                ))
            }
        };
        let (file_type, loc) = self.c.ascii_number::<i64>("the file type (0 or 1)")?;
        let binary = match file_type {
            0 => false,
            1 => true,
            t => {
                return Err(loc.error(
                    file,
                    format!("expected the file type 0 (ASCII) or 1 (binary), found {t}"),
                ))
            }
        };
        let (data_size, loc) = self.c.ascii_number::<i64>("the data size")?;
        if binary && self.version == Version::V22 {
            return Err(loc.error(
                file,
                "binary MSH 2.2 is not supported: save as MSH 4.1 (binary or ASCII) or 2.2 ASCII",
            ));
        }
        if binary && data_size != 8 {
            return Err(loc.error(
                file,
                format!(
                    "data size {data_size} is not supported: squeal reads binary MSH files whose \
                     size_t has 8 bytes"
                ),
            ));
        }
        if binary {
            self.c.end_of_line("the data size")?;
            // From here on positions are byte offsets.
            self.c.offsets = true;
            self.c.binary_numbers = true;
            let (b, loc) = self
                .c
                .binary_bytes::<4>("the integer 1 (byte order check)")?;
            self.c.binary_numbers = false;
            self.c.big_endian = if i32::from_le_bytes(b) == 1 {
                false
            } else if i32::from_be_bytes(b) == 1 {
                true
            } else {
                return Err(loc.error(
                    file,
                    format!("expected the integer 1 (byte order check), found the bytes {b:02x?}"),
                ));
            };
        }
        self.c.expect_end()
    }

    fn physical_names(&mut self) -> Result<(), MeshError> {
        let file = self.file();
        self.c.section = "$PhysicalNames";
        let (count, _) = self.c.ascii_number::<u64>("the number of physical names")?;
        for _ in 0..count {
            let (dim, loc) = self
                .c
                .ascii_number::<i32>("a physical dimension (0 to 3)")?;
            if !(0..=3).contains(&dim) {
                return Err(loc.error(
                    file,
                    format!("expected a physical dimension (0 to 3), found {dim}"),
                ));
            }
            let (tag, _) = self.c.ascii_number::<i32>("a physical tag")?;
            let (rest, loc) = self.c.rest_of_line();
            let text = String::from_utf8_lossy(rest);
            let text = text.trim();
            let name = text
                .strip_prefix('"')
                .and_then(|t| t.strip_suffix('"'))
                .filter(|_| text.len() >= 2)
                .ok_or_else(|| {
                    loc.error(
                        file,
                        format!(
                            "expected a physical name in double quotes after the tag {tag}, \
                             found '{text}'"
                        ),
                    )
                })?;
            self.raw.names.insert((dim, tag), name.to_string());
        }
        self.c.expect_end()
    }

    /// Starts a section whose numbers are binary in a binary file.
    fn begin_data_section(&mut self, section: &'static str) -> Result<(), MeshError> {
        self.c.section = section;
        if self.c.offsets {
            self.c.end_of_line(section)?;
            self.c.binary_numbers = true;
        }
        Ok(())
    }

    fn end_data_section(&mut self) -> Result<(), MeshError> {
        self.c.binary_numbers = false;
        self.c.expect_end()
    }

    fn entities(&mut self, loc: Loc) -> Result<(), MeshError> {
        if self.raw.entities.is_some() {
            return Err(loc.error(self.file(), "a second $Entities section"));
        }
        self.begin_data_section("$Entities")?;
        let what = [
            "the number of points",
            "the number of curves",
            "the number of surfaces",
            "the number of volumes",
        ];
        let mut counts = [0u64; 4];
        for (count, what) in counts.iter_mut().zip(what) {
            *count = self.c.size(what)?.0;
        }
        let mut entities = HashMap::new();
        for (dim, &count) in counts.iter().enumerate() {
            let dim = dim as i32;
            for _ in 0..count {
                let (tag, _) = self.c.int("an entity tag")?;
                let (doubles, what) = if dim == 0 {
                    (3, "a point coordinate")
                } else {
                    (6, "a bounding box coordinate")
                };
                for _ in 0..doubles {
                    self.c.double(what)?;
                }
                let (n, _) = self.c.size("the number of physical tags")?;
                let mut physicals = Vec::with_capacity(capacity(n, self.c.remaining()));
                for _ in 0..n {
                    physicals.push(self.c.int("a physical tag")?.0);
                }
                if dim > 0 {
                    let (n, _) = self.c.size("the number of bounding entities")?;
                    for _ in 0..n {
                        self.c.int("a bounding entity tag")?;
                    }
                }
                entities.insert((dim, tag), physicals);
            }
        }
        self.raw.entities = Some(entities);
        self.end_data_section()
    }

    /// A block header: three ints and a size_t. In ASCII it must be one line of exactly four
    /// numbers; a line of another length almost always means that the block before holds
    /// more (or fewer) items than it declared, and saying so beats a puzzling message about
    /// whatever the numbers would mean as a header.
    fn block_header(
        &mut self,
        header: &str,
        what: [&str; 4],
    ) -> Result<([i32; 3], u64, Loc), MeshError> {
        if self.c.binary_numbers {
            let (a, loc) = self.c.int(what[0])?;
            let (b, _) = self.c.int(what[1])?;
            let (c, _) = self.c.int(what[2])?;
            let (n, _) = self.c.size(what[3])?;
            return Ok(([a, b, c], n, loc));
        }
        let file = self.file();
        let (line, loc) = self.c.record_line(header)?;
        let fields: Vec<&str> = line.split_ascii_whitespace().collect();
        if fields.len() != 4 {
            return Err(loc.error(
                file,
                format!(
                    "expected {header} ({}, {}, {}, {}) on one line, found '{}': does the block \
                     before hold more or fewer items than it declares?",
                    what[0],
                    what[1],
                    what[2],
                    what[3],
                    show(line.as_bytes())
                ),
            ));
        }
        let mut ints = [0i32; 3];
        for k in 0..3 {
            ints[k] =
                parse_number(fields[k].as_bytes(), what[k]).map_err(|m| loc.error(file, m))?;
        }
        let n = parse_number(fields[3].as_bytes(), what[3]).map_err(|m| loc.error(file, m))?;
        Ok((ints, n, loc))
    }

    fn add_node(&mut self, tag: u64, loc: Loc) -> Result<usize, MeshError> {
        if tag == 0 || tag > i64::MAX as u64 {
            return Err(loc.error(
                self.file(),
                format!("expected a node tag from 1 to {}, found {tag}", i64::MAX),
            ));
        }
        let index = self.raw.node_tags.len();
        if self.raw.node_index.insert(tag, index).is_some() {
            return Err(loc.error(self.file(), format!("node tag {tag} appears a second time")));
        }
        self.raw.node_tags.push(tag);
        self.raw.coords.push([0.0; 3]);
        Ok(index)
    }

    fn nodes41(&mut self) -> Result<(), MeshError> {
        self.begin_data_section("$Nodes")?;
        let (blocks, _) = self.c.size("the number of node blocks")?;
        let (declared, _) = self.c.size("the number of nodes")?;
        self.c.size("the smallest node tag")?;
        self.c.size("the largest node tag")?;
        let cap = capacity(declared, self.c.remaining());
        self.raw.node_tags.reserve(cap);
        self.raw.coords.reserve(cap);
        self.raw.node_index.reserve(cap);
        for _ in 0..blocks {
            let ([dim, _, parametric], n, loc) = self.block_header(
                "a node block header",
                [
                    "the entity dimension of a node block",
                    "the entity tag of a node block",
                    "the parametric flag (0 or 1)",
                    "the number of nodes in the block",
                ],
            )?;
            if !(0..=3).contains(&dim) {
                return Err(loc.error(
                    self.file(),
                    format!("expected an entity dimension (0 to 3), found {dim}"),
                ));
            }
            if !(0..=1).contains(&parametric) {
                return Err(loc.error(
                    self.file(),
                    format!("expected the parametric flag 0 or 1, found {parametric}"),
                ));
            }
            let first = self.raw.coords.len();
            for _ in 0..n {
                let (tag, loc) = self.c.size("a node tag")?;
                self.add_node(tag, loc)?;
            }
            // Parametric nodes carry u (curves), u v (surfaces) or u v w (volumes) after x y z.
            let extra = if parametric == 1 { dim as usize } else { 0 };
            for i in first..self.raw.coords.len() {
                let mut x = [0.0; 3];
                for (k, xk) in x.iter_mut().enumerate() {
                    *xk = self
                        .c
                        .double(["a node's x", "a node's y", "a node's z"][k])?
                        .0;
                }
                self.raw.coords[i] = x;
                for _ in 0..extra {
                    self.c.double("a node's parametric coordinate")?;
                }
            }
        }
        let found = self.raw.coords.len() as u64;
        if found != declared {
            let loc = self.c.loc();
            return Err(loc.error(
                self.file(),
                format!("the node blocks hold {found} nodes, but $Nodes declares {declared}"),
            ));
        }
        self.end_data_section()
    }

    fn nodes22(&mut self) -> Result<(), MeshError> {
        let file = self.file();
        self.c.section = "$Nodes";
        let (count, _) = self.c.ascii_number::<u64>("the number of nodes")?;
        let cap = capacity(count, self.c.remaining());
        self.raw.node_tags.reserve(cap);
        self.raw.coords.reserve(cap);
        self.raw.node_index.reserve(cap);
        for _ in 0..count {
            let (line, loc) = self.c.record_line("a node line (tag x y z)")?;
            let fields: Vec<&str> = line.split_ascii_whitespace().collect();
            let what = ["a node tag", "a node's x", "a node's y", "a node's z"];
            if fields.len() != 4 {
                if let Some(f) = fields.first().filter(|f| f.starts_with('$')) {
                    return Err(loc.error(
                        file,
                        format!(
                            "expected a node line (tag x y z), found '{}': $Nodes declares \
                             {count} nodes but holds fewer",
                            show(f.as_bytes())
                        ),
                    ));
                }
                return Err(loc.error(
                    file,
                    format!(
                        "expected a node line with 4 numbers (tag x y z), found {}",
                        fields.len()
                    ),
                ));
            }
            let tag: u64 =
                parse_number(fields[0].as_bytes(), what[0]).map_err(|m| loc.error(file, m))?;
            let index = self.add_node(tag, loc)?;
            for k in 0..3 {
                let v: f64 = parse_number(fields[k + 1].as_bytes(), what[k + 1])
                    .map_err(|m| loc.error(file, m))?;
                if !v.is_finite() {
                    return Err(loc.error(
                        file,
                        format!("expected {} (a finite number), found {v}", what[k + 1]),
                    ));
                }
                self.raw.coords[index][k] = v;
            }
        }
        self.c.expect_end()
    }

    fn check_element_type(&self, element_type: i32, loc: Loc) -> Result<Kind, MeshError> {
        Kind::from_gmsh(element_type).ok_or_else(|| loc.error(self.file(), refusal(element_type)))
    }

    fn push_element(&mut self, tag: u64, kind: Kind, entity: (i32, i32), loc: Loc) {
        self.raw.elements.push(RawElement {
            tag,
            kind,
            entity,
            first: self.raw.element_nodes.len(),
            loc,
        });
    }

    fn elements41(&mut self) -> Result<(), MeshError> {
        let file = self.file();
        self.begin_data_section("$Elements")?;
        let (blocks, _) = self.c.size("the number of element blocks")?;
        let (declared, _) = self.c.size("the number of elements")?;
        self.c.size("the smallest element tag")?;
        self.c.size("the largest element tag")?;
        let mut found = 0u64;
        for _ in 0..blocks {
            let ([dim, entity, element_type], n, loc) = self.block_header(
                "an element block header",
                [
                    "the entity dimension of an element block",
                    "the entity tag of an element block",
                    "an element type",
                    "the number of elements in the block",
                ],
            )?;
            let kind = self.check_element_type(element_type, loc)?;
            if kind.dim() != dim {
                return Err(loc.error(
                    file,
                    format!(
                        "element type {element_type} has dimension {}, but its block belongs \
                         to an entity of dimension {dim}",
                        kind.dim()
                    ),
                ));
            }
            found += n;
            let per = kind.nodes();
            for _ in 0..n {
                if self.c.binary_numbers {
                    let (tag, loc) = self.c.size("an element tag")?;
                    self.push_element(tag, kind, (dim, entity), loc);
                    for _ in 0..per {
                        let (node, _) = self.c.size("a node tag of an element")?;
                        self.raw.element_nodes.push(node);
                    }
                } else {
                    let (line, loc) = self.c.record_line("an element line (tag and node tags)")?;
                    let mut fields = line.split_ascii_whitespace();
                    let tag = fields.next().unwrap_or("");
                    let tag: u64 = parse_number(tag.as_bytes(), "an element tag").map_err(|m| {
                        loc.error(file, format!("{m} (element block of type {element_type})"))
                    })?;
                    self.push_element(tag, kind, (dim, entity), loc);
                    let mut count = 0;
                    for field in fields {
                        let node: u64 = parse_number(field.as_bytes(), "a node tag")
                            .map_err(|m| loc.error(file, format!("element {tag}: {m}")))?;
                        self.raw.element_nodes.push(node);
                        count += 1;
                    }
                    if count != per {
                        return Err(loc.error(
                            file,
                            format!(
                                "element {tag}: expected {per} node tags for element type \
                                 {element_type} ({}), found {count}",
                                type_name(element_type).unwrap_or("?")
                            ),
                        ));
                    }
                }
            }
        }
        if found != declared {
            let loc = self.c.loc();
            return Err(loc.error(
                file,
                format!(
                    "the element blocks hold {found} elements, but $Elements declares {declared}"
                ),
            ));
        }
        self.end_data_section()
    }

    fn elements22(&mut self) -> Result<(), MeshError> {
        let file = self.file();
        self.c.section = "$Elements";
        // MSH 2.2 has no entities: each (dimension, physical tag) acts as one, so that the
        // physical groups resolve as in 4.1. Physical tag 0 means "in no physical group".
        let mut entities: HashMap<(i32, i32), Vec<i32>> = HashMap::new();
        let (count, _) = self.c.ascii_number::<u64>("the number of elements")?;
        for _ in 0..count {
            let (line, loc) = self
                .c
                .record_line("an element line (tag type number-of-tags tags... nodes...)")?;
            let fields: Vec<&str> = line.split_ascii_whitespace().collect();
            if let Some(f) = fields.first().filter(|f| f.starts_with('$')) {
                return Err(loc.error(
                    file,
                    format!(
                        "expected an element line, found '{}': $Elements declares {count} \
                         elements but holds fewer",
                        show(f.as_bytes())
                    ),
                ));
            }
            let field = |i: usize, what: &str| -> Result<i64, MeshError> {
                let text = fields.get(i).ok_or_else(|| {
                    loc.error(file, format!("expected {what}, found the end of the line"))
                })?;
                parse_number(text.as_bytes(), what).map_err(|m| loc.error(file, m))
            };
            let tag = field(0, "an element tag")?;
            let element_type = field(1, "an element type")?;
            let element_type = i32::try_from(element_type).unwrap_or(-1);
            let kind = self.check_element_type(element_type, loc)?;
            let ntags = field(2, "the number of tags")?;
            let ntags = usize::try_from(ntags).map_err(|_| {
                loc.error(
                    file,
                    format!("expected the number of tags (0 or more), found {ntags}"),
                )
            })?;
            let physical = if ntags >= 1 {
                i32::try_from(field(3, "a physical tag")?).map_err(|_| {
                    loc.error(file, "expected a physical tag, found a number out of range")
                })?
            } else {
                0
            };
            let per = kind.nodes();
            let found = fields.len().saturating_sub(3 + ntags);
            if fields.len() < 3 + ntags || found != per {
                return Err(loc.error(
                    file,
                    format!(
                        "element {tag}: expected {ntags} tags and {per} node tags for element \
                         type {element_type} ({}), found {} numbers after the number of tags",
                        type_name(element_type).unwrap_or("?"),
                        fields.len().saturating_sub(3)
                    ),
                ));
            }
            let tag = u64::try_from(tag)
                .map_err(|_| loc.error(file, format!("expected an element tag, found {tag}")))?;
            let entity = (kind.dim(), physical);
            entities.entry(entity).or_insert_with(|| {
                if physical != 0 {
                    vec![physical]
                } else {
                    vec![]
                }
            });
            self.push_element(tag, kind, entity, loc);
            for i in 0..per {
                let node = field(3 + ntags + i, "a node tag")?;
                let node = u64::try_from(node).map_err(|_| {
                    loc.error(
                        file,
                        format!("element {tag}: expected a node tag, found {node}"),
                    )
                })?;
                self.raw.element_nodes.push(node);
            }
        }
        self.raw.entities = Some(entities);
        self.c.expect_end()
    }

    /// Skip a section squeal does not use, up to its `$End...` marker.
    fn skip_section(&mut self, name: &[u8], loc: Loc) -> Result<(), MeshError> {
        let mut end = b"$End".to_vec();
        end.extend_from_slice(name);
        let bytes = self.c.bytes;
        let mut search = self.c.pos;
        while let Some(i) = find(&bytes[search..], &end) {
            let at = search + i;
            let before_ok = at == 0 || bytes[at - 1].is_ascii_whitespace();
            let after_ok = bytes
                .get(at + end.len())
                .is_none_or(|b| b.is_ascii_whitespace());
            if before_ok && after_ok {
                if !self.c.offsets {
                    self.c.line += bytes[self.c.pos..at]
                        .iter()
                        .filter(|&&b| b == b'\n')
                        .count();
                }
                self.c.pos = at + end.len();
                return Ok(());
            }
            search = at + 1;
        }
        Err(loc.error(
            self.file(),
            format!(
                "section ${} never ends: expected {} before the end of the file; it is truncated",
                show(name),
                show(&end)
            ),
        ))
    }
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

// ---------------------------------------------------------------------------------------
// From raw records to the mesh
// ---------------------------------------------------------------------------------------

fn build(file: &Path, raw: Raw) -> Result<Mesh, MeshError> {
    let Raw {
        names,
        entities,
        node_tags,
        coords,
        node_index,
        elements,
        element_nodes,
    } = raw;
    let no_physicals: Vec<i32> = Vec::new();
    let physicals_of = |e: &RawElement| -> Result<&Vec<i32>, MeshError> {
        match &entities {
            None => Ok(&no_physicals),
            Some(map) => map.get(&e.entity).ok_or_else(|| {
                e.loc.error(
                    file,
                    format!(
                        "element {} belongs to entity {} of dimension {}, which $Entities does \
                         not list",
                        e.tag, e.entity.1, e.entity.0
                    ),
                )
            }),
        }
    };
    let any_physical = entities
        .as_ref()
        .is_some_and(|m| m.values().any(|p| !p.is_empty()));
    let resolve = |e: &RawElement, out: &mut Vec<usize>| -> Result<(), MeshError> {
        out.clear();
        for &tag in &element_nodes[e.first..e.first + e.kind.nodes()] {
            let index = node_index.get(&tag).ok_or_else(|| {
                e.loc.error(
                    file,
                    format!(
                        "element {} refers to node {tag}, which is not in $Nodes",
                        e.tag
                    ),
                )
            })?;
            out.push(*index);
        }
        Ok(())
    };

    let mut mesh = Mesh {
        nodes: coords,
        node_labels: node_tags.iter().map(|&t| t as i64).collect(),
        ..Default::default()
    };

    // Tetrahedra, in file order. MSH 2.2 repeats an element once per physical group it is
    // in (with a new number), so an element met again is merged, not duplicated.
    let mut element_physicals: Vec<BTreeSet<i32>> = Vec::new();
    let mut by_corners: HashMap<[usize; 4], usize> = HashMap::new();
    let mut nodes = Vec::with_capacity(10);
    for e in elements.iter().filter(|e| e.kind == Kind::Tet10) {
        resolve(e, &mut nodes)?;
        let conn: [usize; 10] = std::array::from_fn(|k| nodes[GMSH_TET10[k]]);
        let physicals = physicals_of(e)?;
        let mut corners = [conn[0], conn[1], conn[2], conn[3]];
        corners.sort_unstable();
        if let Some(&other) = by_corners.get(&corners) {
            if mesh.elements[other] != conn {
                return Err(e.loc.error(
                    file,
                    format!(
                        "element {} has the same corners as element {} but other nodes",
                        e.tag, mesh.element_labels[other]
                    ),
                ));
            }
            element_physicals[other].extend(physicals.iter().copied());
            continue;
        }
        let label = i64::try_from(e.tag).map_err(|_| {
            e.loc
                .error(file, format!("element tag {} is too large", e.tag))
        })?;
        let index = mesh.elements.len();
        by_corners.insert(corners, index);
        mesh.elements.push(conn);
        mesh.element_labels.push(label);
        element_physicals.push(physicals.iter().copied().collect());
        let volume = mesh.corner_volume(index);
        if !volume.is_finite() || volume <= 0.0 {
            return Err(e.loc.error(
                file,
                format!(
                    "element {} is inverted or flat (volume of its corner tetrahedron {volume:e})",
                    e.tag
                ),
            ));
        }
    }
    if mesh.elements.is_empty() {
        let hint = if any_physical {
            ": Gmsh saves only the elements of physical groups, so add a Physical Volume for \
             every meshed volume (or set Mesh.SaveAll = 1)"
        } else {
            ""
        };
        return Err(MeshError::invalid(
            file,
            format!("the file holds no 10-node tetrahedra (type 11){hint}"),
        ));
    }

    // Parts: one per physical volume, in tag order, then the elements of none.
    let mut volumes: BTreeMap<i32, Vec<usize>> = BTreeMap::new();
    let mut unassigned = Vec::new();
    for (index, physicals) in element_physicals.iter().enumerate() {
        let mut it = physicals.iter();
        match (it.next(), it.next()) {
            (None, _) => unassigned.push(index),
            (Some(&p), None) => volumes.entry(p).or_default().push(index),
            (Some(a), Some(b)) => {
                let name = |p: &i32| physical_name(&names, 3, *p);
                return Err(MeshError::invalid(
                    file,
                    format!(
                        "element {} is in two physical volumes, '{}' and '{}': every element \
                         must be in exactly one part",
                        mesh.element_labels[index],
                        name(a),
                        name(b)
                    ),
                ));
            }
        }
    }
    let mut add_part =
        |name: String, elements: Vec<usize>| match mesh.parts.iter_mut().find(|p| p.name == name) {
            Some(part) => {
                part.elements.extend(elements);
                part.elements.sort_unstable();
            }
            None => mesh.parts.push(Part {
                name,
                elements,
                material: None,
            }),
        };
    for (tag, elements) in volumes {
        add_part(physical_name(&names, 3, tag), elements);
    }
    if !unassigned.is_empty() {
        let name = if any_physical { "unassigned" } else { "all" };
        add_part(name.to_string(), unassigned);
    }

    // Surfaces: triangles of physical surfaces matched to tetrahedron faces.
    let mut faces_by_corners: Option<FaceMap> = None;
    let mut seen_faces: HashSet<(String, usize, u8)> = HashSet::new();
    let mut sets: BTreeMap<String, BTreeSet<usize>> = BTreeMap::new();
    for e in elements.iter().filter(|e| e.kind != Kind::Tet10) {
        let physicals = physicals_of(e)?;
        if physicals.is_empty() {
            continue;
        }
        resolve(e, &mut nodes)?;
        if matches!(e.kind, Kind::Tri3 | Kind::Tri6) {
            let map = faces_by_corners.get_or_insert_with(|| face_map(&mesh));
            let face = match_face(file, &mesh, map, e, &nodes)?;
            for &p in physicals {
                let name = physical_name(&names, 2, p);
                if seen_faces.insert((name.clone(), face.element, face.side)) {
                    mesh.surfaces
                        .entry(name.clone())
                        .or_insert_with(|| Surface {
                            name,
                            faces: Vec::new(),
                        })
                        .faces
                        .push(face);
                }
            }
        } else {
            for &p in physicals {
                sets.entry(physical_name(&names, e.kind.dim(), p))
                    .or_default()
                    .extend(nodes.iter().copied());
            }
        }
    }
    for (name, surface) in &mesh.surfaces {
        sets.entry(name.clone())
            .or_default()
            .extend(mesh.surface_nodes(surface));
    }
    mesh.node_sets = sets
        .into_iter()
        .map(|(name, set)| (name, set.into_iter().collect()))
        .collect();
    Ok(mesh)
}

/// The name of a physical group: from `$PhysicalNames`, else `<kind>_<tag>`.
fn physical_name(names: &HashMap<(i32, i32), String>, dim: i32, tag: i32) -> String {
    names.get(&(dim, tag)).cloned().unwrap_or_else(|| {
        let kind = ["point", "curve", "surface", "volume"][dim.clamp(0, 3) as usize];
        format!("{kind}_{tag}")
    })
}

/// Sorted corner triple -> the (element, side) faces with those corners.
type FaceMap = HashMap<[usize; 3], Vec<(usize, u8)>>;

/// All element faces by their corners.
fn face_map(mesh: &Mesh) -> FaceMap {
    let mut map: FaceMap = HashMap::with_capacity(4 * mesh.elements.len());
    for element in 0..mesh.elements.len() {
        for side in 0..4u8 {
            let f = mesh.face(element, side);
            let mut key = [f.nodes[0], f.nodes[1], f.nodes[2]];
            key.sort_unstable();
            map.entry(key).or_default().push((element, side));
        }
    }
    map
}

/// The tetrahedron face a triangle of a physical surface lies on. A face inside the mesh
/// belongs to two elements; the triangle's own orientation then picks the element whose
/// outward face runs the same way (that is how [`write`] writes it). A boundary face has one
/// element, and the triangle's orientation does not matter (Gmsh orients boundary triangles
/// by the surface's parametrisation, not outward).
fn match_face(
    file: &Path,
    mesh: &Mesh,
    map: &FaceMap,
    e: &RawElement,
    nodes: &[usize],
) -> Result<Face, MeshError> {
    let corners = [nodes[0], nodes[1], nodes[2]];
    let mut key = corners;
    key.sort_unstable();
    let labels = corners.map(|n| mesh.node_labels[n]);
    let candidates = map.get(&key).map(Vec::as_slice).unwrap_or(&[]);
    let same_turn = |f: &Face| (0..3).any(|r| (0..3).all(|k| f.nodes[k] == corners[(r + k) % 3]));
    let faces: Vec<Face> = candidates.iter().map(|&(el, s)| mesh.face(el, s)).collect();
    let face = match faces.as_slice() {
        [] => {
            return Err(e.loc.error(
                file,
                format!(
                    "triangle {} (nodes {} {} {}) is not a face of any 10-node tetrahedron",
                    e.tag, labels[0], labels[1], labels[2]
                ),
            ))
        }
        [only] => *only,
        many => *many.iter().find(|f| same_turn(f)).unwrap_or(&many[0]),
    };
    if e.kind == Kind::Tri6 {
        // Mid-edge node k+3 of the triangle sits on its edge (k, k+1); the face's must agree.
        for k in 0..3 {
            let (a, b) = (corners[k], corners[(k + 1) % 3]);
            let j = (0..3)
                .find(|&j| {
                    let (c, d) = (face.nodes[j], face.nodes[(j + 1) % 3]);
                    (c, d) == (a, b) || (c, d) == (b, a)
                })
                .unwrap_or(0);
            if face.nodes[j + 3] != nodes[k + 3] {
                return Err(e.loc.error(
                    file,
                    format!(
                        "triangle {} has mid-edge node {} on edge {}-{}, but element {} has node \
                         {} there",
                        e.tag,
                        mesh.node_labels[nodes[k + 3]],
                        labels[k],
                        labels[(k + 1) % 3],
                        mesh.element_labels[face.element],
                        mesh.node_labels[face.nodes[j + 3]]
                    ),
                ));
            }
        }
    }
    Ok(face)
}

// ---------------------------------------------------------------------------------------
// Writer
// ---------------------------------------------------------------------------------------

/// Write `mesh` as MSH 4.1 ASCII.
///
/// - One volume entity (and physical volume) per part, one more without a physical group for
///   elements in no part. An element in two parts is an error (Gmsh's parts are disjoint).
/// - One surface entity (and physical surface) per [`Surface`], its faces as 6-node
///   triangles in outward order.
/// - Node sets become physical points (one point entity holding one point element per node),
///   except the node set named like a surface, which reading regenerates from the surface.
///   Empty node sets are not written.
/// - Node and element labels are kept when they are positive and unique, else renumbered.
/// - Materials are not stored (MSH has no place for them), and parts or surfaces without
///   elements do not come back when the file is read.
///
/// The file is written to a temporary file in the same folder, then renamed, so a failed
/// write leaves no half-written mesh.
pub fn write(path: &Path, mesh: &Mesh) -> Result<(), MeshError> {
    let plan = Plan::new(path, mesh)?;
    write_atomically(path, |out| plan.write(out))
}

/// Write a file through a temporary file in the same folder and a rename, so that readers
/// never see a partly written file and a failed write leaves nothing behind.
pub(crate) fn write_atomically(
    path: &Path,
    fill: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<(), MeshError> {
    crate::atomic_file::write_with(path, fill).map_err(|source| MeshError::Io {
        file: path.to_path_buf(),
        source,
    })
}

/// Shortest text that reads back to the same f64, without 300-digit expansions.
fn format_f64(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || (1e-5..1e15).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Everything `write` decides before it writes a byte.
struct Plan<'m> {
    mesh: &'m Mesh,
    node_tags: Vec<u64>,
    element_tags: Vec<u64>,
    /// Volume entity (1-based) of each element.
    element_entity: Vec<usize>,
    /// Physical tag of each volume entity (None: the entity of elements in no part).
    volume_physicals: Vec<Option<usize>>,
    /// Node sets written as physical points.
    point_sets: Vec<(&'m String, &'m Vec<usize>)>,
}

/// `labels` if they are usable Gmsh tags (positive, unique, one per item), else 1..=n.
fn tags(labels: &[i64], n: usize) -> Vec<u64> {
    let usable = labels.len() == n && labels.iter().all(|&l| l > 0) && {
        let mut seen = HashSet::with_capacity(n);
        labels.iter().all(|l| seen.insert(*l))
    };
    if usable {
        labels.iter().map(|&l| l as u64).collect()
    } else {
        (1..=n as u64).collect()
    }
}

fn check_name(path: &Path, what: &str, name: &str) -> Result<(), MeshError> {
    if name.contains(['"', '\n', '\r']) {
        Err(MeshError::invalid(
            path,
            format!(
                "{what} name '{name}' holds a double quote or line break, which MSH cannot store"
            ),
        ))
    } else {
        Ok(())
    }
}

impl<'m> Plan<'m> {
    fn new(path: &Path, mesh: &'m Mesh) -> Result<Self, MeshError> {
        let invalid = |m: String| MeshError::invalid(path, m);
        if mesh.elements.is_empty() {
            return Err(invalid("nothing to write: the mesh has no elements".into()));
        }
        let n = mesh.nodes.len();
        if let Some(i) = mesh
            .nodes
            .iter()
            .position(|x| x.iter().any(|v| !v.is_finite()))
        {
            return Err(invalid(format!(
                "node {i} has a coordinate that is not finite"
            )));
        }
        for (e, conn) in mesh.elements.iter().enumerate() {
            if let Some(&bad) = conn.iter().find(|&&k| k >= n) {
                return Err(invalid(format!(
                    "element {e} refers to node {bad}, but the mesh has {n} nodes"
                )));
            }
        }
        let mut owner: Vec<Option<usize>> = vec![None; mesh.elements.len()];
        for (p, part) in mesh.parts.iter().enumerate() {
            check_name(path, "part", &part.name)?;
            for &e in &part.elements {
                match owner.get_mut(e) {
                    None => {
                        return Err(invalid(format!(
                            "part '{}' refers to element {e}, but the mesh has {} elements",
                            part.name,
                            mesh.elements.len()
                        )))
                    }
                    Some(Some(q)) if *q != p => {
                        return Err(invalid(format!(
                            "element {e} is in parts '{}' and '{}': MSH puts each element in \
                             one volume",
                            mesh.parts[*q].name, part.name
                        )))
                    }
                    Some(slot) => *slot = Some(p),
                }
            }
        }
        for (name, surface) in &mesh.surfaces {
            check_name(path, "surface", name)?;
            for face in &surface.faces {
                if face.element >= mesh.elements.len()
                    || face.side >= 4
                    || face.nodes.iter().any(|&k| k >= n)
                {
                    return Err(invalid(format!(
                        "surface '{name}' has a face (element {}, side {}) that is not in the mesh",
                        face.element, face.side
                    )));
                }
            }
        }
        let mut point_sets = Vec::new();
        for (name, set) in &mesh.node_sets {
            if mesh.surfaces.contains_key(name) || set.is_empty() {
                continue;
            }
            check_name(path, "node set", name)?;
            if let Some(&bad) = set.iter().find(|&&k| k >= n) {
                return Err(invalid(format!(
                    "node set '{name}' refers to node {bad}, but the mesh has {n} nodes"
                )));
            }
            point_sets.push((name, set));
        }
        let mut volume_physicals: Vec<Option<usize>> = (1..=mesh.parts.len()).map(Some).collect();
        let orphans = owner.iter().any(Option::is_none);
        if orphans {
            volume_physicals.push(None);
        }
        let element_entity = owner
            .iter()
            .map(|o| o.map_or(mesh.parts.len() + 1, |p| p + 1))
            .collect();
        Ok(Plan {
            mesh,
            node_tags: tags(&mesh.node_labels, n),
            element_tags: tags(&mesh.element_labels, mesh.elements.len()),
            element_entity,
            volume_physicals,
            point_sets,
        })
    }

    fn bounding_box(&self, nodes: impl Iterator<Item = usize>) -> String {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for k in nodes {
            for d in 0..3 {
                lo[d] = lo[d].min(self.mesh.nodes[k][d]);
                hi[d] = hi[d].max(self.mesh.nodes[k][d]);
            }
        }
        if lo[0] > hi[0] {
            // An entity without nodes (an empty part or surface).
            lo = [0.0; 3];
            hi = [0.0; 3];
        }
        lo.iter()
            .chain(&hi)
            .map(|&v| format_f64(v))
            .collect::<Vec<_>>()
            .join(" ")
    }

    fn write(&self, out: &mut impl Write) -> std::io::Result<()> {
        let mesh = self.mesh;
        writeln!(out, "$MeshFormat\n4.1 0 8\n$EndMeshFormat")?;

        let named = mesh.parts.len() + mesh.surfaces.len() + self.point_sets.len();
        if named > 0 {
            writeln!(out, "$PhysicalNames\n{named}")?;
            for (i, (name, _)) in self.point_sets.iter().enumerate() {
                writeln!(out, "0 {} \"{name}\"", i + 1)?;
            }
            for (i, name) in mesh.surfaces.keys().enumerate() {
                writeln!(out, "2 {} \"{name}\"", i + 1)?;
            }
            for (i, part) in mesh.parts.iter().enumerate() {
                writeln!(out, "3 {} \"{}\"", i + 1, part.name)?;
            }
            writeln!(out, "$EndPhysicalNames")?;
        }

        writeln!(out, "$Entities")?;
        writeln!(
            out,
            "{} 0 {} {}",
            self.point_sets.len(),
            mesh.surfaces.len(),
            self.volume_physicals.len()
        )?;
        for (i, (_, set)) in self.point_sets.iter().enumerate() {
            let x = mesh.nodes[set[0]].map(format_f64);
            writeln!(out, "{} {} {} {} 1 {}", i + 1, x[0], x[1], x[2], i + 1)?;
        }
        for (i, surface) in mesh.surfaces.values().enumerate() {
            let bbox = self.bounding_box(surface.faces.iter().flat_map(|f| f.nodes));
            writeln!(out, "{} {bbox} 1 {} 0", i + 1, i + 1)?;
        }
        for (i, physical) in self.volume_physicals.iter().enumerate() {
            let entity = i + 1;
            let nodes = (0..mesh.elements.len())
                .filter(|&e| self.element_entity[e] == entity)
                .flat_map(|e| mesh.elements[e]);
            let bbox = self.bounding_box(nodes);
            match physical {
                Some(p) => writeln!(out, "{entity} {bbox} 1 {p} 0")?,
                None => writeln!(out, "{entity} {bbox} 0 0")?,
            }
        }
        writeln!(out, "$EndEntities")?;

        // All nodes in one block on volume entity 1 (elements find nodes by tag, wherever
        // they are classified).
        let n = mesh.nodes.len();
        let (lo, hi) = min_max(&self.node_tags);
        writeln!(out, "$Nodes\n1 {n} {lo} {hi}\n3 1 0 {n}")?;
        for tag in &self.node_tags {
            writeln!(out, "{tag}")?;
        }
        for x in &mesh.nodes {
            writeln!(
                out,
                "{} {} {}",
                format_f64(x[0]),
                format_f64(x[1]),
                format_f64(x[2])
            )?;
        }
        writeln!(out, "$EndNodes")?;

        // Tetrahedra in runs of the same entity, so that reading gives back the same element
        // order even when parts interleave; then triangles and points, numbered after them.
        let mut runs: Vec<(usize, std::ops::Range<usize>)> = Vec::new();
        for (e, &entity) in self.element_entity.iter().enumerate() {
            match runs.last_mut() {
                Some((last, range)) if *last == entity => range.end = e + 1,
                _ => runs.push((entity, e..e + 1)),
            }
        }
        let faces: usize = mesh.surfaces.values().map(|s| s.faces.len()).sum();
        let points: usize = self.point_sets.iter().map(|(_, s)| s.len()).sum();
        let blocks = runs.len()
            + mesh
                .surfaces
                .values()
                .filter(|s| !s.faces.is_empty())
                .count()
            + self.point_sets.len();
        let (lo, hi) = min_max(&self.element_tags);
        let total = mesh.elements.len() + faces + points;
        let last = hi + (faces + points) as u64;
        writeln!(out, "$Elements\n{blocks} {total} {lo} {last}")?;
        for (entity, range) in runs {
            writeln!(out, "3 {entity} 11 {}", range.len())?;
            for e in range {
                let conn = &mesh.elements[e];
                write!(out, "{}", self.element_tags[e])?;
                for k in GMSH_TET10 {
                    write!(out, " {}", self.node_tags[conn[k]])?;
                }
                writeln!(out)?;
            }
        }
        let mut next = hi + 1;
        for (i, surface) in mesh.surfaces.values().enumerate() {
            if surface.faces.is_empty() {
                continue;
            }
            writeln!(out, "2 {} 9 {}", i + 1, surface.faces.len())?;
            for face in &surface.faces {
                // The 6-node triangle's order (corners, then mid 0-1, 1-2, 2-0) is the face's.
                write!(out, "{next}")?;
                for k in face.nodes {
                    write!(out, " {}", self.node_tags[k])?;
                }
                writeln!(out)?;
                next += 1;
            }
        }
        for (i, (_, set)) in self.point_sets.iter().enumerate() {
            writeln!(out, "0 {} 15 {}", i + 1, set.len())?;
            for &k in set.iter() {
                writeln!(out, "{next} {}", self.node_tags[k])?;
                next += 1;
            }
        }
        writeln!(out, "$EndElements")
    }
}

fn min_max(tags: &[u64]) -> (u64, u64) {
    let lo = tags.iter().copied().min().unwrap_or(0);
    let hi = tags.iter().copied().max().unwrap_or(0);
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{TET10_EDGES, TET10_FACES};
    use std::path::PathBuf;

    // Two tetrahedra sharing the face B C D:
    //   corners A=1 (0,0,0)  B=2 (1,0,0)  C=3 (0,1,0)  D=4 (0,0,1)  E=5 (1,1,1)
    //   mid-edge nodes 11=AB 12=BC 13=CA 14=AD 15=BD 16=CD 17=BE 18=CE 19=DE
    // Element 7 = A B C D, element 8 = B C D E, written in Gmsh's node order
    // (edges 0-1, 1-2, 2-0, 3-0, 3-2, 3-1). Element 7 is in physical volume "disc",
    // element 8 in none. Physical surface "friction" holds triangle 20 = C E D (a boundary
    // face of element 8, given inward on purpose) and triangle 21 = B C D (the shared face,
    // turning like element 7's outward face). Physical curve "edge" is the 3-node line A B,
    // physical point "corner" is E.
    const TWO_TETS_41: &str = r#"$MeshFormat
4.1 0 8
$EndMeshFormat
$Comments
anything at all, even $Nodes and $Elements
$EndComments
$PhysicalNames
4
0 5 "corner"
1 4 "edge"
2 3 "friction"
3 1 "disc"
$EndPhysicalNames
$Entities
1 1 1 2
1 1 1 1 1 5
1 0 0 0 1 0 0 1 4 0
1 0 0 0 1 1 1 1 3 0
1 0 0 0 1 1 1 1 1 0
2 0 0 0 1 1 1 0 0
$EndEntities
$Nodes
3 14 1 19
3 1 0 5
1
2
3
4
5
0 0 0
1 0 0
0 1 0
0 0 1
1 1 1
2 1 1 3
11
12
13
0.5 0 0 0.5 0
0.5 0.5 0 0.5 0.5
0 0.5 0 0 0.5
3 2 0 6
14
15
16
17
18
19
0 0 0.5
0.5 0 0.5
0 0.5 0.5
1 0.5 0.5
0.5 1 0.5
0.5 0.5 1
$EndNodes
$Elements
5 6 7 40
3 1 11 1
7 1 2 3 4 11 12 13 14 16 15
3 2 11 1
8 2 3 4 5 12 16 15 17 19 18
2 1 9 2
20 3 5 4 18 19 16
21 2 3 4 12 16 15
1 1 8 1
30 1 2 11
0 1 15 1
40 5
$EndElements
"#;

    // The same mesh in MSH 2.2 (physical tag first among each element's tags; 0 = none).
    const TWO_TETS_22: &str = r#"$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
4
0 5 "corner"
1 4 "edge"
2 3 "friction"
3 1 "disc"
$EndPhysicalNames
$Nodes
14
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 1 1 1
11 0.5 0 0
12 0.5 0.5 0
13 0 0.5 0
14 0 0 0.5
15 0.5 0 0.5
16 0 0.5 0.5
17 1 0.5 0.5
18 0.5 1 0.5
19 0.5 0.5 1
$EndNodes
$Elements
6
40 15 2 5 1 5
30 8 2 4 1 1 2 11
7 11 2 1 1 1 2 3 4 11 12 13 14 16 15
8 11 2 0 2 2 3 4 5 12 16 15 17 19 18
20 9 2 3 1 3 5 4 18 19 16
21 9 2 3 1 2 3 4 12 16 15
$EndElements
"#;

    /// The two-tet mesh as MSH 4.1 binary, built byte by byte from the format description
    /// (size_t = 8 bytes, int = 4 bytes, double = 8 bytes, in the given byte order).
    fn two_tets_binary(big_endian: bool) -> Vec<u8> {
        struct B(Vec<u8>, bool);
        impl B {
            fn text(&mut self, s: &str) {
                self.0.extend_from_slice(s.as_bytes());
            }
            fn size(&mut self, v: u64) {
                let b = if self.1 {
                    v.to_be_bytes()
                } else {
                    v.to_le_bytes()
                };
                self.0.extend_from_slice(&b);
            }
            fn int(&mut self, v: i32) {
                let b = if self.1 {
                    v.to_be_bytes()
                } else {
                    v.to_le_bytes()
                };
                self.0.extend_from_slice(&b);
            }
            fn double(&mut self, v: f64) {
                let b = if self.1 {
                    v.to_be_bytes()
                } else {
                    v.to_le_bytes()
                };
                self.0.extend_from_slice(&b);
            }
        }
        let mut b = B(Vec::new(), big_endian);
        b.text("$MeshFormat\n4.1 1 8\n");
        b.int(1);
        b.text("\n$EndMeshFormat\n");
        b.text("$PhysicalNames\n4\n0 5 \"corner\"\n1 4 \"edge\"\n2 3 \"friction\"\n");
        b.text("3 1 \"disc\"\n$EndPhysicalNames\n");
        b.text("$Entities\n");
        for n in [1, 1, 1, 2] {
            b.size(n);
        }
        // point 1 at E, physical 5
        b.int(1);
        for x in [1.0, 1.0, 1.0] {
            b.double(x);
        }
        b.size(1);
        b.int(5);
        // curve 1, physical 4, no bounding points
        b.int(1);
        for x in [0.0, 0.0, 0.0, 1.0, 0.0, 0.0] {
            b.double(x);
        }
        b.size(1);
        b.int(4);
        b.size(0);
        // surface 1, physical 3
        b.int(1);
        for x in [0.0, 0.0, 0.0, 1.0, 1.0, 1.0] {
            b.double(x);
        }
        b.size(1);
        b.int(3);
        b.size(0);
        // volume 1 physical 1, volume 2 no physical
        for (tag, physicals) in [(1, vec![1]), (2, vec![])] {
            b.int(tag);
            for x in [0.0, 0.0, 0.0, 1.0, 1.0, 1.0] {
                b.double(x);
            }
            b.size(physicals.len() as u64);
            for p in physicals {
                b.int(p);
            }
            b.size(0);
        }
        b.text("\n$EndEntities\n$Nodes\n");
        for n in [3, 14, 1, 19] {
            b.size(n);
        }
        type Block<'a> = (i32, i32, i32, &'a [u64], &'a [[f64; 5]]);
        let blocks: [Block; 3] = [
            (
                3,
                1,
                0,
                &[1, 2, 3, 4, 5],
                &[
                    [0.0, 0.0, 0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0, 0.0, 0.0],
                    [0.0, 0.0, 1.0, 0.0, 0.0],
                    [1.0, 1.0, 1.0, 0.0, 0.0],
                ],
            ),
            (
                2,
                1,
                1,
                &[11, 12, 13],
                &[
                    [0.5, 0.0, 0.0, 0.5, 0.0],
                    [0.5, 0.5, 0.0, 0.5, 0.5],
                    [0.0, 0.5, 0.0, 0.0, 0.5],
                ],
            ),
            (
                3,
                2,
                0,
                &[14, 15, 16, 17, 18, 19],
                &[
                    [0.0, 0.0, 0.5, 0.0, 0.0],
                    [0.5, 0.0, 0.5, 0.0, 0.0],
                    [0.0, 0.5, 0.5, 0.0, 0.0],
                    [1.0, 0.5, 0.5, 0.0, 0.0],
                    [0.5, 1.0, 0.5, 0.0, 0.0],
                    [0.5, 0.5, 1.0, 0.0, 0.0],
                ],
            ),
        ];
        for (dim, tag, parametric, tags, coords) in blocks {
            b.int(dim);
            b.int(tag);
            b.int(parametric);
            b.size(tags.len() as u64);
            for &t in tags {
                b.size(t);
            }
            for x in coords {
                let n = if parametric == 1 { 3 + dim as usize } else { 3 };
                for &v in &x[..n] {
                    b.double(v);
                }
            }
        }
        b.text("\n$EndNodes\n$Elements\n");
        for n in [5, 6, 7, 40] {
            b.size(n);
        }
        let blocks: [(i32, i32, i32, &[&[u64]]); 5] = [
            (3, 1, 11, &[&[7, 1, 2, 3, 4, 11, 12, 13, 14, 16, 15]]),
            (3, 2, 11, &[&[8, 2, 3, 4, 5, 12, 16, 15, 17, 19, 18]]),
            (
                2,
                1,
                9,
                &[&[20, 3, 5, 4, 18, 19, 16], &[21, 2, 3, 4, 12, 16, 15]],
            ),
            (1, 1, 8, &[&[30, 1, 2, 11]]),
            (0, 1, 15, &[&[40, 5]]),
        ];
        for (dim, tag, element_type, elements) in blocks {
            b.int(dim);
            b.int(tag);
            b.int(element_type);
            b.size(elements.len() as u64);
            for element in elements {
                for &v in element.iter() {
                    b.size(v);
                }
            }
        }
        b.text("\n$EndElements\n");
        b.0
    }

    fn p(name: &str) -> PathBuf {
        PathBuf::from(name)
    }

    fn parse_str(text: &str) -> Result<Mesh, MeshError> {
        parse(&p("test.msh"), text.as_bytes())
    }

    /// The two-tet mesh as worked out by hand from the comment above.
    fn check_two_tets(m: &Mesh) {
        assert_eq!(
            m.node_labels,
            [1, 2, 3, 4, 5, 11, 12, 13, 14, 15, 16, 17, 18, 19]
        );
        assert_eq!(m.nodes[4], [1.0, 1.0, 1.0]);
        assert_eq!(m.nodes[10], [0.0, 0.5, 0.5]);
        assert_eq!(m.element_labels, [7, 8]);
        // Internal order: corners, then mid 0-1, 1-2, 2-0, 0-3, 1-3, 2-3 (node indices).
        assert_eq!(m.elements[0], [0, 1, 2, 3, 5, 6, 7, 8, 9, 10]);
        assert_eq!(m.elements[1], [1, 2, 3, 4, 6, 10, 9, 11, 12, 13]);
        let parts: Vec<(&str, &[usize], Option<&String>)> = m
            .parts
            .iter()
            .map(|p| (p.name.as_str(), p.elements.as_slice(), p.material.as_ref()))
            .collect();
        assert_eq!(
            parts,
            [("disc", &[0][..], None), ("unassigned", &[1][..], None)]
        );
        let friction = &m.surfaces["friction"];
        assert_eq!(friction.name, "friction");
        let sides: Vec<(usize, u8)> = friction.faces.iter().map(|f| (f.element, f.side)).collect();
        // C D E is side 2 (internal 1 2 3) of element 8; B C D is side 2 of element 7.
        assert_eq!(sides, [(1, 2), (0, 2)]);
        for face in &friction.faces {
            assert_eq!(*face, m.face(face.element, face.side));
        }
        assert_eq!(m.surfaces.len(), 1);
        let sets: Vec<(&str, &[usize])> = m
            .node_sets
            .iter()
            .map(|(k, v)| (k.as_str(), v.as_slice()))
            .collect();
        assert_eq!(
            sets,
            [
                ("corner", &[4][..]),
                ("edge", &[0, 1, 5][..]),
                ("friction", &[1, 2, 3, 4, 6, 9, 10, 12, 13][..]),
            ]
        );
        assert!(m.materials.is_empty());
    }

    fn assert_same(a: &Mesh, b: &Mesh) {
        assert_eq!(a.nodes, b.nodes);
        assert_eq!(a.node_labels, b.node_labels);
        assert_eq!(a.elements, b.elements);
        assert_eq!(a.element_labels, b.element_labels);
        assert_eq!(a.parts, b.parts);
        assert_eq!(a.surfaces, b.surfaces);
        assert_eq!(a.node_sets, b.node_sets);
    }

    fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    fn det3(c: [[f64; 3]; 3]) -> f64 {
        c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1])
            - c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0])
            + c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0])
    }

    #[test]
    fn reads_msh41_ascii() {
        check_two_tets(&parse_str(TWO_TETS_41).unwrap());
    }

    #[test]
    fn reads_msh22_ascii() {
        check_two_tets(&parse_str(TWO_TETS_22).unwrap());
    }

    #[test]
    fn reads_msh41_binary_in_both_byte_orders() {
        for big_endian in [false, true] {
            let m = parse(&p("b.msh"), &two_tets_binary(big_endian)).unwrap();
            check_two_tets(&m);
        }
    }

    #[test]
    fn faces_of_surfaces_point_out_of_their_element() {
        let m = parse_str(TWO_TETS_41).unwrap();
        for face in &m.surfaces["friction"].faces {
            let x = |i: usize| m.nodes[face.nodes[i]];
            let conn = m.elements[face.element];
            let centroid = (0..3).map(|d| (0..4).map(|c| m.nodes[conn[c]][d]).sum::<f64>() / 4.0);
            let centroid: Vec<f64> = centroid.collect();
            let (u, v) = (sub3(x(1), x(0)), sub3(x(2), x(0)));
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let out = sub3(x(0), [centroid[0], centroid[1], centroid[2]]);
            assert!(n[0] * out[0] + n[1] * out[1] + n[2] * out[2] > 0.0);
        }
    }

    #[test]
    fn mid_edge_nodes_sit_on_the_internal_edges() {
        // Every mid-edge node of the straight two-tet mesh is the midpoint of the internal
        // edge TET10_EDGES assigns it; the Gmsh order would put nodes 8 and 9 on 2-3 and 1-3.
        let m = parse_str(TWO_TETS_41).unwrap();
        for conn in &m.elements {
            for (k, [a, b]) in TET10_EDGES.iter().enumerate() {
                let mid = [0, 1, 2].map(|d| 0.5 * (m.nodes[conn[*a]][d] + m.nodes[conn[*b]][d]));
                assert_eq!(m.nodes[conn[4 + k]], mid, "edge {a}-{b}");
            }
        }
    }

    /// Gradients of the internal-order TET10 shape functions at (xi, eta, zeta):
    /// corners N_i = L_i (2 L_i - 1), mid-edge N = 4 L_a L_b.
    fn shape_gradients(xi: [f64; 3]) -> [[f64; 3]; 10] {
        let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
        let dl = [
            [-1.0, -1.0, -1.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let mut g = [[0.0; 3]; 10];
        for i in 0..4 {
            g[i] = dl[i].map(|d| (4.0 * l[i] - 1.0) * d);
        }
        for (k, [a, b]) in TET10_EDGES.iter().enumerate() {
            g[4 + k] = [0, 1, 2].map(|d| 4.0 * (l[*b] * dl[*a][d] + l[*a] * dl[*b][d]));
        }
        g
    }

    fn jacobian_det(x: &[[f64; 3]; 10], xi: [f64; 3]) -> f64 {
        let g = shape_gradients(xi);
        let mut j = [[0.0; 3]; 3];
        for n in 0..10 {
            for r in 0..3 {
                for c in 0..3 {
                    j[r][c] += x[n][r] * g[n][c];
                }
            }
        }
        det3(j)
    }

    /// Volume of a quadratic tetrahedron, integral of det J over the reference element by a
    /// collapsed (Duffy) 3x3x3 Gauss rule: xi = u, eta = (1-u) v, zeta = (1-u)(1-v) w, with
    /// weight (1-u)^2 (1-v). det J is cubic, so the integrand has degree <= 5 in each of u, v,
    /// w, and the 3-point Gauss rule (exact to degree 5) integrates it exactly. Also returns
    /// the smallest det J met at the quadrature points.
    fn volume(x: &[[f64; 3]; 10]) -> (f64, f64) {
        let s = (0.6f64).sqrt();
        let points = [(1.0 - s) / 2.0, 0.5, (1.0 + s) / 2.0];
        let weights = [5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0];
        let (mut v, mut min) = (0.0, f64::INFINITY);
        for (u, wu) in points.iter().zip(weights) {
            for (t, wt) in points.iter().zip(weights) {
                for (w, ww) in points.iter().zip(weights) {
                    let xi = [*u, (1.0 - u) * t, (1.0 - u) * (1.0 - t) * w];
                    let d = jacobian_det(x, xi);
                    min = min.min(d);
                    v += wu * wt * ww * (1.0 - u) * (1.0 - u) * (1.0 - t) * d;
                }
            }
        }
        (v, min)
    }

    #[test]
    fn curved_element_keeps_its_volume_and_a_positive_jacobian() {
        // The unit tetrahedron with the mid node of edge 1-3 (Gmsh's last node, "3-1") pushed
        // out by d. With the straight element mapping x = xi (J0 = I), moving one node by d
        // is a rank-one update: det J = 1 + d . grad N_m, so the volume is exactly
        //   1/6 + d . integral(grad N_m) = 1/6 + d . (boundary integral of N_m n).
        // N_m = 4 L1 L3 lives on the faces y = 0 (area 1/2, n = -e_y) and x+y+z = 1
        // (area sqrt(3)/2, n = (1,1,1)/sqrt(3)); each integral of L1 L3 is area/12, so
        // integral(grad N_m) = (1, 0, 1)/6 and V = 1/6 + (d_x + d_z)/6.
        let delta = 0.1;
        let d = [delta / 2f64.sqrt(), 0.0, delta / 2f64.sqrt()];
        let gmsh = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.0, 0.0],
            [0.5, 0.5, 0.0],
            [0.0, 0.5, 0.0],
            [0.0, 0.0, 0.5],
            [0.0, 0.5, 0.5],
            [0.5 + d[0], d[1], 0.5 + d[2]],
        ];
        let mut text = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 10 1 10\n");
        text += "3 1 0 10\n";
        for i in 1..=10 {
            text += &format!("{i}\n");
        }
        for x in gmsh {
            text += &format!("{} {} {}\n", x[0], x[1], x[2]);
        }
        text += "$EndNodes\n$Elements\n1 1 1 1\n3 1 11 1\n1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";
        let m = parse_str(&text).unwrap();
        assert_eq!(m.parts.len(), 1);
        assert_eq!(
            (m.parts[0].name.as_str(), m.parts[0].elements.as_slice()),
            ("all", &[0][..])
        );
        let x: [[f64; 3]; 10] = m.elements[0].map(|k| m.nodes[k]);
        let (v, min_det) = volume(&x);
        let exact = 1.0 / 6.0 + (d[0] + d[2]) / 6.0;
        // Exact quadrature of a polynomial: only round-off (a few ulps of 1/6) remains.
        assert!((v - exact).abs() < 1e-14, "volume {v}, expected {exact}");
        assert!(min_det > 0.0);
        for corner in [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
            assert!(jacobian_det(&x, corner) > 0.0);
        }

        // The same nodes without the swap (Gmsh order taken as internal): at corner 3 the
        // Jacobian of the straight element would be det[(-1,2,0),(2,-1,0),(0,0,1)] = -3, so
        // this test cannot pass with the wrong order.
        let (v_wrong, min_wrong) = volume(&gmsh);
        assert!((v_wrong - exact).abs() > 1e-3, "{v_wrong}");
        assert!(min_wrong < 0.0);
        assert!(jacobian_det(&gmsh, [0.0, 0.0, 1.0]) < 0.0);
        let mut straight = gmsh;
        straight[9] = [0.5, 0.0, 0.5];
        assert!((jacobian_det(&straight, [0.0, 0.0, 1.0]) + 3.0).abs() < 1e-14);
    }

    #[test]
    fn msh22_merges_repeated_elements_and_reads_3_node_triangles() {
        // MSH 2.2 writes an element once per physical group: triangle 21 again (as 22) in a
        // second physical surface, as a 3-node triangle.
        let text = TWO_TETS_22
            .replace("6\n40 15", "7\n40 15")
            .replace("$EndElements", "22 2 2 6 1 2 3 4\n$EndElements");
        let m = parse_str(&text).unwrap();
        let interface = &m.surfaces["surface_6"];
        assert_eq!(interface.faces, [m.face(0, 2)]);
        assert_eq!(m.node_sets["surface_6"], [1, 2, 3, 6, 9, 10]);
        assert_eq!(m.elements.len(), 2);

        // The same tetrahedron in two physical volumes cannot be in two parts.
        let text = TWO_TETS_22.replace("6\n40 15", "7\n40 15").replace(
            "$EndElements",
            "9 11 2 2 1 1 2 3 4 11 12 13 14 16 15\n$EndElements",
        );
        let err = parse_str(&text).unwrap_err().to_string();
        assert!(
            err.contains("element 7 is in two physical volumes, 'disc' and 'volume_2'"),
            "{err}"
        );
    }

    fn line_of(text: &str, needle: &str) -> usize {
        let at = text.find(needle).expect("needle in text");
        text[..at].matches('\n').count() + 1
    }

    fn parse_error(text: &str) -> (usize, String) {
        match parse_str(text).unwrap_err() {
            MeshError::Parse {
                line,
                message,
                file,
            } => {
                assert_eq!(file, p("test.msh"));
                (line, message)
            }
            other => panic!("expected a parse error, got {other}"),
        }
    }

    #[test]
    fn truncated_files_are_errors_that_say_so() {
        let cut = TWO_TETS_41.find("21 2 3 4 12").unwrap();
        let text = &TWO_TETS_41[..cut];
        let (line, message) = parse_error(text);
        assert_eq!(line, text.lines().count());
        assert!(message.contains("ends inside $Elements"), "{message}");
        assert!(message.contains("$EndElements"), "{message}");
        assert!(message.contains("truncated"), "{message}");

        // Only the end marker missing.
        let text = TWO_TETS_41.replace("$EndElements\n", "");
        let (_, message) = parse_error(&text);
        assert!(
            message.contains("ends inside $Elements (expected $EndElements)"),
            "{message}"
        );

        // A binary file cut inside its element data: the byte offset is named.
        let bytes = two_tets_binary(false);
        let cut = bytes.len() - 40;
        match parse(&p("b.msh"), &bytes[..cut]).unwrap_err() {
            MeshError::Binary {
                offset, message, ..
            } => {
                assert!(
                    offset as usize <= cut && offset as usize > cut - 8,
                    "{offset}"
                );
                assert!(message.contains("ends inside $Elements"), "{message}");
            }
            other => panic!("expected a binary error, got {other}"),
        }
    }

    #[test]
    fn other_element_types_are_refused_by_name() {
        let text = TWO_TETS_41.replace(
            "3 2 11 1\n8 2 3 4 5 12 16 15 17 19 18",
            "3 2 4 1\n8 2 3 4 5",
        );
        let (line, message) = parse_error(&text);
        assert_eq!(line, line_of(&text, "3 2 4 1"));
        assert_eq!(
            message,
            "element type 4 (4-node tetrahedron) is not supported: squeal needs 10-node \
             tetrahedra (type 11); mesh with -order 2"
        );
        let text = TWO_TETS_22.replace("20 9 2 3 1 3 5 4 18 19 16", "20 3 2 3 1 3 5 4 18");
        let (line, message) = parse_error(&text);
        assert_eq!(line, line_of(&text, "20 3 2"));
        assert!(message.starts_with("element type 3 (4-node quadrangle) is not supported"));
    }

    #[test]
    fn a_missing_node_is_named_with_its_element() {
        let text =
            TWO_TETS_41.replace("8 2 3 4 5 12 16 15 17 19 18", "8 2 3 4 5 12 16 15 99 19 18");
        let (line, message) = parse_error(&text);
        assert_eq!(line, line_of(&text, "8 2 3 4 5 12"));
        assert_eq!(
            message,
            "element 8 refers to node 99, which is not in $Nodes"
        );
    }

    #[test]
    fn garbage_names_the_line_and_what_was_expected() {
        let text = TWO_TETS_41.replace("0.5 0 0.5\n0 0.5 0.5\n", "0.5 zero 0.5\n0 0.5 0.5\n");
        let (line, message) = parse_error(&text);
        assert_eq!(line, line_of(&text, "0.5 zero"));
        assert_eq!(message, "expected a node's y, found 'zero'");

        let text = TWO_TETS_22.replace("12 0.5 0.5 0", "12 0.5 0.5 x");
        let (line, message) = parse_error(&text);
        assert_eq!(line, line_of(&text, "12 0.5 0.5 x"));
        assert_eq!(message, "expected a node's z, found 'x'");

        let text = TWO_TETS_41.replace("5 6 7 40", "5 7 7 40");
        let (_, message) = parse_error(&text);
        assert_eq!(
            message,
            "the element blocks hold 6 elements, but $Elements declares 7"
        );

        // A block that holds more elements than it declares.
        let text = TWO_TETS_41
            .replace("5 6 7 40", "5 5 7 40")
            .replace("2 1 9 2", "2 1 9 1");
        let (line, message) = parse_error(&text);
        assert_eq!(line, line_of(&text, "21 2 3 4 12"));
        assert!(
            message.starts_with("expected an element block header"),
            "{message}"
        );
        assert!(
            message.contains("more or fewer items than it declares"),
            "{message}"
        );

        let text = TWO_TETS_41.replace("3 \"friction\"", "3 friction");
        let (line, message) = parse_error(&text);
        assert_eq!(line, line_of(&text, "2 3 friction"));
        assert!(
            message.starts_with("expected a physical name in double quotes"),
            "{message}"
        );

        let (line, message) = parse_error("hello\n");
        assert_eq!(line, 1);
        assert!(message.starts_with("expected $MeshFormat"), "{message}");
    }

    #[test]
    fn unsupported_versions_are_refused() {
        for (version, binary) in [("4.0", "0"), ("3.0", "0"), ("2.2", "1")] {
            let text = TWO_TETS_41.replace("4.1 0 8", &format!("{version} {binary} 8"));
            let (line, message) = parse_error(&text);
            assert_eq!(line, 2);
            if binary == "1" {
                assert!(
                    message.starts_with("binary MSH 2.2 is not supported"),
                    "{message}"
                );
            } else {
                assert!(
                    message.starts_with(&format!("MSH version {version} is not supported")),
                    "{message}"
                );
            }
        }
        // A binary file whose byte-order integer is neither 1 nor byte-swapped 1.
        let mut bytes = two_tets_binary(false);
        let at = "$MeshFormat\n4.1 1 8\n".len();
        bytes[at] = 2;
        match parse(&p("b.msh"), &bytes).unwrap_err() {
            MeshError::Binary {
                offset, message, ..
            } => {
                assert_eq!(offset as usize, at);
                assert!(message.contains("byte order"), "{message}");
            }
            other => panic!("expected a binary error, got {other}"),
        }
        let text = TWO_TETS_41.replace("4.1 0 8", "4.1 1 4");
        let (_, message) = parse_error(&text);
        assert!(
            message.starts_with("data size 4 is not supported"),
            "{message}"
        );
    }

    #[test]
    fn a_triangle_on_no_element_face_is_named() {
        let text = TWO_TETS_41.replace("20 3 5 4 18 19 16", "20 1 5 4 18 19 16");
        let (line, message) = parse_error(&text);
        assert_eq!(line, line_of(&text, "20 1 5 4"));
        assert_eq!(
            message,
            "triangle 20 (nodes 1 5 4) is not a face of any 10-node tetrahedron"
        );

        let text = TWO_TETS_41.replace("20 3 5 4 18 19 16", "20 3 5 4 18 17 16");
        let (_, message) = parse_error(&text);
        assert!(
            message.starts_with("triangle 20 has mid-edge node 17 on edge 5-4"),
            "{message}"
        );
    }

    #[test]
    fn inverted_elements_and_meshes_without_tets_are_refused() {
        let text =
            TWO_TETS_41.replace("7 1 2 3 4 11 12 13 14 16 15", "7 2 1 3 4 11 13 12 15 16 14");
        let (line, message) = parse_error(&text);
        assert_eq!(line, line_of(&text, "7 2 1 3 4"));
        assert!(message.starts_with("element 7 is inverted"), "{message}");

        let text = TWO_TETS_41
            .replace("5 6 7 40", "3 4 20 40")
            .replace("3 1 11 1\n7 1 2 3 4 11 12 13 14 16 15\n", "")
            .replace("3 2 11 1\n8 2 3 4 5 12 16 15 17 19 18\n", "");
        let err = parse_str(&text).unwrap_err().to_string();
        assert!(err.contains("holds no 10-node tetrahedra"), "{err}");
        assert!(err.contains("Physical Volume"), "{err}");
    }

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("squeal-gmsh-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn write_then_read_gives_the_same_mesh() {
        let dir = temp_dir("roundtrip");
        let original = parse_str(TWO_TETS_41).unwrap();
        let path = dir.join("two.msh");
        write(&path, &original).unwrap();
        let back = read(&path).unwrap();
        assert_same(&original, &back);
        check_two_tets(&back);

        // Interleaved parts and labels Gmsh cannot keep (0, repeated): the element order
        // survives, labels are renumbered.
        let mut mesh = original.clone();
        mesh.parts = vec![
            Part {
                name: "pad".into(),
                elements: vec![1],
                material: Some("steel".into()),
            },
            Part {
                name: "disc".into(),
                elements: vec![0],
                material: None,
            },
        ];
        mesh.element_labels = vec![0, 0];
        mesh.node_labels[3] = 1;
        write(&path, &mesh).unwrap();
        let back = read(&path).unwrap();
        assert_eq!(back.elements, mesh.elements);
        assert_eq!(back.nodes, mesh.nodes);
        assert_eq!(back.element_labels, [1, 2]);
        assert_eq!(back.node_labels, (1..=14).collect::<Vec<i64>>());
        let parts: Vec<(&str, &[usize])> = back
            .parts
            .iter()
            .map(|p| (p.name.as_str(), p.elements.as_slice()))
            .collect();
        assert_eq!(parts, [("pad", &[1][..]), ("disc", &[0][..])]);
        assert_eq!(back.surfaces, mesh.surfaces);
        assert_eq!(back.node_sets, mesh.node_sets);
        let listing: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(listing.len(), 1, "no temporary file is left behind");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_failed_write_leaves_no_file() {
        let dir = temp_dir("failed");
        let mut mesh = parse_str(TWO_TETS_41).unwrap();
        mesh.parts.push(Part {
            name: "twice".into(),
            elements: vec![0],
            material: None,
        });
        let path = dir.join("bad.msh");
        let err = write(&path, &mesh).unwrap_err().to_string();
        assert!(
            err.contains("element 0 is in parts 'disc' and 'twice'"),
            "{err}"
        );
        mesh.parts.pop();
        mesh.elements[1][3] = 99;
        assert!(write(&path, &mesh).is_err());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        // A folder that does not exist: an I/O error naming the file.
        let missing = dir.join("no/such/folder/x.msh");
        match write(&missing, &parse_str(TWO_TETS_41).unwrap()).unwrap_err() {
            MeshError::Io { file, .. } => assert_eq!(file, missing),
            other => panic!("expected an I/O error, got {other}"),
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    // Real Gmsh 4.8.4 output (tests/data), made from:
    //   SetFactory("OpenCASCADE");
    //   Box(1) = {0, 0, 0, 1, 1, 0.3};  Box(2) = {0.2, 0.2, 0.3, 0.5, 0.5, 0.2};
    //   BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
    //   Physical Volume("disc") = {1};  Physical Volume("pad") = {2};
    //   Physical Surface("contact") = Surface In BoundingBox{0.19,0.19,0.29, 0.71,0.71,0.31};
    //   Physical Surface("pad_top") = Surface In BoundingBox{0.19,0.19,0.49, 0.71,0.71,0.51};
    //   Physical Surface("bottom") = Surface In BoundingBox{-0.01,-0.01,-0.01, 1.01,1.01,0.01};
    //   Physical Point("origin") = Point In BoundingBox{-0.01,-0.01,-0.01, 0.01,0.01,0.01};
    //   Mesh.MeshSizeMin = 0.4;  Mesh.MeshSizeMax = 0.4;
    // with gmsh -3 -order 2 two_boxes.geo -format msh41 [-bin] (or -format msh22).
    const REAL_41: &[u8] = include_bytes!("../../tests/data/gmsh_two_boxes_41.msh");
    const REAL_41_BINARY: &[u8] = include_bytes!("../../tests/data/gmsh_two_boxes_41_binary.msh");
    const REAL_22: &[u8] = include_bytes!("../../tests/data/gmsh_two_boxes_22.msh");

    fn cross3(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    }

    #[test]
    fn real_gmsh_output_gives_exact_volumes_areas_and_outward_faces() {
        let ascii = parse(&p("a.msh"), REAL_41).unwrap();
        let binary = parse(&p("b.msh"), REAL_41_BINARY).unwrap();
        let legacy = parse(&p("c.msh"), REAL_22).unwrap();
        assert_same(&ascii, &legacy);
        // Binary holds the exact doubles, ASCII Gmsh's 16 significant digits: coordinates
        // (all <= 1 in size) agree to a few 1e-16, everything else exactly.
        assert_eq!(ascii.elements, binary.elements);
        assert_eq!(ascii.node_labels, binary.node_labels);
        assert_eq!(ascii.element_labels, binary.element_labels);
        assert_eq!(ascii.parts, binary.parts);
        assert_eq!(ascii.surfaces, binary.surfaces);
        assert_eq!(ascii.node_sets, binary.node_sets);
        for (a, b) in ascii.nodes.iter().zip(&binary.nodes) {
            for d in 0..3 {
                assert!((a[d] - b[d]).abs() <= 1e-15, "{a:?} {b:?}");
            }
        }

        let m = binary;
        // The meshes of the two boxes are straight-sided, so their corner tetrahedra tile
        // the boxes exactly: volumes 1 x 1 x 0.3 and 0.5 x 0.5 x 0.2 up to round-off.
        let names: Vec<&str> = m.parts.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["disc", "pad"]);
        for (part, exact) in m.parts.iter().zip([0.3, 0.05]) {
            let v: f64 = part.elements.iter().map(|&e| m.corner_volume(e)).sum();
            assert!((v - exact).abs() < 1e-13, "{} volume {v}", part.name);
        }
        assert_eq!(
            m.parts[0].elements.len() + m.parts[1].elements.len(),
            m.elements.len()
        );

        // Surface areas and outward normals: bottom faces look down (-z), the pad's top
        // faces up (+z); the contact faces (between disc and pad) all come from one part and
        // look away from it.
        let part_of = m.element_parts();
        let mut contact_parts = BTreeSet::new();
        for (name, area_exact) in [("bottom", 1.0), ("pad_top", 0.25), ("contact", 0.25)] {
            let surface = &m.surfaces[name];
            let mut area = 0.0;
            for face in &surface.faces {
                assert_eq!(*face, m.face(face.element, face.side));
                let x = |i: usize| m.nodes[face.nodes[i]];
                let n = cross3(sub3(x(1), x(0)), sub3(x(2), x(0)));
                let norm = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                area += 0.5 * norm;
                // Flat faces of axis-aligned boxes: the normal is +-z to round-off.
                let nz = n[2] / norm;
                match name {
                    "bottom" => assert!((nz + 1.0).abs() < 1e-12),
                    "pad_top" => assert!((nz - 1.0).abs() < 1e-12),
                    _ => {
                        let part = part_of[face.element].unwrap();
                        contact_parts.insert(part);
                        let expect = if part == 0 { 1.0 } else { -1.0 };
                        assert!((nz - expect).abs() < 1e-12);
                    }
                }
            }
            assert!((area - area_exact).abs() < 1e-13, "{name} area {area}");
            assert_eq!(m.node_sets[name], m.surface_nodes(surface));
        }
        assert_eq!(contact_parts.len(), 1);
        let origin = &m.node_sets["origin"];
        assert_eq!(origin.len(), 1);
        assert_eq!(m.nodes[origin[0]], [0.0, 0.0, 0.0]);

        // Writing and reading it back changes nothing.
        let dir = temp_dir("real");
        let path = dir.join("boxes.msh");
        write(&path, &m).unwrap();
        assert_same(&read(&path).unwrap(), &m);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_node_order_table_matches_the_documented_faces() {
        // Gmsh's face 0-1-2 of the tet is internal face S1 with the same mid nodes.
        let gmsh_face_012_mids = [4, 5, 6].map(|k| GMSH_TET10[k]);
        assert_eq!(gmsh_face_012_mids, [4, 5, 6]);
        let mut face = TET10_FACES[0];
        face.sort_unstable();
        assert_eq!(face, [0, 1, 2, 4, 5, 6]);
        // The permutation is an involution, so it converts both ways.
        for k in 0..10 {
            assert_eq!(GMSH_TET10[GMSH_TET10[k]], k);
        }
    }

    #[test]
    fn floats_are_written_so_they_read_back_exactly() {
        for x in [
            0.0,
            -0.0,
            0.1,
            1.0 / 3.0,
            1e-300,
            6.02e23,
            -2.5e-7,
            123456.789,
        ] {
            let s = format_f64(x);
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{s}");
            assert!(s.len() < 30, "{s}");
        }
    }
}
