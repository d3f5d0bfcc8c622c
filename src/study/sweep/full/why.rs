//! What an unstable mode's shapes say of its cause, at the equilibrium its CEA was made
//! about: which body moves (kinetic energy), which contact pair feeds it (growth), and how it
//! moves with the swept friction (sensitivity, from its left eigenvector).

use super::FullModel;
use crate::analysis::cea;
use crate::analysis::growth;
use crate::analysis::sensitivity::{self, Sensitivity, StaticLayout};
use crate::analysis::statics;
use crate::contact;
use crate::fem::body_energy;
use crate::model::Operators;
use crate::petsc::Comm;
use num_complex::Complex64;

/// A mode's left eigenvector at every node of the model (rank 0) and y^H M x.
pub(super) struct LeftShape {
    pub re: Vec<[f64; 3]>,
    pub im: Vec<[f64; 3]>,
    pub mass_form: Complex64,
}

impl FullModel<'_> {
    /// Each body's share of the kinetic energy of the shape (`re`, `im` on the mesh nodes).
    pub(in crate::study::sweep) fn body_shares(
        &self,
        re: &[[f64; 3]],
        im: &[[f64; 3]],
    ) -> Option<std::collections::BTreeMap<String, f64>> {
        let model = &self.model;
        body_energy::mode_shares(&model.mesh, &model.point_masses, self.mass_rule, re, im)
    }

    /// What an unstable mode's shape says of its cause (`re`, `im` at every node of the
    /// model): its bodies' shares of kinetic energy and its pairs' parts of the growth rate
    /// ([`growth`]), at the equilibrium its CEA was made about; returns where on the pad
    /// faces it is fed ([`UnstableShape::feed`]). A part that cannot be had is left out and
    /// said in the log: it never fails the point.
    pub(super) fn contributions(
        &self,
        mode: &mut cea::ComplexMode,
        pairs: &[contact::ContactPair],
        equilibrium: &statics::StaticSolution,
        re: &[[f64; 3]],
        im: &[[f64; 3]],
    ) -> Option<Vec<f64>> {
        let model = &self.model;
        let nodes = model.mesh.nodes.len();
        let energies = match body_energy::body_kinetic_energies(
            &model.mesh,
            &model.point_masses,
            self.mass_rule,
            re,
            im,
        ) {
            Ok(e) => e,
            Err(e) => {
                tracing::warn!(
                    "no body shares of the mode at {:.1} Hz: {e}",
                    mode.frequency_hz
                );
                return None;
            }
        };
        mode.body_shares = Some(body_energy::shares(&energies));
        // Undamped: the pairs' parts add up to the real part. With Rayleigh damping the
        // damping's own part -x^H C x / 2m is not among them.
        let modal_mass: f64 = energies.values().sum();
        let omega = mode.lambda.im;
        if modal_mass <= 0.0 || omega <= 0.0 {
            return None;
        }
        match growth::point_growth_rates(
            pairs,
            &equilibrium.slip_after,
            &equilibrium.displacement,
            growth::Shape { re, im },
            omega,
            modal_mass,
        ) {
            Ok(points) => {
                let rates = growth::pair_growth_rates(pairs, &points);
                mode.pair_shares = Some(growth::shares(&rates));
                mode.pair_growth = Some(rates);
                // Spread like the contact pressure: a density on the pad face.
                let mut feed = vec![0.0; nodes];
                for swept in &self.spread {
                    for (node, density) in swept.pressure(&points[swept.pair]) {
                        if node < nodes {
                            feed[node] = density;
                        }
                    }
                }
                Some(feed)
            }
            Err(e) => {
                tracing::warn!(
                    "no pair shares of the mode at {:.1} Hz: {e}",
                    mode.frequency_hz
                );
                None
            }
        }
    }
}

impl FullModel<'_> {
    /// How many points of the kept (not swept) pairs slip with friction at `equilibrium`:
    /// where there are any, the eigenvalues along the sweep follow their slip directions,
    /// and no sensitivity is given ([`sensitivity::HELD_SLIP`]).
    pub(super) fn kept_slipping_points(
        &self,
        pairs: &[contact::ContactPair],
        equilibrium: &statics::StaticSolution,
    ) -> usize {
        pairs
            .iter()
            .zip(&equilibrium.contact)
            .zip(&self.model.swept)
            .filter(|((pair, _), &swept)| !swept && pair.settings.friction > 0.0)
            .map(|((_, states), _)| {
                states
                    .iter()
                    .filter(|s| {
                        s.closed
                            && s.status == contact::Status::Slip
                            && s.friction_force != [0.0; 3]
                    })
                    .count()
            })
            .sum()
    }

    /// du/dmu at the equilibrium of friction `mu` ([`sensitivity::equilibrium_rate`]), on
    /// every rank; `None`, said in the log, when it cannot be had (the point goes on without
    /// sensitivities). Collective.
    pub(super) fn equilibrium_rate(
        &self,
        comm: Comm<'_>,
        mu: f64,
        equilibrium: &statics::StaticSolution,
    ) -> Option<Vec<[f64; 3]>> {
        let Operators {
            dofs,
            stiffness,
            constraints,
            ..
        } = &self.operators;
        let layout = StaticLayout {
            dofs,
            stiffness,
            constraints: constraints.as_ref(),
            linear: &self.cea.linear,
        };
        match sensitivity::equilibrium_rate(
            comm,
            &layout,
            &self.model.pairs_at(mu),
            &self.model.pairs_at(mu + sensitivity::STEP),
            &equilibrium.slip_after,
            &equilibrium.displacement,
        ) {
            Ok(du) => Some(du),
            Err(e) => {
                tracing::warn!("mu {mu}: no friction sensitivities: du/dmu failed: {e}");
                None
            }
        }
    }

    /// The friction sensitivity of `mode` (shape `re`, `im`, left eigenvector `left`) at the
    /// equilibrium of friction `mu` moving by `du` per unit of mu; `None`, said in the log,
    /// where it cannot be had.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn friction_sensitivity(
        &self,
        mode: &cea::ComplexMode,
        mu: f64,
        equilibrium: &statics::StaticSolution,
        re: &[[f64; 3]],
        im: &[[f64; 3]],
        left: &LeftShape,
        du: &[[f64; 3]],
    ) -> Option<Sensitivity> {
        let x = growth::Shape { re, im };
        let y = growth::Shape {
            re: &left.re,
            im: &left.im,
        };
        let still = vec![[0.0; 3]; du.len()];
        let rate = |du: &[[f64; 3]]| {
            sensitivity::tangent_rate(
                |m| self.model.pairs_at(m),
                mu,
                &equilibrium.slip_after,
                &equilibrium.displacement,
                du,
                y,
                x,
            )
        };
        match (rate(du), rate(&still)) {
            (Ok(Some((total, one_sided))), Ok(Some((own, _)))) => Some(sensitivity::sensitivity(
                mode.lambda,
                left.mass_form,
                total,
                own,
                one_sided,
            )),
            (Err(e), _) | (_, Err(e)) => {
                tracing::warn!(
                    "no friction sensitivity of the mode at {:.1} Hz: {e}",
                    mode.frequency_hz
                );
                None
            }
            _ => {
                tracing::warn!(
                    "no friction sensitivity of the mode at {:.1} Hz: contact points change \
                     state on both sides of mu {mu}",
                    mode.frequency_hz
                );
                None
            }
        }
    }
}
