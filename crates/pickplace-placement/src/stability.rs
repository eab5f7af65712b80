//! The stability test of Harada et al., §III-B.2, Fig. 7 ("Stability checking algorithm"): the
//! one home of the test, used by face-face and edge-face placements
//! ([`mod@crate::candidates`]), resting poses ([`crate::resting`]) and the façade's plan validator.
//!
//! The paper assumes friction large enough and checks that the vertical line through the
//! object's CoG passes through the supported area, in four steps:
//! 1. the common area of the outer boundaries of the object's and the environment's clusters;
//! 2. minus the regions inside their inner boundaries (holes), so that an object is not judged
//!    to stand over a hole;
//! 3. the 2D convex hull of that area, the [`SupportHull`];
//! 4. the CoG's vertical must pass inside the hull: [`SupportHull::cog_margin`] is the signed
//!    distance of its foot to the hull's boundary, and [`is_stable`] asks for a minimum margin
//!    and a minimum tipping angle.
//!
//! A support given by contact points instead of areas (an edge-face contact and its second
//! contacts, the contacts measured by a validator) enters at step 3
//! ([`SupportHull::of_points`]); so does a face of the object's convex hull resting on an
//! infinite plane ([`crate::resting`]), where steps 1 and 2 leave the face itself.
//!
//! # Example
//! ```
//! use pickplace_geometry::math::Point2;
//! use pickplace_geometry::polygon::{Polygon, rectangle};
//! use pickplace_placement::stability::{SupportHull, is_stable};
//!
//! let square = |x0: f64, y0: f64, side: f64| {
//!     Polygon::new(rectangle(Point2::new(x0, y0), Point2::new(x0 + side, y0 + side)))
//! };
//! // A 10 cm square foot on a large table, the CoG 5 cm above the foot's centre.
//! let hull = SupportHull::of_regions(&square(0.0, 0.0, 0.1), &square(-1.0, -1.0, 2.0));
//! let margin = hull.cog_margin(&Point2::new(0.05, 0.05));
//! assert!((margin - 0.05).abs() < 1e-6); // the boolean operations snap to about 1e-9 m
//! assert!(is_stable(margin, 0.05, 0.002, 0.0));
//! // Moved half off the table's edge at x = 1, the CoG's vertical misses the support.
//! let hull = SupportHull::of_regions(&square(0.96, 0.0, 0.1), &square(-1.0, -1.0, 2.0));
//! assert!(hull.cog_margin(&Point2::new(1.01, 0.05)) < 0.0);
//! ```

use crate::region::Region;
use pickplace_geometry::math::{Point2, Point3, Real, Vector3};
use pickplace_geometry::polygon::{self, Polygon};

/// The convex hull of a contact's supported area or points, in the coordinates of the contact
/// plane, counter-clockwise (Fig. 7, third step).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SupportHull {
    points: Vec<Point2>,
}

impl SupportHull {
    /// The hull of the supported area of two touching planar regions (Fig. 7, all steps
    /// before the CoG test): the common area of the two outer boundaries, minus the holes of
    /// both, then its convex hull. Both polygons are in the same plane coordinates.
    pub fn of_regions(object: &Polygon, environment: &Polygon) -> Self {
        Self {
            points: polygon::support_hull(object, environment),
        }
    }

    /// The hull of supporting contact points (plane coordinates): a line contact's ends with
    /// the points where the object touches the environment again, or contacts measured on a
    /// placed object.
    pub fn of_points(points: &[Point2]) -> Self {
        Self {
            points: polygon::convex_hull(points),
        }
    }

    /// The hull's corners, counter-clockwise.
    pub fn points(&self) -> &[Point2] {
        &self.points
    }

    /// Whether the support has an area (at least three corners): a point or a segment supports
    /// nothing against tipping.
    pub fn has_area(&self) -> bool {
        self.points.len() >= 3
    }

    /// Fig. 7, last step: the signed distance (m) from the foot of the CoG's vertical line
    /// (plane coordinates) to the hull's boundary, positive inside (the stability margin);
    /// [`Real::NEG_INFINITY`] when the support has no area.
    pub fn cog_margin(&self, cog_foot: &Point2) -> Real {
        if self.has_area() {
            polygon::signed_margin(cog_foot, &self.points)
        } else {
            Real::NEG_INFINITY
        }
    }

