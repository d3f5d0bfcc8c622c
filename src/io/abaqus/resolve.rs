//! Resolution, once the whole deck is read: labels to indices, sets and surfaces to nodes and
//! faces, sections to parts, materials checked, supports and loads to nodes and faces, and the
//! warnings collected.

use std::collections::{BTreeMap, HashMap, HashSet};

use super::drafts::*;
use super::keywords::PERTURBATION_PROCEDURES;
use super::lines::Loc;
use super::reader::Reader;
use super::*;
use crate::mesh::{Face, Material, Mesh, MeshError, Part, Surface};

impl Reader {
    pub(super) fn finish(mut self) -> Result<Deck, MeshError> {
        // Connectivity: labels to indices.
        let mut elements = Vec::with_capacity(self.elements.len());
        for (e, raw) in self.elements.iter().enumerate() {
            let mut conn = [0usize; 10];
            for (slot, label) in conn.iter_mut().zip(raw) {
                *slot = *self.node_index.get(label).ok_or_else(|| {
                    self.err(
                        self.element_locs[e],
                        format!(
                            "element {} references node {label}, which is not defined",
                            self.element_labels[e]
                        ),
                    )
                })?;
            }
            elements.push(conn);
        }
        let mut mesh = Mesh {
            nodes: std::mem::take(&mut self.nodes),
            node_labels: std::mem::take(&mut self.node_labels),
            elements,
            element_labels: self.element_labels.clone(),
            ..Default::default()
        };

        let (node_sets, _) = self.resolve_sets(true)?;
        let (element_sets, discrete_sets) = self.resolve_sets(false)?;
        mesh.node_sets = node_sets;

        self.make_parts(&mut mesh, &element_sets, &discrete_sets)?;
        let (springs, point_masses) = self.resolve_discrete(
            &mesh.nodes,
            &element_sets,
            &discrete_sets,
            &mesh.element_labels,
        )?;
        self.make_materials(&mut mesh)?;
        self.make_surfaces(&mut mesh, &element_sets)?;

        let model = std::mem::take(&mut self.model);
        let (boundaries, concentrated_loads, pressures) =
            self.resolve_loads(&model, &mesh, &element_sets)?;
        let mut steps = Vec::with_capacity(self.steps.len());
        for draft in std::mem::take(&mut self.steps) {
            let (boundaries, concentrated_loads, pressures) =
                self.resolve_loads(&draft.loads, &mesh, &element_sets)?;
            let (procedure, _) = draft
                .procedure
                .ok_or_else(|| self.err(draft.loc, "step without a procedure"))?;
            let perturbation = draft.perturbation_parameter
                || match &procedure {
                    Procedure::Frequency(_) | Procedure::ComplexFrequency(_) => true,
                    Procedure::Static(_) => false,
                    Procedure::Unsupported { keyword } => {
                        let name: String = keyword[1..].split_whitespace().collect();
                        PERTURBATION_PROCEDURES.contains(&name.as_str())
                    }
                };
            steps.push(Step {
                name: draft.name,
                title: draft.title,
                procedure,
                perturbation,
                nlgeom: draft.nlgeom,
                boundaries,
                concentrated_loads,
                pressures,
                replaced: draft.replaced,
                motions: Vec::new(),
                source: self.lines.source(draft.loc),
            });
        }
        let mut motions = self.resolve_motions(&mesh)?;
        for (k, step) in steps.iter_mut().enumerate() {
            step.motions = motions.remove(&Some(k)).unwrap_or_default();
        }
        let first_young = self
            .first_material
            .as_ref()
            .and_then(|m| mesh.materials.get(m))
            .map(|m| m.young);

        let (equations, transforms, couplings) =
            self.resolve_constraints(&mesh, &self.node_surfaces.keys().cloned().collect())?;
        let ties = self.resolve_ties(&mesh)?;
        let interactions = self.resolve_interactions()?;
        let contact_pairs = self.resolve_contact_pairs(&mesh, &interactions)?;

        self.collect_warnings();
        Ok(Deck {
            equations,
            ties,
            transforms,
            couplings,
            interactions,
            contact_pairs,
            mesh,
            heading: self.heading.join("\n"),
            element_sets,
            springs,
            point_masses,
            node_surfaces: self.node_surfaces.keys().cloned().collect(),
            boundaries,
            concentrated_loads,
            pressures,
            steps,
            motions: motions.remove(&None).unwrap_or_default(),
            first_young,
            warnings: self.warnings,
        })
    }

