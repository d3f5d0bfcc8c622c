//! Contact pairs: the settings of an interface (friction coefficient, penalty, separation,
//! sliding direction) and its contact points, built node-to-surface from a mesh
//! ([`node_to_surface`]) or node-to-node from given points ([`node_to_node`]).
//!
//! A contact point ties a slave point and the master point it faces, each a weighted sum of
//! node displacements: node-to-surface, the slave point is one node (weight 1) and the master
//! point the face's six nodes with the face shape functions `N_j` at the projection;
//! node-to-node (the reduced interface), one node on each side. Everything the force law
//! needs is fixed at the reference configuration (small sliding): the weights, the unit
//! normal `n` of the master surface (pointing out of the master, towards the slave), the
//! initial gap `g0 = n . (x_s - x_m)`, the tributary area and the sliding direction `t`.

use super::project::{SearchOptions, SurfaceSearch};
use super::ContactError;
use crate::mesh::{Mesh, Surface};
use crate::vector3::{cross, dot, norm, scale, sub};

/// Direction in which the master surface slides under the slave one: the direction of the
/// friction force on the slave.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum SlidingDirection {
    /// A disc turning about an axis through `centre` along `axis` (any length); `sense` is the
    /// sign of the angular speed about `axis` (only its sign is used). At a slave point `x`,
    /// `t = normalize(P_n (sense * axis x (x - centre)))`, the direction of the disc surface's
    /// velocity there.
    DiscRotation {
        centre: [f64; 3],
        axis: [f64; 3],
        sense: f64,
    },
    /// A fixed direction (any length), projected on the tangent plane and normalised.
    Fixed([f64; 3]),
    /// No relative sliding (or frictionless): no friction force.
    None,
}

/// Projections of the sliding velocity shorter than this fraction of its natural size count
/// as zero: the point is on the rotation axis, or the direction is along the normal.
const VANISHING_TANGENT: f64 = 1e-9;

impl SlidingDirection {
    /// The unit sliding direction at reference point `x` on a surface of unit normal `n`, or
    /// `None` where it vanishes (no sliding direction, a point on the rotation axis, a fixed
    /// direction along the normal).
    pub fn tangent(&self, x: [f64; 3], n: [f64; 3]) -> Option<[f64; 3]> {
        let (v, size) = match self {
            SlidingDirection::DiscRotation {
                centre,
                axis,
                sense,
            } => {
                let a = scale(sense.signum() / norm(*axis), *axis);
                let r = sub(x, *centre);
                (cross(a, r), norm(r))
            }
            SlidingDirection::Fixed(d) => (*d, norm(*d)),
            SlidingDirection::None => return None,
        };
        let tangential = sub(v, scale(dot(v, n), n));
        let length = norm(tangential);
        (length > VANISHING_TANGENT * size && length.is_finite())
            .then(|| scale(1.0 / length, tangential))
    }

    fn check(&self) -> Result<(), String> {
        let finite = |v: &[f64; 3]| v.iter().all(|c| c.is_finite());
        match self {
            SlidingDirection::DiscRotation {
                centre,
                axis,
                sense,
            } => {
                if !finite(centre) {
                    return Err(format!("rotation centre {centre:?} is not finite"));
                }
                if !finite(axis) || norm(*axis) == 0.0 {
                    return Err(format!(
                        "rotation axis {axis:?} must be a finite, non-zero vector"
                    ));
                }
                if !(sense.is_finite() && *sense != 0.0) {
                    return Err(format!(
                        "rotation sense {sense} must be finite and non-zero (its sign is used)"
                    ));
                }
            }
            SlidingDirection::Fixed(d) => {
                if !finite(d) || norm(*d) == 0.0 {
                    return Err(format!(
                        "sliding direction {d:?} must be a finite, non-zero vector"
                    ));
                }
            }
            SlidingDirection::None => {}
        }
        Ok(())
    }
}

/// How friction acts at an interface.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrictionLaw {
    /// The master slides under the slave along an imposed direction everywhere they touch
    /// (the disc under the pads): the friction force is `mu p t`, always.
    #[default]
    SteadySliding,
    /// Coulomb friction with stick and slip for surfaces with no imposed sliding (piston,
    /// caliper and bracket on the pads): a tangential penalty spring of `stick_stiffness`
    /// per unit area holds a point until its force reaches `mu p`, then the point slips
    /// ([`super::coulomb`]).
    Coulomb {
        /// Tangential stiffness per unit area while sticking (Pa/m); `None`: the normal
        /// penalty / 100, the stick slope the CalculiX manual advises for penalty contact.
        stick_stiffness: Option<f64>,
    },
}

/// The default stick stiffness is the normal penalty divided by this.
pub const STICK_STIFFNESS_DIVISOR: f64 = 100.0;

/// What the user sets for one interface (one row of the paper's Table 1).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PairSettings {
    /// Name used in every message about the pair.
    pub name: String,
    /// Coulomb friction coefficient `mu >= 0`.
    pub friction: f64,
    /// Penalty stiffness per unit area `k_n`; `None`: `10 E_min / h` (see
    /// [`node_to_surface`]).
    pub penalty: Option<f64>,
    /// `true`: the surfaces may separate (`p = k_n A max(0, -g)`); `false`: bilateral
    /// (`p = k_n A (-g)`, may pull).
    pub separation: bool,
    pub sliding: SlidingDirection,
    /// Steady sliding along `sliding`, or Coulomb stick/slip (then `sliding` must be
    /// [`SlidingDirection::None`]: the slip direction comes from the solution).
    #[serde(default)]
    pub law: FrictionLaw,
    /// CalculiX's normal law and perturbation tangent instead of squeal's (the CalculiX
    /// contact variant, [`super::variant`]); `None`: squeal's law.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calculix: Option<super::variant::CalculixLaw>,
}

