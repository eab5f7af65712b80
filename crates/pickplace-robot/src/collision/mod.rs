//! The collision world (parry3d-f64): robot links, static environment shapes and meshes, and
//! objects attached to links, with self-collision filtered by an
//! [`AllowedCollisionMatrix`].
//!
//! Harada et al. (§IV) reject a grasp or a placement whose key pose puts the robot, the
//! grasped object or the environment in collision; this module answers that question and,
//! for the failure reasons the planner reports, which pairs collide and how far apart the
//! bodies are.
//!
//! # Broad phase
//! Every robot shape's world AABB (loosened by the margin) is tested against the
//! environment's BVH and against the AABBs of the shapes it may touch; the exact test
//! (parry's `intersection_test`, or `closest_points` with a margin) runs only on overlapping
//! boxes. Self-collision pairs are expanded to shape pairs once, when the world is built.
//! Two robot shapes, one of them a link hull of many vertices, are tested by the same GJK
//! query with a support function that climbs the hull's vertex graph instead of scanning
//! every vertex (`support`).

mod acm;
mod distance;
mod hull;
mod narrow;
mod queries;
mod shape;
mod support;
mod view;

pub use acm::{
    AcmOptions, AcmReport, AllowedCollisionMatrix, DEFAULT_MIN_COLLISION_FRACTION, SAMPLING_VERSION,
};
pub use shape::CollisionShape;
pub use view::{MovingView, StaticPairs};

use crate::error::{Error, Result};
use crate::model::RobotModel;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Pose;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use parry3d_f64::shape::SharedShape;
use pickplace_geometry::math::{Isometry3, Real};
use pickplace_geometry::parry;

/// Identifies a body in query results.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum BodyId {
    /// A robot link (index in the model).
    Link(usize),
    /// An environment object (index of [`CollisionWorld::add_environment`]).
    Environment(usize),
    /// An attached object (index of [`CollisionWorld::attach`]).
    Attached(usize),
}

/// Options of the collision queries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckOptions {
    /// Bodies closer than this (m) count as colliding (default: 0.0).
    pub margin: Real,
}

impl Default for CheckOptions {
    fn default() -> Self {
        Self { margin: 0.0 }
    }
}

/// Which pairs of bodies a query checks, and which of them get the margin of
/// [`CheckOptions`].
///
/// A body *moves* when it is a link marked in the mask (`moving[link]`, by link index, one
/// entry per link of the model; [`crate::RobotModel::links_moved_by`] computes it for an
/// arm) or an object attached to such a link; environment objects never move. A pair
/// *moves* when one of its bodies does. The mask is borrowed, so a scope is `Copy` and a
/// query with it allocates nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PairScope<'a> {
    /// Every pair, with the margin (default).
    #[default]
    Every,
    /// Every pair; the margin applies only to moving pairs, and pairs of two static bodies
    /// (an idle arm against the table, two links of the idle arm) are checked for contact
    /// (margin 0): a static near-contact cannot block a motion.
    MarginOnMoving(&'a [bool]),
    /// Only moving pairs, with the margin; pairs of two static bodies are skipped (they do
    /// not change while the masked links move: check them once with
    /// [`PairScope::StaticOnly`]).
    MovingOnly(&'a [bool]),
    /// Only pairs of two static bodies, with the margin.
    StaticOnly(&'a [bool]),
}

impl PairScope<'_> {
    fn mask(&self) -> Option<&[bool]> {
        match *self {
            Self::Every => None,
            Self::MarginOnMoving(m) | Self::MovingOnly(m) | Self::StaticOnly(m) => Some(m),
        }
    }

    /// The margin of a pair (`moving`: one of its bodies moves), or `None` when the scope
    /// skips it.
    #[inline]
    fn pair_margin(&self, moving: bool, margin: Real) -> Option<Real> {
        match (self, moving) {
            (Self::Every, _) | (Self::MarginOnMoving(_), true) | (Self::MovingOnly(_), true) => {
                Some(margin)
            }
            (Self::MarginOnMoving(_), false) => Some(0.0),
            (Self::MovingOnly(_), false) => None,
            (Self::StaticOnly(_), moving) => (!moving).then_some(margin),
        }
    }

    /// Whether link `link` moves (false for [`PairScope::Every`], whose margin does not
    /// depend on it). The mask's length is checked by the query before.
    #[inline]
    fn moves(&self, link: usize) -> bool {
        self.mask().is_some_and(|m| m[link])
    }
}

/// The nearest pair of bodies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DistanceReport {
    /// Distance (m); 0 when they touch or overlap.
    pub distance: Real,
    /// First body.
    pub first: BodyId,
    /// Second body.
    pub second: BodyId,
}

