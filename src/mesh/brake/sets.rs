//! The brake's named node sets and surfaces: where the study applies supports, springs,
//! piston and caliper loads, and contact. Each is picked by grid plane from the structured
//! blocks (not by coordinates, so no tolerance is involved), as the outward faces of one part.

use std::ops::Range;

use super::caliper;
use super::params::{BrakeParams, Rotation};
use super::parts::{
    MeshedParts, BRACKET, CALIPER, DISC, INBOARD_BACKPLATE, INBOARD_FRICTION, OUTBOARD_BACKPLATE,
    OUTBOARD_FRICTION, PISTON, R, THETA, Z,
};
use crate::mesh::structured::{Meshed, Origin};
use crate::mesh::{Face, Mesh, Surface};

/// Adds the surfaces (each also a node set of the same name) and the node sets that are no
/// surface (the disc hub, the pad guides) to the mesh of the parts.
pub(super) fn add(mesh: &mut Mesh, params: &BrakeParams, meshed: &MeshedParts) {
    let (disc, pad_in, pad_out) = (&meshed.blocks[0], &meshed.blocks[1], &meshed.blocks[2]);
    let (disc_cells, pad_cells) = (meshed.disc_cells, meshed.pad_cells);
    let (theta_min, theta_max) = (0, pad_cells[THETA]);
    let (leading, trailing) = match params.rotation {
        Rotation::CounterClockwise => (theta_min, theta_max),
        Rotation::Clockwise => (theta_max, theta_min),
    };
    let pad_top = pad_cells[Z];
    let lining = &meshed.lining;
    let all_pad = 0..pad_cells[THETA];
    let all_disc = 0..disc_cells[THETA];
    // The outward faces of `part` on grid plane `line` of `axis`, in the theta cells given.
    let pick = |mesh: &Mesh,
                block: &Meshed<usize>,
                part: usize,
                axis: usize,
                line: usize,
                theta_cells: &Range<usize>|
     -> Vec<Face> {
        block.faces_on(mesh, axis, line, |origin| {
            origin.tag == part && theta_cells.contains(&origin.cell[THETA])
        })
    };
    let surfaces = [
        (
            "disc_inboard_face",
            pick(mesh, disc, DISC, Z, disc_cells[Z], &all_disc),
        ),
        (
            "disc_outboard_face",
            pick(mesh, disc, DISC, Z, 0, &all_disc),
        ),
        (
            "pad_inboard_friction_face",
            pick(mesh, pad_in, INBOARD_FRICTION, Z, 0, lining),
        ),
        (
            "pad_outboard_friction_face",
            pick(mesh, pad_out, OUTBOARD_FRICTION, Z, pad_top, lining),
        ),
        (
            "backplate_inboard_piston",
            pick(mesh, pad_in, INBOARD_BACKPLATE, Z, pad_top, lining),
        ),
        (
            "backplate_outboard_caliper",
            pick(mesh, pad_out, OUTBOARD_BACKPLATE, Z, 0, lining),
        ),
        (
            "pad_inboard_abutment_leading",
            pick(mesh, pad_in, INBOARD_BACKPLATE, THETA, leading, &all_pad),
        ),
        (
            "pad_inboard_abutment_trailing",
            pick(mesh, pad_in, INBOARD_BACKPLATE, THETA, trailing, &all_pad),
        ),
        (
            "pad_outboard_abutment_leading",
            pick(mesh, pad_out, OUTBOARD_BACKPLATE, THETA, leading, &all_pad),
        ),
        (
            "pad_outboard_abutment_trailing",
            pick(mesh, pad_out, OUTBOARD_BACKPLATE, THETA, trailing, &all_pad),
        ),
    ];
    let mut surfaces = surfaces.to_vec();
    let mut node_sets = vec![];
    if params.floating_caliper() {
        let (more_surfaces, more_sets) = caliper_sets(mesh, params, meshed);
        surfaces.extend(more_surfaces);
        node_sets.extend(more_sets);
    }
    let spring_held_sets = [
        ("disc_hub", pick(mesh, disc, DISC, R, 0, &all_disc)),
        (
            "pad_inboard_guides",
            pick(mesh, pad_in, INBOARD_BACKPLATE, R, pad_cells[R], &all_pad),
        ),
        (
            "pad_outboard_guides",
            pick(mesh, pad_out, OUTBOARD_BACKPLATE, R, pad_cells[R], &all_pad),
        ),
    ];
    node_sets.extend(spring_held_sets);
    for (name, faces) in surfaces {
        let surface = Surface {
            name: name.to_string(),
            faces,
        };
        mesh.node_sets
            .insert(name.to_string(), mesh.surface_nodes(&surface));
        mesh.surfaces.insert(name.to_string(), surface);
    }
    for (name, faces) in node_sets {
        let faces = Surface {
            name: name.to_string(),
            faces,
        };
        mesh.node_sets
            .insert(name.to_string(), mesh.surface_nodes(&faces));
    }
}