impl PairSettings {
    fn check(&self) -> Result<(), ContactError> {
        let invalid = |what: String| ContactError::Invalid {
            pair: self.name.clone(),
            what,
        };
        if self.name.trim().is_empty() {
            return Err(invalid("the pair has no name".into()));
        }
        if !(self.friction >= 0.0 && self.friction.is_finite()) {
            return Err(invalid(format!(
                "friction coefficient {} must be finite and >= 0",
                self.friction
            )));
        }
        if let Some(k) = self.penalty {
            check_penalty(k).map_err(invalid)?;
        }
        if let Some(law) = self.calculix {
            if !(law.tension >= 0.0 && law.tension.is_finite()) {
                return Err(invalid(format!(
                    "CalculiX's tension at large clearance {} must be finite and >= 0",
                    law.tension
                )));
            }
            if !(law.clearance_factor > 0.0 && law.clearance_factor.is_finite()) {
                return Err(invalid(format!(
                    "CalculiX's clearance factor c0 {} must be finite and > 0",
                    law.clearance_factor
                )));
            }
        }
        if let FrictionLaw::Coulomb { stick_stiffness } = self.law {
            if self.sliding != SlidingDirection::None {
                return Err(invalid(
                    "a pair with the coulomb friction law slips where its forces take it: it \
                     cannot also be given a sliding direction (use friction_law = \
                     \"steady-sliding\" for a disc turning under a pad, or remove `sliding`)"
                        .into(),
                ));
            }
            if let Some(k) = stick_stiffness {
                if !(k > 0.0 && k.is_finite()) {
                    return Err(invalid(format!(
                        "stick_stiffness {k} (tangential stiffness per unit area) must be \
                         finite and > 0"
                    )));
                }
            }
        }
        self.sliding.check().map_err(invalid)
    }
}

fn check_penalty(k: f64) -> Result<(), String> {
    if k > 0.0 && k.is_finite() {
        Ok(())
    } else {
        Err(format!(
            "penalty stiffness per unit area {k} must be finite and > 0"
        ))
    }
}

/// Where a node-to-surface contact point's master point lies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MasterFace {
    /// Index into [`Mesh::elements`] of the element owning the face.
    pub element: usize,
    /// Which face of that element (0..4, Abaqus S1..S4).
    pub side: u8,
    /// Face parametric point of the master point.
    pub q: [f64; 2],
}

/// One contact constraint between a slave point and the master point it faces.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPoint {
    /// The slave point as `(node, weight)`: its displacement is `sum w u_node`. Weights sum
    /// to 1.
    pub slave: Vec<(usize, f64)>,
    /// The master point as `(node, weight)` (node-to-surface: the face nodes with `N_j`).
    /// Weights sum to 1.
    pub master: Vec<(usize, f64)>,
    /// Unit normal of the master surface at the master point, pointing out of the master
    /// (towards the slave).
    pub normal: [f64; 3],
    /// `g0 = n . (x_s - x_m)` in the reference configuration; negative = penetration.
    pub initial_gap: f64,
    /// Tributary area `A_s` of the slave point.
    pub area: f64,
    /// Unit sliding direction (tangent to the master surface), fixed; `None`: no friction at
    /// this point.
    pub tangent: Option<[f64; 3]>,
    /// The slave point in the reference configuration.
    pub position: [f64; 3],
    /// The slave node the point stands for, in reports (node-to-surface: the slave node).
    pub slave_node: usize,
    /// The master face and parametric point (node-to-surface only).
    pub master_face: Option<MasterFace>,
    /// The patch's tilt law (a reduced interface's contact points; `None` elsewhere).
    pub tilt: Option<Tilt>,
}

/// A reduced contact point's patch law: its share of the pad face, integrated.
///
/// A reduced contact node stands for a patch of the pad face, tied to it by a distributing
/// coupling that holds the patch's mean translation only: alone, the point lets the pad
/// patch tilt freely against the disc patch, where the full model's penalty springs over
/// the patch resist it with k_n I (I the closed part's second moment of area). The tilt
/// nodes hold the patches' slopes: r_p's components along `axes` are `arm` times the
/// least-squares slope of the pad patch's normal displacement, r_d's the disc patch's (tied
/// by stiff springs, [`crate::reduce::tilt`]). The point's normal law is then the full
/// model's over its share: the gap at offset xi is g + theta . xi (theta = e . (u_rp - u_rd)
/// / arm) and
/// each quadrature point of the share carries k_n a max(0, -gap), so a partly closed patch
/// carries its closed part's force, moment and stiffness only (a switch on the whole patch
/// over-stiffened the edge of the contact zone: issue 29).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tilt {
    /// The tilt nodes (extra nodes): pad side r_p and disc side r_d, each holding `arm`
    /// times its patch's slope along `axes`; the tilt is theta = e . (u_rp - u_rd) / arm.
    pub nodes: [usize; 2],
    /// Unit in-plane axes (orthogonal to the point's normal and to each other).
    pub axes: [[f64; 3]; 2],
    /// The share of the pad face as quadrature points: (offset from the contact point along
    /// `axes`, area); the areas add up to the point's area.
    pub patch: Vec<([f64; 2], f64)>,
    /// The tilt nodes' scale: theta = e . (u_rp - u_rd) / arm.
    pub arm: f64,
    /// k_n, N/m^3 (the pair's penalty per unit area).
    pub penalty: f64,
    /// The pair's surfaces cannot separate (a bilateral pair): every quadrature point
    /// carries k_n a (-gap), pulling too.
    #[serde(default)]
    pub bilateral: bool,
}

