//! Scene files: what the planner is asked to do (TOML, documented in `docs/scene-format.md`).
//!
//! Relative paths in a scene are resolved against the folder of the scene file. Unknown fields
//! are rejected so that a typo is an error, not a silently ignored option.

use crate::ranges::{self, Range};
use pickplace_geometry::math::{Isometry3, Point3, Real, Translation3, UnitQuaternion, nalgebra};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The current scene format version.
pub const SCENE_FORMAT: u32 = 1;

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
pub(crate) mod exact {
    use super::Real;
    use serde::de::{Deserializer, Error as _, IgnoredAny, SeqAccess, Visitor};
    use std::fmt;

    /// A pose's `position = [x, y, z]`.
    pub fn position<'de, D: Deserializer<'de>>(d: D) -> Result<[Real; 3], D::Error> {
        d.deserialize_seq(Exact::<3>("position", "[x, y, z]"))
    }

    /// `target.point = [x, y, z]`.
    pub fn point<'de, D: Deserializer<'de>>(d: D) -> Result<[Real; 3], D::Error> {
        d.deserialize_seq(Exact::<3>("point", "[x, y, z]"))
    }

    /// A pose's `orientation = [x, y, z, w]`.
    pub fn quaternion<'de, D: Deserializer<'de>>(d: D) -> Result<[Real; 4], D::Error> {
        d.deserialize_seq(Exact::<4>("orientation", "[x, y, z, w]"))
    }

    /// `object.center_of_gravity = [x, y, z]`, optional.
    pub fn optional_xyz<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[Real; 3]>, D::Error> {
        optional_exact3(d, "center_of_gravity")
    }

    /// The gripper overrides' `tool_offset = [x, y, z]`, optional.
    pub(crate) fn optional_tool_offset<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<[Real; 3]>, D::Error> {
        optional_exact3(d, "tool_offset")
    }

    /// The gripper overrides' `approach_axis = [x, y, z]`, optional.
    pub(crate) fn optional_approach_axis<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<[Real; 3]>, D::Error> {
        optional_exact3(d, "approach_axis")
    }

    /// The gripper overrides' `closing_axis = [x, y, z]`, optional.
    pub(crate) fn optional_closing_axis<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<[Real; 3]>, D::Error> {
        optional_exact3(d, "closing_axis")
    }

    /// An optional `[x, y, z]` named `field` in errors.
    fn optional_exact3<'de, D: Deserializer<'de>>(
        d: D,
        field: &'static str,
    ) -> Result<Option<[Real; 3]>, D::Error> {
        /// The array, for `Option`'s own handling of an absent value.
        struct Xyz([Real; 3]);
        /// The field's name, carried into the array's deserializer.
        struct Named(&'static str);
        impl<'de> serde::de::DeserializeSeed<'de> for Named {
            type Value = Xyz;
            fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Xyz, D::Error> {
                d.deserialize_seq(Exact::<3>(self.0, "[x, y, z]")).map(Xyz)
            }
        }
        /// `Option` handling with a seed: `None` for a unit or absent value.
        struct OptionOf(&'static str);
        impl<'de> Visitor<'de> for OptionOf {
            type Value = Option<Xyz>;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{}: exactly 3 numbers [x, y, z]", self.0)
            }
            fn visit_none<E: serde::de::Error>(self) -> Result<Self::Value, E> {
                Ok(None)
            }
            fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
                serde::de::DeserializeSeed::deserialize(Named(self.0), d).map(Some)
            }
        }
        Ok(d.deserialize_option(OptionOf(field))?.map(|x| x.0))
    }

    /// Reads exactly N numbers; the field's name and the numbers' meaning are in the error.
    struct Exact<const N: usize>(&'static str, &'static str);

