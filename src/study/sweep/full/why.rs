//! What an unstable mode's shapes say of its cause, at the equilibrium its CEA was made
//! about: which body moves (kinetic energy), which contact pair feeds it (growth), and how it
//! moves with the swept friction (sensitivity, from its left eigenvector).

use super::FullModel;
use crate::analysis::cea;
use crate::analysis::growth;
use crate::analysis::sensitivity::{self, ModulusSensitivity, Sensitivity, StaticLayout};
use crate::analysis::statics;
use crate::contact;
use crate::fem::{body_energy, body_stiffness};
use crate::model::Operators;
use crate::petsc::Comm;
use num_complex::Complex64;
use std::collections::BTreeMap;

/// The equilibrium's rates of change: with the swept friction, and with each body's ln E.
pub(super) struct Rates {
    pub friction: Vec<[f64; 3]>,
    pub bodies: Vec<BodyRate>,
}

/// du/d ln E_b of one body, and the pairs whose penalty follows its modulus.
pub(super) struct BodyRate {
    pub body: String,
    pub followers: Vec<usize>,
    pub du: Vec<[f64; 3]>,
}

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

    /// Each contact pair's part of the growth rate of the shape (`re`, `im` at every node of
    /// the model) about the displacement `u` with slip history `after` ([`growth`]), with the
    /// modal mass from the mesh's bodies; `None`, said in the log, where it cannot be had.
    /// For a super-element's mode, the expanded shape in the reduced-interface model's pairs:
    /// its parts add up to the real part to the expansion's error.
    pub(in crate::study::sweep) fn pair_growth(
        &self,
        mode: &cea::ComplexMode,
        pairs: &[contact::ContactPair],
        after: &contact::SlipHistory,
        u: &[[f64; 3]],
        re: &[[f64; 3]],
        im: &[[f64; 3]],
    ) -> Option<BTreeMap<String, f64>> {
        let model = &self.model;
        let energies = body_energy::body_kinetic_energies(
            &model.mesh,
            &model.point_masses,
            self.mass_rule,
            re,
            im,
        );
        let modal_mass: f64 = match energies {
            Ok(e) => e.values().sum(),
            Err(e) => {
                tracing::warn!(
                    "no pair shares of the mode at {:.1} Hz: {e}",
                    mode.frequency_hz
                );
                return None;
            }
        };
        let omega = mode.lambda.im;
        if modal_mass <= 0.0 || omega <= 0.0 {
            return None;
        }
        match growth::point_growth_rates(
            pairs,
            after,
            u,
            growth::Shape { re, im },
            omega,
            modal_mass,
        ) {
            Ok(points) => Some(growth::pair_growth_rates(pairs, &points)),
            Err(e) => {
                tracing::warn!(
                    "no pair shares of the mode at {:.1} Hz: {e}",
                    mode.frequency_hz
                );
                None
            }
        }
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

    /// The contact pairs whose penalty follows each body's modulus: a pair given no penalty
    /// takes 10 E_min / h ([`contact::node_to_surface`]), E_min the smallest Young's modulus
    /// of the elements its two surfaces' faces belong to, so its stiffness scales with the
    /// body that has it. Where two bodies share that smallest modulus the minimum has no
    /// derivative: the pair is left out, and said.
    fn penalty_followers(&self) -> BTreeMap<String, Vec<usize>> {
        let mesh = &self.model.mesh;
        let owner = mesh.element_parts();
        let mut out: BTreeMap<String, Vec<usize>> = BTreeMap::new();
        for (i, pair) in self.model.pairs.iter().enumerate() {
            let surfaces = self.model.pair_surfaces.get(i).cloned().flatten();
            let (Some((slave, master)), None) = (surfaces, pair.settings.penalty) else {
                continue;
            };
            let mut moduli: BTreeMap<usize, f64> = BTreeMap::new();
            for name in [slave, master] {
                for f in mesh.surfaces.get(&name).iter().flat_map(|s| &s.faces) {
                    let Some(p) = owner[f.element] else { continue };
                    let part = &mesh.parts[p];
                    if let Some(m) = part.material.as_ref().and_then(|m| mesh.materials.get(m)) {
                        moduli.insert(p, m.young);
                    }
                }
            }
            let least = moduli.values().copied().fold(f64::INFINITY, f64::min);
            let at_least: Vec<usize> = moduli
                .iter()
                .filter(|(_, &e)| e == least)
                .map(|(&p, _)| p)
                .collect();
            match at_least[..] {
                [p] => out.entry(mesh.parts[p].name.clone()).or_default().push(i),
                _ => tracing::debug!(
                    "pair {}: its default penalty follows {} bodies of the same modulus: \
                     left out of the moduli's sensitivities",
                    pair.settings.name,
                    at_least.len()
                ),
            }
        }
        out
    }

    /// The pairs at `mu` with the penalty of `followers` scaled by e^t (a body's ln E moved
    /// by t).
    fn pairs_scaled(&self, mu: f64, followers: &[usize], t: f64) -> Vec<contact::ContactPair> {
        let mut pairs = self.model.pairs_at(mu);
        for &i in followers {
            pairs[i].penalty *= t.exp();
        }
        pairs
    }

    /// du/dmu at the equilibrium of friction `mu`, and du/d ln E_b of each body (its
    /// elastic forces K_b u, and the forces of the pairs whose penalty follows it), with one
    /// factorisation ([`sensitivity::equilibrium_rate`]), on every rank; `None`, said in the
    /// log, when they cannot be had (the point goes on without sensitivities). Collective.
    pub(super) fn equilibrium_rate(
        &self,
        comm: Comm<'_>,
        mu: f64,
        equilibrium: &statics::StaticSolution,
    ) -> Option<Rates> {
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
        let mesh = &self.model.mesh;
        let u = &equilibrium.displacement;
        // The same mesh and displacement on every rank: the same answer on every rank.
        let forces = match body_stiffness::body_forces(mesh, &u[..mesh.nodes.len().min(u.len())]) {
            Ok(f) => f,
            Err(e) => {
                tracing::warn!("mu {mu}: no sensitivities: the bodies' forces failed: {e}");
                return None;
            }
        };
        let followers = self.penalty_followers();
        // A reduced interface's pairs have no surfaces left, and its contact, patch-law and
        // tie stiffnesses follow the lining's modulus through the reduction (measured on
        // `tiny` with 22 nodes per pad: the lining's derivative 10-20 % off the central
        // difference without them): no moduli's sensitivities there.
        let untraced = self.model.pairs.iter().enumerate().any(|(i, p)| {
            p.settings.penalty.is_none()
                && self.model.pair_surfaces.get(i).is_none_or(Option::is_none)
        });
        if untraced {
            tracing::debug!(
                "mu {mu}: no moduli's sensitivities: a pair's default penalty follows a body \
                 this model no longer names (a reduced interface)"
            );
        }
        let forces = if untraced { BTreeMap::new() } else { forces };
        let bodies: Vec<(String, Vec<[f64; 3]>, Vec<usize>)> = forces
            .into_iter()
            .map(|(body, mut f)| {
                f.resize(u.len(), [0.0; 3]);
                let follow = followers.get(&body).cloned().unwrap_or_default();
                (body, f, follow)
            })
            .collect();
        let ahead = self.model.pairs_at(mu + sensitivity::STEP);
        let scaled: Vec<Option<Vec<contact::ContactPair>>> = bodies
            .iter()
            .map(|(_, _, follow)| {
                (!follow.is_empty()).then(|| self.pairs_scaled(mu, follow, sensitivity::STEP))
            })
            .collect();
        let mut perturbations = vec![sensitivity::Perturbation {
            forces: None,
            pairs_ahead: Some(&ahead),
        }];
        for ((_, f, _), pairs) in bodies.iter().zip(&scaled) {
            perturbations.push(sensitivity::Perturbation {
                forces: Some(f),
                pairs_ahead: pairs.as_deref(),
            });
        }
        match sensitivity::equilibrium_rate(
            comm,
            &layout,
            &self.model.pairs_at(mu),
            &equilibrium.slip_after,
            u,
            &perturbations,
        ) {
            Ok(mut rates) => {
                let friction = rates.remove(0);
                Some(Rates {
                    friction,
                    bodies: bodies
                        .into_iter()
                        .zip(rates)
                        .map(|((body, _, follow), du)| BodyRate {
                            body,
                            followers: follow,
                            du,
                        })
                        .collect(),
                })
            }
            Err(e) => {
                tracing::warn!("mu {mu}: no sensitivities: du/dmu failed: {e}");
                None
            }
        }
    }

    /// How `mode` moves with each body's Young's modulus (see
    /// [`sensitivity::ModulusSensitivity`]); `None`, said in the log, where it cannot be had.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn modulus_sensitivities(
        &self,
        mode: &cea::ComplexMode,
        mu: f64,
        equilibrium: &statics::StaticSolution,
        re: &[[f64; 3]],
        im: &[[f64; 3]],
        left: &LeftShape,
        rates: &Rates,
    ) -> Option<BTreeMap<String, ModulusSensitivity>> {
        let x = growth::Shape { re, im };
        let y = growth::Shape {
            re: &left.re,
            im: &left.im,
        };
        let elastic = match body_stiffness::body_stiffness_forms(&self.model.mesh, &[(y, x)]) {
            Ok(mut forms) => forms.remove(0),
            Err(e) => {
                tracing::warn!(
                    "no modulus sensitivities of the mode at {:.1} Hz: {e}",
                    mode.frequency_hz
                );
                return None;
            }
        };
        let still = vec![[0.0; 3]; equilibrium.displacement.len()];
        let mut out = BTreeMap::new();
        for rate in &rates.bodies {
            let Some(&elastic) = elastic.get(&rate.body) else {
                continue;
            };
            // y^H (dJ/dt) x with t = ln E_b: the followers' penalty, and the equilibrium.
            let contact = |du: &[[f64; 3]]| {
                sensitivity::tangent_rate(
                    |t| self.pairs_scaled(mu, &rate.followers, t),
                    0.0,
                    &equilibrium.slip_after,
                    &equilibrium.displacement,
                    du,
                    y,
                    x,
                )
            };
            match (contact(&rate.du), contact(&still)) {
                (Ok(Some((total, one_sided))), Ok(Some((own, _)))) => {
                    let s = sensitivity::sensitivity(
                        mode.lambda,
                        left.mass_form,
                        elastic + total,
                        elastic + own,
                        one_sided,
                    );
                    out.insert(rate.body.clone(), ModulusSensitivity::from(s));
                }
                (Err(e), _) | (_, Err(e)) => tracing::warn!(
                    "no sensitivity of the mode at {:.1} Hz to {}'s modulus: {e}",
                    mode.frequency_hz,
                    rate.body
                ),
                _ => tracing::warn!(
                    "no sensitivity of the mode at {:.1} Hz to {}'s modulus: contact points \
                     change state both ways",
                    mode.frequency_hz,
                    rate.body
                ),
            }
        }
        (!out.is_empty()).then_some(out)
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
