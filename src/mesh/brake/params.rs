//! The brake's parameters: dimensions, materials and mesh divisions, the named presets, and
//! the checks that make every accepted set of parameters meshable.

use serde::{Deserialize, Serialize};

use super::BrakeError;

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

/// Which bodies hold the pads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Layout {
    /// Disc and pads only: the study stands in for the piston and caliper with pressures on
    /// the backplates and for the bracket with springs (the original built-in brake).
    #[default]
    #[serde(alias = "spring_held")]
    SpringHeld,
    /// The paper's floating caliper as meshed bodies: a piston in the caliper's bore, the
    /// caliper (housing, bridge over the disc rim, fingers) and the bracket (abutments, arms
    /// over the rim, a cross-member bolted to the knuckle). See [`super::caliper`].
    #[serde(alias = "floating_caliper")]
    FloatingCaliper,
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
///
/// In the floating-caliper layout the pads' lines also pass through the edges of the contact
/// ring under the piston, every segment cut into cells no larger than the nominal ones
/// (`pad_radial`, `pad_circumferential` over the lining), so a pad has at least as many
/// cells as asked; and the nominal pad cell (the smaller of the two) is the cell size of the
/// piston, the caliper and the bracket.
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
    // The floating-caliper presets: the pads' divisions also set the cell size of the
    // piston, caliper and bracket (the smaller of a pad's nominal radial and
    // circumferential cell), so they are chosen for the total size.
    const TINY_CALIPER: Divisions = Divisions {
        disc_circumferential: 32,
        disc_radial: 3,
        disc_thickness: 2,
        pad_circumferential: 6,
        pad_radial: 2,
        friction_thickness: 1,
        backplate_thickness: 1,
    };
    const SMALL_CALIPER: Divisions = Divisions {
        disc_circumferential: 60,
        disc_radial: 6,
        disc_thickness: 3,
        pad_circumferential: 8,
        pad_radial: 3,
        friction_thickness: 2,
        backplate_thickness: 1,
    };
    const MEDIUM_CALIPER: Divisions = Divisions {
        disc_circumferential: 84,
        disc_radial: 8,
        disc_thickness: 4,
        pad_circumferential: 15,
        pad_radial: 6,
        friction_thickness: 3,
        backplate_thickness: 2,
    };
    const INDUSTRIAL_CALIPER: Divisions = Divisions {
        disc_circumferential: 144,
        disc_radial: 14,
        disc_thickness: 5,
        pad_circumferential: 22,
        pad_radial: 9,
        friction_thickness: 4,
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
    /// Which bodies hold the pads; the fields below, down to `ductile_iron`, are used by the
    /// floating-caliper layout only.
    pub layout: Layout,
    /// Outer radius of the piston, m; its axis is parallel to z through the inboard pad's
    /// centre (mean pad radius, `pad_centre_deg`).
    pub piston_outer_radius: f64,
    /// Inner radius of the (thick-walled, hollow) piston, m.
    pub piston_inner_radius: f64,
    /// Piston length from its face on the backplate to its bottom, m.
    pub piston_length: f64,
    /// Radial clearance between the piston and the walls of the caliper's bore, m.
    pub bore_clearance: f64,
    /// Length of the hydraulic chamber between the piston bottom and the bore bottom, m.
    pub chamber_length: f64,
    /// Thickness of the caliper housing's walls around the bore, m.
    pub caliper_wall: f64,
    /// Thickness of the caliper housing behind the bore bottom, m.
    pub caliper_back_thickness: f64,
    /// Radial thickness of the caliper's bridge over the disc rim, m.
    pub caliper_bridge_thickness: f64,
    /// Axial thickness of the caliper's fingers on the outboard backplate, m.
    pub caliper_finger_thickness: f64,
    /// Radial clearance between the disc rim and the bridges of caliper and bracket, m.
    pub rim_clearance: f64,
    /// Clearance between bodies that do not touch (disc/bracket, bracket/pad, bracket/
    /// caliper, caliper housing/backplate), m.
    pub body_clearance: f64,
    /// Angle spanned by each bracket arm beyond a pad's ears, degrees.
    pub bracket_arm_deg: f64,
    /// Radial thickness of the bracket's cross-member and of its arms' bridges, m.
    pub bracket_thickness: f64,
    /// Caliper and bracket material (parts `caliper`, `bracket`, material `ductile_iron`).
    pub ductile_iron: Elastic,
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
            layout: Layout::SpringHeld,
            // A single-piston floating caliper of a small passenger car, sized to the
            // built-in pad (not taken from a drawing): a 40 mm piston (front calipers of
            // compact cars have 48-57 mm ones; 40 mm is what the 45 mm tall pad holds),
            // thick-walled (16 mm bore) so that its face covers the backplate's square
            // contact ring; caliper walls, bridge and fingers of 5-12 mm and bracket
            // sections of 10 mm, the wall thicknesses of cast calipers and brackets; a
            // 0.5 mm seal clearance, a 2 mm hydraulic chamber; clearances of a few mm keep
            // bodies that do not touch apart. The piston's hydraulic force at 2 MPa line
            // pressure is 2.5 kN (see `hydraulic_pressures`).
            piston_outer_radius: 0.020,
            piston_inner_radius: 0.008,
            piston_length: 0.030,
            bore_clearance: 0.0005,
            chamber_length: 0.002,
            caliper_wall: 0.005,
            caliper_back_thickness: 0.010,
            caliper_bridge_thickness: 0.012,
            caliper_finger_thickness: 0.012,
            rim_clearance: 0.005,
            body_clearance: 0.002,
            bracket_arm_deg: 10.0,
            bracket_thickness: 0.010,
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
            // Spheroidal-graphite (ductile) cast iron of calipers and brackets, EN-GJS-400-15
            // (EN 1563 informative data): E = 169 GPa, nu = 0.275, rho = 7100 kg/m^3.
            ductile_iron: Elastic {
                young: 169e9,
                poisson: 0.275,
                density: 7100.0,
            },
            divisions: Divisions::default(),
        }
    }
}

