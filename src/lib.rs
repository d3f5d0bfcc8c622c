//! squeal: brake-squeal prediction on industrial-size finite-element models, and how far a
//! reduced model can stand in for the full one (Fazio, Nacivet, Sinou 2015).
//!
//! Stages, each using only the ones before it: [`mesh`] -> [`io`] (file formats) -> [`fem`]
//! -> [`contact`] -> [`model`] -> [`analysis`] -> [`reduce`] -> [`study`]. [`petsc`] is the
//! only module with `unsafe`: denied here, allowed there alone.
#![deny(unsafe_code)]

pub mod analysis;
pub mod atomic_file;
pub mod contact;
pub mod fem;
pub mod input_file;
pub mod io;
pub mod mesh;
pub mod model;
pub mod petsc;
pub mod reduce;
pub mod results;
pub mod study;
pub mod vector3;
