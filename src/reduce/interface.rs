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
//!   put a node there; a tie to the face needs no remesh), or, on request
//!   ([`DiscCoupling::Distributing`]), to the disc face's nodes within the pad side's radius
//!   of influence by a distributing coupling of the pad side's weighting;
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
//! multiplying it by 10 and 100 (`tests/numerics/reduced_interface.rs`).

use super::coupling::{couple_grid, couple_points, couple_shares, DistributingCoupling, Weighting};
use super::grid::{isometric_grid, ContactGrid, GridSize};
use super::pairs::ReducePairs;
use super::radius::{grid_optimal, paper_radius};
use super::tilt::{self, PatchQuadrature};
use super::ReduceError;
use crate::contact::project::SurfaceSearch;
use crate::contact::{self, ContactPoint};
use crate::fem::springs::CouplingSpring;
use crate::model::Model;
use std::collections::BTreeMap;

/// k_s = this times the contact stiffness k_n A_k of the node it ties (see the module doc).
pub const DEFAULT_SPRING_FACTOR: f64 = 1e3;

/// A kept pair's k_s: this times its contact stiffness k_n A_k. A kept pair's penalty is
/// 10 E / h of its stiffer body (steel on steel at the caliper's pairs, 50 times the disc/pad
/// pairs' on tiny-caliper), so [`DEFAULT_SPRING_FACTOR`] put its ties at 6e13-9e13 N/m: the
/// CEA's eigenpairs there had relative residuals of 2.6e-6, above its 1e-6 bound, at mu 0.6.
/// Measured on tiny-caliper with every pair reduced (mu 0.3, 40 modes to 6 kHz): 100 moves
/// the eigenvalues by at most 6.4e-5 from 1000, and 10 by 6.9e-4 (the ties' compliance in
/// series, falling as 1/factor): at 100 they transmit as rigidly as the reduction needs.
pub const KEPT_SPRING_FACTOR: f64 = 1e2;

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

/// How a disc node d_k is tied to the disc face it lies on.
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
#[serde(rename_all = "kebab-case")]
pub enum DiscCoupling {
    /// [`DiscCoupling::Share`] where the pad couplings are share couplings,
    /// [`DiscCoupling::ShapeFunctions`] otherwise: the disc side held as the pad side is.
    #[default]
    Auto,
    /// To the six nodes of the face it lies on, by the face's shape functions there: the
    /// displacement of the disc surface at that point, exactly.
    ShapeFunctions,
    /// To the disc face's nodes within the radius of influence, by a distributing coupling
    /// with the pad side's weighting and radius (the paper's reduced disc node, which
    /// stands for a patch of the disc as the pad's stands for a patch of the pad).
    Distributing,
    /// To the disc surface under the node's share of the pad face: the share's quadrature
    /// points projected on the disc, each face's shape functions there weighted by the
    /// point's area over the share's. The tie holds the disc surface's mean displacement
    /// over the share, and spreads the share's force over it as a uniform pressure, where
    /// the other two put it on one point or on the coupling's weights.
    Share,
}

/// How a reduced contact node c_k is tied to the pad face.
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
#[serde(rename_all = "kebab-case")]
pub enum PadCoupling {
    /// [`PadCoupling::Share`] where every share of every pad holds a face node and some
    /// share of each pad a slope of its own (a share whose nodes lie on one line, or too
    /// thin a strip, reads its nearest neighbour's tilt nodes,
    /// [`super::tilt::slope_owners`]) and the contacts carry patch laws;
    /// [`PadCoupling::Distributing`] otherwise (see [`InterfaceSettings::resolved`]). On
    /// small-caliper with 52 nodes per pad, share couplings found 16 of the full model's 18
    /// instabilities where the paper's couplings found 13 with patch laws, and took its
    /// pad-rocking mode without friction from -1.93 % to -0.03 % (issue 29's note).
    #[default]
    Auto,
    /// To the pad face's nodes within the radius of influence, by the weighting's profile
    /// (the paper's distributing coupling; neighbouring couplings overlap).
    Distributing,
    /// To the pad face's nodes of its own share, each by its tributary area (the share's
    /// uniform pressure; the couplings partition the face,
    /// [`super::coupling::couple_shares`]).
    Share,
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
    /// How each reduced contact node is tied to the pad face.
    pub pad_coupling: PadCoupling,
    /// How each disc node is tied to the disc face.
    pub disc_coupling: DiscCoupling,
    /// Distributing couplings weigh each node by its tributary area too
    /// ([`DistributingCoupling::area_weighted`]); false: the paper's weights alone. Share
    /// couplings weigh by area either way.
    pub area_weighting: bool,
    /// Each reduced contact carries its patch law ([`super::tilt`]); false: the paper's
    /// point contacts alone; `None`: patch laws with share couplings, where every swept
    /// pair is unilateral and slides steadily (squeal's law, not CalculiX's), point
    /// contacts otherwise (see [`InterfaceSettings::resolved`]).
    pub tilt: Option<bool>,
    /// Each share's warping springs ([`super::warp`]): the full model's penalty against the
    /// pad face's warping inside the share, which a patch law does not see. Opt-in: they
    /// stand on patch laws over share couplings, and what they are worth depends on the
    /// mesh (issue 29's note: better on tiny-caliper at 22 and small-caliper at 52 nodes per
    /// pad, worse at 106).
    pub warp_springs: bool,
    /// Where each patch law integrates the penalty over its share.
    pub patch_quadrature: PatchQuadrature,
    /// Which pairs are reduced besides the swept ones ([`super::pairs`]).
    pub reduce_pairs: ReducePairs,
    /// A reduced kept pair's own grid, by pair name (default: the swept pads' grid side).
    pub pair_grids: BTreeMap<String, GridSize>,
    /// Kept pairs with patch laws of their own asked for (`[reduction.pairs."name"] tilt`);
    /// every other kept pair has point contacts.
    pub pair_tilts: BTreeMap<String, bool>,
}

impl Default for InterfaceSettings {
    fn default() -> Self {
        InterfaceSettings {
            size: GridSize::Count(52),
            weighting: Weighting::Cubic,
            radius: RadiusChoice::GridOptimal,
            spring_stiffness: None,
            spring_factor: 1.0,
            pad_coupling: PadCoupling::Auto,
            disc_coupling: DiscCoupling::Auto,
            area_weighting: false,
            tilt: None,
            warp_springs: false,
            patch_quadrature: PatchQuadrature::Nodes,
            reduce_pairs: ReducePairs::Swept,
            pair_grids: BTreeMap::new(),
            pair_tilts: BTreeMap::new(),
        }
    }
}

