//! The penalty contact law at one contact point, with steady-sliding friction (METHOD.md
//! section 2) or Coulomb stick/slip ([`super::coulomb`]), its Jacobian, and a pair's summary.
//!
//! With `c_k` the signed weights of a point's nodes (`+w_s` on the slave side, `-N_j` on the
//! master side), `n` and `t` fixed (small sliding):
//!
//! ```text
//!   g = g0 + n . sum_k c_k u_k                    gap, negative = penetration
//!   p = k A max(0, -g)   (separation allowed)     normal force, >= 0
//!   p = k A (-g)         (bilateral)              may be negative (pull)
//!   F = p n + mu p t                              contact force on the slave point
//!   f_k = c_k F                                   nodal contact forces (they sum to 0)
//!   r_k = -f_k                                    residual, internal-force convention
//!   dr_k/du_m = k A c_k c_m (n + mu t) n^T        where the point is closed
//! ```
//!
//! The residual follows the internal-force convention of `K u + F_c(u) - F_ext = 0`: a
//! penetrating slave node gets `r = -p n`, pushing it back out through the equation. The
//! friction block `mu k A c_k c_m t n^T` is what makes the tangent unsymmetric.
//!
//! A point with separation allowed is closed when `g <= 0`: touching counts as closed, so
//! that surfaces that start exactly in contact (`g0 = 0`, the usual case) have their contact
//! stiffness at the first Newton iteration. Bilateral points are always closed. With
//! friction, a bilateral point under tension (`p < 0`) gets `mu p t`, against `t`: the law of
//! METHOD.md as written.
//!
//! A Coulomb pair replaces `mu p t` by the return mapping's friction force `f_T` and its
//! block by `k A n n^T - d f_T/dw` ([`super::coulomb`]); its point state carries the slip
//! anchor the next increment starts from.

use super::coulomb::{self, Status, Tangential};
use super::pair::{ContactPair, ContactPoint, FrictionLaw, SlidingDirection, Tilt};
use super::zone::ZoneStiffness;
use super::ContactError;
use crate::vector3::{add, cross, dot, norm, scale, sub};

/// The state of one contact point for a displacement field (and, for a Coulomb pair, the
/// point's slip history).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointState {
    /// Gap `g`; negative = penetration.
    pub gap: f64,
    /// Normal force on the slave `p` (`>= 0` with separation; bilateral: `k A (-g)`, which
    /// may be negative).
    pub normal_force: f64,
    /// Contact pressure `p / A`.
    pub pressure: f64,
    /// Whether the force law is active: `g <= 0` with separation, always when bilateral.
    pub closed: bool,
    /// Open, stick or slip (a closed steady-sliding point slips).
    pub status: Status,
    /// Friction force on the slave point: `mu p t` (steady sliding) or the Coulomb law's.
    pub friction_force: [f64; 3],
    /// The point's slip anchor after this state (Coulomb pairs; zero otherwise): the history
    /// to carry on when this state is accepted.
    pub anchor: [f64; 3],
    /// `d normal_force / d overclosure` (the whole share's for a patch law).
    pub slope: f64,
    /// The patch's tilt (a patch law's, [`crate::contact::Tilt::theta`]; zero otherwise).
    pub theta: [f64; 2],
}

/// A closed point's contribution to the global residual and Jacobian.
#[derive(Clone, Debug, PartialEq)]
pub struct PointContribution {
    /// The point's nodes: slave nodes then master nodes, in the point's order. A node may
    /// appear twice (self-contact): contributions are to be added.
    pub nodes: Vec<usize>,
    /// 3 per node (node-major): minus the contact force on each node (internal-force
    /// convention, see the module doc).
    pub residual: Vec<f64>,
    /// `(3 n) x (3 n)` row-major: `d residual / d u` of those nodes. Unsymmetric with
    /// friction.
    pub jacobian: Vec<f64>,
}

fn displacement(pair: &ContactPair, u: &[[f64; 3]], node: usize) -> Result<[f64; 3], ContactError> {
    u.get(node)
        .copied()
        .ok_or_else(|| ContactError::NodeOutOfRange {
            pair: pair.settings.name.clone(),
            node,
            nodes: u.len(),
        })
}

/// The signed weights `c_k` of a point: `+w` for slave nodes, `-N_j` for master nodes.
fn signed_weights(point: &ContactPoint) -> impl Iterator<Item = (usize, f64)> + '_ {
    point
        .slave
        .iter()
        .copied()
        .chain(point.master.iter().map(|&(n, w)| (n, -w)))
}

/// The relative displacement `w = sum c_k u_k` of the slave point from the master point.
fn relative(
    pair: &ContactPair,
    point: &ContactPoint,
    u: &[[f64; 3]],
) -> Result<[f64; 3], ContactError> {
    let mut w = [0.0; 3];
    for (node, c) in signed_weights(point) {
        w = add(w, scale(c, displacement(pair, u, node)?));
    }
    Ok(w)
}