    /// As [`SupportHull::cog_margin`], computed through the half-plane distances of the convex
    /// hull ([`polygon::signed_distance_convex`]); the two agree to rounding. Resting poses
    /// ([`crate::resting`]) use this form, and their reported margins keep its last bits.
    pub fn cog_margin_convex(&self, cog_foot: &Point2) -> Real {
        polygon::signed_distance_convex(&self.points, cog_foot)
    }
}

/// The verdict of the stability test: the CoG's vertical passes inside the support with at
/// least `min_margin` (m) to spare, and the object must turn by at least `min_tipping_angle`
/// (rad) about the nearest edge of its support before its CoG, `cog_height` (m) above the
/// support, crosses that edge (`atan(margin / cog_height)`).
///
/// A margin alone favours tall objects; the tipping angle makes the paper's test scale-aware.
/// A height below 1 nm counts as 1 nm.
pub fn is_stable(
    margin: Real,
    cog_height: Real,
    min_margin: Real,
    min_tipping_angle: Real,
) -> bool {
    margin >= min_margin && tipping_angle(margin, cog_height) >= min_tipping_angle
}

/// The tipping angle (rad) of a support: how far the object must turn about the nearest edge
/// of its support before its CoG, `cog_height` (m) above the support, crosses that edge:
/// `atan2(margin, cog_height)`, the height clamped to at least 1 nm as in [`is_stable`].
/// Negative when the margin is (the CoG's vertical misses the support).
pub fn tipping_angle(margin: Real, cog_height: Real) -> Real {
    margin.atan2(cog_height.max(1e-9))
}

/// Where the vertical line through a CoG at `cog_in_world` meets the plane of the environment
/// region `env` (world frame, gravity along −z), in the region's plane coordinates; `None`
/// when gravity does not point into the plane (a wall or a ceiling).
pub fn cog_foot(env: &Region, cog_in_world: &Point3) -> Option<Point2> {
    let (c, h) = env.to_plane(cog_in_world);
    let g = env
        .parent_from_plane
        .inverse_transform_vector(&-Vector3::z());
    if g.z >= -1e-9 {
        return None;
    }
    let s = -h / g.z;
    Some(Point2::new(c.x + s * g.x, c.y + s * g.y))
}

/// The contact model (issue 31): points of a body within this distance (m) of a supporting
/// plane touch it. An object on a plane touches it where its convex hull does; a scanned or
/// generated base is flat only to about a millimetre, so the support is the hull of every
/// point within this tolerance of the plane, not of the few points exactly on it. The default
/// is the paper's h_max of the environment-contact clustering (§III-A, 1 mm): the flatness a
/// cluster the paper calls a contact region is allowed to have.
pub const CONTACT_TOLERANCE: Real = 1e-3;

/// A rise of the centre of gravity smaller than this (m) while the body tips is not a barrier
/// ([`hull_tipping_angle`]): it is a bump of the tessellation or of scan noise, which a body
/// rocks over. A 64-sided can on its side rises 0.04 mm between two facets, a cylinder
/// scanned with 1 mm of noise up to a few tenths of a millimetre (measured with
/// `cargo xtask stability`: with 0.02 mm such cylinders were offered on their side and rolled
/// 4-13° in rapier). A body released 1 mm above its pose (the drop test) must not be able to
/// roll over its barrier; 0.25 mm asks a 19 mm high CoG for a 3.1 mm margin at least.
pub const MIN_BARRIER_RISE: Real = 2.5e-4;

/// Azimuths at which [`hull_tipping_angle`] tips the body (every 7.5°).
const TIP_AZIMUTHS: usize = 48;
/// Tilt steps of [`hull_tipping_angle`] between 0 and 90° (every 0.5°).
const TIP_STEPS: usize = 180;

