//! The study file's `[reduction]` table: the reduced contact interface and the
//! super-elements a user asks for, its checks, and the [`InterfaceSettings`] it gives the
//! reduction (METHOD.md section 5).

use crate::reduce::{
    DiscCoupling, GridSize, InterfaceSettings, PadCoupling, PairGrid, PatchQuadrature,
    RadiusChoice, ReduceError, ReducePairs, Strategy, Weighting,
};
use std::collections::BTreeMap;

/// What [`ReductionSpec::check`] needs of the rest of the study.
#[derive(Clone, Copy, Debug)]
pub struct StudyContext {
    /// `analysis.max_frequency_hz`.
    pub max_frequency_hz: f64,
    /// `comparison.superelements` is not empty.
    pub compared_superelements: bool,
    /// Some `contacts[..]` has `sweep = true`.
    pub any_swept: bool,
}

/// The reduced contact interface (METHOD.md section 5): reduced contact nodes per pad (or
/// the grid side), the distributing coupling's weighting and radius, the tie springs.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReductionSpec {
    /// Reduced contact nodes per pad (the paper's 6, 22, 52, 106).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_nodes_per_pad: Option<usize>,
    /// Or the grid side h (mesh units).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<f64>,
    /// "uniform", "linear", "quadratic" or "cubic".
    #[serde(default = "cubic")]
    pub weighting: Weighting,
    /// "grid-optimal", "paper" or a radius in mesh units.
    #[serde(default = "grid_optimal")]
    pub radius: RadiusChoice,
    /// Stiffness of each tie spring (N/m); default 1000 times the node's contact stiffness.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring_stiffness: Option<f64>,
    /// How each reduced contact node is tied to the pad face: "share" (its share's nodes by
    /// tributary area), "distributing" (the paper's radius of influence) or "auto" (default:
    /// share where every share holds enough face nodes). Always written: its default was
    /// "distributing" before 2026-11-28, so a study without it keys its stages apart.
    #[serde(default)]
    pub pad_coupling: PadCoupling,
    /// How each disc node is tied to the disc face: "shape-functions", "distributing" (the
    /// pad side's weighting and radius), "share" (the disc surface under the node's share)
    /// or "auto" (default: share with share pad couplings, shape functions otherwise).
    #[serde(default)]
    pub disc_coupling: DiscCoupling,
    /// Weigh each coupled node by its tributary area too (Abaqus 6.10's mesh-size weighting).
    #[serde(default)]
    pub area_weighting: bool,
    /// Each reduced contact carries its patch law: the full model's penalty integrated over
    /// its share of the pad face, tilt included (squeal's addition to the paper's point
    /// contacts, [`crate::reduce::tilt`]). Super-elements then carry the same law, with no
    /// cubic k_linear or k_cubic. Absent: patch laws with share couplings where the pad
    /// faces hold them and the swept pairs' laws admit them, the paper's point contacts
    /// otherwise, and whenever k_linear or k_cubic asks for the cubic law.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt: Option<bool>,
    /// Each share's warping springs: the full model's penalty against the pad face's warping
    /// inside the share ([`crate::reduce::warp`]), on patch laws over share couplings. Off
    /// unless asked for.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub warp_springs: bool,
    /// Where each patch law integrates the full pair's penalty over its share: "nodes" (the
    /// share's face nodes by tributary area, the full model's own quadrature; default) or
    /// "area" (the share's area as a continuum, the rule before 2026-12-07). Always written:
    /// its default changed, so a study without it keys its stages apart.
    #[serde(default)]
    pub patch_quadrature: PatchQuadrature,
    /// Craig-Bampton super-elements on the reduced interface, assembled with node-to-node
    /// cubic contact: "single", "per-friction" or "adaptive". Absent: the reduced-interface
    /// model itself is swept.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub superelements: Option<Strategy>,
    /// mu_SE: where the single strategy makes its super-element (default 0.5, the paper's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub superelement_friction: Option<f64>,
    /// Fixed-interface modes kept up to this frequency (Hz); default twice the band's top
    /// (the paper kept 0-12 kHz for a 0-6 kHz study).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutoff_frequency_hz: Option<f64>,
    /// Each super-element with the residual vectors of its band's modes at mu_SE
    /// ([`crate::reduce::residual_vectors`]). Absent: made wherever they can be, a
    /// super-element whose interior holds no contact (every pair reduced); `true` asks for
    /// them and warns where they cannot be made, `false` leaves them out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub residual_vectors: Option<bool>,
    /// k_l of the cubic contact law (N/m); default each pair's penalty times its area, the
    /// reduced-interface model's own stiffness.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_linear: Option<f64>,
    /// k_nl of the cubic contact law (N/m^3); default 0 (linear).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_cubic: Option<f64>,
    /// Pairs reduced besides the swept ones: "swept" (default), "all" or a list of names.
    #[serde(default, skip_serializing_if = "ReducePairs::is_swept")]
    pub reduce_pairs: ReducePairs,
    /// A reduced kept pair's own grid: `[reduction.pairs."caliper/pad"] contact_nodes = 8`.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub pairs: BTreeMap<String, PairGrid>,
}

