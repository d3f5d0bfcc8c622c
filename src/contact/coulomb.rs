//! Coulomb friction with stick and slip at one contact point: the penalty-regularised
//! return mapping, its consistent tangent, and the slip history it carries.
//!
//! With `n` the (fixed) normal, `P = I - n n^T` the projector on the tangent plane, `w` the
//! slave point's displacement relative to the master point (`sum c_k u_k`), `g_T = P w` its
//! tangential part and `a` the point's anchor (the tangential slip accumulated since the
//! contact closed, from the history), at normal force `p` (area `A`, stick stiffness `k_t`):
//!
//! ```text
//!   f_trial = -k_t A (g_T - a)             the tangential spring's force on the slave
//!   stick:  |f_trial| <= mu max(p, 0)      f_T = f_trial,        a' = a
//!   slip:   otherwise                      f_T = mu p s,  s = f_trial / |f_trial|,
//!                                          a' = g_T + f_T / (k_t A)
//!   open:   no force                       f_T = 0,              a' = g_T
//! ```
//!
//! The anchor `a'` is what the point carries to the next load increment or friction value:
//! in slip it moves so that the spring's force stays on the cone. An open point forgets its
//! slip: when it closes again it sticks where it closed.
//!
//! The consistent tangent `d f_T / d w` (with `dp/dw = -k_n A n^T` while closed):
//!
//! ```text
//!   stick:  -k_t A P                                              symmetric
//!   slip:   mu s (dp/dw) - (mu p / |f_trial|) k_t A (P - s s^T)   unsymmetric
//! ```
//!
//! Touching counts as sticking (`|f_trial| = 0 <= 0` at zero pressure), so a pair that
//! starts exactly in contact holds its body tangentially from the first Newton iteration, as
//! the restraint check needs. With `mu = 0` the pair is frictionless: every closed point
//! slips with no tangential force.

use super::pair::{ContactPair, ContactPoint};
use crate::vector3::{add, dot, norm, scale, sub};

/// The state of a contact point.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// No contact force.
    #[default]
    Open,
    /// Closed, held tangentially by the stick spring (Coulomb pairs only).
    Stick,
    /// Closed and slipping: on the Coulomb cone (Coulomb pairs), or sliding along the imposed
    /// direction (steady-sliding pairs).
    Slip,
}

impl Status {
    pub fn name(self) -> &'static str {
        match self {
            Status::Open => "open",
            Status::Stick => "stick",
            Status::Slip => "slip",
        }
    }
}

/// The tangential part of the law at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tangential {
    pub status: Status,
    /// Friction force on the slave point (in the tangent plane).
    pub force: [f64; 3],
    /// `d force / d w`, row-major (`[i][j]` = d force_i / d w_j).
    pub jacobian: [[f64; 3]; 3],
    /// The anchor after this state (`a'` in the module doc).
    pub anchor: [f64; 3],
}

/// What the law needs of a point besides its motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLaw {
    /// Unit normal `n`.
    pub normal: [f64; 3],
    /// `mu`.
    pub friction: f64,
    /// `k_n A`.
    pub normal_stiffness: f64,
    /// `k_t A`.
    pub stick_stiffness: f64,
    /// A point whose trial force reaches this fraction below the cone's radius already
    /// slips: a slipping point evaluated again from its committed anchor, whose trial force
    /// is on the cone to round-off, stays slipping ([`COMMITTED_CONE_TOLERANCE`]).
    pub cone_tolerance: f64,
}

