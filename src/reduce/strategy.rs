//! Which super-element serves each friction value of a sweep (METHOD.md §7 "Strategies"; the
//! paper's Tables 6-7 and Figure 15).
//!
//! A super-element holds the structure with every non-swept contact linearised at one
//! equilibrium: it stays exact for another friction value as long as those contacts keep the
//! states they had (the penalty law is linear in each state, so the kept tangent is the same
//! matrix) and only the swept (disc/pad) contact, which the assembly puts back non-linearly,
//! moves. When one of them opens, closes, sticks or slips, the super-element is a
//! linearisation about the wrong state and must be rebuilt. The three strategies:
//! - single: one super-element, made at mu_SE, for the whole sweep (the paper's first row);
//! - per-friction: a new super-element at every friction value (the paper's second row);
//! - adaptive: the reduced-interface static at each friction value (cheap beside a CEA), a new
//!   super-element only when a kept contact changed state or a slipping one turned its slip
//!   direction by more than [`MAX_SLIP_TURN_DEGREES`] ([`slip_turns`]), else the current one
//!   moved to the new equilibrium ([`super::LocalBasis::coordinates`]).
//!
//! With every pair on the boundary (`reduction.reduce_pairs`, issue 32) nothing is
//! linearised inside: every strategy's super-element is the one made at rest, and the sweep
//! solves no reduced-interface static (`crate::study::sweep`).

use crate::contact::Status;
use serde::{Deserialize, Serialize};

/// How a sweep chooses its super-elements.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Strategy {
    Single,
    PerFriction,
    Adaptive,
}

/// What a strategy does first at a friction value.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// Serve it with the current super-element as it is (no static is solved), and why.
    Keep(String),
    /// Solve the reduced-interface static at this friction value, then ask
    /// [`Strategy::decide`] whether to build there or move the current super-element.
    StaticAt(f64),
}

impl Strategy {
    /// Every strategy, in the order a study compares them.
    pub const ALL: [Strategy; 3] = [Strategy::Single, Strategy::PerFriction, Strategy::Adaptive];

    pub fn name(self) -> &'static str {
        match self {
            Strategy::Single => "single",
            Strategy::PerFriction => "per-friction",
            Strategy::Adaptive => "adaptive",
        }
    }

    /// The first step at friction value `mu`, the single strategy's mu_SE being `mu_se`
    /// and `has_current` saying whether a super-element was made before.
    pub fn step(self, mu: f64, mu_se: f64, has_current: bool) -> Step {
        match self {
            Strategy::Single if has_current => {
                Step::Keep(format!("single: the super-element made at mu_SE = {mu_se}"))
            }
            Strategy::Single => Step::StaticAt(mu_se),
            Strategy::PerFriction | Strategy::Adaptive => Step::StaticAt(mu),
        }
    }

    /// After the static at `at` ([`Step::StaticAt`]): build there, or reuse the current
    /// super-element. `current`: the kept contacts' states the current one was made with
    /// (`None`: there is none); `now`: theirs at `at` (asked for only by the adaptive rule,
    /// [`decide`]).
    pub fn decide(
        self,
        at: f64,
        current: Option<Kept<'_>>,
        now: impl FnOnce() -> (Vec<(String, Vec<Status>)>, Slipping),
    ) -> Decision {
        match self {
            Strategy::Single => Decision::Rebuild(format!("single: made at mu_SE = {at}")),
            Strategy::PerFriction => Decision::Rebuild("per-friction: made at this mu".into()),
            Strategy::Adaptive => {
                let (states, slipping) = now();
                decide(
                    current,
                    Kept {
                        states: &states,
                        slipping: &slipping,
                    },
                )
            }
        }
    }

    /// Whether a super-element may serve a later friction value too, so that a checkpoint
    /// must keep it (per-friction builds a new one at every value).
    pub fn reuses(self) -> bool {
        self != Strategy::PerFriction
    }

    /// Whether mu_SE changes what it computes: the single strategy's alone, so a new mu_SE
    /// recomputes only its stage.
    pub fn depends_on_superelement_friction(self) -> bool {
        self == Strategy::Single
    }
}