fn cubic() -> Weighting {
    Weighting::Cubic
}
fn grid_optimal() -> RadiusChoice {
    RadiusChoice::GridOptimal
}

impl ReductionSpec {
    /// A reduction to `count` nodes per pad with the defaults.
    pub fn with_count(count: usize) -> ReductionSpec {
        ReductionSpec {
            contact_nodes_per_pad: Some(count),
            spacing: None,
            weighting: cubic(),
            radius: grid_optimal(),
            spring_stiffness: None,
            pad_coupling: PadCoupling::default(),
            disc_coupling: DiscCoupling::default(),
            area_weighting: false,
            tilt: None,
            warp_springs: false,
            patch_quadrature: PatchQuadrature::default(),
            superelements: None,
            superelement_friction: None,
            cutoff_frequency_hz: None,
            residual_vectors: None,
            k_linear: None,
            k_cubic: None,
            reduce_pairs: ReducePairs::Swept,
            pairs: BTreeMap::new(),
        }
    }

    /// The settings of [`crate::reduce::reduce_interface`] ([`ReductionSpec::check`] names
    /// what is wrong with the table first; a pair grid that is no grid is refused here too,
    /// for a caller that did not check).
    pub fn settings(&self) -> Result<InterfaceSettings, ReduceError> {
        let pair_grids = PairGrid::sizes(&self.pairs)
            .map_err(|(pair, why)| ReduceError::PairGrid { pair, why })?;
        Ok(InterfaceSettings {
            size: match (self.contact_nodes_per_pad, self.spacing) {
                (_, Some(h)) => GridSize::Spacing(h),
                (Some(n), None) => GridSize::Count(n),
                (None, None) => GridSize::Count(52),
            },
            weighting: self.weighting,
            radius: self.radius,
            spring_stiffness: self.spring_stiffness,
            spring_factor: 1.0,
            pad_coupling: self.pad_coupling,
            disc_coupling: self.disc_coupling,
            area_weighting: self.area_weighting,
            tilt: self.tilt.or(self.cubic_law().then_some(false)),
            warp_springs: self.warp_springs,
            patch_quadrature: self.patch_quadrature,
            reduce_pairs: self.reduce_pairs.clone(),
            pair_grids,
            pair_tilts: PairGrid::tilts(&self.pairs),
        })
    }

    /// Whether k_linear or k_cubic asks for the paper's cubic law between point contacts.
    pub fn cubic_law(&self) -> bool {
        self.k_linear.is_some() || self.k_cubic.is_some_and(|k| k != 0.0)
    }

