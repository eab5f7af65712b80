//! Object-environment penetration tests with parry3d-f64.
//!
//! parry's public math is glam (through glamx); our nalgebra types are converted by
//! [`pickplace_geometry::parry`].

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::{Pose, Vector as PVector};
use parry3d_f64::shape::{ConvexPolyhedron, TriMesh as ParryTriMesh, TriMeshFlags};
use pickplace_geometry::math::{Isometry3, Point3, Real, Vector3};
use pickplace_geometry::mesh::TriMesh;
use pickplace_geometry::parry;

/// A mesh prepared for collision queries (its BVH is built once).
///
/// A convex object mesh (built with [`CollisionMesh::new`]) also keeps its solid as a parry convex polyhedron: a convex solid against a triangle mesh is
/// one GJK test per nearby environment triangle instead of a test per pair of triangles, about
/// ten times cheaper for the can, and it also sees an environment triangle swallowed whole.
#[derive(Debug, Clone)]
pub struct CollisionMesh {
    shape: ParryTriMesh,
    convex: Option<ConvexPolyhedron>,
    /// The convex hull of a non-convex object mesh: only environment triangles that meet it
    /// can meet the mesh (which lies inside it), so each of those alone is tested against the
    /// mesh (see [`CollisionMesh::intersects`]).
    hull: Option<ConvexPolyhedron>,
    /// The hull's box in the object frame (empty without a hull).
    hull_aabb: Aabb,
    /// Balls inside a closed non-convex object mesh (centre, radius; object frame): an
    /// environment triangle that meets one is inside the object, a penetration found with one
    /// cheap test instead of a search of the object's triangles (a scanned can under a shelf
    /// too low: tens of thousands of placements, each pressing the shelf into the can).
    inner_balls: Vec<(Point3, Real)>,
    vertices: Vec<Point3>,
    triangles: Vec<[u32; 3]>,
}

/// Whether every edge of the mesh is used once in each direction (closed, consistently wound).
fn closed_and_oriented(triangles: &[[u32; 3]]) -> bool {
    let mut edges = std::collections::HashSet::with_capacity(triangles.len() * 3);
    for t in triangles {
        for k in 0..3 {
            if !edges.insert((t[k], t[(k + 1) % 3])) {
                return false;
            }
        }
    }
    edges.iter().all(|&(a, b)| edges.contains(&(b, a)))
}

/// Up to [`INNER_BALLS`] balls inside a closed, outward-wound mesh: the centres of a grid over
/// its bounding box that lie inside (by the mesh's pseudo-normals), each with its distance to
/// the surface (less 1 µm), the largest first, none centred inside a chosen one.
fn inner_balls(
    points: &[PVector],
    vertices: &[Point3],
    triangles: &[[u32; 3]],
) -> Vec<(Point3, Real)> {
    use parry3d_f64::query::PointQuery;
    if vertices.is_empty() || !closed_and_oriented(triangles) {
        return Vec::new();
    }
    let Ok(oriented) =
        ParryTriMesh::with_flags(points.to_vec(), triangles.to_vec(), TriMeshFlags::ORIENTED)
    else {
        return Vec::new();
    };
    let (mut lo, mut hi) = (vertices[0], vertices[0]);
    for p in vertices {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let n = INNER_GRID;
    let mut candidates: Vec<(Real, Point3)> = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let f = |a: usize| (a as Real + 0.5) / n as Real;
                let c = Point3::new(
                    lo.x + (hi.x - lo.x) * f(i),
                    lo.y + (hi.y - lo.y) * f(j),
                    lo.z + (hi.z - lo.z) * f(k),
                );
                let projection = oriented.project_local_point(parry::point(&c), false);
                if projection.is_inside {
                    let r = (parry::to_point(projection.point) - c).norm() - 1e-6;
                    if r > 0.0 {
                        candidates.push((r, c));
                    }
                }
            }
        }
    }
    candidates.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.x.total_cmp(&b.1.x)));
    let mut out: Vec<(Point3, Real)> = Vec::new();
    for (r, c) in candidates {
        if out.len() >= INNER_BALLS {
            break;
        }
        if out.iter().all(|(o, ro)| (c - o).norm() > *ro) {
            out.push((c, r));
        }
    }
    out
}

