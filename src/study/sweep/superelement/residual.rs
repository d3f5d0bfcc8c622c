//! The residual vectors of a just-built super-element ([`crate::reduce::residual_vectors`]):
//! the dense model's modes at the build's friction value, expanded, handed to the reduction
//! with the interior's factor the build kept.

use super::SuperElementModel;
use crate::petsc::Comm;
use crate::reduce;
use crate::study::StudyError;
use faer::Mat;
use std::time::Instant;

impl<'rt> SuperElementModel<'rt> {
    /// Adds to the current super-element (just built) the residual vectors
    /// of its own band's modes at `mu` ([`reduce::residual_vectors`]). Collective.
    pub(super) fn add_residual_vectors(
        &mut self,
        comm: Comm<'rt>,
        mu: f64,
        residual: reduce::residual_vectors::ResidualVectors<'rt>,
    ) -> Result<(), StudyError> {
        let started = Instant::now();
        let dense = self.dense(comm, mu, true)?;
        tracing::debug!(
            "residual vectors: the dense modes in {:.2} s",
            started.elapsed().as_secs_f64()
        );
        let current = self.current.as_mut().ok_or(StudyError::NoSuperElement)?;
        let n = current.se.header.size;
        let m = dense.shapes.len();
        let q = Mat::from_fn(n, 2 * m, |i, c| {
            let z = dense.shapes[c / 2][i];
            if c % 2 == 0 {
                z.re
            } else {
                z.im
            }
        });
        let x = current.basis.expand(q.as_ref());
        tracing::debug!(
            "residual vectors: expanded at {:.2} s",
            started.elapsed().as_secs_f64()
        );
        let added = residual
            .add_to(comm, &mut current.se, &mut current.basis, x.as_ref())
            .map_err(|source| StudyError::SuperElement { mu, source })?;
        tracing::info!(
            "super-element: {added} residual vectors of its {m} modes at mu {mu}, size {n} -> \
             {} ({:.1} s)",
            current.se.header.size,
            started.elapsed().as_secs_f64()
        );
        Ok(())
    }
}
