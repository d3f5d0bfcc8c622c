//! From the raw records to the [`Mesh`]: node tags resolved, node order converted, physical
//! volumes made parts, physical surfaces matched to the tetrahedron faces they cover (outward),
//! physical points and curves made node sets.

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};
use std::path::Path;

use super::element_types::Kind;
use super::sections::{Raw, RawElement};
use super::GMSH_TET10;
use crate::mesh::{Face, Mesh, MeshError, Part, Surface};

pub(super) fn build(file: &Path, raw: Raw) -> Result<Mesh, MeshError> {
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

#[cfg(test)]
mod tests {
    use super::super::test_support::*;

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
}
