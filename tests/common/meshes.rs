//! Meshes the integration tests put together.

use squeal::mesh::{Mesh, Surface};

/// Two meshes side by side in one (nodes of `b` after those of `a`); parts, sets and
/// surfaces keep their names with a prefix.
pub fn merge(a: &Mesh, pa: &str, b: &Mesh, pb: &str) -> Mesh {
    let mut m = Mesh::default();
    for (mesh, prefix) in [(a, pa), (b, pb)] {
        let node0 = m.nodes.len();
        let element0 = m.elements.len();
        m.nodes.extend_from_slice(&mesh.nodes);
        m.elements
            .extend(mesh.elements.iter().map(|c| c.map(|n| n + node0)));
        for p in &mesh.parts {
            let mut p = p.clone();
            p.name = format!("{prefix}{}", p.name);
            p.elements.iter_mut().for_each(|e| *e += element0);
            m.parts.push(p);
        }
        for (k, v) in &mesh.materials {
            m.materials.insert(k.clone(), v.clone());
        }
        for (k, v) in &mesh.node_sets {
            m.node_sets.insert(
                format!("{prefix}{k}"),
                v.iter().map(|n| n + node0).collect(),
            );
        }
        for (k, s) in &mesh.surfaces {
            let mut s: Surface = s.clone();
            for f in &mut s.faces {
                f.element += element0;
                f.nodes = f.nodes.map(|n| n + node0);
            }
            m.surfaces.insert(format!("{prefix}{k}"), s);
        }
    }
    m.node_labels = (1..=m.nodes.len() as i64).collect();
    m.element_labels = (1..=m.elements.len() as i64).collect();
    m
}
