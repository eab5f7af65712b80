//! `pickplace.plan_motion`, and the `MotionWorld` and `Motion` classes: motion queries of the
//! façade's `pickplace::motion` (issue 35), as `pickplace motion` runs them.

use crate::convert::{isometry, rows, samples, times, to_python, vector};
use crate::errors::{facade, input_msg, no_plan};
use crate::scene::setup_options;
use numpy::{PyArray1, PyArray2, ToPyArray};
use pickplace::motion::{MotionOptions, MotionOutcome, MotionRequest, StateSpec};
use pickplace::scene::{EnvironmentSpec, PoseSpec};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

/// A robot and its obstacles, ready for motion queries: a scene file's robot(s),
/// environment and object (`MotionWorld.load`), or a robot's URDF and SRDF alone
/// (`MotionWorld.for_robot`), with obstacles given as dicts in the form of a scene's
/// `[[environment]]` entries: `{"name": "table", "box": [0.6, 0.9, 0.04], "pose": P}`, a
/// `"cylinder": {"radius": r, "length": l}` (along z), a `"sphere": {"radius": r}` or a
/// `"mesh": path` (with `"scale"`), and `P` a 4x4 matrix or `{"position": [x, y, z],
/// "orientation": [qx, qy, qz, qw]}` (default: identity). Immutable and safe to share
/// between threads; `with_obstacles` makes a new world.
#[pyclass(frozen, module = "pickplace")]
#[derive(Debug, Clone)]
pub struct MotionWorld {
    inner: Arc<pickplace::motion::MotionWorld>,
}

/// Adds `obstacles` (a sequence of dicts) to `world`.
fn add_obstacles(
    py: Python<'_>,
    world: &mut pickplace::motion::MotionWorld,
    obstacles: &Bound<'_, PyAny>,
) -> PyResult<()> {
    let json = py.import("json")?;
    for (i, item) in obstacles.try_iter()?.enumerate() {
        let field = format!("obstacles[{i}]");
        let item = item?;
        let dict = item
            .cast::<PyDict>()
            .map_err(|_| input_msg(format!("{field}: expected a dict")))?
            .copy()?;
        // A 4x4 matrix as the pose, in the scene's form.
        let pose = match dict.get_item("pose")? {
            Some(p) if !p.is_instance_of::<PyDict>() => {
                let pose = PoseSpec::from_isometry(&isometry(&p, &format!("{field}.pose"))?);
                Some(pose)
            }
            _ => None,
        };
        if pose.is_some() {
            dict.del_item("pose")?;
        }
        let text: String = json
            .call_method1("dumps", (&dict,))
            .map_err(|e| input_msg(format!("{field}: not a JSON-like dict: {e}")))?
            .extract()?;
        let mut spec: EnvironmentSpec =
            serde_json::from_str(&text).map_err(|e| input_msg(format!("{field}: {e}")))?;
        if let Some(pose) = pose {
            spec.pose = pose;
        }
        world
            .add_environment(&spec, &field)
            .map_err(|e| facade(py, &e))?;
    }
    Ok(())
}

#[pymethods]
impl MotionWorld {
    /// The world of a scene file (TOML, docs/scene-format.md; `[object]` and `[target]` may
    /// be left out: the object is an obstacle at its start pose), with `obstacles` added.
    ///
    /// Raises InputError naming the file and what is wrong.
    #[staticmethod]
    #[pyo3(signature = (path, *, obstacles=None, cache_dir=None, use_cache=true, package_dirs=Vec::new()))]
    fn load(
        py: Python<'_>,
        path: PathBuf,
        obstacles: Option<&Bound<'_, PyAny>>,
        cache_dir: Option<PathBuf>,
        use_cache: bool,
        package_dirs: Vec<PathBuf>,
    ) -> PyResult<Self> {
        // The sampled collision matrix's cache; no warning when there is no cache folder.
        let (options, _) = setup_options(cache_dir, use_cache, package_dirs);
        let mut world = py
            .detach(|| pickplace::motion::MotionWorld::load(&path, &options))
            .map_err(|e| facade(py, &e))?;
        if let Some(o) = obstacles {
            add_obstacles(py, &mut world, o)?;
        }
        Ok(Self {
            inner: Arc::new(world),
        })
    }

