//! Forward kinematics and Jacobians.
//!
//! Poses are `root_from_link` (the link frame in the root link's frame). Jacobians map joint
//! velocities of a chosen subset of variables to the spatial velocity of a point fixed in a
//! link, both expressed in the root frame: rows 0–2 linear velocity (m/s), rows 3–5 angular
//! velocity (rad/s).

use crate::error::{Error, Result};
use crate::model::{JointType, JointValueSource, RobotModel};
use pickplace_geometry::math::nalgebra::{Dyn, OMatrix, U6};
use pickplace_geometry::math::{Isometry3, Point3, Real, UnitVector3, Vector3};

/// A 6 × n Jacobian (rows: linear then angular velocity, root frame).
pub type Jacobian = OMatrix<Real, U6, Dyn>;

impl RobotModel {
    /// Forward kinematics of every link into a caller-owned buffer.
    ///
    /// # Arguments
    /// * `q`: one value per variable ([`RobotModel::variable_count`]); not checked against
    ///   the limits.
    /// * `root_from_links`: one pose per link, overwritten.
    ///
    /// # Errors
    /// [`Error::WrongLength`] when a slice has the wrong length.
    ///
    /// # Performance
    /// One isometry product per joint; no allocation.
    pub fn forward_kinematics(&self, q: &[Real], root_from_links: &mut [Isometry3]) -> Result<()> {
        self.check_length(q)?;
        if root_from_links.len() != self.links().len() {
            return Err(Error::WrongLength {
                what: "link pose buffer",
                expected: self.links().len(),
                found: root_from_links.len(),
            });
        }
        root_from_links[0] = Isometry3::identity();
        for joint in self.joints() {
            let parent = root_from_links[joint.parent_link];
            root_from_links[joint.child_link] =
                parent * joint.parent_from_child(joint.source.value(q));
        }
        Ok(())
    }

    /// Forward kinematics into a new vector (allocates; see [`RobotModel::forward_kinematics`]).
    ///
    /// # Errors
    /// [`Error::WrongLength`].
    pub fn link_poses(&self, q: &[Real]) -> Result<Vec<Isometry3>> {
        let mut poses = vec![Isometry3::identity(); self.links().len()];
        self.forward_kinematics(q, &mut poses)?;
        Ok(poses)
    }

    /// The pose of one link, computing only the joints on its path from the root.
    ///
    /// # Errors
    /// [`Error::WrongLength`], or [`Error::UnknownLink`] for an index out of range.
    pub fn link_pose(&self, q: &[Real], link: usize) -> Result<Isometry3> {
        self.check_length(q)?;
        self.check_link(link)?;
        let mut pose = Isometry3::identity();
        for j in self.joint_path(link) {
            let joint = &self.joints()[j];
            pose *= joint.parent_from_child(joint.source.value(q));
        }
        Ok(pose)
    }

    /// The Jacobian of a point fixed in a link, for a subset of the variables.
    ///
    /// # Arguments
    /// * `q`: one value per variable.
    /// * `link`: the link index.
    /// * `point_in_link`: the point, in the link frame.
    /// * `variables`: the variables whose columns are wanted, in column order. A variable
    ///   that does not move the link gives a zero column; a mimic joint adds its multiplier
    ///   times its own column to the column of the variable it copies.
    /// * `jacobian`: the 6 × `variables.len()` output.
    ///
    /// # Errors
    /// [`Error::WrongLength`] (q or the output's columns), [`Error::UnknownLink`].
    pub fn jacobian(
        &self,
        q: &[Real],
        link: usize,
        point_in_link: &Point3,
        variables: &[usize],
        jacobian: &mut Jacobian,
    ) -> Result<()> {
        self.check_length(q)?;
        self.check_link(link)?;
        if jacobian.ncols() != variables.len() {
            return Err(Error::WrongLength {
                what: "Jacobian columns",
                expected: variables.len(),
                found: jacobian.ncols(),
            });
        }
        if let Some(&v) = variables.iter().find(|&&v| v >= self.variable_count()) {
            return Err(Error::WrongLength {
                what: "variable index",
                expected: self.variable_count(),
                found: v + 1,
            });
        }
        jacobian.fill(0.0);
        let path = self.joint_path(link);
        // Joint frames in the root frame.
        let mut frames: Vec<(usize, Isometry3)> = Vec::with_capacity(path.len());
        let mut pose = Isometry3::identity();
        for &j in &path {
            let joint = &self.joints()[j];
            let root_from_joint = pose * joint.parent_from_joint;
            frames.push((j, root_from_joint));
            pose = root_from_joint * joint.motion(joint.source.value(q));
        }
        let point = pose * point_in_link;
        for (j, root_from_joint) in frames {
            let joint = &self.joints()[j];
            let (variable, scale) = match joint.source {
                JointValueSource::Fixed => continue,
                JointValueSource::Variable(v) => (v, 1.0),
                JointValueSource::Mimic {
                    variable,
                    multiplier,
                    ..
                } => (variable, multiplier),
            };
            let axis = root_from_joint.rotation * joint.axis.into_inner();
            let column = joint_column(
                joint.joint_type,
                &axis,
                &root_from_joint.translation.vector,
                &point.coords,
            );
            for (c, _) in variables
                .iter()
                .enumerate()
                .filter(|&(_, &v)| v == variable)
            {
                let mut col = jacobian.column_mut(c);
                col += column * scale;
            }
        }
        Ok(())
    }

