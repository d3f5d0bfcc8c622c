//! The floating-caliper layout ([`Layout::FloatingCaliper`]): the piston, the caliper body and
//! the bracket as meshed elastic bodies, and the pad lines that give the inboard backplate a
//! contact ring under the piston.
//!
//! Section through the pad centre (r to the right, z up, not to scale; the disc and pads as
//! in the module doc of [`super`]):
//!
//! ```text
//!            caliper housing (bore with the piston, bore bottom, back)  bridge
//!          +--------------------------------------------------------+------+
//!          |   +------- bore bottom (hydraulic pressure) -------+   |      |
//!          |   |  chamber                                       |   |      |
//!          |   |  +------ piston bottom (hydraulic pressure) -+ |   |      |
//!          |   |  |  piston (hollow, axis through the pad      | |   |      |
//!          +---+  |  centre, parallel to z)                    | +---+      |
//!  bracket        +------------- piston face -----------------+      |      |
//!  x-member  +--------------------- inboard pad ----------------+    |      |
//!  (mount)   +--------------------------------------------------+    |      |
//!   =========================== disc ==========================      |      |
//!            +--------------------- outboard pad ---------------+    |      |
//!            +--------------------------------------------------+    |      |
//!          +------------------------- fingers --------------------------+------+
//!          +-----------------------------------------------------------------+
//! ```
//!
//! Seen from +z the caliper spans `pad_arc_deg / 2 + backplate_overhang_deg / 2` on either
//! side of the pad centre; the bracket's two arms lie beyond the pads' ears, their abutment
//! faces on the ears' end planes, and reach over the disc rim to the outboard pad; its
//! cross-member joins the arms on the inboard side below the pads (`bracket_mount`, its inner
//! cylindrical face, is bolted to the knuckle).
//!
//! Shapes, chosen so that every body is one structured block (conforming, well-shaped):
//! - the caliper and the bracket are blocks in the disc's cylindrical coordinates with cells
//!   left out; the caliper's bore is therefore a curved box (radial and theta = const walls)
//!   around the round piston, held by the seal springs the study adds (`piston_outer` to
//!   `caliper_bore`), and its bore bottom is that box's floor;
//! - the piston is a thick-walled tube in its own cylindrical coordinates (a hollow cylinder:
//!   the map stays off its axis). Its front face is an annulus, and every slave node of a
//!   node-to-surface pair must face the master surface, so the inboard backplate's lines
//!   place a square ring of cells (`backplate_inboard_piston_ring`, half-sides `a` < `b`
//!   about the pad centre) inside that annulus.
//!
//! Every interface where bodies touch (pad/piston, pad/fingers, pad ears/abutments) has
//! bit-identical planes and non-matching nodes; bodies that do not touch are `body_clearance`
//! or `rim_clearance` apart.

use std::f64::consts::PI;
use std::ops::Range;

use super::params::{BrakeParams, Layout};
use crate::mesh::structured::Grid;

/// Cells no longer than `h` over `length` (at least one; a non-finite ratio gives one).
pub(super) fn cells(length: f64, h: f64) -> usize {
    let n = (length / h * (1.0 - 1e-12)).ceil();
    if n.is_finite() && n >= 1.0 {
        (n as usize).min(super::params::MAX_DIVISIONS)
    } else {
        1
    }
}

/// Grid lines through given break points, each segment cut into equal cells.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Lines {
    pub(super) lines: Vec<f64>,
    /// The cells of each segment.
    pub(super) segments: Vec<Range<usize>>,
}

impl Lines {
    /// `breaks` increasing; `counts[i]` cells between breaks i and i + 1. The breaks are
    /// lines exactly (no round-off), so that touching bodies share bit-identical planes.
    pub(super) fn new(breaks: &[f64], counts: &[usize]) -> Lines {
        let mut lines = vec![breaks[0]];
        let mut segments = Vec::with_capacity(counts.len());
        for (k, &n) in counts.iter().enumerate() {
            let (a, b) = (breaks[k], breaks[k + 1]);
            let first = lines.len() - 1;
            for i in 1..n {
                lines.push(a + (b - a) * (i as f64 / n as f64));
            }
            lines.push(b);
            segments.push(first..first + n);
        }
        Lines { lines, segments }
    }

    /// Lines through `breaks`, each segment cut into cells no longer than `h` where a
    /// parameter step `dp` is `scale * dp` long.
    fn sized(breaks: &[f64], h: f64, scale: impl Fn(usize) -> f64) -> Lines {
        let counts: Vec<usize> = breaks
            .windows(2)
            .enumerate()
            .map(|(k, w)| cells((w[1] - w[0]) * scale(k), h))
            .collect();
        Lines::new(breaks, &counts)
    }

    /// The segment of a cell.
    pub(super) fn segment(&self, cell: usize) -> usize {
        self.segments
            .iter()
            .position(|s| s.contains(&cell))
            .unwrap_or(self.segments.len())
    }

