//! The study file (TOML): everything a user changes for a squeal study — mesh, materials,
//! supports, springs, links, loads, contact pairs, band, friction sweep, output — validated up
//! front with errors that name the file and the key.

pub use super::reduction_spec::ReductionSpec;
use crate::analysis::cea::RayleighDamping;
use crate::contact::SlidingDirection;
use crate::mesh::brake::{self, BrakeParams, Layout};
use crate::model::spec::ModelSpec;
pub use crate::model::spec::{
    ContactSpec, FrictionLawName, LinkSpec, MaterialSpec, MeshSpec, PressureSpec, SpringDirection,
    SpringSpec, SupportSpec,
};
use crate::reduce::Strategy;
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Study {
    #[serde(default)]
    pub mesh: MeshSpec,
    /// Materials per part (override or complete those of the mesh).
    #[serde(default)]
    pub materials: Vec<MaterialSpec>,
    #[serde(default)]
    pub supports: Vec<SupportSpec>,
    #[serde(default)]
    pub springs: Vec<SpringSpec>,
    /// Springs between two bodies' node sets (guide pins, piston seal).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub links: Vec<LinkSpec>,
    #[serde(default)]
    pub pressures: Vec<PressureSpec>,
    #[serde(default)]
    pub contacts: Vec<ContactSpec>,
    #[serde(default)]
    pub analysis: AnalysisSpec,
    /// A reduced contact interface in place of the swept pairs (absent: the full model).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reduction: Option<ReductionSpec>,
    /// What `squeal study` compares with the full model: the reduced interfaces and the
    /// super-element strategies (absent: [`ComparisonSpec::default`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub comparison: Option<ComparisonSpec>,
    /// Output folder.
    #[serde(default = "default_output")]
    pub output: PathBuf,
}

fn default_output() -> PathBuf {
    PathBuf::from("squeal-out")
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalysisSpec {
    /// Modes from 0 to this frequency (Hz).
    #[serde(default = "default_fmax")]
    pub max_frequency_hz: f64,
    /// Friction coefficients of the sweep (applied to the pairs with `sweep = true`).
    #[serde(default = "default_friction")]
    pub friction: Vec<f64>,
    /// Rayleigh damping C = alpha M + beta K (none: undamped CEA).
    pub damping: Option<RayleighDamping>,
    /// Load increments of the static solve.
    #[serde(default = "one")]
    pub increments: usize,
    /// Unstable when Re(lambda) > this * |lambda|.
    #[serde(default = "default_threshold")]
    pub unstable_threshold: f64,
    /// Eigenpairs asked of SLEPc per shift.
    #[serde(default = "default_window")]
    pub window: usize,
    /// Consistent mass rule: "exact" or "gauss4".
    #[serde(default)]
    pub mass_rule: crate::fem::element::MassRule,
    /// At each friction value of a full-size model, the CEA again with this many points of
    /// the disc/pad contact zones' edge opened, then closed (`analysis::contact_edge`): which
    /// modes and instabilities the mesh's edge decides. 0: not done (two more CEAs a point).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub contact_edge_points: usize,
    /// Body shares and the contact pairs' parts of the growth rate for every mode of a
    /// full-size or reduced-interface model, not only the unstable ones (a stable mode's
    /// parts add up to its zero real part: which pair feeds it and which takes it out).
    #[serde(default, skip_serializing_if = "is_false")]
    pub contributions_of_every_mode: bool,
    /// Friction values a sweep may insert, each halfway between two neighbours whose modes
    /// it cannot link with confidence (a link of regret below the tracking's trusted one, or
    /// one that moves a mode's frequency by more than 5 %). 0: none.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub refine_points: usize,
    /// Which solver the CEA's windows use: "block" (block Krylov-Schur on multi-right-hand-
    /// side solves of the window's MUMPS LU, SLEPc's Krylov-Schur where it cannot) or
    /// "krylov-schur" (SLEPc's, one vector at a time). The same modes either way.
    #[serde(default, skip_serializing_if = "is_default_solver")]
    pub cea_solver: crate::analysis::cea::WindowSolver,
}

fn is_default_solver(s: &crate::analysis::cea::WindowSolver) -> bool {
    *s == crate::analysis::cea::WindowSolver::default()
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl Default for AnalysisSpec {
    fn default() -> Self {
        AnalysisSpec {
            max_frequency_hz: default_fmax(),
            friction: default_friction(),
            damping: None,
            increments: 1,
            unstable_threshold: default_threshold(),
            window: default_window(),
            mass_rule: Default::default(),
            contact_edge_points: 0,
            contributions_of_every_mode: false,
            refine_points: 0,
            cea_solver: Default::default(),
        }
    }
}

fn default_fmax() -> f64 {
    10_000.0
}
fn default_friction() -> Vec<f64> {
    (1..=9).map(|k| k as f64 / 10.0).collect()
}
fn one() -> usize {
    1
}
fn default_threshold() -> f64 {
    crate::analysis::cea::DEFAULT_UNSTABLE_THRESHOLD
}
fn default_window() -> usize {
    30
}

/// The models `squeal study` compares with the full one (the paper's sections 4.2-4.4): a
/// reduced-interface model per grid size, and super-elements built on one of them with each
/// strategy. The other settings of the reduced interface and of the super-elements
/// (weighting, radius, cut-off, contact law, mu_SE) come from the study's `[reduction]`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComparisonSpec {
    /// Reduced contact nodes per pad of each reduced-interface model (the paper's 6, 22, 52,
    /// 106); empty: none.
    #[serde(default = "default_grids")]
    pub contact_nodes_per_pad: Vec<usize>,
    /// Super-element strategies to sweep ("single", "per-friction", "adaptive"); empty: none.
    #[serde(default = "all_strategies")]
    pub superelements: Vec<Strategy>,
    /// The reduced interface the super-elements are built on (default: the finest of
    /// `contact_nodes_per_pad`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub superelement_contact_nodes_per_pad: Option<usize>,
    /// First compare the full model and each reduced interface without friction (mu = 0,
    /// one point each): the closed contact zones and the real modes, before any friction
    /// value is run.
    #[serde(default = "yes")]
    pub frictionless: bool,
}

fn yes() -> bool {
    true
}

fn default_grids() -> Vec<usize> {
    vec![22, 52]
}
fn all_strategies() -> Vec<Strategy> {
    Strategy::ALL.to_vec()
}

impl Default for ComparisonSpec {
    fn default() -> Self {
        ComparisonSpec {
            contact_nodes_per_pad: default_grids(),
            superelements: all_strategies(),
            superelement_contact_nodes_per_pad: None,
            frictionless: true,
        }
    }
}

impl ComparisonSpec {
    /// The grid the super-elements are built on, if any are asked for.
    pub fn superelement_grid(&self) -> Option<usize> {
        if self.superelements.is_empty() {
            return None;
        }
        self.superelement_contact_nodes_per_pad
            .or_else(|| self.contact_nodes_per_pad.iter().copied().max())
    }

    fn check(&self, bad: impl Fn(String, String) -> ConfigError) -> Result<(), ConfigError> {
        for (i, &n) in self.contact_nodes_per_pad.iter().enumerate() {
            if n == 0 {
                return Err(bad(
                    format!("comparison.contact_nodes_per_pad[{i}]"),
                    "must be at least 1".into(),
                ));
            }
            if self.contact_nodes_per_pad[..i].contains(&n) {
                return Err(bad(
                    format!("comparison.contact_nodes_per_pad[{i}]"),
                    format!("{n} is given twice"),
                ));
            }
        }
        for (i, s) in self.superelements.iter().enumerate() {
            if self.superelements[..i].contains(s) {
                return Err(bad(
                    format!("comparison.superelements[{i}]"),
                    format!("\"{}\" is given twice", s.name()),
                ));
            }
        }
        match (self.superelements.is_empty(), self.superelement_grid()) {
            (false, None) => Err(bad(
                "comparison.superelement_contact_nodes_per_pad".into(),
                "super-elements are built on a reduced interface: give its size here or in contact_nodes_per_pad".into(),
            )),
            (false, Some(0)) => Err(bad(
                "comparison.superelement_contact_nodes_per_pad".into(),
                "must be at least 1".into(),
            )),
            _ => Ok(()),
        }
    }
}

/// The brake line pressure of the built-in studies, Pa.
pub const LINE_PRESSURE: f64 = 2e6;

/// The disc/pad pair of one side (Table 1: mu 0.5, separation; the swept pair).
fn disc_pad_pair(side: &str) -> ContactSpec {
    table1_pair(
        &format!("disc/pad {side}"),
        &format!("pad_{side}_friction_face"),
        &format!("disc_{side}_face"),
        0.5,
        true,
        true,
    )
}

/// One contact pair of the paper's Table 1, pad side slave: the one place that builds the
/// built-in studies' pairs. `swept`: the disc/pad pair, friction along the disc's rotation
/// (counter-clockwise seen from +z) and set by the sweep.
///
/// The other pairs (piston/pad, caliper/pad, bracket/pad, mu 0.15) have no imposed sliding:
/// Coulomb stick and slip, with the default stick stiffness (the penalty / 100).
fn table1_pair(
    name: &str,
    slave: &str,
    master: &str,
    friction: f64,
    separation: bool,
    swept: bool,
) -> ContactSpec {
    let sliding = if swept {
        SlidingDirection::DiscRotation {
            centre: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            sense: 1.0,
        }
    } else {
        SlidingDirection::None
    };
    ContactSpec {
        name: name.into(),
        slave: slave.into(),
        master: master.into(),
        friction,
        penalty: None,
        separation,
        sliding,
        sweep: swept,
        friction_law: if swept {
            FrictionLawName::SteadySliding
        } else {
            FrictionLawName::Coulomb
        },
        stick_stiffness: None,
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    #[error("{file}: {source}")]
    Io {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{file}: {message}")]
    Syntax { file: PathBuf, message: String },
    /// A study file without a single key.
    #[error(
        "{file}: the study is empty (no mesh, supports, loads or contacts): write one to start \
         from with `squeal sweep --preset NAME --write-study FILE`"
    )]
    Empty { file: PathBuf },
    #[error("{file}: {key}: {message}")]
    Invalid {
        file: PathBuf,
        key: String,
        message: String,
    },
}

/// Whether a study command's file is an Abaqus/CalculiX deck (`.inp`) rather than a study.
pub fn is_deck(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("inp"))
}

