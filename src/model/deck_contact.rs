//! A deck's contact pairs as squeal contact pairs, and the choice of the interaction a
//! friction sweep slides.
//!
//! Each `*CONTACT PAIR` data line becomes one node-to-surface pair named `SLAVE:MASTER`
//! with squeal's penalty law: the `PRESSURE-OVERCLOSURE=LINEAR` slope is the penalty per
//! unit area (`HARD`: squeal's default 10 E_min / h), `NO SEPARATION` makes it bilateral.
//! Friction: none when mu = 0 (a Coulomb law with mu = 0 would still stick at the first
//! iteration and add a tangential stiffness the deck does not have); Coulomb with the
//! deck's stick slope otherwise; steady sliding where a `*MOTION` moves one of a pair's
//! surfaces ([`apply_motions`]: the disc turning under the pads, read from the deck), or
//! once [`slide`] gives the pairs of an interaction a sliding direction (a flag or study
//! key, which replaces the deck's `*MOTION`).

use std::collections::BTreeMap;

use super::{Model, ModelError};
use crate::contact::variant::{self, CalculixLaw, ContactVariant};
use crate::contact::{
    self, ContactPair, FrictionLaw, PairSettings, SearchOptions, SlidingDirection,
};
use crate::io::abaqus::{Deck, DeckContactPair, Motion, MotionKind, NormalBehavior, SlaveSurface};

/// What the CalculiX contact variant ([`crate::contact::variant`]) makes of a deck pair.
#[derive(Clone, Debug, PartialEq)]
pub struct CalculixPair {
    /// The smoothed linear law: the interaction's tension at large clearance (blank: the
    /// first material's E / 70000) and c0; `None` when neither a tension nor a material's E
    /// is there to take it from.
    pub law: Option<CalculixLaw>,
    /// `HARD`: CalculiX's slope, 50 times the first material's E.
    pub hard_penalty: Option<f64>,
    /// CalculiX's slave areas, one per contact point (element-based slaves; a node-based
    /// slave keeps the areas of its `*SURFACE` line).
    pub areas: Option<Vec<f64>>,
    /// The `*SURFACE INTERACTION` line.
    pub source: String,
}

/// The CalculiX variant of each deck pair, by pair name (`pairs` are the deck's, in order).
pub(super) fn calculix_pairs(deck: &Deck, pairs: &[ContactPair]) -> BTreeMap<String, CalculixPair> {
    let mut out = BTreeMap::new();
    for (p, pair) in deck.contact_pairs.iter().zip(pairs) {
        let interaction = &deck.interactions[&p.interaction];
        let tension = interaction.tension.filter(|&t| t > 0.0).or_else(|| {
            deck.first_young
                .map(|e| e / variant::DEFAULT_TENSION_DIVISOR)
        });
        let law = tension.map(|tension| CalculixLaw {
            tension,
            clearance_factor: interaction
                .clearance_factor
                .filter(|&c| c > 0.0)
                .unwrap_or(variant::DEFAULT_CLEARANCE_FACTOR),
            stick_slope: interaction.stick_slope,
        });
        let hard_penalty = match interaction.normal {
            NormalBehavior::Hard => deck.first_young.map(|e| variant::HARD_SLOPE_FACTOR * e),
            NormalBehavior::Linear { .. } => None,
        };
        let areas = match &p.slave {
            SlaveSurface::Faces(name) => {
                let by_node: BTreeMap<usize, f64> =
                    variant::calculix_areas(&deck.mesh, &deck.mesh.surfaces[name])
                        .into_iter()
                        .collect();
                Some(
                    pair.points
                        .iter()
                        .map(|pt| by_node.get(&pt.slave_node).copied().unwrap_or(pt.area))
                        .collect(),
                )
            }
            SlaveSurface::Nodes { .. } => None,
        };
        out.insert(
            p.name.clone(),
            CalculixPair {
                law,
                hard_penalty,
                areas,
                source: interaction.source.to_string(),
            },
        );
    }
    out
}

