//! Reading a plan file: parsed with serde (a bad value named by its JSON path), then checked
//! against the format ([`crate::plan_format::validate`]), so every reader gets a valid file
//! or one error naming the file and the field.

use std::path::Path;

use crate::plan_file::{PlanFile, PlanFileError, PLAN_FORMAT};
use crate::plan_format::validate;

/// Largest plan file read (bytes): a plan of five candidates is about 1 MB.
pub const MAX_PLAN_BYTES: u64 = 256 << 20;

impl PlanFile {
    /// Reads, parses and validates a plan file ([`crate::plan_format::validate`]): a regular
    /// file of at most [`MAX_PLAN_BYTES`].
    pub fn read(path: &Path) -> Result<PlanFile, PlanFileError> {
        let shown = path.display().to_string();
        let bytes = crate::limits::read_limited(path, MAX_PLAN_BYTES).map_err(|error| {
            PlanFileError::Read {
                path: shown.clone(),
                error,
            }
        })?;
        let text = String::from_utf8(bytes).map_err(|_| PlanFileError::Read {
            path: shown.clone(),
            error: std::io::Error::new(std::io::ErrorKind::InvalidData, "not UTF-8 text"),
        })?;
        PlanFile::from_json_str(&text, &shown)
    }

    /// Parses plan-file text (`shown` names it in errors), checking its `format` and then the
    /// whole file's shape and ranges ([`crate::plan_format::validate`]).
    pub fn from_json_str(text: &str, shown: &str) -> Result<PlanFile, PlanFileError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let plan: PlanFile = match serde_path_to_error::deserialize(de) {
            Ok(plan) => plan,
            // A value of the wrong type or outside its vocabulary somewhere inside: named by
            // its path, as the format check names what it refuses.
            Err(e) if e.inner().is_data() && e.path().iter().next().is_some() => {
                return Err(PlanFileError::Invalid {
                    path: shown.to_string(),
                    problem: format!("{}: {}", e.path(), e.inner()),
                })
            }
            Err(e) => {
                return Err(PlanFileError::Parse {
                    path: shown.to_string(),
                    error: e.into_inner(),
                })
            }
        };
        if plan.format != PLAN_FORMAT {
            return Err(PlanFileError::Format {
                path: shown.to_string(),
                found: plan.format,
            });
        }
        validate(&plan).map_err(|problem| PlanFileError::Invalid {
            path: shown.to_string(),
            problem,
        })?;
        Ok(plan)
    }
}
