//! An SRDF resolved against a model ([`Semantics`]): names turned into indices, and what was
//! accepted with a change of meaning reported as [`SrdfWarning`]s.

use super::{GroupSpec, NameKind, Srdf};
use crate::error::{Error, Result, SrdfErrorKind};
use crate::kinematics::KinematicChain;
use crate::model::RobotModel;
use pickplace_geometry::math::{Isometry3, Real};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A planning group resolved against a model.
#[derive(Debug, Clone)]
pub struct Group {
    /// Name.
    pub name: String,
    /// The group's variables, in model order.
    pub variables: Vec<usize>,
    /// The links the group's joints move (the child links of its joints), in model order.
    pub links: Vec<usize>,
    /// The tip link used for IK: the tip of its single chain, else the parent link of the
    /// end effector whose `parent_group` is this group, else, when its moving joints form
    /// one serial chain, the child link of the deepest one.
    pub tip_link: Option<usize>,
    /// Every URDF joint of the group (fixed ones too; virtual joints left out), in model
    /// order.
    pub joints: Vec<usize>,
}

/// An end effector resolved against a model.
#[derive(Debug, Clone)]
pub struct ResolvedEndEffector {
    /// Name.
    pub name: String,
    /// The TCP link.
    pub parent_link: usize,
    /// The end effector's own group.
    pub group: String,
    /// The arm group.
    pub parent_group: Option<String>,
}

/// Something in an SRDF that was accepted with a change of meaning, returned as data by
/// [`Semantics::warnings`] (the library never prints).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum SrdfWarning {
    /// A joint that the URDF does not have, declared by `<virtual_joint>` or given several
    /// numbers in a group state (a floating or planar root): left out of planning. Reported
    /// once per joint, with every place that names it.
    VirtualJoint {
        /// The joint's name.
        name: String,
        /// Its `type` (`fixed`, `planar`, `floating`), or `None` when it is not declared.
        joint_type: Option<String>,
        /// Where the SRDF names it (`group "base"`, `group_state "half_sitting"`, …).
        used_in: Vec<String>,
    },
    /// Elements of a kind this crate does not read, skipped with their content.
    IgnoredElement {
        /// The element's name (`gripper`, `contact`, …).
        element: String,
        /// How many there are.
        count: usize,
    },
    /// The SRDF's link and joint names carry a prefix the URDF's do not (`baxter/right_s0`
    /// for `right_s0`): it was removed.
    StrippedPrefix {
        /// The prefix, ending in `/`.
        prefix: String,
        /// How many names were changed.
        names: usize,
    },
    /// An element that names a link, joint or group the model lacks, or that is malformed:
    /// left out (or the part of it that does), as MoveIt's loader leaves it out.
    LeftOut {
        /// The element (`group_state "half_sitting"`, `end_effector "l_foot"`, …).
        element: String,
        /// What is wrong and what was left out.
        reason: String,
    },
    /// An end effector whose own group holds joints above its parent link: its group is
    /// the arm, not a hand (Panda's `group="arm"`). Accepted; the hand has no group.
    EndEffectorGroupIsArm {
        /// The end effector.
        end_effector: String,
        /// Its group.
        group: String,
    },
}

impl std::fmt::Display for SrdfWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::VirtualJoint {
                name,
                joint_type,
                used_in,
            } => {
                match joint_type {
                    Some(t) => write!(f, "virtual joint {name:?} ({t})")?,
                    None => write!(
                        f,
                        "joint {name:?} is not in the URDF and has several values (a floating or planar root)"
                    )?,
                }
                write!(f, ": left out of planning (the root is fixed)")?;
                if !used_in.is_empty() {
                    write!(f, "; named in {}", used_in.join(", "))?;
                }
                Ok(())
            }
            Self::IgnoredElement { element, count } => {
                write!(
                    f,
                    "{count} <{element}> element(s) ignored (not read by pickplace)"
                )
            }
            Self::StrippedPrefix { prefix, names } => write!(
                f,
                "{names} link and joint names start with {prefix:?}, which the URDF's do not: the prefix was removed"
            ),
            Self::LeftOut { element, reason } => write!(f, "{element}: {reason}"),
            Self::EndEffectorGroupIsArm {
                end_effector,
                group,
            } => write!(
                f,
                "end effector {end_effector:?}: its group {group:?} moves its parent link: it is the limb the end effector hangs from, not a hand"
            ),
        }
    }
}

