//! Resting checks for a planner's pre-search (issue 17): is the object resting where the scene
//! says ([`rest_state`]: on a support, not floating, not penetrating, its CoG's vertical inside
//! the support), and can it stand at the target ([`target_surface`]).
//!
//! The stability part is the paper's test (§III-B.2, Fig. 7, [`crate::stability`]) on the
//! support the object actually has at the given pose: the convex hull of
//! - the common area of every object region lying on an upward-facing environment region
//!   (face-face, Fig. 7's first two steps: outer boundaries intersected, holes removed);
//! - the object's vertices lying on the environment and the environment's vertices touching
//!   the object, found by vertical rays (an edge on a face, a corner in a dent, a can on its
//!   side).
//!
//! Only vertical rays look for contacts, so a wall beside the object carries nothing, as in the
//! paper (friction is assumed large enough, gravity is −z).

use crate::candidates::{
    ContactKind, EnvironmentModel, ObjectModel, PlacementOptions, face_face_can_be_stable,
    include_bounding_box,
};
use crate::region::Region;
use crate::stability::{self, SupportHull};
use pickplace_geometry::math::{Isometry3, Point2, Point3, Real, Vector3};
use pickplace_geometry::polygon::{Polygon, signed_margin};

/// Tolerances of [`rest_state`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestOptions {
    /// The object floats when lowered by this much (m) it still touches nothing
    /// (default: 0.003).
    pub max_gap: Real,
    /// The object penetrates when a point of it lies deeper than this (m) inside the
    /// environment, or a point of the environment that deep inside it, measured vertically
    /// (default: 0.002).
    pub max_depth: Real,
    /// Points of the object and of the environment this close (m) to each other, vertically,
    /// support the object (default: [`stability::CONTACT_TOLERANCE`], 1 mm, the contact
    /// model). On a curved surface that band carries nothing against rolling: with minimums
    /// (a pose the planner chooses) the tipping angle is capped by the object's hull tipping
    /// angle ([`stability::hull_tipping_angle`]).
    pub contact_tolerance: Real,
    /// Minimum stability margin (m) (default: 0: a start pose is what the scene observed, its
    /// CoG's vertical only has to pass inside the support; see [`RestOptions::placement`]).
    pub min_margin: Real,
    /// Minimum tipping angle (rad) (default: 0, as `min_margin`).
    pub min_tipping_angle: Real,
}

impl Default for RestOptions {
    fn default() -> Self {
        Self {
            max_gap: 0.003,
            max_depth: 0.002,
            contact_tolerance: stability::CONTACT_TOLERANCE,
            min_margin: 0.0,
            min_tipping_angle: 0.0,
        }
    }
}

impl RestOptions {
    /// The tolerances of a pose the planner chooses (a placement, an intermediate pose for a
    /// regrasp): the placement search's minimum margin and tipping angle.
    pub fn placement(options: &PlacementOptions) -> Self {
        Self {
            min_margin: options.min_margin,
            min_tipping_angle: options.min_tipping_angle,
            ..Self::default()
        }
    }
}

/// How the object rests at a pose ([`rest_state`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "kebab-case", tag = "state")]
pub enum RestState {
    /// On a support, its CoG's vertical inside it with the minimums to spare.
    Resting {
        /// Stability margin (m).
        margin: Real,
        /// Tipping angle (rad).
        tipping_angle: Real,
    },
    /// Nothing under it within [`RestOptions::max_gap`].
    Floating {
        /// Vertical distance (m) to the first thing below (infinite over nothing).
        gap: Real,
    },
    /// Deeper than [`RestOptions::max_depth`] in the environment.
    Penetrating {
        /// The deepest vertical penetration found (m).
        depth: Real,
    },
    /// On a support that does not hold it: the CoG's vertical misses the support or passes
    /// within the minimums of its boundary.
    Unstable {
        /// Stability margin (m), negative outside the support (−∞ for a support of no area).
        margin: Real,
        /// Tipping angle (rad).
        tipping_angle: Real,
    },
}

impl RestState {
    /// Whether the object rests.
    pub fn is_resting(&self) -> bool {
        matches!(self, RestState::Resting { .. })
    }
}

