//! Discrete elements: `SPRING1`, `SPRING2`, `SPRINGA` and `MASS` element lines, the
//! `*SPRING` and `*MASS` keywords that give them a stiffness or a mass, and their resolution
//! into [`DeckSpring`]s and [`DeckMass`]es.
//!
//! `*SPRING` data lines, as Abaqus and CalculiX 2.20 read them (linear springs): the first
//! line holds the DOF (SPRING1) or the two DOFs (SPRING2); for SPRINGA it is blank, and a
//! blank line is skipped like any other here (CalculiX skips it too, and tells a stiffness
//! line from a DOF line by its decimal point), so a SPRINGA set has its stiffness line alone.
//! The stiffness line is `stiffness[, unused or frequency, temperature]`; several stiffness
//! lines (a temperature table) are refused, as are `NONLINEAR` and `ORIENTATION=`.

use std::collections::BTreeMap;

use super::drafts::*;
use super::lexer::{data_fields, Keyword, Name};
use super::lines::Loc;
use super::reader::Reader;
use super::{DeckMass, DeckSpring, SpringEnds};
use crate::mesh::MeshError;
use crate::vector3::{dot, sub};

/// What a `*SPRING` gives its elements.
struct SpringProperty {
    /// 0-based translation, `None` for SPRINGA.
    dof: Option<usize>,
    stiffness: f64,
}

impl Reader {
    /// A solid or discrete element label must be new among both (they share one space).
    pub(super) fn check_new_element_label(&self, label: i64, loc: Loc) -> Result<(), MeshError> {
        let first = match (
            self.element_index.get(&label),
            self.discrete_index.get(&label),
        ) {
            (Some(&e), _) => self.element_locs[e],
            (None, Some(&d)) => self.discrete[d].loc,
            (None, None) => return Ok(()),
        };
        Err(self.err(
            loc,
            format!(
                "element {label} is defined twice (first at {})",
                self.lines.at(first)
            ),
        ))
    }

    pub(super) fn discrete_line(
        &mut self,
        kind: DiscreteKind,
        elset: Option<&Name>,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        let f = data_fields(text);
        let n = kind.node_count();
        let expected = if n == 1 {
            "a label and 1 node label"
        } else {
            "a label and 2 node labels"
        };
        if f.len() != n + 1 || f.iter().any(|s| s.is_empty()) {
            return Err(self.err(
                loc,
                format!(
                    "{} element: expected {expected}, found \"{text}\"",
                    kind.name()
                ),
            ));
        }
        let label = self.label(f[0], loc, "element label")?;
        let mut nodes = Vec::with_capacity(n);
        for field in &f[1..] {
            nodes.push(self.label(field, loc, "node label")?);
        }
        if n == 2 && nodes[0] == nodes[1] {
            return Err(self.err(
                loc,
                format!(
                    "{} element {label} lists node {} twice (a spring needs two nodes)",
                    kind.name(),
                    nodes[0]
                ),
            ));
        }
        self.check_new_element_label(label, loc)?;
        self.discrete_index.insert(label, self.discrete.len());
        self.discrete.push(DiscreteDraft {
            kind,
            label,
            nodes,
            loc,
        });
        if let Some(set) = elset.and_then(|n| self.element_sets.get_mut(&n.canon)) {
            set.add(Member { label, loc });
        }
        Ok(())
    }

