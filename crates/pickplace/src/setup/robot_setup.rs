//! The robot of a scene as the planner uses it: one model (several URDFs side by side are
//! combined under prefixes), its SRDF completed from the scene and from the URDF, and one or
//! two arms, each with the parallel gripper measured on the URDF
//! ([`pickplace_robot::gripper`]) and a tool link added at the gripper's tool point.
//!
//! What the files lack is completed, and said once in [`RobotSetup::notes`]: arms found in
//! the URDF when the SRDF names none, a single arm when only one is found.

mod arms;

use crate::error::{Error, Result};
use crate::joint_limits::JointLimitSpec;
use crate::scene::{GroupSpecToml, RobotSpec, Scene, SceneOf};
use crate::strategy::Arm;
use pickplace_geometry::io::{FileKind, fmt_real};
use pickplace_geometry::math::{Isometry3, Point3, Real, Vector3};
use pickplace_grasp::gripper::PalmBox;
use pickplace_grasp::{GripperFile, GripperParams};
use pickplace_robot::gripper::{Gripper, GripperOptions};
use pickplace_robot::model::URDF_FILE;
use pickplace_robot::srdf::SRDF_FILE;
use pickplace_robot::srdf::{ChainSpec, GroupSpec};
use pickplace_robot::{KinematicChain, LoadOptions, RobotModel, Semantics, Srdf};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One arm as the planner sees it.
#[derive(Debug, Clone)]
pub struct RobotArm {
    /// Which arm.
    pub arm: Arm,
    /// Its group (SRDF, scene, or `arm_<tip link>` when found in the URDF).
    pub group: String,
    /// Its variables (model order is the chain's order, root side first).
    pub variables: Vec<usize>,
    /// The gripper at its end.
    pub gripper: Gripper,
    /// The grasp planner's model of that gripper (measured, then the overrides file).
    pub gripper_params: GripperParams,
    /// The tool link added at the gripper's tool point.
    pub tcp_link: usize,
    /// Its name.
    pub tcp_name: String,
}

impl RobotArm {
    /// The chain from the root to the tool link over the arm's variables.
    ///
    /// # Errors
    /// [`Error::Internal`] for indices the model does not have (a defect).
    pub fn chain(&self, model: &RobotModel) -> Result<KinematicChain> {
        KinematicChain::new(model, self.tcp_link, Isometry3::identity(), &self.variables)
            .map_err(crate::error::internal("arm chain"))
    }
}

/// A scene's gripper overrides: the robot's gripper file (`robot.gripper`), read by the one
/// reader of gripper files ([`GripperFile`]) and checked against what the façade measures on
/// the URDF ([`GripperOverrides::load`]). Every field optional; `Default` overrides nothing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GripperOverrides(pub GripperFile);

impl std::ops::Deref for GripperOverrides {
    type Target = GripperFile;

    fn deref(&self) -> &GripperFile {
        &self.0
    }
}

impl GripperOverrides {
    /// Reads an overrides file.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the file and the field.
    pub fn load(path: &Path) -> Result<Self> {
        let invalid = |field: &str, reason: String| Error::Invalid {
            path: path.to_path_buf(),
            field: field.to_owned(),
            reason,
        };
        let (file, text) = GripperFile::read(path).map_err(|e| match e {
            pickplace_grasp::Error::Io { source, .. } => {
                invalid("(file)", format!("cannot read: {source}"))
            }
            pickplace_grasp::Error::GripperSyntax { message, .. } => invalid("(syntax)", message),
            other => invalid("(file)", other.to_string()),
        })?;
        let o = Self(file);
        // Scaled by the largest component before normalising, so a huge axis keeps its
        // direction; a zero or non-finite axis gives NaN, which is along nothing.
        let along = |a: [Real; 3], want: [Real; 3]| {
            let v = Vector3::from(a);
            ((v / v.amax()).normalize() - Vector3::from(want)).norm() <= 1e-9
        };
        let axis = |field: &str, given: Option<[Real; 3]>, want: [Real; 3]| -> Result<()> {
            match given {
                Some(a) if !along(a, want) => Err(invalid(
                    field,
                    format!(
                        "the tool frame is measured on the fingers with {field} = {want:?}; use tool_offset to move the tool point"
                    ),
                )),
                _ => Ok(()),
            }
        };
        axis("approach_axis", o.approach_axis, [0.0, 0.0, 1.0])?;
        axis("closing_axis", o.closing_axis, [0.0, 1.0, 0.0])?;
        o.check_values()
            .map_err(|(field, reason)| invalid(&at_line(&text, field), reason))?;
        Ok(o)
    }