/// The return mapping at one point: `w` the relative displacement, `anchor` the slip
/// history, `normal_force` the point's `p` (its normal law's value), `closed` whether the
/// normal law is active.
pub fn return_mapping(
    law: &PointLaw,
    w: [f64; 3],
    anchor: [f64; 3],
    normal_force: f64,
    closed: bool,
) -> Tangential {
    let PointLaw {
        normal,
        friction,
        normal_stiffness,
        stick_stiffness,
        cone_tolerance,
    } = *law;
    let tangential = sub(w, scale(dot(normal, w), normal));
    if !closed || friction == 0.0 {
        return Tangential {
            status: if closed { Status::Slip } else { Status::Open },
            force: [0.0; 3],
            jacobian: [[0.0; 3]; 3],
            anchor: tangential,
        };
    }
    let projector = |i: usize, j: usize| f64::from(u8::from(i == j)) - normal[i] * normal[j];
    // A point pulled apart (a bilateral pair under tension) can carry no friction: it slips
    // with no force whatever its trial force, also when that is exactly zero, as it is from
    // the anchor its slip committed (the slip branch below gives the same at any other
    // trial force). Touching at zero pressure still sticks.
    if normal_force < 0.0 {
        return Tangential {
            status: Status::Slip,
            force: [0.0; 3],
            jacobian: [[0.0; 3]; 3],
            anchor: tangential,
        };
    }
    let trial = scale(-stick_stiffness, sub(tangential, anchor));
    let size = norm(trial);
    let radius = friction * normal_force.max(0.0);
    if size <= radius * (1.0 - cone_tolerance) {
        let mut jacobian = [[0.0; 3]; 3];
        for (i, row) in jacobian.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = -stick_stiffness * projector(i, j);
            }
        }
        return Tangential {
            status: Status::Stick,
            force: trial,
            jacobian,
            anchor,
        };
    }
    let s = scale(1.0 / size, trial);
    let force = scale(radius, s);
    // d radius / d w: -mu k_n A n^T while the pressure is positive, 0 under tension (a
    // bilateral point pulled apart carries no friction).
    let radius_slope = if normal_force > 0.0 {
        -friction * normal_stiffness
    } else {
        0.0
    };
    let shrink = radius / size * stick_stiffness;
    let mut jacobian = [[0.0; 3]; 3];
    for (i, row) in jacobian.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = s[i] * radius_slope * normal[j] - shrink * (projector(i, j) - s[i] * s[j]);
        }
    }
    Tangential {
        status: Status::Slip,
        force,
        jacobian,
        anchor: add(tangential, scale(1.0 / stick_stiffness, force)),
    }
}

/// The slip history of a model's contact points: each Coulomb point's anchor, per pair in
/// the model's order and per point in the pair's. Empty (the default) means no slip yet:
/// every anchor at zero, the state of surfaces that have just closed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SlipHistory {
    anchors: Vec<Vec<[f64; 3]>>,
}

impl SlipHistory {
    /// The anchor of point `point` of pair `pair` (zero when the history has none).
    pub fn anchor(&self, pair: usize, point: usize) -> [f64; 3] {
        self.anchors
            .get(pair)
            .and_then(|p| p.get(point))
            .copied()
            .unwrap_or([0.0; 3])
    }

    /// Every point's anchor, per pair and point (what [`Self::from_anchors`] takes back).
    pub fn anchors(&self) -> &[Vec<[f64; 3]>] {
        &self.anchors
    }

    /// The history of states (each point's anchor after it), per pair and point.
    pub fn from_anchors(anchors: Vec<Vec<[f64; 3]>>) -> Self {
        SlipHistory { anchors }
    }

    /// The histories of the pairs `indices` (in that order), for a model made of those pairs.
    pub fn subset(&self, indices: &[usize]) -> Self {
        SlipHistory {
            anchors: indices
                .iter()
                .map(|&i| self.anchors.get(i).cloned().unwrap_or_default())
                .collect(),
        }
    }
}

/// Every pair's [`PointLaw::cone_tolerance`]: far above the round-off of the anchor update
/// (1e-16 relative), far below any physical distance from the cone. A point evaluated again
/// from the anchor its slip committed (a perturbation step's tangent,
/// [`super::perturbation_history`]) has its trial force on the cone to round-off, and stays
/// slipping whatever that round-off is.
pub const COMMITTED_CONE_TOLERANCE: f64 = 1e-9;

