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

impl Gripper {
    /// Derives the gripper at the end of an arm whose model variables are `arm_variables`.
    ///
    /// # Errors
    /// A [`GripperError`] saying what the hand lacks: no drive, not two fingers, an opening
    /// that does not grow, a continuous or unlimited drive.
    pub fn derive(
        model: &RobotModel,
        arm_variables: &[usize],
        options: &GripperOptions,
    ) -> Result<Self, GripperError> {
        check_options(options)?;
        let arm_tip = arm_tip(model, arm_variables)?;
        let tip_name = model.links()[arm_tip].name.clone();
        let subtree = subtree(model, arm_tip);
        // Drives: actuated joints of the subtree.
        let mut drive_vars: Vec<usize> = Vec::new();
        for &l in &subtree {
            if let Some(j) = model.links()[l].parent_joint
                && let JointValueSource::Variable(v) = model.joints()[j].source
            {
                drive_vars.push(v);
            }
        }
        if drive_vars.is_empty() {
            return Err(GripperError::NoDrive { tip: tip_name });
        }
        for &v in &drive_vars {
            let joint = model.variable_joint(v);
            if joint.joint_type == JointType::Continuous
                || !joint.limits.lower.is_finite()
                || !joint.limits.upper.is_finite()
            {
                return Err(GripperError::BadDrive {
                    joint: joint.name.clone(),
                    reason: "a finger joint needs finite limits (it is continuous or unlimited)",
                });
            }
            if joint.limits.upper - joint.limits.lower <= 1e-9 {
                return Err(GripperError::BadDrive {
                    joint: joint.name.clone(),
                    reason: "its limits are equal: the finger cannot move",
                });
            }
        }
        // Fingers: links moved by a drive, grouped by the first moving joint below the hand.
        let moves = |joint: usize| match model.joints()[joint].source {
            JointValueSource::Fixed => false,
            JointValueSource::Variable(v) | JointValueSource::Mimic { variable: v, .. } => {
                drive_vars.contains(&v)
            }
        };
        let mut below = vec![false; model.links().len()];
        below[arm_tip] = true;
        for &l in &subtree {
            below[l] = true;
        }
        let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
        for &l in &subtree {
            let first_moving = model
                .joint_path(l)
                .into_iter()
                .filter(|&j| below[model.joints()[j].parent_link])
                .find(|&j| moves(j));
            if let Some(j) = first_moving {
                match groups.iter_mut().find(|(k, _)| *k == j) {
                    Some((_, links)) => links.push(l),
                    None => groups.push((j, vec![l])),
                }
            }
        }
        let driver = |joint: usize| match model.joints()[joint].source {
            JointValueSource::Variable(v) | JointValueSource::Mimic { variable: v, .. } => v,
            JointValueSource::Fixed => usize::MAX,
        };
        let mut with_geometry: Vec<(usize, Vec<usize>, Vec<Piece>)> = Vec::new();
        for (j, links) in &groups {
            let pieces: Vec<Piece> = links.iter().flat_map(|&l| pieces_of(model, l)).collect();
            if !pieces.is_empty() {
                with_geometry.push((driver(*j), links.clone(), pieces));
            }
        }
        // One moving jaw closing against the hand: the fixed jaw is the hand's geometry that
        // no drive moves (the links below the arm's tip, else the tip's own geometry).
        let fixed_jaw = drive_vars.len() == 1 && with_geometry.len() == 1;
        if fixed_jaw {
            let moving: Vec<usize> = groups.iter().flat_map(|(_, l)| l.iter().copied()).collect();
            let mut links: Vec<usize> = subtree
                .iter()
                .copied()
                .filter(|l| !moving.contains(l))
                .collect();
            let mut pieces: Vec<Piece> = links.iter().flat_map(|&l| pieces_of(model, l)).collect();
            if pieces.is_empty() {
                links = vec![arm_tip];
                pieces = pieces_of(model, arm_tip);
            }
            if !pieces.is_empty() {
                with_geometry.push((usize::MAX, links, pieces));
            }
        }
        if drive_vars.len() > 2 {
            return Err(GripperError::BadDrive {
                joint: model.variable_joint(drive_vars[2]).name.clone(),
                reason: "a parallel gripper has one or two independent finger joints; this is a third",
            });
        }
        if with_geometry.len() < 2 {
            return Err(GripperError::NotTwoFingers {
                tip: tip_name,
                found: with_geometry.len(),
            });
        }
        let mut sample = Sampler {
            model,
            arm_tip,
            q: model.zero_configuration(),
        };
        // Each drive's open end: the limit at which the fingers are farther apart (measured
        // between the two most distant finger groups, the others held mid-range).
        let mids: Vec<Drive> = drive_vars
            .iter()
            .map(|&v| {
                let l = model.variable_joint(v).limits;
                let mid = 0.5 * (l.lower + l.upper);
                Drive {
                    variable: v,
                    closed: mid,
                    open: mid,
                }
            })
            .collect();
        // Split the moving groups into the two fingers. Two drives: one finger each. One drive:
        // the fingers move towards each other, so a group's side is the sign of its motion
        // over the drive's stroke along the largest motion.
        let side_of: Vec<usize> = if fixed_jaw {
            // The moving jaw first, the fixed one second.
            (0..with_geometry.len())
                .map(|i| usize::from(i > 0))
                .collect()
        } else if drive_vars.len() == 2 {
            with_geometry
                .iter()
                .map(|(v, _, _)| usize::from(*v == drive_vars[1]))
                .collect()
        } else {
            let at = |sample: &mut Sampler<'_>, lower: bool| {
                let ends: Vec<Drive> = mids
                    .iter()
                    .map(|d| {
                        let l = model.variable_joint(d.variable).limits;
                        let x = if lower { l.lower } else { l.upper };
                        Drive {
                            closed: x,
                            open: x,
                            ..*d
                        }
                    })
                    .collect();
                sample.set(&ends, 0.0);
                let poses = sample.hand_poses();
                with_geometry
                    .iter()
                    .map(|(_, _, pieces)| centroid(pieces, &poses))
                    .collect::<Vec<Point3>>()
            };
            let from = at(&mut sample, true);
            let to = at(&mut sample, false);
            let motion: Vec<Vector3> = from.iter().zip(&to).map(|(a, b)| b - a).collect();
            let largest = motion
                .iter()
                .copied()
                .max_by(|a, b| a.norm().total_cmp(&b.norm()))
                .unwrap_or_else(Vector3::zeros);
            motion
                .iter()
                .map(|m| usize::from(m.dot(&largest) < 0.0))
                .collect()
        };
        let mut sides: [(Vec<usize>, Vec<Piece>); 2] = Default::default();
        for (i, (_, links, pieces)) in with_geometry.into_iter().enumerate() {
            sides[side_of[i]].0.extend(links);
            sides[side_of[i]].1.extend(pieces);
        }
        if sides.iter().any(|(_, pieces)| pieces.is_empty()) {
            return Err(GripperError::NotTwoFingers {
                tip: tip_name,
                found: 1,
            });
        }
        // The line between the fingers, at mid stroke.
        sample.set(&mids, 0.0);
        let poses = sample.hand_poses();
        let (ca, cb) = (centroid(&sides[0].1, &poses), centroid(&sides[1].1, &poses));
        let axis = (cb - ca)
            .try_normalize(1e-9)
            .ok_or_else(|| GripperError::NotTwoFingers {
                tip: tip_name.clone(),
                found: 1,
            })?;
        let mid_point = Point3::from((ca.coords + cb.coords) * 0.5);
        let [(links_a, pieces_a), (links_b, pieces_b)] = sides;
        // The pads: on each side, the pieces of geometry that reach farthest towards the finger
        // tips (within 5 mm), the approach being roughly from the hand's origin to the fingers, across the
        // line between them. Proximal links (PR2's, TALOS's) and cross bars (Baxter's) are not pads.
        let rough_approach = (mid_point.coords - axis * mid_point.coords.dot(&axis))
            .try_normalize(1e-6)
            .unwrap_or_else(|| {
                axis.cross(&Vector3::x())
                    .try_normalize(1e-6)
                    .unwrap_or(Vector3::z())
            });
        let pads_of = |pieces: Vec<Piece>| -> Vec<Piece> {
            let reach = |piece: &Piece| {
                piece
                    .points
                    .iter()
                    .map(|p| (poses[piece.link] * p).coords.dot(&rough_approach))
                    .fold(Real::NEG_INFINITY, Real::max)
            };
            let far = pieces.iter().map(reach).fold(Real::NEG_INFINITY, Real::max);
            pieces
                .into_iter()
                .filter(|p| reach(p) >= far - 0.005)
                .collect()
        };
        let pieces = [pads_of(pieces_a), pads_of(pieces_b)];
        // The closing axis: from one finger's pads to the other's, at mid stroke; the opening
        // is the gap between the pads along it (negative when interleaved fingers pass each
        // other, as TALOS's do when fully closed).
        sample.set(&mids, 0.0);
        let poses = sample.hand_poses();
        let closing = (centroid(&pieces[1], &poses) - centroid(&pieces[0], &poses))
            .try_normalize(1e-9)
            .ok_or_else(|| GripperError::NotTwoFingers {
                tip: tip_name.clone(),
                found: 1,
            })?;
        let distance = |sample: &Sampler<'_>| -> Result<Real, GripperError> {
            Ok(axis_gap(&pieces, &sample.hand_poses(), &closing))
        };
        let mut drives = Vec::with_capacity(mids.len());
        for (i, d) in mids.iter().enumerate() {
            let l = model.variable_joint(d.variable).limits;
            let mut probe = mids.clone();
            probe[i].closed = l.lower;
            sample.set(&probe, 0.0);
            let at_lower = distance(&sample)?;
            probe[i].closed = l.upper;
            sample.set(&probe, 0.0);
            let at_upper = distance(&sample)?;
            let (closed, open) = if at_upper >= at_lower {
                (l.lower, l.upper)
            } else {
                (l.upper, l.lower)
            };
            drives.push(Drive {
                variable: d.variable,
                closed,
                open,
            });
        }
        // The opening table.
        let mut table = Vec::with_capacity(TABLE_SAMPLES);
        for k in 0..TABLE_SAMPLES {
            let s = k as Real / (TABLE_SAMPLES - 1) as Real;
            sample.set(&drives, s);
            table.push((s, distance(&sample)?));
        }
        let measured_min = table[0].1;
        let measured_max = table[TABLE_SAMPLES - 1].1;
        if measured_max - measured_min < 0.002 {
            return Err(GripperError::CannotOpen {
                tip: tip_name,
                reason: format!(
                    "opens only from {:.1} mm to {:.1} mm between its closed and open joint limits",
                    measured_min * 1e3,
                    measured_max * 1e3
                ),
            });
        }
        if measured_max < MIN_OPENING {
            return Err(GripperError::CannotOpen {
                tip: tip_name,
                reason: format!(
                    "opens to {:.1} mm at most: its fingers' geometry overlaps at every opening (a jaw whose convex hull takes in the other)",
                    measured_max * 1e3
                ),
            });
        }
        // Monotone: a dip of more than 0.5 mm means the fingers cross or the split is wrong.
        let mut running = measured_min;
        for &(s, o) in &table {
            if o < running - 0.0005 {
                return Err(GripperError::CannotOpen {
                    tip: tip_name,
                    reason: format!(
                        "does not open steadily: the opening falls from {:.1} mm to {:.1} mm at {:.0} % of the stroke",
                        running * 1e3,
                        o * 1e3,
                        s * 100.0
                    ),
                });
            }
            running = running.max(o);
        }
        // Make it non-decreasing (small numerical dips).
        let mut best = Real::NEG_INFINITY;
        for entry in &mut table {
            best = Real::max(best, entry.1);
            entry.1 = best;
        }

        // Pads when closed.
        sample.set(&drives, 0.0);
        let poses = sample.hand_poses();
        let pts_a = side_points(&pieces[0], &poses);
        let pts_b = side_points(&pieces[1], &poses);
        let inner_a = pts_a
            .iter()
            .map(|p| p.coords.dot(&closing))
            .fold(Real::NEG_INFINITY, Real::max);
        let inner_b = pts_b
            .iter()
            .map(|p| p.coords.dot(&closing))
            .fold(Real::INFINITY, Real::min);
        let pad_a: Vec<Point3> = pts_a
            .iter()
            .copied()
            .filter(|p| p.coords.dot(&closing) >= inner_a - PAD_TOLERANCE)
            .collect();
        let pad_b: Vec<Point3> = pts_b
            .iter()
            .copied()
            .filter(|p| p.coords.dot(&closing) <= inner_b + PAD_TOLERANCE)
            .collect();
        let pad_centre = Point3::from((mean(&pad_a).coords + mean(&pad_b).coords) * 0.5);
        // Approach: from the hand's origin (the arm tip) to the pads, across the closing axis.
        let raw = pad_centre.coords - closing * pad_centre.coords.dot(&closing);
        let approach = raw.try_normalize(1e-6).ok_or_else(|| GripperError::CannotOpen {
            tip: tip_name.clone(),
            reason: "has its pads on the line of the closing axis through the arm's last joint: no approach direction".to_owned(),
        })?;
        let lateral = closing.cross(&approach);
        let along = |p: &Point3, axis: &Vector3| p.coords.dot(axis);
        let pads: Vec<&Point3> = pad_a.iter().chain(&pad_b).collect();
        let (a_lo, a_hi) = extent(pads.iter().map(|p| along(p, &approach)));
        let (l_lo, l_hi) = extent(pads.iter().map(|p| along(p, &lateral)));
        let face_depth = (a_hi - a_lo).max(1e-4);
        let pad_depth = options.pad_depth.map_or(face_depth, |d| d.min(face_depth));
        let pad_width = options.pad_width.unwrap_or((l_hi - l_lo).max(1e-4));
        // Midway between the pads when closed; with a fixed jaw, on its pad (a grasp's centre
        // is then half the width away: [`Gripper::centre_from_tcp`]).
        let c_mid = if fixed_jaw {
            inner_b
        } else {
            0.5 * (inner_a + inner_b)
        };
        let tcp_origin =
            closing * c_mid + approach * (a_hi - pad_depth / 2.0) + lateral * (0.5 * (l_lo + l_hi));
        let rotation =
            Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[lateral, closing, approach]));
        let tip_from_tcp_raw = Isometry3::from_parts(
            Translation3::from(tcp_origin),
            UnitQuaternion::from_rotation_matrix(&rotation),
        );
        let tip_from_tcp = tip_from_tcp_raw * Translation3::from(options.tool_offset);
        let tcp_from_tip = tip_from_tcp.inverse();
        // Finger sizes along the TCP axes, and the palm's box, in the TCP frame.
        let in_tcp = |p: &Point3| tcp_from_tip * p;
        let finger_a: Vec<Point3> = pts_a.iter().map(in_tcp).collect();
        let (z_lo, z_hi) = extent(finger_a.iter().map(|p| p.z));
        let (y_lo, y_hi) = extent(finger_a.iter().map(|p| p.y));
        let finger_length = (z_hi - z_lo).max(pad_depth);
        let finger_thickness = (y_hi - y_lo).max(1e-4);
        let moving: Vec<usize> = links_a.iter().chain(&links_b).copied().collect();
        let mut palm_links: Vec<usize> = subtree
            .iter()
            .copied()
            .filter(|l| !moving.contains(l))
            .collect();
        if palm_links
            .iter()
            .all(|&l| model.links()[l].collisions.is_empty())
        {
            palm_links.push(arm_tip);
        }
        let palm_points: Vec<Point3> = palm_links
            .iter()
            .flat_map(|&l| pieces_of(model, l))
            .flat_map(|piece| {
                let pose = poses[piece.link];
                piece.points.into_iter().map(move |p| pose * p)
            })
            .map(|p| in_tcp(&p))
            .collect();
        let palm = if palm_points.is_empty() {
            // No palm geometry: a thin plate behind the finger roots.
            let back = z_lo;
            (
                Point3::new(-pad_width / 2.0, -measured_max / 2.0, back - 0.005),
                Point3::new(pad_width / 2.0, measured_max / 2.0, back),
            )
        } else {
            let (x0, x1) = extent(palm_points.iter().map(|p| p.x));
            let (y0, y1) = extent(palm_points.iter().map(|p| p.y));
            let (z0, z1) = extent(palm_points.iter().map(|p| p.z));
            (Point3::new(x0, y0, z0), Point3::new(x1, y1, z1))
        };
        let opening_max = options
            .opening_max
            .map_or(measured_max, |m| m.min(measured_max));
        let mut hand_links = subtree.clone();
        hand_links.insert(0, arm_tip);
        Ok(Self {
            arm_tip,
            hand_links,
            finger_links: [links_a, links_b],
            drives,
            pieces,
            table,
            opening_min: measured_min.max(0.0),
            opening_max,
            squeeze: options.squeeze,
            tip_from_tcp,
            pad_width,
            pad_depth,
            finger_length,
            finger_thickness,
            palm,
            fixed_jaw,
        })
    }

    /// Whether one jaw is fixed to the hand and the other closes against it (a jaw turning
    /// or sliding against a fixed one, as on many small arms). The tool point then lies on
    /// the fixed jaw's pad.
    pub fn has_fixed_jaw(&self) -> bool {
        self.fixed_jaw
    }

    /// The tool point seen from the centre of a grasp `width` wide (the point midway between
    /// the two contact patches, where the grasp planner puts it): the identity when both
    /// jaws move; with a fixed jaw, `width / 2 +` [`FIXED_JAW_CLEARANCE`] along the closing
    /// axis `y`, so that the fixed jaw's pad stands that clearance off the object's side.
    pub fn centre_from_tcp(&self, width: Real) -> Isometry3 {
        if self.fixed_jaw {
            Isometry3::translation(0.0, width / 2.0 + FIXED_JAW_CLEARANCE, 0.0)
        } else {
            Isometry3::identity()
        }
    }

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
        let object_pose = parry::pose(world_from_object);
        let mut gaps = [Real::INFINITY; 2];
        for (side, pieces) in self.pieces.iter().enumerate() {
            for piece in pieces {
                let Some(pose) = world_from_links.get(piece.link) else {
                    continue;
                };
                let pose = parry::pose(pose);
                let unmeasurable = || GripperError::Unmeasurable {
                    tip: format!("#{}", self.arm_tip),
                    what: "a finger and the object".to_owned(),
                };
                let d = match query::contact(
                    &pose,
                    &*piece.shape.0,
                    &object_pose,
                    &*object.shape.0,
                    0.0,
                )
                .map_err(|_| unmeasurable())?
                {
                    Some(c) if c.dist <= 0.0 => c.dist,
                    _ => {
                        query::distance(&pose, &*piece.shape.0, &object_pose, &*object.shape.0)
                            .map_err(|_| unmeasurable())?
                            .distance
                    }
                };
                gaps[side] = gaps[side].min(d);
            }
        }
        Ok(gaps)
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

