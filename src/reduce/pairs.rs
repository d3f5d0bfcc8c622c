//! Which contact pairs a reduced interface replaces, and each one's grid (issue 32's first
//! step).
//!
//! The paper reduces the disc/pad interface alone: the swept pairs. Every other pair of the
//! floating caliper (piston/pad, caliper/pad, the four abutments) stays node-to-surface in
//! the reduced-interface model and so inside a super-element, linearised about one
//! equilibrium: a change of its contact state or of the equilibrium invalidates the
//! super-element. Reducing those pairs too, the same way (reduced contact nodes, couplings on
//! each side, node-to-node contact with the pair's own law), is the step towards a
//! super-element whose interior holds no contact at all.
//!
//! `reduction.reduce_pairs` says which pairs are reduced besides the swept ones: `"swept"`
//! (the paper's, the default), `"all"`, or a list of pair names. `[reduction.pairs."NAME"]`
//! gives a pair its own grid (`contact_nodes = 8` or `spacing = 0.004`); a reduced kept pair
//! without one takes the swept pads' grid side h, so that the whole interface is reduced at
//! one resolution (a kept face smaller than h then holds a single node: say its own size).

use super::GridSize;
use std::collections::BTreeMap;

/// Which pairs are reduced besides the swept ones.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum ReducePairs {
    /// The swept pairs alone (the paper's reduced interface).
    #[default]
    Swept,
    /// Every node-to-surface pair of the model.
    All,
    /// The swept pairs and these.
    Named(Vec<String>),
}

impl ReducePairs {
    pub fn is_swept(&self) -> bool {
        *self == ReducePairs::Swept
    }

    /// Whether the non-swept pair `name` is reduced.
    pub fn reduces(&self, name: &str) -> bool {
        match self {
            ReducePairs::Swept => false,
            ReducePairs::All => true,
            ReducePairs::Named(names) => names.iter().any(|n| n == name),
        }
    }

    /// The names asked for that are not among `known` (a study or flag naming a pair the
    /// model does not have).
    pub fn unknown<'a>(&'a self, known: &[&str]) -> Vec<&'a str> {
        match self {
            ReducePairs::Named(names) => names
                .iter()
                .map(String::as_str)
                .filter(|n| !known.contains(n))
                .collect(),
            _ => Vec::new(),
        }
    }
}

impl std::fmt::Display for ReducePairs {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReducePairs::Swept => f.write_str("swept"),
            ReducePairs::All => f.write_str("all"),
            ReducePairs::Named(names) => f.write_str(&names.join(",")),
        }
    }
}

/// `--reduce-pairs`: `swept`, `all`, or pair names separated by commas.
impl std::str::FromStr for ReducePairs {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "swept" => Ok(ReducePairs::Swept),
            "all" => Ok(ReducePairs::All),
            "" => Err("give swept, all, or pair names separated by commas".into()),
            list => Ok(ReducePairs::Named(
                list.split(',').map(|n| n.trim().to_string()).collect(),
            )),
        }
    }
}

/// In a study: `reduce_pairs = "swept"`, `"all"` or `["caliper/pad", ...]`.
impl serde::Serialize for ReducePairs {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            ReducePairs::Named(names) => names.serialize(s),
            other => s.serialize_str(&other.to_string()),
        }
    }
}

/// Read by a visitor rather than an untagged enum: serde's untagged enum answers any other
/// value (`reduce_pairs = 3`) with "data did not match any variant", where a user needs
/// the forms the key takes.
struct PairsVisitor;

const EXPECTED: &str = "\"swept\", \"all\" or a list of pair names";

impl<'de> serde::de::Visitor<'de> for PairsVisitor {
    type Value = ReducePairs;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(EXPECTED)
    }

    fn visit_str<E: serde::de::Error>(self, w: &str) -> Result<ReducePairs, E> {
        match w {
            "swept" => Ok(ReducePairs::Swept),
            "all" => Ok(ReducePairs::All),
            _ => Err(E::custom(format!(
                "reduce_pairs = \"{w}\": give {EXPECTED}"
            ))),
        }
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<ReducePairs, A::Error> {
        let mut names = Vec::new();
        while let Some(name) = seq.next_element::<String>()? {
            names.push(name);
        }
        Ok(ReducePairs::Named(names))
    }
}

impl<'de> serde::Deserialize<'de> for ReducePairs {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(PairsVisitor)
    }
}

/// One kept pair's own grid and contact law in a study: `[reduction.pairs."caliper/pad"]`.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PairGrid {
    /// Reduced contact nodes on the pair's slave face.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_nodes: Option<usize>,
    /// Or the grid side h (mesh units).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<f64>,
    /// Patch laws on its reduced contacts (Coulomb stick and slip, or bilateral, over each
    /// share); `None` or false: point contacts, the default for a kept pair.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt: Option<bool>,
}

impl PairGrid {
    /// The grid it asks for (`None`: the default grid, where the table sets `tilt` alone),
    /// or what is wrong with it.
    pub fn size(&self) -> Result<Option<GridSize>, String> {
        match (self.contact_nodes, self.spacing) {
            (Some(_), Some(_)) => Err("give either contact_nodes or spacing, not both".into()),
            (None, None) if self.tilt.is_some() => Ok(None),
            (None, None) => Err("give contact_nodes, spacing or tilt".into()),
            (Some(0), None) => Err("contact_nodes must be at least 1".into()),
            (Some(n), None) => Ok(Some(GridSize::Count(n))),
            (None, Some(h)) if !(h > 0.0 && h.is_finite()) => {
                Err(format!("spacing must be finite and > 0, got {h}"))
            }
            (None, Some(h)) => Ok(Some(GridSize::Spacing(h))),
        }
    }

