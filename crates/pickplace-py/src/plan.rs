//! `pickplace.plan`, `pickplace.validate`, and the `Plan` and `ValidationReport` classes.

use crate::convert::{samples, times, to_python};
use crate::errors::{facade, input_msg, no_plan};
use crate::scene::Scene;
use numpy::{PyArray1, PyArray2};
use pickplace::StrategyChoice;
use pickplace::planner::{Outcome, PlanOptions, PlanOverrides};
use pyo3::prelude::*;
use std::path::PathBuf;

/// A strategy by its name ([`StrategyChoice`]'s, the CLI's `--strategy` values).
pub(crate) fn strategy(name: &str) -> PyResult<StrategyChoice> {
    name.parse()
        .map_err(|e: pickplace::strategy::UnknownStrategy| input_msg(e.to_string()))
}

/// A pick-and-place plan (docs/plan-format.md): the strategy, grasps, placement, key poses
/// and the timed joint trajectory. Immutable; arrays are new copies on every access.
#[pyclass(frozen, module = "pickplace")]
#[derive(Debug)]
pub struct Plan {
    /// The plan.
    pub inner: pickplace::Plan,
}

#[pymethods]
impl Plan {
    /// Reads a plan from its JSON text (as `to_json` or `pickplace plan` writes it).
    ///
    /// Raises InputError with the parser's message (line and column) or the first sample
    /// or pose whose form is wrong.
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &str) -> PyResult<Self> {
        let inner = py
            .detach(|| pickplace::Plan::from_json(text))
            .map_err(|e| input_msg(e.to_string()))?;
        Ok(Self { inner })
    }

    /// Reads a plan file; errors name the file as `pickplace validate` does.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let inner = py
            .detach(|| pickplace::Plan::load(&path))
            .map_err(|e| input_msg(e.to_string()))?;
        Ok(Self { inner })
    }

    /// The plan as pretty JSON with a final newline: byte for byte the file `pickplace plan
    /// SCENE --out FILE` writes (with `--no-timings` when planned with `timings=False`).
    fn to_json(&self) -> String {
        self.inner.to_json()
    }

    /// The plan as a dict (the JSON document).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner)
    }

    /// The plan format (`pickplace.plan/2`).
    #[getter]
    fn format(&self) -> &str {
        &self.inner.format
    }

    /// The seed every random choice derived from.
    #[getter]
    fn seed(&self) -> u64 {
        self.inner.seed
    }

    /// The strategy that succeeded (`right-right`, `right-left`, …).
    #[getter]
    fn strategy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner.strategy)
    }

    /// Every actuated joint (grippers included), in model order: the columns of
    /// `positions`, `velocities` and `accelerations`.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.inner.joint_names.clone()
    }

    /// Sample times from the start, shape (N,), s.
    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        times(py, &self.inner.trajectory)
    }

    /// Joint positions, shape (N, J), float64 (rad or m).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        samples(
            py,
            &self.inner.trajectory,
            self.inner.joint_names.len(),
            |p| &p.positions,
        )
    }

    /// Joint velocities, shape (N, J), rad/s or m/s; None when the plan has none (format
    /// `pickplace.plan/1`).
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.derivative(py, |p| &p.velocities)
    }

    /// Joint accelerations, shape (N, J), rad/s² or m/s²; None when the plan has none.
    #[getter]
    fn accelerations<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.derivative(py, |p| &p.accelerations)
    }

    /// Duration of the motion, s.
    #[getter]
    fn duration(&self) -> f64 {
        self.inner
            .trajectory
            .last()
            .map_or(0.0, |p| p.time_from_start)
    }

    /// Grasps and releases in time order: list of dicts `{time, kind, arm, link,
    /// link_from_object}`.
    #[getter]
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner.events)
    }

    /// The grasps used, in time order (list of dicts).
    #[getter]
    fn grasps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner.grasps)
    }

    /// The placement chosen (dict: contact, clusters, environment, stability margin, rank).
    #[getter]
    fn placement<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner.placement)
    }

    /// The object's start and placed poses (dict of `{position, orientation}`).
    #[getter]
    fn object<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner.object)
    }

    /// The key poses of the motion, in time order (list of dicts).
    #[getter]
    fn key_poses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner.key_poses)
    }

    /// Intermediate resting poses of a regrasp by placing (list of dicts, empty otherwise).
    #[getter]
    fn rests<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner.rests)
    }

    /// Where the robot stands (dict `{link, world_from_root}`: its root link and that link's
    /// pose in the world, the frame of the plan's world poses), or None in plans written
    /// before it was stated.
    #[getter]
    fn base<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner.base)
    }

    /// Each arm's joints and gripper joints, and where its tool link is (list of dicts:
    /// `tool` is `{link, parent, parent_from_tool}`, absent in plans written before it was
    /// stated).
    #[getter]
    fn arms<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner.arms)
    }

    /// How the plan was found (dict: timings when planned with `timings=True`, strategies
    /// with their per-stage counts, candidate counts, duration).
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner.stats)
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<Plan>()
            .is_ok_and(|o| o.get().inner == self.inner)
    }

    fn __repr__(&self) -> String {
        format!(
            "Plan(strategy={}, {} samples over {:.2} s, {} joints)",
            self.inner.strategy,
            self.inner.trajectory.len(),
            self.duration(),
            self.inner.joint_names.len()
        )
    }
}

