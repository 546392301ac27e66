//! File formats of pregrasp: scene files (TOML, `scene-format.md`), meshes (STL, OBJ) and
//! plan files (JSON, `plan-format.md`).

pub mod mesh_io;
pub mod plan_file;
pub mod scene;
