//! Plans played back: the robot's links posed by forward kinematics at every trajectory
//! sample, the object carried by the link that holds it between a grasp and its release, and
//! the environment; as pictures of single frames ([`PlanView::render_frame`]) and as an
//! animated glTF document ([`PlanView::gltf`]) with one keyframe per trajectory sample.
//!
//! This is the last step of the paper's pipeline (Harada et al., Fig. 8): looking at the key
//! poses and the trajectory that joins them.

use crate::camera::{Camera, OBLIQUE_VIEW};
use crate::error::{Error, MotionErrorKind, Result};
use crate::glb::{GltfBuilder, NodeId};
use crate::image::{Colour, Image};
use crate::raster::{RenderOptions, render};
use crate::robot::RobotGeometry;
use crate::scene::{Geometry, Instance, Paint, Scene, check_pose};
use pickplace_geometry::math::{Isometry3, Point3, Real};
use pickplace_robot::RobotModel;
use std::sync::Arc;

/// How far below the object's lowest point [`PlanView::camera`] frames the scene (m).
pub const CROP_BELOW_OBJECT: Real = 0.25;

/// An object held by a link from `grasp_time` to `release_time` (both included).
#[derive(Debug, Clone, PartialEq)]
pub struct Grip {
    /// Index of the holding link in the robot model.
    pub link: usize,
    /// The object's pose in the link frame while held.
    pub link_from_object: Isometry3,
    /// When the gripper closes (s).
    pub grasp_time: Real,
    /// When it opens (s); `None` when the object is never released.
    pub release_time: Option<Real>,
}

/// A robot motion: configurations at times, and the grips on the object.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// Pose of the robot's root link in the world.
    pub world_from_root: Isometry3,
    /// Sample times (s), non-decreasing.
    pub times: Vec<Real>,
    /// One configuration per time, one value per robot variable
    /// ([`RobotModel::variable_names`] order).
    pub configurations: Vec<Vec<Real>>,
    /// The grips, in any order. When two overlap (a handover), the object follows the one
    /// grasped last.
    pub grips: Vec<Grip>,
}

/// A rigid mesh in the world: an environment part, or the object at its start pose.
#[derive(Debug, Clone, PartialEq)]
pub struct Prop {
    /// Name (the glTF node's name).
    pub name: String,
    /// Triangles in the mesh frame.
    pub geometry: Arc<Geometry>,
    /// Where the mesh is (for the object: where it starts).
    pub world_from_mesh: Isometry3,
    /// Colour.
    pub colour: Colour,
}

/// A motion evaluated at every sample: link and object poses, ready to draw or export.
#[derive(Debug, Clone)]
pub struct PlanView {
    robot: RobotGeometry,
    object: Prop,
    environment: Vec<Prop>,
    world_from_root: Isometry3,
    times: Vec<Real>,
    /// `[frame][link]`.
    root_from_links: Vec<Vec<Isometry3>>,
    world_from_object: Vec<Isometry3>,
}

impl PlanView {
    /// Evaluates `motion` for `robot` (whose shapes are `geometry`), carrying `object`.
    ///
    /// # Errors
    /// [`MotionErrorKind`]: no frame, as many times as configurations, times finite and
    /// non-decreasing, one finite value per variable, grips on existing links with ordered
    /// finite times; [`crate::GeometryErrorKind::NonFinitePose`] for a bad pose.
    pub fn new(
        robot: &RobotModel,
        geometry: RobotGeometry,
        motion: &Motion,
        object: Prop,
        environment: Vec<Prop>,
    ) -> Result<Self> {
        let motion_error = |kind| Error::Motion { kind };
        let n = motion.times.len();
        if n == 0 {
            return Err(motion_error(MotionErrorKind::Empty));
        }
        if motion.configurations.len() != n {
            return Err(motion_error(MotionErrorKind::FrameCount {
                times: n,
                configurations: motion.configurations.len(),
            }));
        }
        for (index, &t) in motion.times.iter().enumerate() {
            if !t.is_finite() || (index > 0 && t < motion.times[index - 1]) {
                return Err(motion_error(MotionErrorKind::TimesNotIncreasing { index }));
            }
        }
        let variables = robot.variable_count();
        for (frame, q) in motion.configurations.iter().enumerate() {
            let found = q.iter().position(|v| !v.is_finite()).unwrap_or(q.len());
            if q.len() != variables || found != q.len() {
                return Err(motion_error(MotionErrorKind::Configuration {
                    frame,
                    expected: variables,
                    found,
                }));
            }
        }
        let link_count = robot.links().len();
        for (grip, g) in motion.grips.iter().enumerate() {
            if g.link >= link_count {
                return Err(motion_error(MotionErrorKind::UnknownLink {
                    grip,
                    link: g.link,
                    count: link_count,
                }));
            }
            let ordered = g.grasp_time.is_finite()
                && g.release_time
                    .is_none_or(|r| r.is_finite() && r >= g.grasp_time);
            if !ordered {
                return Err(motion_error(MotionErrorKind::GripTimes { grip }));
            }
            check_pose(&g.link_from_object, "grip")?;
        }
        check_pose(&motion.world_from_root, "robot root")?;
        check_pose(&object.world_from_mesh, "object")?;
        for prop in &environment {
            check_pose(&prop.world_from_mesh, "environment")?;
        }

        let mut root_from_links = Vec::with_capacity(n);
        let mut world_from_object = Vec::with_capacity(n);
        let mut resting = object.world_from_mesh;
        for (&t, q) in motion.times.iter().zip(&motion.configurations) {
            let poses = robot
                .link_poses(q)
                .map_err(|source| Error::Robot { source })?;
            // The grip grasped last among those holding at `t` (a handover has two).
            let holding = motion
                .grips
                .iter()
                .filter(|g| g.grasp_time <= t && g.release_time.is_none_or(|r| t <= r))
                .max_by(|a, b| a.grasp_time.total_cmp(&b.grasp_time));
            if let Some(g) = holding {
                resting = motion.world_from_root * poses[g.link] * g.link_from_object;
            }
            world_from_object.push(resting);
            root_from_links.push(poses);
        }
        Ok(Self {
            robot: geometry,
            object,
            environment,
            world_from_root: motion.world_from_root,
            times: motion.times.clone(),
            root_from_links,
            world_from_object,
        })
    }

