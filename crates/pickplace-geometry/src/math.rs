//! Math aliases shared by every pickplace crate.
//!
//! Everything is `f64` (SI units: metres, radians, kilograms, seconds). The crates above
//! re-use these aliases and this `nalgebra` so that the workspace has one math library.

pub use nalgebra;

/// The scalar type of the whole workspace.
pub type Real = f64;
/// A 3D point (m).
pub type Point3 = nalgebra::Point3<Real>;
/// A 3D vector.
pub type Vector3 = nalgebra::Vector3<Real>;
/// A unit 3D vector.
pub type UnitVector3 = nalgebra::Unit<nalgebra::Vector3<Real>>;
/// A 2D point (m), in the frame of a contact plane.
pub type Point2 = nalgebra::Point2<Real>;
/// A 2D vector.
pub type Vector2 = nalgebra::Vector2<Real>;
/// A rigid transform. Name values by the frames they map: `world_from_object`.
pub type Isometry3 = nalgebra::Isometry3<Real>;
/// A unit quaternion.
pub type UnitQuaternion = nalgebra::UnitQuaternion<Real>;
/// A 3x3 matrix.
pub type Matrix3 = nalgebra::Matrix3<Real>;
/// A translation.
pub type Translation3 = nalgebra::Translation3<Real>;