impl Study {
    /// The files a run of this study reads: its mesh (or deck) and the study file itself
    /// (`file`, when it names a file): what its outputs must never be.
    pub fn input_files(&self, file: Option<&std::path::Path>) -> Vec<std::path::PathBuf> {
        self.mesh
            .file
            .iter()
            .cloned()
            .chain(
                file.filter(|f| f.is_file())
                    .map(std::path::Path::to_path_buf),
            )
            .collect()
    }
    /// The study of a deck run as written (`squeal sweep deck.inp`): the deck as the mesh
    /// file (with its supports, loads and contact pairs), every other key at its default.
    pub fn of_deck(path: &Path) -> Study {
        Study {
            mesh: MeshSpec {
                file: Some(path.to_path_buf()),
                ..Default::default()
            },
            materials: vec![],
            supports: vec![],
            springs: vec![],
            links: vec![],
            pressures: vec![],
            contacts: vec![],
            analysis: AnalysisSpec::default(),
            reduction: None,
            comparison: None,
            output: default_output(),
        }
    }

    /// The built-in study of a preset: [`Self::builtin_floating_caliper`] for the
    /// floating-caliper presets (`tiny-caliper` ... `industrial-caliper`),
    /// [`Self::builtin_spring_held`] for the others (`tiny` ... `industrial`, and unknown
    /// names, which the model stage then refuses).
    pub fn builtin(preset: &str) -> Study {
        match brake::preset(preset) {
            Some(p) if p.floating_caliper() => Study::builtin_floating_caliper(preset),
            _ => Study::builtin_spring_held(preset),
        }
    }

