//! `pickplace.SceneView` and `pickplace.Playback`: what the browser view (`pickplace.web`)
//! draws and asks, computed from the set-up scene as the planner has it. The page only
//! presents: the robot's links are the setup's model (every robot of the scene, prefixed)
//! triangulated by `pickplace_view::RobotGeometry` and posed by its forward kinematics; a
//! click is a ray cast against the setup's environment with the workspace's one ray–triangle
//! test ([`line_triangle`]); a scene is saved as TOML serialised from the scene model and
//! written by [`write_atomic`]; a plan is played back from its holds ([`pickplace::Plan::holds`]).

use crate::convert::{MeshArrays, isometry, matrices, matrix4, mesh_arrays, vector};
use crate::errors::{input, input_msg};
use crate::plan::Plan;
use crate::scene::Scene;
use numpy::{PyArray1, PyArray2, PyArray3, ToPyArray};
use pickplace::Setup;
use pickplace::scene::PoseSpec;
use pickplace_geometry::export::write_atomic;
use pickplace_geometry::math::{Isometry3, Point3, Real, Vector3, line_triangle};
use pickplace_view::{RobotGeometry, RobotGeometryOptions};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Barycentric slack of the click's ray test: a ray through an edge shared by two triangles
/// hits one of them.
const EDGE_TOLERANCE: Real = 1e-9;

/// Nearest distance along the ray that counts as a hit (m): the origin's own surface is not.
const MIN_HIT_DISTANCE: Real = 1e-9;

/// The scene as the browser view shows it: the robot's link meshes and their poses at a
/// configuration, the object's mesh, the environment surface under a ray, the scene as a
/// scene file and saving it with a plan. `SceneView(scene)`; immutable.
#[pyclass(frozen, module = "pickplace")]
#[derive(Debug)]
pub struct SceneView {
    /// The set-up scene (shared with the `Scene` it was made from).
    setup: Arc<Setup>,
    /// Every link's shapes in its frame (visual, else collision).
    geometry: RobotGeometry,
    /// For each environment part, the cluster id of each of its triangles.
    cluster_of: Vec<Vec<Option<u32>>>,
}

/// The set-up scene of a `Scene`.
fn setup_of(scene: &Bound<'_, Scene>) -> Arc<Setup> {
    scene.get().setup.clone()
}

