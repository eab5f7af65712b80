//! Obstacles given as shapes rather than mesh files: boxes, cylinders and spheres (as
//! `shape_msgs/SolidPrimitive` and URDF write them) or triangle meshes. The scene's
//! `[[environment]]` entries take them (`box`, `cylinder`, `sphere` instead of `mesh`), motion
//! queries add them ([`crate::motion::MotionWorld::add_obstacle`]). The collision world checks
//! a primitive exactly; where triangles are needed (surface clusters for placements, the
//! browser view), its tessellation has every vertex on the surface, so it lies inside the
//! exact shape.

use crate::error::{Error, Result};
use crate::robot_setup::robot_err;
use crate::scene::{EnvironmentSource, EnvironmentSpec};
use pickplace_geometry::math::{Isometry3, Real, Vector3};
use pickplace_geometry::mesh::TriMesh;
use pickplace_geometry::shapes;
use pickplace_robot::collision::CollisionShape;
use pickplace_robot::model::Shape;
use std::path::{Path, PathBuf};

/// Facets around a tessellated cylinder or sphere.
const SEGMENTS: usize = 48;
/// Bands from pole to pole of a tessellated sphere.
const RINGS: usize = 24;

/// The shape of an obstacle, in its own frame (centred on it).
#[derive(Debug, Clone)]
pub enum ObstacleShape {
    /// A box of these full sizes along x, y and z (m), as `shape_msgs/SolidPrimitive` BOX.
    Box {
        /// Sizes along x, y, z (m).
        size: [Real; 3],
    },
    /// A cylinder along z, as URDF's and `shape_msgs/SolidPrimitive` CYLINDER.
    Cylinder {
        /// Radius (m).
        radius: Real,
        /// Length along z (m).
        length: Real,
    },
    /// A sphere.
    Sphere {
        /// Radius (m).
        radius: Real,
    },
    /// A triangle mesh, checked by its triangles (not its hull: a shelf's inside is free).
    Mesh(TriMesh),
}

/// An obstacle: a name (unique in the world, for messages), a shape and its pose in the world.
#[derive(Debug, Clone)]
pub struct Obstacle {
    /// Its name.
    pub name: String,
    /// Its shape.
    pub shape: ObstacleShape,
    /// `world_from_obstacle`.
    pub pose: Isometry3,
}

impl ObstacleShape {
    /// The shape for the collision library and its pose in the obstacle's frame (a cylinder's
    /// axis turned onto z).
    ///
    /// # Errors
    /// [`pickplace_robot::Error::InvalidParameter`] for a size that is not positive and finite,
    /// or a mesh with no triangle.
    pub fn collision_shape(&self) -> pickplace_robot::Result<(CollisionShape, Isometry3)> {
        match self {
            Self::Box { size } => CollisionShape::from_shape(&Shape::Box {
                half_extents: Vector3::from(*size) / 2.0,
            }),
            Self::Cylinder { radius, length } => CollisionShape::from_shape(&Shape::Cylinder {
                radius: *radius,
                length: *length,
            }),
            Self::Sphere { radius } => {
                CollisionShape::from_shape(&Shape::Sphere { radius: *radius })
            }
            Self::Mesh(mesh) => Ok((CollisionShape::mesh(mesh)?, Isometry3::identity())),
        }
    }
}

impl ObstacleShape {
    /// `box`, `cylinder`, `sphere` or `mesh`.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Box { .. } => "box",
            Self::Cylinder { .. } => "cylinder",
            Self::Sphere { .. } => "sphere",
            Self::Mesh(_) => "mesh",
        }
    }

    /// The shape as triangles, centred as the shape is: a box exactly; a cylinder with
    /// 48 facets around and a sphere with 24 bands of 48, every vertex on the surface (inside
    /// the exact shape by at most 0.2 % of the radius).
    ///
    /// # Errors
    /// [`pickplace_geometry::Error`] for a size that is not positive and finite.
    pub fn triangles(&self) -> pickplace_geometry::Result<TriMesh> {
        let positive = |what: &'static str, v: Real| {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(pickplace_geometry::Error::InvalidParameter {
                    name: what,
                    value: v,
                    reason: "a size must be positive and finite",
                })
            }
        };
        match self {
            Self::Box { size } => {
                let mut half = [0.0; 3];
                for (h, &s) in half.iter_mut().zip(size) {
                    *h = positive("box size", s)? / 2.0;
                }
                shapes::box_builder(half).build()
            }
            Self::Cylinder { radius, length } => {
                let (r, l) = (
                    positive("cylinder radius", *radius)?,
                    positive("cylinder length", *length)?,
                );
                shapes::cylinder_builder(r, l, SEGMENTS)
                    .translated(Vector3::new(0.0, 0.0, -l / 2.0))
                    .build()
            }
            Self::Sphere { radius } => {
                let r = positive("sphere radius", *radius)?;
                shapes::ellipsoid_builder([r; 3], 0.0, RINGS, SEGMENTS)
                    .translated(Vector3::new(0.0, 0.0, -r))
                    .build()
            }
            Self::Mesh(mesh) => Ok(mesh.clone()),
        }
    }
}

