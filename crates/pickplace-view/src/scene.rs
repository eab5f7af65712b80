//! Scenes: shared triangle geometry placed by poses, coloured per instance or per triangle, and
//! marker shapes (points, arrows, frame axes).

use crate::error::{Error, GeometryErrorKind, Result};
use crate::image::Colour;
use pickplace_geometry::math::{Isometry3, Point3, Real, UnitQuaternion, Vector3};
use pickplace_geometry::mesh::TriMesh;
use std::sync::Arc;

/// Positions and triangles of a mesh in its own frame, validated once and shared (through
/// [`Arc`]) by every instance that draws it.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    positions: Vec<Point3>,
    triangles: Vec<[u32; 3]>,
}

impl Geometry {
    /// Geometry from raw positions and counter-clockwise index triples.
    ///
    /// # Errors
    /// [`GeometryErrorKind::IndexOutOfRange`] or [`GeometryErrorKind::NonFiniteCoordinate`].
    pub fn new(positions: Vec<Point3>, triangles: Vec<[u32; 3]>) -> Result<Self> {
        if let Some(vertex) = positions
            .iter()
            .position(|p| !p.coords.iter().all(|c| c.is_finite()))
        {
            return Err(Error::Geometry {
                kind: GeometryErrorKind::NonFiniteCoordinate { vertex },
            });
        }
        for (triangle, t) in triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(Error::Geometry {
                    kind: GeometryErrorKind::IndexOutOfRange {
                        triangle,
                        index,
                        vertex_count: positions.len(),
                    },
                });
            }
        }
        Ok(Self {
            positions,
            triangles,
        })
    }

    /// The geometry of a mesh (a [`TriMesh`] is valid by construction).
    pub fn from_trimesh(mesh: &TriMesh) -> Self {
        Self {
            positions: mesh.vertices().to_vec(),
            triangles: mesh.triangles().to_vec(),
        }
    }

    /// Vertex positions (mesh frame, m).
    pub fn positions(&self) -> &[Point3] {
        &self.positions
    }

    /// Index triples, counter-clockwise seen from the front.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Unit normal of a triangle (mesh frame); zero for a degenerate triangle.
    pub fn triangle_normal(&self, triangle: usize) -> Vector3 {
        let [a, b, c] = self.triangles[triangle].map(|v| self.positions[v as usize]);
        let n = (b - a).cross(&(c - a));
        let norm = n.norm();
        if norm > 0.0 {
            n / norm
        } else {
            Vector3::zeros()
        }
    }

    /// Axis-aligned bounds `(min, max)` of the positions under `pose`, or `None` when empty.
    pub fn bounds(&self, pose: &Isometry3) -> Option<(Point3, Point3)> {
        let mut it = self.positions.iter().map(|p| pose * p);
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| (lo.inf(&p), hi.sup(&p))))
    }
}

impl From<&TriMesh> for Geometry {
    fn from(mesh: &TriMesh) -> Self {
        Self::from_trimesh(mesh)
    }
}

/// How an instance is coloured.
#[derive(Debug, Clone, PartialEq)]
pub enum Paint {
    /// One colour for the whole instance.
    Uniform(Colour),
    /// One colour per triangle, in the geometry's triangle order (cluster pictures).
    PerTriangle(Arc<[Colour]>),
}

impl Paint {
    /// The colour of a triangle.
    pub fn colour(&self, triangle: usize) -> Colour {
        match self {
            Paint::Uniform(c) => *c,
            Paint::PerTriangle(cs) => cs.get(triangle).copied().unwrap_or(Colour::GREY),
        }
    }
}

/// A geometry drawn at a pose with a paint.
#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    geometry: Arc<Geometry>,
    world_from_mesh: Isometry3,
    paint: Paint,
    opacity: Real,
}

impl Instance {
    /// An instance.
    ///
    /// # Errors
    /// [`GeometryErrorKind::ColourCount`] when a per-triangle paint does not have one colour
    /// per triangle; [`GeometryErrorKind::NonFinitePose`] for a pose with NaN or infinity.
    pub fn new(geometry: Arc<Geometry>, world_from_mesh: Isometry3, paint: Paint) -> Result<Self> {
        if let Paint::PerTriangle(cs) = &paint
            && cs.len() != geometry.triangle_count()
        {
            return Err(Error::Geometry {
                kind: GeometryErrorKind::ColourCount {
                    expected: geometry.triangle_count(),
                    found: cs.len(),
                },
            });
        }
        check_pose(&world_from_mesh, "instance")?;
        Ok(Self {
            geometry,
            world_from_mesh,
            paint,
            opacity: 1.0,
        })
    }

