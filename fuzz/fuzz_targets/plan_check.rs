//! The plan-file reader, the format validation and `check` on arbitrary text, judged against
//! the chair-side example's mesh (the seeds are its plans).
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_planner::check::check_plan;

fn mesh() -> &'static pregrasp_examples::Mesh {
    static MESH: OnceLock<pregrasp_examples::Mesh> = OnceLock::new();
    MESH.get_or_init(|| {
        pregrasp_examples::by_name("chair_side")
            .expect("built-in example")
            .mesh
    })
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(file) = PlanFile::from_json_str(text, "fuzz.json") {
        let _ = check_plan(&file, mesh());
    }
});
