//! A deck's supports, prescribed displacements, concentrated loads, `*EQUATION`s and
//! distributing couplings as the model's supports, forces and linear constraints.
//!
//! - A support at zero in a global direction stays an eliminated DOF ([`Support`]), as
//!   before; a nonzero prescribed displacement is a constraint `u = value` (grown with the
//!   load in a static, held at zero perturbation in modes and CEA).
//! - At a node with a `*TRANSFORM`, supports, prescribed displacements and `*CLOAD`s are in
//!   its local directions: a support becomes `e_i . u = value`, a force `value e_i`.
//! - An `*EQUATION` is `sum_k a_k u_k = 0` with its first term's DOF dependent (local
//!   directions at transformed nodes).
//! - A `*COUPLING` + `*DISTRIBUTING` ties the reference node's translations to its cloud
//!   with the reduction layer's weights ([`crate::fem::distributing`]) times the nodes'
//!   tributary areas (element-based surfaces, as Abaqus), by Abaqus's rigid-placement law
//!   ([`crate::fem::distributing::reference_motion`]).

use std::collections::BTreeMap;

use super::ModelError;
use crate::contact;
use crate::fem::constraints::{LinearConstraint, Pivot};
use crate::fem::distributing::{self, CloudError, Radius, Weighting};
use crate::fem::Support;
use crate::io::abaqus::{
    Boundary, Deck, DeckCoupling, DeckTransform, DistributingWeighting, Loading, SourceLine,
    SpringEnds,
};

/// What a deck's loading in force makes of the model's supports, forces and constraints.
pub(super) struct DeckConditions {
    pub(super) supports: Vec<Support>,
    pub(super) forces: Vec<(usize, usize, f64)>,
    pub(super) constraints: Vec<LinearConstraint>,
}

fn at(source: &SourceLine, why: String) -> ModelError {
    ModelError::AtLine {
        at: source.clone(),
        why,
    }
}

