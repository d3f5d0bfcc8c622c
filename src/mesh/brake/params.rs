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
}