/// An arm found in the URDF by [`find_arms`]: a serial chain of actuated joints ending in a
/// parallel gripper.
#[derive(Debug, Clone)]
pub struct FoundArm {
    /// The arm's variables, root side first.
    pub variables: Vec<usize>,
    /// The link where the chain starts (where it branches off the rest of the robot).
    pub base_link: usize,
    /// The arm's last moving link (the hand hangs from it).
    pub tip_link: usize,
}

/// The arms of a robot that has no SRDF groups for them: for every link whose subtree holds
/// one or two actuated finger joints (and nothing else actuated), the chain of actuated joints
/// above it up to the first link where the robot branches into another actuated chain, when
/// it has at least `min_joints` joints and [`Gripper::derive`] accepts its hand. Sorted by
/// tip link.
pub fn find_arms(model: &RobotModel, min_joints: usize) -> Vec<FoundArm> {
    let n = model.links().len();
    // Actuated (variable) joints in each link's subtree, counted bottom-up (children come
    // after parents).
    let mut actuated_below = vec![0usize; n];
    for l in (1..n).rev() {
        if let Some(j) = model.links()[l].parent_joint {
            let own = usize::from(matches!(
                model.joints()[j].source,
                JointValueSource::Variable(_)
            ));
            let parent = model.joints()[j].parent_link;
            actuated_below[parent] += actuated_below[l] + own;
        }
    }
    let is_variable = |l: usize| {
        model.links()[l]
            .parent_joint
            .is_some_and(|j| matches!(model.joints()[j].source, JointValueSource::Variable(_)))
    };
    let children = |l: usize| -> Vec<usize> {
        (0..n)
            .filter(|&c| model.parent_link(c) == Some(l))
            .collect()
    };
    let mut arms = Vec::new();
    for tip in 0..n {
        // The hand: one or two actuated joints below, each with nothing actuated below it.
        let below = actuated_below[tip];
        if !is_variable(tip) || !(1..=2).contains(&below) {
            continue;
        }
        let fingers_are_leaves = (0..n)
            .filter(|&l| l != tip && model.is_ancestor(tip, l))
            .all(|l| !is_variable(l) || actuated_below[l] == 0);
        if !fingers_are_leaves {
            continue;
        }
        // Up the chain to the branch point.
        let mut variables = Vec::new();
        let mut link = tip;
        let base_link = loop {
            if let Some(j) = model.links()[link].parent_joint
                && let JointValueSource::Variable(v) = model.joints()[j].source
            {
                variables.push(v);
            }
            let Some(parent) = model.parent_link(link) else {
                break link;
            };
            let branches = children(parent)
                .into_iter()
                .filter(|&c| c != link && (actuated_below[c] > 0 || is_variable(c)))
                .count();
            if branches > 0 {
                break parent;
            }
            link = parent;
        };
        variables.reverse();
        if variables.len() < min_joints {
            continue;
        }
        if Gripper::derive(model, &variables, &GripperOptions::default()).is_ok() {
            arms.push(FoundArm {
                variables,
                base_link,
                tip_link: tip,
            });
        }
    }
    arms
}

