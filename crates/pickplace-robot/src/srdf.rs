//! MoveIt's SRDF: planning groups, group states, end effectors and disabled collision pairs.
//!
//! [`Srdf`] is the file as written (names); [`Semantics`] is the SRDF resolved against a
//! [`RobotModel`] (indices), ready for IK and collision checking.

use crate::error::{Error, Result, SrdfErrorKind, memory_path};
use crate::kinematics::KinematicChain;
use crate::model::RobotModel;
use pickplace_geometry::math::{Isometry3, Real};
use quick_xml::events::{BytesStart, Event};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A `<chain base_link tip_link/>` of a group.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChainSpec {
    /// Base link.
    pub base_link: String,
    /// Tip link.
    pub tip_link: String,
}

/// A `<group>` as written.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct GroupSpec {
    /// Group name.
    pub name: String,
    /// `<chain>` elements.
    pub chains: Vec<ChainSpec>,
    /// `<joint name>` elements.
    pub joints: Vec<String>,
    /// `<link name>` elements.
    pub links: Vec<String>,
    /// `<group name>` elements (subgroups).
    pub subgroups: Vec<String>,
}

/// A named joint configuration of a group (`<group_state>`).
#[derive(Debug, Clone, PartialEq)]
pub struct GroupState {
    /// State name ("home").
    pub name: String,
    /// The group.
    pub group: String,
    /// Joint name → value.
    pub values: Vec<(String, Real)>,
}

/// An `<end_effector>`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EndEffector {
    /// Name.
    pub name: String,
    /// The link the end effector is attached to (the TCP link).
    pub parent_link: String,
    /// The end effector's own group (the gripper's joints).
    pub group: String,
    /// The arm group it belongs to, if given.
    pub parent_group: Option<String>,
}

/// Why a pair of links is never checked for collision.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DisableReason {
    /// The links are joined by a joint.
    Adjacent,
    /// Never in collision over the sampled configurations.
    Never,
    /// Always in collision over the sampled configurations.
    Always,
    /// In collision in the default configuration.
    Default,
    /// Any other reason written in the file.
    Custom(String),
}

impl DisableReason {
    /// Parses MoveIt's spelling.
    pub fn parse(text: &str) -> Self {
        match text {
            "Adjacent" => Self::Adjacent,
            "Never" => Self::Never,
            "Always" => Self::Always,
            "Default" => Self::Default,
            other => Self::Custom(other.to_owned()),
        }
    }

    /// MoveIt's spelling.
    pub fn as_str(&self) -> &str {
        match self {
            Self::Adjacent => "Adjacent",
            Self::Never => "Never",
            Self::Always => "Always",
            Self::Default => "Default",
            Self::Custom(s) => s,
        }
    }
}

/// A `<disable_collisions>` pair.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DisabledPair {
    /// First link.
    pub link1: String,
    /// Second link.
    pub link2: String,
    /// Why.
    pub reason: DisableReason,
}

/// An SRDF file as written.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Srdf {
    /// The robot name.
    pub robot_name: String,
    /// Groups, in file order.
    pub groups: Vec<GroupSpec>,
    /// Named states.
    pub group_states: Vec<GroupState>,
    /// End effectors.
    pub end_effectors: Vec<EndEffector>,
    /// Pairs never checked for collision.
    pub disabled_collisions: Vec<DisabledPair>,
    /// Passive joints (kept as names; not used by the planner).
    pub passive_joints: Vec<String>,
}

fn attribute(
    e: &BytesStart<'_>,
    element: &'static str,
    name: &'static str,
) -> std::result::Result<Option<String>, SrdfErrorKind> {
    match e.try_get_attribute(name) {
        Ok(Some(a)) => a
            .unescape_value()
            .map(|v| Some(v.into_owned()))
            .map_err(|err| SrdfErrorKind::Xml {
                position: 0,
                detail: format!("<{element}> {name}: {err}"),
            }),
        Ok(None) => Ok(None),
        Err(err) => Err(SrdfErrorKind::Xml {
            position: 0,
            detail: format!("<{element}>: {err}"),
        }),
    }
}

fn required(
    e: &BytesStart<'_>,
    element: &'static str,
    name: &'static str,
) -> std::result::Result<String, SrdfErrorKind> {
    attribute(e, element, name)?.ok_or(SrdfErrorKind::MissingAttribute {
        element,
        attribute: name,
    })
}