/// The normal law at `point` for relative displacement `w`, and the Coulomb return mapping
/// from `anchor` for a Coulomb pair (ignored otherwise).
fn state_and_tangential(
    pair: &ContactPair,
    point: &ContactPoint,
    anchor: [f64; 3],
    w: [f64; 3],
    theta: [f64; 2],
) -> (PointState, Option<Tangential>) {
    let gap = point.initial_gap + dot(point.normal, w);
    let (closed, normal_force, slope) = match &point.tilt {
        Some(tilt) => {
            let l = tilt.law(gap, theta);
            (l.k0 > 0.0, l.force, l.k0)
        }
        None => normal_law(pair, point, gap),
    };
    let mut state = PointState {
        gap,
        normal_force,
        pressure: normal_force / point.area,
        closed,
        status: if closed { Status::Slip } else { Status::Open },
        friction_force: [0.0; 3],
        anchor: [0.0; 3],
        slope,
        theta,
    };
    match pair.settings.law {
        FrictionLaw::SteadySliding => {
            if let (true, Some(t)) = (closed, point.tangent) {
                state.friction_force = scale(pair.settings.friction * normal_force, t);
            }
            (state, None)
        }
        FrictionLaw::Coulomb { .. } => {
            let mut law = coulomb::point_law(pair, point);
            // The friction radius follows the normal force's own slope.
            law.normal_stiffness = slope;
            let tangential = coulomb::return_mapping(&law, w, anchor, normal_force, closed);
            state.status = tangential.status;
            state.friction_force = tangential.force;
            state.anchor = tangential.anchor;
            (state, Some(tangential))
        }
    }
}

/// Whether the normal law acts at `gap`, the normal force on the slave and its slope
/// `d force / d overclosure`: squeal's `k A max(0, -g)` (bilateral: `k A (-g)`), or
/// CalculiX's smoothed law for a pair with it ([`super::variant`]; its bilateral pairs keep
/// squeal's, CalculiX having none).
fn normal_law(pair: &ContactPair, point: &ContactPoint, gap: f64) -> (bool, f64, f64) {
    let stiffness = pair.penalty * point.area;
    match pair.settings.calculix {
        Some(law) if pair.settings.separation => {
            law.normal(pair.penalty, point.area, point.initial_gap, gap)
        }
        _ => {
            let closed = !pair.settings.separation || gap <= 0.0;
            let force = if closed { -stiffness * gap } else { 0.0 };
            (closed, force, stiffness)
        }
    }
}

/// Gap, normal force, pressure and friction state at `point` for nodal displacements `u`
/// (indexed by node); `anchor` is the point's slip history (Coulomb pairs; ignored
/// otherwise). `Err` if the point refers to a node `u` does not have.
pub fn point_state(
    pair: &ContactPair,
    point: &ContactPoint,
    anchor: [f64; 3],
    u: &[[f64; 3]],
) -> Result<PointState, ContactError> {
    let w = relative(pair, point, u)?;
    let theta = tilt_of(pair, point, u)?;
    Ok(state_and_tangential(pair, point, anchor, w, theta).0)
}

/// The patch's tilt theta of a point with a tilt law (zero without).
fn tilt_of(
    pair: &ContactPair,
    point: &ContactPoint,
    u: &[[f64; 3]],
) -> Result<[f64; 2], ContactError> {
    match &point.tilt {
        Some(t) => {
            let (p, d) = (
                displacement(pair, u, t.nodes[0])?,
                displacement(pair, u, t.nodes[1])?,
            );
            Ok(t.theta(sub(p, d)))
        }
        None => Ok([0.0; 2]),
    }
}

/// The contact force on the slave point, `p n` plus the friction force, for a state.
fn slave_force(point: &ContactPoint, state: &PointState) -> [f64; 3] {
    add(
        scale(state.normal_force, point.normal),
        state.friction_force,
    )
}

/// The state of `point` and, when closed, its contribution to the residual and Jacobian (see
/// the module doc); `anchor` as for [`point_state`]. `Err` if the point refers to a node `u`
/// does not have.
pub fn evaluate(
    pair: &ContactPair,
    point: &ContactPoint,
    anchor: [f64; 3],
    u: &[[f64; 3]],
) -> Result<(PointState, Option<PointContribution>), ContactError> {
    let w = relative(pair, point, u)?;
    let theta = tilt_of(pair, point, u)?;
    let (state, tangential) = state_and_tangential(pair, point, anchor, w, theta);
    if !state.closed {
        return Ok((state, None));
    }
    let weights: Vec<(usize, f64)> = signed_weights(point).collect();
    let force = slave_force(point, &state);
    let n = point.normal;
    // The normal force's slope: k A, or the CalculiX law's at this gap, or the patch's.
    let patch = point.tilt.as_ref().map(|t| t.law(state.gap, theta));
    let stiffness = match &patch {
        Some(l) => l.k0,
        None => normal_law(pair, point, state.gap).2,
    };
    let size = 3 * weights.len();
    let mut residual = vec![0.0; size];
    let mut jacobian = vec![0.0; size * size];
    // -dF/dw, F the force on the slave point: k A (n + mu t) n^T for steady sliding,
    // k A n n^T - d f_T/dw for Coulomb.
    let block: [[f64; 3]; 3] = match tangential {
        None => {
            // Direction of the force's change with the approach: (n + mu t), times n^T.
            let mut direction = n;
            if let Some(t) = point.tangent {
                direction = add(direction, scale(pair.settings.friction, t));
            }
            [0, 1, 2].map(|i| [0, 1, 2].map(|j| direction[i] * n[j]))
        }
        Some(t) => [0, 1, 2].map(|i| [0, 1, 2].map(|j| n[i] * n[j] - t.jacobian[i][j] / stiffness)),
    };
    for (k, &(_, ck)) in weights.iter().enumerate() {
        for i in 0..3 {
            residual[3 * k + i] = -ck * force[i];
        }
        for (m, &(_, cm)) in weights.iter().enumerate() {
            // Products grouped so that the frictionless blocks are symmetric bit for bit.
            let s = stiffness * (ck * cm);
            for i in 0..3 {
                for j in 0..3 {
                    jacobian[(3 * k + i) * size + 3 * m + j] = s * block[i][j];
                }
            }
        }
    }
    let mut contribution = PointContribution {
        nodes: weights.iter().map(|&(node, _)| node).collect(),
        residual,
        jacobian,
    };
    if let (Some(tilt), Some(law)) = (&point.tilt, &patch) {
        // The direction the force on the slave changes in with the patch's tilt: the
        // normal, and the friction where it follows the normal force: a steady-sliding
        // point's mu t, a slipping Coulomb point's f_T / p (on the cone |f_T| = mu p, its
        // direction set by the tangential motion alone). A sticking point's friction is its
        // spring's, whatever p.
        let direction = match &tangential {
            None => point
                .tangent
                .map_or(n, |t| add(n, scale(pair.settings.friction, t))),
            Some(t) if t.status == Status::Slip && state.normal_force > 0.0 => {
                add(n, scale(1.0 / state.normal_force, t.force))
            }
            Some(_) => n,
        };
        contribution.add_patch(tilt, law, &weights, direction, n);
    }
    Ok((state, Some(contribution)))
}

