//! Scene files: what the planner is asked to do (TOML, documented in `docs/scene-format.md`).
//!
//! Relative paths in a scene are resolved against the folder of the scene file. Unknown fields
//! are rejected so that a typo is an error, not a silently ignored option.

use crate::ranges;
pub use crate::strategy::StrategyChoice;
use pickplace_geometry::math::{Isometry3, Point3, Real, Translation3, UnitQuaternion, nalgebra};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The current scene format version.
pub const SCENE_FORMAT: u32 = 1;

/// A scene file; default limit 1 MiB.
pub const SCENE_FILE: pickplace_geometry::io::FileKind =
    pickplace_geometry::io::FileKind::new("a scene", pickplace_geometry::io::MIB);

/// A pose as written in files: position (m) and orientation quaternion `[x, y, z, w]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseSpec {
    /// Position (m); exactly 3 numbers.
    #[serde(deserialize_with = "exact::position")]
    pub position: [Real; 3],
    /// Orientation quaternion in ROS order `[x, y, z, w]` (default: identity); exactly 4
    /// numbers. Normalised on reading; a zero quaternion is an error.
    #[serde(
        default = "identity_quaternion",
        deserialize_with = "exact::quaternion"
    )]
    pub orientation: [Real; 4],
}

/// Fixed-length arrays read exactly: serde's `[T; N]` takes the first N values of a longer
/// array and drops the rest, so a 4-value position or a 6-value quaternion would be read as
/// something the user did not write.
pub(crate) mod exact;
mod parse;
#[cfg(test)]
mod tests;

fn identity_quaternion() -> [Real; 4] {
    [0.0, 0.0, 0.0, 1.0]
}

impl PoseSpec {
    /// The identity pose.
    pub const IDENTITY: Self = Self {
        position: [0.0; 3],
        orientation: [0.0, 0.0, 0.0, 1.0],
    };

    /// The pose as an isometry, or why it is not one.
    pub fn to_isometry(&self) -> Result<Isometry3, &'static str> {
        if self
            .position
            .iter()
            .chain(self.orientation.iter())
            .any(|v| !v.is_finite())
        {
            return Err("pose has a non-finite number");
        }
        let [x, y, z, w] = self.orientation;
        let q = nalgebra::Quaternion::new(w, x, y, z);
        if q.norm() < 1e-9 {
            return Err("orientation quaternion is zero");
        }
        // Scaled by its largest component before normalising: the norm of a quaternion with
        // components above ~1e154 overflows, and dividing by it gave the zero quaternion.
        let largest = self
            .orientation
            .iter()
            .fold(0.0, |m: Real, v| m.max(v.abs()));
        let [px, py, pz] = self.position;
        Ok(Isometry3::from_parts(
            Translation3::new(px, py, pz),
            UnitQuaternion::from_quaternion(q / largest),
        ))
    }

    /// The file form of an isometry.
    pub fn from_isometry(iso: &Isometry3) -> Self {
        let q = iso.rotation.quaternion();
        let t = iso.translation.vector;
        Self {
            position: [t.x, t.y, t.z],
            orientation: [q.i, q.j, q.k, q.w],
        }
    }
}

/// A whole pick-and-place scene file: robots, environment, the object to move and the target.
pub type Scene = SceneOf<ObjectSpec, TargetSpec>;

/// A scene file read for motion queries (`pickplace motion`, [`crate::motion`]): the robots and
/// the environment; the object, when given, is an obstacle at its start pose, and a target is
/// read (and checked) but unused. A pick-and-place [`Scene`] is one with both.
pub type MotionScene = SceneOf<Option<ObjectSpec>, Option<TargetSpec>>;

/// A scene file, whether its object (`O`) and target (`T`) are required ([`Scene`]) or not
/// ([`MotionScene`]). One format, one parser ([`MotionScene::parse`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneOf<O, T> {
    /// Scene format version (default: the current one). A newer version is an error.
    #[serde(default = "current_format")]
    pub format: u32,
    /// The robot, as `[robot]`; after reading, it is the only element of `robots`.
    #[serde(default, skip_serializing)]
    pub robot: Option<RobotSpec>,
    /// The robots, as `[[robots]]` (two single-arm robots side by side, each with its own
    /// `prefix`), or the one `[robot]`. Never empty after reading.
    #[serde(default)]
    pub robots: Vec<RobotSpec>,
    /// The object to move.
    #[serde(default)]
    pub object: O,
    /// Static environment meshes.
    #[serde(default)]
    pub environment: Vec<EnvironmentSpec>,
    /// Where the object should go.
    #[serde(default)]
    pub target: T,
    /// Planner options.
    #[serde(default)]
    pub planner: PlannerOptions,
    /// Timing of the trajectory: limits and scaling.
    #[serde(default)]
    pub trajectory: TrajectorySpec,
    /// How the collision matrix is sampled when the robot's SRDF has none (or there is no
    /// SRDF).
    #[serde(default)]
    pub collision_matrix: CollisionMatrixSpec,
}

