//! The one place where our math (nalgebra, [`crate::math`]) meets parry3d-f64's (glam, through
//! glamx, since parry 0.26). Every crate that queries parry (placement, grasp, robot
//! collision) converts here, at the collision boundary, and nowhere else.
//!
//! parry 0.31 represents points as vectors ([`parry3d_f64::math::Vector`], a `DVec3`).
//!
//! # Example
//! ```
//! use pickplace_geometry::math::{Isometry3, Point3};
//! use pickplace_geometry::parry;
//!
//! let world_from_box = Isometry3::translation(0.0, 0.0, 1.0);
//! let p = parry::pose(&world_from_box).transform_point(parry::point(&Point3::origin()));
//! assert_eq!(parry::to_point(p), Point3::new(0.0, 0.0, 1.0));
//! ```

use crate::math::{Isometry3, Point3, Vector3};
use parry3d_f64::math::{Pose, Rotation, Vector};

/// nalgebra isometry → parry pose.
#[inline]
pub fn pose(iso: &Isometry3) -> Pose {
    let q = iso.rotation.coords;
    let t = iso.translation.vector;
    Pose::from_parts(
        Vector::new(t.x, t.y, t.z),
        Rotation::from_xyzw(q.x, q.y, q.z, q.w),
    )
}

/// nalgebra vector → parry vector.
#[inline]
pub fn vector(v: &Vector3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// nalgebra point → parry point (a vector in parry 0.31).
#[inline]
pub fn point(p: &Point3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// parry point (a vector) → nalgebra point.
#[inline]
pub fn to_point(v: Vector) -> Point3 {
    Point3::new(v.x, v.y, v.z)
}

/// parry vector → nalgebra vector.
#[inline]
pub fn to_vector(v: Vector) -> Vector3 {
    Vector3::new(v.x, v.y, v.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Translation3, UnitQuaternion};
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn pose_conversion_maps_points_the_same_way(
            t in proptest::array::uniform3(-2.0..2.0f64),
            euler in proptest::array::uniform3(-3.0..3.0f64),
            p in proptest::array::uniform3(-2.0..2.0f64),
        ) {
            let iso = Isometry3::from_parts(
                Translation3::new(t[0], t[1], t[2]),
                UnitQuaternion::from_euler_angles(euler[0], euler[1], euler[2]),
            );
            let p = Point3::new(p[0], p[1], p[2]);
            let ours = iso * p;
            let theirs = pose(&iso).transform_point(point(&p));
            prop_assert!((to_point(theirs) - ours).norm() < 1e-13);
            let v = p.coords;
            let rotated = pose(&iso).transform_vector(vector(&v));
            prop_assert!((to_vector(rotated) - iso.rotation * v).norm() < 1e-13);
        }
    }

    #[test]
    fn round_trips_are_exact() {
        let p = Point3::new(0.1, -0.2, 1e-300);
        assert_eq!(to_point(point(&p)), p);
        assert_eq!(to_vector(vector(&p.coords)), p.coords);
    }
}
