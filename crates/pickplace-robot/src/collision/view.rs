//! One arm's view of a collision world: the rest of the robot fixed at a configuration, so
//! that what cannot move is computed once (the static links' poses and boxes, the static
//! pairs' contacts) and each query computes and checks only what moves.
//!
//! A pair of bodies *moves* when the arm's joints change the pose of one body relative to
//! the other: a link moved by the arm against the environment, the idle arm or the torso;
//! two links of the arm with an arm joint between them. Two links below the same arm joint
//! with none of the arm's joints between them (the palm and a finger of the moving hand)
//! keep their relative pose: like two links of the idle arm, they are a static pair,
//! checked once at the rest configuration. Attached objects follow the
//! [`PairScope`] mask rule (an object held by a moving link moves against every body but
//! the ones it may touch).

use super::narrow::{BoxFrame, boxes_overlap};
use super::{BodyId, CheckOptions, CollisionScratch, CollisionWorld, PairScope};
use crate::error::{Error, Result};
use crate::model::{JointValueSource, RobotModel};
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Pose;
use pickplace_geometry::math::{Isometry3, Real};
use pickplace_geometry::parry;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

/// What a query on a [`MovingView`] does with a pair of two static bodies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StaticPairs {
    /// Such pairs count when they touch (margin 0): the answer of
    /// [`PairScope::MarginOnMoving`]. They are checked once, when the view is made (default).
    #[default]
    Contact,
    /// Such pairs are not checked: the answer of [`PairScope::MovingOnly`].
    Skip,
}

/// The world seen by queries in which only some links move (an arm, its hand and whatever
/// it holds) and every other joint keeps the value it has in `rest`.
///
/// Made once by [`CollisionWorld::moving_view`] and queried by
/// [`CollisionWorld::first_collision_in_view`] with the world that made it (a view of
/// another world, or of this world after a change, is refused).
///
/// # Performance
/// A query runs forward kinematics only for the joints below the moving links, transforms
/// only the moving shapes, and tests only the self pairs with a moving shape and the moving
/// shapes against the environment. The scratch keeps the static entries of the last query on
/// the same view and margin (only the moving ones are recomputed), and for each moving pair
/// the direction that last separated it, tried first ([`CollisionWorld::first_collision_in_view`]).
#[derive(Debug, Clone)]
pub struct MovingView {
    moving: Vec<bool>,
    rest: Vec<Real>,
    /// Variables of the joints that do not move with the mask: a query must give them the
    /// values of `rest`.
    rest_variables: Vec<u32>,
    /// Joints whose child link moves, in tree order.
    moving_joints: Vec<u32>,
    /// Whether each attached object's link moves.
    attached_moving: Vec<bool>,
    /// Robot shapes on moving links.
    moving_shapes: Vec<u32>,
    /// For each link, the arm joint nearest above it (`u32::MAX` for a static link): two
    /// links with the same anchor keep their relative pose while the arm moves.
    anchors: Vec<u32>,
    /// Self pairs whose links have different anchors.
    moving_pairs: Vec<(u32, u32)>,
    /// Link poses (world frame) at `rest`.
    link_poses: Vec<Isometry3>,
    /// Shape poses and boxes (not loosened) at `rest`.
    shape_poses: Vec<Pose>,
    shape_aabbs: Vec<Aabb>,
    shape_frames: Vec<BoxFrame>,
    /// The static pairs touching at `rest`, sorted.
    static_contacts: Vec<(BodyId, BodyId)>,
    /// What the world had when the view was made: robot shapes, self pairs, environment
    /// objects, attached objects.
    fingerprint: [usize; 4],
    /// A number no other view made in this process has (a clone keeps it: same contents),
    /// naming the view in a scratch that holds its static entries.
    id: u64,
}

/// The id of the next view.
static NEXT_VIEW_ID: AtomicU64 = AtomicU64::new(0);

impl MovingView {
    /// The moving links (by link index).
    pub fn moving_links(&self) -> &[bool] {
        &self.moving
    }

    /// The configuration of the rest of the robot.
    pub fn rest(&self) -> &[Real] {
        &self.rest
    }

    /// The static pairs (see the module doc: their relative pose does not change while the
    /// arm moves) that touch at the rest configuration, sorted: the same for every query.
    pub fn static_contacts(&self) -> &[(BodyId, BodyId)] {
        &self.static_contacts
    }

    /// Whether the arm's joints change the relative pose of `first` and `second` (the mask
    /// rule for attached objects). Bodies the view's world does not have count as static.
    pub fn pair_moves(&self, first: BodyId, second: BodyId) -> bool {
        self.anchor(first) != self.anchor(second)
    }

    fn anchor(&self, body: BodyId) -> u32 {
        match body {
            BodyId::Link(l) => self.anchors.get(l).copied().unwrap_or(u32::MAX),
            BodyId::Environment(_) => u32::MAX,
            // An attached object moves with its link; the mask rule: against everything.
            BodyId::Attached(k) => self
                .attached_moving
                .get(k)
                .map_or(u32::MAX, |&m| if m { ATTACHED_ANCHOR } else { u32::MAX }),
        }
    }
}

