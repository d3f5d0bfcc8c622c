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
//!   super-element only when a kept contact changed state, else the current one moved to the
//!   new equilibrium ([`super::LocalBasis::coordinates`]).

use serde::{Deserialize, Serialize};

/// How a sweep chooses its super-elements.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Strategy {
    Single,
    PerFriction,
    Adaptive,
}

impl Strategy {
    pub fn name(self) -> &'static str {
        match self {
            Strategy::Single => "single",
            Strategy::PerFriction => "per-friction",
            Strategy::Adaptive => "adaptive",
        }
    }
}

/// The state of every kept (non-swept) contact pair's points: per pair, its name and each
/// point's closed flag, as [`super::SuperElementHeader::other_contacts`] records it.
pub type ContactStates = [(String, Vec<bool>)];

/// What the adaptive strategy does at a friction value.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Decision {
    /// Keep the current super-element (moved to the new equilibrium).
    Reuse,
    /// Build a new one, and why.
    Rebuild(String),
}

/// The adaptive rule: rebuild when there is no super-element yet, or when a kept contact's
/// state differs from the one the current super-element was made with (every changed point
/// counted and named by pair in the reason).
pub fn decide(current: Option<&ContactStates>, now: &ContactStates) -> Decision {
    let Some(current) = current else {
        return Decision::Rebuild("no super-element yet".into());
    };
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
                let opened = before
                    .iter()
                    .zip(states)
                    .filter(|(b, s)| **b && !**s)
                    .count();
                let closed = before
                    .iter()
                    .zip(states)
                    .filter(|(b, s)| !**b && **s)
                    .count();
                if opened + closed > 0 {
                    changes.push(format!(
                        "pair '{name}': {closed} point(s) closed, {opened} opened"
                    ));
                }
            }
        }
    }
    for (name, _) in current {
        if !now.iter().any(|(n, _)| n == name) {
            changes.push(format!("pair '{name}' is gone"));
        }
    }
    if changes.is_empty() {
        Decision::Reuse
    } else {
        Decision::Rebuild(changes.join("; "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn states(list: &[(&str, &[bool])]) -> Vec<(String, Vec<bool>)> {
        list.iter()
            .map(|(n, s)| (n.to_string(), s.to_vec()))
            .collect()
    }

    #[test]
    fn first_point_builds() {
        assert_eq!(
            decide(None, &[]),
            Decision::Rebuild("no super-element yet".into())
        );
    }

    #[test]
    fn same_states_reuse_even_without_kept_pairs() {
        let a = states(&[("caliper/pad", &[true, false, true])]);
        assert_eq!(decide(Some(&a), &a), Decision::Reuse);
        assert_eq!(decide(Some(&[]), &[]), Decision::Reuse);
    }

    #[test]
    fn a_changed_point_rebuilds_and_says_which() {
        let before = states(&[("caliper/pad", &[true, false, true]), ("piston", &[true])]);
        let after = states(&[("caliper/pad", &[false, true, true]), ("piston", &[true])]);
        assert_eq!(
            decide(Some(&before), &after),
            Decision::Rebuild("pair 'caliper/pad': 1 point(s) closed, 1 opened".into())
        );
    }

    #[test]
    fn pairs_that_appear_or_vanish_rebuild() {
        let before = states(&[("a", &[true])]);
        let after = states(&[("b", &[true])]);
        assert_eq!(
            decide(Some(&before), &after),
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
}
