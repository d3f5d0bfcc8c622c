//! The residual vectors of a just-built super-element ([`crate::reduce::residual_vectors`]):
//! the dense model's modes at one friction value, expanded, handed to the reduction with the
//! interior's factor the build kept.
//!
//! Which friction value. A contact-free super-element (every pair on its boundary) is the
//! same at every mu, and so must its vectors be: they come from mu_SE's modes, the dense
//! static ramped from rest, whatever the strategy and wherever the sweep starts or resumes,
//! so that single, per-friction and adaptive keep one basis. Any other super-element is
//! made at its own equilibrium and takes its own point's modes.

use super::SuperElementModel;
use crate::petsc::Comm;
use crate::reduce;
use crate::study::StudyError;
use faer::Mat;
use std::time::Instant;

impl<'rt> SuperElementModel<'rt> {
    /// Adds to the current super-element (just built) the residual vectors of its band's
    /// modes (see the module doc for the friction value) ([`reduce::residual_vectors`]).
    /// Collective.
    pub(super) fn add_residual_vectors(
        &mut self,
        comm: Comm<'rt>,
        residual: reduce::residual_vectors::ResidualVectors<'rt>,
    ) -> Result<(), StudyError> {
        let started = Instant::now();
        let current = self.current.as_ref().ok_or(StudyError::NoSuperElement)?;
        let mu = if self.contact_free {
            self.settings.friction
        } else {
            current.made_at
        };
        // From rest with no history: not from the sweep's previous point.
        let previous = self.dense_previous.take();
        let dense = self.dense(comm, mu, true);
        self.dense_previous = previous;
        let dense = dense?;
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
