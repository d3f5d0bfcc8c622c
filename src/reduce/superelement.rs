//! The super-element (METHOD.md section 6; the paper's section 3.2.1) as plain data: a
//! Craig-Bampton reduction of a reduced-interface model at one friction value mu_SE, with
//! the swept (disc/pad) contact removed and every other contact linearised, kept on the
//! reduced contact nodes. Everything the dense assembly needs, and nothing of the mesh, so it
//! can be saved and used without it.
//!
//! Reduced coordinates q, in this order:
//! - boundary: for each node-to-node pair k (pads in order, nodes in grid order), from its
//!   offset o_k ([`SuperElement::boundary_offsets`]), the three displacement components of
//!   the pad contact node c_k, then of the disc node d_k: q[o_k..o_k+3] = u(c_k),
//!   q[o_k+3..o_k+6] = u(d_k); a pair with a patch law ([`BoundaryTilt`]) then has its tilt
//!   nodes: q[o_k+6..o_k+9] = u(r_p), q[o_k+9..o_k+12] = u(r_d), unless it reads another
//!   pair's ([`BoundaryTilt::shared`]: a share whose own nodes lie on one line). 6 or 12 per
//!   pair;
//! - then the fixed-interface modes (mass-normalised, ascending), and last the load's static
//!   correction (the interior response to the external load with the boundary held), which
//!   puts the super-element's own equilibrium exactly in the span of T so that eq. 5 holds
//!   to round-off.
//!
//! u = T q with T = [[I, 0, 0], [Psi, Phi, r]] in (boundary, interior) order.

use serde::{Deserialize, Serialize};

/// One node-to-node contact of the reduced interface, as the super-element keeps it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoundaryPair {
    /// The pair (disc/pad side) it belongs to.
    pub pair: String,
    /// Reference positions of the pad contact node and of the disc node.
    pub pad_position: [f64; 3],
    pub disc_position: [f64; 3],
    /// Unit normal of the disc face, pointing out of the disc (towards the pad).
    pub normal: [f64; 3],
    /// Unit sliding direction (friction on the pad is +mu F t); `None`: no friction.
    pub sliding: Option<[f64; 3]>,
    /// Initial gap g0 (negative = penetration) along `normal`.
    pub initial_gap: f64,
    /// Tributary area and penalty per unit area: the full law's stiffness is penalty * area.
    pub area: f64,
    pub penalty: f64,
    /// Whether the pair may open.
    pub separation: bool,
    /// Normal contact force of the full (penalty) law at the super-element's equilibrium,
    /// N (>= 0; 0 when open): F_nl of eq. 8.
    pub normal_force: f64,
    /// The patch law of a reduced interface with tilt nodes ([`crate::contact::Tilt`]):
    /// the pair's law is then the reduced-interface model's own, and its tilt nodes are on
    /// the boundary. `None`: a point contact (the paper's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt: Option<BoundaryTilt>,
    /// A kept pair reduced onto the boundary (issue 32: an interior that holds no contact):
    /// its own settings, friction, law (Coulomb stick and slip with its history along the
    /// sweep) and separation, which the swept friction does not change; the assembly
    /// evaluates it with the full model's code ([`crate::contact::evaluate`]). `None`: a
    /// swept pair, its friction the sweep's along `sliding`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub own_law: Option<crate::contact::PairSettings>,
}

/// A boundary pair's patch law without its nodes (they are the pair's boundary coordinates
/// 6..12, or another pair's, [`Self::shared`]): what [`crate::contact::Tilt`] holds besides
/// them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoundaryTilt {
    /// Unit in-plane axes e_1, e_2 (orthogonal to the normal).
    pub axes: [[f64; 3]; 2],
    /// The share of the pad face: (offset along the axes, area) per quadrature point.
    pub patch: Vec<([f64; 2], f64)>,
    /// theta = e . (u_rp - u_rd) / arm.
    pub arm: f64,
    /// The boundary pair (index in [`SuperElementHeader::boundary`]) whose tilt nodes this
    /// one's law reads: a share of the pad face on one line has no slope of its own and
    /// takes its nearest neighbour's ([`crate::reduce::tilt::slope_owners`]); `None`: its
    /// own, at q[o_k+6..o_k+12]. The owner holds its own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shared: Option<usize>,
}

