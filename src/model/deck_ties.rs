//! A deck's `*TIE`s as exact linear constraints: each slave node is tied to the master face
//! it projects on, `u_s = sum_i N_i(q) u_i` per component, `N_i` the six face shape
//! functions at the foot `q` of the normal through the slave node (CalculiX's tie of a
//! quadratic face; a tie across matching meshes reduces to node-on-node equations).
//!
//! - **Position tolerance.** A slave node farther than the tie's `POSITION TOLERANCE` from
//!   the master surface (default [`DEFAULT_TOLERANCE`] times the master's face size, the
//!   square root of its mean face area: Abaqus bases its default on "the typical element
//!   size of the main surface") is left untied, and a warning gives how many and where, as
//!   Abaqus and CalculiX report them. A tie that ties no node stops the run. With `TIED
//!   NSET=` the set's slave nodes are tied whatever their distance (one that projects on
//!   no face is reported the same way), and the others are not.
//! - **ADJUST=YES** (the default) moves each tied slave node onto its master point before
//!   anything is assembled, so the tie stores no initial strain; every tie is projected on
//!   the unmoved mesh first.
//! - **Nodes on both sides** (a slave node that is also a node of the master surface) are
//!   already one node: not tied. A slave node of two ties is held by the first, and the
//!   later one says how many it left (Abaqus keeps the first tie too).
//! - **Supports.** The slave component is the one eliminated when it is free; when a support
//!   holds it, the constraint eliminates a master component instead, so the master point is
//!   held as the slave node is (the tie keeps holding); when the support holds every term,
//!   the constraint says nothing more and is dropped.

use std::collections::BTreeSet;

use super::ModelError;
use crate::contact::SurfaceSearch;
use crate::fem::constraints::{LinearConstraint, Pivot};
use crate::fem::tet10::face_shape;
use crate::fem::Support;
use crate::io::abaqus::{Deck, DeckTie};
use crate::vector3::{norm, sub};

/// The default position tolerance, as a fraction of the master surface's face size.
pub(super) const DEFAULT_TOLERANCE: f64 = 0.05;

/// How far outside a master face (barycentric units) the foot of a slave node's normal may
/// fall: a slave node on the boundary between two master faces belongs to either.
const IN_FACE: f64 = 0.01;

/// How many untied nodes a warning names.
const NAMED: usize = 5;

/// One tied slave node: its master face's nodes with their shape-function weights.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct TiedNode {
    pub(super) slave: usize,
    pub(super) master: Vec<(usize, f64)>,
    /// The tie's name and data line, for messages.
    pub(super) source: String,
}

/// The deck's ties made: the tied nodes, the mesh with adjusted slave nodes (when a tie
/// moved one), and what a person should know.
#[derive(Debug, Default)]
pub(super) struct Ties {
    pub(super) nodes: Vec<TiedNode>,
    pub(super) moved: Option<crate::mesh::Mesh>,
    pub(super) warnings: Vec<String>,
}

/// Projects every tie's slave nodes on its master surface, on the deck's mesh as read.
pub(super) fn tie(deck: &Deck) -> Result<Ties, ModelError> {
    let mesh = &deck.mesh;
    let mut out = Ties::default();
    let mut positions = mesh.nodes.clone();
    let mut moved = false;
    // Each slave node's first tie: Abaqus keeps it and drops the later ones.
    let mut tied_by: std::collections::BTreeMap<usize, &str> = Default::default();
    for t in &deck.ties {
        let at = |why: String| ModelError::AtLine {
            at: t.source.clone(),
            why: format!("*TIE {}: {why}", t.name),
        };
        let master = &mesh.surfaces[&t.master];
        let search = SurfaceSearch::of_surface(mesh, master).map_err(|face| {
            at(format!(
                "face S{} of element {} on the master surface {} is degenerate",
                face.side + 1,
                mesh.element_labels[face.element],
                t.master
            ))
        })?;
        let tolerance = t
            .tolerance
            .unwrap_or(DEFAULT_TOLERANCE * search.mean_face_size());
        let on_master: BTreeSet<usize> = mesh.surface_nodes(master).into_iter().collect();
        let mut untied = Vec::new();
        let mut tied = 0usize;
        // Nodes ADJUST moves by more than round-off of the face size, and the largest move.
        let (mut adjusted, mut farthest) = (0usize, 0.0f64);
        // Slave nodes an earlier tie holds, by that tie's name.
        let mut again: std::collections::BTreeMap<&str, usize> = Default::default();
        let round_off = 1e-9 * search.mean_face_size();
        // TIED NSET ties its nodes whatever their distance.
        let (slaves, reach) = match &t.tied_nodes {
            Some(nodes) => (nodes, f64::INFINITY),
            None => (&t.slave_nodes, tolerance),
        };
        for &s in slaves {
            if on_master.contains(&s) {
                continue;
            }
            if let Some(first) = tied_by.get(&s) {
                *again.entry(*first).or_default() += 1;
                continue;
            }
            let x = mesh.nodes[s];
            let hit = search
                .nearest(x, IN_FACE, reach)
                .filter(|h| h.distance <= reach);
            let Some(hit) = hit else {
                untied.push(s);
                continue;
            };
            let face = &master.faces[hit.face];
            out.nodes.push(TiedNode {
                slave: s,
                master: face.nodes.iter().copied().zip(face_shape(hit.q)).collect(),
                source: format!("{} (*TIE {})", t.source, t.name),
            });
            tied += 1;
            tied_by.insert(s, &t.name);
            let distance = norm(sub(hit.point, x));
            if t.adjust && distance > 0.0 {
                positions[s] = hit.point;
                moved = true;
                if distance > round_off {
                    adjusted += 1;
                    farthest = farthest.max(distance);
                }
            }
        }
        if tied == 0 && again.is_empty() {
            return Err(at(format!(
                "none of the {} slave nodes of {} lies within the position tolerance {tolerance:e} \
                 of the master surface {} (give POSITION TOLERANCE=, or check the surfaces)",
                t.slave_nodes.len(),
                t.slave,
                t.master
            )));
        }
        if !untied.is_empty() {
            out.warnings
                .push(untied_warning(deck, t, &untied, tolerance));
        }
        for (first, count) in &again {
            out.warnings.push(format!(
                "{}: *TIE {}: {count} of its slave nodes are slave nodes of *TIE {first} \
                 already and are not tied again (the first tie holds them, as in Abaqus)",
                t.source, t.name
            ));
        }
        if adjusted > 0 {
            out.warnings.push(format!(
                "{}: *TIE {}: ADJUST moved {adjusted} of its {tied} tied slave nodes onto the \
                 master surface {}, by up to {farthest:.3e} (ADJUST=NO ties them where they \
                 are)",
                t.source, t.name, t.master
            ));
        }
    }
    if moved {
        let mut m = mesh.clone();
        m.nodes = positions;
        out.moved = Some(m);
    }
    Ok(out)
}

