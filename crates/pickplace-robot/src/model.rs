//! The kinematic model: links, joints, geometry, read from a URDF.
//!
//! A [`RobotModel`] is immutable and `Send + Sync`. Joint values live outside it: every query
//! takes a `&[f64]` with one value per *variable* (an actuated joint: revolute, continuous or
//! prismatic and not a mimic), in [`RobotModel::variable_names`] order.
//!
//! Links are stored in depth-first order from the root (index 0), children in file order, so
//! every link comes after its parent; joints likewise (joint `j` moves link `j + 1`).

use crate::error::{Error, MeshProblem, Result, memory_path};
use pickplace_geometry::math::{
    Isometry3, Real, Translation3, UnitQuaternion, UnitVector3, Vector3,
};
use pickplace_geometry::mesh::{MeshOptions, TriMesh};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A URDF file; default limit 64 MiB.
pub const URDF_FILE: pickplace_geometry::io::FileKind =
    pickplace_geometry::io::FileKind::new("a URDF", 64 * pickplace_geometry::io::MIB);
use std::sync::Arc;

/// How a joint moves its child link.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointType {
    /// Rotation about the axis, within limits.
    Revolute,
    /// Rotation about the axis, unlimited.
    Continuous,
    /// Translation along the axis, within limits.
    Prismatic,
    /// No motion.
    Fixed,
}

impl JointType {
    /// The URDF spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Revolute => "revolute",
            Self::Continuous => "continuous",
            Self::Prismatic => "prismatic",
            Self::Fixed => "fixed",
        }
    }
}

/// Position and velocity limits of a joint (rad or m; rad/s or m/s).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointLimits {
    /// Lowest position (−∞ for continuous joints).
    pub lower: Real,
    /// Highest position (+∞ for continuous joints).
    pub upper: Real,
    /// Largest speed (rad/s or m/s); 0 when the URDF gives none.
    pub velocity: Real,
    /// Largest effort (N·m or N); 0 when the URDF gives none.
    pub effort: Real,
}

impl JointLimits {
    /// True when `value` is within the limits, with a tolerance.
    pub fn contains(&self, value: Real, tolerance: Real) -> bool {
        value >= self.lower - tolerance && value <= self.upper + tolerance
    }

    /// `value` clamped into the limits.
    pub fn clamp(&self, value: Real) -> Real {
        value.clamp(self.lower, self.upper)
    }
}

/// A joint that copies another: `value = multiplier * value(mimicked) + offset`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mimic {
    /// Index of the mimicked joint (an actuated joint).
    pub joint: usize,
    /// Multiplier (default 1).
    pub multiplier: Real,
    /// Offset (default 0).
    pub offset: Real,
}

/// Where a joint's value comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointValueSource {
    /// A fixed joint: always 0.
    Fixed,
    /// An actuated joint: `q[variable]`.
    Variable(usize),
    /// `multiplier * q[variable] + offset`.
    Mimic {
        /// The variable of the mimicked joint.
        variable: usize,
        /// Multiplier.
        multiplier: Real,
        /// Offset.
        offset: Real,
    },
}

impl JointValueSource {
    /// The joint's value for the variable values `q`.
    #[inline]
    pub fn value(&self, q: &[Real]) -> Real {
        match *self {
            Self::Fixed => 0.0,
            Self::Variable(v) => q[v],
            Self::Mimic {
                variable,
                multiplier,
                offset,
            } => multiplier * q[variable] + offset,
        }
    }
}

/// A joint of the tree.
#[derive(Debug, Clone)]
pub struct Joint {
    /// Name in the URDF.
    pub name: String,
    /// Type.
    pub joint_type: JointType,
    /// Index of the parent link.
    pub parent_link: usize,
    /// Index of the child link.
    pub child_link: usize,
    /// The joint frame in the parent link's frame (URDF `origin`).
    pub parent_from_joint: Isometry3,
    /// Unit axis in the joint frame.
    pub axis: UnitVector3,
    /// Limits (±∞ position limits for continuous and fixed joints).
    pub limits: JointLimits,
    /// The mimicked joint, if any.
    pub mimic: Option<Mimic>,
    /// Where the value comes from.
    pub source: JointValueSource,
}

