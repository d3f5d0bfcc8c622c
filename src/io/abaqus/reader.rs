//! The reader: its state while the deck is read, the line loop (keyword lines, continuation
//! lines, data lines) and the dispatch of each data line to the keyword block it belongs to.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use super::drafts::*;
use super::lexer::{parse_number, Keyword};
use super::lines::{Lines, Loc};
use crate::mesh::MeshError;

pub(super) struct Reader {
    pub(super) lines: Lines,
    pub(super) block: Block,
    pub(super) heading: Vec<String>,

    pub(super) nodes: Vec<[f64; 3]>,
    pub(super) node_labels: Vec<i64>,
    pub(super) node_locs: Vec<Loc>,
    pub(super) node_index: HashMap<i64, usize>,

    pub(super) elements: Vec<[i64; 10]>,
    pub(super) element_labels: Vec<i64>,
    pub(super) element_locs: Vec<Loc>,
    pub(super) element_index: HashMap<i64, usize>,
    pub(super) pending: Option<PendingElement>,
    /// Springs and point masses; their labels share [`Reader::element_index`]'s space.
    pub(super) discrete: Vec<DiscreteDraft>,
    pub(super) discrete_index: HashMap<i64, usize>,
    /// `*SPRING` and `*MASS` keywords.
    pub(super) properties: Vec<PropertyDraft>,

    pub(super) node_sets: BTreeMap<String, SetDraft>,
    pub(super) element_sets: BTreeMap<String, SetDraft>,
    pub(super) surfaces: BTreeMap<String, SurfaceDraft>,
    pub(super) node_surfaces: BTreeMap<String, Loc>,
    pub(super) materials: BTreeMap<String, MaterialDraft>,
    /// The material that `*ELASTIC` / `*DENSITY` belong to.
    pub(super) material: Option<String>,
    pub(super) sections: Vec<SectionDraft>,
    /// Areas given on `*SURFACE, TYPE=NODE` data lines: (surface, nodes, area).
    pub(super) node_areas: Vec<(String, SetDraft, f64)>,
    pub(super) interactions: BTreeMap<String, InteractionDraft>,
    /// The interaction that `*SURFACE BEHAVIOR` / `*FRICTION` belong to.
    pub(super) interaction: Option<String>,
    pub(super) contact_pairs: Vec<ContactPairDraft>,
    /// `*MOTION` data lines.
    pub(super) motions: Vec<super::motion_lines::MotionDraft>,
    /// Young's modulus of the first `*MATERIAL` (once its `*ELASTIC` is read).
    pub(super) first_material: Option<String>,
    /// Differences between the deck's contact law and squeal's, for one warning.
    pub(super) contact_notes: Tally,

    /// `*EQUATION`, `*TRANSFORM`, `*COUPLING` drafts.
    pub(super) constraints: super::constraint_lines::ConstraintDrafts,
    /// `*TIE` drafts.
    pub(super) ties: Vec<super::tie_lines::TieDraft>,

    pub(super) model: LoadDrafts,
    pub(super) step: Option<StepDraft>,
    pub(super) steps: Vec<StepDraft>,

    pub(super) unknown_keywords: Tally,
    pub(super) ignored_parameters: Tally,
    pub(super) rotational_dofs: Tally,
    pub(super) variant_types: Tally,
    pub(super) other_procedures: Tally,
    pub(super) warnings: Vec<String>,
}

impl Reader {
    pub(super) fn new(path: &Path) -> Result<Self, MeshError> {
        Ok(Reader {
            lines: Lines::new(path)?,
            block: Block::Start,
            heading: Vec::new(),
            nodes: Vec::new(),
            node_labels: Vec::new(),
            node_locs: Vec::new(),
            node_index: HashMap::new(),
            elements: Vec::new(),
            element_labels: Vec::new(),
            element_locs: Vec::new(),
            element_index: HashMap::new(),
            pending: None,
            discrete: Vec::new(),
            discrete_index: HashMap::new(),
            properties: Vec::new(),
            node_sets: BTreeMap::new(),
            element_sets: BTreeMap::new(),
            surfaces: BTreeMap::new(),
            node_surfaces: BTreeMap::new(),
            materials: BTreeMap::new(),
            material: None,
            sections: Vec::new(),
            node_areas: Vec::new(),
            interactions: BTreeMap::new(),
            interaction: None,
            contact_pairs: Vec::new(),
            motions: Vec::new(),
            first_material: None,
            contact_notes: Tally::default(),
            constraints: Default::default(),
            ties: Vec::new(),
            model: LoadDrafts::default(),
            step: None,
            steps: Vec::new(),
            unknown_keywords: Tally::default(),
            ignored_parameters: Tally::default(),
            rotational_dofs: Tally::default(),
            variant_types: Tally::default(),
            other_procedures: Tally::default(),
            warnings: Vec::new(),
        })
    }

