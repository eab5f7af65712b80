//! The crate's error type: invalid inputs, planning failures with their reason, and codec errors.

/// Result alias used throughout the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong in this crate.
///
/// Planning failures (`StartInvalid`, `NoPath`, ...) carry the reason the planner gave up so that a
/// caller (the pick-and-place pipeline of Harada et al. §III-C) can record it and switch strategy.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The joint space has no joints.
    #[error("the joint space has no joints")]
    EmptySpace,
    /// The lower bounds, upper bounds and weights differ in length.
    #[error(
        "joint space vectors differ in length: {lower} lower bounds, {upper} upper bounds, {weights} weights"
    )]
    SpaceLengths {
        /// Number of lower bounds given.
        lower: usize,
        /// Number of upper bounds given.
        upper: usize,
        /// Number of weights given.
        weights: usize,
    },
    /// The space has more joints than the nearest-neighbour index supports.
    #[error("dimension {dimension} exceeds the supported maximum of {max}")]
    DimensionTooLarge {
        /// Requested dimension.
        dimension: usize,
        /// Largest supported dimension.
        max: usize,
    },
    /// A joint's bounds are not finite or not ordered.
    #[error("joint {joint}: bounds [{lower}, {upper}] are not finite and ordered")]
    InvalidBounds {
        /// Joint index.
        joint: usize,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },
    /// A joint's distance weight is not finite and positive.
    #[error("joint {joint}: distance weight {weight} is not finite and positive")]
    InvalidWeight {
        /// Joint index.
        joint: usize,
        /// The weight given.
        weight: f64,
    },
    /// A state has the wrong number of coordinates.
    #[error("state has {found} coordinates, the space has {expected}")]
    StateDimension {
        /// Dimension of the space.
        expected: usize,
        /// Length of the state given.
        found: usize,
    },
    /// A state coordinate is outside the joint bounds or not finite.
    #[error("joint {joint}: value {value} is outside [{lower}, {upper}]")]
    StateOutOfBounds {
        /// Joint index.
        joint: usize,
        /// The value given.
        value: f64,
        /// Lower bound of the joint.
        lower: f64,
        /// Upper bound of the joint.
        upper: f64,
    },
    /// An option has a value outside its allowed range.
    #[error("option `{name}` = {value} is invalid: expected {expected}")]
    InvalidOption {
        /// Name of the option field.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// A per-joint limit (velocity or acceleration) is not finite and positive.
    #[error("joint {joint}: {limit} limit {value} is not finite and positive")]
    InvalidLimit {
        /// Joint index.
        joint: usize,
        /// Which limit (`"velocity"` or `"acceleration"`).
        limit: &'static str,
        /// The value given.
        value: f64,
    },
    /// A list of per-joint values has the wrong length.
    #[error("{what} has {found} entries, the space has {expected} joints")]
    JointCount {
        /// Which list.
        what: &'static str,
        /// Dimension of the space.
        expected: usize,
        /// Length of the list given.
        found: usize,
    },
    /// A timed trajectory would have more samples than
    /// [`crate::timing::MAX_TRAJECTORY_SAMPLES`]: refused before it is allocated.
    #[error(
        "the timed trajectory would last {duration:.4e} s, {samples:.4e} samples at {sample_period} s, more than the limit of {limit} samples (MAX_TRAJECTORY_SAMPLES); joint {joint}, velocity limit {velocity}, sets the pace: is a velocity or acceleration limit far too small?"
    )]
    TooManySamples {
        /// Samples the trajectory would have.
        samples: f64,
        /// The limit.
        limit: usize,
        /// Its duration (s).
        duration: f64,
        /// The sampling period (s).
        sample_period: f64,
        /// The joint that sets the pace of its longest segment.
        joint: usize,
        /// That joint's velocity limit.
        velocity: f64,
    },
    /// A time-optimal parameterization ([`crate::toppra`]) would need more grid points or
    /// samples than [`crate::timing::MAX_TRAJECTORY_SAMPLES`]: refused before allocating.
    #[error(
        "the time-optimal parameterization would need {count:.4e} {what}, more than the limit of {limit} (MAX_TRAJECTORY_SAMPLES): is a limit far too small or the step too fine?"
    )]
    TooManyPoints {
        /// `"grid points"` or `"samples"`.
        what: &'static str,
        /// How many it would need.
        count: f64,
        /// The limit.
        limit: usize,
    },
    /// A path has no waypoints.
    #[error("the path has no waypoints")]
    EmptyPath,
    /// The k-d tree could not be built.
    #[error("the nearest-neighbour index could not be built over {nodes} nodes")]
    NearestIndex {
        /// Number of nodes.
        nodes: usize,
    },

    /// The start state is in collision (rejected by the validity checker).
    #[error("the start state is invalid")]
    StartInvalid,
    /// The goal state is in collision (rejected by the validity checker).
    #[error("the goal state is invalid")]
    GoalInvalid,
    /// No valid edge joins the start to the roadmap, even after growing it.
    #[error("could not connect the start to the roadmap after {growth_rounds} growth rounds")]
    StartNotConnected {
        /// Growth rounds performed.
        growth_rounds: usize,
    },
    /// No valid edge joins the goal to the roadmap, even after growing it.
    #[error("could not connect the goal to the roadmap after {growth_rounds} growth rounds")]
    GoalNotConnected {
        /// Growth rounds performed.
        growth_rounds: usize,
    },
    /// Start and goal are connected to the roadmap but lie in different components.
    #[error(
        "no path between start and goal after {growth_rounds} growth rounds ({nodes_added} nodes added)"
    )]
    NoPath {
        /// Growth rounds performed.
        growth_rounds: usize,
        /// Nodes added by growth.
        nodes_added: usize,
    },
    /// RRT-Connect used all its iterations without joining its trees.
    #[error("RRT-Connect found no path in {iterations} iterations")]
    RrtExhausted {
        /// Iterations performed.
        iterations: usize,
    },
    /// RRT-Connect ran out of its time limit without joining its trees.
    #[error(
        "RRT-Connect found no path within its time limit of {seconds} s ({iterations} iterations)"
    )]
    RrtOutOfTime {
        /// The limit (s).
        seconds: f64,
        /// Iterations performed.
        iterations: usize,
    },

    /// Bytes do not start with the roadmap magic.
    #[error("not a roadmap file: magic {found:?}")]
    BadMagic {
        /// The first bytes found (zero-padded when the input is shorter).
        found: [u8; 8],
    },
    /// The roadmap file has a format version this build cannot read.
    #[error(
        "roadmap format version {found} is not supported (this build reads version {supported})"
    )]
    UnsupportedVersion {
        /// Version in the file.
        found: u32,
        /// Version this build reads.
        supported: u32,
    },
    /// The roadmap was built for a space of another dimension.
    #[error(
        "the roadmap was built for a {stored}-joint space, the space given has {expected} joints"
    )]
    DimensionMismatch {
        /// Dimension stored in the file.
        stored: usize,
        /// Dimension of the space given.
        expected: usize,
    },
    /// The roadmap was built for a space with other bounds or weights.
    #[error(
        "the roadmap was built for another space: joint {joint} {field} is {stored}, expected {expected}"
    )]
    SpaceMismatch {
        /// Joint index.
        joint: usize,
        /// `"lower bound"`, `"upper bound"` or `"weight"`.
        field: &'static str,
        /// Value stored in the file.
        stored: f64,
        /// Value of the space given.
        expected: f64,
    },
    /// The roadmap file is truncated or its body is inconsistent.
    #[error("corrupt roadmap: {what} (at index {index})")]
    CorruptRoadmap {
        /// What is wrong.
        what: &'static str,
        /// Index of the offending item (node, edge or byte).
        index: usize,
    },
    /// bincode could not decode the roadmap body.
    #[error("could not decode the roadmap body")]
    Decode {
        /// The decoder's error.
        #[source]
        source: bincode::error::DecodeError,
    },
    /// bincode could not encode the roadmap.
    #[error("could not encode the roadmap")]
    Encode {
        /// The encoder's error.
        #[source]
        source: bincode::error::EncodeError,
    },
}
