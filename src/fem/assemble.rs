//! Distributed assembly of the structure. The nonzero pattern of the rows a rank owns is
//! built first, from the node groups that couple DOFs (the elements, and later contact
//! pairs), so PETSc is preallocated exactly; element matrices then go in as 30x30 blocks.
//! Every rank holds the whole mesh; each computes the elements whose first node it owns.

use super::dofs::DofMap;
use super::element::{self, ElementError, MassRule};
use crate::mesh::{Face, Material, Mesh};
use crate::petsc::{Comm, Matrix, PetscError, PetscInt, RowPattern, Vector};

#[derive(Debug, thiserror::Error)]
pub enum AssemblyError {
    #[error("part '{part}' has no material (assign one: section, study file or --material)")]
    MissingMaterial { part: String },
    #[error("part '{part}' names material '{material}', which is not defined")]
    UnknownMaterial { part: String, material: String },
    #[error("element {label} belongs to no part, so it has no material")]
    ElementWithoutPart { label: i64 },
    #[error("element {label} (part '{part}'): {reason}")]
    Element {
        label: i64,
        part: String,
        reason: ElementError,
    },
    #[error("on rank {rank}: {message}")]
    OnAnotherRank { rank: usize, message: String },
    /// A field given on fewer nodes than the elements or point masses use.
    #[error("a field on {given} nodes for a model that uses node {node}")]
    FieldTooShort { given: usize, node: usize },
    #[error(transparent)]
    Petsc(#[from] PetscError),
}

/// The material of every element, checked: each element in a part, each part with a
/// defined material.
pub fn element_materials(mesh: &Mesh) -> Result<Vec<&Material>, AssemblyError> {
    let mut part_material = Vec::with_capacity(mesh.parts.len());
    for part in &mesh.parts {
        let name = part
            .material
            .as_ref()
            .ok_or_else(|| AssemblyError::MissingMaterial {
                part: part.name.clone(),
            })?;
        let m = mesh
            .materials
            .get(name)
            .ok_or_else(|| AssemblyError::UnknownMaterial {
                part: part.name.clone(),
                material: name.clone(),
            })?;
        part_material.push(m);
    }
    mesh.element_parts()
        .iter()
        .enumerate()
        .map(|(e, p)| {
            p.map(|p| part_material[p])
                .ok_or(AssemblyError::ElementWithoutPart {
                    label: mesh.element_labels.get(e).copied().unwrap_or(e as i64 + 1),
                })
        })
        .collect()
}

fn to_petsc(i: i64) -> PetscInt {
    i as PetscInt
}

/// The exact pattern of this rank's rows: DOFs of nodes that share a group are coupled.
/// `groups` are the element connectivities plus any other coupling (contact: a slave node
/// and its master face's nodes). Every rank must pass the same groups.
pub fn pattern<'g>(dofs: &DofMap, groups: impl Iterator<Item = &'g [usize]>) -> RowPattern {
    let owned = dofs.owned_nodes();
    let mut adjacency: Vec<Vec<usize>> = vec![Vec::new(); owned.len()];
    for group in groups {
        for &a in group {
            if owned.contains(&a) {
                adjacency[a - owned.start].extend_from_slice(group);
            }
        }
    }
    let mut pattern = RowPattern {
        local_cols: dofs.owned_equations().len(),
        row_start: vec![0],
        columns: Vec::new(),
    };
    for (k, adj) in adjacency.iter_mut().enumerate() {
        adj.sort_unstable();
        adj.dedup();
        let node = owned.start + k;
        // Equations are numbered node-major, so columns come out sorted.
        let columns: Vec<PetscInt> = adj
            .iter()
            .flat_map(|&m| dofs.node_equations(m))
            .filter(|&e| e >= 0)
            .map(to_petsc)
            .collect();
        for e in dofs.node_equations(node) {
            if e >= 0 {
                pattern.columns.extend_from_slice(&columns);
                pattern.row_start.push(pattern.columns.len() as PetscInt);
            }
        }
    }
    pattern
}

/// Which elements this rank computes: those whose first node it owns.
pub fn local_elements<'m>(mesh: &'m Mesh, dofs: &DofMap) -> impl Iterator<Item = usize> + 'm {
    let owned = dofs.owned_nodes();
    (0..mesh.elements.len()).filter(move |&e| owned.contains(&mesh.elements[e][0]))
}