    fn check_link(&self, link: usize) -> Result<()> {
        if link >= self.links().len() {
            return Err(Error::UnknownLink {
                name: format!("#{link}"),
            });
        }
        Ok(())
    }
}

/// The Jacobian column of one joint: `[a × (p − o); a]` for a rotation about the unit axis
/// `a` through `o`, `[a; 0]` for a translation along `a`.
#[inline]
fn joint_column(
    joint_type: JointType,
    axis: &Vector3,
    origin: &Vector3,
    point: &Vector3,
) -> pickplace_geometry::math::nalgebra::Vector6<Real> {
    match joint_type {
        JointType::Prismatic => {
            pickplace_geometry::math::nalgebra::Vector6::new(axis.x, axis.y, axis.z, 0.0, 0.0, 0.0)
        }
        JointType::Fixed => pickplace_geometry::math::nalgebra::Vector6::zeros(),
        JointType::Revolute | JointType::Continuous => {
            let v = axis.cross(&(point - origin));
            pickplace_geometry::math::nalgebra::Vector6::new(v.x, v.y, v.z, axis.x, axis.y, axis.z)
        }
    }
}

/// One joint of a [`KinematicChain`].
#[derive(Debug, Clone)]
struct ChainJoint {
    joint_type: JointType,
    parent_from_joint: Isometry3,
    axis: UnitVector3,
    source: JointValueSource,
    /// Column in the chain's Jacobian and its factor (mimic multiplier), when the joint is
    /// driven by one of the chain's variables.
    column: Option<(usize, Real)>,
}

/// The joints from the root to a tip frame, precomputed for fast pose and Jacobian
/// evaluation of a subset of the variables (a planning group).
///
/// Immutable and `Send + Sync`; build it once per group and tip.
#[derive(Debug, Clone)]
pub struct KinematicChain {
    joints: Vec<ChainJoint>,
    variables: Vec<usize>,
    tip_link: usize,
    tip_from_tcp: Isometry3,
}