impl PointContribution {
    /// Appends the tilt nodes' rows and columns of a patch law (see [`Tilt`]): with
    /// E = sum_j (k_n a_j / 2) max(0, -g_j)^2, g_j = g + theta . xi_j,
    /// theta = e . (u_rp - u_rd) / arm, r_p's internal force -sum_a M_a e_a / arm (r_d's the
    /// opposite), and, for r_p (r_d with the opposite sign),
    /// d r_k / d u_rp = c_k d (sum_a k1_a e_a)^T / arm, d r_rp / d u_m = c_m (sum_a k1_a e_a)
    /// n^T / arm, d r_rp / d u_rp = sum_ab k2_ab e_a e_b^T / arm^2 (symmetric without
    /// friction).
    fn add_patch(
        &mut self,
        tilt: &Tilt,
        law: &super::pair::PatchLaw,
        weights: &[(usize, f64)],
        direction: [f64; 3],
        n: [f64; 3],
    ) {
        let e = tilt.axes;
        let arm = tilt.arm;
        let k1e: [f64; 3] = [0, 1, 2].map(|i| (law.k1[0] * e[0][i] + law.k1[1] * e[1][i]) / arm);
        let k2: [[f64; 3]; 3] = [0, 1, 2].map(|i| {
            [0, 1, 2].map(|j| {
                let mut s = 0.0;
                for a in 0..2 {
                    for b in 0..2 {
                        s += law.k2[a][b] * e[a][i] * e[b][j];
                    }
                }
                s / (arm * arm)
            })
        });
        let old = 3 * self.nodes.len();
        let size = old + 6;
        let mut jacobian = vec![0.0; size * size];
        for i in 0..old {
            jacobian[i * size..i * size + old]
                .copy_from_slice(&self.jacobian[i * old..(i + 1) * old]);
        }
        // r_p enters theta with +1, r_d with -1.
        let sides = [(old, 1.0), (old + 3, -1.0)];
        for &(at, sign) in &sides {
            for (k, &(_, ck)) in weights.iter().enumerate() {
                for i in 0..3 {
                    for j in 0..3 {
                        jacobian[(3 * k + i) * size + at + j] = sign * ck * direction[i] * k1e[j];
                        jacobian[(at + i) * size + 3 * k + j] = sign * ck * k1e[i] * n[j];
                    }
                }
            }
            for &(at2, sign2) in &sides {
                for i in 0..3 {
                    for j in 0..3 {
                        jacobian[(at + i) * size + at2 + j] = sign * sign2 * k2[i][j];
                    }
                }
            }
        }
        // The tilt nodes' internal force: -sum_a M_a e_a / arm on r_p, its opposite on r_d.
        let moment: [f64; 3] =
            [0, 1, 2].map(|i| (law.moment[0] * e[0][i] + law.moment[1] * e[1][i]) / arm);
        for &(_, sign) in &sides {
            self.residual.extend(moment.map(|m| -sign * m));
        }
        self.nodes.extend(tilt.nodes);
        self.jacobian = jacobian;
    }
}

/// Pressure statistics over the closed points of a pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PressureRange {
    pub min: f64,
    pub max: f64,
    /// Arithmetic mean over the closed points (the area-weighted mean is
    /// `normal_force / closed_area`).
    pub mean: f64,
}

/// A pair's state for a displacement field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairSummary {
    pub points: usize,
    pub closed: usize,
    /// Closed points sticking (Coulomb pairs).
    pub stick: usize,
    /// Closed points slipping (every closed point of a steady-sliding pair).
    pub slip: usize,
    /// Sum of the normal forces `p` on the slave points.
    pub normal_force: f64,
    /// Sum of the friction forces on the slave points (`mu p t` for steady sliding).
    pub friction_force: [f64; 3],
    /// Sum of the contact forces `p n + mu p t` on the slave points (the master side gets the
    /// opposite).
    pub force_on_slave: [f64; 3],
    /// Sum of the tributary areas of the closed points.
    pub closed_area: f64,
    /// Moment of the friction forces on the slave about the disc's axis (a pair sliding by
    /// [`SlidingDirection::DiscRotation`]; 0 otherwise): the braking torque, signed along
    /// the axis as given.
    pub braking_torque: f64,
    /// braking_torque / (mu N): where the friction acts on average, between the pad's inner
    /// and outer radius when the pad slides everywhere it touches (0 without friction).
    pub effective_radius: f64,
    /// `None` when no point is closed.
    pub pressure: Option<PressureRange>,
    /// The closed zone's normal stiffness and its moments ([`super::zone`]).
    pub zone: ZoneStiffness,
}

/// Totals and pressure range of `pair` for nodal displacements `u` and the pair's slip
/// anchors (one per point; empty: none).
pub fn summarize(
    pair: &ContactPair,
    anchors: &[[f64; 3]],
    u: &[[f64; 3]],
) -> Result<PairSummary, ContactError> {
    let states = pair
        .points
        .iter()
        .enumerate()
        .map(|(k, point)| point_state(pair, point, anchors.get(k).copied().unwrap_or_default(), u))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(summarize_states(pair, &states))
}

