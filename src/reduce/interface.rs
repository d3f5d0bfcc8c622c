//! The reduced-interface model (the paper's Abaqus12/44/104/212; METHOD.md section 5): the
//! full model with each swept (disc/pad) node-to-surface pair replaced by a few node-to-node
//! contacts between reduced contact nodes.
//!
//! For each reduced contact node k of a pad's isometric grid ([`super::grid`]):
//! - a pad contact node c_k, an extra node (in no element) at the node's position on the pad
//!   face, tied by a stiff isotropic spring to the weighted mean of its distributing
//!   coupling's pad nodes: energy (k_s/2) |u_c - sum_i wbar_i u_i|^2 ([`super::coupling`]);
//! - a disc node d_k at the projection of c_k on the disc face, tied the same way to that
//!   face's six nodes by the face's shape functions there (the paper remeshed the disc to
//!   put a node there; a tie to the face needs no remesh);
//! - a node-to-node penalty contact between c_k and d_k: the disc face's normal and the gap
//!   there, the pair's mu, sliding direction and separation flag, and the penalty per unit
//!   area times the node's tributary area (so the total contact stiffness of a pad is the
//!   full model's).
//!
//! Every other pair, support, spring and load is kept, so the result is a [`Model`] like any
//! other and runs through the same statics, CEA, sweep, tracking and outputs: a full-size
//! model with a reduced interface. The contact nodes are the reduction nodes of the
//! Craig-Bampton super-elements built next.
//!
//! The tie springs: far stiffer than what they hold, so that they only transmit. The stiffest
//! thing a tie holds is its own contact, k_n A_k (10 E / h per unit area by default: already
//! stiffer than the pad's material under a patch), so k_s defaults to
//! [`DEFAULT_SPRING_FACTOR`] k_n A_k; its effect on the eigenvalues is measured by
//! multiplying it by 10 and 100 (`tests/reduced_interface.rs`).

use super::coupling::{couple_grid, DistributingCoupling, Weighting};
use super::grid::{isometric_grid, ContactGrid, GridSize};
use super::radius::{grid_optimal, paper_radius};
use super::ReduceError;
use crate::contact::project::SurfaceSearch;
use crate::contact::{self, ContactPoint};
use crate::fem::springs::CouplingSpring;
use crate::model::Model;

/// k_s = this times the contact stiffness k_n A_k of the node it ties (see the module doc).
pub const DEFAULT_SPRING_FACTOR: f64 = 1e3;

/// Gaps below this fraction of the disc's face size are round-off (see [`reduce_interface`]).
const TOUCHING: f64 = 1e-9;

/// The radius of influence of the distributing couplings.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RadiusChoice {
    /// The radius that makes the normalised load most uniform over a whole grid
    /// ([`grid_optimal`]), times the grid side h.
    GridOptimal,
    /// The paper's elementary-triangle radius (Table 2, [`paper_radius`]), times h.
    Paper,
    /// A radius in mesh units.
    #[serde(untagged)]
    Length(f64),
}

/// How to reduce the interface.
#[derive(Clone, Debug, PartialEq)]
pub struct InterfaceSettings {
    /// Reduced contact nodes per pad (or the grid side).
    pub size: GridSize,
    pub weighting: Weighting,
    pub radius: RadiusChoice,
    /// k_s of every tie spring (N/m); `None`: [`DEFAULT_SPRING_FACTOR`] k_n A_k per node.
    pub spring_stiffness: Option<f64>,
    /// The default k_s multiplied by this (1 normally; 10 and 100 to measure its effect).
    pub spring_factor: f64,
}

impl Default for InterfaceSettings {
    fn default() -> Self {
        InterfaceSettings {
            size: GridSize::Count(52),
            weighting: Weighting::Cubic,
            radius: RadiusChoice::GridOptimal,
            spring_stiffness: None,
            spring_factor: 1.0,
        }
    }
}

/// One pad's reduced interface.
#[derive(Clone, Debug)]
pub struct ReducedPad {
    /// The pair it replaces.
    pub pair: String,
    pub grid: ContactGrid,
    /// Radius of influence used (mesh units).
    pub radius: f64,
    pub couplings: Vec<DistributingCoupling>,
    /// Model node index of each reduced contact node's pad contact node c_k and disc node
    /// d_k (extra nodes), in the grid's order.
    pub contact_nodes: Vec<usize>,
    pub disc_nodes: Vec<usize>,
    /// k_s of each node's ties.
    pub spring_stiffness: Vec<f64>,
}

/// A reduced-interface model and what was reduced.
#[derive(Clone, Debug)]
pub struct ReducedInterface {
    pub model: Model,
    pub pads: Vec<ReducedPad>,
}