    /// What is wrong with the table, as `bad(key, message)`: the grid, the radius, the
    /// springs, the super-element settings and what they need of the rest of the study (its
    /// band's top, whether its comparison sweeps super-elements, whether any pair is swept).
    pub fn check<E>(
        &self,
        study: StudyContext,
        bad: impl Fn(String, String) -> E,
    ) -> Result<(), E> {
        match (self.contact_nodes_per_pad, self.spacing) {
            (Some(_), Some(_)) => {
                return Err(bad(
                    "reduction".into(),
                    "give either contact_nodes_per_pad or spacing, not both".into(),
                ))
            }
            (Some(0), None) => {
                return Err(bad(
                    "reduction.contact_nodes_per_pad".into(),
                    "must be at least 1".into(),
                ))
            }
            (None, Some(h)) if !(h > 0.0 && h.is_finite()) => {
                return Err(bad(
                    "reduction.spacing".into(),
                    format!("must be finite and > 0, got {h}"),
                ))
            }
            _ => {}
        }
        if let RadiusChoice::Length(radius) = self.radius {
            if !(radius > 0.0 && radius.is_finite()) {
                return Err(bad(
                    "reduction.radius".into(),
                    format!("must be \"grid-optimal\", \"paper\" or a length > 0, got {radius}"),
                ));
            }
        }
        if let Some(k) = self.spring_stiffness {
            if !(k > 0.0 && k.is_finite()) {
                return Err(bad(
                    "reduction.spring_stiffness".into(),
                    format!("must be finite and > 0, got {k}"),
                ));
            }
        }
        let positive = |key: &str, value: Option<f64>, zero_allowed: bool| match value {
            Some(v) if !(v.is_finite() && (v > 0.0 || (zero_allowed && v == 0.0))) => Err(bad(
                format!("reduction.{key}"),
                format!(
                    "must be finite and {}, got {v}",
                    if zero_allowed { ">= 0" } else { "> 0" }
                ),
            )),
            _ => Ok(()),
        };
        positive("superelement_friction", self.superelement_friction, true)?;
        positive("cutoff_frequency_hz", self.cutoff_frequency_hz, false)?;
        // Below the band, the super-element keeps no fixed-interface mode of it: the
        // constraint modes alone, every mode of the band stiffened.
        if let Some(c) = self
            .cutoff_frequency_hz
            .filter(|&c| c < study.max_frequency_hz)
        {
            return Err(bad(
                "reduction.cutoff_frequency_hz".into(),
                format!(
                    "{c} Hz is below the band's top, analysis.max_frequency_hz = {} Hz: the \
                         super-element's fixed-interface modes must reach past the band (the \
                         default is twice its top)",
                    study.max_frequency_hz
                ),
            ));
        }
        PairGrid::sizes(&self.pairs)
            .map_err(|(pair, why)| bad(format!("reduction.pairs.\"{pair}\""), why))?;
        positive("k_linear", self.k_linear, false)?;
        positive("k_cubic", self.k_cubic, true)?;
        let compared_superelements = study.compared_superelements;
        if self.tilt == Some(true)
            && self.cubic_law()
            && (self.superelements.is_some() || compared_superelements)
        {
            return Err(bad(
                "reduction.tilt".into(),
                "a super-element's patch laws are the reduced-interface model's penalty \
                     over each share: reduction.k_linear and reduction.k_cubic are a point \
                     contact's cubic law and cannot be set with them (leave them out, or \
                     leave reduction.tilt out)"
                    .into(),
            ));
        }
        let no_patch_laws = self.tilt == Some(false)
            || self.cubic_law()
            || self.pad_coupling == PadCoupling::Distributing;
        if self.warp_springs && no_patch_laws {
            return Err(bad(
                "reduction.warp_springs".into(),
                "warping springs stand on patch laws over share couplings (they hold the pad \
                 face's warping within each share, beyond the share's plane the patch law \
                 holds): ask for those (leave reduction.tilt, reduction.pad_coupling, \
                 reduction.k_linear and reduction.k_cubic out), or leave \
                 reduction.warp_springs out"
                    .into(),
            ));
        }
        // `squeal study` sweeps the strategies of [comparison] with these settings.
        let compared = study.compared_superelements;
        if self.superelements.is_none() && !compared {
            let set: Vec<&str> = [
                (
                    "superelement_friction",
                    self.superelement_friction.is_some(),
                ),
                ("cutoff_frequency_hz", self.cutoff_frequency_hz.is_some()),
                ("k_linear", self.k_linear.is_some()),
                ("k_cubic", self.k_cubic.is_some()),
            ]
            .into_iter()
            .filter_map(|(k, on)| on.then_some(k))
            .collect();
            if let Some(key) = set.first() {
                return Err(bad(
                        format!("reduction.{key}"),
                        "is a super-element setting: give reduction.superelements = \"single\", \"per-friction\" or \"adaptive\" too (or comparison.superelements for squeal study)".into(),
                    ));
            }
        }
        if !study.any_swept {
            return Err(bad(
                    "reduction".into(),
                    "a reduced interface replaces the swept pairs, and no contacts[..] has sweep = true".into(),
                ));
        }
        Ok(())
    }
}