impl Srdf {
    /// Reads an SRDF file.
    ///
    /// # Errors
    /// [`Error::Io`] or [`Error::Srdf`].
    pub fn from_file(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text).map_err(|kind| Error::Srdf {
            path: path.to_path_buf(),
            kind,
        })
    }

    /// Parses SRDF text.
    ///
    /// # Errors
    /// [`Error::Srdf`] with the path `<memory>`.
    pub fn from_xml_str(text: &str) -> Result<Self> {
        Self::parse(text).map_err(|kind| Error::Srdf {
            path: memory_path(),
            kind,
        })
    }

    fn parse(text: &str) -> std::result::Result<Self, SrdfErrorKind> {
        #[derive(PartialEq)]
        enum Open {
            None,
            Group,
            GroupState,
        }
        let mut reader = quick_xml::Reader::from_str(text);
        let mut srdf = Srdf::default();
        let mut open = Open::None;
        let mut depth_of_open = 0usize;
        let mut depth = 0usize;
        let mut saw_robot = false;
        loop {
            let event = reader.read_event().map_err(|err| SrdfErrorKind::Xml {
                position: reader.error_position(),
                detail: err.to_string(),
            })?;
            let (e, is_empty) = match &event {
                Event::Start(e) => (e, false),
                Event::Empty(e) => (e, true),
                Event::End(_) => {
                    if depth == depth_of_open && open != Open::None {
                        open = Open::None;
                    }
                    depth = depth.saturating_sub(1);
                    continue;
                }
                Event::Eof => break,
                _ => continue,
            };
            if !is_empty {
                depth += 1;
            }
            let position = reader.buffer_position();
            let with_position = |kind: SrdfErrorKind| match kind {
                SrdfErrorKind::Xml { detail, .. } => SrdfErrorKind::Xml { position, detail },
                other => other,
            };
            let name_bytes = e.name().as_ref().to_vec();
            let result: std::result::Result<(), SrdfErrorKind> = (|| {
                match (name_bytes.as_slice(), &open) {
                    (b"robot", _) => {
                        saw_robot = true;
                        srdf.robot_name = attribute(e, "robot", "name")?.unwrap_or_default();
                    }
                    (b"group", Open::None) => {
                        srdf.groups.push(GroupSpec {
                            name: required(e, "group", "name")?,
                            ..GroupSpec::default()
                        });
                        if !is_empty {
                            open = Open::Group;
                            depth_of_open = depth;
                        }
                    }
                    (b"group", Open::Group) => {
                        let name = required(e, "group", "name")?;
                        srdf.groups
                            .last_mut()
                            .expect("a group is open")
                            .subgroups
                            .push(name);
                    }
                    (b"chain", Open::Group) => {
                        let chain = ChainSpec {
                            base_link: required(e, "chain", "base_link")?,
                            tip_link: required(e, "chain", "tip_link")?,
                        };
                        srdf.groups
                            .last_mut()
                            .expect("a group is open")
                            .chains
                            .push(chain);
                    }
                    (b"chain", _) => {
                        return Err(SrdfErrorKind::Misplaced {
                            element: "chain",
                            parent: "group",
                        });
                    }
                    (b"link", Open::Group) => {
                        let name = required(e, "link", "name")?;
                        srdf.groups
                            .last_mut()
                            .expect("a group is open")
                            .links
                            .push(name);
                    }
                    (b"joint", Open::Group) => {
                        let name = required(e, "joint", "name")?;
                        srdf.groups
                            .last_mut()
                            .expect("a group is open")
                            .joints
                            .push(name);
                    }
                    (b"group_state", Open::None) => {
                        srdf.group_states.push(GroupState {
                            name: required(e, "group_state", "name")?,
                            group: required(e, "group_state", "group")?,
                            values: Vec::new(),
                        });
                        if !is_empty {
                            open = Open::GroupState;
                            depth_of_open = depth;
                        }
                    }
                    (b"joint", Open::GroupState) => {
                        let name = required(e, "joint", "name")?;
                        let text = required(e, "joint", "value")?;
                        // A value may hold several numbers (multi-DOF joints); ours take one.
                        let first = text.split_whitespace().next().unwrap_or("");
                        let value: Real =
                            first.parse().ok().filter(|v: &Real| v.is_finite()).ok_or(
                                SrdfErrorKind::BadNumber {
                                    element: "joint",
                                    attribute: "value",
                                    value: text.clone(),
                                },
                            )?;
                        srdf.group_states
                            .last_mut()
                            .expect("a state is open")
                            .values
                            .push((name, value));
                    }
                    (b"end_effector", _) => srdf.end_effectors.push(EndEffector {
                        name: required(e, "end_effector", "name")?,
                        parent_link: required(e, "end_effector", "parent_link")?,
                        group: required(e, "end_effector", "group")?,
                        parent_group: attribute(e, "end_effector", "parent_group")?,
                    }),
                    (b"disable_collisions", _) => srdf.disabled_collisions.push(DisabledPair {
                        link1: required(e, "disable_collisions", "link1")?,
                        link2: required(e, "disable_collisions", "link2")?,
                        reason: DisableReason::parse(
                            &attribute(e, "disable_collisions", "reason")?.unwrap_or_default(),
                        ),
                    }),
                    (b"passive_joint", _) => {
                        srdf.passive_joints
                            .push(required(e, "passive_joint", "name")?)
                    }
                    // virtual_joint, disable_default_collisions, link_sphere_approximations, ...:
                    // not used by this planner.
                    _ => {}
                }
                Ok(())
            })();
            result.map_err(with_position)?;
        }
        if !saw_robot {
            return Err(SrdfErrorKind::NoRobotElement);
        }
        Ok(srdf)
    }

    /// Writes the SRDF (groups, states, end effectors, disabled pairs) as XML text.
    pub fn to_xml(&self) -> String {
        use std::fmt::Write as _;
        let esc = |s: &str| quick_xml::escape::escape(s).into_owned();
        let mut out = String::new();
        let _ = writeln!(out, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
        let _ = writeln!(out, "<robot name=\"{}\">", esc(&self.robot_name));
        for g in &self.groups {
            let _ = writeln!(out, "  <group name=\"{}\">", esc(&g.name));
            for c in &g.chains {
                let _ = writeln!(
                    out,
                    "    <chain base_link=\"{}\" tip_link=\"{}\"/>",
                    esc(&c.base_link),
                    esc(&c.tip_link)
                );
            }
            for j in &g.joints {
                let _ = writeln!(out, "    <joint name=\"{}\"/>", esc(j));
            }
            for l in &g.links {
                let _ = writeln!(out, "    <link name=\"{}\"/>", esc(l));
            }
            for s in &g.subgroups {
                let _ = writeln!(out, "    <group name=\"{}\"/>", esc(s));
            }
            let _ = writeln!(out, "  </group>");
        }
        for s in &self.group_states {
            let _ = writeln!(
                out,
                "  <group_state name=\"{}\" group=\"{}\">",
                esc(&s.name),
                esc(&s.group)
            );
            for (j, v) in &s.values {
                let _ = writeln!(out, "    <joint name=\"{}\" value=\"{v}\"/>", esc(j));
            }
            let _ = writeln!(out, "  </group_state>");
        }
        for e in &self.end_effectors {
            let parent_group = e
                .parent_group
                .as_ref()
                .map(|g| format!(" parent_group=\"{}\"", esc(g)))
                .unwrap_or_default();
            let _ = writeln!(
                out,
                "  <end_effector name=\"{}\" parent_link=\"{}\" group=\"{}\"{parent_group}/>",
                esc(&e.name),
                esc(&e.parent_link),
                esc(&e.group)
            );
        }
        for p in &self.passive_joints {
            let _ = writeln!(out, "  <passive_joint name=\"{}\"/>", esc(p));
        }
        for d in &self.disabled_collisions {
            let _ = writeln!(
                out,
                "  <disable_collisions link1=\"{}\" link2=\"{}\" reason=\"{}\"/>",
                esc(&d.link1),
                esc(&d.link2),
                esc(d.reason.as_str())
            );
        }
        let _ = writeln!(out, "</robot>");
        out
    }
}