/// Gives the deck's pairs the law of `variant`: squeal's (as built), or CalculiX's (its
/// slave areas, its smoothed linear law, `HARD` as its slope, and its perturbation
/// tangent). Pairs that are not the deck's (a study's `[[contacts]]`) keep squeal's law.
pub fn apply_variant(model: &mut Model, variant: ContactVariant) -> Result<(), ModelError> {
    if variant == ContactVariant::Squeal {
        return Ok(());
    }
    for pair in &mut model.pairs {
        let Some(c) = model.deck_calculix.get(&pair.settings.name) else {
            continue;
        };
        let Some(law) = c.law else {
            return Err(ModelError::Invalid {
                key: format!("{}: *SURFACE INTERACTION", c.source),
                why: "the CalculiX contact variant needs CalculiX's tension at large clearance: \
                      give it as the 2nd field of the PRESSURE-OVERCLOSURE=LINEAR line (the deck \
                      has no material whose E gives CalculiX's default)"
                    .into(),
            });
        };
        if let Some(k) = c.hard_penalty {
            pair.penalty = k;
        }
        if let Some(areas) = &c.areas {
            for (point, &a) in pair.points.iter_mut().zip(areas) {
                point.area = a;
            }
        }
        pair.settings.calculix = Some(law);
    }
    Ok(())
}

/// A deck pair that a `*MOTION` makes slide.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionSliding {
    /// The `*MOTION` line, "file:line".
    pub source: String,
    /// The pair's law before (the deck's `*FRICTION`).
    pub law: FrictionLaw,
}

/// The `*MOTION`s in force in step `step` (`None`: the model data): the model data's, those
/// of every earlier general (not perturbation) step, and the step's own, in that order (a
/// later motion of a body replaces an earlier one).
pub fn motions_in_step(deck: &Deck, step: Option<usize>) -> Vec<&Motion> {
    let mut out: Vec<&Motion> = deck.motions.iter().collect();
    if let Some(k) = step {
        for (j, s) in deck.steps.iter().enumerate().take(k + 1) {
            if j == k || !s.perturbation {
                out.extend(&s.motions);
            }
        }
    }
    out
}

/// The last of `motions` that moves every one of `nodes` (sorted), or an error when one
/// moves some of them only (a surface is a body's: it moves whole or not at all).
fn moving<'m>(
    motions: &[&'m Motion],
    nodes: &[usize],
    pair: &str,
    role: &str,
) -> Result<Option<&'m Motion>, ModelError> {
    let mut found = None;
    for m in motions {
        let inside = nodes
            .iter()
            .filter(|n| m.nodes.binary_search(n).is_ok())
            .count();
        if inside == nodes.len() {
            found = Some(*m);
        } else if inside > 0 {
            return Err(ModelError::Invalid {
                key: format!("{}: *MOTION", m.source),
                why: format!(
                    "it moves {inside} of the {} nodes of the {role} surface of contact pair \
                     {pair}: a *MOTION gives a body's velocity, so it moves a contact surface \
                     whole or not at all",
                    nodes.len()
                ),
            });
        }
    }
    Ok(found)
}

/// The sliding direction of a surface moving by `motion`, seen from the other surface of
/// its pair: the master's velocity when the master moves (`sign` 1), the opposite when the
/// slave does (`sign` -1).
fn sliding_of(motion: &Motion, sign: f64) -> SlidingDirection {
    match motion.kind {
        MotionKind::Rotation { speed, from, to } => SlidingDirection::DiscRotation {
            centre: from,
            axis: crate::vector3::sub(to, from),
            sense: sign * speed.signum(),
        },
        MotionKind::Translation { velocity } => SlidingDirection::Fixed(velocity.map(|v| sign * v)),
    }
}