    /// Every number given in range, as `(field, reason)`: the measuring options by
    /// [`GripperOptions::check`] (the rules [`Gripper::derive`] applies), the grasp model's
    /// lengths positive and at most 1 m, `opening_min` below `opening_max`, the palm box
    /// finite, within 1 m and not inverted.
    fn check_values(&self) -> std::result::Result<(), (&'static str, String)> {
        if let Err(pickplace_robot::gripper::GripperError::BadOption { name, reason }) =
            self.options().check()
        {
            let given = match name {
                "squeeze" => self.squeeze,
                "pad_depth" => self.pad_depth,
                "pad_width" => self.pad_width,
                "opening_max" => self.opening_max,
                _ => None,
            };
            let reason = match given {
                Some(v) => format!("{reason}, not {}", fmt_real(v)),
                None => reason.to_owned(),
            };
            return Err((name, reason));
        }
        let length = crate::ranges::Range::above(0.0, 1.0, "m");
        for (field, value) in [
            ("finger_length", self.finger_length),
            ("finger_thickness", self.finger_thickness),
        ] {
            if let Some(v) = value {
                length.check(v).map_err(|e| (field, e.to_string()))?;
            }
        }
        if let Some(v) = self.opening_min {
            crate::ranges::Range::closed(0.0, 1.0, "m")
                .check(v)
                .map_err(|e| ("opening_min", e.to_string()))?;
            if let Some(max) = self.opening_max
                && v >= max
            {
                return Err((
                    "opening_min",
                    format!(
                        "{} m is not below opening_max ({} m)",
                        fmt_real(v),
                        fmt_real(max)
                    ),
                ));
            }
        }
        if let Some(p) = &self.palm {
            let within = crate::ranges::Range::closed(-1.0, 1.0, "m");
            for c in p.min.iter().chain(p.max.iter()) {
                within.check(*c).map_err(|e| ("palm", e.to_string()))?;
            }
            if (0..3).any(|i| p.min[i] >= p.max[i]) {
                return Err(("palm", "min must be below max on every axis".to_owned()));
            }
        }
        Ok(())
    }

    /// The measuring options these overrides give [`Gripper::derive`] (squeeze, pads, largest
    /// opening, tool offset; the rest from [`GripperOptions::default`]).
    pub fn options(&self) -> GripperOptions {
        let d = GripperOptions::default();
        GripperOptions {
            squeeze: self.squeeze.unwrap_or(d.squeeze),
            pad_depth: self.pad_depth,
            pad_width: self.pad_width,
            opening_max: self.opening_max,
            tool_offset: self.tool_offset.map_or(d.tool_offset, Vector3::from),
        }
    }
}

/// What a robot is loaded for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RobotPurpose {
    /// Pick and place: the arms and their grippers found and measured.
    PickAndPlace,
    /// Motion queries only ([`crate::motion`]): no arm or gripper needed.
    Motion,
}

