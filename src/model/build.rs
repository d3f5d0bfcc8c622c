//! A model from a study's tables ([`ModelSpec`]): the mesh (file or built-in brake), then
//! materials, supports, springs, pressures and contact pairs resolved by name against it.
//! A deck named as the mesh brings its own supports, loads and warnings along; the
//! study's tables add to them.

use super::spec::{FrictionLawName, LinkSpec, ModelSpec, SpringDirection};
use super::{source, Model, ModelError, Pressure};
use crate::contact::{self, FrictionLaw, PairSettings, SearchOptions};
use crate::fem::springs::{GroundSpring, TwoNodeSpring};
use crate::fem::Support;
use crate::mesh::{brake, Material, Mesh};
use std::collections::BTreeMap;

/// A named item, matched exactly or else ignoring case: Abaqus names are case-insensitive
/// (a deck's reader keeps them upper-case), and a study written for the built-in brake's
/// lower-case names must find the same sets in a deck of it.
fn named<'m, T>(map: &'m BTreeMap<String, T>, name: &str) -> Option<&'m T> {
    map.get(name).or_else(|| {
        map.iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(name))
            .map(|(_, v)| v)
    })
}

fn set_nodes(mesh: &Mesh, name: &str) -> Option<Vec<usize>> {
    named(&mesh.node_sets, name)
        .cloned()
        .or_else(|| named(&mesh.surfaces, name).map(|s| mesh.surface_nodes(s)))
}