/// A point or vector of three finite numbers named `what` in errors.
fn xyz(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vector3> {
    let v = vector(obj, what)?;
    match v.as_slice() {
        [x, y, z] => Ok(Vector3::new(*x, *y, *z)),
        _ => Err(input_msg(format!(
            "{what}: expected 3 numbers, got {}",
            v.len()
        ))),
    }
}

/// A configuration of every variable of the setup's model (`Scene.joint_names` order).
fn configuration(setup: &Setup, q: &Bound<'_, PyAny>) -> PyResult<Vec<Real>> {
    let q = vector(q, "q")?;
    let expected = setup.model.variable_count();
    if q.len() != expected {
        return Err(input_msg(format!(
            "q: {} values for the {expected} joints of {} (Scene.joint_names)",
            q.len(),
            setup.scene_path.display()
        )));
    }
    Ok(q)
}

/// Every link's pose in the world at `q` (model order).
fn world_from_links(setup: &Setup, q: &[Real]) -> PyResult<Vec<Isometry3>> {
    let poses = setup.model.link_poses(q).map_err(|e| input(&e))?;
    Ok(poses.iter().map(|p| setup.world_from_root * p).collect())
}

/// `path` made absolute (canonical when it exists), `package://` URIs left as they are.
fn absolute(path: &mut PathBuf) {
    if path.to_string_lossy().starts_with("package://") {
        return;
    }
    if let Ok(p) = std::fs::canonicalize(&*path).or_else(|_| std::path::absolute(&*path)) {
        *path = p;
    }
}

/// Refuses to replace what is at `path` unless it is a regular file (or nothing): outputs
/// are renamed over their path, which would replace a symbolic link by a file.
fn check_output(path: &Path) -> PyResult<()> {
    let Ok(meta) = std::fs::symlink_metadata(path) else {
        return Ok(());
    };
    if meta.is_file() {
        return Ok(());
    }
    let kind = if meta.file_type().is_symlink() {
        "a symbolic link"
    } else {
        pickplace_geometry::io::path_kind(path).unwrap_or("not a regular file")
    };
    Err(input_msg(format!(
        "{}: is {kind}; the page writes regular files only (a symbolic link is not followed)",
        path.display()
    )))
}

#[pymethods]
impl SceneView {
    /// The view of a set-up scene (triangulates the robot's link shapes once).
    ///
    /// Raises InputError when a link's shape cannot be triangulated.
    #[new]
    fn new(scene: &Bound<'_, Scene>) -> PyResult<Self> {
        let setup = setup_of(scene);
        let geometry = RobotGeometry::new(&setup.model, &RobotGeometryOptions::default())
            .map_err(|e| input_msg(format!("{}: {}", setup.scene_path.display(), e)))?;
        let cluster_of = setup
            .environment
            .iter()
            .map(|part| {
                part.clustering
                    .cluster_of_triangles(part.mesh.triangles().len())
            })
            .collect();
        Ok(Self {
            setup,
            geometry,
            cluster_of,
        })
    }

    /// Every link of the scene's robots (all of them, with their prefixes), in model order:
    /// the rows of `link_poses`.
    #[getter]
    fn link_names(&self) -> Vec<String> {
        let links = self.setup.model.links();
        links.iter().map(|l| l.name.clone()).collect()
    }

    /// The links that have shapes, each as a dict: `link` (name), `index` (its row in
    /// `link_poses`), `vertices` (V, 3) and `faces` (F, 3) in the link frame (its visual
    /// shapes, else its collision shapes, URDF primitives triangulated) and `color` (r, g, b),
    /// 0–255.
    fn link_meshes<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let mut out = Vec::new();
        for index in 0..self.geometry.link_count() {
            let Some(geometry) = self.geometry.link_geometry(index) else {
                continue;
            };
            let d = PyDict::new(py);
            d.set_item("link", self.geometry.link_name(index))?;
            d.set_item("index", index)?;
            let (vertices, faces) = mesh_arrays(py, geometry.positions(), geometry.triangles())?;
            d.set_item("vertices", vertices)?;
            d.set_item("faces", faces)?;
            let c = self.geometry.link_colour(index);
            d.set_item("color", (c.r, c.g, c.b))?;
            out.push(d);
        }
        Ok(out)
    }

    /// Every link's pose in the world at configuration `q` (`Scene.joint_names` order, shape
    /// (J,)), shape (L, 4, 4) in `link_names` order: the robots' base poses times forward
    /// kinematics.
    ///
    /// Raises InputError for a `q` of the wrong length or with a non-finite value.
    fn link_poses<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray3<Real>>> {
        let q = configuration(&self.setup, q)?;
        Ok(matrices(py, &world_from_links(&self.setup, &q)?))
    }

    /// The object's mesh in its frame, as the planner has it: (vertices (V, 3), faces (F, 3)).
    fn object_mesh<'py>(&self, py: Python<'py>) -> PyResult<MeshArrays<'py>> {
        let mesh = &self.setup.object_mesh;
        mesh_arrays(py, mesh.vertices(), mesh.triangles())
    }

    /// The nearest environment surface the ray from `origin` along `direction` (world frame)
    /// meets, either side of a triangle: a dict with `part` (its name), `part_index` (its
    /// index in `Scene.environment_parts()`), `triangle` (in that part's `faces`), `cluster`
    /// (the id of its environment-contact cluster, or None), `point` (3,) and `distance` (m)
    /// along the ray; None when the ray meets nothing.
    ///
    /// Raises InputError for a zero or non-finite direction.
    fn cast_ray<'py>(
        &self,
        py: Python<'py>,
        origin: &Bound<'py, PyAny>,
        direction: &Bound<'py, PyAny>,
    ) -> PyResult<Option<Bound<'py, PyDict>>> {
        let origin = Point3::from(xyz(origin, "origin")?);
        let direction = xyz(direction, "direction")?;
        let length = direction.norm();
        if !(length > 0.0 && length.is_finite()) {
            return Err(input_msg("direction: must be a non-zero vector"));
        }
        let direction = direction / length;
        let mut nearest: Option<(usize, usize, Real)> = None;
        for (k, part) in self.setup.environment.iter().enumerate() {
            let o = part.world_from_mesh.inverse_transform_point(&origin);
            let d = part.world_from_mesh.inverse_transform_vector(&direction);
            let v = part.mesh.vertices();
            for (i, t) in part.mesh.triangles().iter().enumerate() {
                let [Some(a), Some(b), Some(c)] = t.map(|j| v.get(j as usize)) else {
                    continue;
                };
                let Some(s) = line_triangle(&o, &d, [a, b, c], EDGE_TOLERANCE) else {
                    continue;
                };
                if s > MIN_HIT_DISTANCE && nearest.is_none_or(|(_, _, best)| s < best) {
                    nearest = Some((k, i, s));
                }
            }
        }
        let Some((k, triangle, distance)) = nearest else {
            return Ok(None);
        };
        let point = origin + distance * direction;
        let d = PyDict::new(py);
        d.set_item("part", &self.setup.environment[k].name)?;
        d.set_item("part_index", k)?;
        d.set_item("triangle", triangle)?;
        d.set_item(
            "cluster",
            self.cluster_of[k].get(triangle).copied().flatten(),
        )?;
        d.set_item("point", [point.x, point.y, point.z].to_pyarray(py))?;
        d.set_item("distance", distance)?;
        Ok(Some(d))
    }

    /// The scene as a scene file (TOML, docs/scene-format.md), serialised from the scene
    /// model with its paths made absolute (so the file can be saved anywhere), with the
    /// given changes: the target point (3,), the object's start pose (4x4), the planner's
    /// seed and strategy. `pickplace.Scene.from_toml(text)` reads it back.
    ///
    /// Raises InputError for a bad value (a strategy name the planner does not know).
    #[pyo3(signature = (*, target=None, object_start=None, seed=None, strategy=None))]
    fn scene_toml(
        &self,
        target: Option<&Bound<'_, PyAny>>,
        object_start: Option<&Bound<'_, PyAny>>,
        seed: Option<u64>,
        strategy: Option<&str>,
    ) -> PyResult<String> {
        let mut scene = self.setup.scene.clone();
        if let Some(target) = target {
            let p = xyz(target, "target")?;
            scene.target.point = [p.x, p.y, p.z];
        }
        if let Some(pose) = object_start {
            scene.object.start_pose = PoseSpec::from_isometry(&isometry(pose, "object_start")?);
        }
        if let Some(seed) = seed {
            scene.planner.seed = seed;
        }
        if let Some(name) = strategy {
            scene.planner.strategy = crate::plan::strategy(name)?;
        }
        for robot in &mut scene.robots {
            absolute(&mut robot.urdf);
            let files = [&mut robot.srdf, &mut robot.gripper, &mut robot.joint_limits];
            files.into_iter().flatten().for_each(absolute);
            robot.package_dirs.iter_mut().for_each(absolute);
        }
        absolute(&mut scene.object.mesh);
        scene
            .environment
            .iter_mut()
            .filter_map(|e| e.mesh.as_mut())
            .for_each(absolute);
        toml::to_string(&scene).map_err(|e| {
            input_msg(format!(
                "{}: cannot be written as TOML: {e}",
                self.setup.scene_path.display()
            ))
        })
    }

    /// Writes FOLDER/plan.json (`plan.to_json()`) and FOLDER/scene.toml (`scene_toml()`),
    /// creating the folder, each file atomically (a temporary file renamed over it); returns
    /// the two paths. `pickplace plan FOLDER/scene.toml` plans the same plan.
    ///
    /// Raises InputError, before writing anything, when either path is a symbolic link, a
    /// folder or not a regular file; and when the folder cannot be created or a file
    /// written (naming it).
    fn save(&self, folder: PathBuf, plan: &Bound<'_, Plan>) -> PyResult<Vec<PathBuf>> {
        let scene = self.scene_toml(None, None, None, None)?;
        let plan = plan.borrow().inner.to_json();
        std::fs::create_dir_all(&folder).map_err(|e| {
            input_msg(format!(
                "{}: cannot create the folder: {e}",
                folder.display()
            ))
        })?;
        let files = [
            (folder.join("plan.json"), plan),
            (folder.join("scene.toml"), scene),
        ];
        for (path, _) in &files {
            check_output(path)?;
        }
        for (path, text) in &files {
            write_atomic(path, text.as_bytes()).map_err(|e| input(&e))?;
        }
        Ok(files.into_iter().map(|(path, _)| path).collect())
    }

    fn __repr__(&self) -> String {
        format!(
            "SceneView({:?}, {} links, {} environment parts)",
            self.setup.scene_path.display().to_string(),
            self.geometry.link_count(),
            self.setup.environment.len()
        )
    }
}

