//! Everything the online planner needs, loaded once per scene: the robot and its arms (IK,
//! roadmaps), the object and the environment with their cluster databases (paper §III-A, the
//! offline phase), and the collision world.
//!
//! Cluster databases and roadmaps are read from a cache folder when one is given and valid,
//! and built (then written there) otherwise, so the first plan of a scene is slower than the
//! next ones. The cache is an accelerator, never a requirement ([`crate::cache`]): a folder
//! that cannot be written gives one warning in [`Setup::warnings`] and the same setup, made in
//! memory. Long work (clustering a mesh, building a roadmap) is reported to
//! [`SetupOptions::progress`].

use crate::error::{Error, Result};
use crate::scene::Scene;
use crate::strategy::Arm;
use cache::{Cache, CacheWarning};
use pickplace_geometry::cluster::{ClusterParams, Clustering};
use pickplace_geometry::db::{CacheStatus, ClusterDatabase, cache_path};
use pickplace_geometry::hash::mesh_hash;
use pickplace_geometry::math::{Isometry3, Point3, Real};
use pickplace_geometry::mesh::{MassProperties, MeshOptions, TriMesh};
use pickplace_grasp::collide::ObjectCollider;
use pickplace_grasp::{GraspOptions, GraspPlanner, GraspSet, GripperParams};
use pickplace_placement::collide::CollisionMesh;
use pickplace_placement::{EnvironmentModel, ObjectModel};
use pickplace_prm::{JointSpace, Roadmap};
use pickplace_robot::collision::{CollisionShape, CollisionWorld};
use pickplace_robot::gripper::Gripper;
use pickplace_robot::{IkSolver, RobotModel, Semantics};
use reach::ReachMap;
use roadmaps::{RoadmapEntry, RoadmapReport};
use robot_setup::{RobotArm, RobotSetup, robot_err};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

pub mod cache;
pub mod checker;
pub(crate) mod collision_matrix;
pub(crate) mod hand_fit;
pub mod joint_limits;
pub mod mesh_warning;
pub mod obstacle;
pub mod precompute;
mod purpose;
pub mod reach;
pub mod roadmaps;
pub mod robot_setup;
pub(crate) mod robot_state;
mod stages;
#[cfg(test)]
mod tests;
pub mod tool_frame;

pub use purpose::SetupPurpose;
use purpose::{no_clusters, no_grasps};
pub(crate) use stages::load_mesh;
use stages::{arm_setup, clusters, grasps, missing_arm, ms};

/// How far one stage of long setup work got, for a progress bar.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SetupProgress<'a> {
    /// What is done, e.g. `clustering object.mesh (finger)` or `roadmap right_arm`.
    pub stage: &'a str,
    /// Units done, from 0 to `total`.
    pub done: usize,
    /// Units in all; every stage ends with a report where `done == total`.
    pub total: usize,
}

/// Receives [`SetupProgress`] reports, possibly from several threads at once (a roadmap is
/// built on rayon's pool); within a stage, `done` may arrive out of order.
pub type ProgressFn = Arc<dyn Fn(SetupProgress<'_>) + Send + Sync>;

/// Options of [`Setup::load`].
#[derive(Clone, Default)]
pub struct SetupOptions {
    /// Folder of cluster databases and roadmaps (default: none, everything is built in
    /// memory). The CLI passes `$PICKPLACE_CACHE`, else `$XDG_CACHE_HOME/pickplace`, else
    /// `~/.cache/pickplace` ([`crate::cache::default_dir`]).
    pub cache_dir: Option<PathBuf>,
    /// Folders searched for `package://` mesh paths after the scene's own (the CLI's
    /// `--package-dir`); `ROS_PACKAGE_PATH` comes last.
    pub package_dirs: Vec<PathBuf>,
    /// Told how far clustering a mesh and building a roadmap got (default: none). Only work
    /// done now is reported, not what comes from the cache.
    pub progress: Option<ProgressFn>,
}

impl std::fmt::Debug for SetupOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SetupOptions")
            .field("cache_dir", &self.cache_dir)
            .field("package_dirs", &self.package_dirs)
            .field("progress", &self.progress.as_ref().map(|_| "Fn"))
            .finish()
    }
}

