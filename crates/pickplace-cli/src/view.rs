//! `pickplace view`: an animated glTF (`plan.glb`) and PNG pictures of the key poses of a
//! plan, rendered on the CPU by `pickplace-view`; and the `--png` pictures of `clusters` and
//! `placements`.
//!
//! Everything is computed and encoded in memory before the first file is written, and every
//! file is written atomically, so bad input never leaves a partial output behind.

use anyhow::{Context, Result, bail};
use pickplace::{Plan, RobotSetup, Scene};
use pickplace_geometry::math::Isometry3;
use pickplace_geometry::mesh::{self, MeshOptions};
use pickplace_view::{
    Colour, Geometry, Grip, Motion, PlanView, Prop, RenderOptions, RobotGeometry,
    RobotGeometryOptions,
};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

/// Arguments of `pickplace view`.
#[derive(Debug, clap::Args)]
pub struct ViewArgs {
    /// Plan file (JSON, format `pickplace.plan/1`, as written by `pickplace plan`).
    pub plan: PathBuf,
    /// The scene the plan was made for (robot, object and environment meshes).
    #[arg(long, value_name = "SCENE.toml")]
    pub scene: PathBuf,
    /// Output folder, created if needed.
    #[arg(long, value_name = "DIR", default_value = "pickplace-view")]
    pub out: PathBuf,
    /// Size of the key-pose pictures, WIDTHxHEIGHT in pixels.
    #[arg(long, value_name = "WxH", default_value = "800x600")]
    pub size: String,
    /// A folder searched for `package://` mesh paths (repeatable; after the scene's
    /// `package_dirs`, before ROS_PACKAGE_PATH).
    #[arg(long = "package-dir", value_name = "DIR")]
    pub package_dirs: Vec<PathBuf>,
}

/// Default size of the key-pose pictures written by [`write_view`] (pixels).
pub const DEFAULT_SIZE: (u32, u32) = (800, 600);

/// Parses `WIDTHxHEIGHT` (each 1 to [`MAX_IMAGE_SIDE`](pickplace_view::MAX_IMAGE_SIDE)
/// pixels, at most [`MAX_IMAGE_PIXELS`](pickplace_view::MAX_IMAGE_PIXELS) in all), before
/// anything is read or allocated.
pub fn parse_size(text: &str) -> Result<(u32, u32)> {
    let parse = |s: &str| -> Option<u32> {
        s.trim()
            .parse()
            .ok()
            .filter(|v| (1..=pickplace_view::MAX_IMAGE_SIDE).contains(v))
    };
    match text.split_once(['x', 'X']) {
        Some((w, h)) => match (parse(w), parse(h)) {
            (Some(w), Some(h)) => {
                pickplace_view::check_image_size(w, h)
                    .with_context(|| format!("--size `{text}`"))?;
                Ok((w, h))
            }
            _ => bail!(
                "--size `{text}`: width and height must be whole numbers from 1 to {}",
                pickplace_view::MAX_IMAGE_SIDE
            ),
        },
        None => bail!("--size `{text}`: expected WIDTHxHEIGHT, for example 800x600"),
    }
}

/// Render options for a picture of `size`.
pub fn render_options(size: (u32, u32)) -> RenderOptions {
    RenderOptions {
        width: size.0,
        height: size.1,
        ..RenderOptions::default()
    }
}

/// `pickplace view`.
pub fn run(args: &ViewArgs) -> Result<ExitCode> {
    let size = parse_size(&args.size)?;
    let plan = Plan::load(&args.plan)?;
    let mut scene = Scene::load(&args.scene)?;
    for robot in &mut scene.robots {
        robot.package_dirs.extend(args.package_dirs.iter().cloned());
    }
    // Before any work: no output may replace a link, a device or an input.
    let mut inputs = crate::args::scene_inputs(&args.scene, &scene);
    inputs.push(("the plan".to_owned(), args.plan.clone()));
    let inputs = crate::args::as_inputs(&inputs);
    crate::args::check_output_dir(&args.out, "--out", &inputs)?;
    for name in output_names(&plan) {
        crate::args::check_output_file(&args.out.join(name), "--out", &inputs)?;
    }
    let written = write_view_sized(&scene, &args.scene, &plan, &args.out, size)
        .with_context(|| format!("{}", args.plan.display()))?;
    let mut text = String::new();
    for path in &written {
        crate::output::outln!(text, "{}", path.display());
    }
    crate::output::print(&text)?;
    Ok(ExitCode::SUCCESS)
}

/// Writes `out/plan.glb` and `out/keypose-NN-NAME.png` (800x600) for `plan` in `scene`, and
/// returns the paths written (the glb first). Creates `out` if needed.
///
/// # Errors
/// Unreadable robot or meshes (naming the file), a plan whose joint names are not the robot's
/// actuated joints, events naming unknown links, or a write failure. Nothing is written
/// unless everything could be computed.
pub fn write_view(
    scene: &Scene,
    scene_path: &Path,
    plan: &Plan,
    out: &Path,
) -> Result<Vec<PathBuf>> {
    write_view_sized(scene, scene_path, plan, out, DEFAULT_SIZE)
}

