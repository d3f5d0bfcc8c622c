//! The contact keywords: `*SURFACE INTERACTION`, `*SURFACE BEHAVIOR`, `*FRICTION` and
//! `*CONTACT PAIR`, read into drafts and resolved into [`SurfaceInteraction`]s and
//! [`DeckContactPair`]s once the whole deck is read.
//!
//! squeal's law is node-to-surface, small sliding, penalty (METHOD.md section 2). What would
//! change that physics and cannot be mapped onto it is refused at its line (other
//! pressure-overclosure relations, surface-to-surface discretisation, tied pairs, rough or
//! pressure-dependent friction...); what squeal reads differently is said in one warning
//! (the linear law's tension and offset fields, `SLIP TOLERANCE`, finite sliding read as
//! small sliding, the default penalty of `HARD`).

use std::collections::{BTreeMap, HashMap};

use super::drafts::*;
use super::lexer::{data_fields, Keyword, Name};
use super::lines::Loc;
use super::reader::Reader;
use super::{DeckContactPair, NormalBehavior, SlaveSurface, SurfaceInteraction};
use crate::mesh::{Mesh, MeshError};

/// `*FRICTION` parameters that change the friction law squeal has no equivalent for.
const REFUSED_FRICTION: [(&str, &str); 8] = [
    ("ROUGH", "rough (infinite) friction"),
    ("EXPONENTIALDECAY", "static-kinetic exponential decay"),
    ("ANISOTROPIC", "anisotropic friction"),
    ("TAUMAX", "a shear stress limit"),
    (
        "ELASTICSLIP",
        "an absolute elastic slip (a pressure-dependent stick stiffness)",
    ),
    ("LAGRANGE", "Lagrange-multiplier stick (exact sticking)"),
    ("USER", "a user subroutine"),
    ("DEPENDENCIES", "field-variable dependencies"),
];

/// An upper-case parameter value without blanks ("NODE TO SURFACE" -> "NODETOSURFACE").
fn squeezed(value: &str) -> String {
    value.split_whitespace().collect::<String>().to_uppercase()
}