    /// The sets of nodes or of elements, resolved to indices: for elements, the C3D10
    /// elements and the discrete elements of each set apart (both maps have every set).
    #[allow(clippy::type_complexity)]
    fn resolve_sets(
        &mut self,
        of_nodes: bool,
    ) -> Result<(BTreeMap<String, Vec<usize>>, BTreeMap<String, Vec<usize>>), MeshError> {
        let (sets, index, item) = if of_nodes {
            (&self.node_sets, &self.node_index, "node")
        } else {
            (&self.element_sets, &self.element_index, "element")
        };
        let empty = HashMap::new();
        let discrete_index = if of_nodes {
            &empty
        } else {
            &self.discrete_index
        };
        let mut out = BTreeMap::new();
        let mut discrete_out = BTreeMap::new();
        let mut notes = Vec::new();
        for (canon, set) in sets {
            let mut indices = Vec::with_capacity(set.members().len());
            let mut discrete = Vec::new();
            for m in set.members() {
                match (index.get(&m.label), discrete_index.get(&m.label)) {
                    (Some(&i), _) => indices.push(i),
                    (None, Some(&d)) => discrete.push(d),
                    (None, None) => {
                        return Err(self.err(
                            m.loc,
                            format!(
                                "{item} {} (in {item} set {}) is not defined",
                                m.label, set.written
                            ),
                        ))
                    }
                }
            }
            let mut missing: Option<(u64, Loc)> = None;
            for range in set.ranges() {
                let found = range.existing(index);
                let found_discrete = range.existing(discrete_index);
                let absent = range.len() - (found.len() + found_discrete.len()) as u64;
                if absent > 0 {
                    missing.get_or_insert((0, range.loc)).0 += absent;
                }
                indices.extend(found);
                discrete.extend(found_discrete);
            }
            indices.sort_unstable();
            indices.dedup();
            discrete.sort_unstable();
            discrete.dedup();
            if let Some((n, loc)) = missing {
                notes.push(format!(
                    "{item} set {}: {n} label(s) produced by GENERATE (first range at {}) are \
                     not defined and were left out",
                    set.written,
                    self.lines.at(loc)
                ));
            }
            out.insert(canon.clone(), indices);
            discrete_out.insert(canon.clone(), discrete);
        }
        self.warnings.extend(notes);
        Ok((out, discrete_out))
    }

    fn make_parts(
        &self,
        mesh: &mut Mesh,
        element_sets: &BTreeMap<String, Vec<usize>>,
        discrete_sets: &BTreeMap<String, Vec<usize>>,
    ) -> Result<(), MeshError> {
        let mut owner: Vec<Option<usize>> = vec![None; mesh.elements.len()];
        for (s, section) in self.sections.iter().enumerate() {
            let Some(elements) = element_sets.get(&section.elset.canon) else {
                return Err(self.err(
                    section.loc,
                    format!(
                        "*SOLID SECTION: element set {} is not defined",
                        section.elset.written
                    ),
                ));
            };
            // A spring or mass in a solid section would be silently dropped from it.
            if let Some(&d) = discrete_sets
                .get(&section.elset.canon)
                .and_then(|d| d.first())
            {
                return Err(self.err(
                    section.loc,
                    format!(
                        "*SOLID SECTION: element set {} holds the {} element {} (a discrete \
                         element takes *SPRING or *MASS, not a solid section); give the C3D10 \
                         elements a set of their own",
                        section.elset.written,
                        self.discrete[d].kind.name(),
                        self.discrete[d].label
                    ),
                ));
            }
            if !self.materials.contains_key(&section.material.canon) {
                return Err(self.err(
                    section.loc,
                    format!(
                        "*SOLID SECTION: material {} is not defined",
                        section.material.written
                    ),
                ));
            }
            for &e in elements {
                if let Some(previous) = owner[e] {
                    return Err(self.err(
                        section.loc,
                        format!(
                            "element {} is already in the *SOLID SECTION at {}; an element \
                             takes one section only",
                            mesh.element_labels[e],
                            self.lines.at(self.sections[previous].loc)
                        ),
                    ));
                }
                owner[e] = Some(s);
            }
            mesh.parts.push(Part {
                name: section.elset.canon.clone(),
                elements: elements.clone(),
                material: Some(section.material.canon.clone()),
            });
        }
        let orphans: Vec<usize> = (0..owner.len()).filter(|&e| owner[e].is_none()).collect();
        if let Some(&first) = orphans.first() {
            return Err(self.err(
                self.element_locs[first],
                format!(
                    "{} element(s) are in no *SOLID SECTION, so they have no material (first: \
                     element {}); give every element a section",
                    orphans.len(),
                    mesh.element_labels[first]
                ),
            ));
        }
        Ok(())
    }