    impl<'de, const N: usize> Visitor<'de> for Exact<N> {
        type Value = [Real; N];

        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(f, "{}: exactly {N} numbers {}", self.0, self.1)
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
            let mut values = [0.0; N];
            let mut count = 0;
            while let Some(v) = seq.next_element::<Real>()? {
                if count < N {
                    values[count] = v;
                }
                count += 1;
                if count > N {
                    // Count the rest without keeping it.
                    while seq.next_element::<IgnoredAny>()?.is_some() {
                        count += 1;
                    }
                }
            }
            if count == N {
                Ok(values)
            } else {
                Err(A::Error::custom(format!(
                    "{}: expected exactly {N} numbers {}, got {count}",
                    self.0, self.1
                )))
            }
        }
    }
}

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
    /// Checks that it is one thing (a mesh, a box, a cylinder or a sphere) of sizes in range;
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

/// The manipulation strategy (paper §III-B.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum StrategyChoice {
    /// Order the strategies as the paper does (nearest hands first) and switch on failure.
    #[default]
    Auto,
    /// Grasp and place with the right hand.
    RightRight,
    /// Grasp and place with the left hand.
    LeftLeft,
    /// Grasp with the right hand, hand over, place with the left.
    RightLeft,
    /// Grasp with the left hand, hand over, place with the right.
    LeftRight,
    /// Regrasp by placing with the right hand: pick, put down, pick again, place.
    RightPlaceRight,
    /// Regrasp by placing with the left hand.
    LeftPlaceLeft,
    /// The right hand picks and puts the object down, the left picks it up and places it.
    RightPlaceLeft,
    /// The left hand picks and puts the object down, the right picks it up and places it.
    LeftPlaceRight,
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

/// The text of the scene file at `path` and the folder its relative paths are relative to.
fn read_scene_text(path: &Path) -> Result<(String, &Path), SceneError> {
    let text = pickplace_geometry::io::read_text(path, pickplace_geometry::io::FileKind::Scene)
        .map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
    Ok((text, path.parent().unwrap_or(Path::new("."))))
}

impl Scene {
    /// Reads and validates a scene file; relative paths in it become relative to its folder.
    ///
    /// # Errors
    /// [`SceneError`] naming the file, and the field or line at fault.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let (text, base) = read_scene_text(path)?;
        Self::parse(&text, path, base)
    }

    /// Parses scene text. `path` names the source in errors; relative paths are joined to `base`.
    ///
    /// # Errors
    /// [`SceneError::Syntax`] or [`SceneError::Invalid`] (a missing `[object]` or `[target]`
    /// included).
    pub fn parse(text: &str, path: &Path, base: &Path) -> Result<Self, SceneError> {
        let scene = MotionScene::parse(text, path, base)?;
        let missing = |field: &str, what: &str| SceneError::Invalid {
            path: path.to_path_buf(),
            field: field.to_owned(),
            reason: format!("missing: a pick-and-place scene needs {what}"),
        };
        let object = scene
            .object
            .ok_or_else(|| missing("object", "[object] (the mesh to move and its start_pose)"))?;
        let target = scene
            .target
            .ok_or_else(|| missing("target", "[target] (the point where the object goes)"))?;
        Ok(SceneOf {
            format: scene.format,
            robot: None,
            robots: scene.robots,
            object,
            environment: scene.environment,
            target,
            planner: scene.planner,
            trajectory: scene.trajectory,
            collision_matrix: scene.collision_matrix,
        })
    }

    /// The target point.
    pub fn target_point(&self) -> Point3 {
        Point3::from(self.target.point)
    }
}