impl RobotModel {
    /// This model with one more link, `name`, fixed to `parent` at `parent_from_link` (no
    /// geometry): a tool frame. Indices of existing links, joints and variables are unchanged.
    ///
    /// # Errors
    /// [`crate::Error::UnknownLink`] for a bad parent; [`crate::Error::InvalidModel`] when the
    /// name is taken.
    pub fn with_fixed_link(
        &self,
        name: &str,
        parent: usize,
        parent_from_link: Isometry3,
    ) -> crate::Result<Self> {
        if parent >= self.links().len() {
            return Err(crate::Error::UnknownLink {
                name: format!("#{parent}"),
            });
        }
        if self.link_index(name).is_some() || self.joint_index(&format!("{name}_joint")).is_some() {
            return Err(crate::Error::InvalidModel {
                path: self.source().to_path_buf(),
                kind: crate::error::ModelErrorKind::DuplicateLink {
                    name: name.to_owned(),
                },
            });
        }
        let mut links = self.links().to_vec();
        let mut joints = self.joints().to_vec();
        joints.push(crate::model::Joint::fixed(
            format!("{name}_joint"),
            parent,
            links.len(),
            parent_from_link,
        ));
        links.push(crate::model::Link {
            name: name.to_owned(),
            parent_joint: Some(joints.len() - 1),
            collisions: Vec::new(),
            visuals: Vec::new(),
        });
        Ok(Self::from_parts(
            self.name().to_owned(),
            self.source().to_path_buf(),
            links,
            joints,
            self.warnings().to_vec(),
        ))
    }
}

