//! THE MODEL as plain data: the mesh with its materials, supports, springs, loads, contact
//! pairs, and the extra nodes and coupling springs the reduction layer adds. One type for
//! every kind of model squeal analyses (the full reference model, a reduced-interface
//! model), built from a study file ([`Model::from_spec`]), a mesh or deck file
//! ([`source::read`]) or the built-in brake ([`source::builtin`]), and turned into PETSc
//! operators at the last moment by [`assemble::assemble`]. Same on every rank.

pub mod assemble;
mod build;
mod deck_constraints;
pub mod deck_contact;
mod deck_ties;
mod error;
pub mod source;
pub mod spec;

pub use assemble::{assemble, Operators};
pub use error::ModelError;

use crate::contact::ContactPair;
use crate::fem::constraints::LinearConstraint;
use crate::fem::point_mass::PointMass;
use crate::fem::springs::{CouplingSpring, GroundSpring, ScalarSpring, TwoNodeSpring};
use crate::fem::Support;
use crate::mesh::{Face, Mesh};

/// A uniform pressure on a set of faces (positive pushes into the body).
#[derive(Clone, Debug, PartialEq)]
pub struct Pressure {
    /// The surface's name, or where the load came from (a deck's `*DSLOAD`).
    pub name: String,
    pub faces: Vec<Face>,
    pub value: f64,
}

/// A structural model with its contact interfaces.
#[derive(Clone, Debug, Default)]
pub struct Model {
    /// "built-in brake 'tiny'" or the file name, for messages and reports.
    pub source: String,
    pub mesh: Mesh,
    /// Nodes in no element, numbered after the mesh nodes (the reduced contact nodes and
    /// their disc-side partners): their positions.
    pub extra_nodes: Vec<[f64; 3]>,
    pub supports: Vec<Support>,
    pub springs: Vec<GroundSpring>,
    /// Springs between two nodes (guide pins, a piston seal).
    pub links: Vec<TwoNodeSpring>,
    /// Masses concentrated at nodes (a deck's `MASS` elements), on top of the elements' mass.
    pub point_masses: Vec<PointMass>,
    /// Springs tying a node to a weighted combination of nodes (distributing couplings).
    pub couplings: Vec<CouplingSpring>,
    /// Springs on one linear combination of components each (a reduced contact's tilt ties).
    pub scalar_springs: Vec<ScalarSpring>,
    /// Linear multi-point constraints applied exactly (a deck's `*EQUATION`, distributing
    /// couplings, supports and prescribed displacements in local directions, nonzero
    /// prescribed displacements), in the order they are eliminated.
    pub constraints: Vec<LinearConstraint>,
    pub pressures: Vec<Pressure>,
    /// Nodal forces (node, component, value).
    pub forces: Vec<(usize, usize, f64)>,
    pub pairs: Vec<ContactPair>,
    /// Which pairs a friction sweep sets mu on (one flag per pair).
    pub swept: Vec<bool>,
    /// The (slave, master) surface names of each node-to-surface pair (one per pair; `None`
    /// for node-to-node pairs): where the reduction layer lays its grids.
    pub pair_surfaces: Vec<Option<(String, String)>>,
    /// The pairs read from a deck's `*CONTACT PAIR`s: pair name -> its `*SURFACE
    /// INTERACTION` (upper-case names).
    pub deck_interactions: std::collections::BTreeMap<String, String>,
    /// The deck pairs a `*MOTION` makes slide: pair name -> the motion and the law the
    /// pair had before (what a sliding direction given by flag or study key goes back from).
    pub deck_motions: std::collections::BTreeMap<String, deck_contact::MotionSliding>,
    /// What the CalculiX contact variant makes of each deck pair, by pair name
    /// ([`deck_contact::apply_variant`]).
    pub deck_calculix: std::collections::BTreeMap<String, deck_contact::CalculixPair>,
    /// From an Abaqus `*FREQUENCY` step: (number of modes, upper frequency).
    pub frequency_step: Option<(Option<usize>, Option<f64>)>,
    /// What a reader or builder noticed and did not refuse.
    pub warnings: Vec<String>,
}