impl std::fmt::Display for RestState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            RestState::Resting {
                margin,
                tipping_angle,
            } => write!(
                f,
                "resting (margin {:.1} mm, tipping angle {:.1}°)",
                margin * 1e3,
                tipping_angle.to_degrees()
            ),
            RestState::Floating { gap } if gap.is_finite() => {
                write!(f, "floating {:.1} mm above the nearest support", gap * 1e3)
            }
            RestState::Floating { .. } => write!(f, "floating over nothing"),
            RestState::Penetrating { depth } => {
                write!(f, "penetrating the environment by {:.1} mm", depth * 1e3)
            }
            RestState::Unstable {
                margin,
                tipping_angle,
            } if margin.is_finite() => write!(
                f,
                "unstable: its centre of gravity is {:.1} mm {} the support's edge (tipping angle {:.1}°)",
                margin.abs() * 1e3,
                if margin < 0.0 { "outside" } else { "inside" },
                tipping_angle.to_degrees()
            ),
            RestState::Unstable { .. } => {
                write!(
                    f,
                    "unstable: it touches the support at a point or a line only"
                )
            }
        }
    }
}

/// Rays are cast no further than this (m) when looking for a support below the object.
const MAX_RAY: Real = 10.0;

/// How the object rests at `world_from_object` on the environment (gravity −z): penetrating
/// (checked first), floating, or on a support, stable or not (paper §III-B.2, Fig. 7, on the
/// support the object has at that pose; see the module's documentation).
///
/// Penetration is measured vertically: the depth of an object vertex inside the environment
/// (the first environment triangle above it is left from inside) or of an environment vertex
/// inside the object. An edge crossing an edge without a vertex inside is not seen.
///
/// # Performance
/// Two vertical rays per object vertex and one per environment vertex under the object, one
/// collision test, and one polygon intersection per facing pair of regions.
pub fn rest_state(
    object: &ObjectModel,
    env: &EnvironmentModel,
    world_from_object: &Isometry3,
    options: &RestOptions,
) -> RestState {
    let up = Vector3::z();
    let down = -up;
    let identity = Isometry3::identity();
    let object_points: Vec<Point3> = object
        .collision
        .vertices()
        .iter()
        .map(|p| world_from_object * p)
        .collect();
    let (lo, hi) = bounds(&object_points);
    let height = hi.z - lo.z;
    let env_points: Vec<Point3> = env
        .collision
        .vertices()
        .iter()
        .filter(|p| (lo.x..=hi.x).contains(&p.x) && (lo.y..=hi.y).contains(&p.y))
        .filter(|p| p.z >= lo.z - options.max_gap && p.z <= hi.z)
        .copied()
        .collect();

    // Penetration: object vertices under an environment surface that is left from inside going
    // up; environment vertices above an object surface that is left from inside going down.
    let mut depth: Real = 0.0;
    for p in &object_points {
        if let Some((t, true)) = env.collision.ray_hit(&identity, p, &up, height + 0.01) {
            depth = depth.max(t);
        }
    }
    for p in &env_points {
        if let Some((t, true)) = object
            .collision
            .ray_hit(world_from_object, p, &down, height)
        {
            depth = depth.max(t);
        }
    }
    if depth > options.max_depth {
        return RestState::Penetrating { depth };
    }

    // Vertical gaps: object vertices above the environment, environment vertices below the
    // object, each ray started `max_depth` back so that a slightly sunk point counts.
    let back = options.max_depth + 1e-6;
    let mut gaps: Vec<(Real, Point3)> = Vec::new();
    for p in &object_points {
        let from = p + up * back;
        if let Some(t) = env.collision.ray_distance(&identity, &from, &down, MAX_RAY) {
            gaps.push((t - back, *p));
        }
    }
    for p in &env_points {
        let from = p - up * back;
        if let Some(t) =
            object
                .collision
                .ray_distance(world_from_object, &from, &up, height + back + 0.01)
        {
            gaps.push((t - back, *p));
        }
    }
    let gap = gaps.iter().map(|g| g.0).fold(Real::INFINITY, Real::min);
    // The support: points within the tolerance of the environment, or of the lowest point when
    // the object hangs slightly above it.
    let reach = gap.max(0.0) + options.contact_tolerance;
    let mut support: Vec<Point3> = gaps
        .iter()
        .filter(|(g, _)| *g <= reach)
        .map(|(_, p)| *p)
        .collect();
    if gap > options.max_gap {
        // An edge above an edge is not seen by the rays: lowered by `max_gap`, does the object
        // touch anything?
        let lowered = down * options.max_gap;
        if !env
            .collision
            .intersects(&object.collision, world_from_object, &lowered)
        {
            return RestState::Floating { gap };
        }
    }

    // Face-face contacts (Fig. 7): the common area of facing regions.
    for o in &object.regions {
        let o_world = o.transformed(world_from_object);
        for e in env.regions.iter().filter(|e| e.normal().z > 1e-6) {
            if o_world.normal().dot(&e.normal()) > -(2f64.to_radians().cos()) {
                continue;
            }
            if let Some(points) = common_support(&o_world, e, options.max_depth, reach) {
                support.extend(points);
            }
        }
    }
    let horizontal = |p: &Point3| Point2::new(p.x, p.y);
    let cog = world_from_object * object.cog;
    let hull = SupportHull::of_points(&support.iter().map(horizontal).collect::<Vec<_>>());
    let margin = hull.cog_margin(&horizontal(&cog));
    let base = support.iter().map(|p| p.z).fold(Real::INFINITY, Real::min);
    let cog_height = if base.is_finite() { cog.z - base } else { 0.0 };
    // A band of a curved surface within the tolerance carries nothing against rolling: where
    // minimums apply, the hull decides how far the object can tip.
    let margin = if options.min_margin > 0.0 || options.min_tipping_angle > 0.0 {
        let down = world_from_object.inverse_transform_vector(&down);
        let limit = stability::hull_tipping_angle(&object.hull, &object.cog, &down);
        margin.min(cog_height.max(1e-9) * limit.tan())
    } else {
        margin
    };
    let tipping_angle = stability::tipping_angle(margin, cog_height);
    if stability::is_stable(
        margin,
        cog_height,
        options.min_margin,
        options.min_tipping_angle,
    ) && margin > 0.0
    {
        RestState::Resting {
            margin,
            tipping_angle,
        }
    } else {
        RestState::Unstable {
            margin,
            tipping_angle,
        }
    }
}

