//! A map of where an arm's hand can be, and pointing which way: the order in which grasps
//! are tried, not a filter.
//!
//! The paper's planner (§III-B.3, Fig. 8) tries grasps in their rank order and solves IK for
//! each; on real objects most candidates that pass the cheap tests still have no IK (the
//! carton of the scene suite: 498 of 601), and a failed IK costs all the solver's restarts.
//! This map, a capability map in the manner of Zacharias et al. (IROS 2007), records from
//! seeded random configurations of the arm's joints which cells of its workspace (5 cm voxels)
//! the tool point reaches with its approach axis in which of 64 directions (an octahedral
//! map of the sphere). A grasp whose tool pose falls in a recorded cell (or next to one) is
//! tried before those that do not; every candidate is still tried, so the search stays
//! complete and only its order changes.

use pickplace_base::rng::{Stream, salted};
use pickplace_geometry::math::{Isometry3, Real, Vector3};
use pickplace_robot::kinematics::KinematicChain;

/// Edge of a workspace voxel (m).
const VOXEL: Real = 0.05;

/// Configurations sampled per arm.
const SAMPLES: usize = 1 << 16;

/// Samples drawn per generator.
const CHUNK: usize = 4096;

/// Direction bins per axis of the octahedral map (`BINS`² = 64 bins, one bit each).
const BINS: usize = 8;

/// Where an arm's tool point gets to and with which approach directions (root frame).
#[derive(Debug, Clone)]
pub struct ReachMap {
    origin: Vector3,
    dims: [usize; 3],
    /// Per voxel, one bit per approach direction bin reached.
    cells: Vec<u64>,
    /// The approach axis in the tool frame.
    approach: Vector3,
}

