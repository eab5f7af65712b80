//! The error type of the placement crate.

use pickplace_geometry::math::Real;

/// Errors of `pickplace-placement`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The object's vertices do not span a volume, so it has no convex hull to rest on.
    #[error("the object is flat or degenerate: its convex hull could not be built ({reason})")]
    DegenerateHull {
        /// What the hull builder reported.
        reason: String,
    },
    /// The centre of gravity is not a finite point.
    #[error("centre of gravity ({x}, {y}, {z}) is not finite")]
    NonFiniteCog {
        /// x (m).
        x: Real,
        /// y (m).
        y: Real,
        /// z (m).
        z: Real,
    },
    /// An option is outside its valid range.
    #[error("invalid option {name} = {value}: {reason}")]
    InvalidOption {
        /// Option name.
        name: &'static str,
        /// The value given.
        value: Real,
        /// Why it is invalid.
        reason: &'static str,
    },
    /// An error of the geometry layer (mesh, clusters).
    #[error(transparent)]
    Geometry(#[from] pickplace_geometry::Error),
}

/// Shorthand for results of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;
