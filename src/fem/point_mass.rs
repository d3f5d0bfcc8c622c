//! Point masses: a mass m at a node adds m to the node's three translational diagonal
//! entries of M (solid nodes have no rotations, so a point mass has no rotary inertia).

use super::dofs::DofMap;
use crate::petsc::{Matrix, PetscError, PetscInt};

/// A mass concentrated at a node.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PointMass {
    pub node: usize,
    /// kg.
    pub mass: f64,
}

/// Adds the point masses of the nodes this rank owns to M (already assembled: assembles
/// again; the pattern must hold each node's diagonal block). Supported components (equation
/// -1) are skipped by PETSc. Collective.
pub fn add_point_masses(
    m: &mut Matrix,
    dofs: &DofMap,
    masses: &[PointMass],
) -> Result<(), PetscError> {
    let owned = dofs.owned_nodes();
    for p in masses.iter().filter(|p| owned.contains(&p.node)) {
        let idx = dofs.node_equations(p.node).map(|e| e as PetscInt);
        let mut block = [0.0; 9];
        for c in 0..3 {
            block[4 * c] = p.mass;
        }
        m.add_block(&idx, &idx, &block)?;
    }
    m.assemble()
}
