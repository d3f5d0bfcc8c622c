//! Reader for Abaqus / CalculiX input decks (`.inp`): the flat (part-less) subset brake
//! models use, into a [`Deck`] (the [`Mesh`] plus supports, loads and steps).
//!
//! # Keywords read
//!
//! | keyword | what is kept |
//! |---|---|
//! | `*HEADING` | [`Deck::heading`] |
//! | `*INCLUDE, INPUT=` | the file's lines, in place (path relative to the including file; nests) |
//! | `*NODE` (`NSET=`) | nodes; `SYSTEM=` other than `R` is refused |
//! | `*ELEMENT, TYPE=C3D10` (`ELSET=`) | elements; other types are refused by name |
//! | `*NSET` / `*ELSET` (`GENERATE`, set names in data, `*NSET, ELSET=`) | node / element sets |
//! | `*SURFACE, TYPE=ELEMENT` / `TYPE=NODE` | [`Mesh::surfaces`] / a node set listed in [`Deck::node_surfaces`] |
//! | `*MATERIAL, NAME=`, `*ELASTIC` (isotropic), `*DENSITY` | [`Mesh::materials`] |
//! | `*SOLID SECTION, ELSET=, MATERIAL=` | one [`Part`] per section |
//! | `*BOUNDARY`, `*CLOAD`, `*DSLOAD`, `*DLOAD` | [`Boundary`], [`ConcentratedLoad`], [`PressureLoad`] |
//! | `*STEP` ... `*END STEP`, `*STATIC`, `*FREQUENCY` | [`Step`] |
//!
//! `INPUT=` on a data keyword (`*NODE, INPUT=nodes.inp`) reads its data lines from that file.
//! A keyword line ending with a comma continues on the next line. Other keywords (`*OUTPUT`,
//! `*NODE FILE`, `*CONTACT PAIR`, `*TIE`, ...) are skipped with their data lines and listed, with
//! counts and the first place each appeared, in ONE warning. Keywords that would silently change
//! geometry or load directions if skipped (`*PART`/`*INSTANCE`, `*SYSTEM`, `*TRANSFORM`, node and
//! element generation) are refused with an error instead.
//!
//! # Conventions decided here
//!
//! - Keywords, parameter names and the names of sets, surfaces and materials are
//!   case-insensitive, as in Abaqus. Names are stored in UPPER CASE (the keys of
//!   [`Mesh::node_sets`], [`Mesh::surfaces`], [`Mesh::materials`], [`Deck::element_sets`], part
//!   and material names); error messages quote the spelling used on the offending line.
//! - Node and element labels are any positive integers; they may be used before the line that
//!   defines them (they are resolved once the whole deck is read). A set named in the data
//!   lines of `*NSET`, `*ELSET` or `*SURFACE, TYPE=NODE` must already be defined: its current
//!   members are copied, as Abaqus does. Every other name (in `*SOLID SECTION`, element-based
//!   `*SURFACE`, loads, supports) is looked up in the complete model, and an unknown one is an
//!   error at the line that names it. Repeating `*NSET`/`*ELSET` with one name adds to the set.
//! - Labels written explicitly in a set must exist; labels produced by `GENERATE` that no node
//!   or element carries are left out with a warning (ranges over gappy numbering are common).
//! - DOFs are Abaqus' 1-based numbers in the raw records ([`Boundary::first_dof`]); DOFs 4-6
//!   (rotations, which solid nodes do not have) are dropped with a warning. In [`Loading`]
//!   they become 0-based components (0 = x).
//! - Pressures keep Abaqus' sign: a positive value pushes INTO the element, against the
//!   outward face normal of [`crate::mesh::TET10_FACES`].
//!
//! # Steps and what is in force
//!
//! Supports and loads outside any step are model data ([`Deck::boundaries`] ...); those inside
//! a step are stored on that [`Step`]. [`Deck::loading_in_step`] gives what acts in step k, with
//! the Abaqus/CalculiX rules (`OP=MOD` by default):
//! model data, then every earlier step that is not a linear-perturbation step, then step k.
//! A later definition on the same (node, DOF) replaces the earlier value; a `*DSLOAD` on a
//! surface replaces the earlier `*DSLOAD` on that surface; a `*DLOAD` on an element face
//! replaces the earlier one on that face; different surfaces loading one face add up.
//! `OP=NEW` on a keyword removes everything of that kind in force before the step (model data
//! included). The loads of a linear-perturbation step (`*FREQUENCY`, `*COMPLEX FREQUENCY`,
//! `*BUCKLE`, ..., or any step with `PERTURBATION` on `*STEP`) act in that step only.
//!
//! # `*FREQUENCY` data line
//!
//! CalculiX: number of eigenfrequencies desired, lower and upper value of the frequency range
//! of interest (cycles per time). Abaqus' Lanczos and AMS eigensolvers (the default) use the
//! same first three fields, then the shift point; `EIGENSOLVER=SUBSPACE` uses number of
//! eigenvalues, maximum frequency of interest, shift point. All land in [`FrequencyRequest`].

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};
use std::fmt;
use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

use crate::mesh::{Face, Material, Mesh, MeshError, Part, Surface};

/// A file and 1-based line number in the deck (for messages further down the pipeline).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourceLine {
    pub file: PathBuf,
    pub line: usize,
}

impl fmt::Display for SourceLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.file.display(), self.line)
    }
}

/// What a `*BOUNDARY` or `*CLOAD` line names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NodeTarget {
    /// A node set (or node-based surface), by its upper-case name.
    Set(String),
    /// One node, by its label in the file.
    Node(i64),
}

/// One `*BOUNDARY` line: prescribed displacement `value` on DOFs `first_dof..=last_dof`.
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary {
    pub target: NodeTarget,
    /// Internal node indices of the target, sorted.
    pub nodes: Vec<usize>,
    /// Abaqus DOF numbers, 1 = x, 2 = y, 3 = z, with `1 <= first_dof <= last_dof <= 3`.
    pub first_dof: u8,
    pub last_dof: u8,
    pub value: f64,
    pub source: SourceLine,
}

/// One `*CLOAD` line: force `value` on DOF `dof` of every target node.
#[derive(Clone, Debug, PartialEq)]
pub struct ConcentratedLoad {
    pub target: NodeTarget,
    /// Internal node indices of the target, sorted.
    pub nodes: Vec<usize>,
    /// Abaqus DOF number, 1..=3.
    pub dof: u8,
    pub value: f64,
    pub source: SourceLine,
}

/// What a pressure line names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PressureTarget {
    /// `*DSLOAD` on an element-based surface (upper-case name).
    Surface(String),
    /// `*DLOAD` on an element set (upper-case name).
    ElementSet(String),
    /// `*DLOAD` on one element, by its label in the file.
    Element(i64),
}

/// One `*DSLOAD` or `*DLOAD` line: uniform pressure on a list of faces.
#[derive(Clone, Debug, PartialEq)]
pub struct PressureLoad {
    pub target: PressureTarget,
    pub faces: Vec<Face>,
    /// Pressure, Abaqus sign: positive pushes into the element.
    pub value: f64,
    pub source: SourceLine,
}

/// The `*FREQUENCY` request (see the module documentation for the field layouts).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct FrequencyRequest {
    /// Number of eigenvalues wanted (`None`: blank, i.e. all in the range).
    pub eigenvalues: Option<usize>,
    /// Lower end of the frequency range of interest, cycles per time.
    pub lower_frequency: Option<f64>,
    /// Upper end of the frequency range of interest, cycles per time.
    pub upper_frequency: Option<f64>,
    /// Shift point, cycles per time.
    pub shift: Option<f64>,
}

/// The `*STATIC` data line (time incrementation), blanks as `None`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct StaticRequest {
    pub initial_increment: Option<f64>,
    pub time_period: Option<f64>,
    pub minimum_increment: Option<f64>,
    pub maximum_increment: Option<f64>,
}

/// The analysis procedure of a step.
#[derive(Clone, Debug, PartialEq)]
pub enum Procedure {
    Static(StaticRequest),
    Frequency(FrequencyRequest),
    /// A procedure this reader recognises but does not read, e.g. `*COMPLEX FREQUENCY`.
    Unsupported {
        keyword: String,
    },
}

/// Which kinds of load had `OP=NEW` in a step (everything of that kind in force before the
/// step is removed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Replaced {
    pub boundaries: bool,
    pub concentrated_loads: bool,
    /// `*DSLOAD`.
    pub surface_pressures: bool,
    /// `*DLOAD`.
    pub element_pressures: bool,
}

/// One `*STEP` ... `*END STEP`, with the supports and loads defined inside it.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// `NAME=` on `*STEP`.
    pub name: Option<String>,
    /// The optional data line of `*STEP`.
    pub title: Option<String>,
    pub procedure: Procedure,
    /// A linear-perturbation step: its own supports and loads act in this step only.
    pub perturbation: bool,
    /// `NLGEOM` on `*STEP`.
    pub nlgeom: bool,
    pub boundaries: Vec<Boundary>,
    pub concentrated_loads: Vec<ConcentratedLoad>,
    pub pressures: Vec<PressureLoad>,
    pub replaced: Replaced,
    /// The `*STEP` line.
    pub source: SourceLine,
}

/// The supports and loads in force, resolved to nodes and faces.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Loading {
    /// Prescribed displacement per (node index, component 0..3).
    pub displacements: BTreeMap<(usize, usize), f64>,
    /// Concentrated force per (node index, component 0..3).
    pub forces: BTreeMap<(usize, usize), f64>,
    /// Net pressure per face (Abaqus sign), sorted by (element, side).
    pub pressures: Vec<(Face, f64)>,
}

/// Everything read from a deck.
#[derive(Clone, Debug, Default)]
pub struct Deck {
    /// Nodes, C3D10 elements, one part per `*SOLID SECTION`, materials, node sets and
    /// element-based surfaces.
    pub mesh: Mesh,
    /// The `*HEADING` data lines, joined by newlines.
    pub heading: String,
    /// Element sets (internal element indices, sorted, unique).
    pub element_sets: BTreeMap<String, Vec<usize>>,
    /// Names of `*SURFACE, TYPE=NODE` surfaces; each is also in [`Mesh::node_sets`].
    pub node_surfaces: BTreeSet<String>,
    /// Model-data supports (outside any step).
    pub boundaries: Vec<Boundary>,
    /// Model-data concentrated loads.
    pub concentrated_loads: Vec<ConcentratedLoad>,
    /// Model-data pressures.
    pub pressures: Vec<PressureLoad>,
    pub steps: Vec<Step>,
    /// Things a person should know: skipped keywords, ignored parameters and DOFs...
    pub warnings: Vec<String>,
}

impl Deck {
    /// Supports and loads of the model data alone.
    pub fn model_loading(&self) -> Loading {
        let mut state = LoadState::default();
        state.apply(
            &Replaced::default(),
            &self.boundaries,
            &self.concentrated_loads,
            &self.pressures,
        );
        state.finish(&self.mesh)
    }

    /// Supports and loads in force in step `step` (0-based), by the rules in the module
    /// documentation; `None` if there is no such step.
    pub fn loading_in_step(&self, step: usize) -> Option<Loading> {
        let target = self.steps.get(step)?;
        let mut state = LoadState::default();
        state.apply(
            &Replaced::default(),
            &self.boundaries,
            &self.concentrated_loads,
            &self.pressures,
        );
        for earlier in self.steps[..step].iter().filter(|s| !s.perturbation) {
            state.apply(
                &earlier.replaced,
                &earlier.boundaries,
                &earlier.concentrated_loads,
                &earlier.pressures,
            );
        }
        state.apply(
            &target.replaced,
            &target.boundaries,
            &target.concentrated_loads,
            &target.pressures,
        );
        Some(state.finish(&self.mesh))
    }
}

#[derive(Default)]
struct LoadState {
    displacements: BTreeMap<(usize, usize), f64>,
    forces: BTreeMap<(usize, usize), f64>,
    /// `*DSLOAD`s by surface name: a new one on the same surface replaces the old.
    surface_pressures: BTreeMap<String, (Vec<Face>, f64)>,
    /// `*DLOAD`s by (element, side).
    element_pressures: BTreeMap<(usize, u8), f64>,
}

impl LoadState {
    fn apply(
        &mut self,
        replaced: &Replaced,
        boundaries: &[Boundary],
        loads: &[ConcentratedLoad],
        pressures: &[PressureLoad],
    ) {
        if replaced.boundaries {
            self.displacements.clear();
        }
        if replaced.concentrated_loads {
            self.forces.clear();
        }
        if replaced.surface_pressures {
            self.surface_pressures.clear();
        }
        if replaced.element_pressures {
            self.element_pressures.clear();
        }
        for b in boundaries {
            for &n in &b.nodes {
                for dof in b.first_dof..=b.last_dof {
                    self.displacements
                        .insert((n, usize::from(dof) - 1), b.value);
                }
            }
        }
        for c in loads {
            for &n in &c.nodes {
                self.forces.insert((n, usize::from(c.dof) - 1), c.value);
            }
        }
        for p in pressures {
            match &p.target {
                PressureTarget::Surface(name) => {
                    self.surface_pressures
                        .insert(name.clone(), (p.faces.clone(), p.value));
                }
                _ => {
                    for f in &p.faces {
                        self.element_pressures.insert((f.element, f.side), p.value);
                    }
                }
            }
        }
    }

    fn finish(self, mesh: &Mesh) -> Loading {
        let mut net = self.element_pressures;
        for (faces, value) in self.surface_pressures.values() {
            for f in faces {
                *net.entry((f.element, f.side)).or_insert(0.0) += value;
            }
        }
        Loading {
            displacements: self.displacements,
            forces: self.forces,
            pressures: net
                .into_iter()
                .map(|((e, side), p)| (mesh.face(e, side), p))
                .collect(),
        }
    }
}

/// Read an Abaqus/CalculiX deck (and the files it includes).
pub fn read(path: &Path) -> Result<Deck, MeshError> {
    let mut reader = Reader::new(path)?;
    reader.run()?;
    reader.finish()
}

// ---------------------------------------------------------------------------------------------
// Lines from the deck and its included files.

/// Deeper nesting than this is surely a mistake (and a cycle is caught before it anyway).
const MAX_INCLUDE_DEPTH: usize = 32;
/// A `GENERATE` range longer than this is a typo, not a set.
const MAX_GENERATED: i64 = 100_000_000;

/// A place in the deck: index into `Lines::files` and 1-based line.
#[derive(Clone, Copy, Debug)]
struct Loc {
    file: u32,
    line: u32,
}

struct OpenFile {
    reader: BufReader<File>,
    file: u32,
    line: u32,
    canonical: PathBuf,
}

struct Lines {
    files: Vec<PathBuf>,
    stack: Vec<OpenFile>,
    bytes: Vec<u8>,
}

impl Lines {
    fn new(path: &Path) -> Result<Self, MeshError> {
        let file = File::open(path).map_err(|source| MeshError::Io {
            file: path.to_path_buf(),
            source,
        })?;
        Ok(Lines {
            files: vec![path.to_path_buf()],
            stack: vec![OpenFile {
                reader: BufReader::new(file),
                file: 0,
                line: 0,
                canonical: path.canonicalize().unwrap_or_else(|_| path.to_path_buf()),
            }],
            bytes: Vec::new(),
        })
    }

    fn error(&self, loc: Loc, message: impl Into<String>) -> MeshError {
        MeshError::parse(
            self.files[loc.file as usize].clone(),
            loc.line as usize,
            message,
        )
    }