    fn make_materials(&mut self, mesh: &mut Mesh) -> Result<(), MeshError> {
        let mut used: BTreeMap<&str, Loc> = BTreeMap::new();
        for section in &self.sections {
            used.entry(section.material.canon.as_str())
                .or_insert(section.loc);
        }
        let mut notes = Vec::new();
        for (canon, draft) in &self.materials {
            let missing = match (draft.elastic, draft.density) {
                (Some(_), Some(_)) => None,
                (None, Some(_)) => Some("*ELASTIC"),
                (Some(_), None) => Some("*DENSITY"),
                (None, None) => Some("*ELASTIC and *DENSITY"),
            };
            match (missing, used.get(canon.as_str())) {
                (Some(what), Some(&section)) => {
                    return Err(self.err(
                        draft.loc,
                        format!(
                            "material {} has no {what}, but the *SOLID SECTION at {} uses it",
                            draft.written,
                            self.lines.at(section)
                        ),
                    ))
                }
                (Some(what), None) => notes.push(format!(
                    "material {} ({}) has no {what} and no section uses it; left out",
                    draft.written,
                    self.lines.at(draft.loc)
                )),
                (None, _) => {
                    if let (Some((young, poisson)), Some(density)) = (draft.elastic, draft.density)
                    {
                        mesh.materials.insert(
                            canon.clone(),
                            Material {
                                name: canon.clone(),
                                young,
                                poisson,
                                density,
                            },
                        );
                    }
                }
            }
        }
        self.warnings.extend(notes);
        Ok(())
    }

    fn elements_of(
        &self,
        target: &ElementRef,
        loc: Loc,
        keyword: &str,
        element_sets: &BTreeMap<String, Vec<usize>>,
    ) -> Result<Vec<usize>, MeshError> {
        match target {
            ElementRef::Element(label) => match self.element_index.get(label) {
                Some(&e) => Ok(vec![e]),
                None => Err(self.err(
                    loc,
                    match self.discrete_index.get(label) {
                        Some(&d) => format!(
                            "{keyword}: element {label} is a {} element, which has no faces",
                            self.discrete[d].kind.name()
                        ),
                        None => format!("{keyword}: element {label} is not defined"),
                    },
                )),
            },
            ElementRef::Set(name) => element_sets.get(&name.canon).cloned().ok_or_else(|| {
                self.err(
                    loc,
                    format!("{keyword}: element set {} is not defined", name.written),
                )
            }),
        }
    }

    fn make_surfaces(
        &self,
        mesh: &mut Mesh,
        element_sets: &BTreeMap<String, Vec<usize>>,
    ) -> Result<(), MeshError> {
        for (canon, draft) in &self.surfaces {
            let mut faces = Vec::new();
            let mut seen = HashSet::new();
            for member in &draft.members {
                let elements = self.elements_of(
                    &member.target,
                    member.loc,
                    &format!("*SURFACE {}", draft.written),
                    element_sets,
                )?;
                let candidates = match member.side {
                    Some(side) => elements.iter().map(|&e| mesh.face(e, side)).collect(),
                    None => free_faces(mesh, &elements),
                };
                for face in candidates {
                    if seen.insert((face.element, face.side)) {
                        faces.push(face);
                    }
                }
            }
            mesh.surfaces.insert(
                canon.clone(),
                Surface {
                    name: canon.clone(),
                    faces,
                },
            );
        }
        Ok(())
    }