impl Model {
    /// Mesh nodes and extra nodes.
    pub fn node_count(&self) -> usize {
        self.mesh.nodes.len() + self.extra_nodes.len()
    }

    /// Position of any node, mesh or extra.
    pub fn position(&self, node: usize) -> [f64; 3] {
        let n = self.mesh.nodes.len();
        if node < n {
            self.mesh.nodes[node]
        } else {
            self.extra_nodes[node - n]
        }
    }

    /// The nodes that discrete elements (springs, links, point masses) and constraints use:
    /// with the elements' nodes, every node that has a stiffness or a mass or is tied.
    pub fn discrete_nodes(&self) -> impl Iterator<Item = usize> + '_ {
        self.springs
            .iter()
            .map(|s| s.node)
            .chain(self.links.iter().flat_map(|l| l.nodes))
            .chain(self.point_masses.iter().map(|p| p.node))
            .chain(
                self.constraints
                    .iter()
                    .flat_map(|c| c.terms.iter().map(|t| t.0)),
            )
    }

    /// The node's label in its mesh file (the index + 1 of an extra node), for messages.
    pub fn node_label(&self, node: usize) -> String {
        match self.mesh.node_labels.get(node) {
            Some(label) => label.to_string(),
            None => format!("{} (extra)", node + 1),
        }
    }

    /// The constraints solved for their dependent DOFs against the model's supports.
    pub fn resolved_constraints(
        &self,
    ) -> Result<crate::fem::constraints::Resolved, crate::fem::constraints::ConstraintError> {
        crate::fem::constraints::resolve(
            &self.constraints,
            &self.supports,
            self.node_count(),
            &|n| self.node_label(n),
        )
    }

    /// Every loaded face with its pressure.
    pub fn pressure_faces(&self) -> Vec<(Face, f64)> {
        self.pressures
            .iter()
            .flat_map(|p| p.faces.iter().map(move |f| (*f, p.value)))
            .collect()
    }

    /// The resultant of each pressure load, |sum of its consistent nodal forces|, summed
    /// over the loads: what the contact interfaces must carry in all (each pad carries its
    /// own side's load, so the magnitudes add).
    pub fn applied_load(&self) -> f64 {
        self.pressures
            .iter()
            .map(|p| {
                let r = crate::fem::loads::pressure_resultant(&self.mesh, &p.faces, p.value);
                (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt()
            })
            .sum()
    }

    /// The contact pairs with friction `mu` on the swept ones: a copy, so that the sweep's
    /// variable goes to each solve as an argument and the model keeps the friction its
    /// study gave (it was written into the model's own pairs, and a failed cut-back left
    /// them at the last friction tried).
    pub fn pairs_at(&self, mu: f64) -> Vec<ContactPair> {
        self.pairs
            .iter()
            .zip(&self.swept)
            .map(|(pair, &swept)| {
                let mut pair = pair.clone();
                if swept {
                    pair.settings.friction = mu;
                }
                pair
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::config::Study;

    /// `pairs_at` puts mu on the swept pairs of its copy alone: the kept pairs keep their own
    /// friction, and the model keeps the friction its study gave.
    #[test]
    fn pairs_at_sets_mu_on_the_swept_pairs_of_a_copy() {
        let model = Model::from_spec(&Study::builtin("tiny-caliper").model_spec()).unwrap();
        let before: Vec<f64> = model.pairs.iter().map(|p| p.settings.friction).collect();
        assert!(model.swept.iter().any(|&s| s) && model.swept.iter().any(|&s| !s));
        let pairs = model.pairs_at(0.73);
        for (((pair, original), &swept), &own) in pairs
            .iter()
            .zip(&model.pairs)
            .zip(&model.swept)
            .zip(&before)
        {
            let expect = if swept { 0.73 } else { own };
            assert_eq!(pair.settings.friction, expect, "{}", pair.settings.name);
            assert_eq!(pair.points, original.points);
        }
        let after: Vec<f64> = model.pairs.iter().map(|p| p.settings.friction).collect();
        assert_eq!(before, after);
    }
}