impl Joint {
    /// A fixed joint from `parent_link` to `child_link` at `parent_from_joint` (no limits, no
    /// mimic): what [`RobotModel::combine`] and [`RobotModel::with_fixed_link`] add.
    pub fn fixed(
        name: String,
        parent_link: usize,
        child_link: usize,
        parent_from_joint: Isometry3,
    ) -> Self {
        Self {
            name,
            joint_type: JointType::Fixed,
            parent_link,
            child_link,
            parent_from_joint,
            axis: UnitVector3::new_unchecked(Vector3::x()),
            limits: JointLimits {
                lower: 0.0,
                upper: 0.0,
                velocity: 0.0,
                effort: 0.0,
            },
            mimic: None,
            source: JointValueSource::Fixed,
        }
    }

    /// The child frame in the joint frame for joint value `value`.
    #[inline]
    pub fn motion(&self, value: Real) -> Isometry3 {
        match self.joint_type {
            JointType::Revolute | JointType::Continuous => Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_axis_angle(&self.axis, value),
            ),
            JointType::Prismatic => Isometry3::from_parts(
                Translation3::from(self.axis.into_inner() * value),
                UnitQuaternion::identity(),
            ),
            JointType::Fixed => Isometry3::identity(),
        }
    }

    /// `parent_from_child` for joint value `value`.
    #[inline]
    pub fn parent_from_child(&self, value: Real) -> Isometry3 {
        match self.joint_type {
            JointType::Fixed => self.parent_from_joint,
            _ => self.parent_from_joint * self.motion(value),
        }
    }
}

/// A primitive or mesh shape, in its own frame (URDF conventions: cylinders and capsules
/// along z, centred on the origin).
#[derive(Debug, Clone)]
pub enum Shape {
    /// A box with these half extents (m).
    Box {
        /// Half extents along x, y, z.
        half_extents: Vector3,
    },
    /// A cylinder along z.
    Cylinder {
        /// Radius (m).
        radius: Real,
        /// Length (m).
        length: Real,
    },
    /// A capsule along z: a cylinder of `length` with hemispherical caps.
    Capsule {
        /// Radius (m).
        radius: Real,
        /// Length of the cylindrical part (m).
        length: Real,
    },
    /// A sphere.
    Sphere {
        /// Radius (m).
        radius: Real,
    },
    /// A triangle mesh, already scaled.
    Mesh {
        /// The resolved file.
        path: PathBuf,
        /// The scale applied.
        scale: Vector3,
        /// The mesh.
        mesh: Arc<TriMesh>,
    },
}

impl Shape {
    /// A short name of the kind of shape.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Box { .. } => "box",
            Self::Cylinder { .. } => "cylinder",
            Self::Capsule { .. } => "capsule",
            Self::Sphere { .. } => "sphere",
            Self::Mesh { .. } => "mesh",
        }
    }
}

/// A shape placed in a link.
#[derive(Debug, Clone)]
pub struct LinkGeometry {
    /// Where the shape sits in the link frame.
    pub link_from_shape: Isometry3,
    /// The shape.
    pub shape: Shape,
}

/// A link of the tree.
#[derive(Debug, Clone)]
pub struct Link {
    /// Name in the URDF.
    pub name: String,
    /// Index of the joint whose child this link is (`None` for the root).
    pub parent_joint: Option<usize>,
    /// Collision geometry.
    pub collisions: Vec<LinkGeometry>,
    /// Visual geometry.
    pub visuals: Vec<LinkGeometry>,
}

