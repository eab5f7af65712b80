//! Joint velocity and acceleration limits for timing (issue 19): the URDF's velocity limits,
//! overridden by a table in the shape of MoveIt's `joint_limits.yaml` (a file beside the
//! robot, or named by the scene) and by the scene's own `[trajectory.joint_limits]`; URDFs
//! carry no acceleration limit, so a joint the tables leave out gets the scene's
//! `trajectory.max_acceleration`.
//!
//! The YAML read is the subset MoveIt's setup assistant writes: block mappings by
//! indentation, `key: value` scalars and `#` comments. Anything else (flow collections,
//! anchors, several documents, tabs) is refused with its line, so a hostile file cannot nest
//! or expand without bound.

use pickplace_geometry::math::Real;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A joint-limits file (MoveIt's `joint_limits.yaml`); default limit 1 MiB.
pub const JOINT_LIMITS_FILE: pickplace_geometry::io::FileKind =
    pickplace_geometry::io::FileKind::new("a joint-limits file", pickplace_geometry::io::MIB);

/// The file looked for beside a robot's URDF when the scene names none.
pub const FILE_NAME: &str = "joint_limits.yaml";

/// Acceleration limit (rad/s² or m/s²) of a joint no table limits (the scene's
/// `trajectory.max_acceleration` default).
pub const DEFAULT_ACCELERATION: Real = 3.0;

/// Velocity limit (rad/s or m/s) of a joint whose URDF gives none (or 0) and no table limits.
pub const DEFAULT_VELOCITY: Real = 1.0;

/// One joint's entry (MoveIt's field names; every field optional). Position and effort
/// limits are accepted and not used: positions come from the URDF, and the planner does not
/// model torques.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointLimitSpec {
    /// Whether `max_velocity` applies (default: true when it is given).
    pub has_velocity_limits: Option<bool>,
    /// Velocity limit (rad/s or m/s).
    pub max_velocity: Option<Real>,
    /// Whether `max_acceleration` applies (default: true when it is given).
    pub has_acceleration_limits: Option<bool>,
    /// Acceleration limit (rad/s² or m/s²).
    pub max_acceleration: Option<Real>,
    /// Whether `max_jerk` applies (read; the timing is not jerk-limited).
    pub has_jerk_limits: Option<bool>,
    /// Jerk limit (read; the timing is not jerk-limited).
    pub max_jerk: Option<Real>,
    /// Whether the position limits apply (read; the URDF's are used).
    pub has_position_limits: Option<bool>,
    /// Lower position limit (read; the URDF's is used).
    pub min_position: Option<Real>,
    /// Upper position limit (read; the URDF's is used).
    pub max_position: Option<Real>,
    /// Whether `max_effort` applies (read; not used).
    pub has_effort_limits: Option<bool>,
    /// Effort limit (read; not used).
    pub max_effort: Option<Real>,
}

/// A `joint_limits.yaml` file.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointLimitsFile {
    /// Velocity scaling used when neither the command line nor the scene gives one.
    pub default_velocity_scaling_factor: Option<Real>,
    /// Acceleration scaling used when neither the command line nor the scene gives one.
    pub default_acceleration_scaling_factor: Option<Real>,
    /// Limits by joint name (the robot's own names, without a scene prefix).
    #[serde(default)]
    pub joint_limits: BTreeMap<String, JointLimitSpec>,
}

/// The limits a joint's timing keeps, and where each came from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TimingLimit {
    /// Velocity limit (rad/s or m/s), positive.
    pub velocity: Real,
    /// Acceleration limit (rad/s² or m/s²), positive.
    pub acceleration: Real,
    /// Where the velocity limit came from (`urdf`, a file, `scene`, `default`).
    pub velocity_source: String,
    /// Where the acceleration limit came from.
    pub acceleration_source: String,
}

/// Why a joint-limits table could not be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {reason}", path.display())]
pub struct JointLimitsError {
    /// The file (the scene for its own table).
    pub path: PathBuf,
    /// What is wrong, with the line or the field.
    pub reason: String,
}