impl SetupOptions {
    /// Tells [`SetupOptions::progress`] that `stage` did `done` of `total`.
    fn report(&self, stage: &str, done: usize, total: usize) {
        if let Some(progress) = &self.progress {
            progress(SetupProgress { stage, done, total });
        }
    }
}

/// One arm of the robot as the planner uses it.
#[derive(Debug)]
pub struct ArmSetup {
    /// Which arm.
    pub arm: Arm,
    /// Its SRDF group.
    pub group: String,
    /// IK of the group's chain (root frame to the TCP link).
    pub ik: IkSolver,
    /// The group's variables (model order).
    pub variables: Vec<usize>,
    /// The group's joint space (the PRM's).
    pub space: JointSpace,
    /// The precomputed roadmap (no node in a [`SetupPurpose::Validation`] setup).
    pub roadmap: Roadmap,
    /// Whether the roadmap came from the cache, its size, what rejected most samples.
    pub roadmap_report: RoadmapReport,
    /// The tool link: added at the gripper's tool point (midway between the pads).
    pub tcp_link: usize,
    /// Its name.
    pub tcp_name: String,
    /// The gripper, measured on the URDF: its drives, fingers, opening and closing command.
    pub gripper: Gripper,
    /// The gripper's actuated variables (its drives; mimic joints follow them).
    pub finger_variables: Vec<usize>,
    /// Links of the hand (they may touch an object the hand closes on or opens from).
    pub finger_links: Vec<String>,
    /// The links carrying the finger pads ([`Gripper::pad_links`]): the only links of the
    /// hand that may touch a held object, and press into it by the squeeze at most.
    pub pad_links: Vec<String>,
    /// The arm's base (its first joint's position), world frame: the paper's "which hand is
    /// closer" is measured from here.
    pub shoulder: Point3,
    /// Largest distance from the shoulder the TCP reaches (m), measured by sampling.
    pub reach: Real,
    /// Where the tool point gets to with which approach direction (root frame): the order
    /// in which grasps are tried (empty in a [`SetupPurpose::Validation`] setup).
    pub reach_map: ReachMap,
}

/// An environment mesh of the scene.
#[derive(Debug)]
pub struct EnvironmentPart {
    /// Its scene name.
    pub name: String,
    /// The mesh, in its own frame.
    pub mesh: TriMesh,
    /// Its environment-contact clusters (none in a [`SetupPurpose::Validation`] setup).
    pub clustering: Clustering,
    /// Its pose.
    pub world_from_mesh: Isometry3,
    /// Its triangles in the world frame, for gripper-only collision tests (`None` in a
    /// [`SetupPurpose::Validation`] setup).
    pub collider: Option<ObjectCollider>,
    /// The world-frame box of its vertices `(lower, upper)`.
    pub world_box: (Point3, Point3),
    /// Its triangles (world frame) with their BVH for the support rule, built on first use
    /// ([`EnvironmentPart::contact_mesh`]).
    contact_mesh: std::sync::OnceLock<CollisionMesh>,
}

impl EnvironmentPart {
    /// The part's triangles in the world frame with their BVH, for contact queries
    /// ([`crate::contact::supports`]), built the first time they are needed and kept: a part
    /// no query comes near costs nothing, and one the object is placed on many times is
    /// built once.
    ///
    /// # Errors
    /// [`Error::Internal`] when the collision library refuses the mesh (which loading
    /// accepted).
    pub fn contact_mesh(&self) -> Result<&CollisionMesh> {
        if let Some(mesh) = self.contact_mesh.get() {
            return Ok(mesh);
        }
        let mesh = CollisionMesh::from_meshes(&[(&self.mesh, self.world_from_mesh)])
            .map_err(crate::error::internal("environment contact mesh"))?;
        Ok(self.contact_mesh.get_or_init(|| mesh))
    }

    /// Whether [`EnvironmentPart::contact_mesh`] was built (for tests of what queries cost).
    pub fn has_contact_mesh(&self) -> bool {
        self.contact_mesh.get().is_some()
    }
}