impl Plan {
    /// Velocities or accelerations as (N, J), when every sample has them.
    fn derivative<'py>(
        &self,
        py: Python<'py>,
        field: impl Fn(&pickplace::plan::TrajectoryPoint) -> &Vec<f64>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        let j = self.inner.joint_names.len();
        let t = &self.inner.trajectory;
        if t.is_empty() || t.iter().any(|p| field(p).len() != j) {
            return Ok(None);
        }
        samples(py, t, j, field).map(Some)
    }
}

/// Plans a pick-and-place motion for a scene (the paper's Fig. 8) with the GIL released.
///
/// Arguments not given take the scene's values (`planner.seed`, `planner.strategy`,
/// `planner.time_budget`, `trajectory.*_scaling`), as `pickplace plan` does. `timings`
/// (default False) records wall-clock stage timings in `stats["timings"]`; without them the
/// same seed gives the same bytes (`pickplace plan --no-timings`).
///
/// Returns a Plan. Raises NoPlanError (with `reasons` and `stats`) when no strategy
/// succeeds or the scene is infeasible, InputError for options out of range.
#[pyfunction]
#[pyo3(signature = (scene, *, seed=None, strategy=None, time_budget=None, timings=false, velocity_scaling=None, acceleration_scaling=None, sample_period=None))]
#[allow(clippy::too_many_arguments)]
pub fn plan(
    py: Python<'_>,
    scene: &Bound<'_, Scene>,
    seed: Option<u64>,
    strategy: Option<&str>,
    time_budget: Option<f64>,
    timings: bool,
    velocity_scaling: Option<f64>,
    acceleration_scaling: Option<f64>,
    sample_period: Option<f64>,
) -> PyResult<Plan> {
    let setup = scene.get().setup.clone();
    // Ranges are checked by the façade (`PlanOptions::check`, the CLI's table).
    let overrides = PlanOverrides {
        seed,
        strategy: strategy.map(self::strategy).transpose()?,
        time_budget,
        velocity_scaling,
        acceleration_scaling,
        sample_period,
        timings: Some(timings),
    };
    let options = PlanOptions::with_overrides(&setup, &overrides);
    let outcome = py
        .detach(|| pickplace::plan(&setup, &options))
        .map_err(|e| facade(py, &e))?;
    match outcome {
        Outcome::Planned(plan) => Ok(Plan { inner: *plan }),
        Outcome::NoPlan(failure) => {
            let stats = to_python(py, &failure.stats)?;
            let text = format!("no plan: {}", failure.reasons.join("; "));
            Err(no_plan(py, &text, &failure.reasons, Some(stats)))
        }
    }
}

/// What `validate` found (`pickplace validate --json`).
#[pyclass(frozen, module = "pickplace")]
#[derive(Debug)]
pub struct ValidationReport {
    report: pickplace::validate::ValidationReport,
}

#[pymethods]
impl ValidationReport {
    /// True when the plan passed every check (no problem).
    #[getter]
    fn ok(&self) -> bool {
        self.report.problems.is_empty()
    }

    /// Every problem, in time order (empty when the plan is valid).
    #[getter]
    fn problems(&self) -> Vec<String> {
        self.report.problems.clone()
    }

    /// Interpolated states checked.
    #[getter]
    fn states_checked(&self) -> usize {
        self.report.states_checked
    }

    /// Duration of the trajectory, s.
    #[getter]
    fn duration(&self) -> f64 {
        self.report.duration
    }

    /// Stability margin of the final pose (m), when the object ends on a support.
    #[getter]
    fn stability_margin(&self) -> Option<f64> {
        self.report.stability_margin
    }

    /// The report as a dict (the document of `pickplace validate --json`).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.report)
    }

    fn __bool__(&self) -> bool {
        self.ok()
    }

    fn __repr__(&self) -> String {
        format!(
            "ValidationReport(ok={}, {} problems, {} states checked)",
            if self.ok() { "True" } else { "False" },
            self.report.problems.len(),
            self.report.states_checked
        )
    }
}

/// Re-checks a plan against a scene independently (`pickplace validate`): dense
/// interpolation, joint limits, collisions, grasps, stability; with the GIL released.
/// `plan_name` names the plan in errors.
///
/// Returns a ValidationReport (`ok`, `problems`). Raises InputError when the plan does not
/// fit the scene's robot (joint names, lengths, poses).
#[pyfunction]
#[pyo3(signature = (scene, plan, *, plan_name=PathBuf::from("<plan>")))]
pub fn validate(
    py: Python<'_>,
    scene: &Bound<'_, Scene>,
    plan: &Bound<'_, Plan>,
    plan_name: PathBuf,
) -> PyResult<ValidationReport> {
    let setup = scene.get().setup.clone();
    let plan = plan.get();
    let report = py
        .detach(|| pickplace::validate::validate(&setup, &plan.inner, &plan_name))
        .map_err(|e| facade(py, &e))?;
    Ok(ValidationReport { report })
}
