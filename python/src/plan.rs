//! `Plan`, `PlanEntry`, `Segment`, `Report`: plan files in Python, planning with the GIL
//! released, the checker and Algorithm 1.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Instant;

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pregrasp_geometry::Mesh;
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::plan_file::{write_atomic, CandidateJson, PlanFile, PlanJson, SegmentJson};
use pregrasp_planner::pipeline::PlanOptions;
use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{grasps_dict, matrix_array, rows_array, to_python};
use crate::scene::Scene;
use crate::{PlanFileError, PregraspError, SceneError};

/// A plan file (docs/plan-format.md): the outcome of planning a scene, or one read from disk.
///
/// `status` is `"planned"` or `"no_plan"` (then `reason` says why); `plans` holds the plans,
/// best first; `to_json()` is the file `pregrasp plan` writes.
#[pyclass(module = "pregrasp._pregrasp", frozen)]
pub struct Plan {
    pub file: Arc<PlanFile>,
    /// The part's mesh when known (planned here, or given): `check()` needs it.
    pub mesh: Option<Arc<Mesh>>,
}

#[pymethods]
impl Plan {
    /// Reads a plan file. Raises `PlanFileError` (unreadable, not JSON, not a pregrasp plan).
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Plan> {
        read_plan(path)
    }

    /// Parses plan-file text; `name` stands for the file in messages. Raises `PlanFileError`.
    #[staticmethod]
    #[pyo3(signature = (text, name = "<string>"))]
    fn from_json(text: &str, name: &str) -> PyResult<Plan> {
        plan_from_json(text, name)
    }

    /// `"planned"` or `"no_plan"`.
    #[getter]
    fn status(&self) -> String {
        self.file.status.to_string()
    }

    /// Why there is no plan (`None` when planned).
    #[getter]
    fn reason(&self) -> Option<String> {
        self.file.reason.clone()
    }

    /// Algorithm 1's candidates with what became of each: a list of dicts (`id`, `axis`,
    /// `direction`, `length`, `theta_max`, `score`, `theta_goal`, `outcome`), best score first.
    #[getter]
    fn candidates<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.file.candidates)
    }

    /// The plans, best first.
    #[getter]
    fn plans(&self) -> Vec<PlanEntry> {
        (0..self.file.plans.len())
            .map(|index| PlanEntry {
                file: self.file.clone(),
                index,
            })
            .collect()
    }

    /// Time spent per stage (ms).
    #[getter]
    fn timing_ms<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.file.timing_ms)
    }

    /// The grasps used, in the object frame, as the plan file states them (for an auto scene,
    /// the ones its search chose): a dict of 4×4 matrices plus `auto` (the search's numbers).
    #[getter]
    fn grasps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let g = &self.file.grasps;
        let power = [g.power[0].to_isometry(), g.power[1].to_isometry()];
        let d = grasps_dict(py, &power, &g.support.to_isometry())?;
        d.set_item("auto", to_python(py, &g.auto)?)?;
        Ok(d)
    }

    /// The whole plan file as a Python dict (what `json.loads(plan.to_json())` gives).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &*self.file)
    }

    /// The plan file's text, exactly as `pregrasp plan` writes it.
    fn to_json(&self) -> String {
        self.file.to_json()
    }

    /// Writes the plan file to `path` atomically (temp file, then rename), as `pregrasp plan -o
    /// path` would: `to_json()` plus where the scene and the mesh are from the file's folder
    /// (`scene.file_from_plan`, `object.mesh_from_plan`), so that the file finds them wherever
    /// it is opened from.
    fn write(&self, path: PathBuf) -> PyResult<()> {
        let mut file = (*self.file).clone();
        file.locate_inputs(&path);
        write_atomic(&path, file.to_json().as_bytes())
            .map_err(|e| PlanFileError::new_err(e.to_string()))
    }

    fn __repr__(&self) -> String {
        format!(
            "Plan(status={:?}, plans={}, candidates={})",
            self.file.status,
            self.file.plans.len(),
            self.file.candidates.len()
        )
    }
}