/// Makes the deck pairs that `motions` move slide steadily along the motion (the disc's
/// rotation under the pads), with the deck's mu, and marks them as the pairs a friction
/// sweep sets mu on. A pair whose master moves slides along the master's velocity, one
/// whose slave moves along the opposite; a pair whose two surfaces both move is refused
/// (squeal slides one surface under the other). A motion that moves no contact surface is
/// said in a warning.
pub fn apply_motions(
    model: &mut Model,
    deck: &Deck,
    motions: &[&Motion],
) -> Result<(), ModelError> {
    if motions.is_empty() {
        return Ok(());
    }
    let mut used = vec![false; motions.len()];
    for (k, p) in deck.contact_pairs.iter().enumerate() {
        let mesh = &deck.mesh;
        let master = mesh.surface_nodes(&mesh.surfaces[&p.master]);
        let slave: Vec<usize> = match &p.slave {
            SlaveSurface::Faces(name) => mesh.surface_nodes(&mesh.surfaces[name]),
            SlaveSurface::Nodes { nodes, .. } => {
                let mut n: Vec<usize> = nodes.iter().map(|&(n, _)| n).collect();
                n.sort_unstable();
                n.dedup();
                n
            }
        };
        let sliding = match (
            moving(motions, &master, &p.name, "master")?,
            moving(motions, &slave, &p.name, "slave")?,
        ) {
            (None, None) => continue,
            (Some(m), None) => (m, sliding_of(m, 1.0)),
            (None, Some(m)) => (m, sliding_of(m, -1.0)),
            (Some(a), Some(b)) => {
                return Err(ModelError::Invalid {
                    key: format!("{}: *MOTION", b.source),
                    why: format!(
                        "both surfaces of contact pair {} move (the master by the *MOTION at \
                         {}, the slave by this one): squeal's steady sliding is one surface \
                         sliding under the other, held one",
                        p.name, a.source
                    ),
                })
            }
        };
        let (motion, direction) = sliding;
        if let Some(i) = motions.iter().position(|m| std::ptr::eq(*m, motion)) {
            used[i] = true;
        }
        let pair = &mut model.pairs[k];
        let law = pair.settings.law.clone();
        pair.set_sliding(direction)
            .map_err(|source| ModelError::Contact {
                key: format!("{}: *MOTION", motion.source),
                name: p.name.clone(),
                source: Box::new(source),
            })?;
        model.swept[k] = true;
        model.deck_motions.insert(
            p.name.clone(),
            MotionSliding {
                source: motion.source.to_string(),
                law,
            },
        );
    }
    for (m, used) in motions.iter().zip(used) {
        if !used {
            model.warnings.push(format!(
                "{}: this *MOTION moves no contact surface whole, so it makes no pair slide",
                m.source
            ));
        }
    }
    Ok(())
}

/// Takes back the sliding the deck's `*MOTION`s gave (a sliding direction given by flag or
/// study key replaces them): each such pair gets its deck law back and is no longer swept.
fn undo_motions(model: &mut Model) {
    for (k, pair) in model.pairs.iter_mut().enumerate() {
        if let Some(m) = model.deck_motions.get(&pair.settings.name) {
            pair.settings.sliding = SlidingDirection::None;
            pair.settings.law = m.law.clone();
            for point in &mut pair.points {
                point.tangent = None;
            }
            model.swept[k] = false;
        }
    }
}

/// The pairs of `deck`, built on its mesh, and the interaction of each (by pair name).
pub(super) fn pairs(
    deck: &Deck,
) -> Result<(Vec<ContactPair>, BTreeMap<String, String>), ModelError> {
    let mut pairs = Vec::with_capacity(deck.contact_pairs.len());
    let mut interactions = BTreeMap::new();
    for p in &deck.contact_pairs {
        pairs.push(pair(deck, p)?);
        interactions.insert(p.name.clone(), p.interaction.clone());
    }
    Ok((pairs, interactions))
}

