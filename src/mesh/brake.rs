//! The built-in parametric disc brake: a solid disc clamped at its hub and two pads (friction
//! lining glued to a steel backplate) on either face, meshed with 10-node tetrahedra. squeal
//! uses it when the user gives no mesh, and the tests use it as a model of known geometry.
//!
//! Geometry (SI units), disc axis = z through the origin, disc mid-plane z = 0. Section
//! through the pad centre (r to the right, z up, not to scale):
//!
//! ```text
//!                                pad_inner_radius          pad_outer_radius
//!                                        +-------------------------+
//!                                        |  backplate (steel)      |  inboard pad: the
//!                                        +-------------------------+  piston presses here
//!                                        |  lining (friction mat.) |
//!   hub, clamped (disc_hub) +------------+-------------------------+----+  z = +t/2
//!                           |  disc (grey cast iron), solid             |
//!                           +------------+-------------------------+----+  z = -t/2
//!                    disc_inner_radius   |  lining                 |    disc_outer_radius
//!                                        +-------------------------+
//!                                        |  backplate              |  outboard pad: the
//!                                        +-------------------------+  caliper fingers
//! ```
//!
//! Seen from +z, both pads are centred on `pad_centre_deg` and their linings span
//! `pad_arc_deg`; each backplate extends `backplate_overhang_deg` beyond the lining at both
//! ends: the ears that bear on the bracket abutments.
//!
//! Every part is a structured block in cylindrical coordinates (r, theta, z): hexahedral cells
//! split into 6 tetrahedra by the Kuhn (Freudenthal) rule along the cell diagonal from the low
//! (r, theta, z) corner to the high one. The split is the same translated pattern in every cell,
//! so the face diagonals of neighbouring cells agree and the mesh is conforming, also across the
//! theta = 0 / 2 pi seam of the disc (its theta index wraps). The mid-edge nodes of the quadratic
//! tetrahedra are exactly the points of the block's grid refined by two in every direction, each
//! created once and placed at the parametric middle in (r, theta, z): on the true circular arcs.
//! The friction lining and its backplate are one block (shared nodes); the disc and the pads
//! are separate blocks whose meshes do not match at the friction interface, as in an
//! industrial model, while the pad friction face lies exactly on the disc face plane when the
//! gap is zero.
//!
//! The disc is clamped at its inner edge (node set `disc_hub`); the hat is not modelled. The
//! pads are held by what a real caliper provides: normally by contact with the disc and by
//! the piston / caliper fingers (surfaces `backplate_inboard_piston`,
//! `backplate_outboard_caliper`), tangentially by the bracket abutments bearing on the
//! backplate ears (`pad_*_abutment_leading` / `_trailing`) and radially by the guides
//! (node sets `pad_*_guides`, the outer radial edge of the backplates), which the study
//! supports or ties to springs.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use crate::mesh::{Face, Material, Mesh, MeshError, Part, Surface, TET10_EDGES, TET10_FACES};

/// Why a set of brake parameters cannot be meshed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BrakeError {
    /// A size that must be a finite number greater than zero.
    #[error("brake parameter `{name}` must be a finite number greater than zero (got {value})")]
    NotPositive { name: &'static str, value: f64 },
    /// A size that may be zero but must be finite and not negative.
    #[error("brake parameter `{name}` must be a finite number >= 0 (got {value})")]
    Negative { name: &'static str, value: f64 },
    /// A value that must merely be finite (an angle).
    #[error("brake parameter `{name}` must be a finite number (got {value})")]
    NotFinite { name: &'static str, value: f64 },
    /// A mesh division count out of its range.
    #[error("brake mesh division `{name}` must lie in {min}..={max} (got {value})")]
    Divisions {
        name: &'static str,
        value: usize,
        min: usize,
        max: usize,
    },
    /// A Poisson's ratio outside the range a stable isotropic solid allows.
    #[error("brake material `{material}`: Poisson's ratio must lie strictly between -1 and 0.5 (got {value})")]
    Poisson { material: &'static str, value: f64 },
    /// Parameters that are each fine but contradict one another.
    #[error("brake parameters: {0}")]
    Inconsistent(String),
    /// The mesh would be larger than the program is meant to handle.
    #[error("the brake mesh would have {nodes} nodes, more than the limit of {limit}; reduce the divisions")]
    TooLarge { nodes: u128, limit: u128 },
    /// An element came out with a non-positive Jacobian (cannot happen for parameters that
    /// pass the checks above; kept as an error rather than a panic).
    #[error("brake element {label} of part `{part}` has a non-positive Jacobian ({det:e}); the mesh is too coarse for its curvature")]
    Inverted { part: String, label: i64, det: f64 },
}

impl From<BrakeError> for MeshError {
    fn from(err: BrakeError) -> Self {
        MeshError::invalid("<built-in brake>", err.to_string())
    }
}

/// Sense of rotation of the disc, seen from +z (the inboard side). It decides which end of
/// each pad is leading (where the disc surface enters under the pad) and which is trailing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Rotation {
    /// About +z: the disc surface moves toward increasing theta, so the leading abutment is
    /// at the low-theta end of the pads and the trailing one at the high-theta end.
    #[default]
    CounterClockwise,
    /// About -z: leading at the high-theta end.
    Clockwise,
}

/// Isotropic linear-elastic constants of one material (all three must be given).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Elastic {
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Mass density, kg/m^3.
    pub density: f64,
}

/// Mesh density: numbers of hexahedral cells (each cut into 6 tetrahedra) per direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Divisions {
    /// Around the full disc (at least 12: a cell spans at most 30 degrees).
    pub disc_circumferential: usize,
    /// From the hub radius to the outer radius.
    pub disc_radial: usize,
    /// Through the disc thickness.
    pub disc_thickness: usize,
    /// Along the friction lining's arc. Each backplate ear gets the fewest cells no wider
    /// than the lining's (at least one when `backplate_overhang_deg` > 0).
    pub pad_circumferential: usize,
    /// From the pad inner to outer radius.
    pub pad_radial: usize,
    /// Through the friction lining.
    pub friction_thickness: usize,
    /// Through the backplate.
    pub backplate_thickness: usize,
}

impl Default for Divisions {
    /// The `small` preset.
    fn default() -> Self {
        Divisions::SMALL
    }
}

/// The presets. Pad cells are as fine as or finer than the disc's and every cell's edge
/// ratio stays below 5; disc and pad grids share no radius or no angle, so no pad node sits
/// on a disc node (all checked by the tests).
impl Divisions {
    const TINY: Divisions = Divisions {
        disc_circumferential: 32,
        disc_radial: 3,
        disc_thickness: 2,
        pad_circumferential: 6,
        pad_radial: 2,
        friction_thickness: 1,
        backplate_thickness: 1,
    };
    const SMALL: Divisions = Divisions {
        disc_circumferential: 72,
        disc_radial: 7,
        disc_thickness: 3,
        pad_circumferential: 13,
        pad_radial: 5,
        friction_thickness: 2,
        backplate_thickness: 1,
    };
    const MEDIUM: Divisions = Divisions {
        disc_circumferential: 112,
        disc_radial: 11,
        disc_thickness: 4,
        pad_circumferential: 21,
        pad_radial: 8,
        friction_thickness: 3,
        backplate_thickness: 2,
    };
    const INDUSTRIAL: Divisions = Divisions {
        disc_circumferential: 168,
        disc_radial: 16,
        disc_thickness: 6,
        pad_circumferential: 31,
        pad_radial: 13,
        friction_thickness: 4,
        backplate_thickness: 2,
    };
}

/// All dimensions, materials and mesh divisions of the built-in brake. `Default` is a solid
/// front disc of a passenger car (280 mm x 22 mm) with 60-degree pads; every field can be
/// overridden (missing fields of a study file take these defaults).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BrakeParams {
    /// Disc outer radius, m.
    pub disc_outer_radius: f64,
    /// Disc inner radius where it is clamped to the hat/hub, m.
    pub disc_inner_radius: f64,
    /// Disc thickness, m (mid-plane at z = 0).
    pub disc_thickness: f64,
    /// Inner radius of the pads (lining and backplate), m.
    pub pad_inner_radius: f64,
    /// Outer radius of the pads, m.
    pub pad_outer_radius: f64,
    /// Angle spanned by the friction lining, degrees.
    pub pad_arc_deg: f64,
    /// Angular position of the pad centres (both pads), degrees from +x toward +y.
    pub pad_centre_deg: f64,
    /// Thickness of the friction lining, m.
    pub friction_thickness: f64,
    /// Thickness of the steel backplate, m.
    pub backplate_thickness: f64,
    /// Angle by which each backplate ear extends beyond the lining at both ends, degrees
    /// (0: backplate and lining end together). The abutments are the ears' end faces.
    pub backplate_overhang_deg: f64,
    /// Initial gap between each pad's friction face and the disc face, m (0 = touching).
    pub pad_gap: f64,
    /// Disc rotation, which names the leading and trailing abutments.
    pub rotation: Rotation,
    /// Disc material (part `disc`, material `cast_iron`).
    pub cast_iron: Elastic,
    /// Lining material (`pad_*_friction`, material `friction_material`).
    pub friction_material: Elastic,
    /// Backplate material (`pad_*_backplate`, material `steel`).
    pub steel: Elastic,
    /// Mesh density.
    pub divisions: Divisions,
}

