//! The allowed-collision matrix: pairs of bodies that are never checked, each with a reason
//! (MoveIt's `disable_collisions`).

use crate::model::RobotModel;
use crate::srdf::{DisableReason, Srdf};
use std::collections::BTreeMap;

/// Pairs of named bodies (links, environment objects, attached objects) that are allowed to
/// touch, each with the reason. Pairs are unordered.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AllowedCollisionMatrix {
    pairs: BTreeMap<(String, String), DisableReason>,
}

fn key(a: &str, b: &str) -> (String, String) {
    if a <= b { (a.to_owned(), b.to_owned()) } else { (b.to_owned(), a.to_owned()) }
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
                acm.allow(&model.links()[p].name, &model.links()[child].name, DisableReason::Adjacent);
                if !model.links()[p].collisions.is_empty() {
                    break;
                }
                parent = model.parent_link(p);
            }
        }
        acm
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
        self.pairs.iter().map(|((a, b), r)| (a.as_str(), b.as_str(), r))
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
