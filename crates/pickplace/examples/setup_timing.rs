//! Times the robot part of a first setup (empty cache): the URDF with its meshes, the SRDF,
//! the collision world (convex hulls of the link meshes) and each arm's roadmap, built the
//! way `Setup` builds it (`pickplace::roadmaps::load_or_build`, no cache).
//!
//! ```text
//! cargo run --release -p pickplace --example setup_timing -- URDF SRDF [--package-dir DIR]... GROUP...
//! ```
//! The rest of the robot stays at the all-zero configuration (clamped into the limits).

use pickplace::roadmaps;
use pickplace::robot::collision::{AllowedCollisionMatrix, CollisionWorld};
use pickplace::robot::{LoadOptions, RobotModel, Semantics};
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let usage = "usage: setup_timing URDF SRDF [--package-dir DIR]... GROUP...";
    let urdf = PathBuf::from(args.next().ok_or(usage)?);
    let srdf = PathBuf::from(args.next().ok_or(usage)?);
    let mut options = LoadOptions::default();
    let mut groups = Vec::new();
    while let Some(a) = args.next() {
        if a == "--package-dir" {
            options.package_dirs.push(args.next().ok_or(usage)?.into());
        } else {
            groups.push(a);
        }
    }
    let total = Instant::now();
    let t = Instant::now();
    let model = RobotModel::from_urdf_file(&urdf, &options)?;
    let shapes: usize = model.links().iter().map(|l| l.collisions.len()).sum();
    println!(
        "model {:?}: {} links, {} collision shapes, {} variables in {:.1} ms",
        model.name(),
        model.links().len(),
        shapes,
        model.variable_count(),
        ms(t)
    );
    let t = Instant::now();
    let semantics = Semantics::from_file(&model, &srdf)?;
    println!("semantics in {:.1} ms", ms(t));
    let t = Instant::now();
    let world = CollisionWorld::new(&model, AllowedCollisionMatrix::from_srdf(semantics.srdf()))?;
    println!(
        "collision world: {} self pairs in {:.1} ms",
        world.self_pair_count(),
        ms(t)
    );
    let home = model.zero_configuration();
    for group in &groups {
        let t = Instant::now();
        let chain = semantics.chain(&model, group)?;
        let variables = chain.variables().to_vec();
        let space = roadmaps::arm_space(&model, &variables)?;
        let (roadmap, report) = roadmaps::load_or_build(
            &model,
            &world,
            group,
            &variables,
            &home,
            &space,
            None,
            &|_, _| {},
        )?;
        println!(
            "{group}: {report}; {} edges in {:.1} ms",
            roadmap.edge_count(),
            ms(t)
        );
    }
    println!("total {:.1} ms", ms(total));
    Ok(())
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}
