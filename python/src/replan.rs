//! `Replanner`: the cell's loop from Python. A plan is made once; then, each time the camera
//! measures the part, the measured pose is brought onto the table and the plan is replanned
//! there, with the part's geometry and the gripper closings at its grasps built once (they
//! live in the object frame) — what `pregrasp replan` does, in-process and without the
//! per-process set-up.

use std::sync::Arc;
use std::time::Instant;

use numpy::PyReadonlyArray2;
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene as SceneSpec;
use pregrasp_planner::context::PartKnowledge;
use pregrasp_planner::pipeline::PlanOptions;
use pregrasp_planner::replan::replan_from_rot;
use pregrasp_planner::resume::{replan_remaining, Resume};
use pregrasp_planner::settle::{settle, settle_on_hull, SettleTolerance};
use pyo3::exceptions::{PyIndexError, PyValueError};
use pyo3::prelude::*;

use crate::convert::isometry_from_array;
use crate::plan::{thread_pool, Plan};
use crate::scene::Scene;
use crate::SceneError;

/// Replans a plan at measured poses of its part.
///
/// `Replanner(scene, plan)` keeps `plan` (made from `scene`), the part's geometry and the
/// gripper closings at the plan's grasps; `replan(pose)` brings a measured 4×4 pose (object →
/// world, the part as it lies, without the planner's lift) onto the support and replans there,
/// keeping the plan's rotation axis when it still plans (the whole pipeline otherwise).
#[pyclass(module = "pregrasp._pregrasp", frozen)]
pub struct Replanner {
    spec: Arc<SceneSpec>,
    mesh: Arc<Mesh>,
    nominal: Arc<PlanFile>,
    known: Arc<PartKnowledge>,
}

#[pymethods]
impl Replanner {
    /// Builds what every replan of `plan` reuses. Raises `SceneError` if `plan` has no plan.
    #[new]
    fn new(py: Python<'_>, scene: &Scene, plan: &Plan) -> PyResult<Replanner> {
        if plan.file.plans.is_empty() {
            return Err(SceneError::new_err(format!(
                "the plan file has no plan to replan ({})",
                plan.file.reason.as_deref().unwrap_or("no reason given")
            )));
        }
        // An auto scene's placements keep the grasps its search chose.
        let spec = Arc::new(scene.spec.with_grasps_of(&plan.file.grasps));
        let mesh = scene.mesh.clone();
        let known = {
            let (spec, mesh) = (spec.clone(), mesh.clone());
            py.detach(move || PartKnowledge::new(&spec, &mesh).map(Arc::new))
                .map_err(|e| SceneError::new_err(e.to_string()))?
        };
        Ok(Replanner {
            spec,
            mesh,
            nominal: plan.file.clone(),
            known,
        })
    }

    /// Replans plan `plan_index` with the part measured at `pose` (4×4). The pose is first
    /// brought onto the support (raises `SceneError`, "check the measurement", when it is more
    /// than 10 mm or 5° from any resting pose) unless `as_measured`. `start`: the first segment
    /// to plan again, as `pregrasp replan --from`: `"sup1"` (everything), `"rot"` (sup1 has
    /// run), `"mas1"` (rot has run: the part is held turned and taken as measured) or `"sup2"`.
    /// Returns the new `Plan`; its `status` says whether it planned. The GIL is released while
    /// it plans.
    #[pyo3(signature = (pose, plan_index = 0, as_measured = false, threads = None, start = "sup1"))]
    fn replan(
        &self,
        py: Python<'_>,
        pose: PyReadonlyArray2<'_, f64>,
        plan_index: usize,
        as_measured: bool,
        threads: Option<usize>,
        start: &str,
    ) -> PyResult<Plan> {
        let measured = isometry_from_array(&pose, "pose")?;
        if plan_index >= self.nominal.plans.len() {
            return Err(PyIndexError::new_err(format!(
                "plan_index {plan_index}: the plan file has {} plan(s)",
                self.nominal.plans.len()
            )));
        }
        let resume = match start {
            "sup1" | "rot" => None,
            "mas1" => Some(Resume::Mas1),
            "sup2" => Some(Resume::Sup2),
            other => {
                return Err(PyValueError::new_err(format!(
                    "start {other:?}: expected \"sup1\", \"rot\", \"mas1\" or \"sup2\""
                )))
            }
        };
        let from_rot = start == "rot";
        let pose = if as_measured || resume.is_some() {
            measured
        } else {
            let tolerance = SettleTolerance::default();
            let height = self.spec.support_height;
            match self.known.hull() {
                Some(hull) => settle_on_hull(hull, &measured, height, &tolerance),
                None => settle(&self.mesh, &measured, height, &tolerance),
            }
            .map_err(|e| SceneError::new_err(e.to_string()))?
            .pose
        };
        let (spec, mesh, nominal) = (self.spec.clone(), self.mesh.clone(), self.nominal.clone());
        let options = PlanOptions {
            known: Some(self.known.clone()),
            ..PlanOptions::default()
        };
        let started = Instant::now();
        let result: Result<PlanFile, String> = py.detach(move || {
            let pool = thread_pool(threads)?;
            let again = pool.install(|| match resume {
                Some(from) => replan_remaining(&spec, &mesh, &nominal, plan_index, pose, from)
                    .map_err(|e| e.to_string()),
                None if from_rot => replan_from_rot(&spec, &mesh, &nominal, plan_index, pose)
                    .map_err(|e| e.to_string()),
                None => pregrasp_planner::replan::replan(
                    &spec, &mesh, &nominal, plan_index, pose, &options,
                )
                .map_err(|e| e.to_string()),
            })?;
            Ok(again.report.file)
        });
        let mut file = result.map_err(SceneError::new_err)?;
        file.timing_ms
            .insert("replan".into(), started.elapsed().as_secs_f64() * 1e3);
        Ok(Plan {
            file: Arc::new(file),
            mesh: Some(self.mesh.clone()),
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "Replanner(scene {:?}, {} plan(s))",
            self.spec.name.as_deref().unwrap_or("-"),
            self.nominal.plans.len()
        )
    }
}