/// A scene ready for planning.
#[derive(Debug)]
pub struct Setup {
    /// What it was made for, and so what it holds.
    pub purpose: SetupPurpose,
    /// The scene file's path (for messages).
    pub scene_path: PathBuf,
    /// The scene.
    pub scene: Scene,
    /// The robot.
    pub model: RobotModel,
    /// Its SRDF.
    pub semantics: Semantics,
    /// The grasp planner's gripper model (the right arm's, or the one arm's; grasps are
    /// planned once for both hands).
    pub gripper: GripperParams,
    /// `world_from_root` of the robot.
    pub world_from_root: Isometry3,
    /// The start configuration (every variable).
    pub start: Vec<Real>,
    /// The arms the robot has: right then left, or its one arm. Never empty.
    pub arms: Vec<ArmSetup>,
    /// The object's mesh (object frame).
    pub object_mesh: TriMesh,
    /// The object's environment-contact clusters.
    pub object_env: Clustering,
    /// The object's finger-contact clusters and pairs (none in a
    /// [`SetupPurpose::Validation`] setup).
    pub object_finger: Clustering,
    /// The object's grasps for [`Setup::gripper`] (§III-B.1, default
    /// [`pickplace_grasp::GraspOptions`]), ranked; read from the cache when planned before
    /// (none in a [`SetupPurpose::Validation`] setup).
    pub grasp_set: GraspSet,
    /// Its centre of gravity (object frame).
    pub cog: Point3,
    /// `world_from_object` at the start.
    pub object_start: Isometry3,
    /// The object as the placement planner sees it.
    pub placement_object: ObjectModel,
    /// The environment as the placement planner sees it (regions of every mesh).
    pub placement_env: EnvironmentModel,
    /// The environment meshes.
    pub environment: Vec<EnvironmentPart>,
    /// The object's collision shape.
    pub object_shape: CollisionShape,
    /// Robot and environment (no object).
    pub world: CollisionWorld,
    /// Each variable's timing limits (model order), unscaled: velocity from the URDF or a
    /// joint-limits table, acceleration from a table or `trajectory.max_acceleration`.
    pub timing: Vec<crate::joint_limits::TimingLimit>,
    /// The default velocity and acceleration scaling factors: the scene's `[trajectory]`,
    /// else the joint-limits file's defaults, else 1.
    pub scaling: (Real, Real),
    /// What loading did (cache hits, builds, times), one line each.
    pub log: Vec<String>,
    /// Why the cache could not be used, or only in part (at most one warning: the setup went
    /// on in memory, with the same result). For the caller to show; the library prints nothing.
    pub warnings: Vec<CacheWarning>,
    /// Grasps of the grasp set dropped because the robot's hand, closed on the object, puts
    /// a link other than its pads into it, by link name (`crate::hand_fit`).
    pub grasp_hand_rejections: BTreeMap<String, usize>,
    /// What the robot's files got wrong and loading went on from
    /// ([`RobotSetup::warnings`]). For the caller to show; plans carry them.
    pub robot_warnings: Vec<String>,
    /// What the scene's meshes look like they got wrong (stored twice, in millimetres): the
    /// setup went on. For the caller to show.
    pub mesh_warnings: Vec<crate::mesh_warning::MeshWarning>,
    /// The object as the fingers' gaps are measured against it ([`Setup::grip_object`]), made
    /// once on first use: every plan's validation needs it, and a scanned mesh's takes
    /// milliseconds to build.
    grip_object: std::sync::OnceLock<pickplace_robot::gripper::GripObject>,
}

impl Setup {
    /// Reads a scene file and sets it up.
    ///
    /// # Errors
    /// As [`Setup::new`], and [`Error::Scene`] for the file itself.
    pub fn load(path: &Path, options: &SetupOptions) -> Result<Self> {
        let scene = Scene::load(path)?;
        Self::new(scene, path, options)
    }

    /// Sets up a parsed scene; `scene_path` names it in errors.
    ///
    /// # Errors
    /// [`Error::Robot`], [`Error::Gripper`], [`Error::Mesh`] naming the file at fault;
    /// [`Error::Invalid`] for a start state or arm group that does not fit the robot, or an
    /// object start pose in collision. A cache that cannot be used is not an error
    /// ([`Setup::warnings`]).
    pub fn new(scene: Scene, scene_path: &Path, options: &SetupOptions) -> Result<Self> {
        Self::build(scene, scene_path, options, SetupPurpose::Planning)
    }

