//! Robot links as triangles: the URDF primitives (box, cylinder, sphere, capsule) triangulated,
//! mesh shapes taken as they are, and every shape of a link merged into one geometry in the
//! link frame, ready to be posed by forward kinematics.

use crate::error::{Error, Result};
use crate::image::Colour;
use crate::scene::{Geometry, Instance, Paint, Scene, positive, sphere_geometry};
use pickplace_geometry::math::{Isometry3, Point3, Real, Vector3};
use pickplace_geometry::shapes::{box_builder, cylinder_builder, revolve_builder};
use pickplace_robot::RobotModel;
use pickplace_robot::model::{LinkGeometry, Shape};
use std::sync::Arc;

/// Which of a link's geometry lists is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LinkShapes {
    /// The visual shapes, or the collision shapes for a link without visuals (for example
    /// when the model was loaded without visual geometry).
    #[default]
    VisualElseCollision,
    /// The collision shapes only.
    Collision,
}

/// Options of [`RobotGeometry::new`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotGeometryOptions {
    /// Which shapes are drawn (default: [`LinkShapes::VisualElseCollision`]).
    pub shapes: LinkShapes,
    /// Facets around cylinders and capsules (at least 3) (default: 24).
    pub segments: usize,
    /// Icosphere subdivisions of spheres (capped at 5) (default: 2).
    pub sphere_subdivisions: u32,
}

impl Default for RobotGeometryOptions {
    fn default() -> Self {
        Self {
            shapes: LinkShapes::VisualElseCollision,
            segments: 24,
            sphere_subdivisions: 2,
        }
    }
}

/// Triangles of a robot shape in its own frame (URDF conventions: boxes, cylinders, spheres
/// and capsules centred on the origin, cylinders and capsules along z).
///
/// # Errors
/// [`Error::InvalidParameter`] for a non-positive or non-finite size;
/// [`crate::GeometryErrorKind`] for a malformed mesh.
pub fn shape_geometry(shape: &Shape, options: &RobotGeometryOptions) -> Result<Geometry> {
    let segments = options.segments.max(3);
    let builder = match shape {
        Shape::Box { half_extents } => {
            for &h in half_extents.iter() {
                positive("box half extent", h)?;
            }
            box_builder([half_extents.x, half_extents.y, half_extents.z])
        }
        Shape::Cylinder { radius, length } => {
            positive("cylinder radius", *radius)?;
            positive("cylinder length", *length)?;
            cylinder_builder(*radius, *length, segments).translated(Vector3::new(
                0.0,
                0.0,
                -0.5 * length,
            ))
        }
        Shape::Capsule { radius, length } => {
            positive("capsule radius", *radius)?;
            if !(length.is_finite() && *length >= 0.0) {
                return Err(Error::InvalidParameter {
                    name: "capsule length",
                    value: *length,
                    reason: "must be non-negative and finite",
                });
            }
            revolve_builder(
                &capsule_profile(*radius, *length, segments / 4 + 2),
                segments,
            )
        }
        Shape::Sphere { radius } => return sphere_geometry(*radius, options.sphere_subdivisions),
        Shape::Mesh { mesh, .. } => return Ok(Geometry::from_trimesh(mesh)),
    };
    Geometry::new(builder.positions, builder.triangles)
}

/// The `(r, z)` profile of a capsule for [`revolve_builder`]: from the bottom pole round the
/// lower hemisphere, up the side, round the upper hemisphere to the top pole.
fn capsule_profile(radius: Real, length: Real, arc_steps: usize) -> Vec<[Real; 2]> {
    let half = 0.5 * length;
    let mut profile = Vec::with_capacity(2 * arc_steps + 2);
    for k in 0..=arc_steps {
        let a = std::f64::consts::FRAC_PI_2 * k as Real / arc_steps as Real;
        profile.push([radius * a.sin(), -half - radius * a.cos()]);
    }
    for k in (0..=arc_steps).rev() {
        let a = std::f64::consts::FRAC_PI_2 * k as Real / arc_steps as Real;
        let point = [radius * a.sin(), half + radius * a.cos()];
        // A zero-length capsule's side has no height: skip the repeated equator point.
        if profile.last() != Some(&point) {
            profile.push(point);
        }
    }
    profile
}

