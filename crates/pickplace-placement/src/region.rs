//! Contact regions: a cluster seen by the placement planner.

use pickplace_geometry::cluster::Cluster;
use pickplace_geometry::math::nalgebra::Rotation3;
use pickplace_geometry::math::{
    Isometry3, Matrix3, Point2, Point3, Real, Translation3, UnitQuaternion, Vector3,
};
use pickplace_geometry::mesh::TriMesh;
use pickplace_geometry::polygon::{Polygon, Rect2, convex_hull, min_area_rect};

/// A planar contact region of the object or of the environment (paper §III-A.2): a cluster's
/// contact plane with its boundary, 2D convex hull and minimum-area bounding rectangle.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// Id of the cluster this region comes from.
    pub cluster_id: usize,
    /// Frame of the contact plane in its parent (the object frame for object regions, the
    /// world for environment regions): origin on the plane, z along the outward normal.
    pub parent_from_plane: Isometry3,
    /// Outer boundary and holes, in plane coordinates.
    pub polygon: Polygon,
    /// 2D convex hull of the boundary (counter-clockwise).
    pub hull: Vec<Point2>,
    /// Minimum-area bounding rectangle (the paper's 2D bounding box).
    pub rect: Rect2,
    /// Convex hull of the points of the region that actually lie on the contact plane (within
    /// the contact tolerance), counter-clockwise. For a flat region it is [`Region::hull`]; for
    /// a slightly curved one (a strip of a tessellated cylinder, h > 0) it shrinks to the line
    /// the object really rests on, which the stability test (Fig. 7) must use.
    pub support: Vec<Point2>,
    /// Area of the region (m²).
    pub area: Real,
}

impl Region {
    /// Builds a region from a plane frame and a polygon; `None` when the polygon is empty.
    pub fn new(cluster_id: usize, parent_from_plane: Isometry3, polygon: Polygon) -> Option<Self> {
        let points: Vec<Point2> = polygon.points().copied().collect();
        let hull = convex_hull(&points);
        let rect = min_area_rect(&points)?;
        let area = polygon.area();
        Some(Self {
            cluster_id,
            parent_from_plane,
            polygon,
            support: hull.clone(),
            hull,
            rect,
            area,
        })
    }

    /// The region of a cluster (paper §III-A.2) of a mesh placed at `parent_from_mesh`: the
    /// cluster's contact plane S, its 2D frame (z along the outer normal n) and its boundaries.
    /// `None` when the cluster's region is empty.
    pub fn from_cluster(cluster: &Cluster, parent_from_mesh: &Isometry3) -> Option<Self> {
        let f = &cluster.frame;
        let n = f.normal();
        let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
            Matrix3::from_columns(&[f.u, f.v, n]),
        ));
        let mesh_from_plane = Isometry3::from_parts(Translation3::from(f.origin.coords), rotation);
        let mut region = Self::new(
            cluster.id as usize,
            parent_from_mesh * mesh_from_plane,
            cluster.region.clone(),
        )?;
        region.rect = cluster.bounding_rect;
        region.hull.clone_from(&cluster.hull);
        region.support.clone_from(&cluster.hull);
        Some(region)
    }

    /// As [`Region::from_cluster`], with [`Region::support`] computed from the cluster's
    /// vertices in `mesh` that lie within `tolerance` (m) of the contact plane.
    pub fn from_cluster_on_mesh(
        cluster: &Cluster,
        mesh: &TriMesh,
        parent_from_mesh: &Isometry3,
        tolerance: Real,
    ) -> Option<Self> {
        let mut region = Self::from_cluster(cluster, parent_from_mesh)?;
        let mut on_plane: Vec<Point2> = Vec::new();
        for &t in &cluster.triangles {
            for p in mesh.triangle_points(t as usize) {
                if cluster.plane_distance(&p) >= -tolerance {
                    on_plane.push(cluster.frame.to_2d(&p));
                }
            }
        }
        let support = convex_hull(&on_plane);
        region.support = support;
        Some(region)
    }

    /// The region moved onto the plane with outward unit normal `normal` at `offset`
    /// (`normal · p = offset`, parent frame) that the object really rests on (the contact
    /// model, [`crate::stability::CONTACT_TOLERANCE`]): a cluster's fitted plane is tilted from
    /// its resting facet by the unevenness of a scanned base, and placed on its fitted plane the
    /// object would rock onto the facet. The boundary is projected onto the new plane; the
    /// support becomes the hull of `points` (parent frame) within `tolerance` of it.
    pub fn on_plane(
        &self,
        normal: &Vector3,
        offset: Real,
        points: &[Point3],
        tolerance: Real,
    ) -> Option<Self> {
        let turn = crate::resting::rotation_taking(&self.normal(), normal);
        let rotation = turn * self.parent_from_plane.rotation;
        let o = Point3::from(self.parent_from_plane.translation.vector);
        let origin = o - normal * (normal.dot(&o.coords) - offset);
        let parent_from_plane = Isometry3::from_parts(Translation3::from(origin.coords), rotation);
        let project = |q: &Point2| {
            let p = self.parent_from_plane * Point3::new(q.x, q.y, 0.0);
            let r = parent_from_plane.inverse_transform_point(&p);
            Point2::new(r.x, r.y)
        };
        let polygon = Polygon {
            outer: self.polygon.outer.iter().map(project).collect(),
            holes: self
                .polygon
                .holes
                .iter()
                .map(|h| h.iter().map(project).collect())
                .collect(),
        };
        let mut region = Self::new(self.cluster_id, parent_from_plane, polygon)?;
        let on: Vec<Point2> = points
            .iter()
            .filter(|p| offset - normal.dot(&p.coords) <= tolerance)
            .map(|p| {
                let r = parent_from_plane.inverse_transform_point(p);
                Point2::new(r.x, r.y)
            })
            .collect();
        region.support = convex_hull(&on);
        Some(region)
    }

    /// Outward unit normal in the parent frame.
    pub fn normal(&self) -> Vector3 {
        self.parent_from_plane.rotation * Vector3::z()
    }

    /// The region moved by `pose` (its parent becomes the pose's parent).
    pub fn transformed(&self, pose: &Isometry3) -> Self {
        Self {
            parent_from_plane: pose * self.parent_from_plane,
            ..self.clone()
        }
    }

    /// A point of the parent frame in plane coordinates: (x, y) on the plane and the height
    /// above it.
    pub fn to_plane(&self, p: &Point3) -> (Point2, Real) {
        let q = self.parent_from_plane.inverse_transform_point(p);
        (Point2::new(q.x, q.y), q.z)
    }
}
