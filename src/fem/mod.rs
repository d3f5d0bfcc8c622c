//! The structure: TET10 shape functions and element matrices, the DOF map and the
//! distributed assembly into PETSc matrices.

pub mod assemble;
pub mod body_energy;
pub mod body_stiffness;
pub mod constraints;
pub mod distributing;
pub mod dofs;
pub mod element;
pub mod loads;
pub mod mass_sample;
pub mod point_mass;
pub mod springs;
pub mod stress;
pub mod tet10;
pub mod transform;

pub use assemble::{AssemblyError, StructureOptions};
pub use dofs::{DofError, DofMap, Support};
