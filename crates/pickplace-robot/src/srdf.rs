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
    /// Joint name → value, for joints given one number.
    pub values: Vec<(String, Real)>,
    /// Joint name → values, for joints given several numbers (`value="x y z qx qy qz qw"`:
    /// planar and floating joints, normally virtual ones), in file order.
    pub multi_dof_values: Vec<(String, Vec<Real>)>,
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

/// A `<virtual_joint>`: a joint between the robot's root and an outside frame that the
/// URDF does not have (MoveIt's `world_joint`, a mobile base's `planar` joint, a humanoid's
/// `floating` root). This crate plans with a fixed root: virtual joints are kept out of
/// planning and reported once ([`SrdfWarning::VirtualJoint`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VirtualJoint {
    /// Name.
    pub name: String,
    /// `fixed`, `planar` or `floating` (any text is kept).
    pub joint_type: String,
    /// The outside frame (`world`, `odom_combined`).
    pub parent_frame: String,
    /// The robot link it holds (normally the URDF's root).
    pub child_link: String,
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
    /// Virtual joints, in file order.
    pub virtual_joints: Vec<VirtualJoint>,
    /// Elements this crate does not read (`<gripper>`, `<contact>`, `<link_sphere_approximations>`
    /// …), each kind once with how often it appears, in order of first appearance. They are
    /// skipped with their content.
    pub ignored_elements: Vec<(String, usize)>,
}

/// The kind of a name in an SRDF, for [`Srdf::map_names`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NameKind {
    /// A URDF link.
    Link,
    /// A URDF joint (or a virtual joint).
    Joint,
    /// A planning group.
    Group,
    /// A group state.
    State,
    /// An end effector.
    EndEffector,
}

/// The SRDF elements that MoveIt defines but this crate does not use, ignored without a
/// warning: they do not change what a planner may do.
const SILENTLY_IGNORED: &[&str] = &["link_sphere_approximations"];

