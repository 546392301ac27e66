//! How much of a file a reader takes: input files are regular files of bounded size, so a
//! wrong path (a device, a pipe) or a huge file is refused in words, not read into memory
//! (the reader is `pregrasp-limits`', shared with the robot descriptions).

/// Largest scene file (bytes). A scene is a few hundred bytes of TOML; 4 MiB leaves room for
/// comments and inline data without letting a stray multi-gigabyte file be parsed.
pub const MAX_SCENE_BYTES: u64 = 4 << 20;

/// Largest mesh file (bytes): 1 GiB, a binary STL of about 20 million triangles.
pub const MAX_MESH_BYTES: u64 = 1 << 30;

pub use pregrasp_limits::{bytes, read_limited};
