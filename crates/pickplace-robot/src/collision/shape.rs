//! The shapes a caller gives the world: environment objects and attached objects, and the
//! conversion of a link's URDF geometry.

use super::hull;
use crate::error::{Error, Result};
use crate::model::Shape;
use parry3d_f64::shape::SharedShape;
use pickplace_geometry::math::{Isometry3, Real, Translation3, UnitQuaternion, Vector3};
use pickplace_geometry::mesh::{MeshOptions, TriMesh};
use pickplace_geometry::parry;
use std::path::Path;

/// A shape for the environment or an attached object.
#[derive(Debug, Clone)]
pub struct CollisionShape {
    pub(super) shape: SharedShape,
    /// The convex hull of a mesh shape, when asked for ([`CollisionShape::with_hull`]): the
    /// pairs of an attached or environment object are tested against it first, and against
    /// the mesh only when the hull touches (the mesh lies inside it, so the answer is the
    /// mesh's).
    pub(super) hull: Option<SharedShape>,
}

impl CollisionShape {
    /// A box with these half extents (m), centred on its frame.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-positive or non-finite size.
    pub fn cuboid(half_extents: Vector3) -> Result<Self> {
        for &h in half_extents.iter() {
            positive("box half extent", h)?;
        }
        Ok(Self {
            shape: SharedShape::cuboid(half_extents.x, half_extents.y, half_extents.z),
            hull: None,
        })
    }

    /// A sphere.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-positive or non-finite radius.
    pub fn ball(radius: Real) -> Result<Self> {
        Ok(Self {
            shape: SharedShape::ball(positive("sphere radius", radius)?),
            hull: None,
        })
    }

    /// A capsule along z (URDF convention): a segment of `length` with radius `radius`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-positive or non-finite size.
    pub fn capsule_z(radius: Real, length: Real) -> Result<Self> {
        let half = positive("capsule length", length)? / 2.0;
        let r = positive("capsule radius", radius)?;
        Ok(Self {
            shape: SharedShape::capsule(
                parry::vector(&Vector3::new(0.0, 0.0, -half)),
                parry::vector(&Vector3::new(0.0, 0.0, half)),
                r,
            ),
            hull: None,
        })
    }

    /// A triangle mesh (in its own frame).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] when parry rejects the mesh (no triangles).
    pub fn mesh(mesh: &TriMesh) -> Result<Self> {
        let vertices = mesh.vertices().iter().map(parry::point).collect();
        let shape = SharedShape::trimesh(vertices, mesh.triangles().to_vec()).map_err(|_| {
            Error::InvalidParameter {
                name: "mesh",
                value: mesh.triangle_count() as Real,
                reason: "the collision library rejected the triangle mesh",
            }
        })?;
        Ok(Self { shape, hull: None })
    }

    /// This shape with its convex hull kept beside it (for a mesh; other shapes are convex
    /// already): an object with many triangles, held or lying in the environment, is then
    /// tested against a link or an obstacle through its hull first, and through its
    /// triangles only when the hull touches. The answers are those of the mesh alone.
    pub fn with_hull(mut self) -> Self {
        if let Some(mesh) = self.shape.as_trimesh() {
            // Few vertices (GJK scans them all per support point), rounded to contain the
            // exact hull.
            self.hull = hull::link_hull(mesh.vertices());
        }
        self
    }

    /// The convex hull of a triangle mesh's vertices (in the mesh's frame).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] when the vertices span no volume.
    pub fn convex_hull(mesh: &TriMesh) -> Result<Self> {
        let vertices: Vec<_> = mesh.vertices().iter().map(parry::point).collect();
        let shape = SharedShape::convex_hull(&vertices).ok_or(Error::InvalidParameter {
            name: "mesh",
            value: mesh.vertices().len() as Real,
            reason: "the mesh's vertices span no volume: no convex hull",
        })?;
        Ok(Self { shape, hull: None })
    }

    /// A triangle mesh read from a file (STL, OBJ or PLY) through `pickplace-geometry`, for a
    /// static environment object.
    ///
    /// # Errors
    /// [`Error::EnvironmentMesh`] naming the file when it cannot be read;
    /// [`Error::InvalidParameter`] when it has no triangle.
    pub fn mesh_file(path: &Path, options: &MeshOptions) -> Result<Self> {
        let mesh = pickplace_geometry::mesh::load(path, options).map_err(|source| {
            Error::EnvironmentMesh {
                path: path.to_path_buf(),
                source: Box::new(source),
            }
        })?;
        Self::mesh(&mesh)
    }

    /// The local bounding box of the shape.
    pub fn local_aabb(&self) -> (Vector3, Vector3) {
        let aabb = self.shape.compute_local_aabb();
        (parry::to_vector(aabb.mins), parry::to_vector(aabb.maxs))
    }

    /// The shape of a URDF geometry (a box, sphere, cylinder or capsule as a primitive; a
    /// mesh as its convex hull, as robot links are checked) and the pose of the collision
    /// library's shape in the geometry's frame: parry's cylinder axis is y, URDF's (and
    /// MoveIt's) is z, so a cylinder's pose is a quarter turn about x; the others' identity.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-positive or non-finite size.
    pub fn from_shape(shape: &Shape) -> Result<(Self, Isometry3)> {
        Ok(match shape {
            Shape::Box { half_extents } => (Self::cuboid(*half_extents)?, Isometry3::identity()),
            Shape::Sphere { radius } => (Self::ball(*radius)?, Isometry3::identity()),
            Shape::Capsule { radius, length } => {
                (Self::capsule_z(*radius, *length)?, Isometry3::identity())
            }
            Shape::Cylinder { radius, length } => {
                let r = positive("cylinder radius", *radius)?;
                let half = positive("cylinder length", *length)? / 2.0;
                let y_to_z = Isometry3::from_parts(
                    Translation3::identity(),
                    UnitQuaternion::from_axis_angle(
                        &Vector3::x_axis(),
                        std::f64::consts::FRAC_PI_2,
                    ),
                );
                (
                    Self {
                        shape: SharedShape::cylinder(half, r),
                        hull: None,
                    },
                    y_to_z,
                )
            }
            // Robot links are checked as convex shapes: a link mesh becomes its convex hull
            // (conservative, and one GJK query instead of a triangle traversal), with at most
            // `hull::MAX_HULL_VERTICES` vertices and rounded by at most 2 mm when it had
            // more (`hull`); a flat mesh with no hull stays a triangle mesh.
            Shape::Mesh { mesh, .. } => {
                let vertices: Vec<_> = mesh.vertices().iter().map(parry::point).collect();
                let shape = match hull::link_hull(&vertices) {
                    Some(shape) => Self { shape, hull: None },
                    None => Self::mesh(mesh)?,
                };
                (shape, Isometry3::identity())
            }
        })
    }
}

fn positive(name: &'static str, value: Real) -> Result<Real> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            reason: "must be positive and finite",
        })
    }
}
