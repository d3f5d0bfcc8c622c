//! Reader for Abaqus / CalculiX input decks (`.inp`): the flat (part-less) subset brake
//! models use, into a [`Deck`] (the [`Mesh`] plus supports, loads and steps).
//!
//! # Keywords read
//!
//! | keyword | what is kept |
//! |---|---|
//! | `*HEADING` | [`Deck::heading`] |
//! | `*INCLUDE, INPUT=` | the file's lines, in place (path relative to the including file; nests) |
//! | `*NODE` (`NSET=`) | nodes; `SYSTEM=` other than `R` is refused |
//! | `*ELEMENT, TYPE=C3D10` (`ELSET=`) | elements; other types than those below are refused by name |
//! | `*ELEMENT, TYPE=SPRING1` / `SPRING2` / `SPRINGA` / `MASS` (`ELSET=`) | discrete elements (`label, node[, node]`), labels shared with the solids |
//! | `*SPRING, ELSET=` (linear; DOF line for SPRING1/SPRING2, blank for SPRINGA; one stiffness line) | [`Deck::springs`]: SPRING1 to ground along e_i, SPRING2 (DOFs i, i) along e_i, SPRINGA along the nodes' line |
//! | `*MASS, ELSET=` (isotropic) | [`Deck::point_masses`] |
//! | `*NSET` / `*ELSET` (`GENERATE`, set names in data, `*NSET, ELSET=`) | node / element sets |
//! | `*SURFACE, TYPE=ELEMENT` / `TYPE=NODE` | [`Mesh::surfaces`] / a node set listed in [`Deck::node_surfaces`] |
//! | `*MATERIAL, NAME=`, `*ELASTIC` (isotropic), `*DENSITY` | [`Mesh::materials`] |
//! | `*SOLID SECTION, ELSET=, MATERIAL=` | one [`Part`](crate::mesh::Part) per section |
//! | `*BOUNDARY`, `*CLOAD`, `*DSLOAD`, `*DLOAD` | [`Boundary`], [`ConcentratedLoad`], [`PressureLoad`] |
//! | `*STEP` ... `*END STEP`, `*STATIC`, `*FREQUENCY` | [`Step`] |
//! | `*SURFACE INTERACTION, NAME=` with `*SURFACE BEHAVIOR` (`PRESSURE-OVERCLOSURE=LINEAR` slope, `HARD`, `NO SEPARATION`) and `*FRICTION` (mu, stick slope) | [`SurfaceInteraction`] |
//! | `*CONTACT PAIR, INTERACTION=, TYPE=NODE TO SURFACE` (`SMALL SLIDING`, `ADJUST=` distance) | [`DeckContactPair`] (element- or node-based slave) |
//! | `*EQUATION` (node sets expanded), `*TRANSFORM, NSET=, TYPE=R \| C`, `*COUPLING, REF NODE=, SURFACE=` + `*DISTRIBUTING` | [`Equation`], [`DeckTransform`], [`DeckCoupling`] (`constraint_lines.rs`) |
//! | `*TIE, NAME=` (`POSITION TOLERANCE=`, `ADJUST=YES \| NO`, `TYPE=NODE TO SURFACE \| SURFACE TO SURFACE`), `slave, master` | [`DeckTie`] (`tie_lines.rs`; the constraints are made in [`crate::model`]) |
//! | `*MOTION, ROTATION` / `TRANSLATION`, `TYPE=VELOCITY` (node set, angular speed and two axis points, or DOFs and speed) | [`Motion`] (model data or a step's) |
//! | `*COMPLEX FREQUENCY` (modes, minimum and maximum frequency, shift) | [`Procedure::ComplexFrequency`] |
//!
//! `INPUT=` on a data keyword (`*NODE, INPUT=nodes.inp`) reads its data lines from that file.
//! A keyword line ending with a comma continues on the next line. Keywords that cannot change
//! the model squeal solves (output, print and restart requests, solver controls, and the
//! definitions listed at [`keywords::ignored`]) are read past with their data lines and
//! listed, with counts and the first place each appeared, in ONE warning. Every other keyword
//! squeal does not read is refused at its line: skipping one could change the physics (a
//! skipped `*TIE` once left tied pads floating free, and the run exited 0). Some carry a
//! reason and a way out (`*PART`/`*INSTANCE`, `*SYSTEM`, node and element generation,
//! Abaqus general contact, contact clearances); the rest are named as not read.
//!
//! # Conventions decided here
//!
//! - Keywords, parameter names and the names of sets, surfaces and materials are
//!   case-insensitive, as in Abaqus. Names are stored in UPPER CASE (the keys of
//!   [`Mesh::node_sets`], [`Mesh::surfaces`], [`Mesh::materials`], [`Deck::element_sets`], part
//!   and material names); error messages quote the spelling used on the offending line.
//! - Node and element labels are any positive integers; they may be used before the line that
//!   defines them (they are resolved once the whole deck is read). A set named in the data
//!   lines of `*NSET`, `*ELSET` or `*SURFACE, TYPE=NODE` must already be defined: its current
//!   members are copied, as Abaqus does. Every other name (in `*SOLID SECTION`, element-based
//!   `*SURFACE`, loads, supports) is looked up in the complete model, and an unknown one is an
//!   error at the line that names it. Repeating `*NSET`/`*ELSET` with one name adds to the set.
//! - Solid and discrete elements share one label space and may share element sets;
//!   [`Deck::element_sets`] keeps a set's solids. A `*SOLID SECTION` on a set holding
//!   discrete elements, and a `*SPRING` or `*MASS` on one holding solids (or other discrete
//!   types), are refused at their line; every discrete element needs its `*SPRING`/`*MASS`.
//! - Labels written explicitly in a set must exist; labels produced by `GENERATE` that no node
//!   or element carries are left out with a warning (ranges over gappy numbering are common).
//! - DOFs are Abaqus' 1-based numbers in the raw records ([`Boundary::first_dof`]); DOFs 4-6
//!   (rotations, which solid nodes do not have) are dropped with a warning. In [`Loading`]
//!   they become 0-based components (0 = x).
//! - Pressures keep Abaqus' sign: a positive value pushes INTO the element, against the
//!   outward face normal of [`crate::mesh::TET10_FACES`].
//!
//! # Steps and what is in force
//!
//! Supports and loads outside any step are model data ([`Deck::boundaries`] ...); those inside
//! a step are stored on that [`Step`]. [`Deck::loading_in_step`] gives what acts in step k, with
//! the Abaqus/CalculiX rules (`OP=MOD` by default):
//! model data, then every earlier step that is not a linear-perturbation step, then step k.
//! A later definition on the same (node, DOF) replaces the earlier value; a `*DSLOAD` on a
//! surface replaces the earlier `*DSLOAD` on that surface; a `*DLOAD` on an element face
//! replaces the earlier one on that face; different surfaces loading one face add up.
//! `OP=NEW` on a keyword removes everything of that kind in force before the step (model data
//! included). The loads of a linear-perturbation step (`*FREQUENCY`, `*COMPLEX FREQUENCY`,
//! `*BUCKLE`, ..., or any step with `PERTURBATION` on `*STEP`) act in that step only.
//!
//! # `*FREQUENCY` data line
//!
//! CalculiX: number of eigenfrequencies desired, lower and upper value of the frequency range
//! of interest (cycles per time). Abaqus' Lanczos and AMS eigensolvers (the default) use the
//! same first three fields, then the shift point; `EIGENSOLVER=SUBSPACE` uses number of
//! eigenvalues, maximum frequency of interest, shift point. All land in [`FrequencyRequest`].
//!
//! # Where things are
//!
//! `lines.rs` (the deck's lines with includes), `lexer.rs` (keyword lines and fields),
//! `reader.rs` (the reader's state and line loop), `keywords.rs` (what each keyword starts),
//! `mesh_lines.rs`, `material_lines.rs`, `procedure_lines.rs` and `load_lines.rs` (data lines
//! by keyword family), `discrete_lines.rs` (springs and point masses, read and resolved),
//! `contact_lines.rs` (the contact keywords, read and resolved), `motion_lines.rs` (`*MOTION`), `drafts.rs` (what was said, unresolved), `resolve.rs` (labels and names
//! to the model), `records.rs` (the public records) and `steps.rs` (what is in force in a
//! step).