impl BoundaryPair {
    /// Whether it is a swept pair (the sweep's friction acts on it), not a kept pair
    /// reduced onto the boundary.
    pub fn swept(&self) -> bool {
        self.own_law.is_none()
    }

    /// Its reduced coordinates: 6 (c, d), or 12 with tilt nodes of its own (c, d, r_p, r_d).
    pub fn width(&self) -> usize {
        match &self.tilt {
            Some(t) if t.shared.is_none() => 12,
            _ => 6,
        }
    }
}

/// Where a super-element came from and what it holds (the file's header).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SuperElementHeader {
    /// "SI" or whatever the mesh uses; frequencies assume seconds.
    pub units: String,
    /// The friction value of the swept pairs at which it was made.
    pub friction: f64,
    /// Fixed-interface modes kept up to this frequency (Hz).
    pub cutoff_hz: f64,
    /// Interior basis vectors: the fixed-interface modes kept (with a kept frictional
    /// contact, the M_II-orthonormal span of the real and imaginary parts of the right
    /// eigenvectors of the unsymmetric (K_II, M_II)).
    pub modes: usize,
    /// Reduced size: 6 per boundary pair (12 with a patch law) + modes + 1 (the static
    /// correction) + residual vectors.
    pub size: usize,
    /// Residual vectors after the static correction ([`super::residual_vectors`]).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub residual_vectors: usize,
    /// State of every other (non-swept) contact pair's points at the equilibrium: per pair,
    /// its name and each point's state, open, stick or slip (a change means a new
    /// super-element).
    pub other_contacts: Vec<(String, Vec<crate::contact::Status>)>,
    /// Hashes of the mesh and of the settings it came from (hex: the model tables, the
    /// reduction and the analysis of the study), to refuse another's.
    pub mesh_hash: String,
    pub study_hash: String,
    pub boundary: Vec<BoundaryPair>,
}

/// A super-element: its header and the dense reduced operators.
#[derive(Clone, Debug)]
pub struct SuperElement {
    pub header: SuperElementHeader,
    /// K_r = T^T K_t T (without the swept contact; unsymmetric allowed), size x size.
    pub stiffness: faer::Mat<f64>,
    /// M_r = T^T M T, symmetric positive definite.
    pub mass: faer::Mat<f64>,
    /// T^T F_ext.
    pub load: Vec<f64>,
    /// q_s: the reduced coordinates of the equilibrium it was made at.
    pub equilibrium: Vec<f64>,
}

impl SuperElement {
    /// Index of the first modal coordinate (after the boundary).
    pub fn boundary_size(&self) -> usize {
        self.header.boundary_size()
    }

    /// Where each boundary pair's coordinates start in q.
    pub fn boundary_offsets(&self) -> Vec<usize> {
        self.header.boundary_offsets()
    }
}

impl SuperElementHeader {
    /// The boundary's coordinates: the pairs' widths added up.
    pub fn boundary_size(&self) -> usize {
        self.boundary.iter().map(BoundaryPair::width).sum()
    }

    /// Where each boundary pair's coordinates start in q.
    pub fn boundary_offsets(&self) -> Vec<usize> {
        self.boundary
            .iter()
            .scan(0, |at, b| {
                let start = *at;
                *at += b.width();
                Some(start)
            })
            .collect()
    }

    /// Where each boundary pair's patch law reads its tilt nodes r_p, r_d in q (6
    /// coordinates from there): its own after c and d, or its owner's
    /// ([`BoundaryTilt::shared`]); `None` for a point contact, or a share naming a pair that
    /// has no tilt nodes of its own (which [`crate::reduce::superelement_file`] refuses).
    pub fn tilt_offsets(&self) -> Vec<Option<usize>> {
        let offsets = self.boundary_offsets();
        self.boundary
            .iter()
            .zip(&offsets)
            .map(|(b, &at)| match b.tilt.as_ref()?.shared {
                None => Some(at + 6),
                Some(owner) => {
                    let o = self.boundary.get(owner)?;
                    (o.tilt.as_ref()?.shared.is_none()).then(|| offsets[owner] + 6)
                }
            })
            .collect()
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}
