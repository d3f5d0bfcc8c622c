//! Data lines of `*ELASTIC` (isotropic) and `*DENSITY`.

use super::lexer::data_fields;
use super::lines::Loc;
use super::reader::Reader;
use crate::mesh::MeshError;

impl Reader {
    pub(super) fn elastic_line(
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

    pub(super) fn density_line(
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
}
