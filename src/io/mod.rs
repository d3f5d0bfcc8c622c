//! The file formats: one folder or file per format, each reading into (or writing from) the
//! plain data of the stages before it. Node orders of other programs are converted here, on
//! read and on write, so nothing past this stage knows about them.
//!
//! - [`matrix`]: assembled K, M, C from Matrix Market, CalculiX (`.sti`/`.mas`/`.dof`) and
//!   Abaqus (`*MATRIX OUTPUT`) files, and a Matrix Market writer.
//! - [`vtu`]: VTK XML UnstructuredGrid writer for ParaView (mesh, point and cell fields).

pub mod matrix;
pub mod vtu;
