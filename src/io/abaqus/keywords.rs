//! The keyword lines: what each keyword starts (the block its data lines belong to), which are
//! refused because skipping them would silently change geometry or load directions, which are
//! skipped with a warning, and the step structure (`*STEP` ... `*END STEP`).

use super::drafts::*;
use super::lexer::{Keyword, Name};
use super::reader::Reader;
use super::{ComplexFrequencyRequest, FrequencyRequest, Procedure, Replaced, StaticRequest};
use crate::mesh::MeshError;

/// Element types read as C3D10: same nodes and node order; squeal uses its own formulation.
const C3D10_VARIANTS: [&str; 6] = ["C3D10M", "C3D10I", "C3D10H", "C3D10HS", "C3D10MH", "C3D10T"];

/// Procedures that are recognised (so that a step using one is kept) but not read.
const OTHER_PROCEDURES: [&str; 17] = [
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
pub(super) const PERTURBATION_PROCEDURES: [&str; 8] = [
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
pub(super) fn refused(name: &str) -> Option<&'static str> {
    Some(match name {
        "PART" | "ENDPART" | "ASSEMBLY" | "ENDASSEMBLY" | "INSTANCE" | "ENDINSTANCE" => {
            "Abaqus part/assembly input is not supported: write the deck without parts and \
             assemblies (in Abaqus/CAE: Model > Edit Attributes > Do not use parts and \
             assemblies in input files)"
        }
        "SYSTEM" => "*SYSTEM would move the nodes that follow; give global coordinates instead",
        "CONTACT" | "CONTACTINCLUSIONS" | "CONTACTPROPERTYASSIGNMENT" => {
            "Abaqus general contact is not supported (skipping it would lose every contact): \
             give the interfaces as *CONTACT PAIR, TYPE=NODE TO SURFACE"
        }
        "CLEARANCE" | "CONTACTINTERFERENCE" => {
            "initial clearances and interferences of contact pairs are not supported (they \
             would change the gaps): move the nodes, or use ADJUST= on *CONTACT PAIR"
        }
        "NGEN" | "NFILL" | "NCOPY" | "NMAP" | "ELGEN" | "ELCOPY" => {
            "node and element generation is not supported; list the nodes and elements"
        }
        "CHANGEFRICTION" | "CHANGESURFACEBEHAVIOR" => {
            "changing a surface interaction in a step is not supported: give the interaction \
             the friction and law it has in the steps squeal runs (squeal sweep sets the swept \
             interaction's mu itself)"
        }
        "MODELCHANGE" => "removing or adding elements or contact pairs in a step is not supported",
        _ => return None,
    })
}

/// Keywords read past with their data lines because they cannot change the model squeal
/// solves: output, print and restart requests, preprocessor printing, and solver controls
/// (which change how a solver converges, not what it converges to); definitions that act
/// only through something squeal refuses or does not have (`*AMPLITUDE` through an
/// `AMPLITUDE=` on a load, refused there; `*ORIENTATION` on an isotropic material;
/// `*EXPANSION` without a temperature field; `*PHYSICAL CONSTANTS`). They are listed in one
/// warning. Every other keyword squeal does not read stops the run at its line: skipping
/// one that changes the physics (a tie, damping, an initial stress) would report a wrong
/// result as a success.
pub(super) fn ignored(name: &str) -> bool {
    matches!(
        name,
        "OUTPUT"
            | "NODEOUTPUT"
            | "ELEMENTOUTPUT"
            | "CONTACTOUTPUT"
            | "SURFACEOUTPUT"
            | "INTEGRATEDOUTPUT"
            | "ENERGYOUTPUT"
            | "MODALOUTPUT"
            | "NODEFILE"
            | "ELFILE"
            | "ELEMENTFILE"
            | "CONTACTFILE"
            | "SECTIONFILE"
            | "MODALFILE"
            | "NODEPRINT"
            | "ELPRINT"
            | "ELEMENTPRINT"
            | "CONTACTPRINT"
            | "ENERGYPRINT"
            | "SECTIONPRINT"
            | "FACEPRINT"
            | "MODALPRINT"
            | "PRINT"
            | "PREPRINT"
            | "RESTART"
            | "MONITOR"
            | "FILEFORMAT"
            | "OUTPUTDIRECTORY"
            | "CONTROLS"
            | "SOLVERCONTROLS"
            | "DIAGNOSTICS"
            | "AMPLITUDE"
            | "ORIENTATION"
            | "EXPANSION"
            | "PHYSICALCONSTANTS"
    )
}

impl Reader {
    pub(super) fn keyword(&mut self, mut kw: Keyword) -> Result<(), MeshError> {
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
        if !matches!(kw.name.as_str(), "SURFACEBEHAVIOR" | "FRICTION") && self.is_known(&kw.name) {
            self.interaction = None;
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
            "SPRING" => self.spring_keyword(&mut kw)?,
            "MASS" => self.mass_keyword(&mut kw)?,
            "SURFACEINTERACTION" => self.surface_interaction_keyword(&mut kw)?,
            "SURFACEBEHAVIOR" => self.surface_behavior_keyword(&mut kw)?,
            "FRICTION" => self.friction_keyword(&mut kw)?,
            "CONTACTPAIR" => self.contact_pair_keyword(&mut kw)?,
            "EQUATION" | "TRANSFORM" | "COUPLING" | "DISTRIBUTING" | "KINEMATIC" => {
                self.constraint_keyword(&mut kw)?
            }
            "TIE" => self.tie_keyword(&mut kw)?,
            "MOTION" => self.motion_keyword(&mut kw)?,
            "STEP" => self.step_keyword(&mut kw)?,
            "ENDSTEP" => {
                let Some(step) = self.step.take() else {
                    return Err(self.err(kw.loc, "*END STEP without a *STEP before it"));
                };
                if step.procedure.is_none() {
                    return Err(self.err(
                        kw.loc,
                        format!(
                            "the step that begins at {} has no procedure (expected *STATIC, \
                             *FREQUENCY or *COMPLEX FREQUENCY)",
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
            "COMPLEXFREQUENCY" => {
                self.complex_frequency_keyword(&mut kw)?;
                self.set_procedure(
                    &kw,
                    Procedure::ComplexFrequency(ComplexFrequencyRequest::default()),
                )?;
                Block::ComplexFrequency { lines: 0 }
            }
            "BOUNDARY" => {
                self.no_amplitude(&mut kw)?;
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
                let fixed = kw.flag("FIXED");
                if fixed && self.step.is_none() {
                    return Err(self.err(
                        kw.loc,
                        "*BOUNDARY, FIXED holds the displacement a step starts from: it \
                         belongs in a step",
                    ));
                }
                Block::Boundary { fixed }
            }
            "CLOAD" => {
                self.no_amplitude(&mut kw)?;
                if self.op_new(&mut kw)? {
                    self.replaced(|r| r.concentrated_loads = true);
                }
                Block::ConcentratedLoad
            }
            "DSLOAD" => {
                self.no_amplitude(&mut kw)?;
                if self.op_new(&mut kw)? {
                    self.replaced(|r| r.surface_pressures = true);
                }
                Block::SurfacePressure
            }
            "DLOAD" => {
                self.no_amplitude(&mut kw)?;
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
                if !ignored(name) {
                    return Err(self.err(
                        kw.loc,
                        format!(
                            "{}: squeal does not read this keyword, and skipping it could \
                             change the model it solves (only output and print requests, \
                             restart requests and solver controls are read past)",
                            kw.display
                        ),
                    ));
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
                | "SPRING"
                | "MASS"
                | "SURFACEINTERACTION"
                | "SURFACEBEHAVIOR"
                | "FRICTION"
                | "CONTACTPAIR"
                | "EQUATION"
                | "TRANSFORM"
                | "COUPLING"
                | "DISTRIBUTING"
                | "KINEMATIC"
                | "TIE"
                | "MOTION"
                | "COMPLEXFREQUENCY"
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

    /// `AMPLITUDE=` on a load or a prescribed displacement: its value at the step's end
    /// scales the magnitude, and squeal applies the magnitude as written (skipping the
    /// parameter would change the load).
    fn no_amplitude(&self, kw: &mut Keyword) -> Result<(), MeshError> {
        match self.param(kw, "AMPLITUDE")? {
            Some(a) => Err(self.err(
                kw.loc,
                format!(
                    "{}, AMPLITUDE={a}: amplitudes are not supported (squeal applies the \
                     magnitude written on the data lines at the end of the step); scale the \
                     magnitudes by the amplitude's value there and remove AMPLITUDE=",
                    kw.display
                ),
            )),
            None => Ok(()),
        }
    }

    fn note_unused_parameters(&mut self, kw: &Keyword) {
        for p in kw.params.iter().filter(|p| !p.used) {
            self.ignored_parameters
                .add(&format!("{} on {}", p.key, kw.display), kw.loc);
        }
    }

    pub(super) fn model_only(&self, kw: &Keyword) -> Result<(), MeshError> {
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
    pub(super) fn replaced(&mut self, mark: impl FnOnce(&mut Replaced)) {
        if let Some(step) = &mut self.step {
            mark(&mut step.replaced);
        }
    }

    pub(super) fn loads(&mut self) -> &mut LoadDrafts {
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
                .or_insert_with(|| SetDraft::new(&name.written));
        }
        Ok(Block::Node { nset })
    }

    fn element_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        let written = self.required(kw, "TYPE")?;
        let kind = written.to_uppercase();
        let discrete = DiscreteKind::from_type(&kind);
        if kind != "C3D10" && discrete.is_none() {
            if C3D10_VARIANTS.contains(&kind.as_str()) {
                self.variant_types.add(&kind, kw.loc);
            } else {
                return Err(self.err(
                    kw.loc,
                    format!(
                        "element type {written} is not supported (squeal reads C3D10 solids and \
                         the discrete SPRING1, SPRING2, SPRINGA and MASS)"
                    ),
                ));
            }
        }
        let elset = self.param(kw, "ELSET")?.map(|n| Name::new(&n));
        if let Some(name) = &elset {
            self.element_sets
                .entry(name.canon.clone())
                .or_insert_with(|| SetDraft::new(&name.written));
        }
        Ok(Block::Element { elset, discrete })
    }

    fn node_set_keyword(&mut self, kw: &mut Keyword) -> Result<Block, MeshError> {
        self.model_only(kw)?;
        if self.param(kw, "INSTANCE")?.is_some() {
            return Err(self.err(kw.loc, refused("INSTANCE").unwrap_or_default()));
        }
        let name = Name::new(&self.required(kw, "NSET")?);
        let generate = kw.flag("GENERATE");
        if kw.flag("UNSORTED") {
            // Only an *EQUATION's node-by-node pairing depends on the order.
            self.constraints.unsorted.insert(name.canon.clone(), kw.loc);
        }
        kw.flag("INTERNAL");
        let mut members = SetDraft::new(&name.written);
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
            // The discrete elements defined by now hold nodes too.
            let discrete = set
                .members()
                .iter()
                .filter_map(|m| self.discrete_index.get(&m.label).copied())
                .chain(
                    set.ranges()
                        .iter()
                        .flat_map(|r| r.existing(&self.discrete_index)),
                );
            for d in discrete {
                for &label in &self.discrete[d].nodes {
                    members.add(Member {
                        label,
                        loc: self.discrete[d].loc,
                    });
                }
            }
            // The elements defined by now: listed, or in a GENERATE range.
            let listed = set
                .members()
                .iter()
                .filter_map(|m| self.element_index.get(&m.label).copied());
            let generated = set
                .ranges()
                .iter()
                .flat_map(|r| r.existing(&self.element_index));
            for e in listed.chain(generated) {
                for &label in &self.elements[e] {
                    members.add(Member {
                        label,
                        loc: self.element_locs[e],
                    });
                }
            }
        }
        self.node_sets
            .entry(name.canon.clone())
            .or_insert_with(|| SetDraft::new(&name.written))
            .add_all(&members);
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
            .or_insert_with(|| SetDraft::new(&name.written));
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
                self.node_sets
                    .insert(name.canon.clone(), SetDraft::new(&name.written));
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
        if self.first_material.is_none() {
            self.first_material = Some(name.canon.clone());
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
    pub(super) fn finish_element(&mut self, next: Option<&Keyword>) -> Result<(), MeshError> {
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
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use crate::mesh::{Material, Part};

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
    fn output_requests_are_read_past_and_listed_in_one_warning() {
        let text = format!(
            "{}*STEP\n*STATIC\n*OUTPUT, FIELD\n*NODE OUTPUT\nU\n*OUTPUT, HISTORY\n\
             *NODE FILE\nU\n*CONTROLS, PARAMETERS=TIME INCREMENTATION\n4, 8\n*END STEP\n",
            one_tet()
        );
        let deck = read_text("outputs", &text).unwrap();
        assert_eq!(deck.warnings.len(), 1, "{:?}", deck.warnings);
        let w = &deck.warnings[0];
        assert!(w.contains("*OUTPUT (2x, first at "), "{w}");
        assert!(w.contains("*NODE OUTPUT (1x"), "{w}");
        assert!(w.contains("*NODE FILE (1x"), "{w}");
        assert!(w.contains("*CONTROLS (1x"), "{w}");
        assert!(w.contains("deck.inp:"), "{w}");
    }

    /// A keyword squeal does not read may change the physics (a tie, damping, an initial
    /// stress): it stops the run at its line, named, whatever it is (issue 34).
    #[test]
    fn keywords_that_could_change_the_model_stop_the_run_at_their_line() {
        for (keyword, said) in [
            (
                "*DAMPING, ALPHA=2.0\n",
                "*DAMPING: squeal does not read this keyword",
            ),
            (
                "*INITIAL CONDITIONS, TYPE=STRESS\nEALL, 1e6, 0, 0, 0, 0, 0\n",
                "*INITIAL CONDITIONS: squeal does not read",
            ),
            (
                "*SHELL SECTION, ELSET=EALL, MATERIAL=STEEL\n0.002\n",
                "*SHELL SECTION",
            ),
        ] {
            let text = format!("{}{keyword}", one_tet());
            let line = text.lines().count() - keyword.lines().count() + 1;
            let e = read_text("refused", &text).unwrap_err().to_string();
            assert!(e.contains(said), "{keyword}: {e}");
            assert!(e.contains(&format!("deck.inp:{line}")), "{keyword}: {e}");
        }
    }

    #[test]
    fn an_amplitude_on_a_load_is_refused_where_it_is_written() {
        let text = format!(
            "{}*AMPLITUDE, NAME=RAMP\n0, 0, 1, 0.5\n*STEP\n*STATIC\n*CLOAD, AMPLITUDE=RAMP\n\
             11, 3, -10.0\n*END STEP\n",
            one_tet()
        );
        let e = read_text("amplitude", &text).unwrap_err().to_string();
        assert!(e.contains("*CLOAD, AMPLITUDE=RAMP"), "{e}");
        assert!(e.contains("amplitudes are not supported"), "{e}");
        // The definition alone is harmless: read past, said.
        let text = format!(
            "{}*AMPLITUDE, NAME=RAMP\n0, 0, 1, 0.5\n*STEP\n*STATIC\n*CLOAD\n11, 3, -10.0\n\
             *END STEP\n",
            one_tet()
        );
        let deck = read_text("amplitude", &text).unwrap();
        assert!(deck.warnings.iter().any(|w| w.contains("*AMPLITUDE (1x")));
    }

    #[test]
    fn general_contact_and_clearances_are_refused_by_name() {
        for (keyword, said) in [
            (
                "*CONTACT
*CONTACT INCLUSIONS, ALL EXTERIOR
",
                "general contact",
            ),
            (
                "*CONTACT INCLUSIONS, ALL EXTERIOR
",
                "general contact",
            ),
            (
                "*CLEARANCE, MASTER=A, SLAVE=B, VALUE=1e-5
",
                "clearances",
            ),
        ] {
            let text = format!("{}{keyword}", one_tet());
            let (_, line, message) = parse_error(read_text("err-general-contact", &text));
            assert_eq!(line, one_tet().lines().count() + 1, "{message}");
            assert!(message.contains(said), "{message}");
        }
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
    fn other_element_types_are_refused_by_name() {
        for kind in ["C3D4", "C3D8", "C3D20", "S3"] {
            let (_, line, message) = parse_error(read_text(
                "err-type",
                &format!("*NODE\n*ELEMENT, TYPE={kind}\n"),
            ));
            assert_eq!(line, 2);
            assert_eq!(
                message,
                format!(
                    "element type {kind} is not supported (squeal reads C3D10 solids and the \
                     discrete SPRING1, SPRING2, SPRINGA and MASS)"
                )
            );
        }
    }
}