/// The patch law at gap `g` and tilt `theta` ([`Tilt::patch`]): normal force F (on the
/// slave, >= 0), moment M_a = sum f_j xi_ja, and the stiffnesses k0 = k_n sum_closed a_j,
/// k1_a = k_n sum_closed a_j xi_ja, k2_ab = k_n sum_closed a_j xi_ja xi_jb.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PatchLaw {
    pub force: f64,
    pub moment: [f64; 2],
    pub k0: f64,
    pub k1: [f64; 2],
    pub k2: [[f64; 2]; 2],
}

impl Tilt {
    pub fn law(&self, gap: f64, theta: [f64; 2]) -> PatchLaw {
        let mut l = PatchLaw::default();
        for &(xi, a) in &self.patch {
            let g = gap + theta[0] * xi[0] + theta[1] * xi[1];
            if !self.acts(g) {
                continue;
            }
            let k = self.penalty * a;
            let f = -k * g;
            l.force += f;
            l.k0 += k;
            for p in 0..2 {
                l.moment[p] += f * xi[p];
                l.k1[p] += k * xi[p];
                for q in 0..2 {
                    l.k2[p][q] += k * xi[p] * xi[q];
                }
            }
        }
        l
    }

    /// Whether a quadrature point at gap `g` carries the penalty.
    pub fn acts(&self, g: f64) -> bool {
        self.bilateral || g <= 0.0
    }

    /// theta from the tilt nodes' displacements (u_r = u_rp - u_rd).
    pub fn theta(&self, u_r: [f64; 3]) -> [f64; 2] {
        let d = |e: [f64; 3]| (e[0] * u_r[0] + e[1] * u_r[1] + e[2] * u_r[2]) / self.arm;
        [d(self.axes[0]), d(self.axes[1])]
    }
}

/// A contact interface: settings, resolved penalty and contact points.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPair {
    pub settings: PairSettings,
    /// Penalty stiffness per unit area `k_n` in use (the setting, or its default).
    pub penalty: f64,
    pub points: Vec<ContactPoint>,
}

impl ContactPair {
    /// Tangential stiffness per unit area while sticking: the setting, or the penalty / 100;
    /// `None` for a steady-sliding pair.
    pub fn stick_stiffness(&self) -> Option<f64> {
        match self.settings.law {
            FrictionLaw::SteadySliding => None,
            FrictionLaw::Coulomb { stick_stiffness } => {
                Some(stick_stiffness.unwrap_or(self.penalty / STICK_STIFFNESS_DIVISOR))
            }
        }
    }

    /// Makes the pair slide steadily along `sliding` (the disc turning under it): the law
    /// becomes steady sliding and each point's tangent is recomputed at its reference
    /// position, as [`node_to_surface`] would have made it.
    pub fn set_sliding(&mut self, sliding: SlidingDirection) -> Result<(), ContactError> {
        let mut settings = self.settings.clone();
        settings.sliding = sliding;
        settings.law = FrictionLaw::SteadySliding;
        settings.check()?;
        for point in &mut self.points {
            point.tangent = settings.sliding.tangent(point.position, point.normal);
        }
        check_sliding(&settings, &self.points)?;
        self.settings = settings;
        Ok(())
    }

    /// The same pair without friction: only its normal law acts (what holds a body when
    /// nothing can be asked of friction).
    pub fn frictionless(&self) -> ContactPair {
        let mut pair = self.clone();
        pair.settings.friction = 0.0;
        pair.settings.law = FrictionLaw::SteadySliding;
        pair
    }
}

/// Refuses a sliding direction that gives no point a tangent: along the contact normal
/// everywhere (a fixed direction or a `*MOTION` along the normal). The pair then had no
/// friction at all while its points were reported as slipping.
fn check_sliding(settings: &PairSettings, points: &[ContactPoint]) -> Result<(), ContactError> {
    let sliding = !matches!(settings.sliding, SlidingDirection::None);
    if sliding && !points.is_empty() && points.iter().all(|p| p.tangent.is_none()) {
        return Err(ContactError::Invalid {
            pair: settings.name.clone(),
            what: format!(
                "its sliding direction {:?} is along the contact normal at every one of its {} \
                 points: friction would act nowhere; give a direction in the contact plane",
                settings.sliding,
                points.len()
            ),
        });
    }
    Ok(())
}

/// Tolerance on a unit vector's length and on the sum of a point's weights: both come from
/// normalisations and partitions of unity, exact to a few ulps; a wrong input is off by far
/// more.
const UNIT_TOLERANCE: f64 = 1e-9;

fn check_point(point: &ContactPoint) -> Result<(), String> {
    let unit = |v: [f64; 3]| (norm(v) - 1.0).abs() <= UNIT_TOLERANCE;
    let side = |name: &str, list: &[(usize, f64)]| -> Result<(), String> {
        if list.is_empty() {
            return Err(format!("the {name} point has no nodes"));
        }
        if list.iter().any(|(_, w)| !w.is_finite()) {
            return Err(format!("the {name} point has a non-finite weight"));
        }
        let sum: f64 = list.iter().map(|(_, w)| w).sum();
        if (sum - 1.0).abs() > UNIT_TOLERANCE {
            return Err(format!(
                "the {name} point's weights sum to {sum}, not 1 (forces would not balance)"
            ));
        }
        Ok(())
    };
    side("slave", &point.slave)?;
    side("master", &point.master)?;
    if !unit(point.normal) {
        return Err(format!("normal {:?} is not a unit vector", point.normal));
    }
    if !point.initial_gap.is_finite() {
        return Err(format!("initial gap {} is not finite", point.initial_gap));
    }
    if !(point.area > 0.0 && point.area.is_finite()) {
        return Err(format!("area {} must be finite and > 0", point.area));
    }
    if let Some(t) = point.tangent {
        if !unit(t) || dot(t, point.normal).abs() > UNIT_TOLERANCE {
            return Err(format!(
                "sliding direction {t:?} is not a unit vector orthogonal to the normal"
            ));
        }
    }
    if point.position.iter().any(|c| !c.is_finite()) {
        return Err(format!("position {:?} is not finite", point.position));
    }
    Ok(())
}

