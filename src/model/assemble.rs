//! A model's PETSc operators: the DOF map (mesh and extra nodes), K with every spring, link and
//! coupling on a pattern that also holds every contact point's coupling, M with the point
//! masses, and the load vector. Made at the last moment, from the plain data of [`Model`].

use super::Model;
use crate::fem::constraints::ConstraintError;
use crate::fem::element::MassRule;
use crate::fem::point_mass::add_point_masses;
use crate::fem::springs::{
    add_coupling_springs, add_ground_springs, add_scalar_springs, add_two_node_springs,
};
use crate::fem::transform::{Transform, TransformError};
use crate::fem::{assemble as fem_assemble, AssemblyError, DofError, DofMap, StructureOptions};
use crate::petsc::{Comm, Matrix, PetscError, Vector};

/// The operators of a model, in the full numbering (supports eliminated): K, M and the
/// load as assembled, with the constraints' transformation to the free unknowns when the
/// model has constraints.
pub struct Operators<'rt> {
    pub dofs: DofMap,
    pub stiffness: Matrix<'rt>,
    pub mass: Matrix<'rt>,
    pub load: Vector<'rt>,
    /// u = C u_free + lambda g (`None`: no constraints, the full numbering is the free one).
    pub constraints: Option<Transform<'rt>>,
}

impl<'rt> Operators<'rt> {
    /// The numbering the solvers see: the free one with constraints, else the full one.
    pub fn solver_dofs(&self) -> &DofMap {
        self.constraints.as_ref().map_or(&self.dofs, |t| &t.free)
    }
}

#[derive(Debug, thiserror::Error)]
pub enum AssembleError {
    #[error(transparent)]
    Dofs(#[from] DofError),
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error(transparent)]
    Petsc(#[from] PetscError),
    #[error(transparent)]
    Constraints(#[from] ConstraintError),
    #[error(transparent)]
    Transform(#[from] TransformError),
    /// This rank's part went well, another's did not: that rank's message.
    #[error("the assembly failed on rank {rank}: {message}")]
    OnAnotherRank { rank: usize, message: String },
}

/// Makes a rank-local result collective: every rank fails when one does.
fn collective<T, E: Into<AssembleError>>(
    comm: Comm,
    local: Result<T, E>,
) -> Result<T, AssembleError> {
    let local = local.map_err(Into::into);
    let first = comm.first_message(local.as_ref().err().map(|e| e.to_string()));
    match (local, first) {
        (Ok(v), None) => Ok(v),
        (Ok(_), Some((rank, message))) => Err(AssembleError::OnAnotherRank { rank, message }),
        (Err(e), _) => Err(e),
    }
}

/// The DOF map of a model (mesh and extra nodes), the same on every rank. Collective.
pub fn dof_map(comm: Comm, model: &Model) -> Result<DofMap, AssembleError> {
    let local = DofMap::new(
        model.mesh.nodes.len(),
        model.extra_nodes.len(),
        &model.supports,
        comm.size(),
        comm.rank(),
    );
    collective(comm, local)
}

/// Assembles a model's operators. Collective; errors are collective.
pub fn assemble<'rt>(
    comm: Comm<'rt>,
    model: &Model,
    mass_rule: MassRule,
) -> Result<Operators<'rt>, AssembleError> {
    let mesh = &model.mesh;
    let dofs = dof_map(comm, model)?;
    let contact = crate::contact::contact_groups(&model.pairs);
    let couplings: Vec<Vec<usize>> = model
        .couplings
        .iter()
        .map(|c| c.nodes())
        .chain(model.scalar_springs.iter().map(|s| s.nodes()))
        .collect();
    let links: Vec<[usize; 2]> = model.links.iter().map(|l| l.nodes).collect();
    // A node of a grounded spring or a point mass may be in no element (a deck's mass on a
    // node of its own): its diagonal block must still be in the pattern.
    let singles: Vec<[usize; 1]> = model
        .springs
        .iter()
        .map(|s| [s.node])
        .chain(model.point_masses.iter().map(|p| [p.node]))
        .collect();
    let pattern = fem_assemble::pattern(
        &dofs,
        mesh.elements
            .iter()
            .map(|c| &c[..])
            .chain(contact.iter().map(|g| &g[..]))
            .chain(couplings.iter().map(|g| &g[..]))
            .chain(links.iter().map(|g| &g[..]))
            .chain(singles.iter().map(|g| &g[..])),
    );
    let (mut stiffness, mut mass) = collective(
        comm,
        fem_assemble::stiffness_and_mass(
            comm,
            mesh,
            &dofs,
            &pattern,
            StructureOptions { mass_rule },
        ),
    )?;
    add_ground_springs(&mut stiffness, &dofs, &model.springs)?;
    if !model.point_masses.is_empty() {
        add_point_masses(&mut mass, &dofs, &model.point_masses)?;
    }
    if !model.couplings.is_empty() {
        add_coupling_springs(&mut stiffness, &dofs, &model.couplings)?;
    }
    if !model.scalar_springs.is_empty() {
        add_scalar_springs(&mut stiffness, &dofs, &model.scalar_springs)?;
    }
    if !model.links.is_empty() {
        add_two_node_springs(&mut stiffness, &dofs, &model.links)?;
    }
    let load = collective(
        comm,
        fem_assemble::load_vector(comm, mesh, &dofs, &model.pressure_faces(), &model.forces),
    )?;
    let constraints = if model.constraints.is_empty() {
        None
    } else {
        let resolved = collective(comm, model.resolved_constraints())?;
        Some(Transform::new(comm, &dofs, &model.supports, &resolved)?)
    };
    Ok(Operators {
        dofs,
        stiffness,
        mass,
        load,
        constraints,
    })
}