/// The robot of a scene, ready for planning.
#[derive(Debug, Clone)]
pub struct RobotSetup {
    /// The model, with a tool link per arm.
    pub model: RobotModel,
    /// Its semantics (SRDF, completed by the scene's groups).
    pub semantics: Semantics,
    /// The semantic description as merged (for hashing and the allowed-collision matrix).
    pub srdf: Srdf,
    /// `world_from_root`.
    pub world_from_root: Isometry3,
    /// The arms present: the right first.
    pub arms: Vec<RobotArm>,
    /// What was completed or skipped, one line each (said once).
    pub notes: Vec<String>,
    /// What the robot's files got wrong and loading went on from (URDF load warnings, SRDF
    /// elements left out), `file: warning`, also among the notes.
    pub warnings: Vec<String>,
    /// Every input that defines the robot, for cache keys.
    pub key_text: String,
    /// The (first) URDF file, resolved.
    pub urdf_path: PathBuf,
    /// The file that named the groups: the SRDF, or the URDF when there is none.
    pub srdf_path: PathBuf,
    /// Each variable's timing limits (model order): the URDF's velocities, the robots'
    /// joint-limits files, the scene's `[trajectory]` ([`crate::joint_limits::resolve`]).
    pub timing: Vec<crate::joint_limits::TimingLimit>,
    /// The velocity and acceleration scaling of the first joint-limits file that gives one
    /// (MoveIt's `default_*_scaling_factor`), for a scene that sets none.
    pub file_scaling: (Option<Real>, Option<Real>),
}

/// The file a robot error names: the URDF.
pub(crate) fn robot_err(path: &Path) -> impl FnOnce(pickplace_robot::Error) -> Error + '_ {
    move |source| Error::Robot {
        path: path.to_path_buf(),
        source: Box::new(source),
    }
}

impl RobotSetup {
    /// Loads the scene's robot(s). `package_dirs` come after the scene's own.
    ///
    /// # Errors
    /// [`Error::Robot`] for the URDF or SRDF (naming the file), [`Error::Invalid`] for a scene
    /// value that does not fit the robot (an arm group that does not exist, a gripper that
    /// cannot open or close), naming the field.
    pub fn load(scene: &Scene, scene_path: &Path, package_dirs: &[PathBuf]) -> Result<Self> {
        Self::load_for(scene, scene_path, package_dirs, RobotPurpose::PickAndPlace)
    }