/// The 30 PETSc equation numbers of an element (-1 where supported).
pub fn element_equations(dofs: &DofMap, conn: &[usize; 10]) -> [PetscInt; 30] {
    let mut idx = [0 as PetscInt; 30];
    for (a, &n) in conn.iter().enumerate() {
        let eq = dofs.node_equations(n);
        for c in 0..3 {
            idx[3 * a + c] = to_petsc(eq[c]);
        }
    }
    idx
}

/// What to assemble and how.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StructureOptions {
    pub mass_rule: MassRule,
}

/// The stiffness K and consistent mass M of the whole structure, on the given pattern
/// (which may hold more than the elements need, e.g. contact couplings). Collective; an
/// element error on any rank is an error on every rank.
pub fn stiffness_and_mass<'rt>(
    comm: Comm<'rt>,
    mesh: &Mesh,
    dofs: &DofMap,
    pattern: &RowPattern,
    options: StructureOptions,
) -> Result<(Matrix<'rt>, Matrix<'rt>), AssemblyError> {
    let materials = element_materials(mesh);
    let mut k = Matrix::with_pattern(comm, pattern)?;
    let mut m = Matrix::with_pattern(comm, pattern)?;
    let mut local_error = None;
    if let Ok(materials) = &materials {
        let parts = mesh.element_parts();
        let mut flat = vec![0.0; 900];
        for e in local_elements(mesh, dofs) {
            let conn = &mesh.elements[e];
            let x: [[f64; 3]; 10] = conn.map(|n| mesh.nodes[n]);
            let mat = materials[e];
            let matrices = element::stiffness(&x, mat.young, mat.poisson).and_then(|ke| {
                element::mass(&x, mat.density, options.mass_rule).map(|me| (ke, me))
            });
            let (ke, me) = match matrices {
                Ok(km) => km,
                Err(reason) => {
                    local_error = Some(AssemblyError::Element {
                        label: mesh.element_labels.get(e).copied().unwrap_or(e as i64 + 1),
                        part: parts[e]
                            .map(|p| mesh.parts[p].name.clone())
                            .unwrap_or_default(),
                        reason,
                    });
                    break;
                }
            };
            let idx = element_equations(dofs, conn);
            for (dst, row) in flat.chunks_exact_mut(30).zip(&ke) {
                dst.copy_from_slice(row);
            }
            k.add_block(&idx, &idx, &flat)?;
            for (dst, row) in flat.chunks_exact_mut(30).zip(&me) {
                dst.copy_from_slice(row);
            }
            m.add_block(&idx, &idx, &flat)?;
        }
    }
    let local = match (materials, local_error) {
        (Err(e), _) | (_, Some(e)) => Some(e),
        _ => None,
    };
    // Every rank learns the first failing rank's message, so whichever rank reports says
    // why, not only that something failed elsewhere.
    if let Some((rank, message)) = comm.first_message(local.as_ref().map(|e| e.to_string())) {
        return Err(local.unwrap_or(AssemblyError::OnAnotherRank { rank, message }));
    }
    k.assemble()?;
    m.assemble()?;
    k.mark_symmetric()?;
    m.mark_symmetric()?;
    Ok((k, m))
}

/// External loads: uniform pressures on faces (positive pushes into the body) and nodal
/// forces (node, component, value). Each rank adds the loads on the faces and nodes it owns
/// (by first node), so every load counts once. Collective.
pub fn load_vector<'rt>(
    comm: Comm<'rt>,
    mesh: &Mesh,
    dofs: &DofMap,
    pressures: &[(Face, f64)],
    forces: &[(usize, usize, f64)],
) -> Result<Vector<'rt>, AssemblyError> {
    let mut f = Vector::new(comm, dofs.owned_equations().len())?;
    let owned = dofs.owned_nodes();
    for (face, p) in pressures {
        if !owned.contains(&face.nodes[0]) {
            continue;
        }
        let x = face.nodes.map(|n| mesh.nodes[n]);
        let nodal = element::face_pressure_load(&x, *p);
        let mut idx = Vec::with_capacity(18);
        let mut val = Vec::with_capacity(18);
        for (&n, force) in face.nodes.iter().zip(&nodal) {
            for (c, &component) in force.iter().enumerate() {
                if let Some(e) = dofs.equation(n, c) {
                    idx.push(e as PetscInt);
                    val.push(component);
                }
            }
        }
        f.add_values(&idx, &val)?;
    }
    for &(n, c, v) in forces {
        if owned.contains(&n) {
            if let Some(e) = dofs.equation(n, c) {
                f.add_values(&[e as PetscInt], &[v])?;
            }
        }
    }
    f.assemble()?;
    Ok(f)
}