/// The built-in brake when none is named: the paper's floating-caliper brake (Table 1's
/// four contacts), at the size whose sweep runs in minutes on a workstation.
pub const DEFAULT_PRESET: &str = "small-caliper";

/// Names accepted by [`preset`], from coarsest to finest: `tiny` (3,010 nodes, for unit
/// tests), `small` (19,806, the default), `medium` (64,490) and `industrial` (192,690 nodes,
/// 128,280 elements: the size of the paper's brake model, 176,956 nodes), the spring-held
/// brake; then the same sizes of the floating-caliper layout ([`Layout::FloatingCaliper`]):
/// `tiny-caliper` (9,238 nodes), `small-caliper` (21,476), `medium-caliper`
/// (68,438) and `industrial-caliper` (193,082 nodes, 123,336 elements).
pub const PRESETS: &[&str] = &[
    "tiny",
    "small",
    "medium",
    "industrial",
    "tiny-caliper",
    "small-caliper",
    "medium-caliper",
    "industrial-caliper",
];

/// The default passenger-car brake with the mesh density (and layout) of a named preset.
pub fn preset(name: &str) -> Option<BrakeParams> {
    let (divisions, layout) = match name {
        "tiny" => (Divisions::TINY, Layout::SpringHeld),
        "small" => (Divisions::SMALL, Layout::SpringHeld),
        "medium" => (Divisions::MEDIUM, Layout::SpringHeld),
        "industrial" => (Divisions::INDUSTRIAL, Layout::SpringHeld),
        "tiny-caliper" => (Divisions::TINY_CALIPER, Layout::FloatingCaliper),
        "small-caliper" => (Divisions::SMALL_CALIPER, Layout::FloatingCaliper),
        "medium-caliper" => (Divisions::MEDIUM_CALIPER, Layout::FloatingCaliper),
        "industrial-caliper" => (Divisions::INDUSTRIAL_CALIPER, Layout::FloatingCaliper),
        _ => return None,
    };
    Some(BrakeParams {
        divisions,
        layout,
        ..BrakeParams::default()
    })
}