    pub(super) fn spring_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        if kw.flag("NONLINEAR") {
            return Err(self.err(
                kw.loc,
                "*SPRING, NONLINEAR is not supported: squeal's springs are linear (give one \
                 stiffness)",
            ));
        }
        if let Some(o) = self.param(kw, "ORIENTATION")? {
            return Err(self.err(
                kw.loc,
                format!(
                    "*SPRING, ORIENTATION={o} is not supported: the DOFs of SPRING1 and SPRING2 \
                     must be the global x, y, z (a SPRINGA needs no orientation)"
                ),
            ));
        }
        let elset = Name::new(&self.required(kw, "ELSET")?);
        self.properties.push(PropertyDraft {
            keyword: "*SPRING",
            elset,
            lines: Vec::new(),
            loc: kw.loc,
        });
        Ok(Block::Property(self.properties.len() - 1))
    }

    pub(super) fn mass_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        if let Some(t) = self.param(kw, "TYPE")? {
            if !t.eq_ignore_ascii_case("ISOTROPIC") {
                return Err(self.err(
                    kw.loc,
                    format!(
                        "*MASS, TYPE={t} is not supported (only the isotropic point mass, \
                         TYPE=ISOTROPIC)"
                    ),
                ));
            }
        }
        let elset = Name::new(&self.required(kw, "ELSET")?);
        self.properties.push(PropertyDraft {
            keyword: "*MASS",
            elset,
            lines: Vec::new(),
            loc: kw.loc,
        });
        Ok(Block::Property(self.properties.len() - 1))
    }

    /// The springs and point masses, each with the `*SPRING` or `*MASS` of its set.
    /// `solid_sets` and `discrete_sets` are the element sets split by kind (same keys).
    pub(super) fn resolve_discrete(
        &self,
        nodes: &[[f64; 3]],
        solid_sets: &BTreeMap<String, Vec<usize>>,
        discrete_sets: &BTreeMap<String, Vec<usize>>,
        element_labels: &[i64],
    ) -> Result<(Vec<DeckSpring>, Vec<DeckMass>), MeshError> {
        // Per discrete element: its property's index, and the stiffness or mass it gives.
        let mut owner: Vec<Option<usize>> = vec![None; self.discrete.len()];
        let mut springs_of: Vec<Option<SpringProperty>> = Vec::new();
        let mut masses_of: Vec<Option<f64>> = Vec::new();
        for (p, prop) in self.properties.iter().enumerate() {
            let (springs, mass) = (prop.keyword == "*SPRING", prop.keyword == "*MASS");
            let Some(members) = discrete_sets.get(&prop.elset.canon) else {
                return Err(self.err(
                    prop.loc,
                    format!(
                        "{}: element set {} is not defined",
                        prop.keyword, prop.elset.written
                    ),
                ));
            };
            let wanted = if springs {
                "SPRING1, SPRING2 or SPRINGA"
            } else {
                "MASS"
            };
            if let Some(&solid) = solid_sets.get(&prop.elset.canon).and_then(|s| s.first()) {
                return Err(self.err(
                    prop.loc,
                    format!(
                        "{}: element set {} holds C3D10 elements (first: element {}); {} \
                         applies to {wanted} elements only",
                        prop.keyword, prop.elset.written, element_labels[solid], prop.keyword
                    ),
                ));
            }
            let Some(&first) = members.first() else {
                return Err(self.err(
                    prop.loc,
                    format!(
                        "{}: element set {} holds no {wanted} elements",
                        prop.keyword, prop.elset.written
                    ),
                ));
            };
            let kind = self.discrete[first].kind;
            for &d in members {
                let other = &self.discrete[d];
                let fits = if mass {
                    other.kind == DiscreteKind::Mass
                } else {
                    other.kind == kind && kind != DiscreteKind::Mass
                };
                if !fits {
                    return Err(self.err(
                        prop.loc,
                        format!(
                            "{}: element set {} holds {} element {} and {} element {}; {} \
                             applies to {wanted} elements, one type per set",
                            prop.keyword,
                            prop.elset.written,
                            kind.name(),
                            self.discrete[first].label,
                            other.kind.name(),
                            other.label,
                            prop.keyword
                        ),
                    ));
                }
                if let Some(previous) = owner[d] {
                    return Err(self.err(
                        prop.loc,
                        format!(
                            "element {} already has the {} at {}; an element takes one only",
                            other.label,
                            self.properties[previous].keyword,
                            self.lines.at(self.properties[previous].loc)
                        ),
                    ));
                }
                owner[d] = Some(p);
            }
            if springs {
                springs_of.push(Some(self.spring_property(prop, kind)?));
                masses_of.push(None);
            } else {
                springs_of.push(None);
                masses_of.push(Some(self.mass_property(prop)?));
            }
        }
        let mut springs = Vec::new();
        let mut masses = Vec::new();
        for (d, draft) in self.discrete.iter().enumerate() {
            let Some(p) = owner[d] else {
                let keyword = if draft.kind == DiscreteKind::Mass {
                    "*MASS"
                } else {
                    "*SPRING"
                };
                return Err(self.err(
                    draft.loc,
                    format!(
                        "{} element {} is in no {keyword}, so it has no {}; give its element \
                         set a {keyword}",
                        draft.kind.name(),
                        draft.label,
                        if keyword == "*MASS" {
                            "mass"
                        } else {
                            "stiffness"
                        }
                    ),
                ));
            };
            let mut ends = Vec::with_capacity(2);
            for label in &draft.nodes {
                ends.push(*self.node_index.get(label).ok_or_else(|| {
                    self.err(
                        draft.loc,
                        format!(
                            "element {} references node {label}, which is not defined",
                            draft.label
                        ),
                    )
                })?);
            }
            let source = self.lines.source(draft.loc);
            if let Some(mass) = masses_of[p] {
                masses.push(DeckMass {
                    label: draft.label,
                    node: ends[0],
                    mass,
                    source,
                });
                continue;
            }
            let Some(spring) = &springs_of[p] else {
                continue;
            };
            let direction = match spring.dof {
                Some(c) => {
                    let mut e = [0.0; 3];
                    e[c] = 1.0;
                    e
                }
                None => {
                    let d = sub(nodes[ends[1]], nodes[ends[0]]);
                    let length = dot(d, d).sqrt();
                    if length == 0.0 {
                        return Err(self.err(
                            draft.loc,
                            format!(
                                "SPRINGA element {}: its nodes {} and {} coincide, so the \
                                 spring has no direction",
                                draft.label, draft.nodes[0], draft.nodes[1]
                            ),
                        ));
                    }
                    d.map(|x| x / length)
                }
            };
            springs.push(DeckSpring {
                label: draft.label,
                element_type: draft.kind.name(),
                ends: match ends[..] {
                    [a, b] => SpringEnds::Nodes([a, b]),
                    _ => SpringEnds::Ground(ends[0]),
                },
                direction,
                stiffness: spring.stiffness,
                source,
            });
        }
        Ok((springs, masses))
    }

    /// A `*SPRING`'s data lines for elements of `kind`.
    fn spring_property(
        &self,
        prop: &PropertyDraft,
        kind: DiscreteKind,
    ) -> Result<SpringProperty, MeshError> {
        let dofs = match kind {
            DiscreteKind::Spring1 => 1,
            DiscreteKind::Spring2 => 2,
            _ => 0,
        };
        let wanted = match dofs {
            1 => "a DOF line (the SPRING1 DOF) then a stiffness line",
            2 => "a DOF line (the two SPRING2 DOFs) then a stiffness line",
            _ => "a blank line then a stiffness line",
        };
        let expected_lines = if dofs == 0 { 1 } else { 2 };
        if prop.lines.len() < expected_lines {
            return Err(self.err(
                prop.loc,
                format!(
                    "*SPRING, ELSET={} ({} elements): expected {wanted}, found {} data line(s)",
                    prop.elset.written,
                    kind.name(),
                    prop.lines.len()
                ),
            ));
        }
        if dofs == 0 && prop.lines.len() == 2 {
            let (text, loc) = &prop.lines[0];
            return Err(self.err(
                *loc,
                format!(
                    "*SPRING, ELSET={}: SPRINGA elements act along the line through their \
                     nodes and take no DOFs; leave the first data line blank (found \"{text}\")",
                    prop.elset.written
                ),
            ));
        }
        if prop.lines.len() > expected_lines {
            let (_, loc) = &prop.lines[expected_lines];
            return Err(self.err(
                *loc,
                format!(
                    "*SPRING, ELSET={}: a second stiffness line (a temperature-dependent \
                     stiffness) is not supported; give one stiffness line",
                    prop.elset.written
                ),
            ));
        }
        let dof = if dofs > 0 {
            let (text, loc) = &prop.lines[0];
            let f = data_fields(text);
            if f.len() != dofs {
                return Err(self.err(
                    *loc,
                    format!(
                        "*SPRING, ELSET={} ({} elements): expected {dofs} DOF number(s), found \
                         \"{text}\"",
                        prop.elset.written,
                        kind.name()
                    ),
                ));
            }
            let mut numbers = Vec::with_capacity(dofs);
            for field in f {
                let d = self.label(field, *loc, "DOF number 1, 2 or 3")?;
                if d > 3 {
                    return Err(self.err(
                        *loc,
                        format!(
                            "*SPRING: DOF {d} is a rotation, and C3D10 nodes have only \
                             displacements (DOFs 1-3)"
                        ),
                    ));
                }
                numbers.push(d as usize - 1);
            }
            if numbers.len() == 2 && numbers[0] != numbers[1] {
                return Err(self.err(
                    *loc,
                    format!(
                        "*SPRING: SPRING2 DOFs {} and {} differ; such a spring couples u{} of one \
                         node to u{} of the other, which a spring along one direction cannot \
                         represent (give the same DOF twice)",
                        numbers[0] + 1,
                        numbers[1] + 1,
                        numbers[0] + 1,
                        numbers[1] + 1
                    ),
                ));
            }
            Some(numbers[0])
        } else {
            None
        };
        let (text, loc) = &prop.lines[expected_lines - 1];
        let f = data_fields(text);
        if f.is_empty() || f.len() > 3 || f[0].is_empty() {
            return Err(self.err(
                *loc,
                format!("*SPRING: expected \"stiffness[, , temperature]\", found \"{text}\""),
            ));
        }
        let stiffness = self.number(f[0], *loc, "spring stiffness")?;
        if !(stiffness.is_finite() && stiffness > 0.0) {
            return Err(self.err(
                *loc,
                format!("*SPRING: expected a finite stiffness > 0, found {stiffness}"),
            ));
        }
        Ok(SpringProperty { dof, stiffness })
    }

    /// A `*MASS`'s data line.
    fn mass_property(&self, prop: &PropertyDraft) -> Result<f64, MeshError> {
        let Some((text, loc)) = prop.lines.first() else {
            return Err(self.err(
                prop.loc,
                format!(
                    "*MASS, ELSET={}: expected a data line with the mass",
                    prop.elset.written
                ),
            ));
        };
        if let Some((_, extra)) = prop.lines.get(1) {
            return Err(self.err(
                *extra,
                format!(
                    "*MASS, ELSET={}: expected one data line (the mass)",
                    prop.elset.written
                ),
            ));
        }
        let f = data_fields(text);
        if f.len() != 1 || f[0].is_empty() {
            return Err(self.err(
                *loc,
                format!("*MASS: expected one field, the mass, found \"{text}\""),
            ));
        }
        let mass = self.number(f[0], *loc, "mass")?;
        if !(mass.is_finite() && mass > 0.0) {
            return Err(self.err(
                *loc,
                format!("*MASS: expected a finite mass > 0, found {mass}"),
            ));
        }
        Ok(mass)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::super::SpringEnds;

    /// One tet (nodes 11..20, element 7) with a node 30 of its own and `tail`.
    fn deck(tail: &str) -> String {
        format!("{}*NODE\n30, 2.0, 0.0, 0.0\n{tail}", one_tet())
    }

    /// The 1-based line of the `k`-th line (0-based) of `tail` in [`deck`].
    fn line_of(tail_line: usize) -> usize {
        deck("").lines().count() + tail_line + 1
    }

    const ALL_KINDS: &str = "*ELEMENT, TYPE=SPRING1, ELSET=S1\n101, 12\n\
        *ELEMENT, TYPE=SPRING2, ELSET=S2\n102, 13, 30\n\
        *ELEMENT, TYPE=SPRINGA, ELSET=SA\n103, 12, 13\n104, 14, 30\n\
        *ELEMENT, TYPE=MASS, ELSET=M\n105, 30\n\
        *SPRING, ELSET=S1\n3\n1.5e3\n*SPRING, ELSET=S2\n2, 2\n2.5e3, , 20.\n\
        *SPRING, ELSET=SA\n\n4e3\n*MASS, ELSET=m\n0.25\n";

    #[test]
    fn springs_and_masses_are_read_with_their_directions() {
        let d = read_text("discrete", &deck(ALL_KINDS)).unwrap();
        assert_eq!(d.mesh.elements.len(), 1, "discrete elements are not solids");
        assert_eq!(d.springs.len(), 4);
        // Node labels 11.. are indices 0..; node 30 is index 10.
        let s = &d.springs;
        assert_eq!(
            (s[0].label, s[0].element_type, s[0].ends),
            (101, "SPRING1", SpringEnds::Ground(1))
        );
        assert_eq!((s[0].direction, s[0].stiffness), ([0.0, 0.0, 1.0], 1.5e3));
        assert_eq!(s[1].ends, SpringEnds::Nodes([2, 10]));
        assert_eq!((s[1].direction, s[1].stiffness), ([0.0, 1.0, 0.0], 2.5e3));
        // SPRINGA: from (1, 0, 0) to (0, 1, 0), and from (0, 0, 1) to (2, 0, 0).
        let r2 = 0.5f64.sqrt();
        let r5 = 0.2f64.sqrt();
        for (spring, want) in [(&s[2], [-r2, r2, 0.0]), (&s[3], [2.0 * r5, 0.0, -r5])] {
            for (got, want) in spring.direction.iter().zip(want) {
                assert!((got - want).abs() < 1e-15, "{spring:?}");
            }
            assert_eq!(spring.stiffness, 4e3);
        }
        assert_eq!(d.point_masses.len(), 1);
        assert_eq!((d.point_masses[0].node, d.point_masses[0].mass), (10, 0.25));
        assert!(d.point_masses[0].source.to_string().contains("deck.inp:"));
    }

    #[test]
    fn a_springa_stiffness_line_alone_is_read_as_calculix_does() {
        // CalculiX skips the blank line, so a deck may well leave it out.
        let text = deck(ALL_KINDS).replace("*SPRING, ELSET=SA\n\n4e3", "*SPRING, ELSET=SA\n4e3");
        let d = read_text("springa-no-blank", &text).unwrap();
        assert_eq!(d.springs[2].stiffness, 4e3);
    }

    #[test]
    fn an_element_set_used_by_spring_and_section_may_hold_both_elsewhere() {
        // *NSET, ELSET= takes the nodes of discrete elements too.
        let text = deck(&format!(
            "{ALL_KINDS}*ELSET, ELSET=EVERY\nEALL, S2\n*NSET, NSET=FROMSET, ELSET=EVERY\n"
        ));
        let d = read_text("nset-of-discrete", &text).unwrap();
        assert_eq!(d.mesh.node_sets["FROMSET"].len(), 11);
        assert_eq!(d.element_sets["EVERY"], vec![0], "the solids of the set");
    }

    /// Each refusal: (what replaces what in ALL_KINDS, the line of the tail it names, words
    /// the message must hold).
    #[test]
    fn refusals_name_the_line_and_what_was_expected() {
        let cases: [(&str, &str, usize, &[&str]); 14] = [
            (
                "*SPRING, ELSET=S1\n",
                "*SPRING, ELSET=S1, NONLINEAR\n",
                9,
                &["NONLINEAR", "linear"],
            ),
            (
                "*SPRING, ELSET=S1\n",
                "*SPRING, ELSET=S1, ORIENTATION=OR1\n",
                9,
                &["ORIENTATION=OR1", "global x, y, z"],
            ),
            (
                "S1\n3\n",
                "S1\n5\n",
                10,
                &["DOF 5 is a rotation", "DOFs 1-3"],
            ),
            (
                "2, 2\n",
                "1, 2\n",
                13,
                &["SPRING2 DOFs 1 and 2 differ", "cannot"],
            ),
            (
                "SA\n\n4e3",
                "SA\n1, 2\n4e3",
                16,
                &["SPRINGA", "leave the first data line blank", "\"1, 2\""],
            ),
            (
                "103, 12, 13\n",
                "103, 12, 12\n",
                5,
                &["lists node 12 twice"],
            ),
            (
                "102, 13, 30\n",
                "102, 13\n",
                3,
                &[
                    "SPRING2 element: expected a label and 2 node labels",
                    "\"102, 13\"",
                ],
            ),
            (
                "0.25\n",
                "heavy\n",
                19,
                &["expected a number (mass)", "\"heavy\""],
            ),
            (
                "1.5e3\n",
                "-1.5e3\n",
                11,
                &["expected a finite stiffness > 0"],
            ),
            (
                "1.5e3\n",
                "1.5e3\n2.0e3, , 100.\n",
                12,
                &["second stiffness line", "temperature"],
            ),
            (
                "105, 30\n",
                "7, 30\n",
                8,
                &["element 7 is defined twice", "deck.inp:13"],
            ),
            (
                "*MASS, ELSET=m\n",
                "*MASS, ELSET=m, TYPE=ANISOTROPIC\n",
                18,
                &["TYPE=ANISOTROPIC", "isotropic"],
            ),
            (
                "*MASS, ELSET=m\n",
                "*MASS, ELSET=EALL\n",
                18,
                &[
                    "EALL holds C3D10 elements",
                    "element 7",
                    "MASS elements only",
                ],
            ),
            (
                "*SPRING, ELSET=SA\n",
                "*SPRING, ELSET=S1\n",
                15,
                &["element 101 already has the *SPRING at", "deck.inp:"],
            ),
        ];
        for (i, (from, to, line, words)) in cases.iter().enumerate() {
            assert!(ALL_KINDS.contains(from), "case {i}: {from:?}");
            let text = deck(&ALL_KINDS.replacen(from, to, 1));
            let (file, at, message) = parse_error(read_text(&format!("refusal-{i}"), &text));
            assert!(file.ends_with("deck.inp"), "case {i}");
            assert_eq!(at, line_of(*line), "case {i}: {message}");
            for w in *words {
                assert!(message.contains(w), "case {i}: {w:?} not in {message:?}");
            }
        }
    }

    #[test]
    fn coincident_springa_nodes_and_orphans_are_refused_at_the_element() {
        let text = deck(&format!("{ALL_KINDS}*NODE\n31, 0.0, 1.0, 0.0\n"))
            .replace("103, 12, 13", "103, 31, 13");
        let (_, line, message) = parse_error(read_text("coincident", &text));
        assert_eq!(line, line_of(5), "{message}");
        assert!(
            message.contains("SPRINGA element 103") && message.contains("coincide"),
            "{message}"
        );
        let text = deck(&format!("{ALL_KINDS}*ELEMENT, TYPE=SPRING1\n106, 14\n"));
        let (_, line, message) = parse_error(read_text("orphan-spring", &text));
        assert_eq!(line, line_of(21));
        assert!(
            message.contains("SPRING1 element 106 is in no *SPRING"),
            "{message}"
        );
    }

    #[test]
    fn a_solid_section_on_a_set_with_discrete_elements_is_refused() {
        let text = deck(&format!(
            "{ALL_KINDS}*ELSET, ELSET=MIXED\nEALL, M\n\
             *SOLID SECTION, ELSET=MIXED, MATERIAL=STEEL\n"
        ));
        let (_, line, message) = parse_error(read_text("mixed-section", &text));
        assert_eq!(line, line_of(22));
        assert!(
            message.contains("*SOLID SECTION: element set MIXED holds the MASS element 105"),
            "{message}"
        );
    }
}
