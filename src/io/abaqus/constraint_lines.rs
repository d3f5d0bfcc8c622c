//! The constraint keywords, read and resolved: `*EQUATION`, `*TRANSFORM` (rectangular and
//! cylindrical), and `*COUPLING` followed by `*DISTRIBUTING`.
//!
//! - `*EQUATION` (Abaqus and CalculiX): a line with the number of terms N, then N terms
//!   `node or node set, DOF, coefficient`, several to a line (Abaqus writes at most four).
//!   sum_k a_k u_k = 0; the first term's DOF is the dependent one, eliminated. Node sets
//!   expand term by term as Abaqus does: the equation is repeated for the sets' first
//!   nodes, then their second nodes..., each set sorted by label (Abaqus's default sorted
//!   sets); sets of one equation must have the same size, and a single node stands in every
//!   repetition. DOFs 4-6 are refused at their line (solid nodes have no rotations).
//! - `*TRANSFORM, NSET=, TYPE=R | C`, one data line `a_x, a_y, a_z, b_x, b_y, b_z`. TYPE=R
//!   (the default): local 1 along a, local 2 in the plane of a and b, local 3 = a x b.
//!   TYPE=C: a and b are two points on the axis of a cylindrical system, local 1 radial,
//!   2 tangential, 3 axial (from a to b), at each node's own position. The DOFs of
//!   `*BOUNDARY`, `*CLOAD` and `*EQUATION` at those nodes are local ([`DeckTransform`]). A
//!   cylindrical system with a = b (no axis), or a rectangular one whose a is zero or
//!   parallel to b, is refused at its data line; a node on a cylindrical axis, where the
//!   radial direction does not exist, wherever a load or support uses it.
//! - `*COUPLING, CONSTRAINT NAME=, REF NODE=, SURFACE=[, INFLUENCE RADIUS=]` then
//!   `*DISTRIBUTING[, WEIGHTING METHOD=UNIFORM | LINEAR | QUADRATIC | CUBIC]` and its DOF
//!   lines: a distributing coupling of the reference node(s) to the surface's nodes within
//!   the radius ([`DeckCoupling`]; its weights and constraint are made in
//!   [`crate::model`]). `*KINEMATIC`, `COUPLING=STRUCTURAL` (the coupling nodes'
//!   rotations) and `ORIENTATION=` are refused at their line. A load or support on DOFs 4-6
//!   of a reference node, which squeal's reference nodes do not have, is refused at its line.

use std::collections::{BTreeMap, HashMap};

use super::drafts::*;
use super::lexer::{data_fields, looks_numeric, Keyword, Name};
use super::lines::Loc;
use super::reader::Reader;
use super::records::SourceLine;
use crate::mesh::{Mesh, MeshError};
use crate::vector3::{cross, dot, norm, normalize, scale, sub};

/// One term of an `*EQUATION`: coefficient times the node's DOF (local when the node has a
/// `*TRANSFORM`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EquationTerm {
    /// Internal node index.
    pub node: usize,
    /// Abaqus DOF 1..=3.
    pub dof: u8,
    pub coefficient: f64,
}

/// One `*EQUATION` (a node-set equation gives one per node of its sets):
/// sum_k coefficient_k u_k = 0, the first term's DOF dependent.
#[derive(Clone, Debug, PartialEq)]
pub struct Equation {
    pub terms: Vec<EquationTerm>,
    /// The line with its number of terms.
    pub source: SourceLine,
}

/// The kind of a `*TRANSFORM`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransformKind {
    Rectangular,
    Cylindrical,
}

/// A `*TRANSFORM`: the local directions of its nodes' DOFs.
#[derive(Clone, Debug, PartialEq)]
pub struct DeckTransform {
    /// Internal node indices, sorted.
    pub nodes: Vec<usize>,
    pub kind: TransformKind,
    /// The data line's two points.
    pub a: [f64; 3],
    pub b: [f64; 3],
    /// The data line.
    pub source: SourceLine,
}