    /// The same instance drawn translucent: `opacity` 1 is opaque, 0 invisible. Translucent
    /// instances are drawn after the opaque ones, farthest first, blended over what is behind
    /// them and hidden by what is in front (used for candidate placements, as in the paper's
    /// Fig. 6).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an opacity outside [0, 1].
    pub fn with_opacity(self, opacity: Real) -> Result<Self> {
        if !(0.0..=1.0).contains(&opacity) {
            return Err(Error::InvalidParameter {
                name: "opacity",
                value: opacity,
                reason: "must be in [0, 1]",
            });
        }
        Ok(Self { opacity, ..self })
    }

    /// The opacity, in [0, 1] (1 unless set by [`Instance::with_opacity`]).
    pub fn opacity(&self) -> Real {
        self.opacity
    }

    /// The geometry.
    pub fn geometry(&self) -> &Arc<Geometry> {
        &self.geometry
    }

    /// The pose of the mesh frame in the world.
    pub fn world_from_mesh(&self) -> &Isometry3 {
        &self.world_from_mesh
    }

    /// The paint.
    pub fn paint(&self) -> &Paint {
        &self.paint
    }
}

pub(crate) fn check_pose(pose: &Isometry3, what: &'static str) -> Result<()> {
    let finite = pose.translation.vector.iter().all(|c| c.is_finite())
        && pose.rotation.coords.iter().all(|c| c.is_finite());
    if finite {
        Ok(())
    } else {
        Err(Error::Geometry {
            kind: GeometryErrorKind::NonFinitePose { what },
        })
    }
}

/// A list of instances to render or export.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Scene {
    instances: Vec<Instance>,
}

impl Scene {
    /// An empty scene.
    pub fn new() -> Self {
        Self::default()
    }

    /// The instances, in drawing order.
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// Total number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.instances
            .iter()
            .map(|i| i.geometry.triangle_count())
            .sum()
    }

    /// Adds an instance.
    pub fn push(&mut self, instance: Instance) {
        self.instances.push(instance);
    }

    /// Adds a mesh in one colour.
    ///
    /// # Errors
    /// [`GeometryErrorKind::NonFinitePose`].
    pub fn add_mesh(
        &mut self,
        mesh: &TriMesh,
        world_from_mesh: Isometry3,
        colour: Colour,
    ) -> Result<()> {
        let instance = Instance::new(
            Arc::new(Geometry::from_trimesh(mesh)),
            world_from_mesh,
            Paint::Uniform(colour),
        )?;
        self.push(instance);
        Ok(())
    }

    /// Adds a mesh with one colour per triangle (for example [`Colour::palette`] of each
    /// triangle's cluster).
    ///
    /// # Errors
    /// [`GeometryErrorKind::ColourCount`] or [`GeometryErrorKind::NonFinitePose`].
    pub fn add_mesh_per_triangle(
        &mut self,
        mesh: &TriMesh,
        world_from_mesh: Isometry3,
        colours: Vec<Colour>,
    ) -> Result<()> {
        let paint = Paint::PerTriangle(colours.into());
        let instance = Instance::new(
            Arc::new(Geometry::from_trimesh(mesh)),
            world_from_mesh,
            paint,
        )?;
        self.push(instance);
        Ok(())
    }

    /// Adds a point marker: a sphere of `radius` (m) centred on `p_in_world`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-positive radius;
    /// [`GeometryErrorKind::NonFinitePose`] for a non-finite point.
    pub fn add_point_marker(
        &mut self,
        p_in_world: Point3,
        radius: Real,
        colour: Colour,
    ) -> Result<()> {
        let geometry = Arc::new(sphere_geometry(radius, 2)?);
        let pose = Isometry3::translation(p_in_world.x, p_in_world.y, p_in_world.z);
        self.push(Instance::new(geometry, pose, Paint::Uniform(colour))?);
        Ok(())
    }

    /// Adds an arrow from `start_in_world` along `vector` (its length is the arrow's length),
    /// with a shaft of radius `shaft_radius` (m); the head is three shaft diameters wide and
    /// at most a third of the arrow long. Used for placement normals and approach directions.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a zero or non-finite vector or a non-positive radius.
    pub fn add_arrow(
        &mut self,
        start_in_world: Point3,
        vector: Vector3,
        shaft_radius: Real,
        colour: Colour,
    ) -> Result<()> {
        let length = vector.norm();
        if !(length.is_finite() && length > 0.0) {
            return Err(Error::InvalidParameter {
                name: "arrow length",
                value: length,
                reason: "must be positive and finite",
            });
        }
        let geometry = Arc::new(arrow_geometry(length, shaft_radius, 16)?);
        let rotation = rotation_from_z(&(vector / length));
        let world_from_arrow = Isometry3::from_parts(start_in_world.coords.into(), rotation);
        self.push(Instance::new(
            geometry,
            world_from_arrow,
            Paint::Uniform(colour),
        )?);
        Ok(())
    }

    /// Adds the axes of a frame as three arrows of `length` (m): x red, y green, z blue.
    ///
    /// # Errors
    /// As [`Scene::add_arrow`].
    pub fn add_frame_axes(&mut self, world_from_frame: &Isometry3, length: Real) -> Result<()> {
        check_pose(world_from_frame, "frame axes")?;
        let origin = Point3::from(world_from_frame.translation.vector);
        let radius = length * 0.04;
        for (axis, colour) in [
            (Vector3::x(), Colour::RED),
            (Vector3::y(), Colour::GREEN),
            (Vector3::z(), Colour::BLUE),
        ] {
            self.add_arrow(
                origin,
                world_from_frame.rotation * axis * length,
                radius,
                colour,
            )?;
        }
        Ok(())
    }

    /// Axis-aligned bounds `(min, max)` of every instance in the world, or `None` for an empty
    /// scene.
    pub fn bounds(&self) -> Option<(Point3, Point3)> {
        self.instances
            .iter()
            .filter_map(|i| i.geometry.bounds(&i.world_from_mesh))
            .reduce(|(lo, hi), (l, h)| (lo.inf(&l), hi.sup(&h)))
    }
}

