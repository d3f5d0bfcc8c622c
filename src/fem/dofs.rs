//! Node -> equation numbering. Three displacement DOFs per node; supported DOFs are left
//! out of the system (eliminated, so they cannot pollute an eigenvalue band), and the rest
//! are numbered node by node so a node's DOFs sit together on one rank. The map covers the
//! mesh nodes and any extra nodes that belong to no element (the reduction layer's reduced
//! contact nodes), appended after them.

use std::ops::Range;

/// Which displacement components of a set of nodes are held at zero.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Support {
    /// A name for messages (the node set's).
    pub name: String,
    pub nodes: Vec<usize>,
    /// x, y, z held.
    pub components: [bool; 3],
}

/// Why a DOF map could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DofError {
    #[error("support {support}: node index {node} is not in the model")]
    NodeOutside { support: String, node: usize },
    /// The supports leave no equation: there is nothing to solve (`--fix NALL` used to end
    /// in MUMPS's "INFOG(1)=-16" on a 0 x 0 matrix).
    #[error(
        "the supports ({supports}) hold every degree of freedom of the {nodes} nodes: no \
         equation is left to solve"
    )]
    EverythingHeld { supports: String, nodes: usize },
}

/// The DOF numbering of a model, identical on every rank, with each rank's share.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DofMap {
    /// Equation number of each (node, component), or -1 where the DOF is supported.
    equations: Vec<[i64; 3]>,
    mesh_nodes: usize,
    /// Nodes owned by rank r: `node_start[r]..node_start[r + 1]`.
    node_start: Vec<usize>,
    /// Equations owned by rank r: `equation_start[r]..equation_start[r + 1]`.
    equation_start: Vec<usize>,
    rank: usize,
}