fn check_options(o: &GripperOptions) -> Result<(), GripperError> {
    let bad = |name, reason| Err(GripperError::BadOption { name, reason });
    if !o.squeeze.is_finite() || o.squeeze < 0.0 || o.squeeze > 0.02 {
        return bad("squeeze", "must be between 0 and 0.02 m");
    }
    for (name, v) in [
        ("pad_depth", o.pad_depth),
        ("pad_width", o.pad_width),
        ("opening_max", o.opening_max),
    ] {
        if let Some(v) = v
            && (!v.is_finite() || v <= 0.0 || v > 1.0)
        {
            return bad(name, "must be positive and at most 1 m");
        }
    }
    if !o
        .tool_offset
        .iter()
        .all(|x| x.is_finite() && x.abs() <= 1.0)
    {
        return bad("tool_offset", "must be finite and within 1 m");
    }
    Ok(())
}

/// The child link of the arm's deepest joint, checking that the joints are one chain.
fn arm_tip(model: &RobotModel, variables: &[usize]) -> Result<usize, GripperError> {
    let mut links: Vec<usize> = variables
        .iter()
        .filter_map(|&v| {
            model
                .variable_joints()
                .get(v)
                .map(|&j| model.joints()[j].child_link)
        })
        .collect();
    if links.is_empty() {
        return Err(GripperError::NoArmJoints);
    }
    // Deepest first: the one whose root path is longest.
    links.sort_by_key(|&l| std::cmp::Reverse(model.joint_path(l).len()));
    let tip = links[0];
    for &l in &links[1..] {
        if !model.is_ancestor(l, tip) {
            let name = |l: usize| {
                model.links()[l]
                    .parent_joint
                    .map_or_else(String::new, |j| model.joints()[j].name.clone())
            };
            return Err(GripperError::NotAChain {
                first: name(tip),
                second: name(l),
            });
        }
    }
    Ok(tip)
}

