//! The `pickplace grasps --json` document (format `pickplace.grasps/1`, see `docs/grasp.md`).

use crate::planner::{GraspSet, RejectionCounts};
use pickplace_geometry::math::{Point3, Real};

/// The value of the `format` field. Documents written before November 2026 say
/// `pickplace.grasps.v1`, with the same content.
pub const GRASPS_JSON_FORMAT: &str = "pickplace.grasps/1";

pub use pickplace_geometry::json::PoseJson;

/// One grasp in the JSON document.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GraspJson {
    /// Rank, 0 for the best.
    pub rank: usize,
    /// Pose of the TCP in the object frame.
    pub object_from_tcp: PoseJson,
    /// Distance between the pads when closed (m).
    pub width: Real,
    /// Score in [0, 1].
    pub score: Real,
    /// Index of the cluster pair (in the finger-mode clustering's `pairs`).
    pub pair: usize,
    /// Cluster ids under the `+closing` and `−closing` pads.
    pub clusters: [u32; 2],
    /// Approach angle about the grasp axis (rad).
    pub approach_angle: Real,
    /// Pad area on both clusters (m²).
    pub contact_area: Real,
    /// Distance from the centre of gravity to the grasp axis (m).
    pub torque_arm: Real,
    /// Signed distance from the pad centre to the overlap boundary (m).
    pub boundary_margin: Real,
    /// How far a patch rises towards its pad above the contact point (m), absorbed by the
    /// pads' flexible sheet.
    #[serde(default)]
    pub pad_depth: Real,
    /// How far the pads are drawn back along the approach from the grasp centre, so that the
    /// finger tips stop short of a thin object's far edge (m; 0 for most grasps).
    #[serde(default)]
    pub tip_shift: Real,
}

/// The `pickplace grasps --json` document.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GraspsJson {
    /// Always [`GRASPS_JSON_FORMAT`].
    pub format: String,
    /// The mesh file as given by the user.
    pub mesh: String,
    /// The gripper configuration file read.
    pub gripper: String,
    /// `h_max` of the finger clustering (m).
    pub h_max: Real,
    /// Centre of gravity of the object (m, object frame).
    pub center_of_mass: [Real; 3],
    /// Number of cluster pairs.
    pub pairs: usize,
    /// Number of candidates evaluated.
    pub candidates: usize,
    /// Rejections by reason.
    pub rejected: RejectionCounts,
    /// Accepted grasps, best first.
    pub grasps: Vec<GraspJson>,
}

impl GraspsJson {
    /// Builds the document of a planned [`GraspSet`].
    pub fn new(
        mesh: &str,
        gripper: &str,
        h_max: Real,
        center_of_mass: &Point3,
        set: &GraspSet,
    ) -> Self {
        Self {
            format: GRASPS_JSON_FORMAT.to_owned(),
            mesh: mesh.to_owned(),
            gripper: gripper.to_owned(),
            h_max,
            center_of_mass: [center_of_mass.x, center_of_mass.y, center_of_mass.z],
            pairs: set.pairs,
            candidates: set.candidates,
            rejected: set.rejected,
            grasps: set
                .grasps
                .iter()
                .enumerate()
                .map(|(rank, g)| GraspJson {
                    rank,
                    object_from_tcp: PoseJson::from(&g.object_from_tcp),
                    width: g.width,
                    score: g.score,
                    pair: g.pair,
                    clusters: [g.positive_cluster, g.negative_cluster],
                    approach_angle: g.approach_angle,
                    contact_area: g.quality.contact_area,
                    torque_arm: g.quality.torque_arm,
                    boundary_margin: g.quality.boundary_margin,
                    pad_depth: g.quality.pad_depth,
                    tip_shift: g.quality.tip_shift,
                })
                .collect(),
        }
    }
}
