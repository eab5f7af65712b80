//! Gripper-object collision tests with parry3d-f64.
//!
//! parry's public math is glam (through glamx); the conversion from our nalgebra types lives
//! in this module only.

use crate::error::{Error, Result};
use crate::gripper::GripperBox;
use parry3d_f64::math::{Pose, Rotation, Vector as PVector};
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::{Cuboid, TriMesh as ParryTriMesh, TriMeshFlags};
use pickplace_geometry::math::{Isometry3, Point3, Real, UnitQuaternion, Vector3};
use pickplace_geometry::math::nalgebra::Rotation3;
use pickplace_geometry::mesh::TriMesh;

/// The object prepared for collision queries: a parry triangle mesh whose BVH and pseudo-normals
/// are built once.
#[derive(Debug, Clone)]
pub struct ObjectCollider {
    shape: ParryTriMesh,
}

impl ObjectCollider {
    /// Prepares `mesh` (in the object frame) for queries.
    ///
    /// # Errors
    /// [`Error::CollisionMesh`] when parry rejects the mesh (it has no triangle).
    pub fn new(mesh: &TriMesh) -> Result<Self> {
        let vertices: Vec<PVector> = mesh.vertices().iter().map(to_parry_point).collect();
        let shape = ParryTriMesh::with_flags(vertices, mesh.triangles().to_vec(), TriMeshFlags::ORIENTED)
            .map_err(|source| Error::CollisionMesh { source })?;
        Ok(Self { shape })
    }

    /// Whether `body` (a gripper box in the TCP frame, grown by `inflate` m on every side) at
    /// `object_from_tcp` overlaps the object: its surface crosses the object's surface, or its
    /// centre lies inside the object (a box buried in the solid crosses no surface).
    pub fn hits(&self, object_from_tcp: &Isometry3, body: &GripperBox, inflate: Real) -> bool {
        // Gripper box axes are orthonormal (checked when the gripper is validated).
        let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(body.tcp_from_box));
        let tcp_from_box = Isometry3::from_parts(body.center.coords.into(), rotation);
        let object_from_box = object_from_tcp * tcp_from_box;
        let h = body.half_extents.add_scalar(inflate);
        let cuboid = Cuboid::new(PVector::new(h.x, h.y, h.z));
        let surface = parry3d_f64::query::intersection_test(&Pose::IDENTITY, &self.shape, &to_parry_pose(&object_from_box), &cuboid)
            // An unsupported pair never happens for a mesh and a box; treat it as a hit, the safe answer.
            .map(|hit| hit.intersecting)
            .unwrap_or(true);
        surface || self.contains(&Point3::from(object_from_box.translation.vector))
    }

    /// Whether `p` (object frame) is inside the object (by the pseudo-normal of its closest
    /// surface point).
    pub fn contains(&self, p: &Point3) -> bool {
        self.shape.contains_local_point(to_parry_point(p))
    }
}

fn to_parry_point(p: &Point3) -> PVector {
    PVector::new(p.x, p.y, p.z)
}

fn to_parry_pose(iso: &Isometry3) -> Pose {
    let q = iso.rotation.quaternion();
    let t: Vector3 = iso.translation.vector;
    Pose::from_parts(PVector::new(t.x, t.y, t.z), Rotation::from_xyzw(q.i, q.j, q.k, q.w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::{Matrix3, Translation3};
    use pickplace_geometry::shapes;

    fn cube(center: Point3, half: Real) -> GripperBox {
        GripperBox { center, tcp_from_box: Matrix3::identity(), half_extents: Vector3::repeat(half) }
    }

    #[test]
    fn touching_buried_and_free_boxes() {
        let object = ObjectCollider::new(&shapes::box_mesh([0.05, 0.05, 0.05])).expect("valid");
        let identity = Isometry3::identity();
        // Crossing the surface.
        assert!(object.hits(&identity, &cube(Point3::new(0.05, 0.0, 0.0), 0.01), 0.0));
        // Buried in the solid: no surface crossing, caught by containment.
        assert!(object.hits(&identity, &cube(Point3::origin(), 0.01), 0.0));
        // 5 mm away: free, but not with a 6 mm inflation.
        let near = cube(Point3::new(0.065, 0.0, 0.0), 0.01);
        assert!(!object.hits(&identity, &near, 0.0));
        assert!(object.hits(&identity, &near, 0.006));
        // The pose moves the box.
        let away = Isometry3::from_parts(Translation3::new(0.0, 0.0, 0.2), UnitQuaternion::identity());
        assert!(!object.hits(&away, &cube(Point3::origin(), 0.01), 0.0));
    }
}
