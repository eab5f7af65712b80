//! The grasp set as a cache entry: planning the grasps of an object with thousands of
//! triangles costs tens of milliseconds, reading them back well under one.
//!
//! An entry is `PPGS`, the format version ([`FORMAT_VERSION`]), the key ([`key`]: the mesh's
//! content, the clustering parameters, the gripper, the options and [`ALGORITHM_VERSION`]),
//! the payload's length and checksum, then the [`GraspSet`]
//! ([`pickplace_geometry::codec::to_fixed_bytes`]). Anything else (another
//! key, a short or corrupt file) is refused with the reason, and the caller plans the grasps
//! again: a cache entry is never trusted over a fresh plan.

use crate::gripper::GripperParams;
use crate::planner::{GraspOptions, GraspSet};
use pickplace_geometry::cluster::ClusterParams;
use pickplace_geometry::codec::{from_fixed_bytes, to_fixed_bytes};
use pickplace_geometry::hash::{ContentHasher, hash_bytes};

/// File extension of grasp-set entries.
pub const EXTENSION: &str = "ppgs";

/// Version of the entry's layout.
pub const FORMAT_VERSION: u32 = 1;

/// Version of the grasp planner's output: bumped whenever the same input gives other grasps
/// (2: pad contact measured on the mesh, issue 17; 3: its triangles summed in BVH order; 4:
/// triangles stored twice welded, issue 31; 5: pads drawn back on thin objects, issue 31; 6:
/// drawn back on narrow curved strips too), so an older build's entries are rebuilt.
pub const ALGORITHM_VERSION: u32 = 6;

const MAGIC: &[u8; 4] = b"PPGS";
const HEADER: usize = 4 + 4 + 8 + 8 + 8;

/// Why an entry was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum DbError {
    /// Not a grasp-set entry, or cut short.
    #[error("not a grasp-set entry")]
    NotAnEntry,
    /// Another layout version.
    #[error("format version {found}, this build reads {FORMAT_VERSION}")]
    Version {
        /// The entry's version.
        found: u32,
    },
    /// Built for another mesh, clustering, gripper, options or planner version.
    #[error("built for another object, gripper or planner version")]
    OtherKey,
    /// The payload does not match its checksum, or does not decode.
    #[error("corrupt payload")]
    Corrupt,
}

/// The key of the grasp set planned on the mesh with content hash `mesh_hash`
/// ([`pickplace_geometry::hash::mesh_hash`]), clustered with `finger`, for `gripper` and
/// `options`, by this planner version.
pub fn key(
    mesh_hash: u64,
    finger: &ClusterParams,
    gripper: &GripperParams,
    options: &GraspOptions,
) -> u64 {
    let mut h = ContentHasher::default();
    h.word(mesh_hash);
    h.word(u64::from(ALGORITHM_VERSION));
    for part in [
        to_fixed_bytes(finger),
        to_fixed_bytes(gripper),
        to_fixed_bytes(options),
    ] {
        // Plain structs of numbers always encode; an error would only weaken the key to the
        // other parts, never match another object's.
        match part {
            Some(bytes) => h.bytes(&bytes),
            None => h.word(u64::MAX),
        }
    }
    h.finish()
}

/// The entry of `set` under `key`.
pub fn encode(key: u64, set: &GraspSet) -> Vec<u8> {
    let payload = to_fixed_bytes(set).unwrap_or_default();
    let mut out = Vec::with_capacity(HEADER + payload.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&key.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&hash_bytes(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    out
}

/// The grasp set of an entry made under `key`.
///
/// # Errors
/// [`DbError`] naming why the entry is refused.
pub fn decode(bytes: &[u8], key: u64) -> Result<GraspSet, DbError> {
    let word = |at: usize| -> Result<u64, DbError> {
        let b: [u8; 8] = bytes
            .get(at..at + 8)
            .and_then(|s| s.try_into().ok())
            .ok_or(DbError::NotAnEntry)?;
        Ok(u64::from_le_bytes(b))
    };
    if bytes.len() < HEADER || &bytes[..4] != MAGIC {
        return Err(DbError::NotAnEntry);
    }
    let version = u32::from_le_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]);
    if version != FORMAT_VERSION {
        return Err(DbError::Version { found: version });
    }
    if word(8)? != key {
        return Err(DbError::OtherKey);
    }
    let length = word(16)?;
    let payload = &bytes[HEADER..];
    if payload.len() as u64 != length || hash_bytes(payload) != word(24)? {
        return Err(DbError::Corrupt);
    }
    from_fixed_bytes(payload).ok_or(DbError::Corrupt)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planner::GraspPlanner;
    use crate::planner::tests::gripper;
    use pickplace_geometry::cluster::cluster_surface;
    use pickplace_geometry::hash::mesh_hash;
    use pickplace_objects as objects;

    #[test]
    fn an_entry_gives_back_its_set_and_refuses_other_keys_and_damage() {
        let mesh = objects::mug_builder().build().expect("valid");
        let params = ClusterParams::finger();
        let clustering = cluster_surface(&mesh, &params).expect("valid");
        let options = GraspOptions::default();
        let set = GraspPlanner::new(&mesh)
            .and_then(|p| p.plan(&clustering, &gripper(), &options))
            .expect("plans");
        let k = key(mesh_hash(&mesh), &params, &gripper(), &options);
        let bytes = encode(k, &set);
        assert_eq!(decode(&bytes, k), Ok(set));
        // Another gripper, other options, another mesh: other keys.
        let mut wide = gripper();
        wide.opening_max += 0.01;
        let finer = GraspOptions {
            grid_step: 0.005,
            ..options
        };
        let other = objects::can_builder().build().expect("valid");
        for k2 in [
            key(mesh_hash(&mesh), &params, &wide, &options),
            key(mesh_hash(&mesh), &params, &gripper(), &finer),
            key(mesh_hash(&other), &params, &gripper(), &options),
        ] {
            assert_ne!(k2, k);
            assert_eq!(decode(&bytes, k2), Err(DbError::OtherKey));
        }
        // Every flipped byte and every truncation is refused, never decoded into another set.
        for i in (0..bytes.len()).step_by(7) {
            let mut b = bytes.clone();
            b[i] ^= 0x5a;
            assert!(decode(&b, k).is_err(), "byte {i}");
        }
        for n in [0, 3, HEADER - 1, HEADER, bytes.len() - 1] {
            assert!(decode(&bytes[..n], k).is_err(), "length {n}");
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(decode(&longer, k).is_err());
    }
}