/// One plan: a rotation axis, the roles of the arms and the four motions.
#[pyclass(module = "pregrasp._pregrasp", frozen)]
pub struct PlanEntry {
    file: Arc<PlanFile>,
    index: usize,
}

impl PlanEntry {
    fn plan(&self) -> &PlanJson {
        &self.file.plans[self.index]
    }
}

#[pymethods]
impl PlanEntry {
    /// Id of the candidate (rotation axis and sense) this plan rotates about.
    #[getter]
    fn candidate(&self) -> usize {
        self.plan().candidate
    }

    /// S_rot of its axis.
    #[getter]
    fn score(&self) -> f64 {
        self.plan().score
    }

    /// Name of the master arm (it takes its power grasp last).
    #[getter]
    fn master(&self) -> String {
        self.plan().master.clone()
    }

    /// Name of the supportive arm (it pinches G_s and rotates the part).
    #[getter]
    fn supportive(&self) -> String {
        self.plan().supportive.clone()
    }

    /// θ_goal of the rotation (rad).
    #[getter]
    fn theta_goal(&self) -> Option<f64> {
        self.file
            .candidates
            .iter()
            .find(|c| c.id == self.plan().candidate)
            .and_then(|c| c.theta_goal)
    }

    /// P_obj: the part's pose at the end of the rotation (4×4, object frame in world).
    #[getter]
    fn object_goal_pose<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix_array(py, &self.plan().object_goal_pose.to_isometry())
    }

    /// The grip check of the rotation (a dict), if it was run.
    #[getter]
    fn physics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.plan().physics)
    }

    /// Segment names in execution order: `sup1`, `rot`, `mas1`, `sup2`.
    #[getter]
    fn segment_names(&self) -> Vec<String> {
        self.plan()
            .segments
            .iter()
            .map(|s| s.name.to_string())
            .collect()
    }

    /// The segment called `name` (`sup1`, `rot`, `mas1` or `sup2`).
    fn segment(&self, name: &str) -> PyResult<Segment> {
        let plan = self.plan();
        let index = plan
            .segments
            .iter()
            .position(|s| s.name.as_str() == name)
            .ok_or_else(|| {
                PyKeyError::new_err(format!(
                    "no segment {name:?} (this plan has {})",
                    plan.segments
                        .iter()
                        .map(|s| s.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })?;
        Ok(Segment {
            file: self.file.clone(),
            plan: self.index,
            index,
        })
    }

    fn __repr__(&self) -> String {
        let p = self.plan();
        format!(
            "PlanEntry(candidate={}, score={:.4}, master={:?}, supportive={:?})",
            p.candidate, p.score, p.master, p.supportive
        )
    }
}

/// One motion of one arm: time stamps `t` (s, shape (N,)) and joint angles `q` (rad, (N, 6)).
#[pyclass(module = "pregrasp._pregrasp", frozen)]
pub struct Segment {
    file: Arc<PlanFile>,
    plan: usize,
    index: usize,
}

impl Segment {
    fn seg(&self) -> &SegmentJson {
        &self.file.plans[self.plan].segments[self.index]
    }
}

#[pymethods]
impl Segment {
    /// `sup1`, `rot`, `mas1` or `sup2`.
    #[getter]
    fn name(&self) -> String {
        self.seg().name.to_string()
    }

    /// The arm that moves.
    #[getter]
    fn robot(&self) -> String {
        self.seg().robot.clone()
    }

    /// `reach`, `rotate` or `regrasp`.
    #[getter]
    fn kind(&self) -> String {
        self.seg().kind.to_string()
    }

    /// `support` or `power`: the grasp this segment ends in (or holds).
    #[getter]
    fn grasp(&self) -> String {
        self.seg().grasp.to_string()
    }

    /// Gap between the pads once the gripper has closed on the part (m), if stated.
    #[getter]
    fn grip_width(&self) -> Option<f64> {
        self.seg().grip_width
    }

    /// The grip force (N) this closing segment (`sup1`, `mas1`, `sup2`) closes its gripper
    /// with, if stated: `sup1`'s is the pinch's recommended force.
    #[getter]
    fn grip_force(&self) -> Option<f64> {
        self.seg().grip_force
    }

    /// Time stamps (s), shape (N,).
    #[getter]
    fn t<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.seg().points.iter().map(|p| p.t).collect())
    }

    /// Joint angles (rad), shape (N, 6).
    #[getter]
    fn q<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows_array(py, self.seg().points.iter().map(|p| p.q))
    }

    /// The part's pose at every point of `rot` (shape (N, 4, 4)), `None` for other segments.
    #[getter]
    fn object_poses<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let seg = self.seg();
        if seg.points.iter().any(|p| p.object_pose.is_none()) || seg.points.is_empty() {
            return Ok(None);
        }
        let flat: Vec<f64> = seg
            .points
            .iter()
            .flat_map(|p| {
                let h = p
                    .object_pose
                    .as_ref()
                    .unwrap()
                    .to_isometry()
                    .to_homogeneous();
                (0..4)
                    .flat_map(move |i| (0..4).map(move |j| h[(i, j)]))
                    .collect::<Vec<_>>()
            })
            .collect();
        let arr = PyArray1::from_vec(py, flat);
        Ok(Some(arr.reshape([seg.points.len(), 4, 4])?.into_any()))
    }

    fn __len__(&self) -> usize {
        self.seg().points.len()
    }

    fn __repr__(&self) -> String {
        let s = self.seg();
        format!(
            "Segment({:?}, robot={:?}, {} points, {:.3} s)",
            s.name,
            s.robot,
            s.points.len(),
            s.points.last().map_or(0.0, |p| p.t) - s.points.first().map_or(0.0, |p| p.t)
        )
    }
}

