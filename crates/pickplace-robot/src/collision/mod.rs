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

mod acm;

pub use acm::{AcmOptions, AcmReport, AllowedCollisionMatrix};

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
        })
    }

    /// A sphere.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-positive or non-finite radius.
    pub fn ball(radius: Real) -> Result<Self> {
        Ok(Self {
            shape: SharedShape::ball(positive("sphere radius", radius)?),
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
        Ok(Self { shape })
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
        Ok(Self { shape })
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

    /// The shape of a URDF geometry, with the pose correction for parry's conventions
    /// (parry's cylinder axis is y, URDF's is z).
    fn from_model_shape(shape: &Shape) -> Result<(Self, Isometry3)> {
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
                    },
                    y_to_z,
                )
            }
            // Robot links are checked as convex shapes: a link mesh becomes its convex hull
            // (conservative, and one GJK query instead of a triangle traversal); a flat mesh
            // with no hull stays a triangle mesh.
            Shape::Mesh { mesh, .. } => (
                Self::convex_hull(mesh).or_else(|_| Self::mesh(mesh))?,
                Isometry3::identity(),
            ),
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
}

#[derive(Debug, Clone)]
struct EnvironmentObject {
    name: String,
    shape: SharedShape,
    world_from_shape: Pose,
    /// Links allowed to touch this object.
    allowed_links: Vec<bool>,
}

#[derive(Debug, Clone)]
struct AttachedObject {
    name: String,
    link: usize,
    shape: SharedShape,
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
                let (shape, correction) = CollisionShape::from_model_shape(&g.shape)?;
                let local_aabb = shape.shape.compute_local_aabb();
                robot_shapes.push(RobotShape {
                    link,
                    shape: shape.shape,
                    link_from_shape: g.link_from_shape * correction,
                    local_aabb,
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
        self.environment.push(EnvironmentObject {
            name: name.to_owned(),
            shape: shape.shape,
            world_from_shape: pose,
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
        scratch
            .link_poses
            .resize(self.link_names.len(), Isometry3::identity());
        model.forward_kinematics(q, &mut scratch.link_poses)?;
        self.prepare_shapes(scratch, margin);
        Ok(())
    }

    fn prepare_shapes(&self, scratch: &mut CollisionScratch, margin: Real) {
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

    /// Visits colliding pairs until `visit` returns false.
    fn for_each_collision(
        &self,
        scratch: &mut CollisionScratch,
        margin: Real,
        visit: &mut dyn FnMut(BodyId, BodyId) -> bool,
    ) -> Result<()> {
        // Self-collision.
        for &(a, b) in &self.self_pairs {
            let (a, b) = (a as usize, b as usize);
            if !scratch.shape_aabbs[a].intersects(&scratch.shape_aabbs[b]) {
                continue;
            }
            let (sa, sb) = (&self.robot_shapes[a], &self.robot_shapes[b]);
            if self.touching(
                &scratch.shape_poses[a],
                &sa.shape,
                &scratch.shape_poses[b],
                &sb.shape,
                margin,
                || {
                    (
                        self.link_names[sa.link].clone(),
                        self.link_names[sb.link].clone(),
                    )
                },
            )? && !visit(BodyId::Link(sa.link), BodyId::Link(sb.link))
            {
                return Ok(());
            }
        }
        // Robot against environment.
        for (i, s) in self.robot_shapes.iter().enumerate() {
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
                if self.touching(
                    &scratch.shape_poses[i],
                    &s.shape,
                    &env.world_from_shape,
                    &env.shape,
                    margin,
                    || (self.link_names[s.link].clone(), env.name.clone()),
                )? && !visit(BodyId::Link(s.link), BodyId::Environment(e))
                {
                    return Ok(());
                }
            }
        }
        // Attached objects against robot and environment.
        for (k, a) in self.attached.iter().enumerate() {
            for (i, s) in self.robot_shapes.iter().enumerate() {
                if a.allowed_links[s.link]
                    || !scratch.attached_aabbs[k].intersects(&scratch.shape_aabbs[i])
                {
                    continue;
                }
                if self.touching(
                    &scratch.attached_poses[k],
                    &a.shape,
                    &scratch.shape_poses[i],
                    &s.shape,
                    margin,
                    || (a.name.clone(), self.link_names[s.link].clone()),
                )? && !visit(BodyId::Attached(k), BodyId::Link(s.link))
                {
                    return Ok(());
                }
            }
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
                if self.touching(
                    &scratch.attached_poses[k],
                    &a.shape,
                    &env.world_from_shape,
                    &env.shape,
                    margin,
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
    /// stops at the first such pair.
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
        self.prepare(model, q, scratch, options.margin)?;
        let mut found = false;
        self.for_each_collision(scratch, options.margin, &mut |_, _| {
            found = true;
            false
        })?;
        Ok(found)
    }

    /// Every colliding pair (link pairs reported once even when several shapes touch),
    /// sorted.
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
        self.prepare(model, q, scratch, options.margin)?;
        let mut pairs = Vec::new();
        self.for_each_collision(scratch, options.margin, &mut |a, b| {
            pairs.push((a, b));
            true
        })?;
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
        self.prepare(model, q, scratch, 0.0)?;
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
                if sa.link == sb.link || !scratch.shape_aabbs[a].intersects(&scratch.shape_aabbs[b])
                {
                    continue;
                }
                if self.touching(
                    &scratch.shape_poses[a],
                    &sa.shape,
                    &scratch.shape_poses[b],
                    &sb.shape,
                    0.0,
                    || {
                        (
                            self.link_names[sa.link].clone(),
                            self.link_names[sb.link].clone(),
                        )
                    },
                )? {
                    pairs.push((sa.link.min(sb.link), sa.link.max(sb.link)));
                }
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        Ok(pairs)
    }
}