    pub(super) fn nodes_of(
        &self,
        target: &NodeRef,
        loc: Loc,
        keyword: &str,
        mesh: &Mesh,
    ) -> Result<(NodeTarget, Vec<usize>), MeshError> {
        match target {
            NodeRef::Node(label) => match self.node_index.get(label) {
                Some(&n) => Ok((NodeTarget::Node(*label), vec![n])),
                None => Err(self.err(loc, format!("{keyword}: node {label} is not defined"))),
            },
            NodeRef::Set(name) => match mesh.node_sets.get(&name.canon) {
                Some(nodes) => Ok((NodeTarget::Set(name.canon.clone()), nodes.clone())),
                None => Err(self.err(
                    loc,
                    format!("{keyword}: node set {} is not defined", name.written),
                )),
            },
        }
    }

    #[allow(clippy::type_complexity)]
    fn resolve_loads(
        &self,
        drafts: &LoadDrafts,
        mesh: &Mesh,
        element_sets: &BTreeMap<String, Vec<usize>>,
    ) -> Result<(Vec<Boundary>, Vec<ConcentratedLoad>, Vec<PressureLoad>), MeshError> {
        let mut boundaries = Vec::with_capacity(drafts.boundaries.len());
        for b in &drafts.boundaries {
            let (target, nodes) = self.nodes_of(&b.target, b.loc, "*BOUNDARY", mesh)?;
            boundaries.push(Boundary {
                target,
                nodes,
                first_dof: b.first_dof,
                last_dof: b.last_dof,
                value: b.value,
                fixed: b.fixed,
                source: self.lines.source(b.loc),
            });
        }
        let mut loads = Vec::with_capacity(drafts.loads.len());
        for c in &drafts.loads {
            let (target, nodes) = self.nodes_of(&c.target, c.loc, "*CLOAD", mesh)?;
            loads.push(ConcentratedLoad {
                target,
                nodes,
                dof: c.dof,
                value: c.value,
                source: self.lines.source(c.loc),
            });
        }
        let mut pressures = Vec::with_capacity(drafts.pressure_order.len());
        let mut surface = drafts.surface_pressures.iter();
        let mut element = drafts.element_pressures.iter();
        for &is_surface in &drafts.pressure_order {
            if is_surface {
                let Some(p) = surface.next() else { break };
                let faces = match mesh.surfaces.get(&p.surface.canon) {
                    Some(s) => s.faces.clone(),
                    None if self.node_surfaces.contains_key(&p.surface.canon) => {
                        return Err(self.err(
                            p.loc,
                            format!(
                                "*DSLOAD: surface {} is node-based; a pressure needs an \
                                 element-based surface (TYPE=ELEMENT)",
                                p.surface.written
                            ),
                        ))
                    }
                    None => {
                        return Err(self.err(
                            p.loc,
                            format!("*DSLOAD: surface {} is not defined", p.surface.written),
                        ))
                    }
                };
                pressures.push(PressureLoad {
                    target: PressureTarget::Surface(p.surface.canon.clone()),
                    faces,
                    value: p.value,
                    source: self.lines.source(p.loc),
                });
            } else {
                let Some(p) = element.next() else { break };
                let elements = self.elements_of(&p.target, p.loc, "*DLOAD", element_sets)?;
                pressures.push(PressureLoad {
                    target: match &p.target {
                        ElementRef::Set(name) => PressureTarget::ElementSet(name.canon.clone()),
                        ElementRef::Element(label) => PressureTarget::Element(*label),
                    },
                    faces: elements.iter().map(|&e| mesh.face(e, p.side)).collect(),
                    value: p.value,
                    source: self.lines.source(p.loc),
                });
            }
        }
        Ok((boundaries, loads, pressures))
    }

