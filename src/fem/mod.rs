//! The structure: TET10 shape functions and element matrices, the DOF map and the
//! distributed assembly into PETSc matrices.

pub mod element;
pub mod tet10;