    /// Index of the line at break `k`.
    pub(super) fn line(&self, k: usize) -> usize {
        if k == 0 {
            0
        } else {
            self.segments[k - 1].end
        }
    }
}

/// The dimensions every body of the layout is placed by, derived from the parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Frame {
    /// Mean pad radius and pad centre angle (rad): the piston axis.
    pub(super) rm: f64,
    pub(super) centre: f64,
    /// Inboard backplate back face (the outboard one is at -z_back) and disc face.
    pub(super) z_back: f64,
    pub(super) z_disc: f64,
    /// Half-sides of the backplate's contact ring under the piston (inner, outer), m.
    pub(super) ring: (f64, f64),
    /// The pads' ends (the ears' end planes), rad.
    pub(super) pad_ends: (f64, f64),
    /// Target cell size of the layout's bodies, m.
    pub(super) h: f64,
}

impl BrakeParams {
    pub(super) fn frame(&self) -> Frame {
        let rm = 0.5 * (self.pad_inner_radius + self.pad_outer_radius);
        let centre = self.pad_centre_deg.to_radians();
        let half_arc = 0.5 * self.pad_arc_deg.to_radians();
        let ear = self.backplate_overhang_deg.to_radians();
        let z_disc = 0.5 * self.disc_thickness;
        let z_back = z_disc + self.pad_gap + self.friction_thickness + self.backplate_thickness;
        // The ring's outer corners at b sqrt 2 (plus the arcs' bulge) stay inside the
        // piston's outer radius, its inner edge a quarter of the way out from the bore.
        let b = 0.68 * self.piston_outer_radius;
        let a = self.piston_inner_radius + 0.25 * (b - self.piston_inner_radius);
        let d = &self.divisions;
        let h_radial = (self.pad_outer_radius - self.pad_inner_radius) / d.pad_radial as f64;
        let h_arc = rm * self.pad_arc_deg.to_radians() / d.pad_circumferential as f64;
        // Exactly the expressions of the pad's theta lines (bit-identical ear planes).
        let pad_ends = if self.overhang_cells() > 0 {
            (centre - half_arc - ear, centre + half_arc + ear)
        } else {
            (centre - half_arc, centre + half_arc)
        };
        Frame {
            rm,
            centre,
            z_back,
            z_disc,
            ring: (a, b),
            pad_ends,
            h: h_radial.min(h_arc),
        }
    }
}

/// The pad's radial lines and the lining's theta lines in the floating-caliper layout: the
/// spring-held lines plus the contact ring's edges, every segment cut into cells no larger
/// than the spring-held ones. Returns (radii, lining thetas); the ring is segments 1..=3 of
/// both but not segment 2 of both.
pub(super) fn pad_lines(p: &BrakeParams) -> (Lines, Lines) {
    let f = p.frame();
    let (a, b) = f.ring;
    let d = &p.divisions;
    // Cells across the ring are b - a wide: the others no wider than 4 times that keep
    // every cell's edge ratio below 5 (the arcs grow by r2 / rm < 1.25 out to the rim).
    let widest = 4.0 * (b - a);
    let h_radial = ((p.pad_outer_radius - p.pad_inner_radius) / d.pad_radial as f64).min(widest);
    let radii = Lines::sized(
        &[
            p.pad_inner_radius,
            f.rm - b,
            f.rm - a,
            f.rm + a,
            f.rm + b,
            p.pad_outer_radius,
        ],
        h_radial,
        |_| 1.0,
    );
    let half_arc = 0.5 * p.pad_arc_deg.to_radians();
    let h_arc = (f.rm * p.pad_arc_deg.to_radians() / d.pad_circumferential as f64).min(widest);
    let (ta, tb) = (a / f.rm, b / f.rm);
    let c = f.centre;
    let thetas = Lines::sized(
        &[c - half_arc, c - tb, c - ta, c + ta, c + tb, c + half_arc],
        h_arc,
        |_| f.rm,
    );
    (radii, thetas)
}

/// The piston: a tube about the axis through (`centre`, z) in local cylindrical coordinates
/// (rho, phi, z), phi periodic.
pub(super) struct PistonGrid {
    pub(super) grid: Grid,
    /// The axis (x, y) and the angle of phi = 0 (the disc's radial direction there).
    pub(super) axis: [f64; 2],
    pub(super) phase: f64,
}

pub(super) fn piston(p: &BrakeParams) -> PistonGrid {
    let f = p.frame();
    let (r_in, r_out) = (p.piston_inner_radius, p.piston_outer_radius);
    let n_phi = cells(2.0 * PI * r_out, f.h).max(12);
    let grid = Grid {
        lines: [
            Lines::new(&[r_in, r_out], &[cells(r_out - r_in, f.h)]).lines,
            Lines::new(&[0.0, 2.0 * PI], &[n_phi]).lines,
            Lines::new(
                &[f.z_back, f.z_back + p.piston_length],
                &[cells(p.piston_length, f.h)],
            )
            .lines,
        ],
        periodic: [false, true, false],
    };
    PistonGrid {
        grid,
        axis: [f.rm * f.centre.cos(), f.rm * f.centre.sin()],
        phase: f.centre,
    }
}

