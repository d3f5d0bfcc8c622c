//! What is in force in a step: model data, then every earlier step that is not a
//! linear-perturbation step, then the step itself, with the replacement rules of the module
//! documentation of [`super`].

use std::collections::BTreeMap;

use super::{Boundary, ConcentratedLoad, Deck, PressureLoad, PressureTarget, Replaced};
use crate::mesh::{Face, Mesh};

/// The supports and loads in force, resolved to nodes and faces.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Loading {
    /// Prescribed displacement per (node index, component 0..3), the component in the
    /// node's `*TRANSFORM` system when it has one.
    pub displacements: BTreeMap<(usize, usize), f64>,
    /// The DOFs of `displacements` held by `*BOUNDARY, FIXED` (at the displacement the step
    /// starts from; their value above is 0), with the step (0-based) that fixed them.
    pub fixed: BTreeMap<(usize, usize), usize>,
    /// Concentrated force per (node index, component 0..3).
    pub forces: BTreeMap<(usize, usize), f64>,
    /// Net pressure per face (Abaqus sign), sorted by (element, side).
    pub pressures: Vec<(Face, f64)>,
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
            None,
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
            None,
        );
        for (k, earlier) in self.steps[..step].iter().enumerate() {
            if !earlier.perturbation {
                state.apply(
                    &earlier.replaced,
                    &earlier.boundaries,
                    &earlier.concentrated_loads,
                    &earlier.pressures,
                    Some((k, false)),
                );
            }
        }
        state.apply(
            &target.replaced,
            &target.boundaries,
            &target.concentrated_loads,
            &target.pressures,
            Some((step, target.perturbation)),
        );
        Some(state.finish(&self.mesh))
    }
}

#[derive(Default)]
struct LoadState {
    displacements: BTreeMap<(usize, usize), f64>,
    fixed: BTreeMap<(usize, usize), usize>,
    forces: BTreeMap<(usize, usize), f64>,
    /// `*DSLOAD`s by surface name: a new one on the same surface replaces the old.
    surface_pressures: BTreeMap<String, (Vec<Face>, f64)>,
    /// `*DLOAD`s by (element, side).
    element_pressures: BTreeMap<(usize, u8), f64>,
}

impl LoadState {
    /// Applies one step's definitions (`step`: its index and whether it is a perturbation
    /// step; `None` for model data). A perturbation step's `*BOUNDARY` holds its DOFs at
    /// zero perturbation: it adds the DOFs it names (at 0) and leaves the value of a DOF
    /// the base state prescribes.
    fn apply(
        &mut self,
        replaced: &Replaced,
        boundaries: &[Boundary],
        loads: &[ConcentratedLoad],
        pressures: &[PressureLoad],
        step: Option<(usize, bool)>,
    ) {
        if replaced.boundaries {
            self.displacements.clear();
            self.fixed.clear();
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
        let perturbation = step.is_some_and(|(_, p)| p);
        for b in boundaries {
            for &n in &b.nodes {
                for dof in b.first_dof..=b.last_dof {
                    let key = (n, usize::from(dof) - 1);
                    if perturbation {
                        self.displacements.entry(key).or_insert(0.0);
                        continue;
                    }
                    self.displacements.insert(key, b.value);
                    match step {
                        Some((k, _)) if b.fixed => {
                            self.fixed.insert(key, k);
                        }
                        _ => {
                            self.fixed.remove(&key);
                        }
                    }
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
            fixed: self.fixed,
            forces: self.forces,
            pressures: net
                .into_iter()
                .map(|((e, side), p)| (mesh.face(e, side), p))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::super::*;

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