/// One pad's reduced interface.
#[derive(Clone, Debug)]
pub struct ReducedPad {
    /// The pair it replaces.
    pub pair: String,
    pub grid: ContactGrid,
    /// Radius of influence used (mesh units): the couplings' with distributing ones, the
    /// disc-side patches' either way.
    pub radius: f64,
    pub pad_coupling: PadCoupling,
    pub couplings: Vec<DistributingCoupling>,
    /// Model node index of each reduced contact node's pad contact node c_k and disc node
    /// d_k (extra nodes), in the grid's order.
    pub contact_nodes: Vec<usize>,
    pub disc_nodes: Vec<usize>,
    /// Per reduced contact node, the disc face nodes its disc node d_k is tied to and their
    /// weights (adding up to 1): the face's shape functions or a distributing coupling.
    pub disc_ties: Vec<Vec<(usize, f64)>>,
    /// k_s of each node's ties.
    pub spring_stiffness: Vec<f64>,
    /// Model node indices of each reduced contact node's tilt nodes (pad side, disc side;
    /// [`super::tilt`]), in the grid's order; empty without patch laws. A share that reads
    /// its neighbour's has the neighbour's ([`tilt::slope_owners`]).
    pub tilt_nodes: Vec<[usize; 2]>,
    /// Whether the pair is swept (a disc/pad interface, the super-elements' boundary) or a
    /// kept pair reduced too ([`super::pairs`]).
    pub swept: bool,
    /// How many of its share couplings read their nearest neighbour's tilt nodes (their
    /// own face nodes lie on one line, [`tilt::slope_owners`]).
    pub borrowed_slopes: usize,
    /// Where its patch laws integrate their shares: at the face nodes only over share
    /// couplings with [`PatchQuadrature::Nodes`] asked for; `None` without patch laws.
    pub quadrature: Option<PatchQuadrature>,
    /// How many warping springs hold its pad face within the shares ([`super::warp`]): one
    /// per face node, none without them.
    pub warp_springs: usize,
}

/// A reduced-interface model and what was reduced.
#[derive(Clone, Debug)]
pub struct ReducedInterface {
    pub model: Model,
    pub pads: Vec<ReducedPad>,
    /// The settings it was made with, every automatic choice made.
    pub settings: InterfaceSettings,
    /// What the automatic choices chose and why, when any was left to squeal.
    pub choice: Option<String>,
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

/// The disc face nodes and weights each disc node is tied to (see [`DiscCoupling`]), the
/// disc nodes at `hits` on the master surface.
#[allow(clippy::too_many_arguments)]
fn disc_ties(
    mesh: &crate::mesh::Mesh,
    master: &crate::mesh::Surface,
    hits: &[crate::contact::project::SurfaceHit],
    radius: f64,
    settings: &InterfaceSettings,
    grid: &super::grid::ContactGrid,
    search: &SurfaceSearch,
    reach: f64,
) -> Result<Vec<Vec<(usize, f64)>>, ReduceError> {
    match settings.disc_coupling {
        DiscCoupling::Share => grid
            .nodes
            .iter()
            .zip(hits)
            .map(|(node, hit)| {
                let axes = grid.plane.axes;
                let area: f64 = node.patch.iter().map(|p| p.1).sum();
                let mut weights = std::collections::BTreeMap::new();
                for &(xi, a) in &node.patch {
                    let at = [0, 1, 2]
                        .map(|c| node.position[c] + xi[0] * axes[0][c] + xi[1] * axes[1][c]);
                    // A quadrature point past the disc's edge takes the node's own point.
                    let h = search.nearest(at, 1e-6, reach).unwrap_or(*hit);
                    let face = &master.faces[h.face];
                    for (&n, w) in face.nodes.iter().zip(crate::fem::tet10::face_shape(h.q)) {
                        *weights.entry(n).or_insert(0.0) += w * a / area;
                    }
                }
                Ok(weights.into_iter().collect())
            })
            .collect(),
        DiscCoupling::ShapeFunctions => Ok(hits
            .iter()
            .map(|hit| {
                master.faces[hit.face]
                    .nodes
                    .iter()
                    .zip(crate::fem::tet10::face_shape(hit.q))
                    .map(|(&n, w)| (n, w))
                    .collect()
            })
            .collect()),
        DiscCoupling::Auto => unreachable!("resolved by reduce_interface"),
        DiscCoupling::Distributing => {
            let points: Vec<[f64; 3]> = hits.iter().map(|h| h.point).collect();
            let disc_side = |e: ReduceError| ReduceError::InvalidSurface {
                surface: master.name.clone(),
                why: format!("disc-side distributing coupling: {e}"),
            };
            let mut couplings = couple_points(mesh, master, &points, radius, settings.weighting)
                .map_err(disc_side)?;
            if settings.area_weighting {
                let areas = contact::tributary_areas(mesh, master).into_iter().collect();
                couplings = couplings
                    .into_iter()
                    .map(|c| c.area_weighted(&areas))
                    .collect::<Result<_, _>>()
                    .map_err(disc_side)?;
            }
            Ok(couplings
                .iter()
                .map(|c| c.nodes.iter().map(|n| (n.node, n.weight)).collect())
                .collect())
        }
    }
}

/// The disc patch under each of `hits` whose slope a tilt node reads: a distributing
/// coupling of the pad side's radius and weighting (area-weighted as the pad side is), what
/// the disc ties use when they are distributing ones.
fn disc_patches(
    mesh: &crate::mesh::Mesh,
    master: &crate::mesh::Surface,
    hits: &[crate::contact::project::SurfaceHit],
    radius: f64,
    settings: &InterfaceSettings,
    plane_axes: [[f64; 3]; 2],
) -> Result<Vec<DistributingCoupling>, ReduceError> {
    let disc_side = |e: ReduceError| ReduceError::InvalidSurface {
        surface: master.name.clone(),
        why: format!("disc-side patch of a tilt node: {e}"),
    };
    let areas: std::collections::BTreeMap<usize, f64> = if settings.area_weighting {
        contact::tributary_areas(mesh, master).into_iter().collect()
    } else {
        Default::default()
    };
    let mut couplings = Vec::with_capacity(hits.len());
    for hit in hits {
        // The disc is meshed coarser than a fine grid's spacing: a patch of the pad side's
        // radius may catch two disc nodes, which give no slope across their line. Widen it
        // (the disc's face is stiff and smooth under a patch) until it gives one.
        let mut r = radius;
        let mut made = None;
        for _ in 0..6 {
            let Ok(mut found) = couple_points(mesh, master, &[hit.point], r, settings.weighting)
            else {
                r *= 1.5;
                continue;
            };
            let mut c = found.remove(0);
            if settings.area_weighting {
                c = c.area_weighted(&areas).map_err(disc_side)?;
            }
            let slope = tilt::axes(plane_axes, hit.normal)
                .and_then(|e| tilt::slope_terms(&tilt::patch(&c, &mesh.nodes), e, hit.normal));
            if slope.is_some() {
                made = Some(c);
                break;
            }
            r *= 1.5;
        }
        couplings.push(made.ok_or_else(|| ReduceError::InvalidSurface {
            surface: master.name.clone(),
            why: format!(
                "no disc-side patch gives a slope under a tilt node at ({:.4e}, {:.4e}, \
                 {:.4e}): none up to {:.3e} (the radius of influence {radius:.3e}, widened \
                 by 1.5 five times) holds three disc nodes off one line (give a larger radius, \
                 or reduction.tilt = false)",
                hit.point[0],
                hit.point[1],
                hit.point[2],
                r / 1.5
            ),
        })?);
    }
    Ok(couplings)
}

/// What in `pair`'s law a patch law would not carry: CalculiX's smoothed law (a bilateral
/// pair keeps squeal's law, CalculiX having none, and pulls at every quadrature point).
/// Coulomb stick and slip it carries:
/// the cone's radius is mu times the patch's normal force, and a slipping point's friction
/// follows the patch's tilt in the tangent (`contact::penalty::evaluate`).
fn patch_law_problem(pair: &contact::ContactPair) -> Option<String> {
    let s = &pair.settings;
    if s.separation && s.calculix.is_some() {
        Some("CalculiX's contact law".into())
    } else {
        None
    }
}

impl InterfaceSettings {
    /// The paper's reduced interface of `size`: distributing couplings over its radius of
    /// influence, each disc node tied to the disc face at its one point, point contacts.
    pub fn paper(size: GridSize) -> Self {
        InterfaceSettings {
            size,
            pad_coupling: PadCoupling::Distributing,
            disc_coupling: DiscCoupling::ShapeFunctions,
            tilt: Some(false),
            ..Default::default()
        }
    }

