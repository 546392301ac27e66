//! How large a description may be. The readers behind it are linear, but some steps are not:
//! the link tree's adjacency and the self-collision pairs grow with the square of the links,
//! the merging of link shapes with the cube of an arm's. Real descriptions are far below
//! these bounds (an arm: 10–20 links; a cell of two arms and fixtures: a few hundred), and
//! a description beyond them is refused in words before any of that work starts.

/// Most `<link>` elements, and most `<joint>` elements, a description may have.
pub const MAX_LINKS: usize = 10_000;

/// Most links with `<collision>` elements whose geometry one derivation takes (the arm's
/// links when an arm is named, else the whole file's).
pub const MAX_COLLISION_LINKS: usize = 512;

/// Most `<collision>` elements one derivation takes.
pub const MAX_COLLISION_ELEMENTS: usize = 4096;

/// Most bytes of collision meshes one derivation reads, all files together (each file is
/// also at most [`pregrasp_limits::MAX_COLLISION_MESH_BYTES`]).
pub const MAX_TOTAL_MESH_BYTES: u64 = 512 << 20;
