//! `*TIE, NAME=[, POSITION TOLERANCE=][, ADJUST=YES | NO][, TYPE=NODE TO SURFACE | SURFACE
//! TO SURFACE]` and its one data line `slave surface, master surface`: two surfaces bonded
//! across meshes that need not match ([`DeckTie`]; the constraints themselves are made in
//! [`crate::model`], where the master faces are searched).
//!
//! - The slave surface is element-based (its faces' nodes, mid-edge nodes included) or
//!   node-based; the master surface must have faces.
//! - `TIED NSET=` (Abaqus; instead of a position tolerance): only the slave nodes in that
//!   node set are tied, whatever their distance to the master surface.
//! - `NO ROTATION`, `NO THICKNESS`, `NO TEMPERATURE`, `NO PORE`, `NO ELECTRIC POTENTIAL`,
//!   `NO FLUID ELECTRIC POTENTIAL`, `NO ION CONCENTRATION` are read past: they leave
//!   untied DOFs (shells' rotations and thicknesses, temperatures, pore pressures...) that
//!   squeal's solid nodes do not have.
//! - What would tie something else than displacements across the two surfaces is refused at
//!   the keyword's line: `CYCLIC SYMMETRY`, `MULTISTAGE`, `FLUID PERIODIC`, `FLUID CYCLIC`
//!   (CalculiX's cyclic and fluid ties), `CONSTRAINT RATIO` (a slave point inside the
//!   master's thickness), and any parameter squeal does not know.

use super::drafts::Block;
use super::lexer::{data_fields, Keyword, Name};
use super::lines::Loc;
use super::reader::Reader;
use super::records::SourceLine;
use crate::mesh::{Mesh, MeshError};

/// How the slave side is tied, as written (`TYPE=`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TieKind {
    /// Abaqus `TYPE=NODE TO SURFACE`, and CalculiX's only kind.
    NodeToSurface,
    /// Abaqus `TYPE=SURFACE TO SURFACE` (Abaqus's default): squeal ties it node to surface
    /// as well, and says so in a warning (Abaqus then averages over the slave faces).
    SurfaceToSurface,
}

/// A `*TIE`, its surfaces resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct DeckTie {
    /// `NAME=`, as written.
    pub name: String,
    /// The slave surface's upper-case name.
    pub slave: String,
    /// The slave nodes (internal indices, sorted, unique).
    pub slave_nodes: Vec<usize>,
    /// The master surface's upper-case name (an element-based surface of the mesh).
    pub master: String,
    /// `POSITION TOLERANCE=`: a slave node farther than this from the master surface is
    /// left untied; `None` for the default (see [`crate::model`]).
    pub tolerance: Option<f64>,
    /// `TIED NSET=`: the slave nodes to tie (those of the slave surface in this set, sorted),
    /// whatever their distance; `None`: those within the position tolerance.
    pub tied_nodes: Option<Vec<usize>>,
    /// `ADJUST=YES` (the default): tied slave nodes are moved onto the master surface.
    pub adjust: bool,
    pub kind: TieKind,
    /// The data line.
    pub source: SourceLine,
}

pub(super) struct TieDraft {
    name: String,
    tolerance: Option<f64>,
    tied_nset: Option<Name>,
    adjust: bool,
    kind: TieKind,
    /// Slave and master as written, and the data line.
    surfaces: Option<(Name, Name, Loc)>,
    loc: Loc,
}

/// Parameters that tie something other than the two surfaces' displacements.
const REFUSED: [(&str, &str); 5] = [
    ("CYCLICSYMMETRY", "cyclic symmetry"),
    ("MULTISTAGE", "multistage cyclic symmetry"),
    ("FLUIDPERIODIC", "fluid periodicity"),
    ("FLUIDCYCLIC", "fluid cyclic symmetry"),
    (
        "CONSTRAINTRATIO",
        "a constraint ratio (slave points inside a shell's thickness)",
    ),
];

