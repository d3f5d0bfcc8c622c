//! The CalculiX variant of the node-to-surface law, to compare like with like against
//! CalculiX (ccx 2.20's node-to-face penalty contact, read in its source:
//! `tiefaccont.f`, `gencontelem_n2f.f`, `springforc_n2f.f`, `springstiff_n2f.f`,
//! `surfacebehaviors.f`). Where squeal's law differs, the variant does what CalculiX does:
//!
//! 1. **Slave areas of 6-node faces.** squeal splits each face into its four 3-node
//!    sub-triangles and gives each node a third of theirs ([`super::tributary_areas`]);
//!    CalculiX gives a corner node 1/999 and a mid-side node 332/999 of the face's area (the
//!    consistent weights 0 and 1/3 of a uniform pressure, moved off zero). The face area is
//!    integrated over the quadratic face (7-point rule here, 3-point in CalculiX: the same on
//!    the flat faces of the decks compared).
//! 2. **The linear law near zero gap.** `PRESSURE-OVERCLOSURE=LINEAR` with slope K is, in
//!    CalculiX, `p = K d (1/2 + atan(d / eps) / pi)` with d the overclosure and
//!    `eps = pi sigma_inf / K`, sigma_inf the tension at large clearance (the data line's 2nd
//!    field; blank: the first material's E / 70000, CalculiX's default). It tends to
//!    `K d - sigma_inf` under load and pulls with up to sigma_inf when the node lifts off;
//!    a slave node has this spring when it starts within `c0 sqrt(slave area)` of the
//!    master (c0 the 3rd field, default 1e-3: where CalculiX makes the contact element of
//!    a small-sliding pair), none otherwise. Its slope at the operating point is between
//!    K/2 and K, so CalculiX's contact is softer than the slope says at low pressure and
//!    stiffens as the pressure rises (pad on plate: at 1 MPa, about 0.62 K). `HARD` is, in
//!    CalculiX, this law with K = 50 E (the first material's E). squeal's law is
//!    `p = K max(0, d)`.
//! 3. **The tangent of a slipping point in the perturbation step.** CalculiX's `*FREQUENCY`
//!    after a `*STATIC` evaluates the contact from the stored state, whose slip anchor the
//!    static moved onto the Coulomb cone: the slip tangent then has the full stick stiffness
//!    k_t A (I - n n^T - s s^T) across the slip direction. squeal's law does the same
//!    ([`perturbation_history`]); this item is no longer a difference, and is kept here
//!    because the comparisons against CalculiX were first made when it was.
//! 4. **Steady sliding in the perturbation step.** CalculiX has no imposed sliding: a pad
//!    slides when the master is moved under it, and its points then slip on the Coulomb cone,
//!    with the stick stiffness across the slip direction (item 3). squeal's steady sliding
//!    (the disc turning under the pad, a `*MOTION`) has no tangential stiffness at all: the
//!    friction force is mu p along the sliding direction whatever the pad does across it.
//!    The variant adds the stick slope across the sliding direction, k_t A (I - n n^T -
//!    t t^T), to the perturbation tangent of a closed steady-sliding point with friction
//!    ([`across_sliding`]): the tangent of the same point slipping along t in CalculiX.
//!
//! Not followed: CalculiX's NLGEOM (it switches it on for contact: stress stiffening of the
//! perturbation step), its moving normals and projection points (finite-sliding terms of its
//! tangent, a force over element size: 1e3 N/m against contact stiffnesses of 1e8 N/m on the
//! pad-on-plate deck), friction on a bilateral (NO SEPARATION) law it does not have.

use super::coulomb::SlipHistory;
use super::pair::{ContactPair, ContactPoint};
use crate::mesh::{Mesh, Surface};
use crate::vector3::{cross, norm};
use std::f64::consts::PI;

/// Which node-to-surface law a pair follows.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum ContactVariant {
    /// squeal's law (METHOD.md section 2).
    #[default]
    #[value(help = "squeal's penalty law")]
    Squeal,
    /// CalculiX's (see the module documentation).
    #[value(help = "CalculiX's: slave areas, smoothed linear law, perturbation tangent")]
    Calculix,
}

impl ContactVariant {
    pub fn name(self) -> &'static str {
        match self {
            ContactVariant::Squeal => "squeal",
            ContactVariant::Calculix => "calculix",
        }
    }
}

/// CalculiX's linear pressure-overclosure law of one pair (item 2 of the module doc), and
/// its stick slope (item 4).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CalculixLaw {
    /// sigma_inf, the tension at large clearance (pressure).
    pub tension: f64,
    /// c0: a slave node farther than c0 sqrt(area) from the master has no contact spring.
    pub clearance_factor: f64,
    /// The `*FRICTION` stick slope (stiffness per unit area); `None`: the penalty / 100.
    #[serde(default)]
    pub stick_slope: Option<f64>,
}