/// A plan's scene at a time: the configuration (J,), every link's world pose (L, 4, 4) and
/// the object's world pose (4, 4).
type SceneAt<'py> = (
    Bound<'py, PyArray1<Real>>,
    Bound<'py, PyArray3<Real>>,
    Bound<'py, PyArray2<Real>>,
);

/// A hold of the plan on a link of the setup's model.
#[derive(Debug)]
struct LinkHold {
    /// The holding link (model index).
    link: usize,
    /// The object in that link's frame.
    link_from_object: Isometry3,
    /// When the grasp happens (s).
    grasp_time: Real,
    /// When the release happens (s), if it does.
    release_time: Option<Real>,
    /// Where the object rests after the release.
    released_at: Isometry3,
}

/// A plan made ready to show in its scene: the robot's configuration, every link's pose and
/// the object's pose at any time. `Playback(scene, plan)`; immutable.
#[pyclass(frozen, module = "pickplace")]
#[derive(Debug)]
pub struct Playback {
    /// The set-up scene.
    setup: Arc<Setup>,
    /// Sample times (s).
    times: Vec<Real>,
    /// One configuration per sample, in the model's variable order.
    positions: Vec<Vec<Real>>,
    /// The plan's holds, in time order of their grasps.
    holds: Vec<LinkHold>,
    /// The object's pose before the first grasp.
    object_start: Isometry3,
}