/// The anchor of a moving attached object: different from every link's.
const ATTACHED_ANCHOR: u32 = u32::MAX - 1;

impl CollisionWorld {
    fn fingerprint(&self) -> [usize; 4] {
        [
            self.robot_shapes.len(),
            self.self_pairs.len(),
            self.environment.len(),
            self.attached.len(),
        ]
    }

    /// The view of this world in which the arm's `variables` move the links below their
    /// joints ([`RobotModel::links_moved_by`]), the other joints keeping their values in
    /// `rest`.
    ///
    /// # Errors
    /// [`Error::WrongLength`] for `rest`; as [`CollisionWorld::in_collision`] for the
    /// contact check of the static pairs at `rest`.
    pub fn moving_view(
        &self,
        model: &RobotModel,
        rest: &[Real],
        variables: &[usize],
    ) -> Result<MovingView> {
        let moving = model.links_moved_by(variables);
        let moving = moving.as_slice();
        let mut anchors = vec![u32::MAX; model.links().len()];
        for (j, joint) in model.joints().iter().enumerate() {
            let driven = match joint.source {
                JointValueSource::Fixed => false,
                JointValueSource::Variable(v) | JointValueSource::Mimic { variable: v, .. } => {
                    variables.contains(&v)
                }
            };
            anchors[joint.child_link] = if driven {
                j as u32
            } else {
                anchors[joint.parent_link]
            };
        }
        // Every pair touching at `rest` (this checks the lengths), then the static ones.
        let mut scratch = CollisionScratch::default();
        let touching = self.colliding_pairs_in(
            model,
            rest,
            &mut scratch,
            &CheckOptions::default(),
            PairScope::Every,
        )?;
        let attached_moving: Vec<bool> = self.attached.iter().map(|a| moving[a.link]).collect();
        let mut view = MovingView {
            moving: moving.to_vec(),
            rest: rest.to_vec(),
            rest_variables: Vec::new(),
            moving_joints: Vec::new(),
            moving_shapes: Vec::new(),
            anchors,
            moving_pairs: Vec::new(),
            attached_moving,
            link_poses: Vec::new(),
            shape_poses: Vec::new(),
            shape_aabbs: Vec::new(),
            shape_frames: Vec::new(),
            static_contacts: Vec::new(),
            fingerprint: self.fingerprint(),
            id: NEXT_VIEW_ID.fetch_add(1, Relaxed),
        };
        view.static_contacts = touching
            .into_iter()
            .filter(|&(a, b)| !view.pair_moves(a, b))
            .collect();
        // `scratch` now holds the poses at `rest` (margin 0).
        let mut moving_joints = Vec::new();
        let mut rest_variables = Vec::new();
        for (j, joint) in model.joints().iter().enumerate() {
            let variable = match joint.source {
                JointValueSource::Fixed => None,
                JointValueSource::Variable(v) | JointValueSource::Mimic { variable: v, .. } => {
                    Some(v as u32)
                }
            };
            if moving[joint.child_link] {
                moving_joints.push(j as u32);
            } else if let Some(v) = variable {
                rest_variables.push(v);
            }
        }
        rest_variables.sort_unstable();
        rest_variables.dedup();
        let moving_shapes = (0..self.robot_shapes.len() as u32)
            .filter(|&i| moving[self.robot_shapes[i as usize].link])
            .collect();
        view.moving_pairs = self
            .self_pairs
            .iter()
            .copied()
            .filter(|&(a, b)| {
                view.anchors[self.robot_shapes[a as usize].link]
                    != view.anchors[self.robot_shapes[b as usize].link]
            })
            .collect();
        view.rest_variables = rest_variables;
        view.moving_joints = moving_joints;
        view.moving_shapes = moving_shapes;
        view.link_poses = scratch.link_poses;
        view.shape_poses = scratch.shape_poses;
        view.shape_aabbs = scratch.shape_aabbs;
        view.shape_frames = scratch.shape_frames;
        Ok(view)
    }

