//! Data lines of the mesh keywords: `*NODE`, `*ELEMENT` (continued over lines), `*NSET` and
//! `*ELSET` (with `GENERATE` and set names), `*SURFACE` of either type.

use super::drafts::*;
use super::lexer::{data_fields, looks_numeric, parse_number, Name};
use super::lines::Loc;
use super::reader::Reader;
use crate::mesh::MeshError;

/// A `GENERATE` range longer than this is a typo, not a set.
const MAX_GENERATED: i64 = 100_000_000;

impl Reader {
    pub(super) fn node_line(
        &mut self,
        nset: Option<&Name>,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        let f = data_fields(text);
        // label, x, y, z, then optionally a normal direction (meaningless for solids).
        if f.len() < 2 || f.len() > 7 {
            return Err(self.err(
                loc,
                format!(
                    "*NODE: expected a node label and its coordinates, found {} fields",
                    f.len()
                ),
            ));
        }
        let label = self.label(f[0], loc, "node label")?;
        let mut x = [0.0; 3];
        // Blank coordinates are zero, as in Abaqus. The message is only built on error:
        // this loop runs once per node of a model of millions.
        for (k, (field, axis)) in f[1..].iter().zip(["x", "y", "z"]).enumerate() {
            if !field.is_empty() {
                x[k] = parse_number(field).ok_or_else(|| {
                    self.err(
                        loc,
                        format!(
                            "expected a number ({axis} coordinate of node {label}), found \
                             \"{field}\""
                        ),
                    )
                })?;
            }
        }
        if let Some(&first) = self.node_index.get(&label) {
            return Err(self.err(
                loc,
                format!(
                    "node {label} is defined twice (first at {})",
                    self.lines.at(self.node_locs[first])
                ),
            ));
        }
        self.node_index.insert(label, self.nodes.len());
        self.nodes.push(x);
        self.node_labels.push(label);
        self.node_locs.push(loc);
        if let Some(set) = nset.and_then(|n| self.node_sets.get_mut(&n.canon)) {
            set.add(Member { label, loc });
        }
        Ok(())
    }

    pub(super) fn element_line(
        &mut self,
        elset: Option<&Name>,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        let continues = text.ends_with(',');
        let mut values = match self.pending.take() {
            Some(p) => p.values,
            None => Vec::with_capacity(11),
        };
        for field in data_fields(text) {
            let what = if values.is_empty() {
                "element label"
            } else {
                "node label"
            };
            if field.is_empty() {
                return Err(self.err(
                    loc,
                    format!("expected a positive integer ({what}), found an empty field"),
                ));
            }
            values.push(self.label(field, loc, what)?);
        }
        let label = values.first().copied();
        if values.len() > 11 {
            return Err(self.err(
                loc,
                format!(
                    "element {}: C3D10 needs a label and 10 node labels, found {} node labels",
                    values[0],
                    values.len() - 1
                ),
            ));
        }
        if values.len() < 11 {
            if continues {
                if !values.is_empty() {
                    self.pending = Some(PendingElement { values, last: loc });
                }
                return Ok(());
            }
            return Err(self.err(
                loc,
                match label {
                    Some(l) => format!(
                        "element {l}: C3D10 needs a label and 10 node labels, found {} node \
                         labels (a line that ends with a comma continues on the next line)",
                        values.len() - 1
                    ),
                    None => "expected an element label and 10 node labels".to_string(),
                },
            ));
        }
        let label = values[0];
        let mut nodes = [0i64; 10];
        nodes.copy_from_slice(&values[1..]);
        for (k, n) in nodes.iter().enumerate() {
            if nodes[..k].contains(n) {
                return Err(self.err(loc, format!("element {label} lists node {n} twice")));
            }
        }
        self.check_new_element_label(label, loc)?;
        self.element_index.insert(label, self.elements.len());
        self.elements.push(nodes);
        self.element_labels.push(label);
        self.element_locs.push(loc);
        if let Some(set) = elset.and_then(|n| self.element_sets.get_mut(&n.canon)) {
            set.add(Member { label, loc });
        }
        Ok(())
    }