fn pair(deck: &Deck, p: &DeckContactPair) -> Result<ContactPair, ModelError> {
    // The reader checked that the interaction and the surfaces exist.
    let interaction = &deck.interactions[&p.interaction];
    let law = if interaction.friction > 0.0 {
        FrictionLaw::Coulomb {
            stick_stiffness: interaction.stick_slope,
        }
    } else {
        FrictionLaw::SteadySliding
    };
    let settings = PairSettings {
        name: p.name.clone(),
        friction: interaction.friction,
        penalty: match interaction.normal {
            NormalBehavior::Linear { slope } => Some(slope),
            NormalBehavior::Hard => None,
        },
        separation: interaction.separation,
        sliding: SlidingDirection::None,
        law,
        calculix: None,
    };
    let mesh = &deck.mesh;
    let master = &mesh.surfaces[&p.master];
    let options = SearchOptions::default();
    let built = match &p.slave {
        SlaveSurface::Faces(name) => {
            contact::node_to_surface(mesh, &mesh.surfaces[name], master, settings, &options)
        }
        SlaveSurface::Nodes { nodes, .. } => {
            contact::nodes_to_surface(mesh, nodes, master, settings, &options)
        }
    };
    let mut pair = built.map_err(|source| ModelError::Contact {
        key: format!("{}: *CONTACT PAIR", p.source),
        name: p.name.clone(),
        source: Box::new(source),
    })?;
    // ADJUST: the slave nodes closer than the distance (or penetrating) are moved onto the
    // master; squeal keeps the node where it is and starts its gap at zero, which is the
    // same contact law (the slave element's shape differs by at most the distance).
    if let Some(distance) = p.adjust {
        for point in &mut pair.points {
            if point.initial_gap <= distance {
                point.initial_gap = 0.0;
            }
        }
    }
    Ok(pair)
}

