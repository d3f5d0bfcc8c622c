//! The closed-form and semi-analytic reference solutions (`reference/`) checked on their own,
//! against published values, limits and independent computations, before any test leans on
//! them.

#[path = "../reference/checks.rs"]
mod checks;