    fn source(&self, loc: Loc) -> SourceLine {
        SourceLine {
            file: self.files[loc.file as usize].clone(),
            line: loc.line as usize,
        }
    }

    fn at(&self, loc: Loc) -> String {
        self.source(loc).to_string()
    }

    /// Continue reading from `name` (relative to the file of `from`), then return to the
    /// line after `from`.
    fn include(&mut self, name: &str, from: Loc, keyword: &str) -> Result<(), MeshError> {
        let including = &self.files[from.file as usize];
        let path = match including.parent() {
            Some(dir) => dir.join(name),
            None => PathBuf::from(name),
        };
        let file = File::open(&path).map_err(|e| {
            self.error(
                from,
                format!(
                    "{keyword}: cannot open the file \"{name}\" ({}): {e}",
                    path.display()
                ),
            )
        })?;
        let canonical = path.canonicalize().unwrap_or_else(|_| path.clone());
        if self.stack.iter().any(|open| open.canonical == canonical) {
            return Err(self.error(
                from,
                format!("{keyword}: \"{name}\" is already being read (the includes form a cycle)"),
            ));
        }
        if self.stack.len() >= MAX_INCLUDE_DEPTH {
            return Err(self.error(
                from,
                format!("{keyword}: includes nested more than {MAX_INCLUDE_DEPTH} deep"),
            ));
        }
        let index = u32::try_from(self.files.len())
            .map_err(|_| self.error(from, "too many included files"))?;
        self.files.push(path);
        self.stack.push(OpenFile {
            reader: BufReader::new(file),
            file: index,
            line: 0,
            canonical,
        });
        Ok(())
    }

