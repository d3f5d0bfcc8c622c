//! A deck's discrete elements in the assembled operators, on 1 and 2 ranks (see
//! `common/harness.rs`): the point masses are in M exactly once, whichever rank owns their
//! node. The frequencies against CalculiX are in `tests/program/modes_cli.rs` (through the CLI).

use crate::common;

use common::harness::Check;
use squeal::fem::element::{self, MassRule};
use squeal::model::{self, source};
use squeal::petsc::Runtime;
use std::path::Path;

pub const CHECKS: &[Check] = &[Check {
    name: "unsupported_deck_translational_mass_is_solid_plus_point_masses",
    run: translational_mass,
    ranks: &[1, 2],
    agreement: 1e-12,
}];

/// The point masses of tests/data/discrete_c3d10.inp: 20 g at the free end and 5 g on the
/// oscillator node (written here, not read back, so that a reader that lost one fails).
const POINT_MASSES: f64 = 0.02 + 0.005;

/// u^T M u for a unit translation along each axis of the deck's model without its supports
/// is its whole mass: rho V of the elements (V summed from the element volumes) plus the
/// point masses, to round-off (both mass rules integrate rho det J exactly for the total).
fn translational_mass(rt: &Runtime) -> Result<Vec<f64>, String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/discrete_c3d10.inp");
    let mut model = source::read(&path).map_err(|e| e.to_string())?;
    model.supports.clear();
    let mesh = &model.mesh;
    let volume: f64 = mesh
        .elements
        .iter()
        .map(|c| element::volume(&c.map(|n| mesh.nodes[n])))
        .sum::<Result<f64, _>>()
        .map_err(|e| e.to_string())?;
    let solid = mesh.materials["STEEL"].density * volume;
    let exact = solid + POINT_MASSES;
    let e = |err: squeal::petsc::PetscError| err.to_string();
    let mut out = Vec::new();
    for rule in [MassRule::Exact, MassRule::Gauss4] {
        let ops = model::assemble(rt.world(), &model, rule).map_err(|e| e.to_string())?;
        for axis in 0..3 {
            let (mut u, mut mu) = ops.mass.vectors().map_err(e)?;
            let local: Vec<f64> = ops
                .dofs
                .owned_equations()
                .map(|eq| if eq % 3 == axis { 1.0 } else { 0.0 })
                .collect();
            u.set_local(&local).map_err(e)?;
            ops.mass.mult(&u, &mut mu).map_err(e)?;
            let total = u.dot(&mu).map_err(e)?;
            if ((total - exact) / exact).abs() > 1e-12 {
                return Err(format!(
                    "axis {axis} ({rule:?}): u^T M u = {total}, rho V + point masses = {exact} \
                     (rho V = {solid})"
                ));
            }
            out.push(total);
        }
    }
    Ok(out)
}
