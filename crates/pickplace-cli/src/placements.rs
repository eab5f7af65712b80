//! `pickplace placements`: stable placements of an object on an environment (Algorithm 2), or
//! its resting poses on a horizontal plane when no environment is given.

use crate::args::{parse_point, parse_pose};
use crate::output::note;
use crate::output::outln;
use anyhow::{Context, bail};
use pickplace_geometry::cluster::{ClusterParams, ContactMode, cluster_surface};
use pickplace_geometry::math::{Isometry3, Point3, Real, Translation3};
use pickplace_geometry::mesh::{self, MassProperties, MeshOptions};
use pickplace_placement::json::PlacementsJson;
use pickplace_placement::{
    ContactKind, EnvironmentModel, ObjectModel, PlacementOptions, RestingOptions, candidates,
    default_target, resting_poses,
};
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `pickplace placements`.
#[derive(Debug, clap::Args)]
pub struct PlacementsArgs {
    /// Object mesh (.stl, .obj, .ply), in metres.
    pub object: PathBuf,
    /// Environment mesh to place the object on. Without it, the object's resting poses on an
    /// infinite horizontal plane are listed.
    #[arg(long = "on", value_name = "ENV_MESH")]
    pub on: Option<PathBuf>,
    /// Pose of the environment in the world: `x,y,z`, `x,y,z,qx,qy,qz,qw` or
    /// `{"position":[x,y,z],"orientation":[qx,qy,qz,qw]}` (default: identity).
    #[arg(long, value_name = "POSE", requires = "on", allow_hyphen_values = true)]
    pub env_pose: Option<String>,
    /// The point on the environment where the object should go (the paper's click), world
    /// frame. Default: the centre of the environment's largest upward-facing cluster.
    #[arg(
        long,
        value_name = "X,Y,Z",
        requires = "on",
        allow_hyphen_values = true
    )]
    pub target: Option<String>,
    /// Scale applied to both meshes on loading (default: 1, the files are in metres).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true, value_parser = crate::args::number::mesh_scale)]
    pub scale: Real,
    /// h_max of the environment-contact clustering (m).
    #[arg(long, default_value_t = 0.001, allow_negative_numbers = true, value_parser = crate::args::number::h_max)]
    pub h_max: Real,
    /// Maximum number of placements listed.
    #[arg(long, default_value_t = 32)]
    pub max: usize,
    /// Print JSON on stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also draw the placements as a PNG picture (the paper's Fig. 6): the environment, the
    /// best placement opaque and the others translucent, the target as a red sphere. Without
    /// --on, the resting poses side by side on a plate.
    #[arg(long, value_name = "FILE")]
    pub png: Option<PathBuf>,
    /// Size of the --png picture, WIDTHxHEIGHT in pixels.
    #[arg(long, value_name = "WxH", default_value = "800x600", requires = "png")]
    pub size: String,
}

/// Runs the subcommand; exit 1 when no placement exists.
pub fn run(args: &PlacementsArgs) -> anyhow::Result<ExitCode> {
    if !(args.scale.is_finite() && args.scale > 0.0) {
        bail!("--scale {}: must be a positive number", args.scale);
    }
    let options = MeshOptions {
        scale: args.scale,
        ..Default::default()
    };
    let size = crate::view::parse_size(&args.size)?;
    if let Some(png) = &args.png {
        // Before any work: the picture may not replace a link, a device or an input.
        let mut inputs: Vec<crate::args::Input<'_>> = vec![("the object mesh", &args.object)];
        inputs.extend(args.on.as_deref().map(|on| ("the environment mesh", on)));
        crate::args::check_output_file(png, "--png", &inputs)?;
    }
    let object_mesh = mesh::load(&args.object, &options)?;
    for w in pickplace::mesh_warning::check(&object_mesh, "object", &args.object, Some("--scale")) {
        note!("warning: {w}");
    }
    let mass = MassProperties::of(&object_mesh);
    let cog = mass.center_of_mass;
    let object_name = args.object.display().to_string();

    let Some(env_path) = &args.on else {
        let poses = resting_poses(&object_mesh, &cog, &RestingOptions::default())
            .with_context(|| format!("{object_name}: resting poses"))?;
        if let Some(png) = &args.png {
            let poses: Vec<Isometry3> = poses
                .iter()
                .take(args.max)
                .map(|p| p.world_from_object)
                .collect();
            write_resting_png(png, size, &object_mesh, &poses)?;
        }
        let out = PlacementsJson::from_resting(object_name, &poses, args.max);
        return print(&out, args.json);
    };

    let world_from_env = match &args.env_pose {
        Some(text) => parse_pose(text, "--env-pose")?,
        None => Isometry3::identity(),
    };
    let env_mesh = mesh::load(env_path, &options)?;
    let params = ClusterParams {
        h_max: args.h_max,
        ..ClusterParams::environment()
    };
    debug_assert_eq!(params.mode, ContactMode::Environment);
    let object_clusters = cluster_surface(&object_mesh, &params)
        .with_context(|| format!("{object_name}: clustering"))?;
    let env_clusters = cluster_surface(&env_mesh, &params)
        .with_context(|| format!("{}: clustering", env_path.display()))?;
    let object = ObjectModel::new(&object_mesh, &object_clusters, cog)?;
    let env = EnvironmentModel::new(&env_mesh, &env_clusters, &world_from_env)?;
    let placement_options = PlacementOptions {
        max_candidates: args.max,
        ..Default::default()
    };
    let target = match &args.target {
        Some(text) => parse_point(text, "--target")?,
        None => default_target(&env, &placement_options).with_context(|| {
            format!(
                "{}: no upward-facing cluster to place on",
                env_path.display()
            )
        })?,
    };
    let set = candidates(&object, &env, &target, &placement_options)
        .map_err(|e| anyhow::anyhow!("{}: {e}", env_path.display()))?;
    if let Some(png) = &args.png {
        let poses: Vec<Isometry3> = set.placements.iter().map(|p| p.world_from_object).collect();
        let options = pickplace_view::PictureOptions {
            render: crate::view::render_options(size),
            ..Default::default()
        };
        pickplace_view::render_placements(
            &object_mesh,
            &env_mesh,
            &world_from_env,
            &poses,
            Some(target),
            &options,
        )?
        .write_png(png)?;
        note!("wrote {} ({} placements)", png.display(), poses.len());
    }
    let out = PlacementsJson::from_set(object_name, env_path.display().to_string(), &target, &set);
    print(&out, args.json)
}