    pub(super) fn set_line(
        &mut self,
        of_nodes: bool,
        name: &Name,
        generate: bool,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        let (keyword, item, label_of) = if of_nodes {
            ("*NSET", "node", "node label")
        } else {
            ("*ELSET", "element", "element label")
        };
        let f = data_fields(text);
        // What the line adds, gathered first (each label once) because it may name the
        // set itself.
        let mut members = SetDraft::new(&name.written);
        if generate {
            if f.len() < 2 || f.len() > 3 {
                return Err(self.err(
                    loc,
                    format!(
                        "{keyword}, GENERATE: expected first, last[, increment], found {} fields",
                        f.len()
                    ),
                ));
            }
            let first = self.label(f[0], loc, &format!("first {item} label"))?;
            let last = self.label(f[1], loc, &format!("last {item} label"))?;
            let step = match f.get(2) {
                Some(s) if !s.is_empty() => self.label(s, loc, "increment")?,
                _ => 1,
            };
            if last < first {
                return Err(self.err(
                    loc,
                    format!(
                        "{keyword}, GENERATE: the last label {last} is below the first {first}"
                    ),
                ));
            }
            if (last - first) / step >= MAX_GENERATED {
                return Err(self.err(
                    loc,
                    format!("{keyword}, GENERATE: the range {first}..{last} is implausibly long"),
                ));
            }
            members.add_range(GeneratedRange {
                first,
                last,
                step,
                loc,
            });
        } else {
            let sets = if of_nodes {
                &self.node_sets
            } else {
                &self.element_sets
            };
            for field in f.iter().filter(|s| !s.is_empty()) {
                if looks_numeric(field) {
                    members.add(Member {
                        label: self.label(field, loc, label_of)?,
                        loc,
                    });
                } else {
                    let other = Name::new(field);
                    match sets.get(&other.canon) {
                        Some(set) => members.add_all(set),
                        None => {
                            return Err(self.err(
                                loc,
                                format!(
                                    "{keyword} {}: {item} set {} is not defined (above this line)",
                                    name.written, other.written
                                ),
                            ))
                        }
                    }
                }
            }
        }
        let sets = if of_nodes {
            &mut self.node_sets
        } else {
            &mut self.element_sets
        };
        if let Some(set) = sets.get_mut(&name.canon) {
            set.add_all(&members);
        }
        Ok(())
    }

    pub(super) fn element_surface_line(
        &mut self,
        name: &Name,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.is_empty() || f.len() > 2 || f[0].is_empty() {
            return Err(self.err(
                loc,
                "*SURFACE, TYPE=ELEMENT: expected \"element or element set, face (S1..S4)\"",
            ));
        }
        let target = if looks_numeric(f[0]) {
            ElementRef::Element(self.label(f[0], loc, "element label")?)
        } else {
            ElementRef::Set(Name::new(f[0]))
        };
        let side = match f.get(1) {
            None | Some(&"") => None,
            Some(s) => match s.to_uppercase().as_str() {
                "S1" => Some(0),
                "S2" => Some(1),
                "S3" => Some(2),
                "S4" => Some(3),
                _ => {
                    return Err(self.err(
                        loc,
                        format!(
                            "expected a face identifier S1, S2, S3 or S4 (the faces of a \
                             C3D10), found \"{s}\""
                        ),
                    ))
                }
            },
        };
        if let Some(surface) = self.surfaces.get_mut(&name.canon) {
            surface.members.push(SurfaceMember { target, side, loc });
        }
        Ok(())
    }