/// The state of every kept (non-swept) contact pair's points: per pair, its name and each
/// point's state (open, stick, slip), as [`super::SuperElementHeader::other_contacts`]
/// records it.
pub type ContactStates = [(String, Vec<Status>)];

/// Each kept pair's slipping points' friction forces, per pair and point (`None` where a
/// point does not slip with a force).
pub type Slipping = Vec<Vec<Option<[f64; 3]>>>;

/// What the adaptive rule weighs of the kept (non-swept) contacts at one equilibrium.
#[derive(Clone, Copy, Debug)]
pub struct Kept<'a> {
    /// Every point's state, per pair.
    pub states: &'a ContactStates,
    /// Each slipping point's friction force ([`Slipping`]); empty: none slips.
    pub slipping: &'a [Vec<Option<[f64; 3]>>],
}

/// What the adaptive strategy does at a friction value.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Decision {
    /// Keep the current super-element (moved to the new equilibrium), and why.
    Reuse(String),
    /// Build a new one, and why.
    Rebuild(String),
}

/// The turn of a kept point's slip direction past which the adaptive strategy rebuilds.
/// A point slipping on the Coulomb cone is held across its slip direction by the full stick
/// stiffness and free along it ([`crate::contact::perturbation_history`]), so a basis made
/// with one direction stands for another only as far as the two tangents agree: they differ
/// by k_t (s s^T - s' s'^T), of norm k_t sin(turn). On tiny-caliper (22 nodes per pad, 0-4
/// kHz) a basis made at mu 0.7 and reused at 0.8, where the abutments' and fingers' points
/// had turned by up to 9.8 degrees, put the first mode 9.3 % off (464 Hz for 424 Hz) with
/// estimates of 10-100, and at 0.7005 (up to 0.55 degrees) every unstable mode within 0.32 %:
/// see the test `a_reused_superelement_carries_this_frictions_tangent`.
pub const MAX_SLIP_TURN_DEGREES: f64 = 1.0;

/// How many points slipping at both equilibria turned their friction force by more than
/// `limit` degrees, and the largest turn (degrees): `then` and `now` per pair and point,
/// `None` where the point does not slip with a force.
pub fn slip_turns(
    then: &[Vec<Option<[f64; 3]>>],
    now: &[Vec<Option<[f64; 3]>>],
    limit: f64,
) -> (usize, f64) {
    let mut count = 0;
    let mut largest: f64 = 0.0;
    for (a, b) in then.iter().zip(now) {
        for (p, q) in a.iter().zip(b) {
            let (Some(p), Some(q)) = (p, q) else {
                continue;
            };
            let dot = p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
            let norms = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
                * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
            if norms == 0.0 {
                continue;
            }
            let turn = (dot / norms).clamp(-1.0, 1.0).acos().to_degrees();
            largest = largest.max(turn);
            if turn > limit {
                count += 1;
            }
        }
    }
    (count, largest)
}

