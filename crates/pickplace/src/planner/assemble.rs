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
use crate::timing::{Timed, snap_part_ends, tighten, time_parts, timing_error};
use pickplace_geometry::math::{Isometry3, Real};
use pickplace_placement::{ContactKind, Placement};
use pickplace_prm::toppra::{BlendedPath, ToppraOptions};
use pickplace_robot::collision::CollisionWorld;
use std::sync::Arc;
use std::time::Instant;

/// How far (rad) a straight tool motion's blends may cut its corners (the IK waypoints every
/// [`super::PlanOptions::cartesian_step`]): they turn by little, so the blends are short.
pub(super) const STRAIGHT_BLEND_TOLERANCE: Real = 0.005;

/// How far (m) the tool point of a straight motion may leave the straight line between its
/// ends once timed.
pub(super) const STRAIGHT_DEVIATION: Real = 0.001;

/// The timed plan: its samples, and for each segment the sample where it ends.
struct TimedPlan {
    points: Vec<pickplace_prm::TrajectoryPoint>,
    ends: Vec<usize>,
}

/// The segments' waypoints as one path: each segment's first waypoint dropped where it
/// repeats the one before.
struct Path {
    waypoints: Vec<Vec<Real>>,
    /// For each waypoint from the second on, the segment that moves the robot to it:
    /// `owners[i - 1]` for waypoint `i`, so the piece from waypoint `i` to `i + 1` is
    /// segment `owners[i]`'s.
    owners: Vec<usize>,
    /// For each segment, the waypoint it ends at.
    ends: Vec<usize>,
}

impl Path {
    fn of(segments: &[Segment]) -> Self {
        let mut path = Path {
            waypoints: Vec::new(),
            owners: Vec::new(),
            ends: Vec::with_capacity(segments.len()),
        };
        for (j, seg) in segments.iter().enumerate() {
            for (i, q) in seg.path.iter().enumerate() {
                let repeat = i == 0 && path.waypoints.last().is_some_and(|last| last == q);
                if repeat {
                    continue;
                }
                if !path.waypoints.is_empty() {
                    path.owners.push(j);
                }
                path.waypoints.push(q.clone());
            }
            path.ends.push(path.waypoints.len().saturating_sub(1));
        }
        path
    }

    /// The segment whose piece runs from waypoint `i` to the next one.
    fn owner(&self, i: usize) -> Option<usize> {
        self.owners.get(i).copied()
    }

    /// Each waypoint's blend tolerance: within a straight motion
    /// [`STRAIGHT_BLEND_TOLERANCE`], within a free one `free`; between two motions the free
    /// one's (the straight one's line is checked), or the straight one's when both are
    /// straight; 0 (a stop) at the ends and around every segment with an event (the hand
    /// at rest while the fingers close or open).
    fn tolerances(&self, segments: &[Segment], free: Real) -> Vec<Real> {
        let of = |j: usize| match segments.get(j).map(|s| &s.shape) {
            Some(Shape::Free(_)) => free,
            _ => STRAIGHT_BLEND_TOLERANCE,
        };
        let has_event = |j: usize| segments.get(j).is_some_and(|s| s.event.is_some());
        let n = self.waypoints.len();
        (0..n)
            .map(|i| {
                if i == 0 || i + 1 >= n {
                    return 0.0;
                }
                let (before, after) = (self.owners[i - 1], self.owners[i]);
                if before == after {
                    return of(before);
                }
                // A junction: every segment from `before` to `after` ends here (the ones
                // between moved nothing).
                if (before..=after).any(has_event) {
                    0.0
                } else if (before..=after).any(|j| matches!(segments[j].shape, Shape::Free(_))) {
                    free
                } else {
                    STRAIGHT_BLEND_TOLERANCE
                }
            })
            .collect()
    }