/// A block in the disc's cylindrical coordinates whose cells are kept by segment.
pub(super) struct SegmentedBlock {
    /// Lines per axis (r, theta, z) with their segments.
    pub(super) axes: [Lines; 3],
    /// Keeps a cell by its (r, theta, z) segments.
    pub(super) keep: fn([usize; 3]) -> bool,
}

impl SegmentedBlock {
    pub(super) fn grid(&self) -> Grid {
        Grid {
            lines: self.axes.each_ref().map(|l| l.lines.clone()),
            periodic: [false; 3],
        }
    }

    /// The (r, theta, z) segments of a cell.
    pub(super) fn segments(&self, cell: [usize; 3]) -> [usize; 3] {
        [0, 1, 2].map(|a| self.axes[a].segment(cell[a]))
    }

    pub(super) fn has(&self, cell: [usize; 3]) -> bool {
        (self.keep)(self.segments(cell))
    }
}

/// Dimensions of the caliper body (see [`caliper`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct CaliperDims {
    /// Bore walls: radii and half-angle about the pad centre.
    pub(super) bore_radii: (f64, f64),
    pub(super) bore_half_angle: f64,
    /// Housing side wall as an angle.
    pub(super) wall_angle: f64,
    /// Half-angle of bridge and fingers about the pad centre.
    pub(super) half_angle: f64,
    /// Bridge radii.
    pub(super) bridge: (f64, f64),
    /// Axial planes: finger back, finger face (= -z_back), housing front, bore bottom, back.
    pub(super) z: [f64; 5],
}

impl BrakeParams {
    pub(super) fn caliper_dims(&self) -> CaliperDims {
        let f = self.frame();
        let r_bore = self.piston_outer_radius + self.bore_clearance;
        let ratio = (r_bore / f.rm).min(1.0);
        let bore_bottom = f.z_back + self.piston_length + self.chamber_length;
        let bridge0 = self.disc_outer_radius + self.rim_clearance;
        CaliperDims {
            // The outer wall has twice the clearance: the caliper's lines then miss the pad
            // centre, a node of the pad's grid (non-matching fingers).
            bore_radii: (f.rm - r_bore, f.rm + r_bore + self.bore_clearance),
            bore_half_angle: ratio.asin(),
            wall_angle: self.caliper_wall / f.rm,
            half_angle: 0.5 * (self.pad_arc_deg + self.backplate_overhang_deg).to_radians(),
            bridge: (bridge0, bridge0 + self.caliper_bridge_thickness),
            z: [
                -f.z_back - self.caliper_finger_thickness,
                -f.z_back,
                f.z_back + 2.0 * self.body_clearance,
                bore_bottom,
                bore_bottom + self.caliper_back_thickness,
            ],
        }
    }
}

/// Segments of the caliper block.
/// r: 0 housing wall inside the bore, 1 bore, 2 wall outside the bore, 3 up to the bridge,
/// 4 bridge. theta: 0 bridge only, 1 housing wall, 2 bore, 3 housing wall, 4 bridge only.
/// z: 0 fingers, 1 bridge span, 2 bore, 3 housing back.
fn caliper_keeps([r, t, z]: [usize; 3]) -> bool {
    match z {
        0 => true,
        1 => r == 4,
        _ => r == 4 || ((1..=3).contains(&t) && !(z == 2 && r == 1 && t == 2)),
    }
}

pub(super) fn caliper(p: &BrakeParams) -> SegmentedBlock {
    let f = p.frame();
    let c = p.caliper_dims();
    let (rb0, rb1) = c.bore_radii;
    let w = p.caliper_wall;
    let r_breaks = [rb0 - w, rb0, rb1, rb1 + w, c.bridge.0, c.bridge.1];
    let (beta, wt, gamma) = (c.bore_half_angle, c.wall_angle, c.half_angle);
    let t_breaks = [
        f.centre - gamma,
        f.centre - beta - wt,
        f.centre - beta,
        f.centre + beta,
        f.centre + beta + wt,
        f.centre + gamma,
    ];
    let outer = c.bridge.1;
    SegmentedBlock {
        axes: [
            Lines::sized(&r_breaks, f.h, |_| 1.0),
            Lines::sized(&t_breaks, f.h, |_| outer),
            Lines::sized(&c.z, f.h, |_| 1.0),
        ],
        keep: caliper_keeps,
    }
}

/// Dimensions of the bracket (see [`bracket`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct BracketDims {
    /// Radii: cross-member inside (the mount), abutments from, abutments to, arm bridge from,
    /// arm bridge to.
    pub(super) r: [f64; 5],
    /// Angles: leading arm's far side, the two abutment planes (the pads' ends), trailing
    /// arm's far side.
    pub(super) theta: [f64; 4],
    /// Axial planes: outboard arm back, outboard arm front, inboard arm front, inboard back.
    pub(super) z: [f64; 4],
}