mod constraint_lines;
mod contact_lines;
mod discrete_lines;
mod drafts;
mod keywords;
mod lexer;
mod lines;
mod load_lines;
mod material_lines;
mod mesh_lines;
mod motion_lines;
mod procedure_lines;
mod reader;
mod records;
mod resolve;
mod steps;
#[cfg(test)]
mod test_support;
mod tie_lines;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use crate::mesh::{Mesh, MeshError};
pub use constraint_lines::{
    DeckCoupling, DeckTransform, DistributingWeighting, Equation, EquationTerm, TransformKind,
};
use reader::Reader;
pub use records::{
    Boundary, ComplexFrequencyRequest, ConcentratedLoad, DeckContactPair, DeckMass, DeckSpring,
    FrequencyRequest, Motion, MotionKind, NodeTarget, NormalBehavior, PressureLoad, PressureTarget,
    Procedure, Replaced, SlaveSurface, SourceLine, SpringEnds, StaticRequest, Step,
    SurfaceInteraction,
};
pub use steps::Loading;
pub use tie_lines::{DeckTie, TieKind};

/// Everything read from a deck.
#[derive(Clone, Debug, Default)]
pub struct Deck {
    /// Nodes, C3D10 elements, one part per `*SOLID SECTION`, materials, node sets and
    /// element-based surfaces.
    pub mesh: Mesh,
    /// The `*HEADING` data lines, joined by newlines.
    pub heading: String,
    /// Element sets: their C3D10 elements (internal element indices, sorted, unique); the
    /// discrete elements of a set are in [`Deck::springs`] and [`Deck::point_masses`].
    pub element_sets: BTreeMap<String, Vec<usize>>,
    /// `SPRING1`, `SPRING2` and `SPRINGA` elements with their `*SPRING` stiffness.
    pub springs: Vec<DeckSpring>,
    /// `MASS` elements with their `*MASS`.
    pub point_masses: Vec<DeckMass>,
    /// Names of `*SURFACE, TYPE=NODE` surfaces; each is also in [`Mesh::node_sets`].
    pub node_surfaces: BTreeSet<String>,
    /// Model-data supports (outside any step).
    pub boundaries: Vec<Boundary>,
    /// Model-data concentrated loads.
    pub concentrated_loads: Vec<ConcentratedLoad>,
    /// Model-data pressures.
    pub pressures: Vec<PressureLoad>,
    pub steps: Vec<Step>,
    /// `*SURFACE INTERACTION`s by upper-case name, each used by a pair.
    pub interactions: BTreeMap<String, SurfaceInteraction>,
    /// `*CONTACT PAIR` data lines, in the order written.
    pub contact_pairs: Vec<DeckContactPair>,
    /// `*EQUATION`s, node sets expanded, in the order written.
    pub equations: Vec<Equation>,
    /// `*TIE`s, in the order written.
    pub ties: Vec<DeckTie>,
    /// `*TRANSFORM`s (no node in two).
    pub transforms: Vec<DeckTransform>,
    /// `*COUPLING` + `*DISTRIBUTING`, one per reference node.
    pub couplings: Vec<DeckCoupling>,
    /// `*MOTION`s given in the model data (those of a step are on [`Step::motions`]).
    pub motions: Vec<Motion>,
    /// Young's modulus of the deck's first `*MATERIAL`: CalculiX derives its default
    /// tension at large clearance (E / 70000) and `HARD`'s slope (50 E) from it.
    pub first_young: Option<f64>,
    /// Things a person should know: skipped keywords, ignored parameters and DOFs...
    pub warnings: Vec<String>,
}

