//! The plan from its motions (paper Fig. 8, last step): each segment of full configurations
//! time-parameterised under the joints' limits and appended, the grasp and release events
//! placed at the samples where the fingers close and open, the key poses recorded with the
//! object where it is at that instant.

use super::Ctx;
use crate::error::Result;
use crate::plan::{
    ArmJoints, Event, EventKind, GraspInfo, KeyPose, Limits, ObjectMotion, PLAN_FORMAT,
    PlacementInfo, Plan, RestInfo, Stats, TrajectoryPoint,
};
use crate::scene::PoseSpec;
use crate::strategy::{Arm, Strategy};
use pickplace_geometry::math::{Isometry3, Real};
use pickplace_placement::{ContactKind, Placement};
use pickplace_prm::toppra::{self, BlendedPath, ToppraOptions};
use pickplace_robot::collision::CollisionWorld;
use std::sync::Arc;
use std::time::Instant;

/// How far (rad) a straight tool motion's blends may cut its corners (the IK waypoints every
/// [`super::PlanOptions::cartesian_step`]): they turn by little, so the blends are short.
pub(super) const STRAIGHT_BLEND_TOLERANCE: Real = 0.005;

/// How far (m) the tool point of a straight motion may leave the straight line between its
/// ends once timed.
pub(super) const STRAIGHT_DEVIATION: Real = 0.001;

/// Times a blend is tightened (the tolerance divided by 4) when what it changed collides or
/// leaves the line, before the segment is timed without blends (a stop at every waypoint).
const BLEND_ATTEMPTS: usize = 3;

/// Fewest grid stages of a timed part of a path.
const MIN_STAGES: Real = 32.0;

/// A segment's samples (times from its start) and, for each, the part of the path and the
/// arc length it is at.
struct Timed {
    points: Vec<pickplace_prm::TrajectoryPoint>,
    at: Vec<(usize, Real)>,
}

/// How a segment may be smoothed before it is timed.
#[derive(Debug, Clone)]
pub(super) enum Shape {
    /// A straight tool motion (approach, lift, lowering, retreat) or the fingers moving: its
    /// corners are blended only within [`STRAIGHT_BLEND_TOLERANCE`] and its tool point stays
    /// within [`STRAIGHT_DEVIATION`] of the straight line.
    Straight,
    /// A motion through free space (the PRM's): its corners are blended within the plan's
    /// tolerance, and what the blends change is checked again in this world.
    Free(Arc<CollisionWorld>),
}

/// One motion of the plan: full configurations, from rest to rest.
#[derive(Debug, Clone)]
pub(super) struct Segment {
    /// Waypoints (full configurations).
    pub path: Vec<Vec<Real>>,
    /// Key pose reached at the end, if any.
    pub key: Option<(&'static str, Arm)>,
    /// Event at the end of the segment: grasp or release by an arm, `link_from_object`.
    pub event: Option<(EventKind, Arm, Isometry3)>,
    /// How it may be smoothed.
    pub shape: Shape,
}

impl Segment {
    /// A straight motion that ends at the key pose `name` of `arm`.
    pub fn reach(name: &'static str, arm: Arm, path: Vec<Vec<Real>>) -> Self {
        Self {
            path,
            key: Some((name, arm)),
            event: None,
            shape: Shape::Straight,
        }
    }

    /// A motion through free space, checked in `world`, that ends at the key pose `name`.
    pub fn free(
        name: &'static str,
        arm: Arm,
        path: Vec<Vec<Real>>,
        world: &Arc<CollisionWorld>,
    ) -> Self {
        Self {
            path,
            key: Some((name, arm)),
            event: None,
            shape: Shape::Free(Arc::clone(world)),
        }
    }

