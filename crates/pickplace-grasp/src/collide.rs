//! Gripper-object collision tests with parry3d-f64.
//!
//! parry's public math is glam (through glamx); our nalgebra types are converted by
//! [`pickplace_geometry::parry`].

use crate::error::{Error, Result};
use crate::gripper::GripperBox;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector as PVector;
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::{TriMesh as ParryTriMesh, TriMeshFlags};
use pickplace_geometry::math::{Isometry3, Point3, Real, Vector3};
use pickplace_geometry::mesh::TriMesh;
use pickplace_geometry::obb::Obb;
use pickplace_geometry::parry;

/// The object prepared for collision queries: a parry triangle mesh whose BVH and pseudo-normals
/// are built once, and the vertices of its convex hull.
#[derive(Debug, Clone)]
pub struct ObjectCollider {
    shape: ParryTriMesh,
    vertices: Vec<Point3>,
    triangles: Vec<[u32; 3]>,
    /// Vertices of the convex hull (all vertices when the hull cannot be built).
    hull: Vec<Point3>,
}

impl ObjectCollider {
    /// Prepares `mesh` (in the object frame) for queries.
    ///
    /// # Errors
    /// [`Error::CollisionMesh`] when parry rejects the mesh (it has no triangle).
    pub fn new(mesh: &TriMesh) -> Result<Self> {
        let points: Vec<PVector> = mesh.vertices().iter().map(parry::point).collect();
        let hull = match parry3d_f64::transformation::try_convex_hull(&points) {
            Ok((hull, _)) => hull.into_iter().map(parry::to_point).collect(),
            // A flat or degenerate object: every vertex serves as well, only slower.
            Err(_) => mesh.vertices().to_vec(),
        };
        let shape =
            ParryTriMesh::with_flags(points, mesh.triangles().to_vec(), TriMeshFlags::ORIENTED)
                .map_err(|source| Error::CollisionMesh { source })?;
        Ok(Self {
            shape,
            vertices: mesh.vertices().to_vec(),
            triangles: mesh.triangles().to_vec(),
            hull,
        })
    }

    /// Whether `body` (a gripper box in the TCP frame, grown by `inflate` m on every side) at
    /// `object_from_tcp` overlaps the object: its solid touches a triangle, or its centre lies
    /// inside the object (a box buried in the solid touches no triangle).
    ///
    /// # Performance
    /// A face of the box that separates it from the object's convex hull answers at once;
    /// otherwise the triangles whose bounding boxes meet the box's (through the BVH) are tested
    /// with the separating-axis theorem, then the centre's containment (closest point and its
    /// pseudo-normal).
    pub fn hits(&self, object_from_tcp: &Isometry3, body: &GripperBox, inflate: Real) -> bool {
        let r = object_from_tcp.rotation.to_rotation_matrix().into_inner();
        let b = Obb {
            center: object_from_tcp * body.center,
            axes: r * body.tcp_from_box,
            half: body.half_extents.add_scalar(inflate),
        };
        if self.hull_separated(&b) {
            return false;
        }
        let reach = b.reach();
        let (lo, hi) = (b.center - reach, b.center + reach);
        let aabb = Aabb::new(parry::point(&lo), parry::point(&hi));
        let touches = self.shape.bvh().intersect_aabb(&aabb).any(|t| {
            let [i, j, k] = self.triangles[t as usize];
            b.touches_triangle([
                self.vertices[i as usize],
                self.vertices[j as usize],
                self.vertices[k as usize],
            ])
        });
        // A centre outside the mesh's box is outside its solid: no point query.
        touches
            || (self
                .shape
                .local_aabb()
                .contains_local_point(parry::point(&b.center))
                && self.contains(&b.center))
    }

    /// Whether one of the box's face planes has the whole convex hull on its outer side. The
    /// scan of an axis stops at the first pair of hull vertices on both sides of the slab.
    fn hull_separated(&self, b: &Obb) -> bool {
        (0..3).any(|k| {
            let axis: Vector3 = b.axes.column(k).into();
            let (offset, h) = (axis.dot(&b.center.coords), b.half[k]);
            let (mut above, mut below) = (true, true);
            for p in &self.hull {
                let d = axis.dot(&p.coords) - offset;
                above &= d > h;
                below &= d < -h;
                if !(above || below) {
                    return false;
                }
            }
            true
        })
    }

    /// The triangles whose bounding boxes meet the axis-aligned box `[lo, hi]` (object frame),
    /// through the BVH.
    pub(crate) fn triangles_near(&self, lo: &Point3, hi: &Point3) -> Vec<u32> {
        let aabb = Aabb::new(parry::point(lo), parry::point(hi));
        self.shape.bvh().intersect_aabb(&aabb).collect()
    }

    /// Whether `p` (object frame) is inside the object (by the pseudo-normal of its closest
    /// surface point).
    pub fn contains(&self, p: &Point3) -> bool {
        self.shape.contains_local_point(parry::point(p))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::{Matrix3, Translation3, UnitQuaternion};
    use pickplace_geometry::shapes;
    use proptest::prelude::*;

    fn cube(center: Point3, half: Real) -> GripperBox {
        GripperBox {
            center,
            tcp_from_box: Matrix3::identity(),
            half_extents: Vector3::repeat(half),
        }
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
        let away =
            Isometry3::from_parts(Translation3::new(0.0, 0.0, 0.2), UnitQuaternion::identity());
        assert!(!object.hits(&away, &cube(Point3::origin(), 0.01), 0.0));
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

        /// The separating-axis test agrees with parry's support-map query.
        #[test]
        fn sat_agrees_with_parry(
            c in prop::array::uniform3(-0.5..0.5f64), angles in prop::array::uniform3(-3.2..3.2f64),
            half in prop::array::uniform3(0.05..0.6f64), tri in prop::array::uniform9(-1.0..1.0f64),
        ) {
            use parry3d_f64::math::{Pose, Rotation};
            use parry3d_f64::shape::{Cuboid, Triangle};
            let rotation = UnitQuaternion::from_euler_angles(angles[0], angles[1], angles[2]);
            let b = Obb {
                center: Point3::from(c),
                axes: rotation.to_rotation_matrix().into_inner(),
                half: Vector3::from(half),
            };
            let t = [Point3::new(tri[0], tri[1], tri[2]), Point3::new(tri[3], tri[4], tri[5]), Point3::new(tri[6], tri[7], tri[8])];
            prop_assume!((t[1] - t[0]).cross(&(t[2] - t[0])).norm() > 1e-3);
            let q = rotation.quaternion();
            let pose = Pose::from_parts(PVector::new(c[0], c[1], c[2]), Rotation::from_xyzw(q.i, q.j, q.k, q.w));
            let triangle = Triangle::new(parry::point(&t[0]), parry::point(&t[1]), parry::point(&t[2]));
            let expected = parry3d_f64::query::intersection_test(&Pose::IDENTITY, &triangle, &pose, &Cuboid::new(PVector::new(half[0], half[1], half[2])))
                .expect("supported").intersecting;
            let got = b.touches_triangle(t);
            if got != expected {
                // Only grazing contacts may differ: shrinking or growing the box by 1e-9 decides.
                let shrunk = Obb { half: b.half.add_scalar(-1e-9), ..b };
                let grown = Obb { half: b.half.add_scalar(1e-9), ..b };
                prop_assert!(!shrunk.touches_triangle(t) || grown.touches_triangle(t));
                prop_assert!(grown.touches_triangle(t) != shrunk.touches_triangle(t), "disagree: sat {got} parry {expected}");
            }
        }
    }
}
