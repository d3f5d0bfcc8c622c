//! The constrained model's unknowns: u = C u_free + lambda g (METHOD: multi-point
//! constraints applied exactly). Everything is assembled as before, in the full numbering
//! (supports eliminated, every other DOF an equation: [`DofMap`]); the solvers see the free
//! numbering (dependent DOFs left out too), through K_free = C^T K C (PETSc's MatPtAP), the
//! residual C^T F(C x + lambda g) and the expansion u = C x + lambda g. A model without
//! constraints never makes one, so nothing changes for it.

use super::constraints::Resolved;
use super::dofs::{DofError, DofMap};
use super::Support;
use crate::petsc::{Comm, Matrix, PetscError, PetscInt, RowPattern, Vector};

/// Why the transformation could not be made.
#[derive(Debug, thiserror::Error)]
pub enum TransformError {
    #[error(transparent)]
    Dofs(#[from] DofError),
    #[error(transparent)]
    Petsc(#[from] PetscError),
}

/// C (full x free) and g (full), with the free numbering.
pub struct Transform<'rt> {
    /// The solvers' numbering: supported and dependent DOFs left out.
    pub free: DofMap,
    /// C: a row per full equation, identity on independent DOFs, the constraint's
    /// coefficients on dependent ones.
    pub matrix: Matrix<'rt>,
    /// g: the dependent DOFs' offsets at load factor 1, laid out like C's rows.
    pub offset: Vector<'rt>,
    /// Whether g is nonzero anywhere.
    pub prescribes: bool,
    /// How many DOFs the constraints eliminate.
    pub dependents: usize,
}

impl<'rt> Transform<'rt> {
    /// Builds C and g for the dependents of `resolved` on top of the full numbering `full`
    /// (made from `supports`). Collective; every rank passes the same data.
    pub fn new(
        comm: Comm<'rt>,
        full: &DofMap,
        supports: &[Support],
        resolved: &Resolved,
    ) -> Result<Transform<'rt>, TransformError> {
        // The free numbering: supports, plus every dependent DOF held.
        let mut held = supports.to_vec();
        let mut by_node: std::collections::BTreeMap<usize, [bool; 3]> = Default::default();
        for &(n, c) in resolved.dependents.keys() {
            by_node.entry(n).or_default()[c] = true;
        }
        let mut patterns: Vec<Support> = Vec::new();
        for (n, components) in by_node {
            match patterns.iter_mut().find(|s| s.components == components) {
                Some(s) => s.nodes.push(n),
                None => patterns.push(Support {
                    name: "(dependent DOFs of the constraints)".into(),
                    nodes: vec![n],
                    components,
                }),
            }
        }
        held.extend(patterns);
        let free = DofMap::new(
            full.mesh_nodes(),
            full.nodes() - full.mesh_nodes(),
            &held,
            comm.size(),
            comm.rank(),
        )?;
        let free_equation = |n: usize, c: usize| -> PetscInt {
            free.equation(n, c)
                .expect("a constraint's independent DOF is a free equation") as PetscInt
        };
        // This rank's rows of C, node by node in the full numbering (its owned equations
        // are its owned nodes' non-supported DOFs, in order).
        let owned = full.owned_equations();
        let mut pattern = RowPattern {
            local_cols: free.owned_equations().len(),
            row_start: vec![0],
            columns: Vec::new(),
        };
        let mut values = Vec::new();
        let mut offsets = vec![0.0; owned.len()];
        for n in full.owned_nodes() {
            for c in 0..3 {
                let Some(row) = full.equation(n, c) else {
                    continue;
                };
                let mut entries: Vec<(PetscInt, f64)> = match resolved.dependents.get(&(n, c)) {
                    Some(d) => {
                        offsets[row - owned.start] = d.offset;
                        d.terms
                            .iter()
                            .map(|&((k, ck), a)| (free_equation(k, ck), a))
                            .collect()
                    }
                    None => vec![(free_equation(n, c), 1.0)],
                };
                entries.sort_by_key(|e| e.0);
                for (col, v) in entries {
                    pattern.columns.push(col);
                    values.push(v);
                }
                pattern.row_start.push(pattern.columns.len() as PetscInt);
            }
        }
        let mut matrix = Matrix::with_pattern(comm, &pattern)?;
        for (i, row) in owned.clone().enumerate() {
            let span = pattern.row_start[i] as usize..pattern.row_start[i + 1] as usize;
            if span.is_empty() {
                continue;
            }
            matrix.set_block(
                &[row as PetscInt],
                &pattern.columns[span.clone()],
                &values[span],
            )?;
        }
        matrix.assemble()?;
        let mut offset = Vector::new(comm, owned.len())?;
        offset.set_local(&offsets)?;
        Ok(Transform {
            free,
            matrix,
            offset,
            prescribes: resolved.has_offsets(),
            dependents: resolved.dependents.len(),
        })
    }

    /// C^T A C, a new matrix (collective; MatPtAP). Its pattern holds every coupling of
    /// A's pattern (explicit zeros included), so [`Transform::project_into`] can reuse it
    /// for any matrix of A's pattern.
    pub fn project(&self, a: &Matrix<'rt>) -> Result<Matrix<'rt>, PetscError> {
        a.ptap(&self.matrix)
    }

    /// C^T A C into `out`, a matrix [`Transform::project`] made from a matrix of A's
    /// pattern (collective).
    pub fn project_into(&self, a: &Matrix<'rt>, out: &mut Matrix<'rt>) -> Result<(), PetscError> {
        a.ptap_into(&self.matrix, out)
    }

    /// A vector of the free layout (collective).
    pub fn free_vector(&self) -> Result<Vector<'rt>, PetscError> {
        let (x, _) = self.matrix.vectors()?;
        Ok(x)
    }

    /// A vector of the full layout (collective).
    pub fn full_vector(&self) -> Result<Vector<'rt>, PetscError> {
        let (_, y) = self.matrix.vectors()?;
        Ok(y)
    }

    /// `full = C x + load_factor g` (collective).
    pub fn expand_into(
        &self,
        x: &Vector<'rt>,
        load_factor: f64,
        full: &mut Vector<'rt>,
    ) -> Result<(), PetscError> {
        self.matrix.mult(x, full)?;
        if self.prescribes && load_factor != 0.0 {
            full.axpy(load_factor, &self.offset)?;
        }
        Ok(())
    }

    /// `C x + load_factor g`, a new full vector (collective).
    pub fn expand(&self, x: &Vector<'rt>, load_factor: f64) -> Result<Vector<'rt>, PetscError> {
        let mut full = self.full_vector()?;
        self.expand_into(x, load_factor, &mut full)?;
        Ok(full)
    }

    /// `out = C^T f`: a full-layout force or residual onto the free unknowns (collective).
    pub fn restrict_into(&self, f: &Vector<'rt>, out: &mut Vector<'rt>) -> Result<(), PetscError> {
        self.matrix.mult_transpose(f, out)
    }
}