    /// Loads the robot(s) of any scene for `purpose`: with [`RobotPurpose::Motion`] the arms
    /// and grippers are neither looked for nor measured ([`RobotSetup::arms`] is empty), so a
    /// robot without a usable hand plans motions.
    ///
    /// # Errors
    /// As [`RobotSetup::load`].
    pub fn load_for<O, T>(
        scene: &SceneOf<O, T>,
        scene_path: &Path,
        package_dirs: &[PathBuf],
        purpose: RobotPurpose,
    ) -> Result<Self> {
        let invalid = |field: &str, reason: String| Error::Invalid {
            path: scene_path.to_path_buf(),
            field: field.to_owned(),
            reason,
        };
        let several = scene.robots.len() > 1;
        let mut limit_files: Vec<(crate::joint_limits::JointLimitsFile, PathBuf, String)> =
            Vec::new();
        let field = |i: usize, f: &str| {
            if several {
                format!("robots[{i}].{f}")
            } else {
                format!("robot.{f}")
            }
        };
        let mut notes = Vec::new();
        let mut key_text = String::new();
        let mut warnings = Vec::new();
        let mut parts: Vec<(RobotModel, Srdf, Isometry3, RobotSpec)> = Vec::new();
        for (i, spec) in scene.robots.iter().enumerate() {
            let mut dirs = spec.package_dirs.clone();
            dirs.extend(package_dirs.iter().cloned());
            let resolve = |p: &Path, f: &str| -> Result<PathBuf> {
                let text = p.to_string_lossy();
                if text.starts_with("package://") {
                    pickplace_robot::model::resolve_uri(&text, Path::new(""), &dirs).map_err(|e| {
                        invalid(
                            &field(i, f),
                            format!(
                                "{text}: {e} (searched: the scene's package_dirs, --package-dir, ROS_PACKAGE_PATH)"
                            ),
                        )
                    })
                } else {
                    Ok(p.to_path_buf())
                }
            };
            let mut resolved = spec.clone();
            resolved.urdf = resolve(&spec.urdf, "urdf")?;
            resolved.srdf = spec
                .srdf
                .as_deref()
                .map(|p| resolve(p, "srdf"))
                .transpose()?;
            resolved.gripper = spec
                .gripper
                .as_deref()
                .map(|p| resolve(p, "gripper"))
                .transpose()?;
            let spec = resolved;
            // The joint-limits table: the scene's file, else one beside the URDF.
            let limits_path = match &spec.joint_limits {
                Some(p) => Some(p.clone()),
                None => spec
                    .urdf
                    .parent()
                    .map(|d| d.join(crate::joint_limits::FILE_NAME))
                    .filter(|p| p.is_file()),
            };
            if let Some(path) = limits_path {
                let file = crate::joint_limits::JointLimitsFile::load(&path).map_err(|e| {
                    Error::Invalid {
                        path: e.path,
                        field: "(file)".into(),
                        reason: e.reason,
                    }
                })?;
                for (factor, field) in [
                    (
                        file.default_velocity_scaling_factor,
                        "default_velocity_scaling_factor",
                    ),
                    (
                        file.default_acceleration_scaling_factor,
                        "default_acceleration_scaling_factor",
                    ),
                ] {
                    if let Some(v) = factor {
                        crate::ranges::SCALING
                            .check(v)
                            .map_err(|e| Error::Invalid {
                                path: path.clone(),
                                field: field.into(),
                                reason: e.to_string(),
                            })?;
                    }
                }
                limit_files.push((file, path, spec.prefix.clone()));
            }
            let options = LoadOptions {
                package_dirs: dirs,
                ..LoadOptions::default()
            };
            let model =
                RobotModel::from_urdf_file(&spec.urdf, &options).map_err(robot_err(&spec.urdf))?;
            for w in model.warnings() {
                warnings.push(format!("{}: {w}", spec.urdf.display()));
                notes.push(format!("{}: {w}", spec.urdf.display()));
            }
            for l in model.split_links() {
                notes.push(format!(
                    "link {:?}: its collision mesh split into {} convex pieces (a hand with one moving jaw: as one hull each, its jaws would overlap)",
                    l.link, l.pieces
                ));
            }
            let mut srdf = match &spec.srdf {
                Some(path) => Srdf::from_file(path).map_err(robot_err(path))?,
                None => Srdf::default(),
            };
            for (name, g) in &spec.groups {
                srdf.groups.retain(|x| &x.name != name);
                srdf.groups.push(group_spec(name, g));
            }
            let world_from_root = spec
                .base_pose
                .to_isometry()
                .map_err(|r| invalid(&field(i, "base_pose"), r.into()))?;
            key_text.push_str(&read_text(&spec.urdf, URDF_FILE));
            key_text.push_str(&format!(
                "geometry {}",
                pickplace_robot::model::GEOMETRY_VERSION
            ));
            if let Some(p) = &spec.srdf {
                key_text.push_str(&read_text(p, SRDF_FILE));
            }
            key_text.push_str(&format!("{:?}{:?}", spec.prefix, spec.groups));
            parts.push((model, srdf, world_from_root, spec));
        }
        let gripper_file = parts.iter().find_map(|p| p.3.gripper.clone());
        let first_urdf = parts.first().map(|p| p.3.urdf.clone()).unwrap_or_default();
        let (model, srdf, world_from_root, srdf_path) = match parts.len() {
            1 => {
                let (model, srdf, pose, spec) = parts.remove(0);
                let path = spec.srdf.clone().unwrap_or_else(|| spec.urdf.clone());
                (model, srdf, pose, path)
            }
            _ => combine(parts, &mut notes)?,
        };
        let semantics =
            Semantics::resolve(&model, &srdf, &srdf_path).map_err(robot_err(&srdf_path))?;

        // The arms and their grippers (a pick-and-place scene's; a motion query needs none).
        let (model, arms) = match purpose {
            RobotPurpose::PickAndPlace => {
                let (model, arms, overrides) = arms::choose(
                    model,
                    &semantics,
                    &scene.planner,
                    gripper_file.as_deref(),
                    &first_urdf,
                    scene_path,
                    &mut notes,
                )?;
                key_text.push_str(&format!("{overrides:?}"));
                (model, arms)
            }
            RobotPurpose::Motion => (model, Vec::new()),
        };
        // A sampled collision matrix (a robot without one) depends on its options too.
        if srdf.disabled_collisions.is_empty() {
            key_text.push_str(&format!(
                "{:?}{}",
                scene.collision_matrix,
                pickplace_robot::collision::SAMPLING_VERSION
            ));
        }
        // Semantics again, on the model with the tool links.
        let semantics =
            Semantics::resolve(&model, &srdf, &srdf_path).map_err(robot_err(&srdf_path))?;
        for w in semantics.warnings() {
            warnings.push(format!("{}: {w}", srdf_path.display()));
            notes.push(format!("{}: {w}", srdf_path.display()));
        }
        let variables: Vec<String> = model.variable_names().map(str::to_owned).collect();
        let joints: Vec<String> = model.joints().iter().map(|j| j.name.clone()).collect();
        let velocities: Vec<Real> = model.variable_limits().map(|l| l.velocity).collect();
        let mut tables: Vec<(&BTreeMap<String, JointLimitSpec>, String, String)> = limit_files
            .iter()
            .map(|(f, p, prefix)| (&f.joint_limits, p.display().to_string(), prefix.clone()))
            .collect();
        tables.push((
            &scene.trajectory.joint_limits,
            scene_path.display().to_string(),
            String::new(),
        ));
        let timing = crate::joint_limits::resolve(
            &variables,
            &joints,
            &velocities,
            scene.trajectory.max_acceleration,
            &tables,
        )
        .map_err(|(source, field, reason)| {
            // The scene's own table is `[trajectory.joint_limits]`.
            let field = if Path::new(&source) == scene_path {
                format!("trajectory.{field}")
            } else {
                field
            };
            Error::Invalid {
                path: source.into(),
                field,
                reason,
            }
        })?;
        // A limit far too small (a URDF's velocity="1e-300") would make every motion last
        // for ages or underflow the timing: refused here, naming the joint and its source.
        for (name, limit) in variables.iter().zip(&timing) {
            for (what, value, source, range) in [
                (
                    "velocity",
                    limit.velocity,
                    &limit.velocity_source,
                    crate::ranges::JOINT_VELOCITY,
                ),
                (
                    "acceleration",
                    limit.acceleration,
                    &limit.acceleration_source,
                    crate::ranges::JOINT_ACCELERATION,
                ),
            ] {
                if let Err(e) = range.check(value) {
                    let path = match source.as_str() {
                        "urdf" => scene
                            .robots
                            .iter()
                            .filter(|r| name.starts_with(&r.prefix))
                            .max_by_key(|r| r.prefix.len())
                            .map_or_else(|| first_urdf.clone(), |r| r.urdf.clone()),
                        "default" => scene_path.to_path_buf(),
                        file => PathBuf::from(file),
                    };
                    return Err(Error::Invalid {
                        path,
                        field: format!("joint {name:?}"),
                        reason: format!("{what} limit {e}"),
                    });
                }
            }
        }
        let file_scaling = (
            limit_files
                .iter()
                .find_map(|f| f.0.default_velocity_scaling_factor),
            limit_files
                .iter()
                .find_map(|f| f.0.default_acceleration_scaling_factor),
        );
        Ok(Self {
            model,
            semantics,
            srdf,
            world_from_root,
            arms,
            notes,
            warnings,
            key_text,
            urdf_path: first_urdf,
            srdf_path,
            timing,
            file_scaling,
        })
    }