impl MotionScene {
    /// Reads and validates a scene file for motion queries (object and target optional);
    /// relative paths in it become relative to its folder.
    ///
    /// # Errors
    /// [`SceneError`] naming the file, and the field or line at fault.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let (text, base) = read_scene_text(path)?;
        Self::parse(&text, path, base)
    }

    /// Parses scene text (the one parser of the format: [`Scene::parse`] then requires the
    /// object and the target). `path` names the source in errors; relative paths are joined
    /// to `base`.
    ///
    /// # Errors
    /// [`SceneError::Syntax`] or [`SceneError::Invalid`].
    pub fn parse(text: &str, path: &Path, base: &Path) -> Result<Self, SceneError> {
        let mut scene: MotionScene = toml::from_str(text).map_err(|e| SceneError::Syntax {
            path: path.to_path_buf(),
            message: pickplace_geometry::io::parse_error(
                text,
                e.span().map(|s| s.start),
                e.message(),
            ),
        })?;
        let invalid = |field: &str, reason: String| SceneError::Invalid {
            path: path.to_path_buf(),
            field: field.to_string(),
            reason,
        };
        if scene.format > SCENE_FORMAT {
            return Err(invalid(
                "format",
                format!(
                    "scene format {} is newer than this build reads ({SCENE_FORMAT})",
                    scene.format
                ),
            ));
        }
        let range = |field: &str, value: Real, r: Range| {
            r.check(value).map_err(|e| invalid(field, e.to_string()))
        };
        let point = |field: &str, p: &[Real; 3]| {
            p.iter()
                .try_for_each(|&v| range(field, v, ranges::COORDINATE))
        };
        let pose = |field: &str, p: &PoseSpec| {
            p.to_isometry().map_err(|r| invalid(field, r.into()))?;
            point(&format!("{field}.position"), &p.position)
        };
        match (scene.robot.take(), scene.robots.is_empty()) {
            (Some(robot), true) => scene.robots.push(robot),
            (Some(_), false) => {
                return Err(invalid(
                    "robots",
                    "give either [robot] or [[robots]], not both".into(),
                ));
            }
            (None, true) => {
                return Err(invalid(
                    "robot",
                    "missing: give [robot] (or [[robots]] for several)".into(),
                ));
            }
            (None, false) => {}
        }
        check_lengths(&scene).map_err(|(field, reason)| invalid(&field, reason))?;
        let several = scene.robots.len() > 1;
        let mut prefixes = std::collections::BTreeSet::new();
        for (i, robot) in scene.robots.iter().enumerate() {
            let field = |f: &str| {
                if several {
                    format!("robots[{i}].{f}")
                } else {
                    format!("robot.{f}")
                }
            };
            pose(&field("base_pose"), &robot.base_pose)?;
            for (name, &value) in &robot.start_state {
                range(
                    &field(&format!("start_state.{name}")),
                    value,
                    ranges::JOINT_VALUE,
                )?;
            }
            if several && !prefixes.insert(robot.prefix.clone()) {
                return Err(invalid(
                    &field("prefix"),
                    format!(
                        "two robots have the prefix {:?}: each needs its own, e.g. \"right_\" and \"left_\"",
                        robot.prefix
                    ),
                ));
            }
            for (name, g) in &robot.groups {
                if g.joints.is_empty() && (g.base_link.is_none() || g.tip_link.is_none()) {
                    return Err(invalid(
                        &field(&format!("groups.{name}")),
                        "give base_link and tip_link (a chain), or joints".into(),
                    ));
                }
            }
        }
        let matrix = &scene.collision_matrix;
        ranges::MATRIX_SAMPLES
            .check_count(matrix.samples)
            .map_err(|e| invalid("collision_matrix.samples", e.to_string()))?;
        ranges::COLLISION_FRACTION
            .check(matrix.min_collision_fraction)
            .map_err(|e| invalid("collision_matrix.min_collision_fraction", e.to_string()))?;
        if let Some(object) = &scene.object {
            pose("object.start_pose", &object.start_pose)?;
            range("object.scale", object.scale, ranges::MESH_SCALE)?;
            if let Some(m) = object.mass {
                range("object.mass", m, ranges::MASS)?;
            }
            if let Some(c) = &object.center_of_gravity {
                point("object.center_of_gravity", c)?;
            }
        }
        for (i, env) in scene.environment.iter().enumerate() {
            pose(&format!("environment[{i}].pose"), &env.pose)?;
            env.check(&format!("environment[{i}]"))
                .map_err(|(field, reason)| invalid(&field, reason))?;
        }
        if let Some(target) = &scene.target {
            point("target.point", &target.point)?;
            if let Some(t) = target.tolerance {
                range("target.tolerance", t, ranges::TARGET_TOLERANCE)?;
            }
        }
        let t = &scene.trajectory;
        for (field, value) in [
            ("trajectory.velocity_scaling", t.velocity_scaling),
            ("trajectory.acceleration_scaling", t.acceleration_scaling),
        ] {
            if let Some(v) = value {
                range(field, v, ranges::SCALING)?;
            }
        }
        range(
            "trajectory.max_acceleration",
            t.max_acceleration,
            ranges::JOINT_ACCELERATION,
        )?;
        for (joint, spec) in &t.joint_limits {
            pickplace_geometry::io::check_name("the joint name", joint)
                .map_err(|r| invalid("trajectory.joint_limits", r.to_string()))?;
            crate::joint_limits::check_spec(spec)
                .map_err(|r| invalid(&format!("trajectory.joint_limits.{joint}"), r.to_string()))?;
        }
        let p = &scene.planner;
        range(
            "planner.h_max_environment",
            p.h_max_environment,
            ranges::H_MAX,
        )?;
        range("planner.h_max_finger", p.h_max_finger, ranges::H_MAX)?;
        range("planner.time_budget", p.time_budget, ranges::TIME_BUDGET)?;
        let mut names = std::collections::BTreeSet::new();
        for env in &scene.environment {
            if !names.insert(env.name.clone()) {
                return Err(invalid(
                    "environment",
                    format!("two meshes are named {:?}", env.name),
                ));
            }
        }
        // Resolve relative paths against the scene's folder.
        let resolve = |p: &mut PathBuf| {
            // `package://NAME/…` is resolved when the robot is loaded (package folders).
            if p.is_relative() && !p.to_string_lossy().starts_with("package://") {
                *p = base.join(&*p);
            }
        };
        for robot in &mut scene.robots {
            resolve(&mut robot.urdf);
            if let Some(p) = robot.srdf.as_mut() {
                resolve(p);
            }
            if let Some(p) = robot.gripper.as_mut() {
                resolve(p);
            }
            if let Some(p) = robot.joint_limits.as_mut() {
                resolve(p);
            }
            for p in &mut robot.package_dirs {
                resolve(p);
            }
        }
        if let Some(object) = &mut scene.object {
            resolve(&mut object.mesh);
        }
        for env in &mut scene.environment {
            if let Some(mesh) = &mut env.mesh {
                resolve(mesh);
            }
        }
        Ok(scene)
    }
}