impl DeckTransform {
    /// The local unit directions (rows: local 1, 2, 3) at `position`; `None` for a
    /// cylindrical system at a point on its axis (no radial direction there).
    pub fn axes(&self, position: [f64; 3]) -> Option<[[f64; 3]; 3]> {
        match self.kind {
            TransformKind::Rectangular => {
                let e1 = normalize(self.a)?;
                let e3 = normalize(cross(self.a, self.b))?;
                Some([e1, cross(e3, e1), e3])
            }
            TransformKind::Cylindrical => {
                let axis = normalize(sub(self.b, self.a))?;
                let d = sub(position, self.a);
                let radial = sub(d, scale(dot(d, axis), axis));
                // On the axis to round-off of the model's size: no radial direction.
                if norm(radial) <= 1e-12 * norm(d).max(norm(sub(self.b, self.a))) {
                    return None;
                }
                let e1 = normalize(radial)?;
                Some([e1, cross(axis, e1), axis])
            }
        }
    }
}

/// The weighting method of a `*DISTRIBUTING`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DistributingWeighting {
    #[default]
    Uniform,
    Linear,
    Quadratic,
    Cubic,
}

/// A `*COUPLING` with `*DISTRIBUTING`, one per reference node.
#[derive(Clone, Debug, PartialEq)]
pub struct DeckCoupling {
    /// `CONSTRAINT NAME=`.
    pub name: String,
    /// Internal node index of the reference node.
    pub reference: usize,
    /// The surface (upper-case name) whose nodes are the coupling nodes.
    pub surface: String,
    /// Whether it is element-based (weights from the nodes' tributary areas, as Abaqus
    /// does) or node-based (each node alike).
    pub element_based: bool,
    /// The surface's nodes, sorted (the candidates: those within the radius couple).
    pub nodes: Vec<usize>,
    /// `INFLUENCE RADIUS=`; `None`: every node of the surface, with the distance to the
    /// farthest as the radius of the weighting (Abaqus's default).
    pub radius: Option<f64>,
    pub weighting: DistributingWeighting,
    /// The `*COUPLING` line.
    pub source: SourceLine,
}

/// What the constraint keywords said, before labels and names are resolved.
#[derive(Default)]
pub(super) struct ConstraintDrafts {
    equations: Vec<EquationDraft>,
    transforms: Vec<TransformDraft>,
    couplings: Vec<CouplingDraft>,
    /// Loads and supports on rotational DOFs (dropped with a warning, unless the node is a
    /// coupling's reference node): the target as written, the keyword, the line.
    pub(super) rotational: Vec<(String, &'static str, Loc)>,
    /// Node sets defined `UNSORTED` (their order is not kept: refused in an `*EQUATION`).
    pub(super) unsorted: BTreeMap<String, Loc>,
}

struct EquationDraft {
    count: usize,
    terms: Vec<(NodeRef, u8, f64, Loc)>,
    loc: Loc,
}

struct TransformDraft {
    nset: Name,
    kind: TransformKind,
    points: Option<([f64; 3], [f64; 3], Loc)>,
    loc: Loc,
}

struct CouplingDraft {
    name: String,
    reference: NodeRef,
    surface: Name,
    radius: Option<f64>,
    /// The `*DISTRIBUTING` that followed: its weighting and line.
    distributing: Option<(DistributingWeighting, Loc)>,
    loc: Loc,
}

/// Which constraint keyword's data lines follow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum ConstraintBlock {
    Equation,
    Transform,
    Distributing,
}

