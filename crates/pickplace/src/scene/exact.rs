//! The scene's fixed-length arrays, read exactly ([`pickplace_geometry::exact`]).

use pickplace_geometry::exact::{array, optional_xyz as optional};
use pickplace_geometry::math::Real;
use serde::de::Deserializer;

/// A pose's `position = [x, y, z]`.
pub fn position<'de, D: Deserializer<'de>>(d: D) -> Result<[Real; 3], D::Error> {
    array(d, "position", "[x, y, z]")
}

/// `target.point = [x, y, z]`.
pub fn point<'de, D: Deserializer<'de>>(d: D) -> Result<[Real; 3], D::Error> {
    array(d, "point", "[x, y, z]")
}

/// A pose's `orientation = [x, y, z, w]`.
pub fn quaternion<'de, D: Deserializer<'de>>(d: D) -> Result<[Real; 4], D::Error> {
    array(d, "orientation", "[x, y, z, w]")
}

/// `object.center_of_gravity = [x, y, z]`, optional.
pub fn optional_xyz<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[Real; 3]>, D::Error> {
    optional(d, "center_of_gravity")
}
