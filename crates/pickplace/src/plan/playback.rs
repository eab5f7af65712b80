//! How a plan plays back: its holds, its trajectory's columns for a robot's joint order, and
//! its motions (the trajectory cut where the robot stops).

use super::*;

impl Plan {
    /// The plan's holds in time order of their grasps: each grasp lasts until the next
    /// release by the same link.
    ///
    /// # Errors
    /// `event I: …` for an event whose pose is invalid or a release without a grasp by the
    /// same link before it (events numbered in time order).
    pub fn holds(&self) -> Result<Vec<Hold>, PlanFormError> {
        let mut events: Vec<&Event> = self.events.iter().collect();
        events.sort_by(|a, b| a.time.total_cmp(&b.time));
        let mut holds: Vec<Hold> = Vec::new();
        let mut open: Vec<(&str, usize)> = Vec::new();
        for (i, e) in events.iter().enumerate() {
            match e.kind {
                EventKind::Grasp => {
                    let link_from_object = e
                        .link_from_object
                        .to_isometry()
                        .map_err(|r| format!("event {i}: link_from_object: {r}"))?;
                    open.push((&e.link, holds.len()));
                    holds.push(Hold {
                        link: e.link.clone(),
                        link_from_object,
                        grasp_time: e.time,
                        release_time: None,
                    });
                }
                EventKind::Release => {
                    let k = open
                        .iter()
                        .rposition(|(l, _)| *l == e.link)
                        .ok_or_else(|| {
                            format!(
                                "event {i}: release by {:?} without a grasp before it",
                                e.link
                            )
                        })?;
                    let (_, h) = open.remove(k);
                    holds[h].release_time = Some(e.time);
                }
            }
        }
        Ok(holds)
    }

    /// For each of `names` (a robot's actuated joints, in its order), the column of
    /// [`TrajectoryPoint::positions`] that holds it.
    ///
    /// # Errors
    /// When the plan's joints are not exactly these: the missing and the unknown names.
    pub fn columns(&self, names: &[&str]) -> Result<Vec<usize>, PlanFormError> {
        let found: Vec<Option<usize>> = names
            .iter()
            .map(|n| self.joint_names.iter().position(|p| p == n))
            .collect();
        let missing: Vec<&str> = names
            .iter()
            .zip(&found)
            .filter(|(_, c)| c.is_none())
            .map(|(n, _)| *n)
            .collect();
        let unknown: Vec<&str> = self
            .joint_names
            .iter()
            .map(String::as_str)
            .filter(|p| !names.contains(p))
            .collect();
        if !missing.is_empty() || !unknown.is_empty() {
            return Err(format!("missing {missing:?}, unknown {unknown:?}").into());
        }
        Ok(found.into_iter().flatten().collect())
    }

    /// The plan cut into its motions: from one stop of the robot to the next. The robot
    /// stops at the start, at every grasp and release, at the end, and wherever a sample's
    /// velocities are all 0 (format 2: a key pose it does not pass through moving, a corner
    /// that was not blended); in a plan without velocities (format 1), at every key pose. A
    /// motion is the samples from one stop to the next, both included. Times that fall
    /// between samples (a malformed plan) cut at the sample before.
    pub fn motions(&self) -> Vec<Motion> {
        let Some(last) = self.trajectory.len().checked_sub(1) else {
            return Vec::new();
        };
        let index_at = |t: Real| {
            self.trajectory
                .partition_point(|p| p.time_from_start <= t + 1e-9)
                .saturating_sub(1)
        };
        let at_rest = |i: usize| {
            self.trajectory
                .get(i)
                .is_some_and(|p| p.velocities.iter().all(|v| *v == 0.0))
        };
        // Each cut with what happens there (the latest name wins at one instant).
        let mut cuts: BTreeMap<usize, String> = BTreeMap::new();
        for k in &self.key_poses {
            let i = index_at(k.time);
            if at_rest(i) {
                cuts.insert(i, k.name.clone());
            }
        }
        for e in &self.events {
            let name = match e.kind {
                EventKind::Grasp => "grasp",
                EventKind::Release => "release",
            };
            cuts.entry(index_at(e.time))
                .or_insert_with(|| format!("{name} ({})", e.arm));
        }
        for i in 1..last {
            if self.trajectory[i].velocities.iter().any(|_| true) && at_rest(i) {
                cuts.entry(i).or_insert_with(|| "stop".into());
            }
        }
        cuts.entry(last).or_insert_with(|| "end".into());
        let mut motions = Vec::new();
        let mut from = 0;
        for (to, name) in cuts {
            if to <= from {
                continue;
            }
            let moved = |columns: &[usize]| {
                columns.iter().any(|&c| {
                    let first = self.trajectory[from].positions.get(c);
                    self.trajectory[from..=to]
                        .iter()
                        .any(|p| p.positions.get(c) != first)
                })
            };
            let column = |name: &String| self.joint_names.iter().position(|n| n == name);
            let arms = self
                .arms
                .iter()
                .filter(|a| {
                    let columns: Vec<usize> = a
                        .joints
                        .iter()
                        .chain(&a.gripper_joints)
                        .filter_map(column)
                        .collect();
                    moved(&columns)
                })
                .map(|a| a.arm)
                .collect();
            motions.push(Motion {
                first: from,
                last: to,
                to: name,
                arms,
            });
            from = to;
        }
        motions
    }
}

/// A motion of a plan ([`Plan::motions`]): samples `first..=last` of the trajectory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Motion {
    /// Index of its first sample (the robot at rest).
    pub first: usize,
    /// Index of its last sample (the robot at rest).
    pub last: usize,
    /// What it reaches: the key pose's name, `grasp (right)`, `release (left)`, `stop` (a
    /// corner that was not blended) or `end`.
    pub to: String,
    /// The arms (from [`Plan::arms`]) whose joints or gripper move in it.
    pub arms: Vec<Arm>,
}
