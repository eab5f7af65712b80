//! Conservative sphere models of links (issue 35): every link's collision geometry covered by
//! spheres, generated from the geometry itself (no hand-made model, no code generated per
//! robot) and verified by sampling the geometry's surface.
//!
//! A piece of collision geometry (a mesh, a box, a cylinder, a capsule or a sphere) is first
//! taken as a convex polytope that contains it: a mesh's convex hull, a box's corners, a
//! cylinder's or capsule's circumscribed prism of [`PRISM_SIDES`] sides. The polytope is cut
//! into slabs across its longest principal axis, as many as make each slab about as thick as
//! the polytope is wide; each slab's part of the polytope is the convex hull of the polytope's
//! vertices inside the slab and of the points where segments between its vertices cross the
//! slab's faces, and its sphere encloses those points (centre: the middle of their box in the
//! principal frame; radius: the farthest point). So the spheres cover the polytope exactly,
//! hence the geometry, and `margin` is added to every radius. [`SphereModel::verify`] samples
//! the original surface and reports the largest distance of a sample outside every sphere
//! (0 for a model made here).

use crate::model::{RobotModel, Shape};
use crate::rng::Rng;
use pickplace_geometry::math::{Isometry3, Matrix3, Point3, Real, Vector3};
use pickplace_geometry::mesh::TriMesh;

/// Sides of the prism that stands for a cylinder or a capsule's cylinder (circumscribed, so
/// it contains the round shape).
pub const PRISM_SIDES: usize = 16;

/// Most slabs along a piece's axis.
pub const MAX_SLABS: usize = 16;

/// A sphere in a link's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// Centre (m, link frame).
    pub center: Point3,
    /// Radius (m).
    pub radius: Real,
}

/// Every link's spheres (by link index), in the link's frame.
#[derive(Debug, Clone, PartialEq)]
pub struct SphereModel {
    /// Spheres per link; empty for a link without collision geometry.
    pub links: Vec<Vec<Sphere>>,
    /// The margin added to every radius (m).
    pub margin: Real,
}

/// What sampling a model against the geometry found.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Coverage {
    /// Surface points sampled.
    pub samples: usize,
    /// Points outside every sphere of their link.
    pub outside: usize,
    /// The largest distance of a point outside every sphere (m; 0 when all are covered).
    pub worst: Real,
}

impl SphereModel {
    /// The model of every link of `model` with `margin` (m, at least 0) added to each radius.
    pub fn of(model: &RobotModel, margin: Real) -> Self {
        let links = model
            .links()
            .iter()
            .map(|link| {
                link.collisions
                    .iter()
                    .flat_map(|g| {
                        shape_spheres(&g.shape, margin).into_iter().map(|s| Sphere {
                            center: g.link_from_shape * s.center,
                            radius: s.radius,
                        })
                    })
                    .collect()
            })
            .collect();
        Self { links, margin }
    }

    /// Spheres in all.
    pub fn count(&self) -> usize {
        self.links.iter().map(Vec::len).sum()
    }

    /// Samples the surface of every link's collision geometry of `model` (about `density`
    /// points per square metre, at least one per triangle, seeded) and measures how far
    /// outside this model's spheres of the same link they fall.
    pub fn verify(&self, model: &RobotModel, density: Real, seed: u64) -> Coverage {
        (0..model.links().len()).fold(Coverage::default(), |total, i| {
            let c = self.verify_link(model, i, density, seed);
            Coverage {
                samples: total.samples + c.samples,
                outside: total.outside + c.outside,
                worst: total.worst.max(c.worst),
            }
        })
    }

    /// [`SphereModel::verify`] for the link of index `link` alone (its samples seeded by
    /// `seed` and the link).
    pub fn verify_link(
        &self,
        model: &RobotModel,
        link: usize,
        density: Real,
        seed: u64,
    ) -> Coverage {
        let mut rng = Rng::derive(seed, SAMPLING_STREAM, link as u64);
        let mut c = Coverage::default();
        let spheres = self.links.get(link).map_or(&[][..], Vec::as_slice);
        let Some(geometry) = model.links().get(link).map(|l| &l.collisions) else {
            return c;
        };
        for g in geometry {
            for p in surface_samples(&g.shape, density, &mut rng) {
                let p = g.link_from_shape * p;
                let outside = spheres
                    .iter()
                    .map(|s| (p - s.center).norm() - s.radius)
                    .fold(Real::INFINITY, Real::min);
                c.samples += 1;
                if outside > 1e-9 {
                    c.outside += 1;
                    c.worst = c.worst.max(outside);
                }
            }
        }
        c
    }
}

