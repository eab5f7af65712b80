//! Roadmaps of `cargo xtask precompute` (paper §III-C): one PRM roadmap per arm group of the
//! shipped robot, prefiltered by self-collisions only, so one roadmap serves every scene (each
//! query checks its own environment lazily). Written with pickplace-prm's versioned codec.

use anyhow::{Context, Result};
use pickplace_prm::{JointSpace, Roadmap, RoadmapOptions, ValidityChecker, codec};
use pickplace_robot::collision::{
    AllowedCollisionMatrix, CheckOptions, CollisionScratch, CollisionWorld,
};
use pickplace_robot::{LoadOptions, RobotModel, Semantics};
use std::cell::RefCell;
use std::path::Path;

/// The groups planned with a roadmap: each arm with the waist, as in the paper's motions.
pub const GROUPS: [&str; 2] = ["right_arm_waist", "left_arm_waist"];

/// Roadmap size and seed (same seed, same bytes, whatever the thread count).
fn options() -> RoadmapOptions {
    RoadmapOptions {
        node_count: 5000,
        resolution: 0.05,
        seed: 1,
        ..RoadmapOptions::default()
    }
}

/// The robot against itself: the group's joints move, the others stay at `home`.
struct SelfCollisions {
    model: RobotModel,
    world: CollisionWorld,
    variables: Vec<usize>,
    home: Vec<f64>,
}

thread_local! {
    static SCRATCH: RefCell<(CollisionScratch, Vec<f64>)> = RefCell::new(Default::default());
}

impl ValidityChecker for SelfCollisions {
    fn is_state_valid(&self, q: &[f64]) -> bool {
        SCRATCH.with(|cell| {
            let mut guard = cell.borrow_mut();
            let (scratch, full) = &mut *guard;
            full.clear();
            full.extend_from_slice(&self.home);
            for (&v, &x) in self.variables.iter().zip(q) {
                full[v] = x;
            }
            !self
                .world
                .in_collision(&self.model, full, scratch, &CheckOptions { margin: 0.01 })
                .unwrap_or(true)
        })
    }
}

/// Builds and writes `<out>/nx-hiro.<group>.roadmap` for every group of [`GROUPS`]; keeps a
/// file that decodes for its space unless `force`.
pub fn run(root: &Path, out: &Path, force: bool) -> Result<()> {
    let dir = root.join("robots/nx-hiro");
    let urdf = dir.join("nx-hiro.urdf");
    let model = RobotModel::from_urdf_file(&urdf, &LoadOptions::default())?;
    let semantics = Semantics::from_file(&model, &dir.join("nx-hiro.srdf"))?;
    let mut home = model.zero_configuration();
    semantics.apply_state(&model, "home", &mut home)?;
    let world = CollisionWorld::new(&model, AllowedCollisionMatrix::from_srdf(semantics.srdf()))?;
    let limits: Vec<_> = model.variable_limits().copied().collect();
    for group in GROUPS {
        let path = out.join(format!("nx-hiro.{group}.roadmap"));
        let variables = semantics.chain(&model, group)?.variables().to_vec();
        let space = JointSpace::with_unit_weights(
            variables.iter().map(|&v| limits[v].lower).collect(),
            variables.iter().map(|&v| limits[v].upper).collect(),
        )?;
        let valid = |bytes: Vec<u8>| codec::decode(&bytes, &space).is_ok();
        if !force && std::fs::read(&path).is_ok_and(valid) {
            eprintln!("{}: kept (valid for {group})", path.display());
            continue;
        }
        let checker = SelfCollisions {
            model: model.clone(),
            world: world.clone(),
            variables,
            home: home.clone(),
        };
        let start = std::time::Instant::now();
        let roadmap = Roadmap::build_prefiltered(&space, &checker, &options())
            .with_context(|| format!("roadmap of {group}"))?;
        let bytes = codec::encode(&roadmap)?;
        pickplace_geometry::export::write_atomic(&path, &bytes)?;
        eprintln!(
            "{}: built {} nodes for {group} in {:.2} s ({} bytes)",
            path.display(),
            options().node_count,
            start.elapsed().as_secs_f64(),
            bytes.len()
        );
    }
    Ok(())
}