/// Grid points per axis searched for inner balls.
const INNER_GRID: usize = 8;
/// Inner balls kept.
const INNER_BALLS: usize = 24;

/// The convex hull of a closed, outward-wound mesh when the mesh bounds that hull: the volumes
/// agree to within one part in 10^6 (a dent, a hole or a handle makes the hull larger).
fn convex_solid(
    points: &[PVector],
    vertices: &[Point3],
    triangles: &[[u32; 3]],
) -> Option<ConvexPolyhedron> {
    use parry3d_f64::shape::Shape;
    let hull = ConvexPolyhedron::from_convex_hull(points)?;
    let hull_volume = hull.mass_properties(1.0).mass();
    let mesh_volume: Real = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize].coords);
            a.dot(&b.cross(&c)) / 6.0
        })
        .sum();
    ((hull_volume - mesh_volume).abs() <= 1e-6 * hull_volume).then_some(hull)
}

impl CollisionMesh {
    /// Prepares `mesh` (in its own frame) for queries.
    ///
    /// # Errors
    /// parry rejects meshes without triangles; a [`TriMesh`] always has some, so this only
    /// fails on internal inconsistency, reported as [`crate::Error::DegenerateHull`].
    pub fn new(mesh: &TriMesh) -> crate::Result<Self> {
        Self::from_parts(mesh.vertices().to_vec(), mesh.triangles().to_vec(), true)
    }

    /// Prepares several meshes, each placed at its pose, as one collision mesh.
    ///
    /// # Errors
    /// [`crate::Error::InvalidOption`] when `meshes` is empty; otherwise as [`CollisionMesh::new`].
    pub fn from_meshes(meshes: &[(&TriMesh, Isometry3)]) -> crate::Result<Self> {
        if meshes.is_empty() {
            return Err(crate::Error::InvalidOption {
                name: "environment",
                value: 0.0,
                reason: "no environment mesh given",
            });
        }
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        for (mesh, pose) in meshes {
            let base = u32::try_from(vertices.len()).map_err(|_| crate::Error::DegenerateHull {
                reason: "environment meshes have more than 2^32 vertices".into(),
            })?;
            vertices.extend(mesh.vertices().iter().map(|p| pose * p));
            triangles.extend(mesh.triangles().iter().map(|t| t.map(|i| i + base)));
        }
        Self::from_parts(vertices, triangles, false)
    }

    fn from_parts(
        vertices: Vec<Point3>,
        triangles: Vec<[u32; 3]>,
        detect_convex: bool,
    ) -> crate::Result<Self> {
        let points: Vec<PVector> = vertices.iter().map(parry::point).collect();
        let convex = if detect_convex {
            convex_solid(&points, &vertices, &triangles)
        } else {
            None
        };
        let hull = if detect_convex && convex.is_none() {
            ConvexPolyhedron::from_convex_hull(&points)
        } else {
            None
        };
        let inner_balls = if hull.is_some() {
            inner_balls(&points, &vertices, &triangles)
        } else {
            Vec::new()
        };
        let shape = ParryTriMesh::with_flags(points, triangles.clone(), TriMeshFlags::empty())
            .map_err(|e| crate::Error::DegenerateHull {
                reason: format!("collision mesh: {e:?}"),
            })?;
        let hull_aabb = hull
            .as_ref()
            .map_or(Aabb::new_invalid(), |h| h.local_aabb());
        Ok(Self {
            shape,
            convex,
            hull,
            hull_aabb,
            inner_balls,
            vertices,
            triangles,
        })
    }