/// The random stream of [`SphereModel::verify`]'s samples.
const SAMPLING_STREAM: u64 = 0x5350_4845;

/// The spheres covering `shape` (shape frame), `margin` added: a sphere is itself, any other
/// shape the cover of its polytope ([`polytope`], [`piece_spheres`]).
pub fn shape_spheres(shape: &Shape, margin: Real) -> Vec<Sphere> {
    match shape {
        Shape::Sphere { radius } => vec![Sphere {
            center: Point3::origin(),
            radius: radius + margin,
        }],
        other => piece_spheres(&polytope(other), margin),
    }
}

/// The vertices of a convex polytope that contains `shape` (shape frame).
pub fn polytope(shape: &Shape) -> Vec<Point3> {
    let prism = |radius: Real, z: &[Real]| -> Vec<Point3> {
        // Circumscribed: the polygon's edges touch the circle.
        let r = radius / (std::f64::consts::PI / PRISM_SIDES as Real).cos();
        z.iter()
            .flat_map(|&z| {
                (0..PRISM_SIDES).map(move |k| {
                    let a = std::f64::consts::TAU * k as Real / PRISM_SIDES as Real;
                    Point3::new(r * a.cos(), r * a.sin(), z)
                })
            })
            .collect()
    };
    match shape {
        Shape::Box { half_extents: h } => (0..8)
            .map(|k| {
                let s = |bit: usize| if k & bit == 0 { -1.0 } else { 1.0 };
                Point3::new(s(1) * h.x, s(2) * h.y, s(4) * h.z)
            })
            .collect(),
        Shape::Cylinder { radius, length } => prism(*radius, &[-length / 2.0, length / 2.0]),
        // The cylinder's prism grown by the radius along the axis: it contains the caps.
        Shape::Capsule { radius, length } => {
            prism(*radius, &[-length / 2.0 - radius, length / 2.0 + radius])
        }
        Shape::Sphere { radius } => {
            let r = *radius;
            (0..8)
                .map(|k| {
                    let s = |bit: usize| if k & bit == 0 { -r } else { r };
                    Point3::new(s(1), s(2), s(4))
                })
                .collect()
        }
        Shape::Mesh { mesh, .. } => hull_vertices(mesh),
    }
}

/// The vertices of a mesh's convex hull (all of them when the hull fails, which keeps the
/// cover conservative).
fn hull_vertices(mesh: &TriMesh) -> Vec<Point3> {
    use pickplace_geometry::parry as p;
    let points: Vec<_> = mesh.vertices().iter().map(p::point).collect();
    let (hull, _) = parry3d_f64::transformation::convex_hull(&points);
    if hull.len() >= 4 {
        hull.into_iter().map(p::to_point).collect()
    } else {
        mesh.vertices().to_vec()
    }
}