    /// Number of frames (trajectory samples).
    pub fn frame_count(&self) -> usize {
        self.times.len()
    }

    /// The sample times (s).
    pub fn times(&self) -> &[Real] {
        &self.times
    }

    /// The frame shown at `time`: the last sample at or before it (the first for earlier
    /// times).
    pub fn frame_at_time(&self, time: Real) -> usize {
        self.times.partition_point(|&t| t <= time).saturating_sub(1)
    }

    /// Every link's pose in the world at a frame (`None` out of range).
    pub fn world_from_links(&self, frame: usize) -> Option<Vec<Isometry3>> {
        let poses = self.root_from_links.get(frame)?;
        Some(poses.iter().map(|p| self.world_from_root * p).collect())
    }

    /// The object's pose at a frame (`None` out of range).
    pub fn world_from_object(&self, frame: usize) -> Option<Isometry3> {
        self.world_from_object.get(frame).copied()
    }

    /// The scene at a frame (the last frame for an index out of range): environment, object,
    /// robot.
    ///
    /// # Errors
    /// None in practice (poses are checked in [`PlanView::new`]).
    pub fn scene_at(&self, frame: usize) -> Result<Scene> {
        let frame = frame.min(self.frame_count() - 1);
        let mut scene = Scene::new();
        for prop in &self.environment {
            scene.push(Instance::new(
                prop.geometry.clone(),
                prop.world_from_mesh,
                Paint::Uniform(prop.colour),
            )?);
        }
        let object_pose = self.world_from_object[frame];
        scene.push(Instance::new(
            self.object.geometry.clone(),
            object_pose,
            Paint::Uniform(self.object.colour),
        )?);
        let links: Vec<Isometry3> = self.root_from_links[frame]
            .iter()
            .map(|p| self.world_from_root * p)
            .collect();
        self.robot.add_to_scene(&mut scene, &links)?;
        Ok(scene)
    }

    /// A camera that frames the environment, the object's whole path and the robot at the
    /// first frame down to [`CROP_BELOW_OBJECT`] under the object's lowest point, seen obliquely from the front ([`OBLIQUE_VIEW`]) in an image of
    /// `aspect = width / height`.
    ///
    /// # Errors
    /// None in practice (as [`PlanView::scene_at`]).
    pub fn camera(&self, aspect: Real) -> Result<Camera> {
        let scene = self.scene_at(0)?;
        let mut bounds = scene
            .bounds()
            .unwrap_or((Point3::origin(), Point3::origin()));
        let mut object_low = Real::INFINITY;
        for pose in &self.world_from_object {
            if let Some((lo, hi)) = self.object.geometry.bounds(pose) {
                bounds = (bounds.0.inf(&lo), bounds.1.sup(&hi));
                object_low = object_low.min(lo.z);
            }
        }
        // What happens is on and above the work surface: table legs and the robot's stand more
        // than CROP_BELOW_OBJECT under the object's lowest point are left out of the framing
        // (they are still drawn where they fall in the picture).
        if object_low.is_finite() {
            bounds.0.z = bounds
                .0
                .z
                .max(object_low - CROP_BELOW_OBJECT)
                .min(bounds.1.z);
        }
        Ok(Camera::fit_with_aspect(bounds, OBLIQUE_VIEW, aspect))
    }