/// CalculiX's default c0.
pub const DEFAULT_CLEARANCE_FACTOR: f64 = 1e-3;
/// CalculiX's default tension at large clearance is the first material's E over this.
pub const DEFAULT_TENSION_DIVISOR: f64 = 70_000.0;
/// CalculiX's `HARD` is the linear law with this times the first material's E as slope.
pub const HARD_SLOPE_FACTOR: f64 = 50.0;
/// CalculiX's weights of a uniform pressure on a 6-node face, corner and mid-side node.
pub const CORNER_WEIGHT: f64 = 1.0 / 999.0;
pub const MID_WEIGHT: f64 = 332.0 / 999.0;

impl CalculixLaw {
    /// Whether the point has a contact spring, its normal force and the force's slope
    /// d force / d overclosure, at gap `gap` (negative: overclosure), for a pair of penalty
    /// `k` per unit area and a point of area `area` and initial gap `initial_gap`. CalculiX
    /// makes the spring of a slave node within `c0 sqrt(area)` of the master when it pairs
    /// the surfaces (small sliding: at the start), and the spring then acts at any gap,
    /// pulling with up to sigma_inf when the node lifts.
    pub fn normal(&self, k: f64, area: f64, initial_gap: f64, gap: f64) -> (bool, f64, f64) {
        if initial_gap > self.clearance_factor * area.sqrt() {
            return (false, 0.0, 0.0);
        }
        let d = -gap;
        let eps = PI * self.tension / k;
        if eps.is_nan() || eps <= 0.0 {
            // No tension: the plain linear law (CalculiX's formula at eps -> 0).
            return if d >= 0.0 {
                (true, k * area * d, k * area)
            } else {
                (false, 0.0, 0.0)
            };
        }
        let x = d / eps;
        let factor = 0.5 + x.atan() / PI;
        let force = k * area * d * factor;
        let slope = k * area * (factor + x / (PI * (1.0 + x * x)));
        (true, force, slope)
    }
}

/// CalculiX's slave areas of an element-based slave surface (item 1 of the module doc),
/// sorted by node.
pub fn calculix_areas(mesh: &Mesh, surface: &Surface) -> Vec<(usize, f64)> {
    let mut area: std::collections::BTreeMap<usize, f64> = Default::default();
    let rule = crate::fem::tet10::RADON_7;
    for face in &surface.faces {
        let x = face.nodes.map(|n| mesh.nodes[n]);
        let mut a = 0.0;
        for (q, w) in rule.points.iter().zip(rule.weights) {
            let d = crate::fem::tet10::face_shape_derivatives(*q);
            let mut ds = [0.0; 3];
            let mut dt = [0.0; 3];
            for (k, xk) in x.iter().enumerate() {
                for c in 0..3 {
                    ds[c] += d[k][0] * xk[c];
                    dt[c] += d[k][1] * xk[c];
                }
            }
            a += w * norm(cross(ds, dt));
        }
        for (k, &n) in face.nodes.iter().enumerate() {
            let weight = if k < 3 { CORNER_WEIGHT } else { MID_WEIGHT };
            *area.entry(n).or_default() += weight * a;
        }
    }
    area.into_iter().collect()
}

/// The slip history a perturbation step's tangent is formed from: the committed one, the
/// equilibrium's own (`after`), for every pair. A point that slipped in the last increment
/// has its anchor on the Coulomb cone there, and is kept slipping
/// ([`super::coulomb::COMMITTED_CONE_TOLERANCE`]): its tangent is the consistent one of a
/// vanishing increment, with the full stick stiffness across the slip direction. The
/// tangent of the last increment itself (`before`) has (mu p / |f_trial|) k_t A there,
/// which depends on how large that increment was: tiny-caliper's first point of a sweep
/// (the load ramped from rest) and the next one (a friction step of 0.001) came out at 665
/// and 707 Hz for one mode, and both at 674 Hz from the committed history. CalculiX's
/// `*FREQUENCY` after a `*STATIC` does the same (item 3 of the module doc).
pub fn perturbation_history(pairs: &[ContactPair], after: &SlipHistory) -> SlipHistory {
    SlipHistory::from_anchors(
        pairs
            .iter()
            .enumerate()
            .map(|(i, pair)| (0..pair.points.len()).map(|k| after.anchor(i, k)).collect())
            .collect(),
    )
}

