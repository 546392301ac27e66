//! Conversions between Python values and the workspace's types: scene specs (dicts, lists,
//! numbers, 4×4 pose matrices) to TOML, poses to 4×4 numpy arrays, serde values to Python.

use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion};
use numpy::ndarray::Array2;
use numpy::{Element, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// How far a 4×4 pose's rotation block may be from a rotation (Frobenius norm of RᵀR − I)
/// before it is refused.
const ROTATION_TOL: f64 = 1e-6;

/// A Python value as a TOML value: bool, int, float, str, list/tuple, dict; a 4×4 nested
/// list (a homogeneous pose, e.g. `numpy_array.tolist()`) becomes the scene format's inline
/// pose table `{ xyz, quat_xyzw }`. `key` names the value in errors (`grasps.support`).
pub fn to_toml(value: &Bound<'_, PyAny>, key: &str) -> PyResult<toml::Value> {
    if value.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(value.extract()?));
    }
    if value.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(value.extract().map_err(|_| {
            PyValueError::new_err(format!("{key}: integer out of range"))
        })?));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(value.extract()?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract()?));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in dict.iter() {
            let k: String = k
                .extract()
                .map_err(|_| PyValueError::new_err(format!("{key}: keys must be strings")))?;
            let sub = if key.is_empty() {
                k.clone()
            } else {
                format!("{key}.{k}")
            };
            table.insert(k, to_toml(&v, &sub)?);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        if let Some(m) = as_matrix4(value) {
            return pose_table(&m, key);
        }
        let mut items = Vec::new();
        for (i, v) in value.try_iter()?.enumerate() {
            items.push(to_toml(&v?, &format!("{key}[{i}]"))?);
        }
        return Ok(toml::Value::Array(items));
    }
    // numpy scalars and arrays: through their Python equivalents.
    if value.hasattr("tolist")? {
        return to_toml(&value.call_method0("tolist")?, key);
    }
    Err(PyValueError::new_err(format!(
        "{key}: cannot be written in a scene: {}",
        value.get_type().name()?
    )))
}

/// A 4×4 nested list of numbers, if `value` is one.
fn as_matrix4(value: &Bound<'_, PyAny>) -> Option<[[f64; 4]; 4]> {
    let rows: Vec<Vec<f64>> = value.extract().ok()?;
    if rows.len() != 4 || rows.iter().any(|r| r.len() != 4) {
        return None;
    }
    Some(std::array::from_fn(|i| std::array::from_fn(|j| rows[i][j])))
}

/// A numpy 4×4 array as an isometry ([`isometry_from_matrix`]); refuses another shape.
pub fn isometry_from_array(
    pose: &numpy::PyReadonlyArray2<'_, f64>,
    key: &str,
) -> PyResult<Isometry3<f64>> {
    let p = pose.as_array();
    if p.shape() != [4, 4] {
        return Err(PyValueError::new_err(format!(
            "{key} must be a 4×4 matrix, found shape {:?}",
            p.shape()
        )));
    }
    let m: [[f64; 4]; 4] = std::array::from_fn(|i| std::array::from_fn(|j| p[[i, j]]));
    isometry_from_matrix(&m, key)
}

/// A homogeneous 4×4 matrix as an isometry; refuses a matrix that is not a rigid transform.
pub fn isometry_from_matrix(m: &[[f64; 4]; 4], key: &str) -> PyResult<Isometry3<f64>> {
    if m.iter().flatten().any(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{key}: pose matrix has a non-finite entry"
        )));
    }
    if m[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(PyValueError::new_err(format!(
            "{key}: the last row of a pose matrix must be [0, 0, 0, 1], found {:?}",
            m[3]
        )));
    }
    let r = Matrix3::from_fn(|i, j| m[i][j]);
    let err = (r.transpose() * r - Matrix3::identity()).norm();
    if err > ROTATION_TOL || r.determinant() < 0.0 {
        return Err(PyValueError::new_err(format!(
            "{key}: the upper-left 3×3 block of a pose matrix must be a rotation (|RᵀR − I| = {err:.2e}, det = {:.6})",
            r.determinant()
        )));
    }
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
    Ok(Isometry3::from_parts(
        Translation3::new(m[0][3], m[1][3], m[2][3]),
        rotation,
    ))
}

/// The scene format's inline pose table for a 4×4 matrix.
fn pose_table(m: &[[f64; 4]; 4], key: &str) -> PyResult<toml::Value> {
    let pose = isometry_from_matrix(m, key)?;
    let q = pose.rotation.coords;
    let t = pose.translation.vector;
    let mut table = toml::Table::new();
    table.insert(
        "xyz".into(),
        toml::Value::Array(t.iter().map(|&x| toml::Value::Float(x)).collect()),
    );
    table.insert(
        "quat_xyzw".into(),
        toml::Value::Array([q.x, q.y, q.z, q.w].map(toml::Value::Float).to_vec()),
    );
    Ok(toml::Value::Table(table))
}

/// Rows of `K` values as an (N, K) numpy array (shape (0, K) when there are none).
pub fn rows_array<'py, T: Element, const K: usize>(
    py: Python<'py>,
    rows: impl IntoIterator<Item = [T; K]>,
) -> Bound<'py, PyArray2<T>> {
    let flat: Vec<T> = rows.into_iter().flatten().collect();
    let n = flat.len() / K;
    let array = Array2::from_shape_vec((n, K), flat).expect("whole rows of K values");
    PyArray2::from_owned_array(py, array)
}

/// An isometry as a 4×4 numpy array.
pub fn matrix_array<'py>(py: Python<'py>, pose: &Isometry3<f64>) -> Bound<'py, PyArray2<f64>> {
    let h = pose.to_homogeneous();
    rows_array(
        py,
        (0..4).map(|i| std::array::from_fn::<f64, 4, _>(|j| h[(i, j)])),
    )
}

/// The grasps `G_p1`, `G_p2` and `G_s` (object frame) as a dict of 4×4 matrices:
/// `{"power": [G_p1, G_p2], "support": G_s}`.
pub fn grasps_dict<'py>(
    py: Python<'py>,
    power: &[Isometry3<f64>; 2],
    support: &Isometry3<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item(
        "power",
        power
            .iter()
            .map(|p| matrix_array(py, p))
            .collect::<Vec<_>>(),
    )?;
    d.set_item("support", matrix_array(py, support))?;
    Ok(d)
}

/// A serde value as the Python object `json.loads` makes of it.
pub fn to_python<'py, T: serde::Serialize>(
    py: Python<'py>,
    value: &T,
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| PyValueError::new_err(format!("cannot convert to Python: {e}")))?;
    py.import("json")?.call_method1("loads", (text,))
}
