//! A parallel gripper derived from the URDF, never assumed (paper §III-B.1: the grasp is
//! "a pair of contact patches of the two fingers"; this module tells where those fingers are).
//!
//! Given an arm (its variables), the hand is every link below the arm's last moving link. Its
//! *drives* are the actuated joints in that subtree (mimic joints follow them through the
//! model); its *fingers* are the links those joints move, split into the two sides that close
//! on each other. Everything else is measured by forward kinematics on the fingers' collision
//! geometry:
//! - the **opening** as a function of one closing parameter `s ∈ [0, 1]` (every drive moved
//!   linearly from its closed to its open end): the distance between the two sides' geometry,
//!   tabulated once, checked to grow with `s`; so revolute fingers, fingers whose zero is the
//!   closed position and mimic chains all get the right command;
//! - the **tool point** (TCP): midway between the two pads when closed, at the pads' centre,
//!   `z` the approach direction (palm → finger tips) and `y` the closing direction, plus an
//!   optional offset;
//! - the pads' size, the fingers' length and thickness, and the palm's box in the TCP frame,
//!   for the grasp planner's simple gripper model.
//!
//! The closing command for a grasp of width `w` is the `s` whose opening is `w − squeeze`.

use crate::model::{JointType, JointValueSource, RobotModel, Shape};
use parry3d_f64::query;
use parry3d_f64::shape::SharedShape;
use pickplace_geometry::math::nalgebra::Rotation3;
use pickplace_geometry::math::{
    Isometry3, Matrix3, Point3, Real, Translation3, UnitQuaternion, Vector3,
};
use pickplace_geometry::mesh::TriMesh;
use pickplace_geometry::parry;

/// Samples of the opening table.
const TABLE_SAMPLES: usize = 129;
/// The least largest opening (m) of a gripper: one that opens less holds nothing.
const MIN_OPENING: Real = 0.005;
/// How far (m) a fixed jaw's pad stands from the object at a grasp, so that the hand comes
/// down past the object without rubbing it; the moving jaw closes that much farther.
pub const FIXED_JAW_CLEARANCE: Real = 0.001;
/// The largest gap (m) between a holding hand's finger pad and the object (the validator's
/// rule; the planner drops grasps that break it, `pickplace::hand_fit`).
pub const GRIP_GAP: Real = 0.002;
/// Penetration (m) of a holding pad tolerated beyond the gripper's squeeze (the pads are
/// convex hulls, the object a triangle mesh).
pub const GRIP_TOLERANCE: Real = 0.0005;
/// Points within this distance (m) of a finger's innermost point, along the closing axis, are
/// its pad.
const PAD_TOLERANCE: Real = 0.001;

/// Errors of [`Gripper::derive`]: each says what the hand lacks.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GripperError {
    /// The arm has no variable.
    #[error("the arm has no joints")]
    NoArmJoints,
    /// The arm's variables do not form one serial chain.
    #[error("the arm's joints {first:?} and {second:?} are not on one chain")]
    NotAChain {
        /// A joint.
        first: String,
        /// A joint that is neither its ancestor nor its descendant.
        second: String,
    },
    /// No actuated joint below the arm's last link.
    #[error("no actuated joint below link {tip:?}: the arm has no gripper")]
    NoDrive {
        /// The arm's last moving link.
        tip: String,
    },
    /// A drive that cannot close a gripper.
    #[error("gripper joint {joint:?}: {reason}")]
    BadDrive {
        /// The joint.
        joint: String,
        /// What is wrong.
        reason: &'static str,
    },
    /// The moving links do not form two fingers.
    #[error(
        "the gripper below {tip:?} has {found} moving finger(s) with geometry; a parallel gripper needs two"
    )]
    NotTwoFingers {
        /// The arm's last moving link.
        tip: String,
        /// How many moving subtrees with collision geometry were found.
        found: usize,
    },
    /// The opening does not grow from the closed to the open end.
    #[error("the gripper below {tip:?} {reason}")]
    CannotOpen {
        /// The arm's last moving link.
        tip: String,
        /// What was measured.
        reason: String,
    },
    /// The collision library could not measure a distance.
    #[error("the gripper below {tip:?}: the collision library cannot measure {what}")]
    Unmeasurable {
        /// The arm's last moving link.
        tip: String,
        /// Which pair.
        what: String,
    },
    /// An option out of range.
    #[error("gripper option {name}: {reason}")]
    BadOption {
        /// The option.
        name: &'static str,
        /// What is wrong.
        reason: &'static str,
    },
}

/// Overrides of what [`Gripper::derive`] measures (every field optional but `squeeze`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GripperOptions {
    /// How much narrower than the grasp width the fingers are commanded (m): the pads' squeeze
    /// on the object (default 1 mm).
    pub squeeze: Real,
    /// Pad size along the approach axis (m): the distal part of the fingers' inner faces that
    /// carries the pads (default: the whole inner face).
    pub pad_depth: Option<Real>,
    /// Pad size across the finger (m) (default: the inner face's width).
    pub pad_width: Option<Real>,
    /// Largest opening used (m) (default: the measured one).
    pub opening_max: Option<Real>,
    /// Offset of the tool point in the derived TCP frame (m).
    pub tool_offset: Vector3,
}