impl Default for BrakeParams {
    fn default() -> Self {
        BrakeParams {
            disc_outer_radius: 0.140,
            disc_inner_radius: 0.075,
            disc_thickness: 0.022,
            pad_inner_radius: 0.090,
            pad_outer_radius: 0.135,
            pad_arc_deg: 60.0,
            pad_centre_deg: 0.0,
            friction_thickness: 0.010,
            backplate_thickness: 0.0055,
            backplate_overhang_deg: 6.0,
            pad_gap: 0.0,
            rotation: Rotation::CounterClockwise,
            // Grey cast iron of a solid passenger-car disc (EN-GJL-250/300, SAE J431 G3000
            // class). Handbook moduli of these grades span roughly 100-140 GPa depending on
            // grade and carbon content; 125 GPa, nu 0.25 and 7200 kg/m^3 are values commonly
            // used in brake-squeal FE models. With measured free-free disc modes, update E:
            // the disc frequencies scale with sqrt(E / rho).
            cast_iron: Elastic {
                young: 125e9,
                poisson: 0.25,
                density: 7200.0,
            },
            // Organic / low-metallic lining: moduli of a few GPa to ~10 GPa, strongly
            // anisotropic and pressure dependent in reality (modelled isotropic here);
            // density 2000-2800 kg/m^3.
            friction_material: Elastic {
                young: 8e9,
                poisson: 0.25,
                density: 2500.0,
            },
            // Carbon steel backplate: E = 210 GPa, nu = 0.3 (EN 1993-1-1, 3.2.6),
            // rho = 7850 kg/m^3 (EN 1991-1-1).
            steel: Elastic {
                young: 210e9,
                poisson: 0.3,
                density: 7850.0,
            },
            divisions: Divisions::default(),
        }
    }
}

/// Names accepted by [`preset`], from coarsest to finest: `tiny` (3,010 nodes, for unit
/// tests), `small` (19,806, the default), `medium` (64,490) and `industrial` (192,690 nodes,
/// 128,280 elements: the size of the paper's brake model, 176,956 nodes).
pub const PRESETS: &[&str] = &["tiny", "small", "medium", "industrial"];

/// The default passenger-car brake with the mesh density of a named preset.
pub fn preset(name: &str) -> Option<BrakeParams> {
    let divisions = match name {
        "tiny" => Divisions::TINY,
        "small" => Divisions::SMALL,
        "medium" => Divisions::MEDIUM,
        "industrial" => Divisions::INDUSTRIAL,
        _ => return None,
    };
    Some(BrakeParams {
        divisions,
        ..BrakeParams::default()
    })
}

/// Above this the parameters are surely a typo (and the memory would not be there).
const MAX_NODES: u128 = 20_000_000;
/// Largest division count of any direction.
const MAX_DIVISIONS: usize = 100_000;
/// Largest angle h one cell may span. The quadratic arc through a cell's three nodes on a
/// circle of radius r lies inside it by at most r (1 - cos(h/2))^2 / 8 ~ r (h/2)^4 / 32:
/// 1.5e-4 r at 30 degrees, and its Jacobian stays far from zero.
const MAX_CELL_DEG: f64 = 30.0;

impl BrakeParams {
    /// Number of nodes [`build`] will make (for parameters that pass [`Self::validate`]).
    pub fn node_count(&self) -> usize {
        usize::try_from(self.counts().0).unwrap_or(usize::MAX)
    }

    /// Number of elements [`build`] will make (for parameters that pass [`Self::validate`]).
    pub fn element_count(&self) -> usize {
        usize::try_from(self.counts().1).unwrap_or(usize::MAX)
    }

    /// Cells of each backplate ear: the fewest whose angle does not exceed the lining's
    /// cell angle (at least one if there is an ear), so the ears are no coarser than the pad.
    fn overhang_cells(&self) -> usize {
        let d = &self.divisions;
        if self.backplate_overhang_deg <= 0.0 || d.pad_circumferential == 0 {
            return 0;
        }
        let lining_cell = self.pad_arc_deg / d.pad_circumferential as f64;
        // The factor keeps an ear of exactly k lining cells at k despite round-off.
        let n = (self.backplate_overhang_deg / lining_cell * (1.0 - 1e-12)).ceil();
        if n.is_finite() {
            (n as usize).clamp(1, MAX_DIVISIONS)
        } else {
            1
        }
    }

    /// (nodes, elements). A structured
    /// block of a x b x c cells split by Kuhn's rule uses every point of the grid refined by
    /// two (corners, edge, face-diagonal and body-diagonal midpoints): (2a+1)(2b+1)(2c+1)
    /// nodes, 2a instead of 2a+1 along a periodic direction.
    fn counts(&self) -> (u128, u128) {
        let d = &self.divisions;
        // Divisions beyond the limit (which `validate` rejects) are clamped so that nothing
        // can overflow; the counts are exact for valid parameters.
        let u = |n: usize| n.min(MAX_DIVISIONS + 1) as u128;
        let (nt, nr, nz) = (
            u(d.disc_circumferential),
            u(d.disc_radial),
            u(d.disc_thickness),
        );
        let disc_nodes = 2 * nt * (2 * nr + 1) * (2 * nz + 1);
        let disc_elements = 6 * nt * nr * nz;
        let (pt, pr, pf, pb) = (
            u(d.pad_circumferential),
            u(d.pad_radial),
            u(d.friction_thickness),
            u(d.backplate_thickness),
        );
        let o = u(self.overhang_cells());
        let t = pt + 2 * o;
        // The lining is absent under the ears: drop the 2o theta-points per ear that only
        // ear cells use, on the 2 pf lining layers of refined points off the glued interface.
        let pad_nodes =
            (2 * t + 1) * (2 * pr + 1) * (2 * (pf + pb) + 1) - 8 * o * (2 * pr + 1) * pf;
        let pad_elements = 6 * (pt * pr * pf + t * pr * pb);
        (disc_nodes + 2 * pad_nodes, disc_elements + 2 * pad_elements)
    }

