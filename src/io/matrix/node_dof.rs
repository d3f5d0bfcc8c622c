//! Which degree of freedom of the exporting program's model each equation stands for: read
//! from CalculiX's `jobname.dof`, numbered from the (node, dof) pairs of Abaqus files.

use std::collections::HashMap;
use std::fmt;

/// One degree of freedom of the exporting program's model: a node label and a DOF number
/// (1-3 translations, 4-6 rotations in both CalculiX and Abaqus).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct NodeDof {
    pub node: i64,
    pub dof: u32,
}

impl fmt::Display for NodeDof {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{}", self.node, self.dof)
    }
}

/// Which [`NodeDof`] each equation (matrix row and column) stands for, both ways.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeDofMap {
    by_equation: Vec<NodeDof>,
    equation_of: HashMap<NodeDof, usize>,
}

impl NodeDofMap {
    /// The map of `by_equation` (equation k is `by_equation[k]`), or the first two equations
    /// that name the same DOF, and that DOF.
    pub(super) fn new(by_equation: Vec<NodeDof>) -> Result<Self, (usize, usize, NodeDof)> {
        let mut equation_of = HashMap::with_capacity(by_equation.len());
        for (k, nd) in by_equation.iter().enumerate() {
            if let Some(first) = equation_of.insert(*nd, k) {
                return Err((first, k, *nd));
            }
        }
        Ok(NodeDofMap {
            by_equation,
            equation_of,
        })
    }

    /// Number of equations.
    pub fn len(&self) -> usize {
        self.by_equation.len()
    }

    pub fn is_empty(&self) -> bool {
        self.by_equation.is_empty()
    }

    /// The DOF of a 0-based equation.
    pub fn node_dof(&self, equation: usize) -> Option<NodeDof> {
        self.by_equation.get(equation).copied()
    }

    /// The 0-based equation of a DOF (None: not an equation, e.g. constrained).
    pub fn equation(&self, node_dof: NodeDof) -> Option<usize> {
        self.equation_of.get(&node_dof).copied()
    }

    /// All DOFs in equation order.
    pub fn as_slice(&self) -> &[NodeDof] {
        &self.by_equation
    }
}
