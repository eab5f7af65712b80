//! `cargo xtask mbm --spheres`: the Panda's links covered by spheres made from its collision
//! meshes (`pickplace_robot::spheres`), beside VAMP's hand-made model of the same robot
//! (`panda_spherized.urdf` in vamp-planner 0.6.4's resources), both checked against points
//! sampled on the collision meshes (issue 35).

use pickplace_robot::model::Shape;
use pickplace_robot::spheres::{Coverage, Sphere, SphereModel};
use pickplace_robot::{LoadOptions, RobotModel};
use std::path::Path;

/// Surface samples per square metre of mesh.
const DENSITY: f64 = 200_000.0;

/// Prints both models' sizes and coverage of the meshes in `resources` (the Panda's folder).
pub fn run(resources: &Path) -> anyhow::Result<()> {
    let options = LoadOptions {
        package_dirs: vec![resources.to_path_buf()],
        ..LoadOptions::default()
    };
    let panda = RobotModel::from_urdf_file(&resources.join("panda.urdf"), &options)?;
    let spherized = RobotModel::from_urdf_file(&resources.join("panda_spherized.urdf"), &options)?;
    // VAMP's spheres by the mesh model's link index.
    let vamp = SphereModel {
        links: panda
            .links()
            .iter()
            .map(|link| {
                spherized
                    .link_index(&link.name)
                    .map(|i| {
                        spherized.links()[i]
                            .collisions
                            .iter()
                            .filter_map(|g| match g.shape {
                                Shape::Sphere { radius } => Some(Sphere {
                                    center: g.link_from_shape
                                        * pickplace_geometry::math::Point3::origin(),
                                    radius,
                                }),
                                _ => None,
                            })
                            .collect()
                    })
                    .unwrap_or_default()
            })
            .collect(),
        margin: 0.0,
    };
    let ours = SphereModel::of(&panda, 0.0);
    let line = |name: &str, m: &SphereModel, c: Coverage| {
        let biggest = m
            .links
            .iter()
            .flatten()
            .map(|s| s.radius)
            .fold(0.0, f64::max);
        println!(
            "{name:<28} {:>4} spheres (largest radius {:.1} mm): {} of {} surface points outside, \
             the farthest {:.1} mm out",
            m.count(),
            biggest * 1e3,
            c.outside,
            c.samples,
            c.worst * 1e3
        );
    };
    line(
        "ours (from the meshes)",
        &ours,
        ours.verify(&panda, DENSITY, 1),
    );
    line(
        "VAMP 0.6.4 (hand-made)",
        &vamp,
        vamp.verify(&panda, DENSITY, 1),
    );
    // Link by link.
    for (i, link) in panda.links().iter().enumerate() {
        if link.collisions.is_empty() {
            continue;
        }
        let (a, b) = (
            ours.verify_link(&panda, i, DENSITY, 1),
            vamp.verify_link(&panda, i, DENSITY, 1),
        );
        println!(
            "  {:<18} ours {:>2} spheres, {} of {} points out ({:.1} mm); VAMP {:>2} spheres, {} out ({:.1} mm)",
            link.name,
            ours.links[i].len(),
            a.outside,
            a.samples,
            a.worst * 1e3,
            vamp.links[i].len(),
            b.outside,
            b.worst * 1e3
        );
    }
    Ok(())
}