    /// Checks every parameter; the error names the first offending one.
    pub fn validate(&self) -> Result<(), BrakeError> {
        let positive = |name: &'static str, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(BrakeError::NotPositive { name, value })
            }
        };
        positive("disc_outer_radius", self.disc_outer_radius)?;
        positive("disc_inner_radius", self.disc_inner_radius)?;
        positive("disc_thickness", self.disc_thickness)?;
        positive("pad_inner_radius", self.pad_inner_radius)?;
        positive("pad_outer_radius", self.pad_outer_radius)?;
        positive("pad_arc_deg", self.pad_arc_deg)?;
        positive("friction_thickness", self.friction_thickness)?;
        positive("backplate_thickness", self.backplate_thickness)?;
        for (name, value) in [
            ("backplate_overhang_deg", self.backplate_overhang_deg),
            ("pad_gap", self.pad_gap),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(BrakeError::Negative { name, value });
            }
        }
        if !self.pad_centre_deg.is_finite() {
            return Err(BrakeError::NotFinite {
                name: "pad_centre_deg",
                value: self.pad_centre_deg,
            });
        }
        for (material, m, young, density) in [
            (
                "cast_iron",
                &self.cast_iron,
                "cast_iron.young",
                "cast_iron.density",
            ),
            (
                "friction_material",
                &self.friction_material,
                "friction_material.young",
                "friction_material.density",
            ),
            ("steel", &self.steel, "steel.young", "steel.density"),
        ] {
            positive(young, m.young)?;
            positive(density, m.density)?;
            if !(m.poisson.is_finite() && m.poisson > -1.0 && m.poisson < 0.5) {
                return Err(BrakeError::Poisson {
                    material,
                    value: m.poisson,
                });
            }
        }
        let d = &self.divisions;
        for (name, value, min) in [
            ("divisions.disc_circumferential", d.disc_circumferential, 12),
            ("divisions.disc_radial", d.disc_radial, 1),
            ("divisions.disc_thickness", d.disc_thickness, 1),
            ("divisions.pad_circumferential", d.pad_circumferential, 1),
            ("divisions.pad_radial", d.pad_radial, 1),
            ("divisions.friction_thickness", d.friction_thickness, 1),
            ("divisions.backplate_thickness", d.backplate_thickness, 1),
        ] {
            if !(min..=MAX_DIVISIONS).contains(&value) {
                return Err(BrakeError::Divisions {
                    name,
                    value,
                    min,
                    max: MAX_DIVISIONS,
                });
            }
        }
        if self.disc_inner_radius >= self.disc_outer_radius {
            return Err(BrakeError::Inconsistent(format!(
                "disc_inner_radius ({}) must be smaller than disc_outer_radius ({})",
                self.disc_inner_radius, self.disc_outer_radius
            )));
        }
        if self.pad_inner_radius >= self.pad_outer_radius {
            return Err(BrakeError::Inconsistent(format!(
                "pad_inner_radius ({}) must be smaller than pad_outer_radius ({})",
                self.pad_inner_radius, self.pad_outer_radius
            )));
        }
        if self.pad_inner_radius < self.disc_inner_radius
            || self.pad_outer_radius > self.disc_outer_radius
        {
            return Err(BrakeError::Inconsistent(format!(
                "the pads (radii {} to {}) must lie on the disc's friction ring (radii {} to {})",
                self.pad_inner_radius,
                self.pad_outer_radius,
                self.disc_inner_radius,
                self.disc_outer_radius
            )));
        }
        let backplate_arc = self.pad_arc_deg + 2.0 * self.backplate_overhang_deg;
        if backplate_arc >= 180.0 {
            return Err(BrakeError::Inconsistent(format!(
                "a pad spans pad_arc_deg + 2 backplate_overhang_deg = {backplate_arc} degrees; \
                 it must cover less than half the disc (180 degrees)"
            )));
        }
        let lining_cell = self.pad_arc_deg / d.pad_circumferential as f64;
        let o = self.overhang_cells();
        let ear_cell = if o > 0 {
            self.backplate_overhang_deg / o as f64
        } else {
            0.0
        };
        for (what, angle) in [
            ("disc cell", 360.0 / d.disc_circumferential as f64),
            ("pad cell", lining_cell),
            ("backplate ear cell", ear_cell),
        ] {
            if angle > MAX_CELL_DEG {
                return Err(BrakeError::Inconsistent(format!(
                    "a {what} would span {angle:.3} degrees, more than {MAX_CELL_DEG}; \
                     raise the circumferential divisions"
                )));
            }
        }
        let nodes = self.counts().0;
        if nodes > MAX_NODES {
            return Err(BrakeError::TooLarge {
                nodes,
                limit: MAX_NODES,
            });
        }
        Ok(())
    }
}

// Parts, in the order of `Mesh::parts`.
const DISC: usize = 0;
const INBOARD_FRICTION: usize = 1;
const INBOARD_BACKPLATE: usize = 2;
const OUTBOARD_FRICTION: usize = 3;
const OUTBOARD_BACKPLATE: usize = 4;
const PART_NAMES: [&str; 5] = [
    "disc",
    "pad_inboard_friction",
    "pad_inboard_backplate",
    "pad_outboard_friction",
    "pad_outboard_backplate",
];
const PART_MATERIALS: [&str; 5] = [
    "cast_iron",
    "friction_material",
    "steel",
    "friction_material",
    "steel",
];

// Parameter axes of a block, in this order so that (r, theta, z) -> (r cos, r sin, z) is
// orientation preserving (its Jacobian determinant is r > 0).
const R: usize = 0;
const THETA: usize = 1;
const Z: usize = 2;

/// A structured block in cylindrical coordinates. Grid lines are given by their values
/// (cell boundaries); a point of the refined grid has integer coordinates `p` with
/// `p[axis] / 2` the cell boundary (even) or the middle of a cell (odd).
struct Block {
    /// Cell boundaries per axis: r (m), theta (rad), z (m).
    lines: [Vec<f64>; 3],
    /// Theta wraps around (the disc).
    periodic: bool,
    /// Part of the cells in theta column i and layer k (`layout[i * nz + k]`), `None` where
    /// the block has no cell (the lining under the backplate ears).
    layout: Vec<Option<usize>>,
}

impl Block {
    fn cells(&self) -> [usize; 3] {
        self.lines.each_ref().map(|l| l.len() - 1)
    }

    /// Distinct refined points per axis.
    fn points(&self) -> [usize; 3] {
        let c = self.cells();
        [
            2 * c[R] + 1,
            if self.periodic {
                2 * c[THETA]
            } else {
                2 * c[THETA] + 1
            },
            2 * c[Z] + 1,
        ]
    }

    fn part(&self, i_theta: usize, k_z: usize) -> Option<usize> {
        self.layout[i_theta * self.cells()[Z] + k_z]
    }

    /// Index of a refined point, theta-major so that node numbers sweep around the disc
    /// (a narrow band of the stiffness matrix). Theta wraps on a periodic block.
    fn key(&self, p: [usize; 3]) -> usize {
        let n = self.points();
        let t = p[THETA] % n[THETA];
        (t * n[R] + p[R]) * n[Z] + p[Z]
    }

    fn unkey(&self, key: usize) -> [usize; 3] {
        let n = self.points();
        [(key / n[Z]) % n[R], key / (n[Z] * n[R]), key % n[Z]]
    }

    /// Cartesian position of a refined point (parametric middle of a cell for odd indices).
    fn position(&self, p: [usize; 3]) -> [f64; 3] {
        let value = |axis: usize| {
            let l = &self.lines[axis];
            let i = p[axis] / 2;
            if p[axis] % 2 == 1 {
                0.5 * (l[i] + l[i + 1])
            } else {
                l[i]
            }
        };
        let (r, theta, z) = (value(R), value(THETA), value(Z));
        [r * theta.cos(), r * theta.sin(), z]
    }
}

/// The 6 Kuhn tetrahedra of the unit cube as corner offsets per parameter axis, each ordered
/// so that its parametric volume is positive. Tet sigma follows the cube edges from (0,0,0)
/// to (1,1,1) in the axis order sigma; its volume has the sign of the permutation, so odd
/// ones swap corners 1 and 2.
fn kuhn_tets() -> [[[usize; 3]; 4]; 6] {
    const PERMUTATIONS: [([usize; 3], bool); 6] = [
        ([0, 1, 2], true),
        ([1, 2, 0], true),
        ([2, 0, 1], true),
        ([0, 2, 1], false),
        ([2, 1, 0], false),
        ([1, 0, 2], false),
    ];
    PERMUTATIONS.map(|(sigma, even)| {
        let mut corners = [[0usize; 3]; 4];
        for step in 0..3 {
            corners[step + 1] = corners[step];
            corners[step + 1][sigma[step]] = 1;
        }
        if !even {
            corners.swap(1, 2);
        }
        corners
    })
}

/// Where an element came from, for picking surfaces.
struct Origin {
    block: usize,
    part: usize,
    /// Theta cell index.
    theta_cell: usize,
    /// Refined-grid coordinates of the 4 corners (theta not wrapped).
    corners: [[usize; 3]; 4],
}

/// `n` cells between `a` and `b`; the end values are exactly `a` and `b`, so that touching
/// parts share bit-identical coordinates.
fn linspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..=n)
        .map(|i| {
            if i == n {
                b
            } else {
                a + (b - a) * (i as f64 / n as f64)
            }
        })
        .collect()
}