/// An SRDF resolved against a model: indices instead of names.
#[derive(Debug, Clone)]
pub struct Semantics {
    source: PathBuf,
    srdf: Srdf,
    groups: Vec<Group>,
    end_effectors: Vec<ResolvedEndEffector>,
    /// For each group, its end effector (index into `end_effectors`).
    end_effector_of_group: Vec<Option<usize>>,
    /// Groups of the file left out whole, with why.
    groups_left_out: BTreeMap<String, String>,
    /// Groups kept with members left out, with what and why.
    members_left_out: BTreeMap<String, String>,
    warnings: Vec<SrdfWarning>,
}

/// The joints named in the SRDF that are not URDF joints but virtual ones: declared by
/// `<virtual_joint>`, or given several values in a group state. Name → declared type.
fn virtual_joints(model: &RobotModel, srdf: &Srdf) -> BTreeMap<String, Option<String>> {
    let mut out = BTreeMap::new();
    for v in &srdf.virtual_joints {
        if model.joint_index(&v.name).is_none() {
            out.insert(v.name.clone(), Some(v.joint_type.clone()));
        }
    }
    for state in &srdf.group_states {
        for (joint, _) in &state.multi_dof_values {
            if model.joint_index(joint).is_none() {
                out.entry(joint.clone()).or_insert(None);
            }
        }
    }
    out
}

/// The one prefix ending in `/` whose removal turns every unknown link and joint name of
/// the SRDF into a URDF name, with how many names it changes.
fn strippable_prefix(
    model: &RobotModel,
    srdf: &Srdf,
    virtual_names: &BTreeMap<String, Option<String>>,
) -> Option<(String, usize)> {
    let mut unknown: Vec<(NameKind, String)> = Vec::new();
    let mut push = |kind: NameKind, name: &str| {
        let known = match kind {
            NameKind::Link => model.link_index(name).is_some(),
            NameKind::Joint => {
                model.joint_index(name).is_some() || virtual_names.contains_key(name)
            }
            _ => true,
        };
        if !known && !unknown.iter().any(|(_, n)| n == name) {
            unknown.push((kind, name.to_owned()));
        }
    };
    for g in &srdf.groups {
        for c in &g.chains {
            push(NameKind::Link, &c.base_link);
            push(NameKind::Link, &c.tip_link);
        }
        g.joints.iter().for_each(|j| push(NameKind::Joint, j));
        g.links.iter().for_each(|l| push(NameKind::Link, l));
    }
    for s in &srdf.group_states {
        s.values.iter().for_each(|(j, _)| push(NameKind::Joint, j));
    }
    for e in &srdf.end_effectors {
        push(NameKind::Link, &e.parent_link);
    }
    for d in &srdf.disabled_collisions {
        push(NameKind::Link, &d.link1);
        push(NameKind::Link, &d.link2);
    }
    srdf.passive_joints
        .iter()
        .for_each(|j| push(NameKind::Joint, j));
    for v in &srdf.virtual_joints {
        push(NameKind::Link, &v.child_link);
    }
    let (_, first) = unknown.first()?;
    // Candidate prefixes: every leading part of the first unknown name that ends in '/'.
    for (end, _) in first.match_indices('/') {
        let prefix = &first[..=end];
        let all = unknown.iter().all(|(kind, name)| {
            name.strip_prefix(prefix).is_some_and(|rest| match kind {
                NameKind::Link => model.link_index(rest).is_some(),
                _ => model.joint_index(rest).is_some(),
            })
        });
        if all {
            return Some((prefix.to_owned(), unknown.len()));
        }
    }
    None
}