    /// The built-in spring-held brake study: the paper's Table 1 contact set adapted to the
    /// built-in brake. Disc/pad pairs with separation and friction along the disc's rotation
    /// (the sweep); the piston and caliper, not modelled as bodies, become the brake pressure
    /// on the backplates; the bracket becomes stiff springs on the trailing abutments (normal
    /// to them) and the guides radial springs, so each pad is held against every rigid
    /// motion the disc contact does not hold.
    pub fn builtin_spring_held(preset: &str) -> Study {
        let mut springs = Vec::new();
        for side in ["inboard", "outboard"] {
            springs.push(SpringSpec {
                set: format!("pad_{side}_abutment_trailing"),
                direction: SpringDirection::Circumferential,
                stiffness: 1e9,
            });
            springs.push(SpringSpec {
                set: format!("pad_{side}_guides"),
                direction: SpringDirection::Radial,
                stiffness: 1e8,
            });
        }
        Study {
            mesh: MeshSpec {
                file: None,
                preset: Some(preset.to_string()),
                brake: None,
                ..Default::default()
            },
            materials: vec![],
            supports: vec![SupportSpec {
                set: "disc_hub".into(),
                components: "xyz".into(),
            }],
            springs,
            links: vec![],
            // About 5 kN per pad on the built-in backplates (a 2 MPa line pressure on a
            // 2,500 mm^2 piston).
            pressures: vec![
                PressureSpec {
                    surface: "backplate_inboard_piston".into(),
                    value: 2e6,
                },
                PressureSpec {
                    surface: "backplate_outboard_caliper".into(),
                    value: 2e6,
                },
            ],
            contacts: ["inboard", "outboard"].map(disc_pad_pair).to_vec(),
            analysis: AnalysisSpec::default(),
            reduction: None,
            comparison: None,
            output: default_output(),
        }
    }

    /// The built-in floating-caliper study (the paper's brake, section 2): the disc clamped
    /// at its hub, the bracket at its mount; the hydraulic pressure on the piston bottom and,
    /// opposite and equal in force, on the caliper's bore bottom (2 MPa line pressure on the
    /// piston's section: 2.5 kN with the default piston, see
    /// [`BrakeParams::hydraulic_pressures`]); the caliper on two guide pins (`guide pins`:
    /// soft along the disc axis, stiff across it), the piston on its seal in the bore
    /// (`piston seal`); and the four interfaces of Table 1, pad side slave: disc/pad (mu 0.5,
    /// separation, the swept pair), piston/pad and caliper/pad (0.15, no separation),
    /// bracket/pad (0.15, separation; the four ear end faces on the bracket abutments).
    ///
    /// The 0.15 pairs have Coulomb stick and slip (see [`table1_pair`]). The pads' ears sit
    /// in the bracket's slots on spring-steel abutment clips, which hold them radially
    /// (`springs` on `pad_*_guides`, 1e7 N/m per pad): once the disc drag makes the pads
    /// slip on the piston and the fingers (from mu ~ 0.35), friction no longer holds them
    /// radially, and without the clips the static solve finds no equilibrium.
    /// `preset` is a floating-caliper preset; any other preset's mesh density is taken with
    /// the floating-caliper layout.
    pub fn builtin_floating_caliper(preset: &str) -> Study {
        let named = brake::preset(preset);
        let (params, brake_params) = match named {
            Some(p) if p.floating_caliper() => (p, None),
            other => {
                let p = BrakeParams {
                    layout: Layout::FloatingCaliper,
                    ..other.unwrap_or_default()
                };
                (p.clone(), Some(p))
            }
        };
        let (on_piston, on_bore) = params.hydraulic_pressures(LINE_PRESSURE);
        let mut contacts: Vec<ContactSpec> = ["inboard", "outboard"].map(disc_pad_pair).to_vec();
        contacts.push(table1_pair(
            "piston/pad",
            "backplate_inboard_piston_ring",
            "piston_face",
            0.15,
            false,
            false,
        ));
        contacts.push(table1_pair(
            "caliper/pad",
            "backplate_outboard_caliper",
            "caliper_fingers",
            0.15,
            false,
            false,
        ));
        for side in ["inboard", "outboard"] {
            for end in ["leading", "trailing"] {
                contacts.push(table1_pair(
                    &format!("bracket/pad {side} {end}"),
                    &format!("pad_{side}_abutment_{end}"),
                    &format!("bracket_{side}_{end}"),
                    0.15,
                    true,
                    false,
                ));
            }
        }
        Study {
            mesh: MeshSpec {
                file: None,
                preset: Some(preset.to_string()),
                brake: brake_params,
                ..Default::default()
            },
            materials: vec![],
            supports: ["disc_hub", "bracket_mount"]
                .map(|set| SupportSpec {
                    set: set.into(),
                    components: "xyz".into(),
                })
                .to_vec(),
            springs: ["inboard", "outboard"]
                .map(|side| SpringSpec {
                    set: format!("pad_{side}_guides"),
                    direction: SpringDirection::Radial,
                    stiffness: 1e7,
                })
                .to_vec(),
            links: vec![
                // Two greased pins in rubber-booted bores: the caliper slides along them
                // (1e4 N/m in all stands for the boots' drag), and they hold it across
                // (1e8 N/m in all, the bending stiffness of two 10 mm steel pins
                // cantilevered ~30 mm, 3 E I / L^3 ~ 1.1e8 N/m).
                LinkSpec {
                    name: "guide pins".into(),
                    set: "caliper_pins".into(),
                    to: "bracket_pins".into(),
                    axis: [0.0, 0.0, 1.0],
                    axial: 1e4,
                    transverse: 1e8,
                },
                // The piston's rubber seal: stiff across (it centres the piston in the
                // bore), soft along (the seal's roll-back, ~1e5 N/m).
                LinkSpec {
                    name: "piston seal".into(),
                    set: "piston_outer".into(),
                    to: "caliper_bore".into(),
                    axis: [0.0, 0.0, 1.0],
                    axial: 1e5,
                    transverse: 1e8,
                },
            ],
            pressures: vec![
                PressureSpec {
                    surface: "piston_bottom".into(),
                    value: on_piston,
                },
                PressureSpec {
                    surface: "caliper_bore_bottom".into(),
                    value: on_bore,
                },
            ],
            contacts,
            analysis: AnalysisSpec::default(),
            reduction: None,
            comparison: None,
            output: default_output(),
        }
    }

