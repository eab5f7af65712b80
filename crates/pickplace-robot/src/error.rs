//! The error type of the robot crate.

use std::path::PathBuf;

/// Errors of `pickplace-robot`. Each names the file (or `<memory>`) and what is wrong.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be read.
    #[error("{}: cannot read the file", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A URDF file is not well-formed XML or does not follow the URDF schema.
    #[error("{}: malformed URDF: {detail}", path.display())]
    UrdfSyntax {
        /// The URDF file, or `<memory>`.
        path: PathBuf,
        /// What the parser reported.
        detail: String,
    },
    /// A URDF parses but does not describe a valid kinematic tree.
    #[error("{}: {kind}", path.display())]
    InvalidModel {
        /// The URDF file, or `<memory>`.
        path: PathBuf,
        /// What is wrong.
        kind: ModelErrorKind,
    },
    /// A mesh referenced by a link could not be resolved or read.
    #[error("{}: link {link:?}: mesh {uri:?}: {kind}", urdf.display())]
    Mesh {
        /// The URDF file that references the mesh.
        urdf: PathBuf,
        /// The link whose geometry uses the mesh.
        link: String,
        /// The `filename` attribute as written in the URDF.
        uri: String,
        /// What is wrong.
        kind: MeshProblem,
    },
    /// An environment mesh file could not be read.
    #[error("{}: cannot read the environment mesh", path.display())]
    EnvironmentMesh {
        /// The mesh file.
        path: PathBuf,
        /// What the geometry crate reported (boxed: it is large).
        #[source]
        source: Box<pickplace_geometry::Error>,
    },
    /// An SRDF file is malformed or refers to things the URDF does not have.
    #[error("{}: {kind}", path.display())]
    Srdf {
        /// The SRDF file, or `<memory>`.
        path: PathBuf,
        /// What is wrong.
        kind: SrdfErrorKind,
    },
    /// A joint name that the model does not have.
    #[error("unknown joint {name:?}")]
    UnknownJoint {
        /// The name given.
        name: String,
    },
    /// A link name that the model does not have.
    #[error("unknown link {name:?}")]
    UnknownLink {
        /// The name given.
        name: String,
    },
    /// A planning group that the SRDF does not have.
    #[error("unknown group {name:?}")]
    UnknownGroup {
        /// The name given.
        name: String,
    },
    /// A planning group of the SRDF that was left out because a member of it is malformed
    /// ([`crate::srdf::SrdfWarning::LeftOut`]).
    #[error("group {name:?} was left out of the SRDF: {reason}")]
    GroupLeftOut {
        /// The name given.
        name: String,
        /// Why it was left out.
        reason: String,
    },
    /// A group with no single tip link was used where one is needed (IK, Jacobian).
    #[error("group {group:?} has no single tip link (define one chain or an end effector)")]
    GroupWithoutTip {
        /// The group.
        group: String,
    },
    /// A joint-value slice or an output buffer has the wrong length.
    #[error("{what}: expected {expected} values, found {found}")]
    WrongLength {
        /// Which argument.
        what: &'static str,
        /// The length required.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// A joint value is outside its limits.
    #[error(
        "joint {joint:?} = {} is outside its limits [{}, {}]",
        pickplace_geometry::io::fmt_real(*.value),
        pickplace_geometry::io::fmt_real(*.lower),
        pickplace_geometry::io::fmt_real(*.upper)
    )]
    OutOfLimits {
        /// The joint.
        joint: String,
        /// The value given.
        value: f64,
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// A parameter is outside its valid range, or a value is not finite.
    #[error("invalid parameter {name} = {}: {reason}", pickplace_geometry::io::fmt_real(*.value))]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// Why it is invalid.
        reason: &'static str,
    },
    /// The collision library cannot compare two shapes.
    #[error("collision query between {first:?} and {second:?} is not supported")]
    UnsupportedCollisionPair {
        /// First body.
        first: String,
        /// Second body.
        second: String,
    },
}