impl Semantics {
    /// Resolves an SRDF against a model.
    ///
    /// The SRDF is taken as its makers ship it, and read as leniently as MoveIt reads it:
    /// virtual joints (declared, or a joint the URDF lacks given several values in a group
    /// state) are left out of groups and states; elements this crate does not read are
    /// skipped; names carrying one prefix ending in `/` that the URDF's lack have it removed;
    /// whatever names a link, joint or group the model lacks (a group state's toes, an end
    /// effector's parent link, a chain, a disabled pair) is left out, and a group with a
    /// malformed member is left out whole ([`Semantics::group`] says why when it is asked
    /// for). Each is reported once in [`Semantics::warnings`]; the disabled pairs naming
    /// known links are all kept.
    ///
    /// # Arguments
    /// * `source`: the SRDF's path, used in errors.
    ///
    /// # Errors
    /// [`Error::Srdf`] for what is left that a model cannot take (none of the above).
    pub fn resolve(model: &RobotModel, srdf: &Srdf, source: &Path) -> Result<Self> {
        let err = |kind| Error::Srdf {
            path: source.to_path_buf(),
            kind,
        };
        let mut warnings = Vec::new();
        let mut virtual_names = virtual_joints(model, srdf);
        let srdf = match strippable_prefix(model, srdf, &virtual_names) {
            Some((prefix, names)) => {
                let stripped = srdf.map_names(&|kind, name| match kind {
                    NameKind::Link => match name.strip_prefix(prefix.as_str()) {
                        Some(rest) if model.link_index(name).is_none() => rest.to_owned(),
                        _ => name.to_owned(),
                    },
                    NameKind::Joint => match name.strip_prefix(prefix.as_str()) {
                        Some(rest)
                            if model.joint_index(name).is_none()
                                && model.joint_index(rest).is_some() =>
                        {
                            rest.to_owned()
                        }
                        _ => name.to_owned(),
                    },
                    _ => name.to_owned(),
                });
                warnings.push(SrdfWarning::StrippedPrefix { prefix, names });
                virtual_names = virtual_joints(model, &stripped);
                stripped
            }
            None => srdf.clone(),
        };
        let kept = super::lenient::leave_out_unknowns(model, &srdf, &|j: &str| {
            virtual_names.contains_key(j)
        });
        warnings.extend(kept.warnings);
        let (groups_left_out, members_left_out) = (kept.groups_left_out, kept.members_left_out);
        let srdf = &kept.srdf;
        let mut virtual_uses: BTreeMap<&str, Vec<String>> = BTreeMap::new();
        let mut note_virtual = |joint: &str, place: String| -> bool {
            match virtual_names.get_key_value(joint) {
                Some((name, _)) => {
                    let uses = virtual_uses.entry(name.as_str()).or_default();
                    if !uses.contains(&place) {
                        uses.push(place);
                    }
                    true
                }
                None => false,
            }
        };
        for v in &srdf.virtual_joints {
            if model.link_index(&v.child_link).is_none() {
                return Err(err(SrdfErrorKind::UnknownName {
                    element: format!("virtual_joint {:?}", v.name),
                    kind: "link",
                    name: v.child_link.clone(),
                }));
            }
        }

        let by_name: BTreeMap<&str, &GroupSpec> =
            srdf.groups.iter().map(|g| (g.name.as_str(), g)).collect();
        let mut groups = Vec::with_capacity(srdf.groups.len());
        for spec in &srdf.groups {
            let mut joints: Vec<usize> = Vec::new();
            let mut visiting: Vec<&str> = Vec::new();
            let mut skipped: Vec<String> = Vec::new();
            collect_group_joints(
                model,
                &by_name,
                spec,
                &|j: &str| virtual_names.contains_key(j),
                &mut joints,
                &mut skipped,
                &mut visiting,
            )
            .map_err(err)?;
            for joint in skipped {
                note_virtual(&joint, format!("group {:?}", spec.name));
            }
            joints.sort_unstable();
            joints.dedup();
            let mut variables: Vec<usize> = joints
                .iter()
                .filter_map(|&j| match model.joints()[j].source {
                    crate::model::JointValueSource::Variable(v) => Some(v),
                    _ => None,
                })
                .collect();
            variables.sort_unstable();
            let mut links: Vec<usize> = joints
                .iter()
                .map(|&j| model.joints()[j].child_link)
                .collect();
            for l in &spec.links {
                links.push(model.link_index(l).ok_or_else(|| {
                    err(SrdfErrorKind::UnknownName {
                        element: format!("group {:?}", spec.name),
                        kind: "link",
                        name: l.clone(),
                    })
                })?);
            }
            links.sort_unstable();
            links.dedup();
            let tip_link = match spec.chains.as_slice() {
                [chain] => model.link_index(&chain.tip_link),
                _ => None,
            };
            groups.push(Group {
                name: spec.name.clone(),
                variables,
                links,
                tip_link,
                joints,
            });
        }
        let mut end_effectors = Vec::new();
        for ee in &srdf.end_effectors {
            let parent_link = model.link_index(&ee.parent_link).ok_or_else(|| {
                err(SrdfErrorKind::UnknownName {
                    element: format!("end_effector {:?}", ee.name),
                    kind: "link",
                    name: ee.parent_link.clone(),
                })
            })?;
            for g in std::iter::once(&ee.group).chain(ee.parent_group.iter()) {
                if !by_name.contains_key(g.as_str()) {
                    return Err(err(SrdfErrorKind::UnknownName {
                        element: format!("end_effector {:?}", ee.name),
                        kind: "group",
                        name: g.clone(),
                    }));
                }
            }
            if let Some(group) = groups.iter().find(|g| g.name == ee.group)
                && group.joints.iter().any(|&j| {
                    model.joints()[j].joint_type != crate::model::JointType::Fixed
                        && model.is_ancestor(model.joints()[j].child_link, parent_link)
                })
            {
                warnings.push(SrdfWarning::EndEffectorGroupIsArm {
                    end_effector: ee.name.clone(),
                    group: ee.group.clone(),
                });
            }
            end_effectors.push(ResolvedEndEffector {
                name: ee.name.clone(),
                parent_link,
                group: ee.group.clone(),
                parent_group: ee.parent_group.clone(),
            });
        }
        // Groups with no single chain take their tip from an end effector naming them as
        // parent group, else from their joints when these form one serial chain.
        for group in &mut groups {
            if group.tip_link.is_none() {
                let mut tips = end_effectors
                    .iter()
                    .filter(|e| e.parent_group.as_deref() == Some(group.name.as_str()));
                group.tip_link = match (tips.next(), tips.next()) {
                    (Some(e), None) => Some(e.parent_link),
                    _ => serial_tip(model, &group.name, &group.joints).ok(),
                };
            }
        }
        let end_effector_of_group = groups
            .iter()
            .map(|g| find_end_effector(model, g, &end_effectors))
            .collect();
        for state in &srdf.group_states {
            if !by_name.contains_key(state.group.as_str()) {
                return Err(err(SrdfErrorKind::UnknownName {
                    element: format!("group_state {:?}", state.name),
                    kind: "group",
                    name: state.group.clone(),
                }));
            }
            let place = || format!("group_state {:?}", state.name);
            for (joint, _) in &state.values {
                if model.joint_index(joint).is_none() && !note_virtual(joint, place()) {
                    return Err(err(SrdfErrorKind::UnknownName {
                        element: place(),
                        kind: "joint",
                        name: joint.clone(),
                    }));
                }
            }
            for (joint, values) in &state.multi_dof_values {
                if model.joint_index(joint).is_some() {
                    return Err(err(SrdfErrorKind::BadNumber {
                        element: "joint",
                        attribute: "value",
                        value: format!(
                            "{joint}: {} numbers for a one-variable joint",
                            values.len()
                        ),
                    }));
                }
                note_virtual(joint, place());
            }
        }
        for joint in &srdf.passive_joints {
            if model.joint_index(joint).is_none()
                && !note_virtual(joint, "passive_joint".to_owned())
            {
                return Err(err(SrdfErrorKind::UnknownName {
                    element: "passive_joint".to_owned(),
                    kind: "joint",
                    name: joint.clone(),
                }));
            }
        }
        for pair in &srdf.disabled_collisions {
            for l in [&pair.link1, &pair.link2] {
                if model.link_index(l).is_none() {
                    return Err(err(SrdfErrorKind::UnknownName {
                        element: format!("disable_collisions {:?} {:?}", pair.link1, pair.link2),
                        kind: "link",
                        name: l.clone(),
                    }));
                }
            }
        }
        let mut virtual_warnings: Vec<SrdfWarning> = virtual_names
            .iter()
            .map(|(name, joint_type)| SrdfWarning::VirtualJoint {
                name: name.clone(),
                joint_type: joint_type.clone(),
                used_in: virtual_uses.remove(name.as_str()).unwrap_or_default(),
            })
            .collect();
        virtual_warnings.append(&mut warnings);
        let mut warnings = virtual_warnings;
        warnings.extend(srdf.ignored_elements.iter().map(|(element, count)| {
            SrdfWarning::IgnoredElement {
                element: element.clone(),
                count: *count,
            }
        }));
        Ok(Self {
            source: source.to_path_buf(),
            srdf: srdf.clone(),
            groups,
            end_effectors,
            end_effector_of_group,
            groups_left_out,
            members_left_out,
            warnings,
        })
    }