    /// A motion with no key pose or event at its end (opening the hands at the start).
    pub fn plain(path: Vec<Vec<Real>>) -> Self {
        Self {
            path,
            key: None,
            event: None,
            shape: Shape::Straight,
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
            shape: Shape::Straight,
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

/// The timing's refusal as the façade's error: a trajectory too long to sample is the
/// input's fault ([`crate::Error::TrajectoryLimit`]); anything else is a defect.
fn timing_error(e: pickplace_prm::Error) -> crate::Error {
    match e {
        pickplace_prm::Error::TooManySamples { .. }
        | pickplace_prm::Error::TooManyPoints { .. } => crate::Error::TrajectoryLimit {
            reason: e.to_string(),
        },
        other => crate::error::internal("timing")(other),
    }
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
        let limits = self.timing_limits();
        let mut trajectory: Vec<TrajectoryPoint> = vec![TrajectoryPoint {
            time_from_start: 0.0,
            positions: self.setup.start.clone(),
            velocities: vec![0.0; n],
            accelerations: vec![0.0; n],
        }];
        let mut events = Vec::new();
        let mut key_poses = Vec::new();
        let mut object_pose = self.setup.object_start;
        // The hands holding the object, in the order they took it: it moves with the first.
        let mut holders: Vec<(Arm, Isometry3)> = Vec::new();
        let placed = self.placements[found.placement].world_from_object;
        for seg in &found.segments {
            let offset = trajectory.last().map_or(0.0, |p| p.time_from_start);
            for p in self.time_segment(seg, &limits)?.into_iter().skip(1) {
                let point = TrajectoryPoint {
                    time_from_start: round_time(offset + p.time_from_start),
                    positions: p.positions,
                    velocities: p.velocities,
                    accelerations: p.accelerations,
                };
                // A last sample within half a microsecond of the one before replaces it.
                match trajectory.last_mut() {
                    Some(last) if last.time_from_start >= point.time_from_start => *last = point,
                    _ => trajectory.push(point),
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
            arms: self
                .setup
                .arms
                .iter()
                .map(|a| {
                    let names = |vars: &[usize]| -> Vec<String> {
                        vars.iter()
                            .filter_map(|&v| model.variable_names().nth(v).map(str::to_owned))
                            .collect()
                    };
                    ArmJoints {
                        arm: a.arm,
                        group: a.group.clone(),
                        joints: names(&a.variables),
                        gripper_joints: names(&a.finger_variables),
                    }
                })
                .collect(),
            limits: Some(Limits {
                velocities: limits.max_velocities.clone(),
                accelerations: limits.max_accelerations.clone(),
                velocity_scaling: self.options.velocity_scaling,
                acceleration_scaling: self.options.acceleration_scaling,
            }),
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

    /// The joints' limits the trajectory keeps: the setup's ([`Setup::timing`]: URDF
    /// velocities, joint-limits tables, the scene's default acceleration), scaled by the
    /// options' factors.
    ///
    /// [`Setup::timing`]: crate::Setup::timing
    fn timing_limits(&self) -> ToppraOptions {
        let (vs, acs) = (
            self.options.velocity_scaling,
            self.options.acceleration_scaling,
        );
        ToppraOptions {
            max_velocities: self.setup.timing.iter().map(|l| l.velocity * vs).collect(),
            max_accelerations: self
                .setup
                .timing
                .iter()
                .map(|l| l.acceleration * acs)
                .collect(),
            sample_period: self.options.sample_period,
            ..ToppraOptions::default()
        }
    }

    /// The segment's time-optimal trajectory (TOPP-RA on its blended path, see
    /// [`pickplace_prm::toppra`]), from rest at its first waypoint to rest at its last, times
    /// from 0. A blend that collides (free motions) or takes the tool point off its line
    /// (straight motions) is tightened; after [`BLEND_ATTEMPTS`] the robot stops at every
    /// waypoint, on the path exactly as it was checked.
    ///
    /// # Errors
    /// [`crate::Error::TrajectoryLimit`] when the trajectory would be too long to sample;
    /// [`crate::Error::Internal`] when the timing refuses the path or the limits.
    fn time_segment(
        &self,
        seg: &Segment,
        limits: &ToppraOptions,
    ) -> Result<Vec<pickplace_prm::TrajectoryPoint>> {
        let mut tolerance = match seg.shape {
            Shape::Straight => STRAIGHT_BLEND_TOLERANCE,
            Shape::Free(_) => self.options.blend_tolerance,
        };
        for attempt in 0..=BLEND_ATTEMPTS {
            let exact = attempt == BLEND_ATTEMPTS || tolerance.is_nan() || tolerance <= 0.0;
            let parts = if exact {
                // Each straight piece alone: the robot stops at every waypoint.
                let mut parts = Vec::new();
                for w in seg.path.windows(2) {
                    parts.extend(BlendedPath::split(w, 1.0).map_err(timing_error)?);
                }
                parts
            } else {
                BlendedPath::split(&seg.path, tolerance).map_err(timing_error)?
            };
            let mut timed = self.time_parts(&parts, limits, seg.path.first())?;
            if exact || self.blends_hold(seg, &parts, &timed)? {
                // The motion ends at rest exactly at its last waypoint (a grasp, a key pose),
                // not where the arc length's rounding puts it.
                if let (Some(p), Some(q)) = (timed.points.last_mut(), seg.path.last()) {
                    p.positions.clone_from(q);
                    p.velocities.iter_mut().for_each(|v| *v = 0.0);
                }
                return Ok(timed.points);
            }
            tolerance /= 4.0;
        }
        // The last attempt is exact and always returns.
        Err(crate::Error::Internal {
            stage: "timing",
            reason: "no attempt returned".into(),
        })
    }

    /// The parts timed one after the other, the robot at rest between them.
    fn time_parts(
        &self,
        parts: &[BlendedPath],
        limits: &ToppraOptions,
        first: Option<&Vec<Real>>,
    ) -> Result<Timed> {
        let n = self.setup.model.variable_count();
        let mut timed = Timed {
            points: Vec::new(),
            at: Vec::new(),
        };
        if let Some(q) = first {
            timed.points.push(pickplace_prm::TrajectoryPoint {
                time_from_start: 0.0,
                positions: q.clone(),
                velocities: vec![0.0; n],
                accelerations: vec![0.0; n],
            });
            timed.at.push((0, 0.0));
        }
        let mut offset = 0.0;
        for (k, part) in parts.iter().enumerate() {
            // At least MIN_STAGES stages on every part, however short (a gripper closing
            // by millimetres): TOPP-RA's speed lives between the grid points.
            let options = ToppraOptions {
                grid_step: limits.grid_step.min(part.length() / MIN_STAGES),
                ..limits.clone()
            };
            let timing = toppra::parameterize(part, &options).map_err(timing_error)?;
            let mut samples =
                toppra::sample(part, &timing, limits.sample_period).map_err(timing_error)?;
            // A last sample within a millisecond of the one before it is merged into it: the
            // times are rounded to the microsecond, which such a step would not survive.
            let m = samples.points.len();
            if m >= 3
                && samples.points[m - 1].time_from_start - samples.points[m - 2].time_from_start
                    < 1e-3
            {
                samples.points.remove(m - 2);
            }
            // Each part's first sample is where the one before ended, at rest.
            for p in samples.points.into_iter().skip(1) {
                timed.at.push((k, timing.state(p.time_from_start).0));
                timed.points.push(pickplace_prm::TrajectoryPoint {
                    time_from_start: offset + p.time_from_start,
                    ..p
                });
            }
            offset += timing.duration();
        }
        Ok(timed)
    }

    /// Whether what the blends changed still holds: for a free motion, every state between
    /// two samples that are not on one straight piece of the path (checked as densely as
    /// `validate` checks: 1° of joint motion, 1 cm of tool motion) is free of collisions and
    /// keeps the hands apart; for a straight motion, every sample's tool point is within
    /// [`STRAIGHT_DEVIATION`] of the line between the motion's ends.
    fn blends_hold(&self, seg: &Segment, parts: &[BlendedPath], timed: &Timed) -> Result<bool> {
        match &seg.shape {
            Shape::Straight => {
                let (Some(first), Some(last)) = (seg.path.first(), seg.path.last()) else {
                    return Ok(true);
                };
                for a in &self.setup.arms {
                    let p0 = self.tcp(a.arm, first).translation.vector;
                    let p1 = self.tcp(a.arm, last).translation.vector;
                    let line = p1 - p0;
                    let len2 = line.norm_squared();
                    for p in &timed.points {
                        let x = self.tcp(a.arm, &p.positions).translation.vector - p0;
                        let f = if len2 > 0.0 {
                            (x.dot(&line) / len2).clamp(0.0, 1.0)
                        } else {
                            0.0
                        };
                        if (x - line * f).norm() > STRAIGHT_DEVIATION {
                            return Ok(false);
                        }
                    }
                }
                Ok(true)
            }
            Shape::Free(world) => {
                for (i, w) in timed.points.windows(2).enumerate() {
                    let ((k0, s0), (k1, s1)) = (timed.at[i], timed.at[i + 1]);
                    if k0 == k1
                        && let Some(part) = parts.get(k0)
                        && let (Some(l0), Some(l1)) = (part.line_at(s0), part.line_at(s1))
                        && l0 == l1
                    {
                        continue;
                    }
                    if !self.states_free(world, &w[0].positions, &w[1].positions)? {
                        return Ok(false);
                    }
                }
                Ok(true)
            }
        }
    }

    /// Whether the states from `a` (excluded) to `b` (included), as densely as `validate`
    /// checks them, are free of collisions in `world` with the hands apart.
    fn states_free(&self, world: &CollisionWorld, a: &[Real], b: &[Real]) -> Result<bool> {
        use crate::validate::{MAX_CARTESIAN_STEP, MAX_JOINT_STEP};
        let dq = a
            .iter()
            .zip(b)
            .map(|(x, y)| (y - x).abs())
            .fold(0.0, Real::max);
        let tool = self
            .setup
            .arms
            .iter()
            .map(|arm| {
                (self.tcp(arm.arm, b).translation.vector - self.tcp(arm.arm, a).translation.vector)
                    .norm()
            })
            .fold(0.0, Real::max);
        let steps = (dq / MAX_JOINT_STEP)
            .max(tool / MAX_CARTESIAN_STEP)
            .ceil()
            .clamp(1.0, 1e6) as usize;
        let mut q = a.to_vec();
        for i in 1..=steps {
            let f = i as Real / steps as Real;
            for (k, x) in q.iter_mut().enumerate() {
                *x = a[k] + f * (b[k] - a[k]);
            }
            if self.collision(world, &q, 0.0)?.is_some() || self.hands_too_close(&q)? {
                return Ok(false);
            }
        }
        Ok(true)
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
