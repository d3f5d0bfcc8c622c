//! Springs. Grounded: a stiffness k along a direction d at a node adds k d d^T to its 3x3
//! diagonal block; they hold parts the way real calipers do (pad guides and abutments on a
//! bracket not modelled as a body). Two-node: k d d^T between two nodes (the guide pins
//! between a meshed caliper and bracket, a piston's seal). Coupling: a node tied to a
//! weighted combination of nodes (the reduced interface).

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

/// The equations of a spring's nodes when this rank owns its first node (so that each
/// spring is added once), `None` otherwise.
fn owned_spring(
    dofs: &DofMap,
    owned: &std::ops::Range<usize>,
    mut nodes: impl Iterator<Item = usize> + Clone,
) -> Option<Vec<PetscInt>> {
    let first = nodes.clone().next()?;
    if !owned.contains(&first) {
        return None;
    }
    Some(
        nodes
            .by_ref()
            .flat_map(|n| dofs.node_equations(n).map(|e| e as PetscInt))
            .collect(),
    )
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
        let Some(idx) = owned_spring(dofs, &owned, s.terms.iter().map(|t| t.0)) else {
            continue;
        };
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

/// A spring on one linear combination of displacement components: energy
/// (k/2) (sum_j g_j . u_j)^2, each node j with its own coefficient vector g_j. It ties a
/// reduced contact's tilt node to the slopes of its patches ([`crate::contact::Tilt`]), where
/// each node enters along a different direction, which a [`CouplingSpring`] (the same
/// coefficient in every component) cannot say.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ScalarSpring {
    /// (node, g_j).
    pub terms: Vec<(usize, [f64; 3])>,
    /// N/m.
    pub stiffness: f64,
}

impl ScalarSpring {
    /// The nodes it couples (for the sparsity pattern).
    pub fn nodes(&self) -> Vec<usize> {
        self.terms.iter().map(|t| t.0).collect()
    }

    /// Its stiffness k g g^T over the terms' components (3 per term, term-major).
    pub fn matrix(&self) -> Vec<f64> {
        let g: Vec<f64> = self.terms.iter().flat_map(|t| t.1).collect();
        let n = g.len();
        let mut block = vec![0.0; n * n];
        for (a, ga) in g.iter().enumerate() {
            for (b, gb) in g.iter().enumerate() {
                block[a * n + b] = self.stiffness * (ga * gb);
            }
        }
        block
    }
}

/// Adds the scalar springs whose first node this rank owns (each counts once) to K (already
/// assembled: assembles again; the pattern must hold them). Collective.
pub fn add_scalar_springs(
    k: &mut Matrix,
    dofs: &DofMap,
    springs: &[ScalarSpring],
) -> Result<(), PetscError> {
    let owned = dofs.owned_nodes();
    for s in springs {
        if let Some(idx) = owned_spring(dofs, &owned, s.terms.iter().map(|t| t.0)) {
            k.add_block(&idx, &idx, &s.matrix())?;
        }
    }
    k.assemble()
}

/// A spring between two nodes along a direction (a guide pin, a piston seal): energy
/// (k/2) (d . (u_a - u_b))^2, force -k d d^T (u_a - u_b) on node a and its opposite on node b.
/// A rigid translation moves both nodes alike and stores nothing; the nodes need not
/// coincide (then a rigid rotation stretches it, as any offset spring).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TwoNodeSpring {
    pub nodes: [usize; 2],
    /// Unit direction.
    pub direction: [f64; 3],
    /// N/m (force per relative displacement along `direction`).
    pub stiffness: f64,
}

impl TwoNodeSpring {
    /// Its 6x6 stiffness over (u_a, u_b): [[k d d^T, -k d d^T], [-k d d^T, k d d^T]].
    pub fn matrix(&self) -> [[f64; 6]; 6] {
        let d = self.direction;
        let mut m = [[0.0; 6]; 6];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, entry) in row.iter_mut().enumerate() {
                let sign = if (i < 3) == (j < 3) { 1.0 } else { -1.0 };
                *entry = sign * self.stiffness * (d[i % 3] * d[j % 3]);
            }
        }
        m
    }
}

/// Adds the two-node springs whose first node this rank owns (each counts once) to K
/// (already assembled: assembles again; the pattern must hold the node pairs). Collective.
pub fn add_two_node_springs(
    k: &mut Matrix,
    dofs: &DofMap,
    springs: &[TwoNodeSpring],
) -> Result<(), PetscError> {
    let owned = dofs.owned_nodes();
    for s in springs.iter().filter(|s| owned.contains(&s.nodes[0])) {
        let idx: Vec<PetscInt> = s
            .nodes
            .iter()
            .flat_map(|&n| dofs.node_equations(n).map(|e| e as PetscInt))
            .collect();
        let block: Vec<f64> = s.matrix().iter().flatten().copied().collect();
        k.add_block(&idx, &idx, &block)?;
    }
    k.assemble()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn energy(s: &TwoNodeSpring, u: [f64; 6]) -> f64 {
        let m = s.matrix();
        0.5 * (0..6)
            .map(|i| (0..6).map(|j| u[i] * m[i][j] * u[j]).sum::<f64>())
            .sum::<f64>()
    }

    #[test]
    fn a_two_node_spring_stores_nothing_in_a_translation_and_k_along_its_direction() {
        let n = (1.0f64 + 4.0 + 9.0).sqrt();
        let s = TwoNodeSpring {
            nodes: [3, 8],
            direction: [1.0 / n, -2.0 / n, 3.0 / n],
            stiffness: 2.5e7,
        };
        for t in [[1.0, 0.0, 0.0], [0.3, -0.7, 0.2], [0.0, 0.0, -1.0]] {
            let u = [t[0], t[1], t[2], t[0], t[1], t[2]];
            assert!(energy(&s, u).abs() < 1e-9, "{t:?}");
        }
        // Node a moved by e along d: force k e on it, energy k e^2 / 2.
        let e = 1e-4;
        let d = s.direction;
        let u = [e * d[0], e * d[1], e * d[2], 0.0, 0.0, 0.0];
        let want = 0.5 * s.stiffness * e * e;
        assert!((energy(&s, u) - want).abs() < 1e-12 * want);
        let m = s.matrix();
        let force: Vec<f64> = (0..6)
            .map(|i| (0..6).map(|j| m[i][j] * u[j]).sum())
            .collect();
        for c in 0..3 {
            assert!((force[c] - s.stiffness * e * d[c]).abs() < 1e-9);
            assert!((force[3 + c] + force[c]).abs() < 1e-9);
        }
        // Across the direction: nothing.
        let across = [2.0 / n, 1.0 / n, 0.0];
        let u = [across[0], across[1], across[2], 0.0, 0.0, 0.0];
        assert!(energy(&s, u).abs() < 1e-9);
        // Symmetric.
        assert!((0..6).all(|i| (0..6).all(|j| m[i][j] == m[j][i])));
    }
}