/// Above this the parameters are surely a typo (and the memory would not be there).
const MAX_NODES: u128 = 20_000_000;
/// Largest division count of any direction.
pub(super) const MAX_DIVISIONS: usize = 100_000;
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
    pub(super) fn overhang_cells(&self) -> usize {
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
        if self.floating_caliper() {
            return self.caliper_counts();
        }
        self.spring_held_counts()
    }

    /// The floating-caliper layout's counts: every block's used refined points, counted on
    /// its grid, unless a bound on them is already over the limit (then that bound).
    fn caliper_counts(&self) -> (u128, u128) {
        let (disc_and_pads, _) = self.spring_held_counts();
        let refined = |cells: usize| 2 * cells.min(MAX_DIVISIONS + 1) as u128 + 1;
        let bound = |lines: [&[f64]; 3]| -> u128 {
            lines
                .iter()
                .map(|l| refined(l.len().saturating_sub(1)))
                .product::<u128>()
        };
        let (radii, thetas) = super::caliper::pad_lines(self);
        let d = &self.divisions;
        let pad_theta = thetas.lines.len() - 1 + 2 * self.overhang_cells();
        let pad_layers =
            d.friction_thickness.min(MAX_DIVISIONS) + d.backplate_thickness.min(MAX_DIVISIONS);
        let pad = refined(radii.lines.len() - 1) * refined(pad_theta) * refined(pad_layers);
        let piston = super::caliper::piston(self);
        let caliper = super::caliper::caliper(self);
        let bracket = super::caliper::bracket(self);
        let mut upper = disc_and_pads + 2 * pad;
        upper += bound(piston.grid.lines.each_ref().map(|l| &l[..]));
        for block in [&caliper, &bracket] {
            upper += bound(block.axes.each_ref().map(|l| &l.lines[..]));
        }
        if upper > MAX_NODES {
            return (upper, upper);
        }
        let (grids, _) = super::parts::grids(self);
        grids.iter().fold((0, 0), |(n, e), g| {
            let (gn, ge) = g.count();
            (n + gn as u128, e + ge as u128)
        })
    }

    /// (nodes, elements) of the disc and pads with the spring-held lines.
    fn spring_held_counts(&self) -> (u128, u128) {
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
        if self.floating_caliper() {
            self.validate_caliper()?;
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

impl BrakeParams {
    /// The floating-caliper layout's own checks (after the disc and pads passed theirs).
    fn validate_caliper(&self) -> Result<(), BrakeError> {
        let positive = |name: &'static str, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(BrakeError::NotPositive { name, value })
            }
        };
        for (name, value) in [
            ("piston_outer_radius", self.piston_outer_radius),
            ("piston_inner_radius", self.piston_inner_radius),
            ("piston_length", self.piston_length),
            ("bore_clearance", self.bore_clearance),
            ("chamber_length", self.chamber_length),
            ("caliper_wall", self.caliper_wall),
            ("caliper_back_thickness", self.caliper_back_thickness),
            ("caliper_bridge_thickness", self.caliper_bridge_thickness),
            ("caliper_finger_thickness", self.caliper_finger_thickness),
            ("rim_clearance", self.rim_clearance),
            ("body_clearance", self.body_clearance),
            ("bracket_arm_deg", self.bracket_arm_deg),
            ("bracket_thickness", self.bracket_thickness),
            ("ductile_iron.young", self.ductile_iron.young),
            ("ductile_iron.density", self.ductile_iron.density),
            ("backplate_overhang_deg", self.backplate_overhang_deg),
        ] {
            positive(name, value)?;
        }
        let nu = self.ductile_iron.poisson;
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(BrakeError::Poisson {
                material: "ductile_iron",
                value: nu,
            });
        }
        let inconsistent = |text: String| Err(BrakeError::Inconsistent(text));
        let (r_in, r_out) = (self.piston_inner_radius, self.piston_outer_radius);
        let f = self.frame();
        let (a, b) = f.ring;
        if 2.0 * r_out > self.pad_outer_radius - self.pad_inner_radius
            || r_out / f.rm > 0.5 * self.pad_arc_deg.to_radians()
        {
            return inconsistent(format!(
                "piston_outer_radius ({r_out}) must let the piston stand on the pad (radii {} to {}, \
                 lining arc {} degrees)",
                self.pad_inner_radius, self.pad_outer_radius, self.pad_arc_deg
            ));
        }
        if !(a > r_in * (1.0 + 1e-6) && a < b) {
            return inconsistent(format!(
                "piston_inner_radius ({r_in}) must be below 0.68 piston_outer_radius ({}): the \
                 piston's face must cover the backplate's contact ring",
                0.68 * r_out
            ));
        }
        // Every slave node of the ring faces the piston's annulus: its outer corners inside
        // the outer radius (the inner edge is at distance >= a > r_in).
        let corner = |dr: f64, dt: f64| {
            let (r, t) = (f.rm + dr, dt / f.rm);
            ((r * t.cos() - f.rm).powi(2) + (r * t.sin()).powi(2)).sqrt()
        };
        let far = [(b, b), (-b, b)]
            .iter()
            .map(|&(dr, dt)| corner(dr, dt))
            .fold(0.0, f64::max);
        if far > r_out * (1.0 - 1e-6) {
            return inconsistent(format!(
                "piston_outer_radius ({r_out}) is too small for the backplate's contact ring \
                 (corner at {far} from the axis)"
            ));
        }
        let c = self.caliper_dims();
        let (rb0, rb1) = c.bore_radii;
        let w = self.caliper_wall;
        if rb0 - w > self.pad_inner_radius || rb1 + w < self.pad_outer_radius {
            return inconsistent(format!(
                "the caliper fingers (radii {} to {}) must cover the backplate (radii {} to {}): \
                 raise caliper_wall or piston_outer_radius",
                rb0 - w,
                rb1 + w,
                self.pad_inner_radius,
                self.pad_outer_radius
            ));
        }
        if rb1 + w >= c.bridge.0 || self.pad_outer_radius + self.body_clearance >= c.bridge.0 {
            return inconsistent(format!(
                "the caliper housing (to radius {}) and the bracket abutments (to radius {}) must \
                 stay below the bridges over the disc rim (from radius {}): raise rim_clearance",
                rb1 + w,
                self.pad_outer_radius + self.body_clearance,
                c.bridge.0
            ));
        }
        if c.bore_half_angle + c.wall_angle >= c.half_angle || r_out + self.bore_clearance >= f.rm {
            return inconsistent(format!(
                "the caliper housing (half-angle {:.3} degrees with its walls) must be narrower \
                 than its bridge (half-angle {:.3} degrees): lower caliper_wall or \
                 piston_outer_radius",
                (c.bore_half_angle + c.wall_angle).to_degrees(),
                c.half_angle.to_degrees()
            ));
        }
        if c.z[2] >= c.z[3] {
            return inconsistent(format!(
                "piston_length + chamber_length ({}) must exceed 2 body_clearance ({}): the \
                 caliper housing starts that far behind the backplate",
                self.piston_length + self.chamber_length,
                2.0 * self.body_clearance
            ));
        }
        let k = self.bracket_dims();
        if k.r[0] <= 0.0 {
            return inconsistent(format!(
                "the bracket cross-member (radii {} to {}) must stay off the axis: lower \
                 bracket_thickness or body_clearance",
                k.r[0], k.r[1]
            ));
        }
        if (k.theta[3] - k.theta[0]).to_degrees() >= 300.0 {
            return inconsistent(format!(
                "the bracket spans {:.1} degrees; lower bracket_arm_deg",
                (k.theta[3] - k.theta[0]).to_degrees()
            ));
        }
        for (what, lines) in [
            (
                "caliper",
                super::caliper::caliper(self).axes[1].lines.clone(),
            ),
            (
                "bracket",
                super::caliper::bracket(self).axes[1].lines.clone(),
            ),
        ] {
            let widest = lines.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
            if widest.to_degrees() > MAX_CELL_DEG {
                return inconsistent(format!(
                    "a {what} cell would span {:.3} degrees, more than {MAX_CELL_DEG}; raise \
                     divisions.pad_radial or divisions.pad_circumferential",
                    widest.to_degrees()
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::brake::build;
    use crate::mesh::brake::test_geometry::pad_cells;
    use crate::mesh::MeshError;
    use std::f64::consts::PI;

    #[test]
    fn preset_sizes_are_in_range_and_match_the_count_formula() {
        let ranges = [
            ("tiny", 2_000, 5_000),
            ("small", 15_000, 25_000),
            ("medium", 50_000, 70_000),
            ("industrial", 177_000, 250_000),
            ("tiny-caliper", 2_000, 10_000),
            ("small-caliper", 15_000, 25_000),
            ("medium-caliper", 50_000, 70_000),
            ("industrial-caliper", 177_000, 250_000),
        ];
        assert_eq!(PRESETS, ranges.map(|r| r.0).as_slice());
        for (name, lo, hi) in ranges {
            let p = preset(name).unwrap();
            let n = p.node_count();
            assert!((lo..=hi).contains(&n), "{name}: {n} nodes");
            if name.starts_with("tiny") || name.starts_with("small") {
                let m = build(&p).unwrap();
                assert_eq!(m.nodes.len(), n, "{name}");
                assert_eq!(m.elements.len(), p.element_count(), "{name}");
            }
        }
        assert!(preset("huge").is_none());
        assert_eq!(BrakeParams::default(), preset("small").unwrap());
    }

    #[test]
    fn preset_cells_are_moderately_shaped_and_the_pads_not_coarser_than_the_disc() {
        for &name in PRESETS {
            let p = preset(name).unwrap();
            if p.floating_caliper() {
                // Its pad lines are not uniform: `caliper::tests` checks every cell.
                continue;
            }
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
}