    /// The next line (untrimmed) into `buf`, or `None` at the end of the top-level file.
    fn next(&mut self, buf: &mut String) -> Result<Option<Loc>, MeshError> {
        loop {
            let Some(top) = self.stack.last_mut() else {
                return Ok(None);
            };
            self.bytes.clear();
            let n = top
                .reader
                .read_until(b'\n', &mut self.bytes)
                .map_err(|source| MeshError::Io {
                    file: self.files[top.file as usize].clone(),
                    source,
                })?;
            if n == 0 {
                self.stack.pop();
                continue;
            }
            top.line = top.line.saturating_add(1);
            buf.clear();
            // Headings and comments written on Windows are often Latin-1: keep going.
            let text = String::from_utf8_lossy(&self.bytes);
            // A byte-order mark would hide the '*' of a first keyword line.
            buf.push_str(match top.line {
                1 => text.strip_prefix('\u{feff}').unwrap_or(&text),
                _ => &text,
            });
            return Ok(Some(Loc {
                file: top.file,
                line: top.line,
            }));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Keyword lines and fields.

struct Param {
    key: String,
    value: Option<String>,
    used: bool,
}

struct Keyword {
    /// Upper case, blanks removed: "SOLIDSECTION".
    name: String,
    /// For messages: "*SOLID SECTION".
    display: String,
    params: Vec<Param>,
    loc: Loc,
}

impl Keyword {
    fn parse(text: &str, loc: Loc) -> Result<Keyword, String> {
        let fields = split_fields(&text[1..]);
        let words: Vec<&str> = fields[0].split_whitespace().collect();
        if words.is_empty() {
            return Err("expected a keyword after '*'".into());
        }
        let display = format!("*{}", words.join(" ").to_uppercase());
        let mut params = Vec::new();
        for field in &fields[1..] {
            if field.is_empty() {
                continue;
            }
            let (key, value) = match field.split_once('=') {
                Some((k, v)) => (k, Some(unquote(v.trim()).to_string())),
                None => (*field, None),
            };
            let key: String = key.split_whitespace().collect::<String>().to_uppercase();
            if key.is_empty() {
                return Err(format!(
                    "{display}: expected a parameter name before '=' in \"{field}\""
                ));
            }
            params.push(Param {
                key,
                value,
                used: false,
            });
        }
        Ok(Keyword {
            name: words.concat().to_uppercase(),
            display,
            params,
            loc,
        })
    }

    fn flag(&mut self, key: &str) -> bool {
        match self.params.iter_mut().find(|p| p.key == key) {
            Some(p) => {
                p.used = true;
                true
            }
            None => false,
        }
    }

    fn value(&mut self, key: &str) -> Result<Option<String>, String> {
        match self.params.iter_mut().find(|p| p.key == key) {
            None => Ok(None),
            Some(p) => {
                p.used = true;
                match &p.value {
                    Some(v) if !v.is_empty() => Ok(Some(v.clone())),
                    _ => Err(format!(
                        "{}: expected a value for the parameter {key} ({key}=...)",
                        self.display
                    )),
                }
            }
        }
    }

    fn required(&mut self, key: &str) -> Result<String, String> {
        self.value(key)?.ok_or_else(|| {
            format!(
                "{}: expected the parameter {key}= (it is required)",
                self.display
            )
        })
    }
}

/// Split on commas outside double quotes, trimming each field.
fn split_fields(text: &str) -> Vec<&str> {
    if !text.contains('"') {
        return text.split(',').map(str::trim).collect();
    }
    let mut out = Vec::new();
    let (mut start, mut quoted) = (0, false);
    for (i, c) in text.char_indices() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => {
                out.push(text[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(text[start..].trim());
    out
}

/// Data fields with trailing blanks dropped ("1, 2," has two fields).
fn data_fields(text: &str) -> Vec<&str> {
    let mut f = split_fields(text);
    while f.last() == Some(&"") {
        f.pop();
    }
    f
}

fn unquote(s: &str) -> &str {
    s.strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or(s)
}

/// A field that is a label rather than a name: Abaqus names start with a letter or '_'.
fn looks_numeric(field: &str) -> bool {
    field
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_digit() || c == '+' || c == '-')
}

fn parse_number(field: &str) -> Option<f64> {
    // Fortran writers use D exponents (1.0D+03).
    let value = if field.contains(['d', 'D']) {
        field.replace(['d', 'D'], "e").parse::<f64>()
    } else {
        field.parse::<f64>()
    };
    value.ok().filter(|x| x.is_finite())
}

/// A set, surface or material name: canonical (upper-case) and as written.
#[derive(Clone, Debug)]
struct Name {
    canon: String,
    written: String,
}

impl Name {
    fn new(written: &str) -> Name {
        let written = unquote(written.trim()).to_string();
        Name {
            canon: written.to_uppercase(),
            written,
        }
    }
}

/// Element types read as C3D10: same nodes and node order; squeal uses its own formulation.
const C3D10_VARIANTS: [&str; 6] = ["C3D10M", "C3D10I", "C3D10H", "C3D10HS", "C3D10MH", "C3D10T"];

/// Procedures that are recognised (so that a step using one is kept) but not read.
const OTHER_PROCEDURES: [&str; 18] = [
    "COMPLEXFREQUENCY",
    "BUCKLE",
    "STEADYSTATEDYNAMICS",
    "MODALDYNAMIC",
    "RANDOMRESPONSE",
    "RESPONSESPECTRUM",
    "MATRIXGENERATE",
    "SUBSTRUCTUREGENERATE",
    "DYNAMIC",
    "HEATTRANSFER",
    "COUPLEDTEMPERATURE-DISPLACEMENT",
    "UNCOUPLEDTEMPERATURE-DISPLACEMENT",
    "VISCO",
    "GEOSTATIC",
    "SOILS",
    "GREEN",
    "SENSITIVITY",
    "COUPLEDTHERMAL-ELECTRIC",
];

/// Linear-perturbation procedures (their loads do not carry over to later steps).
const PERTURBATION_PROCEDURES: [&str; 8] = [
    "FREQUENCY",
    "COMPLEXFREQUENCY",
    "BUCKLE",
    "STEADYSTATEDYNAMICS",
    "MODALDYNAMIC",
    "RANDOMRESPONSE",
    "RESPONSESPECTRUM",
    "MATRIXGENERATE",
];

/// Keywords whose omission would silently change the geometry or the load directions.
fn refused(name: &str) -> Option<&'static str> {
    Some(match name {
        "PART" | "ENDPART" | "ASSEMBLY" | "ENDASSEMBLY" | "INSTANCE" | "ENDINSTANCE" => {
            "Abaqus part/assembly input is not supported: write the deck without parts and \
             assemblies (in Abaqus/CAE: Model > Edit Attributes > Do not use parts and \
             assemblies in input files)"
        }
        "SYSTEM" => "*SYSTEM would move the nodes that follow; give global coordinates instead",
        "TRANSFORM" => {
            "*TRANSFORM (local DOF directions) is not supported; give supports and loads in \
             global directions"
        }
        "NGEN" | "NFILL" | "NCOPY" | "NMAP" | "ELGEN" | "ELCOPY" => {
            "node and element generation is not supported; list the nodes and elements"
        }
        _ => return None,
    })
}

// ---------------------------------------------------------------------------------------------
// Drafts: what the deck said, before labels and names are resolved.

#[derive(Clone, Copy, Debug)]
struct Member {
    label: i64,
    loc: Loc,
    generated: bool,
}

struct SetDraft {
    written: String,
    members: Vec<Member>,
}

enum NodeRef {
    Set(Name),
    Node(i64),
}

enum ElementRef {
    Set(Name),
    Element(i64),
}

struct SurfaceMember {
    target: ElementRef,
    /// 0..4, or `None` for "every free face of the set".
    side: Option<u8>,
    loc: Loc,
}

struct SurfaceDraft {
    written: String,
    members: Vec<SurfaceMember>,
    loc: Loc,
}

struct MaterialDraft {
    written: String,
    elastic: Option<(f64, f64)>,
    density: Option<f64>,
    loc: Loc,
}

struct SectionDraft {
    elset: Name,
    material: Name,
    loc: Loc,
}

struct BoundaryDraft {
    target: NodeRef,
    first_dof: u8,
    last_dof: u8,
    value: f64,
    loc: Loc,
}

struct LoadDraft {
    target: NodeRef,
    dof: u8,
    value: f64,
    loc: Loc,
}

struct SurfacePressureDraft {
    surface: Name,
    value: f64,
    loc: Loc,
}

struct ElementPressureDraft {
    target: ElementRef,
    side: u8,
    value: f64,
    loc: Loc,
}

#[derive(Default)]
struct LoadDrafts {
    boundaries: Vec<BoundaryDraft>,
    loads: Vec<LoadDraft>,
    surface_pressures: Vec<SurfacePressureDraft>,
    element_pressures: Vec<ElementPressureDraft>,
    /// Surface and element pressures in the order written (true = surface).
    pressure_order: Vec<bool>,
}

struct StepDraft {
    name: Option<String>,
    title: Option<String>,
    procedure: Option<(Procedure, Loc)>,
    perturbation_parameter: bool,
    nlgeom: bool,
    loads: LoadDrafts,
    replaced: Replaced,
    loc: Loc,
}

struct PendingElement {
    values: Vec<i64>,
    last: Loc,
}

/// What data lines mean under the current keyword.
#[derive(Default)]
enum Block {
    /// Before the first keyword.
    #[default]
    Start,
    /// A skipped keyword, or data that is not needed.
    Skip,
    /// A keyword that takes no data lines.
    NoData(String),
    Heading,
    Node {
        nset: Option<Name>,
    },
    Element {
        elset: Option<Name>,
    },
    NodeSet {
        name: Name,
        generate: bool,
    },
    ElementSet {
        name: Name,
        generate: bool,
    },
    ElementSurface {
        name: Name,
    },
    NodeSurface {
        name: Name,
    },
    Elastic {
        material: String,
        lines: usize,
    },
    Density {
        material: String,
        lines: usize,
    },
    StepTitle {
        lines: usize,
    },
    Static {
        lines: usize,
    },
    Frequency {
        subspace: bool,
        lines: usize,
    },
    Boundary,
    ConcentratedLoad,
    SurfacePressure,
    ElementPressure,
}

/// Occurrences of something to warn about, by key: count and first place.
#[derive(Default)]
struct Tally {
    entries: Vec<(String, usize, Loc)>,
    index: HashMap<String, usize>,
}

impl Tally {
    fn add(&mut self, key: &str, loc: Loc) {
        match self.index.get(key) {
            Some(&i) => self.entries[i].1 += 1,
            None => {
                self.index.insert(key.to_string(), self.entries.len());
                self.entries.push((key.to_string(), 1, loc));
            }
        }
    }

    fn describe(&self, lines: &Lines) -> String {
        self.entries
            .iter()
            .map(|(key, n, loc)| format!("{key} ({n}x, first at {})", lines.at(*loc)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

// ---------------------------------------------------------------------------------------------
// The reader.

struct Reader {
    lines: Lines,
    block: Block,
    heading: Vec<String>,

    nodes: Vec<[f64; 3]>,
    node_labels: Vec<i64>,
    node_locs: Vec<Loc>,
    node_index: HashMap<i64, usize>,

    elements: Vec<[i64; 10]>,
    element_labels: Vec<i64>,
    element_locs: Vec<Loc>,
    element_index: HashMap<i64, usize>,
    pending: Option<PendingElement>,

    node_sets: BTreeMap<String, SetDraft>,
    element_sets: BTreeMap<String, SetDraft>,
    surfaces: BTreeMap<String, SurfaceDraft>,
    node_surfaces: BTreeMap<String, Loc>,
    materials: BTreeMap<String, MaterialDraft>,
    /// The material that `*ELASTIC` / `*DENSITY` belong to.
    material: Option<String>,
    sections: Vec<SectionDraft>,

    model: LoadDrafts,
    step: Option<StepDraft>,
    steps: Vec<StepDraft>,

    unknown_keywords: Tally,
    ignored_parameters: Tally,
    rotational_dofs: Tally,
    variant_types: Tally,
    other_procedures: Tally,
    warnings: Vec<String>,
}

impl Reader {
    fn new(path: &Path) -> Result<Self, MeshError> {
        Ok(Reader {
            lines: Lines::new(path)?,
            block: Block::Start,
            heading: Vec::new(),
            nodes: Vec::new(),
            node_labels: Vec::new(),
            node_locs: Vec::new(),
            node_index: HashMap::new(),
            elements: Vec::new(),
            element_labels: Vec::new(),
            element_locs: Vec::new(),
            element_index: HashMap::new(),
            pending: None,
            node_sets: BTreeMap::new(),
            element_sets: BTreeMap::new(),
            surfaces: BTreeMap::new(),
            node_surfaces: BTreeMap::new(),
            materials: BTreeMap::new(),
            material: None,
            sections: Vec::new(),
            model: LoadDrafts::default(),
            step: None,
            steps: Vec::new(),
            unknown_keywords: Tally::default(),
            ignored_parameters: Tally::default(),
            rotational_dofs: Tally::default(),
            variant_types: Tally::default(),
            other_procedures: Tally::default(),
            warnings: Vec::new(),
        })
    }

    fn err(&self, loc: Loc, message: impl Into<String>) -> MeshError {
        self.lines.error(loc, message)
    }

    fn number(&self, field: &str, loc: Loc, what: &str) -> Result<f64, MeshError> {
        parse_number(field).ok_or_else(|| {
            self.err(
                loc,
                format!("expected a number ({what}), found \"{field}\""),
            )
        })
    }

    /// Field `k` as a number, `None` when missing or blank (Abaqus: blank = default).
    fn optional_number(
        &self,
        fields: &[&str],
        k: usize,
        loc: Loc,
        what: &str,
    ) -> Result<Option<f64>, MeshError> {
        match fields.get(k) {
            None | Some(&"") => Ok(None),
            Some(f) => self.number(f, loc, what).map(Some),
        }
    }

    fn label(&self, field: &str, loc: Loc, what: &str) -> Result<i64, MeshError> {
        match field.parse::<i64>() {
            Ok(v) if v > 0 => Ok(v),
            _ => Err(self.err(
                loc,
                format!("expected a positive integer ({what}), found \"{field}\""),
            )),
        }
    }

    fn param(&self, kw: &mut Keyword, key: &str) -> Result<Option<String>, MeshError> {
        kw.value(key).map_err(|m| self.err(kw.loc, m))
    }

    fn required(&self, kw: &mut Keyword, key: &str) -> Result<String, MeshError> {
        kw.required(key).map_err(|m| self.err(kw.loc, m))
    }

    // --- the line loop ------------------------------------------------------------------

    fn run(&mut self) -> Result<(), MeshError> {
        let mut buf = String::new();
        while let Some(loc) = self.lines.next(&mut buf)? {
            let text = buf.trim();
            if text.is_empty() || text.starts_with("**") {
                continue;
            }
            if !text.starts_with('*') {
                self.data(text, loc)?;
                continue;
            }
            // A keyword line that ends with a comma continues on the next line.
            let mut line = text.to_string();
            while line.ends_with(',') {
                if self.lines.next(&mut buf)?.is_none() {
                    return Err(self.err(
                        loc,
                        "the keyword line ends with a comma, so it continues on the next \
                         line, but the file ends here",
                    ));
                }
                let more = buf.trim();
                if more.is_empty() || more.starts_with("**") {
                    continue;
                }
                line.push_str(more);
            }
            let keyword = Keyword::parse(&line, loc).map_err(|m| self.err(loc, m))?;
            self.keyword(keyword)?;
        }
        self.finish_element(None)?;
        if let Some(step) = &self.step {
            return Err(self.err(
                step.loc,
                "this *STEP has no *END STEP before the end of the file",
            ));
        }
        Ok(())
    }

    fn keyword(&mut self, mut kw: Keyword) -> Result<(), MeshError> {
        if kw.name == "INCLUDE" {
            // The included lines take the place of the *INCLUDE line: the current block
            // goes on (an included file may hold just data lines).
            let input = self.required(&mut kw, "INPUT")?;
            self.note_unused_parameters(&kw);
            return self.lines.include(&input, kw.loc, "*INCLUDE");
        }
        self.finish_element(Some(&kw))?;
        if !matches!(kw.name.as_str(), "ELASTIC" | "DENSITY") && self.is_known(&kw.name) {
            self.material = None;
        }
        let input = if self.is_known(&kw.name) {
            self.param(&mut kw, "INPUT")?
        } else {
            None
        };
        let block = match kw.name.as_str() {
            "HEADING" => {
                self.model_only(&kw)?;
                Block::Heading
            }
            "NODE" => self.node_keyword(&mut kw)?,
            "ELEMENT" => self.element_keyword(&mut kw)?,
            "NSET" => self.node_set_keyword(&mut kw)?,
            "ELSET" => self.element_set_keyword(&mut kw)?,
            "SURFACE" => self.surface_keyword(&mut kw)?,
            "MATERIAL" => self.material_keyword(&mut kw)?,
            "ELASTIC" => {
                let material = self.current_material(&kw)?;
                if let Some(t) = self.param(&mut kw, "TYPE")? {
                    if !matches!(t.to_uppercase().as_str(), "ISO" | "ISOTROPIC") {
                        return Err(self.err(
                            kw.loc,
                            format!(
                                "*ELASTIC, TYPE={t} is not supported (squeal needs isotropic \
                                 elasticity: TYPE=ISOTROPIC)"
                            ),
                        ));
                    }
                }
                Block::Elastic { material, lines: 0 }
            }
            "DENSITY" => {
                let material = self.current_material(&kw)?;
                Block::Density { material, lines: 0 }
            }
            "SOLIDSECTION" => {
                self.model_only(&kw)?;
                let elset = Name::new(&self.required(&mut kw, "ELSET")?);
                let material = Name::new(&self.required(&mut kw, "MATERIAL")?);
                // An orientation changes nothing for an isotropic material.
                kw.flag("ORIENTATION");
                kw.flag("CONTROLS");
                self.sections.push(SectionDraft {
                    elset,
                    material,
                    loc: kw.loc,
                });
                // The optional data line (thickness) means nothing for solids.
                Block::Skip
            }
            "STEP" => self.step_keyword(&mut kw)?,
            "ENDSTEP" => {
                let Some(step) = self.step.take() else {
                    return Err(self.err(kw.loc, "*END STEP without a *STEP before it"));
                };
                if step.procedure.is_none() {
                    return Err(self.err(
                        kw.loc,
                        format!(
                            "the step that begins at {} has no procedure (expected *STATIC or \
                             *FREQUENCY)",
                            self.lines.at(step.loc)
                        ),
                    ));
                }
                self.steps.push(step);
                Block::NoData(kw.display.clone())
            }
            "STATIC" => {
                kw.flag("SOLVER");
                self.set_procedure(&kw, Procedure::Static(StaticRequest::default()))?;
                Block::Static { lines: 0 }
            }
            "FREQUENCY" => {
                let solver = self.param(&mut kw, "EIGENSOLVER")?;
                // Solver choices and eigenvector scaling do not change what is asked for.
                for harmless in [
                    "SOLVER",
                    "STORAGE",
                    "NORMALIZATION",
                    "SIM",
                    "ACOUSTICCOUPLING",
                ] {
                    kw.flag(harmless);
                }
                let subspace = solver.is_some_and(|s| s.eq_ignore_ascii_case("SUBSPACE"));
                self.set_procedure(&kw, Procedure::Frequency(FrequencyRequest::default()))?;
                Block::Frequency { subspace, lines: 0 }
            }
            "BOUNDARY" => {
                if let Some(t) = self.param(&mut kw, "TYPE")? {
                    if !t.eq_ignore_ascii_case("DISPLACEMENT") {
                        return Err(self.err(
                            kw.loc,
                            format!(
                                "*BOUNDARY, TYPE={t} is not supported (only prescribed \
                                 displacements)"
                            ),
                        ));
                    }
                }
                if self.op_new(&mut kw)? {
                    self.replaced(|r| r.boundaries = true);
                }
                Block::Boundary
            }
            "CLOAD" => {
                if self.op_new(&mut kw)? {
                    self.replaced(|r| r.concentrated_loads = true);
                }
                Block::ConcentratedLoad
            }
            "DSLOAD" => {
                if self.op_new(&mut kw)? {
                    self.replaced(|r| r.surface_pressures = true);
                }
                Block::SurfacePressure
            }
            "DLOAD" => {
                if self.op_new(&mut kw)? {
                    self.replaced(|r| r.element_pressures = true);
                }
                Block::ElementPressure
            }
            name if OTHER_PROCEDURES.contains(&name) => {
                self.set_procedure(
                    &kw,
                    Procedure::Unsupported {
                        keyword: kw.display.clone(),
                    },
                )?;
                self.other_procedures.add(&kw.display, kw.loc);
                Block::Skip
            }
            name => {
                if let Some(why) = refused(name) {
                    return Err(self.err(kw.loc, format!("{}: {why}", kw.display)));
                }
                self.unknown_keywords.add(&kw.display, kw.loc);
                self.block = Block::Skip;
                return Ok(());
            }
        };
        self.note_unused_parameters(&kw);
        self.block = block;
        if let Some(input) = input {
            self.lines.include(&input, kw.loc, &kw.display)?;
        }
        Ok(())
    }

    fn is_known(&self, name: &str) -> bool {
        matches!(
            name,
            "HEADING"
                | "NODE"
                | "ELEMENT"
                | "NSET"
                | "ELSET"
                | "SURFACE"
                | "MATERIAL"
                | "ELASTIC"
                | "DENSITY"
                | "SOLIDSECTION"
                | "STEP"
                | "ENDSTEP"
                | "STATIC"
                | "FREQUENCY"
                | "BOUNDARY"
                | "CLOAD"
                | "DSLOAD"
                | "DLOAD"
        ) || OTHER_PROCEDURES.contains(&name)
    }

    fn note_unused_parameters(&mut self, kw: &Keyword) {
        for p in kw.params.iter().filter(|p| !p.used) {
            self.ignored_parameters
                .add(&format!("{} on {}", p.key, kw.display), kw.loc);
        }
    }

    fn model_only(&self, kw: &Keyword) -> Result<(), MeshError> {
        match &self.step {
            Some(step) => Err(self.err(
                kw.loc,
                format!(
                    "{} is model data and cannot appear inside the step that begins at {}",
                    kw.display,
                    self.lines.at(step.loc)
                ),
            )),
            None => Ok(()),
        }
    }

    fn current_material(&self, kw: &Keyword) -> Result<String, MeshError> {
        self.model_only(kw)?;
        self.material.clone().ok_or_else(|| {
            self.err(
                kw.loc,
                format!(
                    "{} must follow a *MATERIAL (or another option of that material)",
                    kw.display
                ),
            )
        })
    }

    fn set_procedure(&mut self, kw: &Keyword, procedure: Procedure) -> Result<(), MeshError> {
        let Some(step) = &self.step else {
            return Err(self.err(
                kw.loc,
                format!(
                    "{} is a step procedure and must be inside *STEP",
                    kw.display
                ),
            ));
        };
        if let Some((_, loc)) = &step.procedure {
            return Err(self.err(
                kw.loc,
                format!(
                    "{}: this step already has its procedure at {}",
                    kw.display,
                    self.lines.at(*loc)
                ),
            ));
        }
        if let Some(step) = &mut self.step {
            step.procedure = Some((procedure, kw.loc));
        }
        Ok(())
    }

    fn op_new(&self, kw: &mut Keyword) -> Result<bool, MeshError> {
        match self.param(kw, "OP")? {
            None => Ok(false),
            Some(op) if op.eq_ignore_ascii_case("MOD") => Ok(false),
            Some(op) if op.eq_ignore_ascii_case("NEW") => Ok(true),
            Some(op) => Err(self.err(
                kw.loc,
                format!("{}: expected OP=NEW or OP=MOD, found OP={op}", kw.display),
            )),
        }
    }

    /// Mark `OP=NEW` in the current step (in model data nothing precedes, so it is moot).
    fn replaced(&mut self, mark: impl FnOnce(&mut Replaced)) {
        if let Some(step) = &mut self.step {
            mark(&mut step.replaced);
        }
    }

    fn loads(&mut self) -> &mut LoadDrafts {
        match &mut self.step {
            Some(step) => &mut step.loads,
            None => &mut self.model,
        }
    }

    // --- model keywords -----------------------------------------------------------------

    fn node_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        if let Some(system) = self.param(kw, "SYSTEM")? {
            if !system.eq_ignore_ascii_case("R") {
                return Err(self.err(
                    kw.loc,
                    format!(
                        "*NODE, SYSTEM={system} is not supported (give rectangular \
                         coordinates, SYSTEM=R)"
                    ),
                ));
            }
        }
        let nset = self.param(kw, "NSET")?.map(|n| Name::new(&n));
        if let Some(name) = &nset {
            self.node_sets
                .entry(name.canon.clone())
                .or_insert_with(|| SetDraft {
                    written: name.written.clone(),
                    members: Vec::new(),
                });
        }
        Ok(Block::Node { nset })
    }

    fn element_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        let written = self.required(kw, "TYPE")?;
        let kind = written.to_uppercase();
        if kind != "C3D10" {
            if C3D10_VARIANTS.contains(&kind.as_str()) {
                self.variant_types.add(&kind, kw.loc);
            } else {
                return Err(self.err(
                    kw.loc,
                    format!("element type {written} is not supported (squeal needs C3D10)"),
                ));
            }
        }
        let elset = self.param(kw, "ELSET")?.map(|n| Name::new(&n));
        if let Some(name) = &elset {
            self.element_sets
                .entry(name.canon.clone())
                .or_insert_with(|| SetDraft {
                    written: name.written.clone(),
                    members: Vec::new(),
                });
        }
        Ok(Block::Element { elset })
    }

    fn node_set_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        if self.param(kw, "INSTANCE")?.is_some() {
            return Err(self.err(kw.loc, refused("INSTANCE").unwrap_or_default()));
        }
        let name = Name::new(&self.required(kw, "NSET")?);
        let generate = kw.flag("GENERATE");
        kw.flag("UNSORTED");
        kw.flag("INTERNAL");
        let mut members = Vec::new();
        if let Some(elset) = self.param(kw, "ELSET")? {
            // *NSET, ELSET=: the nodes of those elements, as they are now.
            let elset = Name::new(&elset);
            let Some(set) = self.element_sets.get(&elset.canon) else {
                return Err(self.err(
                    kw.loc,
                    format!(
                        "*NSET: element set {} is not defined (above this line)",
                        elset.written
                    ),
                ));
            };
            for m in &set.members {
                if let Some(&e) = self.element_index.get(&m.label) {
                    members.extend(self.elements[e].iter().map(|&label| Member {
                        label,
                        loc: self.element_locs[e],
                        generated: false,
                    }));
                }
            }
        }
        self.node_sets
            .entry(name.canon.clone())
            .or_insert_with(|| SetDraft {
                written: name.written.clone(),
                members: Vec::new(),
            })
            .members
            .extend(members);
        Ok(Block::NodeSet { name, generate })
    }

    fn element_set_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        if self.param(kw, "INSTANCE")?.is_some() {
            return Err(self.err(kw.loc, refused("INSTANCE").unwrap_or_default()));
        }
        let name = Name::new(&self.required(kw, "ELSET")?);
        let generate = kw.flag("GENERATE");
        kw.flag("UNSORTED");
        kw.flag("INTERNAL");
        self.element_sets
            .entry(name.canon.clone())
            .or_insert_with(|| SetDraft {
                written: name.written.clone(),
                members: Vec::new(),
            });
        Ok(Block::ElementSet { name, generate })
    }

    fn surface_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        let name = Name::new(&self.required(kw, "NAME")?);
        let kind = self
            .param(kw, "TYPE")?
            .unwrap_or_else(|| "ELEMENT".into())
            .to_uppercase();
        let previous = self
            .surfaces
            .get(&name.canon)
            .map(|s| s.loc)
            .or_else(|| self.node_surfaces.get(&name.canon).copied());
        if let Some(loc) = previous {
            return Err(self.err(
                kw.loc,
                format!(
                    "surface {} is already defined at {}",
                    name.written,
                    self.lines.at(loc)
                ),
            ));
        }
        match kind.as_str() {
            "ELEMENT" => {
                self.surfaces.insert(
                    name.canon.clone(),
                    SurfaceDraft {
                        written: name.written.clone(),
                        members: Vec::new(),
                        loc: kw.loc,
                    },
                );
                Ok(Block::ElementSurface { name })
            }
            "NODE" => {
                if self.node_sets.contains_key(&name.canon) {
                    return Err(self.err(
                        kw.loc,
                        format!(
                            "node-based surface {} has the name of a node set; squeal keeps \
                             node-based surfaces as node sets, so the names must differ",
                            name.written
                        ),
                    ));
                }
                self.node_surfaces.insert(name.canon.clone(), kw.loc);
                self.node_sets.insert(
                    name.canon.clone(),
                    SetDraft {
                        written: name.written.clone(),
                        members: Vec::new(),
                    },
                );
                Ok(Block::NodeSurface { name })
            }
            _ => Err(self.err(
                kw.loc,
                format!(
                    "*SURFACE, TYPE={kind} is not supported (expected TYPE=ELEMENT or TYPE=NODE)"
                ),
            )),
        }
    }

    fn material_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        let name = Name::new(&self.required(kw, "NAME")?);
        if let Some(m) = self.materials.get(&name.canon) {
            return Err(self.err(
                kw.loc,
                format!(
                    "material {} is already defined at {}",
                    name.written,
                    self.lines.at(m.loc)
                ),
            ));
        }
        self.materials.insert(
            name.canon.clone(),
            MaterialDraft {
                written: name.written,
                elastic: None,
                density: None,
                loc: kw.loc,
            },
        );
        self.material = Some(name.canon);
        Ok(Block::NoData(kw.display.clone()))
    }

    fn step_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        if let Some(step) = &self.step {
            return Err(self.err(
                kw.loc,
                format!(
                    "*STEP inside the step that begins at {} (expected *END STEP first)",
                    self.lines.at(step.loc)
                ),
            ));
        }
        let name = self.param(kw, "NAME")?;
        let perturbation_parameter = kw.flag("PERTURBATION");
        let nlgeom = match kw.params.iter_mut().find(|p| p.key == "NLGEOM") {
            None => false,
            Some(p) => {
                p.used = true;
                p.value
                    .as_deref()
                    .is_none_or(|v| v.eq_ignore_ascii_case("YES"))
            }
        };
        // The increment limit only matters to an incremental solver; UNSYMM is a storage
        // hint (squeal's contact tangent is unsymmetric anyway).
        kw.flag("INC");
        kw.flag("UNSYMM");
        self.step = Some(StepDraft {
            name,
            title: None,
            procedure: None,
            perturbation_parameter,
            nlgeom,
            loads: LoadDrafts::default(),
            replaced: Replaced::default(),
            loc: kw.loc,
        });
        Ok(Block::StepTitle { lines: 0 })
    }

    /// A pending element at a keyword line or at the end of the file is a truncated one.
    fn finish_element(&mut self, next: Option<&Keyword>) -> Result<(), MeshError> {
        let Some(p) = self.pending.take() else {
            return Ok(());
        };
        let found = match next {
            Some(kw) => format!("the next line is the keyword {}", kw.display),
            None => "the file ends here".to_string(),
        };
        Err(self.err(
            p.last,
            format!(
                "element {}: the line ends with a comma, so the element continues on the next \
                 line, but {found} (C3D10 needs a label and 10 node labels)",
                p.values[0]
            ),
        ))
    }

    // --- data lines ---------------------------------------------------------------------

    fn data(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
        let mut block = std::mem::take(&mut self.block);
        let result = self.data_in(&mut block, text, loc);
        self.block = block;
        result
    }

    fn data_in(&mut self, block: &mut Block, text: &str, loc: Loc) -> Result<(), MeshError> {
        match block {
            Block::Start => Err(self.err(
                loc,
                "expected a keyword line (starting with '*') before the first data line",
            )),
            Block::Skip => Ok(()),
            Block::NoData(keyword) => Err(self.err(
                loc,
                format!("{keyword} takes no data lines, found \"{text}\""),
            )),
            Block::Heading => {
                self.heading.push(text.to_string());
                Ok(())
            }
            Block::Node { nset } => self.node_line(nset.as_ref(), text, loc),
            Block::Element { elset } => self.element_line(elset.as_ref(), text, loc),
            Block::NodeSet { name, generate } => {
                let generate = *generate;
                self.set_line(true, name, generate, text, loc)
            }
            Block::ElementSet { name, generate } => {
                let generate = *generate;
                self.set_line(false, name, generate, text, loc)
            }
            Block::ElementSurface { name } => self.element_surface_line(name, text, loc),
            Block::NodeSurface { name } => self.node_surface_line(name, text, loc),
            Block::Elastic { material, lines } => {
                *lines += 1;
                self.elastic_line(material, *lines, text, loc)
            }
            Block::Density { material, lines } => {
                *lines += 1;
                self.density_line(material, *lines, text, loc)
            }
            Block::StepTitle { lines } => {
                *lines += 1;
                if *lines > 1 {
                    return Err(self.err(loc, "*STEP takes at most one data line (the step title)"));
                }
                if let Some(step) = &mut self.step {
                    step.title = Some(text.to_string());
                }
                Ok(())
            }
            Block::Static { lines } => {
                *lines += 1;
                self.static_line(*lines, text, loc)
            }
            Block::Frequency { subspace, lines } => {
                *lines += 1;
                self.frequency_line(*subspace, *lines, text, loc)
            }
            Block::Boundary => self.boundary_line(text, loc),
            Block::ConcentratedLoad => self.load_line(text, loc),
            Block::SurfacePressure => self.surface_pressure_line(text, loc),
            Block::ElementPressure => self.element_pressure_line(text, loc),
        }
    }

    fn node_line(&mut self, nset: Option<&Name>, text: &str, loc: Loc) -> Result<(), MeshError> {
        let f = data_fields(text);
        // label, x, y, z, then optionally a normal direction (meaningless for solids).
        if f.len() < 2 || f.len() > 7 {
            return Err(self.err(
                loc,
                format!(
                    "*NODE: expected a node label and its coordinates, found {} fields",
                    f.len()
                ),
            ));
        }
        let label = self.label(f[0], loc, "node label")?;
        let mut x = [0.0; 3];
        // Blank coordinates are zero, as in Abaqus. The message is only built on error:
        // this loop runs once per node of a model of millions.
        for (k, (field, axis)) in f[1..].iter().zip(["x", "y", "z"]).enumerate() {
            if !field.is_empty() {
                x[k] = parse_number(field).ok_or_else(|| {
                    self.err(
                        loc,
                        format!(
                            "expected a number ({axis} coordinate of node {label}), found \
                             \"{field}\""
                        ),
                    )
                })?;
            }
        }
        if let Some(&first) = self.node_index.get(&label) {
            return Err(self.err(
                loc,
                format!(
                    "node {label} is defined twice (first at {})",
                    self.lines.at(self.node_locs[first])
                ),
            ));
        }
        self.node_index.insert(label, self.nodes.len());
        self.nodes.push(x);
        self.node_labels.push(label);
        self.node_locs.push(loc);
        if let Some(set) = nset.and_then(|n| self.node_sets.get_mut(&n.canon)) {
            set.members.push(Member {
                label,
                loc,
                generated: false,
            });
        }
        Ok(())
    }

    fn element_line(
        &mut self,
        elset: Option<&Name>,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        let continues = text.ends_with(',');
        let mut values = match self.pending.take() {
            Some(p) => p.values,
            None => Vec::with_capacity(11),
        };
        for field in data_fields(text) {
            let what = if values.is_empty() {
                "element label"
            } else {
                "node label"
            };
            if field.is_empty() {
                return Err(self.err(
                    loc,
                    format!("expected a positive integer ({what}), found an empty field"),
                ));
            }
            values.push(self.label(field, loc, what)?);
        }
        let label = values.first().copied();
        if values.len() > 11 {
            return Err(self.err(
                loc,
                format!(
                    "element {}: C3D10 needs a label and 10 node labels, found {} node labels",
                    values[0],
                    values.len() - 1
                ),
            ));
        }
        if values.len() < 11 {
            if continues {
                if !values.is_empty() {
                    self.pending = Some(PendingElement { values, last: loc });
                }
                return Ok(());
            }
            return Err(self.err(
                loc,
                match label {
                    Some(l) => format!(
                        "element {l}: C3D10 needs a label and 10 node labels, found {} node \
                         labels (a line that ends with a comma continues on the next line)",
                        values.len() - 1
                    ),
                    None => "expected an element label and 10 node labels".to_string(),
                },
            ));
        }
        let label = values[0];
        let mut nodes = [0i64; 10];
        nodes.copy_from_slice(&values[1..]);
        for (k, n) in nodes.iter().enumerate() {
            if nodes[..k].contains(n) {
                return Err(self.err(loc, format!("element {label} lists node {n} twice")));
            }
        }
        if let Some(&first) = self.element_index.get(&label) {
            return Err(self.err(
                loc,
                format!(
                    "element {label} is defined twice (first at {})",
                    self.lines.at(self.element_locs[first])
                ),
            ));
        }
        self.element_index.insert(label, self.elements.len());
        self.elements.push(nodes);
        self.element_labels.push(label);
        self.element_locs.push(loc);
        if let Some(set) = elset.and_then(|n| self.element_sets.get_mut(&n.canon)) {
            set.members.push(Member {
                label,
                loc,
                generated: false,
            });
        }
        Ok(())
    }

    fn set_line(
        &mut self,
        of_nodes: bool,
        name: &Name,
        generate: bool,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        let (keyword, item, label_of) = if of_nodes {
            ("*NSET", "node", "node label")
        } else {
            ("*ELSET", "element", "element label")
        };
        let f = data_fields(text);
        let mut members = Vec::new();
        if generate {
            if f.len() < 2 || f.len() > 3 {
                return Err(self.err(
                    loc,
                    format!(
                        "{keyword}, GENERATE: expected first, last[, increment], found {} fields",
                        f.len()
                    ),
                ));
            }
            let first = self.label(f[0], loc, &format!("first {item} label"))?;
            let last = self.label(f[1], loc, &format!("last {item} label"))?;
            let step = match f.get(2) {
                Some(s) if !s.is_empty() => self.label(s, loc, "increment")?,
                _ => 1,
            };
            if last < first {
                return Err(self.err(
                    loc,
                    format!(
                        "{keyword}, GENERATE: the last label {last} is below the first {first}"
                    ),
                ));
            }
            if (last - first) / step >= MAX_GENERATED {
                return Err(self.err(
                    loc,
                    format!("{keyword}, GENERATE: the range {first}..{last} is implausibly long"),
                ));
            }
            let mut label = first;
            while label <= last {
                members.push(Member {
                    label,
                    loc,
                    generated: true,
                });
                label += step;
            }
        } else {
            let sets = if of_nodes {
                &self.node_sets
            } else {
                &self.element_sets
            };
            for field in f.iter().filter(|s| !s.is_empty()) {
                if looks_numeric(field) {
                    members.push(Member {
                        label: self.label(field, loc, label_of)?,
                        loc,
                        generated: false,
                    });
                } else {
                    let other = Name::new(field);
                    match sets.get(&other.canon) {
                        Some(set) => members.extend_from_slice(&set.members),
                        None => {
                            return Err(self.err(
                                loc,
                                format!(
                                    "{keyword} {}: {item} set {} is not defined (above this line)",
                                    name.written, other.written
                                ),
                            ))
                        }
                    }
                }
            }
        }
        let sets = if of_nodes {
            &mut self.node_sets
        } else {
            &mut self.element_sets
        };
        if let Some(set) = sets.get_mut(&name.canon) {
            set.members.extend(members);
        }
        Ok(())
    }

    fn element_surface_line(&mut self, name: &Name, text: &str, loc: Loc) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.is_empty() || f.len() > 2 || f[0].is_empty() {
            return Err(self.err(
                loc,
                "*SURFACE, TYPE=ELEMENT: expected \"element or element set, face (S1..S4)\"",
            ));
        }
        let target = if looks_numeric(f[0]) {
            ElementRef::Element(self.label(f[0], loc, "element label")?)
        } else {
            ElementRef::Set(Name::new(f[0]))
        };
        let side = match f.get(1) {
            None | Some(&"") => None,
            Some(s) => match s.to_uppercase().as_str() {
                "S1" => Some(0),
                "S2" => Some(1),
                "S3" => Some(2),
                "S4" => Some(3),
                _ => {
                    return Err(self.err(
                        loc,
                        format!(
                            "expected a face identifier S1, S2, S3 or S4 (the faces of a \
                             C3D10), found \"{s}\""
                        ),
                    ))
                }
            },
        };
        if let Some(surface) = self.surfaces.get_mut(&name.canon) {
            surface.members.push(SurfaceMember { target, side, loc });
        }
        Ok(())
    }