/// The deck's conditions for the loading in force in step `step` (`None`: model data).
pub(super) fn conditions(
    deck: &Deck,
    loading: &Loading,
    step: Option<usize>,
) -> Result<DeckConditions, ModelError> {
    let mesh = &deck.mesh;
    let label = |n: usize| mesh.node_labels[n];
    let transform_of: BTreeMap<usize, &DeckTransform> = deck
        .transforms
        .iter()
        .flat_map(|t| t.nodes.iter().map(move |&n| (n, t)))
        .collect();
    // Where each DOF's support or prescribed value was said (the last definition in force).
    let mut said: BTreeMap<(usize, usize), &Boundary> = BTreeMap::new();
    let in_force: Vec<&[Boundary]> = std::iter::once(&deck.boundaries[..])
        .chain(
            deck.steps
                .iter()
                .enumerate()
                .filter(|(k, s)| step.is_some_and(|t| (*k < t && !s.perturbation) || *k == t))
                .map(|(_, s)| &s.boundaries[..]),
        )
        .collect();
    for boundaries in in_force {
        for b in boundaries {
            for &n in &b.nodes {
                for dof in b.first_dof..=b.last_dof {
                    said.insert((n, usize::from(dof) - 1), b);
                }
            }
        }
    }
    let axes = |n: usize, source: &SourceLine| -> Result<Option<[[f64; 3]; 3]>, ModelError> {
        let Some(t) = transform_of.get(&n) else {
            return Ok(None);
        };
        t.axes(mesh.nodes[n]).map(Some).ok_or_else(|| {
            at(
                source,
                format!(
                    "node {} lies on the axis of the cylindrical *TRANSFORM at {}, where the \
                     radial and tangential directions do not exist: hold it in global \
                     directions (leave it out of the transform's node set)",
                    label(n),
                    t.source
                ),
            )
        })
    };
    let mut held: BTreeMap<usize, [bool; 3]> = BTreeMap::new();
    // Eliminated in this order: prescribed displacements, equations, couplings. A prescribed
    // value on an equation's dependent DOF is then refused, as Abaqus refuses it; one on a
    // coupling's reference node drives it (the coupling eliminates a cloud DOF instead).
    let mut prescribed = Vec::new();
    let mut ties = Vec::new();
    for e in &deck.equations {
        let mut terms = Vec::new();
        for t in &e.terms {
            let c = usize::from(t.dof) - 1;
            match axes(t.node, &e.source)? {
                None => terms.push((t.node, c, t.coefficient)),
                Some(a) => terms.extend(
                    (0..3)
                        .filter(|&k| a[c][k] != 0.0)
                        .map(|k| (t.node, k, t.coefficient * a[c][k])),
                ),
            }
        }
        let first = e.terms[0];
        let pivot = match transform_of.contains_key(&first.node) {
            false => Pivot::Fixed((first.node, usize::from(first.dof) - 1)),
            true => Pivot::Node(first.node),
        };
        ties.push(LinearConstraint {
            terms,
            value: 0.0,
            pivot,
            source: format!("{} (*EQUATION)", e.source),
        });
    }
    for c in &deck.couplings {
        ties.extend(coupling(deck, c)?);
    }
    // Springs whose DOFs a transform would turn: Abaqus reads them in the local system.
    for s in &deck.springs {
        let nodes: Vec<usize> = match s.ends {
            SpringEnds::Ground(n) => vec![n],
            SpringEnds::Nodes(n) => n.to_vec(),
        };
        if s.element_type != "SPRINGA" {
            if let Some(&n) = nodes.iter().find(|n| transform_of.contains_key(n)) {
                return Err(at(
                    &s.source,
                    format!(
                        "{} element {}: its node {} has the *TRANSFORM at {}, which would turn \
                         the spring's DOFs; squeal's SPRING1 and SPRING2 act along global \
                         directions (use a SPRINGA, or leave the node out of the transform)",
                        s.element_type,
                        s.label,
                        label(n),
                        transform_of[&n].source
                    ),
                ));
            }
        }
    }
    for (&(n, c), &value) in &loading.displacements {
        let source = said
            .get(&(n, c))
            .map(|b| b.source.clone())
            .unwrap_or(SourceLine {
                file: deck_file(deck),
                line: 0,
            });
        if let Some(&k) = loading.fixed.get(&(n, c)) {
            if let Some(earlier) = deck.steps[..k].iter().position(|s| !s.perturbation) {
                return Err(at(
                    &source,
                    format!(
                        "*BOUNDARY, FIXED holds node {} DOF {} at the displacement step {} ends \
                         with; squeal solves a deck's general steps as one static (their loads \
                         together), so that displacement is not known here: give the value",
                        label(n),
                        c + 1,
                        earlier + 1
                    ),
                ));
            }
        }
        match axes(n, &source)? {
            Some(a) => prescribed.push(LinearConstraint {
                terms: (0..3)
                    .filter(|&k| a[c][k] != 0.0)
                    .map(|k| (n, k, a[c][k]))
                    .collect(),
                value,
                pivot: Pivot::Node(n),
                source: format!("{source} (*BOUNDARY in the *TRANSFORM system)"),
            }),
            None if value == 0.0 => held.entry(n).or_default()[c] = true,
            None => prescribed.push(LinearConstraint {
                terms: vec![(n, c, 1.0)],
                value,
                pivot: Pivot::Fixed((n, c)),
                source: format!("{source} (*BOUNDARY)"),
            }),
        }
    }
    // One support per distinct component pattern keeps the list short.
    let mut supports: Vec<Support> = Vec::new();
    for (node, components) in held {
        match supports.iter_mut().find(|s| s.components == components) {
            Some(s) => s.nodes.push(node),
            None => supports.push(Support {
                name: format!("*BOUNDARY {components:?}"),
                nodes: vec![node],
                components,
            }),
        }
    }
    let mut forces = Vec::new();
    for (&(n, c), &value) in &loading.forces {
        let source = deck
            .concentrated_loads
            .iter()
            .chain(deck.steps.iter().flat_map(|s| &s.concentrated_loads))
            .find(|l| l.nodes.contains(&n) && usize::from(l.dof) == c + 1)
            .map(|l| l.source.clone())
            .unwrap_or(SourceLine {
                file: deck_file(deck),
                line: 0,
            });
        match axes(n, &source)? {
            None => forces.push((n, c, value)),
            Some(a) => forces.extend(
                (0..3)
                    .filter(|&k| a[c][k] != 0.0)
                    .map(|k| (n, k, value * a[c][k])),
            ),
        }
    }
    prescribed.append(&mut ties);
    Ok(DeckConditions {
        supports,
        forces,
        constraints: prescribed,
    })
}