    /// Whether the object, at `world_from_object` moved by `lift` (m, world frame), has its
    /// surface intersecting this environment (in world frame).
    pub fn intersects(
        &self,
        object: &CollisionMesh,
        world_from_object: &Isometry3,
        lift: &Vector3,
    ) -> bool {
        let mut pose = *world_from_object;
        pose.translation.vector += lift;
        let env_pose = Pose::IDENTITY;
        // A query parry does not support between two meshes is treated as a collision, the
        // safe answer for a placement.
        let object_pose = parry::pose(&pose);
        let test = |shape: &dyn parry3d_f64::shape::Shape| {
            parry3d_f64::query::intersection_test(&env_pose, &self.shape, &object_pose, shape)
                .map(|hit| hit.intersecting)
                .unwrap_or(true)
        };
        if let Some(solid) = &object.convex {
            return test(solid);
        }
        if let Some(hull) = &object.hull {
            // Only environment triangles that meet the hull can meet the mesh inside it: each
            // is tested against the object's mesh alone. The environment triangles a resting
            // face almost touches (clear of the lifted hull) cost one GJK test each instead of
            // the pairs of nearly coplanar triangles a mesh-mesh traversal visits.
            use parry3d_f64::query::PointQuery;
            use parry3d_f64::shape::Shape;
            // The hull's box from its local one (looser when turned, never smaller): the
            // hull's own box scans every hull vertex per query.
            let aabb = object.hull_aabb.transform_by(&object_pose);
            let balls: Vec<(PVector, Real)> = object
                .inner_balls
                .iter()
                .map(|(c, r)| (parry::point(&(pose * c)), *r))
                .collect();
            let near: Vec<u32> = self.shape.bvh().intersect_aabb(&aabb).collect();
            // The cheap certain answer first, over every nearby triangle: a ball whose centre
            // is farther than its radius from the triangle's box is skipped without the exact
            // distance.
            if near.iter().any(|&j| {
                let triangle = self.shape.triangle(j);
                let lo = triangle.a.min(triangle.b).min(triangle.c);
                let hi = triangle.a.max(triangle.b).max(triangle.c);
                balls.iter().any(|(c, r)| {
                    c.clamp(lo, hi).distance_squared(*c) < r * r
                        && triangle.distance_to_local_point(*c, true) < *r
                })
            }) {
                return true;
            }
            for j in near {
                let triangle = self.shape.triangle(j);
                let meets = |shape: &dyn Shape| {
                    parry3d_f64::query::intersection_test(&env_pose, &triangle, &object_pose, shape)
                        .map(|hit| hit.intersecting)
                        .unwrap_or(true)
                };
                if meets(hull) && meets(&object.shape) {
                    return true;
                }
            }
            return false;
        }
        test(&object.shape)
    }

    /// Points where `object`, at `world_from_object`, is within `reach` (m) of this mesh: one
    /// point per pair of nearby triangles (the midpoint of their closest points), world frame.
    pub fn touching_points(
        &self,
        object: &CollisionMesh,
        world_from_object: &Isometry3,
        reach: Real,
    ) -> Vec<Point3> {
        use parry3d_f64::shape::Triangle;
        let identity = Pose::IDENTITY;
        let mut out = Vec::new();
        for t in &object.triangles {
            let [a, b, c] = t.map(|i| world_from_object * object.vertices[i as usize]);
            let lo = a.inf(&b).inf(&c);
            let hi = a.sup(&b).sup(&c);
            let aabb = Aabb::new(
                PVector::new(lo.x - reach, lo.y - reach, lo.z - reach),
                PVector::new(hi.x + reach, hi.y + reach, hi.z + reach),
            );
            let tri = Triangle::new(parry::point(&a), parry::point(&b), parry::point(&c));
            for j in self.shape.bvh().intersect_aabb(&aabb) {
                let env_tri = self.shape.triangle(j);
                if let Ok(Some(contact)) =
                    parry3d_f64::query::contact(&identity, &tri, &identity, &env_tri, reach)
                {
                    let m = (contact.point1 + contact.point2) * 0.5;
                    out.push(parry::to_point(m));
                }
            }
        }
        out
    }