impl Reader {
    pub(super) fn surface_interaction_keyword(
        &mut self,
        kw: &mut Keyword,
    ) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        let name = Name::new(&self.required(kw, "NAME")?);
        if let Some(previous) = self.interactions.get(&name.canon) {
            return Err(self.err(
                kw.loc,
                format!(
                    "*SURFACE INTERACTION {} is already defined at {}",
                    name.written,
                    self.lines.at(previous.loc)
                ),
            ));
        }
        self.interactions.insert(
            name.canon.clone(),
            InteractionDraft {
                written: name.written,
                normal: None,
                separation: true,
                friction: None,
                linear_extra: (None, None),
                loc: kw.loc,
            },
        );
        self.interaction = Some(name.canon);
        Ok(Block::Interaction)
    }

    /// The interaction an option keyword belongs to (it must follow `*SURFACE INTERACTION`).
    fn current_interaction(&self, kw: &Keyword) -> Result<String, MeshError> {
        self.model_only(kw)?;
        self.interaction.clone().ok_or_else(|| {
            self.err(
                kw.loc,
                format!(
                    "{} must follow a *SURFACE INTERACTION (or another option of that \
                     interaction)",
                    kw.display
                ),
            )
        })
    }

    pub(super) fn surface_behavior_keyword(
        &mut self,
        kw: &mut Keyword,
    ) -> Result<Block, MeshError> {
        let interaction = self.current_interaction(kw)?;
        let law = self
            .param(kw, "PRESSURE-OVERCLOSURE")?
            .map(|v| squeezed(&v))
            .unwrap_or_else(|| "HARD".into());
        let normal = match law.as_str() {
            "LINEAR" => NormalDraft::Linear(None),
            "HARD" => {
                self.contact_notes.add(
                    "PRESSURE-OVERCLOSURE=HARD read as squeal's penalty law with its default \
                     penalty 10 E_min / h per unit area (give PRESSURE-OVERCLOSURE=LINEAR with \
                     a slope, or a penalty in a study's [[contacts]] table of the pair's name)",
                    kw.loc,
                );
                NormalDraft::Hard
            }
            other => {
                return Err(self.err(
                    kw.loc,
                    format!(
                        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE={other} is not supported: \
                         squeal's contact law is a linear penalty (PRESSURE-OVERCLOSURE=LINEAR \
                         with its slope, or HARD)"
                    ),
                ))
            }
        };
        let bilateral = kw.flag("NOSEPARATION");
        let loc = kw.loc;
        if let Some(draft) = self.interactions.get(&interaction) {
            if let Some((_, previous)) = draft.normal {
                return Err(self.err(
                    loc,
                    format!(
                        "*SURFACE BEHAVIOR: interaction {} already has one at {}",
                        draft.written,
                        self.lines.at(previous)
                    ),
                ));
            }
        }
        if let Some(draft) = self.interactions.get_mut(&interaction) {
            draft.normal = Some((normal, loc));
            draft.separation = !bilateral;
        }
        Ok(Block::SurfaceBehavior {
            interaction,
            lines: 0,
        })
    }

    pub(super) fn surface_behavior_line(
        &mut self,
        interaction: &str,
        lines: usize,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        let Some(&(normal, _)) = self
            .interactions
            .get(interaction)
            .and_then(|d| d.normal.as_ref())
        else {
            return Ok(());
        };
        if matches!(normal, NormalDraft::Hard) {
            return Err(self.err(
                loc,
                "*SURFACE BEHAVIOR: HARD takes no data line here; to give the penalty, write \
                 PRESSURE-OVERCLOSURE=LINEAR with the slope (pressure per unit overclosure)",
            ));
        }
        if lines > 1 {
            return Err(self.err(
                loc,
                "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR: expected one data line (slope)",
            ));
        }
        let f = data_fields(text);
        if f.is_empty() || f.len() > 3 {
            return Err(self.err(
                loc,
                format!(
                    "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR: expected \"slope[, tension \
                     at large clearance, clearance]\", found {} fields",
                    f.len()
                ),
            ));
        }
        let slope = self.number(f[0], loc, "slope of the pressure-overclosure line")?;
        if slope <= 0.0 {
            return Err(self.err(
                loc,
                format!("*SURFACE BEHAVIOR: expected a slope > 0, found {slope}"),
            ));
        }
        let tension = self.optional_number(&f, 1, loc, "tension at large clearance")?;
        let clearance = self.optional_number(&f, 2, loc, "clearance factor c0")?;
        for (value, what) in [(tension, "tension at large clearance"), (clearance, "c0")] {
            if value.is_some_and(|v| !(v.is_finite() && v >= 0.0)) {
                return Err(self.err(loc, format!("*SURFACE BEHAVIOR: expected a {what} >= 0")));
            }
        }
        if tension.is_some() || clearance.is_some() {
            self.contact_notes.add(
                "the 2nd and 3rd fields of PRESSURE-OVERCLOSURE=LINEAR (CalculiX's tension \
                 at large clearance and its clearance) are used by the CalculiX contact \
                 variant only (contact_variant = \"calculix\"): squeal's law is \
                 p = slope * max(0, overclosure), no tension when open",
                loc,
            );
        }
        if let Some(draft) = self.interactions.get_mut(interaction) {
            draft.linear_extra = (tension, clearance);
        }
        if let Some(draft) = self.interactions.get_mut(interaction) {
            if let Some((n, _)) = &mut draft.normal {
                *n = NormalDraft::Linear(Some(slope));
            }
        }
        Ok(())
    }

    pub(super) fn friction_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        let interaction = self.current_interaction(kw)?;
        for (key, what) in REFUSED_FRICTION {
            if kw.flag(key) {
                return Err(self.err(
                    kw.loc,
                    format!(
                        "*FRICTION, {key}: {what} is not supported; squeal's friction is \
                         Coulomb with a constant mu (and a stick slope)"
                    ),
                ));
            }
        }
        if self.param(kw, "SLIPTOLERANCE")?.is_some() {
            self.contact_notes.add(
                "*FRICTION, SLIP TOLERANCE is not used: the stick stiffness is the stick slope \
                 of the *FRICTION data line, or the penalty / 100",
                kw.loc,
            );
        }
        let loc = kw.loc;
        if let Some(draft) = self.interactions.get(&interaction) {
            if let Some(FrictionDraft { loc: previous, .. }) = draft.friction {
                return Err(self.err(
                    loc,
                    format!(
                        "*FRICTION: interaction {} already has one at {}",
                        draft.written,
                        self.lines.at(previous)
                    ),
                ));
            }
        }
        if let Some(draft) = self.interactions.get_mut(&interaction) {
            draft.friction = Some(FrictionDraft {
                mu: None,
                stick_slope: None,
                loc,
            });
        }
        Ok(Block::Friction {
            interaction,
            lines: 0,
        })
    }

    pub(super) fn friction_line(
        &mut self,
        interaction: &str,
        lines: usize,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        if lines > 1 {
            return Err(self.err(
                loc,
                "*FRICTION: expected one data line (friction that depends on slip rate, \
                 pressure or temperature is not supported)",
            ));
        }
        let f = data_fields(text);
        if f.is_empty() || f.len() > 2 {
            return Err(self.err(
                loc,
                format!(
                    "*FRICTION: expected \"friction coefficient[, stick slope]\", found {} \
                     fields (friction that depends on slip rate, pressure or temperature is not \
                     supported)",
                    f.len()
                ),
            ));
        }
        let mu = self.number(f[0], loc, "friction coefficient")?;
        if mu < 0.0 {
            return Err(self.err(
                loc,
                format!("*FRICTION: expected a friction coefficient >= 0, found {mu}"),
            ));
        }
        let stick = self.optional_number(&f, 1, loc, "stick slope")?;
        if let Some(k) = stick {
            if k <= 0.0 {
                return Err(self.err(
                    loc,
                    format!("*FRICTION: expected a stick slope > 0, found {k}"),
                ));
            }
        }
        if let Some(draft) = self.interactions.get_mut(interaction) {
            if let Some(friction) = &mut draft.friction {
                friction.mu = Some(mu);
                friction.stick_slope = stick;
            }
        }
        Ok(())
    }

    pub(super) fn contact_pair_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        let interaction = Name::new(&self.required(kw, "INTERACTION")?);
        if let Some(kind) = self.param(kw, "TYPE")? {
            if squeezed(&kind) != "NODETOSURFACE" {
                return Err(self.err(
                    kw.loc,
                    format!(
                        "*CONTACT PAIR, TYPE={kind} is not supported: squeal's contact is \
                         node-to-surface (TYPE=NODE TO SURFACE)"
                    ),
                ));
            }
        }
        if kw.flag("TIED") {
            return Err(self.err(
                kw.loc,
                "*CONTACT PAIR, TIED is not supported (a tied pair is not a contact)",
            ));
        }
        let small_sliding = kw.flag("SMALLSLIDING");
        let adjust = match self.param(kw, "ADJUST")? {
            None => None,
            Some(value) => match super::lexer::parse_number(&value) {
                Some(d) if d >= 0.0 => Some(d),
                _ => {
                    return Err(self.err(
                        kw.loc,
                        format!(
                            "*CONTACT PAIR, ADJUST={value}: only a distance >= 0 is supported \
                             (slave nodes with a gap below it start in contact), not a node set"
                        ),
                    ))
                }
            },
        };
        Ok(Block::ContactPair {
            interaction,
            adjust,
            small_sliding,
        })
    }

    pub(super) fn contact_pair_line(
        &mut self,
        interaction: Name,
        adjust: Option<f64>,
        small_sliding: bool,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.len() != 2 || f.iter().any(|x| x.is_empty()) {
            return Err(self.err(
                loc,
                "*CONTACT PAIR: expected \"slave surface, master surface\"",
            ));
        }
        if !small_sliding {
            self.contact_notes.add(
                "*CONTACT PAIR without SMALL SLIDING read as small sliding (squeal keeps each \
                 slave node's master point and normal of the reference configuration)",
                loc,
            );
        }
        self.contact_pairs.push(ContactPairDraft {
            interaction,
            slave: Name::new(f[0]),
            master: Name::new(f[1]),
            adjust,
            loc,
        });
        Ok(())
    }

    // --- resolution ---------------------------------------------------------------------

    /// The interactions, checked: a LINEAR law has its slope, a friction its data line.
    pub(super) fn resolve_interactions(
        &self,
    ) -> Result<BTreeMap<String, SurfaceInteraction>, MeshError> {
        let mut out = BTreeMap::new();
        for (canon, draft) in &self.interactions {
            let normal =
                match draft.normal {
                    None | Some((NormalDraft::Hard, _)) => NormalBehavior::Hard,
                    Some((NormalDraft::Linear(Some(slope)), _)) => NormalBehavior::Linear { slope },
                    Some((NormalDraft::Linear(None), loc)) => return Err(self.err(
                        loc,
                        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR needs a data line with \
                         the slope (pressure per unit overclosure)",
                    )),
                };
            let (friction, stick_slope) = match draft.friction {
                None => (0.0, None),
                Some(FrictionDraft {
                    mu: Some(mu),
                    stick_slope,
                    ..
                }) => (mu, stick_slope),
                Some(FrictionDraft { mu: None, loc, .. }) => {
                    return Err(self.err(
                        loc,
                        "*FRICTION needs a data line with the friction coefficient",
                    ))
                }
            };
            out.insert(
                canon.clone(),
                SurfaceInteraction {
                    name: canon.clone(),
                    normal,
                    separation: draft.separation,
                    friction,
                    stick_slope,
                    tension: draft.linear_extra.0,
                    clearance_factor: draft.linear_extra.1,
                    source: self.lines.source(draft.loc),
                },
            );
        }
        Ok(out)
    }

    /// The areas of the nodes of a node-based surface: 1 unless a data line gave one (the
    /// last line naming a node wins).
    fn node_surface_areas(&self, canon: &str, mesh: &Mesh) -> Vec<(usize, f64)> {
        let mut area: BTreeMap<usize, f64> =
            mesh.node_sets[canon].iter().map(|&n| (n, 1.0)).collect();
        for (surface, members, value) in &self.node_areas {
            if surface != canon {
                continue;
            }
            let listed = members
                .members()
                .iter()
                .filter_map(|m| self.node_index.get(&m.label).copied());
            let generated = members
                .ranges()
                .iter()
                .flat_map(|r| r.existing(&self.node_index));
            for n in listed.chain(generated).collect::<Vec<_>>() {
                area.insert(n, *value);
            }
        }
        area.into_iter().collect()
    }

    /// The pairs, each surface and interaction looked up and named at the pair's line; then
    /// every interaction must be used by a pair.
    pub(super) fn resolve_contact_pairs(
        &self,
        mesh: &Mesh,
        interactions: &BTreeMap<String, SurfaceInteraction>,
    ) -> Result<Vec<DeckContactPair>, MeshError> {
        let mut out = Vec::with_capacity(self.contact_pairs.len());
        let mut seen: HashMap<String, Loc> = HashMap::new();
        for p in &self.contact_pairs {
            if !interactions.contains_key(&p.interaction.canon) {
                return Err(self.err(
                    p.loc,
                    format!(
                        "*CONTACT PAIR: interaction {} is not defined (*SURFACE INTERACTION, \
                         NAME={})",
                        p.interaction.written, p.interaction.written
                    ),
                ));
            }
            let slave = if mesh.surfaces.contains_key(&p.slave.canon) {
                SlaveSurface::Faces(p.slave.canon.clone())
            } else if self.node_surfaces.contains_key(&p.slave.canon) {
                SlaveSurface::Nodes {
                    name: p.slave.canon.clone(),
                    nodes: self.node_surface_areas(&p.slave.canon, mesh),
                }
            } else {
                return Err(self.err(
                    p.loc,
                    format!(
                        "*CONTACT PAIR: slave surface {} is not defined",
                        p.slave.written
                    ),
                ));
            };
            if !mesh.surfaces.contains_key(&p.master.canon) {
                let why = if self.node_surfaces.contains_key(&p.master.canon) {
                    "is node-based; a master surface needs faces (TYPE=ELEMENT)"
                } else {
                    "is not defined"
                };
                return Err(self.err(
                    p.loc,
                    format!("*CONTACT PAIR: master surface {} {why}", p.master.written),
                ));
            }
            let name = format!("{}:{}", p.slave.canon, p.master.canon);
            if let Some(previous) = seen.insert(name.clone(), p.loc) {
                return Err(self.err(
                    p.loc,
                    format!(
                        "*CONTACT PAIR: the pair {} {} is already defined at {}",
                        p.slave.written,
                        p.master.written,
                        self.lines.at(previous)
                    ),
                ));
            }
            out.push(DeckContactPair {
                name,
                interaction: p.interaction.canon.clone(),
                slave,
                master: p.master.canon.clone(),
                adjust: p.adjust,
                source: self.lines.source(p.loc),
            });
        }
        // An interaction no pair uses is a pair left out of the deck, or a misspelt name.
        for (canon, draft) in &self.interactions {
            if !out.iter().any(|p| &p.interaction == canon) {
                return Err(self.err(
                    draft.loc,
                    format!(
                        "*SURFACE INTERACTION {} is used by no *CONTACT PAIR (remove it, or \
                         name it with INTERACTION= on a pair)",
                        draft.written
                    ),
                ));
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::super::{NormalBehavior, SlaveSurface};

    /// One tet (nodes 11..20, element 7) with two element-based surfaces and a node-based one.
    fn base() -> String {
        format!(
            "{}*SURFACE, NAME=Pad\n7, S1\n*SURFACE, NAME=Disc\n7, S2\n\
             *SURFACE, NAME=Tips, TYPE=NODE\nNALL\n11, 2.5\n",
            one_tet()
        )
    }

    fn lines_of(text: &str) -> usize {
        text.lines().count()
    }

    #[test]
    fn interactions_and_pairs_are_read_with_their_laws() {
        let text = format!(
            "{}*SURFACE INTERACTION, NAME=Brake\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n\
             2e12\n*FRICTION\n0.4, 1e10\n*SURFACE INTERACTION, NAME=Hold\n\
             *SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD, NO SEPARATION\n\
             *CONTACT PAIR, INTERACTION=brake, TYPE=NODE TO SURFACE, SMALL SLIDING, ADJUST=1e-6\n\
             Pad, Disc\n*CONTACT PAIR, INTERACTION=HOLD, SMALL SLIDING\nTips, Disc\n",
            base()
        );
        let deck = read_text("contact-read", &text).unwrap();
        let brake = &deck.interactions["BRAKE"];
        assert_eq!(brake.normal, NormalBehavior::Linear { slope: 2e12 });
        assert!(brake.separation);
        assert_eq!((brake.friction, brake.stick_slope), (0.4, Some(1e10)));
        let hold = &deck.interactions["HOLD"];
        assert_eq!(hold.normal, NormalBehavior::Hard);
        assert!(!hold.separation, "NO SEPARATION");
        assert_eq!((hold.friction, hold.stick_slope), (0.0, None));
        assert_eq!(deck.contact_pairs.len(), 2);
        let (a, b) = (&deck.contact_pairs[0], &deck.contact_pairs[1]);
        assert_eq!(a.name, "PAD:DISC");
        assert_eq!(a.interaction, "BRAKE");
        assert_eq!(a.slave, SlaveSurface::Faces("PAD".into()));
        assert_eq!(a.master, "DISC");
        assert_eq!(a.adjust, Some(1e-6));
        assert_eq!(a.source.line, lines_of(&text) - 2);
        assert_eq!(b.name, "TIPS:DISC");
        // Node 11 (index 0) has the area of its line; the others Abaqus' 1.
        let SlaveSurface::Nodes { name, nodes } = &b.slave else {
            panic!("node-based slave expected: {:?}", b.slave)
        };
        assert_eq!(name, "TIPS");
        assert_eq!(nodes.len(), 10);
        assert_eq!(nodes[0], (0, 2.5));
        assert!(nodes[1..].iter().all(|&(_, a)| a == 1.0));
        // HARD's default penalty is said, in one warning with the other differences.
        let notes: Vec<&String> = deck
            .warnings
            .iter()
            .filter(|w| w.contains("squeal's law"))
            .collect();
        assert_eq!(notes.len(), 1, "{:?}", deck.warnings);
        assert!(notes[0].contains("HARD"), "{}", notes[0]);
    }

    #[test]
    fn differences_from_the_deck_law_are_listed_in_one_warning() {
        let text = format!(
            "{}*SURFACE INTERACTION, NAME=I\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n\
             1e12, 3.0, 1e-5\n*FRICTION, SLIP TOLERANCE=0.005\n0.3\n\
             *CONTACT PAIR, INTERACTION=I, TYPE=NODE TO SURFACE\nPad, Disc\n",
            base()
        );
        let deck = read_text("contact-notes", &text).unwrap();
        let notes: Vec<&String> = deck
            .warnings
            .iter()
            .filter(|w| w.contains("squeal's law"))
            .collect();
        assert_eq!(notes.len(), 1, "{:?}", deck.warnings);
        let w = notes[0];
        for said in [
            "tension at large clearance",
            "SLIP TOLERANCE",
            "small sliding",
        ] {
            assert!(w.contains(said), "{said}: {w}");
        }
        assert!(w.contains("deck.inp:"), "{w}");
        assert_eq!(deck.interactions["I"].friction, 0.3);
    }

    /// Each refused input, the line it is named at, and what the message must say.
    #[test]
    fn refusals_name_the_file_line_and_keyword() {
        let pair = "*CONTACT PAIR, INTERACTION=I, TYPE=NODE TO SURFACE\nPad, Disc\n";
        let linear =
            "*SURFACE INTERACTION, NAME=I\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1e12\n";
        let cases: Vec<(String, usize, &str)> = vec![
            (
                "*SURFACE INTERACTION, NAME=I\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=EXPONENTIAL\n1e-5, 1e6\n".into(),
                2,
                "PRESSURE-OVERCLOSURE=EXPONENTIAL is not supported",
            ),
            (
                "*SURFACE INTERACTION, NAME=I\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=TIED\n".into(),
                2,
                "PRESSURE-OVERCLOSURE=TIED",
            ),
            (
                "*SURFACE INTERACTION, NAME=I\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n".to_string() + pair,
                2,
                "needs a data line with the slope",
            ),
            (
                "*SURFACE INTERACTION, NAME=I\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n-1e12\n".into(),
                3,
                "slope > 0",
            ),
            (
                "*SURFACE INTERACTION, NAME=I\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD\n1e12\n".into(),
                3,
                "HARD takes no data line",
            ),
            ("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1e12\n".into(), 1, "must follow a *SURFACE INTERACTION"),
            (format!("{linear}*FRICTION, ROUGH\n"), 4, "*FRICTION, ROUGH"),
            (format!("{linear}*FRICTION, EXPONENTIAL DECAY\n0.5\n"), 4, "EXPONENTIALDECAY"),
            (format!("{linear}*FRICTION\n0.3\n0.2, 0.0, 1e6\n"), 6, "expected one data line"),
            (format!("{linear}*FRICTION\n0.3, 1e10, 5.0\n"), 5, "found 3 fields"),
            (format!("{linear}*FRICTION\n-0.1\n"), 5, "friction coefficient >= 0"),
            (format!("{linear}*FRICTION\n{pair}"), 4, "*FRICTION needs a data line"),
            (
                format!("{linear}*CONTACT PAIR, INTERACTION=I, TYPE=SURFACE TO SURFACE\nPad, Disc\n"),
                4,
                "TYPE=SURFACE TO SURFACE is not supported",
            ),
            (format!("{linear}*CONTACT PAIR, INTERACTION=I, TIED\nPad, Disc\n"), 4, "TIED"),
            (
                format!("{linear}*CONTACT PAIR, INTERACTION=I, ADJUST=Tips\nPad, Disc\n"),
                4,
                "ADJUST=Tips: only a distance",
            ),
            (format!("{linear}*CONTACT PAIR, INTERACTION=I\nPad\n"), 5, "\"slave surface, master surface\""),
            (linear.to_string(), 1, "used by no *CONTACT PAIR"),
            (format!("{linear}*CONTACT PAIR, INTERACTION=Other\nPad, Disc\n"), 5, "interaction Other is not defined"),
            (format!("{linear}*CONTACT PAIR, INTERACTION=I\nGhost, Disc\n"), 5, "slave surface Ghost is not defined"),
            (format!("{linear}*CONTACT PAIR, INTERACTION=I\nPad, Nowhere\n"), 5, "master surface Nowhere is not defined"),
            (format!("{linear}*CONTACT PAIR, INTERACTION=I\nPad, Tips\n"), 5, "master surface Tips is node-based"),
            (format!("{linear}{pair}Pad, Disc\n"), 6, "already defined at"),
            (format!("{linear}*SURFACE INTERACTION, NAME=i\n"), 4, "already defined at"),
            (
                format!("{linear}{pair}*STEP\n*STATIC\n*CONTACT PAIR, INTERACTION=I\nPad, Disc\n*END STEP\n"),
                8,
                "model data",
            ),
        ];
        let base = base();
        let offset = lines_of(&base);
        for (k, (tail, line, said)) in cases.iter().enumerate() {
            let (file, at, message) = parse_error(read_text(
                &format!("contact-err-{k}"),
                &format!("{base}{tail}"),
            ));
            assert!(file.ends_with("deck.inp"), "{file:?}");
            assert_eq!(at, offset + line, "case {k}: {message}");
            assert!(
                message.contains(said),
                "case {k}: expected \"{said}\" in: {message}"
            );
        }
    }

    #[test]
    fn a_node_surface_area_must_be_positive() {
        let text = format!("{}*SURFACE, NAME=T, TYPE=NODE\n11, 0\n", one_tet());
        let (_, line, message) = parse_error(read_text("contact-area", &text));
        assert_eq!(line, lines_of(&text));
        assert!(message.contains("area > 0"), "{message}");
    }
}
