//! `Scene`: a scene file, or a part given as numpy arrays, with its mesh loaded.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use numpy::{PyArray2, PyReadonlyArray2};
use pregrasp_geometry::Mesh;
use pregrasp_io::mesh_io::{load_mesh, mesh_from_arrays, LoadedMesh};
use pregrasp_io::scene::Scene as SceneSpec;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::convert::{grasps_dict, matrix_array, rows_array, to_toml};
use crate::SceneError;

/// A planning problem: the scene (support, part pose, grasps, two arms, planner settings) and
/// the part's mesh, in metres.
///
/// Make one with `Scene.load(path)` (a scene file, docs/scene-format.md) or
/// `Scene.from_arrays(vertices, faces, pose, grasps, ...)` (a part from perception).
#[pyclass(module = "pregrasp._pregrasp", frozen)]
pub struct Scene {
    pub spec: Arc<SceneSpec>,
    pub mesh: Arc<Mesh>,
    /// Warnings about the scene and its mesh (unknown keys, an open mesh…).
    pub warnings: Vec<String>,
}

impl Scene {
    /// A scene and its loaded mesh, their warnings together.
    fn from_parts(spec: SceneSpec, loaded: LoadedMesh) -> Scene {
        let mut warnings = spec.warnings.clone();
        warnings.extend(loaded.warnings);
        Scene {
            spec: Arc::new(spec),
            mesh: Arc::new(loaded.mesh),
            warnings,
        }
    }

    /// Loads a scene file and its mesh, with the CLI's error messages.
    pub fn load_path(path: &Path) -> PyResult<Scene> {
        let spec = SceneSpec::load(path).map_err(|e| SceneError::new_err(e.to_string()))?;
        let loaded = load_mesh(&spec.object.mesh_path, spec.object.scale)
            .map_err(|e| SceneError::new_err(format!("{}: object.mesh: {e}", path.display())))?;
        Ok(Scene::from_parts(spec, loaded))
    }
}