    fn collect_warnings(&mut self) {
        let mut front = Vec::new();
        if !self.variant_types.entries.is_empty() {
            front.push(format!(
                "element types read as plain C3D10 (same nodes; squeal uses its own \
                 full-integration formulation): {}",
                self.variant_types.describe(&self.lines)
            ));
        }
        if !self.unknown_keywords.entries.is_empty() {
            front.push(format!(
                "read past (output and print requests, solver controls: they do not change \
                 the model): {}",
                self.unknown_keywords.describe(&self.lines)
            ));
        }
        if !self.other_procedures.entries.is_empty() {
            front.push(format!(
                "steps with procedures this reader does not read (kept as \
                 Procedure::Unsupported): {}",
                self.other_procedures.describe(&self.lines)
            ));
        }
        if !self.ignored_parameters.entries.is_empty() {
            front.push(format!(
                "ignored parameters: {}",
                self.ignored_parameters.describe(&self.lines)
            ));
        }
        if !self.rotational_dofs.entries.is_empty() {
            front.push(format!(
                "rotational DOFs 4-6 ignored (C3D10 nodes have only displacements): {}",
                self.rotational_dofs.describe(&self.lines)
            ));
        }
        if !self.contact_notes.entries.is_empty() {
            front.push(format!(
                "contact read with squeal's law where the deck's differs: {}",
                self.contact_notes.describe(&self.lines)
            ));
        }
        front.append(&mut self.warnings);
        self.warnings = front;
    }
}