impl Default for GripperOptions {
    fn default() -> Self {
        Self {
            squeeze: 0.001,
            pad_depth: None,
            pad_width: None,
            opening_max: None,
            tool_offset: Vector3::zeros(),
        }
    }
}

/// An actuated joint of the gripper and its closed and open ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    /// The model variable.
    pub variable: usize,
    /// Its value when the gripper is closed.
    pub closed: Real,
    /// Its value when the gripper is fully open.
    pub open: Real,
}

/// A convex piece of a finger (in its link's frame).
#[derive(Debug, Clone)]
struct Piece {
    link: usize,
    shape: SharedShape,
    /// Sample points of the piece in the link frame (corners, vertices).
    points: Vec<Point3>,
}

/// A parallel gripper as the URDF builds it. See the [module docs](self).
#[derive(Debug, Clone)]
pub struct Gripper {
    arm_tip: usize,
    hand_links: Vec<usize>,
    finger_links: [Vec<usize>; 2],
    drives: Vec<Drive>,
    pieces: [Vec<Piece>; 2],
    /// `(s, opening)`, `s` ascending, opening non-decreasing.
    table: Vec<(Real, Real)>,
    opening_min: Real,
    opening_max: Real,
    squeeze: Real,
    tip_from_tcp: Isometry3,
    pad_width: Real,
    pad_depth: Real,
    finger_length: Real,
    finger_thickness: Real,
    palm: (Point3, Point3),
    /// One jaw moves against one fixed to the hand (side 1): the tool point lies on the fixed
    /// jaw's pad.
    fixed_jaw: bool,
}

mod measure;
mod split;

pub(crate) use split::split_one_jaw_hands;
pub use split::{
    DECOMPOSITION_CONCAVITY, DECOMPOSITION_MAX_PIECES, DECOMPOSITION_RESOLUTION, SplitLink,
    convex_pieces,
};
#[cfg(test)]
mod tests;

impl Gripper {
    /// The arm's last moving link, to which the hand is attached.
    pub fn arm_tip(&self) -> usize {
        self.arm_tip
    }

    /// The tool point (TCP) in the arm tip's frame: `z` approach, `y` closing.
    pub fn tip_from_tcp(&self) -> &Isometry3 {
        &self.tip_from_tcp
    }

    /// The hand: the arm tip and every link below it.
    pub fn hand_links(&self) -> &[usize] {
        &self.hand_links
    }

    /// The links of each finger.
    pub fn finger_links(&self) -> &[Vec<usize>; 2] {
        &self.finger_links
    }

    /// The links that carry each finger's pads (the pieces of geometry reaching farthest
    /// towards the finger tips: what touches a grasped object), sorted, without repeats.
    pub fn pad_links(&self) -> [Vec<usize>; 2] {
        self.pieces.clone().map(|pieces| {
            let mut links: Vec<usize> = pieces.iter().map(|p| p.link).collect();
            links.sort_unstable();
            links.dedup();
            links
        })
    }

    /// The actuated joints that close the gripper.
    pub fn drives(&self) -> &[Drive] {
        &self.drives
    }

    /// The opening when closed and fully open (m).
    pub fn opening_range(&self) -> (Real, Real) {
        (self.opening_min, self.opening_max)
    }

    /// The squeeze (m): how much narrower than a grasp the fingers are commanded.
    pub fn squeeze(&self) -> Real {
        self.squeeze
    }

    /// Pad size across the finger and along the approach axis (m).
    pub fn pad_size(&self) -> (Real, Real) {
        (self.pad_width, self.pad_depth)
    }

    /// Finger length along the approach axis and thickness along the closing axis (m).
    pub fn finger_size(&self) -> (Real, Real) {
        (self.finger_length, self.finger_thickness)
    }

    /// The palm's axis-aligned box in the TCP frame (lower and upper corners, m).
    pub fn palm_box(&self) -> (Point3, Point3) {
        self.palm
    }

    /// The opening (m) at closing parameter `s ∈ [0, 1]` (clamped), from the table.
    pub fn opening_at(&self, s: Real) -> Real {
        let s = s.clamp(0.0, 1.0);
        let x = s * (self.table.len() - 1) as Real;
        let i = (x.floor() as usize).min(self.table.len() - 2);
        let t = x - i as Real;
        self.table[i].1 * (1.0 - t) + self.table[i + 1].1 * t
    }

    /// The closing parameter whose opening is `opening` (clamped into the range).
    pub fn parameter_for(&self, opening: Real) -> Real {
        let o = opening.clamp(self.table[0].1, self.table[self.table.len() - 1].1);
        let i = self.table.partition_point(|&(_, x)| x < o);
        if i == 0 {
            return 0.0;
        }
        let (s0, o0) = self.table[i - 1];
        let (s1, o1) = self.table[i.min(self.table.len() - 1)];
        if o1 - o0 <= 1e-12 {
            return s0;
        }
        s0 + (s1 - s0) * (o - o0) / (o1 - o0)
    }

