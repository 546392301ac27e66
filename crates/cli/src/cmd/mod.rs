//! One module per subcommand. Each exposes its clap arguments and a `run` function that
//! returns the process exit code; errors are printed by `main` with exit code 1.

pub mod axes;
pub mod batch;
pub mod bench;
pub mod check;
pub mod demo;
pub mod example;
pub mod export;
pub mod kin;
pub mod physics;
pub mod plan;
pub mod replan;
pub mod robustness;
pub mod schema;
pub mod view;

/// Exit code: success (planned, valid, done).
#[allow(dead_code)]
pub const EXIT_OK: u8 = 0;
/// Exit code: bad input (unreadable or malformed scene, mesh or plan file, values out of range).
pub const EXIT_BAD_INPUT: u8 = 1;
/// Exit code: the input was fine but no plan was found (or a checked plan is invalid).
#[allow(dead_code)]
pub const EXIT_NO_PLAN: u8 = 2;
/// Command-line usage error: an unknown command or option, a missing or unparsable argument
/// (64, `EX_USAGE` of sysexits.h), so it is never mistaken for 2, "no plan".
pub const EXIT_USAGE: u8 = 64;