impl Playback {
    /// The configuration at time `t`: linear between samples, the first before the start,
    /// the last after the end.
    fn configuration_at(&self, t: Real) -> Vec<Real> {
        let k = self.times.partition_point(|&s| s <= t).saturating_sub(1);
        let (Some(q0), Some(&t0)) = (self.positions.get(k), self.times.get(k)) else {
            return Vec::new();
        };
        match (self.positions.get(k + 1), self.times.get(k + 1)) {
            (Some(q1), Some(&t1)) if t1 > t0 => {
                let a = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
                q0.iter().zip(q1).map(|(x, y)| x + a * (y - x)).collect()
            }
            _ => q0.clone(),
        }
    }

    /// The object's pose at `t` with the links at `world_from_links`: carried by the hold
    /// grasped last among those holding at `t` (a handover has two), else resting where the
    /// last release left it, else at its start.
    fn object_at(&self, t: Real, world_from_links: &[Isometry3]) -> Isometry3 {
        let holding = self
            .holds
            .iter()
            .filter(|h| h.grasp_time <= t && h.release_time.is_none_or(|r| t <= r))
            .max_by(|a, b| a.grasp_time.total_cmp(&b.grasp_time));
        if let Some(h) = holding
            && let Some(link) = world_from_links.get(h.link)
        {
            return link * h.link_from_object;
        }
        self.holds
            .iter()
            .filter_map(|h| h.release_time.filter(|&r| r <= t).map(|r| (r, h)))
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .map_or(self.object_start, |(_, h)| h.released_at)
    }
}