impl JointLimitsFile {
    /// Reads a `joint_limits.yaml` ([`parse_yaml`]).
    ///
    /// # Errors
    /// [`JointLimitsError`] naming the file: unreadable, not the YAML subset, an unknown key,
    /// a value of the wrong type.
    pub fn load(path: &Path) -> Result<Self, JointLimitsError> {
        let err = |reason: String| JointLimitsError {
            path: path.to_path_buf(),
            reason,
        };
        let text = pickplace_geometry::io::read_text(path, JOINT_LIMITS_FILE)
            .map_err(|e| err(e.to_string()))?;
        let value = parse_yaml(&text).map_err(|e| err(e.to_string()))?;
        serde_json::from_value(value)
            .map_err(|e| err(pickplace_geometry::io::short_message(&e.to_string())))
    }
}

/// A construct of a joint-limits file outside the YAML subset it is read in, with its line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct YamlError {
    /// The line (1-based; 0 for the end of the file).
    pub line: usize,
    /// What is wrong there.
    pub reason: String,
}

impl std::fmt::Display for YamlError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.line == 0 {
            write!(f, "at the end: {}", self.reason)
        } else {
            write!(f, "line {}: {}", self.line, self.reason)
        }
    }
}

impl std::error::Error for YamlError {}

/// A limit of a joint-limits entry that is missing or out of its range.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LimitError {
    /// `max_velocity` or `max_acceleration`.
    pub field: &'static str,
    /// What is wrong.
    pub reason: String,
}

impl std::fmt::Display for LimitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.reason)
    }
}

impl std::error::Error for LimitError {}

/// Most nested mappings in a joint-limits file (the format needs 2).
const MAX_DEPTH: usize = 8;

/// The YAML subset of `joint_limits.yaml` as a JSON value: nested block mappings of scalars.
/// Scalars that read as numbers become numbers, `true`/`false` booleans, quoted or other
/// text strings.
///
/// # Errors
/// [`YamlError`] for a construct outside the subset, with its line.
pub fn parse_yaml(text: &str) -> Result<serde_json::Value, YamlError> {
    use serde_json::{Map, Value};
    // The open mappings: (indentation of their keys, key in the parent, entries).
    let mut stack: Vec<(usize, String, Map<String, Value>)> = vec![(0, String::new(), Map::new())];
    // A key whose value is a mapping on the following lines, more indented.
    let mut pending: Option<(usize, String)> = None;
    for (n, raw) in text.lines().enumerate() {
        let line_no = n + 1;
        let at = |reason: &str| YamlError {
            line: line_no,
            reason: reason.to_owned(),
        };
        let line = strip_comment(raw);
        if line.trim().is_empty() {
            continue;
        }
        if line.contains('\t') {
            return Err(at("a tab (YAML indents with spaces)"));
        }
        let indent = line.len() - line.trim_start().len();
        let body = line.trim();
        if body == "---" && stack.len() == 1 && stack[0].2.is_empty() && pending.is_none() {
            continue;
        }
        if body.starts_with(['-', '[', '{', '&', '*', '!', '|', '>', '?', '%']) || body == "..." {
            return Err(at(
                "only `key: value` lines and nested mappings are read (no lists, flow collections, anchors, tags, block scalars or documents)",
            ));
        }
        let Some((key, value)) = split_key(body) else {
            return Err(at("expected `key: value`"));
        };
        if let Some((parent_indent, parent_key)) = pending.take() {
            if indent <= parent_indent {
                // An empty value: `key:` with nothing under it is null.
                insert(&mut stack, parent_key, Value::Null, line_no)?;
            } else {
                if stack.len() > MAX_DEPTH {
                    return Err(at(&format!("nested deeper than {MAX_DEPTH} mappings")));
                }
                stack.push((indent, parent_key, Map::new()));
            }
        }
        // Close the mappings this line is not inside.
        while stack.len() > 1 && indent < stack[stack.len() - 1].0 {
            close(&mut stack, line_no)?;
        }
        if indent != stack[stack.len() - 1].0 {
            return Err(at("indentation does not match any mapping above"));
        }
        if value.is_empty() {
            pending = Some((indent, key));
        } else {
            insert(&mut stack, key, scalar(value, line_no)?, line_no)?;
        }
    }
    if let Some((_, key)) = pending {
        insert(&mut stack, key, Value::Null, 0)?;
    }
    while stack.len() > 1 {
        close(&mut stack, 0)?;
    }
    Ok(Value::Object(stack.pop().map(|s| s.2).unwrap_or_default()))
}