fn deck_file(deck: &Deck) -> std::path::PathBuf {
    deck.steps
        .first()
        .map(|s| s.source.file.clone())
        .unwrap_or_default()
}

/// The three constraints of a distributing coupling: the reference node's x, y, z as the
/// rigid placement of its weighted cloud.
fn coupling(deck: &Deck, c: &DeckCoupling) -> Result<Vec<LinearConstraint>, ModelError> {
    let mesh = &deck.mesh;
    let reference = mesh.nodes[c.reference];
    let candidates: Vec<(usize, [f64; 3])> = c.nodes.iter().map(|&n| (n, mesh.nodes[n])).collect();
    let weighting = match c.weighting {
        DistributingWeighting::Uniform => Weighting::Uniform,
        DistributingWeighting::Linear => Weighting::Linear,
        DistributingWeighting::Quadratic => Weighting::Quadratic,
        DistributingWeighting::Cubic => Weighting::Cubic,
    };
    let radius = c.radius.map_or(Radius::Farthest, Radius::Within);
    let name = format!(
        "*COUPLING {} (reference node {})",
        c.name, mesh.node_labels[c.reference]
    );
    let mut cloud =
        distributing::weigh(&candidates, reference, radius, weighting).map_err(|e| {
            let why = match (e, c.radius) {
                (CloudError::TooFew { found: 0, .. }, Some(r)) => format!(
                    "no node of surface {} lies within the INFLUENCE RADIUS {r} of the reference \
                 node (the nearest is at {:.6e})",
                    c.surface,
                    candidates
                        .iter()
                        .map(|&(_, x)| crate::vector3::norm(crate::vector3::sub(x, reference)))
                        .fold(f64::INFINITY, f64::min)
                ),
                (e, _) => format!("surface {}: {e}", c.surface),
            };
            at(&c.source, format!("{name}: {why}"))
        })?;
    if c.element_based {
        // Abaqus weighs an element-based surface's nodes by their tributary areas.
        let areas: BTreeMap<usize, f64> =
            contact::tributary_areas(mesh, &mesh.surfaces[&c.surface])
                .into_iter()
                .collect();
        for node in &mut cloud {
            node.weight *= areas.get(&node.node).copied().unwrap_or(0.0);
        }
        cloud.retain(|n| n.weight > 0.0);
        distributing::normalise(&mut cloud);
    }
    let blocks = distributing::reference_motion(&cloud, reference).ok_or_else(|| {
        at(
            &c.source,
            format!(
                "{name}: the coupling nodes lie on one line, so the cloud's rotation about it \
                 is not defined"
            ),
        )
    })?;
    Ok((0..3)
        .map(|comp| {
            let mut terms = vec![(c.reference, comp, 1.0)];
            for (n, b) in &blocks {
                for (j, &bij) in b[comp].iter().enumerate() {
                    if bij != 0.0 {
                        terms.push((*n, j, -bij));
                    }
                }
            }
            LinearConstraint {
                terms,
                value: 0.0,
                // The reference node, unless a *BOUNDARY drives it (then a coupling node).
                pivot: Pivot::Prefer((c.reference, comp)),
                source: format!("{} ({name})", c.source),
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use crate::model::source;

    /// The unit tetrahedron (nodes 11..20, element 7) and a node 30 of its own at
    /// (0.2, 0.2, 2).
    fn deck(tail: &str) -> String {
        let mut s = String::from("*NODE, NSET=NALL\n");
        let c = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let mut p = c.to_vec();
        for [a, b] in crate::mesh::TET10_EDGES {
            p.push([0, 1, 2].map(|k| 0.5 * (c[a][k] + c[b][k])));
        }
        for (i, x) in p.iter().enumerate() {
            s.push_str(&format!("{}, {}, {}, {}\n", 11 + i, x[0], x[1], x[2]));
        }
        s.push_str(
            "*NODE\n30, 0.2, 0.2, 2.0\n*ELEMENT, TYPE=C3D10, ELSET=EALL\n\
             7, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20\n*MATERIAL, NAME=STEEL\n*ELASTIC\n\
             210e9, 0.3\n*DENSITY\n7850.\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n\
             *SURFACE, NAME=BASE\n7, S1\n",
        );
        s.push_str(tail);
        s
    }

    /// The error of reading `tail` after the tet, and the 1-based line of the tail's first
    /// line.
    fn error(test: &str, tail: &str) -> (String, usize) {
        let dir =
            std::env::temp_dir().join(format!("squeal-constraints-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let text = deck(tail);
        let first = text.lines().count() - tail.lines().count() + 1;
        std::fs::write(dir.join("deck.inp"), &text).unwrap();
        let result = source::read(&dir.join("deck.inp"));
        let _ = std::fs::remove_dir_all(&dir);
        match result {
            Ok(_) => panic!("{test}: read without error"),
            Err(e) => (e.to_string(), first),
        }
    }

    #[test]
    fn a_coupling_with_no_node_within_its_radius_names_its_line() {
        let (e, first) = error(
            "radius",
            "*COUPLING, REF NODE=30, SURFACE=BASE, CONSTRAINT NAME=C, INFLUENCE RADIUS=0.5\n\
             *DISTRIBUTING\n",
        );
        assert!(e.contains(&format!("deck.inp:{first}:")), "{e}");
        assert!(
            e.contains("no node of surface BASE lies within the INFLUENCE RADIUS 0.5"),
            "{e}"
        );
        // The default radius takes them all.
        let dir =
            std::env::temp_dir().join(format!("squeal-constraints-ok-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("deck.inp"),
            deck("*COUPLING, REF NODE=30, SURFACE=BASE, CONSTRAINT NAME=C\n*DISTRIBUTING\n"),
        )
        .unwrap();
        let model = source::read(&dir.join("deck.inp")).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(model.constraints.len(), 3);
        // Its x: 1 at the reference, the face's 6 nodes with weights adding up to -1.
        let x = &model.constraints[0];
        let sum: f64 = x.terms.iter().filter(|t| t.1 == 0).map(|t| t.2).sum();
        assert!(sum.abs() < 1e-15, "{:?}", x.terms);
    }

    #[test]
    fn a_coupling_reference_driven_by_a_boundary_hands_its_elimination_to_the_cloud() {
        let dir =
            std::env::temp_dir().join(format!("squeal-constraints-driven-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("deck.inp"),
            deck(
                "*COUPLING, REF NODE=30, SURFACE=BASE, CONSTRAINT NAME=C\n*DISTRIBUTING\n\
                 *BOUNDARY\n30, 1, 2\n30, 3, 3, 0.001\n",
            ),
        )
        .unwrap();
        let model = source::read(&dir.join("deck.inp")).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        let resolved = model.resolved_constraints().unwrap();
        let reference = model
            .mesh
            .node_labels
            .iter()
            .position(|&l| l == 30)
            .unwrap();
        // z prescribed: the reference's own; x and y held: supports. The coupling's three
        // dependents are then DOFs of the face.
        assert_eq!(resolved.dependents[&(reference, 2)].offset, 0.001);
        assert_eq!(resolved.dependents.len(), 4);
        assert_eq!(
            resolved
                .dependents
                .keys()
                .filter(|d| d.0 == reference)
                .count(),
            1
        );
    }

    #[test]
    fn equations_loads_and_supports_at_a_transformed_node_act_in_its_local_directions() {
        // Node 12 in a rectangular system turned 90 degrees about z: local 1 = global y,
        // local 2 = -x.
        let dir =
            std::env::temp_dir().join(format!("squeal-constraints-local-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("deck.inp"),
            deck(
                "*NSET, NSET=T\n12\n*TRANSFORM, NSET=T\n0., 1., 0., -1., 0., 0.\n\
                 *EQUATION\n2\n11, 1, 1., 12, 2, -2.\n*BOUNDARY\n12, 1, 1, 0.25\n\
                 *CLOAD\n12, 2, 3.\n*ELEMENT, TYPE=MASS, ELSET=M\n99, 30\n*MASS, ELSET=M\n1.\n",
            ),
        )
        .unwrap();
        let model = source::read(&dir.join("deck.inp")).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        let (n11, n12) = (0, 1);
        // The prescribed local 1 (global y) first, then the equation u11x - 2 (-u12x) = 0.
        assert_eq!(model.constraints[0].terms, vec![(n12, 1, 1.0)]);
        assert_eq!(model.constraints[0].value, 0.25);
        assert_eq!(
            model.constraints[1].terms,
            vec![(n11, 0, 1.0), (n12, 0, 2.0)]
        );
        // The force along local 2 is -3 along x.
        assert_eq!(model.forces, vec![(n12, 0, -3.0)]);
        let r = model.resolved_constraints().unwrap();
        assert_eq!(r.dependents[&(n12, 1)].offset, 0.25);
        assert_eq!(r.dependents[&(n11, 0)].terms, vec![((n12, 0), -2.0)]);
    }

    #[test]
    fn a_dependent_dof_taken_twice_or_supported_is_refused_naming_both_lines() {
        let (e, first) = error(
            "twice",
            "*EQUATION\n2\n11, 1, 1., 12, 1, -1.\n2\n11, 1, 1., 13, 1, -1.\n",
        );
        assert!(
            e.contains(&format!("deck.inp:{}", first + 3))
                && e.contains(&format!("deck.inp:{}", first + 1))
                && e.contains("already the dependent DOF"),
            "{e}"
        );
        let (e, first) = error(
            "supported",
            "*EQUATION\n2\n11, 1, 1., 12, 1, -1.\n*BOUNDARY\n11, 1\n",
        );
        assert!(
            e.contains(&format!("deck.inp:{}", first + 1))
                && e.contains("also held by the support"),
            "{e}"
        );
        let (e, first) = error(
            "prescribed",
            "*EQUATION\n2\n11, 1, 1., 12, 1, -1.\n*BOUNDARY\n11, 1, 1, 0.001\n",
        );
        assert!(
            e.contains(&format!("deck.inp:{}", first + 4))
                && e.contains(&format!("deck.inp:{}", first + 1)),
            "{e}"
        );
    }

    #[test]
    fn a_node_on_a_cylindrical_axis_and_fixed_after_a_general_step_are_refused() {
        let (e, first) = error(
            "axis",
            "*TRANSFORM, NSET=NALL, TYPE=C\n0., 0., 0., 0., 0., 1.\n*BOUNDARY\n11, 1\n",
        );
        assert!(
            e.contains(&format!("deck.inp:{}", first + 3))
                && e.contains("node 11 lies on the axis"),
            "{e}"
        );
        let (e, first) = error(
            "fixed",
            "*STEP\n*STATIC\n*CLOAD\n14, 3, 1.\n*END STEP\n*STEP\n*STATIC\n\
             *BOUNDARY, FIXED\n14, 1, 3\n*END STEP\n",
        );
        assert!(
            e.contains(&format!("deck.inp:{}", first + 8)) && e.contains("FIXED"),
            "{e}"
        );
    }
}