/// The shapes of every link of a robot, each link's merged into one [`Geometry`] in the link
/// frame (`None` for a link with no shape).
#[derive(Debug, Clone)]
pub struct RobotGeometry {
    names: Vec<String>,
    parents: Vec<Option<usize>>,
    links: Vec<Option<Arc<Geometry>>>,
    colours: Vec<Colour>,
}

impl RobotGeometry {
    /// Triangulates the shapes of every link of `robot`.
    ///
    /// # Errors
    /// As [`shape_geometry`].
    pub fn new(robot: &RobotModel, options: &RobotGeometryOptions) -> Result<Self> {
        let mut links = Vec::with_capacity(robot.links().len());
        for link in robot.links() {
            let shapes: &[LinkGeometry] = match options.shapes {
                LinkShapes::VisualElseCollision if !link.visuals.is_empty() => &link.visuals,
                _ => &link.collisions,
            };
            let mut positions: Vec<Point3> = Vec::new();
            let mut triangles: Vec<[u32; 3]> = Vec::new();
            for shape in shapes {
                let g = shape_geometry(&shape.shape, options)?;
                let base = positions.len() as u32;
                positions.extend(g.positions().iter().map(|p| shape.link_from_shape * p));
                triangles.extend(g.triangles().iter().map(|t| t.map(|v| v + base)));
            }
            links.push(if triangles.is_empty() {
                None
            } else {
                Some(Arc::new(Geometry::new(positions, triangles)?))
            });
        }
        let parents = (0..robot.links().len())
            .map(|l| robot.parent_link(l))
            .collect();
        let names: Vec<String> = robot.links().iter().map(|l| l.name.clone()).collect();
        let colours = names
            .iter()
            .enumerate()
            .map(|(i, n)| default_link_colour(robot, i, n))
            .collect();
        Ok(Self {
            names,
            parents,
            links,
            colours,
        })
    }

    /// Number of links.
    pub fn link_count(&self) -> usize {
        self.links.len()
    }

    /// The name of a link.
    pub fn link_name(&self, link: usize) -> Option<&str> {
        self.names.get(link).map(String::as_str)
    }

    /// The parent link of a link (`None` for the root or an index out of range).
    pub fn parent(&self, link: usize) -> Option<usize> {
        self.parents.get(link).copied().flatten()
    }

    /// The geometry of a link in its frame, if it has any shape.
    pub fn link_geometry(&self, link: usize) -> Option<&Arc<Geometry>> {
        self.links.get(link).and_then(Option::as_ref)
    }

    /// The colour a link is drawn in.
    pub fn link_colour(&self, link: usize) -> Colour {
        self.colours.get(link).copied().unwrap_or(Colour::GREY)
    }

    /// Replaces the colour of a link (an index out of range is ignored).
    pub fn set_link_colour(&mut self, link: usize, colour: Colour) {
        if let Some(c) = self.colours.get_mut(link) {
            *c = colour;
        }
    }

    /// Total number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.links
            .iter()
            .flatten()
            .map(|g| g.triangle_count())
            .sum()
    }

    /// Adds every link with geometry to `scene` at `world_from_links` (one pose per link).
    ///
    /// # Errors
    /// [`crate::MotionErrorKind::Configuration`] when there is not one pose per link;
    /// [`crate::GeometryErrorKind::NonFinitePose`].
    pub fn add_to_scene(&self, scene: &mut Scene, world_from_links: &[Isometry3]) -> Result<()> {
        if world_from_links.len() != self.links.len() {
            return Err(Error::Motion {
                kind: crate::error::MotionErrorKind::Configuration {
                    frame: 0,
                    expected: self.links.len(),
                    found: world_from_links.len(),
                },
            });
        }
        for (link, pose) in world_from_links.iter().enumerate() {
            if let Some(g) = &self.links[link] {
                scene.push(Instance::new(
                    g.clone(),
                    *pose,
                    Paint::Uniform(self.colours[link]),
                )?);
            }
        }
        Ok(())
    }
}

