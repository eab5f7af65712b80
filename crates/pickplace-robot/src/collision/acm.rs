//! The allowed-collision matrix: pairs of bodies that are never checked, each with a reason
//! (MoveIt's `disable_collisions`).

use super::{CollisionScratch, CollisionWorld};
use crate::error::{Error, Result};
use crate::model::RobotModel;
use crate::rng::Rng;
use crate::srdf::{DisableReason, DisabledPair, Srdf};
use pickplace_geometry::math::{Isometry3, Real};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Options of [`AllowedCollisionMatrix::generate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AcmOptions {
    /// Random configurations sampled, uniform within the joint limits (default: 10 000).
    pub samples: usize,
    /// Seed of the sampling (default: 0).
    pub seed: u64,
    /// A pair in collision in at least this fraction of the samples is disabled as
    /// [`DisableReason::Always`] (default: 0.95, MoveIt's setup assistant's "usually in
    /// collision"): a wrist roll link and the palm it carries overlap in most, not all,
    /// sampled configurations, and checking them would leave no free configuration. 1.0
    /// keeps only the pairs in collision in every sample.
    pub min_collision_fraction: Real,
}

/// Version of the sampling of [`AllowedCollisionMatrix::generate`]: a cached matrix made by
/// another version is sampled again.
pub const SAMPLING_VERSION: u32 = 2;

/// Samples per block of [`AllowedCollisionMatrix::generate`] (one generator per block).
const SAMPLE_BLOCK: usize = 250;

/// The stream of [`Rng::derive`] the matrix samples are drawn from.
const ACM_STREAM: u64 = 0x0041_434d;

/// Default of [`AcmOptions::min_collision_fraction`].
pub const DEFAULT_MIN_COLLISION_FRACTION: Real = 0.95;

impl Default for AcmOptions {
    fn default() -> Self {
        Self {
            samples: 10_000,
            seed: 0,
            min_collision_fraction: DEFAULT_MIN_COLLISION_FRACTION,
        }
    }
}

/// What [`AllowedCollisionMatrix::generate`] found, besides the matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct AcmReport {
    /// The generated matrix (adjacent, always and never pairs).
    pub acm: AllowedCollisionMatrix,
    /// Configurations sampled.
    pub samples: usize,
    /// Link pairs with geometry that collided in some but not all samples (checked pairs),
    /// with the number of samples in which they collided, sorted by name.
    pub sometimes: Vec<(String, String, usize)>,
}

/// Pairs of named bodies (links, environment objects, attached objects) that are allowed to
/// touch, each with the reason. Pairs are unordered.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AllowedCollisionMatrix {
    pairs: BTreeMap<(String, String), DisableReason>,
}

fn key(a: &str, b: &str) -> (String, String) {
    if a <= b {
        (a.to_owned(), b.to_owned())
    } else {
        (b.to_owned(), a.to_owned())
    }
}

impl AllowedCollisionMatrix {
    /// An empty matrix: everything is checked.
    pub fn new() -> Self {
        Self::default()
    }

    /// The SRDF's `disable_collisions` pairs.
    pub fn from_srdf(srdf: &Srdf) -> Self {
        let mut acm = Self::new();
        for pair in &srdf.disabled_collisions {
            acm.allow(&pair.link1, &pair.link2, pair.reason.clone());
        }
        acm
    }

    /// Every pair of links joined by a joint (reason [`DisableReason::Adjacent`]), also
    /// across fixed joints to links without geometry (MoveIt's rule: links whose geometry
    /// moves rigidly together, or that share a joint, are adjacent).
    pub fn adjacent_links(model: &RobotModel) -> Self {
        let mut acm = Self::new();
        for joint in model.joints() {
            // The nearest ancestor with geometry, skipping geometry-less links across fixed joints.
            let child = joint.child_link;
            let mut parent = Some(joint.parent_link);
            while let Some(p) = parent {
                acm.allow(
                    &model.links()[p].name,
                    &model.links()[child].name,
                    DisableReason::Adjacent,
                );
                if !model.links()[p].collisions.is_empty() {
                    break;
                }
                parent = model.parent_link(p);
            }
        }
        acm
    }

    /// Generates the matrix the way MoveIt's setup assistant does: links joined by a joint
    /// are [`DisableReason::Adjacent`]; then `options.samples` random configurations
    /// (uniform within the limits, seeded) are checked for self-collision of every pair of
    /// links with geometry (no matrix applied): pairs in collision in at least
    /// `options.min_collision_fraction` of the samples are [`DisableReason::Always`], pairs
    /// never in collision are [`DisableReason::Never`]. Links without collision geometry are
    /// left out: they never collide.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for zero samples or a fraction outside (0, 1]; errors of
    /// the collision queries.
    pub fn generate(model: &RobotModel, options: &AcmOptions) -> Result<AcmReport> {
        if options.samples == 0 {
            return Err(Error::InvalidParameter {
                name: "samples",
                value: 0.0,
                reason: "at least one configuration must be sampled",
            });
        }
        let fraction = options.min_collision_fraction;
        if !(fraction > 0.0 && fraction <= 1.0) {
            return Err(Error::InvalidParameter {
                name: "min_collision_fraction",
                value: fraction,
                reason: "must be in (0, 1]",
            });
        }
        // The least count that is "usually": ceil(fraction x samples), at least one sample.
        let usually =
            ((fraction * options.samples as Real).ceil() as usize).clamp(1, options.samples);
        let world = CollisionWorld::new(model, Self::new())?;
        let link_count = model.links().len();
        let adjacent = Self::adjacent_links(model);
        // Pairs joined by a joint are decided already: not tested (they usually touch, and
        // their narrow phase is the costliest).
        let mut wanted = vec![false; link_count * link_count];
        for a in 0..link_count {
            for b in a + 1..link_count {
                let (na, nb) = (&model.links()[a].name, &model.links()[b].name);
                wanted[a * link_count + b] = !adjacent.is_allowed(na, nb);
            }
        }
        let limits = model.sampling_limits();
        // Fixed blocks of samples, each with a generator of its own, counted in parallel and
        // summed: the counts do not depend on the number of threads.
        let blocks = options.samples.div_ceil(SAMPLE_BLOCK);
        let counts = (0..blocks)
            .into_par_iter()
            .map(|block| -> Result<Vec<usize>> {
                let mut counts = vec![0usize; link_count * link_count];
                let mut scratch = CollisionScratch::default();
                let mut poses = vec![Isometry3::identity(); link_count];
                let mut rng = Rng::derive(options.seed, ACM_STREAM, block as u64);
                let mut q = vec![0.0; model.variable_count()];
                let n = SAMPLE_BLOCK.min(options.samples - block * SAMPLE_BLOCK);
                for _ in 0..n {
                    for (value, &(lower, upper)) in q.iter_mut().zip(&limits) {
                        *value = rng.uniform(lower, upper);
                    }
                    model.forward_kinematics(&q, &mut poses)?;
                    let pairs =
                        world.colliding_link_pairs_where(&poses, &mut scratch, |a, b| {
                            wanted[a * link_count + b]
                        })?;
                    for (a, b) in pairs {
                        counts[a * link_count + b] += 1;
                    }
                }
                Ok(counts)
            })
            .try_reduce(
                || vec![0usize; link_count * link_count],
                |mut a, b| {
                    a.iter_mut().zip(&b).for_each(|(x, y)| *x += y);
                    Ok(a)
                },
            )?;

        let mut acm = adjacent;
        let mut sometimes = Vec::new();
        let links = model.links();
        for a in 0..link_count {
            for b in a + 1..link_count {
                if links[a].collisions.is_empty() || links[b].collisions.is_empty() {
                    continue;
                }
                let (na, nb) = (&links[a].name, &links[b].name);
                if acm.is_allowed(na, nb) {
                    continue;
                }
                match counts[a * link_count + b] {
                    0 => acm.allow(na, nb, DisableReason::Never),
                    n if n >= usually => acm.allow(na, nb, DisableReason::Always),
                    n => sometimes.push((na.clone(), nb.clone(), n)),
                }
            }
        }
        sometimes.sort();
        Ok(AcmReport {
            acm,
            samples: options.samples,
            sometimes,
        })
    }

    /// The pairs as SRDF `disable_collisions` entries, sorted by name.
    pub fn to_disabled_pairs(&self) -> Vec<DisabledPair> {
        self.iter()
            .map(|(a, b, r)| DisabledPair {
                link1: a.to_owned(),
                link2: b.to_owned(),
                reason: r.clone(),
            })
            .collect()
    }

    /// Allows a pair (replacing an earlier reason).
    pub fn allow(&mut self, a: &str, b: &str, reason: DisableReason) {
        if a != b {
            self.pairs.insert(key(a, b), reason);
        }
    }

    /// Adds every pair of `other` not already present.
    pub fn merge(&mut self, other: &Self) {
        for (k, v) in &other.pairs {
            self.pairs.entry(k.clone()).or_insert_with(|| v.clone());
        }
    }

    /// Checks the pair again.
    pub fn forbid(&mut self, a: &str, b: &str) {
        self.pairs.remove(&key(a, b));
    }

    /// Why the pair is allowed, or `None` when it is checked. A body is always allowed to
    /// touch itself.
    pub fn reason(&self, a: &str, b: &str) -> Option<&DisableReason> {
        self.pairs.get(&key(a, b))
    }

    /// True when the pair is not checked.
    pub fn is_allowed(&self, a: &str, b: &str) -> bool {
        a == b || self.pairs.contains_key(&key(a, b))
    }

    /// Number of allowed pairs.
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    /// True when no pair is allowed.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// The pairs, sorted by name.
    pub fn iter(&self) -> impl Iterator<Item = (&str, &str, &DisableReason)> + '_ {
        self.pairs
            .iter()
            .map(|((a, b), r)| (a.as_str(), b.as_str(), r))
    }

    /// Number of pairs per reason, sorted by reason.
    pub fn counts_by_reason(&self) -> BTreeMap<DisableReason, usize> {
        let mut counts = BTreeMap::new();
        for r in self.pairs.values() {
            *counts.entry(r.clone()).or_insert(0) += 1;
        }
        counts
    }
}