    /// Sets the drives of `q` (every model variable) at closing parameter `s`.
    pub fn set_parameter(&self, q: &mut [Real], s: Real) {
        let s = s.clamp(0.0, 1.0);
        for d in &self.drives {
            if let Some(x) = q.get_mut(d.variable) {
                *x = d.closed + s * (d.open - d.closed);
            }
        }
    }

    /// Sets the drives of `q` so that the pads are `opening` apart (m).
    pub fn set_opening(&self, q: &mut [Real], opening: Real) {
        self.set_parameter(q, self.parameter_for(opening));
    }

    /// Sets the drives of `q` to grasp an object `width` wide: the pads at `width − squeeze`
    /// (with a fixed jaw, at `width +` [`FIXED_JAW_CLEARANCE`] `− squeeze`: the fixed jaw
    /// stands that clearance off the object).
    pub fn set_grasp(&self, q: &mut [Real], width: Real) {
        let clearance = if self.fixed_jaw {
            FIXED_JAW_CLEARANCE
        } else {
            0.0
        };
        self.set_opening(q, width + clearance - self.squeeze);
    }

    /// Sets the drives of `q` fully open (at the largest opening used).
    pub fn set_open(&self, q: &mut [Real]) {
        self.set_opening(q, self.opening_max);
    }

    /// The closing parameter of `q`'s drives (the first drive's, which the others follow).
    pub fn parameter_of(&self, q: &[Real]) -> Real {
        self.drives
            .first()
            .and_then(|d| {
                let span = d.open - d.closed;
                q.get(d.variable).map(|&x| {
                    if span.abs() > 1e-12 {
                        (x - d.closed) / span
                    } else {
                        0.0
                    }
                })
            })
            .unwrap_or(0.0)
    }

    /// The signed distance (m) of each finger to an object (negative: penetration depth), for
    /// the link poses `world_from_links` and the object's `world_from_object`.
    ///
    /// # Errors
    /// [`GripperError::Unmeasurable`] when the collision library cannot measure a pair.
    pub fn finger_gaps(
        &self,
        world_from_links: &[Isometry3],
        object: &GripObject,
        world_from_object: &Isometry3,
    ) -> Result<[Real; 2], GripperError> {
        Ok([
            self.finger_gap(0, world_from_links, object, world_from_object)?,
            self.finger_gap(1, world_from_links, object, world_from_object)?,
        ])
    }

    /// [`Gripper::finger_gaps`] of one side (0: the first finger, the moving jaw of a hand
    /// with a fixed one; 1: the other).
    ///
    /// # Errors
    /// As [`Gripper::finger_gaps`].
    pub fn finger_gap(
        &self,
        side: usize,
        world_from_links: &[Isometry3],
        object: &GripObject,
        world_from_object: &Isometry3,
    ) -> Result<Real, GripperError> {
        let object_pose = parry::pose(world_from_object);
        let mut gap = Real::INFINITY;
        for piece in self.pieces.get(side).into_iter().flatten() {
            let Some(pose) = world_from_links.get(piece.link) else {
                continue;
            };
            let pose = parry::pose(pose);
            let unmeasurable = || GripperError::Unmeasurable {
                tip: format!("#{}", self.arm_tip),
                what: "a finger and the object".to_owned(),
            };
            let d =
                match query::contact(&pose, &*piece.shape.0, &object_pose, &*object.shape.0, 0.0)
                    .map_err(|_| unmeasurable())?
                {
                    Some(c) if c.dist <= 0.0 => c.dist,
                    _ => {
                        query::distance(&pose, &*piece.shape.0, &object_pose, &*object.shape.0)
                            .map_err(|_| unmeasurable())?
                            .distance
                    }
                };
            gap = gap.min(d);
        }
        Ok(gap)
    }
}

/// An object the fingers may hold, for [`Gripper::finger_gaps`].
#[derive(Debug, Clone)]
pub struct GripObject {
    shape: SharedShape,
}

impl GripObject {
    /// The object's triangle mesh (its frame). A closed mesh's inside counts as inside: the
    /// penetration of a finger is measured.
    ///
    /// # Errors
    /// [`GripperError::BadOption`] when the collision library refuses the mesh.
    pub fn new(mesh: &TriMesh) -> Result<Self, GripperError> {
        let vertices = mesh.vertices().iter().map(parry::point).collect();
        let shape = SharedShape::trimesh_with_flags(
            vertices,
            mesh.triangles().to_vec(),
            parry3d_f64::shape::TriMeshFlags::ORIENTED
                | parry3d_f64::shape::TriMeshFlags::FIX_INTERNAL_EDGES,
        )
        .or_else(|_| {
            SharedShape::trimesh(
                mesh.vertices().iter().map(parry::point).collect(),
                mesh.triangles().to_vec(),
            )
        })
        .map_err(|_| GripperError::BadOption {
            name: "object mesh",
            reason: "the collision library refused the triangle mesh",
        })?;
        Ok(Self { shape })
    }
}
