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
mod hull;
mod narrow;
mod support;
mod view;

pub use acm::{
    AcmOptions, AcmReport, AllowedCollisionMatrix, DEFAULT_MIN_COLLISION_FRACTION, SAMPLING_VERSION,
};
pub use view::{MovingView, StaticPairs};

use crate::error::{Error, Result};
use crate::model::{RobotModel, Shape};
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Pose;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use parry3d_f64::query::{self, ClosestPoints};
use parry3d_f64::shape::SharedShape;
use pickplace_geometry::math::{Isometry3, Real, Translation3, UnitQuaternion, Vector3};
use pickplace_geometry::mesh::{MeshOptions, TriMesh};
use pickplace_geometry::parry;
use std::path::Path;

/// A shape for the environment or an attached object.
#[derive(Debug, Clone)]
pub struct CollisionShape {
    shape: SharedShape,
    /// The convex hull of a mesh shape, when asked for ([`CollisionShape::with_hull`]): the
    /// pairs of an attached or environment object are tested against it first, and against
    /// the mesh only when the hull touches (the mesh lies inside it, so the answer is the
    /// mesh's).
    hull: Option<SharedShape>,
}

impl CollisionShape {
    /// A box with these half extents (m), centred on its frame.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-positive or non-finite size.
    pub fn cuboid(half_extents: Vector3) -> Result<Self> {
        for &h in half_extents.iter() {
            positive("box half extent", h)?;
        }
        Ok(Self {
            shape: SharedShape::cuboid(half_extents.x, half_extents.y, half_extents.z),
            hull: None,
        })
    }

    /// A sphere.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-positive or non-finite radius.
    pub fn ball(radius: Real) -> Result<Self> {
        Ok(Self {
            shape: SharedShape::ball(positive("sphere radius", radius)?),
            hull: None,
        })
    }

    /// A capsule along z (URDF convention): a segment of `length` with radius `radius`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-positive or non-finite size.
    pub fn capsule_z(radius: Real, length: Real) -> Result<Self> {
        let half = positive("capsule length", length)? / 2.0;
        let r = positive("capsule radius", radius)?;
        Ok(Self {
            shape: SharedShape::capsule(
                parry::vector(&Vector3::new(0.0, 0.0, -half)),
                parry::vector(&Vector3::new(0.0, 0.0, half)),
                r,
            ),
            hull: None,
        })
    }

    /// A triangle mesh (in its own frame).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] when parry rejects the mesh (no triangles).
    pub fn mesh(mesh: &TriMesh) -> Result<Self> {
        let vertices = mesh.vertices().iter().map(parry::point).collect();
        let shape = SharedShape::trimesh(vertices, mesh.triangles().to_vec()).map_err(|_| {
            Error::InvalidParameter {
                name: "mesh",
                value: mesh.triangle_count() as Real,
                reason: "the collision library rejected the triangle mesh",
            }
        })?;
        Ok(Self { shape, hull: None })
    }

    /// This shape with its convex hull kept beside it (for a mesh; other shapes are convex
    /// already): an object with many triangles, held or lying in the environment, is then
    /// tested against a link or an obstacle through its hull first, and through its
    /// triangles only when the hull touches. The answers are those of the mesh alone.
    pub fn with_hull(mut self) -> Self {
        if let Some(mesh) = self.shape.as_trimesh() {
            // Few vertices (GJK scans them all per support point), rounded to contain the
            // exact hull.
            self.hull = hull::link_hull(mesh.vertices());
        }
        self
    }

    /// The convex hull of a triangle mesh's vertices (in the mesh's frame).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] when the vertices span no volume.
    pub fn convex_hull(mesh: &TriMesh) -> Result<Self> {
        let vertices: Vec<_> = mesh.vertices().iter().map(parry::point).collect();
        let shape = SharedShape::convex_hull(&vertices).ok_or(Error::InvalidParameter {
            name: "mesh",
            value: mesh.vertices().len() as Real,
            reason: "the mesh's vertices span no volume: no convex hull",
        })?;
        Ok(Self { shape, hull: None })
    }

    /// A triangle mesh read from a file (STL, OBJ or PLY) through `pickplace-geometry`, for a
    /// static environment object.
    ///
    /// # Errors
    /// [`Error::EnvironmentMesh`] naming the file when it cannot be read;
    /// [`Error::InvalidParameter`] when it has no triangle.
    pub fn mesh_file(path: &Path, options: &MeshOptions) -> Result<Self> {
        let mesh = pickplace_geometry::mesh::load(path, options).map_err(|source| {
            Error::EnvironmentMesh {
                path: path.to_path_buf(),
                source: Box::new(source),
            }
        })?;
        Self::mesh(&mesh)
    }

    /// The local bounding box of the shape.
    pub fn local_aabb(&self) -> (Vector3, Vector3) {
        let aabb = self.shape.compute_local_aabb();
        (parry::to_vector(aabb.mins), parry::to_vector(aabb.maxs))
    }

