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
    #[error("{file}: unknown mesh format (expected .msh or .inp)")]
    UnknownFormat { file: PathBuf },
    #[error("--fix {spec}: {why}")]
    BadFix { spec: String, why: String },
    #[error("--material {spec}: {why}")]
    BadMaterial { spec: String, why: String },
    #[error("{file}: {why}")]
    Unsupported { file: PathBuf, why: String },
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