/// The faces of `elements` that no other element of the list shares (an element set's
/// exterior, which is what Abaqus takes when a surface line has no face identifier).
fn free_faces(mesh: &Mesh, elements: &[usize]) -> Vec<Face> {
    let key = |f: &Face| {
        let mut k = [f.nodes[0], f.nodes[1], f.nodes[2]];
        k.sort_unstable();
        k
    };
    let mut count: HashMap<[usize; 3], u32> = HashMap::new();
    for &e in elements {
        for side in 0..4 {
            *count.entry(key(&mesh.face(e, side))).or_insert(0) += 1;
        }
    }
    elements
        .iter()
        .flat_map(|&e| (0..4).map(move |side| mesh.face(e, side)))
        .filter(|f| count.get(&key(f)) == Some(&1))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use crate::vector3::{cross, dot, sub};

    #[test]
    fn surfaces_s1_to_s4_are_the_abaqus_faces_pointing_outward() {
        let text = format!(
            "{}*SURFACE, NAME=All faces, TYPE=ELEMENT\n7, S1\n7, S2\nEALL, s3\n7, S4\n7, S1\n",
            one_tet()
        );
        let deck = read_text("surfaces", &text).unwrap();
        let mesh = &deck.mesh;
        let surface = &mesh.surfaces["ALL FACES"];
        assert_eq!(surface.faces.len(), 4, "the repeated S1 is kept once");
        // Abaqus' C3D10 faces in 1-based node numbers: corners, and the mid nodes of their
        // edges (5 = 1-2, 6 = 2-3, 7 = 3-1, 8 = 1-4, 9 = 2-4, 10 = 3-4).
        let abaqus: [[usize; 6]; 4] = [
            [1, 2, 3, 5, 6, 7],
            [1, 4, 2, 8, 9, 5],
            [2, 4, 3, 9, 10, 6],
            [3, 4, 1, 10, 8, 7],
        ];
        let centroid = [0.25; 3];
        for (side, face) in surface.faces.iter().enumerate() {
            assert_eq!((face.element, usize::from(face.side)), (0, side));
            let mut got: Vec<usize> = face.nodes.to_vec();
            let mut want: Vec<usize> = abaqus[side].iter().map(|n| n - 1).collect();
            got.sort_unstable();
            want.sort_unstable();
            assert_eq!(got, want, "S{}", side + 1);
            let x = |i: usize| mesh.nodes[face.nodes[i]];
            let normal = cross(sub(x(1), x(0)), sub(x(2), x(0)));
            assert!(
                dot(normal, sub(x(0), centroid)) > 0.0,
                "S{} inward",
                side + 1
            );
        }
    }

    #[test]
    fn a_surface_line_without_a_face_takes_the_free_faces_of_the_set() {
        let text = format!(
            "{}*MATERIAL, NAME=STEEL\n*ELASTIC\n1, 0\n*DENSITY\n1\n\
             *SOLID SECTION, ELSET=CUBE, MATERIAL=STEEL\n*SURFACE, NAME=OUTSIDE\nCUBE\n",
            box_mesh([1, 1, 1], [1.0, 1.0, 1.0], "CUBE")
        );
        let deck = read_text("free-faces", &text).unwrap();
        let mesh = &deck.mesh;
        let faces = &mesh.surfaces["OUTSIDE"].faces;
        // 6 tets, 24 faces, 6 interior pairs: the 12 triangles of the cube's 6 sides.
        assert_eq!(faces.len(), 12);
        let mut area = 0.0;
        for f in faces {
            let x = |i: usize| mesh.nodes[f.nodes[i]];
            let n = cross(sub(x(1), x(0)), sub(x(2), x(0)));
            area += 0.5 * dot(n, n).sqrt();
            assert!(
                dot(n, sub(x(0), [0.5; 3])) > 0.0,
                "face points into the cube"
            );
        }
        assert!((area - 6.0).abs() < 1e-12, "surface area {area}");
    }

    #[test]
    fn an_element_on_an_undefined_node_names_both() {
        let text = format!(
            "*NODE\n{}*ELEMENT, TYPE=C3D10, ELSET=E\n1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 99\n",
            unit_tet_nodes(1)
        );
        let (_, line, message) = parse_error(read_text("err-node", &text));
        assert_eq!(line, 13);
        assert!(
            message.contains("element 1") && message.contains("node 99"),
            "{message}"
        );
    }

    #[test]
    fn unknown_sets_are_named_at_the_line_that_uses_them() {
        let cases = [
            ("*SOLID SECTION, ELSET=Nowhere, MATERIAL=STEEL\n", "Nowhere"),
            ("*BOUNDARY\nFixed, 1, 3\n", "Fixed"),
            ("*SURFACE, NAME=S\nGhost, S1\n", "Ghost"),
            ("*CLOAD\nLoadSet, 1, 3.0\n", "LoadSet"),
            ("*DSLOAD\nSurf, P, 3.0\n", "Surf"),
            ("*NSET, NSET=A\nNotYet\n", "NotYet"),
        ];
        let base = one_tet();
        let base_lines = base.lines().count();
        for (i, (tail, name)) in cases.iter().enumerate() {
            let (_, line, message) =
                parse_error(read_text(&format!("err-set-{i}"), &format!("{base}{tail}")));
            assert_eq!(line, base_lines + tail.lines().count(), "{tail}");
            assert!(message.contains(name), "{message}");
            assert!(message.contains("not defined"), "{message}");
        }
    }

    #[test]
    fn a_section_on_an_undefined_material_names_it() {
        let text = format!(
            "*NODE\n{}*ELEMENT, TYPE=C3D10, ELSET=E\n{}*SOLID SECTION, ELSET=E, MATERIAL=Brass\n",
            unit_tet_nodes(1),
            unit_tet_element(1, 1)
        );
        let (_, line, message) = parse_error(read_text("err-material", &text));
        assert_eq!(line, 14);
        assert!(
            message.contains("material Brass is not defined"),
            "{message}"
        );
    }

    #[test]
    fn a_used_material_needs_elastic_and_density() {
        for (props, missing) in [
            ("*ELASTIC\n1e9, 0.3\n", "*DENSITY"),
            ("*DENSITY\n1\n", "*ELASTIC"),
        ] {
            let text = format!(
                "*NODE\n{}*ELEMENT, TYPE=C3D10, ELSET=E\n{}*MATERIAL, NAME=Half\n{props}\
                 *SOLID SECTION, ELSET=E, MATERIAL=HALF\n",
                unit_tet_nodes(1),
                unit_tet_element(1, 1)
            );
            let (_, line, message) = parse_error(read_text("err-incomplete", &text));
            assert_eq!(line, 14, "at the *MATERIAL line");
            assert!(
                message.contains("Half") && message.contains(missing),
                "{message}"
            );
            assert!(
                message.contains("deck.inp:17"),
                "names the section: {message}"
            );
        }
    }

    #[test]
    fn elements_in_no_section_are_counted_and_the_first_named() {
        let text = format!(
            "*NODE\n{}*ELEMENT, TYPE=C3D10, ELSET=E\n{}*ELEMENT, TYPE=C3D10\n{}{}{STEEL}\
             *SOLID SECTION, ELSET=E, MATERIAL=STEEL\n",
            unit_tet_nodes(1),
            unit_tet_element(1, 1),
            unit_tet_element(40, 1),
            unit_tet_element(41, 1)
        );
        let (_, line, message) = parse_error(read_text("err-orphan", &text));
        assert_eq!(line, 15);
        assert!(message.starts_with("2 element(s)"), "{message}");
        assert!(message.contains("element 40"), "{message}");
    }
}
