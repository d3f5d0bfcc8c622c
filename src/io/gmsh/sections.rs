//! The section parser: `$MeshFormat`, `$PhysicalNames`, `$Entities`, `$Nodes` and
//! `$Elements` of MSH 4.1 (ASCII or binary) and 2.2 (ASCII) into raw records, node tags not
//! yet resolved. A file that stops before a section's end marker is an error, never a
//! shorter mesh.

use std::collections::HashMap;
use std::path::Path;

use super::cursor::{parse_number, show, Cursor, Loc};
use super::element_types::{refusal, type_name, Kind};
use crate::mesh::MeshError;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Version {
    V41,
    V22,
}

/// An element as read, before node tags are resolved.
pub(super) struct RawElement {
    pub(super) tag: u64,
    pub(super) kind: Kind,
    /// (dimension, tag) of the entity that carries its physical groups. In MSH 2.2 the
    /// "entity" is (dimension, physical tag) so that both versions resolve the same way.
    pub(super) entity: (i32, i32),
    /// Index of its first node tag in [`Raw::element_nodes`].
    pub(super) first: usize,
    pub(super) loc: Loc,
}

/// Everything the sections said, resolved afterwards by [`build`](super::build::build).
#[derive(Default)]
pub(super) struct Raw {
    pub(super) names: HashMap<(i32, i32), String>,
    /// Physical tags of each entity; `None` when the file has no `$Entities` section.
    pub(super) entities: Option<HashMap<(i32, i32), Vec<i32>>>,
    pub(super) node_tags: Vec<u64>,
    pub(super) coords: Vec<[f64; 3]>,
    pub(super) node_index: HashMap<u64, usize>,
    pub(super) elements: Vec<RawElement>,
    pub(super) element_nodes: Vec<u64>,
}

pub(super) struct Parser<'a> {
    c: Cursor<'a>,
    version: Version,
    raw: Raw,
    seen_nodes: bool,
    seen_elements: bool,
    /// Read the binary numbers in the other byte order than the check word says (to tell a
    /// wrong check word from a damaged file, see [`super::parse`]).
    against_check: bool,
}

impl<'a> Parser<'a> {
    pub(super) fn new(file: &'a Path, bytes: &'a [u8]) -> Self {
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
            against_check: false,
        }
    }

    pub(super) fn file(&self) -> &'a Path {
        self.c.file
    }

    /// The same parser, reading binary numbers against the byte-order check word.
    pub(super) fn against_byte_order_check(mut self) -> Self {
        self.against_check = true;
        self
    }

    pub(super) fn run(mut self) -> Result<Raw, MeshError> {
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
            } != self.against_check;
        }
        self.c.expect_end()
    }

    fn physical_names(&mut self) -> Result<(), MeshError> {
        let file = self.file();
        self.c.section = "$PhysicalNames";
        let what = "the number of physical names";
        let (count, _) = self.c.ascii_number::<u64>(what)?;
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

    pub(super) fn entities(&mut self, loc: Loc) -> Result<(), MeshError> {
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
                let what = "the number of physical tags";
                let n = self.c.size_count(what, 1, 4)?;
                let mut physicals = Vec::with_capacity(n);
                for _ in 0..n {
                    physicals.push(self.c.int("a physical tag")?.0);
                }
                if dim > 0 {
                    let what = "the number of bounding entities";
                    let (n, _) = self.c.size(what)?;
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
        let what = "the number of nodes";
        let declared_at = self.c.size(what)?;
        self.c.size("the smallest node tag")?;
        self.c.size("the largest node tag")?;
        // A node: its tag and 3 coordinates.
        let cap = self.c.count(declared_at, 4, 32, what)?;
        let declared = cap as u64;
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
        let what = "the number of nodes";
        // A node line: tag x y z.
        let count = self.c.ascii_count(what, 4)?;
        let cap = count;
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
        // Nothing is sized by these counts: a block that declares more elements than the
        // file holds stops at the end of the file, saying so.
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
            // Checked: a binary block of 2^64 - 1 elements once overflowed the tally (fuzzing).
            found = found.checked_add(n).ok_or_else(|| {
                loc.error(
                    file,
                    format!(
                        "the element blocks declare more than 2^64 elements: this block \
                         declares {n}"
                    ),
                )
            })?;
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

pub(super) fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::super::parse;
    use super::super::test_support::*;
    use crate::mesh::MeshError;

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
}
