//! Writes the viewer's fixture scene into a directory: `plate.stl`, `plan.json` (planned,
//! two plans), `no-plan.json`, and their pages `plan.html`, `no-plan.html`. Used by `ci/browser-test.sh`.
//!
//! Usage: `cargo run -p pregrasp-viewer --example fixture_plan -- DIR`

use std::path::PathBuf;
use std::process::ExitCode;

use pregrasp_io::plan_file::write_atomic;
use pregrasp_viewer::ViewOptions;

#[path = "../tests/common/mod.rs"]
mod common;

use common::{fixture, render};

fn main() -> ExitCode {
    let Some(dir) = std::env::args_os().nth(1).map(PathBuf::from) else {
        eprintln!("usage: fixture_plan DIR");
        return ExitCode::from(1);
    };
    let run = || -> Result<(), Box<dyn std::error::Error>> {
        std::fs::create_dir_all(&dir)?;
        let mesh_path = dir.join("plate.stl");
        pregrasp_io::mesh_io::write_stl(&mesh_path, &fixture::plate_mesh())?;
        let mesh = mesh_path.display().to_string();
        let plan = fixture::demo_plan(&mesh)?;
        plan.write_atomic(&dir.join("plan.json"))?;
        let none = fixture::no_plan(&mesh);
        none.write_atomic(&dir.join("no-plan.json"))?;
        let plate = fixture::plate_mesh();
        let options = ViewOptions::default();
        write_atomic(
            &dir.join("plan.html"),
            render(&plan, &plate, &options).as_bytes(),
        )?;
        write_atomic(
            &dir.join("no-plan.html"),
            render(&none, &plate, &options).as_bytes(),
        )?;
        Ok(())
    };
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}