/// The scene's `[collision_matrix]`: the sampling that completes the allowed-collision
/// matrix of a robot whose SRDF lists no `disable_collisions` (or that has no SRDF), as
/// MoveIt's setup assistant and `pickplace robot srdf` do. Unused when the SRDF has a
/// matrix.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CollisionMatrixSpec {
    /// Random configurations sampled, uniform within the joint limits (default: 10 000,
    /// MoveIt's setup assistant's sampling density).
    pub samples: usize,
    /// Seed of the sampling (default: 0, as `pickplace robot srdf`).
    pub seed: u64,
    /// A link pair in collision in at least this fraction of the samples is never checked
    /// ("usually in collision", in (0, 1]; default: 0.95 as MoveIt's setup assistant).
    pub min_collision_fraction: Real,
}

impl Default for CollisionMatrixSpec {
    fn default() -> Self {
        let o = pickplace_robot::collision::AcmOptions::default();
        Self {
            samples: o.samples,
            seed: o.seed,
            min_collision_fraction: o.min_collision_fraction,
        }
    }
}

impl CollisionMatrixSpec {
    /// The sampling options.
    pub fn options(&self) -> pickplace_robot::collision::AcmOptions {
        pickplace_robot::collision::AcmOptions {
            samples: self.samples,
            seed: self.seed,
            min_collision_fraction: self.min_collision_fraction,
        }
    }
}

/// The scene's `[trajectory]`: how fast the robot may move (issue 19).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TrajectorySpec {
    /// Fraction of every joint's velocity limit used, in (0, 1] (default: the joint-limits
    /// file's `default_velocity_scaling_factor`, else 1).
    pub velocity_scaling: Option<Real>,
    /// Fraction of every joint's acceleration limit used, in (0, 1] (default: the file's
    /// `default_acceleration_scaling_factor`, else 1).
    pub acceleration_scaling: Option<Real>,
    /// Acceleration limit of a joint no table limits (rad/s² or m/s²; URDFs carry none)
    /// (default: 3).
    pub max_acceleration: Real,
    /// Limits by joint name (full names, prefix included), in the shape of MoveIt's
    /// `joint_limits.yaml`; over the robots' files.
    pub joint_limits: BTreeMap<String, crate::joint_limits::JointLimitSpec>,
}

impl Default for TrajectorySpec {
    fn default() -> Self {
        Self {
            velocity_scaling: None,
            acceleration_scaling: None,
            max_acceleration: crate::joint_limits::DEFAULT_ACCELERATION,
            joint_limits: BTreeMap::new(),
        }
    }
}

fn current_format() -> u32 {
    SCENE_FORMAT
}

/// The robot of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    /// URDF file.
    pub urdf: PathBuf,
    /// SRDF file (groups, end effectors, named states, allowed collisions) (default: none;
    /// the arms and grippers are then found in the URDF).
    #[serde(default)]
    pub srdf: Option<PathBuf>,
    /// Gripper overrides (TOML; every field optional): `squeeze`, `pad_width`, `pad_depth`,
    /// `opening_max`, `tool_offset`, and the grasp planner's gripper model (default: everything
    /// measured on the URDF).
    #[serde(default)]
    pub gripper: Option<PathBuf>,
    /// Joint velocity and acceleration limits in the shape of MoveIt's `joint_limits.yaml`
    /// (default: `joint_limits.yaml` beside the URDF when there is one, else none).
    #[serde(default)]
    pub joint_limits: Option<PathBuf>,
    /// Folders searched for `package://NAME/…` mesh paths (relative to the scene), before
    /// the command line's `--package-dir` and `ROS_PACKAGE_PATH`.
    #[serde(default)]
    pub package_dirs: Vec<PathBuf>,
    /// Pose of the URDF root link in the world (default: identity).
    #[serde(default = "identity_pose")]
    pub base_pose: PoseSpec,
    /// A named state of the SRDF to start from (default: `home` when the SRDF has one, else
    /// every joint at zero, clamped into its limits).
    #[serde(default)]
    pub named_state: Option<String>,
    /// Start joint values by name (rad or m), over the named state. Names are the robot's own
    /// (without the prefix of `[[robots]]`).
    #[serde(default)]
    pub start_state: BTreeMap<String, Real>,
    /// With `[[robots]]`: prepended to every link, joint and group name of this robot, so that
    /// two copies of one robot can share a scene (e.g. `right_` and `left_`).
    #[serde(default)]
    pub prefix: String,
    /// Planning groups the SRDF lacks (for example which chain is an arm), by name.
    #[serde(default)]
    pub groups: BTreeMap<String, GroupSpecToml>,
}

