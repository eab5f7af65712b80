//! Precomputed PRM roadmaps per arm (paper §III-C: "we plan collision free trajectories
//! between [the key poses] by using the PRM").
//!
//! One roadmap per arm group serves every scene: its nodes are sampled in the arm's joint
//! space and filtered by self-collision only (the rest of the robot at the SRDF's `home`
//! state), and each query checks its own scene lazily. The prefilter checks only the pairs
//! the arm can change (one of their links moved by the arm's joints); the pairs of two
//! static links are checked once, at the template, and reported
//! ([`RoadmapReport::static_contacts`]). Roadmaps are cached in files named by
//! the robot, the group and a hash of everything that defines them (URDF and SRDF text, the
//! options, the codec version, the PRM's [`pickplace_prm::ALGORITHM_VERSION`] and the
//! prefilter's rule); the file starts with that hash too, checked on reading, so a stale or
//! renamed file is never used. A cache that cannot be read or written is not an error: the
//! roadmap is built in memory and [`RoadmapReport::cache_warning`] says why.

use crate::cache::CacheWarning;
use crate::checker::ArmChecker;
use crate::error::{Error, Result};
use pickplace_geometry::hash::ContentHasher;
use pickplace_prm::{
    JointSpace, Roadmap, RoadmapOptions, ValidityChecker, codec, motion_valid_by_interpolation,
};
use pickplace_robot::RobotModel;
use pickplace_robot::collision::{BodyId, CollisionWorld};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

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
    // Finite limits as they are (PR2's upper-arm roll spans 4.7 rad); a continuous joint
    // (infinite limits) over one turn, [−π, π], where IK puts its solutions.
    let clamp = |v: f64| {
        if v.is_finite() {
            v
        } else {
            v.clamp(-std::f64::consts::PI, std::f64::consts::PI)
        }
    };
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

/// The hash that names a roadmap: robot files' text, group, options, codec and algorithm
/// versions, the prefilter's rule.
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
    h.word(u64::from(pickplace_prm::ALGORITHM_VERSION));
    // The prefilter's rule: the margin on the pairs the arm moves only (static pairs are
    // checked once at the template), which changed which nodes survive.
    h.bytes(PREFILTER_RULE.as_bytes());
    h.finish()
}

/// First bytes of a roadmap cache file, before its key and the codec's bytes.
const ENTRY_MAGIC: [u8; 8] = *b"PPRMKEY1";

/// A roadmap cache file: [`ENTRY_MAGIC`], the key (u64 little-endian), the roadmap.
fn entry_bytes(key: u64, roadmap: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(16 + roadmap.len());
    out.extend_from_slice(&ENTRY_MAGIC);
    out.extend_from_slice(&key.to_le_bytes());
    out.extend_from_slice(roadmap);
    out
}

/// The roadmap's bytes of a cache file made for `key`, if it is one.
fn entry_roadmap(bytes: &[u8], key: u64) -> Option<&[u8]> {
    let rest = bytes.strip_prefix(&ENTRY_MAGIC[..])?;
    let (found, roadmap) = rest.split_first_chunk::<8>()?;
    (u64::from_le_bytes(*found) == key).then_some(roadmap)
}

/// A roadmap's cache file and the key that names it ([`roadmap_key`], [`roadmap_path`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RoadmapEntry<'a> {
    /// The file.
    pub path: &'a Path,
    /// The key, also stored in the file and checked on reading.
    pub key: u64,
    /// Whether a roadmap built now is written to the file.
    pub writable: bool,
}

/// Whether a roadmap came from the cache.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoadmapSource {
    /// Read from the cache file.
    Loaded,
    /// Built now (and written to the cache when there is one).
    Built,
}

/// The prefilter's rule, part of the roadmap key.
const PREFILTER_RULE: &str = "moving pairs with a 0.01 m margin; static pairs once";

/// The prefilter's clearance margin (m) on the pairs the arm moves.
const PREFILTER_MARGIN: f64 = 0.01;

/// A pair of bodies and how many sampled states it rejected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PairRejections {
    /// First body's name.
    pub first: String,
    /// Second body's name.
    pub second: String,
    /// Sampled states it rejected (the first colliding pair of each rejected draw).
    pub count: usize,
}