#[pymethods]
impl Scene {
    /// Loads a scene file (TOML, docs/scene-format.md) and its mesh. Raises `SceneError` with
    /// the message `pregrasp plan` prints.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Scene> {
        Scene::load_path(&path)
    }

    /// A scene from a part given as arrays: `vertices` (N, 3) in mesh units (times `scale` =
    /// metres) and `faces` (M, 3) vertex indices, lying at `pose` (4×4, object frame in
    /// world), with `grasps` = `{"power": [G_p1, G_p2], "support": G_s}` (4×4 matrices in the
    /// object frame, or inline pose dicts such as `{"xyz": [...], "rpy_deg": [...]}`) or
    /// `"auto"` (found from the mesh). `robots`: two dicts as `Scene.robots` gives them
    /// (`name`, `model`, `base`, `start`, optional `gripper`, `precision_point_z`,
    /// `power_point_z`); default: `default_robots()`. `planner` and `physics`: dicts of the
    /// scene file's `[planner]` / `[physics]` keys (defaults for the rest). Every value is
    /// checked as in a scene file; errors (`SceneError`) name `file` and the key.
    #[staticmethod]
    #[pyo3(signature = (vertices, faces, pose, grasps, robots = None, *, name = None,
        scale = 1.0, support_height = 0.0, mass = None, planner = None, physics = None,
        file = "<arrays>", mesh_name = "part.stl"))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays<'py>(
        py: Python<'py>,
        vertices: &Bound<'py, PyAny>,
        faces: &Bound<'py, PyAny>,
        pose: &Bound<'_, PyAny>,
        grasps: &Bound<'_, PyAny>,
        robots: Option<&Bound<'_, PyAny>>,
        name: Option<String>,
        scale: f64,
        support_height: f64,
        mass: Option<f64>,
        planner: Option<&Bound<'_, PyAny>>,
        physics: Option<&Bound<'_, PyAny>>,
        file: &str,
        mesh_name: &str,
    ) -> PyResult<Scene> {
        let spec = PyDict::new(py);
        if let Some(name) = name {
            spec.set_item("name", name)?;
        }
        let support = PyDict::new(py);
        support.set_item("height", support_height)?;
        spec.set_item("support", support)?;
        let object = PyDict::new(py);
        object.set_item("scale", scale)?;
        object.set_item("pose", pose)?;
        if let Some(mass) = mass {
            object.set_item("mass", mass)?;
        }
        spec.set_item("object", object)?;
        if let Ok(mode) = grasps.extract::<String>() {
            let g = PyDict::new(py);
            g.set_item("mode", mode)?;
            spec.set_item("grasps", g)?;
        } else {
            spec.set_item("grasps", grasps)?;
        }
        match robots {
            Some(r) => spec.set_item("robot", r)?,
            None => spec.set_item("robot", default_robots(py)?)?,
        }
        if let Some(p) = planner {
            spec.set_item("planner", p)?;
        }
        if let Some(p) = physics {
            spec.set_item("physics", p)?;
        }
        let np = py.import("numpy")?;
        let as_array =
            |value: &Bound<'py, PyAny>, dtype: &str, what: &str| -> PyResult<Bound<'py, PyAny>> {
                let kwargs = PyDict::new(py);
                kwargs.set_item("dtype", dtype)?;
                np.call_method("ascontiguousarray", (value,), Some(&kwargs))
                    .map_err(|e| {
                        SceneError::new_err(format!("{file}: {what}: not a numeric array: {e}"))
                    })
            };
        let v = as_array(vertices, "float64", "vertices")?;
        let f = as_array(faces, "int64", "faces")?;
        let v: PyReadonlyArray2<'_, f64> = v
            .extract()
            .map_err(|_| SceneError::new_err(format!("{file}: vertices must have shape (N, 3)")))?;
        let f: PyReadonlyArray2<'_, i64> = f
            .extract()
            .map_err(|_| SceneError::new_err(format!("{file}: faces must have shape (M, 3)")))?;
        scene_from_spec(v, f, &spec, file, mesh_name)
    }

    /// The scene's `name`, if it has one.
    #[getter]
    fn name(&self) -> Option<String> {
        self.spec.name.clone()
    }

    /// The scene file (`<arrays>` for a scene made from arrays).
    #[getter]
    fn file(&self) -> PathBuf {
        self.spec.file.clone()
    }

    /// Warnings about the scene and its mesh, as the CLI prints them.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// World z of the support plane (m).
    #[getter]
    fn support_height(&self) -> f64 {
        self.spec.support_height
    }

    /// Mesh vertices in the object frame (m), shape (N, 3).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows_array(py, self.mesh.vertices.iter().map(|v| [v.x, v.y, v.z]))
    }

    /// Mesh triangles as vertex indices, shape (M, 3).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        rows_array(py, self.mesh.triangles.iter().map(|t| t.map(i64::from)))
    }

    /// P_init as given (`object.pose`), a 4×4 homogeneous matrix (object frame in world).
    #[getter]
    fn pose<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix_array(py, &self.spec.object.pose)
    }

    /// The grasps in the object frame: `{"power": [G_p1, G_p2], "support": G_s, "mode": ...}`
    /// as 4×4 matrices (identity placeholders for grasps an auto scene has still to find).
    #[getter]
    fn grasps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let g = &self.spec.grasps;
        let d = grasps_dict(py, &g.power, &g.support)?;
        d.set_item("mode", if g.auto.is_some() { "auto" } else { "manual" })?;
        Ok(d)
    }

    /// The two arms: dicts with `name`, `model`, `base` (4×4), `start` (6 angles, rad),
    /// `gripper`, `precision_point_z`, `power_point_z` — the form `from_arrays` takes.
    #[getter]
    fn robots<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let items = self
            .spec
            .robots
            .iter()
            .map(|r| {
                let d = PyDict::new(py);
                d.set_item("name", &r.name)?;
                d.set_item("model", r.arm.ur.map_or("urdf", |m| m.name()))?;
                d.set_item("base", matrix_array(py, &r.base))?;
                d.set_item("start", r.start.to_vec())?;
                d.set_item("gripper", &r.gripper)?;
                d.set_item("precision_point_z", r.precision_point_z)?;
                d.set_item("power_point_z", r.power_point_z)?;
                Ok(d)
            })
            .collect::<PyResult<Vec<_>>>()?;
        PyList::new(py, items)
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene(file={:?}, name={:?}, {} vertices, {} triangles)",
            self.spec.file.display().to_string(),
            self.spec.name.as_deref().unwrap_or(""),
            self.mesh.vertices.len(),
            self.mesh.triangles.len()
        )
    }
}

