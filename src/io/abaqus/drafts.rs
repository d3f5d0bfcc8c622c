//! Drafts: what the deck said, before labels and names are resolved (labels may be used
//! before the line that defines them), and the tallies that become one warning each.

use std::collections::{HashMap, HashSet};

use super::lexer::Name;
use super::lines::{Lines, Loc};
use super::{Procedure, Replaced};

/// A label written in a set (or added by `*NODE, NSET=` / `*ELEMENT, ELSET=`): it must exist.
#[derive(Clone, Copy, Debug)]
pub(super) struct Member {
    pub(super) label: i64,
    pub(super) loc: Loc,
}

/// A `GENERATE` range as written (`first <= last`, `step >= 1`). It is expanded when the
/// sets are resolved, over the labels the deck defines: expanded on its line, `1, 99999999`
/// (12 bytes) once made 100 million members.
#[derive(Clone, Copy, Debug)]
pub(super) struct GeneratedRange {
    pub(super) first: i64,
    pub(super) last: i64,
    pub(super) step: i64,
    pub(super) loc: Loc,
}

impl GeneratedRange {
    /// How many labels the range produces.
    pub(super) fn len(&self) -> u64 {
        // first <= last, both positive: no overflow.
        ((self.last - self.first) / self.step) as u64 + 1
    }

    /// The indices (values of `index`, a label -> index map) of the range's labels that
    /// exist, sorted. Walks the range or the map, whichever is shorter, so the work and the
    /// memory are bounded by the labels the deck defines, never by the range.
    pub(super) fn existing(&self, index: &HashMap<i64, usize>) -> Vec<usize> {
        let mut found: Vec<usize> = if self.len() <= index.len() as u64 {
            (0..self.len() as i64)
                .filter_map(|k| index.get(&(self.first + k * self.step)).copied())
                .collect()
        } else {
            index
                .iter()
                .filter(|(&label, _)| {
                    label >= self.first
                        && label <= self.last
                        && (label - self.first) % self.step == 0
                })
                .map(|(_, &i)| i)
                .collect()
        };
        found.sort_unstable();
        found
    }
}

/// A node or element set as said so far: its labels (each once) and `GENERATE` ranges (each
/// once). Each only once, because a set is a set, and because a deck that copies a set into
/// itself (`*NSET, NSET=A` then data lines `A`) once doubled it at every 2-byte line, until
/// the memory ran out.
#[derive(Clone, Debug)]
pub(super) struct SetDraft {
    pub(super) written: String,
    members: Vec<Member>,
    labels: HashSet<i64>,
    ranges: Vec<GeneratedRange>,
}

impl SetDraft {
    pub(super) fn new(written: &str) -> SetDraft {
        SetDraft {
            written: written.to_string(),
            members: Vec::new(),
            labels: HashSet::new(),
            ranges: Vec::new(),
        }
    }

    pub(super) fn members(&self) -> &[Member] {
        &self.members
    }

    pub(super) fn ranges(&self) -> &[GeneratedRange] {
        &self.ranges
    }

    /// Adds a label, unless the set holds it already (the first place is kept).
    pub(super) fn add(&mut self, member: Member) {
        if self.labels.insert(member.label) {
            self.members.push(member);
        }
    }

    /// Adds a range, unless the set holds the same range already.
    pub(super) fn add_range(&mut self, range: GeneratedRange) {
        let same =
            |r: &GeneratedRange| (r.first, r.last, r.step) == (range.first, range.last, range.step);
        if !self.ranges.iter().any(same) {
            self.ranges.push(range);
        }
    }