    fn node_surface_line(&mut self, name: &Name, text: &str, loc: Loc) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.is_empty() || f.len() > 2 || f[0].is_empty() {
            return Err(self.err(
                loc,
                "*SURFACE, TYPE=NODE: expected \"node or node set[, area]\"",
            ));
        }
        let members = if looks_numeric(f[0]) {
            vec![Member {
                label: self.label(f[0], loc, "node label")?,
                loc,
                generated: false,
            }]
        } else {
            let other = Name::new(f[0]);
            match self.node_sets.get(&other.canon) {
                Some(set) => set.members.clone(),
                None => {
                    return Err(self.err(
                        loc,
                        format!(
                            "*SURFACE {}: node set {} is not defined (above this line)",
                            name.written, other.written
                        ),
                    ))
                }
            }
        };
        if let Some(set) = self.node_sets.get_mut(&name.canon) {
            set.members.extend(members);
        }
        Ok(())
    }

    fn elastic_line(
        &mut self,
        material: &str,
        lines: usize,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        if lines > 1 {
            return Err(self.err(
                loc,
                "*ELASTIC: expected one data line (temperature-dependent elasticity is not \
                 supported)",
            ));
        }
        let f = data_fields(text);
        if f.is_empty() || f.len() > 3 {
            return Err(self.err(
                loc,
                format!(
                    "*ELASTIC: expected \"Young's modulus, Poisson's ratio\", found {} fields",
                    f.len()
                ),
            ));
        }
        let young = self.number(f[0], loc, "Young's modulus")?;
        let poisson = self
            .optional_number(&f, 1, loc, "Poisson's ratio")?
            .unwrap_or(0.0);
        if young <= 0.0 {
            return Err(self.err(
                loc,
                format!("*ELASTIC: expected a positive Young's modulus, found {young}"),
            ));
        }
        // Outside (-1, 1/2) the elasticity tensor is not positive definite.
        if !(poisson > -1.0 && poisson < 0.5) {
            return Err(self.err(
                loc,
                format!("*ELASTIC: expected a Poisson's ratio in (-1, 0.5), found {poisson}"),
            ));
        }
        if let Some(m) = self.materials.get_mut(material) {
            m.elastic = Some((young, poisson));
        }
        Ok(())
    }

    fn density_line(
        &mut self,
        material: &str,
        lines: usize,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        if lines > 1 {
            return Err(self.err(
                loc,
                "*DENSITY: expected one data line (temperature-dependent density is not \
                 supported)",
            ));
        }
        let f = data_fields(text);
        if f.is_empty() || f.len() > 2 {
            return Err(self.err(
                loc,
                format!(
                    "*DENSITY: expected \"mass density\", found {} fields",
                    f.len()
                ),
            ));
        }
        let density = self.number(f[0], loc, "mass density")?;
        if density <= 0.0 {
            return Err(self.err(
                loc,
                format!("*DENSITY: expected a positive mass density, found {density}"),
            ));
        }
        if let Some(m) = self.materials.get_mut(material) {
            m.density = Some(density);
        }
        Ok(())
    }

    fn static_line(&mut self, lines: usize, text: &str, loc: Loc) -> Result<(), MeshError> {
        if lines > 1 {
            return Err(self.err(loc, "*STATIC: expected one data line"));
        }
        let f = data_fields(text);
        let request = StaticRequest {
            initial_increment: self.optional_number(&f, 0, loc, "initial time increment")?,
            time_period: self.optional_number(&f, 1, loc, "time period of the step")?,
            minimum_increment: self.optional_number(&f, 2, loc, "minimum time increment")?,
            maximum_increment: self.optional_number(&f, 3, loc, "maximum time increment")?,
        };
        if let Some(step) = &mut self.step {
            if let Some((procedure, _)) = &mut step.procedure {
                *procedure = Procedure::Static(request);
            }
        }
        Ok(())
    }

    fn frequency_line(
        &mut self,
        subspace: bool,
        lines: usize,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        if lines > 1 {
            return Err(self.err(loc, "*FREQUENCY: expected one data line"));
        }
        let f = data_fields(text);
        let eigenvalues = match f.first() {
            None | Some(&"") => None,
            Some(s) => Some(self.label(s, loc, "number of eigenvalues")? as usize),
        };
        let freq = |k: usize, what: &str| self.optional_number(&f, k, loc, what);
        let request = if subspace {
            FrequencyRequest {
                eigenvalues,
                lower_frequency: None,
                upper_frequency: freq(1, "maximum frequency of interest")?,
                shift: freq(2, "shift point")?,
            }
        } else {
            FrequencyRequest {
                eigenvalues,
                lower_frequency: freq(1, "lower end of the frequency range")?,
                upper_frequency: freq(2, "upper end of the frequency range")?,
                shift: freq(3, "shift point")?,
            }
        };
        if let (Some(lo), Some(hi)) = (request.lower_frequency, request.upper_frequency) {
            if hi < lo {
                return Err(self.err(
                    loc,
                    format!("*FREQUENCY: the upper frequency {hi} is below the lower {lo}"),
                ));
            }
        }
        if let Some(step) = &mut self.step {
            if let Some((procedure, _)) = &mut step.procedure {
                *procedure = Procedure::Frequency(request);
            }
        }
        Ok(())
    }

    fn node_ref(&self, field: &str, loc: Loc) -> Result<NodeRef, MeshError> {
        if field.is_empty() {
            return Err(self.err(loc, "expected a node label or node set name, found a blank"));
        }
        Ok(if looks_numeric(field) {
            NodeRef::Node(self.label(field, loc, "node label")?)
        } else {
            NodeRef::Set(Name::new(field))
        })
    }

    /// A DOF field 1..=6; `None` (with a note) for the rotations 4..=6.
    fn dof(&mut self, field: &str, keyword: &str, loc: Loc) -> Result<Option<u8>, MeshError> {
        match field.parse::<u8>() {
            Ok(d @ 1..=3) => Ok(Some(d)),
            Ok(4..=6) => {
                self.rotational_dofs.add(keyword, loc);
                Ok(None)
            }
            _ => Err(self.err(
                loc,
                format!(
                    "{keyword}: expected a degree of freedom 1..6 (1-3 are used; C3D10 nodes \
                     have no others), found \"{field}\""
                ),
            )),
        }
    }

    fn boundary_line(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.len() < 2 || f.len() > 4 {
            return Err(self.err(
                loc,
                format!(
                    "*BOUNDARY: expected \"node or node set, first DOF[, last DOF[, value]]\", \
                     found {} fields",
                    f.len()
                ),
            ));
        }
        let target = self.node_ref(f[0], loc)?;
        // Abaqus' named conditions; the rotations they also fix do not exist on solids.
        let named: Option<(u8, u8)> = match f[1].to_uppercase().as_str() {
            "ENCASTRE" | "PINNED" => Some((1, 3)),
            "XSYMM" => Some((1, 1)),
            "YSYMM" => Some((2, 2)),
            "ZSYMM" => Some((3, 3)),
            _ => None,
        };
        let (first, last, value) = if let Some((first, last)) = named {
            if f.len() > 2 {
                return Err(self.err(loc, format!("*BOUNDARY: {} takes no further fields", f[1])));
            }
            (first, last, 0.0)
        } else {
            if !looks_numeric(f[1]) && !f[1].is_empty() {
                return Err(self.err(
                    loc,
                    format!(
                        "*BOUNDARY: expected a DOF number or ENCASTRE, PINNED, XSYMM, YSYMM, \
                         ZSYMM, found \"{}\"",
                        f[1]
                    ),
                ));
            }
            let first: u8 = match f[1].parse::<u8>() {
                Ok(d @ 1..=6) => d,
                _ => {
                    return Err(self.err(
                        loc,
                        format!(
                            "*BOUNDARY: expected a first degree of freedom 1..6, found \"{}\"",
                            f[1]
                        ),
                    ))
                }
            };
            let last: u8 = match f.get(2) {
                None | Some(&"") => first,
                Some(s) => match s.parse::<u8>() {
                    Ok(d @ 1..=6) if d >= first => d,
                    _ => {
                        return Err(self.err(
                            loc,
                            format!(
                                "*BOUNDARY: expected a last degree of freedom {first}..6, found \
                                 \"{s}\""
                            ),
                        ))
                    }
                },
            };
            let value = self
                .optional_number(&f, 3, loc, "prescribed displacement")?
                .unwrap_or(0.0);
            if last > 3 {
                self.rotational_dofs.add("*BOUNDARY", loc);
            }
            if first > 3 {
                return Ok(());
            }
            (first, last.min(3), value)
        };
        self.loads().boundaries.push(BoundaryDraft {
            target,
            first_dof: first,
            last_dof: last,
            value,
            loc,
        });
        Ok(())
    }

    fn load_line(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.len() != 3 {
            return Err(self.err(
                loc,
                format!(
                    "*CLOAD: expected \"node or node set, DOF, value\", found {} fields",
                    f.len()
                ),
            ));
        }
        let target = self.node_ref(f[0], loc)?;
        let value = self.number(f[2], loc, "force")?;
        let Some(dof) = self.dof(f[1], "*CLOAD", loc)? else {
            return Ok(());
        };
        self.loads().loads.push(LoadDraft {
            target,
            dof,
            value,
            loc,
        });
        Ok(())
    }

    fn surface_pressure_line(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.len() != 3 || f[0].is_empty() {
            return Err(self.err(
                loc,
                format!(
                    "*DSLOAD: expected \"surface, P, value\", found {} fields",
                    f.len()
                ),
            ));
        }
        if !f[1].eq_ignore_ascii_case("P") {
            return Err(self.err(
                loc,
                format!(
                    "*DSLOAD: load type {} is not supported (only P, uniform pressure)",
                    f[1]
                ),
            ));
        }
        let value = self.number(f[2], loc, "pressure")?;
        let loads = self.loads();
        loads.surface_pressures.push(SurfacePressureDraft {
            surface: Name::new(f[0]),
            value,
            loc,
        });
        loads.pressure_order.push(true);
        Ok(())
    }

    fn element_pressure_line(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
        let f = data_fields(text);
        if f.len() != 3 || f[0].is_empty() {
            return Err(self.err(
                loc,
                format!(
                    "*DLOAD: expected \"element or element set, P1..P4, value\", found {} fields",
                    f.len()
                ),
            ));
        }
        let side = match f[1].to_uppercase().as_str() {
            "P1" => 0,
            "P2" => 1,
            "P3" => 2,
            "P4" => 3,
            _ => {
                return Err(self.err(
                    loc,
                    format!(
                        "*DLOAD: load type {} is not supported (only face pressures P1..P4 \
                         on C3D10)",
                        f[1]
                    ),
                ))
            }
        };
        let target = if looks_numeric(f[0]) {
            ElementRef::Element(self.label(f[0], loc, "element label")?)
        } else {
            ElementRef::Set(Name::new(f[0]))
        };
        let value = self.number(f[2], loc, "pressure")?;
        let loads = self.loads();
        loads.element_pressures.push(ElementPressureDraft {
            target,
            side,
            value,
            loc,
        });
        loads.pressure_order.push(false);
        Ok(())
    }

    // --- resolution -----------------------------------------------------------------------

    fn finish(mut self) -> Result<Deck, MeshError> {
        // Connectivity: labels to indices.
        let mut elements = Vec::with_capacity(self.elements.len());
        for (e, raw) in self.elements.iter().enumerate() {
            let mut conn = [0usize; 10];
            for (slot, label) in conn.iter_mut().zip(raw) {
                *slot = *self.node_index.get(label).ok_or_else(|| {
                    self.err(
                        self.element_locs[e],
                        format!(
                            "element {} references node {label}, which is not defined",
                            self.element_labels[e]
                        ),
                    )
                })?;
            }
            elements.push(conn);
        }
        let mut mesh = Mesh {
            nodes: std::mem::take(&mut self.nodes),
            node_labels: std::mem::take(&mut self.node_labels),
            elements,
            element_labels: self.element_labels.clone(),
            ..Default::default()
        };

        let node_sets = self.resolve_sets(true)?;
        let element_sets = self.resolve_sets(false)?;
        mesh.node_sets = node_sets;

        self.make_parts(&mut mesh, &element_sets)?;
        self.make_materials(&mut mesh)?;
        self.make_surfaces(&mut mesh, &element_sets)?;

        let model = std::mem::take(&mut self.model);
        let (boundaries, concentrated_loads, pressures) =
            self.resolve_loads(&model, &mesh, &element_sets)?;
        let mut steps = Vec::with_capacity(self.steps.len());
        for draft in std::mem::take(&mut self.steps) {
            let (boundaries, concentrated_loads, pressures) =
                self.resolve_loads(&draft.loads, &mesh, &element_sets)?;
            let (procedure, _) = draft
                .procedure
                .ok_or_else(|| self.err(draft.loc, "step without a procedure"))?;
            let perturbation = draft.perturbation_parameter
                || match &procedure {
                    Procedure::Frequency(_) => true,
                    Procedure::Static(_) => false,
                    Procedure::Unsupported { keyword } => {
                        let name: String = keyword[1..].split_whitespace().collect();
                        PERTURBATION_PROCEDURES.contains(&name.as_str())
                    }
                };
            steps.push(Step {
                name: draft.name,
                title: draft.title,
                procedure,
                perturbation,
                nlgeom: draft.nlgeom,
                boundaries,
                concentrated_loads,
                pressures,
                replaced: draft.replaced,
                source: self.lines.source(draft.loc),
            });
        }

        self.collect_warnings();
        Ok(Deck {
            mesh,
            heading: self.heading.join("\n"),
            element_sets,
            node_surfaces: self.node_surfaces.keys().cloned().collect(),
            boundaries,
            concentrated_loads,
            pressures,
            steps,
            warnings: self.warnings,
        })
    }

    fn resolve_sets(&mut self, of_nodes: bool) -> Result<BTreeMap<String, Vec<usize>>, MeshError> {
        let (sets, index, item) = if of_nodes {
            (&self.node_sets, &self.node_index, "node")
        } else {
            (&self.element_sets, &self.element_index, "element")
        };
        let mut out = BTreeMap::new();
        let mut notes = Vec::new();
        for (canon, set) in sets {
            let mut indices = Vec::with_capacity(set.members.len());
            let mut missing: Option<(usize, Loc)> = None;
            for m in &set.members {
                match index.get(&m.label) {
                    Some(&i) => indices.push(i),
                    None if m.generated => {
                        let entry = missing.get_or_insert((0, m.loc));
                        entry.0 += 1;
                    }
                    None => {
                        return Err(self.err(
                            m.loc,
                            format!(
                                "{item} {} (in {item} set {}) is not defined",
                                m.label, set.written
                            ),
                        ))
                    }
                }
            }
            indices.sort_unstable();
            indices.dedup();
            if let Some((n, loc)) = missing {
                notes.push(format!(
                    "{item} set {}: {n} label(s) produced by GENERATE (first range at {}) are \
                     not defined and were left out",
                    set.written,
                    self.lines.at(loc)
                ));
            }
            out.insert(canon.clone(), indices);
        }
        self.warnings.extend(notes);
        Ok(out)
    }

    fn make_parts(
        &self,
        mesh: &mut Mesh,
        element_sets: &BTreeMap<String, Vec<usize>>,
    ) -> Result<(), MeshError> {
        let mut owner: Vec<Option<usize>> = vec![None; mesh.elements.len()];
        for (s, section) in self.sections.iter().enumerate() {
            let Some(elements) = element_sets.get(&section.elset.canon) else {
                return Err(self.err(
                    section.loc,
                    format!(
                        "*SOLID SECTION: element set {} is not defined",
                        section.elset.written
                    ),
                ));
            };
            if !self.materials.contains_key(&section.material.canon) {
                return Err(self.err(
                    section.loc,
                    format!(
                        "*SOLID SECTION: material {} is not defined",
                        section.material.written
                    ),
                ));
            }
            for &e in elements {
                if let Some(previous) = owner[e] {
                    return Err(self.err(
                        section.loc,
                        format!(
                            "element {} is already in the *SOLID SECTION at {}; an element \
                             takes one section only",
                            mesh.element_labels[e],
                            self.lines.at(self.sections[previous].loc)
                        ),
                    ));
                }
                owner[e] = Some(s);
            }
            mesh.parts.push(Part {
                name: section.elset.canon.clone(),
                elements: elements.clone(),
                material: Some(section.material.canon.clone()),
            });
        }
        let orphans: Vec<usize> = (0..owner.len()).filter(|&e| owner[e].is_none()).collect();
        if let Some(&first) = orphans.first() {
            return Err(self.err(
                self.element_locs[first],
                format!(
                    "{} element(s) are in no *SOLID SECTION, so they have no material (first: \
                     element {}); give every element a section",
                    orphans.len(),
                    mesh.element_labels[first]
                ),
            ));
        }
        Ok(())
    }

    fn make_materials(&mut self, mesh: &mut Mesh) -> Result<(), MeshError> {
        let mut used: BTreeMap<&str, Loc> = BTreeMap::new();
        for section in &self.sections {
            used.entry(section.material.canon.as_str())
                .or_insert(section.loc);
        }
        let mut notes = Vec::new();
        for (canon, draft) in &self.materials {
            let missing = match (draft.elastic, draft.density) {
                (Some(_), Some(_)) => None,
                (None, Some(_)) => Some("*ELASTIC"),
                (Some(_), None) => Some("*DENSITY"),
                (None, None) => Some("*ELASTIC and *DENSITY"),
            };
            match (missing, used.get(canon.as_str())) {
                (Some(what), Some(&section)) => {
                    return Err(self.err(
                        draft.loc,
                        format!(
                            "material {} has no {what}, but the *SOLID SECTION at {} uses it",
                            draft.written,
                            self.lines.at(section)
                        ),
                    ))
                }
                (Some(what), None) => notes.push(format!(
                    "material {} ({}) has no {what} and no section uses it; left out",
                    draft.written,
                    self.lines.at(draft.loc)
                )),
                (None, _) => {
                    if let (Some((young, poisson)), Some(density)) = (draft.elastic, draft.density)
                    {
                        mesh.materials.insert(
                            canon.clone(),
                            Material {
                                name: canon.clone(),
                                young,
                                poisson,
                                density,
                            },
                        );
                    }
                }
            }
        }
        self.warnings.extend(notes);
        Ok(())
    }

    fn elements_of(
        &self,
        target: &ElementRef,
        loc: Loc,
        keyword: &str,
        element_sets: &BTreeMap<String, Vec<usize>>,
    ) -> Result<Vec<usize>, MeshError> {
        match target {
            ElementRef::Element(label) => match self.element_index.get(label) {
                Some(&e) => Ok(vec![e]),
                None => Err(self.err(loc, format!("{keyword}: element {label} is not defined"))),
            },
            ElementRef::Set(name) => element_sets.get(&name.canon).cloned().ok_or_else(|| {
                self.err(
                    loc,
                    format!("{keyword}: element set {} is not defined", name.written),
                )
            }),
        }
    }

    fn make_surfaces(
        &self,
        mesh: &mut Mesh,
        element_sets: &BTreeMap<String, Vec<usize>>,
    ) -> Result<(), MeshError> {
        for (canon, draft) in &self.surfaces {
            let mut faces = Vec::new();
            let mut seen = HashSet::new();
            for member in &draft.members {
                let elements = self.elements_of(
                    &member.target,
                    member.loc,
                    &format!("*SURFACE {}", draft.written),
                    element_sets,
                )?;
                let candidates = match member.side {
                    Some(side) => elements.iter().map(|&e| mesh.face(e, side)).collect(),
                    None => free_faces(mesh, &elements),
                };
                for face in candidates {
                    if seen.insert((face.element, face.side)) {
                        faces.push(face);
                    }
                }
            }
            mesh.surfaces.insert(
                canon.clone(),
                Surface {
                    name: canon.clone(),
                    faces,
                },
            );
        }
        Ok(())
    }

    fn nodes_of(
        &self,
        target: &NodeRef,
        loc: Loc,
        keyword: &str,
        mesh: &Mesh,
    ) -> Result<(NodeTarget, Vec<usize>), MeshError> {
        match target {
            NodeRef::Node(label) => match self.node_index.get(label) {
                Some(&n) => Ok((NodeTarget::Node(*label), vec![n])),
                None => Err(self.err(loc, format!("{keyword}: node {label} is not defined"))),
            },
            NodeRef::Set(name) => match mesh.node_sets.get(&name.canon) {
                Some(nodes) => Ok((NodeTarget::Set(name.canon.clone()), nodes.clone())),
                None => Err(self.err(
                    loc,
                    format!("{keyword}: node set {} is not defined", name.written),
                )),
            },
        }
    }

    #[allow(clippy::type_complexity)]
    fn resolve_loads(
        &self,
        drafts: &LoadDrafts,
        mesh: &Mesh,
        element_sets: &BTreeMap<String, Vec<usize>>,
    ) -> Result<(Vec<Boundary>, Vec<ConcentratedLoad>, Vec<PressureLoad>), MeshError> {
        let mut boundaries = Vec::with_capacity(drafts.boundaries.len());
        for b in &drafts.boundaries {
            let (target, nodes) = self.nodes_of(&b.target, b.loc, "*BOUNDARY", mesh)?;
            boundaries.push(Boundary {
                target,
                nodes,
                first_dof: b.first_dof,
                last_dof: b.last_dof,
                value: b.value,
                source: self.lines.source(b.loc),
            });
        }
        let mut loads = Vec::with_capacity(drafts.loads.len());
        for c in &drafts.loads {
            let (target, nodes) = self.nodes_of(&c.target, c.loc, "*CLOAD", mesh)?;
            loads.push(ConcentratedLoad {
                target,
                nodes,
                dof: c.dof,
                value: c.value,
                source: self.lines.source(c.loc),
            });
        }
        let mut pressures = Vec::with_capacity(drafts.pressure_order.len());
        let mut surface = drafts.surface_pressures.iter();
        let mut element = drafts.element_pressures.iter();
        for &is_surface in &drafts.pressure_order {
            if is_surface {
                let Some(p) = surface.next() else { break };
                let faces = match mesh.surfaces.get(&p.surface.canon) {
                    Some(s) => s.faces.clone(),
                    None if self.node_surfaces.contains_key(&p.surface.canon) => {
                        return Err(self.err(
                            p.loc,
                            format!(
                                "*DSLOAD: surface {} is node-based; a pressure needs an \
                                 element-based surface (TYPE=ELEMENT)",
                                p.surface.written
                            ),
                        ))
                    }
                    None => {
                        return Err(self.err(
                            p.loc,
                            format!("*DSLOAD: surface {} is not defined", p.surface.written),
                        ))
                    }
                };
                pressures.push(PressureLoad {
                    target: PressureTarget::Surface(p.surface.canon.clone()),
                    faces,
                    value: p.value,
                    source: self.lines.source(p.loc),
                });
            } else {
                let Some(p) = element.next() else { break };
                let elements = self.elements_of(&p.target, p.loc, "*DLOAD", element_sets)?;
                pressures.push(PressureLoad {
                    target: match &p.target {
                        ElementRef::Set(name) => PressureTarget::ElementSet(name.canon.clone()),
                        ElementRef::Element(label) => PressureTarget::Element(*label),
                    },
                    faces: elements.iter().map(|&e| mesh.face(e, p.side)).collect(),
                    value: p.value,
                    source: self.lines.source(p.loc),
                });
            }
        }
        Ok((boundaries, loads, pressures))
    }

    fn collect_warnings(&mut self) {
        let mut front = Vec::new();
        if !self.variant_types.entries.is_empty() {
            front.push(format!(
                "element types read as plain C3D10 (same nodes; squeal uses its own \
                 full-integration formulation): {}",
                self.variant_types.describe(&self.lines)
            ));
        }
        if !self.unknown_keywords.entries.is_empty() {
            front.push(format!(
                "skipped unsupported keywords with their data lines: {}",
                self.unknown_keywords.describe(&self.lines)
            ));
        }
        if !self.other_procedures.entries.is_empty() {
            front.push(format!(
                "steps with procedures this reader does not read (kept as \
                 Procedure::Unsupported): {}",
                self.other_procedures.describe(&self.lines)
            ));
        }
        if !self.ignored_parameters.entries.is_empty() {
            front.push(format!(
                "ignored parameters: {}",
                self.ignored_parameters.describe(&self.lines)
            ));
        }
        if !self.rotational_dofs.entries.is_empty() {
            front.push(format!(
                "rotational DOFs 4-6 ignored (C3D10 nodes have only displacements): {}",
                self.rotational_dofs.describe(&self.lines)
            ));
        }
        front.append(&mut self.warnings);
        self.warnings = front;
    }
}