#[pymethods]
impl Playback {
    /// The plan in the scene it was planned for (its joints must be the scene's
    /// `joint_names`, its holding links the scene's robots' links).
    ///
    /// Raises InputError naming what does not match.
    #[new]
    fn new(scene: &Bound<'_, Scene>, plan: &Bound<'_, Plan>) -> PyResult<Self> {
        let setup = setup_of(scene);
        let plan = &plan.borrow().inner;
        let scene_path = setup.scene_path.display().to_string();
        let mismatch = |what: String| input_msg(format!("plan for {scene_path}: {what}"));
        let names: Vec<&str> = setup.model.variable_names().collect();
        let columns = plan.columns(&names).map_err(|e| {
            mismatch(format!(
                "its joints are not the scene's robots' joints: {e}"
            ))
        })?;
        let times: Vec<Real> = plan.trajectory.iter().map(|p| p.time_from_start).collect();
        if times.is_empty() {
            return Err(mismatch("it has no trajectory sample".into()));
        }
        let positions: Vec<Vec<Real>> = plan
            .trajectory
            .iter()
            .map(|p| {
                columns
                    .iter()
                    .filter_map(|&c| p.positions.get(c).copied())
                    .collect()
            })
            .collect();
        let object_start = plan
            .object
            .start_pose
            .to_isometry()
            .map_err(|e| mismatch(format!("object.start_pose: {e}")))?;
        let mut playback = Self {
            setup: setup.clone(),
            times,
            positions,
            holds: Vec::new(),
            object_start,
        };
        let holds = plan.holds().map_err(|e| mismatch(e.to_string()))?;
        for h in holds {
            let link = setup.model.link_index(&h.link).ok_or_else(|| {
                mismatch(format!(
                    "grasp at {} s: the scene's robots have no link {:?}",
                    h.grasp_time, h.link
                ))
            })?;
            let released_at = match h.release_time {
                Some(r) => {
                    let links = world_from_links(&setup, &playback.configuration_at(r))?;
                    links
                        .get(link)
                        .map_or(object_start, |l| l * h.link_from_object)
                }
                None => object_start,
            };
            playback.holds.push(LinkHold {
                link,
                link_from_object: h.link_from_object,
                grasp_time: h.grasp_time,
                release_time: h.release_time,
                released_at,
            });
        }
        Ok(playback)
    }

    /// The sample times (s), shape (N,).
    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<Real>> {
        self.times.to_pyarray(py)
    }

    /// The time of the last sample (s).
    #[getter]
    fn duration(&self) -> Real {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// The scene at time `t` (s): (q (J,) in `Scene.joint_names` order, linear between
    /// samples; every link's world pose (L, 4, 4) in `SceneView.link_names` order; the
    /// object's world pose (4, 4), riding on the holding link between grasp and release).
    fn at<'py>(&self, py: Python<'py>, t: Real) -> PyResult<SceneAt<'py>> {
        if !t.is_finite() {
            return Err(input_msg(format!("t = {t} is not finite")));
        }
        let q = self.configuration_at(t);
        let links = world_from_links(&self.setup, &q)?;
        let object = self.object_at(t, &links);
        Ok((q.to_pyarray(py), matrices(py, &links), matrix4(py, &object)))
    }

    fn __repr__(&self) -> String {
        format!(
            "Playback({:?}, {} samples, {:.2} s)",
            self.setup.scene_path.display().to_string(),
            self.times.len(),
            self.duration()
        )
    }
}
