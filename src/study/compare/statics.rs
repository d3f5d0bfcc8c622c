//! The static states of two models compared (the paper's section 4.2): contact states,
//! pad pressures over the other model's patches, and each pair's closed contact zone.

use crate::contact::ZoneRatios;
use crate::results::SweepPointReport as Point;
use std::path::Path;

/// The static states of one model against the reference's at one friction value (paper
/// section 4.2, Figures 7 and 9-11).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct StaticComparison {
    pub model: String,
    pub friction: f64,
    /// Fraction of the model's contact points whose state (open/closed) is the state of the
    /// reference's contact point nearest to it on the same pair.
    pub state_agreement: f64,
    /// Per pair: the L2 difference of the pad pressures at the other model's resolution,
    /// `sqrt(sum_k A_k (P_k - P_ref,k)^2 / sum_k A_k P_ref,k^2)`, where patch k gathers the
    /// pad surface nodes nearest to the other model's contact point k and `P_k` is the
    /// area-weighted mean nodal pressure there (see [`patch_pressure_l2`]). With a full model
    /// as the other, every node is its own patch and this is the nodal L2.
    pub pressure_l2: Vec<(String, f64)>,
    /// Per pair: the nodal L2, `sqrt(sum A (p - p_ref)^2) / sqrt(sum A p_ref^2)` over the pad
    /// surface nodes, A their tributary areas. Its floor for any reduced model is the full
    /// model's own corner/mid-side pressure oscillation (see [`patch_pressure_l2`]).
    pub nodal_pressure_l2: Vec<(String, f64)>,
}

/// One pair's closed zone against the reference's at one friction value.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct ZoneComparison {
    pub model: String,
    pub friction: f64,
    pub pair: String,
    /// Contact points of the pair in the reference and in the model: the pairs a reduction
    /// changed are those whose counts differ. (Read as [0, 0] from a comparison written
    /// before it was.)
    #[serde(default)]
    pub points: [usize; 2],
    #[serde(flatten)]
    pub ratios: ZoneRatios,
}

/// The zones of the pairs both points report, by name.
pub(super) fn compare_zones(model: &str, reference: &Point, other: &Point) -> Vec<ZoneComparison> {
    let mut out = Vec::new();
    for r in &reference.contact {
        let Some(o) = other.contact.iter().find(|o| o.name == r.name) else {
            continue;
        };
        if let (Some(zr), Some(zo)) = (&r.zone, &o.zone) {
            if let Some(ratios) = zo.against(zr) {
                out.push(ZoneComparison {
                    model: model.to_string(),
                    friction: reference.friction,
                    pair: r.name.clone(),
                    points: [r.points, o.points],
                    ratios,
                });
            }
        }
    }
    out
}

pub(super) fn read_contact(dir: &Path, mu: f64) -> Option<crate::results::ContactMap> {
    let file = dir
        .join(crate::study::sweep::point_folder(mu))
        .join("contact.json");
    serde_json::from_slice(&std::fs::read(file).ok()?).ok()
}