/// The line without a `#` comment (a `#` at the start or after a space, outside quotes).
fn strip_comment(line: &str) -> &str {
    let mut quote: Option<char> = None;
    let mut previous = ' ';
    for (i, c) in line.char_indices() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '"' || c == '\'' => quote = Some(c),
            None if c == '#' && previous.is_whitespace() => return &line[..i],
            None => {}
        }
        previous = c;
    }
    line
}

/// `key: value` (value possibly empty), the key unquoted.
fn split_key(body: &str) -> Option<(String, &str)> {
    let (key, value) =
        if let Some(rest) = body.strip_prefix('"').or_else(|| body.strip_prefix('\'')) {
            let q = body.chars().next()?;
            let end = rest.find(q)?;
            let after = rest[end + 1..].trim_start();
            (rest[..end].to_owned(), after.strip_prefix(':')?)
        } else {
            let colon = body
                .find(": ")
                .or_else(|| body.strip_suffix(':').map(|k| k.len()))?;
            (body[..colon].trim_end().to_owned(), &body[colon + 1..])
        };
    if key.is_empty() {
        return None;
    }
    Some((key, value.trim()))
}

/// A scalar of line `line`: a number, a boolean, null, or text.
fn scalar(text: &str, line: usize) -> Result<serde_json::Value, YamlError> {
    use serde_json::Value;
    let at = |reason: String| YamlError { line, reason };
    if let Some(inner) = text
        .strip_prefix('"')
        .and_then(|t| t.strip_suffix('"'))
        .or_else(|| text.strip_prefix('\'').and_then(|t| t.strip_suffix('\'')))
    {
        return Ok(Value::String(inner.to_owned()));
    }
    if text.starts_with(['[', '{', '&', '*', '!', '|', '>']) {
        return Err(at("only plain scalars are read as values".into()));
    }
    Ok(match text {
        "true" | "True" | "TRUE" => Value::Bool(true),
        "false" | "False" | "FALSE" => Value::Bool(false),
        "null" | "~" | "Null" | "NULL" => Value::Null,
        _ => match text.parse::<f64>() {
            Ok(v) if v.is_finite() => serde_json::Number::from_f64(v)
                .map(Value::Number)
                .unwrap_or_else(|| Value::String(text.to_owned())),
            Ok(_) => return Err(at(format!("{text} is not a finite number"))),
            Err(_) => Value::String(text.to_owned()),
        },
    })
}

/// Adds `key: value` to the innermost open mapping; a repeated key is an error.
fn insert(
    stack: &mut [(usize, String, serde_json::Map<String, serde_json::Value>)],
    key: String,
    value: serde_json::Value,
    line_no: usize,
) -> Result<(), YamlError> {
    let at = |reason: String| YamlError {
        line: line_no,
        reason,
    };
    let Some(top) = stack.last_mut() else {
        return Err(at("no open mapping".into()));
    };
    if top.2.contains_key(&key) {
        return Err(at(format!("key {key:?} appears twice")));
    }
    top.2.insert(key, value);
    Ok(())
}

/// Closes the innermost mapping into its parent.
fn close(
    stack: &mut Vec<(usize, String, serde_json::Map<String, serde_json::Value>)>,
    line_no: usize,
) -> Result<(), YamlError> {
    if let Some((_, key, map)) = stack.pop() {
        insert(stack, key, serde_json::Value::Object(map), line_no)?;
    }
    Ok(())
}

