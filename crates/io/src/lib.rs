//! File formats of pregrasp: scene files (TOML, `scene-format.md`), meshes (STL, OBJ) and
//! plan files (JSON, `plan-format.md`).

pub mod limits;
pub mod mesh_io;
pub mod output;
pub mod plan_arms;
pub mod plan_file;
pub mod plan_format;
pub mod plan_model;
pub mod plan_read;
pub mod plan_terms;
pub mod ranges;
pub mod scene;
pub mod text;
