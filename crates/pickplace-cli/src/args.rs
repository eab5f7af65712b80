//! Parsing of the command line's values that more than one command takes: poses and points;
//! and the one check of every output destination ([`check_output_file`], [`check_output_dir`]).
//!
//! One pose syntax for every option that takes a pose (`placements --env-pose`,
//! `robot ik --pose`):
//! - `x,y,z`: a position (m), no rotation;
//! - `x,y,z,qx,qy,qz,qw`: a position and a quaternion in ROS order (normalised);
//! - `{"position":[x,y,z],"orientation":[qx,qy,qz,qw]}`: the pose object of every pickplace
//!   JSON document.

use anyhow::{Context as _, bail};
use pickplace_geometry::math::nalgebra::Quaternion;
use pickplace_geometry::math::{Isometry3, Point3, Real, Translation3, UnitQuaternion};
use std::path::{Path, PathBuf};

/// Parses comma-separated finite numbers; `option` names the option in errors.
pub fn parse_numbers(text: &str, option: &str) -> anyhow::Result<Vec<Real>> {
    text.split(',')
        .map(|s| {
            let v: Real = s
                .trim()
                .parse()
                .with_context(|| format!("{option} `{text}`: `{s}` is not a number"))?;
            if !v.is_finite() {
                bail!("{option} `{text}`: `{s}` is not finite");
            }
            Ok(v)
        })
        .collect()
}

/// Parses a pose in any of the three forms of the module doc; `option` names the option in errors.
///
/// # Errors
/// A number that does not parse or is not finite, a count other than 3 or 7, a zero
/// quaternion, a JSON object of another shape.
pub fn parse_pose(text: &str, option: &str) -> anyhow::Result<Isometry3> {
    let numbers = if text.trim_start().starts_with('{') {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Pose {
            position: [Real; 3],
            orientation: [Real; 4],
        }
        let p: Pose = serde_json::from_str(text).with_context(|| {
            format!(
                "{option} `{text}` is not {{\"position\":[x,y,z],\"orientation\":[qx,qy,qz,qw]}}"
            )
        })?;
        let numbers: Vec<Real> = p.position.iter().chain(&p.orientation).copied().collect();
        if numbers.iter().any(|x| !x.is_finite()) {
            bail!("{option} `{text}`: every number must be finite");
        }
        numbers
    } else {
        parse_numbers(text, option)?
    };
    let rotation = match numbers.len() {
        3 => UnitQuaternion::identity(),
        7 => {
            let q = Quaternion::new(numbers[6], numbers[3], numbers[4], numbers[5]);
            if q.norm() < 1e-9 {
                bail!("{option} `{text}`: the quaternion is zero");
            }
            UnitQuaternion::from_quaternion(q)
        }
        n => {
            bail!("{option} `{text}`: expected 3 numbers (x,y,z) or 7 (x,y,z,qx,qy,qz,qw), got {n}")
        }
    };
    Ok(Isometry3::from_parts(
        Translation3::new(numbers[0], numbers[1], numbers[2]),
        rotation,
    ))
}

/// Parses a point `x,y,z` (m); `option` names the option in errors.
pub fn parse_point(text: &str, option: &str) -> anyhow::Result<Point3> {
    let v = parse_numbers(text, option)?;
    if v.len() != 3 {
        bail!(
            "{option} `{text}`: expected 3 numbers X,Y,Z, got {}",
            v.len()
        );
    }
    Ok(Point3::new(v[0], v[1], v[2]))
}

/// An input file of a command, with what it is (`"the scene"`, `"the object mesh"`).
pub type Input<'a> = (&'a str, &'a Path);