    /// The shape of a URDF geometry (a box, sphere, cylinder or capsule as a primitive; a
    /// mesh as its convex hull, as robot links are checked) and the pose of the collision
    /// library's shape in the geometry's frame: parry's cylinder axis is y, URDF's (and
    /// MoveIt's) is z, so a cylinder's pose is a quarter turn about x; the others' identity.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-positive or non-finite size.
    pub fn from_shape(shape: &Shape) -> Result<(Self, Isometry3)> {
        Ok(match shape {
            Shape::Box { half_extents } => (Self::cuboid(*half_extents)?, Isometry3::identity()),
            Shape::Sphere { radius } => (Self::ball(*radius)?, Isometry3::identity()),
            Shape::Capsule { radius, length } => {
                (Self::capsule_z(*radius, *length)?, Isometry3::identity())
            }
            Shape::Cylinder { radius, length } => {
                let r = positive("cylinder radius", *radius)?;
                let half = positive("cylinder length", *length)? / 2.0;
                let y_to_z = Isometry3::from_parts(
                    Translation3::identity(),
                    UnitQuaternion::from_axis_angle(
                        &Vector3::x_axis(),
                        std::f64::consts::FRAC_PI_2,
                    ),
                );
                (
                    Self {
                        shape: SharedShape::cylinder(half, r),
                        hull: None,
                    },
                    y_to_z,
                )
            }
            // Robot links are checked as convex shapes: a link mesh becomes its convex hull
            // (conservative, and one GJK query instead of a triangle traversal), with at most
            // `hull::MAX_HULL_VERTICES` vertices and rounded by at most 2 mm when it had
            // more (`hull`); a flat mesh with no hull stays a triangle mesh.
            Shape::Mesh { mesh, .. } => {
                let vertices: Vec<_> = mesh.vertices().iter().map(parry::point).collect();
                let shape = match hull::link_hull(&vertices) {
                    Some(shape) => Self { shape, hull: None },
                    None => Self::mesh(mesh)?,
                };
                (shape, Isometry3::identity())
            }
        })
    }
}

/// The distance between two boxes (0 when they overlap): a lower bound of the distance
/// between the shapes inside them.
fn aabb_gap(a: &Aabb, b: &Aabb) -> Real {
    let gap = (a.mins - b.maxs)
        .max(b.mins - a.maxs)
        .max(parry3d_f64::math::Vector::ZERO);
    gap.length()
}