    /// Reads and resolves an SRDF file.
    ///
    /// # Errors
    /// As [`Srdf::from_file`] and [`Semantics::resolve`].
    pub fn from_file(model: &RobotModel, path: &Path) -> Result<Self> {
        let srdf = Srdf::from_file(path)?;
        Self::resolve(model, &srdf, path)
    }

    /// The SRDF file.
    pub fn source(&self) -> &Path {
        &self.source
    }

    /// The SRDF as resolved: as written, with a stripped name prefix removed.
    pub fn srdf(&self) -> &Srdf {
        &self.srdf
    }

    /// What was accepted with a change of meaning (virtual joints, ignored elements, a
    /// stripped name prefix, an end effector whose group is an arm), each reported once.
    pub fn warnings(&self) -> &[SrdfWarning] {
        &self.warnings
    }

    /// Resolved groups, in file order.
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }

    /// What was left out of group `name` because it names links, joints or groups the model
    /// lacks (or a subgroup that includes it again), when anything was: to say why a group
    /// that should be an arm has no joint.
    pub fn left_out_of(&self, name: &str) -> Option<&str> {
        self.members_left_out.get(name).map(String::as_str)
    }

    /// A group by name.
    ///
    /// # Errors
    /// [`Error::GroupLeftOut`] for a group of the file left out (a malformed member),
    /// [`Error::UnknownGroup`] for any other name the resolved groups lack.
    pub fn group(&self, name: &str) -> Result<&Group> {
        self.groups.iter().find(|g| g.name == name).ok_or_else(|| {
            match self.groups_left_out.get(name) {
                Some(reason) => Error::GroupLeftOut {
                    name: name.to_owned(),
                    reason: reason.clone(),
                },
                None => Error::UnknownGroup {
                    name: name.to_owned(),
                },
            }
        })
    }

    /// Resolved end effectors.
    pub fn end_effectors(&self) -> &[ResolvedEndEffector] {
        &self.end_effectors
    }

    /// The end effector of a group (an arm): the one whose `parent_group` is the group,
    /// else the first whose parent link is the group's tip or below it, else the first
    /// whose parent link is one of the group's links. `None` for an unknown group or when
    /// none matches.
    pub fn end_effector_of(&self, group: &str) -> Option<&ResolvedEndEffector> {
        let index = self.groups.iter().position(|g| g.name == group)?;
        self.end_effector_of_group[index].map(|e| &self.end_effectors[e])
    }

    /// The kinematic chain of a group from the root to its tip link, with one Jacobian
    /// column per group variable. The group may be a `<chain>`, a list of joints or links,
    /// or subgroups, as long as its moving joints form one serial chain.
    ///
    /// # Errors
    /// [`Error::UnknownGroup`]; [`Error::Srdf`] naming the SRDF when the group has no
    /// moving joint ([`SrdfErrorKind::GroupWithoutJoints`]) or its joints are not one chain
    /// ([`SrdfErrorKind::NotOneChain`]).
    pub fn chain(&self, model: &RobotModel, group: &str) -> Result<KinematicChain> {
        let g = self.group(group)?;
        let tip = match g.tip_link {
            Some(tip) => tip,
            None => serial_tip(model, &g.name, &g.joints).map_err(|kind| Error::Srdf {
                path: self.source.clone(),
                kind,
            })?,
        };
        KinematicChain::new(model, tip, Isometry3::identity(), &g.variables)
    }

    /// Applies a named group state to `q` (variables not in the state are left alone, and
    /// so are virtual joints).
    ///
    /// # Errors
    /// [`Error::UnknownGroup`] when no state has that name, [`Error::WrongLength`] for `q`.
    pub fn apply_state(&self, model: &RobotModel, name: &str, q: &mut [Real]) -> Result<()> {
        if q.len() != model.variable_count() {
            return Err(Error::WrongLength {
                what: "joint values",
                expected: model.variable_count(),
                found: q.len(),
            });
        }
        let state = self
            .srdf
            .group_states
            .iter()
            .find(|s| s.name == name)
            .ok_or_else(|| Error::UnknownGroup {
                name: name.to_owned(),
            })?;
        for (joint, value) in &state.values {
            if let Some(v) = model.variable_index(joint) {
                q[v] = *value;
            }
        }
        Ok(())
    }
}