    /// The model part of the study, for [`crate::model::Model::from_spec`].
    pub fn model_spec(&self) -> ModelSpec<'_> {
        ModelSpec {
            mesh: &self.mesh,
            materials: &self.materials,
            supports: &self.supports,
            springs: &self.springs,
            links: &self.links,
            pressures: &self.pressures,
            contacts: &self.contacts,
        }
    }

    /// Reads and checks a study file; relative paths are made relative to its folder.
    pub fn read(path: &Path) -> Result<Study, ConfigError> {
        let text = crate::input_file::read_to_string(path).map_err(|source| ConfigError::Io {
            file: path.to_path_buf(),
            source,
        })?;
        Study::parse(path, &text)
    }

    /// Parses and checks the text of a study file; `path` names it in messages and is the
    /// folder relative paths are made relative to (nothing is read from it).
    pub fn parse(path: &Path, text: &str) -> Result<Study, ConfigError> {
        let mut study: Study = toml::from_str(text).map_err(|e| ConfigError::Syntax {
            file: path.to_path_buf(),
            message: e.to_string(),
        })?;
        // Every key has a default, so an empty file used to be the default study (the
        // built-in brake without its supports, reported as a free disc after assembly).
        if toml::from_str::<toml::Table>(text).is_ok_and(|t| t.is_empty()) {
            return Err(ConfigError::Empty {
                file: path.to_path_buf(),
            });
        }
        let base = path.parent().unwrap_or(Path::new("."));
        if let Some(f) = &study.mesh.file {
            if f.is_relative() {
                study.mesh.file = Some(base.join(f));
            }
        }
        study.check(path)?;
        Ok(study)
    }

    /// Checks values that serde cannot (ranges, consistency).
    pub fn check(&self, file: &Path) -> Result<(), ConfigError> {
        let bad = |key: String, message: String| ConfigError::Invalid {
            file: file.to_path_buf(),
            key,
            message,
        };
        if self.output.as_os_str().is_empty() {
            // Found before: after the whole sweep, when the results could not be put there.
            return Err(bad(
                "output".into(),
                "is empty: give the folder the results go to".into(),
            ));
        }
        if self.mesh.file.is_some() && (self.mesh.preset.is_some() || self.mesh.brake.is_some()) {
            return Err(bad(
                "mesh".into(),
                "give either file or the built-in brake (preset/brake), not both".into(),
            ));
        }
        if let Some(c) = &self.comparison {
            c.check(bad)?;
        }
        if let Some(r) = &self.reduction {
            let context = super::reduction_spec::StudyContext {
                max_frequency_hz: self.analysis.max_frequency_hz,
                compared_superelements: self
                    .comparison
                    .as_ref()
                    .is_some_and(|c| !c.superelements.is_empty()),
                // A deck's pairs are swept by its *MOTIONs or the sliding key, which the
                // model decides (a reduction with none swept is refused there by name).
                any_swept: self.contacts.iter().any(|c| c.sweep)
                    || self.mesh.file.as_deref().is_some_and(is_deck),
            };
            r.check(context, bad)?;
        }
        let a = &self.analysis;
        if let Some(why) = crate::analysis::cea::band_problem(a.max_frequency_hz) {
            return Err(bad("analysis.max_frequency_hz".into(), why));
        }
        if let Some(why) = crate::analysis::cea::threshold_problem(a.unstable_threshold) {
            return Err(bad("analysis.unstable_threshold".into(), why));
        }
        if a.window == 0 {
            return Err(bad("analysis.window".into(), "must be at least 1".into()));
        }
        if let Some(d) = &a.damping {
            for (key, value) in [("alpha", d.alpha), ("beta", d.beta)] {
                if !(value >= 0.0 && value.is_finite()) {
                    return Err(bad(
                        format!("analysis.damping.{key}"),
                        format!("must be finite and >= 0, got {value}"),
                    ));
                }
            }
        }
        if a.friction.is_empty() {
            return Err(bad("analysis.friction".into(), "no friction values".into()));
        }
        // The first value given again (0 and -0 are one value), found by sorting: the
        // pairwise search took n^2/2 comparisons, minutes for a list of a million values.
        let mut order: Vec<usize> = (0..a.friction.len())
            .filter(|&i| !a.friction[i].is_nan())
            .collect();
        order.sort_by(|&i, &j| {
            let (x, y) = (a.friction[i], a.friction[j]);
            x.partial_cmp(&y).expect("NaN left out").then(i.cmp(&j))
        });
        let repeat = order
            .windows(2)
            .filter(|w| a.friction[w[0]] == a.friction[w[1]])
            .map(|w| w[1])
            .min();
        if let Some(i) = repeat {
            return Err(bad(
                format!("analysis.friction[{i}]"),
                format!(
                    "{} is given twice: each friction value is one point of the sweep, and its \
                     modes are tracked from the point before",
                    a.friction[i]
                ),
            ));
        }
        for (i, &mu) in a.friction.iter().enumerate() {
            if !(mu >= 0.0 && mu.is_finite()) {
                return Err(bad(
                    format!("analysis.friction[{i}]"),
                    format!("friction must be >= 0, got {mu}"),
                ));
            }
        }
        if a.increments == 0 {
            return Err(bad(
                "analysis.increments".into(),
                "must be at least 1".into(),
            ));
        }
        for (i, c) in self.contacts.iter().enumerate() {
            if !(c.friction >= 0.0 && c.friction.is_finite()) {
                return Err(bad(
                    format!("contacts[{i}].friction"),
                    format!("friction must be >= 0, got {}", c.friction),
                ));
            }
            if let Some(k) = c.penalty {
                if !(k > 0.0 && k.is_finite()) {
                    return Err(bad(
                        format!("contacts[{i}].penalty"),
                        format!("must be positive, got {k}"),
                    ));
                }
            }
            match (c.friction_law, c.stick_stiffness) {
                (FrictionLawName::SteadySliding, Some(_)) => {
                    return Err(bad(
                        format!("contacts[{i}].stick_stiffness"),
                        "a stick stiffness needs friction_law = \"coulomb\" (this pair slides \
                         steadily)"
                            .into(),
                    ))
                }
                (FrictionLawName::Coulomb, Some(k)) if !(k > 0.0 && k.is_finite()) => {
                    return Err(bad(
                        format!("contacts[{i}].stick_stiffness"),
                        format!("must be positive (Pa/m), got {k}"),
                    ))
                }
                _ => {}
            }
            if c.friction_law == FrictionLawName::Coulomb && c.sliding != SlidingDirection::None {
                return Err(bad(
                    format!("contacts[{i}].sliding"),
                    "a coulomb pair slips where its forces take it: it has no imposed sliding \
                     direction (remove `sliding`, or use friction_law = \"steady-sliding\" for \
                     a disc turning under a pad)"
                        .into(),
                ));
            }
        }
        for (i, s) in self.springs.iter().enumerate() {
            if !(s.stiffness > 0.0 && s.stiffness.is_finite()) {
                return Err(bad(
                    format!("springs[{i}].stiffness"),
                    format!("must be positive, got {}", s.stiffness),
                ));
            }
            // A NaN direction used to pass into K and end the static in DIVERGED_FNORM_NAN.
            if let SpringDirection::Vector(v) = &s.direction {
                let length = v.iter().map(|c| c * c).sum::<f64>().sqrt();
                if !(length > 0.0 && length.is_finite()) {
                    return Err(bad(
                        format!("springs[{i}].direction"),
                        format!("must be a finite non-zero vector, got {v:?}"),
                    ));
                }
            }
        }
        for (i, p) in self.pressures.iter().enumerate() {
            // NaN used to end the static in DIVERGED_FNORM_NAN, 0 in a singular tangent with
            // nothing pressing the pads on: both after the model was built and assembled.
            if !(p.value.is_finite() && p.value != 0.0) {
                return Err(bad(
                    format!("pressures[{i}].value"),
                    format!(
                        "must be a finite, non-zero pressure (Pa), got {} (remove the entry to \
                         load nothing there)",
                        p.value
                    ),
                ));
            }
        }
        for (i, l) in self.links.iter().enumerate() {
            for (key, value) in [("axial", l.axial), ("transverse", l.transverse)] {
                if !(value >= 0.0 && value.is_finite()) {
                    return Err(bad(
                        format!("links[{i}].{key}"),
                        format!("must be finite and >= 0, got {value}"),
                    ));
                }
            }
            if l.axial == 0.0 && l.transverse == 0.0 {
                return Err(bad(
                    format!("links[{i}]"),
                    "axial and transverse are both zero: the link holds nothing".into(),
                ));
            }
        }
        for (i, s) in self.supports.iter().enumerate() {
            if s.components.is_empty() || !s.components.chars().all(|c| "xyzXYZ".contains(c)) {
                return Err(bad(
                    format!("supports[{i}].components"),
                    format!("'{}' is not made of x, y, z", s.components),
                ));
            }
        }
        for (i, m) in self.materials.iter().enumerate() {
            let finite = m.young.is_finite() && m.density.is_finite();
            if !(finite && m.young > 0.0 && m.poisson > -1.0 && m.poisson < 0.5 && m.density > 0.0)
            {
                return Err(bad(
                    format!("materials[{i}]"),
                    "need finite young > 0, -1 < poisson < 0.5, finite density > 0".into(),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reduce::{DiscCoupling, GridSize, PadCoupling, ReducePairs};

    fn write(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("squeal-config-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn empty_files_nan_directions_and_null_pressures_are_refused_by_key() {
        let e = Study::read(&write("empty.toml", "# nothing\n")).unwrap_err();
        assert!(e.to_string().contains("the study is empty"), "{e}");
        let mut study = Study::builtin("tiny");
        study.springs[0].direction = SpringDirection::Vector([f64::NAN, 0.0, 1.0]);
        let e = study.check(Path::new("s.toml")).unwrap_err().to_string();
        assert!(e.contains("springs[0].direction"), "{e}");
        for value in [f64::NAN, 0.0] {
            let mut study = Study::builtin("tiny");
            study.pressures[1].value = value;
            let e = study.check(Path::new("s.toml")).unwrap_err().to_string();
            assert!(e.contains("pressures[1].value"), "{e}");
        }
    }

    #[test]
    fn the_builtin_study_round_trips_through_toml() {
        let s = Study::builtin("tiny");
        let text = toml::to_string(&s).unwrap();
        let back: Study = toml::from_str(&text).unwrap();
        assert_eq!(s, back);
        s.check(Path::new("builtin")).unwrap();
    }

    #[test]
    fn the_floating_caliper_study_has_table_1_and_equal_hydraulic_forces() {
        let s = Study::builtin("tiny-caliper");
        assert_eq!(s, Study::builtin_floating_caliper("tiny-caliper"));
        let text = toml::to_string(&s).unwrap();
        let back: Study = toml::from_str(&text).unwrap();
        assert_eq!(s, back);
        s.check(Path::new("builtin")).unwrap();
        // The spring-held study stays the default of the spring-held presets.
        assert_eq!(Study::builtin("tiny"), Study::builtin_spring_held("tiny"));
        assert!(Study::builtin("tiny").links.is_empty());
        // Table 1, pad side slave.
        let pairs: Vec<(&str, f64, bool, bool)> = s
            .contacts
            .iter()
            .map(|c| (c.name.as_str(), c.friction, c.separation, c.sweep))
            .collect();
        assert_eq!(
            pairs,
            [
                ("disc/pad inboard", 0.5, true, true),
                ("disc/pad outboard", 0.5, true, true),
                ("piston/pad", 0.15, false, false),
                ("caliper/pad", 0.15, false, false),
                ("bracket/pad inboard leading", 0.15, true, false),
                ("bracket/pad inboard trailing", 0.15, true, false),
                ("bracket/pad outboard leading", 0.15, true, false),
                ("bracket/pad outboard trailing", 0.15, true, false),
            ]
        );
        assert!(s
            .contacts
            .iter()
            .all(|c| c.slave.starts_with("pad_") || c.slave.starts_with("backplate_")));
        // The hydraulic force is the same on the piston and the caliper.
        let model = crate::model::Model::from_spec(&s.model_spec()).unwrap();
        let force = |k: usize| {
            let p = &model.pressures[k];
            crate::fem::loads::pressure_resultant(&model.mesh, &p.faces, p.value)[2]
        };
        let want = LINE_PRESSURE * std::f64::consts::PI * 0.02f64.powi(2);
        assert!((force(0) + want).abs() < 1e-12 * want);
        assert!((force(1) - want).abs() < 1e-12 * want);
        // Guide pins and seal: three springs per node of the caliper's pins / the piston.
        let pins = model.mesh.node_sets["caliper_pins"].len();
        let seal = model.mesh.node_sets["piston_outer"].len();
        assert_eq!(model.links.len(), 3 * (pins + seal));
        // A spring-held preset's mesh density with the caliper layout.
        let other = Study::builtin_floating_caliper("tiny");
        assert!(other.mesh.brake.as_ref().unwrap().floating_caliper());
    }

    #[test]
    fn link_errors_name_the_key_and_the_set() {
        let mut s = Study::builtin("tiny-caliper");
        s.links[1].to = "caliper_boar".into();
        let e = crate::model::Model::from_spec(&s.model_spec())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("links[1].to") && e.contains("caliper_boar"),
            "{e}"
        );
        let mut s = Study::builtin("tiny-caliper");
        s.links[0].set = "pins".into();
        let e = crate::model::Model::from_spec(&s.model_spec())
            .unwrap_err()
            .to_string();
        assert!(e.contains("links[0].set") && e.contains("pins"), "{e}");
        let p = write(
            "link.toml",
            "[[links]]\nname = \"pins\"\nset = \"a\"\nto = \"b\"\naxial = -1\ntransverse = 1e8\n",
        );
        let e = Study::read(&p).unwrap_err().to_string();
        assert!(e.contains("links[0].axial"), "{e}");
        let p = write(
            "link0.toml",
            "[[links]]\nname = \"pins\"\nset = \"a\"\nto = \"b\"\naxial = 0\ntransverse = 0\n",
        );
        let e = Study::read(&p).unwrap_err().to_string();
        assert!(e.contains("links[0]") && e.contains("holds nothing"), "{e}");
        let p = write(
            "link_axis.toml",
            "[[links]]\nname = \"pins\"\nset = \"a\"\nto = \"b\"\naxial = 1\ntransverse = 1\n",
        );
        let s = Study::read(&p).unwrap();
        assert_eq!(s.links[0].axis, [0.0, 0.0, 1.0]);
    }

    #[test]
    fn the_first_repeated_friction_value_is_named_even_in_a_long_list() {
        let mut s = Study::builtin("tiny");
        // 0 and -0 are one value; NaN is left to the range check.
        s.analysis.friction = vec![0.5, 0.0, f64::NAN, -0.0, 0.5, f64::NAN];
        let e = s.check(Path::new("s.toml")).unwrap_err().to_string();
        assert!(
            e.contains("analysis.friction[3]") && e.contains("given twice"),
            "{e}"
        );
        // A million values: the pairwise search took n^2/2 comparisons.
        s.analysis.friction = (0..1_000_000).map(|k| k as f64 * 1e-6).collect();
        s.analysis.friction.push(0.25);
        let e = s.check(Path::new("s.toml")).unwrap_err().to_string();
        assert!(e.contains("analysis.friction[1000000]"), "{e}");
    }

    #[test]
    fn errors_name_the_file_and_the_key() {
        let p = write("bad_mu.toml", "[analysis]\nfriction = [0.1, -0.2]\n");
        let e = Study::read(&p).unwrap_err().to_string();
        assert!(
            e.contains("bad_mu.toml") && e.contains("analysis.friction[1]"),
            "{e}"
        );
        let p = write("typo.toml", "[analysis]\nmax_frequency = 5000\n");
        let e = Study::read(&p).unwrap_err().to_string();
        assert!(
            e.contains("typo.toml") && e.contains("max_frequency"),
            "{e}"
        );
        let p = write(
            "contact.toml",
            "[[contacts]]\nname = \"a\"\nslave = \"s\"\nmaster = \"m\"\nfriction = -1\n",
        );
        let e = Study::read(&p).unwrap_err().to_string();
        assert!(e.contains("contacts[0].friction"), "{e}");
        let pair = "[[contacts]]\nname = \"a\"\nslave = \"s\"\nmaster = \"m\"\nfriction = 0.15\n";
        for (name, extra, key) in [
            (
                "stick.toml",
                "friction_law = \"coulomb\"\nstick_stiffness = -1e12\n",
                "contacts[0].stick_stiffness",
            ),
            (
                "stick0.toml",
                "friction_law = \"coulomb\"\nstick_stiffness = 0.0\n",
                "contacts[0].stick_stiffness",
            ),
            (
                "steady.toml",
                "stick_stiffness = 1e12\n",
                "contacts[0].stick_stiffness",
            ),
            (
                "moving.toml",
                "friction_law = \"coulomb\"\nsliding = { Fixed = [1.0, 0.0, 0.0] }\n",
                "contacts[0].sliding",
            ),
            ("law.toml", "friction_law = \"stick\"\n", "friction_law"),
        ] {
            let p = write(name, &format!("{pair}{extra}"));
            let e = Study::read(&p).unwrap_err().to_string();
            assert!(e.contains(name) && e.contains(key), "{e}");
        }
        let p = write(
            "coulomb.toml",
            &format!("{pair}friction_law = \"coulomb\"\nstick_stiffness = 1e12\n"),
        );
        let s = Study::read(&p).unwrap();
        assert_eq!(s.contacts[0].friction_law, FrictionLawName::Coulomb);
        assert_eq!(s.contacts[0].stick_stiffness, Some(1e12));
    }

    /// Numbers a sweep would run on for minutes before failing (or never), refused when
    /// the file is read, each naming its key.
    #[test]
    fn analysis_numbers_are_checked_up_front() {
        for (name, analysis, key) in [
            (
                "band.toml",
                "max_frequency_hz = 1e300",
                "analysis.max_frequency_hz",
            ),
            (
                "nan.toml",
                "max_frequency_hz = nan",
                "analysis.max_frequency_hz",
            ),
            (
                "neg.toml",
                "unstable_threshold = -1.0",
                "analysis.unstable_threshold",
            ),
            (
                "one.toml",
                "unstable_threshold = 1.0",
                "analysis.unstable_threshold",
            ),
            (
                "tnan.toml",
                "unstable_threshold = nan",
                "analysis.unstable_threshold",
            ),
            (
                "twice.toml",
                "friction = [0.3, 0.3]",
                "analysis.friction[1]",
            ),
            ("window.toml", "window = 0", "analysis.window"),
            (
                "damp.toml",
                "damping = { alpha = nan, beta = 0.0 }",
                "analysis.damping.alpha",
            ),
        ] {
            let p = write(name, &format!("[analysis]\n{analysis}\n"));
            let e = Study::read(&p).unwrap_err().to_string();
            assert!(e.contains(name) && e.contains(key), "{name}: {e}");
        }
        // The edges of what is allowed.
        let p = write(
            "edges.toml",
            "[analysis]\nmax_frequency_hz = 1e6\nunstable_threshold = 0.0\nfriction = [0.3, 0.1]\n",
        );
        Study::read(&p).unwrap();
    }

    #[test]
    fn mesh_file_is_relative_to_the_study() {
        let p = write("rel.toml", "[mesh]\nfile = \"brake.msh\"\n");
        let s = Study::read(&p).unwrap();
        assert_eq!(s.mesh.file.unwrap(), p.parent().unwrap().join("brake.msh"));
    }

    #[test]
    fn an_empty_output_and_a_superelement_cutoff_below_the_band_are_refused() {
        let study = |cutoff: f64| {
            format!(
                "[analysis]\nmax_frequency_hz = 3000.0\n[reduction]\ncontact_nodes_per_pad = 6\n\
                 superelements = \"single\"\ncutoff_frequency_hz = {cutoff}\n"
            )
        };
        let e = Study::read(&write("empty.toml", "output = \"\"\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("output: is empty"), "{e}");
        let p = write("cutoff.toml", &study(500.0));
        let e = Study::read(&p).unwrap_err().to_string();
        assert!(
            e.contains("reduction.cutoff_frequency_hz")
                && e.contains("500 Hz is below the band's top"),
            "{e}"
        );
        // At the band's top: past this check (refused for want of a swept pair).
        let e = Study::read(&write("at-the-top.toml", &study(3000.0)))
            .unwrap_err()
            .to_string();
        assert!(!e.contains("cutoff") && e.contains("sweep = true"), "{e}");
    }

    #[test]
    fn patch_laws_refuse_a_cubic_law_for_their_super_elements() {
        let e = Study::read(&write(
            "tilt-se.toml",
            "[reduction]\ncontact_nodes_per_pad = 6\ntilt = true\nsuperelements = \
             \"single\"\nk_cubic = 1e17\n",
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("reduction.tilt") && e.contains("k_cubic"), "{e}");
        // Super-elements of patch laws read.
        let s = Study::read(&write(
            "patch-se-alone.toml",
            "[reduction]\ncontact_nodes_per_pad = 6\ntilt = true\nsuperelements = \"single\"\n",
        ));
        assert!(
            s.as_ref()
                .err()
                .is_none_or(|e| !e.to_string().contains("tilt")),
            "{:?}",
            s.err()
        );
        // Alone it reads, and a study without it writes no key.
        let s = Study::read(&write(
            "patch-alone.toml",
            "[reduction]\ncontact_nodes_per_pad = 6\ntilt = true\n",
        ));
        assert!(
            s.as_ref()
                .err()
                .is_none_or(|e| !e.to_string().contains("tilt")),
            "{:?}",
            s.err()
        );
        let text = toml::to_string(&Study::builtin("tiny")).unwrap();
        assert!(!text.contains("tilt"), "{text}");
    }

    /// Without `tilt` the interface decides (None), unless k_linear or k_cubic asks for the
    /// paper's cubic law, which point contacts carry.
    #[test]
    fn tilt_is_left_to_the_interface_unless_a_cubic_law_is_asked_for() {
        let settings = |text: &str| {
            toml::from_str::<ReductionSpec>(&format!("contact_nodes_per_pad = 6\n{text}"))
                .unwrap()
                .settings()
                .unwrap()
                .tilt
        };
        assert_eq!(settings(""), None);
        assert_eq!(settings("k_cubic = 0.0\n"), None);
        assert_eq!(settings("k_cubic = 1e20\n"), Some(false));
        assert_eq!(settings("k_linear = 1e9\n"), Some(false));
        assert_eq!(settings("tilt = true\n"), Some(true));
        assert_eq!(settings("tilt = false\n"), Some(false));
    }

    #[test]
    fn the_disc_coupling_and_area_weighting_keys_read_and_errors_name_them() {
        let r: ReductionSpec = toml::from_str("contact_nodes_per_pad = 6\n").unwrap();
        assert_eq!(r.settings().unwrap().disc_coupling, DiscCoupling::Auto);
        assert!(!r.settings().unwrap().area_weighting);
        let r: ReductionSpec = toml::from_str(
            "contact_nodes_per_pad = 6\ndisc_coupling = \"distributing\"\narea_weighting = true\n",
        )
        .unwrap();
        assert_eq!(
            r.settings().unwrap().disc_coupling,
            DiscCoupling::Distributing
        );
        assert!(r.settings().unwrap().area_weighting);
        let r: ReductionSpec =
            toml::from_str("contact_nodes_per_pad = 6\ndisc_coupling = \"share\"\n").unwrap();
        assert_eq!(r.settings().unwrap().disc_coupling, DiscCoupling::Share);
        let p = write(
            "disc.toml",
            "[reduction]\ncontact_nodes_per_pad = 6\ndisc_coupling = \"glued\"\n",
        );
        let e = Study::read(&p).unwrap_err().to_string();
        assert!(
            e.contains("disc.toml") && e.contains("disc_coupling") && e.contains("distributing"),
            "{e}"
        );
    }

    /// `warp_springs` reads, is off unless asked for (and then not written, so studies
    /// without it keep their keys), and a study that asks for it without patch laws over
    /// share couplings is refused naming the key.
    #[test]
    fn the_warp_springs_key_reads_and_needs_patch_laws_over_shares() {
        let r: ReductionSpec = toml::from_str("contact_nodes_per_pad = 6\n").unwrap();
        assert!(!r.settings().unwrap().warp_springs);
        assert!(!toml::to_string(&r).unwrap().contains("warp_springs"));
        let r: ReductionSpec =
            toml::from_str("contact_nodes_per_pad = 6\nwarp_springs = true\n").unwrap();
        assert!(r.settings().unwrap().warp_springs);
        for other in [
            "tilt = false",
            "pad_coupling = \"distributing\"",
            "k_cubic = 1e15",
        ] {
            let p = write(
                "warp.toml",
                &format!("[reduction]\ncontact_nodes_per_pad = 6\nwarp_springs = true\n{other}\n"),
            );
            let e = Study::read(&p).unwrap_err().to_string();
            assert!(
                e.contains("warp.toml") && e.contains("reduction.warp_springs"),
                "{other}: {e}"
            );
        }
    }

    /// `patch_quadrature` reads ("nodes" by default, "area" the rule before 2026-12-07),
    /// names itself when wrong, and is written at its default too: its default changed, and
    /// a study that does not name it must not find the old rule's stages under its keys.
    #[test]
    fn the_patch_quadrature_key_reads_and_is_always_written() {
        use crate::reduce::PatchQuadrature;
        let r: ReductionSpec = toml::from_str("contact_nodes_per_pad = 6\n").unwrap();
        assert_eq!(
            r.settings().unwrap().patch_quadrature,
            PatchQuadrature::Nodes
        );
        assert!(toml::to_string(&r)
            .unwrap()
            .contains("patch_quadrature = \"nodes\""));
        let r: ReductionSpec =
            toml::from_str("contact_nodes_per_pad = 6\npatch_quadrature = \"area\"\n").unwrap();
        assert_eq!(
            r.settings().unwrap().patch_quadrature,
            PatchQuadrature::Area
        );
        let p = write(
            "quadrature.toml",
            "[reduction]\ncontact_nodes_per_pad = 6\npatch_quadrature = \"gauss\"\n",
        );
        let e = Study::read(&p).unwrap_err().to_string();
        assert!(
            e.contains("quadrature.toml") && e.contains("patch_quadrature") && e.contains("gauss"),
            "{e}"
        );
    }

    /// `pad_coupling` reads, names itself when wrong, and is written at its default too:
    /// the default was "distributing" before it was "auto", and a study that does not name
    /// it must not find the stages of the old default under its keys.
    #[test]
    fn the_pad_coupling_key_reads_and_is_always_written() {
        let r: ReductionSpec = toml::from_str("contact_nodes_per_pad = 6\n").unwrap();
        assert_eq!(r.settings().unwrap().pad_coupling, PadCoupling::Auto);
        assert!(toml::to_string(&r)
            .unwrap()
            .contains("pad_coupling = \"auto\""));
        let r: ReductionSpec =
            toml::from_str("contact_nodes_per_pad = 6\npad_coupling = \"share\"\n").unwrap();
        assert_eq!(r.settings().unwrap().pad_coupling, PadCoupling::Share);
        assert!(toml::to_string(&r)
            .unwrap()
            .contains("pad_coupling = \"share\""));
        let p = write(
            "pad.toml",
            "[reduction]\ncontact_nodes_per_pad = 6\npad_coupling = \"glued\"\n",
        );
        let e = Study::read(&p).unwrap_err().to_string();
        assert!(
            e.contains("pad.toml") && e.contains("pad_coupling") && e.contains("share"),
            "{e}"
        );
    }

    /// `cea_solver`: absent (the block solver), or either solver by name, written only when
    /// not the default (so a study's hash does not change for studies that do not set it);
    /// another name is refused, naming what it may be.
    #[test]
    fn the_cea_solver_reads_by_name_and_is_written_only_when_chosen() {
        use crate::analysis::cea::WindowSolver;
        for (text, expected) in [
            ("", WindowSolver::Block),
            ("cea_solver = \"block\"\n", WindowSolver::Block),
            ("cea_solver = \"krylov-schur\"\n", WindowSolver::KrylovSchur),
        ] {
            let a: AnalysisSpec = toml::from_str(text).unwrap();
            assert_eq!(a.cea_solver, expected, "{text}");
            let written = toml::to_string(&a).unwrap();
            assert_eq!(
                written.contains("cea_solver"),
                expected != WindowSolver::Block,
                "{written}"
            );
        }
        let e = toml::from_str::<AnalysisSpec>("cea_solver = \"arnoldi\"\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("krylov-schur"), "{e}");
    }

    /// `residual_vectors`: absent (the default: made wherever the interior holds no contact),
    /// asked for or left out; a study written before it was a default still reads.
    #[test]
    fn residual_vectors_read_as_absent_asked_or_left_out() {
        for (text, expected) in [
            ("", None),
            ("residual_vectors = true\n", Some(true)),
            ("residual_vectors = false\n", Some(false)),
        ] {
            let r: ReductionSpec =
                toml::from_str(&format!("contact_nodes_per_pad = 6\n{text}")).unwrap();
            assert_eq!(r.residual_vectors, expected, "{text}");
            let written = toml::to_string(&r).unwrap();
            assert_eq!(written.contains("residual_vectors"), expected.is_some());
            let again: ReductionSpec = toml::from_str(&written).unwrap();
            assert_eq!(again, r);
        }
    }

    /// Kept pairs to reduce and their grids: read, written only when not the default,
    /// handed to the interface, and a wrong grid refused naming the pair's key.
    #[test]
    fn reduced_kept_pairs_and_their_grids_read_and_are_checked() {
        let r: ReductionSpec = toml::from_str("contact_nodes_per_pad = 6\n").unwrap();
        assert!(
            r.settings().unwrap().reduce_pairs.is_swept()
                && r.settings().unwrap().pair_grids.is_empty()
        );
        let text = toml::to_string(&r).unwrap();
        assert!(
            !text.contains("reduce_pairs") && !text.contains("pairs"),
            "{text}"
        );
        let r: ReductionSpec = toml::from_str(
            "contact_nodes_per_pad = 6\nreduce_pairs = \"all\"\n\
             [pairs.\"piston/pad\"]\ncontact_nodes = 12\n",
        )
        .unwrap();
        let s = r.settings().unwrap();
        assert_eq!(s.reduce_pairs, ReducePairs::All);
        assert_eq!(s.pair_grids["piston/pad"], GridSize::Count(12));
        assert!(s.pair_tilts.is_empty());
        let again: ReductionSpec = toml::from_str(&toml::to_string(&r).unwrap()).unwrap();
        assert_eq!(again, r);
        // A pair's patch laws alone: its default grid, its patch laws.
        let r: ReductionSpec = toml::from_str(
            "contact_nodes_per_pad = 6\nreduce_pairs = \"all\"\n\
             [pairs.\"piston/pad\"]\ntilt = true\n",
        )
        .unwrap();
        let s = r.settings().unwrap();
        assert!(s.pair_grids.is_empty());
        assert_eq!(s.pair_tilts, [("piston/pad".to_string(), true)].into());
        let written = toml::to_string(&r).unwrap();
        assert!(written.contains("tilt = true") && !written.contains("contact_nodes = "));
        let again: ReductionSpec = toml::from_str(&written).unwrap();
        assert_eq!(again, r);
        let p = write(
            "pairs.toml",
            "[reduction]\ncontact_nodes_per_pad = 6\nreduce_pairs = \"all\"\n\
             [reduction.pairs.\"piston/pad\"]\ncontact_nodes = 12\nspacing = 0.01\n",
        );
        let e = Study::read(&p).unwrap_err().to_string();
        assert!(
            e.contains("pairs.toml")
                && e.contains("reduction.pairs.\"piston/pad\"")
                && e.contains("not both"),
            "{e}"
        );
        // A caller that skips the study's check still gets the grid refused, not dropped.
        let unchecked: ReductionSpec = toml::from_str(
            "contact_nodes_per_pad = 6\nreduce_pairs = \"all\"\n\
             [pairs.\"piston/pad\"]\ncontact_nodes = 12\nspacing = 0.01\n",
        )
        .unwrap();
        let e = unchecked.settings().unwrap_err().to_string();
        assert!(
            e.contains("reduction.pairs.\"piston/pad\"") && e.contains("not both"),
            "{e}"
        );
    }
}
