//! `squeal radius`: the optimal radius of influence of the distributing coupling per
//! weighting degree (the paper's Table 2 recomputed, and the whole-grid optimum). Pure
//! computation: it needs no MPI/PETSc runtime and `main.rs` runs it before starting one.

use crate::reduce::{radius_table, table_text};
use crate::study::StudyError;

/// Prints the table, as text or as JSON (`{"degrees": [{"degree", "paper_radius",
/// "paper_mean", "paper_std", "grid_radius", "grid_std"}]}`, radii in units of the grid side).
pub fn run(json: bool) -> Result<(), StudyError> {
    let table = radius_table();
    if json {
        let text = serde_json::to_string_pretty(&table).map_err(|source| StudyError::Json {
            what: "the radius table",
            source,
        })?;
        println!("{text}");
    } else {
        print!("{}", table_text(&table));
    }
    Ok(())
}