/// A planning group written in a scene: a chain from `base_link` to `tip_link`, or a list of
/// joints.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupSpecToml {
    /// First link of the chain.
    #[serde(default)]
    pub base_link: Option<String>,
    /// Last link of the chain.
    #[serde(default)]
    pub tip_link: Option<String>,
    /// Joints of the group.
    #[serde(default)]
    pub joints: Vec<String>,
}

fn identity_pose() -> PoseSpec {
    PoseSpec::IDENTITY
}

/// The object of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectSpec {
    /// Mesh file (.stl, .obj, .ply), in metres unless `scale` says otherwise.
    pub mesh: PathBuf,
    /// Scale applied to the mesh's coordinates (default: 1).
    #[serde(default = "one")]
    pub scale: Real,
    /// Pose of the object at the start, in the world.
    pub start_pose: PoseSpec,
    /// Mass (kg) (default: none; only the CoG matters for stability).
    #[serde(default)]
    pub mass: Option<Real>,
    /// Centre of gravity in the object frame (m) (default: from the mesh, uniform density).
    #[serde(default, deserialize_with = "exact::optional_xyz")]
    pub center_of_gravity: Option<[Real; 3]>,
}

fn one() -> Real {
    1.0
}

/// One static part of the environment: a mesh file, or a box, a cylinder or a sphere
/// ([`crate::obstacle`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentSpec {
    /// A name for messages and outputs.
    pub name: String,
    /// Mesh file (exactly one of `mesh`, `box`, `cylinder` and `sphere`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<PathBuf>,
    /// A box: its full sizes along x, y and z (m), centred on `pose`.
    #[serde(default, rename = "box", skip_serializing_if = "Option::is_none")]
    pub box_size: Option<[Real; 3]>,
    /// A cylinder along z, centred on `pose`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cylinder: Option<CylinderSpec>,
    /// A sphere centred on `pose`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sphere: Option<SphereSpec>,
    /// Scale applied to the mesh's coordinates (default: 1; meshes only).
    #[serde(default = "one")]
    pub scale: Real,
    /// Pose of the mesh in the world (default: identity).
    #[serde(default = "identity_pose")]
    pub pose: PoseSpec,
}

/// An environment cylinder's size.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CylinderSpec {
    /// Radius (m).
    pub radius: Real,
    /// Length along its axis, z (m).
    pub length: Real,
}

/// An environment sphere's size.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSpec {
    /// Radius (m).
    pub radius: Real,
}

