//! What a [`Setup`] is made for (issue 33): a setup for validation leaves out what only the
//! planner reads, whose cost grows with the environment's triangles (clustering, grasp
//! colliders) or does not concern the validator at all (grasps, roadmaps).
//!
//! [`Setup`]: super::Setup

use pickplace_geometry::cluster::{ClusterParams, Clustering};
use pickplace_grasp::GraspSet;

/// What a [`Setup`] was made for: what it holds depends on it.
///
/// [`Setup`]: super::Setup
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum SetupPurpose {
    /// Everything the planner reads ([`Setup::load`], [`Setup::new`]).
    ///
    /// [`Setup::load`]: super::Setup::load
    /// [`Setup::new`]: super::Setup::new
    Planning,
    /// Only what [`crate::validate::validate`] reads ([`Setup::load_for_validation`]): the
    /// robot, its collision world, the meshes, the object's contact model. Left empty,
    /// because the validator never reads them and their cost grows with the environment's
    /// triangles or is the planner's alone: the environment's clusters
    /// ([`EnvironmentPart::clustering`], none) and grasp colliders
    /// ([`EnvironmentPart::collider`], `None`), the object's finger clusters and grasps
    /// ([`Setup::object_finger`], [`Setup::grasp_set`], none), the arms' roadmaps
    /// ([`ArmSetup::roadmap`], no node). [`crate::plan()`] refuses such a setup.
    ///
    /// [`Setup::load_for_validation`]: super::Setup::load_for_validation
    /// [`EnvironmentPart::clustering`]: super::EnvironmentPart::clustering
    /// [`EnvironmentPart::collider`]: super::EnvironmentPart::collider
    /// [`Setup::object_finger`]: super::Setup::object_finger
    /// [`Setup::grasp_set`]: super::Setup::grasp_set
    /// [`ArmSetup::roadmap`]: super::ArmSetup::roadmap
    Validation,
}

/// The clustering of a mesh that was not clustered ([`SetupPurpose::Validation`]).
pub(super) fn no_clusters(params: &ClusterParams) -> Clustering {
    Clustering {
        params: *params,
        clusters: Vec::new(),
        pairs: Vec::new(),
    }
}

/// The grasp set of an object whose grasps were not planned ([`SetupPurpose::Validation`]).
pub(super) fn no_grasps() -> GraspSet {
    GraspSet {
        grasps: Vec::new(),
        pairs: 0,
        candidates: 0,
        rejected: Default::default(),
    }
}