/// The adaptive rule: rebuild when there is no super-element yet, when a kept contact's
/// state differs from the one the current super-element was made with (every changed point
/// counted and named by pair in the reason), or when a point slipping at both turned its
/// slip direction by more than [`MAX_SLIP_TURN_DEGREES`] (the states alone do not say
/// whether the basis still holds: a slipping point is held across its slip direction).
pub fn decide(current: Option<Kept<'_>>, now: Kept<'_>) -> Decision {
    let Some(current) = current else {
        return Decision::Rebuild("no super-element yet".into());
    };
    let (then, now_slipping) = (current.slipping, now.slipping);
    let (current, now) = (current.states, now.states);
    let mut changes = Vec::new();
    for (name, states) in now {
        match current.iter().find(|(n, _)| n == name) {
            None => changes.push(format!("pair '{name}' is new")),
            Some((_, before)) if before.len() != states.len() => changes.push(format!(
                "pair '{name}' has {} points, had {}",
                states.len(),
                before.len()
            )),
            Some((_, before)) => {
                // Every kind of change, counted by (from, to), in a fixed order.
                let mut counts = std::collections::BTreeMap::<(Status, Status), usize>::new();
                for (b, s) in before.iter().zip(states).filter(|(b, s)| b != s) {
                    *counts.entry((*b, *s)).or_default() += 1;
                }
                if !counts.is_empty() {
                    let list: Vec<String> = counts
                        .iter()
                        .map(|((b, s), n)| format!("{n} {} -> {}", b.name(), s.name()))
                        .collect();
                    changes.push(format!("pair '{name}': {}", list.join(", ")));
                }
            }
        }
    }
    for (name, _) in current {
        if !now.iter().any(|(n, _)| n == name) {
            changes.push(format!("pair '{name}' is gone"));
        }
    }
    if !changes.is_empty() {
        return Decision::Rebuild(changes.join("; "));
    }
    let limit = MAX_SLIP_TURN_DEGREES;
    let (turned, largest) = slip_turns(then, now_slipping, limit);
    if turned > 0 {
        return Decision::Rebuild(format!(
            "adaptive: {turned} slipping kept points turned their slip direction by more than \
             {limit} degrees (up to {largest:.1}) since the super-element was made"
        ));
    }
    Decision::Reuse(format!(
        "adaptive: no kept contact changed state, no slipping one turned by more than {limit} \
         degrees (up to {largest:.2})"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A turn is the angle between the two friction forces of a point slipping at both
    /// equilibria: 2 degrees counts against a 1-degree limit, 0.5 does not; a point that
    /// slips at one of them only, or has no force, is no turn.
    #[test]
    fn slip_turns_measure_the_angle_of_points_slipping_at_both() {
        let at = |degrees: f64| {
            let r = degrees.to_radians();
            Some([3.0 * r.cos(), 3.0 * r.sin(), 0.0])
        };
        let then = vec![vec![at(0.0), at(10.0), at(0.0), None], vec![]];
        let now = vec![vec![at(2.0), at(10.5), None, at(40.0)], vec![]];
        let (count, largest) = slip_turns(&then, &now, 1.0);
        assert_eq!(count, 1);
        assert!((largest - 2.0).abs() < 1e-9, "{largest}");
        assert_eq!(slip_turns(&then, &then, 1.0), (0, 0.0));
        let zero = vec![vec![Some([0.0; 3])]];
        assert_eq!(slip_turns(&zero, &zero, 1.0), (0, 0.0));
    }

    /// 'o' open, 't' stick, 's' slip.
    fn states(list: &[(&str, &str)]) -> Vec<(String, Vec<Status>)> {
        list.iter()
            .map(|(n, s)| {
                let states = s
                    .chars()
                    .map(|c| match c {
                        'o' => Status::Open,
                        't' => Status::Stick,
                        _ => Status::Slip,
                    })
                    .collect();
                (n.to_string(), states)
            })
            .collect()
    }

    /// Kept contacts with these states and no slipping force.
    fn kept(states: &ContactStates) -> Kept<'_> {
        Kept {
            states,
            slipping: &[],
        }
    }

    #[test]
    fn first_point_builds() {
        assert_eq!(
            decide(None, kept(&[])),
            Decision::Rebuild("no super-element yet".into())
        );
    }

    #[test]
    fn same_states_reuse_even_without_kept_pairs() {
        let a = states(&[("caliper/pad", "tos")]);
        assert!(matches!(
            decide(Some(kept(&a)), kept(&a)),
            Decision::Reuse(_)
        ));
        assert!(matches!(
            decide(Some(kept(&[])), kept(&[])),
            Decision::Reuse(_)
        ));
    }

    /// The same states, but a slipping point turned: 2 degrees rebuilds, 0.5 reuses and
    /// says how far.
    #[test]
    fn a_turned_slip_direction_rebuilds_where_the_states_are_the_same() {
        let a = states(&[("caliper/pad", "tss")]);
        let at = |degrees: f64| {
            let r = degrees.to_radians();
            Some([r.cos(), r.sin(), 0.0])
        };
        let then = vec![vec![None, at(0.0), at(30.0)]];
        let turned = vec![vec![None, at(2.0), at(30.0)]];
        let slightly = vec![vec![None, at(0.5), at(30.0)]];
        let make = |s: &Slipping| -> Decision {
            decide(
                Some(Kept {
                    states: &a,
                    slipping: &then,
                }),
                Kept {
                    states: &a,
                    slipping: s,
                },
            )
        };
        assert!(matches!(make(&turned), Decision::Rebuild(why) if why.contains("1 slipping")));
        assert!(matches!(make(&slightly), Decision::Reuse(why) if why.contains("0.50")));
    }

    #[test]
    fn a_changed_point_rebuilds_and_says_which() {
        let before = states(&[("caliper/pad", "tots"), ("piston", "t")]);
        let after = states(&[("caliper/pad", "otss"), ("piston", "t")]);
        assert_eq!(
            decide(Some(kept(&before)), kept(&after)),
            Decision::Rebuild(
                "pair 'caliper/pad': 1 open -> stick, 1 stick -> open, 1 stick -> slip".into()
            )
        );
        // Stick and slip matter as much as open and closed: the tangent changes.
        let slipped = states(&[("caliper/pad", "tots"), ("piston", "s")]);
        assert_eq!(
            decide(Some(kept(&before)), kept(&slipped)),
            Decision::Rebuild("pair 'piston': 1 stick -> slip".into())
        );
    }

    #[test]
    fn pairs_that_appear_or_vanish_rebuild() {
        let before = states(&[("a", "t")]);
        let after = states(&[("b", "t")]);
        assert_eq!(
            decide(Some(kept(&before)), kept(&after)),
            Decision::Rebuild("pair 'b' is new; pair 'a' is gone".into())
        );
    }

    #[test]
    fn strategy_names_are_the_study_keys() {
        for s in [Strategy::Single, Strategy::PerFriction, Strategy::Adaptive] {
            let text = toml::to_string(&std::collections::BTreeMap::from([("s", s)])).unwrap();
            assert_eq!(text.trim(), format!("s = \"{}\"", s.name()));
        }
    }

    /// The three strategies' steps and decisions: single makes one super-element at mu_SE
    /// and keeps it without a static; per-friction builds at every value; adaptive solves
    /// every static and builds only when a kept contact changed state.
    #[test]
    fn each_strategy_steps_and_decides_as_the_paper_describes() {
        let (mu, mu_se) = (0.3, 0.5);
        assert_eq!(
            Strategy::Single.step(mu, mu_se, false),
            Step::StaticAt(mu_se)
        );
        assert!(
            matches!(Strategy::Single.step(mu, mu_se, true), Step::Keep(why) if why.contains("0.5"))
        );
        for s in [Strategy::PerFriction, Strategy::Adaptive] {
            assert_eq!(s.step(mu, mu_se, false), Step::StaticAt(mu));
            assert_eq!(s.step(mu, mu_se, true), Step::StaticAt(mu));
        }
        let was = states(&[("abutment", "oot")]);
        let same = || (states(&[("abutment", "oot")]), Vec::new());
        let changed = || (states(&[("abutment", "ots")]), Vec::new());
        for s in [Strategy::Single, Strategy::PerFriction] {
            assert!(matches!(
                s.decide(mu, Some(kept(&was)), same),
                Decision::Rebuild(_)
            ));
        }
        assert!(matches!(
            Strategy::Adaptive.decide(mu, Some(kept(&was)), same),
            Decision::Reuse(_)
        ));
        assert!(matches!(
            Strategy::Adaptive.decide(mu, Some(kept(&was)), changed),
            Decision::Rebuild(why) if why.contains("abutment")
        ));
        assert!(matches!(
            Strategy::Adaptive.decide(mu, None, same),
            Decision::Rebuild(_)
        ));
        assert_eq!(
            Strategy::ALL.map(|s| (s.reuses(), s.depends_on_superelement_friction())),
            [(true, true), (false, false), (true, false)]
        );
    }
}