impl ReachMap {
    /// Samples `chain` at seeded random values of `variables` (model indices, between
    /// `lower` and `upper`), the other joints at `template`, and records the cells reached.
    pub fn build(
        chain: &KinematicChain,
        template: &[Real],
        variables: &[usize],
        (lower, upper): (&[Real], &[Real]),
        approach: Vector3,
        seed: u64,
    ) -> Self {
        use rayon::prelude::*;
        // Chunks of samples on the thread pool, each with its own seeded generator: the same
        // samples whatever the thread count.
        let hits: Vec<(Vector3, u32)> = (0..SAMPLES / CHUNK)
            .into_par_iter()
            .flat_map_iter(|k| {
                let mut rng = pickplace_prm::rng::Rng::new(salted(seed, Stream::Ik, k as u64));
                let mut q = template.to_vec();
                (0..CHUNK)
                    .map(|_| {
                        for (c, &v) in variables.iter().enumerate() {
                            q[v] = rng.uniform(lower[c], upper[c]);
                        }
                        let pose = chain.pose(&q);
                        (
                            pose.translation.vector,
                            direction_bin(&(pose.rotation * approach)),
                        )
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        let mut lo = Vector3::repeat(Real::INFINITY);
        let mut hi = Vector3::repeat(Real::NEG_INFINITY);
        for (p, _) in &hits {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        if hits.is_empty() || !lo.iter().chain(hi.iter()).all(|x| x.is_finite()) {
            return Self::empty(approach);
        }
        let dims = [0, 1, 2].map(|k| ((hi[k] - lo[k]) / VOXEL).floor() as usize + 1);
        let mut map = Self {
            origin: lo,
            dims,
            cells: vec![0; dims[0] * dims[1] * dims[2]],
            approach,
        };
        for (p, bin) in hits {
            if let Some(i) = map.index(&map.voxel(&p)) {
                map.cells[i] |= 1 << bin;
            }
        }
        map
    }

    /// A map of no cell: every pose scores 0. For a setup that never asks (validation).
    pub fn empty(approach: Vector3) -> Self {
        Self {
            origin: Vector3::zeros(),
            dims: [0; 3],
            cells: Vec::new(),
            approach,
        }
    }

    /// The voxel coordinates of `p` (may be outside the grid).
    fn voxel(&self, p: &Vector3) -> [i64; 3] {
        [0, 1, 2].map(|k| ((p[k] - self.origin[k]) / VOXEL).floor() as i64)
    }

    fn index(&self, v: &[i64; 3]) -> Option<usize> {
        let mut i = 0;
        for k in (0..3).rev() {
            let d = self.dims[k];
            let c = usize::try_from(v[k]).ok().filter(|&c| c < d)?;
            i = i * d + c;
        }
        Some(i)
    }

    /// How many of the voxel of `root_from_tcp` and its 26 neighbours were reached with the
    /// pose's approach direction (0 to 27): 0 means no sample came near, and IK is likely to
    /// fail; more means the pose is well inside the sampled workspace.
    pub fn score(&self, root_from_tcp: &Isometry3) -> u32 {
        let bit = 1u64 << direction_bin(&(root_from_tcp.rotation * self.approach));
        let v = self.voxel(&root_from_tcp.translation.vector);
        let mut n = 0;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(i) = self.index(&[v[0] + dx, v[1] + dy, v[2] + dz])
                        && self.cells[i] & bit != 0
                    {
                        n += 1;
                    }
                }
            }
        }
        n
    }
}

/// The bin (0 to 63) of a direction on the octahedral map of the sphere.
fn direction_bin(d: &Vector3) -> u32 {
    let l1 = d.x.abs() + d.y.abs() + d.z.abs();
    if l1 <= 0.0 || !l1.is_finite() {
        return 0;
    }
    let (mut u, mut v) = (d.x / l1, d.y / l1);
    if d.z < 0.0 {
        (u, v) = ((1.0 - v.abs()) * u.signum(), (1.0 - u.abs()) * v.signum());
    }
    let cell =
        |x: Real| (((x + 1.0) * 0.5 * BINS as Real).floor() as i64).clamp(0, BINS as i64 - 1);
    (cell(u) * BINS as i64 + cell(v)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn direction_bins_cover_the_sphere_and_separate_opposites() {
        let mut seen = std::collections::BTreeSet::new();
        let mut rng = pickplace_prm::rng::Rng::new(3);
        for _ in 0..20_000 {
            let d = Vector3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            );
            let b = direction_bin(&d);
            assert!(b < 64);
            seen.insert(b);
            assert_ne!(b, direction_bin(&-d), "{d:?}");
        }
        assert_eq!(seen.len(), 64);
    }

    #[test]
    fn reached_poses_score_and_poses_beyond_the_arm_do_not() {
        let setup = crate::testing::setup("fig9-near.toml");
        for arm in &setup.arms {
            let chain = arm.ik.chain();
            let mut rng = pickplace_prm::rng::Rng::new(11);
            let mut q = setup.start.clone();
            let mut scored = 0;
            for _ in 0..200 {
                for (c, &v) in arm.variables.iter().enumerate() {
                    q[v] = rng.uniform(arm.space.lower()[c], arm.space.upper()[c]);
                }
                if arm.reach_map.score(&chain.pose(&q)) > 0 {
                    scored += 1;
                }
            }
            // Fresh samples of the arm's own space land in (or next to) sampled cells.
            assert!(scored >= 190, "{}: {scored} of 200", arm.group);
            let far = Isometry3::translation(5.0, 0.0, 0.0);
            assert_eq!(arm.reach_map.score(&far), 0);
        }
    }

    #[test]
    fn the_map_is_the_same_whatever_the_thread_count() {
        let setup = crate::testing::setup("fig9-near.toml");
        let arm = &setup.arms[0];
        let build = || {
            ReachMap::build(
                arm.ik.chain(),
                &setup.start,
                &arm.variables,
                (arm.space.lower(), arm.space.upper()),
                setup.gripper.approach(),
                7,
            )
        };
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("a pool")
            .install(build);
        let two = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("a pool")
            .install(build);
        assert_eq!(one.cells, two.cells);
        assert_eq!(one.dims, two.dims);
    }
}