#[derive(Debug, Clone)]
struct RobotShape {
    link: usize,
    shape: SharedShape,
    link_from_shape: Isometry3,
    /// The local box's centre and half extents (the world box is made from them): an
    /// oriented box around the shape, tested (separating axes) before the exact test of a
    /// self pair.
    box_centre: parry3d_f64::math::Vector,
    box_half_extents: parry3d_f64::math::Vector,
    /// The shape's support function by climbing, for a hull of many vertices
    /// ([`support::ClimbingHull`]).
    climbing: Option<support::ClimbingHull>,
}

#[derive(Debug, Clone)]
struct EnvironmentObject {
    name: String,
    shape: SharedShape,
    /// The mesh's hull, tested first ([`CollisionShape::with_hull`]).
    hull: Option<SharedShape>,
    world_from_shape: Pose,
    /// The centre and half extents of the shape's local box: an oriented box around it,
    /// tested before the exact test.
    box_centre: parry3d_f64::math::Vector,
    box_half_extents: parry3d_f64::math::Vector,
    /// The box's frame in the world.
    frame: narrow::BoxFrame,
    /// Links allowed to touch this object.
    allowed_links: Vec<bool>,
}

#[derive(Debug, Clone)]
struct AttachedObject {
    name: String,
    link: usize,
    shape: SharedShape,
    /// The mesh's hull, tested first ([`CollisionShape::with_hull`]).
    hull: Option<SharedShape>,
    link_from_object: Isometry3,
    local_aabb: Aabb,
    /// Links allowed to touch it (its link, the fingers).
    allowed_links: Vec<bool>,
    /// Environment objects allowed to touch it (the surface it rests on).
    allowed_environment: Vec<bool>,
}

/// Caller-owned buffers for the queries (link poses, shape poses and boxes), so that queries
/// allocate nothing and a world is shared between threads.
#[derive(Debug, Clone, Default)]
pub struct CollisionScratch {
    link_poses: Vec<Isometry3>,
    shape_poses: Vec<Pose>,
    shape_aabbs: Vec<Aabb>,
    /// The shapes' box frames (rotation matrices and box centres).
    shape_frames: Vec<narrow::BoxFrame>,
    attached_poses: Vec<Pose>,
    attached_aabbs: Vec<Aabb>,
    candidates: Vec<u32>,
    /// The view (its id) and margin (bits) whose static link and shape entries the buffers
    /// hold, so that the next query on that view computes only the moving ones; `None`
    /// after any other query.
    view_key: Option<(u64, u64)>,
    /// For each moving pair of that view, the direction that last separated it (zero: none).
    pair_directions: Vec<parry3d_f64::math::Vector>,
    /// For each moving shape of that view and environment object (`shape * objects +
    /// object`), the direction that last separated them (zero: none).
    env_directions: Vec<parry3d_f64::math::Vector>,
}

/// Robot links, environment and attached objects. Build it once (`&mut self` methods), then
/// query it from any number of threads (`&self` methods with a scratch each).
#[derive(Debug, Clone)]
pub struct CollisionWorld {
    link_names: Vec<String>,
    variable_count: usize,
    world_from_root: Isometry3,
    acm: AllowedCollisionMatrix,
    robot_shapes: Vec<RobotShape>,
    /// Shape pairs (indices into `robot_shapes`) checked for self-collision.
    self_pairs: Vec<(u32, u32)>,
    environment: Vec<EnvironmentObject>,
    environment_aabbs: Vec<Aabb>,
    environment_bvh: Bvh,
    /// The union of the environment's boxes (empty when there is no environment).
    environment_bounds: Aabb,
    attached: Vec<AttachedObject>,
}

