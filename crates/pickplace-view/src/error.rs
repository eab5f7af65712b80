//! The error type of the view crate.

/// Errors of `pickplace-view`. Each says which file, parameter or element is wrong and how.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be written (or its temporary file renamed into place) by the one
    /// atomic writer, [`pickplace_geometry::io::write_atomic`]; its error names the file.
    #[error(transparent)]
    Write {
        /// The writer's error.
        #[from]
        source: pickplace_geometry::io::WriteError,
    },
    /// The PNG encoder refused the image.
    #[error("PNG encoding of a {width}x{height} image failed: {source}")]
    PngEncode {
        /// Image width (pixels).
        width: u32,
        /// Image height (pixels).
        height: u32,
        /// The encoder's error.
        #[source]
        source: png::EncodingError,
    },
    /// A parameter is outside its valid range.
    #[error("invalid parameter {name} = {}: {reason}", pickplace_geometry::io::fmt_real(*.value))]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// Why it is invalid.
        reason: &'static str,
    },
    /// An image (or a picture to render) has more pixels than
    /// [`MAX_IMAGE_PIXELS`](crate::MAX_IMAGE_PIXELS); refused before its buffers are allocated.
    #[error(
        "an image of {width}x{height} pixels is {pixels} pixels, over the limit of {limit} (8192x8192)"
    )]
    ImageTooLarge {
        /// Width asked for (pixels).
        width: u64,
        /// Height asked for (pixels).
        height: u64,
        /// `width * height`.
        pixels: u64,
        /// [`MAX_IMAGE_PIXELS`](crate::MAX_IMAGE_PIXELS).
        limit: u64,
    },
    /// Geometry handed to the scene or the glTF writer is malformed.
    #[error("invalid geometry: {kind}")]
    Geometry {
        /// What is wrong.
        kind: GeometryErrorKind,
    },
    /// A glTF document being built is inconsistent (wrong index, bad animation track).
    #[error("invalid glTF document: {kind}")]
    Gltf {
        /// What is wrong.
        kind: GltfErrorKind,
    },
    /// Forward kinematics of the robot failed.
    #[error("robot kinematics: {source}")]
    Robot {
        /// The robot crate's error.
        #[source]
        source: pickplace_robot::Error,
    },
    /// A motion to show (times, configurations, grips) is inconsistent.
    #[error("invalid motion: {kind}")]
    Motion {
        /// What is wrong.
        kind: MotionErrorKind,
    },
    /// A `.glb` file read back by [`crate::glb::validate_glb`] breaks the glTF 2.0 rules.
    #[error("invalid .glb: {kind}")]
    InvalidGlb {
        /// What is wrong.
        kind: GlbErrorKind,
    },
}

/// What is wrong with geometry.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GeometryErrorKind {
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle} refers to vertex {index}, but there are {vertex_count} vertices")]
    IndexOutOfRange {
        /// The triangle.
        triangle: usize,
        /// The vertex index found.
        index: u32,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// The vertex.
        vertex: usize,
    },
    /// A per-triangle colour list does not have one colour per triangle.
    #[error("{found} triangle colours for {expected} triangles")]
    ColourCount {
        /// Number of triangles.
        expected: usize,
        /// Number of colours given.
        found: usize,
    },
    /// The geometry has no triangle where at least one is needed.
    #[error("the geometry has no triangle")]
    Empty,
    /// A pose has a non-finite component.
    #[error("pose of {what} has a non-finite component")]
    NonFinitePose {
        /// Which pose ("instance", "marker", "node").
        what: &'static str,
    },
}

/// What is wrong with a motion handed to [`crate::plan::PlanView`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MotionErrorKind {
    /// The motion has no frame.
    #[error("the motion has no frame")]
    Empty,
    /// Times and configurations have different lengths.
    #[error("{times} times but {configurations} configurations")]
    FrameCount {
        /// Number of times.
        times: usize,
        /// Number of configurations.
        configurations: usize,
    },
    /// A time is not finite or goes back.
    #[error("time {index} is not finite or earlier than the previous one")]
    TimesNotIncreasing {
        /// Index of the offending time.
        index: usize,
    },
    /// A configuration does not have one value per robot variable, or a non-finite one.
    #[error("configuration {frame} has {found} finite values, the robot has {expected} variables")]
    Configuration {
        /// The frame.
        frame: usize,
        /// Number of robot variables.
        expected: usize,
        /// Number of values given (or the index of the first non-finite one).
        found: usize,
    },
    /// A grip names a link the robot does not have.
    #[error("grip {grip}: link index {link} is out of range ({count} links)")]
    UnknownLink {
        /// The grip.
        grip: usize,
        /// The link index.
        link: usize,
        /// Number of links.
        count: usize,
    },
    /// A grip's times are not finite, or it is released before it is grasped, or it overlaps
    /// the previous grip.
    #[error("grip {grip}: grasp and release times are not finite and in order")]
    GripTimes {
        /// The grip.
        grip: usize,
    },
}

