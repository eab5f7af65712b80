//! The `pickplace placements --json` document (format [`PLACEMENTS_JSON_FORMAT`]): stable
//! placements on an environment ([`PlacementsJson::from_set`]) or resting poses on a plane
//! ([`PlacementsJson::from_resting`]).

use crate::candidates::{ContactKind, PlacementSet};
use crate::resting::RestingPose;
use pickplace_geometry::math::{Point3, Real};

/// The value of the `format` field. Documents written before November 2026 say
/// `pickplace.placements.v1`, with the same content.
pub const PLACEMENTS_JSON_FORMAT: &str = "pickplace.placements/1";

pub use pickplace_geometry::json::PoseJson;

/// One placement (or resting pose) in the document.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PlacementJson {
    /// `world_from_object`.
    pub pose: PoseJson,
    /// Face-face or edge-face (resting poses are face-face).
    pub contact: ContactKind,
    /// The object's contact cluster (none for resting poses).
    pub object_cluster: Option<usize>,
    /// The environment's contact cluster (none for resting poses).
    pub env_cluster: Option<usize>,
    /// Stability margin (m), see [`crate::stability`].
    pub stability_margin: Real,
    /// Tipping angle (rad): `atan(stability_margin / CoG height)`, see
    /// [`crate::stability::tipping_angle`].
    pub tipping_angle: Real,
    /// Horizontal distance (m) from the target to the CoG's vertical (none for resting poses),
    /// see [`crate::Placement::distance_to_target`].
    pub distance_to_target: Option<Real>,
    /// Tilt of an edge-face contact (rad).
    pub tilt: Real,
}

/// Rejection counts on one environment cluster.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct RejectionJson {
    /// The environment cluster.
    pub env_cluster: usize,
    /// Object regions that did not fit.
    pub did_not_fit: usize,
    /// Poses that failed the stability test.
    pub unstable: usize,
    /// Poses that penetrated the environment.
    pub penetrates: usize,
    /// Poses accepted.
    pub accepted: usize,
}

/// The `pickplace placements --json` document.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PlacementsJson {
    /// Always [`PLACEMENTS_JSON_FORMAT`].
    pub format: &'static str,
    /// The object mesh as the user named it.
    pub object: String,
    /// The environment mesh as the user named it (none for resting poses).
    pub environment: Option<String>,
    /// The target point, world frame (none for resting poses).
    pub target: Option<[Real; 3]>,
    /// The environment cluster the target selected (none for resting poses).
    pub target_cluster: Option<usize>,
    /// Placements, best first.
    pub placements: Vec<PlacementJson>,
    /// Rejection counts per environment cluster searched.
    pub rejections: Vec<RejectionJson>,
}

impl PlacementsJson {
    /// The document of a placement search of `object` on `environment` towards `target`.
    pub fn from_set(
        object: String,
        environment: String,
        target: &Point3,
        set: &PlacementSet,
    ) -> Self {
        Self {
            format: PLACEMENTS_JSON_FORMAT,
            object,
            environment: Some(environment),
            target: Some([target.x, target.y, target.z]),
            target_cluster: Some(set.target_cluster),
            placements: set
                .placements
                .iter()
                .map(|p| PlacementJson {
                    pose: (&p.world_from_object).into(),
                    contact: p.contact,
                    object_cluster: Some(p.object_cluster),
                    env_cluster: Some(p.env_cluster),
                    stability_margin: p.stability_margin,
                    tipping_angle: p.tipping_angle,
                    distance_to_target: Some(p.distance_to_target),
                    tilt: p.tilt,
                })
                .collect(),
            rejections: set
                .rejections
                .iter()
                .map(|(id, r)| RejectionJson {
                    env_cluster: *id,
                    did_not_fit: r.did_not_fit,
                    unstable: r.unstable,
                    penetrates: r.penetrates,
                    accepted: r.accepted,
                })
                .collect(),
        }
    }

    /// The document of the resting poses of `object` on a plane (the first `max` of `poses`).
    pub fn from_resting(object: String, poses: &[RestingPose], max: usize) -> Self {
        Self {
            format: PLACEMENTS_JSON_FORMAT,
            object,
            environment: None,
            target: None,
            target_cluster: None,
            placements: poses
                .iter()
                .take(max)
                .map(|p| PlacementJson {
                    pose: (&p.world_from_object).into(),
                    contact: ContactKind::FaceFace,
                    object_cluster: None,
                    env_cluster: None,
                    stability_margin: p.stability_margin,
                    tipping_angle: p.tipping_angle,
                    distance_to_target: None,
                    tilt: 0.0,
                })
                .collect(),
            rejections: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resting::{RestingOptions, resting_poses};
    use pickplace_geometry::shapes::box_mesh;

    #[test]
    fn resting_document_keeps_the_order_and_the_limit() {
        let cube = box_mesh([0.05, 0.05, 0.05]);
        let poses =
            resting_poses(&cube, &Point3::origin(), &RestingOptions::default()).expect("poses");
        assert_eq!(poses.len(), 6);
        let doc = PlacementsJson::from_resting("cube.stl".into(), &poses, 4);
        assert_eq!(doc.placements.len(), 4);
        let value = serde_json::to_value(&doc).expect("json");
        assert_eq!(value["format"], "pickplace.placements/1");
        assert_eq!(value["environment"], serde_json::Value::Null);
        assert_eq!(value["placements"][0]["contact"], "face-face");
        let margin = value["placements"][0]["stability_margin"]
            .as_f64()
            .expect("margin");
        assert!((margin - 0.05).abs() < 1e-9, "{margin}");
        // A cube's CoG is as high as the margin: a 45° tipping angle.
        let tipping = value["placements"][0]["tipping_angle"]
            .as_f64()
            .expect("tipping angle");
        assert!(
            (tipping - std::f64::consts::FRAC_PI_4).abs() < 1e-9,
            "{tipping}"
        );
    }
}