impl CollisionWorld {
    /// A world with the robot's collision geometry and no environment.
    ///
    /// # Arguments
    /// * `acm`: pairs of links never checked (from the SRDF, plus adjacency as you wish).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a degenerate shape.
    pub fn new(model: &RobotModel, acm: AllowedCollisionMatrix) -> Result<Self> {
        let mut robot_shapes = Vec::new();
        for (link, l) in model.links().iter().enumerate() {
            for g in &l.collisions {
                let (shape, correction) = CollisionShape::from_shape(&g.shape)?;
                let local_aabb = shape.shape.compute_local_aabb();
                let climbing = support::ClimbingHull::of(&shape.shape);
                robot_shapes.push(RobotShape {
                    link,
                    shape: shape.shape,
                    link_from_shape: g.link_from_shape * correction,
                    box_centre: local_aabb.center(),
                    box_half_extents: local_aabb.half_extents(),
                    climbing,
                });
            }
        }
        let link_names: Vec<String> = model.links().iter().map(|l| l.name.clone()).collect();
        let mut world = Self {
            link_names,
            variable_count: model.variable_count(),
            world_from_root: Isometry3::identity(),
            acm,
            robot_shapes,
            self_pairs: Vec::new(),
            environment: Vec::new(),
            environment_aabbs: Vec::new(),
            environment_bvh: Bvh::new(),
            environment_bounds: Aabb::new_invalid(),
            attached: Vec::new(),
        };
        world.rebuild_self_pairs();
        Ok(world)
    }

    fn rebuild_self_pairs(&mut self) {
        self.self_pairs.clear();
        for a in 0..self.robot_shapes.len() {
            for b in a + 1..self.robot_shapes.len() {
                let (la, lb) = (self.robot_shapes[a].link, self.robot_shapes[b].link);
                if la != lb
                    && !self
                        .acm
                        .is_allowed(&self.link_names[la], &self.link_names[lb])
                {
                    self.self_pairs.push((a as u32, b as u32));
                }
            }
        }
    }

    /// The allowed-collision matrix.
    pub fn acm(&self) -> &AllowedCollisionMatrix {
        &self.acm
    }

    /// Replaces the allowed-collision matrix (it also applies to environment and attached
    /// objects, by name).
    pub fn set_acm(&mut self, acm: AllowedCollisionMatrix) {
        self.acm = acm;
        self.rebuild_self_pairs();
        for i in 0..self.environment.len() {
            let allowed = self.allowed_links_for(&self.environment[i].name.clone());
            self.environment[i].allowed_links = allowed;
        }
        for i in 0..self.attached.len() {
            let name = self.attached[i].name.clone();
            let mut allowed = self.allowed_links_for(&name);
            allowed[self.attached[i].link] = true;
            for (l, a) in self.attached[i].allowed_links.iter().enumerate() {
                allowed[l] |= *a;
            }
            self.attached[i].allowed_links = allowed;
            self.attached[i].allowed_environment = self
                .environment
                .iter()
                .map(|e| self.acm.is_allowed(&name, &e.name))
                .collect();
        }
    }

    fn allowed_links_for(&self, name: &str) -> Vec<bool> {
        self.link_names
            .iter()
            .map(|l| self.acm.is_allowed(l, name))
            .collect()
    }

    /// Where the robot's root link sits in the world (default identity).
    pub fn set_world_from_root(&mut self, world_from_root: Isometry3) {
        self.world_from_root = world_from_root;
    }

    /// Where the robot's root link is in the world ([`CollisionWorld::set_world_from_root`]).
    pub fn world_from_root(&self) -> Isometry3 {
        self.world_from_root
    }

    /// Number of link shape pairs checked for self-collision.
    pub fn self_pair_count(&self) -> usize {
        self.self_pairs.len()
    }