    /// Reads a scene file and sets up only what [`crate::validate::validate`] reads
    /// ([`SetupPurpose::Validation`]): no clustering of the environment, no grasps, no
    /// roadmaps, so that validating a plan costs what the validator checks, not what the
    /// planner needed.
    ///
    /// # Errors
    /// As [`Setup::load`].
    pub fn load_for_validation(path: &Path, options: &SetupOptions) -> Result<Self> {
        let scene = Scene::load(path)?;
        Self::new_for_validation(scene, path, options)
    }

    /// [`Setup::load_for_validation`] of a parsed scene; `scene_path` names it in errors.
    ///
    /// # Errors
    /// As [`Setup::new`].
    pub fn new_for_validation(
        scene: Scene,
        scene_path: &Path,
        options: &SetupOptions,
    ) -> Result<Self> {
        Self::build(scene, scene_path, options, SetupPurpose::Validation)
    }

    fn build(
        scene: Scene,
        scene_path: &Path,
        options: &SetupOptions,
        purpose: SetupPurpose,
    ) -> Result<Self> {
        let planning = purpose == SetupPurpose::Planning;
        let mut log = Vec::new();
        let invalid = |field: &str, reason: String| Error::Invalid {
            path: scene_path.to_path_buf(),
            field: field.to_owned(),
            reason,
        };
        let t = Instant::now();
        let robot = RobotSetup::load(&scene, scene_path, &options.package_dirs)?;
        log.extend(robot.notes.iter().cloned());
        let robot_warnings = robot.warnings.clone();
        let timing = robot.timing.clone();
        let scaling = robot.scaling(&scene.trajectory);
        let model = robot.model.clone();
        let semantics = robot.semantics.clone();
        let world_from_root = robot.world_from_root;
        let urdf_path = robot.urdf_path.clone();
        let gripper = robot.arms[0].gripper_params;

        let start = robot_state::start_configuration(&scene, &robot, scene_path)?;
        if let Some(strategy_arms) = missing_arm(&scene, &robot) {
            return Err(invalid("planner.strategy", strategy_arms));
        }
        log.push(format!(
            "robot {:?}: {} links, {} joints ({} actuated), {} arm(s) in {:.1} ms",
            model.name(),
            model.links().len(),
            model.joints().len(),
            model.variable_count(),
            robot.arms.len(),
            ms(t)
        ));
        for a in &robot.arms {
            let (lo, hi) = a.gripper.opening_range();
            log.push(format!(
                "{} arm ({}): {} joints, gripper opening {:.1}-{:.1} mm, tool link {:?}",
                a.arm,
                a.group,
                a.variables.len(),
                lo * 1e3,
                hi * 1e3,
                a.tcp_name
            ));
        }

        // The collision world: robot, SRDF's disabled pairs (else sampled), environment meshes.
        let mut cache = Cache::open(options.cache_dir.as_deref());
        let self_world = robot_state::self_world(
            &robot,
            &start,
            &scene.collision_matrix,
            &mut cache,
            &mut log,
        )?;
        let mut world = self_world.clone();

        // Environment meshes and their clusters.
        let env_params = ClusterParams {
            h_max: scene.planner.h_max_environment,
            ..ClusterParams::environment()
        };
        let finger_params = ClusterParams {
            h_max: scene.planner.h_max_finger,
            ..ClusterParams::finger()
        };
        let mut mesh_warnings = Vec::new();
        let mut environment = Vec::new();
        for (i, env) in scene.environment.iter().enumerate() {
            let what = format!("environment[{i}] {:?}", env.name);
            let body =
                crate::obstacle::load_environment(env, &format!("environment[{i}]"), scene_path)?;
            let mesh = body.mesh;
            if body.from_file {
                mesh_warnings.extend(crate::mesh_warning::check(
                    &mesh,
                    &what,
                    &body.cache_name,
                    None,
                ));
            }
            let clustering = if planning {
                clusters(
                    &mesh,
                    &body.cache_name,
                    &env_params,
                    &mut cache,
                    &what,
                    options,
                    &mut log,
                )?
            } else {
                no_clusters(&env_params)
            };
            let world_from_mesh = body.world_from_mesh;
            world.add_environment(&env.name, body.shape, &body.world_from_shape);
            let collider = if planning {
                Some(
                    ObjectCollider::new(&mesh.transformed(&world_from_mesh)).map_err(|source| {
                        Error::Gripper {
                            source: Box::new(source),
                        }
                    })?,
                )
            } else {
                None
            };
            let world_box = mesh.vertices().iter().fold(
                (
                    Point3::from([Real::INFINITY; 3]),
                    Point3::from([Real::NEG_INFINITY; 3]),
                ),
                |(lo, hi), v| {
                    let p = world_from_mesh * v;
                    (lo.inf(&p), hi.sup(&p))
                },
            );
            environment.push(EnvironmentPart {
                name: env.name.clone(),
                mesh,
                clustering,
                world_from_mesh,
                collider,
                world_box,
                contact_mesh: std::sync::OnceLock::new(),
            });
        }

        // The object.
        let object_mesh = load_mesh(&scene.object.mesh, scene.object.scale, "object.mesh")?;
        mesh_warnings.extend(crate::mesh_warning::check(
            &object_mesh,
            "object.mesh",
            &scene.object.mesh,
            Some("object.scale"),
        ));
        let cog = scene
            .object
            .center_of_gravity
            .map(Point3::from)
            .unwrap_or_else(|| MassProperties::of(&object_mesh).center_of_mass);
        let object_start = scene
            .object
            .start_pose
            .to_isometry()
            .map_err(|r| invalid("object.start_pose", r.into()))?;
        // The object's two clusterings at once (two cores): environment contact with the
        // placement model on one side, finger contact with the grasp set on the other. Each side
        // keeps a log and cache warnings of its own, joined in the sequential order after.
        let mut finger_cache = cache.fork();
        let mut finger_log = Vec::new();
        let (env_side, finger_side) = rayon::join(
            || -> Result<(Clustering, ObjectModel)> {
                let object_env = clusters(
                    &object_mesh,
                    &scene.object.mesh,
                    &env_params,
                    &mut cache,
                    "object.mesh",
                    options,
                    &mut log,
                )?;
                let placement_object = ObjectModel::new(&object_mesh, &object_env, cog)
                    .map_err(crate::error::internal("placement object model"))?;
                Ok((object_env, placement_object))
            },
            || -> Result<(Clustering, GraspSet)> {
                if !planning {
                    return Ok((no_clusters(&finger_params), no_grasps()));
                }
                let object_finger = clusters(
                    &object_mesh,
                    &scene.object.mesh,
                    &finger_params,
                    &mut finger_cache,
                    "object.mesh",
                    options,
                    &mut finger_log,
                )?;
                let grasp_set = grasps(
                    &object_mesh,
                    &scene.object.mesh,
                    (&finger_params, &object_finger),
                    &gripper,
                    &mut finger_cache,
                    &mut finger_log,
                )?;
                Ok((object_finger, grasp_set))
            },
        );
        let (object_env, placement_object) = env_side?;
        let (object_finger, mut grasp_set) = finger_side?;
        let mut grasp_hand_rejections = BTreeMap::new();
        // The grasp planner puts a grasp's centre midway between the contacts; a gripper with
        // a fixed jaw has its tool point on that jaw (issue 32), half the width away.
        if let Some(first) = robot.arms.first()
            && first.gripper.has_fixed_jaw()
        {
            for g in &mut grasp_set.grasps {
                g.object_from_tcp *= first.gripper.centre_from_tcp(g.width);
            }
        }
        log.append(&mut finger_log);
        cache.absorb(finger_cache);
        let parts: Vec<_> = environment
            .iter()
            .map(|e| (&e.mesh, &e.clustering, e.world_from_mesh))
            .collect();
        let placement_env = EnvironmentModel::from_parts(&parts)
            .map_err(crate::error::internal("placement environment model"))?;
        let object_shape = CollisionShape::mesh(&object_mesh)
            .map_err(robot_err(&scene.object.mesh))?
            .with_hull();
        // The grasps the robot's own hand can close: no link but the pads in the object.
        if let Some(first) = robot.arms.first().filter(|_| planning) {
            let t = Instant::now();
            let before = grasp_set.grasps.len();
            let dropped = crate::hand_fit::drop_grasps_the_hand_cannot_close(
                &model,
                &self_world,
                (&first.gripper, first.tcp_link),
                &start,
                (&object_shape, &object_mesh),
                &mut grasp_set,
            )
            .map_err(robot_err(&urdf_path))?;
            if !dropped.is_empty() {
                let what: Vec<String> = dropped.iter().map(|(r, n)| format!("{r} ×{n}")).collect();
                log.push(format!(
                    "object grasps: {} of {before} dropped, the robot's hand closed on the object does not hold it as the validator asks ({}), in {:.1} ms",
                    before - grasp_set.grasps.len(),
                    what.join(", "),
                    ms(t)
                ));
            }
            grasp_hand_rejections = dropped;
        }

        // The arms.
        let mut arms = Vec::with_capacity(robot.arms.len());
        for robot_arm in &robot.arms {
            let t = Instant::now();
            let key = roadmaps::roadmap_key(&robot.key_text, "", &robot_arm.group);
            let path = cache
                .dir()
                .map(|dir| roadmaps::roadmap_path(dir, model.name(), &robot_arm.group, key));
            let entry = path.as_deref().map(|path| RoadmapEntry {
                path,
                key,
                writable: cache.writable(),
            });
            let stage = format!("roadmap {}", robot_arm.group);
            let arm_setup = arm_setup(
                &model,
                &self_world,
                &start,
                &world_from_root,
                robot_arm,
                entry.filter(|_| planning),
                purpose,
                &|done, total| options.report(&stage, done, total),
            )?;
            if let Some(warning) = &arm_setup.roadmap_report.cache_warning {
                cache.report(warning.clone());
            }
            log.push(if planning {
                format!(
                    "{} arm ({}): {} in {:.1} ms",
                    robot_arm.arm,
                    robot_arm.group,
                    arm_setup.roadmap_report,
                    ms(t)
                )
            } else {
                format!(
                    "{} arm ({}): set up for validation (no roadmap) in {:.1} ms",
                    robot_arm.arm,
                    robot_arm.group,
                    ms(t)
                )
            });
            arms.push(arm_setup);
        }
        if !planning {
            log.push(
                "validation: no environment clusters, grasps, roadmaps or reach maps (the validator reads none)"
                    .to_owned(),
            );
        }
        Ok(Self {
            purpose,
            scene_path: scene_path.to_path_buf(),
            scene,
            model,
            semantics,
            gripper,
            world_from_root,
            start,
            arms,
            object_mesh,
            object_env,
            object_finger,
            grasp_set,
            cog,
            object_start,
            placement_object,
            placement_env,
            environment,
            object_shape,
            world,
            timing,
            scaling,
            log,
            warnings: cache.into_warnings(),
            mesh_warnings,
            robot_warnings,
            grasp_hand_rejections,
            grip_object: std::sync::OnceLock::new(),
        })
    }