/// What is wrong with a URDF's kinematic tree.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ModelErrorKind {
    /// The robot has no link.
    #[error("the robot has no link")]
    NoLinks,
    /// Two links share a name.
    #[error("link {name:?} is defined twice")]
    DuplicateLink {
        /// The name.
        name: String,
    },
    /// Two joints share a name.
    #[error("joint {name:?} is defined twice")]
    DuplicateJoint {
        /// The name.
        name: String,
    },
    /// A joint refers to a link that is not defined.
    #[error("joint {joint:?} refers to missing link {link:?}")]
    MissingLink {
        /// The joint.
        joint: String,
        /// The link name it uses.
        link: String,
    },
    /// A link is the child of two joints.
    #[error("link {link:?} is the child of two joints ({first:?} and {second:?})")]
    TwoParents {
        /// The link.
        link: String,
        /// The first joint.
        first: String,
        /// The second joint.
        second: String,
    },
    /// Several links have no parent joint, so there is no single root.
    #[error("the links do not form one tree: roots {roots:?}")]
    MultipleRoots {
        /// The parentless links (first few).
        roots: Vec<String>,
    },
    /// The joints form a cycle.
    #[error("the joints form a cycle through link {link:?}")]
    Cycle {
        /// A link on the cycle.
        link: String,
    },
    /// A joint's lower limit is above its upper limit.
    #[error(
        "joint {joint:?}: lower limit {} is above upper limit {}",
        pickplace_geometry::io::fmt_real(*.lower),
        pickplace_geometry::io::fmt_real(*.upper)
    )]
    LimitsInverted {
        /// The joint.
        joint: String,
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// A number is NaN or infinite where a finite value is required.
    #[error("{element} {name:?}: {field} is not finite")]
    NonFinite {
        /// "joint" or "link".
        element: &'static str,
        /// Its name.
        name: String,
        /// The attribute ("origin xyz", "axis", "limit lower", ...).
        field: &'static str,
    },
    /// A joint's velocity limit is negative.
    #[error("joint {joint:?}: negative velocity limit {}", pickplace_geometry::io::fmt_real(*.velocity))]
    NegativeVelocity {
        /// The joint.
        joint: String,
        /// The value.
        velocity: f64,
    },
    /// A joint's axis has zero length.
    #[error("joint {joint:?}: axis has zero length")]
    ZeroAxis {
        /// The joint.
        joint: String,
    },
    /// A joint type this crate does not model (floating, planar, spherical).
    #[error("joint {joint:?}: unsupported joint type {joint_type}")]
    UnsupportedJointType {
        /// The joint.
        joint: String,
        /// The type name.
        joint_type: &'static str,
    },
    /// A mimic joint refers to a joint that does not exist or cannot be mimicked.
    #[error("joint {joint:?} mimics {mimicked:?}, which {reason}")]
    BadMimic {
        /// The mimic joint.
        joint: String,
        /// The joint it names.
        mimicked: String,
        /// Why it cannot be mimicked.
        reason: &'static str,
    },
    /// A mesh scale with a zero or non-finite component (a negative one mirrors the mesh and
    /// is accepted).
    #[error("link {link:?}: mesh {uri:?} has scale {scale:?} with a zero or non-finite component")]
    BadMeshScale {
        /// The link.
        link: String,
        /// The mesh's `filename` as written.
        uri: String,
        /// The scale, per axis.
        scale: [f64; 3],
    },
    /// A geometry has a non-positive or non-finite size.
    #[error("link {link:?}: {shape} has invalid size {}", pickplace_geometry::io::fmt_real(*.value))]
    BadGeometry {
        /// The link.
        link: String,
        /// "box", "cylinder", "sphere", "capsule" or "mesh scale".
        shape: &'static str,
        /// The offending value.
        value: f64,
    },
}

/// Why a mesh could not be used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MeshProblem {
    /// `package://NAME/...` with no package directory named NAME.
    #[error("package {package:?} not found in the package directories or ROS_PACKAGE_PATH")]
    PackageNotFound {
        /// The package name.
        package: String,
    },
    /// A URI scheme we do not resolve (http, ...).
    #[error("unsupported URI scheme")]
    UnsupportedUri,
    /// The file does not exist.
    #[error("file {} does not exist", path.display())]
    NotFound {
        /// The resolved path.
        path: PathBuf,
    },
    /// The path is there but is no regular file (a device, a folder, a FIFO, a symbolic
    /// link to a missing file).
    #[error("{} is {kind}, not a mesh file", path.display())]
    NotAFile {
        /// The resolved path.
        path: PathBuf,
        /// What it is (`pickplace_geometry::io::path_kind`).
        kind: &'static str,
    },
    /// A format we cannot read (3DS, ...).
    #[error("file {} has unsupported format {extension:?} (expected .stl, .obj, .ply or .dae)", path.display())]
    UnsupportedFormat {
        /// The resolved path.
        path: PathBuf,
        /// Its extension.
        extension: String,
    },
    /// The geometry crate could not read it (boxed: it is large).
    #[error(transparent)]
    Geometry(Box<pickplace_geometry::Error>),
}

