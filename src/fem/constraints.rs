//! Linear multi-point constraints on displacement components: `sum_k a_k u_k = value`, one
//! component of which (the dependent DOF) is eliminated, so that u = C u_free + lambda g with
//! u_free the remaining components (METHOD: applied exactly, not by penalty). A deck's
//! `*EQUATION`, a distributing coupling's reference node, a support or a prescribed
//! displacement in a local (`*TRANSFORM`) direction and a nonzero prescribed displacement
//! are each one such constraint; supports at zero in global directions stay eliminated DOFs
//! ([`super::Support`]) and drop out of every constraint as zeros.
//!
//! [`resolve`] picks the dependent DOFs and writes each dependent as a combination of
//! independent DOFs only (chains substituted), checking what Abaqus refuses: a DOF made
//! dependent twice, a dependent that a support also holds, and constraints that leave no
//! DOF to eliminate (redundant or contradictory ones).

use std::collections::{BTreeMap, BTreeSet};

use super::Support;

/// A displacement component: (node index, component 0 = x, 1 = y, 2 = z).
pub type Dof = (usize, usize);

/// Which DOF a constraint eliminates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Pivot {
    /// This one, as Abaqus's `*EQUATION` eliminates its first term's DOF: refused when it
    /// is already dependent or supported.
    Fixed(Dof),
    /// Any component of this node that the constraint involves (a direction that is not a
    /// global axis: a support in a `*TRANSFORM` system); the largest coefficient, once the
    /// constraints before it are substituted.
    Node(usize),
    /// This one when it is free; when a support or an earlier constraint already holds it
    /// (a distributing coupling's reference node driven by a `*BOUNDARY`), the DOF of the
    /// largest coefficient among the others.
    Prefer(Dof),
}

/// `sum_k a_k u_k = value` (the value at load factor 1: prescribed displacements grow with
/// the load in a static solve, and are zero perturbations in modes and CEA).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LinearConstraint {
    /// (node, component, a_k).
    pub terms: Vec<(usize, usize, f64)>,
    pub value: f64,
    pub pivot: Pivot,
    /// Where it came from, for messages: "deck.inp:12 (*EQUATION)".
    pub source: String,
}

/// A dependent DOF as independent DOFs: `u_dependent = sum_k c_k u_k + offset`.
#[derive(Clone, Debug, PartialEq)]
pub struct Dependent {
    pub terms: Vec<(Dof, f64)>,
    pub offset: f64,
    /// The constraint's source.
    pub source: String,
}

/// Every constraint solved for its dependent DOF, over independent DOFs only.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Resolved {
    pub dependents: BTreeMap<Dof, Dependent>,
}

impl Resolved {
    /// Whether any dependent has a nonzero offset (a prescribed displacement).
    pub fn has_offsets(&self) -> bool {
        self.dependents.values().any(|d| d.offset != 0.0)
    }
}

/// Why constraints cannot be applied.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConstraintError {
    #[error("{at}: node index {node} is not in the model")]
    NodeOutside { at: String, node: usize },
    #[error("{at}: its coefficient {coefficient} of the dependent DOF (node {node}, DOF {dof}) cannot be eliminated: it is zero")]
    ZeroPivot {
        at: String,
        node: String,
        dof: usize,
        coefficient: f64,
    },
    #[error("{at}: the dependent DOF {dof} of node {node} is already the dependent DOF of the constraint at {first} (Abaqus refuses a DOF eliminated twice: make it an independent term of one of them)")]
    DependentTwice {
        at: String,
        first: String,
        node: String,
        dof: usize,
    },
    #[error("{at}: the dependent DOF {dof} of node {node} is also held by the support '{support}' (Abaqus refuses a boundary condition on an eliminated DOF: hold another DOF of the equation, or drop the support)")]
    DependentSupported {
        at: String,
        support: String,
        node: String,
        dof: usize,
    },
    #[error("{at}: the DOF {dof} of node {node} appears in the constraint as its dependent DOF and again as an independent term")]
    DependentRepeated {
        at: String,
        node: String,
        dof: usize,
    },
    #[error("{at}: no DOF is left to eliminate: {why}")]
    NothingLeft { at: String, why: String },
}