    /// The object's mesh as [`pickplace_robot::gripper::Gripper::finger_gaps`] measures
    /// against it, built on first use and kept.
    ///
    /// # Errors
    /// [`Error::Internal`] when the collision library refuses the object's mesh (which it
    /// accepted for the object's collision shape).
    pub fn grip_object(&self) -> Result<&pickplace_robot::gripper::GripObject> {
        if let Some(object) = self.grip_object.get() {
            return Ok(object);
        }
        let object = pickplace_robot::gripper::GripObject::new(&self.object_mesh)
            .map_err(crate::error::internal("grip check"))?;
        Ok(self.grip_object.get_or_init(|| object))
    }

    /// The arm's setup. A single-arm robot has only one: every strategy that needs the other
    /// is filtered out before planning ([`Setup::has_arm`]), and this returns the one arm.
    pub fn arm(&self, arm: Arm) -> &ArmSetup {
        let one = self.arms.iter().find(|a| a.arm == arm);
        match one {
            Some(a) => a,
            None => &self.arms[0],
        }
    }

    /// Whether the robot has this arm.
    pub fn has_arm(&self, arm: Arm) -> bool {
        self.arms.iter().any(|a| a.arm == arm)
    }

    /// The environment mesh a placement region (numbered across meshes) belongs to, and the
    /// cluster's index in that mesh's clustering.
    pub fn environment_of_cluster(&self, cluster: usize) -> Option<(usize, usize)> {
        let mut offset = 0;
        for (i, e) in self.environment.iter().enumerate() {
            let n = e.clustering.clusters.len();
            if cluster < offset + n {
                return Some((i, cluster - offset));
            }
            offset += n;
        }
        None
    }
}