    pub(super) fn err(&self, loc: Loc, message: impl Into<String>) -> MeshError {
        self.lines.error(loc, message)
    }

    pub(super) fn number(&self, field: &str, loc: Loc, what: &str) -> Result<f64, MeshError> {
        parse_number(field).ok_or_else(|| {
            self.err(
                loc,
                format!("expected a number ({what}), found \"{field}\""),
            )
        })
    }

    /// Field `k` as a number, `None` when missing or blank (Abaqus: blank = default).
    pub(super) fn optional_number(
        &self,
        fields: &[&str],
        k: usize,
        loc: Loc,
        what: &str,
    ) -> Result<Option<f64>, MeshError> {
        match fields.get(k) {
            None | Some(&"") => Ok(None),
            Some(f) => self.number(f, loc, what).map(Some),
        }
    }

    pub(super) fn label(&self, field: &str, loc: Loc, what: &str) -> Result<i64, MeshError> {
        match field.parse::<i64>() {
            Ok(v) if v > 0 => Ok(v),
            _ => Err(self.err(
                loc,
                format!("expected a positive integer ({what}), found \"{field}\""),
            )),
        }
    }

    pub(super) fn param(&self, kw: &mut Keyword, key: &str) -> Result<Option<String>, MeshError> {
        kw.value(key).map_err(|m| self.err(kw.loc, m))
    }

    pub(super) fn required(&self, kw: &mut Keyword, key: &str) -> Result<String, MeshError> {
        kw.required(key).map_err(|m| self.err(kw.loc, m))
    }

    // --- the line loop ------------------------------------------------------------------

    pub(super) fn run(&mut self) -> Result<(), MeshError> {
        let mut buf = String::new();
        while let Some(loc) = self.lines.next(&mut buf)? {
            let text = buf.trim();
            if text.is_empty() || text.starts_with("**") {
                continue;
            }
            if !text.starts_with('*') {
                self.data(text, loc)?;
                continue;
            }
            // A keyword line that ends with a comma continues on the next line.
            let mut line = text.to_string();
            while line.ends_with(',') {
                if self.lines.next(&mut buf)?.is_none() {
                    return Err(self.err(
                        loc,
                        "the keyword line ends with a comma, so it continues on the next \
                         line, but the file ends here",
                    ));
                }
                let more = buf.trim();
                if more.is_empty() || more.starts_with("**") {
                    continue;
                }
                line.push_str(more);
            }
            let keyword = Keyword::parse(&line, loc).map_err(|m| self.err(loc, m))?;
            self.keyword(keyword)?;
        }
        self.finish_element(None)?;
        if let Some(step) = &self.step {
            return Err(self.err(
                step.loc,
                "this *STEP has no *END STEP before the end of the file",
            ));
        }
        Ok(())
    }

    // --- data lines ---------------------------------------------------------------------

    pub(super) fn data(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
        let mut block = std::mem::take(&mut self.block);
        let result = self.data_in(&mut block, text, loc);
        self.block = block;
        result
    }

