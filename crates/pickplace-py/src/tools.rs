//! `pickplace.clusters`, `pickplace.placements` and `pickplace.grasps`: the stages of the
//! paper as the CLI commands of the same names run them; each returns the CLI's `--json`
//! document as Python dicts and lists.

use crate::convert::{isometry, to_python, vector};
use crate::errors::{input_msg, message};
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_geometry::db::ClusterDatabase;
use pickplace_geometry::math::{Isometry3, Point3, Real};
use pickplace_geometry::mesh::{self, MassProperties, MeshOptions, TriMesh};
use pickplace_grasp::json::GraspsJson;
use pickplace_grasp::{GraspOptions, GraspPlanner, GripperParams};
use pickplace_placement::json::PlacementsJson;
use pickplace_placement::{
    EnvironmentModel, ObjectModel, PlacementOptions, RestingOptions, candidates, default_target,
    resting_poses,
};
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// A mesh file scaled by `scale`, with the library's message (naming the file) on failure.
fn load_mesh(path: &Path, scale: Real) -> PyResult<TriMesh> {
    let options = MeshOptions {
        scale,
        ..MeshOptions::default()
    };
    mesh::load(path, &options).map_err(|e| input_msg(message(&e)))
}

/// `scale` in the CLI's `--scale` range ([`pickplace::ranges::MESH_SCALE`]).
fn check_scale(scale: Real) -> PyResult<()> {
    pickplace::ranges::MESH_SCALE
        .check(scale)
        .map_err(|e| input_msg(format!("scale: {e}")))
}

/// `h_max` in the CLI's `--h-max` range ([`pickplace::ranges::H_MAX`]).
fn check_h_max(h_max: Real) -> PyResult<()> {
    pickplace::ranges::H_MAX
        .check(h_max)
        .map_err(|e| input_msg(format!("h_max: {e}")))
}

/// Clusters a mesh's surface into planar contact regions (the paper's §III-A, Algorithm 1),
/// as `pickplace clusters MESH --json`: `mode` is "env" (object–environment contact, h_max
/// 0.001 m by default) or "finger" (finger contact, h_max 0.005 m, with parallel `pairs`).
///
/// Returns the `pickplace.clusters/1` document (dict). Raises InputError for an unreadable
/// mesh or invalid parameters.
#[pyfunction]
#[pyo3(signature = (mesh, *, mode="env", h_max=None, scale=1.0))]
pub fn clusters<'py>(
    py: Python<'py>,
    mesh: PathBuf,
    mode: &str,
    h_max: Option<Real>,
    scale: Real,
) -> PyResult<Bound<'py, PyAny>> {
    let mut params = match mode {
        "env" => ClusterParams::environment(),
        "finger" => ClusterParams::finger(),
        other => {
            return Err(input_msg(format!(
                "mode {other:?} is not one of env, finger"
            )));
        }
    };
    if let Some(h) = h_max {
        check_h_max(h)?;
        params.h_max = h;
    }
    params
        .validate()
        .map_err(|e| input_msg(format!("h_max: {}", message(&e))))?;
    check_scale(scale)?;
    let doc = py.detach(|| -> PyResult<_> {
        let m = load_mesh(&mesh, scale)?;
        let db = ClusterDatabase::build(&m, &params).map_err(|e| input_msg(message(&e)))?;
        Ok(db.to_json(&m, &mesh.to_string_lossy()))
    })?;
    to_python(py, &doc)
}