/// As [`write_view`], with pictures of `size` (width, height) pixels.
pub fn write_view_sized(
    scene: &Scene,
    scene_path: &Path,
    plan: &Plan,
    out: &Path,
    size: (u32, u32),
) -> Result<Vec<PathBuf>> {
    let view = plan_view(scene, scene_path, plan)?;
    // Compute and encode everything before writing anything.
    let glb = view
        .gltf("plan")
        .and_then(|g| g.encode())
        .context("building the glTF")?;
    let options = render_options(size);
    let camera = view.camera(f64::from(size.0) / f64::from(size.1))?;
    let mut names = output_names(plan).into_iter();
    let mut files: Vec<(PathBuf, Vec<u8>)> = Vec::with_capacity(plan.key_poses.len() + 1);
    files.extend(names.next().map(|name| (out.join(name), glb)));
    for (key, name) in plan.key_poses.iter().zip(names) {
        let frame = view.frame_at_time(key.time);
        let png = view
            .render_frame(frame, Some(&camera), &options)?
            .encode_png()?;
        files.push((out.join(name), png));
    }
    std::fs::create_dir_all(out)
        .with_context(|| format!("{}: cannot create the folder", out.display()))?;
    let mut written = Vec::with_capacity(files.len());
    for (path, bytes) in files {
        pickplace_geometry::export::write_atomic(&path, &bytes)?;
        written.push(path);
    }
    Ok(written)
}

/// The names of the files [`write_view`] writes for `plan`: `plan.glb`, then one PNG per key
/// pose.
fn output_names(plan: &Plan) -> Vec<String> {
    std::iter::once("plan.glb".to_owned())
        .chain(
            plan.key_poses
                .iter()
                .enumerate()
                .map(|(i, key)| format!("keypose-{:02}-{}.png", i, file_name_part(&key.name))),
        )
        .collect()
}

/// `name` with every character outside `[A-Za-z0-9_-]` replaced by `-`.
fn file_name_part(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect();
    if s.is_empty() { "pose".into() } else { s }
}

/// Colours of the environment parts, in scene order.
const ENVIRONMENT_COLOURS: [Colour; 4] = [
    Colour::new(176, 140, 100),
    Colour::new(150, 160, 175),
    Colour::new(140, 170, 130),
    Colour::new(190, 170, 150),
];

/// The plan evaluated in the scene: robot loaded, joints mapped, grips from the events.
pub fn plan_view(scene: &Scene, scene_path: &Path, plan: &Plan) -> Result<PlanView> {
    // The robot as the planner saw it (combined robots, tool links).
    let setup = RobotSetup::load(scene, scene_path, &[])?;
    let robot = setup.model;
    let world_from_root = setup.world_from_root;

    // Plan columns -> robot variables; the names must be exactly the robot's variables.
    let robot_names: Vec<&str> = robot.variable_names().collect();
    let columns = plan.columns(&robot_names).map_err(|e| {
        anyhow::anyhow!(
            "the plan's joint names do not match the robot {} ({}): {e}",
            robot.name(),
            scene.robots[0].urdf.display()
        )
    })?;
    let times: Vec<f64> = plan.trajectory.iter().map(|p| p.time_from_start).collect();
    let configurations: Vec<Vec<f64>> = plan
        .trajectory
        .iter()
        .map(|p| columns.iter().map(|&c| p.positions[c]).collect())
        .collect();
    // Grips: the plan's holds, on the robot's links (every event's link first).
    let mut events: Vec<&pickplace::plan::Event> = plan.events.iter().collect();
    events.sort_by(|a, b| a.time.total_cmp(&b.time));
    for (i, e) in events.iter().enumerate() {
        if robot.link_index(&e.link).is_none() {
            bail!(
                "event {i} ({:?} at {} s): the robot has no link {:?}",
                e.kind,
                e.time,
                e.link
            );
        }
    }
    let grips: Vec<Grip> = plan
        .holds()
        .map_err(anyhow::Error::msg)?
        .into_iter()
        .map(|h| {
            Ok(Grip {
                link: robot.link_index(&h.link).with_context(|| {
                    format!(
                        "grasp at {} s: the robot has no link {:?}",
                        h.grasp_time, h.link
                    )
                })?,
                link_from_object: h.link_from_object,
                grasp_time: h.grasp_time,
                release_time: h.release_time,
            })
        })
        .collect::<Result<_>>()?;
    let motion = Motion {
        world_from_root,
        times,
        configurations,
        grips,
    };

    let object_mesh = mesh::load(
        &scene.object.mesh,
        &MeshOptions {
            scale: scene.object.scale,
            ..MeshOptions::default()
        },
    )?;
    let object = Prop {
        name: "object".into(),
        geometry: Arc::new(Geometry::from_trimesh(&object_mesh)),
        world_from_mesh: pose(&plan.object.start_pose, "object.start_pose")?,
        colour: Colour::ORANGE,
    };
    let mut environment = Vec::with_capacity(scene.environment.len());
    for (i, env) in scene.environment.iter().enumerate() {
        let body =
            pickplace::obstacle::load_environment(env, &format!("environment[{i}]"), scene_path)?;
        environment.push(Prop {
            name: env.name.clone(),
            geometry: Arc::new(Geometry::from_trimesh(&body.mesh)),
            world_from_mesh: body.world_from_mesh,
            colour: ENVIRONMENT_COLOURS[i % ENVIRONMENT_COLOURS.len()],
        });
    }
    let geometry = RobotGeometry::new(&robot, &RobotGeometryOptions::default())?;
    Ok(PlanView::new(
        &robot,
        geometry,
        &motion,
        object,
        environment,
    )?)
}

fn pose(spec: &pickplace::scene::PoseSpec, what: &str) -> Result<Isometry3> {
    spec.to_isometry()
        .map_err(|e| anyhow::anyhow!("{what}: {e}"))
}
