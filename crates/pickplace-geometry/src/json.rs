//! JSON documents: the pose object every pickplace document shares ([`PoseJson`]) and this
//! crate's own document, the clusters of a mesh ([`ClustersJson`], format
//! [`CLUSTERS_JSON_FORMAT`], defined beside the clusters in [`crate::cluster`]).
//!
//! Every document names its format as `pickplace.<name>/<version>` (`pickplace.plan/1`,
//! `pickplace.clusters/1`, …).

use crate::math::{Isometry3, Real};

pub use crate::cluster::{CLUSTERS_JSON_FORMAT, ClusterJson, ClusterPairJson, ClustersJson};

/// A pose as in every pickplace file: position (m) and orientation quaternion `[x, y, z, w]`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PoseJson {
    /// Translation (m).
    pub position: [Real; 3],
    /// Unit quaternion, ROS order `[x, y, z, w]`.
    pub orientation: [Real; 4],
}

impl From<&Isometry3> for PoseJson {
    fn from(iso: &Isometry3) -> Self {
        let t = iso.translation.vector;
        let q = iso.rotation.quaternion();
        Self {
            position: [t.x, t.y, t.z],
            orientation: [q.i, q.j, q.k, q.w],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::UnitQuaternion;

    #[test]
    fn poses_are_position_and_ros_quaternion() {
        let p = Isometry3::translation(1.0, 2.0, 3.0);
        let json = PoseJson::from(&p);
        assert_eq!(json.position, [1.0, 2.0, 3.0]);
        assert_eq!(json.orientation, [0.0, 0.0, 0.0, 1.0]);
        let turned = Isometry3::from_parts(
            p.translation,
            UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::PI),
        );
        let q = PoseJson::from(&turned).orientation;
        assert!(q[2].abs() > 0.999 && q[3].abs() < 1e-12, "{q:?}");
    }
}