    /// Adds a static object; returns its [`BodyId::Environment`] index.
    pub fn add_environment(
        &mut self,
        name: &str,
        shape: CollisionShape,
        world_from_shape: &Isometry3,
    ) -> usize {
        let pose = parry::pose(world_from_shape);
        let aabb = shape.shape.compute_aabb(&pose);
        let local = shape.shape.compute_local_aabb();
        self.environment.push(EnvironmentObject {
            name: name.to_owned(),
            shape: shape.shape,
            hull: shape.hull,
            world_from_shape: pose,
            box_centre: local.center(),
            box_half_extents: local.half_extents(),
            frame: narrow::BoxFrame::of(&pose, local.center()),
            allowed_links: self.allowed_links_for(name),
        });
        self.environment_aabbs.push(aabb);
        self.environment_bounds.merge(&aabb);
        self.environment_bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &self.environment_aabbs);
        for a in &mut self.attached {
            a.allowed_environment
                .push(self.acm.is_allowed(&a.name, name));
        }
        self.environment.len() - 1
    }

    /// Attaches an object to a link (a grasped object); returns its [`BodyId::Attached`]
    /// index. It is checked against the environment and the robot, except its own link and
    /// `touch_links` (the fingers), and pairs the ACM allows.
    ///
    /// # Errors
    /// [`Error::UnknownLink`] for a link name the robot does not have.
    pub fn attach(
        &mut self,
        name: &str,
        link: &str,
        shape: CollisionShape,
        link_from_object: &Isometry3,
        touch_links: &[&str],
    ) -> Result<usize> {
        let index = |n: &str| {
            self.link_names
                .iter()
                .position(|l| l == n)
                .ok_or_else(|| Error::UnknownLink { name: n.to_owned() })
        };
        let link = index(link)?;
        let mut allowed_links = self.allowed_links_for(name);
        allowed_links[link] = true;
        for t in touch_links {
            allowed_links[index(t)?] = true;
        }
        let local_aabb = shape.shape.compute_local_aabb();
        self.attached.push(AttachedObject {
            name: name.to_owned(),
            link,
            shape: shape.shape,
            hull: shape.hull,
            link_from_object: *link_from_object,
            local_aabb,
            allowed_links,
            allowed_environment: self
                .environment
                .iter()
                .map(|e| self.acm.is_allowed(name, &e.name))
                .collect(),
        });
        Ok(self.attached.len() - 1)
    }

    /// Removes every attached object.
    pub fn detach_all(&mut self) {
        self.attached.clear();
    }

    /// The name of a body.
    pub fn body_name(&self, body: BodyId) -> &str {
        match body {
            BodyId::Link(i) => &self.link_names[i],
            BodyId::Environment(i) => &self.environment[i].name,
            BodyId::Attached(i) => &self.attached[i].name,
        }
    }

    /// Checks a query's joint values (one per variable of the world's model) and margin.
    fn check_query(&self, model: &RobotModel, q: &[Real], margin: Real) -> Result<()> {
        if q.len() != self.variable_count || model.links().len() != self.link_names.len() {
            return Err(Error::WrongLength {
                what: "joint values",
                expected: self.variable_count,
                found: q.len(),
            });
        }
        if !(margin.is_finite() && margin >= 0.0) {
            return Err(Error::InvalidParameter {
                name: "margin",
                value: margin,
                reason: "must be finite and >= 0",
            });
        }
        Ok(())
    }

    /// Runs FK and fills the scratch's poses and boxes.
    fn prepare(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        margin: Real,
        scope: PairScope<'_>,
    ) -> Result<()> {
        self.check_query(model, q, margin)?;
        if let Some(mask) = scope.mask()
            && mask.len() != self.link_names.len()
        {
            return Err(Error::WrongLength {
                what: "moving-link mask",
                expected: self.link_names.len(),
                found: mask.len(),
            });
        }
        scratch.view_key = None;
        scratch
            .link_poses
            .resize(self.link_names.len(), Isometry3::identity());
        model.forward_kinematics(q, &mut scratch.link_poses)?;
        self.prepare_shapes(scratch, margin);
        Ok(())
    }

    fn prepare_shapes(&self, scratch: &mut CollisionScratch, margin: Real) {
        scratch.view_key = None;
        scratch.shape_poses.clear();
        scratch.shape_aabbs.clear();
        scratch.shape_frames.clear();
        if self.world_from_root != Isometry3::identity() {
            for pose in &mut scratch.link_poses {
                *pose = self.world_from_root * *pose;
            }
        }
        for s in &self.robot_shapes {
            let pose = parry::pose(&(scratch.link_poses[s.link] * s.link_from_shape));
            let frame = narrow::BoxFrame::of(&pose, s.box_centre);
            scratch
                .shape_aabbs
                .push(frame.aabb(s.box_half_extents).loosened(margin));
            scratch.shape_frames.push(frame);
            scratch.shape_poses.push(pose);
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
    }
}

#[cfg(test)]
mod tests;
