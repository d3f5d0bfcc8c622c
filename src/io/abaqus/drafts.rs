//! Drafts: what the deck said, before labels and names are resolved (labels may be used
//! before the line that defines them), and the tallies that become one warning each.

use std::collections::HashMap;

use super::lexer::Name;
use super::lines::{Lines, Loc};
use super::{Procedure, Replaced};

#[derive(Clone, Copy, Debug)]
pub(super) struct Member {
    pub(super) label: i64,
    pub(super) loc: Loc,
    pub(super) generated: bool,
}

pub(super) struct SetDraft {
    pub(super) written: String,
    pub(super) members: Vec<Member>,
}

pub(super) enum NodeRef {
    Set(Name),
    Node(i64),
}

pub(super) enum ElementRef {
    Set(Name),
    Element(i64),
}

pub(super) struct SurfaceMember {
    pub(super) target: ElementRef,
    /// 0..4, or `None` for "every free face of the set".
    pub(super) side: Option<u8>,
    pub(super) loc: Loc,
}

pub(super) struct SurfaceDraft {
    pub(super) written: String,
    pub(super) members: Vec<SurfaceMember>,
    pub(super) loc: Loc,
}

pub(super) struct MaterialDraft {
    pub(super) written: String,
    pub(super) elastic: Option<(f64, f64)>,
    pub(super) density: Option<f64>,
    pub(super) loc: Loc,
}

pub(super) struct SectionDraft {
    pub(super) elset: Name,
    pub(super) material: Name,
    pub(super) loc: Loc,
}

pub(super) struct BoundaryDraft {
    pub(super) target: NodeRef,
    pub(super) first_dof: u8,
    pub(super) last_dof: u8,
    pub(super) value: f64,
    pub(super) loc: Loc,
}

pub(super) struct LoadDraft {
    pub(super) target: NodeRef,
    pub(super) dof: u8,
    pub(super) value: f64,
    pub(super) loc: Loc,
}

pub(super) struct SurfacePressureDraft {
    pub(super) surface: Name,
    pub(super) value: f64,
    pub(super) loc: Loc,
}

pub(super) struct ElementPressureDraft {
    pub(super) target: ElementRef,
    pub(super) side: u8,
    pub(super) value: f64,
    pub(super) loc: Loc,
}

#[derive(Default)]
pub(super) struct LoadDrafts {
    pub(super) boundaries: Vec<BoundaryDraft>,
    pub(super) loads: Vec<LoadDraft>,
    pub(super) surface_pressures: Vec<SurfacePressureDraft>,
    pub(super) element_pressures: Vec<ElementPressureDraft>,
    /// Surface and element pressures in the order written (true = surface).
    pub(super) pressure_order: Vec<bool>,
}

pub(super) struct StepDraft {
    pub(super) name: Option<String>,
    pub(super) title: Option<String>,
    pub(super) procedure: Option<(Procedure, Loc)>,
    pub(super) perturbation_parameter: bool,
    pub(super) nlgeom: bool,
    pub(super) loads: LoadDrafts,
    pub(super) replaced: Replaced,
    pub(super) loc: Loc,
}

pub(super) struct PendingElement {
    pub(super) values: Vec<i64>,
    pub(super) last: Loc,
}

/// What data lines mean under the current keyword.
#[derive(Default)]
pub(super) enum Block {
    /// Before the first keyword.
    #[default]
    Start,
    /// A skipped keyword, or data that is not needed.
    Skip,
    /// A keyword that takes no data lines.
    NoData(String),
    Heading,
    Node {
        nset: Option<Name>,
    },
    Element {
        elset: Option<Name>,
    },
    NodeSet {
        name: Name,
        generate: bool,
    },
    ElementSet {
        name: Name,
        generate: bool,
    },
    ElementSurface {
        name: Name,
    },
    NodeSurface {
        name: Name,
    },
    Elastic {
        material: String,
        lines: usize,
    },
    Density {
        material: String,
        lines: usize,
    },
    StepTitle {
        lines: usize,
    },
    Static {
        lines: usize,
    },
    Frequency {
        subspace: bool,
        lines: usize,
    },
    Boundary,
    ConcentratedLoad,
    SurfacePressure,
    ElementPressure,
}

/// Occurrences of something to warn about, by key: count and first place.
#[derive(Default)]
pub(super) struct Tally {
    pub(super) entries: Vec<(String, usize, Loc)>,
    pub(super) index: HashMap<String, usize>,
}

impl Tally {
    pub(super) fn add(&mut self, key: &str, loc: Loc) {
        match self.index.get(key) {
            Some(&i) => self.entries[i].1 += 1,
            None => {
                self.index.insert(key.to_string(), self.entries.len());
                self.entries.push((key.to_string(), 1, loc));
            }
        }
    }

    pub(super) fn describe(&self, lines: &Lines) -> String {
        self.entries
            .iter()
            .map(|(key, n, loc)| format!("{key} ({n}x, first at {})", lines.at(*loc)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}