impl MeshProblem {
    /// What to do about it, in a sentence.
    pub fn fix(&self) -> String {
        match self {
            Self::PackageNotFound { package } => format!(
                "pass --package-dir DIR where DIR contains a folder {package:?} (or add it to ROS_PACKAGE_PATH)"
            ),
            Self::UnsupportedUri => {
                "download the mesh and refer to it by a relative path or package://".to_owned()
            }
            Self::NotFound { path } => format!(
                "the file {} is missing: install the mesh package or correct the filename",
                path.display()
            ),
            Self::NotAFile { path, .. } => format!(
                "point the URDF at the mesh file itself ({} is not one)",
                path.display()
            ),
            Self::UnsupportedFormat { .. } => {
                "convert the mesh to STL, OBJ, PLY or COLLADA (.dae)".to_owned()
            }
            Self::Geometry(_) => {
                "the file is damaged or empty: export it again from its source".to_owned()
            }
        }
    }
}

impl Error {
    /// The file this error names at the start of its message, when it names one: a caller
    /// that adds the file itself leaves it out then, so that no message says `P: P: …`.
    pub fn file(&self) -> Option<&std::path::Path> {
        match self {
            Self::Io { path, .. }
            | Self::UrdfSyntax { path, .. }
            | Self::InvalidModel { path, .. }
            | Self::EnvironmentMesh { path, .. }
            | Self::Srdf { path, .. } => Some(path),
            Self::Mesh { urdf, .. } => Some(urdf),
            _ => None,
        }
    }
}

impl From<pickplace_geometry::Error> for MeshProblem {
    fn from(error: pickplace_geometry::Error) -> Self {
        Self::Geometry(Box::new(error))
    }
}

/// What is wrong with an SRDF.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SrdfErrorKind {
    /// The XML is not well-formed.
    #[error("malformed XML at byte {position}: {detail}")]
    Xml {
        /// Byte offset of the problem.
        position: u64,
        /// What the parser reported.
        detail: String,
    },
    /// An attribute value is over its limit: a name over
    /// [`MAX_NAME_BYTES`](pickplace_geometry::io::MAX_NAME_BYTES), a `value` or `reason` over
    /// [`MAX_PATH_BYTES`](pickplace_geometry::io::MAX_PATH_BYTES).
    #[error("<{element}> attribute {attribute:?} is {bytes} bytes, over the limit of {limit}")]
    TooLong {
        /// The element.
        element: &'static str,
        /// The attribute.
        attribute: &'static str,
        /// Its length (bytes, as written in the file).
        bytes: usize,
        /// The limit (bytes).
        limit: usize,
    },
    /// The text has no `<robot>` element: not an SRDF.
    #[error("no <robot> element: not an SRDF file")]
    NoRobotElement,
    /// An element lacks a required attribute.
    #[error("<{element}> lacks attribute {attribute:?}")]
    MissingAttribute {
        /// The element.
        element: &'static str,
        /// The attribute.
        attribute: &'static str,
    },
    /// An attribute that must be a number is not one.
    #[error("<{element}> attribute {attribute:?} = {value:?} is not a finite number")]
    BadNumber {
        /// The element.
        element: &'static str,
        /// The attribute.
        attribute: &'static str,
        /// The text found.
        value: String,
    },
    /// An element appears outside the element that must contain it.
    #[error("<{element}> outside <{parent}>")]
    Misplaced {
        /// The element.
        element: &'static str,
        /// Where it belongs.
        parent: &'static str,
    },
    /// A name used in the SRDF is not in the URDF (or not a group).
    #[error("{element} refers to unknown {kind} {name:?}")]
    UnknownName {
        /// The element that uses the name (e.g. `group "right_arm"`).
        element: String,
        /// "link", "joint" or "group".
        kind: &'static str,
        /// The name.
        name: String,
    },
    /// A chain whose tip is not below its base.
    #[error("group {group:?}: chain tip {tip:?} is not below base {base:?}")]
    BadChain {
        /// The group.
        group: String,
        /// Base link.
        base: String,
        /// Tip link.
        tip: String,
    },
    /// A group used as an arm has no moving joint.
    #[error("group {group:?} has no moving joint: it cannot be used as an arm")]
    GroupWithoutJoints {
        /// The group.
        group: String,
    },
    /// A group used as an arm whose moving joints do not form one serial chain.
    #[error(
        "group {group:?}: its joints are not one chain ({first:?} and {second:?} are on different branches)"
    )]
    NotOneChain {
        /// The group.
        group: String,
        /// A joint of the group.
        first: String,
        /// A joint of the group that is not below `first`.
        second: String,
    },
    /// Groups that include each other.
    #[error("group {group:?} includes itself through its subgroups")]
    RecursiveGroup {
        /// The group.
        group: String,
    },
}

/// Result alias of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// The path used in errors for models built from strings.
pub(crate) fn memory_path() -> PathBuf {
    PathBuf::from("<memory>")
}
