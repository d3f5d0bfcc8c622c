//! Data lines of the step procedures read: `*STATIC` (time incrementation), `*FREQUENCY`
//! (in the layout of the eigensolver named, see the module documentation of [`super`]) and
//! `*COMPLEX FREQUENCY` (Abaqus: number of modes, minimum and maximum frequency, shift),
//! with the `*COMPLEX FREQUENCY` parameters that change what is computed refused.

use super::lexer::{data_fields, Keyword};
use super::lines::Loc;
use super::reader::Reader;
use super::{ComplexFrequencyRequest, FrequencyRequest, Procedure, StaticRequest};
use crate::mesh::MeshError;

impl Reader {
    /// The parameters of `*COMPLEX FREQUENCY`: those that change the physics squeal cannot
    /// follow are refused; output options are left for the ignored-parameter warning.
    pub(super) fn complex_frequency_keyword(&self, kw: &mut Keyword) -> Result<(), MeshError> {
        if kw.flag("CORIOLIS") {
            return Err(self.err(
                kw.loc,
                "*COMPLEX FREQUENCY, CORIOLIS (CalculiX's Coriolis forces of a rotating frame) \
                 is not supported: squeal's complex eigenvalue analysis is the friction one \
                 (Abaqus' *COMPLEX FREQUENCY)",
            ));
        }
        if let Some(v) = self.param(kw, "FRICTIONDAMPING")? {
            if !v.eq_ignore_ascii_case("NO") {
                return Err(self.err(
                    kw.loc,
                    format!(
                        "*COMPLEX FREQUENCY, FRICTION DAMPING={v} is not supported: squeal \
                         leaves out friction-induced damping (Abaqus' default, FRICTION \
                         DAMPING=NO)"
                    ),
                ));
            }
        }
        if let Some(v) = self.param(kw, "STIFFNESSPROJECTION")? {
            if v.eq_ignore_ascii_case("NO") {
                return Err(self.err(
                    kw.loc,
                    "*COMPLEX FREQUENCY, STIFFNESS PROJECTION=NO (which leaves the friction out \
                     of the stiffness) is not supported: squeal's CEA uses the whole tangent",
                ));
            }
        }
        // squeal has no frequency-dependent properties: evaluating them at a frequency
        // changes nothing.
        kw.flag("PROPERTYEVALUATION");
        Ok(())
    }

    pub(super) fn complex_frequency_line(
        &mut self,
        lines: usize,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
        if lines > 1 {
            return Err(self.err(loc, "*COMPLEX FREQUENCY: expected one data line"));
        }
        let f = data_fields(text);
        if f.len() > 4 {
            return Err(self.err(
                loc,
                format!(
                    "*COMPLEX FREQUENCY: expected \"number of modes, minimum frequency, maximum \
                     frequency, shift point\", found {} fields",
                    f.len()
                ),
            ));
        }
        let eigenvalues = match f.first() {
            None | Some(&"") => None,
            Some(s) => Some(self.label(s, loc, "number of complex eigenmodes")? as usize),
        };
        let request = ComplexFrequencyRequest {
            eigenvalues,
            lower_frequency: self.optional_number(&f, 1, loc, "minimum frequency of interest")?,
            upper_frequency: self.optional_number(&f, 2, loc, "maximum frequency of interest")?,
            shift: self.optional_number(&f, 3, loc, "shift point")?,
        };
        if let (Some(lo), Some(hi)) = (request.lower_frequency, request.upper_frequency) {
            if hi < lo {
                return Err(self.err(
                    loc,
                    format!(
                        "*COMPLEX FREQUENCY: the maximum frequency {hi} is below the minimum {lo}"
                    ),
                ));
            }
        }
        if let Some(step) = &mut self.step {
            if let Some((procedure, _)) = &mut step.procedure {
                *procedure = Procedure::ComplexFrequency(request);
            }
        }
        Ok(())
    }

    pub(super) fn static_line(
        &mut self,
        lines: usize,
        text: &str,
        loc: Loc,
    ) -> Result<(), MeshError> {
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

    pub(super) fn frequency_line(
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
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::super::*;

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
            Procedure::ComplexFrequency(ComplexFrequencyRequest {
                eigenvalues: Some(20),
                ..Default::default()
            })
        );
        assert!(deck.steps[3].perturbation);
    }

    #[test]
    fn complex_frequency_reads_its_band_and_refuses_what_it_cannot_compute() {
        let text = format!(
            "{}*STEP\n*COMPLEX FREQUENCY, FRICTION DAMPING=NO, PROPERTY EVALUATION=100.\n\
             , 100., 8000., 4000.\n*END STEP\n",
            one_tet()
        );
        let deck = read_text("complex-band", &text).unwrap();
        assert_eq!(
            deck.steps[0].procedure,
            Procedure::ComplexFrequency(ComplexFrequencyRequest {
                eigenvalues: None,
                lower_frequency: Some(100.0),
                upper_frequency: Some(8000.0),
                shift: Some(4000.0),
            })
        );
        let n = one_tet().lines().count();
        for (tail, line, said) in [
            (
                "*STEP\n*COMPLEX FREQUENCY, CORIOLIS\n10\n*END STEP\n",
                n + 2,
                "CORIOLIS",
            ),
            (
                "*STEP\n*COMPLEX FREQUENCY, FRICTION DAMPING=YES\n10\n*END STEP\n",
                n + 2,
                "FRICTION DAMPING=YES is not supported",
            ),
            (
                "*STEP\n*COMPLEX FREQUENCY, STIFFNESS PROJECTION=NO\n*END STEP\n",
                n + 2,
                "STIFFNESS PROJECTION=NO",
            ),
            (
                "*STEP\n*COMPLEX FREQUENCY\n, 9., 8.\n*END STEP\n",
                n + 3,
                "below the minimum",
            ),
            (
                "*STEP\n*COMPLEX FREQUENCY\n1, 2, 3, 4, 5\n*END STEP\n",
                n + 3,
                "found 5 fields",
            ),
            ("*COMPLEX FREQUENCY\n", n + 1, "inside *STEP"),
        ] {
            let (_, at, message) =
                parse_error(read_text("complex-err", &format!("{}{tail}", one_tet())));
            assert_eq!(at, line, "{tail}: {message}");
            assert!(message.contains(said), "{tail}: {message}");
        }
    }
}
