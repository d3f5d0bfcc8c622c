//! VTK XML UnstructuredGrid (`.vtu`) files for ParaView: the mesh as quadratic tetrahedra,
//! optional extra points shown as vertex cells (e.g. reduced contact nodes that belong to no
//! element), and f64 point and cell fields.
//!
//! Node order: VTK's `vtkQuadraticTetra` (cell type 24) documents its points as "ids 0-3 are
//! the four tetra vertices; and point ids 4-9 are the midedge nodes between (0,1), (1,2),
//! (2,0), (0,3), (1,3), and (2,3)" (VTK class reference, vtkQuadraticTetra,
//! <https://vtk.org/doc/nightly/html/classvtkQuadraticTetra.html>). That is the internal
//! order of [`crate::mesh::TET10_EDGES`], so elements are written as they are.
//!
//! Data arrays are written either as ASCII or, by default, as inline base64 binary
//! (`format="binary"`): for each array, an 8-byte little-endian byte count
//! (`header_type="UInt64"`) followed by the little-endian values, base64-encoded as one
//! stream, which is how VTK's own writer encodes uncompressed data.

use std::io::Write;
use std::path::Path;

use crate::mesh::{Mesh, MeshError};

/// VTK cell type of a 10-node tetrahedron (`VTK_QUADRATIC_TETRA`).
pub const VTK_QUADRATIC_TETRA: u8 = 24;
/// VTK cell type of a single point (`VTK_VERTEX`).
pub const VTK_VERTEX: u8 = 1;

/// A named array of f64 values with `components` values per point (or cell), stored point
/// after point: `values[i * components + c]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    pub name: String,
    pub components: usize,
    pub values: Vec<f64>,
}

impl Field {
    /// A field with `components` values per item.
    pub fn new(name: impl Into<String>, components: usize, values: Vec<f64>) -> Self {
        Field {
            name: name.into(),
            components,
            values,
        }
    }

    /// One value per item.
    pub fn scalar(name: impl Into<String>, values: Vec<f64>) -> Self {
        Field::new(name, 1, values)
    }

    /// A 3-vector per item (ParaView shows it as a vector: glyphs, warp by vector).
    pub fn vector(name: impl Into<String>, values: &[[f64; 3]]) -> Self {
        Field::new(name, 3, values.iter().flatten().copied().collect())
    }

    /// Cell field "part": the index in [`Mesh::parts`] of each element's part, -1 for an
    /// element in no part and for each of the `extra_cells` vertex cells that follow the
    /// elements.
    pub fn part_ids(mesh: &Mesh, extra_cells: usize) -> Self {
        let mut values: Vec<f64> = mesh
            .element_parts()
            .iter()
            .map(|p| p.map_or(-1.0, |p| p as f64))
            .collect();
        values.resize(values.len() + extra_cells, -1.0);
        Field::scalar("part", values)
    }
}

/// How data arrays are stored in the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Encoding {
    /// Human-readable numbers; large files, slow to load.
    Ascii,
    /// Inline base64 of the raw little-endian values: exact and about 3 times smaller.
    #[default]
    Base64,
}

/// Writes one `.vtu` file: the mesh's quadratic tetrahedra, then one vertex cell per extra
/// point. Point fields have one entry per mesh node followed by one per extra point; cell
/// fields one per element followed by one per extra point.
///
/// ```no_run
/// # use squeal::io::vtu::{Field, VtuWriter};
/// # use squeal::mesh::Mesh;
/// # fn f(mesh: &Mesh, u: &[[f64; 3]]) -> Result<(), squeal::mesh::MeshError> {
/// let shape = Field::vector("mode 1", u);
/// let parts = Field::part_ids(mesh, 0);
/// VtuWriter::new(mesh).point_field(&shape).cell_field(&parts).write("mode1.vtu".as_ref())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct VtuWriter<'a> {
    mesh: &'a Mesh,
    extra_points: &'a [[f64; 3]],
    point_fields: Vec<&'a Field>,
    cell_fields: Vec<&'a Field>,
    encoding: Encoding,
}

impl<'a> VtuWriter<'a> {
    pub fn new(mesh: &'a Mesh) -> Self {
        VtuWriter {
            mesh,
            extra_points: &[],
            point_fields: Vec::new(),
            cell_fields: Vec::new(),
            encoding: Encoding::default(),
        }
    }