/// The corners (world frame) of the supported area of the object region `o` (world frame) on
/// the environment region `e` (Fig. 7's first two steps) when `o`'s support lies on `e`'s
/// plane, from `max_depth` (m) below it to `reach` (m) above; `None` otherwise.
fn common_support(o: &Region, e: &Region, max_depth: Real, reach: Real) -> Option<Vec<Point3>> {
    let to_e = |q: &Point2| {
        let w = o.parent_from_plane * Point3::new(q.x, q.y, 0.0);
        e.to_plane(&w)
    };
    let support: Vec<(Point2, Real)> = o.support.iter().map(to_e).collect();
    if support.len() < 3 || support.iter().any(|(_, h)| *h < -max_depth || *h > reach) {
        return None;
    }
    let moved = Polygon {
        outer: support.iter().map(|(q, _)| *q).collect(),
        holes: o
            .polygon
            .holes
            .iter()
            .map(|h| h.iter().map(|q| to_e(q).0).collect())
            .collect(),
    };
    let hull = SupportHull::of_regions(&moved, &e.polygon);
    Some(
        hull.points()
            .iter()
            .map(|q| e.parent_from_plane * Point3::new(q.x, q.y, 0.0))
            .collect(),
    )
}

fn bounds(points: &[Point3]) -> (Point3, Point3) {
    let mut lo = Point3::new(Real::INFINITY, Real::INFINITY, Real::INFINITY);
    let mut hi = Point3::new(Real::NEG_INFINITY, Real::NEG_INFINITY, Real::NEG_INFINITY);
    for p in points {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (lo, hi)
}

/// The environment surface a target point lies on, and how the object can stand on it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TargetSurface {
    /// The environment cluster (the paper's clicked cluster).
    pub env_cluster: usize,
    /// Its slope from horizontal (rad).
    pub slope: Real,
    /// The object's resting faces that fit it: (object cluster, contact kind), face-face where
    /// the face's bounding box fits the region (`includeBoundingBox`), edge-face where one side
    /// of it fits (paper Fig. 6).
    pub fits: Vec<(usize, ContactKind)>,
}

