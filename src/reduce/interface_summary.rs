//! What a reduced interface says about itself in the log and the report: per pad, its grid,
//! couplings, tie springs and contact laws.

use super::interface::{PadCoupling, ReducedInterface};
use super::PatchQuadrature;

impl ReducedInterface {
    /// One line per pad: count, h, radius, k_s; the automatic choice first, if any.
    pub fn summary(&self) -> String {
        self.choice
            .iter()
            .cloned()
            .chain(self.pads.iter().map(|p| {
                let ks = p.spring_stiffness.iter().fold(0.0, |a: f64, &b| a.max(b));
                let kept = match (p.swept, p.tilt_nodes.is_empty()) {
                    (true, _) => "",
                    (false, true) => " (kept pair, point contacts)",
                    (false, false) => " (kept pair)",
                };
                let at = match p.quadrature {
                    Some(PatchQuadrature::Nodes) => "at the shares' face nodes",
                    _ => "over the shares' area",
                };
                let patch = match (p.tilt_nodes.is_empty(), p.borrowed_slopes) {
                    (true, _) => String::new(),
                    (false, 0) => {
                        format!("; patch laws {at} (two tilt nodes per reduced contact node)")
                    }
                    (false, b) => format!(
                        "; patch laws {at} (two tilt nodes per reduced contact node; {b} \
                         share(s) with their face nodes on one line or a thin strip read their \
                         nearest neighbour's)"
                    ),
                };
                // With share couplings the radius is the master-side patches' alone.
                let radius = match (p.pad_coupling, p.swept) {
                    (PadCoupling::Share, true) => "pad couplings over the shares; disc-side radius",
                    (PadCoupling::Share, false) => {
                        "couplings over the shares; master-side radius"
                    }
                    _ => "radius of influence",
                };
                let warp = match p.warp_springs {
                    0 => String::new(),
                    n => format!("; {n} warping springs on the pad face"),
                };
                format!(
                    "{}{kept}: {}; {radius} {:.4e} ({:.3} h), tie springs up to {:.3e} N/m{patch}{warp}",
                    p.pair,
                    p.grid.summary(),
                    p.radius,
                    p.radius / p.grid.spacing,
                    ks
                )
            }))
            .collect::<Vec<_>>()
            .join("\n")
    }
}