/// Stable placements of an object (the paper's §III-B.2, Algorithm 2), as `pickplace
/// placements OBJECT --json`: on the mesh `on` (posed by `env_pose`, a 4x4 matrix, default
/// identity) near `target` (3 values, world frame; default the centre of its largest
/// upward-facing cluster), best first, at most `max`; without `on`, the object's resting
/// poses on a horizontal plane.
///
/// Returns the `pickplace.placements/1` document (dict). Raises InputError for unreadable
/// meshes or invalid values.
#[pyfunction]
#[pyo3(signature = (object, *, on=None, env_pose=None, target=None, scale=1.0, h_max=0.001, max=32))]
#[allow(clippy::too_many_arguments)]
pub fn placements<'py>(
    py: Python<'py>,
    object: PathBuf,
    on: Option<PathBuf>,
    env_pose: Option<&Bound<'py, PyAny>>,
    target: Option<&Bound<'py, PyAny>>,
    scale: Real,
    h_max: Real,
    max: usize,
) -> PyResult<Bound<'py, PyAny>> {
    check_scale(scale)?;
    check_h_max(h_max)?;
    if on.is_none() && (env_pose.is_some() || target.is_some()) {
        return Err(input_msg(
            "env_pose and target need an environment mesh (on=...)",
        ));
    }
    let world_from_env = match env_pose {
        Some(p) => isometry(p, "env_pose")?,
        None => Isometry3::identity(),
    };
    let target = target
        .map(|t| -> PyResult<Point3> {
            let v = vector(t, "target")?;
            if v.len() != 3 {
                return Err(input_msg(format!("target: {} values, expected 3", v.len())));
            }
            Ok(Point3::new(v[0], v[1], v[2]))
        })
        .transpose()?;
    let doc = py.detach(|| -> PyResult<PlacementsJson> {
        let object_mesh = load_mesh(&object, scale)?;
        let cog = MassProperties::of(&object_mesh).center_of_mass;
        let object_name = object.display().to_string();
        let Some(env_path) = &on else {
            let poses = resting_poses(&object_mesh, &cog, &RestingOptions::default())
                .map_err(|e| input_msg(format!("{object_name}: resting poses: {}", message(&e))))?;
            return Ok(PlacementsJson::from_resting(object_name, &poses, max));
        };
        let env_mesh = load_mesh(env_path, scale)?;
        let params = ClusterParams {
            h_max,
            ..ClusterParams::environment()
        };
        let object_clusters = cluster_surface(&object_mesh, &params)
            .map_err(|e| input_msg(format!("{object_name}: clustering: {}", message(&e))))?;
        let env_clusters = cluster_surface(&env_mesh, &params).map_err(|e| {
            input_msg(format!(
                "{}: clustering: {}",
                env_path.display(),
                message(&e)
            ))
        })?;
        let object_model = ObjectModel::new(&object_mesh, &object_clusters, cog)
            .map_err(|e| input_msg(message(&e)))?;
        let env = EnvironmentModel::new(&env_mesh, &env_clusters, &world_from_env)
            .map_err(|e| input_msg(message(&e)))?;
        let options = PlacementOptions {
            max_candidates: max,
            ..PlacementOptions::default()
        };
        let target = match target {
            Some(t) => t,
            None => default_target(&env, &options).ok_or_else(|| {
                input_msg(format!(
                    "{}: no upward-facing cluster to place on",
                    env_path.display()
                ))
            })?,
        };
        let set = candidates(&object_model, &env, &target, &options)
            .map_err(|e| input_msg(format!("{}: {e}", env_path.display())))?;
        Ok(PlacementsJson::from_set(
            object_name,
            env_path.display().to_string(),
            &target,
            &set,
        ))
    })?;
    to_python(py, &doc)
}

/// Parallel-gripper grasps of an object (the paper's §III-B.1), as `pickplace grasps MESH
/// --robot ROBOT --json`: `robot` is a robot folder (its `gripper.toml` is read) or a gripper
/// file. Options left at None take the CLI's defaults.
///
/// Returns the `pickplace.grasps/1` document (dict; `grasps` ranked best first, possibly
/// empty). Raises InputError for unreadable files or invalid values.
#[pyfunction]
#[pyo3(signature = (mesh, robot, *, h_max=None, grid_step=None, approaches=None, clearance=None))]
pub fn grasps<'py>(
    py: Python<'py>,
    mesh: PathBuf,
    robot: PathBuf,
    h_max: Option<Real>,
    grid_step: Option<Real>,
    approaches: Option<usize>,
    clearance: Option<Real>,
) -> PyResult<Bound<'py, PyAny>> {
    use pickplace::ranges::{APPROACHES, CLEARANCE, GRID_STEP, Range};
    let check = |name: &str, value: Option<Real>, range: Range| {
        value.map_or(Ok(()), |v| {
            range
                .check(v)
                .map_err(|e| input_msg(format!("{name}: {e}")))
        })
    };
    check("grid_step", grid_step, GRID_STEP)?;
    check("clearance", clearance, CLEARANCE)?;
    check("approaches", approaches.map(|a| a as Real), APPROACHES)?;
    if let Some(h) = h_max {
        check_h_max(h)?;
    }
    let defaults = GraspOptions::default();
    let options = GraspOptions {
        grid_step: grid_step.unwrap_or(defaults.grid_step),
        approach_count: approaches.unwrap_or(defaults.approach_count),
        clearance: clearance.unwrap_or(defaults.clearance),
        ..defaults
    };
    let params = ClusterParams {
        h_max: h_max.unwrap_or(ClusterParams::finger().h_max),
        ..ClusterParams::finger()
    };
    let doc = py.detach(|| -> PyResult<GraspsJson> {
        let gripper_file = if robot.is_dir() {
            robot.join("gripper.toml")
        } else {
            robot.clone()
        };
        let gripper = GripperParams::load(&gripper_file).map_err(|e| input_msg(message(&e)))?;
        let m = load_mesh(&mesh, 1.0)?;
        let clustering = cluster_surface(&m, &params)
            .map_err(|e| input_msg(format!("h_max: {}", message(&e))))?;
        let planner = GraspPlanner::new(&m)
            .map_err(|e| input_msg(format!("{}: {}", mesh.display(), message(&e))))?;
        let set = planner
            .plan(&clustering, &gripper, &options)
            .map_err(|e| input_msg(message(&e)))?;
        Ok(GraspsJson::new(
            &mesh.display().to_string(),
            &gripper_file.display().to_string(),
            params.h_max,
            &planner.center_of_mass(),
            &set,
        ))
    })?;
    to_python(py, &doc)
}