/// The blocks: disc, inboard pad, outboard pad. Also returns the theta-cell range of the
/// lining (same in both pads).
fn blocks(p: &BrakeParams) -> ([Block; 3], std::ops::Range<usize>) {
    let d = &p.divisions;
    let half = 0.5 * p.disc_thickness;
    let disc = Block {
        lines: [
            linspace(p.disc_inner_radius, p.disc_outer_radius, d.disc_radial),
            linspace(0.0, 2.0 * PI, d.disc_circumferential),
            linspace(-half, half, d.disc_thickness),
        ],
        periodic: true,
        layout: vec![Some(DISC); d.disc_circumferential * d.disc_thickness],
    };

    let o = p.overhang_cells();
    let centre = p.pad_centre_deg.to_radians();
    let half_arc = 0.5 * p.pad_arc_deg.to_radians();
    let ear = p.backplate_overhang_deg.to_radians();
    let mut theta = Vec::with_capacity(d.pad_circumferential + 2 * o + 1);
    if o > 0 {
        let left = linspace(centre - half_arc - ear, centre - half_arc, o);
        theta.extend_from_slice(&left[..o]);
    }
    theta.extend(linspace(
        centre - half_arc,
        centre + half_arc,
        d.pad_circumferential,
    ));
    if o > 0 {
        let right = linspace(centre + half_arc, centre + half_arc + ear, o);
        theta.extend_from_slice(&right[1..]);
    }
    let lining = o..o + d.pad_circumferential;
    let radii = linspace(p.pad_inner_radius, p.pad_outer_radius, d.pad_radial);

    // Inboard pad from the friction face up: lining layers first, then the backplate.
    let z0 = half + p.pad_gap;
    let z1 = z0 + p.friction_thickness;
    let z2 = z1 + p.backplate_thickness;
    let mut z_in = linspace(z0, z1, d.friction_thickness);
    z_in.extend_from_slice(&linspace(z1, z2, d.backplate_thickness)[1..]);
    let (nf, nb) = (d.friction_thickness, d.backplate_thickness);
    let n_theta = theta.len() - 1;
    let layout = |friction_first: bool, friction: usize, backplate: usize| {
        let mut layout = Vec::with_capacity(n_theta * (nf + nb));
        for i in 0..n_theta {
            for k in 0..nf + nb {
                let is_friction = if friction_first { k < nf } else { k >= nb };
                layout.push(if !is_friction {
                    Some(backplate)
                } else if lining.contains(&i) {
                    Some(friction)
                } else {
                    None
                });
            }
        }
        layout
    };
    let inboard = Block {
        lines: [radii.clone(), theta.clone(), z_in.clone()],
        periodic: false,
        layout: layout(true, INBOARD_FRICTION, INBOARD_BACKPLATE),
    };
    // Outboard pad: the mirror image in z = 0 (exact negation), z increasing from the
    // backplate's back face to the friction face.
    let z_out: Vec<f64> = z_in.iter().rev().map(|z| -z).collect();
    let outboard = Block {
        lines: [radii, theta, z_out],
        periodic: false,
        layout: layout(false, OUTBOARD_FRICTION, OUTBOARD_BACKPLATE),
    };
    ([disc, inboard, outboard], lining)
}

/// A surface (or node set) picked as the element faces of some parts of a block whose three
/// corners lie on the grid plane `axis = value` (refined index).
struct Pick {
    block: usize,
    part: usize,
    axis: usize,
    value: usize,
    theta_cells: std::ops::Range<usize>,
}

/// Builds the brake mesh. Node and element labels are 1-based and contiguous; nodes are
/// numbered block by block (disc, inboard pad, outboard pad), theta-major.
pub fn build(params: &BrakeParams) -> Result<Mesh, BrakeError> {
    params.validate()?;
    let (blocks, lining) = blocks(params);
    let kuhn = kuhn_tets();

    let mut mesh = Mesh::default();
    let mut origins: Vec<Origin> = Vec::with_capacity(params.element_count());
    mesh.elements.reserve(params.element_count());
    mesh.nodes.reserve(params.node_count());
    let mut parts: Vec<Vec<usize>> = vec![Vec::new(); PART_NAMES.len()];

    for (b, block) in blocks.iter().enumerate() {
        let cells = block.cells();
        let n = block.points();
        // Block-local keys of every element first; then the used refined points get global
        // numbers in key order, so that each point (corner or mid-edge) is one node, shared
        // by all elements around it, and no node is unused.
        let first_element = mesh.elements.len();
        let mut keys: Vec<[usize; 10]> = Vec::new();
        for i in 0..cells[THETA] {
            for j in 0..cells[R] {
                for k in 0..cells[Z] {
                    let Some(part) = block.part(i, k) else {
                        continue;
                    };
                    let cell = [j, i, k];
                    for tet in &kuhn {
                        let corners: [[usize; 3]; 4] =
                            tet.map(|off| [0, 1, 2].map(|a| 2 * (cell[a] + off[a])));
                        let mut element = [0usize; 10];
                        for (c, corner) in corners.iter().enumerate() {
                            element[c] = block.key(*corner);
                        }
                        for (m, [a, bb]) in TET10_EDGES.iter().enumerate() {
                            let mid = [0, 1, 2].map(|ax| (corners[*a][ax] + corners[*bb][ax]) / 2);
                            element[4 + m] = block.key(mid);
                        }
                        parts[part].push(first_element + keys.len());
                        keys.push(element);
                        origins.push(Origin {
                            block: b,
                            part,
                            theta_cell: i,
                            corners,
                        });
                    }
                }
            }
        }
        let mut global = vec![usize::MAX; n[0] * n[1] * n[2]];
        for element in &keys {
            for &key in element {
                global[key] = 0;
            }
        }
        for (key, id) in global.iter_mut().enumerate() {
            if *id == 0 {
                *id = mesh.nodes.len();
                mesh.nodes.push(block.position(block.unkey(key)));
            }
        }
        mesh.elements
            .extend(keys.iter().map(|element| element.map(|key| global[key])));
    }
    mesh.node_labels = (1..=mesh.nodes.len() as i64).collect();
    mesh.element_labels = (1..=mesh.elements.len() as i64).collect();

    for (e, conn) in mesh.elements.iter().enumerate() {
        let x = conn.map(|n| mesh.nodes[n]);
        let bad = CHECK_POINTS
            .iter()
            .map(|l| jacobian_det(&x, *l))
            .find(|det| det.is_nan() || *det <= 0.0);
        if let Some(det) = bad {
            return Err(BrakeError::Inverted {
                part: PART_NAMES[origins[e].part].to_string(),
                label: mesh.element_labels[e],
                det,
            });
        }
    }

    mesh.parts = PART_NAMES
        .iter()
        .zip(PART_MATERIALS)
        .zip(parts)
        .map(|((name, material), elements)| Part {
            name: name.to_string(),
            elements,
            material: Some(material.to_string()),
        })
        .collect();
    for (name, e) in [
        ("cast_iron", params.cast_iron),
        ("friction_material", params.friction_material),
        ("steel", params.steel),
    ] {
        mesh.materials.insert(
            name.to_string(),
            Material {
                name: name.to_string(),
                young: e.young,
                poisson: e.poisson,
                density: e.density,
            },
        );
    }

    // Surfaces and node sets.
    let [disc, pad_in, _] = &blocks;
    let disc_cells = disc.cells();
    let pad_cells = pad_in.cells();
    let (theta_min, theta_max) = (0, 2 * pad_cells[THETA]);
    let (leading, trailing) = match params.rotation {
        Rotation::CounterClockwise => (theta_min, theta_max),
        Rotation::Clockwise => (theta_max, theta_min),
    };
    let pad_top = 2 * pad_cells[Z];
    let all_pad = 0..pad_cells[THETA];
    let all_disc = 0..disc_cells[THETA];
    let pick = |block, part, axis, value, theta_cells: &std::ops::Range<usize>| Pick {
        block,
        part,
        axis,
        value,
        theta_cells: theta_cells.clone(),
    };
    let surfaces = [
        (
            "disc_inboard_face",
            pick(0, DISC, Z, 2 * disc_cells[Z], &all_disc),
        ),
        ("disc_outboard_face", pick(0, DISC, Z, 0, &all_disc)),
        (
            "pad_inboard_friction_face",
            pick(1, INBOARD_FRICTION, Z, 0, &lining),
        ),
        (
            "pad_outboard_friction_face",
            pick(2, OUTBOARD_FRICTION, Z, pad_top, &lining),
        ),
        (
            "backplate_inboard_piston",
            pick(1, INBOARD_BACKPLATE, Z, pad_top, &lining),
        ),
        (
            "backplate_outboard_caliper",
            pick(2, OUTBOARD_BACKPLATE, Z, 0, &lining),
        ),
        (
            "pad_inboard_abutment_leading",
            pick(1, INBOARD_BACKPLATE, THETA, leading, &all_pad),
        ),
        (
            "pad_inboard_abutment_trailing",
            pick(1, INBOARD_BACKPLATE, THETA, trailing, &all_pad),
        ),
        (
            "pad_outboard_abutment_leading",
            pick(2, OUTBOARD_BACKPLATE, THETA, leading, &all_pad),
        ),
        (
            "pad_outboard_abutment_trailing",
            pick(2, OUTBOARD_BACKPLATE, THETA, trailing, &all_pad),
        ),
    ];
    for (name, spec) in &surfaces {
        let surface = Surface {
            name: name.to_string(),
            faces: pick_faces(&mesh, &origins, spec),
        };
        mesh.node_sets
            .insert(name.to_string(), mesh.surface_nodes(&surface));
        mesh.surfaces.insert(name.to_string(), surface);
    }
    let node_sets = [
        ("disc_hub", pick(0, DISC, R, 0, &all_disc)),
        (
            "pad_inboard_guides",
            pick(1, INBOARD_BACKPLATE, R, 2 * pad_cells[R], &all_pad),
        ),
        (
            "pad_outboard_guides",
            pick(2, OUTBOARD_BACKPLATE, R, 2 * pad_cells[R], &all_pad),
        ),
    ];
    for (name, spec) in &node_sets {
        let faces = Surface {
            name: name.to_string(),
            faces: pick_faces(&mesh, &origins, spec),
        };
        mesh.node_sets
            .insert(name.to_string(), mesh.surface_nodes(&faces));
    }
    Ok(mesh)
}

