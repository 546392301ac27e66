//! `pregrasp schema plan`: the plan file's JSON Schema (`docs/plan.schema.json`, compiled
//! into the binary), so any tool can validate plan files without the repository.
//! `pregrasp schema scene` says where the scene format is described.

use std::process::ExitCode;

use super::EXIT_OK;

/// The plan file's JSON Schema (draft 2020-12), exactly as `docs/plan.schema.json`.
pub const PLAN_SCHEMA: &str = include_str!("../../../../docs/plan.schema.json");

/// Which format's schema to print.
#[derive(Clone, Copy, clap::ValueEnum)]
pub enum Format {
    /// The plan file (`plan.json`): its JSON Schema.
    Plan,
    /// The scene file (`*.toml`): where its format is described (it has no JSON Schema).
    Scene,
}

#[derive(clap::Args)]
pub struct Args {
    /// `plan` or `scene`.
    #[arg(value_enum)]
    pub format: Format,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    match args.format {
        Format::Plan => print!("{PLAN_SCHEMA}"),
        Format::Scene => println!(
            "The scene file is TOML; its keys, units and ranges are described in \
             docs/scene-format.md of pregrasp {}.\n\
             `pregrasp axes SCENE.toml` validates a scene (exit 1 with the file and key of \
             the first problem) without planning.",
            env!("CARGO_PKG_VERSION")
        ),
    }
    Ok(ExitCode::from(EXIT_OK))
}