/// Something the loader skipped, returned as data (the library never prints).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum LoadWarning {
    /// A mesh could not be read and was skipped, as [`UnreadableMesh::Skip`] asked.
    SkippedMesh {
        /// The link.
        link: String,
        /// Collision or visual.
        usage: GeometryUsage,
        /// The URI in the URDF.
        uri: String,
        /// Why it could not be read.
        reason: String,
        /// What to do about it ([`MeshProblem::fix`]).
        fix: String,
    },
    /// A revolute or prismatic joint with no limits (lower = upper = 0): it cannot move.
    FrozenJoint {
        /// The joint.
        joint: String,
    },
    /// A joint whose `<mimic>` names a joint the URDF does not have: it moves on its own,
    /// as MoveIt and Pinocchio load it.
    MimicOfUnknownJoint {
        /// The joint.
        joint: String,
        /// The name its `<mimic>` gives.
        mimicked: String,
    },
}

impl std::fmt::Display for LoadWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::SkippedMesh {
                link,
                usage,
                uri,
                reason,
                fix,
            } => {
                write!(
                    f,
                    "link {link:?}: skipped {usage:?} mesh {uri:?}: {reason} (fix: {fix})"
                )
            }
            Self::FrozenJoint { joint } => {
                write!(
                    f,
                    "joint {joint:?} has lower = upper = 0 (no <limit>?): it cannot move"
                )
            }
            Self::MimicOfUnknownJoint { joint, mimicked } => write!(
                f,
                "joint {joint:?} mimics {mimicked:?}, which the URDF does not have: it moves on its own"
            ),
        }
    }
}

/// Which geometry list a shape belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GeometryUsage {
    /// `<collision>`.
    Collision,
    /// `<visual>`.
    Visual,
}

/// What to do with a mesh that cannot be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UnreadableMesh {
    /// Fail with an error naming the file.
    #[default]
    Error,
    /// Drop the geometry and return a [`LoadWarning::SkippedMesh`].
    Skip,
}

/// Which geometry to load.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VisualGeometry {
    /// Load only the collision geometry; visual meshes are not read.
    #[default]
    Skip,
    /// Load visual geometry too.
    Load,
}

/// Options of [`RobotModel::from_urdf_file`].
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// Directories searched for `package://NAME/...`: a directory named NAME inside one of
    /// them, or a directory that is itself named NAME. `ROS_PACKAGE_PATH` is searched after
    /// them (default: empty).
    pub package_dirs: Vec<PathBuf>,
    /// What to do with a mesh that cannot be read (default: [`UnreadableMesh::Error`]).
    pub unreadable_mesh: UnreadableMesh,
    /// Whether visual geometry is loaded (default: [`VisualGeometry::Skip`]).
    pub visual_geometry: VisualGeometry,
    /// Options for reading meshes; the URDF's scale multiplies `mesh.scale` (default:
    /// [`MeshOptions::default`]).
    pub mesh: MeshOptions,
}

/// The version of the collision model the loader builds from a robot's files: it changes
/// when the same files give other collision geometry, so that whatever was computed on the
/// geometry (roadmaps, sampled collision matrices) and cached by the files' text is computed
/// again. 2: the jaws of a one-moving-jaw hand split into convex pieces
/// ([`crate::gripper::SplitLink`]).
pub const GEOMETRY_VERSION: u32 = 2;

/// An immutable robot model read from a URDF.
#[derive(Debug, Clone)]
pub struct RobotModel {
    name: String,
    source: PathBuf,
    links: Vec<Link>,
    joints: Vec<Joint>,
    variables: Vec<usize>,
    link_by_name: BTreeMap<String, usize>,
    joint_by_name: BTreeMap<String, usize>,
    warnings: Vec<LoadWarning>,
    split_links: Vec<crate::gripper::SplitLink>,
}

