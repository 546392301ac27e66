//! `pregrasp check PLAN.json`: re-verifies a plan file against every validity rule.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_planner::check::check_plan_at;

use super::{EXIT_NO_PLAN, EXIT_OK};

#[derive(clap::Args)]
#[command(
    after_help = "Exit status: 0 valid, 2 invalid (the failed rules are marked FAIL), 1 unreadable or malformed plan file (the offending field is named) or unreadable mesh."
)]
pub struct Args {
    /// The plan file to check.
    pub plan: PathBuf,
    /// The object mesh, when it is not at the path the plan file names (`object.mesh`, taken
    /// relative to the current directory, then to the plan file's directory).
    #[arg(long)]
    pub mesh: Option<PathBuf>,
}

/// Prints one line per rule with its worst value; exit 0 iff the plan file is valid, 2 if not.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let file = PlanFile::read(&args.plan)?;
    let mesh_path = args
        .mesh
        .clone()
        .unwrap_or_else(|| file.mesh_path(&args.plan));
    let mesh = load_mesh(&mesh_path, file.object.scale)
        .with_context(|| format!("{}: object.mesh", args.plan.display()))?
        .mesh;
    let report = check_plan_at(&file, Some(&args.plan), &mesh);
    if let Some(problem) = &report.malformed {
        anyhow::bail!("{}: not a valid plan file: {problem}", args.plan.display());
    }
    for rule in &report.rules {
        let verdict = match rule.ok {
            Some(true) => "ok  ",
            Some(false) => "FAIL",
            None => "--  ",
        };
        println!(
            "rule {} {verdict} {}: {}",
            rule.rule, rule.title, rule.detail
        );
    }
    let valid = report.is_valid();
    println!(
        "{}: {}",
        args.plan.display(),
        if valid { "valid" } else { "INVALID" }
    );
    Ok(ExitCode::from(if valid { EXIT_OK } else { EXIT_NO_PLAN }))
}