/// Why the object cannot stand at a target ([`target_surface`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TargetSurfaceError {
    /// The target is on no environment surface.
    #[error(
        "the target is not on any surface: {:.1} mm from the nearest (cluster {nearest_cluster})",
        distance * 1e3
    )]
    NotOnSurface {
        /// The nearest environment cluster (`usize::MAX` when the environment has none).
        nearest_cluster: usize,
        /// Its distance to the target (m).
        distance: Real,
    },
    /// The target's surface is too steep to stand on.
    #[error(
        "the target's surface (cluster {env_cluster}) is too steep: {:.1}° from horizontal, at most {:.1}°",
        slope.to_degrees(), max_slope.to_degrees()
    )]
    TooSteep {
        /// The environment cluster.
        env_cluster: usize,
        /// Its slope (rad).
        slope: Real,
        /// The steepest allowed ([`PlacementOptions::max_slope`]).
        max_slope: Real,
    },
    /// No resting face of the object fits the target's surface.
    #[error(
        "the target's surface (cluster {env_cluster}, {:.1} x {:.1} mm) is too small for any face of the object (smallest face that could stand: {:.1} x {:.1} mm)",
        surface[0] * 1e3, surface[1] * 1e3, smallest_face[0] * 1e3, smallest_face[1] * 1e3
    )]
    TooSmall {
        /// The environment cluster.
        env_cluster: usize,
        /// Its bounding rectangle's sides (m), short first.
        surface: [Real; 2],
        /// The smallest bounding rectangle (short side first, m) among the object's faces
        /// that can hold it stably.
        smallest_face: [Real; 2],
    },
    /// No face of the object can stand on any plane with the stability minimums, whatever the
    /// surface: a round or pointed object, or minimums set too high.
    #[error(
        "no face of the object can stand on a plane with a margin of {:.1} mm and a tipping angle of {:.1}° (the placement minimums): the object rolls or tips on every face",
        min_margin * 1e3, min_tipping_angle.to_degrees()
    )]
    NoStableFace {
        /// The environment cluster.
        env_cluster: usize,
        /// The minimum margin asked for (m).
        min_margin: Real,
        /// The minimum tipping angle asked for (rad).
        min_tipping_angle: Real,
    },
}