impl RobotModel {
    /// Reads a URDF file. Relative mesh paths resolve against the file's directory.
    ///
    /// # Errors
    /// [`Error::Io`], [`Error::UrdfSyntax`] (also for elements nested more than 256 deep, more
    /// than 10 000 links or joints, a name over 1024 bytes or another attribute over 4096,
    /// refused before parsing), [`Error::InvalidModel`] (cycle, missing link, inverted limits,
    /// non-finite numbers, ...) or [`Error::Mesh`].
    pub fn from_urdf_file(path: &Path, options: &LoadOptions) -> Result<Self> {
        let text =
            pickplace_geometry::io::read_text(path, URDF_FILE).map_err(|source| Error::Io {
                path: path.to_path_buf(),
                source,
            })?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::from_urdf_str_inner(&text, path, &base, options)
    }

    /// Reads a URDF from a string; relative mesh paths resolve against `base_dir`.
    ///
    /// # Errors
    /// As [`RobotModel::from_urdf_file`], with the path `<memory>`.
    pub fn from_urdf_str(text: &str, base_dir: &Path, options: &LoadOptions) -> Result<Self> {
        Self::from_urdf_str_inner(text, &memory_path(), base_dir, options)
    }

    fn from_urdf_str_inner(
        text: &str,
        path: &Path,
        base_dir: &Path,
        options: &LoadOptions,
    ) -> Result<Self> {
        if let Some(detail) = crate::urdf::check_text(text) {
            return Err(Error::UrdfSyntax {
                path: path.to_path_buf(),
                detail,
            });
        }
        let robot = urdf_rs::read_from_string(text).map_err(|e| Error::UrdfSyntax {
            path: path.to_path_buf(),
            detail: pickplace_geometry::io::short_message(&e.to_string()),
        })?;
        let mut model = crate::urdf::build(&robot, path, base_dir, options)?;
        model.split_links = crate::gripper::split_one_jaw_hands(&mut model);
        Ok(model)
    }

    /// The links whose collision meshes the loader split into convex pieces, so that a hand
    /// with one moving jaw could be measured ([`crate::gripper::SplitLink`]); empty for most
    /// robots.
    pub fn split_links(&self) -> &[crate::gripper::SplitLink] {
        &self.split_links
    }

    /// Replaces a link's collision geometry (the loader's jaw split).
    pub(crate) fn set_collisions(&mut self, link: usize, collisions: Vec<LinkGeometry>) {
        self.links[link].collisions = collisions;
    }

    pub(crate) fn from_parts(
        name: String,
        source: PathBuf,
        links: Vec<Link>,
        joints: Vec<Joint>,
        warnings: Vec<LoadWarning>,
    ) -> Self {
        let variables = joints
            .iter()
            .enumerate()
            .filter(|(_, j)| matches!(j.source, JointValueSource::Variable(_)))
            .map(|(i, _)| i)
            .collect();
        let link_by_name = links
            .iter()
            .enumerate()
            .map(|(i, l)| (l.name.clone(), i))
            .collect();
        let joint_by_name = joints
            .iter()
            .enumerate()
            .map(|(i, j)| (j.name.clone(), i))
            .collect();
        Self {
            name,
            source,
            links,
            joints,
            variables,
            link_by_name,
            joint_by_name,
            warnings,
            split_links: Vec::new(),
        }
    }

    /// The robot's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The URDF file (or `<memory>`).
    pub fn source(&self) -> &Path {
        &self.source
    }

    /// Links, root first, every parent before its children.
    pub fn links(&self) -> &[Link] {
        &self.links
    }

    /// Joints; joint `j` moves link `j + 1`.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// The root link's index (always 0).
    pub fn root(&self) -> usize {
        0
    }

    /// What the loader skipped.
    pub fn warnings(&self) -> &[LoadWarning] {
        &self.warnings
    }

    /// Number of variables (actuated joints): the length of every joint-value slice.
    pub fn variable_count(&self) -> usize {
        self.variables.len()
    }

    /// The joint index of each variable.
    pub fn variable_joints(&self) -> &[usize] {
        &self.variables
    }

    /// The joint of variable `variable`.
    pub fn variable_joint(&self, variable: usize) -> &Joint {
        &self.joints[self.variables[variable]]
    }