/// The tipping angle (rad) of a rigid body resting with its `down` direction (unit, body frame)
/// towards gravity, as its convex hull decides it: the least tilt, over every direction, at
/// which the CoG passes over the point it pivots on, the body rolling on its hull as a rigid
/// body does on a plane. Bumps lower than [`MIN_BARRIER_RISE`] do not count; a body whose CoG
/// never rises by that much (a sphere, a cylinder on its side), or first sinks by that much
/// (it rests beside a lower pose), has a tipping angle of 0.
///
/// This is the paper's Fig. 7 test seen from the hull: on a flat support it is
/// `atan(margin / height)` ([`tipping_angle`]) up to the 7.5° azimuth sampling (which can only
/// make it larger), and it is what keeps a tolerance support ([`CONTACT_TOLERANCE`]) honest on
/// a curved surface, where the points within the tolerance carry nothing against rolling.
/// `hull` may hold any points of the body (its convex hull's vertices are enough).
pub fn hull_tipping_angle(hull: &[Point3], cog: &Point3, down: &Vector3) -> Real {
    let Some(d) = down.try_normalize(1e-12) else {
        return 0.0;
    };
    let (u0, v0) = crate::resting::plane_basis(&d);
    // (height below the CoG along `down`, horizontal offset), sorted by height, deepest first:
    // the same order serves every azimuth.
    let mut rel: Vec<(Real, Real, Real)> = hull
        .iter()
        .map(|p| {
            let w = p - cog;
            (w.dot(&d), w.dot(&u0), w.dot(&v0))
        })
        .filter(|(a, x, y)| a.is_finite() && x.is_finite() && y.is_finite())
        .collect();
    if rel.is_empty() {
        return 0.0;
    }
    rel.sort_by(|p, q| q.0.total_cmp(&p.0));
    let trig: Vec<(Real, Real)> = (0..=TIP_STEPS)
        .map(|i| {
            let a = std::f64::consts::FRAC_PI_2 * i as Real / TIP_STEPS as Real;
            (a.cos(), a.sin())
        })
        .collect();
    let mut best = Real::INFINITY;
    let mut front: Vec<(Real, Real)> = Vec::new();
    for k in 0..TIP_AZIMUTHS {
        let phi = std::f64::consts::TAU * k as Real / TIP_AZIMUTHS as Real;
        let (c, s) = (phi.cos(), phi.sin());
        // Tilting towards `u`, the contact maximises a·cos α + b·sin α with cos, sin ≥ 0: only
        // the points that no other point beats in both a and b (the staircase) can be it.
        front.clear();
        let mut b_max = Real::NEG_INFINITY;
        for &(a, x, y) in &rel {
            let b = x * c + y * s;
            if b > b_max {
                b_max = b;
                front.push((a, b));
            }
        }
        let height = |i: usize| {
            let (ca, sa) = trig[i];
            front
                .iter()
                .map(|(a, b)| a * ca + b * sa)
                .fold(Real::NEG_INFINITY, Real::max)
        };
        let angle = first_barrier(height, &front, &trig);
        best = best.min(angle);
        if best <= 0.0 {
            return 0.0;
        }
    }
    best
}

/// The first significant barrier of a tilt profile (see [`hull_tipping_angle`]): `height(i)` is
/// the CoG's height at tilt step `i`; the peak's angle is exact, the angle at which the CoG is
/// over the contact point that makes the peak.
fn first_barrier(
    height: impl Fn(usize) -> Real,
    front: &[(Real, Real)],
    trig: &[(Real, Real)],
) -> Real {
    let h0 = height(0);
    let mut low = h0;
    let mut peak: Option<(usize, Real)> = None;
    for i in 1..trig.len() {
        let h = height(i);
        match peak {
            None => {
                if h < low {
                    low = h;
                    if h0 - low > MIN_BARRIER_RISE {
                        return 0.0;
                    }
                } else if h - low >= MIN_BARRIER_RISE {
                    peak = Some((i, h));
                }
            }
            Some((_, top)) if h > top => peak = Some((i, h)),
            Some((_, top)) if top - h >= MIN_BARRIER_RISE => break,
            Some(_) => {}
        }
    }
    let Some((i, _)) = peak else {
        return 0.0;
    };
    // The contact at the peak sample; the CoG is over it at atan2(b, a).
    let (ca, sa) = trig[i];
    let (a, b, _) = front.iter().fold(
        (0.0, 0.0, Real::NEG_INFINITY),
        |best: (Real, Real, Real), &(a, b)| {
            let h = a * ca + b * sa;
            if h > best.2 { (a, b, h) } else { best }
        },
    );
    b.atan2(a).clamp(0.0, std::f64::consts::FRAC_PI_2)
}

