//! The plan from its motions (paper Fig. 8, last step): each segment of full configurations
//! time-parameterised under the joints' limits and appended, the grasp and release events
//! placed at the samples where the fingers close and open, the key poses recorded with the
//! object where it is at that instant.

use super::Ctx;
use crate::error::Result;
use crate::plan::{
    Event, EventKind, GraspInfo, KeyPose, ObjectMotion, PLAN_FORMAT, PlacementInfo, Plan, RestInfo,
    Stats, TrajectoryPoint,
};
use crate::scene::PoseSpec;
use crate::strategy::{Arm, Strategy};
use pickplace_geometry::math::{Isometry3, Real};
use pickplace_placement::{ContactKind, Placement};
use pickplace_prm::{Path as PrmPath, TimingOptions, time_parameterize};
use std::time::Instant;

/// One motion of the plan: full configurations, from rest to rest.
#[derive(Debug, Clone)]
pub(super) struct Segment {
    /// Waypoints (full configurations).
    pub path: Vec<Vec<Real>>,
    /// Key pose reached at the end, if any.
    pub key: Option<(&'static str, Arm)>,
    /// Event at the end of the segment: grasp or release by an arm, `link_from_object`.
    pub event: Option<(EventKind, Arm, Isometry3)>,
}

impl Segment {
    /// A motion that ends at the key pose `name` of `arm`.
    pub fn reach(name: &'static str, arm: Arm, path: Vec<Vec<Real>>) -> Self {
        Self {
            path,
            key: Some((name, arm)),
            event: None,
        }
    }

    /// A motion with no key pose or event at its end (opening the hands at the start).
    pub fn plain(path: Vec<Vec<Real>>) -> Self {
        Self {
            path,
            key: None,
            event: None,
        }
    }

    /// The fingers closing or opening: `event` at the end, perhaps a key pose.
    pub fn event(
        path: Vec<Vec<Real>>,
        key: Option<(&'static str, Arm)>,
        event: (EventKind, Arm, Isometry3),
    ) -> Self {
        Self {
            path,
            key,
            event: Some(event),
        }
    }
}

/// A found motion: its segments, the grasps used (arm, grasp index), the placement index
/// and the intermediate resting poses of a regrasp by placing (indices into [`Ctx::rests`]).
#[derive(Debug)]
pub(super) struct Found {
    pub segments: Vec<Segment>,
    pub grasps: Vec<(Arm, usize)>,
    pub placement: usize,
    pub rests: Vec<usize>,
}

/// Times are rounded to the microsecond so that the JSON is short and stable.
fn round_time(t: Real) -> Real {
    (t * 1e6).round() / 1e6
}

impl Ctx<'_> {
    /// Times the segments and writes the plan.
    pub(super) fn assemble(
        &mut self,
        strategy: Strategy,
        found: Found,
        mut stats: Stats,
        t_all: Instant,
    ) -> Result<Plan> {
        let t = Instant::now();
        let model = &self.setup.model;
        let n = model.variable_count();
        let velocities: Vec<Real> = model
            .variable_limits()
            .map(|l| if l.velocity > 0.0 { l.velocity } else { 1.0 })
            .collect();
        let timing = TimingOptions {
            max_velocities: velocities,
            max_accelerations: vec![self.options.max_acceleration; n],
            sample_period: self.options.sample_period,
        };
        let mut trajectory: Vec<TrajectoryPoint> = vec![TrajectoryPoint {
            time_from_start: 0.0,
            positions: self.setup.start.clone(),
        }];
        let mut events = Vec::new();
        let mut key_poses = Vec::new();
        let mut object_pose = self.setup.object_start;
        // The hands holding the object, in the order they took it: it moves with the first.
        let mut holders: Vec<(Arm, Isometry3)> = Vec::new();
        let placed = self.placements[found.placement].world_from_object;
        for seg in &found.segments {
            let path = PrmPath::from_waypoints(n, seg.path.iter().map(|q| q.as_slice()))
                .map_err(crate::error::internal("trajectory"))?;
            let offset = trajectory.last().map_or(0.0, |p| p.time_from_start);
            if path.len() >= 2 {
                let timed = time_parameterize(&path, &timing).map_err(|e| match e {
                    pickplace_prm::Error::TooManySamples { .. } => crate::Error::TrajectoryLimit {
                        reason: e.to_string(),
                    },
                    other => crate::error::internal("timing")(other),
                })?;
                for p in timed.points.iter().skip(1) {
                    trajectory.push(TrajectoryPoint {
                        time_from_start: round_time(offset + p.time_from_start),
                        positions: p.positions.clone(),
                    });
                }
            }
            // The trajectory starts with the start state and only grows.
            let end = &trajectory[trajectory.len() - 1];
            let q_end = end.positions.clone();
            let time = end.time_from_start;
            if let Some((kind, arm, link_from_object)) = seg.event {
                let a = self.setup.arm(arm);
                events.push(Event {
                    time,
                    kind,
                    arm,
                    link: a.tcp_name.clone(),
                    link_from_object: PoseSpec::from_isometry(&link_from_object),
                });
                match kind {
                    EventKind::Grasp => {
                        holders.retain(|(h, _)| *h != arm);
                        holders.push((arm, link_from_object));
                    }
                    EventKind::Release => holders.retain(|(h, _)| *h != arm),
                }
            }
            if let Some(&(arm, link_from_object)) = holders.first() {
                object_pose = self.tcp(arm, &q_end) * link_from_object;
            }
            if let Some((name, arm)) = seg.key {
                key_poses.push(KeyPose {
                    name: name.to_owned(),
                    arm,
                    time,
                    world_from_tcp: PoseSpec::from_isometry(&self.tcp(arm, &q_end)),
                    world_from_object: PoseSpec::from_isometry(&object_pose),
                });
            }
        }
        let grasps = found
            .grasps
            .iter()
            .map(|&(arm, gi)| {
                let g = &self.grasps[gi];
                GraspInfo {
                    arm,
                    object_from_tcp: PoseSpec::from_isometry(&g.object_from_tcp),
                    width: g.width,
                    score: g.score,
                    rank: gi,
                }
            })
            .collect();
        let placement = self.placement_info(&self.placements[found.placement], found.placement);
        let rests = found
            .rests
            .iter()
            .map(|&k| {
                let r = &self.rests()[k];
                RestInfo {
                    world_from_object: PoseSpec::from_isometry(&r.world_from_object),
                    placement: self.placement_info(r, k),
                }
            })
            .collect();
        self.timings
            .insert("trajectory".to_owned(), t.elapsed().as_secs_f64());
        stats.trajectory_points = trajectory.len();
        stats.duration = trajectory.last().map_or(0.0, |p| p.time_from_start);
        self.finish_stats(&mut stats, t_all);
        Ok(Plan {
            format: PLAN_FORMAT.to_owned(),
            seed: self.options.seed,
            strategy,
            joint_names: model.variable_names().map(str::to_owned).collect(),
            trajectory,
            events,
            object: ObjectMotion {
                start_pose: PoseSpec::from_isometry(&self.setup.object_start),
                placed_pose: PoseSpec::from_isometry(&placed),
            },
            placement,
            rests,
            grasps,
            key_poses,
            stats,
        })
    }