pub(super) fn compare_statics(reference: &Path, other: &Path, mu: f64) -> Option<StaticComparison> {
    let (r, o) = (read_contact(reference, mu)?, read_contact(other, mu)?);
    let d2 = |a: [f64; 3], b: [f64; 3]| (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>();
    let mut agree = 0usize;
    for p in &o.points {
        let nearest = r
            .points
            .iter()
            .filter(|q| q.pair == p.pair)
            .min_by(|a, b| d2(a.position, p.position).total_cmp(&d2(b.position, p.position)));
        if nearest.is_some_and(|q| q.closed == p.closed) {
            agree += 1;
        }
    }
    let mut pairs: Vec<String> = r.surface.iter().map(|s| s.pair.clone()).collect();
    pairs.dedup();
    let mut pressure_l2 = Vec::new();
    let mut nodal_pressure_l2 = Vec::new();
    for pair in pairs {
        let on = |m: &crate::results::ContactMap| -> Vec<crate::results::SurfacePressure> {
            m.surface
                .iter()
                .filter(|s| s.pair == pair)
                .cloned()
                .collect()
        };
        let points: Vec<[f64; 3]> = o
            .points
            .iter()
            .filter(|p| p.pair == pair)
            .map(|p| p.position)
            .collect();
        if let Some(l2) = patch_pressure_l2(&on(&r), &on(&o), &points) {
            pressure_l2.push((pair.clone(), l2));
        }
        let reference: std::collections::BTreeMap<usize, (f64, f64)> = r
            .surface
            .iter()
            .filter(|s| s.pair == pair)
            .map(|s| (s.node, (s.area, s.pressure)))
            .collect();
        let (mut num, mut den) = (0.0, 0.0);
        for s in o.surface.iter().filter(|s| s.pair == pair) {
            if let Some(&(area, p_ref)) = reference.get(&s.node) {
                num += area * (s.pressure - p_ref).powi(2);
                den += area * p_ref * p_ref;
            }
        }
        if den > 0.0 {
            nodal_pressure_l2.push((pair, (num / den).sqrt()));
        }
    }
    Some(StaticComparison {
        model: other.display().to_string(),
        friction: mu,
        state_agreement: agree as f64 / o.points.len().max(1) as f64,
        pressure_l2,
        nodal_pressure_l2,
    })
}

/// The L2 difference of two pad pressures at the resolution of `points` (the other model's
/// contact points on that pad): each reference surface node goes to the patch of the point
/// nearest to it; a patch's pressure is its nodes' force over their area,
/// `P_k = sum_i A_i p_i / sum_i A_i`, for both models; the result is
/// `sqrt(sum_k A_k (P_k - P_ref,k)^2 / sum_k A_k P_ref,k^2)`. `None` without points or
/// reference pressure.
///
/// Why not node by node: on the 6-node faces of the pads, the full model's nodal penalty
/// pressure (nodal force over tributary area) oscillates between corner and mid-side nodes
/// (measured on the small brake at mu 0.5: loaded corners 6.1e5 Pa on average, mid-sides
/// 2.5e6 Pa), a mesh-scale pattern that no model with fewer contact points can carry. Fed
/// through any reconstruction, the full model's own forces over the 106-node patches give
/// 44-49 % back node by node: that floor, not the reduced model, made the 40-79 % nodal
/// differences. A patch's force is what the other model resolves, and the average is
/// exact for a uniform pressure, whatever the nodes' areas.
pub fn patch_pressure_l2(
    reference: &[crate::results::SurfacePressure],
    other: &[crate::results::SurfacePressure],
    points: &[[f64; 3]],
) -> Option<f64> {
    if points.is_empty() {
        return None;
    }
    let d2 = |a: [f64; 3], b: [f64; 3]| (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>();
    let other: std::collections::BTreeMap<usize, f64> =
        other.iter().map(|s| (s.node, s.pressure)).collect();
    // (area, reference force, other force) per patch.
    let mut patches = vec![(0.0, 0.0, 0.0); points.len()];
    for s in reference {
        let Some(&p) = other.get(&s.node) else {
            continue;
        };
        let k = (0..points.len())
            .min_by(|&a, &b| d2(points[a], s.position).total_cmp(&d2(points[b], s.position)))
            .unwrap_or(0);
        let patch = &mut patches[k];
        patch.0 += s.area;
        patch.1 += s.area * s.pressure;
        patch.2 += s.area * p;
    }
    let (mut num, mut den) = (0.0, 0.0);
    for &(area, f_ref, f) in patches.iter().filter(|p| p.0 > 0.0) {
        num += (f - f_ref).powi(2) / area;
        den += f_ref * f_ref / area;
    }
    (den > 0.0).then(|| (num / den).sqrt())
}