/// A scene from a mesh given as arrays and a spec dict in the scene file's layout (poses as
/// 4×4 matrices or inline pose dicts). `name` stands for the scene file in messages and
/// `mesh_name` for the mesh file.
fn scene_from_spec(
    vertices: PyReadonlyArray2<'_, f64>,
    faces: PyReadonlyArray2<'_, i64>,
    spec: &Bound<'_, PyDict>,
    name: &str,
    mesh_name: &str,
) -> PyResult<Scene> {
    let table = match to_toml(spec.as_any(), "") {
        Ok(toml::Value::Table(t)) => t,
        Ok(_) => unreachable!("a dict converts to a table"),
        // The message alone, without the Python exception class in front of it.
        Err(e) => {
            return Err(SceneError::new_err(format!(
                "{name}: {}",
                e.value(spec.py())
            )))
        }
    };
    let mut table = table;
    let object = table
        .entry("object")
        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    if let toml::Value::Table(object) = object {
        object.insert("mesh".into(), toml::Value::String(mesh_name.into()));
    }
    let text = toml::to_string(&table)
        .map_err(|e| SceneError::new_err(format!("{name}: cannot be written as TOML: {e}")))?;
    let spec = SceneSpec::from_str(&text, Path::new(name))
        .map_err(|e| SceneError::new_err(e.to_string()))?;
    let shape_err = |what: &str, shape: &[usize]| {
        SceneError::new_err(format!(
            "{name}: {what} must have shape (N, 3), found {shape:?}"
        ))
    };
    let v = vertices.as_array();
    if v.ncols() != 3 {
        return Err(shape_err("vertices", v.shape()));
    }
    let f = faces.as_array();
    if f.ncols() != 3 {
        return Err(shape_err("faces", f.shape()));
    }
    let verts: Vec<[f64; 3]> = v.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect();
    let tris: Vec<[i64; 3]> = f.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect();
    let loaded = mesh_from_arrays(&verts, &tris, mesh_name, spec.object.scale)
        .map_err(|e| SceneError::new_err(format!("{name}: object.mesh: {e}")))?;
    Ok(Scene::from_parts(spec, loaded))
}

/// The two arms of the built-in examples (two UR5e, 0.9 m apart along y, facing +x), in the
/// form `Scene.from_arrays(robots=...)` takes: the default when no robots are given.
#[pyfunction]
pub fn default_robots<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let layout = pregrasp_examples::SceneLayout::default();
    let items = layout
        .arms
        .iter()
        .map(|a| {
            let d = PyDict::new(py);
            d.set_item("name", a.name)?;
            d.set_item("model", "ur5e")?;
            let base =
                nalgebra::Isometry3::translation(a.base_xyz[0], a.base_xyz[1], a.base_xyz[2]);
            d.set_item("base", matrix_array(py, &base))?;
            d.set_item("start", a.start.to_vec())?;
            Ok(d)
        })
        .collect::<PyResult<Vec<_>>>()?;
    PyList::new(py, items)
}

/// Writes the built-in example scenes (chair, shelf, stool side; or only `only`) and their
/// meshes into `dir`, as `pregrasp example write` does; returns the scene files.
#[pyfunction]
#[pyo3(signature = (dir, only = None))]
pub fn write_examples(dir: PathBuf, only: Option<String>) -> PyResult<Vec<PathBuf>> {
    let examples = match only {
        None => pregrasp_examples::all(),
        Some(name) => vec![pregrasp_examples::by_name(&name).ok_or_else(|| {
            pyo3::exceptions::PyValueError::new_err(format!(
                "unknown example \"{name}\" (expected one of {})",
                pregrasp_examples::NAMES.join(", ")
            ))
        })?],
    };
    let mut scenes = Vec::new();
    for e in &examples {
        let [scene, _mesh] = pregrasp_examples::write_example(&dir, e)
            .map_err(|e| pyo3::exceptions::PyOSError::new_err(e.to_string()))?;
        scenes.push(scene);
    }
    Ok(scenes)
}