impl Reader {
    pub(super) fn tie_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        for (key, what) in REFUSED {
            if kw.flag(key) {
                return Err(self.err(
                    kw.loc,
                    format!(
                        "*TIE with {what} is not supported (squeal ties the displacements of \
                         two surfaces)"
                    ),
                ));
            }
        }
        let name = self.required(kw, "NAME")?;
        let tolerance = match self.param(kw, "POSITIONTOLERANCE")? {
            None => None,
            Some(t) => {
                let t = self.number(&t, kw.loc, "POSITION TOLERANCE")?;
                if !(t > 0.0 && t.is_finite()) {
                    return Err(self.err(
                        kw.loc,
                        format!("*TIE: POSITION TOLERANCE={t} must be a positive distance"),
                    ));
                }
                Some(t)
            }
        };
        let tied_nset = self.param(kw, "TIEDNSET")?.map(|n| Name::new(&n));
        if tied_nset.is_some() && tolerance.is_some() {
            return Err(self.err(
                kw.loc,
                "*TIE: POSITION TOLERANCE and TIED NSET exclude each other (give one)",
            ));
        }
        let adjust = match self.param(kw, "ADJUST")?.map(|a| a.to_uppercase()) {
            None => true,
            Some(a) if a == "YES" => true,
            Some(a) if a == "NO" => false,
            Some(a) => {
                return Err(self.err(kw.loc, format!("*TIE: ADJUST={a} (expected YES or NO)")))
            }
        };
        let kind = match self.param(kw, "TYPE")? {
            None => TieKind::NodeToSurface,
            Some(t) => match t
                .split_whitespace()
                .collect::<String>()
                .to_uppercase()
                .as_str()
            {
                "NODETOSURFACE" => TieKind::NodeToSurface,
                "SURFACETOSURFACE" => {
                    self.contact_notes.add(
                        "*TIE, TYPE=SURFACE TO SURFACE tied node to surface (each slave node \
                         to the master face it projects on, as CalculiX ties; Abaqus's \
                         surface-to-surface tie averages over the slave faces, which differs \
                         where the meshes do not match)",
                        kw.loc,
                    );
                    TieKind::SurfaceToSurface
                }
                _ => {
                    return Err(self.err(
                        kw.loc,
                        format!("*TIE: TYPE={t} (expected NODE TO SURFACE or SURFACE TO SURFACE)"),
                    ))
                }
            },
        };
        // DOFs left untied that solid displacement nodes do not have.
        for untied in [
            "NOROTATION",
            "NOTHICKNESS",
            "NOTEMPERATURE",
            "NOPORE",
            "NOELECTRICPOTENTIAL",
            "NOFLUIDELECTRICPOTENTIAL",
            "NOIONCONCENTRATION",
        ] {
            kw.flag(untied);
        }
        if let Some(p) = kw.params.iter().find(|p| !p.used) {
            return Err(self.err(
                kw.loc,
                format!(
                    "*TIE: the parameter {} is not supported (squeal reads NAME, POSITION \
                     TOLERANCE, TIED NSET, ADJUST and TYPE)",
                    p.key
                ),
            ));
        }
        self.ties.push(TieDraft {
            name,
            tolerance,
            tied_nset,
            adjust,
            kind,
            surfaces: None,
            loc: kw.loc,
        });
        Ok(Block::Tie)
    }

    pub(super) fn tie_line(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.len() != 2 || f.iter().any(|x| x.is_empty()) {
            return Err(self.err(loc, "*TIE: expected \"slave surface, master surface\""));
        }
        let Some(tie) = self.ties.last_mut() else {
            return Err(self.err(loc, "*TIE data line without its keyword"));
        };
        if tie.surfaces.is_some() {
            let first = tie.loc;
            return Err(self.err(
                loc,
                format!(
                    "*TIE: the tie at {} already has its line (one \"slave, master\" line per \
                     *TIE)",
                    self.lines.at(first)
                ),
            ));
        }
        tie.surfaces = Some((Name::new(f[0]), Name::new(f[1]), loc));
        Ok(())
    }

    /// The ties with their surfaces checked: the slave surface exists and has nodes, the
    /// master has faces, a tie name is used once.
    pub(super) fn resolve_ties(&self, mesh: &Mesh) -> Result<Vec<DeckTie>, MeshError> {
        let mut out: Vec<DeckTie> = Vec::with_capacity(self.ties.len());
        for draft in &self.ties {
            let Some((slave, master, line)) = &draft.surfaces else {
                return Err(self.err(
                    draft.loc,
                    "*TIE: expected a data line \"slave surface, master surface\"",
                ));
            };
            if let Some(first) = out
                .iter()
                .find(|t| t.name.eq_ignore_ascii_case(&draft.name))
            {
                return Err(self.err(
                    draft.loc,
                    format!(
                        "*TIE: NAME={} is already the tie at {}",
                        draft.name, first.source
                    ),
                ));
            }
            let slave_nodes = match mesh.surfaces.get(&slave.canon) {
                Some(s) => mesh.surface_nodes(s),
                None if self.node_surfaces.contains_key(&slave.canon) => {
                    mesh.node_sets[&slave.canon].clone()
                }
                None => {
                    return Err(self.err(
                        *line,
                        format!("*TIE: slave surface {} is not defined", slave.written),
                    ))
                }
            };
            if slave_nodes.is_empty() {
                return Err(self.err(
                    *line,
                    format!("*TIE: slave surface {} has no nodes", slave.written),
                ));
            }
            match mesh.surfaces.get(&master.canon) {
                Some(s) if !s.faces.is_empty() => {}
                Some(_) => {
                    return Err(self.err(
                        *line,
                        format!("*TIE: master surface {} has no faces", master.written),
                    ))
                }
                None => {
                    let why = if self.node_surfaces.contains_key(&master.canon) {
                        "is node-based; a master surface needs faces (TYPE=ELEMENT)"
                    } else {
                        "is not defined"
                    };
                    return Err(self.err(
                        *line,
                        format!("*TIE: master surface {} {why}", master.written),
                    ));
                }
            }
            let tied_nodes = match &draft.tied_nset {
                None => None,
                Some(set) => {
                    let Some(members) = mesh.node_sets.get(&set.canon) else {
                        return Err(self.err(
                            draft.loc,
                            format!("*TIE: TIED NSET={} is not defined", set.written),
                        ));
                    };
                    let tied: Vec<usize> = slave_nodes
                        .iter()
                        .copied()
                        .filter(|n| members.binary_search(n).is_ok())
                        .collect();
                    if tied.is_empty() {
                        return Err(self.err(
                            draft.loc,
                            format!(
                                "*TIE: TIED NSET={} holds no node of the slave surface {}",
                                set.written, slave.written
                            ),
                        ));
                    }
                    Some(tied)
                }
            };
            if slave.canon == master.canon {
                return Err(self.err(
                    *line,
                    format!(
                        "*TIE: surface {} is both slave and master (a tie bonds two surfaces)",
                        slave.written
                    ),
                ));
            }
            out.push(DeckTie {
                name: draft.name.clone(),
                slave: slave.canon.clone(),
                slave_nodes,
                master: master.canon.clone(),
                tolerance: draft.tolerance,
                tied_nodes,
                adjust: draft.adjust,
                kind: draft.kind,
                source: self.lines.source(*line),
            });
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::*;

    /// One tet (element 7, nodes 11..20) with two element surfaces on faces S1 and S2 and a
    /// node surface.
    fn deck_with(tie: &str) -> String {
        format!(
            "{}*SURFACE, NAME=A\n7, S1\n*SURFACE, NAME=B\n7, S2\n*NSET, NSET=NA\n11, 12\n\
             *SURFACE, NAME=NS, TYPE=NODE\nNA\n{tie}",
            one_tet()
        )
    }

    #[test]
    fn a_tie_reads_its_surfaces_tolerance_and_adjust() {
        let deck = read_text(
            "tie",
            &deck_with("*TIE, NAME=Glue, POSITION TOLERANCE=0.01, ADJUST=NO\nA, B\n"),
        )
        .unwrap();
        assert_eq!(deck.ties.len(), 1);
        let t = &deck.ties[0];
        assert_eq!(t.name, "Glue");
        assert_eq!((t.slave.as_str(), t.master.as_str()), ("A", "B"));
        assert_eq!(t.tolerance, Some(0.01));
        assert!(!t.adjust);
        assert_eq!(t.kind, TieKind::NodeToSurface);
        assert_eq!(t.slave_nodes.len(), 6, "a face's six nodes");
        let line = deck_with("").lines().count() + 2;
        assert_eq!(t.source.line, line);
        // Defaults, a node-based slave, and Abaqus's type said in a warning.
        let deck = read_text(
            "tie",
            &deck_with("*TIE, NAME=G, TYPE=SURFACE TO SURFACE\nNS, B\n"),
        )
        .unwrap();
        let t = &deck.ties[0];
        assert_eq!((t.tolerance, t.adjust), (None, true));
        assert_eq!(t.kind, TieKind::SurfaceToSurface);
        assert_eq!(t.slave_nodes, vec![0, 1]);
        assert_eq!(t.tied_nodes, None);
        assert!(
            deck.warnings
                .iter()
                .any(|w| w.contains("SURFACE TO SURFACE")),
            "{:?}",
            deck.warnings
        );
        // TIED NSET: the slave surface's nodes in the set; other DOFs' flags read past.
        let deck = read_text(
            "tie-nset",
            &deck_with("*TIE, NAME=G, TIED NSET=NA, NO ROTATION, NO TEMPERATURE\nA, B\n"),
        )
        .unwrap();
        assert_eq!(deck.ties[0].tied_nodes, Some(vec![0, 1]));
    }

    #[test]
    fn what_a_tie_cannot_honour_stops_the_read_at_its_line() {
        for (tie, said) in [
            ("*TIE, NAME=G, CYCLIC SYMMETRY\nA, B\n", "cyclic symmetry"),
            ("*TIE, NAME=G, MULTISTAGE\nA, B\n", "multistage"),
            ("*TIE, NAME=G, FLUID PERIODIC\nA, B\n", "fluid periodicity"),
            (
                "*TIE, NAME=G, CONSTRAINT RATIO=0.5\nA, B\n",
                "constraint ratio",
            ),
            ("*TIE, NAME=G, SMOOTH=0.2\nA, B\n", "the parameter SMOOTH"),
            (
                "*TIE, NAME=G, TIED NSET=NA, POSITION TOLERANCE=0.1\nA, B\n",
                "exclude each other",
            ),
            (
                "*TIE, NAME=G, TIED NSET=NOPE\nA, B\n",
                "TIED NSET=NOPE is not defined",
            ),
            (
                "*NSET, NSET=NC\n13\n*TIE, NAME=G, TIED NSET=NC\nB, A\n",
                "holds no node of the slave surface B",
            ),
            ("*TIE, NAME=G, ADJUST=MAYBE\nA, B\n", "ADJUST=MAYBE"),
            ("*TIE, NAME=G, TYPE=NODE\nA, B\n", "TYPE=NODE"),
            (
                "*TIE, NAME=G, POSITION TOLERANCE=-1\nA, B\n",
                "positive distance",
            ),
            ("*TIE\nA, B\n", "NAME="),
            ("*TIE, NAME=G\nA\n", "slave surface, master surface"),
            ("*TIE, NAME=G\nA, B\nB, A\n", "one \"slave, master\" line"),
            ("*TIE, NAME=G\n", "expected a data line"),
            (
                "*TIE, NAME=G\nA, NOPE\n",
                "master surface NOPE is not defined",
            ),
            (
                "*TIE, NAME=G\nNOPE, B\n",
                "slave surface NOPE is not defined",
            ),
            ("*TIE, NAME=G\nA, NS\n", "node-based"),
            ("*TIE, NAME=G\nA, A\n", "both slave and master"),
            (
                "*TIE, NAME=G\nA, B\n*TIE, NAME=g\nB, A\n",
                "already the tie",
            ),
        ] {
            let text = deck_with(tie);
            let e = read_text("tie-refused", &text).unwrap_err().to_string();
            assert!(e.contains(said), "{tie}: {e}");
            assert!(e.contains("deck.inp:"), "{tie}: {e}");
        }
    }
}