    /// Every pair's own grid (the pairs that give one), or the first pair whose grid is
    /// wrong and why.
    pub fn sizes(
        grids: &BTreeMap<String, PairGrid>,
    ) -> Result<BTreeMap<String, GridSize>, (String, String)> {
        grids
            .iter()
            .filter_map(|(name, g)| match g.size() {
                Ok(size) => size.map(|s| Ok((name.clone(), s))),
                Err(e) => Some(Err((name.clone(), e))),
            })
            .collect()
    }

    /// Every pair's `tilt`, where it gives one.
    pub fn tilts(grids: &BTreeMap<String, PairGrid>) -> BTreeMap<String, bool> {
        grids
            .iter()
            .filter_map(|(name, g)| g.tilt.map(|t| (name.clone(), t)))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Serialize, serde::Deserialize, Debug, PartialEq)]
    struct Holder {
        #[serde(default)]
        reduce_pairs: ReducePairs,
    }

    #[test]
    fn the_selection_reads_and_writes_as_a_word_or_a_list() {
        let read = |t: &str| toml::from_str::<Holder>(t).map(|h| h.reduce_pairs);
        assert_eq!(read("").unwrap(), ReducePairs::Swept);
        assert_eq!(read("reduce_pairs = \"all\"").unwrap(), ReducePairs::All);
        assert_eq!(
            read("reduce_pairs = \"swept\"").unwrap(),
            ReducePairs::Swept
        );
        let named = read("reduce_pairs = [\"caliper/pad\", \"piston/pad\"]").unwrap();
        assert_eq!(
            named,
            ReducePairs::Named(vec!["caliper/pad".into(), "piston/pad".into()])
        );
        let e = read("reduce_pairs = \"some\"").unwrap_err().to_string();
        assert!(e.contains("\"swept\", \"all\" or a list"), "{e}");
        // Any other value is told the forms the key takes (an untagged enum said only
        // "data did not match any variant").
        for wrong in ["3", "true", "{ a = 1 }", "[1, 2]"] {
            let e = read(&format!("reduce_pairs = {wrong}"))
                .unwrap_err()
                .to_string();
            let expected = if wrong.starts_with('[') {
                "a string"
            } else {
                "\"swept\", \"all\" or a list of pair names"
            };
            assert!(e.contains(expected) && e.contains("line 1"), "{wrong}: {e}");
        }
        for r in [ReducePairs::Swept, ReducePairs::All, named.clone()] {
            let text = toml::to_string(&Holder {
                reduce_pairs: r.clone(),
            })
            .unwrap();
            assert_eq!(read(&text).unwrap(), r, "{text}");
        }
        // The flag's spelling.
        assert_eq!("all".parse::<ReducePairs>().unwrap(), ReducePairs::All);
        assert_eq!(
            "caliper/pad, piston/pad".parse::<ReducePairs>().unwrap(),
            named
        );
        assert!("".parse::<ReducePairs>().is_err());
        assert!(named.reduces("caliper/pad") && !named.reduces("bracket/pad inboard leading"));
        assert!(ReducePairs::All.reduces("anything") && !ReducePairs::Swept.reduces("x"));
        assert_eq!(named.unknown(&["caliper/pad"]), ["piston/pad"]);
    }

    #[test]
    fn a_pair_grid_is_a_count_or_a_side() {
        let g = |n, h| PairGrid {
            contact_nodes: n,
            spacing: h,
            tilt: None,
        };
        assert_eq!(g(Some(8), None).size(), Ok(Some(GridSize::Count(8))));
        assert_eq!(
            g(None, Some(0.004)).size(),
            Ok(Some(GridSize::Spacing(0.004)))
        );
        // `tilt` alone keeps the default grid.
        let tilt = PairGrid {
            tilt: Some(true),
            ..g(None, None)
        };
        assert_eq!(tilt.size(), Ok(None));
        assert!(g(Some(8), Some(0.004))
            .size()
            .unwrap_err()
            .contains("not both"));
        assert!(g(None, None).size().is_err());
        assert!(g(Some(0), None).size().is_err());
        assert!(g(None, Some(-1.0)).size().is_err());
        let grids: BTreeMap<String, PairGrid> = [
            ("a".to_string(), g(Some(3), None)),
            ("b".to_string(), g(None, Some(f64::NAN))),
        ]
        .into_iter()
        .collect();
        assert_eq!(PairGrid::sizes(&grids).unwrap_err().0, "b");
        let grids: BTreeMap<String, PairGrid> =
            [("a".to_string(), g(Some(3), None)), ("b".to_string(), tilt)]
                .into_iter()
                .collect();
        assert_eq!(PairGrid::sizes(&grids).unwrap().len(), 1);
        assert_eq!(PairGrid::tilts(&grids), [("b".to_string(), true)].into());
        let read: PairGrid = toml::from_str("tilt = true").unwrap();
        assert_eq!(read, tilt);
    }
}