/// Every link strictly below `link`.
fn subtree(model: &RobotModel, link: usize) -> Vec<usize> {
    (0..model.links().len())
        .filter(|&l| l != link && model.is_ancestor(link, l))
        .collect()
}

/// The convex pieces of a link's collision geometry, with sample points.
fn pieces_of(model: &RobotModel, link: usize) -> Vec<Piece> {
    let mut out = Vec::new();
    for g in &model.links()[link].collisions {
        let local = shape_points(&g.shape);
        let points: Vec<Point3> = local.iter().map(|p| g.link_from_shape * p).collect();
        let hull_points: Vec<_> = points.iter().map(parry::point).collect();
        if let Some(shape) = SharedShape::convex_hull(&hull_points) {
            out.push(Piece {
                link,
                shape,
                points,
            });
        }
    }
    out
}

/// Points on a shape's surface, in its own frame: exact for boxes and meshes (their corners
/// and vertices), 24 around each rim for round shapes.
fn shape_points(shape: &Shape) -> Vec<Point3> {
    let ring = |r: Real, z: Real| -> Vec<Point3> {
        (0..24)
            .map(|k| {
                let a = k as Real * std::f64::consts::TAU / 24.0;
                Point3::new(r * a.cos(), r * a.sin(), z)
            })
            .collect()
    };
    match shape {
        Shape::Box { half_extents: h } => {
            let mut v = Vec::with_capacity(8);
            for sx in [-1.0, 1.0] {
                for sy in [-1.0, 1.0] {
                    for sz in [-1.0, 1.0] {
                        v.push(Point3::new(sx * h.x, sy * h.y, sz * h.z));
                    }
                }
            }
            v
        }
        Shape::Cylinder { radius, length } => {
            let mut v = ring(*radius, -length / 2.0);
            v.extend(ring(*radius, length / 2.0));
            v
        }
        Shape::Capsule { radius, length } => {
            let mut v = Vec::new();
            for k in 0..=4 {
                let phi = k as Real * std::f64::consts::FRAC_PI_2 / 4.0;
                let (r, dz) = (radius * phi.cos(), radius * phi.sin());
                v.extend(ring(r, length / 2.0 + dz));
                v.extend(ring(r, -length / 2.0 - dz));
            }
            v
        }
        Shape::Sphere { radius } => {
            let mut v = Vec::new();
            for k in -4..=4 {
                let phi = k as Real * std::f64::consts::FRAC_PI_2 / 4.0;
                v.extend(ring(radius * phi.cos(), radius * phi.sin()));
            }
            v
        }
        Shape::Mesh { mesh, .. } => mesh.vertices().to_vec(),
    }
}