/// Totals and pressure range of `pair` for given point states (one per point, in order):
/// what another force law (the super-element assembly's cubic one) gives on the same points.
pub fn summarize_states(pair: &ContactPair, states: &[PointState]) -> PairSummary {
    let mut summary = PairSummary {
        points: pair.points.len(),
        closed: 0,
        stick: 0,
        slip: 0,
        normal_force: 0.0,
        friction_force: [0.0; 3],
        force_on_slave: [0.0; 3],
        closed_area: 0.0,
        braking_torque: 0.0,
        effective_radius: 0.0,
        pressure: None,
        zone: zone_stiffness(pair, states),
    };
    let axis = match &pair.settings.sliding {
        SlidingDirection::DiscRotation { centre, axis, .. } => {
            Some((*centre, scale(1.0 / norm(*axis), *axis)))
        }
        _ => None,
    };
    let mut range = PressureRange {
        min: f64::INFINITY,
        max: f64::NEG_INFINITY,
        mean: 0.0,
    };
    for (point, state) in pair.points.iter().zip(states) {
        if !state.closed {
            continue;
        }
        summary.closed += 1;
        match state.status {
            Status::Stick => summary.stick += 1,
            _ => summary.slip += 1,
        }
        summary.closed_area += point.area;
        summary.normal_force += state.normal_force;
        let force = slave_force(point, state);
        summary.force_on_slave = add(summary.force_on_slave, force);
        let friction = state.friction_force;
        summary.friction_force = add(summary.friction_force, friction);
        if let Some((centre, a)) = axis {
            summary.braking_torque += dot(a, cross(sub(point.position, centre), friction));
        }
        range.min = range.min.min(state.pressure);
        range.max = range.max.max(state.pressure);
        range.mean += state.pressure;
    }
    if summary.closed > 0 {
        range.mean /= summary.closed as f64;
        summary.pressure = Some(range);
    }
    let mu_n = pair.settings.friction * summary.normal_force;
    if mu_n > 0.0 {
        summary.effective_radius = summary.braking_torque / mu_n;
    }
    summary
}

