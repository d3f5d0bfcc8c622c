//! A structured TET10 mesh of a rectangular block: the beams and plates of the verification
//! tests and the examples, made by the one structured mesher ([`super::structured`]) with the
//! identity map.

use super::model::{Material, Mesh, Part, Surface};
use super::structured::{Grid, NodeOrder, Numbering, TetOrder};
use std::collections::BTreeMap;

/// How a block is numbered: cells and corner nodes with x fastest, then z slowest; the
/// corner nodes first, then the mid-edge nodes in order of first use; the Kuhn tetrahedra
/// of a cell in lexicographic order of their paths. Pinned by `mesh::fingerprint`.
const NUMBERING: Numbering = Numbering {
    sweep: [2, 1, 0],
    nodes: NodeOrder::CornersFirst,
    tets: TetOrder::Lexicographic,
};

/// Block dimensions that make no mesh.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("block needs positive lengths and divisions, got {lengths:?} and {divisions:?}")]
pub struct BadBlock {
    pub lengths: [f64; 3],
    pub divisions: [usize; 3],
}

/// A block [0, lx] x [0, ly] x [0, lz] shifted by `origin`, with `divisions` cells per
/// direction, in one part "block" of `material`. Node sets and surfaces `x0`, `x1`, `y0`,
/// `y1`, `z0`, `z1` are its six faces.
pub fn block(
    origin: [f64; 3],
    lengths: [f64; 3],
    divisions: [usize; 3],
    material: Material,
) -> Result<Mesh, BadBlock> {
    if divisions.contains(&0) || lengths.iter().any(|&l| !(l > 0.0 && l.is_finite())) {
        return Err(BadBlock { lengths, divisions });
    }
    let grid = Grid {
        lines: [0, 1, 2].map(|axis| {
            let n = divisions[axis];
            (0..=n)
                .map(|i| origin[axis] + lengths[axis] * i as f64 / n as f64)
                .collect()
        }),
        periodic: [false; 3],
    };
    let mut mesh = Mesh::default();
    let meshed = grid.mesh(&mut mesh, &NUMBERING, |_| Some(()), |x| x);
    mesh.node_labels = (1..=mesh.nodes.len() as i64).collect();
    mesh.element_labels = (1..=mesh.elements.len() as i64).collect();
    mesh.parts.push(Part {
        name: "block".into(),
        elements: (0..mesh.elements.len()).collect(),
        material: Some(material.name.clone()),
    });
    mesh.materials = BTreeMap::from([(material.name.clone(), material)]);
    for (axis, name) in [(0, "x"), (1, "y"), (2, "z")] {
        for (side, line) in [(0, 0), (1, divisions[axis])] {
            let set_name = format!("{name}{side}");
            let surface = Surface {
                name: set_name.clone(),
                faces: meshed.faces_on(&mesh, axis, line, |_| true),
            };
            let node_set = mesh.surface_nodes(&surface);
            mesh.node_sets.insert(set_name.clone(), node_set);
            mesh.surfaces.insert(set_name, surface);
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn steel() -> Material {
        Material {
            name: "steel".into(),
            young: 210e9,
            poisson: 0.3,
            density: 7850.0,
        }
    }

    #[test]
    fn volumes_are_positive_and_add_up_and_the_mesh_conforms() {
        let m = block([1.0, 2.0, 3.0], [0.3, 0.2, 0.1], [3, 2, 2], steel()).unwrap();
        let total: f64 = (0..m.elements.len()).map(|e| m.corner_volume(e)).sum();
        assert!((0..m.elements.len()).all(|e| m.corner_volume(e) > 0.0));
        assert!((total - 0.006).abs() < 1e-15);
        // Nodes of a structured quadratic grid: (2n+1) per direction.
        assert_eq!(m.nodes.len(), 7 * 5 * 5);
        // Every interior face shared by exactly two elements, boundary faces by one.
        let mut count: HashMap<[usize; 3], usize> = HashMap::new();
        for e in 0..m.elements.len() {
            for s in 0..4u8 {
                let f = m.face(e, s);
                let mut key = [f.nodes[0], f.nodes[1], f.nodes[2]];
                key.sort_unstable();
                *count.entry(key).or_default() += 1;
            }
        }
        let boundary = count.values().filter(|&&c| c == 1).count();
        assert!(count.values().all(|&c| c <= 2));
        let expected_boundary = 2 * 2 * (3 * 2 + 3 * 2 + 2 * 2);
        assert_eq!(boundary, expected_boundary);
        let on_surfaces: usize = m.surfaces.values().map(|s| s.faces.len()).sum();
        assert_eq!(on_surfaces, expected_boundary);
        assert_eq!(m.node_sets["x0"].len(), 5 * 5);
    }

    #[test]
    fn bad_sizes_are_refused() {
        assert!(block([0.0; 3], [1.0, 1.0, 0.0], [1, 1, 1], steel()).is_err());
        assert!(block([0.0; 3], [1.0; 3], [1, 0, 1], steel()).is_err());
    }
}