/// Resting poses side by side along x on a thin plate, as a picture.
fn write_resting_png(
    png: &std::path::Path,
    size: (u32, u32),
    object: &pickplace_geometry::mesh::TriMesh,
    world_from_object: &[Isometry3],
) -> anyhow::Result<()> {
    let (lo, hi) = object.aabb();
    let spacing = (hi - lo).norm() * 1.2;
    let poses: Vec<Isometry3> = world_from_object
        .iter()
        .enumerate()
        .map(|(i, p)| Translation3::new(spacing * i as Real, 0.0, 0.0) * p)
        .collect();
    // The plate spans every copy; its top is at the lowest point of any copy.
    let (mut min, mut max) = (
        Point3::new(Real::MAX, Real::MAX, Real::MAX),
        Point3::new(Real::MIN, Real::MIN, Real::MIN),
    );
    for pose in &poses {
        for v in object.vertices() {
            let p = pose * v;
            min = min.inf(&p);
            max = max.sup(&p);
        }
    }
    if poses.is_empty() {
        (min, max) = (lo, hi);
    }
    let margin = spacing * 0.25;
    let half = [
        0.5 * (max.x - min.x) + margin,
        0.5 * (max.y - min.y) + margin,
        0.001,
    ];
    let plate = pickplace_geometry::shapes::box_mesh(half);
    let world_from_plate = Isometry3::translation(
        0.5 * (min.x + max.x),
        0.5 * (min.y + max.y),
        min.z - half[2],
    );
    let options = pickplace_view::PictureOptions {
        render: crate::view::render_options(size),
        ..Default::default()
    };
    pickplace_view::render_placements(object, &plate, &world_from_plate, &poses, None, &options)?
        .write_png(png)?;
    note!("wrote {} ({} resting poses)", png.display(), poses.len());
    Ok(())
}

fn print(out: &PlacementsJson, json: bool) -> anyhow::Result<ExitCode> {
    if json {
        crate::output::print_json(out)?;
    } else {
        let mut text = String::new();
        if let Some(t) = out.target {
            outln!(
                text,
                "target ({:.4}, {:.4}, {:.4}) on environment cluster {}",
                t[0],
                t[1],
                t[2],
                out.target_cluster
                    .map_or_else(|| "-".into(), |c| c.to_string())
            );
        }
        outln!(
            text,
            "{:>3}  {:<9}  {:>7}  {:>10}  {:>9}  {:>7}  position",
            "#",
            "contact",
            "object",
            "margin(m)",
            "dist(m)",
            "tilt(°)"
        );
        for (i, p) in out.placements.iter().enumerate() {
            let contact = match p.contact {
                ContactKind::FaceFace => "face-face",
                ContactKind::EdgeFace => "edge-face",
            };
            outln!(
                text,
                "{:>3}  {:<9}  {:>7}  {:>10.4}  {:>9}  {:>7.2}  ({:.4}, {:.4}, {:.4})",
                i,
                contact,
                p.object_cluster
                    .map_or_else(|| "-".into(), |c| c.to_string()),
                p.stability_margin,
                p.distance_to_target
                    .map_or_else(|| "-".into(), |d| format!("{d:.4}")),
                p.tilt.to_degrees(),
                p.pose.position[0],
                p.pose.position[1],
                p.pose.position[2],
            );
        }
        crate::output::print(&text)?;
    }
    if out.placements.is_empty() {
        if out.rejections.is_empty() {
            note!(
                "no stable placement found: no face of the object holds it with a margin of {:.1} mm and a tipping angle of {:.1}° (the placement minimums; docs/placement.md)",
                pickplace_placement::DEFAULT_MIN_MARGIN * 1e3,
                pickplace_placement::DEFAULT_MIN_TIPPING_ANGLE.to_degrees()
            );
            return Ok(ExitCode::from(1));
        }
        note!("no stable placement found:");
        for r in &out.rejections {
            note!(
                "  environment cluster {}: {} object regions did not fit, {} poses unstable, {} penetrate the environment",
                r.env_cluster,
                r.did_not_fit,
                r.unstable,
                r.penetrates
            );
        }
        return Ok(ExitCode::from(1));
    }
    Ok(ExitCode::SUCCESS)
}