/// The outward element faces selected by `spec` (outward because every element is
/// positively oriented and [`TET10_FACES`] lists faces outward).
fn pick_faces(mesh: &Mesh, origins: &[Origin], spec: &Pick) -> Vec<Face> {
    let mut faces = Vec::new();
    for (e, origin) in origins.iter().enumerate() {
        if origin.block != spec.block
            || origin.part != spec.part
            || !spec.theta_cells.contains(&origin.theta_cell)
        {
            continue;
        }
        for (side, local) in TET10_FACES.iter().enumerate() {
            if local[..3]
                .iter()
                .all(|&c| origin.corners[c][spec.axis] == spec.value)
            {
                faces.push(mesh.face(e, side as u8));
            }
        }
    }
    faces
}

/// Barycentric points where [`build`] checks the Jacobian: the 4 corners and the 4-point
/// Gauss rule used for the stiffness.
const CHECK_POINTS: [[f64; 4]; 8] = {
    const A: f64 = 0.585_410_196_624_968_5;
    const B: f64 = 0.138_196_601_125_010_5;
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [A, B, B, B],
        [B, A, B, B],
        [B, B, A, B],
        [B, B, B, A],
    ]
};

/// Determinant of the Jacobian of the TET10 map at barycentric point `l` (l[0] = 1 - xi -
/// eta - zeta, l[1] = xi, l[2] = eta, l[3] = zeta), node order of [`TET10_EDGES`].
fn jacobian_det(x: &[[f64; 3]; 10], l: [f64; 4]) -> f64 {
    // d l_i / d(xi, eta, zeta).
    const DL: [[f64; 3]; 4] = [
        [-1.0, -1.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let mut jac = [[0.0f64; 3]; 3];
    let mut add = |node: usize, grad: [f64; 3]| {
        for (row, coord) in jac.iter_mut().zip(x[node]) {
            for (entry, g) in row.iter_mut().zip(grad) {
                *entry += coord * g;
            }
        }
    };
    for i in 0..4 {
        // N_i = l_i (2 l_i - 1).
        add(i, DL[i].map(|g| (4.0 * l[i] - 1.0) * g));
    }
    for (m, [a, b]) in TET10_EDGES.iter().enumerate() {
        // N = 4 l_a l_b.
        add(
            4 + m,
            [0, 1, 2].map(|d| 4.0 * (l[*a] * DL[*b][d] + l[*b] * DL[*a][d])),
        );
    }
    jac[0][0] * (jac[1][1] * jac[2][2] - jac[1][2] * jac[2][1])
        - jac[0][1] * (jac[1][0] * jac[2][2] - jac[1][2] * jac[2][0])
        + jac[0][2] * (jac[1][0] * jac[2][1] - jac[1][1] * jac[2][0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::model::{cross, dot, sub};
    use std::collections::HashMap;

    fn tiny() -> (BrakeParams, Mesh) {
        let p = preset("tiny").unwrap();
        let m = build(&p).unwrap();
        (p, m)
    }

    fn part<'a>(m: &'a Mesh, name: &str) -> &'a Part {
        m.parts.iter().find(|p| p.name == name).unwrap()
    }

    /// Area swept from the axis by the quadratic (parabolic) arc through three equally spaced
    /// points of the circle of radius `r` over the angle `h`: with the arc parametrised as
    /// x = r (1 - (1 - c) t^2), y = r s t, t in [-1, 1], c = cos(h/2), s = sin(h/2),
    /// (1/2) int (x y' - y x') dt = r^2 s (1 + (1 - c) / 3) = (r^2 h / 2)(1 - (h/2)^4 / 30 + ...).
    fn fan(r: f64, h: f64) -> f64 {
        let (s, c) = (0.5 * h).sin_cos();
        r * r * s * (1.0 + (1.0 - c) / 3.0)
    }

    /// (angle, count) of the theta cells of the lining and of the backplate ears.
    fn pad_cells(p: &BrakeParams) -> [(f64, usize); 2] {
        let o = p.overhang_cells();
        let ear = if o > 0 {
            p.backplate_overhang_deg.to_radians() / o as f64
        } else {
            0.0
        };
        [
            (
                p.pad_arc_deg.to_radians() / p.divisions.pad_circumferential as f64,
                p.divisions.pad_circumferential,
            ),
            (ear, 2 * o),
        ]
    }

    /// Plan-view area of the discretised (parabolic-arc) ring sector made of `cells`.
    fn ring_area(r1: f64, r2: f64, cells: &[(f64, usize)]) -> f64 {
        cells
            .iter()
            .map(|&(h, n)| n as f64 * (fan(r2, h) - fan(r1, h)))
            .sum()
    }

    /// Keast's 5-point rule, exact for cubics: the TET10 Jacobian determinant is a cubic,
    /// so this gives the exact volume of the quadratic element.
    fn element_volume(m: &Mesh, e: usize) -> f64 {
        let x = m.elements[e].map(|n| m.nodes[n]);
        let (a, b) = (0.5, 1.0 / 6.0);
        let points = [
            (-0.8, [0.25; 4]),
            (0.45, [a, b, b, b]),
            (0.45, [b, a, b, b]),
            (0.45, [b, b, a, b]),
            (0.45, [b, b, b, a]),
        ];
        points
            .iter()
            .map(|(w, l)| w * jacobian_det(&x, *l) / 6.0)
            .sum()
    }

    /// Position and normal (x_s cross x_t, outward for an outward face) of a 6-node face at
    /// (s, t), corner a at (0, 0), b at (1, 0), c at (0, 1).
    fn face_point(m: &Mesh, f: &Face, s: f64, t: f64) -> ([f64; 3], [f64; 3]) {
        let x = f.nodes.map(|n| m.nodes[n]);
        let l = [1.0 - s - t, s, t];
        let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
        let mut n = [0.0; 6];
        let mut dn = [[0.0; 2]; 6];
        for i in 0..3 {
            n[i] = l[i] * (2.0 * l[i] - 1.0);
            dn[i] = dl[i].map(|g| (4.0 * l[i] - 1.0) * g);
            let j = (i + 1) % 3;
            n[3 + i] = 4.0 * l[i] * l[j];
            dn[3 + i] = [0, 1].map(|d| 4.0 * (l[i] * dl[j][d] + l[j] * dl[i][d]));
        }
        let mut pos = [0.0; 3];
        let mut xs = [0.0; 3];
        let mut xt = [0.0; 3];
        for k in 0..6 {
            for c in 0..3 {
                pos[c] += n[k] * x[k][c];
                xs[c] += dn[k][0] * x[k][c];
                xt[c] += dn[k][1] * x[k][c];
            }
        }
        (pos, cross(xs, xt))
    }

    /// Integral of normal . dir over a flat face (the integrand is quadratic, so the
    /// 3-point rule is exact), asserting that normal . dir > 0 at every point.
    fn flat_face_area(m: &Mesh, f: &Face, dir: [f64; 3]) -> f64 {
        let mut area = 0.0;
        for (s, t) in [
            (1.0 / 6.0, 1.0 / 6.0),
            (2.0 / 3.0, 1.0 / 6.0),
            (1.0 / 6.0, 2.0 / 3.0),
        ] {
            let (_, n) = face_point(m, f, s, t);
            let along = dot(n, dir);
            assert!(along > 0.0, "face of element {} points inward", f.element);
            area += along / 6.0;
        }
        area
    }

    fn cylindrical(x: [f64; 3]) -> [f64; 3] {
        [x[0].hypot(x[1]), x[1].atan2(x[0]), x[2]]
    }

    #[test]
    fn preset_sizes_are_in_range_and_match_the_count_formula() {
        let ranges = [
            ("tiny", 2_000, 5_000),
            ("small", 15_000, 25_000),
            ("medium", 50_000, 70_000),
            ("industrial", 177_000, 250_000),
        ];
        assert_eq!(PRESETS, ranges.map(|r| r.0).as_slice());
        for (name, lo, hi) in ranges {
            let p = preset(name).unwrap();
            let n = p.node_count();
            assert!((lo..=hi).contains(&n), "{name}: {n} nodes");
            if name == "tiny" || name == "small" {
                let m = build(&p).unwrap();
                assert_eq!(m.nodes.len(), n, "{name}");
                assert_eq!(m.elements.len(), p.element_count(), "{name}");
            }
        }
        assert!(preset("huge").is_none());
        assert_eq!(BrakeParams::default(), preset("small").unwrap());
    }

    #[test]
    fn tiny_builds_well_under_a_second() {
        let start = std::time::Instant::now();
        let m = build(&preset("tiny").unwrap()).unwrap();
        assert!(!m.nodes.is_empty());
        // Debug build on a loaded machine: a generous bound; it takes a few milliseconds.
        assert!(start.elapsed().as_secs_f64() < 1.0, "{:?}", start.elapsed());
    }

    #[test]
    fn every_element_is_positive_and_its_mid_nodes_sit_on_the_parametric_middle() {
        for name in ["tiny", "small"] {
            let m = build(&preset(name).unwrap()).unwrap();
            let (a, b) = (0.5, 1.0 / 6.0);
            let mut points: Vec<[f64; 4]> = CHECK_POINTS.to_vec();
            points.extend([
                [0.25; 4],
                [a, b, b, b],
                [b, a, b, b],
                [b, b, a, b],
                [b, b, b, a],
            ]);
            for [i, j] in TET10_EDGES {
                let mut l = [0.0; 4];
                l[i] = 0.5;
                l[j] = 0.5;
                points.push(l);
            }
            for (e, conn) in m.elements.iter().enumerate() {
                assert!(m.corner_volume(e) > 0.0, "{name}: element {e}");
                let x = conn.map(|n| m.nodes[n]);
                for l in &points {
                    assert!(jacobian_det(&x, *l) > 0.0, "{name}: element {e} at {l:?}");
                }
                // Mid node = (r, theta, z) average of its corners, theta unwrapped across
                // the seam: on the circle, not on the chord. Coordinates are ~0.1 m and
                // exact to a few ulps; 1e-12 m leaves margin for atan2's rounding.
                for (k, [i, j]) in TET10_EDGES.iter().enumerate() {
                    let (ci, cj) = (cylindrical(x[*i]), cylindrical(x[*j]));
                    let mut dt = cj[1] - ci[1];
                    if dt > PI {
                        dt -= 2.0 * PI;
                    } else if dt < -PI {
                        dt += 2.0 * PI;
                    }
                    let (r, t, z) = (
                        0.5 * (ci[0] + cj[0]),
                        ci[1] + 0.5 * dt,
                        0.5 * (ci[2] + cj[2]),
                    );
                    let expect = [r * t.cos(), r * t.sin(), z];
                    let d = sub(x[4 + k], expect);
                    assert!(dot(d, d).sqrt() < 1e-12, "{name}: element {e} edge {k}");
                }
            }
        }
    }

    #[test]
    fn part_volumes_match_the_discretised_and_the_true_geometry() {
        for name in ["tiny", "small"] {
            let p = preset(name).unwrap();
            let m = build(&p).unwrap();
            let d = &p.divisions;
            let h_disc = 2.0 * PI / d.disc_circumferential as f64;
            let cells = pad_cells(&p);
            let (r1, r2) = (p.pad_inner_radius, p.pad_outer_radius);
            let disc_cells = [(h_disc, d.disc_circumferential)];
            let lining_area = ring_area(r1, r2, &cells[..1]);
            let backplate_area = ring_area(r1, r2, &cells);
            let backplate_arc = (p.pad_arc_deg + 2.0 * p.backplate_overhang_deg).to_radians();
            let lining_arc = p.pad_arc_deg.to_radians();
            let exact_sector = |arc: f64| 0.5 * (r2 * r2 - r1 * r1) * arc;
            let expected = [
                (
                    "disc",
                    p.disc_thickness
                        * ring_area(p.disc_inner_radius, p.disc_outer_radius, &disc_cells),
                    p.disc_thickness
                        * PI
                        * (p.disc_outer_radius.powi(2) - p.disc_inner_radius.powi(2)),
                    h_disc,
                ),
                (
                    "pad_inboard_friction",
                    p.friction_thickness * lining_area,
                    p.friction_thickness * exact_sector(lining_arc),
                    cells[0].0,
                ),
                (
                    "pad_inboard_backplate",
                    p.backplate_thickness * backplate_area,
                    p.backplate_thickness * exact_sector(backplate_arc),
                    cells[0].0.max(cells[1].0),
                ),
                (
                    "pad_outboard_friction",
                    p.friction_thickness * lining_area,
                    p.friction_thickness * exact_sector(lining_arc),
                    cells[0].0,
                ),
                (
                    "pad_outboard_backplate",
                    p.backplate_thickness * backplate_area,
                    p.backplate_thickness * exact_sector(backplate_arc),
                    cells[0].0.max(cells[1].0),
                ),
            ];
            for (part_name, discretised, exact, h) in expected {
                let v: f64 = part(&m, part_name)
                    .elements
                    .iter()
                    .map(|&e| element_volume(&m, e))
                    .sum();
                // The elements tile the region bounded by flat faces and parabolic arcs
                // exactly (shared quadratic faces cancel), so only summation round-off is
                // left: ~n * eps relative.
                let rel = (v - discretised).abs() / discretised;
                assert!(
                    rel < 1e-11,
                    "{name} {part_name}: {v} vs {discretised} ({rel:e})"
                );
                // The parabolic arc lies inside the circle by (h/2)^4 / 30 of the sector
                // area to leading order (expansion of `fan`); allow 10 % for the next term.
                let chord = (exact - v) / exact;
                let bound = 1.1 * (0.5 * h).powi(4) / 30.0;
                assert!(
                    chord >= 0.0 && chord < bound,
                    "{name} {part_name}: {v} vs {exact} ({chord:e} > {bound:e})"
                );
            }
        }
    }

    #[test]
    fn surfaces_lie_on_their_planes_with_outward_normals_and_full_area() {
        let (p, m) = tiny();
        let half = 0.5 * p.disc_thickness;
        let face_z = half + p.pad_gap;
        let back_z = face_z + p.friction_thickness + p.backplate_thickness;
        let d = &p.divisions;
        let disc_cells = [(
            2.0 * PI / d.disc_circumferential as f64,
            d.disc_circumferential,
        )];
        let disc_area = ring_area(p.disc_inner_radius, p.disc_outer_radius, &disc_cells);
        let lining_area = ring_area(p.pad_inner_radius, p.pad_outer_radius, &pad_cells(&p)[..1]);
        let flat = [
            ("disc_inboard_face", half, 1.0, disc_area),
            ("disc_outboard_face", -half, -1.0, disc_area),
            ("pad_inboard_friction_face", face_z, -1.0, lining_area),
            ("pad_outboard_friction_face", -face_z, 1.0, lining_area),
            ("backplate_inboard_piston", back_z, 1.0, lining_area),
            ("backplate_outboard_caliper", -back_z, -1.0, lining_area),
        ];
        for (name, z, sign, expected_area) in flat {
            let s = &m.surfaces[name];
            assert_eq!(s.name, name);
            assert!(!s.faces.is_empty(), "{name}");
            let mut area = 0.0;
            for f in &s.faces {
                assert_eq!(*f, m.face(f.element, f.side), "{name}");
                for &n in &f.nodes {
                    assert_eq!(m.nodes[n][2], z, "{name}: node {n} off the plane");
                }
                area += flat_face_area(&m, f, [0.0, 0.0, sign]);
            }
            let rel = (area - expected_area).abs() / expected_area;
            assert!(rel < 1e-12, "{name}: area {area} vs {expected_area}");
            assert_eq!(m.node_sets[name], m.surface_nodes(s), "{name}");
        }

        // Abutments: the planes theta = const at the backplate ends, normal along -/+ the
        // circumferential direction for the leading/trailing end, area = height x thickness.
        let half_span = (0.5 * p.pad_arc_deg + p.backplate_overhang_deg).to_radians();
        let centre = p.pad_centre_deg.to_radians();
        let z_range = [face_z + p.friction_thickness, back_z];
        for (side, sign) in [("inboard", 1.0), ("outboard", -1.0)] {
            for (end, theta, out) in [
                ("leading", centre - half_span, -1.0),
                ("trailing", centre + half_span, 1.0),
            ] {
                let name = format!("pad_{side}_abutment_{end}");
                let s = &m.surfaces[&name];
                let tangent = [-theta.sin(), theta.cos(), 0.0];
                let radial = [theta.cos(), theta.sin(), 0.0];
                let mut area = 0.0;
                for f in &s.faces {
                    for &n in &f.nodes {
                        let x = m.nodes[n];
                        assert!(
                            dot(x, tangent).abs() < 1e-15,
                            "{name}: node {n} off the plane"
                        );
                        assert!(dot(x, radial) > 0.0);
                        let z = sign * x[2];
                        assert!(
                            z >= z_range[0] && z <= z_range[1],
                            "{name}: node {n} not on the backplate"
                        );
                    }
                    area += flat_face_area(&m, f, tangent.map(|c| out * c));
                }
                let expected = (p.pad_outer_radius - p.pad_inner_radius) * p.backplate_thickness;
                assert!(
                    (area - expected).abs() < 1e-12 * expected,
                    "{name}: {area} vs {expected}"
                );
            }
        }

        // Node sets on cylinders: the hub (every disc node at r_inner) and the guides (the
        // backplates' outer radial edge, ears included).
        let o = p.overhang_cells();
        let t = d.pad_circumferential + 2 * o;
        let on_radius = |set: &str, r: f64, count: usize| {
            let nodes = &m.node_sets[set];
            assert_eq!(nodes.len(), count, "{set}");
            for &n in nodes {
                let x = m.nodes[n];
                assert!((x[0].hypot(x[1]) - r).abs() < 1e-15, "{set}: node {n}");
            }
        };
        on_radius(
            "disc_hub",
            p.disc_inner_radius,
            2 * d.disc_circumferential * (2 * d.disc_thickness + 1),
        );
        let guide_count = (2 * t + 1) * (2 * d.backplate_thickness + 1);
        on_radius("pad_inboard_guides", p.pad_outer_radius, guide_count);
        on_radius("pad_outboard_guides", p.pad_outer_radius, guide_count);
        for &n in &m.node_sets["pad_inboard_guides"] {
            assert!(m.nodes[n][2] >= z_range[0] && m.nodes[n][2] <= z_range[1]);
        }
        let expected_sets = [
            "backplate_inboard_piston",
            "backplate_outboard_caliper",
            "disc_hub",
            "disc_inboard_face",
            "disc_outboard_face",
            "pad_inboard_abutment_leading",
            "pad_inboard_abutment_trailing",
            "pad_inboard_friction_face",
            "pad_inboard_guides",
            "pad_outboard_abutment_leading",
            "pad_outboard_abutment_trailing",
            "pad_outboard_friction_face",
            "pad_outboard_guides",
        ];
        assert_eq!(
            m.node_sets.keys().map(String::as_str).collect::<Vec<_>>(),
            expected_sets
        );
        assert_eq!(m.surfaces.len(), 10);
    }

    #[test]
    fn clockwise_rotation_swaps_leading_and_trailing() {
        let (p, ccw) = tiny();
        let cw = build(&BrakeParams {
            rotation: Rotation::Clockwise,
            ..p
        })
        .unwrap();
        for side in ["inboard", "outboard"] {
            let lead = format!("pad_{side}_abutment_leading");
            let trail = format!("pad_{side}_abutment_trailing");
            assert_eq!(cw.surfaces[&lead].faces, ccw.surfaces[&trail].faces);
            assert_eq!(cw.surfaces[&trail].faces, ccw.surfaces[&lead].faces);
        }
    }

    #[test]
    fn mesh_is_conforming_across_the_seam_and_the_glued_interface() {
        let (p, m) = tiny();
        let owner = m.element_parts();
        let mut faces: HashMap<[usize; 3], Vec<(usize, [usize; 6])>> = HashMap::new();
        for e in 0..m.elements.len() {
            for side in 0..4u8 {
                let f = m.face(e, side);
                let mut corners = [f.nodes[0], f.nodes[1], f.nodes[2]];
                corners.sort_unstable();
                let mut all = f.nodes;
                all.sort_unstable();
                faces.entry(corners).or_default().push((e, all));
            }
        }
        let d = &p.divisions;
        let mut boundary = 0;
        let mut seam = 0;
        let mut glued = 0;
        for (corners, users) in &faces {
            assert!(
                users.len() <= 2,
                "face {corners:?} shared by {} elements",
                users.len()
            );
            if users.len() == 1 {
                boundary += 1;
                continue;
            }
            let ((e0, n0), (e1, n1)) = (users[0], users[1]);
            assert_eq!(n0, n1, "shared face {corners:?} with different mid nodes");
            let (p0, p1) = (owner[e0].unwrap(), owner[e1].unwrap());
            if p0 != p1 {
                // Only lining and backplate of one pad may share faces.
                let pair = [p0.min(p1), p0.max(p1)];
                assert!(
                    pair == [INBOARD_FRICTION, INBOARD_BACKPLATE]
                        || pair == [OUTBOARD_FRICTION, OUTBOARD_BACKPLATE],
                    "parts {p0} and {p1} share a face"
                );
                glued += 1;
            }
            if p0 == DISC
                && corners
                    .iter()
                    .all(|&n| m.nodes[n][1] == 0.0 && m.nodes[n][0] > 0.0)
            {
                seam += 1;
            }
        }
        // Independent count of boundary quads (2 triangles each). Disc: 2 faces + inner
        // and outer cylinder, no theta ends (it is closed). Pad: T = lining + ear cells;
        // backplate top, ear bottoms, inner/outer edges, ends; lining friction face, inner
        // and outer edges, ends.
        let (nt, nr, nz) = (d.disc_circumferential, d.disc_radial, d.disc_thickness);
        let (pt, pr, pf, pb) = (
            d.pad_circumferential,
            d.pad_radial,
            d.friction_thickness,
            d.backplate_thickness,
        );
        let t = pt + 2 * p.overhang_cells();
        let disc_quads = 2 * nt * nr + 2 * nt * nz;
        let pad_quads =
            t * pr + (t - pt) * pr + 2 * t * pb + 2 * pr * pb + pt * pr + 2 * pt * pf + 2 * pr * pf;
        assert_eq!(boundary, 2 * (disc_quads + 2 * pad_quads));
        // The theta = 0 half-plane inside the disc: every quad there is shared.
        assert_eq!(seam, 2 * nr * nz);
        assert_eq!(glued, 2 * 2 * pt * pr);
    }

    #[test]
    fn no_unused_or_duplicate_nodes_and_contiguous_labels() {
        for name in ["tiny", "small"] {
            let m = build(&preset(name).unwrap()).unwrap();
            let mut used = vec![false; m.nodes.len()];
            for conn in &m.elements {
                for &n in conn {
                    used[n] = true;
                }
            }
            assert!(used.iter().all(|&u| u), "{name}: unused node");
            let mut order: Vec<usize> = (0..m.nodes.len()).collect();
            order.sort_by(|&a, &b| m.nodes[a][0].total_cmp(&m.nodes[b][0]));
            for (k, &a) in order.iter().enumerate() {
                for &b in &order[k + 1..] {
                    if m.nodes[b][0] - m.nodes[a][0] > 1e-9 {
                        break;
                    }
                    let d = sub(m.nodes[a], m.nodes[b]);
                    assert!(
                        dot(d, d).sqrt() > 1e-9,
                        "{name}: nodes {a} and {b} coincide"
                    );
                }
            }
            assert!(m
                .node_labels
                .iter()
                .enumerate()
                .all(|(i, &l)| l == i as i64 + 1));
            assert!(m
                .element_labels
                .iter()
                .enumerate()
                .all(|(i, &l)| l == i as i64 + 1));
            let mut in_parts: Vec<usize> =
                m.parts.iter().flat_map(|p| p.elements.clone()).collect();
            in_parts.sort_unstable();
            assert_eq!(
                in_parts,
                (0..m.elements.len()).collect::<Vec<_>>(),
                "{name}"
            );
            for part in &m.parts {
                let material = part.material.as_ref().unwrap();
                assert!(m.materials.contains_key(material), "{}", part.name);
            }
        }
    }

    #[test]
    fn pads_touch_the_disc_faces_without_matching_nodes() {
        for name in ["tiny", "small"] {
            let p = preset(name).unwrap();
            let m = build(&p).unwrap();
            for (pad, disc) in [
                ("pad_inboard_friction_face", "disc_inboard_face"),
                ("pad_outboard_friction_face", "disc_outboard_face"),
            ] {
                let disc_nodes = &m.node_sets[disc];
                let z = m.nodes[disc_nodes[0]][2];
                assert_eq!(z.abs(), 0.5 * p.disc_thickness);
                for &n in &m.node_sets[pad] {
                    // Bit-identical plane: zero initial gap.
                    assert_eq!(m.nodes[n][2], z, "{name} {pad}");
                    for &q in disc_nodes {
                        let d = sub(m.nodes[n], m.nodes[q]);
                        assert!(
                            dot(d, d).sqrt() > 1e-9,
                            "{name}: pad node {n} on disc node {q}"
                        );
                    }
                }
            }
        }
    }

    /// For every preset, not only the ones built here: the disc and pad grids are tensor
    /// products, so a pad friction-face node sits on a disc face node only if some refined
    /// radius and some refined angle of the two grids coincide.
    #[test]
    fn no_preset_has_pad_nodes_on_disc_nodes() {
        let refined = |lines: &[f64]| {
            let mut v: Vec<f64> = lines.to_vec();
            v.extend(lines.windows(2).map(|w| 0.5 * (w[0] + w[1])));
            v
        };
        let common = |a: &[f64], b: &[f64], period: Option<f64>| {
            a.iter().any(|x| {
                b.iter().any(|y| {
                    let mut d = (x - y).abs();
                    if let Some(p) = period {
                        d = d.rem_euclid(p).min(p - d.rem_euclid(p));
                    }
                    d < 1e-9
                })
            })
        };
        for &name in PRESETS {
            let p = preset(name).unwrap();
            let ([disc, pad, _], _) = blocks(&p);
            let radii = common(&refined(&disc.lines[R]), &refined(&pad.lines[R]), None);
            let angles = common(
                &refined(&disc.lines[THETA]),
                &refined(&pad.lines[THETA]),
                Some(2.0 * PI),
            );
            assert!(
                !(radii && angles),
                "{name}: matching nodes at the interface"
            );
        }
    }

    #[test]
    fn the_gap_moves_the_pads_off_the_disc() {
        let p = BrakeParams {
            pad_gap: 5e-4,
            ..preset("tiny").unwrap()
        };
        let m = build(&p).unwrap();
        let z = 0.5 * p.disc_thickness + p.pad_gap;
        for &n in &m.node_sets["pad_inboard_friction_face"] {
            assert_eq!(m.nodes[n][2], z);
        }
        for &n in &m.node_sets["pad_outboard_friction_face"] {
            assert_eq!(m.nodes[n][2], -z);
        }
        // Without ears the backplate ends with the lining.
        let flush = build(&BrakeParams {
            backplate_overhang_deg: 0.0,
            ..p
        })
        .unwrap();
        assert_eq!(
            flush.nodes.len(),
            BrakeParams {
                backplate_overhang_deg: 0.0,
                ..preset("tiny").unwrap()
            }
            .node_count()
        );
        assert!(!flush.surfaces["pad_inboard_abutment_leading"]
            .faces
            .is_empty());
    }

    #[test]
    fn preset_cells_are_moderately_shaped_and_the_pads_not_coarser_than_the_disc() {
        for &name in PRESETS {
            let p = preset(name).unwrap();
            let d = &p.divisions;
            // Largest edge ratio of a cell, over its inner and outer arc.
            let ratio = |r1: f64, r2: f64, dr: f64, dtheta: f64, dz: f64| {
                let dims = [dr, r1 * dtheta, r2 * dtheta, dz];
                let max = dims.iter().copied().fold(0.0, f64::max);
                let min = dims.iter().copied().fold(f64::INFINITY, f64::min);
                (max / min, max)
            };
            let dr = (p.disc_outer_radius - p.disc_inner_radius) / d.disc_radial as f64;
            let (disc_ratio, disc_size) = [p.disc_inner_radius, p.disc_outer_radius - dr]
                .iter()
                .map(|&r| {
                    ratio(
                        r,
                        r + dr,
                        dr,
                        2.0 * PI / d.disc_circumferential as f64,
                        p.disc_thickness / d.disc_thickness as f64,
                    )
                })
                .fold((0.0f64, 0.0f64), |a, b| (a.0.max(b.0), a.1.max(b.1)));
            assert!(disc_ratio < 5.0, "{name}: disc cell ratio {disc_ratio}");
            let pr = (p.pad_outer_radius - p.pad_inner_radius) / d.pad_radial as f64;
            for (h, _) in pad_cells(&p).into_iter().filter(|c| c.1 > 0) {
                for dz in [
                    p.friction_thickness / d.friction_thickness as f64,
                    p.backplate_thickness / d.backplate_thickness as f64,
                ] {
                    for r in [p.pad_inner_radius, p.pad_outer_radius - pr] {
                        let (pad_ratio, pad_size) = ratio(r, r + pr, pr, h, dz);
                        assert!(pad_ratio < 5.0, "{name}: pad cell ratio {pad_ratio}");
                        assert!(
                            pad_size <= 1.05 * disc_size,
                            "{name}: pad {pad_size} disc {disc_size}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn bad_parameters_are_errors_not_panics() {
        let good = preset("tiny").unwrap();
        let check = |p: BrakeParams, expect: &str| {
            let err = build(&p).unwrap_err();
            let text = err.to_string();
            assert!(text.contains(expect), "{text:?} lacks {expect:?}");
            let mesh_err: MeshError = err.into();
            assert!(mesh_err.to_string().contains(expect));
        };
        check(
            BrakeParams {
                disc_thickness: -0.01,
                ..good.clone()
            },
            "`disc_thickness`",
        );
        check(
            BrakeParams {
                disc_outer_radius: f64::NAN,
                ..good.clone()
            },
            "`disc_outer_radius`",
        );
        check(
            BrakeParams {
                pad_gap: -1e-3,
                ..good.clone()
            },
            "`pad_gap`",
        );
        check(
            BrakeParams {
                pad_centre_deg: f64::INFINITY,
                ..good.clone()
            },
            "`pad_centre_deg`",
        );
        check(
            BrakeParams {
                pad_outer_radius: 0.145,
                ..good.clone()
            },
            "friction ring",
        );
        check(
            BrakeParams {
                pad_inner_radius: 0.07,
                ..good.clone()
            },
            "friction ring",
        );
        check(
            BrakeParams {
                disc_inner_radius: 0.15,
                ..good.clone()
            },
            "disc_inner_radius",
        );
        check(
            BrakeParams {
                pad_inner_radius: 0.136,
                ..good.clone()
            },
            "pad_inner_radius",
        );
        check(
            BrakeParams {
                pad_arc_deg: 170.0,
                ..good.clone()
            },
            "half the disc",
        );
        let mut zero = good.clone();
        zero.divisions.pad_radial = 0;
        check(zero, "`divisions.pad_radial`");
        let mut coarse = good.clone();
        coarse.divisions.disc_circumferential = 6;
        check(coarse, "`divisions.disc_circumferential`");
        let mut coarse_pad = good.clone();
        coarse_pad.divisions.pad_circumferential = 1;
        check(coarse_pad, "pad cell");
        let mut nu = good.clone();
        nu.steel.poisson = 0.5;
        check(nu, "`steel`");
        let mut rho = good.clone();
        rho.friction_material.density = 0.0;
        check(rho, "`friction_material.density`");
        let mut absurd = good.clone();
        absurd.divisions.pad_radial = usize::MAX;
        assert!(absurd.node_count() > 0, "the count must not overflow");
        check(absurd, "`divisions.pad_radial`");
        let mut huge = good.clone();
        huge.divisions.disc_circumferential = 50_000;
        huge.divisions.disc_radial = 1_000;
        check(huge, "limit");
    }

    #[test]
    fn params_round_trip_through_serde_and_take_defaults() {
        let p = preset("medium").unwrap();
        let text = serde_json::to_string(&p).unwrap();
        let back: BrakeParams = serde_json::from_str(&text).unwrap();
        assert_eq!(back, p);
        let partial: BrakeParams = serde_json::from_str(
            r#"{"disc_thickness": 0.028, "rotation": "clockwise",
                "divisions": {"disc_radial": 9}, "steel": {"young": 2e11, "poisson": 0.29, "density": 7800}}"#,
        )
        .unwrap();
        assert_eq!(partial.disc_thickness, 0.028);
        assert_eq!(partial.rotation, Rotation::Clockwise);
        assert_eq!(partial.divisions.disc_radial, 9);
        assert_eq!(
            partial.divisions.disc_thickness,
            Divisions::default().disc_thickness
        );
        assert_eq!(partial.steel.young, 2e11);
        assert_eq!(partial.cast_iron, BrakeParams::default().cast_iron);
        assert!(serde_json::from_str::<BrakeParams>(r#"{"disc_thikness": 0.02}"#).is_err());
    }

    /// `cargo test --release -- --ignored --nocapture` prints the sizes and the build time.
    #[test]
    #[ignore]
    fn industrial_preset_builds_and_prints_sizes() {
        for &name in PRESETS {
            let p = preset(name).unwrap();
            let start = std::time::Instant::now();
            let m = build(&p).unwrap();
            let elapsed = start.elapsed();
            assert_eq!(m.nodes.len(), p.node_count());
            assert_eq!(m.elements.len(), p.element_count());
            println!(
                "{name:>10}: {:>7} nodes {:>7} elements, built in {:.3} s",
                m.nodes.len(),
                m.elements.len(),
                elapsed.as_secs_f64()
            );
        }
    }
}