    /// Renders a frame, with `camera` or else [`PlanView::camera`].
    ///
    /// # Errors
    /// As [`render`].
    pub fn render_frame(
        &self,
        frame: usize,
        camera: Option<&Camera>,
        options: &RenderOptions,
    ) -> Result<Image> {
        let scene = self.scene_at(frame)?;
        let camera = match camera {
            Some(c) => *c,
            None => self.camera(f64::from(options.width) / f64::from(options.height.max(1)))?,
        };
        render(&scene, &camera, options)
    }

    /// An animated glTF document: a `robot` node at the root's world pose with one child node
    /// per link (nested as in the kinematic tree, each with its merged shapes as a mesh), an
    /// `object` node and one node per environment part. Every link whose pose relative to its
    /// parent changes, and the object, get translation and rotation channels with one
    /// keyframe per trajectory sample.
    ///
    /// glTF needs strictly increasing keyframe times in `f32`: a sample at the same time as
    /// the previous one (a gripper closing in place, say) is moved to the next `f32` after it.
    ///
    /// # Errors
    /// None in practice; propagated from the [`GltfBuilder`].
    pub fn gltf(&self, animation_name: &str) -> Result<GltfBuilder> {
        let mut gltf = GltfBuilder::new(animation_name);
        for prop in &self.environment {
            let mesh = gltf.add_mesh(&prop.name, &prop.geometry, &Paint::Uniform(prop.colour))?;
            gltf.add_node(&prop.name, Some(mesh), None, &prop.world_from_mesh)?;
        }
        let robot = gltf.add_node("robot", None, None, &self.world_from_root)?;
        let link_count = self.robot.link_count();
        let parent_from_link = |frame: usize, link: usize| -> Isometry3 {
            let poses = &self.root_from_links[frame];
            match self.robot.parent(link) {
                Some(p) => poses[p].inv_mul(&poses[link]),
                None => poses[link],
            }
        };
        // Links are created parents first: a parent's index precedes its children's in the
        // model (joints are in tree order), but walk the tree to be independent of that.
        let mut nodes: Vec<Option<NodeId>> = vec![None; link_count];
        let mut order: Vec<usize> = (0..link_count)
            .filter(|&l| self.robot.parent(l).is_none())
            .collect();
        let mut k = 0;
        while k < order.len() {
            let link = order[k];
            order.extend((0..link_count).filter(|&c| self.robot.parent(c) == Some(link)));
            k += 1;
        }
        for &link in &order {
            let parent = self
                .robot
                .parent(link)
                .and_then(|p| nodes[p])
                .unwrap_or(robot);
            let name = self.robot.link_name(link).unwrap_or("link").to_owned();
            let mesh = match self.robot.link_geometry(link) {
                Some(g) => {
                    Some(gltf.add_mesh(&name, g, &Paint::Uniform(self.robot.link_colour(link)))?)
                }
                None => None,
            };
            nodes[link] =
                Some(gltf.add_node(&name, mesh, Some(parent), &parent_from_link(0, link))?);
        }
        let object_mesh = gltf.add_mesh(
            &self.object.name,
            &self.object.geometry,
            &Paint::Uniform(self.object.colour),
        )?;
        let object = gltf.add_node(
            &self.object.name,
            Some(object_mesh),
            None,
            &self.world_from_object[0],
        )?;

        let times = strictly_increasing_f32_times(&self.times);
        for &link in &order {
            let Some(node) = nodes[link] else { continue };
            let poses: Vec<Isometry3> = (0..self.frame_count())
                .map(|f| parent_from_link(f, link))
                .collect();
            if poses.iter().any(|p| *p != poses[0]) {
                gltf.animate_poses(node, &times, &poses)?;
            }
        }
        gltf.animate_poses(object, &times, &self.world_from_object)?;
        Ok(gltf)
    }
}

/// Times made non-negative and strictly increasing once rounded to `f32` (a time not after
/// the previous one moves to the next `f32`), as glTF animation inputs require.
pub fn strictly_increasing_f32_times(times: &[Real]) -> Vec<Real> {
    let mut out = Vec::with_capacity(times.len());
    let mut previous: Option<f32> = None;
    for &t in times {
        let mut f = if t.is_finite() {
            t.max(0.0) as f32
        } else {
            0.0
        };
        if let Some(p) = previous
            && f <= p
        {
            // p >= 0 and finite, so the next representable f32 is one bit pattern up.
            f = f32::from_bits(p.to_bits() + 1);
        }
        previous = Some(f);
        out.push(f64::from(f));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_times_become_strictly_increasing_in_f32() {
        let t = strictly_increasing_f32_times(&[0.0, 0.5, 0.5, 0.5 + 1e-12, 1.0, -3.0]);
        assert_eq!(t.len(), 6);
        for w in t.windows(2).take(4) {
            assert!((w[1] as f32) > (w[0] as f32), "{t:?}");
        }
        assert_eq!(t[0], 0.0);
        assert_eq!(t[4], 1.0);
        assert!(
            t[5] > t[4],
            "a time going back is moved after the previous one"
        );
        assert!((t[3] - 0.5).abs() < 1e-6);
    }
}