    /// The world of a robot alone (its root at the origin, the SRDF's `home` as the start
    /// state when it has one), with `obstacles`.
    #[staticmethod]
    #[pyo3(signature = (urdf, srdf=None, *, obstacles=None, cache_dir=None, use_cache=true, package_dirs=Vec::new()))]
    fn for_robot(
        py: Python<'_>,
        urdf: PathBuf,
        srdf: Option<PathBuf>,
        obstacles: Option<&Bound<'_, PyAny>>,
        cache_dir: Option<PathBuf>,
        use_cache: bool,
        package_dirs: Vec<PathBuf>,
    ) -> PyResult<Self> {
        // The sampled collision matrix's cache; no warning when there is no cache folder.
        let (options, _) = setup_options(cache_dir, use_cache, package_dirs);
        let mut world = py
            .detach(|| pickplace::motion::MotionWorld::for_robot(&urdf, srdf.as_deref(), &options))
            .map_err(|e| facade(py, &e))?;
        if let Some(o) = obstacles {
            add_obstacles(py, &mut world, o)?;
        }
        Ok(Self {
            inner: Arc::new(world),
        })
    }

    /// A new world: this one with `obstacles` added.
    fn with_obstacles(&self, py: Python<'_>, obstacles: &Bound<'_, PyAny>) -> PyResult<Self> {
        let mut world = (*self.inner).clone();
        add_obstacles(py, &mut world, obstacles)?;
        Ok(Self {
            inner: Arc::new(world),
        })
    }

    /// Every actuated joint of the robot, in model order (the columns of `start`).
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.inner
            .model()
            .variable_names()
            .map(str::to_owned)
            .collect()
    }

    /// The start state (every joint): what a query's joints outside its group keep.
    #[getter]
    fn start<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.start().to_pyarray(py)
    }

    /// The obstacles' names, sorted.
    #[getter]
    fn obstacles(&self) -> Vec<String> {
        self.inner.obstacle_names().map(str::to_owned).collect()
    }

    /// What loading did, one line each.
    #[getter]
    fn log(&self) -> Vec<String> {
        self.inner.log().to_vec()
    }

    /// What loading went on from (robot files, cache), one line each.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings().to_vec()
    }

    fn __repr__(&self) -> String {
        format!(
            "MotionWorld(robot={:?}, {} obstacles)",
            self.inner.model().name(),
            self.inner.obstacle_names().count()
        )
    }
}

/// A planned motion (docs/motion.md): the group's joints, the path and the timed trajectory.
/// Immutable; arrays are new copies on every access.
#[pyclass(frozen, module = "pickplace")]
#[derive(Debug)]
pub struct Motion {
    inner: pickplace::motion::MotionPlan,
}

#[pymethods]
impl Motion {
    /// The motion as pretty JSON with a final newline: byte for byte the file `pickplace
    /// motion --out FILE` writes (with `--no-timings` when planned with `timings=False`).
    fn to_json(&self) -> String {
        self.inner.to_json()
    }

    /// The motion as a dict (the JSON document).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner)
    }

    /// The planning group.
    #[getter]
    fn group(&self) -> String {
        self.inner.group.clone()
    }

    /// The group's joints: the columns of `positions` and `waypoints`.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.inner.joint_names.clone()
    }

    /// Sample times, shape (N,), s.
    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        times(py, &self.inner.trajectory)
    }

    /// Joint positions, shape (N, J).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        samples(
            py,
            &self.inner.trajectory,
            self.inner.joint_names.len(),
            |p| &p.positions,
        )
    }

    /// Joint velocities, shape (N, J).
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        samples(
            py,
            &self.inner.trajectory,
            self.inner.joint_names.len(),
            |p| &p.velocities,
        )
    }

    /// The collision-free path the trajectory follows, shape (W, J).
    #[getter]
    fn waypoints<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let r: Vec<&[f64]> = self.inner.waypoints.iter().map(Vec::as_slice).collect();
        rows(py, &r, self.inner.joint_names.len())
    }

    /// Duration of the motion, s.
    #[getter]
    fn duration(&self) -> f64 {
        self.inner.stats.duration
    }

    /// How it was found (`search_ms`, `states_checked`, `attempts`, `length`, …).
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.inner.stats)
    }

    fn __repr__(&self) -> String {
        format!(
            "Motion(group={:?}, {} waypoints, {:.2} s, {} samples)",
            self.inner.group,
            self.inner.waypoints.len(),
            self.inner.stats.duration,
            self.inner.trajectory.len()
        )
    }
}