/// The perturbation stiffness item 4 of the module doc adds at a closed steady-sliding
/// point with friction of a pair with CalculiX's law: `k_t A (I - n n^T - t t^T)` on the
/// point's relative displacement (rows and columns of its nodes, slave then master, as
/// [`super::evaluate`] orders them); `None` elsewhere.
pub fn across_sliding(
    pair: &ContactPair,
    point: &ContactPoint,
    state: &super::PointState,
) -> Option<super::PointContribution> {
    let law = pair.settings.calculix?;
    let t = point.tangent?;
    if !state.closed
        || pair.settings.friction == 0.0
        || pair.settings.law != super::FrictionLaw::SteadySliding
    {
        return None;
    }
    let kt = law
        .stick_slope
        .unwrap_or(pair.penalty / super::pair::STICK_STIFFNESS_DIVISOR)
        * point.area;
    let n = point.normal;
    let block: [[f64; 3]; 3] = [0, 1, 2]
        .map(|i| [0, 1, 2].map(|j| kt * (f64::from(u8::from(i == j)) - n[i] * n[j] - t[i] * t[j])));
    let weights: Vec<(usize, f64)> = point
        .slave
        .iter()
        .copied()
        .chain(point.master.iter().map(|&(node, w)| (node, -w)))
        .collect();
    let size = 3 * weights.len();
    let mut jacobian = vec![0.0; size * size];
    for (k, &(_, ck)) in weights.iter().enumerate() {
        for (m, &(_, cm)) in weights.iter().enumerate() {
            for i in 0..3 {
                for j in 0..3 {
                    jacobian[(3 * k + i) * size + 3 * m + j] = ck * cm * block[i][j];
                }
            }
        }
    }
    Some(super::PointContribution {
        nodes: weights.iter().map(|&(node, _)| node).collect(),
        residual: vec![0.0; size],
        jacobian,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_smoothed_law_tends_to_the_linear_law_less_the_tension() {
        let law = CalculixLaw {
            tension: 3e6,
            clearance_factor: 1e-3,
            stick_slope: None,
        };
        let (k, area) = (1e13, 2e-5);
        // Deep overclosure: K d - sigma_inf per unit area, slope K.
        let d = 1e-4;
        let (closed, f, slope) = law.normal(k, area, 0.0, -d);
        assert!(closed);
        // The next term of the expansion is K d / (3 pi (d / eps)^3), 88 Pa here.
        assert!((f / area - (k * d - 3e6)).abs() < 1e-3 * 3e6, "{f}");
        assert!((slope / (k * area) - 1.0).abs() < 1e-4);
        // At zero gap: no force, half the slope.
        let (_, f0, s0) = law.normal(k, area, 0.0, 0.0);
        assert_eq!(f0, 0.0);
        assert!((s0 / (k * area) - 0.5).abs() < 1e-15);
        // The slope is the force's derivative (central difference).
        for d in [-2e-6, -1e-7, 3e-7, 2e-6] {
            let h = 1e-10;
            let (_, fp, _) = law.normal(k, area, 0.0, -(d + h));
            let (_, fm, _) = law.normal(k, area, 0.0, -(d - h));
            let (_, _, s) = law.normal(k, area, 0.0, -d);
            assert!(((fp - fm) / (2.0 * h) - s).abs() < 1e-6 * s, "at {d}");
        }
        // Lifted off: a pull, up to sigma_inf; a node that starts beyond c0 sqrt(A): nothing.
        let reach = 1e-3 * area.sqrt();
        let (closed, f, _) = law.normal(k, area, 0.0, 10.0 * reach);
        assert!(closed && f < 0.0 && f > -3e6 * area);
        assert_eq!(law.normal(k, area, 1.1 * reach, 0.0), (false, 0.0, 0.0));
        // No tension: the linear law.
        let plain = CalculixLaw {
            tension: 0.0,
            clearance_factor: 1e-3,
            stick_slope: None,
        };
        assert_eq!(
            plain.normal(k, area, 0.0, -1e-6),
            (true, k * area * 1e-6, k * area)
        );
        assert_eq!(plain.normal(k, area, 0.0, 1e-9).1, 0.0);
    }

    #[test]
    fn calculix_areas_add_up_to_the_surface_area_with_its_weights() {
        let mesh = crate::contact::test_models::pad_on_disc(0.0);
        let surface = &mesh.surfaces["pad.z0"];
        let areas = calculix_areas(&mesh, surface);
        let total: f64 = areas.iter().map(|a| a.1).sum();
        // 3 corner weights and 3 mid weights per face: 3/999 + 996/999 = 1.
        assert!((total - 0.15).abs() < 1e-14, "{total}");
        // A corner node of one face only (the pad's corner) has 1/999 of a face area.
        let squeal = crate::contact::tributary_areas(&mesh, surface);
        assert_eq!(areas.len(), squeal.len());
        let smallest = areas.iter().map(|a| a.1).fold(f64::INFINITY, f64::min);
        let face = 0.15 / surface.faces.len() as f64;
        assert!(smallest <= 2.0 * face / 999.0 + 1e-18, "{smallest}");
    }
}