    /// Names of the variables, in order.
    pub fn variable_names(&self) -> impl Iterator<Item = &str> + '_ {
        self.variables.iter().map(|&j| self.joints[j].name.as_str())
    }

    /// Limits of each variable.
    pub fn variable_limits(&self) -> impl Iterator<Item = &JointLimits> + '_ {
        self.variables.iter().map(|&j| &self.joints[j].limits)
    }

    /// Index of a link by name.
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.link_by_name.get(name).copied()
    }

    /// Index of a joint by name.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joint_by_name.get(name).copied()
    }

    /// Index of a link by name, or [`Error::UnknownLink`].
    pub fn require_link(&self, name: &str) -> Result<usize> {
        self.link_index(name).ok_or_else(|| Error::UnknownLink {
            name: name.to_owned(),
        })
    }

    /// The variable of an actuated joint, by joint name.
    pub fn variable_index(&self, joint_name: &str) -> Option<usize> {
        match self.joints[self.joint_index(joint_name)?].source {
            JointValueSource::Variable(v) => Some(v),
            _ => None,
        }
    }

    /// The parent link of a link (`None` for the root).
    pub fn parent_link(&self, link: usize) -> Option<usize> {
        self.links[link]
            .parent_joint
            .map(|j| self.joints[j].parent_link)
    }

    /// The joints from the root to `link`, root side first.
    pub fn joint_path(&self, link: usize) -> Vec<usize> {
        let mut path = Vec::new();
        let mut current = link;
        while let Some(j) = self.links[current].parent_joint {
            path.push(j);
            current = self.joints[j].parent_link;
        }
        path.reverse();
        path
    }

    /// True when `ancestor` is `link` or one of its ancestors.
    pub fn is_ancestor(&self, ancestor: usize, link: usize) -> bool {
        let mut current = Some(link);
        while let Some(l) = current {
            if l == ancestor {
                return true;
            }
            current = self.parent_link(l);
        }
        false
    }

    /// Each variable's range for uniform sampling: its limits, or one turn [−π, π] for a
    /// joint without finite limits (continuous).
    pub fn sampling_limits(&self) -> Vec<(Real, Real)> {
        self.variable_limits()
            .map(|l| {
                if l.lower.is_finite() && l.upper.is_finite() {
                    (l.lower, l.upper)
                } else {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                }
            })
            .collect()
    }

    /// The all-zero variable vector, clamped into the limits.
    pub fn zero_configuration(&self) -> Vec<Real> {
        self.variable_limits().map(|l| l.clamp(0.0)).collect()
    }

    /// Checks a joint-value slice: its length, finiteness and limits (tolerance 1e-9).
    ///
    /// # Errors
    /// [`Error::WrongLength`], [`Error::InvalidParameter`] or [`Error::OutOfLimits`].
    pub fn check_configuration(&self, q: &[Real]) -> Result<()> {
        self.check_length(q)?;
        for (v, &value) in q.iter().enumerate() {
            let joint = self.variable_joint(v);
            if !value.is_finite() {
                return Err(Error::InvalidParameter {
                    name: "joint value",
                    value,
                    reason: "joint values must be finite",
                });
            }
            if !joint.limits.contains(value, 1e-9) {
                return Err(Error::OutOfLimits {
                    joint: joint.name.clone(),
                    value,
                    lower: joint.limits.lower,
                    upper: joint.limits.upper,
                });
            }
        }
        Ok(())
    }

    pub(crate) fn check_length(&self, q: &[Real]) -> Result<()> {
        if q.len() != self.variable_count() {
            return Err(Error::WrongLength {
                what: "joint values",
                expected: self.variable_count(),
                found: q.len(),
            });
        }
        Ok(())
    }

    /// The links that move when the variables `variables` change, as a mask by link index:
    /// every link whose path from the root has a joint driven by one of them (actuated, or
    /// mimicking one). For an arm's variables this is the arm, its hand and its fingers; the
    /// mask is what [`crate::collision::PairScope`] takes. Variables out of range move
    /// nothing.
    pub fn links_moved_by(&self, variables: &[usize]) -> Vec<bool> {
        let driven = |j: &Joint| match j.source {
            JointValueSource::Fixed => false,
            JointValueSource::Variable(v) | JointValueSource::Mimic { variable: v, .. } => {
                variables.contains(&v)
            }
        };
        let mut moved = vec![false; self.links.len()];
        for (l, slot) in moved.iter_mut().enumerate() {
            let mut current = l;
            while let Some(j) = self.links[current].parent_joint {
                let joint = &self.joints[j];
                if driven(joint) {
                    *slot = true;
                    break;
                }
                current = joint.parent_link;
            }
        }
        moved
    }
}