/// The faces of `elements` that no other element of the list shares (an element set's
/// exterior, which is what Abaqus takes when a surface line has no face identifier).
fn free_faces(mesh: &Mesh, elements: &[usize]) -> Vec<Face> {
    let key = |f: &Face| {
        let mut k = [f.nodes[0], f.nodes[1], f.nodes[2]];
        k.sort_unstable();
        k
    };
    let mut count: HashMap<[usize; 3], u32> = HashMap::new();
    for &e in elements {
        for side in 0..4 {
            *count.entry(key(&mesh.face(e, side))).or_insert(0) += 1;
        }
    }
    elements
        .iter()
        .flat_map(|&e| (0..4).map(move |side| mesh.face(e, side)))
        .filter(|f| count.get(&key(f)) == Some(&1))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::TET10_EDGES;
    use crate::vector3::{cross, dot, sub};
    use std::fmt::Write as _;

    // --- helpers ------------------------------------------------------------------------

    /// A directory under the system temp dir, removed when dropped.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(test: &str) -> TempDir {
            let dir =
                std::env::temp_dir().join(format!("squeal-abaqus-{test}-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).expect("create temp dir");
            TempDir(dir)
        }

        fn write(&self, name: &str, text: &str) -> PathBuf {
            let path = self.0.join(name);
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent).expect("create dir");
            }
            std::fs::write(&path, text).expect("write deck");
            path
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    fn read_text(test: &str, text: &str) -> Result<Deck, MeshError> {
        let dir = TempDir::new(test);
        read(&dir.write("deck.inp", text))
    }

    fn parse_error(result: Result<Deck, MeshError>) -> (PathBuf, usize, String) {
        match result {
            Err(MeshError::Parse {
                file,
                line,
                message,
            }) => (file, line, message),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    /// Corners of the unit tetrahedron and its 10 nodes in C3D10 order.
    fn unit_tet_points() -> Vec<[f64; 3]> {
        let c = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let mut p = c.to_vec();
        for [a, b] in TET10_EDGES {
            p.push([0, 1, 2].map(|k| 0.5 * (c[a][k] + c[b][k])));
        }
        p
    }

    /// `*NODE` lines of the unit tet with labels `first, first + 1, ...`.
    fn unit_tet_nodes(first: i64) -> String {
        let mut s = String::new();
        for (i, x) in unit_tet_points().iter().enumerate() {
            writeln!(s, "{}, {}, {}, {}", first + i as i64, x[0], x[1], x[2]).unwrap();
        }
        s
    }

    fn unit_tet_element(label: i64, first: i64) -> String {
        let nodes: Vec<String> = (0..10).map(|k| (first + k).to_string()).collect();
        format!("{label}, {}\n", nodes.join(", "))
    }

    const STEEL: &str = "*MATERIAL, NAME=Steel\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n";

    /// One unit tet, nodes 11..20, element 7, in set EALL with steel.
    fn one_tet() -> String {
        format!(
            "*NODE, NSET=NALL\n{}*ELEMENT, TYPE=C3D10, ELSET=EALL\n{}{STEEL}\
             *SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n",
            unit_tet_nodes(11),
            unit_tet_element(7, 11)
        )
    }

    /// A box of `n[0] x n[1] x n[2]` cubes, each split into the six Kuhn tetrahedra (a
    /// conforming mesh), with quadratic nodes at the edge midpoints. Returns the `*NODE` and
    /// `*ELEMENT` text and, per node label, its half-grid index. Node labels are odd numbers
    /// (so not contiguous), element labels start at 101.
    fn box_mesh(n: [usize; 3], size: [f64; 3], elset: &str) -> String {
        let m = [2 * n[0] + 1, 2 * n[1] + 1, 2 * n[2] + 1];
        let label = |h: [usize; 3]| 2 * (h[0] + m[0] * (h[1] + m[1] * h[2])) + 1;
        let mut s = String::from("*NODE, NSET=NALL\n");
        for k in 0..m[2] {
            for j in 0..m[1] {
                for i in 0..m[0] {
                    let x = [i, j, k]
                        .iter()
                        .zip(size.iter().zip(n))
                        .map(|(&h, (&l, n))| h as f64 * l / (2 * n) as f64)
                        .collect::<Vec<_>>();
                    writeln!(
                        s,
                        "{}, {:.8}, {:.8}, {:.8}",
                        label([i, j, k]),
                        x[0],
                        x[1],
                        x[2]
                    )
                    .unwrap();
                }
            }
        }
        writeln!(s, "*ELEMENT, TYPE=C3D10, ELSET={elset}").unwrap();
        let perms = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        let mut e = 101;
        for k in 0..n[2] {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    for p in perms {
                        // Path from the cube's (0,0,0) corner to (1,1,1) along p.
                        let mut v = [[2 * i, 2 * j, 2 * k]; 4];
                        for step in 0..3 {
                            v[step + 1] = v[step];
                            v[step + 1][p[step]] += 2;
                        }
                        // Odd permutations give negative volumes: swap two corners.
                        let d = |a: usize| [0, 1, 2].map(|c| v[a][c] as f64 - v[0][c] as f64);
                        if dot(d(1), cross(d(2), d(3))) < 0.0 {
                            v.swap(1, 2);
                        }
                        let mut nodes: Vec<usize> = v.iter().map(|&h| label(h)).collect();
                        for [a, b] in TET10_EDGES {
                            nodes.push(label([0, 1, 2].map(|c| (v[a][c] + v[b][c]) / 2)));
                        }
                        let list: Vec<String> = nodes.iter().map(|x| x.to_string()).collect();
                        writeln!(s, "{e}, {}", list.join(", ")).unwrap();
                        e += 1;
                    }
                }
            }
        }
        s
    }

    /// The committed test deck: a 0.1 x 0.01 x 0.01 m steel cantilever, clamped at x = 0,
    /// with a 10-mode *FREQUENCY step, as CalculiX runs it.
    fn beam_deck() -> String {
        let n = [10, 2, 2];
        let mut s = String::from(
            "*HEADING\nCantilever beam 0.1 x 0.01 x 0.01 m, 10 x 2 x 2 cubes of 6 C3D10, steel, \
             clamped at x = 0\n** Written by write_beam_deck in src/mesh/abaqus.rs (squeal).\n",
        );
        s.push_str(&box_mesh(n, [0.1, 0.01, 0.01], "EBEAM"));
        s.push_str("*NSET, NSET=FIX\n");
        let m = [2 * n[0] + 1, 2 * n[1] + 1, 2 * n[2] + 1];
        let fixed: Vec<String> = (0..m[1] * m[2])
            .map(|jk| (2 * m[0] * jk + 1).to_string())
            .collect();
        for chunk in fixed.chunks(8) {
            writeln!(s, "{}", chunk.join(", ")).unwrap();
        }
        s.push_str(
            "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n\
             *SOLID SECTION, ELSET=EBEAM, MATERIAL=STEEL\n\
             *BOUNDARY\nFIX, 1, 3\n\
             *STEP\n*FREQUENCY\n10\n*NODE FILE\nU\n*EL FILE\nS\n*END STEP\n",
        );
        s
    }

    fn beam_path() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/beam_c3d10.inp")
    }

    /// Regenerates tests/data/beam_c3d10.inp: `cargo test write_beam_deck -- --ignored`.
    #[test]
    #[ignore]
    fn write_beam_deck() {
        std::fs::write(beam_path(), beam_deck()).expect("write beam deck");
    }

    // --- the test deck ------------------------------------------------------------------

    #[test]
    fn beam_deck_reads_with_right_counts_and_positive_volumes() {
        let path = beam_path();
        let text = std::fs::read_to_string(&path).expect("tests/data/beam_c3d10.inp");
        assert_eq!(
            text,
            beam_deck(),
            "committed deck differs from its generator"
        );
        let deck = read(&path).unwrap();
        let mesh = &deck.mesh;
        // (2*10+1) * (2*2+1)^2 half-grid points, all used; 6 tets per cube.
        assert_eq!(mesh.nodes.len(), 21 * 5 * 5);
        assert_eq!(mesh.elements.len(), 6 * 10 * 2 * 2);
        // Kuhn tets all have volume (cube volume)/6 > 0, and they tile the beam exactly.
        let cube = 0.01 * 0.005 * 0.005;
        let mut total = 0.0;
        for e in 0..mesh.elements.len() {
            let v = mesh.corner_volume(e);
            assert!((v - cube / 6.0).abs() < 1e-12 * cube, "element {e}: {v}");
            total += v;
        }
        assert!((total - 1e-5).abs() < 1e-12 * 1e-5);
        // Each mid node sits at the middle of its edge (the C3D10 order was kept).
        for conn in &mesh.elements {
            for (k, [a, b]) in TET10_EDGES.iter().enumerate() {
                let (mid, p, q) = (
                    mesh.nodes[conn[4 + k]],
                    mesh.nodes[conn[*a]],
                    mesh.nodes[conn[*b]],
                );
                for (c, m) in mid.iter().enumerate() {
                    assert!((m - 0.5 * (p[c] + q[c])).abs() < 1e-12);
                }
            }
        }
        assert_eq!(mesh.parts.len(), 1);
        assert_eq!(mesh.parts[0].name, "EBEAM");
        assert_eq!(mesh.parts[0].elements.len(), 240);
        let steel = &mesh.materials["STEEL"];
        assert_eq!(
            (steel.young, steel.poisson, steel.density),
            (210e9, 0.3, 7850.0)
        );
        let fix = &mesh.node_sets["FIX"];
        assert_eq!(fix.len(), 25);
        assert!(fix.iter().all(|&n| mesh.nodes[n][0] == 0.0));
        assert_eq!(deck.steps.len(), 1);
        assert_eq!(
            deck.steps[0].procedure,
            Procedure::Frequency(FrequencyRequest {
                eigenvalues: Some(10),
                ..Default::default()
            })
        );
        let loading = deck.loading_in_step(0).unwrap();
        assert_eq!(loading.displacements.len(), 75);
        assert!(loading.displacements.values().all(|&v| v == 0.0));
        assert_eq!(deck.warnings.len(), 1, "{:?}", deck.warnings);
        assert!(deck.warnings[0].contains("*NODE FILE (1x"));
        assert!(deck.warnings[0].contains("*EL FILE (1x"));
    }

    // --- keywords -----------------------------------------------------------------------

    #[test]
    fn model_keywords_build_nodes_elements_sets_materials_and_parts() {
        let text = format!(
            "** a comment\n*HEADING\nOne tet\nsecond heading line\n\n{}\
             *NSET, NSET=corners\n11, 12\n13, 14,\n*NSET, NSET=Mixed\ncorners, 20\n\
             *ELSET, ELSET=Again\nEALL\n*MATERIAL, NAME=Unused\n*ELASTIC\n1e9\n",
            one_tet()
        );
        let deck = read_text("model", &text).unwrap();
        let mesh = &deck.mesh;
        assert_eq!(deck.heading, "One tet\nsecond heading line");
        assert_eq!(mesh.nodes.len(), 10);
        assert_eq!(mesh.node_labels, (11..=20).collect::<Vec<_>>());
        assert_eq!(mesh.nodes[4], [0.5, 0.0, 0.0]);
        assert_eq!(mesh.elements, vec![[0, 1, 2, 3, 4, 5, 6, 7, 8, 9]]);
        assert_eq!(mesh.element_labels, vec![7]);
        assert!((mesh.corner_volume(0) - 1.0 / 6.0).abs() < 1e-15);
        assert_eq!(mesh.node_sets["NALL"], (0..10).collect::<Vec<_>>());
        assert_eq!(mesh.node_sets["CORNERS"], vec![0, 1, 2, 3]);
        assert_eq!(mesh.node_sets["MIXED"], vec![0, 1, 2, 3, 9]);
        assert_eq!(deck.element_sets["AGAIN"], vec![0]);
        assert_eq!(
            mesh.parts,
            vec![Part {
                name: "EALL".into(),
                elements: vec![0],
                material: Some("STEEL".into()),
            }]
        );
        assert_eq!(
            mesh.materials["STEEL"],
            Material {
                name: "STEEL".into(),
                young: 210e9,
                poisson: 0.3,
                density: 7850.0
            }
        );
        // The incomplete, unused material is left out with a warning.
        assert!(!mesh.materials.contains_key("UNUSED"));
        assert!(deck
            .warnings
            .iter()
            .any(|w| w.contains("Unused") && w.contains("*DENSITY")));
    }

    #[test]
    fn generate_expands_ranges_and_drops_missing_labels_with_a_warning() {
        let text = format!(
            "{}*NSET, NSET=EVERY2, GENERATE\n11, 19, 2\n*NSET, NSET=GAPPY, GENERATE\n18, 25\n\
             *ELSET, ELSET=E, GENERATE\n7, 7\n",
            one_tet()
        );
        let deck = read_text("generate", &text).unwrap();
        assert_eq!(deck.mesh.node_sets["EVERY2"], vec![0, 2, 4, 6, 8]);
        assert_eq!(deck.mesh.node_sets["GAPPY"], vec![7, 8, 9]);
        assert_eq!(deck.element_sets["E"], vec![0]);
        let w = deck
            .warnings
            .iter()
            .find(|w| w.contains("GAPPY"))
            .expect("warning for GAPPY");
        assert!(w.contains("5 label(s)") && w.contains("deck.inp:"), "{w}");
    }

    #[test]
    fn an_element_may_continue_on_the_next_line() {
        let text = format!(
            "*NODE\n{}*ELEMENT, TYPE=C3D10, ELSET=EALL\n7, 11, 12, 13, 14, 15, 16, 17,\n\
             18, 19, 20\n** a comment between elements\n8, 11, 12, 13, 14, 15, 16, 17, 18, 19, \
             20,\n{STEEL}*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n",
            unit_tet_nodes(11)
        );
        let deck = read_text("continuation", &text).unwrap();
        assert_eq!(deck.mesh.element_labels, vec![7, 8]);
        assert_eq!(deck.mesh.elements[0], deck.mesh.elements[1]);
        assert_eq!(deck.mesh.elements[0], [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]);
    }

    #[test]
    fn include_is_relative_to_the_including_file_and_nests() {
        let dir = TempDir::new("include");
        dir.write("sub/nodes.inp", &unit_tet_nodes(11));
        dir.write(
            "sub/mesh.inp",
            "*NODE, NSET=NALL\n*INCLUDE, INPUT=nodes.inp\n*ELEMENT, TYPE=C3D10, \
             ELSET=EALL, INPUT=elements.inp\n",
        );
        dir.write("sub/elements.inp", &unit_tet_element(7, 11));
        let main = dir.write(
            "main.inp",
            &format!(
                "*INCLUDE, INPUT=sub/mesh.inp\n{STEEL}*SOLID SECTION, ELSET=EALL, \
                 MATERIAL=STEEL\n"
            ),
        );
        let deck = read(&main).unwrap();
        assert_eq!(deck.mesh.nodes.len(), 10);
        assert_eq!(deck.mesh.node_sets["NALL"].len(), 10);
        assert_eq!(deck.mesh.elements.len(), 1);
        assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
    }

    #[test]
    fn an_error_in_an_included_file_names_that_file_and_its_line() {
        let dir = TempDir::new("include-error");
        let bad = dir.write("sub/nodes.inp", "** nodes\n11, 0, 0, 0\n12, 1, zero, 0\n");
        let main = dir.write("main.inp", "*NODE\n*INCLUDE, INPUT=sub/nodes.inp\n");
        let (file, line, message) = parse_error(read(&main));
        assert_eq!((file, line), (bad, 3));
        assert!(
            message.contains("\"zero\"") && message.contains("node 12"),
            "{message}"
        );
    }

    #[test]
    fn a_missing_include_names_the_file_and_the_including_line() {
        let dir = TempDir::new("include-missing");
        let main = dir.write("main.inp", "*HEADING\nx\n*INCLUDE, INPUT=\"absent.inp\"\n");
        let (file, line, message) = parse_error(read(&main));
        assert_eq!((file, line), (main, 3));
        assert!(message.contains("absent.inp"), "{message}");
    }

    #[test]
    fn an_include_cycle_is_an_error() {
        let dir = TempDir::new("include-cycle");
        dir.write("a.inp", "*INCLUDE, INPUT=b.inp\n");
        let b = dir.write("b.inp", "** b\n*INCLUDE, INPUT=a.inp\n");
        let (file, line, message) = parse_error(read(&dir.0.join("a.inp")));
        assert_eq!((file, line), (b, 2));
        assert!(message.contains("cycle"), "{message}");
    }

    #[test]
    fn surfaces_s1_to_s4_are_the_abaqus_faces_pointing_outward() {
        let text = format!(
            "{}*SURFACE, NAME=All faces, TYPE=ELEMENT\n7, S1\n7, S2\nEALL, s3\n7, S4\n7, S1\n",
            one_tet()
        );
        let deck = read_text("surfaces", &text).unwrap();
        let mesh = &deck.mesh;
        let surface = &mesh.surfaces["ALL FACES"];
        assert_eq!(surface.faces.len(), 4, "the repeated S1 is kept once");
        // Abaqus' C3D10 faces in 1-based node numbers: corners, and the mid nodes of their
        // edges (5 = 1-2, 6 = 2-3, 7 = 3-1, 8 = 1-4, 9 = 2-4, 10 = 3-4).
        let abaqus: [[usize; 6]; 4] = [
            [1, 2, 3, 5, 6, 7],
            [1, 4, 2, 8, 9, 5],
            [2, 4, 3, 9, 10, 6],
            [3, 4, 1, 10, 8, 7],
        ];
        let centroid = [0.25; 3];
        for (side, face) in surface.faces.iter().enumerate() {
            assert_eq!((face.element, usize::from(face.side)), (0, side));
            let mut got: Vec<usize> = face.nodes.to_vec();
            let mut want: Vec<usize> = abaqus[side].iter().map(|n| n - 1).collect();
            got.sort_unstable();
            want.sort_unstable();
            assert_eq!(got, want, "S{}", side + 1);
            let x = |i: usize| mesh.nodes[face.nodes[i]];
            let normal = cross(sub(x(1), x(0)), sub(x(2), x(0)));
            assert!(
                dot(normal, sub(x(0), centroid)) > 0.0,
                "S{} inward",
                side + 1
            );
        }
    }

    #[test]
    fn a_surface_line_without_a_face_takes_the_free_faces_of_the_set() {
        let text = format!(
            "{}*MATERIAL, NAME=STEEL\n*ELASTIC\n1, 0\n*DENSITY\n1\n\
             *SOLID SECTION, ELSET=CUBE, MATERIAL=STEEL\n*SURFACE, NAME=OUTSIDE\nCUBE\n",
            box_mesh([1, 1, 1], [1.0, 1.0, 1.0], "CUBE")
        );
        let deck = read_text("free-faces", &text).unwrap();
        let mesh = &deck.mesh;
        let faces = &mesh.surfaces["OUTSIDE"].faces;
        // 6 tets, 24 faces, 6 interior pairs: the 12 triangles of the cube's 6 sides.
        assert_eq!(faces.len(), 12);
        let mut area = 0.0;
        for f in faces {
            let x = |i: usize| mesh.nodes[f.nodes[i]];
            let n = cross(sub(x(1), x(0)), sub(x(2), x(0)));
            area += 0.5 * dot(n, n).sqrt();
            assert!(
                dot(n, sub(x(0), [0.5; 3])) > 0.0,
                "face points into the cube"
            );
        }
        assert!((area - 6.0).abs() < 1e-12, "surface area {area}");
    }

    #[test]
    fn a_node_based_surface_becomes_a_node_set_and_is_marked() {
        let text = format!(
            "{}*SURFACE, NAME=Contact, TYPE=NODE\nNALL\n*NSET, NSET=SOME\n11\n\
             *SURFACE, NAME=Two, TYPE=NODE\nSOME, 1.0\n12\n",
            one_tet()
        );
        let deck = read_text("node-surface", &text).unwrap();
        assert_eq!(deck.mesh.node_sets["CONTACT"].len(), 10);
        assert_eq!(deck.mesh.node_sets["TWO"], vec![0, 1]);
        assert_eq!(
            deck.node_surfaces,
            BTreeSet::from(["CONTACT".to_string(), "TWO".to_string()])
        );
        assert!(deck.mesh.surfaces.is_empty());
    }

    #[test]
    fn supports_and_loads_belong_to_model_data_or_their_step() {
        let text = format!(
            "{}*SURFACE, NAME=BOTTOM\n7, S1\n*NSET, NSET=BASE\n11, 12, 13\n\
             *BOUNDARY\nBASE, 3\n11, 1, 2\n12, 2,, 0.0\n\
             *STEP, NAME=Press, NLGEOM\nSqueeze the tet\n*STATIC\n0.1, 1.0\n\
             *CLOAD\n14, 1, 5.0\nBASE, 2, -1.5\n*DSLOAD\nBottom, P, 2.0e5\n\
             *DLOAD\nEALL, P2, 3.0\n*END STEP\n\
             *STEP\n*FREQUENCY\n12, 100., 5000.\n*CLOAD, OP=NEW\n15, 3, 1\n*END STEP\n\
             *STEP\n*STATIC\n*BOUNDARY, OP=NEW\n14, 1, 3, 0.001\n*CLOAD\n14, 1, 7.0\n\
             *DSLOAD\nBOTTOM, P, 1.0\n*END STEP\n",
            one_tet()
        );
        let deck = read_text("loads", &text).unwrap();
        let mesh = &deck.mesh;
        assert_eq!(deck.boundaries.len(), 3);
        assert_eq!(deck.boundaries[0].target, NodeTarget::Set("BASE".into()));
        assert_eq!(deck.boundaries[0].nodes, vec![0, 1, 2]);
        assert_eq!(
            (deck.boundaries[0].first_dof, deck.boundaries[0].last_dof),
            (3, 3)
        );
        assert_eq!(deck.boundaries[1].target, NodeTarget::Node(11));
        assert_eq!(
            (deck.boundaries[1].first_dof, deck.boundaries[1].last_dof),
            (1, 2)
        );
        assert_eq!(
            deck.boundaries[2].source.line,
            deck.boundaries[1].source.line + 1
        );
        assert_eq!(deck.steps.len(), 3);

        let s0 = &deck.steps[0];
        assert_eq!(s0.name.as_deref(), Some("Press"));
        assert_eq!(s0.title.as_deref(), Some("Squeeze the tet"));
        assert!(s0.nlgeom && !s0.perturbation);
        assert_eq!(
            s0.procedure,
            Procedure::Static(StaticRequest {
                initial_increment: Some(0.1),
                time_period: Some(1.0),
                ..Default::default()
            })
        );
        assert_eq!(s0.concentrated_loads.len(), 2);
        assert_eq!(s0.concentrated_loads[1].nodes, vec![0, 1, 2]);
        assert_eq!(s0.pressures.len(), 2);
        assert_eq!(
            s0.pressures[0].target,
            PressureTarget::Surface("BOTTOM".into())
        );
        assert_eq!(s0.pressures[0].faces, vec![mesh.face(0, 0)]);
        assert_eq!(
            s0.pressures[1].target,
            PressureTarget::ElementSet("EALL".into())
        );
        assert_eq!(s0.pressures[1].faces, vec![mesh.face(0, 1)]);
        assert_eq!(
            deck.steps[1].procedure,
            Procedure::Frequency(FrequencyRequest {
                eigenvalues: Some(12),
                lower_frequency: Some(100.0),
                upper_frequency: Some(5000.0),
                shift: None,
            })
        );
        assert!(deck.steps[1].perturbation && deck.steps[1].replaced.concentrated_loads);

        // Model data alone: z of nodes 0..3, x and y of node 0, y of node 1.
        let model = deck.model_loading();
        let fixed: Vec<(usize, usize)> = model.displacements.keys().copied().collect();
        assert_eq!(fixed, vec![(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)]);
        assert!(model.forces.is_empty() && model.pressures.is_empty());

        // Step 1: model supports + its loads.
        let l0 = deck.loading_in_step(0).unwrap();
        assert_eq!(l0.displacements, model.displacements);
        assert_eq!(l0.forces[&(3, 0)], 5.0);
        assert_eq!(l0.forces[&(0, 1)], -1.5);
        assert_eq!(l0.forces.len(), 4);
        assert_eq!(
            l0.pressures,
            vec![(mesh.face(0, 0), 2.0e5), (mesh.face(0, 1), 3.0)]
        );

        // Step 2 (perturbation, OP=NEW on *CLOAD): the step-1 forces are gone, only its own.
        let l1 = deck.loading_in_step(1).unwrap();
        assert_eq!(l1.displacements, model.displacements);
        assert_eq!(l1.forces, BTreeMap::from([((4, 2), 1.0)]));
        assert_eq!(l1.pressures.len(), 2);

        // Step 3: step 2 does not carry over; OP=NEW removes all earlier supports; the force
        // on node 14 x is replaced, the *DSLOAD on BOTTOM replaced, the *DLOAD kept.
        let l2 = deck.loading_in_step(2).unwrap();
        assert_eq!(
            l2.displacements,
            BTreeMap::from([((3, 0), 0.001), ((3, 1), 0.001), ((3, 2), 0.001)])
        );
        assert_eq!(l2.forces[&(3, 0)], 7.0);
        assert_eq!(l2.forces[&(0, 1)], -1.5);
        assert!(!l2.forces.contains_key(&(4, 2)));
        assert_eq!(
            l2.pressures,
            vec![(mesh.face(0, 0), 1.0), (mesh.face(0, 1), 3.0)]
        );
        assert!(deck.loading_in_step(3).is_none());
    }

    #[test]
    fn two_surfaces_on_one_face_add_up() {
        let text = format!(
            "{}*SURFACE, NAME=A\n7, S3\n*SURFACE, NAME=B\n7, S3\n*DSLOAD\nA, P, 1.0\nB, P, 2.5\n\
             *DLOAD\n7, P3, 0.5\n",
            one_tet()
        );
        let deck = read_text("pressure-sum", &text).unwrap();
        let loading = deck.model_loading();
        assert_eq!(loading.pressures, vec![(deck.mesh.face(0, 2), 4.0)]);
        assert_eq!(deck.pressures[2].target, PressureTarget::Element(7));
    }

    #[test]
    fn frequency_data_line_follows_the_eigensolver_layout() {
        let text = format!(
            "{}*STEP\n*FREQUENCY, EIGENSOLVER=SUBSPACE\n8, 2000., 10.\n*END STEP\n\
             *STEP\n*FREQUENCY, EIGENSOLVER=LANCZOS\n, 0., 3.0D3, 5.\n*END STEP\n\
             *STEP, PERTURBATION\n*STATIC\n*END STEP\n\
             *STEP\n*COMPLEX FREQUENCY\n20\n*END STEP\n",
            one_tet()
        );
        let deck = read_text("frequency", &text).unwrap();
        assert_eq!(
            deck.steps[0].procedure,
            Procedure::Frequency(FrequencyRequest {
                eigenvalues: Some(8),
                lower_frequency: None,
                upper_frequency: Some(2000.0),
                shift: Some(10.0),
            })
        );
        assert_eq!(
            deck.steps[1].procedure,
            Procedure::Frequency(FrequencyRequest {
                eigenvalues: None,
                lower_frequency: Some(0.0),
                upper_frequency: Some(3000.0),
                shift: Some(5.0),
            })
        );
        assert!(deck.steps[2].perturbation);
        assert_eq!(
            deck.steps[3].procedure,
            Procedure::Unsupported {
                keyword: "*COMPLEX FREQUENCY".into()
            }
        );
        assert!(deck.steps[3].perturbation);
        assert!(deck
            .warnings
            .iter()
            .any(|w| w.contains("*COMPLEX FREQUENCY")));
    }

    #[test]
    fn keywords_parameters_and_names_are_case_insensitive() {
        let text = format!(
            "*node, nset=All\n{}*Element, Type=c3d10, Elset=Body\n{}*material, name=Iron\n\
             *elastic, type=Isotropic\n100e9, 0.25\n*density\n7000\n\
             *Solid Section, elset=BODY, material=iron\n*boundary\nall, 1, 3\n\
             *Solid\n*NSET,\n    NSET=Continued\nALL\n",
            unit_tet_nodes(11),
            unit_tet_element(7, 11)
        );
        let deck = read_text("case", &text).unwrap();
        assert_eq!(deck.mesh.parts[0].name, "BODY");
        assert_eq!(deck.mesh.parts[0].material.as_deref(), Some("IRON"));
        assert_eq!(deck.mesh.materials["IRON"].young, 100e9);
        assert_eq!(deck.boundaries[0].nodes.len(), 10);
        assert_eq!(deck.mesh.node_sets["CONTINUED"].len(), 10);
        assert_eq!(deck.warnings.len(), 1, "{:?}", deck.warnings);
        assert!(deck.warnings[0].contains("*SOLID (1x"));
    }

    #[test]
    fn unknown_keywords_are_skipped_and_listed_in_one_warning() {
        let text = format!(
            "{}*CONTACT PAIR, INTERACTION=FRIC\nPAD, DISC\n*STEP\n*STATIC\n*OUTPUT, FIELD\n\
             *NODE OUTPUT\nU\n*OUTPUT, HISTORY\n*END STEP\n",
            one_tet()
        );
        let deck = read_text("unknown", &text).unwrap();
        assert_eq!(deck.warnings.len(), 1, "{:?}", deck.warnings);
        let w = &deck.warnings[0];
        assert!(w.contains("*CONTACT PAIR (1x, first at "), "{w}");
        assert!(w.contains("*OUTPUT (2x, first at "), "{w}");
        assert!(w.contains("*NODE OUTPUT (1x"), "{w}");
        assert!(w.contains("deck.inp:"), "{w}");
    }

    #[test]
    fn rotational_dofs_are_ignored_with_a_warning_and_named_conditions_work() {
        let text = format!(
            "{}*BOUNDARY\nNALL, 1, 6\n11, 4, 6\n12, ENCASTRE\n13, XSYMM\n*CLOAD\n14, 5, 1.0\n",
            one_tet()
        );
        let deck = read_text("rotations", &text).unwrap();
        let b: Vec<(u8, u8)> = deck
            .boundaries
            .iter()
            .map(|b| (b.first_dof, b.last_dof))
            .collect();
        assert_eq!(b, vec![(1, 3), (1, 3), (1, 1)]);
        assert!(deck.concentrated_loads.is_empty());
        let w = deck
            .warnings
            .iter()
            .find(|w| w.contains("rotational"))
            .expect("warning");
        assert!(
            w.contains("*BOUNDARY (2x") && w.contains("*CLOAD (1x"),
            "{w}"
        );
    }

    #[test]
    fn c3d10_variants_are_read_with_a_warning() {
        let text = format!(
            "*NODE\n{}*ELEMENT, TYPE=C3D10M, ELSET=E\n{}{STEEL}\
             *SOLID SECTION, ELSET=E, MATERIAL=STEEL\n",
            unit_tet_nodes(1),
            unit_tet_element(1, 1)
        );
        let deck = read_text("variant", &text).unwrap();
        assert_eq!(deck.mesh.elements.len(), 1);
        assert!(deck.warnings[0].contains("C3D10M"));
    }

    #[test]
    fn a_byte_order_mark_crlf_and_latin1_are_accepted() {
        let mut bytes = b"\xef\xbb\xbf*HEADING\r\nCaf\xe9 brake\r\n".to_vec();
        bytes.extend(one_tet().replace('\n', "\r\n").into_bytes());
        let dir = TempDir::new("bom");
        let path = dir.0.join("deck.inp");
        std::fs::write(&path, bytes).unwrap();
        let deck = read(&path).unwrap();
        assert!(deck.heading.starts_with("Caf") && deck.heading.ends_with(" brake"));
        assert_eq!(deck.mesh.elements.len(), 1);
    }

    #[test]
    fn numbers_in_fortran_and_c_notation() {
        for (s, v) in [
            ("1.", 1.0),
            ("1.e5", 1e5),
            (".5", 0.5),
            ("2.1D+11", 2.1e11),
            ("-3d-2", -0.03),
        ] {
            assert_eq!(parse_number(s), Some(v), "{s}");
        }
        for s in ["nan", "inf", "1.2.3", "", "x"] {
            assert_eq!(parse_number(s), None, "{s}");
        }
    }

    // --- errors -------------------------------------------------------------------------

    #[test]
    fn a_non_numeric_field_is_an_error_at_its_line() {
        let (_, line, message) = parse_error(read_text(
            "err-number",
            "*NODE\n1, 0, 0, 0\n2, 1.0, 0, abc\n",
        ));
        assert_eq!(line, 3);
        assert!(
            message.contains("\"abc\"") && message.contains("z coordinate"),
            "{message}"
        );
        let (_, line, message) = parse_error(read_text(
            "err-label",
            "*NODE\n1, 0, 0, 0\n*ELEMENT, TYPE=C3D10\n5, 1, 2, 3, x4, 5, 6, 7, 8, 9, 10\n",
        ));
        assert_eq!(line, 4);
        assert!(message.contains("\"x4\""), "{message}");
    }

    #[test]
    fn a_wrong_node_count_for_c3d10_is_an_error() {
        let base = format!("*NODE\n{}*ELEMENT, TYPE=C3D10\n", unit_tet_nodes(1));
        let (_, line, message) = parse_error(read_text(
            "err-count-short",
            &format!("{base}5, 1, 2, 3, 4, 5, 6, 7, 8, 9\n"),
        ));
        assert_eq!(line, 13);
        assert!(
            message.contains("element 5") && message.contains("found 9"),
            "{message}"
        );
        let (_, line, message) = parse_error(read_text(
            "err-count-long",
            &format!("{base}5, 1, 2, 3, 4, 5, 6,\n7, 8, 9, 10, 11\n"),
        ));
        assert_eq!(line, 14);
        assert!(message.contains("found 11"), "{message}");
    }

    #[test]
    fn an_element_on_an_undefined_node_names_both() {
        let text = format!(
            "*NODE\n{}*ELEMENT, TYPE=C3D10, ELSET=E\n1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 99\n",
            unit_tet_nodes(1)
        );
        let (_, line, message) = parse_error(read_text("err-node", &text));
        assert_eq!(line, 13);
        assert!(
            message.contains("element 1") && message.contains("node 99"),
            "{message}"
        );
    }

    #[test]
    fn unknown_sets_are_named_at_the_line_that_uses_them() {
        let cases = [
            ("*SOLID SECTION, ELSET=Nowhere, MATERIAL=STEEL\n", "Nowhere"),
            ("*BOUNDARY\nFixed, 1, 3\n", "Fixed"),
            ("*SURFACE, NAME=S\nGhost, S1\n", "Ghost"),
            ("*CLOAD\nLoadSet, 1, 3.0\n", "LoadSet"),
            ("*DSLOAD\nSurf, P, 3.0\n", "Surf"),
            ("*NSET, NSET=A\nNotYet\n", "NotYet"),
        ];
        let base = one_tet();
        let base_lines = base.lines().count();
        for (i, (tail, name)) in cases.iter().enumerate() {
            let (_, line, message) =
                parse_error(read_text(&format!("err-set-{i}"), &format!("{base}{tail}")));
            assert_eq!(line, base_lines + tail.lines().count(), "{tail}");
            assert!(message.contains(name), "{message}");
            assert!(message.contains("not defined"), "{message}");
        }
    }

    #[test]
    fn a_section_on_an_undefined_material_names_it() {
        let text = format!(
            "*NODE\n{}*ELEMENT, TYPE=C3D10, ELSET=E\n{}*SOLID SECTION, ELSET=E, MATERIAL=Brass\n",
            unit_tet_nodes(1),
            unit_tet_element(1, 1)
        );
        let (_, line, message) = parse_error(read_text("err-material", &text));
        assert_eq!(line, 14);
        assert!(
            message.contains("material Brass is not defined"),
            "{message}"
        );
    }

    #[test]
    fn a_used_material_needs_elastic_and_density() {
        for (props, missing) in [
            ("*ELASTIC\n1e9, 0.3\n", "*DENSITY"),
            ("*DENSITY\n1\n", "*ELASTIC"),
        ] {
            let text = format!(
                "*NODE\n{}*ELEMENT, TYPE=C3D10, ELSET=E\n{}*MATERIAL, NAME=Half\n{props}\
                 *SOLID SECTION, ELSET=E, MATERIAL=HALF\n",
                unit_tet_nodes(1),
                unit_tet_element(1, 1)
            );
            let (_, line, message) = parse_error(read_text("err-incomplete", &text));
            assert_eq!(line, 14, "at the *MATERIAL line");
            assert!(
                message.contains("Half") && message.contains(missing),
                "{message}"
            );
            assert!(
                message.contains("deck.inp:17"),
                "names the section: {message}"
            );
        }
    }

    #[test]
    fn elements_in_no_section_are_counted_and_the_first_named() {
        let text = format!(
            "*NODE\n{}*ELEMENT, TYPE=C3D10, ELSET=E\n{}*ELEMENT, TYPE=C3D10\n{}{}{STEEL}\
             *SOLID SECTION, ELSET=E, MATERIAL=STEEL\n",
            unit_tet_nodes(1),
            unit_tet_element(1, 1),
            unit_tet_element(40, 1),
            unit_tet_element(41, 1)
        );
        let (_, line, message) = parse_error(read_text("err-orphan", &text));
        assert_eq!(line, 15);
        assert!(message.starts_with("2 element(s)"), "{message}");
        assert!(message.contains("element 40"), "{message}");
    }

    #[test]
    fn a_duplicate_node_label_is_an_error() {
        let (_, line, message) = parse_error(read_text(
            "err-duplicate",
            "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n*NODE\n1, 5, 5, 5\n",
        ));
        assert_eq!(line, 5);
        assert!(message.contains("node 1 is defined twice") && message.contains(":2"));
    }

    #[test]
    fn a_missing_continuation_line_is_an_error() {
        let base = format!("*NODE\n{}*ELEMENT, TYPE=C3D10\n", unit_tet_nodes(1));
        let (_, line, message) = parse_error(read_text(
            "err-eof",
            &format!("{base}5, 1, 2, 3, 4, 5, 6, 7,\n** the end\n"),
        ));
        assert_eq!(line, 13);
        assert!(
            message.contains("element 5") && message.contains("file ends"),
            "{message}"
        );
        let (_, line, message) = parse_error(read_text(
            "err-keyword",
            &format!("{base}5, 1, 2, 3, 4, 5, 6, 7,\n*NSET, NSET=X\n"),
        ));
        assert_eq!(line, 13);
        assert!(message.contains("*NSET"), "{message}");
        // An *ELEMENT without data is fine.
        let deck = read_text("empty-element", &base).unwrap();
        assert!(deck.mesh.elements.is_empty());
    }

    #[test]
    fn other_element_types_are_refused_by_name() {
        for kind in ["C3D4", "C3D8", "C3D20", "S3"] {
            let (_, line, message) = parse_error(read_text(
                "err-type",
                &format!("*NODE\n*ELEMENT, TYPE={kind}\n"),
            ));
            assert_eq!(line, 2);
            assert_eq!(
                message,
                format!("element type {kind} is not supported (squeal needs C3D10)")
            );
        }
    }

    #[test]
    fn step_structure_errors() {
        let base = one_tet();
        let n = base.lines().count();
        let cases = [
            ("*STEP\n*STATIC\n", n + 1, "no *END STEP"),
            ("*STEP\n*STATIC\n*NODE\n", n + 3, "model data"),
            ("*END STEP\n", n + 1, "without a *STEP"),
            (
                "*STEP\n*BOUNDARY\nNALL, 1\n*END STEP\n",
                n + 4,
                "no procedure",
            ),
            ("*STATIC\n", n + 1, "inside *STEP"),
            ("*STEP\n*STEP\n", n + 2, "inside the step"),
            ("*PART, NAME=Disc\n", n + 1, "part/assembly"),
            ("*DLOAD\nEALL, GRAV, 9.81\n", n + 2, "GRAV"),
            (
                "*SURFACE, NAME=NS, TYPE=NODE\nNALL\n*DSLOAD\nns, P, 1\n",
                n + 4,
                "node-based",
            ),
            (
                "*NSET, NSET=NALL\n*SURFACE, NAME=nall, TYPE=NODE\n",
                n + 2,
                "node set",
            ),
            ("*SYSTEM\n0, 0, 0\n", n + 1, "*SYSTEM"),
        ];
        for (i, (tail, line, needle)) in cases.iter().enumerate() {
            let (_, got, message) = parse_error(read_text(
                &format!("err-step-{i}"),
                &format!("{base}{tail}"),
            ));
            assert_eq!(got, *line, "{tail}: {message}");
            assert!(message.contains(needle), "{tail}: {message}");
        }
    }
}