    /// The mesh's vertices (in the frame it was prepared in).
    pub fn vertices(&self) -> &[Point3] {
        &self.vertices
    }

    /// The distance (m) along the unit direction `dir` from the world point `origin` to this
    /// mesh's surface, the mesh placed at `world_from_mesh`; `None` when the ray misses it
    /// within `max` (m).
    pub fn ray_distance(
        &self,
        world_from_mesh: &Isometry3,
        origin: &Point3,
        dir: &Vector3,
        max: Real,
    ) -> Option<Real> {
        use parry3d_f64::query::{Ray, RayCast};
        let ray = Ray::new(parry::point(origin), parry::vector(dir));
        self.shape
            .cast_ray(&parry::pose(world_from_mesh), &ray, max, false)
    }

    /// As [`CollisionMesh::ray_distance`], with whether the ray leaves the solid there: the
    /// hit triangle's outward normal (from its winding, the mesh placed at `world_from_mesh`)
    /// points along the ray, so `origin` lies inside a closed, outward-wound mesh.
    pub fn ray_hit(
        &self,
        world_from_mesh: &Isometry3,
        origin: &Point3,
        dir: &Vector3,
        max: Real,
    ) -> Option<(Real, bool)> {
        use parry3d_f64::query::{Ray, RayCast};
        let ray = Ray::new(parry::point(origin), parry::vector(dir));
        let hit =
            self.shape
                .cast_ray_and_get_normal(&parry::pose(world_from_mesh), &ray, max, false)?;
        let exits = self.triangles.get(hit.subshape as usize).is_some_and(|t| {
            let [a, b, c] = t.map(|i| self.vertices[i as usize]);
            let n = world_from_mesh.rotation * (b - a).cross(&(c - a));
            n.dot(dir) > 0.0
        });
        Some((hit.time_of_impact, exits))
    }

    /// Whether this mesh bounds a convex solid (queries then use its convex hull).
    pub fn is_convex(&self) -> bool {
        self.convex.is_some()
    }

    /// Distance from a world point to this mesh's surface (m).
    pub fn distance_to_point(&self, p: &Point3) -> Real {
        use parry3d_f64::query::PointQuery;
        self.shape.distance_to_local_point(parry::point(p), false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::Translation3;
    use pickplace_geometry::shapes;
    use pickplace_objects as objects;

    #[test]
    fn resting_box_touches_but_lifted_box_is_free() {
        let table = CollisionMesh::new(&shapes::box_mesh([0.5, 0.5, 0.05])).expect("table");
        let cube = CollisionMesh::new(&shapes::box_mesh([0.02, 0.02, 0.02])).expect("cube");
        let on_top = Isometry3::from_parts(Translation3::new(0.1, 0.0, 0.07), Default::default());
        assert!(!table.intersects(&cube, &on_top, &Vector3::new(0.0, 0.0, 1e-4)));
        assert!(table.intersects(&cube, &on_top, &Vector3::new(0.0, 0.0, -1e-3)));
        let p = Point3::new(0.0, 0.0, 0.2);
        assert!((table.distance_to_point(&p) - 0.15).abs() < 1e-9);
        assert!(cube.is_convex());
    }

    #[test]
    fn a_dented_or_hollow_mesh_is_not_convex() {
        let can = CollisionMesh::new(&objects::can_builder().build().expect("can")).expect("can");
        assert!(can.is_convex());
        let mug = CollisionMesh::new(&objects::mug_builder().build().expect("mug")).expect("mug");
        assert!(!mug.is_convex());
        let pallet = CollisionMesh::new(&objects::pallet_builder().build().expect("pallet"))
            .expect("pallet");
        assert!(!pallet.is_convex());
    }
}