/// Read an Abaqus/CalculiX deck (and the files it includes).
pub fn read(path: &Path) -> Result<Deck, MeshError> {
    let mut reader = Reader::new(path)?;
    reader.run()?;
    reader.finish()
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;
    use crate::mesh::TET10_EDGES;

    /// Regenerates tests/data/beam_c3d10.inp: `cargo test write_beam_deck -- --ignored`.
    #[test]
    #[ignore]
    fn write_beam_deck() {
        std::fs::write(beam_path(), beam_deck()).expect("write beam deck");
    }

    #[test]
    fn beam_deck_reads_with_right_counts_and_positive_volumes() {
        let path = beam_path();
        let text = std::fs::read_to_string(&path).expect("tests/data/beam_c3d10.inp");
        assert_eq!(
            text,
            beam_deck(),
            "committed deck differs from its generator"
        );
        let deck = read(&path).unwrap();
        let mesh = &deck.mesh;
        // (2*10+1) * (2*2+1)^2 half-grid points, all used; 6 tets per cube.
        assert_eq!(mesh.nodes.len(), 21 * 5 * 5);
        assert_eq!(mesh.elements.len(), 6 * 10 * 2 * 2);
        // Kuhn tets all have volume (cube volume)/6 > 0, and they tile the beam exactly.
        let cube = 0.01 * 0.005 * 0.005;
        let mut total = 0.0;
        for e in 0..mesh.elements.len() {
            let v = mesh.corner_volume(e);
            assert!((v - cube / 6.0).abs() < 1e-12 * cube, "element {e}: {v}");
            total += v;
        }
        assert!((total - 1e-5).abs() < 1e-12 * 1e-5);
        // Each mid node sits at the middle of its edge (the C3D10 order was kept).
        for conn in &mesh.elements {
            for (k, [a, b]) in TET10_EDGES.iter().enumerate() {
                let (mid, p, q) = (
                    mesh.nodes[conn[4 + k]],
                    mesh.nodes[conn[*a]],
                    mesh.nodes[conn[*b]],
                );
                for (c, m) in mid.iter().enumerate() {
                    assert!((m - 0.5 * (p[c] + q[c])).abs() < 1e-12);
                }
            }
        }
        assert_eq!(mesh.parts.len(), 1);
        assert_eq!(mesh.parts[0].name, "EBEAM");
        assert_eq!(mesh.parts[0].elements.len(), 240);
        let steel = &mesh.materials["STEEL"];
        assert_eq!(
            (steel.young, steel.poisson, steel.density),
            (210e9, 0.3, 7850.0)
        );
        let fix = &mesh.node_sets["FIX"];
        assert_eq!(fix.len(), 25);
        assert!(fix.iter().all(|&n| mesh.nodes[n][0] == 0.0));
        assert_eq!(deck.steps.len(), 1);
        assert_eq!(
            deck.steps[0].procedure,
            Procedure::Frequency(FrequencyRequest {
                eigenvalues: Some(10),
                ..Default::default()
            })
        );
        let loading = deck.loading_in_step(0).unwrap();
        assert_eq!(loading.displacements.len(), 75);
        assert!(loading.displacements.values().all(|&v| v == 0.0));
        assert_eq!(deck.warnings.len(), 1, "{:?}", deck.warnings);
        assert!(deck.warnings[0].contains("*NODE FILE (1x"));
        assert!(deck.warnings[0].contains("*EL FILE (1x"));
    }
}