/// What loading or building an arm's roadmap found, for the setup's log.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RoadmapReport {
    /// Whether the roadmap came from the cache.
    pub source: RoadmapSource,
    /// Nodes in the roadmap.
    pub node_count: usize,
    /// Nodes asked for ([`RoadmapOptions::node_count`]).
    pub requested: usize,
    /// The pair of bodies that rejected most sampled states while building (`None` for a
    /// roadmap read from the cache, or when no sample was rejected).
    pub most_rejected: Option<PairRejections>,
    /// Pairs of links whose relative pose the arm does not change (two links of the rest of
    /// the robot, or two links of the hand with no arm joint between them) that touch at
    /// the template (its rest state): the prefilter does not check them per sample, but no
    /// state of the arm is free while they touch.
    pub static_contacts: Vec<(String, String)>,
    /// Why the cache file could not be read or written (`None` when it could, or when
    /// there is no cache): the roadmap is the same, built in memory.
    pub cache_warning: Option<CacheWarning>,
}

impl std::fmt::Display for RoadmapReport {
    /// `roadmap 3120 of 5000 nodes built; most rejected samples: a ~ b (1410)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "roadmap ")?;
        if self.node_count < self.requested {
            write!(f, "{} of {} nodes", self.node_count, self.requested)?;
        } else {
            write!(f, "{} nodes", self.node_count)?;
        }
        write!(
            f,
            " {}",
            match self.source {
                RoadmapSource::Loaded => "loaded from the cache",
                RoadmapSource::Built => "built",
            }
        )?;
        if let Some(r) = &self.most_rejected
            && self.node_count < self.requested
        {
            write!(
                f,
                "; most rejected samples: {} ~ {} ({})",
                r.first, r.second, r.count
            )?;
        }
        // The first few static contacts, then how many more.
        const SHOWN: usize = 3;
        for (a, b) in self.static_contacts.iter().take(SHOWN) {
            write!(f, "; static contact: {a} ~ {b}")?;
        }
        if self.static_contacts.len() > SHOWN {
            write!(
                f,
                " (and {} more static contacts)",
                self.static_contacts.len() - SHOWN
            )?;
        }
        Ok(())
    }
}

/// The prefilter: the arm's checker on the pairs it moves, counting the first colliding pair
/// of every rejected sample (not of edge states).
struct CountingPrefilter<'a> {
    checker: ArmChecker<'a>,
    rejections: Mutex<BTreeMap<(BodyId, BodyId), usize>>,
}

impl ValidityChecker for CountingPrefilter<'_> {
    fn is_state_valid(&self, q: &[f64]) -> bool {
        match self.checker.first_collision(q) {
            None => true,
            Some(pair) => {
                let mut counts = self
                    .rejections
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                *counts.entry(pair).or_insert(0) += 1;
                false
            }
        }
    }

    fn is_motion_valid(
        &self,
        space: &JointSpace,
        from: &[f64],
        to: &[f64],
        resolution: f64,
        scratch: &mut [f64],
    ) -> bool {
        motion_valid_by_interpolation(&self.checker, space, from, to, resolution, scratch)
    }
}

/// Loads the roadmap of an arm from `cache` (when given and valid), or builds it (nodes
/// prefiltered by self-collision with the rest of the robot at `home`: the pairs with a link
/// the arm moves, with a 1 cm margin) and saves it there.
///
/// # Returns
/// The roadmap and a report: its size against the size asked, the pair of bodies that
/// rejected most samples, and the static pairs in contact at `home`.
///
/// `progress(done, total)` is told how far a build got (see
/// [`Roadmap::build_prefiltered_with_progress`]); nothing is said for a roadmap read from the
/// cache.
///
/// A cache file that cannot be read (other than missing or damaged: rebuilt) or written is
/// not an error: the report's [`RoadmapReport::cache_warning`] says why.
///
/// # Errors
/// [`Error::EmptyRoadmap`] naming the pair that rejected most samples when no sample is
/// free; [`Error::Internal`] when the PRM rejects the space or the collision library fails.
pub fn load_or_build(
    model: &RobotModel,
    self_world: &CollisionWorld,
    group: &str,
    variables: &[usize],
    home: &[f64],
    space: &JointSpace,
    cache: Option<RoadmapEntry<'_>>,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(Roadmap, RoadmapReport)> {
    let checker = ArmChecker::new(
        model,
        self_world,
        variables,
        home.to_vec(),
        PREFILTER_MARGIN,
    )
    .moving_pairs_only();
    // The pairs the arm cannot change, checked once at `home`.
    checker.check_error()?;
    let static_contacts = checker
        .static_contacts()
        .iter()
        .map(|&(a, b)| {
            (
                self_world.body_name(a).to_owned(),
                self_world.body_name(b).to_owned(),
            )
        })
        .collect();
    let requested = roadmap_options().node_count;
    let mut cache_warning = None;
    if let Some(entry) = cache {
        match pickplace_geometry::io::read_bytes(entry.path, pickplace_geometry::io::CACHE_ENTRY) {
            Ok(bytes) => {
                if let Some(roadmap) = entry_roadmap(&bytes, entry.key)
                    .and_then(|bytes| codec::decode(bytes, space).ok())
                {
                    let report = RoadmapReport {
                        source: RoadmapSource::Loaded,
                        node_count: roadmap.node_count(),
                        requested,
                        most_rejected: None,
                        static_contacts,
                        cache_warning: None,
                    };
                    return Ok((roadmap, report));
                }
            }
            // Missing, or damaged (a FIFO, too large): built and written over.
            Err(e)
                if e.kind() == std::io::ErrorKind::NotFound
                    || pickplace_geometry::io::is_refused(&e) => {}
            Err(e) => {
                cache_warning = Some(CacheWarning::Unreadable {
                    entry: entry.path.to_path_buf(),
                    reason: crate::cache::os_reason(&e),
                });
            }
        }
    }
    let (roadmap, mut report) = build(
        self_world,
        group,
        checker,
        space,
        &roadmap_options(),
        static_contacts,
        progress,
    )?;
    if let Some(entry) = cache
        && entry.writable
        && cache_warning.is_none()
    {
        let bytes = codec::encode(&roadmap).map_err(crate::error::internal("roadmap encoding"))?;
        let written = match entry.path.parent() {
            Some(dir) if !dir.as_os_str().is_empty() => {
                std::fs::create_dir_all(dir).map_err(|e| (dir.to_path_buf(), e.to_string()))
            }
            _ => Ok(()),
        }
        .and_then(|()| {
            pickplace_geometry::export::write_atomic(entry.path, &entry_bytes(entry.key, &bytes))
                .map_err(|e| {
                    let folder = entry.path.parent().unwrap_or(Path::new(".")).to_path_buf();
                    (folder, crate::cache::write_reason(entry.path, &e))
                })
        });
        if let Err((folder, reason)) = written {
            cache_warning = Some(CacheWarning::NotWritable { folder, reason });
        }
    }
    report.cache_warning = cache_warning;
    Ok((roadmap, report))
}