/// Gives the pairs of one interaction the sliding direction `sliding` (steady-sliding
/// friction) and marks them as the ones a friction sweep sets mu on. `interaction`:
/// the interaction's name; `None`: the deck's only interaction used by pairs. `key` names
/// the setting in messages.
pub fn slide(
    model: &mut Model,
    interaction: Option<&str>,
    sliding: &SlidingDirection,
    key: &str,
) -> Result<(), ModelError> {
    let invalid = |why: String| ModelError::Invalid {
        key: key.to_string(),
        why,
    };
    let mut names: Vec<&String> = model.deck_interactions.values().collect();
    names.sort_unstable();
    names.dedup();
    let listed = names
        .iter()
        .map(|n| n.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    let chosen = match interaction {
        Some(wanted) => names
            .iter()
            .find(|n| n.eq_ignore_ascii_case(wanted))
            .map(|n| n.to_string())
            .ok_or_else(|| {
                invalid(format!(
                    "no interaction named '{wanted}' is used by a *CONTACT PAIR of {} \
                     (interactions: {})",
                    model.source,
                    if listed.is_empty() { "none" } else { &listed }
                ))
            })?,
        None => match names.as_slice() {
            [one] => one.to_string(),
            [] => {
                return Err(invalid(format!(
                    "{} has no *CONTACT PAIR to slide",
                    model.source
                )))
            }
            _ => {
                return Err(invalid(format!(
                    "{} has several interactions ({listed}): name the one whose pairs the \
                     disc slides under",
                    model.source
                )))
            }
        },
    };
    if model.swept.len() != model.pairs.len() {
        model.swept.resize(model.pairs.len(), false);
    }
    if !model.deck_motions.is_empty() {
        let mut lines: Vec<&str> = model
            .deck_motions
            .values()
            .map(|m| m.source.as_str())
            .collect();
        lines.sort_unstable();
        lines.dedup();
        model.warnings.push(format!(
            "{key} replaces the deck's *MOTION at {} (the sliding of pairs {}): the pairs of \
             interaction {chosen} slide along {key}'s direction, and the deck's motion is not \
             used",
            lines.join(", "),
            model
                .deck_motions
                .keys()
                .cloned()
                .collect::<Vec<_>>()
                .join(", ")
        ));
        undo_motions(model);
    }
    for (pair, swept) in model.pairs.iter_mut().zip(model.swept.iter_mut()) {
        if model.deck_interactions.get(&pair.settings.name) == Some(&chosen) {
            let name = pair.settings.name.clone();
            pair.set_sliding(sliding.clone())
                .map_err(|source| ModelError::Contact {
                    key: key.to_string(),
                    name,
                    source: Box::new(source),
                })?;
            *swept = true;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::FrictionLaw;
    use crate::model::source;
    use std::path::{Path, PathBuf};

    fn deck_path() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pad_on_plate.inp")
    }

    /// The committed deck with its interaction's lines replaced by `interaction`, written
    /// beside a copy of its mesh in a fresh folder.
    fn variant(test: &str, interaction: &str) -> (PathBuf, PathBuf) {
        let dir =
            std::env::temp_dir().join(format!("squeal-deck-contact-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let data = deck_path().parent().unwrap().to_path_buf();
        std::fs::copy(
            data.join("pad_on_plate_mesh.inp"),
            dir.join("pad_on_plate_mesh.inp"),
        )
        .unwrap();
        let text = std::fs::read_to_string(deck_path()).unwrap().replace(
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1e13\n",
            interaction,
        );
        let path = dir.join("deck.inp");
        std::fs::write(&path, text).unwrap();
        (dir, path)
    }

    #[test]
    fn the_deck_pair_has_the_slope_as_penalty_and_no_friction() {
        let model = source::read(&deck_path()).unwrap();
        assert_eq!(model.pairs.len(), 1);
        let pair = &model.pairs[0];
        assert_eq!(pair.settings.name, "PADBOTTOM:PLATETOP");
        assert_eq!(pair.penalty, 1e13);
        assert_eq!(pair.settings.friction, 0.0);
        assert_eq!(pair.settings.law, FrictionLaw::SteadySliding);
        assert!(pair.settings.separation);
        assert_eq!(pair.points.len(), 49);
        // The slave areas add up to the pad's 0.026 x 0.026 m bottom.
        let area: f64 = pair.points.iter().map(|p| p.area).sum();
        assert!((area - 0.026 * 0.026).abs() < 1e-12, "{area}");
        assert!(pair.points.iter().all(|p| p.tangent.is_none()));
        assert_eq!(model.swept, vec![false]);
        assert_eq!(model.deck_interactions["PADBOTTOM:PLATETOP"], "PADPLATE");
    }

    #[test]
    fn friction_with_a_stick_slope_is_coulomb_and_sliding_makes_it_steady() {
        let (dir, path) = variant(
            "coulomb",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD, NO SEPARATION\n*FRICTION\n0.4, 3e10\n",
        );
        let mut model = source::read(&path).unwrap();
        let pair = &model.pairs[0];
        assert_eq!(pair.settings.friction, 0.4);
        assert_eq!(
            pair.settings.law,
            FrictionLaw::Coulomb {
                stick_stiffness: Some(3e10)
            }
        );
        assert!(!pair.settings.separation);
        assert_eq!(
            pair.settings.penalty, None,
            "HARD: squeal's default penalty"
        );
        // Sliding about the z axis through the plate's middle: steady sliding, swept, and
        // each point's tangent circumferential.
        let axis = SlidingDirection::DiscRotation {
            centre: [0.02, 0.02, 0.0],
            axis: [0.0, 0.0, 1.0],
            sense: 1.0,
        };
        slide(&mut model, None, &axis, "mesh.sliding").unwrap();
        let pair = &model.pairs[0];
        assert_eq!(pair.settings.law, FrictionLaw::SteadySliding);
        assert_eq!(model.swept, vec![true]);
        for p in &pair.points {
            let r = [p.position[0] - 0.02, p.position[1] - 0.02];
            match p.tangent {
                Some(t) => assert!(
                    (t[0] * r[0] + t[1] * r[1]).abs() < 1e-12 && t[2].abs() < 1e-12,
                    "{t:?} at {r:?}"
                ),
                None => assert!(r[0].hypot(r[1]) < 1e-9, "only on the axis"),
            }
        }
        // A wrong name lists the interactions.
        let e = slide(&mut model, Some("disc"), &axis, "--interaction")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no interaction named 'disc'") && e.contains("PADPLATE"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn adjust_starts_the_near_slave_nodes_in_contact() {
        // Lift the pad by 1e-6 m: without ADJUST every gap is 1e-6, with ADJUST=2e-6 none.
        let (dir, path) = variant(
            "adjust",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1e13\n",
        );
        let mesh = dir.join("pad_on_plate_mesh.inp");
        let lifted: String = std::fs::read_to_string(&mesh)
            .unwrap()
            .lines()
            .map(|l| {
                let f: Vec<&str> = l.split(", ").collect();
                match f[..] {
                    [label, x, y, z]
                        if label.parse::<i64>().is_ok_and(|n| n > 1000)
                            && f.len() == 4
                            && !l.starts_with('*') =>
                    {
                        let z: f64 = z.parse().unwrap();
                        format!("{label}, {x}, {y}, {:.9}\n", z + 1e-6)
                    }
                    _ => format!("{l}\n"),
                }
            })
            .collect();
        std::fs::write(&mesh, lifted).unwrap();
        let model = source::read(&path).unwrap();
        assert!(model.pairs[0]
            .points
            .iter()
            .all(|p| (p.initial_gap - 1e-6).abs() < 1e-12));
        let text = std::fs::read_to_string(&path)
            .unwrap()
            .replace("SMALL SLIDING\n", "SMALL SLIDING, ADJUST=2e-6\n");
        std::fs::write(&path, text).unwrap();
        let model = source::read(&path).unwrap();
        assert!(model.pairs[0].points.iter().all(|p| p.initial_gap == 0.0));
        let _ = std::fs::remove_dir_all(dir);
    }

    /// A *MOTION moving the master makes the pair slide along its velocity; moving the
    /// slave, along the opposite; moving both is refused naming the pair and both lines.
    #[test]
    fn a_motion_slides_the_pairs_whose_surface_it_moves() {
        let mut tangents = Vec::new();
        for (test, set) in [("master", "PLATE"), ("slave", "PAD")] {
            let (dir, path) = variant(
                &format!("motion-{test}"),
                &format!(
                    "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1e13\n*FRICTION\n0.3\n\
                     *NSET, NSET=MOVING, ELSET={set}\n*MOTION, TRANSLATION, TYPE=VELOCITY\n\
                     MOVING, 2, 2, 3.0\n"
                ),
            );
            let model = source::read(&path).unwrap();
            assert_eq!(model.swept, vec![true], "{test}");
            let pair = &model.pairs[0];
            assert_eq!(pair.settings.law, FrictionLaw::SteadySliding);
            assert_eq!(pair.settings.friction, 0.3);
            assert!(model.deck_motions.contains_key("PADBOTTOM:PLATETOP"));
            tangents.push(pair.points[0].tangent.unwrap());
            let _ = std::fs::remove_dir_all(dir);
        }
        // The plate's normal is z to round-off (1e-16): the tangent likewise.
        let near = |a: [f64; 3], b: [f64; 3]| (0..3).all(|c| (a[c] - b[c]).abs() < 1e-12);
        assert!(
            near(tangents[0], [0.0, 1.0, 0.0]),
            "the plate moves +y: {tangents:?}"
        );
        assert!(
            near(tangents[1], [0.0, -1.0, 0.0]),
            "the pad moves +y: {tangents:?}"
        );
        let (dir, path) = variant(
            "motion-both",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1e13\n\
             *MOTION, TRANSLATION\nNALL, 1, 1, 1.0\n",
        );
        let e = source::read(&path).unwrap_err().to_string();
        assert!(
            e.contains("both surfaces of contact pair PADBOTTOM:PLATETOP move"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(dir);
    }
}
