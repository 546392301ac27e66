//! A plan file for the tests: the planner run in-process on the built-in chair side.

#![allow(dead_code)]

use pregrasp_io::plan_file::PlanStatus;
use std::path::Path;
use std::sync::OnceLock;

use pregrasp_export::{export, Drawing, ExportError, Format, Options, OutFile};
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;
use pregrasp_planner::pipeline::{plan, PlanOptions};

/// The chair-side plan file and its part mesh (planned once per test binary).
pub fn chair_side() -> &'static (PlanFile, Mesh) {
    static PLAN: OnceLock<(PlanFile, Mesh)> = OnceLock::new();
    PLAN.get_or_init(|| {
        let ex = pregrasp_examples::by_name("chair_side").expect("built-in example");
        let scene = Scene::from_str(&ex.scene_toml, Path::new("examples/chair_side.toml"))
            .expect("example scene parses");
        let file = plan(&scene, &ex.mesh, &PlanOptions::default(), &|_| {}, &|| {})
            .unwrap()
            .file;
        assert_eq!(file.status, PlanStatus::Planned, "{:?}", file.reason);
        (file, ex.mesh)
    })
}

/// Exports plan `index` of `file` as `pregrasp export` does: the file as a plan set, and for
/// glTF (`mesh` given) its arms and grippers loaded from their descriptions.
pub fn export_file(
    file: &PlanFile,
    index: usize,
    formats: &[Format],
    options: &Options,
    mesh: Option<&Mesh>,
) -> Result<Vec<OutFile>, ExportError> {
    let set = file.to_model().expect("the plan file is a plan set");
    let loaded = mesh.map(|m| {
        let (arms, grippers) = file.arms_and_grippers(None).expect("the arms load");
        (m, arms, grippers)
    });
    let drawing = loaded.as_ref().map(|(mesh, arms, grippers)| Drawing {
        mesh,
        arms,
        grippers,
    });
    export(&set, index, formats, options, drawing.as_ref())
}

/// Plan points of plan `index` as (plan time, robot name, q): segments back to back.
pub fn plan_points(file: &PlanFile, index: usize) -> Vec<(f64, String, [f64; 6])> {
    let mut out = Vec::new();
    let mut t0 = 0.0;
    for seg in &file.plans[index].segments {
        for p in &seg.points {
            out.push((t0 + p.t, seg.robot.clone(), p.q));
        }
        t0 += seg.points.last().unwrap().t;
    }
    out
}

/// Where arm `robot` is at plan time `t`, from the plan file alone (independent of the crate):
/// linear between its points, holding still outside its segments.
pub fn plan_q(file: &PlanFile, index: usize, robot: &str, t: f64) -> [f64; 6] {
    let start = file.robots.iter().find(|r| r.name == robot).unwrap().start;
    let pts: Vec<(f64, [f64; 6])> = plan_points(file, index)
        .into_iter()
        .filter(|p| p.1 == robot)
        .map(|p| (p.0, p.2))
        .collect();
    let mut q = start;
    for w in pts.windows(2) {
        if t >= w[0].0 && t <= w[1].0 && w[1].0 > w[0].0 {
            let s = (t - w[0].0) / (w[1].0 - w[0].0);
            return std::array::from_fn(|i| w[0].1[i] + (w[1].1[i] - w[0].1[i]) * s);
        }
        if t >= w[1].0 {
            q = w[1].1;
        }
    }
    if let Some(first) = pts.first() {
        if t < first.0 {
            return first.1;
        }
    }
    q
}