/// The tip of a group whose moving joints form one serial chain: the child link of the
/// deepest one.
fn serial_tip(
    model: &RobotModel,
    group: &str,
    joints: &[usize],
) -> std::result::Result<usize, SrdfErrorKind> {
    let mut moving: Vec<usize> = joints
        .iter()
        .copied()
        .filter(|&j| model.joints()[j].joint_type != crate::model::JointType::Fixed)
        .collect();
    // Joints are in depth-first order, so a parent's joint comes before its children's.
    moving.sort_unstable();
    let Some(&last) = moving.last() else {
        return Err(SrdfErrorKind::GroupWithoutJoints {
            group: group.to_owned(),
        });
    };
    for pair in moving.windows(2) {
        let (a, b) = (&model.joints()[pair[0]], &model.joints()[pair[1]]);
        if !model.is_ancestor(a.child_link, b.parent_link) {
            return Err(SrdfErrorKind::NotOneChain {
                group: group.to_owned(),
                first: a.name.clone(),
                second: b.name.clone(),
            });
        }
    }
    Ok(model.joints()[last].child_link)
}

fn find_end_effector(
    model: &RobotModel,
    group: &Group,
    end_effectors: &[ResolvedEndEffector],
) -> Option<usize> {
    end_effectors
        .iter()
        .position(|e| e.parent_group.as_deref() == Some(group.name.as_str()))
        .or_else(|| {
            let tip = group.tip_link?;
            end_effectors
                .iter()
                .position(|e| model.is_ancestor(tip, e.parent_link))
        })
        .or_else(|| {
            end_effectors
                .iter()
                .position(|e| group.links.contains(&e.parent_link))
        })
}