/// The closed zone of `pair` in the states `states` (one per point, in order, as
/// [`super::point_state`] gives them).
pub fn zone_stiffness(pair: &ContactPair, states: &[PointState]) -> ZoneStiffness {
    let mut zone = ZoneStiffness::default();
    for (point, state) in pair.points.iter().zip(states) {
        if !state.closed {
            continue;
        }
        match &point.tilt {
            None => zone.add(state.slope, point.position),
            Some(tilt) => {
                for &(xi, a) in &tilt.patch {
                    if !tilt.acts(state.gap + state.theta[0] * xi[0] + state.theta[1] * xi[1]) {
                        continue;
                    }
                    let at = [0, 1, 2].map(|c| {
                        point.position[c] + xi[0] * tilt.axes[0][c] + xi[1] * tilt.axes[1][c]
                    });
                    zone.add(tilt.penalty * a, at);
                }
            }
        }
    }
    zone
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::pair::{node_to_node, node_to_surface, PairSettings, SlidingDirection};
    use crate::contact::project::SearchOptions;
    use crate::contact::test_models::pad_on_disc;
    use crate::mesh::Mesh;
    use crate::vector3::{cross, norm, sub};

    struct Lcg(u64);
    impl Lcg {
        /// Uniform in [-1, 1).
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            2.0 * ((self.0 >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        }
    }

    fn pair(
        mesh: &Mesh,
        friction: f64,
        separation: bool,
        sliding: SlidingDirection,
    ) -> ContactPair {
        node_to_surface(
            mesh,
            &mesh.surfaces["pad.z0"],
            &mesh.surfaces["z1"],
            PairSettings {
                name: "disc/pad".into(),
                friction,
                penalty: Some(1e11),
                separation,
                sliding,
                law: crate::contact::FrictionLaw::SteadySliding,
                calculix: None,
            },
            &SearchOptions::default(),
        )
        .unwrap()
    }

    fn rotation() -> SlidingDirection {
        SlidingDirection::DiscRotation {
            centre: [0.45, 0.5, 0.0],
            axis: [0.0, 0.0, 1.0],
            sense: 1.0,
        }
    }

    /// Random displacements of size `amplitude`, plus `shift` on the pad's nodes (all nodes
    /// past the disc's).
    fn displacements(mesh: &Mesh, seed: u64, amplitude: f64, shift: [f64; 3]) -> Vec<[f64; 3]> {
        let mut rng = Lcg(seed);
        let pad_start = mesh.node_sets["pad.z0"][0];
        (0..mesh.nodes.len())
            .map(|n| {
                let r = [rng.next(), rng.next(), rng.next()].map(|c| amplitude * c);
                if n >= pad_start {
                    add(r, shift)
                } else {
                    r
                }
            })
            .collect()
    }

    /// Checks every closed point's Jacobian against central differences of its residual.
    ///
    /// With `n` and `t` fixed the residual is linear in `u` on each side of the kink `g = 0`,
    /// so central differences have no truncation error at all; only round-off remains,
    /// about `eps |r| / h` relative to the entries `k A`. With `|g| ~ 1e-3` and `h = 1e-7`
    /// that is ~1e-12, far below the 1e-6 asked for, while the step moves `g` by at most
    /// `2 h` (the weights are <= 1 in size), which does not cross the kink when `|g| > 2h`:
    /// points nearer the kink are skipped (and counted, to see that few are).
    /// Returns the number of closed points checked.
    fn check_jacobian(pair: &ContactPair, u: &[[f64; 3]]) -> usize {
        check_jacobian_from(pair, &[], u).0
    }

    /// [`check_jacobian`] from slip anchors (Coulomb pairs). A Coulomb point in slip has a
    /// residual that is not linear (the slip direction turns): central differences then
    /// carry a truncation error of order (h / |g_T - a|)^2 ~ 1e-8 here. Points whose state
    /// changes within the step (the stick/slip kink) are skipped. Returns (points checked,
    /// of which sticking, of which slipping).
    fn check_jacobian_from(
        pair: &ContactPair,
        anchors: &[[f64; 3]],
        u: &[[f64; 3]],
    ) -> (usize, usize, usize) {
        let h = 1e-7;
        let (mut checked, mut stick, mut slip) = (0, 0, 0);
        for (k, point) in pair.points.iter().enumerate() {
            let anchor = anchors.get(k).copied().unwrap_or_default();
            let (state, contribution) = evaluate(pair, point, anchor, u).unwrap();
            let Some(c) = contribution else {
                assert!(!state.closed && state.normal_force == 0.0);
                continue;
            };
            if state.gap.abs() <= 2.0 * h && pair.settings.separation {
                continue;
            }
            let same_state = c.nodes.iter().all(|&node| {
                (0..3).all(|j| {
                    [h, -h].iter().all(|d| {
                        let mut v = u.to_vec();
                        v[node][j] += d;
                        point_state(pair, point, anchor, &v).unwrap().status == state.status
                    })
                })
            });
            if !same_state {
                continue;
            }
            checked += 1;
            match state.status {
                Status::Stick => stick += 1,
                _ => slip += 1,
            }
            let size = 3 * c.nodes.len();
            let scale_j = c.jacobian.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            for (m, &node) in c.nodes.iter().enumerate() {
                for j in 0..3 {
                    let mut up = u.to_vec();
                    let mut um = u.to_vec();
                    up[node][j] += h;
                    um[node][j] -= h;
                    let rp = evaluate(pair, point, anchor, &up)
                        .unwrap()
                        .1
                        .unwrap()
                        .residual;
                    let rm = evaluate(pair, point, anchor, &um)
                        .unwrap()
                        .1
                        .unwrap()
                        .residual;
                    for row in 0..size {
                        let fd = (rp[row] - rm[row]) / (2.0 * h);
                        let exact = c.jacobian[row * size + 3 * m + j];
                        assert!(
                            (fd - exact).abs() <= 1e-6 * scale_j,
                            "row {row}, column {}: {fd} vs {exact}",
                            3 * m + j
                        );
                    }
                }
            }
        }
        (checked, stick, slip)
    }

    /// A Coulomb pair's Jacobian against central differences of its residual, with points
    /// sticking and slipping (anchors spread so that some points' springs reach the cone and
    /// others do not), bilateral and with separation.
    #[test]
    fn coulomb_jacobian_matches_finite_differences_in_stick_and_slip() {
        let mesh = pad_on_disc(1e-3);
        for separation in [true, false] {
            let mut p = pair(&mesh, 0.3, separation, SlidingDirection::None);
            p.settings.law = crate::contact::FrictionLaw::Coulomb {
                stick_stiffness: Some(1e10),
            };
            // Pressed 3e-3 down (p ~ k A 2e-3), slid 2e-3 along x relative to the disc on
            // average: the spring's force k_t A |g_T - a| against mu p = 0.3 k_n A 2e-3 with
            // k_t = k_n / 10: the anchors decide which points slip.
            let u = displacements(&mesh, 7, 5e-4, [2e-3, 0.0, -3e-3]);
            let mut rng = Lcg(11);
            let anchors: Vec<[f64; 3]> = (0..p.points.len())
                .map(|_| [2e-3 + 8e-3 * rng.next(), 4e-3 * rng.next(), 0.0])
                .collect();
            let (checked, stick, slip) = check_jacobian_from(&p, &anchors, &u);
            assert!(
                stick > 0 && slip > 0,
                "stick {stick}, slip {slip} of {checked}"
            );
            assert!(
                checked >= p.points.len() * 3 / 4,
                "{checked} of {}",
                p.points.len()
            );
            // Action = reaction: the nodal residuals of every point sum to zero.
            for (k, point) in p.points.iter().enumerate() {
                if let (_, Some(c)) = evaluate(&p, point, anchors[k], &u).unwrap() {
                    for i in 0..3 {
                        let sum: f64 = c.residual.iter().skip(i).step_by(3).sum();
                        let size = c.residual.iter().fold(0.0f64, |a, b| a.max(b.abs()));
                        assert!(sum.abs() <= 1e-12 * size);
                    }
                }
            }
        }
    }

    #[test]
    fn jacobian_matches_finite_differences_in_every_state() {
        // Pad 1e-3 above the disc; random displacements of 5e-4 on every node.
        let mesh = pad_on_disc(1e-3);
        let friction = pair(&mesh, 0.5, true, rotation());
        // Open: pad lifted by 1e-3 more; nothing is closed and the residual is zero.
        let u = displacements(&mesh, 1, 5e-4, [0.0, 0.0, 1e-3]);
        assert_eq!(check_jacobian(&friction, &u), 0);
        assert_eq!(summarize(&friction, &[], &u).unwrap().closed, 0);
        // Closed, sliding with friction: pad pushed 3e-3 down, every point penetrates.
        let u = displacements(&mesh, 2, 5e-4, [0.0, 0.0, -3e-3]);
        assert_eq!(check_jacobian(&friction, &u), friction.points.len());
        // Partly closed: pad pushed 1e-3 down, gaps -1e-3 +- 1e-3.
        let u = displacements(&mesh, 3, 5e-4, [0.0, 0.0, -1e-3]);
        let closed = check_jacobian(&friction, &u);
        assert!(closed > 0 && closed < friction.points.len(), "{closed}");
        // Bilateral, in tension and in compression: every point contributes.
        let tied = pair(&mesh, 0.15, false, SlidingDirection::Fixed([1.0, 1.0, 0.0]));
        for shift in [2e-3, -3e-3] {
            let u = displacements(&mesh, 4, 5e-4, [0.0, 0.0, shift]);
            assert_eq!(check_jacobian(&tied, &u), tied.points.len());
        }
    }

    #[test]
    fn friction_makes_the_jacobian_unsymmetric_and_frictionless_is_symmetric() {
        let mesh = pad_on_disc(0.0);
        let u = displacements(&mesh, 5, 1e-4, [0.0, 0.0, -1e-3]);
        for (mu, sliding) in [
            (0.0, rotation()),
            (0.5, SlidingDirection::None),
            (0.5, rotation()),
        ] {
            let p = pair(&mesh, mu, true, sliding.clone());
            let mut asymmetry = 0.0f64;
            let mut largest = 0.0f64;
            for point in &p.points {
                let c = evaluate(&p, point, [0.0; 3], &u).unwrap().1.unwrap();
                let size = 3 * c.nodes.len();
                for i in 0..size {
                    for j in 0..size {
                        let (a, b) = (c.jacobian[i * size + j], c.jacobian[j * size + i]);
                        asymmetry = asymmetry.max((a - b).abs());
                        largest = largest.max(a.abs());
                    }
                }
            }
            if mu > 0.0 && sliding != SlidingDirection::None {
                // mu k A c_k c_m (t n^T - n t^T): entries of mu times the normal ones.
                assert!(asymmetry > 0.1 * mu * largest, "{asymmetry} vs {largest}");
            } else {
                // Without friction the blocks are k A c_k c_m n n^T: symmetric bit for bit.
                assert_eq!(asymmetry, 0.0);
            }
        }
    }

    #[test]
    fn action_equals_reaction_and_moments_balance() {
        // Forces f_k = c_k F with sum c_k = 1 - sum N_j = 0 up to round-off, so the nodal
        // forces of each point sum to ~eps |F|. Moments about the origin: sum c_k x_k x F =
        // (x_s - x_m) x F = g0 n x F, zero when g0 = 0 (the pad starts on the disc).
        let mesh = pad_on_disc(0.0);
        let p = pair(&mesh, 0.5, true, rotation());
        let u = displacements(&mesh, 6, 1e-4, [0.0, 0.0, -1e-3]);
        let mut total = [0.0; 3];
        let mut moment = [0.0; 3];
        let mut scale_f = 0.0f64;
        for point in &p.points {
            let c = evaluate(&p, point, [0.0; 3], &u).unwrap().1.unwrap();
            let mut point_total = [0.0; 3];
            for (k, &node) in c.nodes.iter().enumerate() {
                let f = [0, 1, 2].map(|i| -c.residual[3 * k + i]);
                point_total = add(point_total, f);
                moment = add(moment, cross(mesh.nodes[node], f));
                scale_f = scale_f.max(norm(f));
            }
            assert!(norm(point_total) <= 1e-14 * scale_f, "{point_total:?}");
            total = add(total, point_total);
        }
        assert!(norm(total) <= 1e-13 * scale_f, "{total:?}");
        assert!(norm(moment) <= 1e-13 * scale_f, "{moment:?}");
    }

    #[test]
    fn uniform_penetration_gives_k_a_delta_and_friction_mu_n() {
        // Pad pressed by delta everywhere: g = -delta at every slave node, p = k A_s delta,
        // total N = k delta sum A_s = k delta 0.15 (the tributary areas tile the pad's
        // 0.5 x 0.3 bottom exactly). With a fixed sliding direction x, the friction is mu N x.
        let mesh = pad_on_disc(0.0);
        let delta = 2e-4;
        let u: Vec<[f64; 3]> = (0..mesh.nodes.len())
            .map(|n| {
                if n >= mesh.node_sets["pad.z0"][0] {
                    [0.0, 0.0, -delta]
                } else {
                    [0.0; 3]
                }
            })
            .collect();
        let p = pair(&mesh, 0.4, true, SlidingDirection::Fixed([2.0, 0.0, 0.0]));
        let s = summarize(&p, &[], &u).unwrap();
        let n_expected = 1e11 * 0.15 * delta;
        assert_eq!(s.closed, p.points.len());
        assert!((s.normal_force / n_expected - 1.0).abs() < 1e-13);
        assert!((s.closed_area - 0.15).abs() < 1e-15);
        assert!(norm(sub(s.friction_force, [0.4 * n_expected, 0.0, 0.0])) < 1e-13 * n_expected);
        assert!(
            norm(sub(s.force_on_slave, [0.4 * n_expected, 0.0, n_expected])) < 1e-13 * n_expected
        );
        let range = s.pressure.unwrap();
        for v in [range.min, range.max, range.mean] {
            assert!((v / (1e11 * delta) - 1.0).abs() < 1e-13);
        }
        // Turning disc: friction of size mu N, each point's along its own tangent (the sum
        // of the vectors is shorter), tangents horizontal and orthogonal to the radius.
        let p = pair(&mesh, 0.4, true, rotation());
        let s = summarize(&p, &[], &u).unwrap();
        assert!((s.normal_force / n_expected - 1.0).abs() < 1e-13);
        assert!(s.friction_force[2].abs() < 1e-13 * n_expected);
        let mut sum_of_sizes = 0.0;
        for point in &p.points {
            let state = point_state(&p, point, [0.0; 3], &u).unwrap();
            let t = point.tangent.unwrap();
            assert!(t[2].abs() < 1e-15);
            assert!(dot(t, sub(point.position, [0.45, 0.5, 0.0])).abs() < 1e-15);
            sum_of_sizes += 0.4 * state.normal_force;
        }
        assert!((sum_of_sizes / (0.4 * n_expected) - 1.0).abs() < 1e-13);
        // Lifted instead: open everywhere, no force.
        let lifted: Vec<[f64; 3]> = u.iter().map(|v| scale(-1.0, *v)).collect();
        let s = summarize(&p, &[], &lifted).unwrap();
        assert_eq!((s.closed, s.normal_force, s.pressure), (0, 0.0, None));
    }

    #[test]
    fn node_to_node_points_with_several_slave_nodes() {
        // A slave point spread over three nodes (a distributing coupling) against a master
        // point on two: the same law, checked against finite differences (same reasoning as
        // check_jacobian) and for action = reaction.
        let settings = PairSettings {
            name: "reduced".into(),
            friction: 0.3,
            penalty: None,
            separation: true,
            sliding: SlidingDirection::Fixed([0.0, 1.0, 0.0]),
            law: crate::contact::FrictionLaw::SteadySliding,
            calculix: None,
        };
        let n = [0.6, 0.0, 0.8];
        let t = [0.0, 1.0, 0.0];
        let point = crate::contact::pair::ContactPoint {
            slave: vec![(0, 0.5), (1, 0.3), (2, 0.2)],
            master: vec![(3, 0.7), (4, 0.3)],
            normal: n,
            initial_gap: 1e-3,
            area: 0.02,
            tangent: Some(t),
            position: [0.0; 3],
            slave_node: 0,
            master_face: None,
            tilt: None,
        };
        let p = node_to_node(settings, 5e10, vec![point]).unwrap();
        let mut rng = Lcg(9);
        let mut u: Vec<[f64; 3]> = (0..5)
            .map(|_| [0.0; 3].map(|_| 1e-4 * rng.next()))
            .collect();
        // Push the slave nodes 2e-3 along -n: g = 1e-3 - 2e-3 + O(1e-4) < 0.
        for v in u.iter_mut().take(3) {
            *v = add(*v, scale(-2e-3, n));
        }
        assert_eq!(check_jacobian(&p, &u), 1);
        let (state, c) = evaluate(&p, &p.points[0], [0.0; 3], &u).unwrap();
        let c = c.unwrap();
        assert_eq!(c.nodes, vec![0, 1, 2, 3, 4]);
        let force: [f64; 3] = std::array::from_fn(|i| (0..5).map(|k| c.residual[3 * k + i]).sum());
        assert!(norm(force) < 1e-15 * state.normal_force);
        // Slave side carries p (n + mu t) in its weights' proportions.
        let expect = add(
            scale(state.normal_force, n),
            scale(0.3 * state.normal_force, t),
        );
        for (k, w) in [0.5, 0.3, 0.2].iter().enumerate() {
            for (i, e) in expect.iter().enumerate() {
                assert!((-c.residual[3 * k + i] - w * e).abs() < 1e-12 * state.normal_force);
            }
        }
        // A displacement field too short is an error naming the pair and the node.
        let err = evaluate(&p, &p.points[0], [0.0; 3], &u[..4]).unwrap_err();
        assert_eq!(
            err,
            ContactError::NodeOutOfRange {
                pair: "reduced".into(),
                node: 4,
                nodes: 4
            }
        );
    }

    /// A reduced contact with its tilt nodes 3, 4: slave nodes 0, 1, master node 2, normal
    /// z, a 0.2 x 0.2 share as 8 x 8 points offset a little from the contact point, penalty
    /// 5e10, friction `mu` by `law`.
    fn patch_pair(mu: f64, law: crate::contact::FrictionLaw) -> ContactPair {
        let e = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let mut patch = Vec::new();
        for i in 0..8 {
            for j in 0..8 {
                let x = -0.09 + 0.2 * (i as f64 + 0.5) / 8.0 - 0.1;
                let y = 0.013 + 0.2 * (j as f64 + 0.5) / 8.0 - 0.1;
                patch.push(([x, y], 0.04 / 64.0));
            }
        }
        // A Coulomb pair slips where its forces take it: no imposed direction.
        let sliding = match law {
            crate::contact::FrictionLaw::SteadySliding => SlidingDirection::Fixed([0.0, 1.0, 0.0]),
            crate::contact::FrictionLaw::Coulomb { .. } => SlidingDirection::None,
        };
        let tangent = sliding.tangent([0.0; 3], [0.0, 0.0, 1.0]);
        let settings = PairSettings {
            name: "reduced".into(),
            friction: mu,
            penalty: None,
            separation: true,
            sliding,
            law,
            calculix: None,
        };
        let point = crate::contact::pair::ContactPoint {
            slave: vec![(0, 0.6), (1, 0.4)],
            master: vec![(2, 1.0)],
            normal: [0.0, 0.0, 1.0],
            initial_gap: 0.0,
            area: 0.04,
            tangent,
            position: [0.0; 3],
            slave_node: 0,
            master_face: None,
            tilt: Some(crate::contact::Tilt {
                nodes: [3, 4],
                axes: e,
                patch,
                arm: 0.05,
                penalty: 5e10,
                bilateral: false,
            }),
        };
        node_to_node(settings, 5e10, vec![point]).unwrap()
    }

    /// Approach 1e-4, tilt -3e-3 rad along x and -1e-3 along y (theta = e . (u_rp - u_rd) /
    /// arm, the disc side tilted too): the patch of [`patch_pair`] closed on one side only.
    fn partly_closed() -> Vec<[f64; 3]> {
        let mut u = vec![[0.0; 3]; 5];
        u[0] = [0.0, 0.0, -1e-4];
        u[1] = [0.0, 0.0, -1e-4];
        u[3] = [0.05 * -2e-3, 0.05 * -0.5e-3, 0.0];
        u[4] = [0.05 * 1e-3, 0.05 * 0.5e-3, 0.0];
        u
    }

    /// A Coulomb pair's patch law (a kept pair reduced with its tilt nodes): the Jacobian
    /// against central differences, sticking and slipping, the patch partly closed. Slipping,
    /// the cone's radius mu p follows the patch's tilt, so the friction force changes with
    /// the tilt nodes' motion (the rows of the slave and master nodes in the tilt nodes'
    /// columns): a tangent without that term fails here.
    #[test]
    fn coulomb_patch_law_jacobian_matches_finite_differences() {
        let law = crate::contact::FrictionLaw::Coulomb {
            stick_stiffness: None,
        };
        let p = patch_pair(0.3, law);
        let u = partly_closed();
        // The slave's tangential motion is zero: an anchor at zero sticks, one 1.1e-2 m
        // away pulls the stick spring far past the cone (k_t A |a| = 2.2e5 N against
        // mu p < 6e4 N).
        let stick = check_jacobian_from(&p, &[[0.0; 3]], &u);
        assert_eq!(stick, (1, 1, 0));
        let slip = check_jacobian_from(&p, &[[1e-2, 5e-3, 0.0]], &u);
        assert_eq!(slip, (1, 0, 1));
        let (state, _) = evaluate(&p, &p.points[0], [1e-2, 5e-3, 0.0], &u).unwrap();
        assert!((norm(state.friction_force) / (0.3 * state.normal_force) - 1.0).abs() < 1e-12);
        // Bilateral (the piston's pair): every point of the share acts, pulling where open,
        // so the tilted share pushed 1e-4 carries k A 1e-4 (the tilt's moment about the
        // share's centre adds nothing to the force where every point acts) and its tangent
        // is the derivative.
        let mut bilateral = p.clone();
        bilateral.settings.separation = false;
        let tilt = bilateral.points[0].tilt.as_mut().unwrap();
        tilt.bilateral = true;
        let centre = [0, 1].map(|a| tilt.patch.iter().map(|q| q.0[a] * q.1).sum::<f64>() / 0.04);
        let (state, _) = evaluate(&bilateral, &bilateral.points[0], [0.0; 3], &u).unwrap();
        let theta = state.theta;
        let expected = 5e10 * 0.04 * (1e-4 - theta[0] * centre[0] - theta[1] * centre[1]);
        assert!(
            (state.normal_force / expected - 1.0).abs() < 1e-12,
            "{state:?}"
        );
        assert_eq!(
            check_jacobian_from(&bilateral, &[[1e-2, 5e-3, 0.0]], &u),
            (1, 0, 1)
        );
    }

    /// A patch law (a reduced contact with its tilt nodes): the Jacobian against central
    /// differences with the patch partly closed, symmetric without friction, and the whole
    /// patch closed with no tilt giving the point law k A (-g).
    #[test]
    fn patch_law_jacobian_matches_finite_differences_partly_closed() {
        for mu in [0.0, 0.3] {
            let p = patch_pair(mu, crate::contact::FrictionLaw::SteadySliding);
            let u = partly_closed();
            let (state, c) = evaluate(&p, &p.points[0], [0.0; 3], &u).unwrap();
            let l = p.points[0]
                .tilt
                .as_ref()
                .unwrap()
                .law(state.gap, [-3e-3, -1e-3]);
            assert!(
                l.k0 > 0.0 && l.k0 < 5e10 * 0.04 * 0.9,
                "partly closed: {l:?}"
            );
            assert_eq!(check_jacobian(&p, &u), 1);
            // The closed zone from the summary is the patch law's own closed stiffness and
            // moments (k0, k1 along the axes, k2), placed at the contact point.
            let zone = summarize(&p, &[], &u).unwrap().zone;
            assert!((zone.total / l.k0 - 1.0).abs() < 1e-14, "{zone:?} {l:?}");
            for a in 0..2 {
                assert!(
                    (zone.first[a] - l.k1[a]).abs() < 1e-14 * l.k0,
                    "{zone:?} {l:?}"
                );
                for b in 0..2 {
                    let k2 = zone.second[a][b];
                    assert!((k2 - l.k2[a][b]).abs() < 1e-14 * l.k0, "{zone:?} {l:?}");
                }
            }
            let c = c.unwrap();
            assert_eq!(c.nodes, vec![0, 1, 2, 3, 4]);
            if mu == 0.0 {
                let size = 15;
                for r in 0..size {
                    for k in 0..size {
                        let (a, b) = (c.jacobian[r * size + k], c.jacobian[k * size + r]);
                        assert!((a - b).abs() <= 1e-12 * 5e10 * 0.04, "{r},{k}: {a} vs {b}");
                    }
                }
            }
            // No tilt, everything closed: the point law.
            let flat = vec![
                [0.0, 0.0, -1e-4],
                [0.0, 0.0, -1e-4],
                [0.0; 3],
                [1e-3; 3],
                [1e-3; 3],
            ];
            let s = point_state(&p, &p.points[0], [0.0; 3], &flat).unwrap();
            assert!((s.normal_force / (5e10 * 0.04 * 1e-4) - 1.0).abs() < 1e-12);
            // ... and the whole share closed, centred where its points are.
            let zone = summarize(&p, &[], &flat).unwrap().zone;
            assert!((zone.total / (5e10 * 0.04) - 1.0).abs() < 1e-12);
            let c = zone.centroid().unwrap();
            assert!(
                (c[0] + 0.09).abs() < 1e-12 && (c[1] - 0.013).abs() < 1e-12,
                "{c:?}"
            );
        }
    }
}