/// What is wrong with a glTF document being built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GltfErrorKind {
    /// A node, mesh or parent index does not exist.
    #[error("{what} index {index} is out of range ({count} exist)")]
    IndexOutOfRange {
        /// "mesh", "node" or "parent".
        what: &'static str,
        /// The index given.
        index: usize,
        /// How many exist.
        count: usize,
    },
    /// An animation track has no keyframe.
    #[error("animation track of node {node} has no keyframe")]
    EmptyTrack {
        /// The animated node.
        node: usize,
    },
    /// Keyframe times and values have different lengths.
    #[error("animation track of node {node}: {times} times but {values} {path} values")]
    TrackLength {
        /// The animated node.
        node: usize,
        /// "translation" or "rotation".
        path: &'static str,
        /// Number of times.
        times: usize,
        /// Number of values.
        values: usize,
    },
    /// Keyframe times are not finite and strictly increasing (after conversion to `f32`).
    #[error(
        "animation track of node {node}: time {index} is not finite and strictly after the previous one"
    )]
    TimesNotIncreasing {
        /// The animated node.
        node: usize,
        /// Index of the offending time.
        index: usize,
    },
    /// A keyframe value is NaN or infinite.
    #[error("animation track of node {node}: {path} value {index} is not finite")]
    NonFiniteValue {
        /// The animated node.
        node: usize,
        /// "translation" or "rotation".
        path: &'static str,
        /// Index of the offending keyframe.
        index: usize,
    },
    /// The same node and path are animated twice.
    #[error("node {node} has two {path} tracks")]
    DuplicateTrack {
        /// The animated node.
        node: usize,
        /// "translation" or "rotation".
        path: &'static str,
    },
    /// The binary buffer would exceed the 4 GiB a `.glb` can address.
    #[error("binary buffer of {bytes} bytes exceeds the .glb limit")]
    TooLarge {
        /// Bytes needed.
        bytes: u64,
    },
}

/// What is wrong with a `.glb` file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GlbErrorKind {
    /// The file ends before a structure it announces.
    #[error("truncated: {what} needs {needed} bytes, {available} available")]
    Truncated {
        /// The structure being read.
        what: &'static str,
        /// Bytes needed.
        needed: u64,
        /// Bytes available.
        available: u64,
    },
    /// The file does not start with `glTF`.
    #[error("bad magic (not a binary glTF)")]
    BadMagic,
    /// The container version is not 2.
    #[error("container version {version}, expected 2")]
    Version {
        /// Version found.
        version: u32,
    },
    /// The header's length is not the file's length.
    #[error("header says {header} bytes, the file has {actual}")]
    LengthMismatch {
        /// Length in the header.
        header: u64,
        /// Actual length.
        actual: u64,
    },
    /// A chunk has the wrong type, or a length that is not a multiple of 4.
    #[error("chunk {index}: type {chunk_type:#010x}, length {length}: {reason}")]
    Chunk {
        /// Chunk number (0 = JSON).
        index: usize,
        /// Chunk type found.
        chunk_type: u32,
        /// Chunk length.
        length: u64,
        /// The rule broken.
        reason: &'static str,
    },
    /// The JSON chunk is not valid JSON.
    #[error("JSON chunk: {detail}")]
    Json {
        /// What the parser reported.
        detail: String,
    },
    /// A required property is missing or has the wrong JSON type.
    #[error("{element} {index}: property {property} is missing or malformed")]
    Property {
        /// "accessor", "bufferView", "node", ...
        element: &'static str,
        /// Index of the element (0 for top-level properties).
        index: usize,
        /// The property.
        property: &'static str,
    },
    /// An index refers to an element that does not exist.
    #[error("{element} {index}: {property} = {value} is out of range ({count} exist)")]
    Reference {
        /// The referring element.
        element: &'static str,
        /// Its index.
        index: usize,
        /// The referring property.
        property: &'static str,
        /// The index found.
        value: u64,
        /// How many exist.
        count: usize,
    },
    /// A byte range does not fit in its container.
    #[error("{element} {index}: bytes {start}..{end} exceed its container of {container} bytes")]
    Range {
        /// "accessor" or "bufferView".
        element: &'static str,
        /// Its index.
        index: usize,
        /// First byte.
        start: u64,
        /// One past the last byte.
        end: u64,
        /// Size of the container.
        container: u64,
    },
    /// A value breaks a glTF rule (alignment, min/max, monotone times, counts).
    #[error("{element} {index}: {rule}")]
    Rule {
        /// The element.
        element: &'static str,
        /// Its index.
        index: usize,
        /// The rule broken.
        rule: &'static str,
    },
    /// An animation sampler's input and output counts disagree.
    #[error("animation {animation} sampler {sampler}: {input} times but {output} values")]
    SamplerCounts {
        /// Animation index.
        animation: usize,
        /// Sampler index.
        sampler: usize,
        /// Input accessor count.
        input: u64,
        /// Output accessor count.
        output: u64,
    },
}

/// Shorthand for results of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

pub(crate) fn glb_error(kind: GlbErrorKind) -> Error {
    Error::InvalidGlb { kind }
}
