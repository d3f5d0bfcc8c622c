//! The frictional interfaces (METHOD.md section 2): node-to-surface contact in small sliding
//! with a penalty normal law and steady-sliding Coulomb friction.
//!
//! - [`pair`]: what a contact pair is ([`ContactPair`], [`ContactPoint`], [`PairSettings`],
//!   [`SlidingDirection`]) and how one is built, node-to-surface from a mesh
//!   ([`node_to_surface`]) or node-to-node from given points ([`node_to_node`]).
//! - [`project`]: projection of a point on a 6-node triangular face and the bucket search for
//!   the closest face of a surface ([`SurfaceSearch`]).
//! - [`coulomb`]: Coulomb friction with stick and slip ([`Status`]), its return mapping and
//!   consistent tangent, and the slip history a model carries ([`SlipHistory`]).
//! - [`variant`]: CalculiX's variant of the law ([`ContactVariant`]), to compare like with
//!   like against CalculiX.
//! - [`penalty`]: the gap, the contact force and its (unsymmetric) Jacobian at one contact
//!   point for a displacement field ([`evaluate`]), and a pair's summary ([`summarize`]).
//! - [`zone`]: the closed zone's normal stiffness and its moments ([`ZoneStiffness`]).
//!
//! Small sliding: every contact point keeps, for the whole analysis, the master point it
//! faced in the reference configuration (its weights `N_j`), the unit normal `n` there and the
//! sliding direction `t`. The gap is then linear in the displacements and the only
//! non-linearity is the switch between open and closed.

pub mod coulomb;
pub mod pair;
pub mod penalty;
pub mod project;
pub mod variant;
pub mod zone;

pub use coulomb::{SlipHistory, Status};
pub use pair::{
    node_to_node, node_to_surface, nodes_to_surface, tributary_areas, ContactPair, ContactPoint,
    FrictionLaw, MasterFace, PairSettings, SlidingDirection, Tilt,
};
pub use penalty::{
    evaluate, point_state, summarize, summarize_states, zone_stiffness, PairSummary,
    PointContribution, PointState, PressureRange,
};
pub use project::{project_on_face, FaceProjection, SearchOptions, SurfaceHit, SurfaceSearch};
pub use variant::{perturbation_history, CalculixLaw, ContactVariant};
pub use zone::{ZoneRatios, ZoneStiffness};

/// Errors of the contact stage. Every variant names the pair.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ContactError {
    /// A setting, a surface or a contact point that cannot be used (negative friction
    /// coefficient, non-finite penalty, zero rotation axis, empty surface, degenerate face,
    /// non-unit normal...). `what` says which and why.
    #[error("contact pair '{pair}': {what}")]
    Invalid { pair: String, what: String },
    /// Slave nodes that face no master face: their projection falls outside every master face
    /// by more than the in-face tolerance, or farther from it than the largest distance
    /// allowed. `examples` are the first few, as (node label, reference coordinates).
    #[error(
        "contact pair '{pair}': {count} slave node(s) do not project onto the master surface \
         ({tolerance}); first ones (label: x, y, z): {}",
        format_examples(examples)
    )]
    Unprojected {
        pair: String,
        count: usize,
        /// The tolerances used, in words, so that the user knows what to relax.
        tolerance: String,
        examples: Vec<(i64, [f64; 3])>,
    },
    /// A contact point refers to a node the displacement field does not have.
    #[error(
        "contact pair '{pair}': contact point refers to node index {node}, but the \
         displacement field has {nodes} nodes"
    )]
    NodeOutOfRange {
        pair: String,
        node: usize,
        nodes: usize,
    },
}

/// Nodes as "label: x, y, z; ..." for messages that name a few of them.
pub(crate) fn format_examples(examples: &[(i64, [f64; 3])]) -> String {
    examples
        .iter()
        .map(|(label, x)| format!("{label}: {:.6e}, {:.6e}, {:.6e}", x[0], x[1], x[2]))
        .collect::<Vec<_>>()
        .join("; ")
}

/// Node groups coupled by the contact pairs (a point's slave and master nodes), for the
/// matrix pattern.
pub fn contact_groups(pairs: &[pair::ContactPair]) -> Vec<Vec<usize>> {
    pairs
        .iter()
        .flat_map(|p| p.points.iter())
        .map(|pt| {
            pt.slave
                .iter()
                .chain(&pt.master)
                .map(|&(n, _)| n)
                .chain(pt.tilt.iter().flat_map(|t| t.nodes))
                .collect()
        })
        .collect()
}

/// Meshes for the tests of this module: two blocks in one mesh.
#[cfg(test)]
pub(crate) mod test_models {
    use crate::mesh::block::block;
    use crate::mesh::{Material, Mesh, Surface};

    pub fn material(name: &str, young: f64) -> Material {
        Material {
            name: name.into(),
            young,
            poisson: 0.3,
            density: 7800.0,
        }
    }

    /// `b` appended to `a`: nodes, elements, parts and materials; `b`'s surfaces and node sets
    /// get the prefix `prefix`, `a`'s keep their names. Labels are renumbered to stay unique.
    pub fn merge(mut a: Mesh, b: Mesh, prefix: &str) -> Mesh {
        let node_offset = a.nodes.len();
        let element_offset = a.elements.len();
        a.nodes.extend(b.nodes);
        a.node_labels = (1..=a.nodes.len() as i64).collect();
        a.elements
            .extend(b.elements.iter().map(|c| c.map(|n| n + node_offset)));
        a.element_labels = (1..=a.elements.len() as i64).collect();
        for mut part in b.parts {
            part.name = format!("{prefix}{}", part.name);
            part.elements.iter_mut().for_each(|e| *e += element_offset);
            a.parts.push(part);
        }
        a.materials.extend(b.materials);
        for (name, nodes) in b.node_sets {
            let shifted = nodes.iter().map(|n| n + node_offset).collect();
            a.node_sets.insert(format!("{prefix}{name}"), shifted);
        }
        for (name, surface) in b.surfaces {
            let faces = surface
                .faces
                .iter()
                .map(|f| crate::mesh::Face {
                    element: f.element + element_offset,
                    side: f.side,
                    nodes: f.nodes.map(|n| n + node_offset),
                })
                .collect();
            let name = format!("{prefix}{name}");
            a.surfaces.insert(name.clone(), Surface { name, faces });
        }
        a
    }

    /// A "disc" block [0, 1] x [0, 1] x [-0.2, 0] (5 x 5 x 1 cells, E = 210e9) and a "pad"
    /// block [0.2, 0.7] x [0.3, 0.6] x [gap, gap + 0.1] (3 x 2 x 1 cells, E = 1e9) above it:
    /// non-matching meshes. The disc's top is surface `z1`, the pad's bottom `pad.z0`.
    pub fn pad_on_disc(gap: f64) -> Mesh {
        let disc = block(
            [0.0, 0.0, -0.2],
            [1.0, 1.0, 0.2],
            [5, 5, 1],
            material("steel", 210e9),
        )
        .unwrap();
        let pad = block(
            [0.2, 0.3, gap],
            [0.5, 0.3, 0.1],
            [3, 2, 1],
            material("lining", 1e9),
        )
        .unwrap();
        merge(disc, pad, "pad.")
    }
}