/// A state argument: a state's name (str), values (a sequence or array, one per joint of the
/// group) or joints by name (a dict); `what` names it in errors.
fn state(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<StateSpec> {
    if let Ok(name) = obj.cast::<PyString>() {
        return Ok(StateSpec::Named(name.to_str()?.to_owned()));
    }
    if let Ok(dict) = obj.cast::<PyDict>() {
        let mut joints = BTreeMap::new();
        for (k, v) in dict.iter() {
            let name: String = k
                .extract()
                .map_err(|_| input_msg(format!("{what}: joint names are str")))?;
            let value: f64 = v
                .extract()
                .map_err(|_| input_msg(format!("{what}[{name:?}]: expected a number")))?;
            joints.insert(name, value);
        }
        return Ok(StateSpec::Joints(joints));
    }
    Ok(StateSpec::Values(vector(obj, what)?))
}

/// A collision-free, time-optimal motion of a planning group from `start` to `goal` among
/// the world's obstacles (`pickplace motion`; docs/motion.md), with the GIL released.
///
/// `world` is a MotionWorld or the path of a scene file; `start` and `goal` are a state's
/// name, one value per joint of the group, or a dict of joint values (the group's others as
/// in the world's start state); `start=None` is the world's start state. `group` defaults to
/// the robot's only planning group. `timings=False` (the default) leaves the wall-clock
/// times out, so that the same seed gives the same bytes.
///
/// Returns a Motion. Raises NoPlanError (with `reasons`) when an end collides or no path is
/// found within `time_limit` seconds, InputError for a group, state or option the robot or
/// the ranges refuse.
#[pyfunction]
#[pyo3(signature = (world, goal, start=None, *, group=None, seed=1, time_limit=1.0, margin=0.0, shortcut_attempts=100, velocity_scaling=None, acceleration_scaling=None, sample_period=0.04, blend_tolerance=0.1, timings=false))]
#[allow(clippy::too_many_arguments)]
pub fn plan_motion(
    py: Python<'_>,
    world: &Bound<'_, PyAny>,
    goal: &Bound<'_, PyAny>,
    start: Option<&Bound<'_, PyAny>>,
    group: Option<String>,
    seed: u64,
    time_limit: f64,
    margin: f64,
    shortcut_attempts: usize,
    velocity_scaling: Option<f64>,
    acceleration_scaling: Option<f64>,
    sample_period: f64,
    blend_tolerance: f64,
    timings: bool,
) -> PyResult<Motion> {
    let world = match world.cast::<MotionWorld>() {
        Ok(w) => w.get().clone(),
        Err(_) => {
            let path: PathBuf = world.extract().map_err(|_| {
                input_msg("world: expected a MotionWorld or the path of a scene file")
            })?;
            MotionWorld::load(py, path, None, None, true, Vec::new())?
        }
    };
    let request = MotionRequest {
        group,
        start: match start {
            Some(s) => state(s, "start")?,
            None => StateSpec::Joints(BTreeMap::new()),
        },
        goal: state(goal, "goal")?,
    };
    if !(time_limit.is_finite() && time_limit >= 0.0) {
        return Err(input_msg(format!(
            "time_limit {time_limit}: a number of seconds, 0 or more"
        )));
    }
    let options = MotionOptions {
        seed,
        time_limit: Duration::from_secs_f64(time_limit.min(1e9)),
        margin,
        shortcut_attempts,
        velocity_scaling,
        acceleration_scaling,
        sample_period,
        blend_tolerance,
    };
    let inner = world.inner.clone();
    let outcome = py
        .detach(|| pickplace::motion::plan_motion(&inner, &request, &options))
        .map_err(|e| facade(py, &e))?;
    match outcome {
        MotionOutcome::Planned(m) => Ok(Motion {
            inner: if timings { m } else { m.without_timings() },
        }),
        MotionOutcome::NoMotion(why) => {
            let text = format!("no motion: {why}");
            Err(no_plan(py, &text, &[why.to_string()], None))
        }
    }
}