/// Light greys alternating along the kinematic chain (so that neighbouring links stand
/// apart), dark grey for hands, grippers and fingers.
fn default_link_colour(robot: &RobotModel, link: usize, name: &str) -> Colour {
    let lower = name.to_ascii_lowercase();
    if lower.contains("finger") {
        return Colour::new(60, 60, 66);
    }
    if lower.contains("hand") || lower.contains("gripper") {
        return Colour::new(95, 95, 105);
    }
    let mut depth = 0;
    let mut l = link;
    while let Some(p) = robot.parent_link(l) {
        depth += 1;
        l = p;
    }
    if depth % 2 == 0 {
        Colour::new(215, 215, 220)
    } else {
        Colour::new(185, 188, 196)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn centroid_outward(g: &Geometry) -> bool {
        (0..g.triangle_count()).all(|t| {
            let [a, b, c] = g.triangles()[t].map(|v| g.positions()[v as usize]);
            let centroid = (a.coords + b.coords + c.coords) / 3.0;
            g.triangle_normal(t).dot(&centroid) > -1e-12
        })
    }

    #[test]
    fn primitives_are_centred_closed_and_outward() {
        let options = RobotGeometryOptions::default();
        let shapes = [
            Shape::Box {
                half_extents: Vector3::new(0.1, 0.2, 0.3),
            },
            Shape::Cylinder {
                radius: 0.05,
                length: 0.4,
            },
            Shape::Capsule {
                radius: 0.05,
                length: 0.2,
            },
            Shape::Capsule {
                radius: 0.05,
                length: 0.0,
            },
            Shape::Sphere { radius: 0.07 },
        ];
        let expected_half_z = [0.3, 0.2, 0.15, 0.05, 0.07];
        for (shape, half_z) in shapes.iter().zip(expected_half_z) {
            let g = shape_geometry(shape, &options).expect("valid shape");
            let (lo, hi) = g.bounds(&Isometry3::identity()).expect("not empty");
            assert!(
                (hi.z - half_z).abs() < 1e-9 && (lo.z + half_z).abs() < 1e-9,
                "{} z extent",
                shape.kind()
            );
            assert!(
                (lo.coords + hi.coords).norm() < 1e-3 * half_z.max(0.1),
                "{} centred",
                shape.kind()
            );
            assert!(centroid_outward(&g), "{} faces outwards", shape.kind());
        }
        assert!(
            shape_geometry(
                &Shape::Cylinder {
                    radius: 0.0,
                    length: 1.0
                },
                &options
            )
            .is_err()
        );
        assert!(
            shape_geometry(
                &Shape::Capsule {
                    radius: 0.1,
                    length: -1.0
                },
                &options
            )
            .is_err()
        );
    }

    #[test]
    fn capsule_volume_is_close_to_the_exact_one() {
        let g = shape_geometry(
            &Shape::Capsule {
                radius: 0.05,
                length: 0.2,
            },
            &RobotGeometryOptions {
                segments: 64,
                ..RobotGeometryOptions::default()
            },
        )
        .expect("valid capsule");
        // Divergence theorem: V = Σ (a · (b × c)) / 6 over outward triangles.
        let volume: Real = g
            .triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| g.positions()[v as usize].coords);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum();
        let (r, l) = (0.05f64, 0.2f64);
        let exact = std::f64::consts::PI * r * r * l + 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        assert!((volume - exact).abs() < 0.02 * exact, "{volume} vs {exact}");
    }
}
