//! Choosing the intermediate resting poses of a regrasp by placing, and the bodies the object
//! touches at each.

use crate::contact::supports;
use crate::planner::Ctx;
use pickplace_geometry::math::{Isometry3, Point3, Real, Vector2};
use pickplace_placement::{Placement, PlacementOptions};
use std::sync::OnceLock;

/// Radius (m) around the object's start within which intermediate resting poses are sought
/// on the surfaces there.
pub const REST_RADIUS: Real = 0.15;

/// How far (m) the third anchor of the rests lies from halfway, towards the robot's base.
const REST_INWARD: Real = 0.10;

/// Spacing (m) of the positions searched for rests.
const REST_POSITION_STEP: Real = 0.02;

impl Ctx<'_> {
    /// The intermediate resting poses (computed once): stable placements (paper §III-B.2,
    /// Algorithm 2 with every resting face) on the surface the object starts on, within
    /// [`REST_RADIUS`] of its start, then within [`REST_RADIUS`] of the point halfway to the
    /// target on that surface (where both arms reach when one hand picks and the other
    /// places), then of that point drawn [`REST_INWARD`] towards the robot's base (where
    /// both reach down when start and target lie far out on either side); the start pose
    /// itself and duplicates left out.
    pub(in crate::planner) fn rests(&self) -> &[Placement] {
        self.regrasp.rests.get_or_init(|| {
            let setup = self.run.setup;
            let start = setup.object_start;
            // Where the object stands: below its centre of mass, at its lowest point.
            let lowest = setup
                .object_mesh
                .vertices()
                .iter()
                .map(|v| (start * v).z)
                .fold(Real::INFINITY, Real::min);
            let cog = start * setup.cog;
            let target = setup.scene.target_point();
            let half = Point3::new(0.5 * (cog.x + target.x), 0.5 * (cog.y + target.y), lowest);
            // Halfway drawn towards the robot's base by REST_INWARD: far out on both sides,
            // the hands reach down to the middle only nearer the robot (the suite's stone
            // from far left to far right is put down 10 cm in from halfway).
            let base = setup.world_from_root.translation.vector;
            let inward = Vector2::new(base.x - half.x, base.y - half.y);
            let step = REST_INWARD.min(inward.norm());
            let inward = inward.try_normalize(1e-12).unwrap_or_else(Vector2::zeros) * step;
            let anchors = [
                Point3::new(cog.x, cog.y, lowest),
                half,
                Point3::new(half.x + inward.x, half.y + inward.y, lowest),
            ];
            // A rest needs a few stable poses per resting face near the anchor, not the
            // exhaustive search of the target's cluster: a small effort bounds its cost on
            // large tables and objects with many faces.
            let options = PlacementOptions {
                search_radius: REST_RADIUS,
                max_per_pair: 4,
                edge_segments: 2,
                edge_positions: 8,
                max_candidates: 48,
                max_distance: REST_RADIUS,
                // A rest need not be at a precise point: a coarse grid of positions and yaws
                // finds its few poses among obstacles in a sixteenth of the tests.
                position_step: REST_POSITION_STEP,
                yaw_steps: 8,
                ..PlacementOptions::default()
            };
            let mut rests: Vec<Placement> = Vec::new();
            for anchor in &anchors {
                let Ok(set) = pickplace_placement::candidates(
                    &setup.placement_object,
                    &setup.placement_env,
                    anchor,
                    &options,
                ) else {
                    continue;
                };
                for p in set.placements {
                    let same = |q: &Isometry3| {
                        (p.world_from_object.translation.vector - q.translation.vector).norm()
                            <= 0.01
                            && p.world_from_object.rotation.angle_to(&q.rotation)
                                <= 5f64.to_radians()
                    };
                    if !same(&start) && !rests.iter().any(|r| same(&r.world_from_object)) {
                        rests.push(p);
                    }
                }
            }
            rests
        })
    }

    /// The bodies the object touches at rest `k`, found once.
    pub(in crate::planner) fn rest_supports(&self, k: usize) -> &[String] {
        let all = self
            .regrasp
            .rest_supports
            .get_or_init(|| self.rests().iter().map(|_| OnceLock::new()).collect());
        match all.get(k) {
            Some(cell) => {
                cell.get_or_init(|| supports(self.run.setup, &self.rests()[k].world_from_object))
            }
            None => &[],
        }
    }
}