/// Resolves a URDF `filename` to a path.
///
/// `package://NAME/rest` looks for `DIR/NAME/rest` (or `DIR/rest` when DIR itself is named
/// NAME) in `package_dirs` and then in the directories of `ROS_PACKAGE_PATH`; `file://` is an
/// absolute path; anything else is relative to `base_dir`.
///
/// # Errors
/// [`MeshProblem::PackageNotFound`] or [`MeshProblem::UnsupportedUri`].
pub fn resolve_uri(
    uri: &str,
    base_dir: &Path,
    package_dirs: &[PathBuf],
) -> std::result::Result<PathBuf, MeshProblem> {
    if let Some(rest) = uri.strip_prefix("package://") {
        let (package, relative) = rest.split_once('/').unwrap_or((rest, ""));
        let env_dirs: Vec<PathBuf> = std::env::var_os("ROS_PACKAGE_PATH")
            .map(|v| std::env::split_paths(&v).collect())
            .unwrap_or_default();
        for dir in package_dirs.iter().chain(env_dirs.iter()) {
            if dir.file_name().is_some_and(|n| n == package) && dir.is_dir() {
                return Ok(dir.join(relative));
            }
            let candidate = dir.join(package);
            if candidate.is_dir() {
                return Ok(candidate.join(relative));
            }
        }
        Err(MeshProblem::PackageNotFound {
            package: package.to_owned(),
        })
    } else if let Some(absolute) = uri.strip_prefix("file://") {
        Ok(PathBuf::from(absolute))
    } else if uri.contains("://") {
        Err(MeshProblem::UnsupportedUri)
    } else {
        Ok(base_dir.join(uri))
    }
}

impl RobotModel {
    /// This model with one more link, `name`, fixed to `parent` at `parent_from_link` (no
    /// geometry): a tool frame. Indices of existing links, joints and variables are unchanged.
    ///
    /// # Errors
    /// [`crate::Error::UnknownLink`] for a bad parent; [`crate::Error::InvalidModel`] when the
    /// name is taken.
    pub fn with_fixed_link(
        &self,
        name: &str,
        parent: usize,
        parent_from_link: Isometry3,
    ) -> crate::Result<Self> {
        if parent >= self.links().len() {
            return Err(crate::Error::UnknownLink {
                name: format!("#{parent}"),
            });
        }
        if self.link_index(name).is_some() || self.joint_index(&format!("{name}_joint")).is_some() {
            return Err(crate::Error::InvalidModel {
                path: self.source().to_path_buf(),
                kind: crate::error::ModelErrorKind::DuplicateLink {
                    name: name.to_owned(),
                },
            });
        }
        let mut links = self.links().to_vec();
        let mut joints = self.joints().to_vec();
        joints.push(crate::model::Joint::fixed(
            format!("{name}_joint"),
            parent,
            links.len(),
            parent_from_link,
        ));
        links.push(crate::model::Link {
            name: name.to_owned(),
            parent_joint: Some(joints.len() - 1),
            collisions: Vec::new(),
            visuals: Vec::new(),
        });
        let mut model = Self::from_parts(
            self.name().to_owned(),
            self.source().to_path_buf(),
            links,
            joints,
            self.warnings().to_vec(),
        );
        model.split_links = self.split_links.clone();
        Ok(model)
    }
}