/// Forward kinematics of the hand for the closing parameter.
struct Sampler<'a> {
    model: &'a RobotModel,
    arm_tip: usize,
    q: Vec<Real>,
}

impl Sampler<'_> {
    fn set(&mut self, drives: &[Drive], s: Real) {
        for d in drives {
            self.q[d.variable] = d.closed + s * (d.open - d.closed);
        }
    }

    /// Every link's pose in the arm tip's frame (identity for links not computed).
    fn hand_poses(&self) -> Vec<Isometry3> {
        match self.model.link_poses(&self.q) {
            Ok(poses) => {
                let tip_from_root = poses[self.arm_tip].inverse();
                poses.iter().map(|p| tip_from_root * p).collect()
            }
            Err(_) => vec![Isometry3::identity(); self.model.links().len()],
        }
    }
}

fn centroid(pieces: &[Piece], poses: &[Isometry3]) -> Point3 {
    let pts: Vec<Point3> = side_points(pieces, poses);
    mean(&pts)
}

fn side_points(pieces: &[Piece], poses: &[Isometry3]) -> Vec<Point3> {
    pieces
        .iter()
        .flat_map(|piece| piece.points.iter().map(move |p| poses[piece.link] * p))
        .collect()
}

fn mean(points: &[Point3]) -> Point3 {
    if points.is_empty() {
        return Point3::origin();
    }
    let sum: Vector3 = points.iter().map(|p| p.coords).sum();
    Point3::from(sum / points.len() as Real)
}

