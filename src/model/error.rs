//! Why a model could not be built: each error names the key, set, surface or file at fault.

use crate::mesh::{brake, MeshError};
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error("unknown preset '{0}': the built-in brake presets are {presets}", presets = brake::PRESETS.join(", "))]
    UnknownPreset(String),
    #[error("built-in brake: {0}")]
    Brake(#[from] brake::BrakeError),
    #[error("{key}: {source}")]
    BrakeParams {
        key: String,
        #[source]
        source: brake::BrakeError,
    },
    /// A mesh file with no (supported) element: nothing to assemble or to write.
    #[error(
        "{file}: the mesh has no elements ({nodes} nodes): squeal needs 10-node tetrahedra \
         (C3D10 in a deck, type 11 in Gmsh)"
    )]
    NoElements { file: PathBuf, nodes: usize },
    /// Nodes of a mesh file that no element uses: nothing holds them, so K is singular
    /// there (MUMPS used to stop on it with "INFOG(1)=-10"). `examples` are the first few,
    /// as (label, coordinates).
    #[error(
        "{file}: {count} node(s) belong to no element, so nothing holds them; first ones \
         (label: x, y, z): {}; remove them from the file or mesh them",
        crate::contact::format_examples(examples)
    )]
    NodesInNoElement {
        file: PathBuf,
        count: usize,
        examples: Vec<(i64, [f64; 3])>,
    },
    #[error("{file}: unknown mesh format (expected .msh or .inp)")]
    UnknownFormat { file: PathBuf },
    #[error("--fix {spec}: {why}")]
    BadFix { spec: String, why: String },
    #[error("--material {spec}: {why}")]
    BadMaterial { spec: String, why: String },
    #[error("{file}: {why}")]
    Unsupported { file: PathBuf, why: String },
    #[error(transparent)]
    Constraints(#[from] crate::fem::constraints::ConstraintError),
    /// A deck line that cannot be used as written.
    #[error("{at}: {why}")]
    AtLine {
        at: crate::io::abaqus::SourceLine,
        why: String,
    },
    /// A study key names something the mesh does not have.
    #[error("{key}: no {what} named '{name}' in {source_name}")]
    Missing {
        key: String,
        what: &'static str,
        name: String,
        source_name: String,
    },
    /// A study key's value cannot be used.
    #[error("{key}: {why}")]
    Invalid { key: String, why: String },
    #[error("{key} ('{name}'): {source}")]
    Contact {
        key: String,
        name: String,
        #[source]
        source: Box<crate::contact::ContactError>,
    },
}