/// Whether `target` lies on an environment surface the object can stand on (issue 17's
/// pre-search check): on a region (its plane within [`PlacementOptions::target_tolerance`] of
/// the point, the point's projection inside its polygon), facing up within
/// [`PlacementOptions::max_slope`], where some resting face of the object fits: face-face when
/// the face's 2D bounding box fits the region's (`includeBoundingBox`, paper Fig. 6(b)) and the
/// face's support is wide enough for the stability minimums, edge-face when one side of it
/// fits (Fig. 6(d)). A fit is necessary, not sufficient: obstacles and the stability of each
/// pose are [`crate::candidates`]' to decide.
///
/// # Errors
/// [`TargetSurfaceError`]: not on any surface (with the distance to the nearest), too steep,
/// or too small for any face of the object.
pub fn target_surface(
    object: &ObjectModel,
    env: &EnvironmentModel,
    target: &Point3,
    options: &PlacementOptions,
) -> Result<TargetSurface, TargetSurfaceError> {
    // Every region the point lies on, nearest plane first; the nearest of all otherwise.
    let mut on: Vec<(Real, &Region)> = Vec::new();
    let mut nearest: Option<(Real, &Region)> = None;
    for r in &env.regions {
        let (q, h) = r.to_plane(target);
        let inside = r.polygon.contains(&q);
        if h.abs() <= options.target_tolerance && inside {
            on.push((h.abs(), r));
        }
        let outside = if inside {
            0.0
        } else {
            (-signed_margin(&q, &r.polygon.outer)).max(0.0)
        };
        let d = h.hypot(outside);
        if nearest.is_none_or(|(nd, _)| d < nd) {
            nearest = Some((d, r));
        }
    }
    on.sort_by(|a, b| {
        a.0.total_cmp(&b.0)
            .then(a.1.cluster_id.cmp(&b.1.cluster_id))
    });
    if on.is_empty() {
        return Err(TargetSurfaceError::NotOnSurface {
            nearest_cluster: nearest.map_or(usize::MAX, |(_, r)| r.cluster_id),
            distance: nearest.map_or(Real::INFINITY, |(d, _)| d),
        });
    }
    let slope = |r: &Region| r.normal().z.clamp(-1.0, 1.0).acos();
    let Some(&(_, e)) = on.iter().find(|(_, r)| slope(r) <= options.max_slope) else {
        let (_, e) = on[0];
        return Err(TargetSurfaceError::TooSteep {
            env_cluster: e.cluster_id,
            slope: slope(e),
            max_slope: options.max_slope,
        });
    };
    let supporting = &object.supporting;
    let mut fits = Vec::new();
    let mut smallest = [Real::INFINITY; 2];
    let (env_short, env_long) = e.rect.sorted_sides();
    for (o, region) in object.regions.iter().enumerate() {
        if !supporting[o] || region.support.len() < 3 {
            continue;
        }
        if !face_face_can_be_stable(object, o, options) {
            continue;
        }
        let (short, long) = region.rect.sorted_sides();
        if short * long < smallest[0] * smallest[1] {
            smallest = [short, long];
        }
        if include_bounding_box(region, e) {
            fits.push((region.cluster_id, ContactKind::FaceFace));
        } else if short <= env_long {
            fits.push((region.cluster_id, ContactKind::EdgeFace));
        }
    }
    if fits.is_empty() && !smallest[0].is_finite() {
        return Err(TargetSurfaceError::NoStableFace {
            env_cluster: e.cluster_id,
            min_margin: options.min_margin,
            min_tipping_angle: options.min_tipping_angle,
        });
    }
    if fits.is_empty() {
        return Err(TargetSurfaceError::TooSmall {
            env_cluster: e.cluster_id,
            surface: [env_short, env_long],
            smallest_face: smallest,
        });
    }
    Ok(TargetSurface {
        env_cluster: e.cluster_id,
        slope: slope(e),
        fits,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
    use pickplace_geometry::math::{Translation3, UnitQuaternion};
    use pickplace_geometry::mesh::{MassProperties, TriMesh};
    use pickplace_geometry::shapes;
    use pickplace_objects as objects;

    fn object(mesh: &TriMesh) -> ObjectModel {
        let clusters = cluster_surface(mesh, &ClusterParams::environment()).expect("clusters");
        let cog = MassProperties::of(mesh).center_of_mass;
        ObjectModel::new(mesh, &clusters, cog).expect("object")
    }

    /// A 1 x 1 m table whose top is z = 0, its edges at x, y = ±0.5.
    fn table() -> EnvironmentModel {
        let mesh = shapes::box_builder([0.5, 0.5, 0.025])
            .translated(Vector3::new(0.0, 0.0, -0.025))
            .build()
            .expect("table");
        let clusters = cluster_surface(&mesh, &ClusterParams::environment()).expect("clusters");
        EnvironmentModel::new(&mesh, &clusters, &Isometry3::identity()).expect("env")
    }

    /// The 6 x 4 x 10 cm box standing on the table at (x, y), its bottom `dz` above the top.
    fn box_at(x: Real, y: Real, dz: Real) -> Isometry3 {
        Isometry3::translation(x, y, 0.05 + dz)
    }

    fn boxed() -> ObjectModel {
        object(&shapes::box_mesh([0.03, 0.02, 0.05]))
    }

    #[test]
    fn a_box_on_the_table_rests_with_its_margin() {
        let state = rest_state(
            &boxed(),
            &table(),
            &box_at(0.1, 0.0, 0.0),
            &RestOptions::default(),
        );
        let RestState::Resting {
            margin,
            tipping_angle,
        } = state
        else {
            panic!("{state}");
        };
        assert!((margin - 0.02).abs() < 1e-6, "{margin}");
        assert!((tipping_angle - (0.02f64).atan2(0.05)).abs() < 1e-6);
        // Half a millimetre above or below (within the tolerances): still resting.
        for dz in [5e-4, -5e-4] {
            let s = rest_state(
                &boxed(),
                &table(),
                &box_at(0.1, 0.0, dz),
                &RestOptions::default(),
            );
            assert!(s.is_resting(), "{dz}: {s}");
        }
    }

    #[test]
    fn a_box_above_the_table_floats() {
        let state = rest_state(
            &boxed(),
            &table(),
            &box_at(0.1, 0.0, 0.01),
            &RestOptions::default(),
        );
        let RestState::Floating { gap } = state else {
            panic!("{state}");
        };
        assert!((gap - 0.01).abs() < 1e-6, "{gap}");
        assert!(state.to_string().contains("10.0 mm"), "{state}");
        // Beside the table, over nothing.
        let state = rest_state(
            &boxed(),
            &table(),
            &box_at(2.0, 0.0, 0.0),
            &RestOptions::default(),
        );
        assert_eq!(
            state,
            RestState::Floating {
                gap: Real::INFINITY
            }
        );
    }

    #[test]
    fn a_box_sunk_into_the_table_penetrates() {
        let state = rest_state(
            &boxed(),
            &table(),
            &box_at(0.1, 0.0, -0.005),
            &RestOptions::default(),
        );
        let RestState::Penetrating { depth } = state else {
            panic!("{state}");
        };
        assert!((depth - 0.005).abs() < 1e-6, "{depth}");
    }

    #[test]
    fn a_box_overhanging_the_edge_is_unstable() {
        // The table's edge at x = 0.5; the box's CoG 2 cm beyond it, its foot 1 cm on the table.
        let state = rest_state(
            &boxed(),
            &table(),
            &box_at(0.52, 0.0, 0.0),
            &RestOptions::default(),
        );
        let RestState::Unstable { margin, .. } = state else {
            panic!("{state}");
        };
        assert!((margin + 0.02).abs() < 1e-6, "{margin}");
        assert!(state.to_string().contains("outside"), "{state}");
        // Its CoG 1 cm back from the edge it rests, with a 1 cm margin (to the edge).
        let state = rest_state(
            &boxed(),
            &table(),
            &box_at(0.49, 0.0, 0.0),
            &RestOptions::default(),
        );
        let RestState::Resting { margin, .. } = state else {
            panic!("{state}");
        };
        assert!((margin - 0.01).abs() < 1e-6, "{margin}");
    }

    #[test]
    fn a_can_on_its_side_rests_as_a_start_but_is_no_placement() {
        let can = object(&objects::can_builder().build().expect("can"));
        // Axis along y, a line of vertices at the bottom, the neighbouring ones 0.16 mm up.
        let pose = Isometry3::from_parts(
            Translation3::new(0.0, 0.06, objects::CAN_RADIUS),
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI_2),
        );
        let state = rest_state(&can, &table(), &pose, &RestOptions::default());
        let RestState::Resting { margin, .. } = state else {
            panic!("{state}");
        };
        // The lines within the contact tolerance (1 mm: the bottom one, 0.16 mm and 0.63 mm
        // up): half of 13 mm. A start pose only needs its CoG over the support.
        assert!(margin > 0.006 && margin < 0.0066, "{margin}");
        // As a placement, the hull decides: the can rolls (tipping angle 2.8° to the next
        // facet's edge, under the 6° minimum).
        let strict = RestOptions::placement(&PlacementOptions::default());
        let state = rest_state(&can, &table(), &pose, &strict);
        assert!(matches!(state, RestState::Unstable { .. }), "{state}");
    }

    const PI_2: Real = std::f64::consts::FRAC_PI_2;

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
        /// Anywhere on the table, turned about z: resting with the face's margin; lifted by
        /// more than `max_gap`: floating by the lift; sunk by more than `max_depth`: penetrating
        /// by the sink.
        #[test]
        fn the_state_follows_the_height(
            x in -0.4f64..0.4,
            y in -0.4f64..0.4,
            yaw in 0.0f64..std::f64::consts::TAU,
            lift in 0.004f64..0.05,
            sink in 0.003f64..0.04,
        ) {
            let (object, env) = (boxed(), table());
            let at = |dz: Real| {
                Isometry3::from_parts(
                    Translation3::new(x, y, 0.05 + dz),
                    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw),
                )
            };
            let options = RestOptions::default();
            match rest_state(&object, &env, &at(0.0), &options) {
                RestState::Resting { margin, .. } => {
                    proptest::prop_assert!((margin - 0.02).abs() < 1e-6, "{}", margin)
                }
                other => proptest::prop_assert!(false, "{}", other),
            }
            match rest_state(&object, &env, &at(lift), &options) {
                RestState::Floating { gap } => {
                    proptest::prop_assert!((gap - lift).abs() < 1e-6, "{} vs {}", gap, lift)
                }
                other => proptest::prop_assert!(false, "{}", other),
            }
            match rest_state(&object, &env, &at(-sink), &options) {
                RestState::Penetrating { depth } => {
                    proptest::prop_assert!((depth - sink).abs() < 1e-6, "{} vs {}", depth, sink)
                }
                other => proptest::prop_assert!(false, "{}", other),
            }
        }
    }

    #[test]
    fn target_on_the_table_fits_every_face_of_the_box() {
        let surface = target_surface(
            &boxed(),
            &table(),
            &Point3::new(0.1, 0.1, 0.0),
            &PlacementOptions::default(),
        )
        .expect("on the table");
        assert!(surface.slope.abs() < 1e-9);
        assert_eq!(surface.fits.len(), 6, "{surface:?}");
        assert!(
            surface
                .fits
                .iter()
                .all(|(_, k)| *k == ContactKind::FaceFace)
        );
    }

    #[test]
    fn target_in_the_air_is_on_no_surface() {
        let err = target_surface(
            &boxed(),
            &table(),
            &Point3::new(0.1, 0.1, 0.05),
            &PlacementOptions::default(),
        )
        .expect_err("5 cm above the table");
        let TargetSurfaceError::NotOnSurface { distance, .. } = err else {
            panic!("{err}");
        };
        assert!((distance - 0.05).abs() < 1e-9, "{distance}");
        assert!(err.to_string().contains("50.0 mm"), "{err}");
    }

    #[test]
    fn target_on_the_table_side_is_too_steep() {
        let err = target_surface(
            &boxed(),
            &table(),
            &Point3::new(0.5, 0.0, -0.03),
            &PlacementOptions::default(),
        )
        .expect_err("a vertical face");
        let TargetSurfaceError::TooSteep { slope, .. } = err else {
            panic!("{err}");
        };
        assert!((slope - PI_2).abs() < 1e-6, "{slope}");
    }

    #[test]
    fn target_in_the_small_dent_is_too_small_for_the_can() {
        let can = object(&objects::can_builder().build().expect("can"));
        let pallet = objects::pallet_builder().build().expect("pallet");
        let clusters = cluster_surface(&pallet, &ClusterParams::environment()).expect("clusters");
        let env = EnvironmentModel::new(&pallet, &clusters, &Isometry3::identity()).expect("env");
        let d = &objects::PALLET_DENTS[1];
        let floor = Point3::new(d.center[0], d.center[1], objects::PALLET_SIZE[2] - d.depth);
        let err = target_surface(&can, &env, &floor, &PlacementOptions::default())
            .expect_err("the 5 cm dent");
        let TargetSurfaceError::TooSmall { smallest_face, .. } = err else {
            panic!("{err}");
        };
        // The can's caps (66 mm across) are its only faces that can stand.
        assert!(
            (smallest_face[0] - 2.0 * objects::CAN_RADIUS).abs() < 1e-3,
            "{err}"
        );
        // The large dent (9 x 9 cm) takes the can face-face.
        let d = &objects::PALLET_DENTS[0];
        let floor = Point3::new(d.center[0], d.center[1], objects::PALLET_SIZE[2] - d.depth);
        let surface =
            target_surface(&can, &env, &floor, &PlacementOptions::default()).expect("fits");
        assert!(
            surface
                .fits
                .contains(&(surface.fits[0].0, ContactKind::FaceFace))
        );
    }
}