/// The checker's verdict on a plan file: every rule of docs/plan-format.md.
#[pyclass(module = "pregrasp._pregrasp", frozen)]
pub struct Report {
    /// True iff no checked rule failed.
    #[pyo3(get)]
    valid: bool,
    /// One dict per rule: `rule` (number), `title`, `ok` (True, False or None: not checkable
    /// from a plan file), `detail` (the worst value or the first violation).
    #[pyo3(get)]
    rules: Vec<Py<PyDict>>,
    /// The file does not follow the plan format: the field and the problem.
    #[pyo3(get)]
    malformed: Option<String>,
    /// Closest approach of a grasping gripper to the support (m).
    #[pyo3(get)]
    closest_grasp_to_support: Option<f64>,
}

#[pymethods]
impl Report {
    fn __bool__(&self) -> bool {
        self.valid
    }

    fn __repr__(&self) -> String {
        format!(
            "Report(valid={}, rules={}{})",
            if self.valid { "True" } else { "False" },
            self.rules.len(),
            self.malformed
                .as_ref()
                .map(|m| format!(", malformed={m:?}"))
                .unwrap_or_default()
        )
    }
}

/// Plans running right now with the GIL released (a diagnostic: the tests read it from another
/// Python thread to show that planning lets Python run).
static PLANNING_NOW: AtomicUsize = AtomicUsize::new(0);

/// How many plans are running right now with the GIL released.
#[pyfunction]
pub fn _planning_now() -> usize {
    PLANNING_NOW.load(Ordering::SeqCst)
}

/// Plans `scene` (Algorithms 1–3, then the checker on every plan) with the GIL released.
#[pyfunction]
#[pyo3(signature = (scene, threads = None, max_plans = None))]
pub fn plan_scene(
    py: Python<'_>,
    scene: &Scene,
    threads: Option<usize>,
    max_plans: Option<usize>,
) -> PyResult<Plan> {
    let options = PlanOptions {
        max_plans: max_plans.unwrap_or(3).max(1),
        ..PlanOptions::default()
    };
    let spec = scene.spec.clone();
    let mesh = scene.mesh.clone();
    let started = Instant::now();
    let result: Result<PlanFile, String> = py.detach(move || {
        PLANNING_NOW.fetch_add(1, Ordering::SeqCst);
        let result = plan_detached(&spec, &mesh, &options, threads);
        PLANNING_NOW.fetch_sub(1, Ordering::SeqCst);
        result
    });
    let mut file = result.map_err(SceneError::new_err)?;
    file.timing_ms
        .insert("process".into(), started.elapsed().as_secs_f64() * 1e3);
    Ok(Plan {
        file: Arc::new(file),
        mesh: Some(scene.mesh.clone()),
    })
}

