//! The world of motion queries: a robot as its maker ships it (URDF, SRDF), where it stands,
//! its start state, and obstacles (the scene's environment meshes, its object at its start
//! pose, and boxes, cylinders, spheres or meshes added by the caller).

use crate::cache::{Cache, CacheWarning};
use crate::error::{Error, Result};
use crate::obstacle::{Obstacle, ObstacleShape};
use crate::robot_setup::{RobotPurpose, RobotSetup, robot_err};
use crate::scene::{EnvironmentSpec, MotionScene, PoseSpec, RobotSpec, SceneOf};
use crate::setup::SetupOptions;
use crate::setup::robot_state;
use pickplace_geometry::math::{Isometry3, Real};
use pickplace_robot::collision::CollisionWorld;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// A robot and its obstacles, ready for motion queries ([`super::plan_motion`]).
#[derive(Debug, Clone)]
pub struct MotionWorld {
    pub(super) robot: RobotSetup,
    /// The start configuration (every variable): the values of the joints a query does not
    /// move.
    pub(super) start: Vec<Real>,
    pub(super) world: CollisionWorld,
    /// The default velocity and acceleration scaling (the scene's, else the joint-limits
    /// file's, else 1).
    pub(super) scaling: (Real, Real),
    /// The file errors name: the scene, or the URDF of [`MotionWorld::for_robot`].
    pub(super) source: PathBuf,
    names: BTreeSet<String>,
    log: Vec<String>,
    warnings: Vec<String>,
}

impl MotionWorld {
    /// The world of a scene file (`docs/scene-format.md`): its robot(s) at their start state,
    /// its environment meshes, and its object, when it has one, as an obstacle at its start
    /// pose; a target is ignored. The collision matrix is the SRDF's, completed by sampling
    /// (cached in `options.cache_dir`) when it has none.
    ///
    /// # Errors
    /// [`Error::Scene`], [`Error::Robot`], [`Error::Mesh`] or [`Error::Invalid`], naming the
    /// file and what is wrong.
    pub fn load(scene_path: &Path, options: &SetupOptions) -> Result<Self> {
        let scene = MotionScene::load(scene_path)?;
        Self::from_scene(&scene, scene_path, options)
    }

    /// The world of a robot alone: its URDF and, when given, its SRDF, the root at the world's
    /// origin, the SRDF's `home` as the start state when it has one (else every joint at 0,
    /// clamped into its limits), no obstacle ([`MotionWorld::add_obstacle`]).
    ///
    /// # Errors
    /// As [`MotionWorld::load`], naming the URDF or SRDF.
    pub fn for_robot(urdf: &Path, srdf: Option<&Path>, options: &SetupOptions) -> Result<Self> {
        let scene: MotionScene = SceneOf {
            format: crate::scene::SCENE_FORMAT,
            robot: None,
            robots: vec![RobotSpec {
                urdf: urdf.to_path_buf(),
                srdf: srdf.map(Path::to_path_buf),
                gripper: None,
                joint_limits: None,
                package_dirs: Vec::new(),
                base_pose: PoseSpec::IDENTITY,
                named_state: None,
                start_state: Default::default(),
                prefix: String::new(),
                groups: Default::default(),
            }],
            object: None,
            environment: Vec::new(),
            target: None,
            planner: Default::default(),
            trajectory: Default::default(),
            collision_matrix: Default::default(),
        };
        Self::from_scene(&scene, urdf, options)
    }

