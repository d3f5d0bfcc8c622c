//! The mesh as plain Rust data: nodes, 10-node tetrahedra, named parts with materials,
//! node sets and surfaces made of element faces. Readers convert every file format to the
//! one internal node order documented on [`TET10_FACES`]; nothing downstream knows where a
//! mesh came from.

use std::collections::BTreeMap;

use crate::vector3::{cross, dot, sub};

/// Internal TET10 node order (the Abaqus/CalculiX C3D10 order, 0-based):
///
/// ```text
///            3
///           /|\            corners 0 1 2 3
///          / | \           edges   4 = 0-1   5 = 1-2   6 = 2-0
///         7  |  9                  7 = 0-3   8 = 1-3   9 = 2-3
///        /   8   \
///       0 ---|----2        a positive element has
///        \   |   /         det[x1-x0, x2-x0, x3-x0] > 0
///         4  |  6
///          \ | /
///            1   (edge 1-2 carries node 5)
/// ```
pub const TET10_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];

/// The four faces of a TET10 as 6-node triangles, ordered so that the right-hand normal of
/// (corner a, corner b, corner c) points OUT of the element. Each row is
/// `[a, b, c, mid(a,b), mid(b,c), mid(c,a)]`. Row k is Abaqus face S(k+1):
/// S1 = 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1 (Abaqus lists them inward; the node sets
/// are the same).
pub const TET10_FACES: [[usize; 6]; 4] = [
    [0, 2, 1, 6, 5, 4],
    [0, 1, 3, 4, 8, 7],
    [1, 2, 3, 5, 9, 8],
    [2, 0, 3, 6, 7, 9],
];

/// Isotropic linear-elastic material.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Material {
    pub name: String,
    /// Young's modulus.
    pub young: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Mass density.
    pub density: f64,
}

/// A named set of elements with one material (a physical volume in Gmsh, an elset with a
/// `*SOLID SECTION` in Abaqus).
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    pub name: String,
    /// Indices into [`Mesh::elements`].
    pub elements: Vec<usize>,
    /// Name of the material in [`Mesh::materials`]; `None` until a section assigns one.
    pub material: Option<String>,
}

/// One 6-node triangular face of an element, nodes in [`TET10_FACES`] order (outward).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Face {
    /// Index into [`Mesh::elements`] of the element that owns the face.
    pub element: usize,
    /// Which face of that element (0..4, Abaqus S1..S4).
    pub side: u8,
    /// The face's nodes: 3 corners then the mid-edge nodes, outward orientation.
    pub nodes: [usize; 6],
}

/// A named surface made of element faces.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Surface {
    pub name: String,
    pub faces: Vec<Face>,
}

/// The mesh of a whole model.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Node coordinates; the index is the internal node number.
    pub nodes: Vec<[f64; 3]>,
    /// The label each node had in its file (for messages and round trips).
    pub node_labels: Vec<i64>,
    /// Element connectivity in the internal TET10 order.
    pub elements: Vec<[usize; 10]>,
    /// The label each element had in its file.
    pub element_labels: Vec<i64>,
    pub parts: Vec<Part>,
    pub materials: BTreeMap<String, Material>,
    /// Named node sets (internal node indices, sorted, unique).
    pub node_sets: BTreeMap<String, Vec<usize>>,
    pub surfaces: BTreeMap<String, Surface>,
}

impl Mesh {
    /// The 6 nodes of face `side` of element `element`, outward order.
    pub fn face(&self, element: usize, side: u8) -> Face {
        let conn = &self.elements[element];
        let local = TET10_FACES[side as usize];
        Face {
            element,
            side,
            nodes: local.map(|k| conn[k]),
        }
    }

    /// Signed volume of the straight-sided tetrahedron spanned by an element's corners
    /// (positive for a correctly ordered element).
    pub fn corner_volume(&self, element: usize) -> f64 {
        let c = &self.elements[element];
        let x = |i: usize| self.nodes[c[i]];
        let (a, b, d, e) = (x(0), x(1), x(2), x(3));
        let u = sub(b, a);
        let v = sub(d, a);
        let w = sub(e, a);
        dot(u, cross(v, w)) / 6.0
    }