impl ReducedInterface {
    /// One line per pad: count, h, radius, k_s.
    pub fn summary(&self) -> String {
        self.pads
            .iter()
            .map(|p| {
                let ks = p.spring_stiffness.iter().fold(0.0, |a: f64, &b| a.max(b));
                format!(
                    "{}: {}; radius of influence {:.4e} ({:.3} h), tie springs up to {:.3e} N/m",
                    p.pair,
                    p.grid.summary(),
                    p.radius,
                    p.radius / p.grid.spacing,
                    ks
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }
}

/// The radius of influence for a grid of side h.
pub fn radius_for(choice: RadiusChoice, weighting: Weighting, h: f64) -> Result<f64, ReduceError> {
    let r = match choice {
        RadiusChoice::GridOptimal => grid_optimal(weighting).map(|(r, _)| r * h),
        RadiusChoice::Paper => Some(paper_radius(weighting) * h),
        RadiusChoice::Length(r) => Some(r),
    };
    r.filter(|r| r.is_finite() && *r > 0.0)
        .ok_or(ReduceError::InvalidRadius {
            reduced_node: 0,
            radius: r.unwrap_or(f64::NAN),
        })
}

/// Replaces every swept node-to-surface pair of `model` by a reduced interface.
pub fn reduce_interface(
    model: &Model,
    settings: &InterfaceSettings,
) -> Result<ReducedInterface, ReduceError> {
    let mut reduced = model.clone();
    let mut pads = Vec::new();
    let swept: Vec<usize> = (0..model.pairs.len()).filter(|&i| model.swept[i]).collect();
    if swept.is_empty() {
        return Err(ReduceError::NothingToReduce);
    }
    for i in swept {
        let pair = &model.pairs[i];
        let name = pair.settings.name.clone();
        let Some(Some((slave_name, master_name))) = model.pair_surfaces.get(i) else {
            return Err(ReduceError::NotNodeToSurface { pair: name });
        };
        let mesh = &model.mesh;
        let surface = |n: &str| {
            mesh.surfaces
                .get(n)
                .ok_or_else(|| ReduceError::InvalidSurface {
                    surface: n.to_string(),
                    why: "is not in the mesh".into(),
                })
        };
        let (slave, master) = (surface(slave_name)?, surface(master_name)?);
        let grid = isometric_grid(mesh, slave, settings.size)?;
        let radius = radius_for(settings.radius, settings.weighting, grid.spacing)?;
        let couplings = couple_grid(mesh, slave, &grid, radius, settings.weighting)?;
        let faces: Vec<[[f64; 3]; 6]> = master
            .faces
            .iter()
            .map(|f| f.nodes.map(|n| mesh.nodes[n]))
            .collect();
        let search = SurfaceSearch::new(faces).map_err(|k| ReduceError::InvalidSurface {
            surface: master_name.clone(),
            why: format!("face {k} is degenerate"),
        })?;
        // As far as a node-to-surface pair looks for its master point.
        let reach = search.mean_face_size();
        let mut points = Vec::with_capacity(grid.nodes.len());
        let mut pad = ReducedPad {
            pair: name.clone(),
            grid: grid.clone(),
            radius,
            couplings: couplings.clone(),
            contact_nodes: Vec::new(),
            disc_nodes: Vec::new(),
            spring_stiffness: Vec::new(),
        };
        for (k, (node, coupling)) in grid.nodes.iter().zip(&couplings).enumerate() {
            let p = node.position;
            let hit = search
                .nearest(p, 1e-6, reach)
                .ok_or(ReduceError::Unprojected {
                    pair: name.clone(),
                    reduced_node: k,
                    position: p,
                    surface: master_name.clone(),
                })?;
            let c = reduced.node_count();
            reduced.extra_nodes.push(p);
            let d = reduced.node_count();
            reduced.extra_nodes.push(hit.point);
            let k_contact = pair.penalty * node.area;
            let k_s = settings
                .spring_stiffness
                .unwrap_or(DEFAULT_SPRING_FACTOR * k_contact)
                * settings.spring_factor;
            let mut pad_tie = vec![(c, 1.0)];
            pad_tie.extend(coupling.nodes.iter().map(|n| (n.node, -n.weight)));
            let face = &master.faces[hit.face];
            let mut disc_tie = vec![(d, 1.0)];
            disc_tie.extend(
                face.nodes
                    .iter()
                    .zip(crate::fem::tet10::face_shape(hit.q))
                    .map(|(&n, w)| (n, -w)),
            );
            reduced.couplings.push(CouplingSpring {
                terms: pad_tie,
                stiffness: k_s,
            });
            reduced.couplings.push(CouplingSpring {
                terms: disc_tie,
                stiffness: k_s,
            });
            // The contact node lies on the pad face by construction, found by intersecting a
            // line with a curved face: a gap at round-off level is a touching pad (closed at
            // the first Newton step, as the full model's coincident nodes are), not an open
            // one that leaves the pad free and the first tangent singular.
            let initial_gap = if hit.gap.abs() <= TOUCHING * reach {
                0.0
            } else {
                hit.gap
            };
            points.push(ContactPoint {
                slave: vec![(c, 1.0)],
                master: vec![(d, 1.0)],
                normal: hit.normal,
                initial_gap,
                area: node.area,
                tangent: pair.settings.sliding.tangent(p, hit.normal),
                position: p,
                slave_node: c,
                master_face: None,
            });
            pad.contact_nodes.push(c);
            pad.disc_nodes.push(d);
            pad.spring_stiffness.push(k_s);
        }
        reduced.pairs[i] = contact::node_to_node(pair.settings.clone(), pair.penalty, points)
            .map_err(|e| ReduceError::InvalidSurface {
                surface: slave_name.clone(),
                why: e.to_string(),
            })?;
        reduced.pair_surfaces[i] = None;
        pads.push(pad);
    }
    reduced.source = format!(
        "{} (reduced interface: {})",
        model.source,
        pads.iter()
            .map(|p| format!("{} nodes", p.grid.count()))
            .collect::<Vec<_>>()
            .join(" + ")
    );
    Ok(ReducedInterface {
        model: reduced,
        pads,
    })
}