/// The spheres covering the convex hull of `points` (module doc), `margin` added.
pub fn piece_spheres(points: &[Point3], margin: Real) -> Vec<Sphere> {
    if points.is_empty() {
        return Vec::new();
    }
    let n = points.len() as Real;
    let mean = points.iter().fold(Vector3::zeros(), |a, p| a + p.coords) / n;
    let mut cov = Matrix3::zeros();
    for p in points {
        let d = p.coords - mean;
        cov += d * d.transpose();
    }
    let eig = cov.symmetric_eigen();
    // Principal axes, the longest first.
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let axes: [Vector3; 3] = order.map(|k| eig.eigenvectors.column(k).normalize());
    let local: Vec<Vector3> = points
        .iter()
        .map(|p| {
            let d = p.coords - mean;
            Vector3::new(axes[0].dot(&d), axes[1].dot(&d), axes[2].dot(&d))
        })
        .collect();
    let (lo, hi) = local.iter().fold(
        (
            Vector3::repeat(Real::INFINITY),
            Vector3::repeat(Real::NEG_INFINITY),
        ),
        |(lo, hi), v| (lo.inf(v), hi.sup(v)),
    );
    let extent = hi - lo;
    let width = extent.y.max(extent.z).max(1e-9);
    let slabs = ((extent.x / width).round() as usize).clamp(1, MAX_SLABS);
    let thickness = extent.x / slabs as Real;
    let to_world = |v: &Vector3| Point3::from(mean + axes[0] * v.x + axes[1] * v.y + axes[2] * v.z);
    (0..slabs)
        .map(|k| {
            let (a, b) = (
                lo.x + thickness * k as Real,
                if k + 1 == slabs {
                    hi.x
                } else {
                    lo.x + thickness * (k + 1) as Real
                },
            );
            let mut inside: Vec<Vector3> = local
                .iter()
                .filter(|v| v.x >= a && v.x <= b)
                .copied()
                .collect();
            // Where segments between the vertices cross the slab's two faces.
            for plane in [a, b] {
                for (i, u) in local.iter().enumerate() {
                    for w in &local[i + 1..] {
                        if (u.x - plane) * (w.x - plane) < 0.0 {
                            let t = (plane - u.x) / (w.x - u.x);
                            inside.push(u + (w - u) * t);
                        }
                    }
                }
            }
            let (slo, shi) = inside.iter().fold(
                (
                    Vector3::repeat(Real::INFINITY),
                    Vector3::repeat(Real::NEG_INFINITY),
                ),
                |(lo, hi), v| (lo.inf(v), hi.sup(v)),
            );
            let centre = (slo + shi) / 2.0;
            let radius = inside
                .iter()
                .map(|v| (v - centre).norm())
                .fold(0.0, Real::max);
            Sphere {
                center: to_world(&centre),
                radius: radius + margin,
            }
        })
        .collect()
}

/// Points on the surface of `shape` (shape frame): about `density` per square metre on each
/// triangle of a mesh (at least one), on a primitive's surface by its area.
fn surface_samples(shape: &Shape, density: Real, rng: &mut Rng) -> Vec<Point3> {
    let mut out = Vec::new();
    let triangle = |a: Point3, b: Point3, c: Point3, rng: &mut Rng, out: &mut Vec<Point3>| {
        let area = (b - a).cross(&(c - a)).norm() / 2.0;
        let count = ((area * density).ceil() as usize).max(1);
        for _ in 0..count {
            let (mut u, mut v) = (rng.next_f64(), rng.next_f64());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            out.push(a + (b - a) * u + (c - a) * v);
        }
    };
    match shape {
        Shape::Mesh { mesh, .. } => {
            let v = mesh.vertices();
            for t in mesh.triangles() {
                triangle(
                    v[t[0] as usize],
                    v[t[1] as usize],
                    v[t[2] as usize],
                    rng,
                    &mut out,
                );
            }
        }
        other => {
            // Primitives: uniform directions scaled onto the surface by rejection-free
            // formulas (a point per density unit of the bounding sphere's area).
            let r = match other {
                Shape::Box { half_extents } => half_extents.norm(),
                Shape::Cylinder { radius, length } => {
                    (radius * radius + length * length / 4.0).sqrt()
                }
                Shape::Capsule { radius, length } => radius + length / 2.0,
                Shape::Sphere { radius } => *radius,
                Shape::Mesh { .. } => 0.0,
            };
            let count = ((4.0 * std::f64::consts::PI * r * r * density).ceil() as usize).max(8);
            for _ in 0..count {
                let z = rng.uniform(-1.0, 1.0);
                let a = rng.uniform(0.0, std::f64::consts::TAU);
                let s = (1.0 - z * z).sqrt();
                let d = Vector3::new(s * a.cos(), s * a.sin(), z);
                out.push(onto_surface(other, &d));
            }
        }
    }
    out
}

/// The point of a primitive's surface in direction `d` (unit) from its centre.
fn onto_surface(shape: &Shape, d: &Vector3) -> Point3 {
    match shape {
        Shape::Box { half_extents: h } => {
            let t = [h.x / d.x.abs(), h.y / d.y.abs(), h.z / d.z.abs()]
                .into_iter()
                .fold(Real::INFINITY, Real::min);
            Point3::from(d * t)
        }
        Shape::Cylinder { radius, length } => {
            let radial = (d.x * d.x + d.y * d.y).sqrt();
            let t = (radius / radial).min(length / 2.0 / d.z.abs());
            Point3::from(d * t)
        }
        Shape::Capsule { radius, length } => {
            // The sphere of the nearer cap's centre, or the cylinder between.
            let radial = (d.x * d.x + d.y * d.y).sqrt();
            let t = radius / radial;
            let p = d * t;
            if p.z.abs() <= length / 2.0 {
                Point3::from(p)
            } else {
                let c = Vector3::new(0.0, 0.0, length / 2.0 * p.z.signum());
                Point3::from(c + d * *radius)
            }
        }
        Shape::Sphere { radius } => Point3::from(d * *radius),
        Shape::Mesh { .. } => Point3::origin(),
    }
}