/// A node-to-node pair from given contact points (the reduced interface), checked: settings,
/// the penalty per unit area `penalty` (this one is resolved by the caller), unit normals,
/// positive areas, weights summing to 1 on each side, unit tangents orthogonal to the normals.
pub fn node_to_node(
    settings: PairSettings,
    penalty: f64,
    points: Vec<ContactPoint>,
) -> Result<ContactPair, ContactError> {
    settings.check()?;
    let invalid = |what: String| ContactError::Invalid {
        pair: settings.name.clone(),
        what,
    };
    check_penalty(penalty).map_err(invalid)?;
    for (k, point) in points.iter().enumerate() {
        check_point(point).map_err(|e| {
            invalid(format!(
                "contact point {k} (slave node index {}): {e}",
                point.slave_node
            ))
        })?;
    }
    Ok(ContactPair {
        settings,
        penalty,
        points,
    })
}

/// The sub-triangles of a 6-node face, as face-local node indices: corner a with mid(a,b) and
/// mid(c,a), corner b with mid(b,c) and mid(a,b), corner c with mid(c,a) and mid(b,c), and the
/// middle one.
const SUB_TRIANGLES: [[usize; 3]; 4] = [[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]];

/// Tributary area of every node of `surface`, sorted by node: each 6-node face is split into
/// its four 3-node sub-triangles and each sub-triangle's (flat) area goes in thirds to its
/// nodes. The areas add up to the sum of the sub-triangle areas, which is the surface's area
/// when the faces are flat with straight edges. (The consistent weights of the quadratic
/// triangle would give the corners nothing: see METHOD.md section 2.) Node indices must be
/// valid for `mesh` (the caller checks).
pub fn tributary_areas(mesh: &Mesh, surface: &Surface) -> Vec<(usize, f64)> {
    let mut area: std::collections::BTreeMap<usize, f64> = Default::default();
    for face in &surface.faces {
        let x = face.nodes.map(|n| mesh.nodes[n]);
        for tri in SUB_TRIANGLES {
            let a = 0.5 * norm(cross(sub(x[tri[1]], x[tri[0]]), sub(x[tri[2]], x[tri[0]])));
            for k in tri {
                *area.entry(face.nodes[k]).or_default() += a / 3.0;
            }
        }
    }
    area.into_iter().collect()
}

/// Checks that a surface has faces and that its faces refer to elements and nodes of the mesh.
fn check_surface(mesh: &Mesh, surface: &Surface, role: &str) -> Result<(), String> {
    if surface.faces.is_empty() {
        return Err(format!("{role} surface '{}' has no faces", surface.name));
    }
    for face in &surface.faces {
        if face.element >= mesh.elements.len() || face.nodes.iter().any(|&n| n >= mesh.nodes.len())
        {
            return Err(format!(
                "{role} surface '{}' has a face (element index {}, side {}) outside the mesh",
                surface.name, face.element, face.side
            ));
        }
    }
    Ok(())
}

fn element_label(mesh: &Mesh, element: usize) -> i64 {
    mesh.element_labels
        .get(element)
        .copied()
        .unwrap_or(element as i64 + 1)
}

fn node_label(mesh: &Mesh, node: usize) -> i64 {
    mesh.node_labels
        .get(node)
        .copied()
        .unwrap_or(node as i64 + 1)
}

/// The smallest Young's modulus of the materials of the elements owning the faces of
/// `surfaces`.
fn smallest_young(mesh: &Mesh, surfaces: &[(&Surface, &str)]) -> Result<f64, String> {
    let owner = mesh.element_parts();
    let mut smallest = f64::INFINITY;
    for (surface, role) in surfaces {
        for face in &surface.faces {
            let part = owner[face.element].map(|p| &mesh.parts[p]);
            let material = part
                .and_then(|p| p.material.as_ref())
                .and_then(|m| mesh.materials.get(m));
            let Some(material) = material else {
                return Err(format!(
                    "element {} of the {role} surface '{}' has no material (it is in {}), so \
                     the default penalty 10 E_min / h cannot be formed: give the pair a penalty",
                    element_label(mesh, face.element),
                    surface.name,
                    part.map_or("no part".to_string(), |p| format!("part '{}'", p.name)),
                ));
            };
            if !(material.young > 0.0 && material.young.is_finite()) {
                return Err(format!(
                    "material '{}' of the {role} surface '{}' has Young's modulus {}",
                    material.name, surface.name, material.young
                ));
            }
            smallest = smallest.min(material.young);
        }
    }
    Ok(smallest)
}

/// A given penalty may be at most this many times the default 10 E_min / h. A penalty a
/// million times the bodies' own stiffness already costs K six of its sixteen digits; at
/// 1e300 Pa/m the static stopped with "the tangent stiffness is singular: 'disc' is free",
/// which blamed the supports.
const MAX_PENALTY_RATIO: f64 = 1e6;

/// Slave nodes that did not project are listed up to this many in the error.
const UNPROJECTED_EXAMPLES: usize = 10;