impl BrakeParams {
    pub(super) fn bracket_dims(&self) -> BracketDims {
        let f = self.frame();
        let clear = self.body_clearance;
        let r1 = self.pad_inner_radius - clear;
        let bridge = self.disc_outer_radius + self.rim_clearance;
        let arm = self.bracket_arm_deg.to_radians();
        let (z0, z1) = (f.z_disc + clear, f.z_back + clear);
        BracketDims {
            r: [
                r1 - self.bracket_thickness,
                r1,
                self.pad_outer_radius + clear,
                bridge,
                bridge + self.bracket_thickness,
            ],
            theta: [
                f.pad_ends.0 - arm,
                f.pad_ends.0,
                f.pad_ends.1,
                f.pad_ends.1 + arm,
            ],
            z: [-z1, -z0, z0, z1],
        }
    }
}

/// Segments of the bracket block.
/// r: 0 cross-member, 1 abutments, 2 up to the bridge, 3 arm bridge. theta: 0 leading arm,
/// 1 between the arms, 2 trailing arm. z: 0 outboard, 1 disc, 2 inboard.
fn bracket_keeps([r, t, z]: [usize; 3]) -> bool {
    if t == 1 {
        return z == 2 && r == 0;
    }
    match z {
        0 => r >= 1,
        1 => r == 3,
        _ => true,
    }
}

pub(super) fn bracket(p: &BrakeParams) -> SegmentedBlock {
    let f = p.frame();
    let b = p.bracket_dims();
    let (r_arm, r_mid) = (b.r[4], b.r[1]);
    SegmentedBlock {
        axes: [
            Lines::sized(&b.r, f.h, |_| 1.0),
            Lines::sized(&b.theta, f.h, |k| if k == 1 { r_mid } else { r_arm }),
            Lines::sized(&b.z, f.h, |_| 1.0),
        ],
        keep: bracket_keeps,
    }
}

/// Areas of the discretised piston bottom and bore bottom (parabolic arcs through the mesh
/// nodes, as the pressure loads integrate them), m^2.
pub(super) fn hydraulic_areas(p: &BrakeParams) -> (f64, f64) {
    // Area swept from a centre by the parabolic arc through three equally spaced points of
    // the circle of radius r over the angle h (see the brake's test geometry).
    let fan = |r: f64, h: f64| {
        let (s, c) = (0.5 * h).sin_cos();
        r * r * s * (1.0 + (1.0 - c) / 3.0)
    };
    let piston = piston(p);
    let n_phi = piston.grid.cells()[1];
    let h = 2.0 * PI / n_phi as f64;
    let piston_area =
        n_phi as f64 * (fan(p.piston_outer_radius, h) - fan(p.piston_inner_radius, h));
    let block = caliper(p);
    let (rb0, rb1) = p.caliper_dims().bore_radii;
    let bore = &block.axes[1].segments[2];
    let bore_area: f64 = bore
        .clone()
        .map(|i| {
            let t = &block.axes[1].lines;
            let h = t[i + 1] - t[i];
            fan(rb1, h) - fan(rb0, h)
        })
        .sum();
    (piston_area, bore_area)
}

impl BrakeParams {
    /// Cells per axis (rho, phi, z) of the piston.
    pub(super) fn piston_cells(&self) -> [usize; 3] {
        piston(self).grid.cells()
    }

    /// The pressures on `piston_bottom` and on `caliper_bore_bottom` that make a hydraulic
    /// force of `line_pressure` times the bore's section pi R^2 (R the piston's outer
    /// radius) on each: what the brake fluid exerts on a real piston and caliper. Equal and
    /// opposite forces; the two surfaces' areas differ (a hollow piston, a box bore), so the
    /// pressures do. Only for the floating-caliper layout.
    pub fn hydraulic_pressures(&self, line_pressure: f64) -> (f64, f64) {
        let force = line_pressure * PI * self.piston_outer_radius.powi(2);
        let (piston, bore) = hydraulic_areas(self);
        (force / piston, force / bore)
    }

