//! `*MOTION, TYPE=VELOCITY` (Abaqus: a transport velocity given as a predefined field, the
//! way brake-squeal decks give the disc's rotation for steady-sliding friction): read into
//! drafts, resolved into [`Motion`]s once the whole deck is read.
//!
//! Data lines (Abaqus Keywords Reference, `*MOTION`):
//!
//! ```text
//!   ROTATION (DEFINITION=COORDINATES, the default):
//!       node set or node, angular speed (radians per time), a_x, a_y, a_z, b_x, b_y, b_z
//!   ROTATION, DEFINITION=NODES:
//!       node set or node, angular speed, node a, node b
//!   TRANSLATION (the default):
//!       node set or node, first DOF, last DOF (blank: the first), speed
//! ```
//!
//! The rotation is about the axis from a to b (right-handed, positive speed). Translation
//! lines of one keyword on one target give the components of one velocity. What squeal
//! keeps is the direction of the velocity field: steady-sliding friction acts along it with
//! any speed, so an `AMPLITUDE` (which scales the speed) changes nothing and is said in the
//! contact warning; `TYPE=DISPLACEMENT` (a prescribed rigid motion, not a transport
//! velocity) and `USER` are refused at their line.

use std::collections::BTreeMap;

use super::drafts::*;
use super::lexer::{data_fields, looks_numeric, Keyword, Name};
use super::lines::Loc;
use super::reader::Reader;
use super::{Motion, MotionKind};
use crate::mesh::{Mesh, MeshError};

/// A point of a rotation axis as written.
pub(super) enum AxisPoint {
    At([f64; 3]),
    Node(i64),
}

pub(super) enum MotionDraftKind {
    Rotation {
        speed: f64,
        from: AxisPoint,
        to: AxisPoint,
    },
    /// One translation line: the speed on DOFs `first..=last` (1-based).
    Translation { first: u8, last: u8, speed: f64 },
}

/// One `*MOTION` data line.
pub(super) struct MotionDraft {
    pub(super) target: NodeRef,
    pub(super) kind: MotionDraftKind,
    /// Which `*MOTION` keyword it belongs to (translation lines of one keyword merge).
    pub(super) keyword: Loc,
    /// The step it was given in (an index into the steps read so far), `None`: model data.
    pub(super) step: Option<usize>,
    pub(super) loc: Loc,
}

