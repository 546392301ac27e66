//! `pregrasp example`: the built-in example parts (the paper's chair, shelf and stool sides)
//! and their scenes.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;

use super::EXIT_OK;

#[derive(clap::Subcommand)]
pub enum ExampleCommand {
    /// List the built-in examples: name, title, mesh size.
    List,
    /// Write every example's scene (`<name>.toml`) and mesh (`meshes/<name>.stl`, binary STL)
    /// into DIR, creating it. Plan one with `pregrasp plan DIR/<name>.toml`.
    Write {
        /// Output directory (created if missing; existing example files are overwritten).
        dir: PathBuf,
        /// Write only this example (default: all).
        #[arg(long, value_name = "NAME")]
        only: Option<String>,
    },
    /// Write generated parts (six families, drawn from seeds, hand-placed grasps by the
    /// family's rule; with `--hard` the six hard-case families, whose grasps have material
    /// next to them) into DIR: each part's scene `<family>_<seed>.toml` and mesh
    /// `meshes/<family>_<seed>.stl` (binary STL), all files or none. Same seed, same bytes.
    Generate {
        /// Output directory (created if missing; existing files of the same names are
        /// overwritten).
        dir: PathBuf,
        /// Parts per family.
        #[arg(long, value_name = "N", default_value_t = 5)]
        per_family: usize,
        /// Seed of each family's first part; the next parts take the following seeds.
        #[arg(long, value_name = "S", default_value_t = 1)]
        first_seed: u64,
        /// Only this family: frame, ladder, u_frame, panel, stool or h_frame, or a hard one:
        /// t_junction, l_corner, hand_hole, parallel_bars, chamfered or thin_rungs (default:
        /// all of the six, or of the hard six with `--hard`).
        #[arg(long, value_name = "NAME")]
        family: Option<String>,
        /// The hard-case families instead of the six (T-junctions, L-corners, hand holes,
        /// parallel bars, chamfers and tapers, thin rungs next to the grasps).
        #[arg(long, conflicts_with = "family")]
        hard: bool,
        /// The arm in place of each UR5e: another UR model (ur3e, ur10e, ur16e, ur5: only
        /// `model` changes), or a described arm: fr3 (Franka FR3, elbow held at 0) or xarm6
        /// (UFACTORY xArm6), with its URDF, start and bases 0.1 m nearer the part, as the
        /// other-arm replay tables were planned.
        #[arg(long, value_name = "ARM", default_value = "ur5e")]
        arm: String,
        /// Where the described arms' URDF files are (`fr3.urdf`, `xarm6.urdf`); written into
        /// the scenes as absolute paths.
        #[arg(long, value_name = "DIR", default_value = "data/robots")]
        robots: PathBuf,
    },
}

pub fn run(command: ExampleCommand) -> anyhow::Result<ExitCode> {
    match command {
        ExampleCommand::List => {
            for e in pregrasp_examples::all() {
                println!(
                    "{:<12} {:<18} {} triangles, {}.toml + {}",
                    e.name,
                    e.title,
                    e.mesh.triangles.len(),
                    e.name,
                    pregrasp_examples::mesh_relative_path(e.name)
                );
            }
        }
        ExampleCommand::Write { dir, only } => {
            let examples = match only {
                None => pregrasp_examples::all(),
                Some(name) => vec![pregrasp_examples::by_name(&name).with_context(|| {
                    format!(
                        "unknown example \"{name}\" (expected one of {})",
                        pregrasp_examples::NAMES.join(", ")
                    )
                })?],
            };
            for e in &examples {
                let written = pregrasp_examples::write_example(&dir, e)?;
                for path in written {
                    println!("wrote {}", path.display());
                }
            }
        }
        ExampleCommand::Generate {
            dir,
            per_family,
            first_seed,
            family,
            hard,
            arm,
            robots,
        } => {
            use pregrasp_examples::arm_in_place::ArmInPlace;
            use pregrasp_examples::generated::{generated_scene, select_from, write_generated};
            let set = if hard {
                &pregrasp_examples::HARD_FAMILIES
            } else {
                &pregrasp_examples::FAMILIES
            };
            let parts = select_from(set, first_seed, per_family, family.as_deref())
                .map_err(anyhow::Error::msg)?;
            let arm = ArmInPlace::by_name(&arm, &robots)?;
            let scenes: Vec<_> = parts
                .iter()
                .map(|part| {
                    let mut scene = generated_scene(part);
                    scene.scene_toml = arm.put_in(&scene.scene_toml);
                    scene
                })
                .collect();
            for path in write_generated(&dir, &scenes)? {
                println!("wrote {}", path.display());
            }
        }
    }
    Ok(ExitCode::from(EXIT_OK))
}