    /// What the plan says of placement `p`, the `rank`-th of its list.
    fn placement_info(&self, p: &Placement, rank: usize) -> PlacementInfo {
        let (env_index, env_cluster) = self
            .setup
            .environment_of_cluster(p.env_cluster)
            .unwrap_or((0, p.env_cluster));
        PlacementInfo {
            contact: match p.contact {
                ContactKind::FaceFace => "face-face",
                ContactKind::EdgeFace => "edge-face",
            }
            .to_owned(),
            object_cluster: p.object_cluster,
            environment: self
                .setup
                .environment
                .get(env_index)
                .map(|e| e.name.clone())
                .unwrap_or_default(),
            env_cluster,
            stability_margin: p.stability_margin,
            rank,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::ctx;
    use super::*;

    #[test]
    fn times_round_to_the_microsecond() {
        assert_eq!(round_time(1.234_567_89), 1.234_568);
        assert_eq!(round_time(0.0), 0.0);
    }

    #[test]
    fn segments_are_timed_back_to_back_with_events_at_their_ends() {
        let mut ctx = ctx("fig9-near.toml");
        let setup = ctx.setup;
        let start = setup.start.clone();
        let arm = Arm::Right;
        let raised = {
            let mut q = start.clone();
            let v = setup.arm(arm).variables[0];
            q[v] += 0.2;
            q
        };
        let g = ctx.grasps[0].object_from_tcp.inverse();
        let found = Found {
            segments: vec![
                Segment::reach("pre-grasp", arm, vec![start.clone(), raised.clone()]),
                Segment::event(vec![raised.clone()], None, (EventKind::Grasp, arm, g)),
                Segment::reach("lift", arm, vec![raised.clone(), start.clone()]),
                Segment::event(
                    vec![start.clone()],
                    Some(("release", arm)),
                    (EventKind::Release, arm, g),
                ),
            ],
            grasps: vec![(arm, 0)],
            placement: 0,
            rests: Vec::new(),
        };
        let plan = ctx
            .assemble(
                Strategy::RightRight,
                found,
                Stats::default(),
                Instant::now(),
            )
            .expect("assembles");
        let times: Vec<Real> = plan.trajectory.iter().map(|p| p.time_from_start).collect();
        assert!(times.windows(2).all(|w| w[0] < w[1]), "{times:?}");
        assert_eq!(plan.trajectory[0].positions, start);
        assert_eq!(plan.trajectory.last().unwrap().positions, start);
        let names: Vec<&str> = plan.key_poses.iter().map(|k| k.name.as_str()).collect();
        assert_eq!(names, ["pre-grasp", "lift", "release"]);
        // The grasp happens where the first motion ends; the release at the very end.
        assert_eq!(plan.events.len(), 2);
        assert_eq!(plan.events[0].time, plan.key_poses[0].time);
        assert_eq!(plan.events[1].time, *times.last().unwrap());
        assert_eq!(plan.stats.trajectory_points, plan.trajectory.len());
        // While held, the object moves with the hand: at "lift" it is where the hand holds it.
        let tcp = ctx.tcp(arm, &start);
        let object = plan.key_poses[1].world_from_object.to_isometry().unwrap();
        assert!(((tcp * g).translation.vector - object.translation.vector).norm() < 1e-9);
    }
}