fn collect_group_joints<'a>(
    model: &RobotModel,
    by_name: &BTreeMap<&str, &'a GroupSpec>,
    spec: &'a GroupSpec,
    is_virtual: &dyn Fn(&str) -> bool,
    joints: &mut Vec<usize>,
    skipped: &mut Vec<String>,
    visiting: &mut Vec<&'a str>,
) -> std::result::Result<(), SrdfErrorKind> {
    if visiting.contains(&spec.name.as_str()) {
        return Err(SrdfErrorKind::RecursiveGroup {
            group: spec.name.clone(),
        });
    }
    visiting.push(&spec.name);
    let element = || format!("group {:?}", spec.name);
    let link = |name: &str| {
        model
            .link_index(name)
            .ok_or_else(|| SrdfErrorKind::UnknownName {
                element: element(),
                kind: "link",
                name: name.to_owned(),
            })
    };
    for chain in &spec.chains {
        let base = link(&chain.base_link)?;
        let tip = link(&chain.tip_link)?;
        if !model.is_ancestor(base, tip) {
            return Err(SrdfErrorKind::BadChain {
                group: spec.name.clone(),
                base: chain.base_link.clone(),
                tip: chain.tip_link.clone(),
            });
        }
        let mut current = tip;
        while current != base {
            let Some(j) = model.links()[current].parent_joint else {
                break;
            };
            joints.push(j);
            current = model.joints()[j].parent_link;
        }
    }
    for name in &spec.joints {
        match model.joint_index(name) {
            Some(j) => joints.push(j),
            None if is_virtual(name) => skipped.push(name.clone()),
            None => {
                return Err(SrdfErrorKind::UnknownName {
                    element: element(),
                    kind: "joint",
                    name: name.clone(),
                });
            }
        }
    }
    for name in &spec.links {
        if let Some(j) = model.links()[link(name)?].parent_joint {
            joints.push(j);
        }
    }
    for sub in &spec.subgroups {
        let sub_spec = by_name
            .get(sub.as_str())
            .ok_or_else(|| SrdfErrorKind::UnknownName {
                element: element(),
                kind: "group",
                name: sub.clone(),
            })?;
        collect_group_joints(
            model, by_name, sub_spec, is_virtual, joints, skipped, visiting,
        )?;
    }
    visiting.pop();
    Ok(())
}
