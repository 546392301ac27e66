//! `pregrasp._pregrasp`: the Python extension module behind the `pregrasp` package.
//!
//! A thin layer: scenes, plans, the checker, Algorithm 1, kinematics and the batch are the
//! workspace's crates, called as the CLI calls them, so a plan made here is the CLI's plan
//! byte for byte (but `timing_ms`). Planning releases the GIL. Errors become the exceptions
//! below, with the CLI's messages. The Python-facing API (argument normalisation, numpy
//! conversion, the Ray backend) is in `python/pregrasp/`.

mod batch;
mod convert;
mod kin;
mod plan;
mod replan;
mod scene;

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    _pregrasp,
    PregraspError,
    PyException,
    "Base class of pregrasp's errors."
);
create_exception!(
    _pregrasp,
    SceneError,
    PregraspError,
    "A scene (file or arrays) or its mesh cannot be used; the message names the file and the key."
);
create_exception!(
    _pregrasp,
    PlanFileError,
    PregraspError,
    "A plan file cannot be read, is not a pregrasp plan, or cannot be written."
);

/// The extension module.
#[pymodule]
fn _pregrasp(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("PregraspError", py.get_type::<PregraspError>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("PlanFileError", py.get_type::<PlanFileError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<plan::Plan>()?;
    m.add_class::<plan::PlanEntry>()?;
    m.add_class::<plan::Segment>()?;
    m.add_class::<plan::Report>()?;
    m.add_class::<replan::Replanner>()?;
    m.add_function(wrap_pyfunction!(scene::default_robots, m)?)?;
    m.add_function(wrap_pyfunction!(scene::write_examples, m)?)?;
    m.add_function(wrap_pyfunction!(plan::plan_scene, m)?)?;
    m.add_function(wrap_pyfunction!(plan::axes, m)?)?;
    m.add_function(wrap_pyfunction!(plan::_planning_now, m)?)?;
    m.add_function(wrap_pyfunction!(plan::check_plan, m)?)?;
    m.add_function(wrap_pyfunction!(kin::fk, m)?)?;
    m.add_function(wrap_pyfunction!(kin::ik, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_discover, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_plan_one, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_run, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_write_report, m)?)?;
    Ok(())
}