type Named = (&'static str, Vec<Face>);

/// The floating-caliper layout's surfaces and node sets (see [`super::caliper`]), picked by
/// the segments of each block's lines.
fn caliper_sets(
    mesh: &Mesh,
    params: &BrakeParams,
    meshed: &MeshedParts,
) -> (Vec<Named>, Vec<Named>) {
    let (pad_in, piston, caliper_mesh, bracket_mesh) = (
        &meshed.blocks[1],
        &meshed.blocks[PISTON - 2],
        &meshed.blocks[CALIPER - 2],
        &meshed.blocks[BRACKET - 2],
    );
    // The backplate's contact ring: radial and lining segments 1..=3 but not both 2.
    let (radii, thetas) = caliper::pad_lines(params);
    let o = meshed.lining.start;
    let pad_top = meshed.pad_cells[Z];
    let ring = pad_in.faces_on(mesh, Z, pad_top, |origin| {
        let [r, t] = [radii.segment(origin.cell[R]), {
            let t = origin.cell[THETA];
            if t < o {
                usize::MAX
            } else {
                thetas.segment(t - o)
            }
        }];
        origin.tag == INBOARD_BACKPLATE
            && (1..=3).contains(&r)
            && (1..=3).contains(&t)
            && !(r == 2 && t == 2)
    });
    let piston_cells = params.piston_cells();
    let all = |_: &Origin<usize>| true;
    let piston_face = piston.faces_on(mesh, Z, 0, all);
    let piston_bottom = piston.faces_on(mesh, Z, piston_cells[Z], all);
    let piston_outer = piston.faces_on(mesh, R, piston_cells[R], all);

    let block = caliper::caliper(params);
    let seg = |origin: &Origin<usize>| block.segments(origin.cell);
    let line = |axis: usize, k: usize| block.axes[axis].line(k);
    let on = |axis: usize, k: usize, keep: &dyn Fn([usize; 3]) -> bool| {
        caliper_mesh.faces_on(mesh, axis, line(axis, k), |o| keep(seg(o)))
    };
    let fingers = on(Z, 1, &|[r, _, z]| z == 0 && r <= 2);
    let bore_bottom = on(Z, 3, &|[r, t, z]| z == 3 && r == 1 && t == 2);
    let mut bore = on(R, 1, &|[r, t, z]| z == 2 && r == 0 && t == 2);
    bore.extend(on(R, 2, &|[r, t, z]| z == 2 && r == 2 && t == 2));
    bore.extend(on(THETA, 2, &|[r, t, z]| z == 2 && r == 1 && t == 1));
    bore.extend(on(THETA, 3, &|[r, t, z]| z == 2 && r == 1 && t == 3));
    let mut caliper_pins = on(THETA, 0, &|[r, t, z]| z == 1 && r == 4 && t == 0);
    caliper_pins.extend(on(THETA, 5, &|[r, t, z]| z == 1 && r == 4 && t == 4));

    let block = caliper::bracket(params);
    let seg = |origin: &Origin<usize>| block.segments(origin.cell);
    let line = |axis: usize, k: usize| block.axes[axis].line(k);
    let on = |axis: usize, k: usize, keep: &dyn Fn([usize; 3]) -> bool| {
        bracket_mesh.faces_on(mesh, axis, line(axis, k), |o| keep(seg(o)))
    };
    // The abutment planes are the pads' end planes: theta break 1 (low end) faces the
    // pads' low-theta ears, break 2 the high-theta ones.
    let abutment = |low: bool, z_seg: usize| {
        if low {
            on(THETA, 1, &|[r, t, z]| z == z_seg && r == 1 && t == 0)
        } else {
            on(THETA, 2, &|[r, t, z]| z == z_seg && r == 1 && t == 2)
        }
    };
    let ccw = params.rotation == Rotation::CounterClockwise;
    let mut bracket_pins = on(THETA, 1, &|[r, t, _]| r == 3 && t == 0);
    bracket_pins.extend(on(THETA, 2, &|[r, t, _]| r == 3 && t == 2));
    let mount = on(R, 0, &|[r, _, _]| r == 0);
    let surfaces = vec![
        ("backplate_inboard_piston_ring", ring),
        ("piston_face", piston_face),
        ("piston_bottom", piston_bottom),
        ("piston_outer", piston_outer),
        ("caliper_fingers", fingers),
        ("caliper_bore_bottom", bore_bottom),
        ("caliper_bore", bore),
        ("bracket_inboard_leading", abutment(ccw, 2)),
        ("bracket_inboard_trailing", abutment(!ccw, 2)),
        ("bracket_outboard_leading", abutment(ccw, 0)),
        ("bracket_outboard_trailing", abutment(!ccw, 0)),
    ];
    let node_sets = vec![
        ("caliper_pins", caliper_pins),
        ("bracket_pins", bracket_pins),
        ("bracket_mount", mount),
    ];
    (surfaces, node_sets)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::brake::build;
    use crate::mesh::brake::test_geometry::*;
    use crate::vector3::dot;
    use std::f64::consts::PI;

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
}