fn positive(name: &'static str, value: Real) -> Result<Real> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            reason: "must be positive and finite",
        })
    }
}

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
    local_aabb: Aabb,
    /// The local box's centre and half extents: an oriented box around the shape, tested
    /// (separating axes) before the exact test of a self pair.
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
                    local_aabb,
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

    /// Runs FK and fills the scratch's poses and boxes.
    fn prepare(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        margin: Real,
        scope: PairScope<'_>,
    ) -> Result<()> {
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
        if self.world_from_root != Isometry3::identity() {
            for pose in &mut scratch.link_poses {
                *pose = self.world_from_root * *pose;
            }
        }
        for s in &self.robot_shapes {
            let pose = parry::pose(&(scratch.link_poses[s.link] * s.link_from_shape));
            scratch
                .shape_aabbs
                .push(s.local_aabb.transform_by(&pose).loosened(margin));
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

    /// The exact test of two shapes: overlap (margin 0) or closer than the margin.
    fn touching(
        &self,
        pose1: &Pose,
        shape1: &SharedShape,
        pose2: &Pose,
        shape2: &SharedShape,
        margin: Real,
        names: impl Fn() -> (String, String),
    ) -> Result<bool> {
        let unsupported = |_| {
            let (first, second) = names();
            Error::UnsupportedCollisionPair { first, second }
        };
        if margin == 0.0 {
            Ok(
                query::intersection_test(pose1, &*shape1.0, pose2, &*shape2.0)
                    .map_err(unsupported)?
                    .intersecting,
            )
        } else {
            Ok(!matches!(
                query::closest_points(pose1, &*shape1.0, pose2, &*shape2.0, margin)
                    .map_err(unsupported)?,
                ClosestPoints::Disjoint
            ))
        }
    }

    /// [`CollisionWorld::touching`] of a mesh kept with its hull (an attached object, an
    /// environment object made [`CollisionShape::with_hull`]) and another shape: through the
    /// hull first when there is one (a hull clear of the other shape, or farther than the
    /// margin, leaves the mesh inside it clear too), then the mesh itself.
    #[allow(clippy::too_many_arguments)]
    fn hulled_touching(
        &self,
        pose1: &Pose,
        shape1: &SharedShape,
        hull1: Option<&SharedShape>,
        pose2: &Pose,
        shape2: &SharedShape,
        margin: Real,
        names: impl Fn() -> (String, String),
    ) -> Result<bool> {
        if let Some(hull) = hull1
            && !self.touching(pose1, hull, pose2, shape2, margin, &names)?
        {
            return Ok(false);
        }
        self.touching(pose1, shape1, pose2, shape2, margin, names)
    }

    /// Visits colliding pairs of the scope until `visit` returns false: the self pairs
    /// `self_pairs`, the robot shapes `env_shapes` (every shape when `None`) against the
    /// environment, the attached objects against both.
    fn for_each_collision(
        &self,
        scratch: &mut CollisionScratch,
        margin: Real,
        scope: PairScope<'_>,
        self_pairs: &[(u32, u32)],
        env_shapes: Option<&[u32]>,
        visit: &mut dyn FnMut(BodyId, BodyId) -> bool,
    ) -> Result<()> {
        // Self-collision.
        for &(a, b) in self_pairs {
            let (a, b) = (a as usize, b as usize);
            let (sa, sb) = (&self.robot_shapes[a], &self.robot_shapes[b]);
            let Some(pair_margin) =
                scope.pair_margin(scope.moves(sa.link) || scope.moves(sb.link), margin)
            else {
                continue;
            };
            if scratch.shape_aabbs[a].intersects(&scratch.shape_aabbs[b])
                && self.robot_pair_touching(scratch, a, b, pair_margin)?
                && !visit(BodyId::Link(sa.link), BodyId::Link(sb.link))
            {
                return Ok(());
            }
        }
        // Robot against environment.
        let shape_count = env_shapes.map_or(self.robot_shapes.len(), <[u32]>::len);
        for n in 0..shape_count {
            let i = env_shapes.map_or(n, |shapes| shapes[n] as usize);
            let s = &self.robot_shapes[i];
            let Some(pair_margin) = scope.pair_margin(scope.moves(s.link), margin) else {
                continue;
            };
            // Most link boxes are far from every environment object: one box test, no BVH
            // traversal.
            if !self.environment_bounds.intersects(&scratch.shape_aabbs[i]) {
                continue;
            }
            scratch.candidates.clear();
            scratch
                .candidates
                .extend(self.environment_bvh.intersect_aabb(&scratch.shape_aabbs[i]));
            for c in 0..scratch.candidates.len() {
                let e = scratch.candidates[c] as usize;
                let env = &self.environment[e];
                if env.allowed_links[s.link] {
                    continue;
                }
                // A moving view's query keeps each pair's last separating direction.
                let slot = n * self.environment.len() + e;
                let last = if env_shapes.is_some() && scratch.view_key.is_some() {
                    scratch.env_directions.get_mut(slot)
                } else {
                    None
                };
                if self.robot_env_touching(&scratch.shape_poses[i], s, env, pair_margin, last)?
                    && !visit(BodyId::Link(s.link), BodyId::Environment(e))
                {
                    return Ok(());
                }
            }
        }
        // Attached objects against robot and environment.
        for (k, a) in self.attached.iter().enumerate() {
            let attached_moves = scope.moves(a.link);
            for (i, s) in self.robot_shapes.iter().enumerate() {
                let Some(pair_margin) =
                    scope.pair_margin(attached_moves || scope.moves(s.link), margin)
                else {
                    continue;
                };
                if a.allowed_links[s.link]
                    || !scratch.attached_aabbs[k].intersects(&scratch.shape_aabbs[i])
                {
                    continue;
                }
                if self.hulled_touching(
                    &scratch.attached_poses[k],
                    &a.shape,
                    a.hull.as_ref(),
                    &scratch.shape_poses[i],
                    &s.shape,
                    pair_margin,
                    || (a.name.clone(), self.link_names[s.link].clone()),
                )? && !visit(BodyId::Attached(k), BodyId::Link(s.link))
                {
                    return Ok(());
                }
            }
            let Some(pair_margin) = scope.pair_margin(attached_moves, margin) else {
                continue;
            };
            scratch.candidates.clear();
            scratch.candidates.extend(
                self.environment_bvh
                    .intersect_aabb(&scratch.attached_aabbs[k]),
            );
            for c in 0..scratch.candidates.len() {
                let e = scratch.candidates[c] as usize;
                if a.allowed_environment[e] {
                    continue;
                }
                let env = &self.environment[e];
                if self.hulled_touching(
                    &scratch.attached_poses[k],
                    &a.shape,
                    a.hull.as_ref(),
                    &env.world_from_shape,
                    &env.shape,
                    pair_margin,
                    || (a.name.clone(), env.name.clone()),
                )? && !visit(BodyId::Attached(k), BodyId::Environment(e))
                {
                    return Ok(());
                }
            }
        }
        Ok(())
    }

    /// True when some pair that is not allowed is in collision (closer than the margin);
    /// stops at the first such pair. Every pair gets the margin ([`PairScope::Every`]).
    ///
    /// # Errors
    /// [`Error::WrongLength`] for `q`, [`Error::InvalidParameter`] for a bad margin,
    /// [`Error::UnsupportedCollisionPair`].
    ///
    /// # Performance
    /// FK, one AABB per shape, a BVH query per shape against the environment, an AABB test
    /// per self pair, and exact tests only on overlapping boxes.
    pub fn in_collision(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        options: &CheckOptions,
    ) -> Result<bool> {
        Ok(self
            .first_collision(model, q, scratch, options, PairScope::Every)?
            .is_some())
    }

    /// The first colliding pair of `scope` that is not allowed (closer than its margin), or
    /// `None` when there is none; stops there. As cheap as [`CollisionWorld::in_collision`],
    /// which is this query with [`PairScope::Every`]; the pair is the first in the query's
    /// order (self pairs, robot–environment, attached objects), not the deepest.
    ///
    /// # Errors
    /// As [`CollisionWorld::in_collision`], and [`Error::WrongLength`] for a mask that does
    /// not have one entry per link.
    ///
    /// # Performance
    /// As [`CollisionWorld::in_collision`]; with [`PairScope::MovingOnly`], static shapes
    /// skip their environment query and static pairs their box test.
    pub fn first_collision(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        options: &CheckOptions,
        scope: PairScope<'_>,
    ) -> Result<Option<(BodyId, BodyId)>> {
        self.prepare(model, q, scratch, options.margin, scope)?;
        let mut found = None;
        self.for_each_collision(
            scratch,
            options.margin,
            scope,
            &self.self_pairs,
            None,
            &mut |a, b| {
                found = Some((a, b));
                false
            },
        )?;
        Ok(found)
    }

    /// Every colliding pair (link pairs reported once even when several shapes touch),
    /// sorted. Every pair gets the margin ([`PairScope::Every`]).
    ///
    /// # Errors
    /// As [`CollisionWorld::in_collision`].
    pub fn colliding_pairs(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        options: &CheckOptions,
    ) -> Result<Vec<(BodyId, BodyId)>> {
        self.colliding_pairs_in(model, q, scratch, options, PairScope::Every)
    }

    /// Every colliding pair of `scope` (link pairs reported once even when several shapes
    /// touch), sorted.
    ///
    /// # Errors
    /// As [`CollisionWorld::first_collision`].
    pub fn colliding_pairs_in(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        options: &CheckOptions,
        scope: PairScope<'_>,
    ) -> Result<Vec<(BodyId, BodyId)>> {
        self.prepare(model, q, scratch, options.margin, scope)?;
        let mut pairs = Vec::new();
        self.for_each_collision(
            scratch,
            options.margin,
            scope,
            &self.self_pairs,
            None,
            &mut |a, b| {
                pairs.push((a, b));
                true
            },
        )?;
        pairs.sort_unstable();
        pairs.dedup();
        Ok(pairs)
    }

    /// The smallest distance between any pair that is checked (robot–environment,
    /// robot–robot, attached–robot, attached–environment), or `None` when there is no pair.
    ///
    /// # Errors
    /// As [`CollisionWorld::in_collision`].
    pub fn min_distance(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
    ) -> Result<Option<DistanceReport>> {
        self.prepare(model, q, scratch, 0.0, PairScope::Every)?;
        let mut best: Option<DistanceReport> = None;
        // Each pair is skipped when the gap between its boxes, a lower bound of its
        // distance, is already no better than the best found; the cheap primitive pairs
        // (self-collision) go first so that the bound is tight before the meshes.
        let mut visit = |aabb1: &Aabb,
                         p1: &Pose,
                         s1: &SharedShape,
                         aabb2: &Aabb,
                         p2: &Pose,
                         s2: &SharedShape,
                         first: BodyId,
                         second: BodyId|
         -> Result<()> {
            if best.is_some_and(|b| aabb_gap(aabb1, aabb2) >= b.distance) {
                return Ok(());
            }
            let d = query::distance(p1, &*s1.0, p2, &*s2.0)
                .map_err(|_| Error::UnsupportedCollisionPair {
                    first: self.body_name(first).to_owned(),
                    second: self.body_name(second).to_owned(),
                })?
                .distance;
            if best.is_none_or(|b| d < b.distance) {
                best = Some(DistanceReport {
                    distance: d,
                    first,
                    second,
                });
            }
            Ok(())
        };
        for &(a, b) in &self.self_pairs {
            let (a, b) = (a as usize, b as usize);
            let (sa, sb) = (&self.robot_shapes[a], &self.robot_shapes[b]);
            visit(
                &scratch.shape_aabbs[a],
                &scratch.shape_poses[a],
                &sa.shape,
                &scratch.shape_aabbs[b],
                &scratch.shape_poses[b],
                &sb.shape,
                BodyId::Link(sa.link),
                BodyId::Link(sb.link),
            )?;
        }
        for (k, a) in self.attached.iter().enumerate() {
            for (i, s) in self.robot_shapes.iter().enumerate() {
                if !a.allowed_links[s.link] {
                    visit(
                        &scratch.attached_aabbs[k],
                        &scratch.attached_poses[k],
                        &a.shape,
                        &scratch.shape_aabbs[i],
                        &scratch.shape_poses[i],
                        &s.shape,
                        BodyId::Attached(k),
                        BodyId::Link(s.link),
                    )?;
                }
            }
        }
        for (i, s) in self.robot_shapes.iter().enumerate() {
            for (e, env) in self.environment.iter().enumerate() {
                if !env.allowed_links[s.link] {
                    visit(
                        &scratch.shape_aabbs[i],
                        &scratch.shape_poses[i],
                        &s.shape,
                        &self.environment_aabbs[e],
                        &env.world_from_shape,
                        &env.shape,
                        BodyId::Link(s.link),
                        BodyId::Environment(e),
                    )?;
                }
            }
        }
        for (k, a) in self.attached.iter().enumerate() {
            for (e, env) in self.environment.iter().enumerate() {
                if !a.allowed_environment[e] {
                    visit(
                        &scratch.attached_aabbs[k],
                        &scratch.attached_poses[k],
                        &a.shape,
                        &self.environment_aabbs[e],
                        &env.world_from_shape,
                        &env.shape,
                        BodyId::Attached(k),
                        BodyId::Environment(e),
                    )?;
                }
            }
        }
        Ok(best)
    }

    /// The signed distance between two bodies at `q` (m): the distance between their nearest
    /// shapes when they are apart, minus the deepest penetration of their shapes when they
    /// overlap (a mesh's penetration is measured from its triangles). For reports, e.g. of a
    /// start state in collision; the ACM is not consulted.
    ///
    /// # Errors
    /// As [`CollisionWorld::in_collision`]; [`Error::InvalidParameter`] for a body the
    /// world does not have or a link without collision geometry.
    pub fn signed_distance(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        first: BodyId,
        second: BodyId,
    ) -> Result<Real> {
        self.prepare(model, q, scratch, 0.0, PairScope::Every)?;
        let scratch = &*scratch;
        let exists = |b: BodyId| match b {
            BodyId::Link(i) => self.robot_shapes.iter().any(|s| s.link == i),
            BodyId::Environment(i) => i < self.environment.len(),
            BodyId::Attached(i) => i < self.attached.len(),
        };
        for b in [first, second] {
            if !exists(b) {
                let index = match b {
                    BodyId::Link(i) | BodyId::Environment(i) | BodyId::Attached(i) => i,
                };
                return Err(Error::InvalidParameter {
                    name: "body",
                    value: index as Real,
                    reason: "no such body with collision geometry in the world",
                });
            }
        }
        let shapes_of = |b: BodyId| -> Box<dyn Iterator<Item = (Pose, &SharedShape)> + '_> {
            match b {
                BodyId::Link(l) => Box::new(
                    self.robot_shapes
                        .iter()
                        .enumerate()
                        .filter(move |(_, s)| s.link == l)
                        .map(|(i, s)| (scratch.shape_poses[i], &s.shape)),
                ),
                BodyId::Environment(e) => Box::new(std::iter::once((
                    self.environment[e].world_from_shape,
                    &self.environment[e].shape,
                ))),
                BodyId::Attached(k) => Box::new(std::iter::once((
                    scratch.attached_poses[k],
                    &self.attached[k].shape,
                ))),
            }
        };
        let unsupported = |_| Error::UnsupportedCollisionPair {
            first: self.body_name(first).to_owned(),
            second: self.body_name(second).to_owned(),
        };
        let mut best = Real::INFINITY;
        for (p1, s1) in shapes_of(first) {
            for (p2, s2) in shapes_of(second) {
                let d = query::distance(&p1, &*s1.0, &p2, &*s2.0)
                    .map_err(unsupported)?
                    .distance;
                let d = if d > 0.0 {
                    d
                } else {
                    query::contact(&p1, &*s1.0, &p2, &*s2.0, 0.0)
                        .map_err(unsupported)?
                        .map_or(0.0, |c| c.dist.min(0.0))
                };
                best = best.min(d);
            }
        }
        Ok(best)
    }

    /// Self-collision of link pairs only (no environment, no attached objects) for the
    /// given link poses: every colliding pair of link indices, sorted. Used to generate the
    /// allowed-collision matrix.
    ///
    /// # Errors
    /// [`Error::WrongLength`] for the poses; [`Error::UnsupportedCollisionPair`].
    pub fn colliding_link_pairs_all(
        &self,
        root_from_links: &[Isometry3],
        scratch: &mut CollisionScratch,
    ) -> Result<Vec<(usize, usize)>> {
        self.colliding_link_pairs_where(root_from_links, scratch, |_, _| true)
    }

    /// As [`CollisionWorld::colliding_link_pairs_all`], testing only the link pairs
    /// `(a, b)` (`a < b`, link indices) for which `wanted(a, b)` holds; the matrix
    /// generator leaves out the pairs it has already decided (links joined by a joint).
    ///
    /// # Errors
    /// As [`CollisionWorld::colliding_link_pairs_all`].
    pub fn colliding_link_pairs_where(
        &self,
        root_from_links: &[Isometry3],
        scratch: &mut CollisionScratch,
        wanted: impl Fn(usize, usize) -> bool,
    ) -> Result<Vec<(usize, usize)>> {
        if root_from_links.len() != self.link_names.len() {
            return Err(Error::WrongLength {
                what: "link poses",
                expected: self.link_names.len(),
                found: root_from_links.len(),
            });
        }
        scratch.link_poses.clear();
        scratch.link_poses.extend_from_slice(root_from_links);
        self.prepare_shapes(scratch, 0.0);
        let mut pairs = Vec::new();
        for a in 0..self.robot_shapes.len() {
            for b in a + 1..self.robot_shapes.len() {
                let (sa, sb) = (&self.robot_shapes[a], &self.robot_shapes[b]);
                let (la, lb) = (sa.link.min(sb.link), sa.link.max(sb.link));
                if la == lb
                    || !scratch.shape_aabbs[a].intersects(&scratch.shape_aabbs[b])
                    || !wanted(la, lb)
                {
                    continue;
                }
                if self.robot_shapes_touching(
                    &scratch.shape_poses[a],
                    sa,
                    &scratch.shape_poses[b],
                    sb,
                    0.0,
                )? {
                    pairs.push((la, lb));
                }
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        Ok(pairs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::LoadOptions;

    /// Two 10 cm cubes beside a slab: `idle` on a revolute joint at the origin, `arm` on a
    /// prismatic joint along z at x = 1; both 2 mm above the slab at zero.
    fn two_cubes() -> (RobotModel, CollisionWorld) {
        let cube = r#"<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>"#;
        let limit = r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#;
        let urdf = format!(
            r#"<robot name="two">
                <link name="base"/>
                <link name="idle">{cube}</link>
                <link name="arm">{cube}</link>
                <joint name="idle_joint" type="revolute"><parent link="base"/><child link="idle"/>
                  <axis xyz="0 0 1"/>{limit}</joint>
                <joint name="arm_joint" type="prismatic"><parent link="base"/><child link="arm"/>
                  <origin xyz="1 0 0"/><axis xyz="0 0 1"/>{limit}</joint>
              </robot>"#
        );
        let model = RobotModel::from_urdf_str(&urdf, Path::new("."), &LoadOptions::default())
            .expect("valid URDF");
        let mut world =
            CollisionWorld::new(&model, AllowedCollisionMatrix::new()).expect("valid shapes");
        let slab = CollisionShape::cuboid(Vector3::new(1.0, 0.5, 0.05)).expect("valid box");
        world.add_environment(
            "slab",
            slab,
            &Isometry3::translation(0.5, 0.0, -0.05 - 0.002 - 0.05),
        );
        (model, world)
    }

    /// The configuration with the arm cube at height `arm_z`.
    fn arm_at(model: &RobotModel, arm_z: Real) -> Vec<Real> {
        let mut q = model.zero_configuration();
        q[model.variable_index("arm_joint").expect("joint")] = arm_z;
        q
    }

    #[test]
    fn the_arm_moves_its_own_link_only() {
        let (model, _) = two_cubes();
        let arm = model.variable_index("arm_joint").expect("joint");
        assert_eq!(model.links_moved_by(&[arm]), [false, false, true]);
        assert_eq!(model.links_moved_by(&[]), [false; 3]);
        assert_eq!(model.links_moved_by(&[99]), [false; 3]);
    }

    #[test]
    fn an_idle_link_near_the_environment_does_not_block_a_moving_arm() {
        let (model, world) = two_cubes();
        let moving = model.links_moved_by(&[model.variable_index("arm_joint").expect("joint")]);
        let mut scratch = CollisionScratch::default();
        let options = CheckOptions { margin: 0.01 };
        let q = arm_at(&model, 0.1);
        // The margin on every pair: the idle cube, 2 mm from the slab, blocks everything.
        let idle = BodyId::Link(model.link_index("idle").expect("link"));
        assert_eq!(
            world
                .colliding_pairs(&model, &q, &mut scratch, &options)
                .expect("valid"),
            [(idle, BodyId::Environment(0))]
        );
        for scope in [
            PairScope::MarginOnMoving(&moving),
            PairScope::MovingOnly(&moving),
        ] {
            assert_eq!(
                world
                    .first_collision(&model, &q, &mut scratch, &options, scope)
                    .expect("valid"),
                None,
                "{scope:?}"
            );
        }
        // The static pair alone, with the margin: the near-contact is still reported.
        assert_eq!(
            world
                .colliding_pairs_in(
                    &model,
                    &q,
                    &mut scratch,
                    &options,
                    PairScope::StaticOnly(&moving)
                )
                .expect("valid"),
            [(idle, BodyId::Environment(0))]
        );
    }

    #[test]
    fn a_moving_link_within_the_margin_blocks() {
        let (model, world) = two_cubes();
        let moving = model.links_moved_by(&[model.variable_index("arm_joint").expect("joint")]);
        let mut scratch = CollisionScratch::default();
        let options = CheckOptions { margin: 0.01 };
        // The arm cube 5 mm above the slab.
        let q = arm_at(&model, 0.003);
        let arm = BodyId::Link(model.link_index("arm").expect("link"));
        for scope in [
            PairScope::MarginOnMoving(&moving),
            PairScope::MovingOnly(&moving),
        ] {
            assert_eq!(
                world
                    .first_collision(&model, &q, &mut scratch, &options, scope)
                    .expect("valid"),
                Some((arm, BodyId::Environment(0))),
                "{scope:?}"
            );
        }
        // The static pairs touch nothing (the idle cube is 2 mm off the slab).
        assert!(
            world
                .first_collision(
                    &model,
                    &q,
                    &mut scratch,
                    &CheckOptions::default(),
                    PairScope::StaticOnly(&moving)
                )
                .expect("valid")
                .is_none()
        );
    }

    #[test]
    fn a_static_contact_still_collides_with_the_margin_on_moving_pairs_only() {
        let (model, world) = two_cubes();
        let moving = model.links_moved_by(&[model.variable_index("arm_joint").expect("joint")]);
        let mut scratch = CollisionScratch::default();
        let options = CheckOptions { margin: 0.01 };
        // A small block inside the idle cube: a static contact.
        let mut world = world;
        let block = CollisionShape::cuboid(Vector3::new(0.02, 0.02, 0.02)).expect("valid box");
        world.add_environment("block", block, &Isometry3::translation(0.0, 0.0, 0.0));
        let q = arm_at(&model, 0.1);
        let idle = BodyId::Link(model.link_index("idle").expect("link"));
        assert_eq!(
            world
                .first_collision(
                    &model,
                    &q,
                    &mut scratch,
                    &options,
                    PairScope::MarginOnMoving(&moving)
                )
                .expect("valid"),
            Some((idle, BodyId::Environment(1)))
        );
        assert!(
            world
                .first_collision(
                    &model,
                    &q,
                    &mut scratch,
                    &options,
                    PairScope::MovingOnly(&moving)
                )
                .expect("valid")
                .is_none()
        );
        // The block is inside the idle cube: 2 cm + 5 cm deep along every axis.
        let depth = world
            .signed_distance(&model, &q, &mut scratch, idle, BodyId::Environment(1))
            .expect("valid");
        assert!((depth + 0.07).abs() < 1e-6, "{depth}");
        // The slab is 2 mm below it.
        let gap = world
            .signed_distance(&model, &q, &mut scratch, idle, BodyId::Environment(0))
            .expect("valid");
        assert!((gap - 0.002).abs() < 1e-9, "{gap}");
    }

    #[test]
    fn two_links_of_the_moving_hand_always_close_do_not_block_it() {
        // The arm cube with a finger fixed 5 mm from it: within the 10 mm margin, always.
        let cube = r#"<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>"#;
        let finger = r#"<collision><origin xyz="0.06 0 0"/><geometry><box size="0.01 0.01 0.01"/></geometry></collision>"#;
        let urdf = format!(
            r#"<robot name="hand">
                <link name="base"/>
                <link name="arm">{cube}</link>
                <link name="finger">{finger}</link>
                <joint name="arm_joint" type="prismatic"><parent link="base"/><child link="arm"/>
                  <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
                <joint name="finger_joint" type="fixed"><parent link="arm"/><child link="finger"/></joint>
              </robot>"#
        );
        let model = RobotModel::from_urdf_str(&urdf, Path::new("."), &LoadOptions::default())
            .expect("valid URDF");
        let world =
            CollisionWorld::new(&model, AllowedCollisionMatrix::new()).expect("valid shapes");
        let arm = [model.variable_index("arm_joint").expect("joint")];
        let moving = model.links_moved_by(&arm);
        let q = [0.3];
        let mut scratch = CollisionScratch::default();
        let options = CheckOptions { margin: 0.01 };
        // The mask rule: both links move, the margin applies, every state is blocked.
        assert!(
            world
                .first_collision(
                    &model,
                    &q,
                    &mut scratch,
                    &options,
                    PairScope::MarginOnMoving(&moving)
                )
                .expect("valid")
                .is_some()
        );
        // The view: no arm joint between them, a static pair, apart at the rest.
        let view = world.moving_view(&model, &[0.0], &arm).expect("valid");
        let (a, f) = (
            BodyId::Link(model.link_index("arm").expect("link")),
            BodyId::Link(model.link_index("finger").expect("link")),
        );
        assert!(!view.pair_moves(a, f));
        assert!(view.pair_moves(a, BodyId::Environment(0)));
        assert!(view.static_contacts().is_empty());
        for rule in [StaticPairs::Contact, StaticPairs::Skip] {
            assert_eq!(
                world
                    .first_collision_in_view(&model, &view, &q, &mut scratch, &options, rule)
                    .expect("valid"),
                None
            );
        }
    }

    #[test]
    fn a_scratch_shared_by_views_margins_and_other_queries_answers_as_a_fresh_one() {
        let (model, world) = two_cubes();
        let arm = [model.variable_index("arm_joint").expect("joint")];
        let moving = model.links_moved_by(&arm);
        let rest = model.zero_configuration();
        let views = [
            world.moving_view(&model, &rest, &arm).expect("valid"),
            world.moving_view(&model, &rest, &arm).expect("valid"),
        ];
        let mut shared = CollisionScratch::default();
        for step in 0..40 {
            let view = &views[step % 2];
            let margin = [0.0, 0.01, 0.004][step % 3];
            let q = arm_at(&model, -0.02 + 0.001 * step as Real);
            let options = CheckOptions { margin };
            if step % 5 == 0 {
                // Another query fills the shared scratch with the whole robot.
                world
                    .first_collision(
                        &model,
                        &q,
                        &mut shared,
                        &options,
                        PairScope::MovingOnly(&moving),
                    )
                    .expect("valid");
            }
            let got = world
                .first_collision_in_view(&model, view, &q, &mut shared, &options, StaticPairs::Skip)
                .expect("valid");
            let fresh = world
                .first_collision_in_view(
                    &model,
                    view,
                    &q,
                    &mut CollisionScratch::default(),
                    &options,
                    StaticPairs::Skip,
                )
                .expect("valid");
            assert_eq!(got, fresh, "step {step}");
        }
    }

    #[test]
    fn self_pairs_of_link_hulls_answer_as_parry() {
        // Two links whose meshes have many vertices (climbing hulls), moved against each
        // other: the world's test agrees with parry's query on the same shapes.
        let sphere = |n: usize, r: Real| -> Vec<parry3d_f64::math::Vector> {
            (0..n)
                .map(|i| {
                    let z = 1.0 - 2.0 * (i as Real + 0.5) / n as Real;
                    let rho = (1.0 - z * z).sqrt();
                    let phi = i as Real * 2.399_963_229_728_653;
                    parry3d_f64::math::Vector::new(
                        r * rho * phi.cos(),
                        0.5 * r * rho * phi.sin(),
                        r * z,
                    )
                })
                .collect()
        };
        let hull =
            |points: Vec<parry3d_f64::math::Vector>| hull::link_hull(&points).expect("a volume");
        let shapes = [hull(sphere(400, 0.05)), hull(sphere(90, 0.03))];
        let climbing: Vec<_> = shapes
            .iter()
            .map(|s| support::ClimbingHull::of(s).expect("many vertices"))
            .collect();
        let robot_shape = |k: usize| {
            let local_aabb = shapes[k].compute_local_aabb();
            RobotShape {
                link: k,
                shape: shapes[k].clone(),
                link_from_shape: Isometry3::identity(),
                local_aabb,
                box_centre: local_aabb.center(),
                box_half_extents: local_aabb.half_extents(),
                climbing: Some(climbing[k].clone()),
            }
        };
        let (a, b) = (robot_shape(0), robot_shape(1));
        let (_, world) = two_cubes();
        let mut last = [parry3d_f64::math::Vector::ZERO; 2];
        let mut agreed = [0usize; 2];
        for i in 0..400 {
            let t = i as Real * 0.37;
            let pose1 = parry::pose(&Isometry3::from_parts(
                Translation3::new(0.0, 0.0, 0.0),
                UnitQuaternion::from_euler_angles(t, 0.5 * t, 0.0),
            ));
            let pose2 = parry::pose(&Isometry3::from_parts(
                Translation3::new(0.06 + 0.04 * (t * 1.3).sin(), 0.02 * t.cos(), 0.01),
                UnitQuaternion::from_euler_angles(0.2 * t, t, 0.3),
            ));
            for margin in [0.0, 0.01] {
                let ours = world
                    .robot_shapes_touching(&pose1, &a, &pose2, &b, margin)
                    .expect("supported");
                let theirs = world
                    .touching(&pose1, &a.shape, &pose2, &b.shape, margin, || {
                        (String::new(), String::new())
                    })
                    .expect("supported");
                assert_eq!(ours, theirs, "pose {i}, margin {margin}");
                // Starting from the direction that separated the pair at the previous pose.
                let from_last = world
                    .robot_shapes_touching_from(
                        &pose1,
                        &a,
                        &pose2,
                        &b,
                        margin,
                        Some(&mut last[usize::from(margin > 0.0)]),
                    )
                    .expect("supported");
                assert_eq!(
                    from_last, theirs,
                    "pose {i}, margin {margin}, from the last"
                );
                agreed[usize::from(ours)] += 1;
            }
        }
        // Both answers occur.
        assert!(agreed[0] > 20 && agreed[1] > 20, "{agreed:?}");
    }

    #[test]
    fn a_mask_of_the_wrong_length_is_an_error() {
        let (model, world) = two_cubes();
        let q = arm_at(&model, 0.1);
        let mut scratch = CollisionScratch::default();
        assert!(matches!(
            world.first_collision(
                &model,
                &q,
                &mut scratch,
                &CheckOptions::default(),
                PairScope::MovingOnly(&[true])
            ),
            Err(Error::WrongLength {
                what: "moving-link mask",
                expected: 3,
                found: 1
            })
        ));
    }

    #[test]
    fn a_held_mesh_tested_through_its_hull_first_gives_the_mesh_answer() {
        // The paper's mug (a handle: far from convex), attached, against a box at poses that
        // sweep through contact, with and without a margin.
        let mug = pickplace_geometry::shapes::mug_builder()
            .build()
            .expect("mug");
        let shape = CollisionShape::mesh(&mug).expect("mesh").with_hull();
        assert!(shape.hull.is_some());
        let object = AttachedObject {
            name: "mug".into(),
            link: 0,
            shape: shape.shape.clone(),
            hull: shape.hull.clone(),
            link_from_object: Isometry3::identity(),
            local_aabb: shape.shape.compute_local_aabb(),
            allowed_links: Vec::new(),
            allowed_environment: Vec::new(),
        };
        let other = SharedShape::cuboid(0.01, 0.02, 0.015);
        let (_, world) = two_cubes();
        let (mut touching, mut apart) = (0, 0);
        for i in 0..600 {
            let t = i as Real * 0.21;
            let pose1 = parry::pose(&Isometry3::from_parts(
                Translation3::new(0.0, 0.0, 0.0),
                UnitQuaternion::from_euler_angles(0.3 * t, 0.1 * t, 0.0),
            ));
            let pose2 = parry::pose(&Isometry3::from_parts(
                Translation3::new(
                    0.07 * t.sin(),
                    0.07 * (0.7 * t).cos(),
                    0.05 + 0.05 * (0.3 * t).sin(),
                ),
                UnitQuaternion::from_euler_angles(0.2 * t, t, 0.3),
            ));
            for margin in [0.0, 0.005] {
                let names = || (String::new(), String::new());
                let ours = world
                    .hulled_touching(
                        &pose1,
                        &object.shape,
                        object.hull.as_ref(),
                        &pose2,
                        &other,
                        margin,
                        names,
                    )
                    .expect("supported");
                let mesh_only = world
                    .touching(&pose1, &object.shape, &pose2, &other, margin, names)
                    .expect("supported");
                assert_eq!(ours, mesh_only, "pose {i}, margin {margin}");
                if ours { touching += 1 } else { apart += 1 }
            }
        }
        // Both answers occur (the sweep crosses the mug's surface, handle included).
        assert!(
            touching > 50 && apart > 50,
            "{touching} touching, {apart} apart"
        );
    }
}
