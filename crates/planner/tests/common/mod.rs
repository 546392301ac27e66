//! Helpers shared by the planner's integration tests.
#![allow(dead_code)]

pub mod replay_table;
pub mod scenes;