/// The law of a pair's point (`k_t` = 0 for steady sliding).
pub(super) fn point_law(pair: &ContactPair, point: &ContactPoint) -> PointLaw {
    PointLaw {
        normal: point.normal,
        friction: pair.settings.friction,
        normal_stiffness: pair.penalty * point.area,
        stick_stiffness: pair.stick_stiffness().unwrap_or(0.0) * point.area,
        cone_tolerance: COMMITTED_CONE_TOLERANCE,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: [f64; 3] = [0.0, 0.0, 1.0];

    /// Closed with p = k_n A (-w_z): the normal law of a point with zero initial gap.
    fn at(w: [f64; 3], anchor: [f64; 3], mu: f64) -> Tangential {
        let law = PointLaw {
            normal: N,
            friction: mu,
            normal_stiffness: 1e3,
            stick_stiffness: 1e2,
            cone_tolerance: 0.0,
        };
        let p = -law.normal_stiffness * w[2];
        return_mapping(&law, w, anchor, p, p >= 0.0)
    }

    #[test]
    fn sticks_inside_the_cone_and_slips_on_it() {
        // p = 1e3 * 1e-2 = 10, mu p = 3; the spring gives 1e2 * |g_T|.
        let stick = at([0.02, 0.0, -0.01], [0.0; 3], 0.3);
        assert_eq!(stick.status, Status::Stick);
        assert_eq!(stick.force, [-2.0, 0.0, 0.0]);
        let slip = at([0.05, 0.0, -0.01], [0.0; 3], 0.3);
        assert_eq!(slip.status, Status::Slip);
        assert!((norm(slip.force) - 3.0).abs() < 1e-12);
        assert!(slip.force[0] < 0.0);
        // The new anchor puts the spring's force exactly on the cone: evaluated again from it,
        // the same displacement sticks with the same force.
        let again = at([0.05, 0.0, -0.01], slip.anchor, 0.3);
        assert!((again.force[0] - slip.force[0]).abs() < 1e-12);
        // Open: no force, and the slip is forgotten.
        let open = at([0.05, 0.01, 0.01], [0.3, 0.0, 0.0], 0.3);
        assert_eq!(open.status, Status::Open);
        assert_eq!(open.force, [0.0; 3]);
        assert_eq!(open.anchor, [0.05, 0.01, 0.0]);
        // Frictionless: closed points slip freely.
        let free = at([0.05, 0.0, -0.01], [0.0; 3], 0.0);
        assert_eq!((free.status, free.force), (Status::Slip, [0.0; 3]));
    }

    /// Evaluated again from the anchor its slip committed, a slipping point stays slipping
    /// with the full stick stiffness across its slip direction, whatever the round-off of
    /// its trial force (the perturbation tangent, [`super::super::perturbation_history`]);
    /// a point pulled apart (bilateral, under tension) slips with no force and no stiffness,
    /// though its committed trial force is exactly zero.
    #[test]
    fn a_committed_slip_stays_slipping_and_a_pulled_point_carries_no_friction() {
        let law = PointLaw {
            normal: N,
            friction: 0.3,
            normal_stiffness: 1e3,
            stick_stiffness: 1e2,
            cone_tolerance: COMMITTED_CONE_TOLERANCE,
        };
        let w = [0.05, 0.02, -0.01];
        let slip = return_mapping(&law, w, [0.0; 3], 10.0, true);
        assert_eq!(slip.status, Status::Slip);
        let again = return_mapping(&law, w, slip.anchor, 10.0, true);
        assert_eq!(again.status, Status::Slip);
        // Across the slip direction s: the stick stiffness (mu p / |f_trial| = 1); along s
        // and along n: only the friction's mu s (dp/dw).
        let s = scale(1.0 / norm(again.force), again.force);
        let across = [-s[1], s[0], 0.0];
        let along = |v: [f64; 3]| -> [f64; 3] {
            let mut out = [0.0; 3];
            for (i, o) in out.iter_mut().enumerate() {
                *o = (0..3).map(|j| again.jacobian[i][j] * v[j]).sum();
            }
            out
        };
        let k_across = along(across);
        for i in 0..3 {
            assert!((k_across[i] + 1e2 * across[i]).abs() < 1e-9, "{k_across:?}");
            assert!(along(s)[i].abs() < 1e-9, "{:?}", along(s));
        }
        // Under tension (p < 0), from the anchor its slip left: no friction at all.
        let pulled = return_mapping(&law, w, [0.05, 0.02, 0.0], -10.0, true);
        assert_eq!(pulled.status, Status::Slip);
        assert_eq!((pulled.force, pulled.jacobian), ([0.0; 3], [[0.0; 3]; 3]));
        // Touching at zero pressure from rest still sticks (the restraint check's case).
        let touching = return_mapping(&law, [0.0; 3], [0.0; 3], 0.0, true);
        assert_eq!(touching.status, Status::Stick);
    }

    /// The consistent tangent against central differences, in the stick and slip states,
    /// for directions in and out of the tangent plane.
    #[test]
    fn tangent_matches_finite_differences() {
        let cases = [
            ([0.01, -0.004, -0.01], [0.002, 0.001, 0.0], Status::Stick),
            ([0.05, 0.02, -0.01], [0.0, 0.004, 0.0], Status::Slip),
            ([-0.03, 0.07, -0.02], [0.01, -0.01, 0.0], Status::Slip),
        ];
        for (w, anchor, expected) in cases {
            let base = at(w, anchor, 0.3);
            assert_eq!(base.status, expected);
            for j in 0..3 {
                let h = 1e-7;
                let mut plus = w;
                let mut minus = w;
                plus[j] += h;
                minus[j] -= h;
                let (fp, fm) = (at(plus, anchor, 0.3).force, at(minus, anchor, 0.3).force);
                for i in 0..3 {
                    let fd = (fp[i] - fm[i]) / (2.0 * h);
                    let exact = base.jacobian[i][j];
                    let scale = base
                        .jacobian
                        .iter()
                        .flatten()
                        .map(|v| v.abs())
                        .fold(0.0, f64::max);
                    assert!(
                        (fd - exact).abs() <= 1e-6 * scale,
                        "{expected:?} d f_{i}/d w_{j}: exact {exact}, differences {fd}"
                    );
                }
            }
        }
    }

    #[test]
    fn slip_tangent_is_unsymmetric_and_stick_tangent_symmetric() {
        let stick = at([0.01, -0.004, -0.01], [0.0; 3], 0.3).jacobian;
        let slip = at([0.05, 0.02, -0.01], [0.0; 3], 0.3).jacobian;
        let asym = |m: [[f64; 3]; 3]| {
            (0..3)
                .flat_map(|i| (0..3).map(move |j| (i, j)))
                .map(|(i, j)| (m[i][j] - m[j][i]).abs())
                .fold(0.0, f64::max)
        };
        assert_eq!(asym(stick), 0.0);
        assert!(asym(slip) > 1.0);
    }

    #[test]
    fn history_defaults_to_zero_and_subsets_keep_order() {
        let h =
            SlipHistory::from_anchors(vec![vec![[1.0, 0.0, 0.0]], vec![], vec![[0.0, 2.0, 0.0]]]);
        assert_eq!(h.anchor(0, 0), [1.0, 0.0, 0.0]);
        assert_eq!(h.anchor(0, 5), [0.0; 3]);
        assert_eq!(SlipHistory::default().anchor(3, 3), [0.0; 3]);
        let s = h.subset(&[2, 0]);
        assert_eq!(s.anchor(0, 0), [0.0, 2.0, 0.0]);
        assert_eq!(s.anchor(1, 0), [1.0, 0.0, 0.0]);
    }
}