    /// For each segment, the index of the sample where it ends: where its part of the path
    /// ends when the robot stops there, else the sample nearest to the middle of the blend
    /// through its last waypoint.
    fn segment_samples(
        &self,
        segments: &[Segment],
        parts: &[BlendedPath],
        timed: &Timed,
    ) -> Vec<usize> {
        let last = timed.points.len().saturating_sub(1);
        // The sample where each part ends.
        let part_end: Vec<usize> = (0..parts.len())
            .map(|k| timed.at.iter().rposition(|&(p, _)| p == k).unwrap_or(last))
            .collect();
        let mut from = 0;
        segments
            .iter()
            .enumerate()
            .map(|(j, _)| {
                let w = self.ends[j];
                let found = parts.iter().enumerate().find_map(|(k, part)| {
                    if part.ends().1 == w {
                        return Some(part_end[k]);
                    }
                    if part.ends().0 == w {
                        // The path's start, or a stop where the part before ended.
                        return Some(if k == 0 { 0 } else { part_end[k - 1] });
                    }
                    let middle = part.corner_middle(w)?;
                    // On a straight motion's side of the blend, where its line is checked.
                    let straight = |i: Option<usize>| {
                        i.and_then(|j| segments.get(j))
                            .is_some_and(|s| matches!(s.shape, Shape::Straight))
                    };
                    let (before, after) = (
                        straight(self.owner(w.wrapping_sub(1))),
                        straight(self.owner(w)),
                    );
                    let side = |s: Real| match (before, after) {
                        (false, true) => s > middle,
                        (true, false) => s <= middle,
                        _ => true,
                    };
                    timed
                        .at
                        .iter()
                        .enumerate()
                        .filter(|(_, (p, s))| *p == k && side(*s))
                        .min_by(|(_, a), (_, b)| {
                            (a.1 - middle).abs().total_cmp(&(b.1 - middle).abs())
                        })
                        .map(|(i, _)| i)
                });
                // A corner the path goes straight through (no arc) or a waypoint dropped as
                // a repeat: the nearest sample from the last end on.
                let i = found.unwrap_or_else(|| {
                    let q = &self.waypoints[w.min(self.waypoints.len() - 1)];
                    (from..=last)
                        .min_by(|&a, &b| {
                            let d = |i: usize| {
                                timed.points[i]
                                    .positions
                                    .iter()
                                    .zip(q)
                                    .map(|(x, y)| (x - y) * (x - y))
                                    .sum::<Real>()
                            };
                            d(a).total_cmp(&d(b))
                        })
                        .unwrap_or(last)
                });
                from = from.max(i);
                i
            })
            .collect()
    }
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

/// One motion of the plan: full configurations. The robot is at rest at its ends only next
/// to a segment with an event; elsewhere the segments are blended into each other.
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
        let model = &self.run.setup.model;
        let n = model.variable_count();
        let limits = self.timing_limits();
        let mut trajectory: Vec<TrajectoryPoint> = vec![TrajectoryPoint {
            time_from_start: 0.0,
            positions: self.run.setup.start.clone(),
            velocities: vec![0.0; n],
            accelerations: vec![0.0; n],
        }];
        let mut events = Vec::new();
        let mut key_poses = Vec::new();
        let mut object_pose = self.run.setup.object_start;
        // The hands holding the object, in the order they took it: it moves with the first.
        let mut holders: Vec<(Arm, Isometry3)> = Vec::new();
        let placed = self.run.placements[found.placement].world_from_object;
        let path = Path::of(&found.segments);
        let timed = self.time_path(&found.segments, &path, &limits)?;
        // Each sample once, times rounded; a sample within half a microsecond of the one
        // before replaces it. `index[i]`: where timed sample `i` went.
        let mut index = Vec::with_capacity(timed.points.len());
        for p in timed.points {
            let point = TrajectoryPoint {
                time_from_start: round_time(p.time_from_start),
                positions: p.positions,
                velocities: p.velocities,
                accelerations: p.accelerations,
            };
            match trajectory.last_mut() {
                Some(last) if last.time_from_start >= point.time_from_start => *last = point,
                _ => trajectory.push(point),
            }
            index.push(trajectory.len() - 1);
        }
        for (j, seg) in found.segments.iter().enumerate() {
            // The sample where the segment ends: a stop, or the middle of its blend.
            let at = timed
                .ends
                .get(j)
                .and_then(|&i| index.get(i).copied())
                .unwrap_or(trajectory.len() - 1);
            // The key pose as planned (the robot passes within the blend's tolerance of it
            // when it does not stop there), at the time it passes.
            let q_end = path
                .ends
                .get(j)
                .and_then(|&w| path.waypoints.get(w))
                .unwrap_or(&trajectory[at].positions)
                .clone();
            let time = trajectory[at].time_from_start;
            if let Some((kind, arm, link_from_object)) = seg.event {
                let a = self.run.setup.arm(arm);
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
                let g = &self.run.grasps[gi];
                GraspInfo {
                    arm,
                    object_from_tcp: PoseSpec::from_isometry(&g.object_from_tcp),
                    width: g.width,
                    score: g.score,
                    rank: gi,
                }
            })
            .collect();
        let placement = self.placement_info(&self.run.placements[found.placement], found.placement);
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
        self.budget
            .timings
            .insert("trajectory".to_owned(), t.elapsed().as_secs_f64());
        stats.trajectory_points = trajectory.len();
        stats.duration = trajectory.last().map_or(0.0, |p| p.time_from_start);
        self.finish_stats(&mut stats, t_all);
        Ok(Plan {
            format: PLAN_FORMAT.to_owned(),
            seed: self.run.options.seed,
            strategy,
            joint_names: model.variable_names().map(str::to_owned).collect(),
            base: Some(crate::tool_frame::BaseFrame::of_model(
                model,
                &self.run.setup.world_from_root,
            )),
            arms: self
                .run
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
                        tool: crate::tool_frame::ToolFrame::of_link(model, a.tcp_link),
                    }
                })
                .collect(),
            limits: Some(Limits {
                velocities: limits.max_velocities.clone(),
                accelerations: limits.max_accelerations.clone(),
                velocity_scaling: self.run.options.velocity_scaling,
                acceleration_scaling: self.run.options.acceleration_scaling,
            }),
            trajectory,
            events,
            object: ObjectMotion {
                start_pose: PoseSpec::from_isometry(&self.run.setup.object_start),
                placed_pose: PoseSpec::from_isometry(&placed),
            },
            placement,
            rests,
            grasps,
            key_poses,
            stats,
            warnings: self
                .run
                .setup
                .robot_warnings
                .iter()
                .cloned()
                .chain(self.run.setup.mesh_warnings.iter().map(ToString::to_string))
                .collect(),
        })
    }

    /// The joints' limits the trajectory keeps: the setup's ([`Setup::timing`]: URDF
    /// velocities, joint-limits tables, the scene's default acceleration), scaled by the
    /// options' factors.
    ///
    /// [`Setup::timing`]: crate::Setup::timing
    fn timing_limits(&self) -> ToppraOptions {
        let (vs, acs) = (
            self.run.options.velocity_scaling,
            self.run.options.acceleration_scaling,
        );
        ToppraOptions {
            max_velocities: self
                .run
                .setup
                .timing
                .iter()
                .map(|l| l.velocity * vs)
                .collect(),
            max_accelerations: self
                .run
                .setup
                .timing
                .iter()
                .map(|l| l.acceleration * acs)
                .collect(),
            sample_period: self.run.options.sample_period,
            ..ToppraOptions::default()
        }
    }

    /// The whole plan's time-optimal trajectory (TOPP-RA on the blended path of all its
    /// segments, see [`pickplace_prm::toppra`]), from rest at the start to rest at the end,
    /// with the robot at rest only where the task needs it: before and after the fingers
    /// close or open (a segment with an event), where the path turns back on itself, and
    /// where a blend was refused. Each corner's blend is checked ([`Ctx::blend_failures`]);
    /// a corner whose blend collides (free motions) or takes a tool point off its line
    /// (straight motions) is tightened (its tolerance divided by 4), and after
    /// [`BLEND_ATTEMPTS`](crate::timing::BLEND_ATTEMPTS) the robot stops there, on the path exactly as it was checked.
    ///
    /// # Errors
    /// [`crate::Error::TrajectoryLimit`] when the trajectory would be too long to sample;
    /// [`crate::Error::Internal`] when the timing refuses the path or the limits.
    fn time_path(
        &self,
        segments: &[Segment],
        path: &Path,
        limits: &ToppraOptions,
    ) -> Result<TimedPlan> {
        let mut tolerances = path.tolerances(segments, self.run.options.blend_tolerance);
        let mut tightened = vec![0usize; tolerances.len()];
        loop {
            let parts =
                BlendedPath::split_with(&path.waypoints, &tolerances).map_err(timing_error)?;
            let mut timed = time_parts(
                &parts,
                limits,
                path.waypoints.first(),
                self.run.setup.model.variable_count(),
            )?;
            let failed = self.blend_failures(segments, path, &parts, &timed)?;
            if failed.is_empty() {
                snap_part_ends(&mut timed, &parts, &path.waypoints);
                let ends = path.segment_samples(segments, &parts, &timed);
                return Ok(TimedPlan {
                    points: timed.points,
                    ends,
                });
            }
            tighten(&mut tolerances, &mut tightened, failed);
        }
    }

    /// The corners whose blends do not hold. For a pair of consecutive samples that are not
    /// on one straight piece of the path, every state between them (as densely as `validate`
    /// checks: 1° of joint motion, 1 cm of tool motion) must be free of collisions, with the
    /// hands apart, in the world of each free motion the pair touches; the corners whose
    /// arcs the pair crosses fail otherwise. On a straight motion (the blend's half on its
    /// side included) every sample's tool points stay within [`STRAIGHT_DEVIATION`] of the
    /// lines between the motion's ends; a sample on an arc that leaves them fails its
    /// corner. (Samples on the waypoints' own lines follow the path as it was checked.)
    fn blend_failures(
        &self,
        segments: &[Segment],
        path: &Path,
        parts: &[BlendedPath],
        timed: &Timed,
    ) -> Result<std::collections::BTreeSet<usize>> {
        use pickplace_prm::toppra::Location;
        let mut failed = std::collections::BTreeSet::new();
        for (i, w) in timed.points.windows(2).enumerate() {
            let ((k0, s0), (k1, s1)) = (timed.at[i], timed.at[i + 1]);
            let Some(part) = parts.get(k1) else {
                continue;
            };
            // A part ends where the next one starts: from there, the pair is on the next.
            let s0 = if k0 == k1 { s0 } else { 0.0 };
            let corners = part.corners_between(s0, s1);
            if corners.is_empty() {
                continue;
            }
            let mut worlds: Vec<&Arc<CollisionWorld>> = Vec::new();
            for &c in &corners {
                for owner in [path.owner(c.wrapping_sub(1)), path.owner(c)] {
                    if let Some(Shape::Free(world)) =
                        owner.and_then(|j| segments.get(j)).map(|s| &s.shape)
                        && !worlds.iter().any(|w| Arc::ptr_eq(w, world))
                    {
                        worlds.push(world);
                    }
                }
            }
            for world in worlds {
                if !self.states_free(world, &w[0].positions, &w[1].positions)? {
                    failed.extend(corners.iter().copied());
                    break;
                }
            }
        }
        for (p, &(k, s)) in timed.points.iter().zip(&timed.at) {
            let Some(part) = parts.get(k) else {
                continue;
            };
            let Location::Arc {
                corner,
                past_middle,
            } = part.locate(s)
            else {
                continue;
            };
            if failed.contains(&corner) {
                continue;
            }
            let owner = path.owner(if past_middle {
                corner
            } else {
                corner.wrapping_sub(1)
            });
            let Some(seg) = owner.and_then(|j| segments.get(j)) else {
                continue;
            };
            if matches!(seg.shape, Shape::Straight) && !self.on_line(seg, &p.positions) {
                failed.insert(corner);
            }
        }
        Ok(failed)
    }

    /// Whether every tool point at `q` is within [`STRAIGHT_DEVIATION`] of the straight
    /// line between its positions at the segment's two ends.
    fn on_line(&self, seg: &Segment, q: &[Real]) -> bool {
        let (Some(first), Some(last)) = (seg.path.first(), seg.path.last()) else {
            return true;
        };
        self.run.setup.arms.iter().all(|a| {
            let p0 = self.tcp(a.arm, first).translation.vector;
            let p1 = self.tcp(a.arm, last).translation.vector;
            let line = p1 - p0;
            let len2 = line.norm_squared();
            let x = self.tcp(a.arm, q).translation.vector - p0;
            let f = if len2 > 0.0 {
                (x.dot(&line) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (x - line * f).norm() <= STRAIGHT_DEVIATION
        })
    }

    /// Whether the states from `a` (excluded) to `b` (included), as densely as `validate`
    /// checks them, are free of collisions in `world` with the hands apart.
    fn states_free(&self, world: &CollisionWorld, a: &[Real], b: &[Real]) -> Result<bool> {
        use crate::rules::{MAX_CARTESIAN_STEP, MAX_JOINT_STEP};
        let dq = a
            .iter()
            .zip(b)
            .map(|(x, y)| (y - x).abs())
            .fold(0.0, Real::max);
        let tool = self
            .run
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
            .run
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
                .run
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
        let setup = ctx.run.setup;
        let start = setup.start.clone();
        let arm = Arm::Right;
        let raised = {
            let mut q = start.clone();
            let v = setup.arm(arm).variables[0];
            q[v] += 0.2;
            q
        };
        let g = ctx.run.grasps[0].object_from_tcp.inverse();
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