/// A node-to-surface pair: every node of `slave` projected on the closest face of `master`
/// (see [`SurfaceSearch::nearest`] and [`SearchOptions`]), with its tributary area
/// ([`tributary_areas`]), the face shape functions at the projection as master weights, the
/// unit normal there, `g0 = n . (x_s - x_m)` and the sliding direction at `x_s`.
///
/// Default penalty per unit area (when `settings.penalty` is `None`): `k_n = 10 E_min / h`,
/// `E_min` the smallest Young's modulus among the materials of the elements owning the slave
/// and master faces, `h = sqrt(mean master face area)` (for right isosceles faces of legs `a`,
/// `h = a / sqrt 2`).
///
/// Errors: invalid settings or search options, empty surfaces, faces outside the mesh,
/// degenerate master faces (named by element label), missing materials when the default
/// penalty is needed, and slave nodes that do not project ([`ContactError::Unprojected`]:
/// how many, and the first ones' labels and coordinates).
pub fn node_to_surface(
    mesh: &Mesh,
    slave: &Surface,
    master: &Surface,
    settings: PairSettings,
    options: &SearchOptions,
) -> Result<ContactPair, ContactError> {
    check_surface(mesh, slave, "slave").map_err(|what| ContactError::Invalid {
        pair: settings.name.clone(),
        what,
    })?;
    let slaves = tributary_areas(mesh, slave);
    project_slave_nodes(mesh, slaves, Some(slave), master, settings, options)
}

/// A node-to-surface pair whose slave side is a list of nodes, each with the area it stands
/// for (an Abaqus node-based surface): the same as [`node_to_surface`] otherwise; the
/// default penalty takes `E_min` from the master faces alone.
pub fn nodes_to_surface(
    mesh: &Mesh,
    slave_nodes: &[(usize, f64)],
    master: &Surface,
    settings: PairSettings,
    options: &SearchOptions,
) -> Result<ContactPair, ContactError> {
    let invalid = |what: String| ContactError::Invalid {
        pair: settings.name.clone(),
        what,
    };
    if slave_nodes.is_empty() {
        return Err(invalid("the slave node set is empty".into()));
    }
    if let Some(&(n, _)) = slave_nodes.iter().find(|(n, _)| *n >= mesh.nodes.len()) {
        return Err(invalid(format!("slave node index {n} is outside the mesh")));
    }
    project_slave_nodes(mesh, slave_nodes.to_vec(), None, master, settings, options)
}