    /// These settings with every automatic choice made for the swept pairs `swept` of
    /// `model`, one choice for the whole interface so that both pads are reduced alike:
    /// squeal's interface (share couplings on both sides, patch laws) where every pad's
    /// shares can hold a coupling and every pair's law admits a patch law, the paper's
    /// (distributing couplings, the disc tied at one point, point contacts) otherwise.
    ///
    /// Share couplings are what make patch laws safe on any mesh they fit: shares are
    /// disjoint, so each one's translation and slope ties bind three or more face nodes of
    /// their own, and the ties are independent. The paper's couplings overlap: on a mesh
    /// with few face nodes per coupling (`tiny`, 22 nodes per pad), the slope ties of
    /// neighbouring couplings bind the same nodes: there, patch laws on the paper's
    /// couplings gave a single super-element whose reduced mass is not positive definite
    /// (measured; dependent ties of the massless tilt nodes would do that).
    pub fn resolved(
        &self,
        model: &Model,
        swept: &[usize],
    ) -> Result<InterfaceSettings, ReduceError> {
        Ok(self.resolved_with_reason(model, swept)?.0)
    }

    /// [`Self::resolved`], and a sentence on what was chosen and why when anything was left
    /// to choose.
    fn resolved_with_reason(
        &self,
        model: &Model,
        swept: &[usize],
    ) -> Result<(InterfaceSettings, Option<String>), ReduceError> {
        let mut s = self.clone();
        let automatic = s.pad_coupling == PadCoupling::Auto || s.tilt.is_none();
        // Chosen by default where every swept pair is unilateral and slides steadily (the
        // disc/pad pairs): patch laws carry Coulomb stick and slip and bilateral pairs too,
        // but nothing has measured them on such a swept pair.
        let laws_fit = swept.iter().all(|&i| {
            let pair = &model.pairs[i];
            patch_law_problem(pair).is_none()
                && pair.settings.separation
                && pair.settings.law == contact::FrictionLaw::SteadySliding
        });
        if s.pad_coupling == PadCoupling::Auto {
            let wanted = s.tilt.unwrap_or(laws_fit);
            s.pad_coupling = if wanted && shares_fit(model, swept, s.size)? {
                PadCoupling::Share
            } else {
                PadCoupling::Distributing
            };
        }
        if s.tilt.is_none() {
            s.tilt = Some(laws_fit && s.pad_coupling == PadCoupling::Share);
        }
        let shares_with_laws = s.tilt == Some(true) && s.pad_coupling == PadCoupling::Share;
        if s.warp_springs && !shares_with_laws {
            return Err(ReduceError::WarpSprings);
        }
        if s.disc_coupling == DiscCoupling::Auto {
            s.disc_coupling = match s.pad_coupling {
                PadCoupling::Share => DiscCoupling::Share,
                _ => DiscCoupling::ShapeFunctions,
            };
        }
        let reason = automatic.then(|| {
            let why = if !laws_fit {
                "a swept pair is bilateral or its law is not squeal's steady sliding"
            } else if self.tilt == Some(false) {
                "point contacts asked for"
            } else if s.pad_coupling == PadCoupling::Share {
                "every share of the pad faces holds a face node"
            } else {
                "a share of the pad faces would hold no face node, or no share of a pad a \
                 slope"
            };
            let (pad, laws) = (
                if s.pad_coupling == PadCoupling::Share {
                    "share couplings"
                } else {
                    "the paper's distributing couplings"
                },
                if s.tilt == Some(true) {
                    "patch laws"
                } else {
                    "point contacts"
                },
            );
            format!("chosen by default: {pad} with {laws} ({why})")
        });
        Ok((s, reason))
    }