/// A rayon pool of `threads` workers (default: one per core).
pub(crate) fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool, String> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| e.to_string())
}

/// The planning itself, run without the GIL.
fn plan_detached(
    spec: &pregrasp_io::scene::Scene,
    mesh: &Mesh,
    options: &PlanOptions,
    threads: Option<usize>,
) -> Result<PlanFile, String> {
    let report = thread_pool(threads)?
        .install(|| pregrasp_planner::plan_scene(spec, mesh, options, &|_| {}, &|| {}))
        .map_err(|e| e.to_string())?;
    Ok(report.file)
}

/// Algorithm 1 on `scene`: the rotation-axis candidates, best first, as the plan format's
/// `candidates` records (no outcome yet).
#[pyfunction]
pub fn axes<'py>(py: Python<'py>, scene: &Scene) -> PyResult<Bound<'py, PyAny>> {
    let spec = scene.spec.clone();
    let mesh = scene.mesh.clone();
    let candidates: Vec<CandidateJson> = py.detach(move || {
        pregrasp_planner::rotation_axis_candidates(
            &mesh,
            &spec.object.pose,
            spec.support_height,
            &spec.planner,
        )
        .candidates
        .iter()
        .map(|c| c.to_json())
        .collect()
    });
    to_python(py, &candidates)
}

/// Reads a plan file; its mesh is found as `pregrasp check` finds it (as written, then next
/// to the plan file) when the file is checked.
fn read_plan(path: PathBuf) -> PyResult<Plan> {
    let file = PlanFile::read(&path).map_err(|e| PlanFileError::new_err(e.to_string()))?;
    let mesh_path = file.mesh_path(&path);
    let mesh = load_mesh(&mesh_path, file.object.scale)
        .ok()
        .map(|m| Arc::new(m.mesh));
    Ok(Plan {
        file: Arc::new(file),
        mesh,
    })
}

/// Parses plan-file text (`name` stands for the file in messages).
fn plan_from_json(text: &str, name: &str) -> PyResult<Plan> {
    let file =
        PlanFile::from_json_str(text, name).map_err(|e| PlanFileError::new_err(e.to_string()))?;
    Ok(Plan {
        file: Arc::new(file),
        mesh: None,
    })
}

/// Re-verifies `plan` against every rule of the plan format, with `mesh_path` or the plan's
/// own mesh (GIL released).
#[pyfunction]
#[pyo3(signature = (plan, mesh_path = None))]
pub fn check_plan(py: Python<'_>, plan: &Plan, mesh_path: Option<PathBuf>) -> PyResult<Report> {
    let mesh = match mesh_path {
        Some(path) => Arc::new(
            load_mesh(&path, plan.file.object.scale)
                .map_err(|e| SceneError::new_err(format!("object.mesh: {e}")))?
                .mesh,
        ),
        None => plan.mesh.clone().ok_or_else(|| {
            PregraspError::new_err(format!(
                "the plan's mesh {:?} was not found: give mesh=PATH",
                plan.file.object.mesh
            ))
        })?,
    };
    let file = plan.file.clone();
    let report = py.detach(move || pregrasp_planner::check::check_plan(&file, &mesh));
    let rules = report
        .rules
        .iter()
        .map(|r| {
            let d = PyDict::new(py);
            d.set_item("rule", r.rule)?;
            d.set_item("title", r.title)?;
            d.set_item("ok", r.ok)?;
            d.set_item("detail", &r.detail)?;
            Ok(d.unbind())
        })
        .collect::<PyResult<Vec<_>>>()?;
    Ok(Report {
        valid: report.is_valid(),
        rules,
        malformed: report.malformed.clone(),
        closest_grasp_to_support: report.closest_grasp_to_support,
    })
}