/// Coefficients below this fraction of a constraint's largest one are round-off of the
/// substitutions (a tie of two nodes substituted into its own mirror image): they are
/// dropped rather than made pivots or kept as near-zero couplings.
const NEGLIGIBLE: f64 = 1e-13;

/// Solves `constraints` for their dependent DOFs, in order: each constraint has the
/// dependents found before it substituted, picks its pivot, and is substituted back into the
/// earlier ones, so every dependent ends up over independent DOFs (neither dependent nor
/// supported). `labels` names nodes in messages (the file's labels), `nodes` counts them.
pub fn resolve(
    constraints: &[LinearConstraint],
    supports: &[Support],
    nodes: usize,
    labels: &dyn Fn(usize) -> String,
) -> Result<Resolved, ConstraintError> {
    let mut held: BTreeMap<Dof, &str> = BTreeMap::new();
    for s in supports {
        for &n in &s.nodes {
            for (c, &h) in s.components.iter().enumerate() {
                if h {
                    held.entry((n, c)).or_insert(&s.name);
                }
            }
        }
    }
    let mut dependents: BTreeMap<Dof, Dependent> = BTreeMap::new();
    // Which dependents mention an independent DOF (for the back-substitution).
    let mut users: BTreeMap<Dof, BTreeSet<Dof>> = BTreeMap::new();
    for constraint in constraints {
        let source = &constraint.source;
        for &(n, c, _) in &constraint.terms {
            if n >= nodes || c > 2 {
                return Err(ConstraintError::NodeOutside {
                    at: source.clone(),
                    node: n,
                });
            }
        }
        if let Pivot::Fixed(dof) = constraint.pivot {
            if let Some(support) = held.get(&dof) {
                return Err(ConstraintError::DependentSupported {
                    at: source.clone(),
                    support: support.to_string(),
                    node: labels(dof.0),
                    dof: dof.1 + 1,
                });
            }
            if let Some(first) = dependents.get(&dof) {
                return Err(ConstraintError::DependentTwice {
                    at: source.clone(),
                    first: first.source.clone(),
                    node: labels(dof.0),
                    dof: dof.1 + 1,
                });
            }
            let mentions = constraint
                .terms
                .iter()
                .filter(|&&(n, c, _)| (n, c) == dof)
                .count();
            if mentions > 1 {
                return Err(ConstraintError::DependentRepeated {
                    at: source.clone(),
                    node: labels(dof.0),
                    dof: dof.1 + 1,
                });
            }
        }
        // The constraint over independent DOFs: sum a_k u_k = value.
        let mut sum: BTreeMap<Dof, f64> = BTreeMap::new();
        let mut value = constraint.value;
        for &(n, c, a) in &constraint.terms {
            let dof = (n, c);
            if held.contains_key(&dof) {
                continue;
            }
            match dependents.get(&dof) {
                Some(d) => {
                    value -= a * d.offset;
                    for &(k, ck) in &d.terms {
                        *sum.entry(k).or_insert(0.0) += a * ck;
                    }
                }
                None => *sum.entry(dof).or_insert(0.0) += a,
            }
        }
        let largest = sum.values().fold(0.0f64, |m, a| m.max(a.abs()));
        sum.retain(|_, a| a.abs() > NEGLIGIBLE * largest);
        let pivot = match constraint.pivot {
            Pivot::Fixed(dof) => {
                let a = sum.get(&dof).copied().unwrap_or(0.0);
                if a == 0.0 {
                    return Err(ConstraintError::ZeroPivot {
                        at: source.clone(),
                        node: labels(dof.0),
                        dof: dof.1 + 1,
                        coefficient: a,
                    });
                }
                dof
            }
            Pivot::Prefer(dof) if sum.contains_key(&dof) => dof,
            Pivot::Node(_) | Pivot::Prefer(_) => {
                let node = match constraint.pivot {
                    Pivot::Node(node) => Some(node),
                    _ => None,
                };
                let best = sum
                    .iter()
                    .filter(|(dof, _)| node.is_none_or(|n| dof.0 == n))
                    .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()));
                match best {
                    Some((&dof, _)) => dof,
                    None => {
                        let why =
                            if sum.is_empty() && value.abs() <= NEGLIGIBLE * value.abs().max(1.0) {
                                "it repeats what supports and earlier constraints already impose \
                             on this node"
                            } else if sum.is_empty() {
                                "supports and earlier constraints already fix every DOF it \
                             involves, to other values (it contradicts them)"
                            } else {
                                "supports and earlier constraints already fix every DOF of this \
                             node it involves"
                            };
                        let node = node.unwrap_or(match constraint.pivot {
                            Pivot::Prefer((n, _)) | Pivot::Fixed((n, _)) | Pivot::Node(n) => n,
                        });
                        return Err(ConstraintError::NothingLeft {
                            at: source.clone(),
                            why: format!("{why} (node {})", labels(node)),
                        });
                    }
                }
            }
        };
        let a = sum.remove(&pivot).unwrap_or(1.0);
        let dependent = Dependent {
            terms: sum.iter().map(|(&k, &ak)| (k, -ak / a)).collect(),
            offset: value / a,
            source: source.clone(),
        };
        // Back-substitution into the earlier dependents that use the new one.
        if let Some(earlier) = users.remove(&pivot) {
            for e in earlier {
                let Some(d) = dependents.get_mut(&e) else {
                    continue;
                };
                let Some(position) = d.terms.iter().position(|(k, _)| *k == pivot) else {
                    continue;
                };
                let (_, c) = d.terms.remove(position);
                d.offset += c * dependent.offset;
                let mut merged: BTreeMap<Dof, f64> = d.terms.iter().copied().collect();
                for &(k, ck) in &dependent.terms {
                    *merged.entry(k).or_insert(0.0) += c * ck;
                    users.entry(k).or_default().insert(e);
                }
                let largest = merged.values().fold(0.0f64, |m, a| m.max(a.abs()));
                merged.retain(|_, a| a.abs() > NEGLIGIBLE * largest);
                d.terms = merged.into_iter().collect();
            }
        }
        for &(k, _) in &dependent.terms {
            users.entry(k).or_default().insert(pivot);
        }
        dependents.insert(pivot, dependent);
    }
    Ok(Resolved { dependents })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn label(n: usize) -> String {
        (n + 1).to_string()
    }

    fn equation(terms: &[(usize, usize, f64)], value: f64, source: &str) -> LinearConstraint {
        LinearConstraint {
            terms: terms.to_vec(),
            value,
            pivot: Pivot::Fixed((terms[0].0, terms[0].1)),
            source: source.into(),
        }
    }

    #[test]
    fn chains_are_substituted_both_ways_and_supports_drop_out() {
        // u(0,x) = u(1,x) (written 1 u0 - 1 u1 = 0); then u(1,x) = 2 u(2,x) + 0.5;
        // u(3,y) = u(0,x) + u(4,z) with u(4,z) supported.
        let support = Support {
            name: "base".into(),
            nodes: vec![4],
            components: [false, false, true],
        };
        let resolved = resolve(
            &[
                equation(&[(0, 0, 1.0), (1, 0, -1.0)], 0.0, "a"),
                equation(&[(1, 0, 1.0), (2, 0, -2.0)], 0.5, "b"),
                equation(&[(3, 1, 2.0), (0, 0, -2.0), (4, 2, 5.0)], 0.0, "c"),
            ],
            &[support],
            5,
            &label,
        )
        .unwrap();
        let d = &resolved.dependents;
        assert_eq!(d.len(), 3);
        assert_eq!(d[&(0, 0)].terms, vec![((2, 0), 2.0)]);
        assert_eq!(d[&(0, 0)].offset, 0.5);
        assert_eq!(d[&(1, 0)].terms, vec![((2, 0), 2.0)]);
        assert_eq!(d[&(3, 1)].terms, vec![((2, 0), 2.0)]);
        assert_eq!(d[&(3, 1)].offset, 0.5);
        assert!(resolved.has_offsets());
    }

    #[test]
    fn a_local_direction_takes_its_largest_component_and_two_on_one_node_stay_independent() {
        let s = 0.5f64.sqrt();
        // e1 . u = 0.1 and e2 . u = 0 on node 0, e1 = (s, s, 0), e2 = (-s, s, 0).
        let local = |e: [f64; 2], value: f64| LinearConstraint {
            terms: vec![(0, 0, e[0]), (0, 1, e[1])],
            value,
            pivot: Pivot::Node(0),
            source: "t".into(),
        };
        let r = resolve(&[local([s, s], 0.1), local([-s, s], 0.0)], &[], 1, &label).unwrap();
        // Both components dependent: u = 0.1 e1 exactly.
        assert_eq!(r.dependents.len(), 2);
        for (&(_, c), d) in &r.dependents {
            assert!(d.terms.is_empty(), "{c}: {:?}", d.terms);
            assert!((d.offset - 0.1 * s).abs() < 1e-15, "{c}: {}", d.offset);
        }
    }

    #[test]
    fn a_preferred_dependent_that_is_held_gives_way_to_the_largest_other_term() {
        // u(0,x) = 0.25 u(1,x) + 0.75 u(2,x), preferring u(0,x); u(0,x) prescribed first.
        let tie = LinearConstraint {
            terms: vec![(0, 0, 1.0), (1, 0, -0.25), (2, 0, -0.75)],
            value: 0.0,
            pivot: Pivot::Prefer((0, 0)),
            source: "c".into(),
        };
        let r = resolve(
            &[equation(&[(0, 0, 1.0)], 0.3, "b"), tie.clone()],
            &[],
            3,
            &label,
        )
        .unwrap();
        assert_eq!(r.dependents[&(0, 0)].offset, 0.3);
        let d = &r.dependents[&(2, 0)];
        assert_eq!(d.terms, vec![((1, 0), -0.25 / 0.75)]);
        assert!((d.offset - 0.3 / 0.75).abs() < 1e-15);
        // Free, it is the one eliminated.
        let r = resolve(&[tie], &[], 3, &label).unwrap();
        assert_eq!(
            r.dependents.keys().copied().collect::<Vec<_>>(),
            vec![(0, 0)]
        );
    }

    #[test]
    fn what_abaqus_refuses_is_refused_naming_both_places() {
        let support = Support {
            name: "fix".into(),
            nodes: vec![0],
            components: [true, false, false],
        };
        let e = resolve(
            &[equation(&[(0, 0, 1.0), (1, 0, -1.0)], 0.0, "deck.inp:7")],
            &[support],
            2,
            &label,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("deck.inp:7") && e.contains("'fix'"), "{e}");
        let e = resolve(
            &[
                equation(&[(0, 0, 1.0), (1, 0, -1.0)], 0.0, "deck.inp:7"),
                equation(&[(0, 0, 1.0), (1, 1, -1.0)], 0.0, "deck.inp:9"),
            ],
            &[],
            2,
            &label,
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("deck.inp:9") && e.contains("deck.inp:7"),
            "{e}"
        );
        assert!(e.contains("DOF 1 of node 1"), "{e}");
        let e = resolve(
            &[equation(&[(0, 0, 0.0), (1, 0, -1.0)], 0.0, "z")],
            &[],
            2,
            &label,
        )
        .unwrap_err();
        assert!(matches!(e, ConstraintError::ZeroPivot { .. }), "{e}");
        let e = resolve(
            &[equation(&[(0, 0, 1.0), (0, 0, -1.0)], 0.0, "r")],
            &[],
            2,
            &label,
        )
        .unwrap_err();
        assert!(
            matches!(e, ConstraintError::DependentRepeated { .. }),
            "{e}"
        );
        // Fixed at 0.1 then again at 0.2 through a local direction: a contradiction.
        let e = resolve(
            &[
                equation(&[(0, 0, 1.0)], 0.1, "p"),
                LinearConstraint {
                    terms: vec![(0, 0, 1.0)],
                    value: 0.2,
                    pivot: Pivot::Node(0),
                    source: "q".into(),
                },
            ],
            &[],
            1,
            &label,
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("q:") && e.contains("contradicts"), "{e}");
    }
}