/// An environment part of a scene, read: its triangles (the mesh file's, or a primitive's
/// tessellation), its collision shape (the mesh, or the primitive exactly) and poses.
#[derive(Debug)]
pub struct EnvironmentBody {
    /// Triangles, in the part's frame.
    pub mesh: TriMesh,
    /// `world_from_mesh`.
    pub world_from_mesh: Isometry3,
    /// What the collision world checks, and where it is.
    pub shape: CollisionShape,
    /// `world_from_shape` (a cylinder's axis turned onto z).
    pub world_from_shape: Isometry3,
    /// The mesh file, or `NAME-KIND` for a primitive: names the part's cluster cache.
    pub cache_name: PathBuf,
    /// Whether it is a mesh file (whose defects are worth a warning).
    pub from_file: bool,
}

/// Reads an environment part (`env`, named `field` in errors, `environment[2]`, of the file
/// `source`); its form is checked ([`EnvironmentSpec::check`]).
///
/// # Errors
/// [`Error::Mesh`] for an unreadable mesh, [`Error::Invalid`] for a pose or size out of
/// range, [`Error::Robot`] when the collision library refuses the shape.
pub fn load_environment(
    env: &EnvironmentSpec,
    field: &str,
    source: &Path,
) -> Result<EnvironmentBody> {
    let invalid = |f: &str, reason: String| Error::Invalid {
        path: source.to_path_buf(),
        field: format!("{field}.{f}"),
        reason,
    };
    env.check(field).map_err(|(field, reason)| Error::Invalid {
        path: source.to_path_buf(),
        field,
        reason,
    })?;
    let world_from_mesh = env
        .pose
        .to_isometry()
        .map_err(|r| invalid("pose", r.into()))?;
    match (env.source(), env.primitive()) {
        (EnvironmentSource::Mesh(path), _) => {
            let what = format!("{field} {:?}", env.name);
            let mesh = crate::setup::load_mesh(path, env.scale, &what)?;
            let shape = CollisionShape::mesh(&mesh).map_err(robot_err(path))?;
            Ok(EnvironmentBody {
                mesh,
                world_from_mesh,
                shape,
                world_from_shape: world_from_mesh,
                cache_name: path.to_path_buf(),
                from_file: true,
            })
        }
        (EnvironmentSource::Primitive(_), Some(primitive)) => {
            let kind = primitive.kind();
            let mesh = primitive
                .triangles()
                .map_err(|e| invalid(kind, e.to_string()))?;
            let (shape, correction) = primitive
                .collision_shape()
                .map_err(|e| invalid(kind, e.to_string()))?;
            let stem: String = env
                .name
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
                .collect();
            Ok(EnvironmentBody {
                mesh,
                world_from_mesh,
                shape,
                world_from_shape: world_from_mesh * correction,
                cache_name: PathBuf::from(format!("{stem}-{kind}")),
                from_file: false,
            })
        }
        (EnvironmentSource::Primitive(_), None) => Err(invalid(
            "mesh",
            "missing: give one of mesh, box, cylinder and sphere".into(),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::Point3;

    fn extent(mesh: &TriMesh) -> (Point3, Point3) {
        mesh.vertices().iter().fold(
            (Point3::from([Real::MAX; 3]), Point3::from([Real::MIN; 3])),
            |(lo, hi), v| (lo.inf(v), hi.sup(v)),
        )
    }

    #[test]
    fn tessellations_are_centred_and_inside_the_exact_shape() {
        let cases = [
            (
                ObstacleShape::Box {
                    size: [0.4, 0.2, 0.1],
                },
                [0.2, 0.1, 0.05],
            ),
            (
                ObstacleShape::Cylinder {
                    radius: 0.1,
                    length: 0.5,
                },
                [0.1, 0.1, 0.25],
            ),
            (ObstacleShape::Sphere { radius: 0.2 }, [0.2, 0.2, 0.2]),
        ];
        for (shape, half) in cases {
            let mesh = shape.triangles().expect("valid sizes");
            let (lo, hi) = extent(&mesh);
            for k in 0..3 {
                assert!((hi[k] - half[k]).abs() < 1e-9, "{shape:?} {k}: {}", hi[k]);
                assert!((lo[k] + half[k]).abs() < 1e-9, "{shape:?} {k}: {}", lo[k]);
            }
            // Every vertex inside the exact shape (within rounding).
            let (collision, correction) = shape.collision_shape().expect("valid");
            let _ = collision;
            for v in mesh.vertices() {
                let inside = match &shape {
                    ObstacleShape::Box { .. } => true,
                    ObstacleShape::Cylinder { radius, .. } => {
                        (v.x * v.x + v.y * v.y).sqrt() <= radius + 1e-12
                    }
                    ObstacleShape::Sphere { radius } => v.coords.norm() <= radius + 1e-12,
                    ObstacleShape::Mesh(_) => true,
                };
                assert!(inside, "{shape:?}: {v:?}");
            }
            // A cylinder's exact shape is turned onto z, the others are not.
            let turned = matches!(shape, ObstacleShape::Cylinder { .. });
            assert_eq!(correction != Isometry3::identity(), turned);
        }
    }

    #[test]
    fn sizes_must_be_positive_and_finite() {
        for shape in [
            ObstacleShape::Box {
                size: [1.0, 0.0, 1.0],
            },
            ObstacleShape::Cylinder {
                radius: -1.0,
                length: 1.0,
            },
            ObstacleShape::Sphere { radius: Real::NAN },
        ] {
            assert!(shape.triangles().is_err(), "{shape:?}");
            assert!(shape.collision_shape().is_err(), "{shape:?}");
        }
    }
}
