//! Python bindings of the `pickplace` façade: the extension module `pickplace._pickplace` of
//! the Python package `pickplace` (maturin's mixed layout; the pure-Python part is in
//! `python/pickplace/`, the API is documented in `docs/python.md`).
//!
//! Every class is a frozen (immutable) `pyclass` holding `Send + Sync` Rust values, so one
//! object can be used from several Python threads; planning, validation, clustering,
//! placements and grasps run with the GIL released. No Rust error crosses the boundary as a
//! panic: bad input is `pickplace.InputError` (a `ValueError`) with the message the CLI
//! prints after `error: `, a scene without solution is `pickplace.NoPlanError`.

mod batch;
mod convert;
mod errors;
mod motion;
mod plan;
mod robot;
mod scene;
mod tools;
mod view;

use pyo3::prelude::*;

/// The extension module; `pickplace/__init__.py` re-exports its names.
#[pymodule]
fn _pickplace(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("PLAN_FORMAT", pickplace::PLAN_FORMAT)?;
    // The strategy names `plan`, `plan_many` and the browser page accept, `auto` first.
    let strategies: Vec<&str> = pickplace::StrategyChoice::all()
        .map(pickplace::StrategyChoice::name)
        .collect();
    m.add("STRATEGIES", pyo3::types::PyTuple::new(py, strategies)?)?;
    m.add("InputError", py.get_type::<errors::InputError>())?;
    m.add("NoPlanError", py.get_type::<errors::NoPlanError>())?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<plan::Plan>()?;
    m.add_class::<plan::ValidationReport>()?;
    m.add_class::<robot::Robot>()?;
    m.add_class::<robot::IkSolution>()?;
    m.add_class::<motion::MotionWorld>()?;
    m.add_class::<motion::Motion>()?;
    m.add_function(wrap_pyfunction!(motion::plan_motion, m)?)?;
    m.add_function(wrap_pyfunction!(plan::plan, m)?)?;
    m.add_function(wrap_pyfunction!(plan::validate, m)?)?;
    m.add_function(wrap_pyfunction!(tools::clusters, m)?)?;
    m.add_function(wrap_pyfunction!(tools::placements, m)?)?;
    m.add_function(wrap_pyfunction!(tools::grasps, m)?)?;
    m.add_class::<view::SceneView>()?;
    m.add_class::<view::Playback>()?;
    m.add_class::<batch::Options>()?;
    m.add_function(wrap_pyfunction!(batch::_batch_options, m)?)?;
    m.add_function(wrap_pyfunction!(batch::_batch_plan_many, m)?)?;
    m.add_function(wrap_pyfunction!(batch::_batch_prepare, m)?)?;
    m.add_function(wrap_pyfunction!(batch::_batch_plan_one, m)?)?;
    m.add_function(wrap_pyfunction!(batch::_batch_write_summary, m)?)?;
    Ok(())
}