    /// The default velocity and acceleration scaling factors: the scene's `[trajectory]`,
    /// else the joint-limits file's defaults, else 1.
    pub fn scaling(&self, trajectory: &crate::scene::TrajectorySpec) -> (Real, Real) {
        (
            trajectory
                .velocity_scaling
                .or(self.file_scaling.0)
                .unwrap_or(1.0),
            trajectory
                .acceleration_scaling
                .or(self.file_scaling.1)
                .unwrap_or(1.0),
        )
    }

    /// The arm, if the robot has it.
    pub fn arm(&self, arm: Arm) -> Option<&RobotArm> {
        self.arms.iter().find(|a| a.arm == arm)
    }
}

/// The grasp planner's gripper model: measured on the URDF (`gripper`), then overridden by
/// `o`; a bad value names `source` (the overrides file, else the URDF).
///
/// # Errors
/// [`pickplace_grasp::Error::InvalidGripper`] naming the first bad parameter.
pub fn grasp_model(
    gripper: &Gripper,
    o: &GripperOverrides,
    source: &Path,
) -> std::result::Result<GripperParams, pickplace_grasp::Error> {
    let (lo, hi) = gripper.opening_range();
    let (pad_width, pad_depth) = gripper.pad_size();
    let (finger_length, finger_thickness) = gripper.finger_size();
    let (pmin, mut pmax) = gripper.palm_box();
    if gripper.has_fixed_jaw() {
        // The palm in the grasp's centre frame moves with the width (the tool point is on
        // the fixed jaw): the box covers every width.
        pmax.y += hi / 2.0 + pickplace_robot::gripper::FIXED_JAW_CLEARANCE;
    }
    let params = GripperParams {
        opening_min: o.opening_min.unwrap_or(lo),
        opening_max: o.opening_max.map_or(hi, |m| m.min(hi)),
        pad_width: o.pad_width.unwrap_or(pad_width),
        pad_depth: o.pad_depth.unwrap_or(pad_depth),
        finger_length: o.finger_length.unwrap_or(finger_length),
        finger_thickness: o.finger_thickness.unwrap_or(finger_thickness),
        approach_axis: Vector3::z(),
        closing_axis: Vector3::y(),
        palm: o.palm.unwrap_or(PalmBox {
            min: Point3::from(pmin.coords),
            max: Point3::from(pmax.coords),
        }),
    };
    params.validate_for(source)?;
    Ok(params)
}

