//! The paper's three test parts (§VII): parametric generators.

pub mod chair;
pub mod shelf;
pub mod stool;
