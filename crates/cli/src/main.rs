//! `pregrasp`: the command-line front end. It only parses arguments, calls the library
//! crates and prints; every algorithm lives in a library crate.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod cmd;

/// Dual-arm pre-grasp manipulation planning.
///
/// A flat, heavy part lies on a table where a gripper cannot power-grasp it. pregrasp finds
/// how one arm can rotate the part about one of its edges, with the table carrying its
/// weight, until both grippers have room, and plans every motion of both arms.
#[derive(Parser)]
#[command(
    name = "pregrasp",
    version,
    about,
    long_about,
    after_help = "Exit status: 0 success (planned, valid); 1 bad input (unreadable or malformed \
                  file, value out of range; nothing written); 2 no plan, or a plan that fails \
                  `check`; 64 command-line usage error (unknown command or option, missing or \
                  unparsable argument)."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the whole method on the built-in chair-side example and write demo-plan.json.
    Demo(cmd::demo::Args),
    /// Plan the pre-grasp manipulation of a scene (Algorithms 1-3) and write a plan file.
    Plan(cmd::plan::Args),
    /// Re-verify a plan file against every validity rule of the plan format.
    Check(cmd::check::Args),
    /// List the rotation-axis candidates of a scene (Algorithm 1).
    Axes(cmd::axes::Args),
    /// Kinematics of the built-in arms: forward and inverse.
    #[command(subcommand)]
    Kin(cmd::kin::KinCommand),
    /// Benchmarks anyone can rerun.
    #[command(subcommand)]
    Bench(cmd::bench::BenchCommand),
    /// The built-in example parts and scenes.
    #[command(subcommand)]
    Example(cmd::example::ExampleCommand),
    /// Write an interactive 3D view (HTML) of a plan file.
    View(cmd::view::Args),
    /// Export a plan for the cell: URScript per arm, CSV, ROS 2 trajectories, glTF.
    Export(cmd::export::Args),
    /// Will the pinch hold? The minimum grip force along the rotation (quasi-static).
    Physics(cmd::physics::Args),
    /// Plan every scene of a folder: plans, viewer pages, summary.csv/json and an HTML report.
    Batch(cmd::batch::Args),
    /// Re-plan for the part measured at another pose, keeping the plan's rotation axis if it works.
    Replan(cmd::replan::Args),
    /// How far may the part lie from where the scene says? Placement errors, each re-planned.
    Robustness(cmd::robustness::Args),
    /// Print the plan file's JSON Schema (`schema plan`), to validate plans without the repository.
    Schema(cmd::schema::Args),
}

fn main() -> ExitCode {
    // `kin` numbers such as `-3.3e-05` are made readable to clap first (see cmd::kin).
    let cli = match Cli::try_parse_from(cmd::kin::normalize_args(std::env::args_os())) {
        Ok(cli) => cli,
        Err(err) => {
            // --help and --version are answers, not errors; any other command-line mistake
            // exits with the usage code, never with 1 (bad input) or 2 (no plan).
            let _ = err.print();
            return ExitCode::from(if err.use_stderr() {
                cmd::EXIT_USAGE
            } else {
                cmd::EXIT_OK
            });
        }
    };
    let result = match cli.command {
        Command::Demo(args) => cmd::demo::run(args),
        Command::Plan(args) => cmd::plan::run(args),
        Command::Check(args) => cmd::check::run(args),
        Command::Axes(args) => cmd::axes::run(args),
        Command::Kin(command) => cmd::kin::run(command),
        Command::Bench(command) => cmd::bench::run(command),
        Command::Example(command) => cmd::example::run(command),
        Command::View(args) => cmd::view::run(args),
        Command::Export(args) => cmd::export::run(args),
        Command::Physics(args) => cmd::physics::run(args),
        Command::Batch(args) => cmd::batch::run(args),
        Command::Replan(args) => cmd::replan::run(args),
        Command::Robustness(args) => cmd::robustness::run(args),
        Command::Schema(args) => cmd::schema::run(args),
    };
    match result {
        Ok(code) => code,
        Err(err) => {
            // One line, numbers as people write them (Rust prints 1e308 with 309 digits).
            let message = format!("{err:#}");
            eprintln!(
                "error: {}",
                pregrasp_io::text::readable_numbers(&message.replace('\n', " | "))
            );
            ExitCode::from(cmd::EXIT_BAD_INPUT)
        }
    }
}
