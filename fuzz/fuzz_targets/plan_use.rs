//! The plan reader behind `export`, `physics` and `replan` (issue 33): arbitrary text is read
//! as a plan file (with the format validation every command applies), and whatever is accepted
//! is exported in every format and put through the grip check of every plan. A panic, a hang
//! or an allocation past the limit is a finding; an error is the expected answer.
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use pregrasp_export::{export, Format, Options};
use pregrasp_io::plan_file::PlanFile;
use pregrasp_physics::{analyse_plan, PartMass, PhysicsSettings};

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
    let Ok(file) = PlanFile::from_json_str(text, "fuzz.json") else {
        return;
    };
    for index in 0..file.plans.len().min(2) {
        let _ = export(&file, index, &Format::ALL, &Options::default(), Some(mesh()));
    }
    let settings = PhysicsSettings::default();
    if let Ok(part) = PartMass::resolve(&file, mesh(), None, settings.density) {
        for index in 0..file.plans.len().min(2) {
            let _ = analyse_plan(&file, index, &part, &settings);
        }
    }
});