    /// Whether this is the floating-caliper layout.
    pub fn floating_caliper(&self) -> bool {
        self.layout == Layout::FloatingCaliper
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::brake::parts::{grids, Map, R, THETA, Z};
    use crate::mesh::brake::test_geometry::*;
    use crate::mesh::brake::{build, preset, PRESETS};
    use crate::mesh::Mesh;
    use crate::vector3::{dot, sub};
    use std::collections::HashMap;

    fn caliper_presets() -> impl Iterator<Item = (&'static str, BrakeParams)> {
        PRESETS
            .iter()
            .map(|&name| (name, preset(name).unwrap()))
            .filter(|(_, p)| p.floating_caliper())
    }

    fn tiny_caliper() -> (BrakeParams, Mesh) {
        let p = preset("tiny-caliper").unwrap();
        let m = build(&p).unwrap();
        (p, m)
    }

    /// Every meshed cell of every block of every caliper preset: edge ratio below 5 (cell
    /// sides along r, theta at both radii, z) and no cell over 30 degrees. Positive
    /// Jacobians at the corners and Gauss points are checked by `build` itself, and for
    /// every element of the tiny and small presets at more points here.
    #[test]
    fn every_caliper_layout_cell_is_well_shaped_and_every_element_positive() {
        for (name, p) in caliper_presets() {
            let (blocks, _) = grids(&p);
            for (b, block) in blocks.iter().enumerate() {
                let [lr, lt, lz] = &block.grid.lines;
                let cells = block.grid.cells();
                for i in 0..cells[R] {
                    for j in 0..cells[THETA] {
                        for k in 0..cells[Z] {
                            if block.part([i, j, k]).is_none() {
                                continue;
                            }
                            let dt = lt[j + 1] - lt[j];
                            assert!(dt.to_degrees() <= 30.0 + 1e-9, "{name} block {b}");
                            let dims = [
                                lr[i + 1] - lr[i],
                                lr[i] * dt,
                                lr[i + 1] * dt,
                                lz[k + 1] - lz[k],
                            ];
                            let max = dims.iter().copied().fold(0.0, f64::max);
                            let min = dims.iter().copied().fold(f64::INFINITY, f64::min);
                            assert!(
                                max / min < 5.0,
                                "{name} block {b} cell {:?}: ratio {}",
                                [i, j, k],
                                max / min
                            );
                        }
                    }
                }
            }
            if name.starts_with("tiny") || name.starts_with("small") {
                let m = build(&p).unwrap();
                let (a, c) = (0.5, 1.0 / 6.0);
                for e in 0..m.elements.len() {
                    let x = m.elements[e].map(|n| m.nodes[n]);
                    for l in [
                        [0.25; 4],
                        [a, c, c, c],
                        [c, a, c, c],
                        [c, c, a, c],
                        [c, c, c, a],
                    ] {
                        assert!(
                            crate::mesh::brake::parts::jacobian_det(&x, l) > 0.0,
                            "{name}: element {e}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn piston_caliper_and_bracket_volumes_match_the_true_geometry() {
        for name in ["tiny-caliper", "small-caliper"] {
            let p = preset(name).unwrap();
            let m = build(&p).unwrap();
            let f = p.frame();
            let volume = |part_name: &str| -> f64 {
                part(&m, part_name)
                    .elements
                    .iter()
                    .map(|&e| element_volume(&m, e))
                    .sum()
            };
            let sector = |r0: f64, r1: f64, angle: f64| 0.5 * (r1 * r1 - r0 * r0) * angle;
            let (r_in, r_out) = (p.piston_inner_radius, p.piston_outer_radius);
            let piston = p.piston_length * sector(r_in, r_out, 2.0 * PI);
            let c = p.caliper_dims();
            let (rb0, rb1) = c.bore_radii;
            let w = p.caliper_wall;
            let (r0, r4, r5) = (rb0 - w, c.bridge.0, c.bridge.1);
            let (beta, housing, gamma) = (
                c.bore_half_angle,
                c.bore_half_angle + c.wall_angle,
                c.half_angle,
            );
            let bridge = sector(r4, r5, 2.0 * gamma);
            let z = c.z;
            let caliper = (z[1] - z[0]) * sector(r0, r5, 2.0 * gamma)
                + (z[2] - z[1]) * bridge
                + (z[3] - z[2])
                    * (bridge + sector(r0, r4, 2.0 * housing) - sector(rb0, rb1, 2.0 * beta))
                + (z[4] - z[3]) * (bridge + sector(r0, r4, 2.0 * housing));
            let k = p.bracket_dims();
            let arm = p.bracket_arm_deg.to_radians();
            let level = k.z[3] - k.z[2];
            let bracket = 2.0
                * (level * sector(k.r[1], k.r[4], arm)
                    + (k.z[2] - k.z[1]) * sector(k.r[3], k.r[4], arm)
                    + level * sector(k.r[0], k.r[4], arm))
                + level * sector(k.r[0], k.r[1], k.theta[2] - k.theta[1]);
            for (part_name, exact, widest) in [
                ("piston", piston, 2.0 * PI / p.piston_cells()[1] as f64),
                ("caliper", caliper, f.h / c.bridge.1),
                ("bracket", bracket, 30f64.to_radians()),
            ] {
                let v = volume(part_name);
                // Parabolic arcs inside the circles: (h/2)^4 / 30 of the area at most.
                let chord = (exact - v) / exact;
                let bound = 1.1 * (0.5 * widest).powi(4) / 30.0;
                assert!(
                    chord >= -1e-11 && chord < bound.max(1e-11),
                    "{name} {part_name}: {v} vs {exact} ({chord:e}, bound {bound:e})"
                );
            }
        }
    }

    /// Unit vectors radial and circumferential at angle t.
    fn radial(t: f64) -> [f64; 3] {
        [t.cos(), t.sin(), 0.0]
    }
    fn tangent(t: f64) -> [f64; 3] {
        [-t.sin(), t.cos(), 0.0]
    }

    #[test]
    fn caliper_layout_surfaces_lie_on_their_planes_with_outward_normals_and_full_area() {
        let (p, m) = tiny_caliper();
        let f = p.frame();
        let c = p.caliper_dims();
        let k = p.bracket_dims();
        let axis = [f.rm * f.centre.cos(), f.rm * f.centre.sin(), 0.0];
        let (r_in, r_out) = (p.piston_inner_radius, p.piston_outer_radius);
        let (piston_area, bore_area) = hydraulic_areas(&p);
        let (rb0, rb1) = c.bore_radii;
        let w = p.caliper_wall;
        let flat = [
            ("piston_face", f.z_back, -1.0, Some(piston_area)),
            (
                "piston_bottom",
                f.z_back + p.piston_length,
                1.0,
                Some(piston_area),
            ),
            ("caliper_fingers", -f.z_back, 1.0, None),
            ("caliper_bore_bottom", c.z[3], -1.0, Some(bore_area)),
            ("backplate_inboard_piston_ring", f.z_back, 1.0, None),
        ];
        for (name, z, sign, expected) in flat {
            let s = &m.surfaces[name];
            assert!(!s.faces.is_empty(), "{name}");
            let mut area = 0.0;
            for face in &s.faces {
                assert_eq!(*face, m.face(face.element, face.side), "{name}");
                for &n in &face.nodes {
                    assert_eq!(m.nodes[n][2], z, "{name}: node {n} off the plane");
                }
                area += flat_face_area(&m, face, [0.0, 0.0, sign]);
            }
            if let Some(expected) = expected {
                assert!(
                    (area - expected).abs() < 1e-12 * expected,
                    "{name}: {area} vs {expected}"
                );
            }
            assert_eq!(m.node_sets[name], m.surface_nodes(s), "{name}");
        }
        // The fingers: the true sector less the parabolic arcs' bulge.
        let exact = 0.5 * ((rb1 + w).powi(2) - (rb0 - w).powi(2)) * 2.0 * c.half_angle;
        let area: f64 = m.surfaces["caliper_fingers"]
            .faces
            .iter()
            .map(|face| flat_face_area(&m, face, [0.0, 0.0, 1.0]))
            .sum();
        assert!(
            area < exact && area > exact * (1.0 - 1e-4),
            "{area} vs {exact}"
        );
        // The ring: every node faces the piston's annulus.
        for &n in &m.node_sets["backplate_inboard_piston_ring"] {
            let d = sub(m.nodes[n], axis);
            let rho = d[0].hypot(d[1]);
            assert!(rho > r_in && rho < r_out, "ring node {n} at {rho}");
        }
        // The piston's outer cylinder, outward.
        for face in &m.surfaces["piston_outer"].faces {
            for &n in &face.nodes {
                let d = sub(m.nodes[n], axis);
                assert!((d[0].hypot(d[1]) - r_out).abs() < 1e-15, "node {n}");
            }
            let (x, normal) = face_point(&m, face, 1.0 / 3.0, 1.0 / 3.0);
            assert!(dot(normal, sub(x, axis)) > 0.0);
        }
        // The bore: four walls around the piston, normals into the bore (towards its
        // centre line).
        for face in &m.surfaces["caliper_bore"].faces {
            let (x, normal) = face_point(&m, face, 1.0 / 3.0, 1.0 / 3.0);
            assert!(dot(normal, sub(axis, [x[0], x[1], 0.0])) > 0.0);
            assert!(x[2] >= c.z[2] && x[2] <= c.z[3]);
        }
        // Abutments on the pads' end planes, facing the pads, covering the ears.
        let abutment_area = (k.r[2] - k.r[1]) * (k.z[3] - k.z[2]);
        for (side, zs) in [("inboard", 1.0), ("outboard", -1.0)] {
            for (end, t, out) in [
                ("leading", f.pad_ends.0, 1.0),
                ("trailing", f.pad_ends.1, -1.0),
            ] {
                let name = format!("bracket_{side}_{end}");
                let mut area = 0.0;
                for face in &m.surfaces[&name].faces {
                    for &n in &face.nodes {
                        let x = m.nodes[n];
                        assert!(dot(x, tangent(t)).abs() < 1e-15, "{name}: node {n}");
                        assert!(zs * x[2] >= k.z[2] && zs * x[2] <= k.z[3], "{name}");
                    }
                    area += flat_face_area(&m, face, tangent(t).map(|v| out * v));
                }
                assert!(
                    (area - abutment_area).abs() < 1e-12 * abutment_area,
                    "{name}: {area} vs {abutment_area}"
                );
                for &n in &m.node_sets[&format!("pad_{side}_abutment_{end}")] {
                    let x = m.nodes[n];
                    let r = dot(x, radial(t));
                    assert!(r > k.r[1] && r < k.r[2] && zs * x[2] > k.z[2] && zs * x[2] < k.z[3]);
                }
            }
        }
        // Node sets: the mount on the cross-member's inner cylinder, the pins on the
        // caliper bridge's ends and on the bracket arms facing them.
        for &n in &m.node_sets["bracket_mount"] {
            let x = m.nodes[n];
            assert!((x[0].hypot(x[1]) - k.r[0]).abs() < 1e-15);
        }
        for (set, low, high, radii) in [
            (
                "caliper_pins",
                f.centre - c.half_angle,
                f.centre + c.half_angle,
                c.bridge,
            ),
            ("bracket_pins", f.pad_ends.0, f.pad_ends.1, (k.r[3], k.r[4])),
        ] {
            let nodes = &m.node_sets[set];
            assert!(!nodes.is_empty(), "{set}");
            for &n in nodes {
                let x = m.nodes[n];
                let on = |t: f64| dot(x, tangent(t)).abs() < 1e-15;
                assert!(on(low) || on(high), "{set}: node {n}");
                let r = x[0].hypot(x[1]);
                assert!(
                    r >= radii.0 - 1e-15 && r <= radii.1 + 1e-15,
                    "{set}: node {n}"
                );
            }
        }
        // The outboard backplate's back face lies on the fingers.
        for &n in &m.node_sets["backplate_outboard_caliper"] {
            let x = m.nodes[n];
            let (r, t) = (x[0].hypot(x[1]), x[1].atan2(x[0]) - f.centre);
            assert!(r > rb0 - w && r < rb1 + w && t.abs() < c.half_angle);
        }
        let expected_sets = [
            "backplate_inboard_piston",
            "backplate_inboard_piston_ring",
            "backplate_outboard_caliper",
            "bracket_inboard_leading",
            "bracket_inboard_trailing",
            "bracket_mount",
            "bracket_outboard_leading",
            "bracket_outboard_trailing",
            "bracket_pins",
            "caliper_bore",
            "caliper_bore_bottom",
            "caliper_fingers",
            "caliper_pins",
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
            "piston_bottom",
            "piston_face",
            "piston_outer",
        ];
        assert_eq!(
            m.node_sets.keys().map(String::as_str).collect::<Vec<_>>(),
            expected_sets
        );
        assert_eq!(m.surfaces.len(), expected_sets.len() - 6);
        let parts: Vec<(&str, &str)> = m
            .parts
            .iter()
            .map(|p| (p.name.as_str(), p.material.as_deref().unwrap()))
            .collect();
        assert_eq!(
            &parts[5..],
            [
                ("piston", "steel"),
                ("caliper", "ductile_iron"),
                ("bracket", "ductile_iron")
            ]
        );
        assert_eq!(m.materials["ductile_iron"].young, p.ductile_iron.young);
        // Clockwise swaps leading and trailing.
        let cw = build(&BrakeParams {
            rotation: crate::mesh::brake::Rotation::Clockwise,
            ..p.clone()
        })
        .unwrap();
        for side in ["inboard", "outboard"] {
            let lead = format!("bracket_{side}_leading");
            let trail = format!("bracket_{side}_trailing");
            assert_eq!(cw.surfaces[&lead].faces, m.surfaces[&trail].faces);
        }
    }

    /// Nodes of `a` on nodes of `b` (closer than 1e-9 m), by hashing positions to a grid.
    fn shared_nodes(m: &Mesh, a: &[usize], b: &[usize]) -> usize {
        let key = |x: [f64; 3]| x.map(|v| (v / 1e-6).floor() as i64);
        let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for &n in b {
            grid.entry(key(m.nodes[n])).or_default().push(n);
        }
        a.iter()
            .filter(|&&n| {
                let k = key(m.nodes[n]);
                (-1..=1).any(|i| {
                    (-1..=1).any(|j| {
                        (-1..=1).any(|l| {
                            grid.get(&[k[0] + i, k[1] + j, k[2] + l])
                                .into_iter()
                                .flatten()
                                .any(|&q| {
                                    let d = sub(m.nodes[n], m.nodes[q]);
                                    dot(d, d).sqrt() < 1e-9
                                })
                        })
                    })
                })
            })
            .count()
    }

    /// Every contact interface of every caliper preset: no slave node on a master node.
    #[test]
    fn no_caliper_preset_has_matching_nodes_at_an_interface() {
        for (name, p) in caliper_presets() {
            let m = build(&p).unwrap();
            let mut pairs = vec![
                ("backplate_inboard_piston_ring", "piston_face".to_string()),
                ("backplate_outboard_caliper", "caliper_fingers".to_string()),
                ("pad_inboard_friction_face", "disc_inboard_face".to_string()),
                (
                    "pad_outboard_friction_face",
                    "disc_outboard_face".to_string(),
                ),
            ];
            for side in ["inboard", "outboard"] {
                for end in ["leading", "trailing"] {
                    let slave: &'static str = match (side, end) {
                        ("inboard", "leading") => "pad_inboard_abutment_leading",
                        ("inboard", _) => "pad_inboard_abutment_trailing",
                        (_, "leading") => "pad_outboard_abutment_leading",
                        _ => "pad_outboard_abutment_trailing",
                    };
                    pairs.push((slave, format!("bracket_{side}_{end}")));
                }
            }
            for (slave, master) in &pairs {
                let shared = shared_nodes(&m, &m.node_sets[*slave], &m.node_sets[master]);
                assert_eq!(shared, 0, "{name}: {slave} on {master}");
            }
        }
    }

    #[test]
    fn the_hydraulic_pressures_give_equal_and_opposite_forces() {
        let (p, m) = tiny_caliper();
        let (on_piston, on_bore) = p.hydraulic_pressures(2e6);
        let force = 2e6 * PI * p.piston_outer_radius.powi(2);
        let resultant = |name: &str, value: f64| {
            crate::fem::loads::pressure_resultant(&m, &m.surfaces[name].faces, value)
        };
        let piston = resultant("piston_bottom", on_piston);
        let bore = resultant("caliper_bore_bottom", on_bore);
        assert!(
            (piston[2] + force).abs() < 1e-12 * force,
            "{piston:?} vs {force}"
        );
        assert!(
            (bore[2] - force).abs() < 1e-12 * force,
            "{bore:?} vs {force}"
        );
        assert!(piston[0].abs().max(piston[1].abs()) < 1e-12 * force);
        assert!(bore[0].abs().max(bore[1].abs()) < 1e-12 * force);
    }

    #[test]
    fn bad_caliper_parameters_are_named() {
        let good = preset("tiny-caliper").unwrap();
        let check = |p: BrakeParams, expect: &str| {
            let text = match build(&p) {
                Ok(_) => panic!("accepted, expected an error naming {expect:?}"),
                Err(e) => e.to_string(),
            };
            assert!(text.contains(expect), "{text:?} lacks {expect:?}");
        };
        let with = |f: &dyn Fn(&mut BrakeParams)| {
            let mut p = good.clone();
            f(&mut p);
            p
        };
        check(with(&|p| p.piston_length = 0.0), "`piston_length`");
        check(with(&|p| p.caliper_wall = f64::NAN), "`caliper_wall`");
        check(with(&|p| p.bracket_arm_deg = -3.0), "`bracket_arm_deg`");
        check(with(&|p| p.body_clearance = 0.0), "`body_clearance`");
        check(with(&|p| p.ductile_iron.poisson = 0.6), "`ductile_iron`");
        check(
            with(&|p| p.ductile_iron.young = 0.0),
            "`ductile_iron.young`",
        );
        check(
            with(&|p| p.backplate_overhang_deg = 0.0),
            "`backplate_overhang_deg`",
        );
        check(
            with(&|p| p.piston_outer_radius = 0.03),
            "piston_outer_radius",
        );
        check(
            with(&|p| p.piston_inner_radius = 0.015),
            "piston_inner_radius",
        );
        check(with(&|p| p.caliper_wall = 0.001), "caliper_wall");
        check(with(&|p| p.caliper_wall = 0.012), "rim_clearance");
        check(with(&|p| p.bracket_arm_deg = 140.0), "bracket_arm_deg");
        check(with(&|p| p.bracket_thickness = 0.2), "bracket_thickness");
        // The spring-held layout ignores them.
        let mut spring_held = with(&|p| p.piston_length = -1.0);
        spring_held.layout = Layout::SpringHeld;
        assert!(build(&spring_held).is_ok());
    }

    #[test]
    fn the_layout_reads_in_kebab_or_snake_case() {
        let p: BrakeParams = serde_json::from_str(r#"{"layout": "floating-caliper"}"#).unwrap();
        assert!(p.floating_caliper());
        let p: BrakeParams = serde_json::from_str(r#"{"layout": "floating_caliper"}"#).unwrap();
        assert!(p.floating_caliper());
        let p: BrakeParams = serde_json::from_str(r#"{"layout": "spring-held"}"#).unwrap();
        assert_eq!(p, BrakeParams::default());
        assert!(serde_json::from_str::<BrakeParams>(r#"{"layout": "fixed"}"#).is_err());
        assert!(serde_json::from_str::<BrakeParams>(r#"{"piston_lenght": 0.03}"#).is_err());
        let p = preset("small-caliper").unwrap();
        let back: BrakeParams = serde_json::from_str(&serde_json::to_string(&p).unwrap()).unwrap();
        assert_eq!(back, p);
        assert!(matches!(grids(&p).0[PISTON_BLOCK].map, Map::Local { .. }));
    }

    const PISTON_BLOCK: usize = 3;
}