/// A velocity or acceleration limit of a table: `Some` when it applies.
fn applies(has: Option<bool>, value: Option<Real>) -> Option<Real> {
    if has == Some(false) { None } else { value }
}

/// Checks that the limits a table gives are positive and finite; `field` names the entry.
///
/// # Errors
/// [`LimitError`]: the field and what is wrong.
pub fn check_spec(spec: &JointLimitSpec) -> Result<(), LimitError> {
    for (name, has, value) in [
        ("max_velocity", spec.has_velocity_limits, spec.max_velocity),
        (
            "max_acceleration",
            spec.has_acceleration_limits,
            spec.max_acceleration,
        ),
    ] {
        if has == Some(true) && value.is_none() {
            return Err(LimitError {
                field: name,
                reason: format!("has_{}_limits is true but it is missing", &name[4..]),
            });
        }
        let range = if name == "max_velocity" {
            crate::ranges::JOINT_VELOCITY
        } else {
            crate::ranges::JOINT_ACCELERATION
        };
        if let Some(v) = value {
            range.check(v).map_err(|e| LimitError {
                field: name,
                reason: e.to_string(),
            })?;
        }
    }
    Ok(())
}

/// The timing limits of every variable of the model, in model order: the URDF's velocity
/// (or [`DEFAULT_VELOCITY`]) and `default_acceleration`, overridden by each table in turn
/// (`tables`: the table, its source for messages, and the prefix its joint names take).
/// `variables` are the model's variable names, `joints` all its joint names: an entry for a
/// joint that is not a variable (fixed, mimic) is ignored, as MoveIt's files list them too.
///
/// # Errors
/// A table's entry that is invalid, or names a joint the robot does not have, as
/// `(source, field, reason)`.
pub fn resolve(
    variables: &[String],
    joints: &[String],
    urdf_velocities: &[Real],
    default_acceleration: Real,
    tables: &[(&BTreeMap<String, JointLimitSpec>, String, String)],
) -> Result<Vec<TimingLimit>, (String, String, String)> {
    let mut limits: Vec<TimingLimit> = urdf_velocities
        .iter()
        .map(|&v| {
            let from_urdf = v.is_finite() && v > 0.0;
            TimingLimit {
                velocity: if from_urdf { v } else { DEFAULT_VELOCITY },
                acceleration: default_acceleration,
                velocity_source: if from_urdf { "urdf" } else { "default" }.to_owned(),
                acceleration_source: "default".to_owned(),
            }
        })
        .collect();
    for (table, source, prefix) in tables {
        for (joint, spec) in table.iter() {
            let field = format!("joint_limits.{joint}");
            check_spec(spec).map_err(|r| (source.clone(), field.clone(), r.to_string()))?;
            let full = format!("{prefix}{joint}");
            let Some(i) = variables.iter().position(|n| *n == full) else {
                if joints.contains(&full) {
                    continue;
                }
                return Err((
                    source.clone(),
                    field,
                    format!("the robot has no joint {full:?}"),
                ));
            };
            if let Some(v) = applies(spec.has_velocity_limits, spec.max_velocity) {
                limits[i].velocity = v;
                limits[i].velocity_source.clone_from(source);
            }
            if let Some(a) = applies(spec.has_acceleration_limits, spec.max_acceleration) {
                limits[i].acceleration = a;
                limits[i].acceleration_source.clone_from(source);
            }
        }
    }
    Ok(limits)
}

#[cfg(test)]
mod tests {
    use super::*;

    const MOVEIT: &str = "# joint_limits.yaml allows the dynamics properties specified in the URDF to be overwritten
# Specific joint properties can be changed with the keys [max_position, min_position, max_velocity, max_acceleration]

# For beginners, we downscale velocity and acceleration limits.
default_velocity_scaling_factor: 0.1
default_acceleration_scaling_factor: 0.1

joint_limits:
  panda_finger_joint1:
    has_velocity_limits: true
    max_velocity: 0.1
    has_acceleration_limits: false
    max_acceleration: 0
  panda_joint1:
    has_velocity_limits: true
    max_velocity: 2.175
    has_acceleration_limits: true
    max_acceleration: 3.75 # rad/s^2
";

