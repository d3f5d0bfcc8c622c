//! Data lines of the step procedures read: `*STATIC` (time incrementation) and `*FREQUENCY`
//! (in the layout of the eigensolver named, see the module documentation of [`super`]).

use super::lexer::data_fields;
use super::lines::Loc;
use super::reader::Reader;
use super::{FrequencyRequest, Procedure, StaticRequest};
use crate::mesh::MeshError;

impl Reader {
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
}