    /// Whether each reduced contact carries its patch law (after [`Self::resolved`]).
    fn patch_laws(&self) -> bool {
        self.tilt == Some(true)
    }
}

/// Whether every swept pad face of `model` can be split into shares of a grid of `size`,
/// each with a face node ([`couple_shares`]) and a slope to read, its own or its nearest
/// neighbour's ([`tilt::slope_owners`]). A pair without its surfaces is left to
/// [`reduce_interface`] to refuse by name.
fn shares_fit(model: &Model, swept: &[usize], size: GridSize) -> Result<bool, ReduceError> {
    for slave in swept
        .iter()
        .filter_map(|&i| model.pair_surfaces.get(i).cloned().flatten())
        .filter_map(|(slave, _)| model.mesh.surfaces.get(&slave))
    {
        let grid = isometric_grid(&model.mesh, slave, size)?;
        let couplings = match couple_shares(&model.mesh, slave, &grid) {
            Ok(c) => c,
            Err(ReduceError::ShareTooSmall { .. }) => return Ok(false),
            Err(e) => return Err(e),
        };
        if tilt::slope_owners(&couplings, &grid, &model.mesh.nodes).is_none() {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Replaces every swept node-to-surface pair of `model` by a reduced interface.
pub fn reduce_interface(
    model: &Model,
    settings: &InterfaceSettings,
) -> Result<ReducedInterface, ReduceError> {
    // A model's constraints stay as they are: the reduced interface appends its nodes, and
    // its model is assembled with them like any other (C^T K C).
    let mut reduced = model.clone();
    let mut pads: Vec<ReducedPad> = Vec::new();
    let swept: Vec<usize> = (0..model.pairs.len()).filter(|&i| model.swept[i]).collect();
    if swept.is_empty() {
        return Err(ReduceError::NothingToReduce);
    }
    let (resolved, choice) = settings.resolved_with_reason(model, &swept)?;
    // The swept pairs first: a kept pair's default grid side is theirs.
    let order: Vec<usize> = swept
        .iter()
        .copied()
        .chain(kept_pairs(model, &resolved)?)
        .collect();
    for i in order {
        let kept;
        let settings = if model.swept[i] {
            &resolved
        } else {
            kept = kept_settings(model, i, &resolved, pads[0].grid.spacing)?;
            &kept
        };
        let pair = &model.pairs[i];
        let name = pair.settings.name.clone();
        if settings.patch_laws() {
            patch_law_problem(pair).map_or(Ok(()), |law| {
                Err(ReduceError::PatchLaw {
                    pair: name.clone(),
                    law,
                })
            })?;
        }
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
        let mut couplings = match settings.pad_coupling {
            PadCoupling::Distributing => {
                couple_grid(mesh, slave, &grid, radius, settings.weighting)?
            }
            PadCoupling::Share => couple_shares(mesh, slave, &grid)?,
            PadCoupling::Auto => unreachable!("resolved above"),
        };
        if settings.area_weighting && settings.pad_coupling == PadCoupling::Distributing {
            let areas = contact::tributary_areas(mesh, slave).into_iter().collect();
            couplings = couplings
                .into_iter()
                .map(|c| c.area_weighted(&areas))
                .collect::<Result<_, _>>()?;
        }
        let search = SurfaceSearch::of_surface(mesh, master).map_err(|face| {
            ReduceError::InvalidSurface {
                surface: master_name.clone(),
                why: format!(
                    "face S{} of element {} is degenerate",
                    face.side + 1,
                    mesh.element_labels[face.element]
                ),
            }
        })?;
        // As far as a node-to-surface pair looks for its master point.
        let reach = search.mean_face_size();
        let mut points = Vec::with_capacity(grid.nodes.len());
        let mut pad = ReducedPad {
            pair: name.clone(),
            grid: grid.clone(),
            radius,
            pad_coupling: settings.pad_coupling,
            couplings: couplings.clone(),
            contact_nodes: Vec::new(),
            disc_nodes: Vec::new(),
            disc_ties: Vec::new(),
            spring_stiffness: Vec::new(),
            tilt_nodes: Vec::new(),
            swept: model.swept[i],
            borrowed_slopes: 0,
            quadrature: None,
            warp_springs: 0,
        };
        // Whose tilt nodes each reduced contact's patch law reads: its own, or with share
        // couplings, where a share's nodes lie on one line, its nearest neighbour's.
        let owners: Vec<usize> = match (settings.patch_laws(), settings.pad_coupling) {
            (true, PadCoupling::Share) => tilt::slope_owners(&couplings, &grid, &mesh.nodes)
                .ok_or_else(|| ReduceError::Tilt {
                    pair: name.clone(),
                    reduced_node: 0,
                    why: "no share of the pad face has face nodes off one line: no slope to \
                          read"
                        .into(),
                })?,
            _ => (0..couplings.len()).collect(),
        };
        pad.borrowed_slopes = owners.iter().enumerate().filter(|&(k, &o)| o != k).count();
        let hits = grid
            .nodes
            .iter()
            .enumerate()
            .map(|(k, node)| {
                search
                    .nearest(node.position, 1e-6, reach)
                    .ok_or(ReduceError::Unprojected {
                        pair: name.clone(),
                        reduced_node: k,
                        position: node.position,
                        surface: master_name.clone(),
                    })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let disc_ties = disc_ties(mesh, master, &hits, radius, settings, &grid, &search, reach)?;
        let disc_patches = if settings.patch_laws() {
            disc_patches(mesh, master, &hits, radius, settings, grid.plane.axes)?
        } else {
            Vec::new()
        };
        // The share as its patch law integrates it: at its nodes on shares with patch laws.
        let nodal = settings.patch_laws()
            && settings.patch_quadrature == PatchQuadrature::Nodes
            && settings.pad_coupling == PadCoupling::Share;
        let areas = nodal.then(|| contact::tributary_areas(mesh, slave).into_iter().collect());
        pad.quadrature = settings.patch_laws().then_some(if nodal {
            PatchQuadrature::Nodes
        } else {
            PatchQuadrature::Area
        });
        let shares = tilt::shares(&grid, &couplings, areas.as_ref());
        for (k, ((node, coupling), hit)) in grid.nodes.iter().zip(&couplings).zip(&hits).enumerate()
        {
            let p = node.position;
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
            let mut disc_tie = vec![(d, 1.0)];
            disc_tie.extend(disc_ties[k].iter().map(|&(n, w)| (n, -w)));
            reduced.couplings.push(CouplingSpring {
                terms: pad_tie,
                stiffness: k_s,
            });
            reduced.couplings.push(CouplingSpring {
                terms: disc_tie,
                stiffness: k_s,
            });
            // A share that reads its neighbour's tilt nodes gets its law below, once every
            // owner has its nodes.
            let tilt = if settings.patch_laws() && owners[k] == k {
                let r = [reduced.node_count(), reduced.node_count() + 1];
                let made = tilt::node_tilt(
                    &name,
                    k,
                    r,
                    hit.normal,
                    grid.plane.axes,
                    &tilt::patch(coupling, &mesh.nodes),
                    &tilt::patch(&disc_patches[k], &mesh.nodes),
                    node.area,
                    node.second_moment,
                    &shares[k],
                    pair.penalty,
                    k_s,
                )?
                .ok_or_else(|| ReduceError::Tilt {
                    pair: name.clone(),
                    reduced_node: k,
                    why: format!(
                        "its share of the pad face (area {:.3e}) has no second moment",
                        node.area
                    ),
                })?;
                reduced.extra_nodes.push(p);
                reduced.extra_nodes.push(hit.point);
                reduced.scalar_springs.extend(made.ties);
                pad.tilt_nodes.push(r);
                // A bilateral pair's (the piston's, reduced as a kept pair) pulls at every
                // point of its share, as its full pair does.
                Some(contact::Tilt {
                    bilateral: !pair.settings.separation,
                    ..made.law
                })
            } else {
                if settings.patch_laws() {
                    pad.tilt_nodes.push([usize::MAX; 2]);
                }
                None
            };
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
                // The quadrature's area (the full pair's over the share's nodes with nodal).
                area: shares[k].iter().map(|q| q.1).sum(),
                tangent: pair.settings.sliding.tangent(p, hit.normal),
                position: p,
                slave_node: c,
                master_face: None,
                tilt,
            });
            pad.contact_nodes.push(c);
            pad.disc_nodes.push(d);
            pad.disc_ties.push(disc_ties[k].clone());
            pad.spring_stiffness.push(k_s);
        }
        for (k, &owner) in owners.iter().enumerate() {
            if owner == k || !settings.patch_laws() {
                continue;
            }
            let law = points[owner]
                .tilt
                .as_ref()
                .expect("an owner has its own tilt nodes");
            let shared = tilt::shared_tilt(
                law,
                points[k].normal,
                grid.plane.axes,
                &shares[k],
                pair.penalty,
            )
            .ok_or_else(|| ReduceError::Tilt {
                pair: name.clone(),
                reduced_node: k,
                why: "its normal lies in the grid's plane".into(),
            })?;
            pad.tilt_nodes[k] = shared.nodes;
            points[k].tilt = Some(shared);
        }
        if settings.warp_springs && settings.patch_laws() {
            let springs = super::warp::pad_springs(
                &points,
                &couplings,
                &pad.contact_nodes,
                &mesh.nodes,
                pair.penalty,
            );
            pad.warp_springs = springs.len();
            reduced.scalar_springs.extend(springs);
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
        settings: resolved,
        choice,
    })
}

/// The kept (not swept) pairs `settings.reduce_pairs` asks to reduce, in the model's order;
/// a name in it or in `settings.pair_grids` that is no pair of the model, a grid given to a
/// swept pair or to a pair that is not reduced, and a named pair that is not node-to-surface
/// are refused by name. `"all"` takes every node-to-surface pair (a deck's node-to-node pair
/// is already point contacts).
fn kept_pairs(model: &Model, settings: &InterfaceSettings) -> Result<Vec<usize>, ReduceError> {
    let names: Vec<&str> = model
        .pairs
        .iter()
        .map(|p| p.settings.name.as_str())
        .collect();
    let unknown = |key: &str, name: &str| ReduceError::UnknownPair {
        key: key.to_string(),
        name: name.to_string(),
        known: names.iter().map(|n| n.to_string()).collect(),
    };
    if let Some(name) = settings.reduce_pairs.unknown(&names).first() {
        return Err(unknown("reduction.reduce_pairs", name));
    }
    let node_to_surface = |i: usize| matches!(model.pair_surfaces.get(i), Some(Some(_)));
    let mut kept = Vec::new();
    for (i, name) in names.iter().enumerate() {
        if model.swept[i] || !settings.reduce_pairs.reduces(name) {
            continue;
        }
        if node_to_surface(i) {
            kept.push(i);
        } else if settings.reduce_pairs != ReducePairs::All {
            return Err(ReduceError::NotNodeToSurface {
                pair: name.to_string(),
            });
        }
    }
    for name in settings.pair_grids.keys().chain(settings.pair_tilts.keys()) {
        let Some(i) = names.iter().position(|n| n == name) else {
            return Err(unknown("reduction.pairs", name));
        };
        if !kept.contains(&i) {
            return Err(ReduceError::PairGridUnused {
                pair: name.clone(),
                why: if model.swept[i] {
                    "it is swept: the swept pairs take reduction.contact_nodes_per_pad or \
                     reduction.spacing, and reduction.tilt"
                } else {
                    "reduction.reduce_pairs does not reduce it"
                },
            });
        }
    }
    Ok(kept)
}

/// The least fraction of its face's second moment of area a kept pair's default grid holds
/// with point contacts ([`crate::reduce::ContactGrid::second_moment_held`]): below it the
/// grid is refined. small-caliper's piston ring at the pads' h got 4 nodes holding 64.5 %,
/// and the full-size model with every pair reduced then found no equilibrium at mu 0.1 from
/// rest (Newton stalled or cycled at every load step down to 1/64 of the load); 12 nodes
/// holding 89.1 % (and 24 holding 97.2 %) reached it with no cut-back. The disc/pad grids
/// hold 97-98 %, every other kept face of the built-in brakes 89-153 % at the pads' h.
pub const MIN_KEPT_SECOND_MOMENT: f64 = 0.85;

/// How many times a kept pair's default grid side may be divided by sqrt 2.
const MAX_KEPT_REFINEMENTS: usize = 4;

/// A kept pair's default grid: the swept pads' side `h`, divided by sqrt 2 while its point
/// contacts hold less than [`MIN_KEPT_SECOND_MOMENT`] of the face's second moment, as long
/// as the grid keeps at most a quarter of the face's nodes (a reduction, with a few face
/// nodes per share). A pair without its surfaces is left to [`reduce_interface`] to refuse.
fn kept_default_size(model: &Model, pair: usize, h: f64) -> Result<GridSize, ReduceError> {
    let Some(slave) = model
        .pair_surfaces
        .get(pair)
        .cloned()
        .flatten()
        .and_then(|(slave, _)| model.mesh.surfaces.get(&slave))
    else {
        return Ok(GridSize::Spacing(h));
    };
    let face_nodes = model.mesh.surface_nodes(slave).len();
    let mut spacing = h;
    let mut grid = isometric_grid(&model.mesh, slave, GridSize::Spacing(spacing))?;
    let (at_h, count_at_h) = (grid.second_moment_held(), grid.count());
    for _ in 0..MAX_KEPT_REFINEMENTS {
        if grid.second_moment_held() >= MIN_KEPT_SECOND_MOMENT {
            break;
        }
        let finer = spacing / 2f64.sqrt();
        match isometric_grid(&model.mesh, slave, GridSize::Spacing(finer)) {
            Ok(g) if 4 * g.count() <= face_nodes => {
                spacing = finer;
                grid = g;
            }
            _ => break,
        }
    }
    if spacing < h {
        tracing::info!(
            "reduced interface: {}: at the pads' grid side its {} point contacts would hold \
             {:.1} % of the face's second moment of area (less than {:.0} %): grid side \
             {spacing:.4e}, {} nodes, {:.1} %",
            model.pairs[pair].settings.name,
            count_at_h,
            100.0 * at_h,
            100.0 * MIN_KEPT_SECOND_MOMENT,
            grid.count(),
            100.0 * grid.second_moment_held()
        );
    }
    Ok(GridSize::Spacing(spacing))
}

/// How a kept pair is reduced: on its own grid (by default the swept pads' grid side `h`,
/// one resolution for the whole interface, refined where its point contacts would not hold
/// the face's rocking, [`kept_default_size`]), ties of [`KEPT_SPRING_FACTOR`] unless the
/// study sets their stiffness, and the swept pairs' couplings where its face holds them
/// (share couplings need a face node in every share; the paper's distributing couplings,
/// the master tied at one point, otherwise), with point contacts unless the study asks for
/// its patch laws (`[reduction.pairs."name"] tilt = true`, over share couplings only).
///
/// Why not patch laws by default: measured on small-caliper at 52 nodes per pad (every
/// pair reduced, mu 0.1 ... 0.9, 0-10 kHz), the piston's patch laws find 14 of the full
/// model's 21 instabilities where point contacts find 12, and 25 of its 49 unstable modes
/// within 1 % friction value by friction value where they find 20; but on the caliper's
/// face (bilateral too) or the abutments' they do harm: the modes to 3 kHz move by up to
/// 8-11 % (17 % with every kept pair's) where point contacts move them by at most 4.7 %.
/// Nothing yet says which faces a rule should pick.
fn kept_settings(
    model: &Model,
    pair: usize,
    swept: &InterfaceSettings,
    h: f64,
) -> Result<InterfaceSettings, ReduceError> {
    let name = &model.pairs[pair].settings.name;
    let size = match swept.pair_grids.get(name) {
        Some(&size) => size,
        None => kept_default_size(model, pair, h)?,
    };
    let mut s = InterfaceSettings {
        size,
        warp_springs: false,
        ..swept.clone()
    };
    if s.spring_stiffness.is_none() {
        s.spring_factor *= KEPT_SPRING_FACTOR / DEFAULT_SPRING_FACTOR;
    }
    if s.pad_coupling == PadCoupling::Share && !shares_fit(model, &[pair], size)? {
        s.pad_coupling = PadCoupling::Distributing;
        if s.disc_coupling == DiscCoupling::Share {
            s.disc_coupling = DiscCoupling::ShapeFunctions;
        }
    }
    let shares = s.pad_coupling == PadCoupling::Share;
    let asked = swept.pair_tilts.get(name).copied();
    if asked == Some(true) && !shares {
        return Err(ReduceError::PatchLaw {
            pair: name.clone(),
            law: "a face whose grid leaves a share without a face node (patch laws stand on \
                  share couplings)"
                .into(),
        });
    }
    s.tilt = Some(asked.unwrap_or(false));
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::config::Study;
    use crate::vector3::{norm, sub};

    fn tiny() -> Model {
        Model::from_spec(&Study::builtin("tiny").model_spec()).unwrap()
    }

    fn settings(count: usize, disc: DiscCoupling, area_weighting: bool) -> InterfaceSettings {
        InterfaceSettings {
            disc_coupling: disc,
            area_weighting,
            ..InterfaceSettings::paper(GridSize::Count(count))
        }
    }

    /// With nodal quadrature (the default) each patch law integrates at its share's face
    /// nodes: a law's points are its share's coupling nodes, with the full pair's areas of
    /// those nodes, about their area-weighted centre; over a pad they hold the full pair's
    /// area, so a pad pushed closed everywhere gets the full pair's k_n A from its laws. The
    /// area rule keeps the grid's sub-triangles (more points than nodes, the share's area).
    #[test]
    fn nodal_patch_laws_integrate_at_the_full_pairs_nodes() {
        let model = tiny();
        let run = |quadrature: PatchQuadrature| {
            let settings = InterfaceSettings {
                size: GridSize::Count(22),
                patch_quadrature: quadrature,
                ..Default::default()
            };
            reduce_interface(&model, &settings).unwrap()
        };
        let (nodal, area) = (run(PatchQuadrature::Nodes), run(PatchQuadrature::Area));
        for (pad, other) in nodal.pads.iter().zip(&area.pads) {
            assert_eq!(pad.pad_coupling, PadCoupling::Share);
            let full = model
                .pairs
                .iter()
                .find(|p| p.settings.name == pad.pair)
                .unwrap();
            let areas: BTreeMap<usize, f64> =
                full.points.iter().map(|p| (p.slave_node, p.area)).collect();
            let pair = nodal
                .model
                .pairs
                .iter()
                .find(|p| p.settings.name == pad.pair)
                .unwrap();
            let (mut held, mut quadrature_points) = (0.0, 0);
            for (k, coupling) in pad.couplings.iter().enumerate() {
                let point = pair
                    .points
                    .iter()
                    .find(|p| p.slave_node == pad.contact_nodes[k])
                    .unwrap();
                let law = point.tilt.as_ref().unwrap();
                assert_eq!(law.patch.len(), coupling.nodes.len());
                let own: f64 = coupling.nodes.iter().map(|c| areas[&c.node]).sum();
                let sum: f64 = law.patch.iter().map(|q| q.1).sum();
                assert!((sum - own).abs() < 1e-12 * own, "share {k}: {sum} vs {own}");
                assert!((point.area - own).abs() < 1e-12 * own);
                for i in 0..2 {
                    let first: f64 = law.patch.iter().map(|q| q.1 * q.0[i]).sum();
                    assert!(
                        first.abs() < 1e-12 * own * pad.grid.spacing,
                        "share {k}: {first}"
                    );
                }
                held += law.law(-1e-6, [0.0; 2]).k0;
                quadrature_points += other.grid.nodes[k].patch.len();
            }
            let total: f64 = full.points.iter().map(|p| p.area).sum();
            assert!((held - full.penalty * total).abs() < 1e-12 * full.penalty * total);
            assert!(quadrature_points > pad.couplings.iter().map(|c| c.nodes.len()).sum());
        }
    }

    /// The disc node's tie: its weights add up to 1 (so the tie spring stores no energy under
    /// a rigid translation), every weight of a distributing tie is positive and within R, a
    /// share tie's weighted position is its quadrature points' centroid on the disc face.
    #[test]
    fn disc_ties_are_normalised_and_hold_a_rigid_translation() {
        let model = tiny();
        let disc_couplings = [
            DiscCoupling::ShapeFunctions,
            DiscCoupling::Distributing,
            DiscCoupling::Share,
        ];
        for disc in disc_couplings {
            for area_weighting in [false, true] {
                let r = reduce_interface(&model, &settings(22, disc, area_weighting)).unwrap();
                let translation = [1e-3, -2e-3, 5e-4];
                let u = vec![translation; r.model.node_count()];
                for pad in &r.pads {
                    assert_eq!(pad.disc_ties.len(), pad.grid.count());
                    for (k, tie) in pad.disc_ties.iter().enumerate() {
                        let sum: f64 = tie.iter().map(|t| t.1).sum();
                        assert!((sum - 1.0).abs() < 1e-14, "{disc:?}: {sum}");
                        let d = r.model.position(pad.disc_nodes[k]);
                        if disc == DiscCoupling::Distributing {
                            assert!(tie.len() >= 3, "{} nodes", tie.len());
                            for &(n, w) in tie {
                                assert!(w > 0.0);
                                assert!(norm(sub(model.mesh.nodes[n], d)) < pad.radius);
                            }
                        } else {
                            let x = tie.iter().fold([0.0; 3], |a, &(n, w)| {
                                crate::vector3::add(
                                    a,
                                    crate::vector3::scale(w, model.mesh.nodes[n]),
                                )
                            });
                            let node = &pad.grid.nodes[k];
                            let target = if disc == DiscCoupling::Share {
                                // The shape functions reproduce the face's geometry: the
                                // weighted position is the projected points' centroid, in
                                // the (flat) disc face's plane the share's own centroid.
                                let area: f64 = node.patch.iter().map(|p| p.1).sum();
                                let e = pad.grid.plane.axes;
                                let mut c = node.position;
                                for &(xi, a) in &node.patch {
                                    for i in 0..3 {
                                        c[i] += a / area * (xi[0] * e[0][i] + xi[1] * e[1][i]);
                                    }
                                }
                                // Onto the face: d's height along the disc axis (z).
                                [c[0], c[1], d[2]]
                            } else {
                                // The face's shape functions put the tie exactly at d.
                                d
                            };
                            assert!(
                                norm(sub(x, target)) < 1e-12 * norm(d),
                                "{disc:?}: {x:?} vs {target:?}"
                            );
                        }
                    }
                }
                // Every tie spring (pad and disc) stretches by nothing under the translation.
                for spring in &r.model.couplings {
                    let stretch = spring.terms.iter().fold([0.0; 3], |a, &(n, c)| {
                        crate::vector3::add(a, crate::vector3::scale(c, u[n]))
                    });
                    assert!(norm(stretch) < 1e-15 * norm(translation) * 10.0);
                }
            }
        }
    }

    /// Area weighting: each coupled node's weight is w(r/R) A_i over the sum, A_i its
    /// tributary area, on the pad side and (distributing) on the disc side.
    #[test]
    fn area_weighting_weighs_by_the_tributary_areas() {
        let model = tiny();
        let plain =
            reduce_interface(&model, &settings(22, DiscCoupling::Distributing, false)).unwrap();
        let weighted =
            reduce_interface(&model, &settings(22, DiscCoupling::Distributing, true)).unwrap();
        for (p, q) in plain.pads.iter().zip(&weighted.pads) {
            let pair = model
                .pairs
                .iter()
                .position(|x| x.settings.name == p.pair)
                .unwrap();
            let (slave, master) = model.pair_surfaces[pair].clone().unwrap();
            let area = |s: &str| -> std::collections::BTreeMap<usize, f64> {
                crate::contact::tributary_areas(&model.mesh, &model.mesh.surfaces[s])
                    .into_iter()
                    .collect()
            };
            let (a_pad, a_disc) = (area(&slave), area(&master));
            let check = |plain: &[(usize, f64)],
                         weighted: &[(usize, f64)],
                         a: &std::collections::BTreeMap<usize, f64>| {
                let total: f64 = plain.iter().map(|&(n, w)| w * a[&n]).sum();
                assert_eq!(plain.len(), weighted.len());
                for (&(n, w), &(m, v)) in plain.iter().zip(weighted) {
                    assert_eq!(n, m);
                    assert!(
                        (v - w * a[&n] / total).abs() < 1e-15,
                        "{v} vs {}",
                        w * a[&n] / total
                    );
                }
            };
            for (c, d) in p.couplings.iter().zip(&q.couplings) {
                let pw: Vec<(usize, f64)> = c.nodes.iter().map(|n| (n.node, n.weight)).collect();
                let qw: Vec<(usize, f64)> = d.nodes.iter().map(|n| (n.node, n.weight)).collect();
                check(&pw, &qw, &a_pad);
            }
            for (c, d) in p.disc_ties.iter().zip(&q.disc_ties) {
                check(c, d, &a_disc);
            }
        }
    }

    /// The disc side catches too few nodes for a radius far below its mesh: an error naming
    /// the disc surface.
    #[test]
    fn a_disc_coupling_catching_too_few_nodes_names_the_disc_surface() {
        let model = tiny();
        let r =
            reduce_interface(&model, &settings(6, DiscCoupling::ShapeFunctions, false)).unwrap();
        let pad = &r.pads[0];
        let pair = model
            .pairs
            .iter()
            .position(|x| x.settings.name == pad.pair)
            .unwrap();
        let (_, master) = model.pair_surfaces[pair].clone().unwrap();
        let master = &model.mesh.surfaces[&master];
        let hit = crate::contact::project::SurfaceHit {
            face: 0,
            q: [0.3, 0.3],
            point: r.model.position(pad.disc_nodes[0]),
            normal: [0.0, 0.0, 1.0],
            gap: 0.0,
            outside: 0.0,
            distance: 0.0,
        };
        let s = settings(6, DiscCoupling::Distributing, false);
        let faces: Vec<[[f64; 3]; 6]> = master
            .faces
            .iter()
            .map(|f| f.nodes.map(|n| model.mesh.nodes[n]))
            .collect();
        let search = SurfaceSearch::new(faces).unwrap();
        let reach = search.mean_face_size();
        let ties = |radius: f64| {
            disc_ties(
                &model.mesh,
                master,
                &[hit],
                radius,
                &s,
                &pad.grid,
                &search,
                reach,
            )
        };
        let err = ties(1e-5).unwrap_err().to_string();
        assert!(
            err.contains(&master.name) && err.contains("disc-side") && err.contains("catches"),
            "{err}"
        );
        assert!(ties(pad.radius).is_ok());
    }

    /// A kept face whose point contacts at the pads' h would not hold its rocking gets a
    /// finer default grid: tiny-caliper's piston ring at 52 nodes per pad (4 nodes, 64.5 %
    /// of its second moment) is refined to hold at least MIN_KEPT_SECOND_MOMENT; the faces
    /// that already hold it keep the pads' h; a grid the study gives is kept as it is.
    #[test]
    fn a_kept_face_that_would_not_hold_its_rocking_gets_a_finer_default_grid() {
        let model = Model::from_spec(&Study::builtin("tiny-caliper").model_spec()).unwrap();
        let all = |grids: &[(&str, usize)]| {
            reduce_interface(
                &model,
                &InterfaceSettings {
                    size: GridSize::Count(52),
                    reduce_pairs: ReducePairs::All,
                    pair_grids: grids
                        .iter()
                        .map(|&(n, c)| (n.to_string(), GridSize::Count(c)))
                        .collect(),
                    ..Default::default()
                },
            )
            .unwrap()
        };
        let reduced = all(&[]);
        let h = reduced.pads[0].grid.spacing;
        for pad in reduced.pads.iter().filter(|p| !p.swept) {
            let at_h = isometric_grid(&model.mesh, &model.mesh.surfaces[&pad.grid.surface], {
                GridSize::Spacing(h)
            })
            .unwrap();
            if at_h.second_moment_held() >= MIN_KEPT_SECOND_MOMENT {
                assert!((pad.grid.spacing - h).abs() <= 1e-12 * h, "{}", pad.pair);
            } else {
                assert!(pad.grid.spacing < h, "{}", pad.pair);
                assert!(pad.grid.count() > at_h.count(), "{}", pad.pair);
                assert!(pad.grid.second_moment_held() >= MIN_KEPT_SECOND_MOMENT);
            }
        }
        let piston = |r: &ReducedInterface| {
            r.pads
                .iter()
                .find(|p| p.pair == "piston/pad")
                .unwrap()
                .grid
                .count()
        };
        assert!(piston(&reduced) > 4, "the ring's 4 nodes at h are refined");
        assert_eq!(
            piston(&all(&[("piston/pad", 4)])),
            4,
            "a given grid is kept"
        );
    }

    /// A kept pair's contact law: point contacts by default, patch laws where the study asks
    /// (`[reduction.pairs."name"] tilt = true`) with its Coulomb law, bilateral over every
    /// point of its shares where the full pair is (Table 1's piston/pad and caliper/pad);
    /// asked of a swept pair, refused by name.
    #[test]
    fn a_kept_pair_takes_patch_laws_where_asked() {
        let model = Model::from_spec(&Study::builtin("tiny-caliper").model_spec()).unwrap();
        let with = |tilts: &[(&str, bool)]| InterfaceSettings {
            size: GridSize::Count(22),
            reduce_pairs: ReducePairs::All,
            pair_tilts: tilts.iter().map(|&(n, t)| (n.to_string(), t)).collect(),
            ..Default::default()
        };
        let check = |reduced: &ReducedInterface, with_laws: &[&str]| {
            for pad in reduced.pads.iter().filter(|p| !p.swept) {
                let i = model
                    .pairs
                    .iter()
                    .position(|p| p.settings.name == pad.pair)
                    .unwrap();
                let (full, pair) = (&model.pairs[i], &reduced.model.pairs[i]);
                if !with_laws.contains(&pad.pair.as_str()) {
                    assert!(pad.tilt_nodes.is_empty(), "{} {with_laws:?}", pad.pair);
                    continue;
                }
                assert_eq!(pad.pad_coupling, PadCoupling::Share);
                assert_eq!(pad.tilt_nodes.len(), pad.grid.count(), "{}", pad.pair);
                assert_eq!(pair.settings.law, full.settings.law);
                for point in &pair.points {
                    let tilt = point.tilt.as_ref().expect("a patch law on every contact");
                    assert_eq!(tilt.bilateral, !full.settings.separation, "{}", pad.pair);
                    // Its share's points hold the share's area; pushed 1 um, all of them
                    // act: the point law.
                    let area: f64 = tilt.patch.iter().map(|q| q.1).sum();
                    assert!((area / point.area - 1.0).abs() < 1e-12);
                    let law = tilt.law(-1e-6, [0.0; 2]);
                    assert!((law.force / (full.penalty * point.area * 1e-6) - 1.0).abs() < 1e-12);
                    // Pulled 1 um, a bilateral share pulls back as much; a unilateral one
                    // lets go.
                    let pulled = tilt.law(1e-6, [0.0; 2]).force;
                    assert_eq!(pulled == 0.0, full.settings.separation, "{}", pad.pair);
                }
            }
        };
        assert!(
            !model
                .pairs
                .iter()
                .find(|p| p.settings.name == "piston/pad")
                .unwrap()
                .settings
                .separation,
            "Table 1's piston/pad is bilateral"
        );
        check(&reduce_interface(&model, &with(&[])).unwrap(), &[]);
        let asked = with(&[("piston/pad", true), ("caliper/pad", false)]);
        check(&reduce_interface(&model, &asked).unwrap(), &["piston/pad"]);
        let unilateral = with(&[("bracket/pad inboard leading", true)]);
        check(
            &reduce_interface(&model, &unilateral).unwrap(),
            &["bracket/pad inboard leading"],
        );
        let e = reduce_interface(&model, &with(&[("disc/pad inboard", true)]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("disc/pad inboard") && e.contains("swept"), "{e}");
    }

    /// Kept pairs reduced too (issue 32): every pair of the floating caliper, or the named
    /// ones, each a node-to-node pair on its own grid (the swept pads' side h by default, or
    /// its own), with point contacts and ties of KEPT_SPRING_FACTOR k_n A_k; the swept
    /// pairs as without them; names and grids that do not fit refused by name.
    #[test]
    fn kept_pairs_are_reduced_on_their_own_grids_where_asked() {
        let model = Model::from_spec(&Study::builtin("tiny-caliper").model_spec()).unwrap();
        let with = |pairs: ReducePairs, grids: &[(&str, usize)]| InterfaceSettings {
            size: GridSize::Count(22),
            reduce_pairs: pairs,
            pair_grids: grids
                .iter()
                .map(|&(n, c)| (n.to_string(), GridSize::Count(c)))
                .collect(),
            ..Default::default()
        };
        let swept_only = reduce_interface(&model, &with(ReducePairs::Swept, &[])).unwrap();
        assert_eq!(swept_only.pads.len(), 2);
        let all = reduce_interface(&model, &with(ReducePairs::All, &[("piston/pad", 12)])).unwrap();
        assert_eq!(all.pads.len(), model.pairs.len());
        let h = all.pads[0].grid.spacing;
        for pad in &all.pads {
            let i = model
                .pairs
                .iter()
                .position(|p| p.settings.name == pad.pair)
                .unwrap();
            let pair = &all.model.pairs[i];
            assert_eq!(pad.swept, model.swept[i], "{}", pad.pair);
            assert!(
                all.model.pair_surfaces[i].is_none(),
                "{} still node-to-surface",
                pad.pair
            );
            assert_eq!(pair.points.len(), pad.grid.count());
            // Every coupling transmits a rigid translation: its weights add up to 1.
            for c in &pad.couplings {
                let sum: f64 = c.nodes.iter().map(|n| n.weight).sum();
                assert!(
                    (sum - 1.0).abs() < 1e-12,
                    "{}: weights add up to {sum}",
                    pad.pair
                );
            }
            if pad.swept {
                // The swept pads as without the kept pairs: same grid, same ties.
                let alone = swept_only.pads.iter().find(|p| p.pair == pad.pair).unwrap();
                assert_eq!(pad.grid.count(), alone.grid.count());
                assert_eq!(pad.spring_stiffness, alone.spring_stiffness);
                continue;
            }
            assert!(
                pad.tilt_nodes.is_empty(),
                "{}: a kept pair has point contacts unless asked",
                pad.pair
            );
            if pad.pair == "piston/pad" {
                assert_eq!(pad.grid.count(), 12);
            } else {
                assert!((pad.grid.spacing - h).abs() <= 1e-12 * h, "{}", pad.pair);
            }
            let penalty = model.pairs[i].penalty;
            for (k, node) in pad.grid.nodes.iter().enumerate() {
                let expected = KEPT_SPRING_FACTOR * penalty * node.area;
                assert!((pad.spring_stiffness[k] - expected).abs() <= 1e-12 * expected);
            }
        }
        // Named: that pair alone besides the swept ones.
        let named = ReducePairs::Named(vec!["caliper/pad".into()]);
        let one = reduce_interface(&model, &with(named, &[])).unwrap();
        let kept: Vec<&str> = one
            .pads
            .iter()
            .filter(|p| !p.swept)
            .map(|p| p.pair.as_str())
            .collect();
        assert_eq!(kept, ["caliper/pad"]);
        // Refusals, by name.
        let e = reduce_interface(
            &model,
            &with(ReducePairs::Named(vec!["calliper/pad".into()]), &[]),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("'calliper/pad'") && e.contains("caliper/pad,"),
            "{e}"
        );
        let e = reduce_interface(&model, &with(ReducePairs::All, &[("disc/pad inboard", 6)]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("disc/pad inboard") && e.contains("swept"), "{e}");
        let e = reduce_interface(&model, &with(ReducePairs::Swept, &[("caliper/pad", 6)]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("caliper/pad") && e.contains("does not reduce"),
            "{e}"
        );
        let e = reduce_interface(&model, &with(ReducePairs::All, &[("nothing", 6)]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("reduction.pairs") && e.contains("'nothing'"),
            "{e}"
        );
    }

    /// The default interface is squeal's (share couplings on both sides, patch laws) where
    /// the pad faces hold its shares and the pairs' laws admit patch laws, the paper's
    /// otherwise; an explicit choice is kept as given.
    #[test]
    fn the_default_interface_is_squeals_where_the_mesh_and_the_law_allow_it() {
        let model = tiny();
        let swept: Vec<usize> = (0..model.pairs.len()).filter(|&i| model.swept[i]).collect();
        let auto = |count: usize| InterfaceSettings {
            size: GridSize::Count(count),
            ..Default::default()
        };
        let chosen = |s: &InterfaceSettings| {
            let r = s.resolved(&model, &swept).unwrap();
            (r.pad_coupling, r.disc_coupling, r.tilt)
        };
        let squeals = (PadCoupling::Share, DiscCoupling::Share, Some(true));
        let papers = (
            PadCoupling::Distributing,
            DiscCoupling::ShapeFunctions,
            Some(false),
        );
        // tiny's pad faces (65 face nodes) hold 22 shares, not 52: a share of that grid
        // holds no face node (`couple_shares` refuses it). At 22, some shares hold fewer
        // than three nodes, one row or a thin strip: they read their neighbours' tilt nodes
        // (`tilt::slope_owners`), and the default is squeal's interface there too.
        let face = &model.mesh.surfaces["pad_inboard_friction_face"];
        let shares = |n: usize| {
            couple_shares(
                &model.mesh,
                face,
                &isometric_grid(&model.mesh, face, GridSize::Count(n)).unwrap(),
            )
        };
        assert!(shares(22).is_ok());
        assert!(matches!(shares(52), Err(ReduceError::ShareTooSmall { .. })));
        assert_eq!(chosen(&auto(6)), squeals);
        assert_eq!(chosen(&auto(22)), squeals);
        assert_eq!(chosen(&auto(52)), papers);
        // Point contacts asked for: the paper's couplings go with them.
        let point = InterfaceSettings {
            tilt: Some(false),
            ..auto(6)
        };
        assert_eq!(chosen(&point), papers);
        // Patch laws asked for where shares do not fit: the paper's couplings carry them.
        let patch = InterfaceSettings {
            tilt: Some(true),
            ..auto(52)
        };
        assert_eq!(
            chosen(&patch),
            (
                PadCoupling::Distributing,
                DiscCoupling::ShapeFunctions,
                Some(true)
            )
        );
        // A law no patch law carries (Coulomb stick and slip): the paper's interface.
        let mut coulomb = model.clone();
        for &i in &swept {
            coulomb.pairs[i].settings.law = contact::FrictionLaw::Coulomb {
                stick_stiffness: None,
            };
        }
        assert_eq!(
            auto(6)
                .resolved(&coulomb, &swept)
                .map(|r| (r.pad_coupling, r.disc_coupling, r.tilt))
                .unwrap(),
            papers
        );
        // What was resolved is what the interface says it was made with.
        let reduced = reduce_interface(&model, &auto(6)).unwrap();
        assert_eq!(
            (
                reduced.settings.pad_coupling,
                reduced.settings.disc_coupling,
                reduced.settings.tilt
            ),
            squeals
        );
        assert!(reduced
            .pads
            .iter()
            .all(|p| p.pad_coupling == PadCoupling::Share && p.tilt_nodes.len() == p.grid.count()));
        // And the log says what was chosen and why, first; nothing when all was given.
        let said = reduced.summary();
        assert!(
            said.starts_with("chosen by default: share couplings with patch laws (every share"),
            "{said}"
        );
        // At 22 nodes per pad some shares hold one row of face nodes: asked for by name,
        // they read their nearest neighbour's tilt nodes.
        let asked = InterfaceSettings {
            pad_coupling: PadCoupling::Share,
            ..auto(22)
        };
        let reduced = reduce_interface(&model, &asked).unwrap();
        assert!(reduced
            .pads
            .iter()
            .all(|p| p.pad_coupling == PadCoupling::Share
                && p.borrowed_slopes > 0
                && p.tilt_nodes.len() == p.grid.count()));
        let said = reduced.summary();
        assert!(said.contains("read their nearest neighbour's"), "{said}");
        // Each borrower's law reads an owner's tilt nodes: no more tilt nodes than owners.
        for p in &reduced.pads {
            let distinct: std::collections::BTreeSet<_> = p.tilt_nodes.iter().collect();
            assert_eq!(distinct.len(), p.grid.count() - p.borrowed_slopes);
        }
        let given = reduce_interface(&model, &InterfaceSettings::paper(GridSize::Count(6)));
        assert!(!given.unwrap().summary().contains("chosen by default"));
    }
}