/// `line N: field` for the line of a TOML file where `field` (or, for the palm, its table)
/// is given; the bare field when it cannot be found (a dotted or inline form).
fn at_line(text: &str, field: &str) -> String {
    let found = text.lines().position(|line| {
        let line = line.trim_start();
        if field == "palm" && line.starts_with("[palm]") {
            return true;
        }
        line.strip_prefix(field)
            .is_some_and(|rest| rest.trim_start().starts_with('='))
    });
    match found {
        Some(i) => format!("line {}: {field}", i + 1),
        None => field.to_owned(),
    }
}

fn group_spec(name: &str, g: &GroupSpecToml) -> GroupSpec {
    GroupSpec {
        name: name.to_owned(),
        chains: match (&g.base_link, &g.tip_link) {
            (Some(b), Some(t)) => vec![ChainSpec {
                base_link: b.clone(),
                tip_link: t.clone(),
            }],
            _ => Vec::new(),
        },
        joints: g.joints.clone(),
        links: Vec::new(),
        subgroups: Vec::new(),
    }
}

fn read_text(path: &Path, kind: FileKind) -> String {
    // A file that cannot be read keys as empty; loading it reports the error.
    pickplace_geometry::io::read_text(path, kind).unwrap_or_default()
}

/// Several robots as one model under a `world` root, names prefixed.
fn combine(
    parts: Vec<(RobotModel, Srdf, Isometry3, RobotSpec)>,
    notes: &mut Vec<String>,
) -> Result<(RobotModel, Srdf, Isometry3, PathBuf)> {
    let first = parts.first().map(|p| p.3.urdf.clone()).unwrap_or_default();
    let models: Vec<(String, &RobotModel, Isometry3)> = parts
        .iter()
        .map(|(m, _, pose, spec)| (spec.prefix.clone(), m, *pose))
        .collect();
    let name = parts
        .iter()
        .map(|p| format!("{}{}", p.3.prefix, p.0.name()))
        .collect::<Vec<_>>()
        .join("+");
    let model = RobotModel::combine(&name, &models).map_err(robot_err(&first))?;
    let srdfs: Vec<Srdf> = parts
        .iter()
        .map(|(_, s, _, spec)| s.prefixed(&spec.prefix))
        .collect();
    let srdf = Srdf::merge(&srdfs, &name);
    notes.push(format!(
        "{} robots combined as {name:?} under a root link \"world\" (names prefixed)",
        parts.len()
    ));
    Ok((model, srdf, Isometry3::identity(), first))
}