    /// Points that belong to no element, written after the mesh nodes (point ids
    /// `mesh.nodes.len()..`) with one `VTK_VERTEX` cell each.
    pub fn extra_points(mut self, points: &'a [[f64; 3]]) -> Self {
        self.extra_points = points;
        self
    }

    pub fn point_field(mut self, field: &'a Field) -> Self {
        self.point_fields.push(field);
        self
    }

    pub fn cell_field(mut self, field: &'a Field) -> Self {
        self.cell_fields.push(field);
        self
    }

    pub fn encoding(mut self, encoding: Encoding) -> Self {
        self.encoding = encoding;
        self
    }

    fn point_count(&self) -> usize {
        self.mesh.nodes.len() + self.extra_points.len()
    }

    fn cell_count(&self) -> usize {
        self.mesh.elements.len() + self.extra_points.len()
    }

    /// Check sizes and values before anything is written; `file` names the target in errors.
    fn check(&self, file: &Path) -> Result<(), MeshError> {
        let invalid = |m: String| MeshError::invalid(file, m);
        let n = self.mesh.nodes.len();
        for (e, conn) in self.mesh.elements.iter().enumerate() {
            if let Some(&bad) = conn.iter().find(|&&k| k >= n) {
                return Err(invalid(format!(
                    "element {e} refers to node {bad}, but the mesh has {n} nodes"
                )));
            }
        }
        let points = self.mesh.nodes.iter().chain(self.extra_points);
        if let Some(i) = points
            .into_iter()
            .position(|x| x.iter().any(|v| !v.is_finite()))
        {
            return Err(invalid(format!(
                "point {i} has a coordinate that is not finite"
            )));
        }
        let groups = [
            ("point", &self.point_fields, self.point_count()),
            ("cell", &self.cell_fields, self.cell_count()),
        ];
        for (kind, fields, count) in groups {
            for field in fields.iter() {
                if field.components == 0 {
                    return Err(invalid(format!(
                        "{kind} field '{}' has 0 components",
                        field.name
                    )));
                }
                let expected = count.checked_mul(field.components);
                if expected != Some(field.values.len()) {
                    return Err(invalid(format!(
                        "{kind} field '{}' has {} values, expected {count} {kind}s x {} \
                         components",
                        field.name,
                        field.values.len(),
                        field.components
                    )));
                }
                if self.encoding == Encoding::Ascii {
                    // VTK's ASCII reader cannot read "NaN" or "inf" back.
                    if let Some(i) = field.values.iter().position(|v| !v.is_finite()) {
                        return Err(invalid(format!(
                            "{kind} field '{}' holds the value {} at index {i}, which ASCII VTK \
                             cannot store (use the base64 encoding)",
                            field.name, field.values[i]
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    /// Write the file (through a temporary file and a rename, so a failed write leaves no
    /// half-written file).
    pub fn write(&self, path: &Path) -> Result<(), MeshError> {
        self.check(path)?;
        crate::atomic_file::write_with(path, |out| self.write_xml(out))
            .map_err(|source| MeshError::io(path, source))
    }

    /// The file's contents; `file` only names the target in error messages.
    pub fn to_bytes(&self, file: &Path) -> Result<Vec<u8>, MeshError> {
        self.check(file)?;
        let mut out = Vec::new();
        self.write_xml(&mut out).map_err(|source| MeshError::Io {
            file: file.to_path_buf(),
            source,
        })?;
        Ok(out)
    }

    fn write_xml(&self, out: &mut impl Write) -> std::io::Result<()> {
        let mesh = self.mesh;
        writeln!(out, "<?xml version=\"1.0\"?>")?;
        writeln!(
            out,
            "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
             header_type=\"UInt64\">"
        )?;
        writeln!(out, "  <UnstructuredGrid>")?;
        writeln!(
            out,
            "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
            self.point_count(),
            self.cell_count()
        )?;
        for (tag, fields) in [
            ("PointData", &self.point_fields),
            ("CellData", &self.cell_fields),
        ] {
            if fields.is_empty() {
                continue;
            }
            writeln!(out, "      <{tag}>")?;
            for field in fields.iter() {
                let name = format!(" Name=\"{}\"", xml_escape(&field.name));
                self.data_array(out, &name, field.components, &Values::F64(&field.values))?;
            }
            writeln!(out, "      </{tag}>")?;
        }

        writeln!(out, "      <Points>")?;
        let coords: Vec<f64> = mesh
            .nodes
            .iter()
            .chain(self.extra_points)
            .flatten()
            .copied()
            .collect();
        self.data_array(out, " Name=\"Points\"", 3, &Values::F64(&coords))?;
        writeln!(out, "      </Points>")?;

        writeln!(out, "      <Cells>")?;
        let n = mesh.nodes.len();
        let connectivity: Vec<i64> = mesh
            .elements
            .iter()
            .flatten()
            .map(|&k| k as i64)
            .chain((0..self.extra_points.len()).map(|i| (n + i) as i64))
            .collect();
        let tets = mesh.elements.len();
        let offsets: Vec<i64> = (1..=tets)
            .map(|e| 10 * e as i64)
            .chain((1..=self.extra_points.len()).map(|i| (10 * tets + i) as i64))
            .collect();
        let mut types = vec![VTK_QUADRATIC_TETRA; tets];
        types.resize(self.cell_count(), VTK_VERTEX);
        self.data_array(
            out,
            " Name=\"connectivity\"",
            1,
            &Values::I64(&connectivity),
        )?;
        self.data_array(out, " Name=\"offsets\"", 1, &Values::I64(&offsets))?;
        self.data_array(out, " Name=\"types\"", 1, &Values::U8(&types))?;
        writeln!(out, "      </Cells>")?;
        writeln!(out, "    </Piece>")?;
        writeln!(out, "  </UnstructuredGrid>")?;
        writeln!(out, "</VTKFile>")
    }

    fn data_array(
        &self,
        out: &mut impl Write,
        name: &str,
        components: usize,
        values: &Values,
    ) -> std::io::Result<()> {
        let format = match self.encoding {
            Encoding::Ascii => "ascii",
            Encoding::Base64 => "binary",
        };
        writeln!(
            out,
            "        <DataArray type=\"{}\"{name} NumberOfComponents=\"{components}\" \
             format=\"{format}\">",
            values.vtk_type()
        )?;
        match self.encoding {
            Encoding::Ascii => values.write_ascii(out, components)?,
            Encoding::Base64 => {
                // The UInt64 byte count, then the values, encoded as one base64 stream.
                let mut bytes = Vec::with_capacity(8 + values.byte_len());
                bytes.extend_from_slice(&(values.byte_len() as u64).to_le_bytes());
                values.append_little_endian(&mut bytes);
                out.write_all(base64_encode(&bytes).as_bytes())?;
                writeln!(out)?;
            }
        }
        writeln!(out, "        </DataArray>")
    }
}

/// Write `mesh` with point and cell fields as a `.vtu` file (base64 binary).
pub fn write_vtu(
    path: &Path,
    mesh: &Mesh,
    point_fields: &[Field],
    cell_fields: &[Field],
) -> Result<(), MeshError> {
    let writer = point_fields
        .iter()
        .fold(VtuWriter::new(mesh), |w, f| w.point_field(f));
    cell_fields
        .iter()
        .fold(writer, |w, f| w.cell_field(f))
        .write(path)
}

enum Values<'v> {
    F64(&'v [f64]),
    I64(&'v [i64]),
    U8(&'v [u8]),
}

impl Values<'_> {
    fn vtk_type(&self) -> &'static str {
        match self {
            Values::F64(_) => "Float64",
            Values::I64(_) => "Int64",
            Values::U8(_) => "UInt8",
        }
    }

    fn byte_len(&self) -> usize {
        match self {
            Values::F64(v) => 8 * v.len(),
            Values::I64(v) => 8 * v.len(),
            Values::U8(v) => v.len(),
        }
    }

    fn append_little_endian(&self, out: &mut Vec<u8>) {
        match self {
            Values::F64(v) => out.extend(v.iter().flat_map(|x| x.to_le_bytes())),
            Values::I64(v) => out.extend(v.iter().flat_map(|x| x.to_le_bytes())),
            Values::U8(v) => out.extend_from_slice(v),
        }
    }

    fn write_ascii(&self, out: &mut impl Write, per_line: usize) -> std::io::Result<()> {
        // One point (or cell) per line for readability; `{:e}` is the shortest text that
        // reads back to the same f64 and never expands to hundreds of digits.
        let items: Vec<String> = match self {
            Values::F64(v) => v.iter().map(|x| format!("{x:e}")).collect(),
            Values::I64(v) => v.iter().map(i64::to_string).collect(),
            Values::U8(v) => v.iter().map(u8::to_string).collect(),
        };
        let per_line = if per_line == 1 { 10 } else { per_line };
        for chunk in items.chunks(per_line) {
            writeln!(out, "          {}", chunk.join(" "))?;
        }
        Ok(())
    }
}

fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// Standard base64 (RFC 4648, section 4: alphabet A-Z a-z 0-9 + /, '=' padding).
pub fn base64_encode(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        // Three bytes make 24 bits, read as four 6-bit digits; a short final chunk is
        // zero-filled and its missing digits are written as '='.
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Part, TET10_EDGES};
    use std::collections::BTreeMap;
    use std::path::PathBuf;

    #[test]
    fn base64_matches_the_rfc_4648_test_vectors() {
        // RFC 4648, section 10.
        let vectors = [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ];
        for (plain, encoded) in vectors {
            assert_eq!(base64_encode(plain.as_bytes()), encoded);
        }
        // All 256 byte values survive a round trip through an independent decoder.
        let all: Vec<u8> = (0..=255).collect();
        assert_eq!(base64_decode(&base64_encode(&all)), all);
        assert_eq!(base64_encode(&[0xff, 0xfe, 0xfd]), "//79");
    }

    /// Test-only decoder, written from the RFC's description, not from the encoder.
    fn base64_decode(text: &str) -> Vec<u8> {
        let value = |c: u8| -> u32 {
            match c {
                b'A'..=b'Z' => (c - b'A') as u32,
                b'a'..=b'z' => (c - b'a') as u32 + 26,
                b'0'..=b'9' => (c - b'0') as u32 + 52,
                b'+' => 62,
                b'/' => 63,
                _ => panic!("not base64: {c}"),
            }
        };
        let text: Vec<u8> = text.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
        assert_eq!(text.len() % 4, 0);
        let mut out = Vec::new();
        for group in text.chunks(4) {
            let pad = group.iter().filter(|&&c| c == b'=').count();
            let mut n = 0u32;
            for &c in group {
                n = (n << 6) | if c == b'=' { 0 } else { value(c) };
            }
            let bytes = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
            out.extend_from_slice(&bytes[..3 - pad]);
        }
        out
    }

    /// A minimal XML element tree: enough to check nesting and read attributes and text.
    #[derive(Debug, Default)]
    struct Element {
        name: String,
        attributes: BTreeMap<String, String>,
        children: Vec<Element>,
        text: String,
    }

    impl Element {
        fn child(&self, name: &str) -> &Element {
            self.children
                .iter()
                .find(|c| c.name == name)
                .unwrap_or_else(|| panic!("<{}> has no <{name}>", self.name))
        }
        fn array(&self, name: &str) -> &Element {
            self.children
                .iter()
                .find(|c| c.name == "DataArray" && c.attributes["Name"] == name)
                .unwrap_or_else(|| panic!("<{}> has no DataArray {name}", self.name))
        }
    }

    /// Parses the writer's output: declaration, nested elements with quoted attributes,
    /// text. Panics on anything malformed (unbalanced or mismatched tags, stray text).
    fn parse_xml(text: &str) -> Element {
        let rest = text.trim_start();
        let rest = rest.strip_prefix("<?xml").expect("XML declaration");
        let mut rest = &rest[rest.find("?>").expect("end of declaration") + 2..];
        let mut stack: Vec<Element> = vec![Element::default()];
        loop {
            let open = match rest.find('<') {
                Some(i) => i,
                None => {
                    assert!(rest.trim().is_empty(), "text after the root: {rest}");
                    break;
                }
            };
            stack.last_mut().unwrap().text.push_str(&rest[..open]);
            let close = rest[open..].find('>').expect("unclosed tag") + open;
            let tag = &rest[open + 1..close];
            rest = &rest[close + 1..];
            if let Some(name) = tag.strip_prefix('/') {
                let done = stack.pop().unwrap();
                assert_eq!(done.name, name.trim(), "mismatched closing tag");
                stack
                    .last_mut()
                    .expect("closing tag without opening")
                    .children
                    .push(done);
                continue;
            }
            let self_closing = tag.ends_with('/');
            let tag = tag.trim_end_matches('/');
            let mut parts = tag.splitn(2, char::is_whitespace);
            let mut element = Element {
                name: parts.next().unwrap().to_string(),
                ..Default::default()
            };
            let mut attrs = parts.next().unwrap_or("").trim();
            while !attrs.is_empty() {
                let eq = attrs.find("=\"").expect("attribute =\"");
                let key = attrs[..eq].trim().to_string();
                let end = attrs[eq + 2..].find('"').expect("closing quote") + eq + 2;
                let value = attrs[eq + 2..end]
                    .replace("&lt;", "<")
                    .replace("&gt;", ">")
                    .replace("&quot;", "\"")
                    .replace("&apos;", "'")
                    .replace("&amp;", "&");
                assert!(
                    element.attributes.insert(key, value).is_none(),
                    "repeated attribute"
                );
                attrs = attrs[end + 1..].trim_start();
            }
            if self_closing {
                stack.last_mut().unwrap().children.push(element);
            } else {
                stack.push(element);
            }
        }
        assert_eq!(stack.len(), 1, "unclosed elements");
        let mut root = stack.pop().unwrap();
        assert_eq!(root.children.len(), 1, "one root element");
        root.children.pop().unwrap()
    }

    /// Values of a DataArray as f64 (decoding base64 with its UInt64 byte-count header).
    fn values(array: &Element) -> Vec<f64> {
        let kind = array.attributes["type"].as_str();
        match array.attributes["format"].as_str() {
            "ascii" => array
                .text
                .split_ascii_whitespace()
                .map(|t| t.parse().unwrap())
                .collect(),
            "binary" => {
                let bytes = base64_decode(array.text.trim());
                let count = u64::from_le_bytes(bytes[..8].try_into().unwrap()) as usize;
                let data = &bytes[8..];
                assert_eq!(data.len(), count, "header byte count");
                match kind {
                    "Float64" => data
                        .chunks(8)
                        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                        .collect(),
                    "Int64" => data
                        .chunks(8)
                        .map(|c| i64::from_le_bytes(c.try_into().unwrap()) as f64)
                        .collect(),
                    "UInt8" => data.iter().map(|&b| b as f64).collect(),
                    other => panic!("unexpected type {other}"),
                }
            }
            other => panic!("unexpected format {other}"),
        }
    }

    /// Two tetrahedra sharing a face (corners A B C D and B C D E), mid-edge nodes added
    /// edge by edge in internal order; element 0 in part "disc", element 1 in none.
    fn two_tets() -> Mesh {
        let mut nodes = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
        ];
        let mut elements = Vec::new();
        let mut mids = BTreeMap::new();
        for corners in [[0, 1, 2, 3], [1, 2, 3, 4]] {
            let mut conn = [0; 10];
            conn[..4].copy_from_slice(&corners);
            for (k, [a, b]) in TET10_EDGES.iter().enumerate() {
                let key = (corners[*a].min(corners[*b]), corners[*a].max(corners[*b]));
                conn[4 + k] = *mids.entry(key).or_insert_with(|| {
                    let (x, y): ([f64; 3], [f64; 3]) = (nodes[key.0], nodes[key.1]);
                    nodes.push([0, 1, 2].map(|d| 0.5 * (x[d] + y[d])));
                    nodes.len() - 1
                });
            }
            elements.push(conn);
        }
        Mesh {
            node_labels: (1..=nodes.len() as i64).collect(),
            nodes,
            element_labels: vec![1, 2],
            elements,
            parts: vec![Part {
                name: "disc".into(),
                elements: vec![0],
                material: None,
            }],
            ..Default::default()
        }
    }

    #[test]
    fn writes_well_formed_vtu_that_reads_back() {
        let mesh = two_tets();
        assert_eq!(mesh.nodes.len(), 14);
        let extra = [[2.0, 2.0, 2.0], [3.0, -1.0, 0.5]];
        let points = mesh.nodes.len() + extra.len();
        let temperature = Field::scalar("T <K> & \"x\"", (0..points).map(|i| i as f64).collect());
        let shape: Vec<[f64; 3]> = (0..points)
            .map(|i| [i as f64, -(i as f64), 0.1 * i as f64])
            .collect();
        let shape = Field::vector("mode 1", &shape);
        let parts = Field::part_ids(&mesh, extra.len());
        assert_eq!(parts.values, [0.0, -1.0, -1.0, -1.0]);

        for encoding in [Encoding::Base64, Encoding::Ascii] {
            let writer = VtuWriter::new(&mesh)
                .extra_points(&extra)
                .point_field(&temperature)
                .point_field(&shape)
                .cell_field(&parts)
                .encoding(encoding);
            let bytes = writer.to_bytes(&PathBuf::from("t.vtu")).unwrap();
            let root = parse_xml(std::str::from_utf8(&bytes).unwrap());
            assert_eq!(root.name, "VTKFile");
            assert_eq!(root.attributes["type"], "UnstructuredGrid");
            assert_eq!(root.attributes["header_type"], "UInt64");
            let piece = root.child("UnstructuredGrid").child("Piece");
            assert_eq!(piece.attributes["NumberOfPoints"], "16");
            assert_eq!(piece.attributes["NumberOfCells"], "4");

            let xyz = values(piece.child("Points").array("Points"));
            let expected: Vec<f64> = mesh.nodes.iter().chain(&extra).flatten().copied().collect();
            assert_eq!(xyz, expected);

            let cells = piece.child("Cells");
            let connectivity = values(cells.array("connectivity"));
            let mut expected: Vec<f64> =
                mesh.elements.iter().flatten().map(|&k| k as f64).collect();
            expected.extend([14.0, 15.0]);
            assert_eq!(connectivity, expected);
            assert_eq!(values(cells.array("offsets")), [10.0, 20.0, 21.0, 22.0]);
            assert_eq!(values(cells.array("types")), [24.0, 24.0, 1.0, 1.0]);

            let point_data = piece.child("PointData");
            assert_eq!(
                values(point_data.array("T <K> & \"x\"")),
                temperature.values
            );
            let mode = point_data.array("mode 1");
            assert_eq!(mode.attributes["NumberOfComponents"], "3");
            assert_eq!(values(mode), shape.values);
            assert_eq!(values(piece.child("CellData").array("part")), parts.values);
        }
    }

    #[test]
    fn vtk_mid_edge_nodes_are_the_midpoints_vtk_expects() {
        // vtkQuadraticTetra: ids 4-9 are mid-edge nodes of (0,1) (1,2) (2,0) (0,3) (1,3)
        // (2,3). Check the written connectivity against that list directly.
        let mesh = two_tets();
        let vtk_edges = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
        let bytes = VtuWriter::new(&mesh)
            .to_bytes(&PathBuf::from("t.vtu"))
            .unwrap();
        let root = parse_xml(std::str::from_utf8(&bytes).unwrap());
        let piece = root.child("UnstructuredGrid").child("Piece");
        let xyz = values(piece.child("Points").array("Points"));
        let conn = values(piece.child("Cells").array("connectivity"));
        let x = |id: f64| [0, 1, 2].map(|d| xyz[3 * id as usize + d]);
        for cell in conn.chunks(10) {
            for (k, [a, b]) in vtk_edges.iter().enumerate() {
                let mid = [0, 1, 2].map(|d| 0.5 * (x(cell[*a])[d] + x(cell[*b])[d]));
                assert_eq!(x(cell[4 + k]), mid);
            }
        }
    }

    #[test]
    fn wrong_field_sizes_are_refused_and_nothing_is_written() {
        let mesh = two_tets();
        let dir = std::env::temp_dir().join(format!("squeal-vtu-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bad.vtu");
        let short = Field::new("u", 3, vec![0.0; 3 * 14 - 1]);
        let err = write_vtu(&path, &mesh, &[short], &[])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("point field 'u' has 41 values, expected 14 points x 3"),
            "{err}"
        );
        let cells = Field::scalar("part", vec![0.0; 3]);
        let err = write_vtu(&path, &mesh, &[], &[cells])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("cell field 'part' has 3 values, expected 2 cells"),
            "{err}"
        );
        let nan = Field::scalar("p", vec![f64::NAN; 14]);
        let ascii = VtuWriter::new(&mesh)
            .point_field(&nan)
            .encoding(Encoding::Ascii);
        assert!(ascii.write(&path).is_err());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);

        // A good write leaves exactly the file.
        write_vtu(&path, &mesh, &[], &[Field::part_ids(&mesh, 0)]).unwrap();
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["bad.vtu"]);
        let text = std::fs::read_to_string(&path).unwrap();
        let root = parse_xml(&text);
        assert_eq!(
            root.child("UnstructuredGrid").child("Piece").attributes["NumberOfCells"],
            "2"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