/// The spheres of `model` placed by the link poses `world_from_link` (for drawing and tests).
pub fn placed(model: &SphereModel, world_from_link: &[Isometry3]) -> Vec<(usize, Sphere)> {
    model
        .links
        .iter()
        .zip(world_from_link)
        .enumerate()
        .flat_map(|(i, (spheres, pose))| {
            spheres.iter().map(move |s| {
                (
                    i,
                    Sphere {
                        center: pose * s.center,
                        radius: s.radius,
                    },
                )
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::shapes;
    use std::sync::Arc;

    fn covered(points: &[Point3], spheres: &[Sphere]) -> Real {
        points
            .iter()
            .map(|p| {
                spheres
                    .iter()
                    .map(|s| (p - s.center).norm() - s.radius)
                    .fold(Real::INFINITY, Real::min)
            })
            .fold(Real::NEG_INFINITY, Real::max)
    }

    #[test]
    fn a_long_box_gets_a_row_of_spheres_that_covers_it_tightly() {
        let shape = Shape::Box {
            half_extents: Vector3::new(0.4, 0.05, 0.05),
        };
        let spheres = shape_spheres(&shape, 0.0);
        // The cross-section's principal axes are any pair of the square's: 6 to 8 slabs.
        assert!((6..=8).contains(&spheres.len()), "{}", spheres.len());
        let mut rng = Rng::new(3);
        let samples = surface_samples(&shape, 20_000.0, &mut rng);
        assert!(covered(&samples, &spheres) <= 1e-9);
        // No sphere much larger than its slab: a slab of the 0.1 m square section at most
        // 0.8 / 6 long.
        let bound = (0.05f64 * 0.05 * 2.0 + (0.4 / 6.0f64).powi(2)).sqrt();
        for s in &spheres {
            assert!(s.radius <= bound + 1e-9, "{}", s.radius);
        }
    }

    #[test]
    fn every_primitive_and_a_mesh_is_covered_with_the_margin_added() {
        let mesh = shapes::cylinder(0.03, 0.3, 40);
        let cases = [
            Shape::Cylinder {
                radius: 0.05,
                length: 0.4,
            },
            Shape::Capsule {
                radius: 0.04,
                length: 0.2,
            },
            Shape::Sphere { radius: 0.1 },
            Shape::Mesh {
                path: "cylinder.stl".into(),
                scale: Vector3::repeat(1.0),
                mesh: Arc::new(mesh),
            },
        ];
        let mut rng = Rng::new(5);
        for shape in cases {
            let samples = surface_samples(&shape, 50_000.0, &mut rng);
            let spheres = shape_spheres(&shape, 0.002);
            assert!(!spheres.is_empty());
            // Every sample at least the margin inside.
            let worst = covered(&samples, &spheres);
            assert!(worst <= -0.002 + 1e-9, "{shape:?}: {worst}");
        }
    }

    #[test]
    fn a_model_verifies_against_its_robot_and_a_shrunk_one_does_not() {
        let urdf = r#"<robot name="r">
          <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
          <link name="arm"><collision><origin xyz="0 0 0.25"/><geometry><cylinder radius="0.03" length="0.5"/></geometry></collision></link>
          <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
            <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#;
        let model = RobotModel::from_urdf_str(urdf, std::path::Path::new("."), &Default::default())
            .expect("a robot");
        let spheres = SphereModel::of(&model, 0.0);
        assert!(spheres.count() >= 2);
        let c = spheres.verify(&model, 20_000.0, 1);
        assert!(c.samples > 1000);
        assert_eq!((c.outside, c.worst), (0, 0.0));
        let mut shrunk = spheres.clone();
        for s in shrunk.links.iter_mut().flatten() {
            s.radius *= 0.8;
        }
        let c = shrunk.verify(&model, 20_000.0, 1);
        assert!(c.outside > 0 && c.worst > 0.001, "{c:?}");
    }
}
