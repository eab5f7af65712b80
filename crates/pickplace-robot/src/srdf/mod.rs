//! MoveIt's SRDF: planning groups, group states, end effectors and disabled collision pairs.
//!
//! [`Srdf`] is the file as written (names); [`Semantics`] is the SRDF resolved against a
//! [`RobotModel`](crate::RobotModel) (indices), ready for IK and collision checking.

mod lenient;
mod semantics;

pub use semantics::{Group, ResolvedEndEffector, Semantics, SrdfWarning};

use crate::error::{Error, Result, SrdfErrorKind, memory_path};
use pickplace_geometry::math::Real;
use quick_xml::events::{BytesStart, Event};

/// An SRDF file; default limit 16 MiB.
pub const SRDF_FILE: pickplace_geometry::io::FileKind =
    pickplace_geometry::io::FileKind::new("an SRDF", 16 * pickplace_geometry::io::MIB);
use std::path::Path;

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
    /// Elements skipped because they are malformed (an attribute missing, a value that is
    /// not a number, an element out of place), in file order, as MoveIt's loader skips them.
    /// [`Semantics::resolve`] leaves out a group with a malformed member and reports each.
    pub skipped: Vec<SkippedElement>,
}

/// An element of an SRDF skipped because it is malformed.
#[derive(Debug, Clone, PartialEq)]
pub struct SkippedElement {
    /// The element as written, with its name when it has one (`<group_state name="half">`).
    pub element: String,
    /// The group it belongs to when it is a member of one (a `<chain>`, `<joint>`, …).
    pub group: Option<String>,
    /// What is wrong with it.
    pub reason: SrdfErrorKind,
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

/// An element as a message names it: `<group_state name="half">`, or `<chain>` when it has
/// no (readable) name.
fn describe(e: &BytesStart<'_>, element: &str) -> String {
    match e.try_get_attribute("name") {
        Ok(Some(a)) if a.value.len() <= pickplace_geometry::io::MAX_NAME_BYTES => {
            format!("<{element} name={:?}>", String::from_utf8_lossy(&a.value))
        }
        _ => format!("<{element}>"),
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
        let text =
            pickplace_geometry::io::read_text(path, SRDF_FILE).map_err(|source| Error::Io {
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
            let context = match srdf.element(&e, &name, parent) {
                Ok(context) => context,
                // A malformed element is skipped with its content, as MoveIt skips it; what
                // depends on it is decided when the SRDF is resolved against a model.
                Err(
                    reason @ (SrdfErrorKind::MissingAttribute { .. }
                    | SrdfErrorKind::BadNumber { .. }
                    | SrdfErrorKind::Misplaced { .. }),
                ) => {
                    let group = match parent {
                        Some(Context::Group) => srdf.groups.last().map(|g| g.name.clone()),
                        _ => None,
                    };
                    srdf.skipped.push(SkippedElement {
                        element: describe(&e, &name),
                        group,
                        reason,
                    });
                    if !is_empty {
                        reader
                            .read_to_end(e.name())
                            .map_err(|err| xml_error(&reader, err))?;
                    }
                    continue;
                }
                Err(other) => return Err(with_position(other)),
            };
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
            skipped: self
                .skipped
                .iter()
                .map(|k| SkippedElement {
                    group: k.group.as_deref().map(|g| rename(NameKind::Group, g)),
                    ..k.clone()
                })
                .collect(),
        }
    }

    /// A copy with `prefix` put before every name: links, joints, groups, states, end
    /// effectors, disabled pairs, passive and virtual joints — the SRDF of one robot of a
    /// [`RobotModel::combine`](crate::RobotModel::combine)d model.
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
            out.skipped.extend(part.skipped.iter().cloned());
            for (element, count) in &part.ignored_elements {
                match out.ignored_elements.iter_mut().find(|(e, _)| e == element) {
                    Some((_, total)) => *total += count,
                    None => out.ignored_elements.push((element.clone(), *count)),
                }
            }
        }
        out
    }

    /// As [`Srdf::to_xml`], with `comment` (whole lines, `<!-- … -->` included) right after
    /// the XML declaration: how the file was made.
    pub fn to_xml_with_comment(&self, comment: &str) -> String {
        let xml = self.to_xml();
        match xml.split_once('\n') {
            Some((declaration, rest)) => format!("{declaration}\n{comment}{rest}"),
            None => format!("{comment}{xml}"),
        }
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