/// The rotation taking +z to the unit vector `direction` (the half-turn about x when
/// `direction` is -z).
pub(crate) fn rotation_from_z(direction: &Vector3) -> UnitQuaternion {
    UnitQuaternion::rotation_between(&Vector3::z(), direction).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    })
}

/// `Ok` when `value` is positive and finite, else [`Error::InvalidParameter`] naming `name`.
pub(crate) fn positive(name: &'static str, value: Real) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            reason: "must be positive and finite",
        })
    }
}

/// A sphere of `radius` (m) centred at the origin: an icosahedron subdivided `subdivisions`
/// times (20 · 4^s triangles; `subdivisions` is capped at 5).
///
/// # Errors
/// [`Error::InvalidParameter`] for a non-positive radius.
pub fn sphere_geometry(radius: Real, subdivisions: u32) -> Result<Geometry> {
    positive("sphere radius", radius)?;
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<Vector3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|p| Vector3::from(*p).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions.min(5) {
        // Edge midpoints are shared through a sorted list of (edge, vertex) pairs, which keeps
        // the construction deterministic without hashing.
        let mut midpoints: Vec<((u32, u32), u32)> = Vec::new();
        let mut next = Vec::with_capacity(triangles.len() * 4);
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vector3>| -> u32 {
            let key = (a.min(b), a.max(b));
            match midpoints.binary_search_by_key(&key, |&(k, _)| k) {
                Ok(i) => midpoints[i].1,
                Err(i) => {
                    let p = (positions[a as usize] + positions[b as usize]).normalize();
                    positions.push(p);
                    let v = (positions.len() - 1) as u32;
                    midpoints.insert(i, (key, v));
                    v
                }
            }
        };
        for &[a, b, c] in &triangles {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    let positions = positions
        .into_iter()
        .map(|p| Point3::from(p * radius))
        .collect();
    Geometry::new(positions, triangles)
}

/// An arrow along +z from the origin, `length` long (m), with a cylindrical shaft of
/// `shaft_radius` and a conical head three shaft diameters wide and at most a third of the
/// length long; `segments` facets around (at least 3).
///
/// # Errors
/// [`Error::InvalidParameter`] for a non-positive length or radius.
pub fn arrow_geometry(length: Real, shaft_radius: Real, segments: usize) -> Result<Geometry> {
    positive("arrow length", length)?;
    positive("arrow shaft radius", shaft_radius)?;
    let segments = segments.max(3);
    let head_radius = 3.0 * shaft_radius;
    let head_length = (6.0 * shaft_radius).min(length / 3.0);
    let shaft_end = length - head_length;
    let ring = |r: Real, z: Real| -> Vec<Point3> {
        (0..segments)
            .map(|i| {
                let a = std::f64::consts::TAU * i as Real / segments as Real;
                Point3::new(r * a.cos(), r * a.sin(), z)
            })
            .collect()
    };
    let mut positions = Vec::with_capacity(3 * segments + 2);
    positions.extend(ring(shaft_radius, 0.0));
    positions.extend(ring(shaft_radius, shaft_end));
    positions.extend(ring(head_radius, shaft_end));
    let base = positions.len() as u32;
    positions.push(Point3::origin());
    positions.push(Point3::new(0.0, 0.0, length));
    let (bottom_centre, tip) = (base, base + 1);
    let s = segments as u32;
    let mut triangles = Vec::with_capacity(5 * segments);
    for i in 0..s {
        let j = (i + 1) % s;
        // Bottom cap (faces -z), shaft side, head underside (annulus, faces -z), head cone.
        triangles.push([bottom_centre, j, i]);
        triangles.push([i, j, s + j]);
        triangles.push([i, s + j, s + i]);
        triangles.push([s + i, s + j, 2 * s + j]);
        triangles.push([s + i, 2 * s + j, 2 * s + i]);
        triangles.push([2 * s + i, 2 * s + j, tip]);
    }
    Geometry::new(positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_outward(g: &Geometry, centre: Point3) {
        for t in 0..g.triangle_count() {
            let [a, b, c] = g.triangles()[t].map(|v| g.positions()[v as usize]);
            let centroid = Point3::from((a.coords + b.coords + c.coords) / 3.0);
            let n = g.triangle_normal(t);
            assert!(n.norm() > 0.5, "triangle {t} degenerate");
            assert!(
                n.dot(&(centroid - centre)) > -1e-12,
                "triangle {t} faces inwards"
            );
        }
    }

    #[test]
    fn sphere_is_closed_outward_and_round() {
        let g = sphere_geometry(0.5, 2).expect("valid radius");
        assert_eq!(g.triangle_count(), 320);
        assert_eq!(
            g.positions().len(),
            162,
            "shared midpoints: V = 10 * 4^s + 2"
        );
        for p in g.positions() {
            assert!((p.coords.norm() - 0.5).abs() < 1e-12);
        }
        assert_outward(&g, Point3::origin());
        assert!(sphere_geometry(0.0, 1).is_err());
    }

    #[test]
    fn arrow_spans_its_length_and_faces_outward() {
        let g = arrow_geometry(1.0, 0.02, 12).expect("valid arrow");
        let (lo, hi) = g.bounds(&Isometry3::identity()).expect("non-empty");
        assert!((lo.z - 0.0).abs() < 1e-12 && (hi.z - 1.0).abs() < 1e-12);
        assert!((hi.x - 0.06).abs() < 1e-12);
        // Every face points away from the axis or along it, never into the solid: check the
        // caps and annulus by sign of z, the sides by radial direction.
        for t in 0..g.triangle_count() {
            let n = g.triangle_normal(t);
            let [a, b, c] = g.triangles()[t].map(|v| g.positions()[v as usize]);
            let centroid = (a.coords + b.coords + c.coords) / 3.0;
            let radial = Vector3::new(centroid.x, centroid.y, 0.0);
            let outward =
                n.dot(&radial) > 1e-9 || (n.x.abs() < 1e-9 && n.y.abs() < 1e-9 && n.z < 0.0);
            assert!(outward, "triangle {t} normal {n:?} at {centroid:?}");
        }
    }

    #[test]
    fn arrows_point_where_asked() {
        let mut scene = Scene::new();
        for v in [Vector3::z(), -Vector3::z(), Vector3::new(1.0, 2.0, -0.5)] {
            scene
                .add_arrow(Point3::new(1.0, 0.0, 0.0), v, 0.01, Colour::RED)
                .expect("valid arrow");
            let i = scene.instances().last().expect("just added");
            let tip = i.world_from_mesh() * Point3::new(0.0, 0.0, v.norm());
            assert!((tip - (Point3::new(1.0, 0.0, 0.0) + v)).norm() < 1e-12);
        }
        assert!(
            scene
                .add_arrow(Point3::origin(), Vector3::zeros(), 0.01, Colour::RED)
                .is_err()
        );
    }

    #[test]
    fn bad_geometry_is_rejected() {
        let p = vec![
            Point3::origin(),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ];
        assert!(Geometry::new(p.clone(), vec![[0, 1, 3]]).is_err());
        let mut nan = p.clone();
        nan[1].x = f64::NAN;
        assert!(Geometry::new(nan, vec![[0, 1, 2]]).is_err());
        let g = Arc::new(Geometry::new(p, vec![[0, 1, 2]]).expect("valid"));
        let two = Paint::PerTriangle(vec![Colour::RED, Colour::BLUE].into());
        assert!(Instance::new(g.clone(), Isometry3::identity(), two).is_err());
        let bad_pose = Isometry3::translation(f64::INFINITY, 0.0, 0.0);
        assert!(Instance::new(g, bad_pose, Paint::Uniform(Colour::RED)).is_err());
    }
}