    /// The world of a scene already read ([`MotionWorld::load`]); `scene_path` names it in
    /// errors.
    ///
    /// # Errors
    /// As [`MotionWorld::load`].
    pub fn from_scene(
        scene: &MotionScene,
        scene_path: &Path,
        options: &SetupOptions,
    ) -> Result<Self> {
        let mut log = Vec::new();
        let robot = RobotSetup::load_for(
            scene,
            scene_path,
            &options.package_dirs,
            RobotPurpose::Motion,
        )?;
        log.extend(robot.notes.iter().cloned());
        let start = robot_state::start_configuration(scene, &robot, scene_path)?;
        let mut cache = Cache::open(options.cache_dir.as_deref());
        let world = robot_state::self_world(
            &robot,
            &start,
            &scene.collision_matrix,
            &mut cache,
            &mut log,
        )?;
        let scaling = robot.scaling(&scene.trajectory);
        let mut warnings = robot.warnings.clone();
        warnings.extend(cache.into_warnings().iter().map(CacheWarning::to_string));
        let mut out = Self {
            robot,
            start,
            world,
            scaling,
            source: scene_path.to_path_buf(),
            names: BTreeSet::new(),
            log,
            warnings,
        };
        for (i, env) in scene.environment.iter().enumerate() {
            out.add_environment(env, &format!("environment[{i}]"))?;
        }
        if let Some(object) = &scene.object {
            let mesh = crate::setup::load_mesh(&object.mesh, object.scale, "object.mesh")?;
            let pose = object
                .start_pose
                .to_isometry()
                .map_err(|r| out.invalid("object.start_pose", r.into()))?;
            out.add(
                crate::contact::OBJECT_NAME,
                &ObstacleShape::Mesh(mesh),
                &pose,
                &object.mesh,
            )?;
        }
        Ok(out)
    }

    /// Adds an environment part given as a scene writes it (a mesh file, relative paths to the
    /// working folder, or a box, cylinder or sphere; `docs/scene-format.md`); `field` names it
    /// in errors (`obstacles[2]`).
    ///
    /// # Errors
    /// As [`MotionWorld::add_obstacle`], and [`crate::Error::Mesh`] for an unreadable mesh.
    pub fn add_environment(&mut self, env: &EnvironmentSpec, field: &str) -> Result<()> {
        let source = self.source.clone();
        let body = crate::obstacle::load_environment(env, field, &source)?;
        self.insert_name(&env.name)?;
        self.world
            .add_environment(&env.name, body.shape, &body.world_from_shape);
        Ok(())
    }

    /// Adds an obstacle.
    ///
    /// # Errors
    /// [`Error::Invalid`] for a name already in the world or a size that is not positive and
    /// finite.
    pub fn add_obstacle(&mut self, obstacle: &Obstacle) -> Result<()> {
        let source = self.source.clone();
        self.add(&obstacle.name, &obstacle.shape, &obstacle.pose, &source)
    }

    fn add(
        &mut self,
        name: &str,
        shape: &ObstacleShape,
        pose: &Isometry3,
        source: &Path,
    ) -> Result<()> {
        self.insert_name(name)?;
        let (collision, correction) = shape.collision_shape().map_err(robot_err(source))?;
        self.world
            .add_environment(name, collision, &(pose * correction));
        Ok(())
    }

    /// Records an obstacle's name, refused when it is not a name or is taken.
    fn insert_name(&mut self, name: &str) -> Result<()> {
        let field = format!("obstacle {name:?}");
        pickplace_geometry::io::check_name("the obstacle's name", name)
            .map_err(|r| self.invalid(&field, r.to_string()))?;
        if !self.names.insert(name.to_owned()) {
            return Err(self.invalid(&field, "two obstacles have this name".into()));
        }
        Ok(())
    }

    pub(super) fn invalid(&self, field: &str, reason: String) -> Error {
        Error::Invalid {
            path: self.source.clone(),
            field: field.to_owned(),
            reason,
        }
    }

    /// The robot model.
    pub fn model(&self) -> &pickplace_robot::RobotModel {
        &self.robot.model
    }

    /// The start configuration (every variable, model order): what a query's joints outside
    /// its group keep.
    pub fn start(&self) -> &[Real] {
        &self.start
    }

    /// The collision world: the robot and every obstacle.
    pub fn collision_world(&self) -> &CollisionWorld {
        &self.world
    }

    /// The names of the obstacles, sorted.
    pub fn obstacle_names(&self) -> impl Iterator<Item = &str> {
        self.names.iter().map(String::as_str)
    }

    /// What loading did, one line each (the robot's notes, the collision matrix's source).
    pub fn log(&self) -> &[String] {
        &self.log
    }

    /// What the robot's files got wrong and loading went on from, and why the cache could not
    /// be used; one line each, for the caller to show.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }
}
