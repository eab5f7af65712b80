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

/// Möller–Trumbore line/triangle intersection, two-sided: the parameter `t` of the crossing
/// `o + t d` (either sign), `None` when the line misses the triangle or runs parallel to it.
/// A crossing within `edge_tolerance` (barycentric) of an edge counts, so a line through an
/// edge shared by two triangles meets both.
pub fn line_triangle(
    o: &Point3,
    d: &Vector3,
    [a, b, c]: [&Point3; 3],
    edge_tolerance: Real,
) -> Option<Real> {
    let e1 = b - a;
    let e2 = c - a;
    let p = d.cross(&e2);
    let det = e1.dot(&p);
    if det.abs() < 1e-300 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - a;
    let u = s.dot(&p) * inv;
    if !(-edge_tolerance..=1.0 + edge_tolerance).contains(&u) {
        return None;
    }
    let q = s.cross(&e1);
    let v = d.dot(&q) * inv;
    if v < -edge_tolerance || u + v > 1.0 + edge_tolerance {
        return None;
    }
    let t = e2.dot(&q) * inv;
    t.is_finite().then_some(t)
}