    pub(super) fn node_surface_line(
        &mut self,
        name: &Name,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.is_empty() || f.len() > 2 || f[0].is_empty() {
            return Err(self.err(
                loc,
                "*SURFACE, TYPE=NODE: expected \"node or node set[, area]\"",
            ));
        }
        let members = if looks_numeric(f[0]) {
            let mut one = SetDraft::new(&name.written);
            one.add(Member {
                label: self.label(f[0], loc, "node label")?,
                loc,
            });
            one
        } else {
            let other = Name::new(f[0]);
            match self.node_sets.get(&other.canon) {
                Some(set) => set.clone(),
                None => {
                    return Err(self.err(
                        loc,
                        format!(
                            "*SURFACE {}: node set {} is not defined (above this line)",
                            name.written, other.written
                        ),
                    ))
                }
            }
        };
        // The area each node stands for in node-to-surface contact (Abaqus: 1 when blank).
        if let Some(area) = self.optional_number(&f, 1, loc, "area of each node")? {
            if area <= 0.0 {
                return Err(self.err(
                    loc,
                    format!(
                        "*SURFACE {}: expected an area > 0, found {area}",
                        name.written
                    ),
                ));
            }
            self.node_areas
                .push((name.canon.clone(), members.clone(), area));
        }
        if let Some(set) = self.node_sets.get_mut(&name.canon) {
            set.add_all(&members);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::super::*;

    #[test]
    fn generate_expands_ranges_and_drops_missing_labels_with_a_warning() {
        let text = format!(
            "{}*NSET, NSET=EVERY2, GENERATE\n11, 19, 2\n*NSET, NSET=GAPPY, GENERATE\n18, 25\n\
             *ELSET, ELSET=E, GENERATE\n7, 7\n",
            one_tet()
        );
        let deck = read_text("generate", &text).unwrap();
        assert_eq!(deck.mesh.node_sets["EVERY2"], vec![0, 2, 4, 6, 8]);
        assert_eq!(deck.mesh.node_sets["GAPPY"], vec![7, 8, 9]);
        assert_eq!(deck.element_sets["E"], vec![0]);
        let w = deck
            .warnings
            .iter()
            .find(|w| w.contains("GAPPY"))
            .expect("warning for GAPPY");
        assert!(w.contains("5 label(s)") && w.contains("deck.inp:"), "{w}");
    }

    #[test]
    fn a_set_named_in_its_own_data_lines_keeps_each_label_once() {
        // Each line naming the set being defined once doubled it: 40 such lines asked for
        // 2^40 members (found writing the fuzz targets; the memory ran out).
        let text = format!(
            "{}*NSET, NSET=A\n11, 12\n*NSET, NSET=A\n{}*NSET, NSET=B, ELSET=EALL\n\
             *NSET, NSET=B\n{}*SURFACE, NAME=S, TYPE=NODE\n{}",
            one_tet(),
            "A, A, 11\n".repeat(40),
            "B, A\n".repeat(40),
            "B\n".repeat(40),
        );
        let deck = read_text("self-copy", &text).unwrap();
        assert_eq!(deck.mesh.node_sets["A"], vec![0, 1]);
        assert_eq!(deck.mesh.node_sets["B"].len(), 10);
        assert_eq!(deck.mesh.node_sets["S"].len(), 10);
    }

    #[test]
    fn a_long_generate_range_costs_only_the_labels_that_exist() {
        // Expanded on its line, "1, 99999999" (12 bytes) made 100 million members.
        let text = format!(
            "{}*NSET, NSET=G, GENERATE\n1, 99999999\n*ELSET, ELSET=EG, GENERATE\n\
             1, 99999999, 2\n*NSET, NSET=FROM, ELSET=EG\n*NSET, NSET=G\nG, G\n",
            one_tet()
        );
        let deck = read_text("long-generate", &text).unwrap();
        assert_eq!(deck.mesh.node_sets["G"], (0..10).collect::<Vec<_>>());
        // Element 7 is odd, so in the second range.
        assert_eq!(deck.element_sets["EG"], vec![0]);
        assert_eq!(deck.mesh.node_sets["FROM"].len(), 10);
        let w = deck
            .warnings
            .iter()
            .find(|w| w.contains("node set G:"))
            .expect("warning for G");
        assert!(w.contains("99999989 label(s)"), "{w}");
    }

    #[test]
    fn an_element_may_continue_on_the_next_line() {
        let text = format!(
            "*NODE\n{}*ELEMENT, TYPE=C3D10, ELSET=EALL\n7, 11, 12, 13, 14, 15, 16, 17,\n\
             18, 19, 20\n** a comment between elements\n8, 11, 12, 13, 14, 15, 16, 17, 18, 19, \
             20,\n{STEEL}*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n",
            unit_tet_nodes(11)
        );
        let deck = read_text("continuation", &text).unwrap();
        assert_eq!(deck.mesh.element_labels, vec![7, 8]);
        assert_eq!(deck.mesh.elements[0], deck.mesh.elements[1]);
        assert_eq!(deck.mesh.elements[0], [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]);
    }

    #[test]
    fn a_node_based_surface_becomes_a_node_set_and_is_marked() {
        let text = format!(
            "{}*SURFACE, NAME=Contact, TYPE=NODE\nNALL\n*NSET, NSET=SOME\n11\n\
             *SURFACE, NAME=Two, TYPE=NODE\nSOME, 1.0\n12\n",
            one_tet()
        );
        let deck = read_text("node-surface", &text).unwrap();
        assert_eq!(deck.mesh.node_sets["CONTACT"].len(), 10);
        assert_eq!(deck.mesh.node_sets["TWO"], vec![0, 1]);
        assert_eq!(
            deck.node_surfaces,
            BTreeSet::from(["CONTACT".to_string(), "TWO".to_string()])
        );
        assert!(deck.mesh.surfaces.is_empty());
    }

    #[test]
    fn a_wrong_node_count_for_c3d10_is_an_error() {
        let base = format!("*NODE\n{}*ELEMENT, TYPE=C3D10\n", unit_tet_nodes(1));
        let (_, line, message) = parse_error(read_text(
            "err-count-short",
            &format!("{base}5, 1, 2, 3, 4, 5, 6, 7, 8, 9\n"),
        ));
        assert_eq!(line, 13);
        assert!(
            message.contains("element 5") && message.contains("found 9"),
            "{message}"
        );
        let (_, line, message) = parse_error(read_text(
            "err-count-long",
            &format!("{base}5, 1, 2, 3, 4, 5, 6,\n7, 8, 9, 10, 11\n"),
        ));
        assert_eq!(line, 14);
        assert!(message.contains("found 11"), "{message}");
    }

    #[test]
    fn a_duplicate_node_label_is_an_error() {
        let (_, line, message) = parse_error(read_text(
            "err-duplicate",
            "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n*NODE\n1, 5, 5, 5\n",
        ));
        assert_eq!(line, 5);
        assert!(message.contains("node 1 is defined twice") && message.contains(":2"));
    }
}
