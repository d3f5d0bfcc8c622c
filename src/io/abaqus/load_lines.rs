//! Data lines of the supports and loads: `*BOUNDARY`, `*CLOAD`, `*DSLOAD`, `*DLOAD`, with
//! Abaqus DOF numbers (rotations dropped with a warning).

use super::drafts::*;
use super::lexer::{data_fields, looks_numeric, Name};
use super::lines::Loc;
use super::reader::Reader;
use crate::mesh::MeshError;

impl Reader {
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
    pub(super) fn dof(
        &mut self,
        field: &str,
        keyword: &str,
        loc: Loc,
    ) -> Result<Option<u8>, MeshError> {
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

    pub(super) fn boundary_line(
        &mut self,
        text: &str,
        loc: Loc,
        fixed: bool,
    ) -> Result<(), MeshError> {
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
            // All but PINNED also hold rotations.
            if !f[1].eq_ignore_ascii_case("PINNED") {
                self.constraints
                    .rotational
                    .push((f[0].to_string(), "*BOUNDARY", loc));
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
                self.constraints
                    .rotational
                    .push((f[0].to_string(), "*BOUNDARY", loc));
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
            // FIXED: the value is the step's starting displacement, whatever is written.
            value: if fixed { 0.0 } else { value },
            fixed,
            loc,
        });
        Ok(())
    }

    pub(super) fn load_line(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
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
            self.constraints
                .rotational
                .push((f[0].to_string(), "*CLOAD", loc));
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

    pub(super) fn surface_pressure_line(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
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

    pub(super) fn element_pressure_line(&mut self, text: &str, loc: Loc) -> Result<(), MeshError> {
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
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;

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
}