impl DofMap {
    /// Numbers `mesh_nodes + extra_nodes` nodes, leaving out supported components, and splits
    /// them over `ranks` in contiguous node blocks of about equal equation counts.
    pub fn new(
        mesh_nodes: usize,
        extra_nodes: usize,
        supports: &[Support],
        ranks: usize,
        rank: usize,
    ) -> Result<DofMap, DofError> {
        let nodes = mesh_nodes + extra_nodes;
        let mut held = vec![[false; 3]; nodes];
        for s in supports {
            for &n in &s.nodes {
                let h = held.get_mut(n).ok_or_else(|| DofError::NodeOutside {
                    support: s.name.clone(),
                    node: n,
                })?;
                for (held, &component) in h.iter_mut().zip(&s.components) {
                    *held |= component;
                }
            }
        }
        let mut equations = vec![[-1i64; 3]; nodes];
        let mut next = 0i64;
        for (eq, h) in equations.iter_mut().zip(&held) {
            for c in 0..3 {
                if !h[c] {
                    eq[c] = next;
                    next += 1;
                }
            }
        }
        let total = next as usize;
        if total == 0 && nodes > 0 {
            return Err(DofError::EverythingHeld {
                supports: supports
                    .iter()
                    .map(|s| s.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                nodes,
            });
        }
        // Cut after the node where the running equation count passes r * total / ranks.
        let mut node_start = vec![0usize; ranks + 1];
        let mut equation_start = vec![0usize; ranks + 1];
        let mut count = 0usize;
        let mut r = 1;
        for (n, h) in held.iter().enumerate() {
            while r < ranks && count >= r * total / ranks {
                node_start[r] = n;
                equation_start[r] = count;
                r += 1;
            }
            count += h.iter().filter(|&&x| !x).count();
        }
        while r <= ranks {
            node_start[r] = nodes;
            equation_start[r] = total;
            r += 1;
        }
        Ok(DofMap {
            equations,
            mesh_nodes,
            node_start,
            equation_start,
            rank,
        })
    }

    /// All nodes, mesh and extra.
    pub fn nodes(&self) -> usize {
        self.equations.len()
    }

    /// Nodes of the mesh (the extra nodes follow them).
    pub fn mesh_nodes(&self) -> usize {
        self.mesh_nodes
    }

    /// Number of equations (free DOFs) in the whole model.
    pub fn equations(&self) -> usize {
        *self.equation_start.last().unwrap_or(&0)
    }

    /// The equation of (node, component), `None` if supported.
    pub fn equation(&self, node: usize, component: usize) -> Option<usize> {
        let e = self.equations[node][component];
        (e >= 0).then_some(e as usize)
    }

    /// Equation numbers of a node as PETSc indices (-1 where supported: PETSc skips those).
    pub fn node_equations(&self, node: usize) -> [i64; 3] {
        self.equations[node]
    }

    /// The nodes this rank owns (their rows are assembled here).
    pub fn owned_nodes(&self) -> Range<usize> {
        self.node_start[self.rank]..self.node_start[self.rank + 1]
    }

    /// The equations this rank owns.
    pub fn owned_equations(&self) -> Range<usize> {
        self.equation_start[self.rank]..self.equation_start[self.rank + 1]
    }

    /// The rank that owns a node.
    pub fn owner(&self, node: usize) -> usize {
        self.node_start.partition_point(|&s| s <= node) - 1
    }

    /// This rank's number.
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// Scatters a global solution vector (indexed by equation) into node displacements,
    /// zero on supported DOFs.
    pub fn displacements(&self, solution: &[f64]) -> Vec<[f64; 3]> {
        self.equations
            .iter()
            .map(|eq| eq.map(|e| if e >= 0 { solution[e as usize] } else { 0.0 }))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn supported_components_are_left_out_and_numbering_is_node_major() {
        let s = Support {
            name: "fix".into(),
            nodes: vec![1],
            components: [true, false, true],
        };
        let m = DofMap::new(3, 1, &[s], 1, 0).unwrap();
        assert_eq!(m.equations(), 3 * 4 - 2);
        assert_eq!(m.node_equations(0), [0, 1, 2]);
        assert_eq!(m.node_equations(1), [-1, 3, -1]);
        assert_eq!(m.node_equations(3), [7, 8, 9]);
        assert_eq!(m.nodes(), 4);
        assert_eq!(m.mesh_nodes(), 3);
        let u = m.displacements(&(0..10).map(|i| i as f64).collect::<Vec<_>>());
        assert_eq!(u[1], [0.0, 3.0, 0.0]);
    }

    #[test]
    fn supports_that_hold_everything_are_refused_by_name() {
        let all = Support {
            name: "NALL".into(),
            nodes: vec![0, 1],
            components: [true; 3],
        };
        let e = DofMap::new(2, 0, &[all], 1, 0).unwrap_err().to_string();
        assert!(
            e.contains("NALL") && e.contains("every degree of freedom"),
            "{e}"
        );
        // No node at all is no support's doing.
        assert_eq!(DofMap::new(0, 0, &[], 1, 0).unwrap().equations(), 0);
    }

    #[test]
    fn ranks_get_contiguous_node_blocks_covering_everything_once() {
        for ranks in 1..=5 {
            let maps: Vec<DofMap> = (0..ranks)
                .map(|r| DofMap::new(101, 0, &[], ranks, r).unwrap())
                .collect();
            let mut next_node = 0;
            let mut next_eq = 0;
            for (r, m) in maps.iter().enumerate() {
                let nodes = m.owned_nodes();
                let eqs = m.owned_equations();
                assert_eq!(nodes.start, next_node);
                assert_eq!(eqs.start, next_eq);
                // Equations owned = the owned nodes' free DOFs.
                assert_eq!(eqs.len(), 3 * nodes.len());
                // Balanced to within one node.
                assert!(
                    eqs.len().abs_diff(303 / ranks) <= 3,
                    "{ranks} ranks: {eqs:?}"
                );
                for n in nodes.clone() {
                    assert_eq!(m.owner(n), r);
                }
                next_node = nodes.end;
                next_eq = eqs.end;
            }
            assert_eq!((next_node, next_eq), (101, 303));
        }
    }

    #[test]
    fn a_support_on_a_missing_node_is_an_error_naming_the_support() {
        let s = Support {
            name: "hub".into(),
            nodes: vec![7],
            components: [true; 3],
        };
        let err = DofMap::new(3, 0, &[s], 1, 0).unwrap_err();
        let text = err.to_string();
        assert!(text.contains("hub") && text.contains('7'), "{text}");
    }
}
