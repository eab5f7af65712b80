//! The one place where nalgebra (our math) meets glam (parry's math since parry 0.26).

use parry3d_f64::glamx::glam::{DQuat, DVec3};
use parry3d_f64::math::Pose;
use pickplace_geometry::math::{Isometry3, Point3, Vector3};

/// nalgebra isometry → parry pose.
#[inline]
pub(crate) fn pose(iso: &Isometry3) -> Pose {
    let q = iso.rotation.coords;
    let t = iso.translation.vector;
    Pose::from_parts(
        DVec3::new(t.x, t.y, t.z),
        DQuat::from_xyzw(q.x, q.y, q.z, q.w),
    )
}

/// nalgebra vector → parry vector.
#[inline]
pub(crate) fn vector(v: &Vector3) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}

/// nalgebra point → parry vector (parry 0.31 uses vectors for points).
#[inline]
pub(crate) fn point(p: &Point3) -> DVec3 {
    DVec3::new(p.x, p.y, p.z)
}

/// parry vector → nalgebra point.
#[cfg(test)]
fn to_point(v: DVec3) -> Point3 {
    Point3::new(v.x, v.y, v.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::{Translation3, UnitQuaternion};

    #[test]
    fn pose_conversion_maps_points_the_same_way() {
        let iso = Isometry3::from_parts(
            Translation3::new(0.1, -0.2, 0.3),
            UnitQuaternion::from_euler_angles(0.3, -1.1, 2.0),
        );
        let p = Point3::new(0.4, 0.5, -0.6);
        let ours = iso * p;
        let theirs = pose(&iso).transform_point(point(&p));
        assert!((to_point(theirs) - ours).norm() < 1e-14);
        assert_eq!(
            vector(&Vector3::new(1.0, 2.0, 3.0)),
            DVec3::new(1.0, 2.0, 3.0)
        );
    }
}