    /// Adds everything `other` holds now (Abaqus copies a named set's current members).
    pub(super) fn add_all(&mut self, other: &SetDraft) {
        for &m in &other.members {
            self.add(m);
        }
        for &r in &other.ranges {
            self.add_range(r);
        }
    }
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
    /// `*BOUNDARY, FIXED`.
    pub(super) fixed: bool,
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

/// The normal law of an interaction as `*SURFACE BEHAVIOR` said it.
#[derive(Clone, Copy)]
pub(super) enum NormalDraft {
    /// `PRESSURE-OVERCLOSURE=LINEAR`: the slope once its data line is read.
    Linear(Option<f64>),
    /// `PRESSURE-OVERCLOSURE=HARD` (or no `*SURFACE BEHAVIOR`): squeal's default penalty.
    Hard,
}

/// A `*SURFACE INTERACTION` with the options that followed it.
pub(super) struct InteractionDraft {
    pub(super) written: String,
    /// `*SURFACE BEHAVIOR`, and where.
    pub(super) normal: Option<(NormalDraft, Loc)>,
    /// `false` with `NO SEPARATION`.
    pub(super) separation: bool,
    pub(super) friction: Option<FrictionDraft>,
    /// `PRESSURE-OVERCLOSURE=LINEAR`'s tension at large clearance and clearance factor.
    pub(super) linear_extra: (Option<f64>, Option<f64>),
    pub(super) loc: Loc,
}

/// A `*FRICTION`: mu (once its data line is read) and the stick slope.
#[derive(Clone, Copy)]
pub(super) struct FrictionDraft {
    pub(super) mu: Option<f64>,
    pub(super) stick_slope: Option<f64>,
    pub(super) loc: Loc,
}

/// One data line of `*CONTACT PAIR`.
pub(super) struct ContactPairDraft {
    pub(super) interaction: Name,
    pub(super) slave: Name,
    pub(super) master: Name,
    pub(super) adjust: Option<f64>,
    pub(super) loc: Loc,
}

/// The discrete element types read (`*ELEMENT, TYPE=`): springs and point masses, whose
/// stiffness or mass comes from a `*SPRING` or `*MASS` on their element set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum DiscreteKind {
    Spring1,
    Spring2,
    SpringA,
    Mass,
}

impl DiscreteKind {
    /// The kind of an upper-case element type, `None` for any other type.
    pub(super) fn from_type(upper: &str) -> Option<DiscreteKind> {
        Some(match upper {
            "SPRING1" => DiscreteKind::Spring1,
            "SPRING2" => DiscreteKind::Spring2,
            "SPRINGA" => DiscreteKind::SpringA,
            "MASS" => DiscreteKind::Mass,
            _ => return None,
        })
    }

    pub(super) fn name(self) -> &'static str {
        match self {
            DiscreteKind::Spring1 => "SPRING1",
            DiscreteKind::Spring2 => "SPRING2",
            DiscreteKind::SpringA => "SPRINGA",
            DiscreteKind::Mass => "MASS",
        }
    }

    pub(super) fn node_count(self) -> usize {
        match self {
            DiscreteKind::Spring1 | DiscreteKind::Mass => 1,
            DiscreteKind::Spring2 | DiscreteKind::SpringA => 2,
        }
    }
}

/// One discrete element line: `label, node[, node]`.
pub(super) struct DiscreteDraft {
    pub(super) kind: DiscreteKind,
    pub(super) label: i64,
    pub(super) nodes: Vec<i64>,
    pub(super) loc: Loc,
}

/// A `*SPRING` or `*MASS` as said: its element set and its data lines, kept as text because
/// what they mean (a DOF line or not) depends on the type of the set's elements, known once
/// the whole deck is read.
pub(super) struct PropertyDraft {
    /// `*SPRING` or `*MASS`.
    pub(super) keyword: &'static str,
    pub(super) elset: Name,
    pub(super) lines: Vec<(String, Loc)>,
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
        /// `None` for C3D10.
        discrete: Option<DiscreteKind>,
    },
    /// The data lines of `*SPRING` / `*MASS`: the index of its [`PropertyDraft`].
    Property(usize),
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
    ComplexFrequency {
        lines: usize,
    },
    /// `*MOTION` data lines (the keyword's place merges its translation lines).
    Motion {
        rotation: bool,
        by_nodes: bool,
        keyword: Loc,
    },
    /// Data lines of `*SURFACE INTERACTION` (Abaqus: the out-of-plane thickness of 2D models).
    Interaction,
    SurfaceBehavior {
        interaction: String,
        lines: usize,
    },
    Friction {
        interaction: String,
        lines: usize,
    },
    ContactPair {
        interaction: Name,
        adjust: Option<f64>,
        small_sliding: bool,
    },
    Boundary {
        /// `*BOUNDARY, FIXED`: held at the displacement the step starts from.
        fixed: bool,
    },
    ConcentratedLoad,
    SurfacePressure,
    ElementPressure,
    /// `*EQUATION`, `*TRANSFORM`, `*DISTRIBUTING` ([`super::constraint_lines`]).
    Constraint(super::constraint_lines::ConstraintBlock),
    /// The data line of a `*TIE` ([`super::tie_lines`]).
    Tie,
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