impl Model {
    /// Builds the model a study describes. Errors name the study key at fault (the caller
    /// adds the file).
    pub fn from_spec(spec: &ModelSpec) -> Result<Model, ModelError> {
        let mut model = match &spec.mesh.file {
            Some(path) => {
                let mut m = source::read(path)?;
                let discrete = m.springs.len() + m.links.len() + m.point_masses.len();
                let from_deck = m.supports.len()
                    + m.pressures.len()
                    + m.forces.len()
                    + m.pairs.len()
                    + discrete;
                if from_deck > 0 {
                    m.warnings.push(format!(
                        "{}: kept the deck's {} supports, {} loaded faces, {} nodal forces, {} \
                         springs, {} point masses and {} contact pairs{} (the study's tables add \
                         to them; a [[contacts]] table of a pair's name replaces it)",
                        m.source,
                        m.supports.len(),
                        m.pressures.len(),
                        m.forces.len(),
                        m.springs.len() + m.links.len(),
                        m.point_masses.len(),
                        m.pairs.len(),
                        deck_pair_list(&m),
                    ));
                }
                // A study's band replaces the deck's *FREQUENCY request: say so.
                if let Some((count, upper)) = m.frequency_step.take() {
                    m.warnings.push(format!(
                        "{}: the deck's *FREQUENCY request ({} modes, upper frequency {}) is \
                         not used: the study's analysis.max_frequency_hz (squeal sweep: --fmax) \
                         sets the band",
                        m.source,
                        count.map_or("all".to_string(), |n| n.to_string()),
                        upper.map_or("none".to_string(), |f| format!("{f} Hz")),
                    ));
                }
                deck_sliding(&mut m, spec)?;
                if let Some(v) = spec.mesh.contact_variant {
                    super::deck_contact::apply_variant(&mut m, v)?;
                }
                m
            }
            None => {
                let preset = spec.mesh.preset.as_deref().unwrap_or(brake::DEFAULT_PRESET);
                let params = match &spec.mesh.brake {
                    Some(p) => p.clone(),
                    None => brake::preset(preset).ok_or_else(|| ModelError::Invalid {
                        key: "mesh.preset".into(),
                        why: format!(
                            "unknown preset '{preset}' (presets: {})",
                            brake::PRESETS.join(", ")
                        ),
                    })?,
                };
                let mesh = brake::build(&params).map_err(|source| ModelError::BrakeParams {
                    key: "mesh.brake".into(),
                    source,
                })?;
                Model {
                    source: format!("built-in brake '{preset}'"),
                    mesh,
                    ..Default::default()
                }
            }
        };
        if spec.mesh.file.is_none()
            && (spec.mesh.interaction.is_some()
                || spec.mesh.sliding.is_some()
                || spec.mesh.contact_variant.is_some())
        {
            let key = if spec.mesh.interaction.is_some() {
                "mesh.interaction"
            } else if spec.mesh.sliding.is_some() {
                "mesh.sliding"
            } else {
                "mesh.contact_variant"
            };
            return Err(ModelError::Invalid {
                key: key.into(),
                why: "mesh.interaction, mesh.sliding and mesh.contact_variant are about a deck's \
                      contact pairs: give a deck as mesh.file, or use [[contacts]]"
                    .into(),
            });
        }
        add_materials(&mut model, spec)?;
        let source_name = model.source.clone();
        let missing = |key: String, name: &str, what: &'static str| ModelError::Missing {
            key,
            what,
            name: name.to_string(),
            source_name: source_name.clone(),
        };
        let mesh = &model.mesh;
        for (i, s) in spec.supports.iter().enumerate() {
            let nodes = set_nodes(mesh, &s.set)
                .ok_or_else(|| missing(format!("supports[{i}].set"), &s.set, "node set"))?;
            let c = s.components.to_ascii_lowercase();
            model.supports.push(Support {
                name: s.set.clone(),
                nodes,
                components: [c.contains('x'), c.contains('y'), c.contains('z')],
            });
        }
        for (i, s) in spec.springs.iter().enumerate() {
            let nodes = set_nodes(mesh, &s.set)
                .ok_or_else(|| missing(format!("springs[{i}].set"), &s.set, "node set"))?;
            model.springs.extend(ground_springs(mesh, &nodes, s, i)?);
        }
        for (i, l) in spec.links.iter().enumerate() {
            let from = set_nodes(mesh, &l.set)
                .ok_or_else(|| missing(format!("links[{i}].set"), &l.set, "node set"))?;
            let to = set_nodes(mesh, &l.to)
                .ok_or_else(|| missing(format!("links[{i}].to"), &l.to, "node set"))?;
            model.links.extend(link_springs(mesh, &from, &to, l, i)?);
        }
        for (i, p) in spec.pressures.iter().enumerate() {
            let surface = named(&mesh.surfaces, &p.surface)
                .ok_or_else(|| missing(format!("pressures[{i}].surface"), &p.surface, "surface"))?;
            model.pressures.push(Pressure {
                name: p.surface.clone(),
                faces: surface.faces.clone(),
                value: p.value,
            });
        }
        for (i, c) in spec.contacts.iter().enumerate() {
            let slave = named(&mesh.surfaces, &c.slave)
                .ok_or_else(|| missing(format!("contacts[{i}].slave"), &c.slave, "surface"))?;
            let master = named(&mesh.surfaces, &c.master)
                .ok_or_else(|| missing(format!("contacts[{i}].master"), &c.master, "surface"))?;
            let law = match (c.friction_law, c.stick_stiffness) {
                (FrictionLawName::SteadySliding, Some(_)) => {
                    return Err(ModelError::Invalid {
                        key: format!("contacts[{i}].stick_stiffness"),
                        why: format!(
                            "pair '{}' slides steadily (friction_law = \"steady-sliding\"): a \
                             stick stiffness needs friction_law = \"coulomb\"",
                            c.name
                        ),
                    })
                }
                (FrictionLawName::SteadySliding, None) => FrictionLaw::SteadySliding,
                (FrictionLawName::Coulomb, stick_stiffness) => {
                    FrictionLaw::Coulomb { stick_stiffness }
                }
            };
            let settings = PairSettings {
                name: c.name.clone(),
                friction: c.friction,
                penalty: c.penalty,
                separation: c.separation,
                sliding: c.sliding.clone(),
                law,
                calculix: None,
            };
            let pair =
                contact::node_to_surface(mesh, slave, master, settings, &SearchOptions::default())
                    .map_err(|source| ModelError::Contact {
                        key: format!("contacts[{i}]"),
                        name: c.name.clone(),
                        source: Box::new(source),
                    })?;
            let surfaces = Some((slave.name.clone(), master.name.clone()));
            // A table of a deck pair's name replaces that pair where it stands.
            let replaced = model
                .pairs
                .iter()
                .position(|p| p.settings.name.eq_ignore_ascii_case(&c.name));
            match replaced {
                Some(k) => {
                    model.warnings.push(format!(
                        "contacts[{i}] '{}' replaces the deck's contact pair {}",
                        c.name, model.pairs[k].settings.name
                    ));
                    model.pairs[k] = pair;
                    model.swept[k] = c.sweep;
                    model.pair_surfaces[k] = surfaces;
                }
                None => {
                    model.pairs.push(pair);
                    model.swept.push(c.sweep);
                    model.pair_surfaces.push(surfaces);
                }
            }
        }
        Ok(model)
    }
}

