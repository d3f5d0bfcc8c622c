//! The file formats: one folder or file per format, each reading into (or writing from) the
//! plain data of the stages before it. Node orders of other programs are converted here, on
//! read and on write, so nothing past this stage knows about them.
//!
//! - [`vtu`]: VTK XML UnstructuredGrid writer for ParaView (mesh, point and cell fields).

pub mod vtu;