/// Refuses an output file that must not be written, before any work is done: `path` must be
/// a regular file or not exist yet, and not be one of the command's `inputs`.
///
/// Outputs are written atomically (a temporary file renamed over `path`), which would replace
/// a symbolic link (`/dev/stdout`) or a device node (`/dev/null`) by a plain file, and would
/// overwrite an input (the scene given as `--out`). Refused, each with its own words:
/// - a symbolic link (give the file it points to);
/// - a folder;
/// - a device, FIFO or socket (`/dev/null` included: to print the output, leave the option
///   out where the command prints on standard output, or redirect that);
/// - one of `inputs`, by identity (the same file reached by another path or a hard link).
///
/// # Errors
/// Each case above, naming `option`, the path and what it is.
pub fn check_output_file(path: &Path, option: &str, inputs: &[Input<'_>]) -> anyhow::Result<()> {
    let shown = path.display();
    let meta = match std::fs::symlink_metadata(path) {
        Ok(meta) => meta,
        // Not there yet (or unreachable: the write will say why).
        Err(_) => return Ok(()),
    };
    let kind = meta.file_type();
    if kind.is_symlink() {
        bail!(
            "{option} {shown}: is a symbolic link; outputs replace what is at the path, so give the file the link points to"
        );
    }
    if kind.is_dir() {
        bail!("{option} {shown}: is a folder; give a file name");
    }
    if !kind.is_file() {
        bail!(
            "{option} {shown}: is a device, FIFO or socket, not a regular file; outputs are regular files only"
        );
    }
    for (what, input) in inputs {
        if same_file(path, &meta, input) {
            bail!(
                "{option} {shown}: is {what} ({}), an input of this command; it would be overwritten",
                input.display()
            );
        }
    }
    Ok(())
}

/// Refuses an output folder that must not be written into, before any work is done: `path`
/// must be a folder (a symbolic link to one is followed: the files are written inside it,
/// the link stays) or not exist yet, and not be one of `inputs`.
///
/// # Errors
/// A path that exists and is not a folder (a file, a device), naming `option` and the path.
pub fn check_output_dir(path: &Path, option: &str, inputs: &[Input<'_>]) -> anyhow::Result<()> {
    let shown = path.display();
    let Ok(meta) = std::fs::metadata(path) else {
        return Ok(());
    };
    if !meta.is_dir() {
        for (what, input) in inputs {
            if same_file(path, &meta, input) {
                bail!(
                    "{option} {shown}: is {what} ({}), an input of this command, not a folder",
                    input.display()
                );
            }
        }
        bail!("{option} {shown}: is not a folder; give a folder (created if missing)");
    }
    Ok(())
}

/// True when `input` is the file `path` (whose metadata is `meta`), by identity.
fn same_file(path: &Path, meta: &std::fs::Metadata, input: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        let _ = path;
        std::fs::metadata(input).is_ok_and(|m| m.dev() == meta.dev() && m.ino() == meta.ino())
    }
    #[cfg(not(unix))]
    {
        let _ = meta;
        let canonical = |p: &Path| -> Option<PathBuf> { std::fs::canonicalize(p).ok() };
        canonical(path).is_some_and(|a| canonical(input) == Some(a))
    }
}

/// The files a scene names (the scene itself, each robot's URDF, SRDF and gripper file, the
/// object and environment meshes), as inputs for [`check_output_file`]. `package://` paths
/// and the meshes a URDF names are not included.
pub fn scene_inputs<O: SceneObject, T>(
    scene_path: &Path,
    scene: &pickplace::scene::SceneOf<O, T>,
) -> Vec<(String, PathBuf)> {
    let mut inputs = vec![("the scene".to_owned(), scene_path.to_path_buf())];
    for robot in &scene.robots {
        inputs.push(("the robot's URDF".to_owned(), robot.urdf.clone()));
        if let Some(p) = &robot.srdf {
            inputs.push(("the robot's SRDF".to_owned(), p.clone()));
        }
        if let Some(p) = &robot.gripper {
            inputs.push(("the gripper file".to_owned(), p.clone()));
        }
    }
    if let Some(mesh) = scene.object.mesh() {
        inputs.push(("the object mesh".to_owned(), mesh.to_path_buf()));
    }
    for env in &scene.environment {
        if let Some(mesh) = &env.mesh {
            inputs.push((format!("the mesh of {:?}", env.name), mesh.clone()));
        }
    }
    inputs
}

/// The object of a scene, required ([`pickplace::Scene`]) or not
/// ([`pickplace::scene::MotionScene`]).
pub trait SceneObject {
    /// Its mesh file, when there is an object.
    fn mesh(&self) -> Option<&Path>;
}

impl SceneObject for pickplace::scene::ObjectSpec {
    fn mesh(&self) -> Option<&Path> {
        Some(&self.mesh)
    }
}

impl SceneObject for Option<pickplace::scene::ObjectSpec> {
    fn mesh(&self) -> Option<&Path> {
        self.as_ref().map(|o| o.mesh.as_path())
    }
}

/// `inputs` as [`Input`]s.
pub fn as_inputs(inputs: &[(String, PathBuf)]) -> Vec<Input<'_>> {
    inputs
        .iter()
        .map(|(w, p)| (w.as_str(), p.as_path()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn output_destinations_that_must_not_be_written_are_refused() {
        let dir = tempfile_dir();
        let scene = dir.join("scene.toml");
        std::fs::write(&scene, "x").expect("scene");
        let inputs: [Input<'_>; 1] = [("the scene", &scene)];
        let link = dir.join("link.json");
        std::os::unix::fs::symlink(dir.join("elsewhere.json"), &link).expect("symlink");
        let hard = dir.join("hard.toml");
        std::fs::hard_link(&scene, &hard).expect("hard link");
        let message = |p: &Path| {
            format!(
                "{:#}",
                check_output_file(p, "--out", &inputs).expect_err("refused")
            )
        };
        assert!(message(&link).contains("is a symbolic link"));
        assert!(message(&dir).contains("is a folder"));
        assert!(message(Path::new("/dev/null")).contains("is a device"));
        let m = message(&scene);
        assert!(
            m.starts_with(&format!("--out {}: is the scene", scene.display())),
            "{m}"
        );
        assert!(message(&hard).contains("is the scene"));
        assert!(message(&dir.join(".").join("scene.toml")).contains("is the scene"));
        // A new file and an existing regular file are fine.
        check_output_file(&dir.join("new.json"), "--out", &inputs).expect("new");
        std::fs::write(dir.join("old.json"), "x").expect("old");
        check_output_file(&dir.join("old.json"), "--out", &inputs).expect("old");
        // Folders.
        check_output_dir(&dir, "--out", &inputs).expect("a folder");
        check_output_dir(&dir.join("new"), "--out", &inputs).expect("created later");
        let e = check_output_dir(&scene, "--out", &inputs).expect_err("the scene");
        assert!(format!("{e:#}").contains("is the scene"), "{e:#}");
        let e = check_output_dir(Path::new("/dev/null"), "--out", &[]).expect_err("device");
        assert!(format!("{e:#}").contains("is not a folder"), "{e:#}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A fresh folder under the system's temporary folder.
    #[cfg(unix)]
    fn tempfile_dir() -> PathBuf {
        let dir = std::env::temp_dir().join(format!("pickplace-args-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch");
        dir
    }
    use pickplace_geometry::math::Vector3;

    fn error(text: &str) -> String {
        format!("{:#}", parse_pose(text, "--pose").expect_err(text))
    }

    #[test]
    fn the_three_spellings_give_the_same_pose() {
        let json = parse_pose(
            r#"{"position":[0.1,0.2,0.3],"orientation":[0,0,0.6,0.8]}"#,
            "--pose",
        )
        .expect("json");
        let list = parse_pose("0.1, 0.2, 0.3, 0, 0, 0.6, 0.8", "--pose").expect("list");
        assert_eq!(json, list);
        assert_eq!(list.translation.vector, Vector3::new(0.1, 0.2, 0.3));
        assert!((list.rotation.quaternion().k - 0.6).abs() < 1e-12);
        let position = parse_pose("-1,2,3", "--pose").expect("position only");
        assert_eq!(position, Isometry3::translation(-1.0, 2.0, 3.0));
    }

    #[test]
    fn quaternions_are_normalised() {
        let p = parse_pose("0,0,0,0,0,2,0", "--pose").expect("valid");
        assert!((p.rotation.quaternion().k - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bad_poses_say_what_is_wrong() {
        for (text, needle) in [
            ("1,2", "expected 3 numbers"),
            ("1,2,3,4", "got 4"),
            ("1,2,3,0,0,0,0", "quaternion is zero"),
            ("1,2,NaN", "not finite"),
            ("1,2,x", "`x` is not a number"),
            (r#"{"position":[1,2,3]}"#, "is not {"),
            (
                r#"{"position":[1,2,3],"orientation":[0,0,0,1],"x":1}"#,
                "is not {",
            ),
        ] {
            let message = error(text);
            assert!(message.starts_with("--pose"), "{text}: {message}");
            assert!(message.contains(needle), "{text}: {message}");
        }
    }

    #[test]
    fn points_need_three_numbers() {
        assert_eq!(
            parse_point("1, -2, 3", "--target").expect("point"),
            Point3::new(1.0, -2.0, 3.0)
        );
        let e = format!("{:#}", parse_point("1,2", "--target").expect_err("two"));
        assert!(e.contains("--target") && e.contains("got 2"), "{e}");
        assert!(parse_point("a,b,c", "--target").is_err());
    }
}

/// `clap` value parsers for numbers, each over its range in the one table
/// ([`pickplace::ranges`]): a value out of range is a usage error (exit 2) naming the flag.
pub mod number {
    use pickplace::ranges::{self, FlagError, parse_flag};

    /// A mesh scale factor.
    pub fn mesh_scale(text: &str) -> Result<f64, FlagError> {
        parse_flag(text, ranges::MESH_SCALE)
    }

    /// A cluster thickness h_max (m).
    pub fn h_max(text: &str) -> Result<f64, FlagError> {
        parse_flag(text, ranges::H_MAX)
    }

    /// The "usually in collision" fraction of a sampled collision matrix.
    pub fn collision_fraction(text: &str) -> Result<f64, FlagError> {
        parse_flag(text, ranges::COLLISION_FRACTION)
    }

    /// A number of sampled configurations.
    pub fn samples(text: &str) -> Result<usize, FlagError> {
        parse_flag(text, ranges::MATRIX_SAMPLES).map(|v| v as usize)
    }

    /// The grasp planner's grid step (m).
    pub fn grid_step(text: &str) -> Result<f64, FlagError> {
        parse_flag(text, ranges::GRID_STEP)
    }

    /// The grasp planner's clearance (m).
    pub fn clearance(text: &str) -> Result<f64, FlagError> {
        parse_flag(text, ranges::CLEARANCE)
    }

    /// Approach directions about a grasp axis.
    pub fn approaches(text: &str) -> Result<usize, FlagError> {
        parse_flag(text, ranges::APPROACHES).map(|v| v as usize)
    }
}

/// The trajectory's timing options of `plan`, `batch` and `motion` (`#[command(flatten)]`).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct TimingArgs {
    /// Fraction of every joint's velocity limit the trajectories use, in (0, 1] (MoveIt's
    /// velocity scaling factor; default: the scene's trajectory.velocity_scaling, else the
    /// joint-limits file's default, else 1).
    #[arg(long, value_name = "FACTOR", value_parser = crate::plan::scaling_factor)]
    pub velocity_scaling: Option<f64>,
    /// Fraction of every joint's acceleration limit the trajectories use, in (0, 1] (default
    /// as for --velocity-scaling).
    #[arg(long, value_name = "FACTOR", value_parser = crate::plan::scaling_factor)]
    pub acceleration_scaling: Option<f64>,
    /// Time between trajectory samples, seconds, in [0.001, 1] (default: 0.04).
    #[arg(long, value_name = "SECONDS", value_parser = crate::plan::sample_period)]
    pub sample_period: Option<f64>,
}

impl TimingArgs {
    /// These options over a scene's planner values (the rest left unset).
    pub fn overrides(&self) -> pickplace::planner::PlanOverrides {
        pickplace::planner::PlanOverrides {
            velocity_scaling: self.velocity_scaling,
            acceleration_scaling: self.acceleration_scaling,
            sample_period: self.sample_period,
            ..pickplace::planner::PlanOverrides::default()
        }
    }
}

/// The cache and package folders of the commands that set up a scene (`plan`, `validate`,
/// `motion`, `batch`; `#[command(flatten)]`).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct SceneFolders {
    /// Folder of the cache: cluster databases, grasp sets, roadmaps and sampled collision
    /// matrices, each read when present and written when built (default: $PICKPLACE_CACHE,
    /// else $XDG_CACHE_HOME/pickplace, else ~/.cache/pickplace). `validate` reads only the
    /// object's clusters there.
    #[arg(long, value_name = "DIR")]
    pub cache: Option<PathBuf>,
    /// Use no cache: what it would hold is built in memory (same results, slower).
    #[arg(long, conflicts_with = "cache")]
    pub no_cache: bool,
    /// A folder searched for `package://` mesh paths (repeatable; after the scene's
    /// `package_dirs`, before ROS_PACKAGE_PATH).
    #[arg(long = "package-dir", value_name = "DIR")]
    pub package_dirs: Vec<PathBuf>,
}

impl SceneFolders {
    /// The cache these flags choose.
    pub fn cache_choice(&self) -> crate::plan::CacheChoice {
        crate::plan::CacheChoice::from_args(self.cache.as_deref(), self.no_cache)
    }
}