fn attribute(
    e: &BytesStart<'_>,
    element: &'static str,
    name: &'static str,
) -> std::result::Result<Option<String>, SrdfErrorKind> {
    match e.try_get_attribute(name) {
        Ok(Some(a)) => {
            // Checked before the value is unescaped and copied.
            let limit = match name {
                "value" | "reason" => pickplace_geometry::io::MAX_PATH_BYTES,
                _ => pickplace_geometry::io::MAX_NAME_BYTES,
            };
            if a.value.len() > limit {
                return Err(SrdfErrorKind::TooLong {
                    element,
                    attribute: name,
                    bytes: a.value.len(),
                    limit,
                });
            }
            a.unescape_value()
                .map(|v| Some(v.into_owned()))
                .map_err(|err| SrdfErrorKind::Xml {
                    position: 0,
                    detail: format!("<{element}> {name}: {err}"),
                })
        }
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

/// Parses a group-state value: one or more finite numbers separated by white space.
fn parse_values(text: &str) -> std::result::Result<Vec<Real>, SrdfErrorKind> {
    let values: Option<Vec<Real>> = text
        .split_whitespace()
        .map(|t| t.parse::<Real>().ok().filter(|v| v.is_finite()))
        .collect();
    match values {
        Some(v) if !v.is_empty() => Ok(v),
        _ => Err(SrdfErrorKind::BadNumber {
            element: "joint",
            attribute: "value",
            value: text.to_owned(),
        }),
    }
}

/// The group being read (the parser only reads group members inside a `<group>`).
fn open_group(groups: &mut [GroupSpec]) -> std::result::Result<&mut GroupSpec, SrdfErrorKind> {
    groups.last_mut().ok_or(SrdfErrorKind::Misplaced {
        element: "group member",
        parent: "group",
    })
}

/// Where the parser is: the element whose children it reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Context {
    Robot,
    Group,
    GroupState,
    /// A known element with no children of interest (`end_effector`, …).
    Leaf,
}

impl Srdf {
    /// Reads an SRDF file.
    ///
    /// # Errors
    /// [`Error::Io`] or [`Error::Srdf`].
    pub fn from_file(path: &Path) -> Result<Self> {
        let text = pickplace_geometry::io::read_text(path, pickplace_geometry::io::FileKind::Srdf)
            .map_err(|source| Error::Io {
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
        let mut reader = quick_xml::Reader::from_str(text);
        let mut srdf = Srdf::default();
        let mut stack: Vec<Context> = Vec::new();
        let mut saw_robot = false;
        loop {
            let xml_error =
                |reader: &quick_xml::Reader<&[u8]>, err: quick_xml::Error| SrdfErrorKind::Xml {
                    position: reader.error_position(),
                    detail: pickplace_geometry::io::short_message(&err.to_string()),
                };
            let event = reader.read_event().map_err(|err| xml_error(&reader, err))?;
            let (e, is_empty) = match event {
                Event::Start(e) => (e, false),
                Event::Empty(e) => (e, true),
                Event::End(_) => {
                    stack.pop();
                    continue;
                }
                Event::Eof => break,
                _ => continue,
            };
            let position = reader.buffer_position();
            let with_position = |kind: SrdfErrorKind| match kind {
                SrdfErrorKind::Xml { detail, .. } => SrdfErrorKind::Xml { position, detail },
                other => other,
            };
            let parent = stack.last().copied();
            let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
            let context = srdf.element(&e, &name, parent).map_err(with_position)?;
            match context {
                Some(context) => {
                    if context == Context::Robot {
                        saw_robot = true;
                    }
                    if !is_empty {
                        stack.push(context);
                    }
                }
                None => {
                    if !SILENTLY_IGNORED.contains(&name.as_str()) {
                        match srdf.ignored_elements.iter_mut().find(|(n, _)| *n == name) {
                            Some((_, count)) => *count += 1,
                            None => srdf.ignored_elements.push((name.clone(), 1)),
                        }
                    }
                    if !is_empty {
                        // Skip the element with everything inside it.
                        reader
                            .read_to_end(e.name())
                            .map_err(|err| xml_error(&reader, err))?;
                    }
                }
            }
        }
        if !saw_robot {
            return Err(SrdfErrorKind::NoRobotElement);
        }
        Ok(srdf)
    }

    /// Reads one element; `None` when it is not one this crate reads there.
    fn element(
        &mut self,
        e: &BytesStart<'_>,
        name: &str,
        parent: Option<Context>,
    ) -> std::result::Result<Option<Context>, SrdfErrorKind> {
        Ok(Some(match (name, parent) {
            ("robot", None) => {
                self.robot_name = attribute(e, "robot", "name")?.unwrap_or_default();
                Context::Robot
            }
            ("group", Some(Context::Robot)) => {
                self.groups.push(GroupSpec {
                    name: required(e, "group", "name")?,
                    ..GroupSpec::default()
                });
                Context::Group
            }
            ("group", Some(Context::Group)) => {
                let sub = required(e, "group", "name")?;
                open_group(&mut self.groups)?.subgroups.push(sub);
                Context::Leaf
            }
            ("chain", Some(Context::Group)) => {
                let chain = ChainSpec {
                    base_link: required(e, "chain", "base_link")?,
                    tip_link: required(e, "chain", "tip_link")?,
                };
                open_group(&mut self.groups)?.chains.push(chain);
                Context::Leaf
            }
            ("chain", _) => {
                return Err(SrdfErrorKind::Misplaced {
                    element: "chain",
                    parent: "group",
                });
            }
            ("link", Some(Context::Group)) => {
                let link = required(e, "link", "name")?;
                open_group(&mut self.groups)?.links.push(link);
                Context::Leaf
            }
            ("joint", Some(Context::Group)) => {
                let joint = required(e, "joint", "name")?;
                open_group(&mut self.groups)?.joints.push(joint);
                Context::Leaf
            }
            ("group_state", Some(Context::Robot)) => {
                self.group_states.push(GroupState {
                    name: required(e, "group_state", "name")?,
                    group: required(e, "group_state", "group")?,
                    values: Vec::new(),
                    multi_dof_values: Vec::new(),
                });
                Context::GroupState
            }
            ("joint", Some(Context::GroupState)) => {
                let joint = required(e, "joint", "name")?;
                let values = parse_values(&required(e, "joint", "value")?)?;
                let state = self
                    .group_states
                    .last_mut()
                    .ok_or(SrdfErrorKind::Misplaced {
                        element: "joint",
                        parent: "group_state",
                    })?;
                match values.as_slice() {
                    [one] => state.values.push((joint, *one)),
                    _ => state.multi_dof_values.push((joint, values)),
                }
                Context::Leaf
            }
            ("end_effector", Some(Context::Robot)) => {
                self.end_effectors.push(EndEffector {
                    name: required(e, "end_effector", "name")?,
                    parent_link: required(e, "end_effector", "parent_link")?,
                    group: required(e, "end_effector", "group")?,
                    parent_group: attribute(e, "end_effector", "parent_group")?,
                });
                Context::Leaf
            }
            ("disable_collisions", Some(Context::Robot)) => {
                self.disabled_collisions.push(DisabledPair {
                    link1: required(e, "disable_collisions", "link1")?,
                    link2: required(e, "disable_collisions", "link2")?,
                    reason: DisableReason::parse(
                        &attribute(e, "disable_collisions", "reason")?.unwrap_or_default(),
                    ),
                });
                Context::Leaf
            }
            ("passive_joint", Some(Context::Robot)) => {
                self.passive_joints
                    .push(required(e, "passive_joint", "name")?);
                Context::Leaf
            }
            ("virtual_joint", Some(Context::Robot)) => {
                self.virtual_joints.push(VirtualJoint {
                    name: required(e, "virtual_joint", "name")?,
                    joint_type: attribute(e, "virtual_joint", "type")?.unwrap_or_default(),
                    parent_frame: attribute(e, "virtual_joint", "parent_frame")?
                        .unwrap_or_default(),
                    child_link: required(e, "virtual_joint", "child_link")?,
                });
                Context::Leaf
            }
            _ => return Ok(None),
        }))
    }

    /// A copy with every name passed through `rename` (with its kind); the robot name, the
    /// virtual joints' parent frames and the ignored elements are kept.
    pub fn map_names(&self, rename: &dyn Fn(NameKind, &str) -> String) -> Srdf {
        let link = |n: &str| rename(NameKind::Link, n);
        let joint = |n: &str| rename(NameKind::Joint, n);
        let group = |n: &str| rename(NameKind::Group, n);
        Srdf {
            robot_name: self.robot_name.clone(),
            groups: self
                .groups
                .iter()
                .map(|g| GroupSpec {
                    name: group(&g.name),
                    chains: g
                        .chains
                        .iter()
                        .map(|c| ChainSpec {
                            base_link: link(&c.base_link),
                            tip_link: link(&c.tip_link),
                        })
                        .collect(),
                    joints: g.joints.iter().map(|j| joint(j)).collect(),
                    links: g.links.iter().map(|l| link(l)).collect(),
                    subgroups: g.subgroups.iter().map(|s| group(s)).collect(),
                })
                .collect(),
            group_states: self
                .group_states
                .iter()
                .map(|s| GroupState {
                    name: rename(NameKind::State, &s.name),
                    group: group(&s.group),
                    values: s.values.iter().map(|(j, v)| (joint(j), *v)).collect(),
                    multi_dof_values: s
                        .multi_dof_values
                        .iter()
                        .map(|(j, v)| (joint(j), v.clone()))
                        .collect(),
                })
                .collect(),
            end_effectors: self
                .end_effectors
                .iter()
                .map(|e| EndEffector {
                    name: rename(NameKind::EndEffector, &e.name),
                    parent_link: link(&e.parent_link),
                    group: group(&e.group),
                    parent_group: e.parent_group.as_deref().map(group),
                })
                .collect(),
            disabled_collisions: self
                .disabled_collisions
                .iter()
                .map(|d| DisabledPair {
                    link1: link(&d.link1),
                    link2: link(&d.link2),
                    reason: d.reason.clone(),
                })
                .collect(),
            passive_joints: self.passive_joints.iter().map(|j| joint(j)).collect(),
            virtual_joints: self
                .virtual_joints
                .iter()
                .map(|v| VirtualJoint {
                    name: joint(&v.name),
                    joint_type: v.joint_type.clone(),
                    parent_frame: v.parent_frame.clone(),
                    child_link: link(&v.child_link),
                })
                .collect(),
            ignored_elements: self.ignored_elements.clone(),
        }
    }

    /// A copy with `prefix` put before every name: links, joints, groups, states, end
    /// effectors, disabled pairs, passive and virtual joints — the SRDF of one robot of a
    /// [`RobotModel::combine`]d model.
    pub fn prefixed(&self, prefix: &str) -> Srdf {
        self.map_names(&|_, name| format!("{prefix}{name}"))
    }

    /// One SRDF holding every part's groups, states, end effectors, disabled pairs, passive
    /// and virtual joints, in the parts' order, under the robot name `name`. Names are not
    /// changed: give each part its own prefix first ([`Srdf::prefixed`]).
    pub fn merge(parts: &[Srdf], name: &str) -> Srdf {
        let mut out = Srdf {
            robot_name: name.to_owned(),
            ..Srdf::default()
        };
        for part in parts {
            out.groups.extend(part.groups.iter().cloned());
            out.group_states.extend(part.group_states.iter().cloned());
            out.end_effectors.extend(part.end_effectors.iter().cloned());
            out.disabled_collisions
                .extend(part.disabled_collisions.iter().cloned());
            out.passive_joints
                .extend(part.passive_joints.iter().cloned());
            out.virtual_joints
                .extend(part.virtual_joints.iter().cloned());
            for (element, count) in &part.ignored_elements {
                match out.ignored_elements.iter_mut().find(|(e, _)| e == element) {
                    Some((_, total)) => *total += count,
                    None => out.ignored_elements.push((element.clone(), *count)),
                }
            }
        }
        out
    }

    /// Writes the SRDF (groups, states, end effectors, disabled pairs) as XML text.
    pub fn to_xml(&self) -> String {
        use std::fmt::Write as _;
        // Attribute values: XML's five entities, and tab, newline and carriage return as
        // character references, which every XML reader keeps (attribute-value normalisation
        // turns the raw characters into spaces).
        let esc = |s: &str| {
            quick_xml::escape::escape(s)
                .replace('\t', "&#9;")
                .replace('\n', "&#10;")
                .replace('\r', "&#13;")
        };
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
            for (j, values) in &s.multi_dof_values {
                let text: Vec<String> = values.iter().map(ToString::to_string).collect();
                let _ = writeln!(
                    out,
                    "    <joint name=\"{}\" value=\"{}\"/>",
                    esc(j),
                    text.join(" ")
                );
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
        for v in &self.virtual_joints {
            let _ = writeln!(
                out,
                "  <virtual_joint name=\"{}\" type=\"{}\" parent_frame=\"{}\" child_link=\"{}\"/>",
                esc(&v.name),
                esc(&v.joint_type),
                esc(&v.parent_frame),
                esc(&v.child_link)
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
    /// The SRDF is taken as its makers ship it: virtual joints (declared, or a joint the URDF
    /// lacks given several values in a group state) are left out of groups and states;
    /// elements this crate does not read are skipped; names carrying one prefix ending in
    /// `/` that the URDF's lack have it removed. Each is reported once in
    /// [`Semantics::warnings`].
    ///
    /// # Arguments
    /// * `source`: the SRDF's path, used in errors.
    ///
    /// # Errors
    /// [`Error::Srdf`] naming the element and the unknown link, joint or group, a bad chain
    /// or a recursive group.
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
        let srdf = &srdf;
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

#[cfg(test)]
mod limit_tests {
    use super::*;

    #[test]
    fn a_name_over_the_limit_is_refused_before_it_is_copied() {
        // Regression (issue 18): names had no limit but the file's size (16 MiB).
        let text = format!(
            "<robot name=\"r\"><group name=\"{}\"><joint name=\"j\"/></group></robot>",
            "g".repeat(5000)
        );
        let e = Srdf::from_xml_str(&text).expect_err("refused");
        assert!(
            e.to_string()
                .contains("<group> attribute \"name\" is 5000 bytes, over the limit of 1024"),
            "{e}"
        );
        let ok = "<robot name=\"r\"><group name=\"arm\"><joint name=\"j\"/></group></robot>";
        assert!(Srdf::from_xml_str(ok).is_ok());
    }
}