/// Projects each slave node (with its area) on `master`: the body of [`node_to_surface`]
/// and [`nodes_to_surface`]; `slave_faces` is the slave surface when there is one.
fn project_slave_nodes(
    mesh: &Mesh,
    slaves: Vec<(usize, f64)>,
    slave_faces: Option<&Surface>,
    master: &Surface,
    settings: PairSettings,
    options: &SearchOptions,
) -> Result<ContactPair, ContactError> {
    settings.check()?;
    let invalid = |what: String| ContactError::Invalid {
        pair: settings.name.clone(),
        what,
    };
    options.check().map_err(invalid)?;
    check_surface(mesh, master, "master").map_err(invalid)?;

    let search = SurfaceSearch::of_surface(mesh, master).map_err(|face| {
        invalid(format!(
            "face S{} of element {} on the master surface '{}' is degenerate (zero area or \
             non-finite coordinates)",
            face.side + 1,
            element_label(mesh, face.element),
            master.name
        ))
    })?;
    if let Some(slave) = slave_faces.filter(|s| s.faces == master.faces) {
        return Err(invalid(format!(
            "the slave surface '{}' and the master surface '{}' are the same faces: a pair is \
             two surfaces facing each other",
            slave.name, master.name
        )));
    }
    let h = search.mean_face_size();
    let mut owners = vec![(master, "master")];
    if let Some(slave) = slave_faces {
        owners.insert(0, (slave, "slave"));
    }
    let young = smallest_young(mesh, &owners);
    let penalty = match settings.penalty {
        Some(k) => k,
        None => 10.0 * young.clone().map_err(invalid)? / h,
    };
    check_penalty(penalty).map_err(invalid)?;
    tracing::debug!(
        "contact pair '{}': penalty {penalty:.6e} Pa/m ({}; master face size h = {h:.4e} m)",
        settings.name,
        if settings.penalty.is_some() {
            "given"
        } else {
            "the default 10 E_min / h"
        }
    );
    if let (Some(k), Ok(young)) = (settings.penalty, young) {
        let default = 10.0 * young / h;
        if k > MAX_PENALTY_RATIO * default {
            return Err(invalid(format!(
                "penalty {k:e} Pa/m is {:.1e} times the default 10 E_min / h = {default:.3e} \
                 Pa/m: a contact stiffness that swamps the bodies' own leaves K none of their \
                 digits, and the static fails as if a body were free; give at most \
                 {MAX_PENALTY_RATIO:e} times the default",
                k / default
            )));
        }
    }

    let tolerance = options.in_face_tolerance;
    let max_distance = options.max_distance.unwrap_or(h);
    let mut points = Vec::new();
    let mut unprojected = Vec::new();
    for (node, area) in slaves {
        let x = mesh.nodes[node];
        let Some(hit) = search.nearest(x, tolerance, max_distance) else {
            unprojected.push(node);
            continue;
        };
        if area.is_nan() || area <= 0.0 {
            return Err(invalid(format!(
                "slave node {} has a zero tributary area (degenerate slave faces)",
                node_label(mesh, node)
            )));
        }
        let face = &master.faces[hit.face];
        let weights = crate::fem::tet10::face_shape(hit.q);
        points.push(ContactPoint {
            slave: vec![(node, 1.0)],
            master: face.nodes.iter().copied().zip(weights).collect(),
            normal: hit.normal,
            initial_gap: hit.gap,
            area,
            tangent: settings.sliding.tangent(x, hit.normal),
            position: x,
            slave_node: node,
            master_face: Some(MasterFace {
                element: face.element,
                side: face.side,
                q: hit.q,
            }),
            tilt: None,
        });
    }
    if !unprojected.is_empty() {
        return Err(ContactError::Unprojected {
            pair: settings.name.clone(),
            count: unprojected.len(),
            tolerance: format!(
                "in-face tolerance {tolerance}, largest distance {max_distance:e} onto master \
                 surface '{}'",
                master.name
            ),
            examples: unprojected
                .iter()
                .take(UNPROJECTED_EXAMPLES)
                .map(|&n| (node_label(mesh, n), mesh.nodes[n]))
                .collect(),
        });
    }
    check_sliding(&settings, &points)?;
    Ok(ContactPair {
        settings,
        penalty,
        points,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::test_models::pad_on_disc;

    fn settings(sliding: SlidingDirection) -> PairSettings {
        PairSettings {
            name: "disc/pad".into(),
            friction: 0.5,
            penalty: None,
            separation: true,
            sliding,
            law: FrictionLaw::SteadySliding,
            calculix: None,
        }
    }

    fn rotation() -> SlidingDirection {
        SlidingDirection::DiscRotation {
            centre: [0.5, 0.5, -1.0],
            axis: [0.0, 0.0, 2.0],
            sense: -1.0,
        }
    }

    #[test]
    fn flat_pad_projects_with_zero_gap_and_areas_add_up() {
        let mesh = pad_on_disc(0.0);
        let pair = node_to_surface(
            &mesh,
            &mesh.surfaces["pad.z0"],
            &mesh.surfaces["z1"],
            settings(rotation()),
            &SearchOptions::default(),
        )
        .unwrap();
        // Every node of the pad's bottom: (2*3 + 1) x (2*2 + 1) quadratic grid.
        assert_eq!(pair.points.len(), 7 * 5);
        // The faces are flat and straight-sided, so the sub-triangles tile them exactly and
        // the areas add up to 0.5 x 0.3 to round-off.
        let total: f64 = pair.points.iter().map(|p| p.area).sum();
        assert!((total - 0.15).abs() < 1e-15);
        for p in &pair.points {
            assert!(p.initial_gap.abs() < 1e-15);
            assert!((p.normal[2] - 1.0).abs() < 1e-15);
            // The master point is the slave node's position: sum N_j x_j = x_s.
            let xm = p.master.iter().fold([0.0; 3], |acc, &(n, w)| {
                crate::vector3::add(acc, scale(w, mesh.nodes[n]))
            });
            assert!(norm(sub(xm, p.position)) < 1e-15);
            let wsum: f64 = p.master.iter().map(|(_, w)| w).sum();
            assert!((wsum - 1.0).abs() < 1e-15);
            // Clockwise seen from +z (sense -1): t = -z x (x - c), normalised.
            let r = sub(p.position, [0.5, 0.5, 0.0]);
            let expect = scale(1.0 / norm(r), [r[1], -r[0], 0.0]);
            let t = p.tangent.unwrap();
            assert!(norm(sub(t, expect)) < 1e-15, "{t:?} vs {expect:?}");
        }
    }

    /// A sliding direction along the normal everywhere (the pad faces +z) gives no
    /// friction anywhere: refused, built or set later (a `*MOTION`), naming the pair.
    #[test]
    fn a_sliding_direction_along_the_normal_is_refused() {
        let mesh = pad_on_disc(0.0);
        let build = |sliding| {
            node_to_surface(
                &mesh,
                &mesh.surfaces["pad.z0"],
                &mesh.surfaces["z1"],
                settings(sliding),
                &SearchOptions::default(),
            )
        };
        let e = build(SlidingDirection::Fixed([0.0, 0.0, 2.0]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("along the contact normal at every one of its 35 points"),
            "{e}"
        );
        let mut pair = build(SlidingDirection::None).unwrap();
        let e = pair
            .set_sliding(SlidingDirection::Fixed([0.0, 0.0, -1.0]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("friction would act nowhere"), "{e}");
        // Tilted off the normal: a direction in the plane remains.
        let tilted = build(SlidingDirection::Fixed([0.1, 0.0, 1.0])).unwrap();
        assert!(tilted
            .points
            .iter()
            .all(|p| p.tangent == Some([1.0, 0.0, 0.0])));
    }

    /// A node-based slave: the given nodes and areas, the same points as the face-based
    /// pair otherwise; `set_sliding` then gives the tangents `node_to_surface` would have.
    #[test]
    fn a_node_list_slave_keeps_its_areas_and_set_sliding_recomputes_the_tangents() {
        let mesh = pad_on_disc(0.0);
        let faces = node_to_surface(
            &mesh,
            &mesh.surfaces["pad.z0"],
            &mesh.surfaces["z1"],
            settings(rotation()),
            &SearchOptions::default(),
        )
        .unwrap();
        let nodes: Vec<(usize, f64)> = faces.points.iter().map(|p| (p.slave_node, 2.0)).collect();
        let mut listed = nodes_to_surface(
            &mesh,
            &nodes,
            &mesh.surfaces["z1"],
            settings(SlidingDirection::None),
            &SearchOptions::default(),
        )
        .unwrap();
        assert_eq!(listed.points.len(), faces.points.len());
        // The default penalty's E_min comes from the master alone: the disc's 210e9, not
        // the pad's 1e9.
        assert!((listed.penalty / faces.penalty - 210.0).abs() < 1e-9);
        for (a, b) in listed.points.iter().zip(&faces.points) {
            assert_eq!(a.area, 2.0);
            assert_eq!((a.master.clone(), a.normal), (b.master.clone(), b.normal));
            assert_eq!(a.tangent, None);
        }
        listed.set_sliding(rotation()).unwrap();
        for (a, b) in listed.points.iter().zip(&faces.points) {
            assert_eq!(a.tangent, b.tangent);
        }
        let e = nodes_to_surface(
            &mesh,
            &[],
            &mesh.surfaces["z1"],
            settings(SlidingDirection::None),
            &SearchOptions::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("slave node set is empty"), "{e}");
    }

    #[test]
    fn tributary_areas_give_corners_and_mid_nodes_their_thirds() {
        // One right-triangle face of legs 0.1 (area 0.005), flat: each of the four
        // sub-triangles has area 0.005 / 4. Corners belong to one sub-triangle (1/12 of the
        // face), mid nodes to three (1/4 of it): 3/12 + 3/4 = 1.
        let mesh = pad_on_disc(0.0);
        let surface = Surface {
            name: "one".into(),
            faces: vec![mesh.surfaces["z1"].faces[0]],
        };
        let areas = tributary_areas(&mesh, &surface);
        let face_area =
            crate::fem::element::face_area(&surface.faces[0].nodes.map(|n| mesh.nodes[n]));
        assert!((face_area - 0.02).abs() < 1e-16);
        let corners = &surface.faces[0].nodes[..3];
        for (n, a) in areas {
            let expect = if corners.contains(&n) {
                1.0 / 12.0
            } else {
                0.25
            };
            assert!((a - expect * face_area).abs() < 1e-17, "node {n}: {a}");
        }
    }

    #[test]
    fn default_penalty_is_ten_e_min_over_h() {
        // E_min = 1e9 (the lining); master faces are right triangles of legs 0.2, area 0.02.
        let mesh = pad_on_disc(0.0);
        let pair = node_to_surface(
            &mesh,
            &mesh.surfaces["pad.z0"],
            &mesh.surfaces["z1"],
            settings(SlidingDirection::None),
            &SearchOptions::default(),
        )
        .unwrap();
        let expect = 10.0 * 1e9 / 0.02f64.sqrt();
        assert!((pair.penalty / expect - 1.0).abs() < 1e-14);
        // A given penalty is kept.
        let mut given = settings(SlidingDirection::None);
        given.penalty = Some(3e12);
        let pair = node_to_surface(
            &mesh,
            &mesh.surfaces["pad.z0"],
            &mesh.surfaces["z1"],
            given,
            &SearchOptions::default(),
        )
        .unwrap();
        assert_eq!(pair.penalty, 3e12);
        // Without a material the default cannot be formed, and the message says why.
        let mut bare = mesh.clone();
        bare.parts[1].material = None;
        let err = node_to_surface(
            &bare,
            &bare.surfaces["pad.z0"],
            &bare.surfaces["z1"],
            settings(SlidingDirection::None),
            &SearchOptions::default(),
        )
        .unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("disc/pad") && text.contains("pad.block") && text.contains("penalty"),
            "{text}"
        );
    }

    #[test]
    fn overhanging_slave_nodes_are_reported_by_count_and_place() {
        // Pad [0.8, 1.3] x [0.3, 0.6] over a disc ending at x = 1: the quadratic pad grid has
        // nodes every 0.05 in x, and those at x = 1.05 .. 1.3 (6 columns of 5) overhang; the
        // column at x = 1 projects on the disc's edge.
        let disc = crate::mesh::block::block(
            [0.0, 0.0, -0.2],
            [1.0, 1.0, 0.2],
            [5, 5, 1],
            crate::contact::test_models::material("steel", 210e9),
        )
        .unwrap();
        let pad = crate::mesh::block::block(
            [0.8, 0.3, 0.0],
            [0.5, 0.3, 0.1],
            [5, 2, 1],
            crate::contact::test_models::material("lining", 1e9),
        )
        .unwrap();
        let mesh = crate::contact::test_models::merge(disc, pad, "pad.");
        let err = node_to_surface(
            &mesh,
            &mesh.surfaces["pad.z0"],
            &mesh.surfaces["z1"],
            settings(rotation()),
            &SearchOptions::default(),
        )
        .unwrap_err();
        let ContactError::Unprojected {
            pair,
            count,
            examples,
            ..
        } = &err
        else {
            panic!("{err}");
        };
        assert_eq!(pair, "disc/pad");
        assert_eq!(*count, 6 * 5);
        assert_eq!(examples.len(), 10);
        for (label, x) in examples {
            assert!(x[0] > 1.04, "{label}: {x:?}");
            assert_eq!(mesh.nodes[(*label - 1) as usize], *x);
        }
        assert!(err.to_string().contains("30 slave node(s)"));
        // A pad floating 0.5 above the disc is beyond the default largest distance h = 0.14.
        let mesh = pad_on_disc(0.5);
        let err = node_to_surface(
            &mesh,
            &mesh.surfaces["pad.z0"],
            &mesh.surfaces["z1"],
            settings(rotation()),
            &SearchOptions::default(),
        )
        .unwrap_err();
        assert!(
            matches!(err, ContactError::Unprojected { count: 35, .. }),
            "{err}"
        );
        // ... and found with a larger one, with g0 = 0.5.
        let pair = node_to_surface(
            &mesh,
            &mesh.surfaces["pad.z0"],
            &mesh.surfaces["z1"],
            settings(rotation()),
            &SearchOptions {
                max_distance: Some(0.6),
                ..Default::default()
            },
        )
        .unwrap();
        assert!(pair
            .points
            .iter()
            .all(|p| (p.initial_gap - 0.5).abs() < 1e-15));
    }

    #[test]
    fn bad_settings_and_points_are_named() {
        let mesh = pad_on_disc(0.0);
        let run = |s: PairSettings| {
            node_to_surface(
                &mesh,
                &mesh.surfaces["pad.z0"],
                &mesh.surfaces["z1"],
                s,
                &SearchOptions::default(),
            )
            .unwrap_err()
            .to_string()
        };
        let mut s = settings(rotation());
        s.friction = -0.1;
        assert!(run(s).contains("'disc/pad': friction coefficient -0.1"));
        let mut s = settings(rotation());
        s.penalty = Some(f64::NAN);
        assert!(run(s).contains("penalty stiffness per unit area NaN"));
        let s = settings(SlidingDirection::DiscRotation {
            centre: [0.0; 3],
            axis: [0.0; 3],
            sense: 1.0,
        });
        assert!(run(s).contains("rotation axis"));
        let s = settings(SlidingDirection::DiscRotation {
            centre: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            sense: 0.0,
        });
        assert!(run(s).contains("rotation sense"));
        assert!(run(settings(SlidingDirection::Fixed([0.0; 3]))).contains("sliding direction"));
        let empty = Surface::default();
        let err = node_to_surface(
            &mesh,
            &empty,
            &mesh.surfaces["z1"],
            settings(rotation()),
            &SearchOptions::default(),
        )
        .unwrap_err();
        assert!(err.to_string().contains("slave surface '' has no faces"));

        let good = ContactPoint {
            slave: vec![(0, 1.0)],
            master: vec![(1, 0.25), (2, 0.75)],
            normal: [0.0, 0.0, 1.0],
            initial_gap: 0.0,
            area: 1.0,
            tangent: Some([1.0, 0.0, 0.0]),
            position: [0.0; 3],
            slave_node: 0,
            master_face: None,
            tilt: None,
        };
        assert!(node_to_node(settings(rotation()), 1.0, vec![good.clone()]).is_ok());
        let check = |f: &dyn Fn(&mut ContactPoint), expect: &str| {
            let mut p = good.clone();
            f(&mut p);
            let text = node_to_node(settings(rotation()), 1.0, vec![good.clone(), p])
                .unwrap_err()
                .to_string();
            assert!(
                text.contains("contact point 1") && text.contains(expect),
                "{text}"
            );
        };
        check(&|p| p.normal = [0.0, 0.0, 2.0], "not a unit vector");
        check(&|p| p.area = 0.0, "area 0");
        check(&|p| p.master[0].1 = 0.5, "sum to 1.25");
        check(&|p| p.slave.clear(), "slave point has no nodes");
        check(&|p| p.tangent = Some([0.0, 0.0, 1.0]), "orthogonal");
        check(&|p| p.initial_gap = f64::INFINITY, "initial gap inf");
        let text = node_to_node(settings(rotation()), -1.0, vec![good])
            .unwrap_err()
            .to_string();
        assert!(
            text.contains("penalty stiffness per unit area -1"),
            "{text}"
        );
    }

    /// Timing of a whole node-to-surface construction at an industrial size (51,200 master
    /// faces, 5,041 slave nodes): run with
    /// `cargo test --release -- --ignored --nocapture node_to_surface_timing`.
    #[test]
    #[ignore]
    fn node_to_surface_timing() {
        use crate::contact::test_models::{material, merge};
        let t0 = std::time::Instant::now();
        let disc = crate::mesh::block::block(
            [0.0, 0.0, -0.01],
            [1.0, 1.0, 0.01],
            [160, 160, 1],
            material("steel", 210e9),
        )
        .unwrap();
        let pad = crate::mesh::block::block(
            [0.2, 0.3, 0.0],
            [0.5, 0.4, 0.01],
            [35, 35, 1],
            material("lining", 1e9),
        )
        .unwrap();
        let mesh = merge(disc, pad, "pad.");
        let meshing = t0.elapsed();
        let t1 = std::time::Instant::now();
        let pair = node_to_surface(
            &mesh,
            &mesh.surfaces["pad.z0"],
            &mesh.surfaces["z1"],
            settings(rotation()),
            &SearchOptions::default(),
        )
        .unwrap();
        let search = t1.elapsed();
        println!(
            "meshes built in {meshing:?}; {} master faces, {} slave nodes projected in {search:?}",
            mesh.surfaces["z1"].faces.len(),
            pair.points.len()
        );
        assert_eq!(pair.points.len(), 71 * 71);
    }

    #[test]
    fn sliding_directions_vanish_on_the_axis_and_along_the_normal() {
        let n = [0.0, 0.0, 1.0];
        let disc = rotation();
        assert_eq!(disc.tangent([0.5, 0.5, 0.0], n), None);
        let t = disc.tangent([1.0, 0.5, 0.0], n).unwrap();
        assert!(norm(sub(t, [0.0, -1.0, 0.0])) < 1e-15);
        assert_eq!(
            SlidingDirection::Fixed([0.0, 0.0, -3.0]).tangent([0.0; 3], n),
            None
        );
        let t = SlidingDirection::Fixed([3.0, 0.0, 4.0])
            .tangent([0.0; 3], n)
            .unwrap();
        assert_eq!(t, [1.0, 0.0, 0.0]);
        assert_eq!(SlidingDirection::None.tangent([1.0; 3], n), None);
    }
}