/// Refuses names over [`MAX_NAME_BYTES`](pickplace_geometry::io::MAX_NAME_BYTES) and paths
/// over [`MAX_PATH_BYTES`](pickplace_geometry::io::MAX_PATH_BYTES): `Err((field, reason))`.
fn check_lengths(scene: &MotionScene) -> Result<(), (String, String)> {
    use pickplace_geometry::io::{check_name, check_path_text};
    let name = |field: String, text: &str| {
        check_name("the name", text).map_err(|r| (field, r.to_string()))
    };
    let path = |field: String, p: &Path| {
        check_path_text("the path", &p.to_string_lossy()).map_err(|r| (field, r.to_string()))
    };
    let several = scene.robots.len() > 1;
    for (i, robot) in scene.robots.iter().enumerate() {
        let field = |f: &str| {
            if several {
                format!("robots[{i}].{f}")
            } else {
                format!("robot.{f}")
            }
        };
        path(field("urdf"), &robot.urdf)?;
        if let Some(p) = &robot.srdf {
            path(field("srdf"), p)?;
        }
        if let Some(p) = &robot.gripper {
            path(field("gripper"), p)?;
        }
        if let Some(p) = &robot.joint_limits {
            path(field("joint_limits"), p)?;
        }
        for (k, p) in robot.package_dirs.iter().enumerate() {
            path(field(&format!("package_dirs[{k}]")), p)?;
        }
        if let Some(n) = &robot.named_state {
            name(field("named_state"), n)?;
        }
        name(field("prefix"), &robot.prefix)?;
        // Keys first: a long key would otherwise end up in the field name of the error.
        for key in robot.start_state.keys() {
            name(field("start_state"), key)?;
        }
        for (key, g) in &robot.groups {
            name(field("groups"), key)?;
            for (f, n) in [("base_link", &g.base_link), ("tip_link", &g.tip_link)] {
                if let Some(n) = n {
                    name(field(&format!("groups.{key}.{f}")), n)?;
                }
            }
            for (k, n) in g.joints.iter().enumerate() {
                name(field(&format!("groups.{key}.joints[{k}]")), n)?;
            }
        }
    }
    if let Some(object) = &scene.object {
        path("object.mesh".into(), &object.mesh)?;
    }
    for (i, env) in scene.environment.iter().enumerate() {
        name(format!("environment[{i}].name"), &env.name)?;
        if let Some(mesh) = &env.mesh {
            path(format!("environment[{i}].mesh"), mesh)?;
        }
    }
    for (f, n) in [
        ("planner.right_arm", &scene.planner.right_arm),
        ("planner.left_arm", &scene.planner.left_arm),
    ] {
        if let Some(n) = n {
            name(f.into(), n)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str = r#"
[robot]
urdf = "robot.urdf"
srdf = "robot.srdf"
gripper = "gripper.toml"
[object]
mesh = "can.stl"
start_pose = { position = [0.4, -0.2, 0.0] }
[[environment]]
name = "pallet"
mesh = "/abs/pallet.stl"
[target]
point = [0.45, 0.1, 0.02]
"#;

    fn parse(text: &str) -> Result<Scene, SceneError> {
        Scene::parse(text, Path::new("scene.toml"), Path::new("/scenes"))
    }

    #[test]
    fn minimal_scene_gets_defaults_and_resolved_paths() {
        let s = parse(MINIMAL).expect("valid");
        assert_eq!(s.robots[0].urdf, PathBuf::from("/scenes/robot.urdf"));
        assert_eq!(s.robots.len(), 1);
        assert!(s.robot.is_none());
        assert_eq!(
            s.environment[0].mesh,
            Some(PathBuf::from("/abs/pallet.stl"))
        );
        assert_eq!(s.planner, PlannerOptions::default());
        assert_eq!(s.object.start_pose.orientation, [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(s.target.tolerance, None);
        assert_eq!(s.target.tolerance(), DEFAULT_TARGET_TOLERANCE);
        let s = parse(&MINIMAL.replace("[target]", "[target]\ntolerance = 0.01")).expect("valid");
        assert_eq!(s.target.tolerance(), 0.01);
    }

    #[test]
    fn fixed_length_arrays_are_exact() {
        for (from, to, expected) in [
            (
                "[0.4, -0.2, 0.0] }",
                "[0.4, -0.2, 0.0, 9.0] }",
                "position: expected exactly 3 numbers [x, y, z], got 4",
            ),
            (
                "[0.4, -0.2, 0.0] }",
                "[0.4, -0.2] }",
                "expected exactly 3 numbers [x, y, z], got 2",
            ),
            (
                "[0.4, -0.2, 0.0] }",
                "[0.4, -0.2, 0.0], orientation = [0, 0, 0, 1, 0, 0] }",
                "orientation: expected exactly 4 numbers [x, y, z, w], got 6",
            ),
            (
                "[0.4, -0.2, 0.0] }",
                "[0.4, -0.2, 0.0], orientation = [0, 0, 1] }",
                "expected exactly 4 numbers [x, y, z, w], got 3",
            ),
            (
                "point = [0.45, 0.1, 0.02]",
                "point = [0.45, 0.1, 0.02, 0.0]",
                "got 4",
            ),
            ("point = [0.45, 0.1, 0.02]", "point = []", "got 0"),
            (
                "mesh = \"can.stl\"",
                "mesh = \"can.stl\"\ncenter_of_gravity = [0, 0, 0.1, 0]",
                "got 4",
            ),
        ] {
            let text = MINIMAL.replace(from, to);
            assert_ne!(text, MINIMAL, "{to}");
            let err = parse(&text).expect_err(to).to_string();
            assert!(err.starts_with("scene.toml: "), "{err}");
            assert!(err.contains(expected), "{to}: {err}");
        }
        let s = parse(&MINIMAL.replace(
            "mesh = \"can.stl\"",
            "mesh = \"can.stl\"\ncenter_of_gravity = [0, 0, 0.1]",
        ))
        .expect("three numbers");
        assert_eq!(s.object.center_of_gravity, Some([0.0, 0.0, 0.1]));
    }

    #[test]
    fn unknown_fields_and_bad_values_are_named() {
        let err = parse(&MINIMAL.replace("[target]", "[target]\nradius = 3")).unwrap_err();
        assert!(err.to_string().contains("unknown field `radius`"), "{err}");
        let err = parse(&MINIMAL.replace(
            "[0.4, -0.2, 0.0] }",
            "[0.4, -0.2, 0.0], orientation = [0,0,0,0] }",
        ))
        .unwrap_err();
        assert!(
            err.to_string()
                .contains("object.start_pose: orientation quaternion is zero"),
            "{err}"
        );
        let err = parse(&MINIMAL.replace("[target]", "[target]\ntolerance = -0.01")).unwrap_err();
        assert!(err.to_string().contains("target.tolerance"), "{err}");
        let err = parse(&format!("{MINIMAL}\n[planner]\nh_max_finger = -1")).unwrap_err();
        assert!(err.to_string().contains("planner.h_max_finger"), "{err}");
        let err = parse("[robot").unwrap_err();
        assert!(err.to_string().starts_with("scene.toml: "), "{err}");
    }

    #[test]
    fn names_and_paths_over_their_limits_are_refused() {
        let long = "n".repeat(1025);
        let err = parse(&MINIMAL.replace("name = \"pallet\"", &format!("name = \"{long}\"")))
            .unwrap_err();
        assert_eq!(
            err.to_string(),
            "scene.toml: environment[0].name: the name is 1025 bytes, over the limit of 1024"
        );
        let err = parse(&MINIMAL.replace(
            "[object]",
            &format!("start_state = {{ {long} = 1.0 }}\n[object]"),
        ))
        .unwrap_err();
        assert!(
            err.to_string()
                .contains("robot.start_state: the name is 1025 bytes"),
            "{err}"
        );
        let err = parse(&MINIMAL.replace("can.stl", &"p".repeat(5000))).unwrap_err();
        assert!(
            err.to_string()
                .contains("object.mesh: the path is 5000 bytes, over the limit of 4096"),
            "{err}"
        );
        assert!(parse(&MINIMAL.replace("pallet\"", &format!("{}\"", "n".repeat(1018)))).is_ok());
    }

    #[test]
    fn syntax_errors_give_line_and_column_without_quoting_the_file() {
        // Regression (issue 18): `gripper = "/etc/passwd"` printed the file's first line.
        let err = parse("root:x:0:0:root:/root:/bin/bash\n").unwrap_err();
        let message = err.to_string();
        assert!(message.starts_with("scene.toml: "), "{message}");
        assert!(
            message.contains("line 1, column 32: key with no value"),
            "{message}"
        );
        assert!(!message.contains("/bin/bash"), "{message}");
        assert!(!message.contains('|'), "{message}");
    }
}