    /// The sorted, unique node indices of a surface.
    pub fn surface_nodes(&self, surface: &Surface) -> Vec<usize> {
        let mut nodes: Vec<usize> = surface.faces.iter().flat_map(|f| f.nodes).collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// The part each element belongs to (`None` for an element in no part).
    pub fn element_parts(&self) -> Vec<Option<usize>> {
        let mut owner = vec![None; self.elements.len()];
        for (p, part) in self.parts.iter().enumerate() {
            for &e in &part.elements {
                owner[e] = Some(p);
            }
        }
        owner
    }
}

/// A part name the mesh does not have.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("no part named '{0}'")]
pub struct NoSuchPart(pub String);

impl Mesh {
    /// The sub-mesh made of the named parts: only their elements and the nodes those use,
    /// renumbered; node sets and surfaces keep what lies in it (empty ones are dropped).
    /// Errors name a part that does not exist.
    pub fn extract_parts(&self, names: &[&str]) -> Result<Mesh, NoSuchPart> {
        let mut keep_element = vec![false; self.elements.len()];
        let mut parts = Vec::new();
        for name in names {
            let part = self
                .parts
                .iter()
                .find(|p| p.name == *name)
                .ok_or_else(|| NoSuchPart(name.to_string()))?;
            for &e in &part.elements {
                keep_element[e] = true;
            }
            parts.push(part.clone());
        }
        let mut new_node = vec![usize::MAX; self.nodes.len()];
        let mut new_element = vec![usize::MAX; self.elements.len()];
        let mut out = Mesh::default();
        for (e, conn) in self.elements.iter().enumerate() {
            if !keep_element[e] {
                continue;
            }
            let mapped = conn.map(|n| {
                if new_node[n] == usize::MAX {
                    new_node[n] = out.nodes.len();
                    out.nodes.push(self.nodes[n]);
                    out.node_labels.push(self.node_labels[n]);
                }
                new_node[n]
            });
            new_element[e] = out.elements.len();
            out.elements.push(mapped);
            out.element_labels.push(self.element_labels[e]);
        }
        for mut part in parts {
            part.elements = part.elements.iter().map(|&e| new_element[e]).collect();
            if let Some(m) = part.material.as_ref().and_then(|m| self.materials.get(m)) {
                out.materials.insert(m.name.clone(), m.clone());
            }
            out.parts.push(part);
        }
        for (name, nodes) in &self.node_sets {
            let kept: Vec<usize> = nodes
                .iter()
                .filter_map(|&n| (new_node[n] != usize::MAX).then_some(new_node[n]))
                .collect();
            if !kept.is_empty() {
                out.node_sets.insert(name.clone(), kept);
            }
        }
        for (name, surface) in &self.surfaces {
            let faces: Vec<Face> = surface
                .faces
                .iter()
                .filter(|f| keep_element[f.element])
                .map(|f| Face {
                    element: new_element[f.element],
                    side: f.side,
                    nodes: f.nodes.map(|n| new_node[n]),
                })
                .collect();
            if !faces.is_empty() {
                out.surfaces.insert(
                    name.clone(),
                    Surface {
                        name: name.clone(),
                        faces,
                    },
                );
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_tet() -> Mesh {
        let c = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let mut nodes = c.to_vec();
        for [a, b] in TET10_EDGES {
            nodes.push([0, 1, 2].map(|k| 0.5 * (c[a][k] + c[b][k])));
        }
        Mesh {
            node_labels: (1..=10).collect(),
            nodes,
            elements: vec![[0, 1, 2, 3, 4, 5, 6, 7, 8, 9]],
            element_labels: vec![1],
            ..Default::default()
        }
    }

    #[test]
    fn extracting_a_part_keeps_only_its_nodes_sets_and_faces() {
        let mut m = unit_tet();
        // A second element sharing face S1's corners, mirrored through z = 0.
        let base = m.nodes.len();
        m.nodes.push([0.0, 0.0, -1.0]);
        m.node_labels.push(11);
        // Corners 0, 2, 1 of the first tet plus the new apex: positive orientation.
        let c = [0, 2, 1, base];
        let mut conn = [0usize; 10];
        conn[..4].copy_from_slice(&c);
        for (k, [a, b]) in TET10_EDGES.iter().enumerate() {
            let (xa, xb) = (m.nodes[c[*a]], m.nodes[c[*b]]);
            let mid = [0, 1, 2].map(|d| 0.5 * (xa[d] + xb[d]));
            conn[4 + k] = match m.nodes.iter().position(|x| *x == mid) {
                Some(n) => n,
                None => {
                    m.nodes.push(mid);
                    m.node_labels.push(m.nodes.len() as i64);
                    m.nodes.len() - 1
                }
            };
        }
        m.elements.push(conn);
        m.element_labels.push(2);
        m.parts = vec![
            Part {
                name: "a".into(),
                elements: vec![0],
                material: None,
            },
            Part {
                name: "b".into(),
                elements: vec![1],
                material: None,
            },
        ];
        m.node_sets.insert("apex".into(), vec![3]);
        m.surfaces.insert(
            "top".into(),
            Surface {
                name: "top".into(),
                faces: vec![m.face(0, 2)],
            },
        );
        assert!(m.corner_volume(1) > 0.0);
        let b = m.extract_parts(&["b"]).unwrap();
        assert_eq!(b.elements.len(), 1);
        assert_eq!(b.nodes.len(), 10);
        assert!(!b.node_sets.contains_key("apex"));
        assert!(b.surfaces.is_empty());
        assert!(b.corner_volume(0) > 0.0);
        let a = m.extract_parts(&["a"]).unwrap();
        assert_eq!(
            a.surfaces["top"].faces[0].nodes.map(|n| a.nodes[n]),
            m.face(0, 2).nodes.map(|n| m.nodes[n])
        );
        assert!(m
            .extract_parts(&["c"])
            .unwrap_err()
            .to_string()
            .contains("'c'"));
    }

    #[test]
    fn faces_point_outward_and_mid_nodes_sit_on_their_edges() {
        let m = unit_tet();
        assert!((m.corner_volume(0) - 1.0 / 6.0).abs() < 1e-15);
        let centroid = [0.25; 3];
        for side in 0..4u8 {
            let f = m.face(0, side);
            let x = |i: usize| m.nodes[f.nodes[i]];
            let n = cross(sub(x(1), x(0)), sub(x(2), x(0)));
            assert!(
                dot(n, sub(x(0), centroid)) > 0.0,
                "face {side} points inward"
            );
            for (mid, (a, b)) in [(3, (0, 1)), (4, (1, 2)), (5, (2, 0))] {
                let expect = [0, 1, 2].map(|k| 0.5 * (x(a)[k] + x(b)[k]));
                assert_eq!(x(mid), expect, "face {side} mid node {mid}");
            }
        }
    }
}
