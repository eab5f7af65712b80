//! Precomputed PRM roadmaps per arm (paper §III-C: "we plan collision free trajectories
//! between [the key poses] by using the PRM").
//!
//! One roadmap per arm group serves every scene: its nodes are sampled in the arm's joint
//! space and filtered by self-collision only (the rest of the robot at the SRDF's `home`
//! state), and each query checks its own scene lazily. Roadmaps are cached in files named by
//! the robot, the group and a hash of everything that defines them (URDF and SRDF text, the
//! options, the codec version), so a stale file is never used.

use crate::checker::ArmChecker;
use crate::error::{Error, Result};
use pickplace_geometry::hash::ContentHasher;
use pickplace_prm::{JointSpace, Roadmap, RoadmapOptions, codec};
use pickplace_robot::RobotModel;
use pickplace_robot::collision::CollisionWorld;
use std::path::{Path, PathBuf};

/// Extension of roadmap files.
pub const ROADMAP_EXTENSION: &str = "roadmap";

/// The options every arm roadmap is built with (fixed, so that a cached roadmap is the one
/// these options build): 5 000 nodes, 10 neighbours, 0.05 rad edge resolution, seed 1.
pub fn roadmap_options() -> RoadmapOptions {
    RoadmapOptions {
        node_count: 5000,
        resolution: 0.05,
        seed: 1,
        ..RoadmapOptions::default()
    }
}

/// The joint space of an arm group: its variables' limits, unit weights.
///
/// # Errors
/// [`Error::Internal`] when a limit is infinite (a continuous joint in an arm).
pub fn arm_space(model: &RobotModel, variables: &[usize]) -> Result<JointSpace> {
    let limits: Vec<_> = model.variable_limits().copied().collect();
    let clamp = |v: f64| v.clamp(-std::f64::consts::PI, std::f64::consts::PI);
    JointSpace::with_unit_weights(
        variables.iter().map(|&v| clamp(limits[v].lower)).collect(),
        variables.iter().map(|&v| clamp(limits[v].upper)).collect(),
    )
    .map_err(crate::error::internal("arm joint space"))
}

/// The cache file of a group's roadmap: `<dir>/<robot>.<group>.<hash>.roadmap`.
pub fn roadmap_path(dir: &Path, robot_name: &str, group: &str, key: u64) -> PathBuf {
    dir.join(format!(
        "{robot_name}.{group}.{key:016x}.{ROADMAP_EXTENSION}"
    ))
}

/// The hash that names a roadmap: robot files' text, group, options and codec version.
pub fn roadmap_key(urdf_text: &str, srdf_text: &str, group: &str) -> u64 {
    let o = roadmap_options();
    let mut h = ContentHasher::default();
    h.bytes(urdf_text.as_bytes());
    h.bytes(srdf_text.as_bytes());
    h.bytes(group.as_bytes());
    h.word(o.node_count as u64);
    h.word(o.neighbors as u64);
    h.word(o.max_edge_length.to_bits());
    h.word(o.resolution.to_bits());
    h.word(o.seed);
    h.word(u64::from(codec::FORMAT_VERSION));
    h.finish()
}

/// Whether a roadmap came from the cache.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoadmapSource {
    /// Read from the cache file.
    Loaded,
    /// Built now (and written to the cache when there is one).
    Built,
}

/// Loads the roadmap of an arm from `cache` (when given and valid), or builds it (nodes
/// prefiltered by self-collision with the rest of the robot at `home`) and saves it there.
///
/// # Errors
/// [`Error::Cache`] when the file cannot be written; [`Error::Internal`] when the PRM rejects
/// the space.
pub fn load_or_build(
    model: &RobotModel,
    self_world: &CollisionWorld,
    variables: &[usize],
    home: &[f64],
    space: &JointSpace,
    cache: Option<&Path>,
) -> Result<(Roadmap, RoadmapSource)> {
    if let Some(path) = cache
        && let Ok(bytes) = std::fs::read(path)
        && let Ok(roadmap) = codec::decode(&bytes, space)
    {
        return Ok((roadmap, RoadmapSource::Loaded));
    }
    let checker = ArmChecker::new(model, self_world, variables, home.to_vec(), 0.01);
    let roadmap = Roadmap::build_prefiltered(space, &checker, &roadmap_options())
        .map_err(crate::error::internal("roadmap construction"))?;
    checker.check_error()?;
    if let Some(path) = cache {
        let bytes = codec::encode(&roadmap).map_err(crate::error::internal("roadmap encoding"))?;
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|source| Error::Cache {
                path: path.to_path_buf(),
                source,
            })?;
        }
        pickplace_geometry::export::write_atomic(path, &bytes).map_err(|e| Error::Cache {
            path: path.to_path_buf(),
            source: std::io::Error::other(e.to_string()),
        })?;
    }
    Ok((roadmap, RoadmapSource::Built))
}