fn extent(values: impl Iterator<Item = Real>) -> (Real, Real) {
    values.fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

/// The gap between the two sides' pads along the closing axis (side a → side b).
fn axis_gap(pieces: &[Vec<Piece>; 2], poses: &[Isometry3], closing: &Vector3) -> Real {
    let along = |side: &[Piece]| {
        side_points(side, poses)
            .into_iter()
            .map(|p| p.coords.dot(closing))
    };
    let inner_a = along(&pieces[0]).fold(Real::NEG_INFINITY, Real::max);
    let inner_b = along(&pieces[1]).fold(Real::INFINITY, Real::min);
    inner_b - inner_a
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::LoadOptions;
    use std::path::Path;

    /// A one-joint arm with a hand: `fingers` is the URDF text of the finger links and joints
    /// (parent link `hand`).
    fn robot(fingers: &str) -> RobotModel {
        let text = format!(
            r#"<robot name="t">
  <link name="base"/>
  <link name="hand"><collision><origin xyz="0 0 -0.02"/><geometry><box size="0.04 0.1 0.04"/></geometry></collision></link>
  <joint name="wrist" type="revolute"><parent link="base"/><child link="hand"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="1"/></joint>
  {fingers}
</robot>"#
        );
        RobotModel::from_urdf_str(&text, Path::new("."), &LoadOptions::default())
            .expect("test URDF")
    }

    fn finger(
        name: &str,
        parent: &str,
        kind: &str,
        xyz: &str,
        axis: &str,
        limits: (f64, f64),
        mimic: &str,
        box_xyz: &str,
    ) -> String {
        format!(
            r#"<link name="{name}"><collision><origin xyz="{box_xyz}"/><geometry><box size="0.02 0.01 0.06"/></geometry></collision></link>
  <joint name="{name}_joint" type="{kind}"><parent link="{parent}"/><child link="{name}"/>
    <origin xyz="{xyz}"/><axis xyz="{axis}"/><limit lower="{}" upper="{}" velocity="1" effort="1"/>{mimic}</joint>"#,
            limits.0, limits.1
        )
    }

    fn derive(model: &RobotModel) -> Gripper {
        let wrist = model.variable_index("wrist").expect("wrist");
        Gripper::derive(
            model,
            &[wrist],
            &GripperOptions {
                squeeze: 0.0,
                ..GripperOptions::default()
            },
        )
        .expect("gripper")
    }

    #[test]
    fn prismatic_mimic_fingers_open_by_twice_the_joint_value() {
        let model = robot(&format!(
            "{}\n{}",
            finger(
                "l",
                "hand",
                "prismatic",
                "0 0 0",
                "0 1 0",
                (0.0, 0.04),
                "",
                "0 0.005 0.03"
            ),
            finger(
                "r",
                "hand",
                "prismatic",
                "0 0 0",
                "0 -1 0",
                (0.0, 0.04),
                r#"<mimic joint="l_joint"/>"#,
                "0 -0.005 0.03"
            ),
        ));
        let g = derive(&model);
        let (lo, hi) = g.opening_range();
        assert!(lo.abs() < 1e-6 && (hi - 0.08).abs() < 1e-6, "{lo} {hi}");
        let mut q = model.zero_configuration();
        g.set_grasp(&mut q, 0.05);
        let v = model.variable_index("l_joint").expect("l");
        assert!((q[v] - 0.025).abs() < 1e-6, "{}", q[v]);
        // The TCP: midway between the pads, at their centre, z towards the tips.
        let t = g.tip_from_tcp();
        assert!(
            (t.translation.vector - Vector3::new(0.0, 0.0, 0.03)).norm() < 1e-6,
            "{t:?}"
        );
        let z = t.rotation * Vector3::z();
        assert!((z - Vector3::z()).norm() < 1e-6);
        let y = t.rotation * Vector3::y();
        assert!(y.y.abs() > 0.999);
        assert_eq!(g.pad_size().1, 0.06);
    }

    #[test]
    fn a_finger_closed_at_its_upper_limit_is_commanded_there() {
        // Zero is fully open: the fingers start 40 mm out and move in.
        let model = robot(&format!(
            "{}\n{}",
            finger(
                "l",
                "hand",
                "prismatic",
                "0 0.04 0",
                "0 -1 0",
                (0.0, 0.04),
                "",
                "0 0.005 0.03"
            ),
            finger(
                "r",
                "hand",
                "prismatic",
                "0 -0.04 0",
                "0 1 0",
                (0.0, 0.04),
                r#"<mimic joint="l_joint"/>"#,
                "0 -0.005 0.03"
            ),
        ));
        let g = derive(&model);
        assert_eq!(g.drives()[0].closed, 0.04);
        assert_eq!(g.drives()[0].open, 0.0);
        let mut q = model.zero_configuration();
        g.set_grasp(&mut q, 0.03);
        let v = model.variable_index("l_joint").expect("l");
        assert!((q[v] - 0.025).abs() < 1e-6, "{}", q[v]);
    }

    #[test]
    fn revolute_fingers_with_a_mimic_chain_close_on_the_width() {
        // Each finger: a proximal link hinged at the palm and a tip that counter-rotates
        // (a mimic of the driving joint) to keep the pad parallel, as on PR2.
        let prox = |name: &str, y: f64, axis: &str, mimic: &str| {
            format!(
                r#"<link name="{name}"><collision><origin xyz="0 0 0.03"/><geometry><box size="0.02 0.01 0.06"/></geometry></collision></link>
  <joint name="{name}_joint" type="revolute"><parent link="hand"/><child link="{name}"/>
    <origin xyz="0 {y} 0"/><axis xyz="{axis}"/><limit lower="0" upper="0.5" velocity="1" effort="1"/>{mimic}</joint>"#
            )
        };
        let tip = |name: &str, parent: &str, y: f64, axis: &str| {
            format!(
                r#"<link name="{name}"><collision><origin xyz="0 {y} 0.02"/><geometry><box size="0.02 0.01 0.04"/></geometry></collision></link>
  <joint name="{name}_joint" type="revolute"><parent link="{parent}"/><child link="{name}"/>
    <origin xyz="0 0 0.06"/><axis xyz="{axis}"/><limit lower="0" upper="0.5" velocity="1" effort="1"/><mimic joint="l_joint"/></joint>"#
            )
        };
        let model = robot(&format!(
            "{}\n{}\n{}\n{}",
            prox("l", 0.012, "-1 0 0", ""),
            prox("r", -0.012, "1 0 0", r#"<mimic joint="l_joint"/>"#),
            tip("lt", "l", -0.007, "1 0 0"),
            tip("rt", "r", 0.007, "-1 0 0"),
        ));
        let g = derive(&model);
        let (lo, hi) = g.opening_range();
        assert!(lo < 0.002, "{lo}");
        // Open: each proximal link turns 0.5 rad outwards: the tips move 60 mm · sin 0.5 out.
        let expected = 2.0 * (0.012 + 0.06 * 0.5f64.sin() - 0.007 - 0.005);
        assert!((hi - expected).abs() < 0.002, "{hi} vs {expected}");
        // Commanded to 40 mm, the measured opening is 40 mm.
        let mut q = model.zero_configuration();
        g.set_opening(&mut q, 0.04);
        let s = g.parameter_of(&q);
        assert!((g.opening_at(s) - 0.04).abs() < 1e-4);
        let v = model.variable_index("l_joint").expect("l");
        assert!(q[v] > 0.0 && q[v] < 0.5);
    }

    #[test]
    fn a_jaw_closing_against_a_fixed_one_is_a_gripper_with_its_tool_point_on_the_fixed_jaw() {
        // The fixed jaw's inner face at y = +0.01, the moving jaw's at y = +0.01 − 0 when
        // closed, sliding towards −y to open 40 mm.
        let model = robot(&format!(
            r#"<link name="fixed"><collision><origin xyz="0 0.015 0.03"/><geometry><box size="0.02 0.01 0.06"/></geometry></collision></link>
  <joint name="fixed_joint" type="fixed"><parent link="hand"/><child link="fixed"/></joint>
  {}"#,
            finger(
                "moving",
                "hand",
                "prismatic",
                "0 0 0",
                "0 -1 0",
                (0.0, 0.04),
                "",
                "0 0.005 0.03",
            )
        ));
        let g = derive(&model);
        assert!(g.has_fixed_jaw());
        let (lo, hi) = g.opening_range();
        assert!(lo.abs() < 1e-6 && (hi - 0.04).abs() < 1e-6, "{lo} {hi}");
        // The tool point is on the fixed jaw's pad (y = 0.01 in the hand's frame), its y axis
        // towards the fixed jaw.
        let t = g.tip_from_tcp();
        assert!((t.translation.y - 0.01).abs() < 1e-6, "{t}");
        assert!((t.rotation * Vector3::y()).y > 0.99, "{t}");
        // A grasp 30 mm wide: its centre 16 mm from the tool point, the moving jaw at 31 mm
        // (the fixed jaw 1 mm off the object; squeeze 0 here).
        let c = g.centre_from_tcp(0.03);
        assert!((c.translation.y - 0.016).abs() < 1e-9, "{c}");
        let mut q = model.zero_configuration();
        g.set_grasp(&mut q, 0.03);
        let v = model.variable_index("moving_joint").expect("jaw");
        assert!((q[v] - 0.031).abs() < 1e-6, "{}", q[v]);
        // The pads: the moving jaw and the fixed jaw, not the hand's box.
        let pads = g.pad_links();
        let name = |l: &usize| model.links()[*l].name.as_str();
        assert_eq!(pads[0].iter().map(name).collect::<Vec<_>>(), ["moving"]);
        assert_eq!(pads[1].iter().map(name).collect::<Vec<_>>(), ["fixed"]);
    }

    #[test]
    fn a_single_moving_finger_with_nothing_to_close_against_is_refused() {
        let text = r#"<robot name="t"><link name="base"/><link name="hand"/>
  <joint name="wrist" type="revolute"><parent link="base"/><child link="hand"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="1"/></joint>
  <link name="l"><collision><origin xyz="0 0.005 0.03"/><geometry><box size="0.02 0.01 0.06"/></geometry></collision></link>
  <joint name="l_joint" type="prismatic"><parent link="hand"/><child link="l"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/></joint>
</robot>"#;
        let model = RobotModel::from_urdf_str(text, Path::new("."), &LoadOptions::default())
            .expect("test URDF");
        let wrist = model.variable_index("wrist").expect("wrist");
        let e =
            Gripper::derive(&model, &[wrist], &GripperOptions::default()).expect_err("one finger");
        assert!(
            matches!(e, GripperError::NotTwoFingers { found: 1, .. }),
            "{e}"
        );
    }

    #[test]
    fn an_arm_without_a_gripper_is_refused() {
        let model = robot("");
        let wrist = model.variable_index("wrist").expect("wrist");
        let e =
            Gripper::derive(&model, &[wrist], &GripperOptions::default()).expect_err("no gripper");
        assert!(matches!(e, GripperError::NoDrive { .. }), "{e}");
        assert!(matches!(
            Gripper::derive(&model, &[], &GripperOptions::default()),
            Err(GripperError::NoArmJoints)
        ));
    }

    #[test]
    fn a_single_arm_is_found_and_a_gripperless_chain_is_not() {
        // Four revolute joints, then the prismatic fingers of `robot`'s hand.
        let mut arm = String::new();
        let mut parent = "hand".to_owned();
        for k in 0..3 {
            arm.push_str(&format!(
                r#"<link name="a{k}"/><joint name="a{k}_joint" type="revolute"><parent link="{parent}"/><child link="a{k}"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>"#
            ));
            parent = format!("a{k}");
        }
        arm.push_str(&format!(
            "{}\n{}",
            finger(
                "l",
                &parent,
                "prismatic",
                "0 0 0",
                "0 1 0",
                (0.0, 0.04),
                "",
                "0 0.005 0.03"
            ),
            finger(
                "r",
                &parent,
                "prismatic",
                "0 0 0",
                "0 -1 0",
                (0.0, 0.04),
                r#"<mimic joint="l_joint"/>"#,
                "0 -0.005 0.03"
            ),
        ));
        let model = robot(&arm);
        let arms = find_arms(&model, 4);
        assert_eq!(arms.len(), 1, "{arms:?}");
        assert_eq!(arms[0].variables.len(), 4);
        assert_eq!(model.links()[arms[0].tip_link].name, "a2");
        // Three joints are not an arm; a chain without fingers has no gripper.
        assert!(find_arms(&model, 5).is_empty());
        assert!(find_arms(&robot(""), 1).is_empty());
    }

    #[test]
    fn nx_hiro_tcp_matches_its_tool_link() {
        let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../robots/nx-hiro/nx-hiro.urdf");
        let model = RobotModel::from_urdf_file(&urdf, &LoadOptions::default()).expect("nx-hiro");
        let arm: Vec<usize> = (0..6)
            .map(|i| {
                model
                    .variable_index(&format!("RARM_JOINT{i}"))
                    .expect("joint")
            })
            .collect();
        let g = Gripper::derive(
            &model,
            &arm,
            &GripperOptions {
                pad_depth: Some(0.025),
                ..GripperOptions::default()
            },
        )
        .expect("gripper");
        let tip = g.arm_tip();
        let tcp = model.require_link("RARM_TCP").expect("tcp");
        let q = model.zero_configuration();
        let poses = model.link_poses(&q).expect("fk");
        let want = poses[tip].inverse() * poses[tcp];
        let got = g.tip_from_tcp();
        assert!(
            (want.translation.vector - got.translation.vector).norm() < 1e-6,
            "{want:?} {got:?}"
        );
        // Same approach axis; the closing axis up to its sign.
        assert!(((want.rotation * Vector3::z()) - (got.rotation * Vector3::z())).norm() < 1e-6);
        assert!(
            (want.rotation * Vector3::y())
                .dot(&(got.rotation * Vector3::y()))
                .abs()
                > 1.0 - 1e-6
        );
        let (lo, hi) = g.opening_range();
        assert!(lo.abs() < 1e-6 && (hi - 0.08).abs() < 1e-6, "{lo} {hi}");
    }
}
