//! What a friction sweep's model is made from: the model tables, the reduction and the
//! analysis settings of a study, and nothing else of it (not its output folder, not what
//! `squeal study` compares). The models of a sweep ([`super::FullModel`],
//! [`super::SuperElementModel`]) are built from these, so a change elsewhere in the study
//! neither reaches them nor changes the hash a super-element file carries.

use crate::model::spec::ModelSpec;
use crate::study::config::{AnalysisSpec, ReductionSpec, Study};

#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct SweepSettings<'a> {
    pub model: ModelSpec<'a>,
    /// A reduced contact interface in place of the swept pairs (absent: the full model).
    pub reduction: Option<&'a ReductionSpec>,
    pub analysis: &'a AnalysisSpec,
    /// Where they come from (the study or deck file, or "built-in study"): what errors name.
    #[serde(skip)]
    pub source: &'a str,
}

impl<'a> SweepSettings<'a> {
    /// A study's, read from `source`.
    pub fn of(study: &'a Study, source: &'a str) -> Self {
        SweepSettings {
            model: study.model_spec(),
            reduction: study.reduction.as_ref(),
            analysis: &study.analysis,
            source,
        }
    }

    /// A hash (hex) of everything the models are made from: equal settings, equal hash.
    pub fn hash(&self) -> String {
        let text = serde_json::to_string(self).expect("plain data serialises");
        crate::mesh::hash::text_hash(&text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The output folder and the comparison are not the model's: they leave the hash as it
    /// is; the friction values, the reduction and the model tables change it.
    #[test]
    fn the_hash_sees_the_model_reduction_and_analysis_only() {
        let base = Study::builtin("tiny");
        let hash = |s: &Study| SweepSettings::of(s, "a").hash();
        let h = hash(&base);
        assert_eq!(h, SweepSettings::of(&base, "another name").hash());
        let mut s = base.clone();
        s.output = "elsewhere".into();
        s.comparison = Some(Default::default());
        assert_eq!(hash(&s), h);
        let mut s = base.clone();
        s.analysis.friction.push(0.95);
        assert_ne!(hash(&s), h);
        let mut s = base.clone();
        s.reduction = Some(toml::from_str("contact_nodes_per_pad = 6\n").unwrap());
        assert_ne!(hash(&s), h);
        let mut s = base.clone();
        s.pressures[0].value *= 2.0;
        assert_ne!(hash(&s), h);
    }
}