fn untied_warning(deck: &Deck, t: &DeckTie, untied: &[usize], tolerance: f64) -> String {
    let mesh = &deck.mesh;
    let named: Vec<String> = untied
        .iter()
        .take(NAMED)
        .map(|&n| {
            let x = mesh.nodes[n];
            format!(
                "{} at ({:.6e}, {:.6e}, {:.6e})",
                mesh.node_labels[n], x[0], x[1], x[2]
            )
        })
        .collect();
    let more = match untied.len().saturating_sub(NAMED) {
        0 => String::new(),
        k => format!(" and {k} more"),
    };
    let (of, why) = match &t.tied_nodes {
        Some(nodes) => (
            format!("{} slave nodes of TIED NSET", nodes.len()),
            format!("project on no face of the master surface {}", t.master),
        ),
        None => (
            format!("{} slave nodes of {}", t.slave_nodes.len(), t.slave),
            format!(
                "lie farther than the position tolerance {tolerance:e} from the master surface {}",
                t.master
            ),
        ),
    };
    format!(
        "{}: *TIE {}: {} of the {of} {why} and are not tied: {}{more}",
        t.source,
        t.name,
        untied.len(),
        named.join(", ")
    )
}

/// The tied nodes as constraints, one per component, given the supports in force:
/// the slave component eliminated when free, a master one when a support holds it, none when
/// the support holds every term.
pub(super) fn constraints(nodes: &[TiedNode], supports: &[Support]) -> Vec<LinearConstraint> {
    let held: BTreeSet<(usize, usize)> = supports
        .iter()
        .flat_map(|s| {
            s.nodes.iter().flat_map(move |&n| {
                (0..3)
                    .filter(move |&c| s.components[c])
                    .map(move |c| (n, c))
            })
        })
        .collect();
    let mut out = Vec::with_capacity(3 * nodes.len());
    for t in nodes {
        for c in 0..3 {
            let terms: Vec<(usize, usize, f64)> = std::iter::once((t.slave, c, 1.0))
                .chain(
                    t.master
                        .iter()
                        .filter(|(_, w)| *w != 0.0)
                        .map(|&(n, w)| (n, c, -w)),
                )
                .collect();
            if terms.iter().all(|&(n, c, _)| held.contains(&(n, c))) {
                continue;
            }
            out.push(LinearConstraint {
                terms,
                value: 0.0,
                pivot: Pivot::Prefer((t.slave, c)),
                source: t.source.clone(),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tied(slave: usize, master: &[(usize, f64)]) -> TiedNode {
        TiedNode {
            slave,
            master: master.to_vec(),
            source: "deck.inp:9 (*TIE G)".into(),
        }
    }

    #[test]
    fn a_tied_node_is_three_equations_whose_pivot_is_the_slave_unless_a_support_holds_it() {
        let nodes = [tied(7, &[(1, 0.5), (2, 0.5), (3, 0.0)])];
        let c = constraints(&nodes, &[]);
        assert_eq!(c.len(), 3);
        for (k, e) in c.iter().enumerate() {
            assert_eq!(e.terms, vec![(7, k, 1.0), (1, k, -0.5), (2, k, -0.5)]);
            assert_eq!(e.pivot, Pivot::Prefer((7, k)));
            assert_eq!(e.value, 0.0);
        }
        // z of the slave held: its equation stays (a master component will be eliminated);
        // every term of y held: nothing left to say.
        let supports = [
            Support {
                name: "S".into(),
                nodes: vec![7],
                components: [false, true, true],
            },
            Support {
                name: "M".into(),
                nodes: vec![1, 2],
                components: [false, true, false],
            },
        ];
        let c = constraints(&nodes, &supports);
        let dofs: Vec<usize> = c.iter().map(|e| e.terms[0].1).collect();
        assert_eq!(dofs, vec![0, 2]);
    }
}
