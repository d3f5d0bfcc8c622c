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

/// A spring between a node and a weighted combination of nodes, isotropic: energy
/// (k/2) |sum_j a_j u_j|^2, the same in each component. With terms (c, 1) and (i, -wbar_i)
/// it ties a node to the weighted mean of others (a distributing coupling made elastic:
/// the reduced contact node's spring to its coupling nodes, METHOD §5). The coefficients of
/// a tie sum to zero, so a rigid translation stores no energy.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CouplingSpring {
    /// (node, a_j).
    pub terms: Vec<(usize, f64)>,
    /// N/m.
    pub stiffness: f64,
}

impl CouplingSpring {
    /// The nodes it couples (for the sparsity pattern).
    pub fn nodes(&self) -> Vec<usize> {
        self.terms.iter().map(|t| t.0).collect()
    }
}

/// Adds k a_i a_j I to the (i, j) blocks of every coupling spring whose first node this rank
/// owns, so each spring counts once (K already assembled: assembles again; the pattern must
/// hold the couplings). Collective.
pub fn add_coupling_springs(
    k: &mut Matrix,
    dofs: &DofMap,
    springs: &[CouplingSpring],
) -> Result<(), PetscError> {
    let owned = dofs.owned_nodes();
    for s in springs {
        let Some(&(first, _)) = s.terms.first() else {
            continue;
        };
        if !owned.contains(&first) {
            continue;
        }
        let idx: Vec<PetscInt> = s
            .terms
            .iter()
            .flat_map(|&(n, _)| dofs.node_equations(n).map(|e| e as PetscInt))
            .collect();
        let n = idx.len();
        let mut block = vec![0.0; n * n];
        for (a, &(_, ca)) in s.terms.iter().enumerate() {
            for (b, &(_, cb)) in s.terms.iter().enumerate() {
                for c in 0..3 {
                    block[(3 * a + c) * n + 3 * b + c] = s.stiffness * ca * cb;
                }
            }
        }
        k.add_block(&idx, &idx, &block)?;
    }
    k.assemble()
}