/// What an environment part is made of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EnvironmentSource<'a> {
    /// A mesh file.
    Mesh(&'a Path),
    /// A box, cylinder or sphere.
    Primitive(&'a EnvironmentSpec),
}

impl EnvironmentSpec {
    /// Checks that it is one thing (a mesh, a box, a cylinder or a sphere) of sizes in range at
    /// a pose in range;
    /// `field` names it (`environment[2]`) in the error `(field, reason)`.
    ///
    /// # Errors
    /// Several shapes or none, a scale on a primitive, a size out of range.
    pub fn check(&self, field: &str) -> Result<(), (String, String)> {
        let given: Vec<&str> = [
            ("mesh", self.mesh.is_some()),
            ("box", self.box_size.is_some()),
            ("cylinder", self.cylinder.is_some()),
            ("sphere", self.sphere.is_some()),
        ]
        .into_iter()
        .filter_map(|(k, on)| on.then_some(k))
        .collect();
        if given.len() != 1 {
            return Err((
                field.to_owned(),
                format!(
                    "give exactly one of mesh, box, cylinder and sphere (given: {})",
                    if given.is_empty() {
                        "none".to_owned()
                    } else {
                        given.join(", ")
                    }
                ),
            ));
        }
        let at = |f: &str| format!("{field}.{f}");
        self.pose
            .to_isometry()
            .map_err(|r| (at("pose"), r.to_owned()))?;
        for &v in &self.pose.position {
            ranges::COORDINATE
                .check(v)
                .map_err(|e| (at("pose.position"), e.to_string()))?;
        }
        if let Err(e) = ranges::MESH_SCALE.check(self.scale) {
            return Err((at("scale"), e.to_string()));
        }
        if self.mesh.is_none() && self.scale != 1.0 {
            return Err((
                at("scale"),
                "scales a mesh; give a primitive's sizes as they are".into(),
            ));
        }
        let sizes: Vec<(String, Real)> = match (self.box_size, self.cylinder, self.sphere) {
            (Some(b), ..) => (0..3)
                .map(|k| (format!("{}[{k}]", at("box")), b[k]))
                .collect(),
            (_, Some(c), _) => vec![
                (at("cylinder.radius"), c.radius),
                (at("cylinder.length"), c.length),
            ],
            (.., Some(sp)) => vec![(at("sphere.radius"), sp.radius)],
            _ => Vec::new(),
        };
        for (f, v) in sizes {
            ranges::SHAPE_SIZE
                .check(v)
                .map_err(|e| (f, e.to_string()))?;
        }
        Ok(())
    }

    /// Its mesh file, or the primitive it is (exactly one, checked when the scene is read).
    pub fn source(&self) -> EnvironmentSource<'_> {
        match &self.mesh {
            Some(path) => EnvironmentSource::Mesh(path),
            None => EnvironmentSource::Primitive(self),
        }
    }

    /// Its primitive's shape, or `None` for a mesh.
    pub fn primitive(&self) -> Option<crate::obstacle::ObstacleShape> {
        use crate::obstacle::ObstacleShape;
        if let Some(size) = self.box_size {
            Some(ObstacleShape::Box { size })
        } else if let Some(c) = self.cylinder {
            Some(ObstacleShape::Cylinder {
                radius: c.radius,
                length: c.length,
            })
        } else {
            self.sphere
                .map(|s| ObstacleShape::Sphere { radius: s.radius })
        }
    }
}

/// The target: the paper's click on the environment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TargetSpec {
    /// A point on an environment surface (world frame, m).
    #[serde(deserialize_with = "exact::point")]
    pub point: [Real; 3],
    /// How far (m) the vertical through the placed object's centre of mass may pass from
    /// `point` for `pickplace validate` to accept the placement (default:
    /// [`DEFAULT_TARGET_TOLERANCE`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<Real>,
}

/// The default of `target.tolerance` (m): every shipped scene's placement passes with it
/// (measured: `fig10a-edge` 5.6 mm, `fig10b-mug` 4.5 mm, Baxter 0.1 mm, the others under
/// 0.1 mm), while a plan for another scene, placed 14 cm away, does not.
pub const DEFAULT_TARGET_TOLERANCE: Real = 0.04;

impl TargetSpec {
    /// `tolerance`, or [`DEFAULT_TARGET_TOLERANCE`].
    pub fn tolerance(&self) -> Real {
        self.tolerance.unwrap_or(DEFAULT_TARGET_TOLERANCE)
    }
}

/// Planner options of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlannerOptions {
    /// Seed of every random choice (default: 1).
    pub seed: u64,
    /// h_max for environment-contact clusters (m) (default: 0.001, the paper's value).
    pub h_max_environment: Real,
    /// h_max for finger-contact clusters (m) (default: 0.005, the paper's value).
    pub h_max_finger: Real,
    /// Time budget for the whole plan (s) (default: 10).
    pub time_budget: Real,
    /// Strategy (default: auto).
    pub strategy: StrategyChoice,
    /// SRDF group of the right arm (default: the group `right_arm` when there is one; else
    /// the arms found in the URDF, the one whose hand is on the robot's right). An empty name:
    /// no right arm.
    pub right_arm: Option<String>,
    /// SRDF group of the left arm (default: as `right_arm`, with `left_arm`). An empty name:
    /// no left arm (a single-arm robot plans with its one arm only).
    pub left_arm: Option<String>,
}

impl Default for PlannerOptions {
    fn default() -> Self {
        Self {
            seed: 1,
            h_max_environment: 0.001,
            h_max_finger: 0.005,
            time_budget: 10.0,
            strategy: StrategyChoice::Auto,
            right_arm: None,
            left_arm: None,
        }
    }
}

/// Why a scene file could not be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The scene file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The TOML is malformed or does not match the format.
    #[error("{}: {message}", path.display())]
    Syntax {
        /// The scene file.
        path: PathBuf,
        /// The parser's message, with line and column.
        message: String,
    },
    /// A value is out of range.
    #[error("{}: {field}: {reason}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// The field, as a TOML path (`object.start_pose`).
        field: String,
        /// What is wrong.
        reason: String,
    },
}