/// " (NAME: interaction I, ...)" for the deck's pairs, or nothing.
fn deck_pair_list(model: &Model) -> String {
    if model.deck_interactions.is_empty() {
        return String::new();
    }
    let list: Vec<String> = model
        .deck_interactions
        .iter()
        .map(|(pair, interaction)| format!("{pair}: interaction {interaction}"))
        .collect();
    format!(" ({})", list.join(", "))
}

/// `mesh.sliding` (and `mesh.interaction`): the deck pairs the disc slides under. A sliding
/// direction given here replaces the deck's `*MOTION` (said in a warning); without one, the
/// pairs the deck's `*MOTION` moves slide, and `mesh.interaction` only picks among them.
fn deck_sliding(model: &mut Model, spec: &ModelSpec) -> Result<(), ModelError> {
    match (&spec.mesh.sliding, &spec.mesh.interaction) {
        (Some(sliding), interaction) => {
            super::deck_contact::slide(model, interaction.as_deref(), sliding, "mesh.sliding")
        }
        (None, Some(name)) if !model.deck_motions.is_empty() => {
            let mut found = false;
            for (k, pair) in model.pairs.iter().enumerate() {
                let of_it = model
                    .deck_interactions
                    .get(&pair.settings.name)
                    .is_some_and(|i| i.eq_ignore_ascii_case(name));
                found |= of_it && model.swept[k];
                if !of_it {
                    model.swept[k] = false;
                }
            }
            if found {
                Ok(())
            } else {
                Err(ModelError::Invalid {
                    key: "mesh.interaction".into(),
                    why: format!(
                        "no pair of interaction '{name}' slides: the deck's *MOTION moves the \
                         pairs {}; give mesh.sliding (squeal sweep: --disc-axis or \
                         --sliding-direction) to make the pairs of '{name}' slide",
                        model
                            .deck_motions
                            .keys()
                            .cloned()
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                })
            }
        }
        (None, Some(name)) => Err(ModelError::Invalid {
            key: "mesh.interaction".into(),
            why: format!(
                "the pairs of interaction '{name}' need a sliding direction, and the deck gives \
                 none (no *MOTION moves their surfaces): give mesh.sliding (squeal sweep: \
                 --disc-axis or --sliding-direction)"
            ),
        }),
        (None, None) => Ok(()),
    }
}

/// The study's materials, each given to the part of its name.
fn add_materials(model: &mut Model, spec: &ModelSpec) -> Result<(), ModelError> {
    for (i, m) in spec.materials.iter().enumerate() {
        let part = model
            .mesh
            .parts
            .iter_mut()
            .find(|p| p.name == m.part || p.name.eq_ignore_ascii_case(&m.part))
            .ok_or_else(|| ModelError::Invalid {
                key: format!("materials[{i}].part"),
                why: format!("no part named '{}'", m.part),
            })?;
        let name = part.name.clone();
        part.material = Some(name.clone());
        model.mesh.materials.insert(
            name.clone(),
            Material {
                name,
                young: m.young,
                poisson: m.poisson,
                density: m.density,
            },
        );
    }
    Ok(())
}

/// A spring set's stiffness shared equally by its nodes, each along the set's direction
/// there (fixed, or radial/circumferential about the disc axis, z through the origin).
fn ground_springs(
    mesh: &Mesh,
    nodes: &[usize],
    s: &super::spec::SpringSpec,
    i: usize,
) -> Result<Vec<GroundSpring>, ModelError> {
    let each = s.stiffness / nodes.len() as f64;
    let mut springs = Vec::with_capacity(nodes.len());
    for &n in nodes {
        let x = mesh.nodes[n];
        let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
        let direction = match &s.direction {
            SpringDirection::Vector(v) => {
                let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                if l == 0.0 {
                    return Err(ModelError::Invalid {
                        key: format!("springs[{i}].direction"),
                        why: "zero vector".into(),
                    });
                }
                v.map(|c| c / l)
            }
            SpringDirection::Radial if r > 0.0 => [x[0] / r, x[1] / r, 0.0],
            SpringDirection::Circumferential if r > 0.0 => [-x[1] / r, x[0] / r, 0.0],
            _ => {
                return Err(ModelError::Invalid {
                    key: format!("springs[{i}]"),
                    why: "node on the disc axis has no radial direction".into(),
                })
            }
        };
        springs.push(GroundSpring {
            node: n,
            direction,
            stiffness: each,
        });
    }
    Ok(springs)
}

/// A link's springs: each node of `from` tied to its nearest node of `to` along the axis and
/// along two directions across it, each stiffness shared equally by the nodes of `from`.
fn link_springs(
    mesh: &Mesh,
    from: &[usize],
    to: &[usize],
    l: &LinkSpec,
    i: usize,
) -> Result<Vec<TwoNodeSpring>, ModelError> {
    let invalid = |key: String, why: String| ModelError::Invalid { key, why };
    let length = l.axis.iter().map(|c| c * c).sum::<f64>().sqrt();
    if !(length > 0.0 && length.is_finite()) {
        return Err(invalid(
            format!("links[{i}].axis"),
            format!("must be a finite non-zero vector, got {:?}", l.axis),
        ));
    }
    if from.is_empty() || to.is_empty() {
        return Err(invalid(
            format!("links[{i}]"),
            format!("'{}' or '{}' has no nodes", l.set, l.to),
        ));
    }
    let axis = l.axis.map(|c| c / length);
    // Two unit vectors across the axis: the axis crossed with the coordinate axis least
    // along it, then the axis crossed with that.
    let least = (0..3)
        .min_by(|&a, &b| axis[a].abs().total_cmp(&axis[b].abs()))
        .unwrap_or(0);
    let mut e = [0.0; 3];
    e[least] = 1.0;
    let unit = |v: [f64; 3]| {
        let n = v.iter().map(|c| c * c).sum::<f64>().sqrt();
        v.map(|c| c / n)
    };
    let across1 = unit(crate::vector3::cross(axis, e));
    let across2 = crate::vector3::cross(axis, across1);
    let share = from.len() as f64;
    let mut springs = Vec::with_capacity(3 * from.len());
    for &a in from {
        let x = mesh.nodes[a];
        let b = to
            .iter()
            .copied()
            .min_by(|&p, &q| {
                let d = |n: usize| crate::vector3::sub(mesh.nodes[n], x);
                let (dp, dq) = (d(p), d(q));
                crate::vector3::dot(dp, dp).total_cmp(&crate::vector3::dot(dq, dq))
            })
            .unwrap_or(to[0]);
        for (direction, total) in [
            (axis, l.axial),
            (across1, l.transverse),
            (across2, l.transverse),
        ] {
            if total > 0.0 {
                springs.push(TwoNodeSpring {
                    nodes: [a, b],
                    direction,
                    stiffness: total / share,
                });
            }
        }
    }
    Ok(springs)
}
