//! The MSH 4.1 ASCII writer: parts as physical volumes, surfaces as physical surfaces of
//! 6-node triangles, node sets as physical points; written whole or not at all through
//! [`crate::atomic_file`].

use std::collections::HashSet;
use std::io::Write;
use std::path::Path;

use super::GMSH_TET10;
use crate::mesh::{Mesh, MeshError};

/// Write `mesh` as MSH 4.1 ASCII.
///
/// - One volume entity (and physical volume) per part, one more without a physical group for
///   elements in no part. An element in two parts is an error (Gmsh's parts are disjoint).
/// - One surface entity (and physical surface) per [`Surface`](crate::mesh::Surface), its
///   faces as 6-node triangles in outward order.
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
    crate::atomic_file::write_with(path, |out| plan.write(out))
        .map_err(|source| MeshError::io(path, source))
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
    use super::super::test_support::*;
    use super::super::*;
    use super::*;
    use crate::mesh::Part;

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
