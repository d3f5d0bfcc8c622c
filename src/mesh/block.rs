//! A structured TET10 mesh of a rectangular block: the beams and plates of the verification
//! tests and the examples. Each hexahedral cell is split into the six tetrahedra of the Kuhn
//! subdivision (paths from the cell's lowest to its highest corner), which conform across
//! cells; mid-edge nodes are shared through an edge table.

use super::model::{Face, Material, Mesh, Part, Surface, TET10_EDGES, TET10_FACES};
use std::collections::{BTreeMap, HashMap};

/// A block [0, lx] x [0, ly] x [0, lz] shifted by `origin`, with `divisions` cells per
/// direction, in one part "block" of `material`. Node sets and surfaces `x0`, `x1`, `y0`,
/// `y1`, `z0`, `z1` are its six faces.
pub fn block(
    origin: [f64; 3],
    lengths: [f64; 3],
    divisions: [usize; 3],
    material: Material,
) -> Result<Mesh, String> {
    if divisions.contains(&0) || lengths.iter().any(|&l| !(l > 0.0 && l.is_finite())) {
        return Err(format!(
            "block needs positive lengths and divisions, got {lengths:?} and {divisions:?}"
        ));
    }
    let [nx, ny, nz] = divisions;
    let corner = |i: usize, j: usize, k: usize| (k * (ny + 1) + j) * (nx + 1) + i;
    let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                nodes.push([
                    origin[0] + lengths[0] * i as f64 / nx as f64,
                    origin[1] + lengths[1] * j as f64 / ny as f64,
                    origin[2] + lengths[2] * k as f64 / nz as f64,
                ]);
            }
        }
    }
    const PERMUTATIONS: [[usize; 3]; 6] = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
    let mut elements = Vec::with_capacity(6 * nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                for perm in &PERMUTATIONS {
                    let mut at = [i, j, k];
                    let mut c = [corner(i, j, k); 4];
                    for (step, &axis) in perm.iter().enumerate() {
                        at[axis] += 1;
                        c[step + 1] = corner(at[0], at[1], at[2]);
                    }
                    // The path's volume is det[e_p0, e_p1, e_p2], the sign of the
                    // permutation: odd ones (a transposition away from identity) are
                    // negatively oriented, so swap two corners.
                    let inversions = usize::from(perm[0] > perm[1])
                        + usize::from(perm[0] > perm[2])
                        + usize::from(perm[1] > perm[2]);
                    if inversions % 2 == 1 {
                        c.swap(1, 2);
                    }
                    let mut conn = [0usize; 10];
                    conn[..4].copy_from_slice(&c);
                    for (m, [a, b]) in TET10_EDGES.iter().enumerate() {
                        let key = (c[*a].min(c[*b]), c[*a].max(c[*b]));
                        conn[4 + m] = *edges.entry(key).or_insert_with(|| {
                            let (xa, xb) = (nodes[key.0], nodes[key.1]);
                            nodes.push([0, 1, 2].map(|d| 0.5 * (xa[d] + xb[d])));
                            nodes.len() - 1
                        });
                    }
                    elements.push(conn);
                }
            }
        }
    }
    let mut mesh = Mesh {
        node_labels: (1..=nodes.len() as i64).collect(),
        element_labels: (1..=elements.len() as i64).collect(),
        nodes,
        elements,
        parts: vec![],
        materials: BTreeMap::new(),
        node_sets: BTreeMap::new(),
        surfaces: BTreeMap::new(),
    };
    mesh.parts.push(Part {
        name: "block".into(),
        elements: (0..mesh.elements.len()).collect(),
        material: Some(material.name.clone()),
    });
    mesh.materials.insert(material.name.clone(), material);
    // Boundary faces: all six face nodes on one of the block's planes.
    let tol = 1e-9 * lengths.iter().fold(0.0f64, |a, &b| a.max(b));
    for (axis, name) in [(0, "x"), (1, "y"), (2, "z")] {
        for (side, value) in [(0, origin[axis]), (1, origin[axis] + lengths[axis])] {
            let on = |n: usize| (mesh.nodes[n][axis] - value).abs() <= tol;
            let mut faces: Vec<Face> = Vec::new();
            for e in 0..mesh.elements.len() {
                for s in 0..4u8 {
                    let local = TET10_FACES[s as usize];
                    if local.iter().all(|&l| on(mesh.elements[e][l])) {
                        faces.push(mesh.face(e, s));
                    }
                }
            }
            let set_name = format!("{name}{side}");
            let surface = Surface {
                name: set_name.clone(),
                faces,
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