    /// The first colliding pair at `q` (every variable; those of the static joints equal to
    /// the view's rest) that is not allowed: the moving pairs closer than the margin, and
    /// the static pairs (see the module doc) as `static_pairs` says (with
    /// [`StaticPairs::Contact`], a static contact is found first). The validity of
    /// [`CollisionWorld::first_collision`] with [`PairScope::MarginOnMoving`] or
    /// [`PairScope::MovingOnly`] and the view's mask, except that two links below the same
    /// arm joint form a static pair.
    ///
    /// # Errors
    /// [`Error::WrongLength`] for `q`; [`Error::InvalidParameter`] for a bad margin, a view
    /// made by another world, or a static joint whose value differs from the rest;
    /// [`Error::UnsupportedCollisionPair`].
    ///
    /// # Performance
    /// See [`MovingView`]; no allocation once the scratch has grown.
    pub fn first_collision_in_view(
        &self,
        model: &RobotModel,
        view: &MovingView,
        q: &[Real],
        scratch: &mut CollisionScratch,
        options: &CheckOptions,
        static_pairs: StaticPairs,
    ) -> Result<Option<(BodyId, BodyId)>> {
        self.prepare_view(model, view, q, scratch, options.margin)?;
        if static_pairs == StaticPairs::Contact
            && let Some(&pair) = view.static_contacts.first()
        {
            return Ok(Some(pair));
        }
        // The self pairs, all moving (two static links share their anchor): the margin on
        // each, in the order of `for_each_collision`.
        for (p, &(a, b)) in view.moving_pairs.iter().enumerate() {
            let (a, b) = (a as usize, b as usize);
            if !scratch.shape_aabbs[a].intersects(&scratch.shape_aabbs[b]) {
                continue;
            }
            let (sa, sb) = (&self.robot_shapes[a], &self.robot_shapes[b]);
            let (pa, pb) = (scratch.shape_poses[a], scratch.shape_poses[b]);
            let (fa, fb) = (&scratch.shape_frames[a], &scratch.shape_frames[b]);
            if !boxes_overlap(fa, sa, fb, sb, options.margin) {
                continue;
            }
            let last = scratch.pair_directions.get_mut(p);
            if self.robot_shapes_touching_from(&pa, sa, &pb, sb, options.margin, last)? {
                return Ok(Some((
                    BodyId::Link(self.robot_shapes[a].link),
                    BodyId::Link(self.robot_shapes[b].link),
                )));
            }
        }
        let mut found = None;
        self.for_each_collision(
            scratch,
            options.margin,
            PairScope::MovingOnly(&view.moving),
            &[],
            Some(&view.moving_shapes),
            &mut |a, b| {
                found = Some((a, b));
                false
            },
        )?;
        Ok(found)
    }

    /// Fills the scratch from the view: the rest's poses, the moving links' and shapes'
    /// poses and boxes for `q`, the attached objects'.
    fn prepare_view(
        &self,
        model: &RobotModel,
        view: &MovingView,
        q: &[Real],
        scratch: &mut CollisionScratch,
        margin: Real,
    ) -> Result<()> {
        self.check_query(model, q, margin)?;
        if view.fingerprint != self.fingerprint() || view.rest.len() != q.len() {
            return Err(Error::InvalidParameter {
                name: "moving view",
                value: view.fingerprint[0] as Real,
                reason: "the view was made by another collision world, or before a change",
            });
        }
        for &v in &view.rest_variables {
            let v = v as usize;
            if q[v] != view.rest[v] {
                return Err(Error::InvalidParameter {
                    name: "static joint value",
                    value: q[v],
                    reason: "a joint that does not move in the view differs from its rest",
                });
            }
        }
        // The static entries stay as the last query on this view with this margin left them
        // (a query overwrites the moving entries only).
        let key = Some((view.id, margin.to_bits()));
        let fresh = scratch.view_key != key
            || scratch.link_poses.len() != view.link_poses.len()
            || scratch.shape_aabbs.len() != view.shape_aabbs.len()
            || scratch.shape_frames.len() != view.shape_frames.len();
        if fresh {
            scratch.link_poses.clear();
            scratch.link_poses.extend_from_slice(&view.link_poses);
            scratch.shape_poses.clear();
            scratch.shape_poses.extend_from_slice(&view.shape_poses);
            scratch.shape_frames.clear();
            scratch.shape_frames.extend_from_slice(&view.shape_frames);
            scratch.shape_aabbs.clear();
            scratch
                .shape_aabbs
                .extend(view.shape_aabbs.iter().map(|a| a.loosened(margin)));
            scratch.env_directions.clear();
            scratch.env_directions.resize(
                view.moving_shapes.len() * self.environment.len(),
                parry3d_f64::math::Vector::ZERO,
            );
            scratch.pair_directions.clear();
            scratch
                .pair_directions
                .resize(view.moving_pairs.len(), parry3d_f64::math::Vector::ZERO);
            scratch.view_key = key;
        }
        let joints = model.joints();
        for &j in &view.moving_joints {
            let joint = &joints[j as usize];
            scratch.link_poses[joint.child_link] = scratch.link_poses[joint.parent_link]
                * joint.parent_from_child(joint.source.value(q));
        }
        for &i in &view.moving_shapes {
            let i = i as usize;
            let s = &self.robot_shapes[i];
            let pose = parry::pose(&(scratch.link_poses[s.link] * s.link_from_shape));
            let frame = BoxFrame::of(&pose, s.box_centre);
            scratch.shape_aabbs[i] = frame.aabb(s.box_half_extents).loosened(margin);
            scratch.shape_frames[i] = frame;
            scratch.shape_poses[i] = pose;
        }
        scratch.attached_poses.clear();
        scratch.attached_aabbs.clear();
        for a in &self.attached {
            let pose = parry::pose(&(scratch.link_poses[a.link] * a.link_from_object));
            scratch
                .attached_aabbs
                .push(a.local_aabb.transform_by(&pose).loosened(margin));
            scratch.attached_poses.push(pose);
        }
        Ok(())
    }
}