impl KinematicChain {
    /// The chain from the root to `tip_link`, with Jacobian columns for `variables`.
    ///
    /// # Arguments
    /// * `tip_from_tcp`: the frame whose pose and Jacobian are computed, in the tip link's
    ///   frame (identity for the link frame itself).
    ///
    /// # Errors
    /// [`Error::UnknownLink`] or [`Error::WrongLength`] for an out-of-range index.
    pub fn new(
        model: &RobotModel,
        tip_link: usize,
        tip_from_tcp: Isometry3,
        variables: &[usize],
    ) -> Result<Self> {
        model.check_link(tip_link)?;
        if let Some(&v) = variables.iter().find(|&&v| v >= model.variable_count()) {
            return Err(Error::WrongLength {
                what: "variable index",
                expected: model.variable_count(),
                found: v + 1,
            });
        }
        let mut joints: Vec<ChainJoint> = Vec::new();
        for j in model.joint_path(tip_link) {
            let joint = &model.joints()[j];
            let column = match joint.source {
                JointValueSource::Fixed => None,
                JointValueSource::Variable(v) => {
                    variables.iter().position(|&x| x == v).map(|c| (c, 1.0))
                }
                JointValueSource::Mimic {
                    variable,
                    multiplier,
                    ..
                } => variables
                    .iter()
                    .position(|&x| x == variable)
                    .map(|c| (c, multiplier)),
            };
            // Merge consecutive fixed joints into the next joint's origin.
            if let Some(last) = joints.last_mut()
                && last.joint_type == JointType::Fixed
            {
                let merged = last.parent_from_joint * joint.parent_from_joint;
                *last = ChainJoint {
                    joint_type: joint.joint_type,
                    parent_from_joint: merged,
                    axis: joint.axis,
                    source: joint.source,
                    column,
                };
                continue;
            }
            joints.push(ChainJoint {
                joint_type: joint.joint_type,
                parent_from_joint: joint.parent_from_joint,
                axis: joint.axis,
                source: joint.source,
                column,
            });
        }
        Ok(Self {
            joints,
            variables: variables.to_vec(),
            tip_link,
            tip_from_tcp,
        })
    }

    /// The variables of the Jacobian's columns.
    pub fn variables(&self) -> &[usize] {
        &self.variables
    }

    /// The tip link.
    pub fn tip_link(&self) -> usize {
        self.tip_link
    }

    /// The TCP frame in the tip link's frame.
    pub fn tip_from_tcp(&self) -> &Isometry3 {
        &self.tip_from_tcp
    }

    /// `root_from_tcp` for the full variable vector `q` (not length-checked: `q` must have
    /// one value per model variable).
    pub fn pose(&self, q: &[Real]) -> Isometry3 {
        let mut pose = Isometry3::identity();
        for joint in &self.joints {
            pose *= joint.parent_from_joint;
            if joint.joint_type != JointType::Fixed {
                pose *= motion(joint.joint_type, &joint.axis, joint.source.value(q));
            }
        }
        pose * self.tip_from_tcp
    }

    /// `root_from_tcp` and the TCP's Jacobian (6 × `variables().len()`, overwritten).
    pub fn pose_and_jacobian(&self, q: &[Real], jacobian: &mut Jacobian) -> Isometry3 {
        jacobian.fill(0.0);
        // First pass: joint frames; we store axis and origin per driven joint.
        let mut pose = Isometry3::identity();
        let mut driven: [(usize, Real, JointType, Vector3, Vector3); 32] =
            [(0, 0.0, JointType::Fixed, Vector3::zeros(), Vector3::zeros()); 32];
        let mut count = 0;
        let mut overflow: Vec<(usize, Real, JointType, Vector3, Vector3)> = Vec::new();
        for joint in &self.joints {
            pose *= joint.parent_from_joint;
            if joint.joint_type == JointType::Fixed {
                continue;
            }
            if let Some((c, factor)) = joint.column {
                let entry = (
                    c,
                    factor,
                    joint.joint_type,
                    pose.rotation * joint.axis.into_inner(),
                    pose.translation.vector,
                );
                if count < driven.len() {
                    driven[count] = entry;
                    count += 1;
                } else {
                    overflow.push(entry);
                }
            }
            pose *= motion(joint.joint_type, &joint.axis, joint.source.value(q));
        }
        let tcp = pose * self.tip_from_tcp;
        let p = tcp.translation.vector;
        for &(c, factor, joint_type, axis, origin) in driven[..count].iter().chain(overflow.iter())
        {
            let column = joint_column(joint_type, &axis, &origin, &p);
            let mut col = jacobian.column_mut(c);
            col += column * factor;
        }
        tcp
    }
}

#[inline]
fn motion(joint_type: JointType, axis: &UnitVector3, value: Real) -> Isometry3 {
    use pickplace_geometry::math::{Translation3, UnitQuaternion};
    match joint_type {
        JointType::Revolute | JointType::Continuous => Isometry3::from_parts(
            Translation3::identity(),
            UnitQuaternion::from_axis_angle(axis, value),
        ),
        JointType::Prismatic => Isometry3::from_parts(
            Translation3::from(axis.into_inner() * value),
            UnitQuaternion::identity(),
        ),
        JointType::Fixed => Isometry3::identity(),
    }
}
