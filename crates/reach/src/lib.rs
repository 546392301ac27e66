//! The reach benchmark (`pregrasp bench reach`): one arm among static cuboids, many
//! start/goal queries, each planned with RRT-Connect and simplification.
//!
//! - [`problem`]: the problem-set file format and its validating loader.
//! - [`run`]: planning every query and summarising success rate and time percentiles.
//! - [`generate`]: the deterministic generator of `data/reach-ur5-table-boxes.json`.

pub mod generate;
pub mod problem;
pub mod run;

pub use generate::{generate_table_boxes, table_boxes_obstacles, GENERATOR_SEED};
pub use problem::{CuboidSpec, ProblemError, ReachProblemSet, ReachQuery};
pub use run::{
    percentile, run_reach, summarize, QueryOutcome, ReachPlanner, ReachReport, ReachSettings,
    DEFAULT_MARGIN, DEFAULT_RESOLUTION,
};
