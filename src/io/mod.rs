//! The file formats: one folder or file per format, each reading into (or writing from) the
//! plain data of the stages before it. Node orders of other programs are converted here, on
//! read and on write, so nothing past this stage knows about them.
//!
//! - [`abaqus`]: Abaqus / CalculiX input decks (`.inp`): mesh, materials, supports, loads,
//!   steps.
//! - [`gmsh`]: Gmsh MSH reader (4.1 ASCII and binary, 2.2 ASCII) and MSH 4.1 writer.
//! - [`matrix`]: assembled K, M, C from Matrix Market, CalculiX (`.sti`/`.mas`/`.dof`) and
//!   Abaqus (`*MATRIX OUTPUT`) files, and a Matrix Market writer.
//! - [`vtu`]: VTK XML UnstructuredGrid writer for ParaView (mesh, point and cell fields).

pub mod abaqus;
pub mod gmsh;
pub mod matrix;
pub mod vtu;