    fn data_in(&mut self, block: &mut Block, text: &str, loc: Loc) -> Result<(), MeshError> {
        match block {
            Block::Start => Err(self.err(
                loc,
                "expected a keyword line (starting with '*') before the first data line",
            )),
            Block::Skip => Ok(()),
            Block::NoData(keyword) => Err(self.err(
                loc,
                format!("{keyword} takes no data lines, found \"{text}\""),
            )),
            Block::Heading => {
                self.heading.push(text.to_string());
                Ok(())
            }
            Block::Node { nset } => self.node_line(nset.as_ref(), text, loc),
            Block::Element {
                elset,
                discrete: None,
            } => self.element_line(elset.as_ref(), text, loc),
            Block::Element {
                elset,
                discrete: Some(kind),
            } => {
                let kind = *kind;
                self.discrete_line(kind, elset.as_ref(), text, loc)
            }
            Block::Property(index) => {
                let index = *index;
                self.properties[index].lines.push((text.to_string(), loc));
                Ok(())
            }
            Block::NodeSet { name, generate } => {
                let generate = *generate;
                self.set_line(true, name, generate, text, loc)
            }
            Block::ElementSet { name, generate } => {
                let generate = *generate;
                self.set_line(false, name, generate, text, loc)
            }
            Block::ElementSurface { name } => self.element_surface_line(name, text, loc),
            Block::NodeSurface { name } => self.node_surface_line(name, text, loc),
            Block::Elastic { material, lines } => {
                *lines += 1;
                self.elastic_line(material, *lines, text, loc)
            }
            Block::Density { material, lines } => {
                *lines += 1;
                self.density_line(material, *lines, text, loc)
            }
            Block::StepTitle { lines } => {
                *lines += 1;
                if *lines > 1 {
                    return Err(self.err(loc, "*STEP takes at most one data line (the step title)"));
                }
                if let Some(step) = &mut self.step {
                    step.title = Some(text.to_string());
                }
                Ok(())
            }
            Block::Static { lines } => {
                *lines += 1;
                self.static_line(*lines, text, loc)
            }
            Block::Frequency { subspace, lines } => {
                *lines += 1;
                self.frequency_line(*subspace, *lines, text, loc)
            }
            Block::ComplexFrequency { lines } => {
                *lines += 1;
                self.complex_frequency_line(*lines, text, loc)
            }
            Block::Motion {
                rotation,
                by_nodes,
                keyword,
            } => {
                let (rotation, by_nodes, keyword) = (*rotation, *by_nodes, *keyword);
                self.motion_line(rotation, by_nodes, keyword, text, loc)
            }
            Block::Interaction => {
                self.ignored_parameters.add(
                    "data line of *SURFACE INTERACTION (out-of-plane thickness, 2D models only)",
                    loc,
                );
                Ok(())
            }
            Block::SurfaceBehavior { interaction, lines } => {
                *lines += 1;
                self.surface_behavior_line(interaction, *lines, text, loc)
            }
            Block::Friction { interaction, lines } => {
                *lines += 1;
                self.friction_line(interaction, *lines, text, loc)
            }
            Block::ContactPair {
                interaction,
                adjust,
                small_sliding,
            } => {
                let (interaction, adjust, small_sliding) =
                    (interaction.clone(), *adjust, *small_sliding);
                self.contact_pair_line(interaction, adjust, small_sliding, text, loc)
            }
            Block::Boundary { fixed } => {
                let fixed = *fixed;
                self.boundary_line(text, loc, fixed)
            }
            Block::Constraint(kind) => {
                let kind = *kind;
                self.constraint_line(kind, text, loc)
            }
            Block::Tie => self.tie_line(text, loc),
            Block::ConcentratedLoad => self.load_line(text, loc),
            Block::SurfacePressure => self.surface_pressure_line(text, loc),
            Block::ElementPressure => self.element_pressure_line(text, loc),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;

    #[test]
    fn a_missing_continuation_line_is_an_error() {
        let base = format!("*NODE\n{}*ELEMENT, TYPE=C3D10\n", unit_tet_nodes(1));
        let (_, line, message) = parse_error(read_text(
            "err-eof",
            &format!("{base}5, 1, 2, 3, 4, 5, 6, 7,\n** the end\n"),
        ));
        assert_eq!(line, 13);
        assert!(
            message.contains("element 5") && message.contains("file ends"),
            "{message}"
        );
        let (_, line, message) = parse_error(read_text(
            "err-keyword",
            &format!("{base}5, 1, 2, 3, 4, 5, 6, 7,\n*NSET, NSET=X\n"),
        ));
        assert_eq!(line, 13);
        assert!(message.contains("*NSET"), "{message}");
        // An *ELEMENT without data is fine.
        let deck = read_text("empty-element", &base).unwrap();
        assert!(deck.mesh.elements.is_empty());
    }

    #[test]
    fn a_non_numeric_field_is_an_error_at_its_line() {
        let (_, line, message) = parse_error(read_text(
            "err-number",
            "*NODE\n1, 0, 0, 0\n2, 1.0, 0, abc\n",
        ));
        assert_eq!(line, 3);
        assert!(
            message.contains("\"abc\"") && message.contains("z coordinate"),
            "{message}"
        );
        let (_, line, message) = parse_error(read_text(
            "err-label",
            "*NODE\n1, 0, 0, 0\n*ELEMENT, TYPE=C3D10\n5, 1, 2, 3, x4, 5, 6, 7, 8, 9, 10\n",
        ));
        assert_eq!(line, 4);
        assert!(message.contains("\"x4\""), "{message}");
    }
}
