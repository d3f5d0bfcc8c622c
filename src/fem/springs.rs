//! Grounded springs: a stiffness k along a direction d at a node adds k d d^T to its 3x3
//! diagonal block. They hold parts the way real calipers do (pad guides and abutments on a
//! bracket not modelled as a body).

use super::dofs::DofMap;
use crate::petsc::{Matrix, PetscError, PetscInt};

/// One spring to ground at a node.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GroundSpring {
    pub node: usize,
    /// Unit direction.
    pub direction: [f64; 3],
    /// N/m (force per displacement along `direction`).
    pub stiffness: f64,
}

/// Adds the springs of the nodes this rank owns to K (already assembled: assembles again).
/// Collective.
pub fn add_ground_springs(
    k: &mut Matrix,
    dofs: &DofMap,
    springs: &[GroundSpring],
) -> Result<(), PetscError> {
    let owned = dofs.owned_nodes();
    for s in springs.iter().filter(|s| owned.contains(&s.node)) {
        let idx = dofs.node_equations(s.node).map(|e| e as PetscInt);
        let d = s.direction;
        let block: Vec<f64> = (0..9).map(|k| s.stiffness * d[k / 3] * d[k % 3]).collect();
        k.add_block(&idx, &idx, &block)?;
    }
    k.assemble()
}