    #[test]
    fn moveit_setup_assistant_files_are_read() {
        let value = parse_yaml(MOVEIT).expect("parses");
        let file: JointLimitsFile = serde_json::from_value(value).expect("fits");
        assert_eq!(file.default_velocity_scaling_factor, Some(0.1));
        let j1 = &file.joint_limits["panda_joint1"];
        assert_eq!(j1.max_velocity, Some(2.175));
        assert_eq!(j1.max_acceleration, Some(3.75));
        assert_eq!(
            file.joint_limits["panda_finger_joint1"].has_acceleration_limits,
            Some(false)
        );
    }

    #[test]
    fn constructs_outside_the_subset_are_refused_with_their_line() {
        for (text, line) in [
            ("joint_limits: {a: 1}", 1),
            ("joint_limits:\n  - a", 2),
            ("a: 1\n\tb: 2", 2),
            ("a: &x 1", 1),
            ("a: 1\na: 2", 2),
            ("a:\n    b: 1\n  c: 2", 3),
        ] {
            let e = parse_yaml(text).expect_err(text);
            assert_eq!(e.line, line, "{text:?}: {e}");
            assert!(
                e.to_string().starts_with(&format!("line {line}:")),
                "{text:?}: {e}"
            );
        }
        let deep: String = (0..20)
            .map(|d| format!("{}k{d}:\n", "  ".repeat(d)))
            .collect();
        assert!(
            parse_yaml(&deep)
                .expect_err("too deep")
                .reason
                .contains("deeper")
        );
    }

    #[test]
    fn tables_override_the_urdf_in_turn_and_unknown_joints_are_errors() {
        let names = vec!["a".to_owned(), "b".to_owned()];
        let mut file = BTreeMap::new();
        file.insert(
            "a".to_owned(),
            JointLimitSpec {
                max_velocity: Some(0.5),
                max_acceleration: Some(2.0),
                ..JointLimitSpec::default()
            },
        );
        let mut scene = BTreeMap::new();
        scene.insert(
            "a".to_owned(),
            JointLimitSpec {
                has_velocity_limits: Some(false),
                max_velocity: Some(9.0),
                max_acceleration: Some(1.0),
                ..JointLimitSpec::default()
            },
        );
        let limits = resolve(
            &names,
            &names,
            &[1.5, 0.0],
            3.0,
            &[
                (&file, "f.yaml".into(), String::new()),
                (&scene, "scene".into(), String::new()),
            ],
        )
        .expect("resolves");
        assert_eq!((limits[0].velocity, limits[0].acceleration), (0.5, 1.0));
        assert_eq!(limits[0].velocity_source, "f.yaml");
        assert_eq!(limits[0].acceleration_source, "scene");
        assert_eq!(
            (limits[1].velocity, limits[1].acceleration),
            (DEFAULT_VELOCITY, 3.0)
        );
        let mut bad = BTreeMap::new();
        bad.insert(
            "a".to_owned(),
            JointLimitSpec {
                max_acceleration: Some(-1.0),
                ..JointLimitSpec::default()
            },
        );
        let e = resolve(
            &names,
            &names,
            &[1.0, 1.0],
            3.0,
            &[(&bad, "s".into(), String::new())],
        );
        assert!(
            e.expect_err("negative")
                .2
                .contains("max_acceleration: -1 is not in")
        );
        let mut unknown = BTreeMap::new();
        unknown.insert("c".to_owned(), JointLimitSpec::default());
        let e = resolve(
            &names,
            &names,
            &[1.0, 1.0],
            3.0,
            &[(&unknown, "s".into(), String::new())],
        );
        assert!(e.expect_err("no such joint").2.contains("no joint \"c\""));
    }
}