/// A planning group resolved against a model.
#[derive(Debug, Clone)]
pub struct Group {
    /// Name.
    pub name: String,
    /// The group's variables, in model order.
    pub variables: Vec<usize>,
    /// The links the group's joints move (the child links of its joints), in model order.
    pub links: Vec<usize>,
    /// The tip link used for IK: the tip of its single chain, or the parent link of the end
    /// effector whose `parent_group` is this group.
    pub tip_link: Option<usize>,
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

/// An SRDF resolved against a model: indices instead of names.
#[derive(Debug, Clone)]
pub struct Semantics {
    source: PathBuf,
    srdf: Srdf,
    groups: Vec<Group>,
    end_effectors: Vec<ResolvedEndEffector>,
}

impl Semantics {
    /// Resolves an SRDF against a model.
    ///
    /// # Arguments
    /// * `source`: the SRDF's path, used in errors.
    ///
    /// # Errors
    /// [`Error::Srdf`] naming the unknown link, joint or group, a bad chain or a recursive
    /// group.
    pub fn resolve(model: &RobotModel, srdf: &Srdf, source: &Path) -> Result<Self> {
        let err = |kind| Error::Srdf {
            path: source.to_path_buf(),
            kind,
        };
        let by_name: BTreeMap<&str, &GroupSpec> =
            srdf.groups.iter().map(|g| (g.name.as_str(), g)).collect();
        let mut groups = Vec::with_capacity(srdf.groups.len());
        for spec in &srdf.groups {
            let mut joints: Vec<usize> = Vec::new();
            let mut visiting: Vec<&str> = Vec::new();
            collect_group_joints(model, &by_name, spec, &mut joints, &mut visiting).map_err(err)?;
            joints.sort_unstable();
            joints.dedup();
            let variables: Vec<usize> = {
                let mut v: Vec<usize> = joints
                    .iter()
                    .filter_map(|&j| match model.joints()[j].source {
                        crate::model::JointValueSource::Variable(v) => Some(v),
                        _ => None,
                    })
                    .collect();
                v.sort_unstable();
                v
            };
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
            end_effectors.push(ResolvedEndEffector {
                name: ee.name.clone(),
                parent_link,
                group: ee.group.clone(),
                parent_group: ee.parent_group.clone(),
            });
        }
        // Groups with no single chain take their tip from an end effector.
        for group in &mut groups {
            if group.tip_link.is_none() {
                let mut tips = end_effectors
                    .iter()
                    .filter(|e| e.parent_group.as_deref() == Some(group.name.as_str()));
                if let (Some(e), None) = (tips.next(), tips.next()) {
                    group.tip_link = Some(e.parent_link);
                }
            }
        }
        for state in &srdf.group_states {
            if !by_name.contains_key(state.group.as_str()) {
                return Err(err(SrdfErrorKind::UnknownName {
                    element: format!("group_state {:?}", state.name),
                    kind: "group",
                    name: state.group.clone(),
                }));
            }
            for (joint, _) in &state.values {
                if model.joint_index(joint).is_none() {
                    return Err(err(SrdfErrorKind::UnknownName {
                        element: format!("group_state {:?}", state.name),
                        kind: "joint",
                        name: joint.clone(),
                    }));
                }
            }
        }
        for pair in &srdf.disabled_collisions {
            for l in [&pair.link1, &pair.link2] {
                if model.link_index(l).is_none() {
                    return Err(err(SrdfErrorKind::UnknownName {
                        element: "disable_collisions".to_owned(),
                        kind: "link",
                        name: l.clone(),
                    }));
                }
            }
        }
        Ok(Self {
            source: source.to_path_buf(),
            srdf: srdf.clone(),
            groups,
            end_effectors,
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

    /// The SRDF as written.
    pub fn srdf(&self) -> &Srdf {
        &self.srdf
    }

    /// Resolved groups, in file order.
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }

    /// A group by name.
    ///
    /// # Errors
    /// [`Error::UnknownGroup`].
    pub fn group(&self, name: &str) -> Result<&Group> {
        self.groups
            .iter()
            .find(|g| g.name == name)
            .ok_or_else(|| Error::UnknownGroup {
                name: name.to_owned(),
            })
    }

    /// Resolved end effectors.
    pub fn end_effectors(&self) -> &[ResolvedEndEffector] {
        &self.end_effectors
    }

    /// The kinematic chain of a group from the root to its tip link, with one Jacobian
    /// column per group variable.
    ///
    /// # Errors
    /// [`Error::UnknownGroup`] or [`Error::GroupWithoutTip`].
    pub fn chain(&self, model: &RobotModel, group: &str) -> Result<KinematicChain> {
        let g = self.group(group)?;
        let tip = g.tip_link.ok_or_else(|| Error::GroupWithoutTip {
            group: group.to_owned(),
        })?;
        KinematicChain::new(model, tip, Isometry3::identity(), &g.variables)
    }

    /// Applies a named group state to `q` (variables not in the state are left alone).
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

fn collect_group_joints<'a>(
    model: &RobotModel,
    by_name: &BTreeMap<&str, &'a GroupSpec>,
    spec: &'a GroupSpec,
    joints: &mut Vec<usize>,
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
            let j = model.links()[current]
                .parent_joint
                .expect("below base, so not the root");
            joints.push(j);
            current = model.joints()[j].parent_link;
        }
    }
    for name in &spec.joints {
        joints.push(
            model
                .joint_index(name)
                .ok_or_else(|| SrdfErrorKind::UnknownName {
                    element: element(),
                    kind: "joint",
                    name: name.clone(),
                })?,
        );
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
        collect_group_joints(model, by_name, sub_spec, joints, visiting)?;
    }
    visiting.pop();
    Ok(())
}
