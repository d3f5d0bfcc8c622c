//! Stable hashes of meshes and texts: FNV-1a per field of a [`Mesh`], the same on every
//! machine and Rust version. The pinned mesh fingerprints (tests) and the mesh and study
//! hashes a super-element file records (to refuse another mesh's) are built on them.

use super::Mesh;

/// FNV-1a, 64 bit: tiny, dependency-free and stable across Rust versions (unlike
/// `DefaultHasher`, whose algorithm is unspecified).
pub(crate) struct Fnv(pub(crate) u64);

impl Fnv {
    pub(crate) fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    pub(crate) fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    pub(crate) fn u64(&mut self, x: u64) {
        self.bytes(&x.to_le_bytes());
    }
    pub(crate) fn usize(&mut self, x: usize) {
        self.u64(x as u64);
    }
    pub(crate) fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }
    /// Length-prefixed, so that ("ab", "c") and ("a", "bc") differ.
    pub(crate) fn str(&mut self, s: &str) {
        self.usize(s.len());
        self.bytes(s.as_bytes());
    }
}

/// One hash of a whole mesh (every field of its fingerprint), as 16 hex digits: what a
/// super-element file records to refuse being used with another mesh.
pub fn mesh_hash(m: &Mesh) -> String {
    let mut all = Fnv::new();
    fingerprint(m).iter().for_each(|&h| all.u64(h));
    format!("{:016x}", all.0)
}

/// The FNV-1a hash of a file's bytes, as 16 hex digits.
pub fn bytes_hash(bytes: &[u8]) -> String {
    let mut h = Fnv::new();
    h.usize(bytes.len());
    h.bytes(bytes);
    format!("{:016x}", h.0)
}

/// The FNV-1a hash of a text (a study written out), as 16 hex digits.
pub fn text_hash(text: &str) -> String {
    let mut h = Fnv::new();
    h.str(text);
    format!("{:016x}", h.0)
}

/// Hashes of the fields of a mesh: nodes, node labels, elements (with labels), parts and
/// materials, node sets, surfaces.
pub(crate) type Fingerprint = [u64; 6];

pub(crate) fn fingerprint(m: &Mesh) -> Fingerprint {
    let mut nodes = Fnv::new();
    nodes.usize(m.nodes.len());
    for x in &m.nodes {
        x.iter().for_each(|&c| nodes.f64(c));
    }
    let mut node_labels = Fnv::new();
    node_labels.usize(m.node_labels.len());
    m.node_labels
        .iter()
        .for_each(|&l| node_labels.u64(l as u64));
    let mut elements = Fnv::new();
    elements.usize(m.elements.len());
    for conn in &m.elements {
        conn.iter().for_each(|&n| elements.usize(n));
    }
    elements.usize(m.element_labels.len());
    m.element_labels
        .iter()
        .for_each(|&l| elements.u64(l as u64));
    let mut parts = Fnv::new();
    parts.usize(m.parts.len());
    for part in &m.parts {
        parts.str(&part.name);
        parts.usize(part.elements.len());
        part.elements.iter().for_each(|&e| parts.usize(e));
        parts.str(part.material.as_deref().unwrap_or("\0none"));
    }
    parts.usize(m.materials.len());
    for (key, material) in &m.materials {
        parts.str(key);
        parts.str(&material.name);
        parts.f64(material.young);
        parts.f64(material.poisson);
        parts.f64(material.density);
    }
    let mut sets = Fnv::new();
    sets.usize(m.node_sets.len());
    for (name, nodes) in &m.node_sets {
        sets.str(name);
        sets.usize(nodes.len());
        nodes.iter().for_each(|&n| sets.usize(n));
    }
    let mut surfaces = Fnv::new();
    surfaces.usize(m.surfaces.len());
    for (key, surface) in &m.surfaces {
        surfaces.str(key);
        surfaces.str(&surface.name);
        surfaces.usize(surface.faces.len());
        for f in &surface.faces {
            surfaces.usize(f.element);
            surfaces.u64(u64::from(f.side));
            f.nodes.iter().for_each(|&n| surfaces.usize(n));
        }
    }
    [
        nodes.0,
        node_labels.0,
        elements.0,
        parts.0,
        sets.0,
        surfaces.0,
    ]
}