impl Reader {
    pub(super) fn motion_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        if kw.flag("USER") {
            return Err(self.err(
                kw.loc,
                "*MOTION, USER (velocities from user subroutine UMOTION) is not supported: give \
                 the rotation or translation on the data lines",
            ));
        }
        let rotation = kw.flag("ROTATION");
        let translation = kw.flag("TRANSLATION");
        if rotation && translation {
            return Err(self.err(
                kw.loc,
                "*MOTION: ROTATION and TRANSLATION exclude each other",
            ));
        }
        if let Some(kind) = self.param(kw, "TYPE")? {
            if !kind.eq_ignore_ascii_case("VELOCITY") {
                return Err(self.err(
                    kw.loc,
                    format!(
                        "*MOTION, TYPE={kind} is not supported: squeal reads *MOTION as the \
                         transport velocity of a sliding body (TYPE=VELOCITY, the only type of \
                         a static analysis), whose direction gives the sliding direction of its \
                         contact pairs"
                    ),
                ));
            }
        }
        let by_nodes = match self.param(kw, "DEFINITION")? {
            None => false,
            Some(d) if d.eq_ignore_ascii_case("COORDINATES") => false,
            Some(d) if d.eq_ignore_ascii_case("NODES") => true,
            Some(d) => {
                return Err(self.err(
                    kw.loc,
                    format!("*MOTION: expected DEFINITION=COORDINATES or NODES, found {d}"),
                ))
            }
        };
        if by_nodes && !rotation {
            return Err(self.err(
                kw.loc,
                "*MOTION: DEFINITION=NODES defines a rotation axis; it needs ROTATION",
            ));
        }
        if self.param(kw, "AMPLITUDE")?.is_some() {
            self.contact_notes.add(
                "*MOTION, AMPLITUDE only scales the speed: steady-sliding friction uses the \
                 direction of the motion, not its speed",
                kw.loc,
            );
        }
        Ok(Block::Motion {
            rotation,
            by_nodes,
            keyword: kw.loc,
        })
    }

    pub(super) fn motion_line(
        &mut self,
        rotation: bool,
        by_nodes: bool,
        keyword: Loc,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        let f = data_fields(text);
        let expected = match (rotation, by_nodes) {
            (true, false) => (
                8,
                "node set or node, angular speed, a_x, a_y, a_z, b_x, b_y, b_z",
            ),
            (true, true) => (4, "node set or node, angular speed, node a, node b"),
            (false, _) => (4, "node set or node, first DOF, last DOF, speed"),
        };
        let translation_short = !rotation && f.len() == 3;
        if f.len() != expected.0 && !translation_short {
            return Err(self.err(
                loc,
                format!(
                    "*MOTION: expected \"{}\", found {} fields",
                    expected.1,
                    f.len()
                ),
            ));
        }
        let target = if f[0].is_empty() {
            return Err(self.err(loc, "*MOTION: expected a node set or node, found a blank"));
        } else if looks_numeric(f[0]) {
            NodeRef::Node(self.label(f[0], loc, "node label")?)
        } else {
            NodeRef::Set(Name::new(f[0]))
        };
        let kind = if rotation {
            let speed = self.number(f[1], loc, "angular speed")?;
            if speed == 0.0 || !speed.is_finite() {
                return Err(self.err(
                    loc,
                    format!(
                        "*MOTION: an angular speed of {speed} gives no sliding direction (give \
                         the disc's speed, radians per time; its sign is the sense of rotation)"
                    ),
                ));
            }
            let (from, to) = if by_nodes {
                (
                    AxisPoint::Node(self.label(f[2], loc, "node a of the axis")?),
                    AxisPoint::Node(self.label(f[3], loc, "node b of the axis")?),
                )
            } else {
                let mut p = [0.0; 6];
                for (k, (v, what)) in p
                    .iter_mut()
                    .zip(["a_x", "a_y", "a_z", "b_x", "b_y", "b_z"])
                    .enumerate()
                {
                    *v = self.number(f[2 + k], loc, &format!("{what} of the rotation axis"))?;
                }
                if p[..3] == p[3..] {
                    return Err(self.err(
                        loc,
                        "*MOTION: the axis points a and b are the same point (no axis)",
                    ));
                }
                (
                    AxisPoint::At([p[0], p[1], p[2]]),
                    AxisPoint::At([p[3], p[4], p[5]]),
                )
            };
            MotionDraftKind::Rotation { speed, from, to }
        } else {
            let dof = |s: &str, what: &str| -> Result<u8, MeshError> {
                match s.parse::<u8>() {
                    Ok(d @ 1..=3) => Ok(d),
                    _ => Err(self.err(
                        loc,
                        format!(
                            "*MOTION, TRANSLATION: expected the {what} DOF 1, 2 or 3, found \
                             \"{s}\" (a rotation is *MOTION, ROTATION)"
                        ),
                    )),
                }
            };
            let first = dof(f[1], "first")?;
            let (last, speed_field) = if f.len() == 3 {
                (first, f[2])
            } else if f[2].is_empty() {
                (first, f[3])
            } else {
                (dof(f[2], "last")?, f[3])
            };
            if last < first {
                return Err(self.err(
                    loc,
                    format!("*MOTION: the last DOF {last} is below the first {first}"),
                ));
            }
            let speed = self.number(speed_field, loc, "speed")?;
            if !speed.is_finite() {
                return Err(self.err(loc, format!("*MOTION: speed {speed} is not finite")));
            }
            MotionDraftKind::Translation { first, last, speed }
        };
        let step = self.step.as_ref().map(|_| self.steps.len());
        self.motions.push(MotionDraft {
            target,
            kind,
            keyword,
            step,
            loc,
        });
        Ok(())
    }

    /// The motions, resolved: per step (`None`: model data), in the order written; the
    /// translation lines of one keyword on one target merged into one velocity.
    pub(super) fn resolve_motions(
        &self,
        mesh: &Mesh,
    ) -> Result<BTreeMap<Option<usize>, Vec<Motion>>, MeshError> {
        let mut out: BTreeMap<Option<usize>, Vec<Motion>> = BTreeMap::new();
        // (keyword, target) of each merged translation -> its place in `out[step]`.
        let mut merged: BTreeMap<(u32, u32, String), (Option<usize>, usize)> = BTreeMap::new();
        for d in &self.motions {
            let (target, nodes) = self.nodes_of(&d.target, d.loc, "*MOTION", mesh)?;
            if nodes.is_empty() {
                return Err(self.err(d.loc, "*MOTION: the node set is empty"));
            }
            let list = out.entry(d.step).or_default();
            match &d.kind {
                MotionDraftKind::Rotation { speed, from, to } => {
                    let point = |p: &AxisPoint| -> Result<[f64; 3], MeshError> {
                        match p {
                            AxisPoint::At(x) => Ok(*x),
                            AxisPoint::Node(label) => match self.node_index.get(label) {
                                Some(&n) => Ok(mesh.nodes[n]),
                                None => Err(self.err(
                                    d.loc,
                                    format!("*MOTION: axis node {label} is not defined"),
                                )),
                            },
                        }
                    };
                    let (from, to) = (point(from)?, point(to)?);
                    if from == to {
                        return Err(self.err(
                            d.loc,
                            "*MOTION: the axis nodes a and b are at the same place (no axis)",
                        ));
                    }
                    list.push(Motion {
                        target,
                        nodes,
                        kind: MotionKind::Rotation {
                            speed: *speed,
                            from,
                            to,
                        },
                        source: self.lines.source(d.loc),
                    });
                }
                MotionDraftKind::Translation { first, last, speed } => {
                    let key = (d.keyword.file, d.keyword.line, format!("{target:?}"));
                    let k = match merged.get(&key) {
                        Some(&(_, k)) => k,
                        None => {
                            list.push(Motion {
                                target,
                                nodes,
                                kind: MotionKind::Translation { velocity: [0.0; 3] },
                                source: self.lines.source(d.loc),
                            });
                            merged.insert(key, (d.step, list.len() - 1));
                            list.len() - 1
                        }
                    };
                    if let MotionKind::Translation { velocity } = &mut list[k].kind {
                        for dof in *first..=*last {
                            velocity[usize::from(dof) - 1] = *speed;
                        }
                    }
                }
            }
        }
        for (&(file, line, _), (step, k)) in &merged {
            let at = Loc { file, line };
            let zero = out
                .get(step)
                .and_then(|list| list.get(*k))
                .is_some_and(|m| m.kind == MotionKind::Translation { velocity: [0.0; 3] });
            if zero {
                return Err(self.err(
                    at,
                    "*MOTION, TRANSLATION: a zero velocity gives no sliding direction",
                ));
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::super::{MotionKind, NodeTarget};

    #[test]
    fn rotations_and_translations_are_read_per_step() {
        let text = format!(
            "{}*MOTION, ROTATION, TYPE=VELOCITY\nNALL, -5.0, 0., 0., 0., 0., 0., 2.\n\
             *STEP\n*STATIC\n*MOTION, TRANSLATION\nNALL, 1, 2, 0.5\nNALL, 3,, -2.0\n11, 1, 1, 1.\n\
             *MOTION, ROTATION, DEFINITION=NODES, TYPE=VELOCITY\n11, 3.0, 12, 13\n*END STEP\n",
            one_tet()
        );
        let deck = read_text("motion-read", &text).unwrap();
        assert_eq!(deck.motions.len(), 1);
        let m = &deck.motions[0];
        assert_eq!(m.target, NodeTarget::Set("NALL".into()));
        assert_eq!(m.nodes.len(), 10);
        assert_eq!(
            m.kind,
            MotionKind::Rotation {
                speed: -5.0,
                from: [0.0; 3],
                to: [0.0, 0.0, 2.0]
            }
        );
        let step = &deck.steps[0].motions;
        assert_eq!(step.len(), 3, "{step:?}");
        // The two NALL lines of one keyword make one velocity; node 11 its own.
        assert_eq!(
            step[0].kind,
            MotionKind::Translation {
                velocity: [0.5, 0.5, -2.0]
            }
        );
        assert_eq!(step[1].target, NodeTarget::Node(11));
        assert_eq!(
            step[2].kind,
            MotionKind::Rotation {
                speed: 3.0,
                from: [1.0, 0.0, 0.0],
                to: [0.0, 1.0, 0.0]
            }
        );
    }

    #[test]
    fn bad_motions_are_refused_at_their_line() {
        let n = one_tet().lines().count();
        for (tail, line, said) in [
            (
                "*MOTION, ROTATION\nGHOST, 1., 0, 0, 0, 0, 0, 1\n",
                n + 2,
                "node set GHOST is not defined",
            ),
            (
                "*MOTION, ROTATION\n99, 1., 0, 0, 0, 0, 0, 1\n",
                n + 2,
                "node 99 is not defined",
            ),
            (
                "*MOTION, ROTATION\nNALL, 0., 0, 0, 0, 0, 0, 1\n",
                n + 2,
                "angular speed of 0",
            ),
            (
                "*MOTION, ROTATION\nNALL, 1., 0, 0, 1, 0, 0, 1\n",
                n + 2,
                "same point",
            ),
            (
                "*MOTION, ROTATION\nNALL, 1., 0, 0, 0\n",
                n + 2,
                "found 5 fields",
            ),
            (
                "*MOTION, ROTATION, TYPE=DISPLACEMENT\n",
                n + 1,
                "TYPE=DISPLACEMENT is not supported",
            ),
            ("*MOTION, USER\n", n + 1, "UMOTION"),
            (
                "*MOTION, TRANSLATION\nNALL, 4, 4, 1.\n",
                n + 2,
                "DOF 1, 2 or 3",
            ),
            (
                "*MOTION, TRANSLATION\nNALL, 1, 1, 0.\n",
                n + 1,
                "zero velocity",
            ),
            (
                "*MOTION, ROTATION, DEFINITION=NODES\nNALL, 1., 11, 77\n",
                n + 2,
                "axis node 77",
            ),
            ("*MOTION, DEFINITION=NODES\n", n + 1, "needs ROTATION"),
            (
                "*CHANGE FRICTION, INTERACTION=I\n",
                n + 1,
                "changing a surface interaction",
            ),
        ] {
            let (_, at, message) =
                parse_error(read_text("motion-err", &format!("{}{tail}", one_tet())));
            assert_eq!(at, line, "{tail}: {message}");
            assert!(message.contains(said), "{tail}: {message}");
        }
    }
}