/// A roadmap with no node, for a setup that never plans a motion
/// ([`crate::setup::SetupPurpose::Validation`]): nothing sampled, nothing read from the cache.
///
/// # Errors
/// [`Error::Internal`] when the PRM rejects the space.
pub fn empty(space: &JointSpace) -> Result<(Roadmap, RoadmapReport)> {
    let options = RoadmapOptions {
        node_count: 0,
        ..roadmap_options()
    };
    let roadmap =
        Roadmap::build_lazy(space, &options).map_err(crate::error::internal("empty roadmap"))?;
    let report = RoadmapReport {
        source: RoadmapSource::Built,
        node_count: 0,
        requested: 0,
        most_rejected: None,
        static_contacts: Vec::new(),
        cache_warning: None,
    };
    Ok((roadmap, report))
}

/// Builds the roadmap with the counting prefilter; an empty one is an error.
fn build(
    self_world: &CollisionWorld,
    group: &str,
    checker: ArmChecker<'_>,
    space: &JointSpace,
    options: &RoadmapOptions,
    static_contacts: Vec<(String, String)>,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(Roadmap, RoadmapReport)> {
    let prefilter = CountingPrefilter {
        checker,
        rejections: Mutex::default(),
    };
    let roadmap = Roadmap::build_prefiltered_with_progress(space, &prefilter, options, progress)
        .map_err(crate::error::internal("roadmap construction"))?;
    prefilter.checker.check_error()?;
    let counts = prefilter
        .rejections
        .into_inner()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    // The largest count; the first pair in body order among equals.
    let most_rejected = counts
        .iter()
        .fold(
            None,
            |best: Option<(&(BodyId, BodyId), usize)>, (pair, &n)| match best {
                Some((_, m)) if m >= n => best,
                _ => Some((pair, n)),
            },
        )
        .map(|(&(a, b), count)| PairRejections {
            first: self_world.body_name(a).to_owned(),
            second: self_world.body_name(b).to_owned(),
            count,
        });
    if roadmap.node_count() == 0 {
        return Err(match most_rejected {
            Some(r) => Error::EmptyRoadmap {
                group: group.to_owned(),
                first: r.first,
                second: r.second,
                rejections: r.count,
            },
            None => Error::Internal {
                stage: "roadmap construction",
                reason: format!("the roadmap of {group} is empty and no sample was rejected"),
            },
        });
    }
    let report = RoadmapReport {
        source: RoadmapSource::Built,
        node_count: roadmap.node_count(),
        requested: options.node_count,
        most_rejected,
        static_contacts,
        cache_warning: None,
    };
    Ok((roadmap, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_robot::collision::AllowedCollisionMatrix;

    fn small() -> RoadmapOptions {
        RoadmapOptions {
            node_count: 40,
            ..roadmap_options()
        }
    }

    #[test]
    fn the_right_arm_of_nx_hiro_fills_its_roadmap_with_no_static_contact() {
        let setup = crate::testing::setup("fig9-near.toml");
        let arm = setup.arm(crate::Arm::Right);
        let world = CollisionWorld::new(
            &setup.model,
            AllowedCollisionMatrix::from_srdf(setup.semantics.srdf()),
        )
        .expect("valid shapes");
        let checker = ArmChecker::new(
            &setup.model,
            &world,
            &arm.variables,
            setup.start.clone(),
            0.01,
        )
        .moving_pairs_only();
        let (roadmap, report) = build(
            &world,
            "right_arm",
            checker,
            &arm.space,
            &small(),
            Vec::new(),
            &|_, _| {},
        )
        .expect("builds");
        assert_eq!(roadmap.node_count(), 40);
        assert_eq!((report.node_count, report.requested), (40, 40));
        assert_eq!(report.to_string(), "roadmap 40 nodes built");
        // The setup's own report: no two static links touch at NX-HIRO's start.
        assert!(arm.roadmap_report.static_contacts.is_empty());
    }

    #[test]
    fn an_arm_always_in_collision_gives_an_error_naming_the_pair() {
        let setup = crate::testing::setup("fig9-near.toml");
        let arm = setup.arm(crate::Arm::Right);
        // Without the SRDF's disabled pairs, neighbouring links of the arm always touch.
        let world =
            CollisionWorld::new(&setup.model, AllowedCollisionMatrix::new()).expect("valid shapes");
        let checker = ArmChecker::new(
            &setup.model,
            &world,
            &arm.variables,
            setup.start.clone(),
            0.01,
        )
        .moving_pairs_only();
        let e = build(
            &world,
            "right_arm",
            checker,
            &arm.space,
            &small(),
            Vec::new(),
            &|_, _| {},
        )
        .expect_err("no free sample");
        let Error::EmptyRoadmap {
            group,
            first,
            second,
            rejections,
        } = &e
        else {
            panic!("{e}");
        };
        assert_eq!(group, "right_arm");
        assert!(
            first.starts_with("RARM") || second.starts_with("RARM"),
            "{e}"
        );
        assert!(
            *rejections > 0 && *rejections <= 40 * small().max_sample_attempts,
            "{e}"
        );
    }

    #[test]
    fn a_short_roadmap_names_the_pair_that_rejected_most() {
        let report = RoadmapReport {
            source: RoadmapSource::Built,
            node_count: 3120,
            requested: 5000,
            most_rejected: Some(PairRejections {
                first: "r_forearm_link".into(),
                second: "r_upper_arm_link".into(),
                count: 1410,
            }),
            static_contacts: vec![("torso".into(), "l_shoulder".into())],
            cache_warning: None,
        };
        assert_eq!(
            report.to_string(),
            "roadmap 3120 of 5000 nodes built; most rejected samples: r_forearm_link ~ \
             r_upper_arm_link (1410); static contact: torso ~ l_shoulder"
        );
    }

    #[test]
    fn a_cached_roadmap_equals_the_built_one_and_a_file_of_another_key_is_rebuilt() {
        let setup = crate::testing::setup("fig9-near.toml");
        let arm = setup.arm(crate::Arm::Right);
        let world = CollisionWorld::new(
            &setup.model,
            AllowedCollisionMatrix::from_srdf(setup.semantics.srdf()),
        )
        .expect("valid shapes");
        let dir = std::env::temp_dir().join(format!("pickplace-roadmap-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let path = dir.join("arm.roadmap");
        let run = |key: u64| {
            load_or_build(
                &setup.model,
                &world,
                &arm.group,
                &arm.variables,
                &setup.start,
                &arm.space,
                Some(RoadmapEntry {
                    path: &path,
                    key,
                    writable: true,
                }),
                &|_, _| {},
            )
            .expect("roadmap")
        };
        let (built, report) = run(7);
        assert_eq!(report.source, RoadmapSource::Built);
        assert_eq!(report.cache_warning, None);
        let (loaded, report) = run(7);
        assert_eq!(report.source, RoadmapSource::Loaded);
        assert!(loaded == built);
        // The key is checked in the file, not only in its name.
        let (_, report) = run(8);
        assert_eq!(report.source, RoadmapSource::Built);
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }

    #[test]
    fn entries_carry_their_key() {
        let bytes = entry_bytes(0x1234, b"roadmap");
        assert_eq!(entry_roadmap(&bytes, 0x1234), Some(&b"roadmap"[..]));
        assert_eq!(entry_roadmap(&bytes, 0x1235), None);
        assert_eq!(entry_roadmap(b"PPRMKEY1", 0), None);
        assert_eq!(entry_roadmap(b"", 0), None);
    }
}