/// The support of a body on a plane under the contact model ([`CONTACT_TOLERANCE`]): the 2D
/// convex hull, in the plane's coordinates `(u, v)`, of the `points` (body frame) lying within
/// `tolerance` of the supporting plane with outward normal `normal` (unit, pointing into the
/// support) at `offset` (`normal · p ≤ offset` for every point of the body).
pub fn tolerance_support(
    points: &[Point3],
    normal: &Vector3,
    offset: Real,
    basis: (&Vector3, &Vector3),
    tolerance: Real,
) -> SupportHull {
    let on: Vec<Point2> = points
        .iter()
        .filter(|p| offset - normal.dot(&p.coords) <= tolerance)
        .map(|p| Point2::new(p.coords.dot(basis.0), p.coords.dot(basis.1)))
        .collect();
    SupportHull::of_points(&on)
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::{Isometry3, Translation3, UnitQuaternion};

    fn square(x0: Real, y0: Real, side: Real) -> Vec<Point2> {
        polygon::rectangle(Point2::new(x0, y0), Point2::new(x0 + side, y0 + side))
    }

    fn table() -> Polygon {
        Polygon::new(square(-1.0, -1.0, 2.0))
    }

    #[test]
    fn square_support_margin_is_the_distance_to_the_nearest_edge() {
        let hull = SupportHull::of_regions(&Polygon::new(square(0.0, 0.0, 0.2)), &table());
        assert!(hull.has_area());
        assert_eq!(hull.points().len(), 4);
        for (foot, expected) in [((0.1, 0.1), 0.1), ((0.05, 0.1), 0.05), ((0.1, 0.19), 0.01)] {
            let margin = hull.cog_margin(&Point2::new(foot.0, foot.1));
            // The boolean operations snap coordinates to about 1e-9 m.
            assert!((margin - expected).abs() < 1e-6, "{foot:?}: {margin}");
            let convex = hull.cog_margin_convex(&Point2::new(foot.0, foot.1));
            assert!((convex - margin).abs() < 1e-12);
        }
    }

    #[test]
    fn support_is_only_the_common_area() {
        // The object overhangs the table's edge at x = 1: the support is x in [0.9, 1].
        let hull = SupportHull::of_regions(&Polygon::new(square(0.9, 0.0, 0.2)), &table());
        let xs: Vec<Real> = hull.points().iter().map(|p| p.x).collect();
        assert!(
            xs.iter().all(|x| (0.9 - 1e-6..=1.0 + 1e-6).contains(x)),
            "{xs:?}"
        );
        assert!(hull.cog_margin(&Point2::new(1.0, 0.1)).abs() < 1e-6);
        assert!(hull.cog_margin(&Point2::new(1.05, 0.1)) < 0.0);
    }

    #[test]
    fn a_hole_under_one_side_shrinks_the_support() {
        // A table with a hole covering x < 0.1 under a 0.2 m square foot: the supported area is
        // the strip x in [0.1, 0.2], so a CoG over the hole's side is outside the support.
        let mut table = table();
        table.holes.push(vec![
            Point2::new(-0.5, -0.5),
            Point2::new(-0.5, 0.5),
            Point2::new(0.1, 0.5),
            Point2::new(0.1, -0.5),
        ]);
        let hull = SupportHull::of_regions(&Polygon::new(square(0.0, 0.0, 0.2)), &table);
        assert!(hull.cog_margin(&Point2::new(0.05, 0.1)) < 0.0);
        let margin = hull.cog_margin(&Point2::new(0.15, 0.1));
        assert!((margin - 0.05).abs() < 1e-6, "{margin}");
    }

    #[test]
    fn a_hole_surrounded_by_support_does_not_matter_after_the_hull() {
        // A ring-shaped foot (a mug's rim): the hull bridges the hole (Fig. 7, third step).
        let mut foot = Polygon::new(square(0.0, 0.0, 0.2));
        foot.holes
            .push(square(0.05, 0.05, 0.1).into_iter().rev().collect());
        let hull = SupportHull::of_regions(&foot, &table());
        let margin = hull.cog_margin(&Point2::new(0.1, 0.1));
        assert!((margin - 0.1).abs() < 1e-6, "{margin}");
    }

    #[test]
    fn cog_outside_is_negative_and_unstable() {
        let hull = SupportHull::of_points(&square(0.0, 0.0, 0.1));
        let margin = hull.cog_margin(&Point2::new(0.13, 0.05));
        assert!((margin + 0.03).abs() < 1e-12, "{margin}");
        assert!(!is_stable(margin, 0.05, 0.0, 0.0));
    }

    #[test]
    fn degenerate_supports_have_no_area() {
        let foot = Point2::new(0.0, 0.0);
        for points in [
            vec![],
            vec![Point2::new(0.0, 0.0)],
            vec![Point2::new(-1.0, 0.0), Point2::new(1.0, 0.0)],
            vec![
                Point2::new(-1.0, 0.0),
                Point2::new(0.0, 0.0),
                Point2::new(1.0, 0.0),
            ],
        ] {
            let hull = SupportHull::of_points(&points);
            assert!(!hull.has_area(), "{points:?}");
            assert_eq!(hull.cog_margin(&foot), Real::NEG_INFINITY);
            assert_eq!(hull.cog_margin_convex(&foot), Real::NEG_INFINITY);
            assert!(!is_stable(hull.cog_margin(&foot), 0.1, 0.0, 0.0));
        }
        // Regions that do not overlap support nothing.
        let apart = SupportHull::of_regions(
            &Polygon::new(square(5.0, 5.0, 0.1)),
            &Polygon::new(square(0.0, 0.0, 0.1)),
        );
        assert!(!apart.has_area());
    }

    #[test]
    fn tipping_angle_rejects_tall_objects_with_small_margins() {
        // 1 cm margin: fine at 1 cm height (45°), not at 1 m (0.57°) when 5° are asked for.
        let five_deg = 5f64.to_radians();
        assert!(is_stable(0.01, 0.01, 0.002, five_deg));
        assert!(!is_stable(0.01, 1.0, 0.002, five_deg));
        assert!(!is_stable(0.001, 0.01, 0.002, 0.0));
        // A zero height is clamped, not divided by.
        assert!(is_stable(0.01, 0.0, 0.002, five_deg));
    }

    #[test]
    fn hull_tipping_angle_is_the_flat_support_s_on_a_box_and_zero_on_a_cylinder_s_side() {
        // A 10 x 6 x 4 cm box lying on its largest face, CoG at the centre: tipping about the
        // long edge first, atan(3 / 2).
        let corners: Vec<Point3> = (0..8)
            .map(|i| {
                Point3::new(
                    if i & 1 == 0 { -0.05 } else { 0.05 },
                    if i & 2 == 0 { -0.03 } else { 0.03 },
                    if i & 4 == 0 { -0.02 } else { 0.02 },
                )
            })
            .collect();
        let down = -Vector3::z();
        let angle = hull_tipping_angle(&corners, &Point3::origin(), &down);
        let exact = 0.03f64.atan2(0.02);
        // The azimuth sampling can only make it larger, by at most 1/cos(3.75°).
        assert!(
            angle >= exact - 1e-9 && angle < exact + 0.01,
            "{angle} vs {exact}"
        );
        // A 64-sided cylinder of radius 3 cm on its side: the CoG rises 0.04 mm at most.
        let ring: Vec<Point3> = (0..64)
            .flat_map(|k| {
                let a = std::f64::consts::TAU * (k as Real + 0.5) / 64.0;
                [-0.06, 0.06].map(|y| Point3::new(0.03 * a.cos(), y, 0.03 * a.sin()))
            })
            .collect();
        assert_eq!(hull_tipping_angle(&ring, &Point3::origin(), &down), 0.0);
        // Off its equilibrium (tilted 10° about y): it sinks first.
        let tilted = Vector3::new(10f64.to_radians().sin(), 0.0, -10f64.to_radians().cos());
        assert_eq!(
            hull_tipping_angle(&corners, &Point3::origin(), &tilted),
            0.0
        );
    }

    #[test]
    fn tolerance_support_takes_the_points_within_the_tolerance() {
        let points = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0005),
            Point3::new(0.0, 1.0, 0.0009),
            Point3::new(1.0, 1.0, 0.002),
        ];
        // The plane z = 0 with outward normal -z (offset 0): z <= 1 mm lies on it.
        let (u, v) = (Vector3::x(), -Vector3::y());
        let s = tolerance_support(&points, &-Vector3::z(), 0.0, (&u, &v), CONTACT_TOLERANCE);
        assert_eq!(s.points().len(), 3);
        let rigid = tolerance_support(&points, &-Vector3::z(), 0.0, (&u, &v), 0.0);
        assert!(!rigid.has_area());
    }

    #[test]
    fn cog_foot_follows_gravity_onto_the_plane() {
        let horizontal = Region::new(
            0,
            Isometry3::translation(1.0, 2.0, 0.5),
            Polygon::new(square(0.0, 0.0, 1.0)),
        )
        .expect("region");
        let foot = cog_foot(&horizontal, &Point3::new(1.3, 2.4, 0.9)).expect("below");
        assert!((foot - Point2::new(0.3, 0.4)).norm() < 1e-12);
        // A vertical wall: gravity runs along it, no foot.
        let wall = Region::new(
            0,
            Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2),
            ),
            Polygon::new(square(0.0, 0.0, 1.0)),
        )
        .expect("region");
        assert_eq!(cog_foot(&wall, &Point3::new(0.0, 0.0, 1.0)), None);
    }
}
