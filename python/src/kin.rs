//! `pregrasp.kin`: forward and inverse kinematics of the built-in arms (standard DH in the
//! controller's base frame; the flange frame is tool0, z out of the flange).

use numpy::{PyArray2, PyReadonlyArray2};
use pregrasp_robot::{Joints, UrKinematics, UrModel};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::convert::{isometry_from_array, matrix_array, rows_array};

fn model_of(name: &str) -> PyResult<UrModel> {
    UrModel::from_name(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "unknown robot model {name:?} (expected ur3e, ur5e, ur10e, ur16e or ur5)"
        ))
    })
}

fn joints(q: &[f64], what: &str) -> PyResult<Joints> {
    if q.len() != 6 || q.iter().any(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{what} must be 6 finite joint angles (rad), found {q:?}"
        )));
    }
    Ok(std::array::from_fn(|i| q[i]))
}

/// The flange pose (4×4, base frame) of `model` at joint angles `q` (rad).
#[pyfunction]
#[pyo3(signature = (q, model = "ur5e"))]
pub fn fk<'py>(py: Python<'py>, q: Vec<f64>, model: &str) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let kin = UrKinematics::new(model_of(model)?);
    Ok(matrix_array(py, &kin.fk(&joints(&q, "q")?)))
}

/// Every joint solution (rad, shape (K, 6), K = 0 when unreachable; with the ±2π alternates
/// the joint limits allow) that puts the flange of
/// `model` at `pose` (4×4, base frame), within the joint limits, nearest to `seed` first.
#[pyfunction]
#[pyo3(signature = (pose, model = "ur5e", seed = None))]
pub fn ik<'py>(
    py: Python<'py>,
    pose: PyReadonlyArray2<'_, f64>,
    model: &str,
    seed: Option<Vec<f64>>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let kin = UrKinematics::new(model_of(model)?);
    let flange = isometry_from_array(&pose, "pose")?;
    let seed = match seed {
        Some(s) => joints(&s, "seed")?,
        None => [0.0; 6],
    };
    Ok(rows_array(py, kin.ik(&flange, &seed)))
}