impl Reader {
    /// `*EQUATION`, `*TRANSFORM`, `*COUPLING`, `*DISTRIBUTING` and `*KINEMATIC`.
    pub(super) fn constraint_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        let after_coupling = matches!(self.block, Block::NoData(ref k) if k == "*COUPLING");
        match kw.name.as_str() {
            "EQUATION" => Ok(Block::Constraint(ConstraintBlock::Equation)),
            "TRANSFORM" => {
                let nset = Name::new(&self.required(kw, "NSET")?);
                let kind = match self.param(kw, "TYPE")?.map(|t| t.to_uppercase()) {
                    None => TransformKind::Rectangular,
                    Some(t) if t == "R" => TransformKind::Rectangular,
                    Some(t) if t == "C" => TransformKind::Cylindrical,
                    Some(t) => {
                        return Err(self.err(
                            kw.loc,
                            format!(
                                "*TRANSFORM, TYPE={t} is not supported (squeal reads TYPE=R, \
                                 rectangular, and TYPE=C, cylindrical)"
                            ),
                        ))
                    }
                };
                self.constraints.transforms.push(TransformDraft {
                    nset,
                    kind,
                    points: None,
                    loc: kw.loc,
                });
                Ok(Block::Constraint(ConstraintBlock::Transform))
            }
            "COUPLING" => {
                let name = self.required(kw, "CONSTRAINTNAME")?;
                let reference = self.required(kw, "REFNODE")?;
                let reference = if looks_numeric(&reference) {
                    NodeRef::Node(self.label(&reference, kw.loc, "REF NODE label")?)
                } else {
                    NodeRef::Set(Name::new(&reference))
                };
                let surface = Name::new(&self.required(kw, "SURFACE")?);
                let radius = match self.param(kw, "INFLUENCERADIUS")? {
                    None => None,
                    Some(r) => {
                        let r = self.number(&r, kw.loc, "INFLUENCE RADIUS")?;
                        if r <= 0.0 {
                            return Err(self.err(
                                kw.loc,
                                format!("*COUPLING: INFLUENCE RADIUS={r} must be positive"),
                            ));
                        }
                        Some(r)
                    }
                };
                if let Some(o) = self.param(kw, "ORIENTATION")? {
                    return Err(self.err(
                        kw.loc,
                        format!(
                            "*COUPLING, ORIENTATION={o} is not supported (the coupling's DOFs \
                             must be the global ones)"
                        ),
                    ));
                }
                self.constraints.couplings.push(CouplingDraft {
                    name,
                    reference,
                    surface,
                    radius,
                    distributing: None,
                    loc: kw.loc,
                });
                Ok(Block::NoData("*COUPLING".into()))
            }
            "DISTRIBUTING" | "KINEMATIC" => {
                if !after_coupling {
                    return Err(self.err(kw.loc, format!("{} must follow a *COUPLING", kw.display)));
                }
                if kw.name == "KINEMATIC" {
                    return Err(self.err(
                        kw.loc,
                        "*KINEMATIC coupling is not supported (squeal reads *DISTRIBUTING \
                         couplings)",
                    ));
                }
                if let Some(c) = self.param(kw, "COUPLING")? {
                    if !c.eq_ignore_ascii_case("CONTINUUM") {
                        return Err(self.err(
                            kw.loc,
                            format!(
                                "*DISTRIBUTING, COUPLING={c} is not supported (it couples the \
                                 rotations of the coupling nodes, which solid nodes do not have: \
                                 use COUPLING=CONTINUUM, the default)"
                            ),
                        ));
                    }
                }
                // With solid coupling nodes these change nothing: the coupling nodes have
                // no rotations to take part, and every node of a surface is attached.
                kw.flag("ROTATIONALCOUPLING");
                kw.flag("FREENODES");
                let weighting = match self.param(kw, "WEIGHTINGMETHOD")?.map(|w| w.to_uppercase()) {
                    None => DistributingWeighting::Uniform,
                    Some(w) => match w.as_str() {
                        "UNIFORM" => DistributingWeighting::Uniform,
                        "LINEAR" => DistributingWeighting::Linear,
                        "QUADRATIC" => DistributingWeighting::Quadratic,
                        "CUBIC" => DistributingWeighting::Cubic,
                        _ => {
                            return Err(self.err(
                                kw.loc,
                                format!(
                                    "*DISTRIBUTING: WEIGHTING METHOD={w} is not one of UNIFORM, \
                                     LINEAR, QUADRATIC, CUBIC"
                                ),
                            ))
                        }
                    },
                };
                if let Some(c) = self.constraints.couplings.last_mut() {
                    c.distributing = Some((weighting, kw.loc));
                }
                Ok(Block::Constraint(ConstraintBlock::Distributing))
            }
            _ => Ok(Block::Skip),
        }
    }

    pub(super) fn constraint_line(
        &mut self,
        block: ConstraintBlock,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        match block {
            ConstraintBlock::Equation => self.equation_line(text, loc),
            ConstraintBlock::Transform => self.transform_line(text, loc),
            ConstraintBlock::Distributing => self.distributing_line(text, loc),
        }
    }

    fn equation_line(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
        let f = data_fields(text);
        let open = self
            .constraints
            .equations
            .last()
            .is_some_and(|e| e.terms.len() < e.count);
        if !open {
            // A new equation: its number of terms.
            let count = match f[..] {
                [n] => n.parse::<usize>().ok().filter(|&n| n >= 1),
                _ => None,
            };
            let Some(count) = count else {
                return Err(self.err(
                    loc,
                    format!(
                        "*EQUATION: expected the number of terms of the next equation (a \
                         positive integer alone on its line), found \"{text}\""
                    ),
                ));
            };
            self.constraints.equations.push(EquationDraft {
                count,
                terms: Vec::with_capacity(count.min(64)),
                loc,
            });
            return Ok(());
        }
        if f.is_empty() || !f.len().is_multiple_of(3) {
            return Err(self.err(
                loc,
                format!(
                    "*EQUATION: expected terms \"node or node set, DOF, coefficient\" (3 \
                     fields each), found {} fields",
                    f.len()
                ),
            ));
        }
        let mut terms = Vec::with_capacity(f.len() / 3);
        for t in f.chunks(3) {
            if t[0].is_empty() {
                return Err(self.err(loc, "*EQUATION: a term has no node or node set"));
            }
            let target = if looks_numeric(t[0]) {
                NodeRef::Node(self.label(t[0], loc, "node label")?)
            } else {
                NodeRef::Set(Name::new(t[0]))
            };
            let dof = match t[1].parse::<u8>() {
                Ok(d @ 1..=3) => d,
                Ok(d @ 4..=6) => {
                    return Err(self.err(
                        loc,
                        format!(
                            "*EQUATION: DOF {d} is a rotation, which C3D10 nodes do not have \
                             (squeal's equations tie displacements, DOFs 1-3)"
                        ),
                    ))
                }
                _ => {
                    return Err(self.err(
                        loc,
                        format!(
                            "*EQUATION: expected a degree of freedom 1, 2 or 3, found \"{}\"",
                            t[1]
                        ),
                    ))
                }
            };
            let a = self.number(t[2], loc, "equation coefficient")?;
            terms.push((target, dof, a, loc));
        }
        let equation = self
            .constraints
            .equations
            .last_mut()
            .expect("an open equation");
        if equation.terms.len() + terms.len() > equation.count {
            let (count, eq_loc) = (equation.count, equation.loc);
            return Err(self.err(
                loc,
                format!(
                    "*EQUATION: the equation at {} has {count} terms, and this line goes past \
                     them",
                    self.lines.at(eq_loc)
                ),
            ));
        }
        equation.terms.extend(terms);
        Ok(())
    }

    fn transform_line(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.len() != 6 {
            return Err(self.err(
                loc,
                format!(
                    "*TRANSFORM: expected the coordinates of two points a and b (6 numbers), \
                     found {} fields",
                    f.len()
                ),
            ));
        }
        let mut x = [0.0; 6];
        for (k, field) in f.iter().enumerate() {
            x[k] = self.number(field, loc, "*TRANSFORM point coordinate")?;
        }
        let (a, b) = ([x[0], x[1], x[2]], [x[3], x[4], x[5]]);
        let Some(draft) = self.constraints.transforms.last_mut() else {
            return Ok(());
        };
        if let Some((_, _, first)) = draft.points {
            let first = self.lines.at(first);
            return Err(self.err(
                loc,
                format!("*TRANSFORM takes one data line (the first is at {first})"),
            ));
        }
        let kind = draft.kind;
        draft.points = Some((a, b, loc));
        let scale_of = norm(a).max(norm(b)).max(f64::MIN_POSITIVE);
        match kind {
            TransformKind::Cylindrical if norm(sub(b, a)) <= 1e-12 * scale_of => Err(self.err(
                loc,
                format!(
                    "*TRANSFORM, TYPE=C: the two points on the axis are the same point \
                         ({}, {}, {}), so the cylindrical system has no axis",
                    a[0], a[1], a[2]
                ),
            )),
            TransformKind::Rectangular
                if norm(a) == 0.0 || norm(cross(a, b)) <= 1e-12 * norm(a) * norm(b) =>
            {
                Err(self.err(
                    loc,
                    "*TRANSFORM, TYPE=R: point a must be off the origin and b off the line \
                     through the origin and a (they give the local 1 axis and the 1-2 plane)",
                ))
            }
            _ => Ok(()),
        }
    }

    fn distributing_line(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.len() > 2 {
            return Err(self.err(
                loc,
                format!(
                    "*DISTRIBUTING: expected \"first DOF[, last DOF]\", found {} fields",
                    f.len()
                ),
            ));
        }
        for field in f.iter().filter(|s| !s.is_empty()) {
            match field.parse::<u8>() {
                Ok(1..=6) => {}
                _ => {
                    return Err(self.err(
                        loc,
                        format!("*DISTRIBUTING: expected a DOF 1..6, found \"{field}\""),
                    ))
                }
            }
        }
        // All translations are coupled whatever the line says (Abaqus: only rotations can
        // be released); the reference node's rotations are no DOFs in squeal, so coupling
        // or releasing them changes nothing unless a load or support acts on them, which
        // is refused at its line.
        Ok(())
    }

    /// The constraint records, resolved against the mesh.
    #[allow(clippy::type_complexity)]
    pub(super) fn resolve_constraints(
        &self,
        mesh: &Mesh,
        node_surfaces: &std::collections::BTreeSet<String>,
    ) -> Result<(Vec<Equation>, Vec<DeckTransform>, Vec<DeckCoupling>), MeshError> {
        let drafts = &self.constraints;
        // Node sets sorted by label, as Abaqus orders a set's members.
        let sorted = |nodes: &[usize]| -> Vec<usize> {
            let mut v = nodes.to_vec();
            v.sort_by_key(|&n| mesh.node_labels[n]);
            v
        };
        let nodes_of =
            |target: &NodeRef, loc: Loc, keyword: &str| -> Result<Vec<usize>, MeshError> {
                match target {
                    NodeRef::Node(label) => {
                        self.node_index.get(label).map(|&n| vec![n]).ok_or_else(|| {
                            self.err(loc, format!("{keyword}: node {label} is not defined"))
                        })
                    }
                    NodeRef::Set(name) => match mesh.node_sets.get(&name.canon) {
                        Some(nodes) if nodes.is_empty() => Err(self.err(
                            loc,
                            format!("{keyword}: node set {} is empty", name.written),
                        )),
                        Some(nodes) => Ok(sorted(nodes)),
                        None => Err(self.err(
                            loc,
                            format!("{keyword}: node set {} is not defined", name.written),
                        )),
                    },
                }
            };
        let mut equations = Vec::new();
        for draft in &drafts.equations {
            if draft.terms.len() < draft.count {
                return Err(self.err(
                    draft.loc,
                    format!(
                        "*EQUATION: {} terms announced, {} given before the next keyword or \
                         the end of the file",
                        draft.count,
                        draft.terms.len()
                    ),
                ));
            }
            let mut expanded: Vec<(Vec<usize>, u8, f64, Loc)> = Vec::new();
            for (target, dof, a, loc) in &draft.terms {
                if let NodeRef::Set(name) = target {
                    if let Some(&defined) = drafts.unsorted.get(&name.canon) {
                        return Err(self.err(
                            *loc,
                            format!(
                                "*EQUATION: node set {} is UNSORTED (at {}); squeal keeps sets \
                                 sorted, so it cannot pair its nodes in the order given: list \
                                 the equations node by node",
                                name.written,
                                self.lines.at(defined)
                            ),
                        ));
                    }
                }
                expanded.push((nodes_of(target, *loc, "*EQUATION")?, *dof, *a, *loc));
            }
            // Abaqus: after a single node, every entry must be a single node.
            if let (Some(first), Some(set)) =
                (expanded.first(), expanded.iter().find(|t| t.0.len() > 1))
            {
                if first.0.len() == 1 && matches!(draft.terms[0].0, NodeRef::Node(_)) {
                    return Err(self.err(
                        set.3,
                        "*EQUATION: the first term is a single node, so every term must be a \
                         single node (Abaqus); a node set may follow a node set only",
                    ));
                }
            }
            let repeats = expanded.iter().map(|t| t.0.len()).max().unwrap_or(1);
            if let Some(t) = expanded
                .iter()
                .find(|t| t.0.len() != 1 && t.0.len() != repeats)
            {
                return Err(self.err(
                    t.3,
                    format!(
                        "*EQUATION: the node sets of one equation must have the same number of \
                         nodes (Abaqus repeats the equation node by node): this term's set \
                         has {}, another {repeats}",
                        t.0.len()
                    ),
                ));
            }
            for k in 0..repeats {
                equations.push(Equation {
                    terms: expanded
                        .iter()
                        .map(|(nodes, dof, a, _)| EquationTerm {
                            node: if nodes.len() == 1 { nodes[0] } else { nodes[k] },
                            dof: *dof,
                            coefficient: *a,
                        })
                        .collect(),
                    source: self.lines.source(draft.loc),
                });
            }
        }
        let mut transforms = Vec::new();
        let mut owner: HashMap<usize, Loc> = HashMap::new();
        for draft in &drafts.transforms {
            let Some((a, b, line)) = draft.points else {
                return Err(self.err(
                    draft.loc,
                    "*TRANSFORM: expected a data line with the two points a and b",
                ));
            };
            let nodes = nodes_of(&NodeRef::Set(draft.nset.clone()), draft.loc, "*TRANSFORM")?;
            for &n in &nodes {
                if let Some(first) = owner.insert(n, draft.loc) {
                    return Err(self.err(
                        draft.loc,
                        format!(
                            "*TRANSFORM: node {} already has the *TRANSFORM at {} (a node \
                             takes one local system)",
                            mesh.node_labels[n],
                            self.lines.at(first)
                        ),
                    ));
                }
            }
            let mut nodes = nodes;
            nodes.sort_unstable();
            transforms.push(DeckTransform {
                nodes,
                kind: draft.kind,
                a,
                b,
                source: self.lines.source(line),
            });
        }
        let mut couplings = Vec::new();
        let mut references: BTreeMap<usize, Loc> = BTreeMap::new();
        for draft in &drafts.couplings {
            let Some((weighting, _)) = draft.distributing else {
                return Err(self.err(
                    draft.loc,
                    "*COUPLING must be followed by *DISTRIBUTING (squeal reads distributing \
                     couplings)",
                ));
            };
            let refs = nodes_of(&draft.reference, draft.loc, "*COUPLING, REF NODE")?;
            let (nodes, element_based) = match mesh.surfaces.get(&draft.surface.canon) {
                Some(s) => (mesh.surface_nodes(s), true),
                None if node_surfaces.contains(&draft.surface.canon) => {
                    (mesh.node_sets[&draft.surface.canon].clone(), false)
                }
                None => {
                    return Err(self.err(
                        draft.loc,
                        format!(
                            "*COUPLING: surface {} is not defined",
                            draft.surface.written
                        ),
                    ))
                }
            };
            if refs.len() > 1 && draft.radius.is_none() {
                return Err(self.err(
                    draft.loc,
                    format!(
                        "*COUPLING: REF NODE names {} nodes; several reference nodes need an \
                         INFLUENCE RADIUS (each couples the surface nodes within it)",
                        refs.len()
                    ),
                ));
            }
            for reference in refs {
                if let Some(first) = references.insert(reference, draft.loc) {
                    return Err(self.err(
                        draft.loc,
                        format!(
                            "*COUPLING: node {} is already the reference node of the coupling \
                             at {}",
                            mesh.node_labels[reference],
                            self.lines.at(first)
                        ),
                    ));
                }
                if nodes.binary_search(&reference).is_ok() {
                    return Err(self.err(
                        draft.loc,
                        format!(
                            "*COUPLING: the reference node {} is a node of the surface {} it \
                             couples to",
                            mesh.node_labels[reference], draft.surface.written
                        ),
                    ));
                }
                couplings.push(DeckCoupling {
                    name: draft.name.clone(),
                    reference,
                    surface: draft.surface.canon.clone(),
                    element_based,
                    nodes: nodes.clone(),
                    radius: draft.radius,
                    weighting,
                    source: self.lines.source(draft.loc),
                });
            }
        }
        // A reference node has no rotations here: a load or a support on them cannot be
        // dropped as on other nodes.
        for (target, keyword, loc) in &drafts.rotational {
            let target = if looks_numeric(target) {
                match target.parse::<i64>() {
                    Ok(label) => NodeRef::Node(label),
                    Err(_) => continue,
                }
            } else {
                NodeRef::Set(Name::new(target))
            };
            let Ok(nodes) = nodes_of(&target, *loc, keyword) else {
                continue;
            };
            if let Some(&n) = nodes.iter().find(|n| references.contains_key(n)) {
                return Err(self.err(
                    *loc,
                    format!(
                        "{keyword} on DOFs 4-6 of node {}, the reference node of the \
                         *COUPLING at {}: squeal's reference nodes have no rotations (a \
                         distributing coupling carries forces and their moments through the \
                         translations: apply a moment as a couple of forces on coupled nodes)",
                        mesh.node_labels[n],
                        self.lines.at(references[&n])
                    ),
                ));
            }
        }
        Ok((equations, transforms, couplings))
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::*;

    #[test]
    fn equations_expand_node_sets_label_by_label_and_read_terms_over_lines() {
        let text = format!(
            "{}*NSET, NSET=A\n13, 11\n*NSET, NSET=B\n14, 12\n*EQUATION\n3\n15, 1, 1.0, 16, 2, \
             -0.5,\n17, 3, -0.5\n2\nA, 2, 1., B, 2, -1.\n",
            one_tet()
        );
        let deck = read_text("equations", &text).unwrap();
        assert_eq!(deck.equations.len(), 3);
        let terms = |k: usize| -> Vec<(i64, u8, f64)> {
            deck.equations[k]
                .terms
                .iter()
                .map(|t| (deck.mesh.node_labels[t.node], t.dof, t.coefficient))
                .collect()
        };
        assert_eq!(terms(0), vec![(15, 1, 1.0), (16, 2, -0.5), (17, 3, -0.5)]);
        // Sets sorted by label: 11 with 12, then 13 with 14.
        assert_eq!(terms(1), vec![(11, 2, 1.0), (12, 2, -1.0)]);
        assert_eq!(terms(2), vec![(13, 2, 1.0), (14, 2, -1.0)]);
        assert_eq!(deck.equations[1].source, deck.equations[2].source);
    }

    #[test]
    fn transforms_give_orthonormal_local_axes() {
        let text = format!(
            "{}*TRANSFORM, NSET=NALL, TYPE=C\n0., 0., -1., 0., 0., 3.\n",
            one_tet()
        );
        let deck = read_text("transform-c", &text).unwrap();
        let t = &deck.transforms[0];
        assert_eq!(t.kind, TransformKind::Cylindrical);
        let axes = t.axes([0.0, 2.0, 5.0]).unwrap();
        assert_eq!(axes, [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]);
        assert!(t.axes([0.0, 0.0, 0.5]).is_none(), "on the axis");
        let text = format!(
            "{}*TRANSFORM, NSET=NALL\n1., 1., 0., -1., 1., 0.\n",
            one_tet()
        );
        let deck = read_text("transform-r", &text).unwrap();
        let axes = deck.transforms[0].axes([9.0; 3]).unwrap();
        let s = 0.5f64.sqrt();
        for (got, want) in axes
            .iter()
            .zip([[s, s, 0.0], [-s, s, 0.0], [0.0, 0.0, 1.0]])
        {
            for k in 0..3 {
                assert!((got[k] - want[k]).abs() < 1e-15, "{axes:?}");
            }
        }
    }

    #[test]
    fn bad_constraint_input_is_refused_at_its_line() {
        let base = one_tet();
        let n = base.lines().count();
        let cases = [
            (
                "*TRANSFORM, NSET=NALL, TYPE=C\n1., 2., 3., 1., 2., 3.\n",
                n + 2,
                "no axis",
            ),
            (
                "*TRANSFORM, NSET=NALL, TYPE=R\n1., 0., 0., 2., 0., 0.\n",
                n + 2,
                "off the line",
            ),
            ("*TRANSFORM, NSET=NALL, TYPE=X\n", n + 1, "TYPE=X"),
            ("*EQUATION\n2\n11, 1, 1., 99, 1, -1.\n", n + 3, "node 99"),
            ("*EQUATION\n2\n11, 1, 1., GHOST, 1, -1.\n", n + 3, "GHOST"),
            ("*EQUATION\n2\n11, 4, 1., 12, 4, -1.\n", n + 3, "rotation"),
            (
                "*EQUATION\n2\n11, 1, 1.\n*NSET, NSET=Z\n11\n",
                n + 2,
                "2 terms announced",
            ),
            (
                "*EQUATION\n2\n11, 1, 1., 12, 1, -1., 13, 1, 1.\n",
                n + 3,
                "goes past",
            ),
            ("*EQUATION\nx\n", n + 2, "number of terms"),
            (
                "*EQUATION\n2\n11, 1, 1., NALL, 1, -1.\n",
                n + 3,
                "single node",
            ),
            (
                "*NSET, NSET=U, UNSORTED\n12, 11\n*NSET, NSET=V\n13, 14\n*EQUATION\n2\nU, 1, \
                 1., V, 1, -1.\n",
                n + 7,
                "UNSORTED",
            ),
            (
                "*NSET, NSET=TWO\n11, 12\n*EQUATION\n2\nTWO, 1, 1., NALL, 1, -1.\n",
                n + 5,
                "same number of nodes",
            ),
            (
                "*SURFACE, NAME=S\n7, S1\n*COUPLING, REF NODE=20, SURFACE=S, CONSTRAINT NAME=C\n\
                 *KINEMATIC\n",
                n + 4,
                "*KINEMATIC",
            ),
            (
                "*SURFACE, NAME=S\n7, S1\n*COUPLING, REF NODE=20, SURFACE=S, CONSTRAINT NAME=C\n\
                 *DISTRIBUTING, COUPLING=STRUCTURAL\n",
                n + 4,
                "STRUCTURAL",
            ),
            ("*DISTRIBUTING\n", n + 1, "must follow a *COUPLING"),
            (
                "*SURFACE, NAME=S\n7, S1\n*COUPLING, REF NODE=20, SURFACE=S, CONSTRAINT NAME=C\n\
                 *DISTRIBUTING\n*BOUNDARY\n20, 4, 6\n",
                n + 6,
                "no rotations",
            ),
            (
                "*SURFACE, NAME=S\n7, S1\n*COUPLING, REF NODE=20, SURFACE=S, CONSTRAINT NAME=C\n\
                 *DISTRIBUTING\n*BOUNDARY\nNALL, ENCASTRE\n",
                n + 6,
                "no rotations",
            ),
            (
                "*COUPLING, REF NODE=20, SURFACE=NOPE, CONSTRAINT NAME=C\n*DISTRIBUTING\n",
                n + 1,
                "surface NOPE",
            ),
            ("*BOUNDARY, FIXED\nNALL, 1\n", n + 1, "belongs in a step"),
        ];
        for (i, (tail, line, needle)) in cases.iter().enumerate() {
            let (_, got, message) = parse_error(read_text(
                &format!("err-constraint-{i}"),
                &format!("{base}{tail}"),
            ));
            assert_eq!(got, *line, "{tail}: {message}");
            assert!(message.contains(needle), "{tail}: {message}");
        }
    }
}
