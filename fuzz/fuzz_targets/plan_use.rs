//! The plan reader behind `export`, `physics` and `replan` (issue 33): arbitrary text is read
//! as a plan file (with the format validation every command applies), and whatever is accepted
//! is exported in every format and put through the grip check of every plan. A panic, a hang
//! or an allocation past the limit is a finding; an error is the expected answer.
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use pregrasp_export::{export, Drawing, Format, Options};
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
    if let Ok(set) = file.to_model() {
        // glTF as `pregrasp export` makes it: with the arms it could load.
        let loaded = file.arms_and_grippers(None).ok();
        let formats: &[Format] = match loaded {
            Some(_) => &Format::ALL,
            None => &[Format::UrScript, Format::Csv, Format::Ros2],
        };
        let drawing = loaded.as_ref().map(|(arms, grippers)| Drawing {
            mesh: mesh(),
            arms,
            grippers,
        });
        for index in 0..set.plans.len().min(2) {
            let _ = export(&set, index, formats, &Options::default(), drawing.as_ref());
        }
    }
    let settings = PhysicsSettings::default();
    let Ok(set) = file.to_model() else {
        return;
    };
    if let Ok(part) = PartMass::resolve(set.object.mass, mesh(), None, settings.density) {
        for index in 0..set.plans.len().min(2) {
            let _ = analyse_plan(&set, index, &part, &settings);
        }
    }
});
